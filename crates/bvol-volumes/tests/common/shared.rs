//! Test helpers shared by the crates' integration tests (included by
//! `#[path]` from each crate's tests/common): the real meshes shipped in the
//! repo's tests/meshes, and random rotations and directions.

use std::path::PathBuf;

use glam::{Quat, Vec3};

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

/// A uniformly random rotation (Shoemake, Graphics Gems III: uniform random rotations).
pub fn random_rotation(rng: &mut impl rand::Rng) -> Quat {
    use rand::RngExt;
    let (u1, u2, u3): (f32, f32, f32) = (rng.random(), rng.random(), rng.random());
    let tau = std::f32::consts::TAU;
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    Quat::from_xyzw(
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
