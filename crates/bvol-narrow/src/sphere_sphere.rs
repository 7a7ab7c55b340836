//! Two spheres: the line of their centres decides.

use bvol_volumes::Sphere;
use glam::DVec3;

use crate::ball::check_sphere;
use crate::isometry::DIsometry3;
use crate::manifold::Manifold;
use crate::{Body, Collision, NarrowError, Pose};

/// Whether two spheres touch, and how: along the line of their centres, from
/// A's to B's. Concentric spheres have no such line; they touch along A's
/// local up axis (`pose_a.rotation * Vec3::Y`), a fixed choice that turns
/// with A.
///
/// Errors as for [`sphere_hull`](crate::sphere_hull), for either sphere.
///
/// ```
/// use bvol_narrow::{Pose, sphere_sphere};
/// use bvol_volumes::Sphere;
/// use glam::{Quat, Vec3};
/// let s = Sphere::new(Vec3::ZERO, 1.0);
/// let near = Pose::new(Vec3::new(1.5, 0.0, 0.0), Quat::IDENTITY);
/// let contact = *sphere_sphere(&s, &Pose::IDENTITY, &s, &near)?.contact().unwrap();
/// assert_eq!((contact.normal, contact.depth), (Vec3::X, 0.5));
/// assert_eq!(contact.points()[0].position, Vec3::new(0.75, 0.0, 0.0));
/// # Ok::<(), bvol_narrow::NarrowError>(())
/// ```
pub fn sphere_sphere(
    a: &Sphere,
    pose_a: &Pose,
    b: &Sphere,
    pose_b: &Pose,
) -> Result<Collision, NarrowError> {
    let iso_a = DIsometry3::of_pose(pose_a, Body::A)?;
    check_sphere(a, Body::A)?;
    let iso_b = DIsometry3::of_pose(pose_b, Body::B)?;
    check_sphere(b, Body::B)?;
    let ca = iso_a.apply(a.center.as_dvec3());
    let cb = iso_b.apply(b.center.as_dvec3());
    let (ra, rb) = (f64::from(a.radius), f64::from(b.radius));
    let offset = cb - ca;
    let distance = offset.length();
    let normal = offset.try_normalize().unwrap_or_else(|| iso_a.rotate(DVec3::Y));
    let gap = distance - ra - rb;
    if gap > 0.0 {
        return Ok(Collision::separated(normal, gap));
    }
    // Midway between A's surface point ca + ra n and B's cb - rb n.
    let mut manifold = Manifold::default();
    manifold.push((ca + normal * ra + cb - normal * rb) * 0.5, -gap);
    Ok(Collision::touching(normal, -gap, &manifold, &DIsometry3::IDENTITY))
}
