//! Shared by the integration tests: the real meshes shipped in the repo's
//! tests/meshes (sources and licences in SOURCES.tsv beside them) and their
//! reference values (REFERENCE.tsv, from exact and best-known solvers).
#![allow(dead_code, unused_imports)] // each test binary uses its own part of this module

mod shared;

pub use shared::{mesh, mesh_dir, random_rotation, random_unit};

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
