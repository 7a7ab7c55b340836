//! Shared by the integration tests: the real meshes shipped in the repo's
//! tests/meshes, the test hulls, random poses, conversions to parry3d, and an
//! exact f64 separating-axis reference ([`reference`]).
#![allow(dead_code, unused_imports)] // each test binary uses its own part of this module

pub mod reference;
pub mod shapes;
#[path = "../../../bvol-volumes/tests/common/shared.rs"]
mod shared;
pub mod tally;

use bvol_volumes::Pose;
use glam::Vec3;
pub use shared::{mesh, mesh_dir, random_rotation, random_unit};

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
