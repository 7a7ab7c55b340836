//! Shared by the integration tests: the real meshes shipped in the repo's
//! tests/meshes (sources and licences in SOURCES.tsv beside them) and their
//! reference values (REFERENCE.tsv, from exact and best-known solvers).
#![allow(dead_code)] // each test binary uses its own part of this module

use std::path::PathBuf;

use glam::Vec3;

/// The repo's tests/meshes folder.
pub fn mesh_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/meshes")
}

/// The vertices of a shipped mesh, every object of the file, as stored.
pub fn mesh(name: &str) -> Vec<Vec3> {
    let path = mesh_dir().join(format!("{name}.obj"));
    let (models, _) = tobj::load_obj(&path, &tobj::LoadOptions::default())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    models
        .iter()
        .flat_map(|m| m.mesh.positions.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])))
        .collect()
}

/// One row of REFERENCE.tsv.
#[derive(Clone, Debug)]
pub struct Reference {
    pub name: String,
    pub vertices: usize,
    pub min_sphere_radius: f64,
    pub ritter_radius: f64,
    pub aabb_volume: f64,
    pub pca_points_obb_volume: f64,
    pub best_known_obb_volume: f64,
}

/// Every row of REFERENCE.tsv.
pub fn references() -> Vec<Reference> {
    let text = std::fs::read_to_string(mesh_dir().join("REFERENCE.tsv")).expect("REFERENCE.tsv");
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|line| {
            let f: Vec<&str> = line.split('\t').collect();
            let num = |i: usize| f[i].parse::<f64>().expect("number in REFERENCE.tsv");
            Reference {
                name: f[0].to_string(),
                vertices: f[1].parse().expect("vertex count"),
                min_sphere_radius: num(2),
                ritter_radius: num(3),
                aabb_volume: num(4),
                pca_points_obb_volume: num(5),
                best_known_obb_volume: num(6),
            }
        })
        .collect()
}

/// A uniformly random rotation (Shoemake, Graphics Gems III: uniform random rotations).
pub fn random_rotation(rng: &mut impl rand::Rng) -> glam::Quat {
    use rand::RngExt;
    let (u1, u2, u3): (f32, f32, f32) = (rng.random(), rng.random(), rng.random());
    let tau = std::f32::consts::TAU;
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    glam::Quat::from_xyzw(
        a * (tau * u2).sin(),
        a * (tau * u2).cos(),
        b * (tau * u3).sin(),
        b * (tau * u3).cos(),
    )
    .normalize()
}

/// A uniformly random unit vector.
pub fn random_unit(rng: &mut impl rand::Rng) -> Vec3 {
    random_rotation(rng) * Vec3::Z
}
