//! The demo end to end: headless runs render bodies, report the World's own
//! pair counts and keep every body above the floor; the windowed mode opens
//! under Xvfb; bad assets are reported and skipped. Needs a Vulkan driver
//! (Mesa's software one does) and, for the window, xvfb-run: the README's
//! test command installs both.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::Arc;

use bvol::volumes::Pose;
use bvol::{BodyDesc, BodyKind, FitOptions, Part, World};
use bvol_falling::render::CLEAR_COLOR;
use bvol_falling::shapes::ShapeLibrary;
use bvol_falling::sim;
use glam::{Mat4, Quat, Vec3, Vec4};
use serde_json::Value;

/// A fresh folder for one test's files.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs the demo with `args`, or `wrapper` with `args` (which then name the
/// demo themselves); Mesa's "XDG_RUNTIME_DIR is invalid" kept away.
fn falling(wrapper: Option<&str>, args: &[&str], dir: &Path) -> Output {
    let mut command = Command::new(wrapper.unwrap_or(env!("CARGO_BIN_EXE_falling")));
    let runtime = dir.join("xdg");
    std::fs::create_dir_all(&runtime).unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&runtime, std::fs::Permissions::from_mode(0o700)).unwrap();
    }
    let output = command.args(args).env("XDG_RUNTIME_DIR", &runtime).output().unwrap();
    assert!(
        output.status.success(),
        "falling {args:?} failed: {}\n{}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn vec3(v: &Value) -> Vec3 {
    Vec3::from_slice(&floats(v))
}

fn floats(v: &Value) -> Vec<f32> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap() as f32).collect()
}

/// The bodies of a stats file's end state rebuilt in a fresh World (the
/// floor as the demo makes it, every body of its library shape, kind and
/// pose), updated once.
fn rebuild(end: &Value, library: &ShapeLibrary) -> (World, Vec<bvol::BodyId>) {
    let mut world = World::new();
    world.add_body(sim::floor()).unwrap();
    let mut ids = Vec::new();
    for body in end["bodies"].as_array().unwrap() {
        let shape = library.entries[body["shape"].as_u64().unwrap() as usize].shape.clone();
        let position = vec3(&body["position"]);
        let rotation = Quat::from_slice(&floats(&body["rotation"]));
        let kind = match body["kind"].as_str().unwrap() {
            "Sleeping" => BodyKind::Sleeping,
            "Dynamic" => BodyKind::Dynamic,
            other => panic!("a body of kind {other} in the stats"),
        };
        let desc = BodyDesc::new(Arc::clone(&shape), Pose::new(position, rotation)).with_kind(kind);
        ids.push(world.add_body(desc).unwrap());
    }
    world.update();
    (world, ids)
}

/// The lowest point of a body: its parts' support points straight down,
/// posed.
fn lowest_point(world: &World, id: bvol::BodyId) -> f32 {
    let pose = world.pose(id).unwrap();
    let shape = world.shape(id).unwrap();
    let down = pose.rotation.inverse() * Vec3::NEG_Y;
    let low = |part: &Part| (pose.rotation * part.support(down) + pose.position).y;
    shape.parts().iter().map(low).fold(f32::INFINITY, f32::min)
}

