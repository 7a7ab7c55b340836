//! Oriented box against oriented box, with the same contact as two hulls.

use bvol_volumes::Obb;

use crate::cuboid::Cuboid;
use crate::hull_hull::collide;
use crate::isometry::DIsometry3;
use crate::{Body, Collision, NarrowError, Pose, WarmStart};

/// Whether two oriented boxes touch, and how: the test and contact of
/// [`hull_hull`](crate::hull_hull) on the two boxes, each made on the spot
/// (nothing allocated) from the unit cube's topology scaled by its half
/// extents, and placed by its body's pose followed by its own centre and axes.
/// The result is the one `hull_hull` gives for [`Polyhedron::cuboid`]s of the
/// same half extents placed where the boxes are (bit for bit when the boxes'
/// own centre is zero and axes the identity; else up to the rounding of
/// composing the placements). For a yes/no answer only, [`Obb::overlaps`] is
/// several times faster.
///
/// The box's axes are made exactly orthonormal first (Gram-Schmidt, the first
/// axis kept). A pose that is not finite is [`NarrowError::NonFinitePose`]; a
/// box with a non-finite field or a negative half extent is
/// [`NarrowError::NonFiniteShape`]. Zero half extents (flat boxes) are fine.
///
/// [`Polyhedron::cuboid`]: crate::Polyhedron::cuboid
///
/// ```
/// use bvol_narrow::{Pose, obb_obb};
/// use bvol_volumes::Obb;
/// use glam::{Mat3, Quat, Vec3};
/// let crate_box = Obb { center: Vec3::ZERO, axes: Mat3::IDENTITY, half_extents: Vec3::ONE };
/// let lid = Obb { half_extents: Vec3::new(1.0, 0.1, 1.0), ..crate_box };
/// let on_top = Pose::new(Vec3::new(0.0, 1.05, 0.0), Quat::IDENTITY);
/// let hit = obb_obb(&crate_box, &Pose::IDENTITY, &lid, &on_top)?;
/// let contact = hit.contact().expect("the lid sinks 0.05 into the box");
/// assert_eq!(contact.normal, Vec3::Y);
/// assert!((contact.depth - 0.05).abs() < 1e-6);
/// # Ok::<(), bvol_narrow::NarrowError>(())
/// ```
pub fn obb_obb(a: &Obb, pose_a: &Pose, b: &Obb, pose_b: &Pose) -> Result<Collision, NarrowError> {
    let iso_a = DIsometry3::of_pose(pose_a, Body::A)?;
    check_obb(a, Body::A)?;
    let iso_b = DIsometry3::of_pose(pose_b, Body::B)?;
    check_obb(b, Body::B)?;
    Ok(collide(
        &Cuboid::new(a.half_extents),
        &iso_a.with_box(a.center, a.axes),
        &Cuboid::new(b.half_extents),
        &iso_b.with_box(b.center, b.axes),
        &mut WarmStart::default(),
    )
    .collision())
}

/// Whether a box's fields are finite and its half extents not negative.
pub(crate) fn check_obb(obb: &Obb, body: Body) -> Result<(), NarrowError> {
    let finite = obb.center.is_finite() && obb.axes.is_finite() && obb.half_extents.is_finite();
    if finite && obb.half_extents.cmpge(glam::Vec3::ZERO).all() {
        Ok(())
    } else {
        Err(NarrowError::NonFiniteShape { body })
    }
}
