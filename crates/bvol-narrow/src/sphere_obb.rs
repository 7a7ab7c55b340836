//! A sphere against an oriented box: the centre clamped to the box is its
//! closest point (Ericson, Real-Time Collision Detection 5.1.4).

use bvol_volumes::{Obb, Sphere};
use glam::DVec3;

use crate::ball::check_sphere;
use crate::isometry::DIsometry3;
use crate::obb_obb::check_obb;
use crate::sphere_hull::{Nearest, sphere_contact};
use crate::{Body, Collision, NarrowError, Pose};

/// Whether sphere `a` touches box `b`, and how: the closest point of the box
/// is the centre clamped to it in the box's frame (Ericson 5.1.4); a centre
/// inside goes out through the nearest face. The normal points from the
/// sphere to the box.
///
/// Errors as for [`sphere_hull`](crate::sphere_hull), and a box with a non-finite field or a
/// negative half extent is [`NarrowError::NonFiniteShape`].
///
/// ```
/// use bvol_narrow::{Collision, Pose, sphere_obb};
/// use bvol_volumes::{Obb, Sphere};
/// use glam::{Mat3, Quat, Vec3};
/// let b = Obb { center: Vec3::ZERO, axes: Mat3::IDENTITY, half_extents: Vec3::ONE };
/// let ball = Sphere::new(Vec3::ZERO, 0.5);
/// let beside = Pose::new(Vec3::new(2.0, 0.0, 0.0), Quat::IDENTITY);
/// let hit = sphere_obb(&ball, &beside, &b, &Pose::IDENTITY)?;
/// assert_eq!(hit, Collision::Separated { axis: -Vec3::X, distance: 0.5 });
/// # Ok::<(), bvol_narrow::NarrowError>(())
/// ```
pub fn sphere_obb(
    a: &Sphere,
    pose_a: &Pose,
    b: &Obb,
    pose_b: &Pose,
) -> Result<Collision, NarrowError> {
    let iso_a = DIsometry3::of_pose(pose_a, Body::A)?;
    check_sphere(a, Body::A)?;
    let iso_b = DIsometry3::of_pose(pose_b, Body::B)?.with_box(b.center, b.axes);
    check_obb(b, Body::B)?;
    let centre = iso_b.relative(&iso_a).apply(a.center.as_dvec3());
    let nearest = nearest_on_box(centre, b.half_extents.as_dvec3());
    Ok(sphere_contact(centre, a.radius.into(), nearest, &iso_b))
}

/// Where `centre` is with respect to the box `[-half, half]` (Ericson 5.1.4):
/// outside, the centre clamped to the box; inside, the face it is nearest,
/// on the axis with the least `half - |centre|` (first on ties).
fn nearest_on_box(centre: DVec3, half: DVec3) -> Nearest {
    let point = centre.clamp(-half, half);
    let excess = centre.abs() - half;
    let axis = (1..3).fold(0, |k, i| if excess[i] > excess[k] { i } else { k });
    let normal = DVec3::AXES[axis] * if centre[axis] < 0.0 { -1.0 } else { 1.0 };
    if point != centre {
        Nearest::Outside { point, fallback: normal }
    } else {
        Nearest::Inside { normal, separation: excess[axis] }
    }
}
