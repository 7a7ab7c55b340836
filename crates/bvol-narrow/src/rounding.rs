//! What a warm start's records, kept in f32, allow for: the rounding of
//! their f64 sums and of what they store.

use bvol_volumes::Pose;
use glam::DVec3;

/// Relative rounding allowed for in the records' f64 sums.
pub(crate) const ROUNDING: f64 = 16.0 * f64::EPSILON;

/// How far from unit an f32-rounded unit vector's length may be: `2^-23`,
/// more than the `2^-24` relative rounding of each component gives; and so
/// how far an f32-rounded vector may be off, relative to its coordinates.
pub(crate) const STORED: f64 = 1.0 / (1 << 23) as f64;

/// B's position less A's, in f64 (exact from f32).
pub(crate) fn offset(pose_a: &Pose, pose_b: &Pose) -> DVec3 {
    pose_b.position.as_dvec3() - pose_a.position.as_dvec3()
}

/// The greatest f32 at most `x`.
pub(crate) fn down(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) > x { y.next_down() } else { y }
}

/// The least f32 at least `x`.
pub(crate) fn up(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) < x { y.next_up() } else { y }
}
