//! The coordinates a world can hold: the one place their limits are set and
//! tested, for poses, shapes' points and primitives' sizes.

use std::ops::RangeInclusive;

use bvol_volumes::Pose;
use glam::Vec3;

pub use bvol_volumes::MAX_COORDINATE;

/// The squared lengths a body's rotation quaternion may have (it need not be
/// a unit one). Within them the world bounds' f32 rotation, normalised in
/// f32, is the exact rotation to a few ulps; a longer quaternion's squared
/// length overflows, and a shorter one's loses its digits, and the bounds
/// would no longer hold the shape the narrow phase tests.
pub const ROTATION_LENGTH_SQUARED: RangeInclusive<f32> = 1e-18..=1e18;

/// Whether every coordinate of `v` is at most [`MAX_COORDINATE`] in
/// magnitude (a NaN one is not): the one test of that limit, for poses,
/// shapes' points and primitives' sizes.
pub(crate) fn within_limit(v: Vec3) -> bool {
    v.abs().cmple(Vec3::splat(MAX_COORDINATE)).all()
}

/// Whether a world can place a body at `pose`: its position finite and within
/// [`MAX_COORDINATE`], its rotation's squared length within
/// [`ROTATION_LENGTH_SQUARED`] (which no NaN or infinite one is).
pub(crate) fn placeable(pose: &Pose) -> bool {
    within_limit(pose.position) && ROTATION_LENGTH_SQUARED.contains(&pose.rotation.length_squared())
}