/// 500 bodies, 300 frames headless: the image shows bodies where they are,
/// the last frame's reported pair counts are those of a fresh World holding
/// the same bodies, and no body sinks below the floor.
#[test]
fn headless_run_shows_bodies_and_the_worlds_own_pairs() {
    let dir = scratch("headless");
    let (png, json) = (dir.join("shot.png"), dir.join("stats.json"));
    let args = [
        "--headless",
        "--frames",
        "300",
        "--bodies",
        "500",
        "--screenshot",
        png.to_str().unwrap(),
        "--stats",
        json.to_str().unwrap(),
    ];
    falling(None, &args, &dir);
    let stats = read_json(&json);
    assert_eq!(stats["mode"], "headless");
    let frames = stats["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 300);
    let end = &stats["end"];
    assert_eq!(end["bodies"].as_array().unwrap().len(), 500);

    // The counts shown for the last frame are the World's own: a fresh
    // World with the same bodies finds the same pairs at every stage (the
    // tree decides on tight bounds, so its history does not matter).
    let library = ShapeLibrary::load(&ShapeLibrary::default_mesh_files(), FitOptions::default());
    assert!(library.errors.is_empty(), "{:?}", library.errors);
    let (world, ids) = rebuild(end, &library);
    let last = frames.last().unwrap();
    let s = world.stats();
    for (name, want) in [
        ("candidates", s.candidates),
        ("after_spheres", s.after_spheres),
        ("after_obbs", s.after_obbs),
        ("touching", s.touching),
    ] {
        assert_eq!(last[name].as_u64().unwrap() as usize, want, "{name} in the last frame");
    }
    let most = frames.iter().map(|f| f["touching"].as_u64().unwrap()).max().unwrap();
    assert!(most > 100, "500 falling bodies touch in many places, at most {most} here");
    // The touching pairs too, by body (slots map in order: the floor is 0).
    let slot_of: std::collections::HashMap<u64, usize> = end["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .map(|(i, b)| (b["slot"].as_u64().unwrap(), i + 1))
        .collect();
    let mut reported: Vec<(usize, usize)> = end["touching_pairs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let slot = |k: usize| {
                let s = p[k].as_u64().unwrap();
                if s == 0 { 0 } else { slot_of[&s] }
            };
            (slot(0).min(slot(1)), slot(0).max(slot(1)))
        })
        .collect();
    reported.sort_unstable();
    let slot = |id: bvol::BodyId| id.index() as usize;
    let mut fresh: Vec<(usize, usize)> = world
        .events()
        .iter()
        .filter(|e| e.contact.is_some())
        .map(|e| (slot(e.a).min(slot(e.b)), slot(e.a).max(slot(e.b))))
        .collect();
    fresh.sort_unstable();
    assert_eq!(reported, fresh);

    // Nothing below the floor's top (y = 0) beyond the solver's slop.
    for id in &ids {
        let y = lowest_point(&world, *id);
        assert!(y > -0.03, "body {} reaches {y} below the floor", id.index());
    }

    // Where bodies are, the image is neither the background nor the bare
    // floor (whose flat shading gives it one colour).
    let (size, pixels) = read_png(&png);
    let view_proj = Mat4::from_cols_slice(&floats(&stats["view"]["view_proj"]));
    let viewport = floats(&stats["view"]["viewport"]);
    let clear = [CLEAR_COLOR.r, CLEAR_COLOR.g, CLEAR_COLOR.b].map(|c| (c * 255.0).round() as u8);
    let floor_pixel = pixel(&pixels, size, [viewport[0] as u32 + 5, size[1] - 5]);
    let mut seen = 0;
    for id in &ids {
        let clip = view_proj * Vec4::from((world.pose(*id).unwrap().position, 1.0));
        let ndc = clip.truncate() / clip.w;
        let x = viewport[0] + (ndc.x + 1.0) / 2.0 * viewport[2];
        let y = viewport[1] + (1.0 - ndc.y) / 2.0 * viewport[3];
        if clip.w <= 0.0 || x < viewport[0] + 1.0 || y < 1.0 || x >= size[0] as f32 - 1.0 {
            continue;
        }
        if y >= size[1] as f32 - 1.0 {
            continue;
        }
        let p = pixel(&pixels, size, [x as u32, y as u32]);
        assert!(
            !close(p, clear) && !close(p, floor_pixel),
            "body {} at pixel ({x}, {y}) shows {p:?}",
            id.index()
        );
        seen += 1;
    }
    assert!(seen > 250, "only {seen} bodies in view");
}

fn close(a: [u8; 3], b: [u8; 3]) -> bool {
    a.iter().zip(&b).all(|(x, y)| x.abs_diff(*y) <= 2)
}

fn read_png(path: &Path) -> ([u32; 2], Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgba);
    ([info.width, info.height], pixels)
}

fn pixel(pixels: &[u8], size: [u32; 2], [x, y]: [u32; 2]) -> [u8; 3] {
    let i = ((y * size[0] + x) * 4) as usize;
    [pixels[i], pixels[i + 1], pixels[i + 2]]
}

/// Under Xvfb the window opens and draws the frames asked for.
#[test]
fn window_opens_under_xvfb() {
    let dir = scratch("windowed");
    let json = dir.join("stats.json");
    let args = [
        "-a",
        "-s",
        "-screen 0 1280x720x24",
        env!("CARGO_BIN_EXE_falling"),
        "--frames",
        "30",
        "--bodies",
        "200",
        "--stats",
        json.to_str().unwrap(),
    ];
    let output = falling(Some("xvfb-run"), &args[..], &dir);
    let stats = read_json(&json);
    assert_eq!(stats["mode"], "windowed", "{}", String::from_utf8_lossy(&output.stderr));
    let frames = stats["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 30);
    assert!(frames.iter().all(|f| f["bodies"] == 200));
}

/// A missing and a broken OBJ file are reported (log and UI messages) and
/// the demo runs with the rest.
#[test]
fn bad_assets_are_reported_and_skipped() {
    let dir = scratch("bad_assets");
    let broken = dir.join("broken.obj");
    std::fs::write(&broken, "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n").unwrap();
    let missing = dir.join("missing.obj");
    let json = dir.join("stats.json");
    let args = [
        "--headless",
        "--frames",
        "5",
        "--bodies",
        "50",
        "--mesh",
        missing.to_str().unwrap(),
        "--mesh",
        broken.to_str().unwrap(),
        "--stats",
        json.to_str().unwrap(),
    ];
    let output = falling(None, &args, &dir);
    let log = String::from_utf8_lossy(&output.stderr);
    let messages = read_json(&json)["messages"].clone();
    let messages: Vec<&str> =
        messages.as_array().unwrap().iter().map(|m| m.as_str().unwrap()).collect();
    for file in [&missing, &broken] {
        let name = file.to_str().unwrap();
        assert!(log.contains(name), "the log does not name {name}: {log}");
        assert_eq!(messages.iter().filter(|m| m.contains(name)).count(), 1, "{messages:?}");
    }
    assert_eq!(read_json(&json)["end"]["bodies"].as_array().unwrap().len(), 50);
}
