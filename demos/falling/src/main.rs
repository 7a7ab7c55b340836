//! `falling`: the demo's command line. Windowed when a display is there,
//! headless otherwise (or with `--headless`).

use std::path::PathBuf;
use std::process::ExitCode;

use bvol_falling::app::App;
use bvol_falling::headless::{self, HeadlessRun};
use bvol_falling::shapes::ShapeLibrary;
use bvol_falling::windowed::{self, WindowedRun};
use clap::Parser;

/// bvol's falling-objects demo: bodies rain onto a floor and pile up.
#[derive(Parser, Debug)]
#[command(version, about)]
struct Args {
    /// Draw offscreen instead of in a window (the default with no display).
    #[arg(long)]
    headless: bool,
    /// Frames to draw before exiting (headless: default 300; windowed: until closed).
    #[arg(long)]
    frames: Option<usize>,
    /// Write the last frame as a PNG (headless).
    #[arg(long, value_name = "PNG")]
    screenshot: Option<PathBuf>,
    /// Write the per-frame figures as JSON at the end.
    #[arg(long, value_name = "JSON")]
    stats: Option<PathBuf>,
    /// Bodies dropped at the start.
    #[arg(long, default_value_t = 500)]
    bodies: usize,
    /// Image or window size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    size: [u32; 2],
    /// An OBJ file to drop bodies of (repeat for several); the demo's own
    /// assets are used too unless --no-default-meshes.
    #[arg(long = "mesh", value_name = "OBJ")]
    meshes: Vec<PathBuf>,
    /// Leave out the meshes shipped in demos/falling/assets.
    #[arg(long)]
    no_default_meshes: bool,
    /// Overlays on at the start: any of spheres, obbs, tree, contacts (comma separated).
    #[arg(long, value_delimiter = ',', value_name = "LIST")]
    show: Vec<Overlay>,
    /// Seed of the random drop positions and shapes.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

/// An overlay that `--show` switches on.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
enum Overlay {
    Spheres,
    Obbs,
    Tree,
    Contacts,
}

/// glibc hands a thread's freed memory back to the system at once
/// (`madvise` when an arena's top shrinks past 128 KiB), and lavapipe frees
/// and allocates its vertex buffers at every draw: each frame then faults in
/// fresh zeroed pages, a fifth of a frame at 1 000 bodies. Keeping up to
/// 1 GiB of freed memory for reuse, and blocks up to 32 MiB (glibc's
/// largest) on the heap rather than mapped and unmapped each time, ends the
/// churn (`mallopt(3)`: `M_TRIM_THRESHOLD`, `M_MMAP_THRESHOLD`, which the
/// first would otherwise fix at 128 KiB). Elsewhere nothing is done.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        const M_TRIM_THRESHOLD: i32 = -1;
        const M_MMAP_THRESHOLD: i32 = -3;
        unsafe extern "C" {
            fn mallopt(param: i32, value: i32) -> i32;
        }
        // SAFETY: glibc's mallopt with valid parameters and values; it only
        // changes tunables, before any other thread is started.
        unsafe {
            mallopt(M_TRIM_THRESHOLD, 1 << 30);
            mallopt(M_MMAP_THRESHOLD, 32 << 20);
        }
    }
}

fn parse_size(text: &str) -> Result<[u32; 2], String> {
    let bad = || format!("expected WIDTHxHEIGHT like 1280x720, got {text:?}");
    let (w, h) = text.split_once('x').ok_or_else(bad)?;
    let (w, h) = (w.parse::<u32>().map_err(|_| bad())?, h.parse::<u32>().map_err(|_| bad())?);
    if !(16..=8192).contains(&w) || !(16..=8192).contains(&h) {
        return Err(format!("each side must be 16 to 8192 pixels, got {text:?}"));
    }
    Ok([w, h])
}

fn main() -> ExitCode {
    keep_freed_memory();
    let args = Args::parse();
    let mut files =
        if args.no_default_meshes { Vec::new() } else { ShapeLibrary::default_mesh_files() };
    files.extend(args.meshes.iter().cloned());
    let library = ShapeLibrary::load(&files, bvol::FitOptions::default());
    let mut app = App::new(library, args.seed);
    for overlay in &args.show {
        let s = &mut app.settings;
        match overlay {
            Overlay::Spheres => s.show_spheres = true,
            Overlay::Obbs => s.show_obbs = true,
            Overlay::Tree => s.show_tree = true,
            Overlay::Contacts => s.show_contacts = true,
        }
    }
    app.add_bodies(args.bodies);
    match run(app, &args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("falling: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(app: App, args: &Args) -> Result<(), String> {
    let headless_run = || HeadlessRun {
        frames: args.frames.unwrap_or(300),
        size: args.size,
        screenshot: args.screenshot.clone(),
        stats: args.stats.clone(),
    };
    if args.headless {
        return headless::run(app, headless_run());
    }
    let has_display = ["DISPLAY", "WAYLAND_DISPLAY"].iter().any(|v| std::env::var_os(v).is_some());
    if !has_display {
        eprintln!("falling: no display (DISPLAY and WAYLAND_DISPLAY unset): running headless");
        return headless::run(app, headless_run());
    }
    let event_loop = match windowed::event_loop() {
        Ok(event_loop) => event_loop,
        Err(windowed::NoDisplay(why)) => {
            eprintln!("falling: cannot open a window ({why}): running headless");
            return headless::run(app, headless_run());
        }
    };
    if args.screenshot.is_some() {
        eprintln!("falling: --screenshot is written in headless mode only (add --headless)");
    }
    let run = WindowedRun { size: args.size, frames: args.frames, stats: args.stats.clone() };
    windowed::run(app, event_loop, run)
}
