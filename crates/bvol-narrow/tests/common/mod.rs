//! Shared by the integration tests: the real meshes shipped in the repo's
//! tests/meshes, the test hulls, random poses, conversions to parry3d, and an
//! exact f64 separating-axis reference ([`reference`]).
#![allow(dead_code)] // each test binary uses its own part of this module

pub mod reference;
pub mod shapes;

use std::path::PathBuf;

use bvol_volumes::Pose;
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

/// A uniformly random point in the ball of radius `r`.
pub fn random_in_ball(rng: &mut impl rand::Rng, r: f32) -> Vec3 {
    use rand::RngExt;
    random_unit(rng) * r * rng.random::<f32>().cbrt()
}

/// parry3d's vector (glam 0.33 through glamx) from ours (glam 0.34).
pub fn to_parry(v: Vec3) -> parry3d::math::Vector {
    parry3d::math::Vector::new(v.x, v.y, v.z)
}

/// Ours from parry3d's.
pub fn from_parry(v: parry3d::math::Vector) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// parry3d's pose from ours.
pub fn parry_pose(p: &Pose) -> parry3d::math::Pose {
    let q = p.rotation;
    parry3d::math::Pose::from_parts(
        to_parry(p.position),
        parry3d::math::Rotation::from_xyzw(q.x, q.y, q.z, q.w),
    )
}
