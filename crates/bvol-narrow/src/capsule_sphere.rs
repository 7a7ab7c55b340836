//! A capsule against a sphere: the point of the capsule's core nearest the
//! sphere's centre decides (Ericson, Real-Time Collision Detection 5.1.2),
//! as for two spheres.

use bvol_volumes::Sphere;
use glam::DVec3;

use crate::ball::check_sphere;
use crate::capsule::MEET;
use crate::isometry::DIsometry3;
use crate::manifold::Manifold;
use crate::{Body, Capsule, Collision, NarrowError, Pose};

/// Whether capsule `a` touches sphere `b`, and how: along the line from the
/// point of A's core nearest B's centre to that centre, from A to B; one
/// contact point, midway between the surfaces. Computed in A's space in f64.
///
/// A centre on the core (to f64 rounding) has no such line: the contact is
/// then square to the core, along A's local x axis, or out through the end it lies at, along
/// A's local y axis or against it (at the middle of a capsule of
/// `half_height` 0, along its y axis, the choice of
/// [`sphere_sphere`](crate::sphere_sphere)). Each is a direction of least
/// penetration.
///
/// A pose that is not finite is [`NarrowError::NonFinitePose`]; a capsule or
/// a sphere with a non-finite field or a negative size is
/// [`NarrowError::NonFiniteShape`].
///
/// ```
/// use bvol_narrow::{Capsule, Collision, Pose, capsule_sphere};
/// use bvol_volumes::Sphere;
/// use glam::{Quat, Vec3};
/// let capsule = Capsule::new(0.5, 1.0); // its core from y = -1 to y = 1
/// let ball = Sphere::new(Vec3::ZERO, 0.25);
/// // Beside the core: the contact is square to it.
/// let beside = Pose::new(Vec3::new(0.7, 0.5, 0.0), Quat::IDENTITY);
/// let contact = *capsule_sphere(&capsule, &Pose::IDENTITY, &ball, &beside)?.contact().unwrap();
/// assert_eq!(contact.normal, Vec3::X);
/// assert!((contact.depth - 0.05).abs() < 1e-6);
/// // Above the top cap: apart along y by 2 - 1 - 0.5 - 0.25.
/// let above = Pose::new(Vec3::new(0.0, 2.0, 0.0), Quat::IDENTITY);
/// let hit = capsule_sphere(&capsule, &Pose::IDENTITY, &ball, &above)?;
/// assert_eq!(hit, Collision::Separated { axis: Vec3::Y, distance: 0.25 });
/// # Ok::<(), bvol_narrow::NarrowError>(())
/// ```
pub fn capsule_sphere(
    a: &Capsule,
    pose_a: &Pose,
    b: &Sphere,
    pose_b: &Pose,
) -> Result<Collision, NarrowError> {
    let iso_a = DIsometry3::of_pose(pose_a, Body::A)?;
    a.check(Body::A)?;
    let iso_b = DIsometry3::of_pose(pose_b, Body::B)?;
    check_sphere(b, Body::B)?;
    let centre = iso_a.relative(&iso_b).apply(b.center.as_dvec3());
    let half = f64::from(a.half_height);
    let nearest = DVec3::new(0.0, centre.y.clamp(-half, half), 0.0);
    let offset = centre - nearest;
    let (ra, rb) = (f64::from(a.radius), f64::from(b.radius));
    let span = centre.length() + f64::from(b.center.length()) + half + ra + rb;
    let normal = if offset.length() > MEET * span {
        offset.normalize()
    } else if nearest.y >= half {
        DVec3::Y
    } else if nearest.y <= -half {
        DVec3::NEG_Y
    } else {
        DVec3::X
    };
    let gap = offset.length() - ra - rb;
    if gap > 0.0 {
        return Ok(Collision::separated(iso_a.rotate(normal), gap));
    }
    // Midway between A's surface point and B's.
    let mut manifold = Manifold::default();
    manifold.push((nearest + normal * ra + centre - normal * rb) * 0.5, -gap);
    Ok(Collision::touching(iso_a.rotate(normal), -gap, &manifold, &iso_a))
}
