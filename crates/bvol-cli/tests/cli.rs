//! The `bvol` command line, run as a user would.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use glam::DVec3;
use serde_json::Value;

fn bvol(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_bvol")).args(args).output().expect("run bvol")
}

fn mesh(name: &str) -> PathBuf {
    // The engine's test meshes, at the workspace root.
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/meshes").join(name)
}

/// A scratch file holding `bytes`, unique to this test process.
fn scratch(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bvol-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn bad_mesh_files_give_one_line_errors_and_exit_code_2() {
    let cases: Vec<(PathBuf, &str)> = vec![
        (PathBuf::from("/no/such/mesh.obj"), "cannot read"),
        (scratch("binary.obj", b"\x89PNG\r\n\x1a\n\0\0\xff\xfe"), "not an OBJ file"),
        (scratch("words.obj", b"hello\nthis is not a mesh\n"), "no vertices"),
        (scratch("empty.obj", b"o empty\n"), "no vertices"),
        (scratch("nan.obj", b"v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n"), "vertex 1: NaN"),
        (scratch("inf.obj", b"v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n"), "NaN or infinite"),
        (scratch("range.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), "not a valid OBJ file"),
    ];
    for (path, problem) in cases {
        let out = bvol(&["fit", path.to_str().unwrap()]);
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(2), "{}: {err}", path.display());
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(path.to_str().unwrap()) && err.contains(problem), "{err}");
        assert!(out.stdout.is_empty() && !err.contains("panicked"));
    }
}

/// Every bound in the JSON output holds every vertex of the mesh, read back
/// from the JSON alone, checked in f64 from each bound's definition.
#[test]
fn json_bounds_hold_every_vertex() {
    let path = mesh("duck.obj");
    let out = bvol(&["fit", "--json", path.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows: Vec<Value> = serde_json::from_slice(&out.stdout).unwrap();
    let points: Vec<DVec3> =
        bvol::load_obj(&path).unwrap()[0].positions.iter().map(|p| p.as_dvec3()).collect();
    let v3 = |v: &Value| {
        DVec3::new(v[0].as_f64().unwrap(), v[1].as_f64().unwrap(), v[2].as_f64().unwrap())
    };
    let kinds: Vec<&str> = rows.iter().map(|r| r["kind"].as_str().unwrap()).collect();
    for kind in ["sphere", "aabb", "obb", "kdop"] {
        assert!(kinds.contains(&kind), "no {kind} in {kinds:?}");
    }
    for row in &rows {
        let b = &row["bound"];
        let holds = |p: &DVec3| match row["kind"].as_str().unwrap() {
            "sphere" => (*p - v3(&b["center"])).length() <= b["radius"].as_f64().unwrap(),
            "aabb" => p.cmpge(v3(&b["min"])).all() && p.cmple(v3(&b["max"])).all(),
            "obb" => (0..3).all(|i| {
                (*p - v3(&b["center"])).dot(v3(&b["axes"][i])).abs()
                    <= b["half_extents"][i].as_f64().unwrap()
            }),
            "kdop" => (0..b["min"].as_array().unwrap().len()).all(|i| {
                let s = v3(&b["directions"][i]).dot(*p);
                b["min"][i].as_f64().unwrap() <= s && s <= b["max"][i].as_f64().unwrap()
            }),
            other => panic!("unknown kind {other}"),
        };
        assert!(points.iter().all(holds), "{} {} misses a vertex", row["kind"], row["method"]);
        assert!(row["ratio"].as_f64().unwrap() >= 1.0 && row["micros"].as_f64().unwrap() >= 0.0);
        let volume = row["volume"].as_f64().unwrap();
        assert!(volume.is_finite() && volume > 0.0);
    }
}

/// Coordinates beyond `bvol::MAX_COORDINATE` are refused with a World's
/// error, naming the file, the object and the vertex (near 3e38 they once
/// gave `null` radii and volumes, exit 0); up to the limit, every number in
/// the output is finite (volumes near 1e55 once printed `inf` and ratios
/// NaN).
#[test]
fn fit_refuses_coordinates_beyond_the_worlds_limit() {
    for z in ["-3e38", "1.1e18"] {
        let obj = format!("o thing\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 {z}\nf 1 2 3 4\n");
        let path = scratch(&format!("far{z}.obj"), obj.as_bytes());
        let out = bvol(&["fit", "--json", path.to_str().unwrap()]);
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(2), "{err}");
        let world = bvol::ShapeError::OutOfRange { part: "thing".into(), point: 3 };
        assert_eq!(err, format!("bvol: {}: {world}\n", path.display()));
        assert!(out.stdout.is_empty());
    }
    let obj = "v 1e18 1e18 1e18\nv -1e18 0 0\nv 0 -1e18 0\nv 0 0 -1e18\nf 1 2 3 4\n";
    let path = scratch("at-the-limit.obj", obj.as_bytes());
    let out = bvol(&["fit", "--json", path.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows: Vec<Value> = serde_json::from_slice(&out.stdout).unwrap();
    for row in &rows {
        for key in ["volume", "ratio"] {
            let v = row[key].as_f64();
            assert!(v.is_some_and(|v| v.is_finite() && v > 0.0), "{key} in {row}");
        }
    }
    let table = bvol(&["fit", path.to_str().unwrap()]);
    let text = String::from_utf8(table.stdout).unwrap();
    assert!(!text.contains("inf") && !text.contains("NaN"), "{text}");
}

/// `bench world --shape` errors say where and what: the file with the part
/// (a part's error once named only the part); a mesh too small to scale to a
/// body (coordinates near 1e-44 were once said to be NaN or infinite); a
/// 1 x 1 x 1e13 tetrahedron, a solid in exact arithmetic, is a line at f32
/// precision, and the error says so; a part on a line is named. A flat
/// sheet is taken.
#[test]
fn bench_world_shape_errors_name_the_file_and_the_real_problem() {
    let tetra = |x: &str, z: &str| {
        format!("v 0 0 0\nv {x} 0 0\nv 0 {x} 0\nv 0 0 {z}\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n")
    };
    let cases = [
        ("tiny.obj", tetra("1e-44", "1e-44"), "too small to scale to a body"),
        ("needle.obj", tetra("1", "1e13"), "at f32 precision the points span 1 dimension"),
        ("line.obj", "o rod\nv 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n".into(), "part \"rod\""),
    ];
    for (name, obj, problem) in cases {
        let path = scratch(name, obj.as_bytes());
        let out = bvol(&[
            "bench",
            "world",
            "--n",
            "10",
            "--frames",
            "1",
            "--shape",
            path.to_str().unwrap(),
        ]);
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(path.to_str().unwrap()) && err.contains(problem), "{err}");
        assert!(!err.contains("NaN or infinite"), "{err}");
    }
    // A flat sheet is a shape: a thin slab.
    let sheet = scratch("sheet.obj", b"o sheet\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let out =
        bvol(&["bench", "world", "--n", "10", "--frames", "1", "--shape", sheet.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
}
