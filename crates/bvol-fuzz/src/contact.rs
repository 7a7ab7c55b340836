//! Two parts and their poses, through the pair table.

use arbitrary::{Result, Unstructured};
use bvol::glam::{DVec3, Vec3};
use bvol::narrow::{Collision, Pose, WarmStart, collide_parts, contact_within};
use bvol::{MAX_COORDINATE, Part, ROTATION_LENGTH_SQUARED, Shape};

use crate::checks::{finite, one_line_error, unit};
use crate::floats;

/// Most points of a hull part.
const MAX_HULL_POINTS: usize = 24;

/// Tests two parts `data` spells (boxes, balls, capsules, hulls of any
/// points) at any poses, both ways round. An error is one line; an answer
/// is finite, agrees with the parts' bounding spheres (apart beyond them
/// means separated), and the other way round gives the same verdict unless
/// the two are within rounding of touching; a touching pair's placed
/// spheres and boxes (the World's culling tests) meet; within a margin
/// the input's next float gives, the contact agrees (see [`within`]); and
/// reusing features at a tolerance it gives, the answer agrees with a cold
/// call's after a nudge (see [`reused`]).
pub fn run(data: &[u8]) {
    let u = &mut Unstructured::new(data);
    let (Ok(a), Ok(b)) = (shape(u), shape(u)) else { return };
    let (Ok(pose_a), Ok(pose_b)) = (pose(u), pose(u)) else { return };
    let (a, b) = match (a, b) {
        (Ok(a), Ok(b)) => (a, b),
        (Err(e), _) | (_, Err(e)) => return one_line_error(&e.to_string(), None),
    };
    let (part_a, part_b) = (&a.parts()[0], &b.parts()[0]);
    let forward = match collide_parts(part_a, &pose_a, part_b, &pose_b, &mut WarmStart::default()) {
        Ok(c) => c,
        Err(e) => return one_line_error(&e.to_string(), None),
    };
    let backward = collide_parts(part_b, &pose_b, part_a, &pose_a, &mut WarmStart::default())
        .expect("the same pair the other way round is accepted");
    let placed = [Placed::new(&a, part_a, &pose_a), Placed::new(&b, part_b, &pose_b)];
    check(&forward, &placed);
    check(&backward, &[placed[1], placed[0]]);
    if let Ok(margin) = floats::float(u) {
        within(part_a, &pose_a, part_b, &pose_b, margin, &forward, &placed);
    }
    if let (Ok(tolerance), Ok(nudge)) = (floats::float(u), floats::float(u)) {
        reused((part_a, &pose_a), (part_b, &pose_b), tolerance, nudge, &placed);
    }
    if let Collision::Touching(_) = forward {
        bounds_meet(&a, &pose_a, &b, &pose_b);
    }
    let slack = 1e-4 * placed[0].scale.max(placed[1].scale);
    if depth(&forward) > slack || depth(&forward) < -slack {
        let same = matches!(
            (&forward, &backward),
            (Collision::Separated { .. }, Collision::Separated { .. })
                | (Collision::Touching(_), Collision::Touching(_))
        );
        assert!(
            same || depth(&backward).abs() <= slack,
            "{forward:?} one way, {backward:?} the other"
        );
    }
}

/// An answer's depth, signed: a touching pair's depth, or minus an apart
/// pair's distance.
fn depth(c: &Collision) -> f64 {
    match c {
        Collision::Separated { distance, .. } => -f64::from(*distance),
        Collision::Touching(contact) => f64::from(contact.depth),
    }
}

/// A part's bounding sphere and a point of it, in the world, in f64.
#[derive(Clone, Copy)]
struct Placed {
    center: DVec3,
    radius: f64,
    point: DVec3,
    /// Its size and distance from the origin: what rounding scales with.
    scale: f64,
}

impl Placed {
    fn new(shape: &Shape, part: &Part, pose: &Pose) -> Placed {
        let place = |p: Vec3| pose.rotation_f64() * p.as_dvec3() + pose.position.as_dvec3();
        let (center, radius) = (place(shape.sphere().center), shape.sphere().radius as f64);
        let scale = radius + center.abs().max_element();
        Placed { center, radius, point: place(part.support(Vec3::X)), scale }
    }
}

fn check(c: &Collision, [a, b]: &[Placed; 2]) {
    let gap = a.center.distance(b.center) - a.radius - b.radius;
    let slack = 1e-4 * a.scale.max(b.scale);
    match c {
        Collision::Separated { axis, distance } => {
            unit(*axis, "a separating axis");
            assert!(distance.is_finite() && *distance > 0.0, "distance {distance}");
            let bound = a.point.distance(b.point) + slack;
            assert!((*distance as f64) <= bound, "distance {distance} past two points' {bound}");
        }
        Collision::Touching(contact) => {
            assert!(gap <= slack, "touching, but the bounding spheres are {gap} apart");
            unit(contact.normal, "a contact normal");
            assert!(contact.depth.is_finite() && contact.depth >= 0.0, "depth {}", contact.depth);
            assert!(!contact.points().is_empty(), "a contact without points");
            for p in contact.points() {
                finite(p.position, "a contact point");
                assert!(p.depth.is_finite() && p.depth >= 0.0, "point depth {}", p.depth);
                let reach = |s: &Placed| s.radius + contact.depth as f64 + slack;
                let at = p.position.as_dvec3();
                assert!(at.distance(a.center) <= reach(a), "contact point {at} far from A");
                assert!(at.distance(b.center) <= reach(b), "contact point {at} far from B");
            }
        }
    }
}

