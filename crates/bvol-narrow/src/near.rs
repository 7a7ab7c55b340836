//! Contacts within a margin: pairs that touch, and pairs apart by no more
//! than a distance, with their closest points (what a solver's speculative
//! contacts need, parry's and rapier's prediction distance).

use crate::gjk::{Core, closest_points};
use crate::isometry::DIsometry3;
use crate::{Collision, Contact, ContactPoint, NarrowError, Part, Pose, WarmStart, collide_parts};

/// How parts `a` and `b` touch, or how near they are when apart by at most
/// `margin`: `None` when they are farther apart. The normal points from `a`
/// to `b`. A touching pair's contact is [`collide_parts`]'s; an apart one's
/// has a negative depth, minus their distance, and one point midway between
/// their closest points (which are that point less and plus half the
/// distance along the normal), its depth the contact's.
///
/// The distance is GJK's (Gilbert, Johnson & Keerthi 1988) on the parts'
/// cores (a hull, a ball's centre, a capsule's segment), less their radii,
/// run only when the separating-axis test's gap (a lower bound of the
/// distance) is within the margin.
///
/// Errors: a `margin` that is negative or not finite is
/// [`NarrowError::BadMargin`]; the rest as [`collide_parts`]'.
///
/// ```
/// use bvol_narrow::{Part, Polyhedron, Pose, WarmStart, contact_within};
/// use bvol_narrow::HullPart;
/// use glam::{Quat, Vec3};
/// let cube = Part::Hull(Box::new(HullPart::from_points(&[
///     Vec3::new(-1.0, -1.0, -1.0), Vec3::new(1.0, -1.0, -1.0),
///     Vec3::new(-1.0, 1.0, -1.0), Vec3::new(1.0, 1.0, -1.0),
///     Vec3::new(-1.0, -1.0, 1.0), Vec3::new(1.0, -1.0, 1.0),
///     Vec3::new(-1.0, 1.0, 1.0), Vec3::new(1.0, 1.0, 1.0),
/// ])?));
/// let above = Pose::new(Vec3::new(0.5, 2.1, 0.0), Quat::IDENTITY);
/// let mut warm = WarmStart::default();
/// let near = contact_within(&cube, &Pose::IDENTITY, &cube, &above, 0.2, &mut warm)?;
/// let near = near.expect("0.1 apart, within 0.2");
/// assert!(!near.is_touching() && (near.depth + 0.1).abs() < 1e-6);
/// assert!((near.normal - Vec3::Y).length() < 1e-6);
/// assert!((near.points()[0].position.y - 1.05).abs() < 1e-6);
/// assert!(contact_within(&cube, &Pose::IDENTITY, &cube, &above, 0.05, &mut warm)?.is_none());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn contact_within(
    a: &Part,
    pose_a: &Pose,
    b: &Part,
    pose_b: &Pose,
    margin: f32,
    warm: &mut WarmStart,
) -> Result<Option<Contact>, NarrowError> {
    if !(margin.is_finite() && margin >= 0.0) {
        return Err(NarrowError::BadMargin);
    }
    let (axis, lower) = match collide_parts(a, pose_a, b, pose_b, warm)? {
        Collision::Touching(contact) => return Ok(Some(contact)),
        Collision::Separated { axis, distance } => (axis.as_dvec3(), f64::from(distance)),
    };
    if lower > f64::from(margin) {
        return Ok(None);
    }
    // The poses passed `collide_parts`' checks. In A's space, as the pair
    // tests work.
    let to_world = DIsometry3::of_checked(pose_a);
    let rel = to_world.relative(&DIsometry3::of_checked(pose_b));
    let (core_a, radius_a, size_a) = core(a, DIsometry3::IDENTITY);
    let (core_b, radius_b, size_b) = core(b, rel);
    let local_axis = to_world.unrotate(axis);
    let (normal, distance, midway) =
        match closest_points(&core_a, &core_b, size_a.max(size_b), local_axis) {
            Some((pa, pb)) => {
                let offset = pb - pa;
                let normal = offset.try_normalize().unwrap_or(local_axis);
                let distance = offset.length() - radius_a - radius_b;
                let (on_a, on_b) = (pa + normal * radius_a, pb - normal * radius_b);
                (normal, distance.max(lower), (on_a + on_b) * 0.5)
            }
            // Apart by a gap too small for the search to see: the test's axis
            // and gap, at A's point farthest along it.
            None => {
                let on_a = a.support(local_axis.as_vec3()).as_dvec3();
                (local_axis, lower, on_a + local_axis * (lower * 0.5))
            }
        };
    if distance > f64::from(margin) {
        return Ok(None);
    }
    let depth = -(distance as f32).max(f32::MIN_POSITIVE);
    let point = ContactPoint { position: to_world.apply(midway).as_vec3(), depth };
    Ok(Some(Contact::new(to_world.rotate(normal).as_vec3(), depth, &[point])))
}

/// A part's core placed by `to` into the space the search works in, its
/// radius (what the part adds round the core), and a length it is of the
/// order of, for relative tolerances.
fn core(part: &Part, to: DIsometry3) -> (Core<'_>, f64, f64) {
    match part {
        Part::Hull(hull) => (Core::Hull(&hull.polyhedron, to), 0.0, hull.polyhedron.size),
        Part::Ball(ball) => {
            let radius = f64::from(ball.radius);
            (Core::Point(to.apply(ball.center.as_dvec3())), radius, radius)
        }
        Part::Capsule(c) => {
            let (radius, half) = (f64::from(c.radius), f64::from(c.half_height));
            (Core::Segment(c.core(&to)), radius, radius + half)
        }
    }
}
