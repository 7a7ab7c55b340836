//! Two capsules: the closest points of their cores decide (Ericson,
//! Real-Time Collision Detection 5.1.9); cores lying side by side touch at
//! both ends of the stretch where they face each other.

use glam::DVec3;

use crate::capsule::{END_SLOP, MEET, PARALLEL_SINE};
use crate::isometry::DIsometry3;
use crate::manifold::Manifold;
use crate::segment::Segment;
use crate::{Body, Capsule, Collision, NarrowError, Pose};

/// Whether capsules `a` and `b` touch, and how: along the line between the
/// closest points of their cores, from A's to B's, by the sum of the radii
/// less the cores' distance. Computed in A's space in f64.
///
/// Cores that meet (to f64 rounding) have no such line: the contact is then
/// square to both (across them where they cross, a fixed direction square to
/// A's axis where they are parallel, A's local y axis for two of
/// `half_height` 0, as [`sphere_sphere`](crate::sphere_sphere) takes), each a
/// direction of least penetration.
///
/// The manifold has one point, midway between the surfaces, or two where the
/// cores are parallel to within about a degree and face each other along a
/// stretch whose ends both touch: a point at each end of it, each midway
/// between the surfaces where the ends' closest points say.
///
/// A pose that is not finite is [`NarrowError::NonFinitePose`]; a capsule
/// with a non-finite field or a negative size is
/// [`NarrowError::NonFiniteShape`].
///
/// ```
/// use bvol_narrow::{Capsule, Pose, capsule_capsule};
/// use glam::{Quat, Vec3};
/// // Two capsules side by side along y, their cores 0.9 apart, half overlapping.
/// let capsule = Capsule::new(0.5, 1.0);
/// let beside = Pose::new(Vec3::new(0.9, 1.0, 0.0), Quat::IDENTITY);
/// let contact = *capsule_capsule(&capsule, &Pose::IDENTITY, &capsule, &beside)?
///     .contact()
///     .expect("touching");
/// assert_eq!(contact.normal, Vec3::X);
/// assert!((contact.depth - 0.1).abs() < 1e-6);
/// // A point at each end of the stretch where they lie side by side, y 0 to 1.
/// let mut ys: Vec<f32> = contact.points().iter().map(|p| p.position.y).collect();
/// ys.sort_by(f32::total_cmp);
/// assert_eq!(ys, [0.0, 1.0]);
/// # Ok::<(), bvol_narrow::NarrowError>(())
/// ```
pub fn capsule_capsule(
    a: &Capsule,
    pose_a: &Pose,
    b: &Capsule,
    pose_b: &Pose,
) -> Result<Collision, NarrowError> {
    let iso_a = DIsometry3::of_pose(pose_a, Body::A)?;
    a.check(Body::A)?;
    let iso_b = DIsometry3::of_pose(pose_b, Body::B)?;
    b.check(Body::B)?;
    let core_a = a.core(&DIsometry3::IDENTITY);
    let rel = iso_a.relative(&iso_b);
    let core_b = b.core(&rel);
    let (pa, pb) = core_a.closest_points(&core_b);
    let offset = pb - pa;
    let radii = (f64::from(a.radius), f64::from(b.radius));
    let span =
        rel.translation.length() + f64::from(a.half_height + b.half_height) + radii.0 + radii.1;
    let normal = if offset.length() > MEET * span {
        offset.normalize()
    } else {
        square_to_both(&core_a, &core_b, offset)
    };
    let gap = offset.length() - radii.0 - radii.1;
    if gap > 0.0 {
        return Ok(Collision::separated(iso_a.rotate(normal), gap));
    }
    let manifold = side_by_side(&core_a, &core_b, radii).unwrap_or_else(|| {
        let mut one = Manifold::default();
        one.push(midway((pa, pb), normal, radii), -gap);
        one
    });
    Ok(Collision::touching(iso_a.rotate(normal), -gap, &manifold, &iso_a))
}

/// A unit direction square to both cores, for cores that meet: across them
/// where they cross at more than [`MEET`] rad (nearer parallel, rounding
/// turns their cross product), else square to whichever has a length, else
/// y; turned towards `offset`, what rounding left between their closest points.
fn square_to_both(a: &Segment, b: &Segment, offset: DVec3) -> DVec3 {
    let square_to = |s: &Segment| s.delta.try_normalize().map(|d| d.any_orthonormal_vector());
    let across = a.delta.cross(b.delta);
    let crossing = across.length() > MEET * a.delta.length() * b.delta.length();
    let n = crossing
        .then(|| across.normalize())
        .or_else(|| square_to(a))
        .or_else(|| square_to(b))
        .unwrap_or(DVec3::Y);
    if n.dot(offset) < 0.0 { -n } else { n }
}

/// The point midway between the surfaces of two capsules of `radii` whose
/// cores' points `(pa, pb)` face each other along `normal`.
fn midway((pa, pb): (DVec3, DVec3), normal: DVec3, (ra, rb): (f64, f64)) -> DVec3 {
    (pa + normal * ra + pb - normal * rb) * 0.5
}

/// The two-point manifold of nearly parallel cores: the stretch of A's core
/// that B's faces (B's ends projected on A's line, clipped to A's ends), and
/// at each end of it, the point of A's core there and the nearest point of
/// B's, a contact point if they touch. `None` unless the cores are parallel
/// to [`PARALLEL_SINE`], the stretch has a length and both ends touch.
fn side_by_side(a: &Segment, b: &Segment, radii: (f64, f64)) -> Option<Manifold> {
    let (ua, ub) = (a.delta.try_normalize()?, b.delta.try_normalize()?);
    if ua.cross(ub).length() > PARALLEL_SINE {
        return None;
    }
    let length = a.delta.length();
    let along = |p: DVec3| (p - a.start).dot(ua) / length;
    let (t0, t1) = (along(b.start), along(b.end()));
    let (lo, hi) = (t0.min(t1).max(0.0), t0.max(t1).min(1.0));
    if lo >= hi {
        return None;
    }
    let reach = radii.0 + radii.1;
    let slop = END_SLOP * (length + b.delta.length() + reach);
    let mut manifold = Manifold::default();
    for t in [lo, hi] {
        let pa = a.at(t);
        let pb = b.at(b.nearest_to(pa));
        let offset = pb - pa;
        let depth = reach - offset.length();
        if depth < -slop {
            return None;
        }
        let normal = offset.try_normalize().unwrap_or_else(|| square_to_both(a, b, offset));
        manifold.push(midway((pa, pb), normal, radii), depth);
    }
    Some(manifold)
}