/// The pair within `margin` (any float): a one-line error for a bad one;
/// else a touching pair's contact as the pair table gave it, and an apart
/// pair's, if any, within the margin and no nearer than the separating
/// gap the pair table measured.
fn within(
    a: &Part,
    pose_a: &Pose,
    b: &Part,
    pose_b: &Pose,
    margin: f32,
    forward: &Collision,
    placed: &[Placed; 2],
) {
    let near = match contact_within(a, pose_a, b, pose_b, margin, &mut WarmStart::default()) {
        Ok(near) => near,
        Err(e) => return one_line_error(&e.to_string(), None),
    };
    let slack = 1e-4 * placed[0].scale.max(placed[1].scale);
    match (forward, near) {
        (Collision::Touching(c), near) => {
            assert_eq!(near.as_ref(), Some(c), "a touching pair within a margin");
        }
        (Collision::Separated { distance, .. }, Some(c)) => {
            unit(c.normal, "a near contact's normal");
            let d = -f64::from(c.depth);
            assert!(d > 0.0 && d <= f64::from(margin), "near contact at {d}, margin {margin}");
            let gap = f64::from(*distance);
            assert!(d >= gap - slack, "a near contact at {d}, nearer than the gap {gap}");
            c.points().iter().for_each(|p| finite(p.position, "a near contact's point"));
        }
        (Collision::Separated { .. }, None) => {}
    }
}

/// The pair through a warm start reusing touching pairs' features at
/// `tolerance` (any float): a one-line error for a bad one; else, with B
/// then moved along x by `nudge` times its bounding radius (any float), the
/// answer agrees with a cold call's there: the same verdict unless within
/// rounding of touching, and a depth within the reuse's bound of the cold
/// one (each within `2e-5 + 2 * tolerance` of the least, of a size taken
/// generously as the larger bounding diameter).
fn reused(
    (a, pose_a): (&Part, &Pose),
    (b, pose_b): (&Part, &Pose),
    tolerance: f32,
    nudge: f32,
    placed: &[Placed; 2],
) {
    let mut warm = match WarmStart::reusing(tolerance) {
        Ok(warm) => warm,
        Err(e) => return one_line_error(&e.to_string(), None),
    };
    collide_parts(a, pose_a, b, pose_b, &mut warm).expect("accepted above");
    let moved =
        Pose::new(pose_b.position + Vec3::X * nudge * placed[1].radius as f32, pose_b.rotation);
    let Ok(cold) = collide_parts(a, pose_a, b, &moved, &mut WarmStart::default()) else { return };
    let got = collide_parts(a, pose_a, b, &moved, &mut warm).expect("the cold call took it");
    let slack = 1e-4 * placed[0].scale.max(placed[1].scale);
    if depth(&cold).abs() > slack {
        assert_eq!(got.is_touching(), cold.is_touching(), "reused {got:?}, cold {cold:?}");
    }
    if got.is_touching() && cold.is_touching() {
        let size = 2.0 * placed[0].radius.max(placed[1].radius);
        let bound = (4e-5 + 2.0 * f64::from(tolerance)) * size + slack;
        let off = (depth(&got) - depth(&cold)).abs();
        assert!(off <= bound, "reused depth {got:?} off the cold {cold:?} by {off}");
    }
}

/// The culling tests a World runs before the pair table: for a touching
/// pair, at poses a World takes, the placed spheres and boxes must meet
/// (else the pair would be lost before it is tested).
fn bounds_meet(a: &Shape, pose_a: &Pose, b: &Shape, pose_b: &Pose) {
    let placeable = |p: &Pose| {
        p.position.abs().max_element() <= MAX_COORDINATE
            && ROTATION_LENGTH_SQUARED.contains(&p.rotation.length_squared())
    };
    if !(placeable(pose_a) && placeable(pose_b)) {
        return;
    }
    let (sa, sb) = (a.sphere().transformed(pose_a), b.sphere().transformed(pose_b));
    assert!(sa.overlaps(&sb), "touching, but the placed spheres {sa:?} and {sb:?} are apart");
    let (oa, ob) = (a.obb().transformed(pose_a), b.obb().transformed(pose_b));
    assert!(oa.overlaps(&ob), "touching, but the placed boxes {oa:?} and {ob:?} are apart");
}

/// A box, ball, capsule or hull, of any size: the constructor's answer.
fn shape(u: &mut Unstructured) -> Result<std::result::Result<Shape, bvol::ShapeError>> {
    Ok(match u.int_in_range(0u8..=3)? {
        0 => Shape::cuboid(Vec3::new(floats::size(u)?, floats::size(u)?, floats::size(u)?)),
        1 => Shape::ball(floats::size(u)?),
        2 => Shape::capsule(floats::size(u)?, floats::size(u)?),
        _ => {
            let n = u.int_in_range(1..=MAX_HULL_POINTS)?;
            let scale = floats::size(u)?;
            let points =
                (0..n).map(|_| Ok(floats::position(u)? * scale)).collect::<Result<Vec<Vec3>>>()?;
            Shape::convex(&points)
        }
    })
}

fn pose(u: &mut Unstructured) -> Result<Pose> {
    Ok(Pose::new(floats::position(u)?, floats::rotation(u)?))
}
