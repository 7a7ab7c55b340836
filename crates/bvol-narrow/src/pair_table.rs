//! The pair table: which routine tests two parts, by their kinds.

use crate::Part::{Ball, Capsule, Hull};
use crate::{
    Collision, NarrowError, Part, Pose, WarmStart, capsule_capsule, capsule_hull, capsule_sphere,
    hull_hull, sphere_hull, sphere_sphere,
};

/// Whether two parts touch, and how, the normal from `a` to `b`: the routine
/// for their two kinds, each pair of kinds in a file of its own.
///
/// | A \ B   | hull         | ball            | capsule           |
/// | ------- | ------------ | --------------- | ----------------- |
/// | hull    | [`hull_hull`]| mirrored        | mirrored          |
/// | ball    | [`sphere_hull`] | [`sphere_sphere`] | mirrored     |
/// | capsule | [`capsule_hull`] | [`capsule_sphere`] | [`capsule_capsule`] |
///
/// A mirrored pair is tested by the routine of the two swapped and its answer
/// turned round ([`Collision::flipped`]), an error naming the body it names
/// in the caller's order. `warm` is the pair's cache from call to call (see
/// [`WarmStart`]); the routines that keep nothing leave it alone.
///
/// Errors as the routine's: a pose that is not finite, or a part with a
/// non-finite or negative size.
///
/// ```
/// use bvol_narrow::{Capsule, Part, Pose, WarmStart, collide_parts};
/// use bvol_volumes::Sphere;
/// use glam::{Quat, Vec3};
/// let ball = Part::Ball(Sphere::new(Vec3::ZERO, 0.5));
/// let rod = Part::Capsule(Capsule::new(0.25, 1.0));
/// let beside = Pose::new(Vec3::new(0.7, 0.0, 0.0), Quat::IDENTITY);
/// let mut warm = WarmStart::default();
/// let hit = collide_parts(&ball, &Pose::IDENTITY, &rod, &beside, &mut warm)?;
/// let contact = hit.contact().expect("0.05 deep");
/// assert_eq!(contact.normal, Vec3::X); // from the ball to the rod
/// assert!((contact.depth - 0.05).abs() < 1e-6);
/// # Ok::<(), bvol_narrow::NarrowError>(())
/// ```
pub fn collide_parts(
    a: &Part,
    pose_a: &Pose,
    b: &Part,
    pose_b: &Pose,
    warm: &mut WarmStart,
) -> Result<Collision, NarrowError> {
    match (a, b) {
        (Hull(x), Hull(y)) => hull_hull(&x.polyhedron, pose_a, &y.polyhedron, pose_b, warm),
        (Ball(x), Hull(y)) => sphere_hull(x, pose_a, &y.polyhedron, pose_b),
        (Ball(x), Ball(y)) => sphere_sphere(x, pose_a, y, pose_b),
        (Capsule(x), Hull(y)) => capsule_hull(x, pose_a, &y.polyhedron, pose_b),
        (Capsule(x), Ball(y)) => capsule_sphere(x, pose_a, y, pose_b),
        (Capsule(x), Capsule(y)) => capsule_capsule(x, pose_a, y, pose_b),
        (Hull(_), Ball(_) | Capsule(_)) | (Ball(_), Capsule(_)) => {
            collide_parts(b, pose_b, a, pose_a, warm)
                .map(Collision::flipped)
                .map_err(NarrowError::swapped)
        }
    }
}
