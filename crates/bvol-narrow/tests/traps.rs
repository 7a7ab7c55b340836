//! Traps for the narrow phase, each against an exact or independent answer:
//! faces exactly touching, a box resting on a box (its manifold's corners
//! known), exactly and nearly parallel edges, deep penetration, identical
//! poses, tiny and huge scales, warm starts that must not change an answer,
//! bad input, boxes against hulls of the same boxes, and spheres against the
//! exact closest point.
//!
//! The independent reference is [`brute_force_sat`]: the exact separating-axis
//! test in f64 over every face normal of both hulls and every cross product of
//! an edge of each, with every vertex projected. The bodies are the f32 input
//! taken as exact: local f32 points, the f32 position, the f32 quaternion
//! normalised in f64 (the model bvol-narrow computes with too).
//!
//! Where bvol-narrow deliberately differs from parry3d 0.31.1 (see
//! shared/PEER_NOTES.md), the test says so: identical poses give the true
//! depth (parry: 0), pairs at 1e-3 scale get their contact (parry: none), and
//! the verdict is exact near touching where parry has a band of about 1e-4.

mod common;

use bvol_narrow::{
    Body, Capsule, Collision, Contact, FLAT_THICKNESS, HullPart, NarrowError, Part, Polyhedron,
    Pose, ShapeError, WarmStart, capsule_capsule, capsule_hull, capsule_sphere, hull_hull, obb_obb,
    sphere_hull, sphere_obb, sphere_sphere,
};
use bvol_volumes::{ConvexHull, Obb, Sphere};
use common::random_rotation;
use common::reference::closest_on_triangle;
use glam::{DMat3, DVec3, Mat3, Quat, Vec3};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

/// Near touching, the f32 input's rounding (about 1e-7 of the size) and the
/// tolerances of the hull (coplanar faces merged within about 4e-7) make the
/// truth of "apart or touching" a matter of those roundings. Verdicts are
/// compared only where the exact f64 reference puts the pair farther than
/// this, relative to the pair's size, from touching.
const BAND: f64 = 1e-5;

/// Slack of the contact checks, relative to the pair's size plus its distance
/// from the origin: f32 output, hull tolerance, f64 rounding, with room.
const TOL: f64 = 2e-6;
/// How much shallower than the least penetration a preferred face or edge
/// may be, relative to the size (`hull_hull`'s docs).
const PREFER: f64 = 2e-5;

// ---------------------------------------------------------------------------
// The independent reference: exact f64 brute-force SAT.

/// A hull placed in the world, in f64: what the brute-force reference reads.
struct WorldHull {
    vertices: Vec<DVec3>,
    /// Unit outward face normals with their offsets (the greatest projection of a vertex).
    planes: Vec<(DVec3, f64)>,
    edges: Vec<DVec3>,
    /// Half the diagonal of the local bounding box.
    size: f64,
}

/// The pose's rotation, its f32 quaternion normalised in f64.
fn rotation_f64(q: Quat) -> DMat3 {
    DMat3::from_quat(q.as_dquat().normalize())
}

/// The hull of `points` placed by `pose`, exactly in f64.
fn world_hull(points: &[Vec3], pose: &Pose) -> WorldHull {
    let hull = ConvexHull::new(points).expect("test points are finite");
    let r = rotation_f64(pose.rotation);
    let t = pose.position.as_dvec3();
    let vertices: Vec<DVec3> = hull.vertices().iter().map(|v| r * v.as_dvec3() + t).collect();
    let planes = (0..hull.face_count())
        .map(|f| {
            let n = r * hull.face_normal(f);
            (n, vertices.iter().map(|v| n.dot(*v)).fold(f64::NEG_INFINITY, f64::max))
        })
        .collect();
    let at = |i: u32| hull.vertices()[i as usize].as_dvec3();
    let edges = hull.edges().map(|[a, b]| r * (at(b) - at(a))).collect();
    let (lo, hi) =
        hull.vertices().iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), v| {
            (l.min(v.as_dvec3()), h.max(v.as_dvec3()))
        });
    WorldHull { vertices, planes, edges, size: ((hi - lo) * 0.5).length() }
}

/// Least and greatest projection of the points on `axis`.
fn project(points: &[DVec3], axis: DVec3) -> (f64, f64) {
    points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
        let d = axis.dot(*p);
        (lo.min(d), hi.max(d))
    })
}

/// The gap from A to B along unit `axis`: `min_B - max_A`.
fn gap_along(a: &WorldHull, b: &WorldHull, axis: DVec3) -> f64 {
    project(&b.vertices, axis).0 - project(&a.vertices, axis).1
}

/// Exact brute-force separating-axis test in f64: the greatest separation
/// over every face normal of both hulls and every non-zero cross product of an
/// edge of each, each axis tried both ways, every vertex projected. Positive:
/// they are apart, by at least that much. Otherwise minus the least overlap
/// over those axes, which is the penetration depth (the minimum translation
/// distance: the Minkowski difference's face normals are all among them, and
/// any direction's overlap is at least the depth).
fn brute_force_sat(a: &WorldHull, b: &WorldHull) -> f64 {
    let mut best = f64::NEG_INFINITY;
    let mut test = |axis: DVec3| {
        let (lo_a, hi_a) = project(&a.vertices, axis);
        let (lo_b, hi_b) = project(&b.vertices, axis);
        best = best.max((lo_b - hi_a).max(lo_a - hi_b));
    };
    a.planes.iter().chain(&b.planes).for_each(|&(n, _)| test(n));
    for ea in &a.edges {
        for eb in &b.edges {
            let c = ea.cross(*eb);
            if c != DVec3::ZERO {
                test(c.normalize());
            }
        }
    }
    best
}

/// Signed distance of `p` outside the hull's face planes (the greatest): at
/// most its distance to the hull, and `<= 0` inside.
fn outside(hull: &WorldHull, p: DVec3) -> f64 {
    hull.planes.iter().map(|&(n, o)| n.dot(p) - o).fold(f64::NEG_INFINITY, f64::max)
}

/// The length a pair's tolerances scale with: its size plus how far from the
/// origin it is (f32 output rounds relative to that).
fn reach(a: &WorldHull, b: &WorldHull) -> f64 {
    let far =
        a.vertices.iter().chain(&b.vertices).map(|v| v.abs().max_element()).fold(0.0, f64::max);
    a.size.max(b.size) + far
}

/// Checks a hull-hull answer against the brute-force reference: the verdict
/// outside the band, and for any verdict that it is self-consistent with the
/// exact geometry (the separating axis really separates by the distance; the
/// normal's overlap is the depth, at least the true depth and within the
/// face-preference tolerance of it; every contact point is within half the
/// depth of both hulls). Returns the reference separation.
fn check_against_brute(hit: &Collision, a: &WorldHull, b: &WorldHull, what: &str) -> f64 {
    let truth = brute_force_sat(a, b);
    let size = a.size.max(b.size);
    let tol = TOL * reach(a, b);
    match hit {
        Collision::Separated { axis, distance } => {
            assert!(
                truth > -BAND * size,
                "{what}: separated, but the reference overlaps by {}",
                -truth
            );
            assert!((axis.length() - 1.0).abs() < 1e-6, "{what}: axis {axis} not unit");
            let gap = gap_along(a, b, axis.as_dvec3());
            assert!(*distance > 0.0, "{what}: distance {distance}");
            assert!((gap - f64::from(*distance)).abs() <= tol, "{what}: gap {gap} vs {distance}");
            // Every axis's gap is at most the distance, which is at most any
            // two vertices' (the reference's greatest gap over its finite axis
            // set is only a lower bound of the distance).
            let closest = a
                .vertices
                .iter()
                .flat_map(|p| b.vertices.iter().map(move |q| p.distance(*q)))
                .fold(f64::INFINITY, f64::min);
            assert!(f64::from(*distance) <= closest + tol, "{what}: {distance} beyond {closest}");
        }
        Collision::Touching(c) => {
            assert!(truth < BAND * size, "{what}: touching, but the reference is apart by {truth}");
            check_contact(c, a, b, -truth.min(0.0), tol, what);
        }
    }
    truth
}

/// A contact against the geometry and the true depth `mtd`.
fn check_contact(c: &Contact, a: &WorldHull, b: &WorldHull, mtd: f64, tol: f64, what: &str) {
    let n = c.normal.as_dvec3();
    let depth = f64::from(c.depth);
    assert!((n.length() - 1.0).abs() < 1e-6, "{what}: normal {n} not unit");
    assert!(depth >= 0.0, "{what}: depth {depth}");
    // The depth is the overlap along the normal it comes with.
    let overlap = -gap_along(a, b, n);
    assert!(
        (overlap - depth).abs() <= tol,
        "{what}: overlap {overlap} along the normal, depth {depth}"
    );
    // At least the least overlap over all axes, and at most the preference's
    // slack (2e-5 of the size) above it.
    assert!(depth >= mtd - tol, "{what}: depth {depth} below the true depth {mtd}");
    let size = a.size.max(b.size);
    assert!(
        depth <= mtd + PREFER * size + tol,
        "{what}: depth {depth} above the true depth {mtd} by {} of the size",
        (depth - mtd) / size
    );
    assert!(!c.points().is_empty() && c.points().len() <= 4, "{what}: {} points", c.points().len());
    for p in c.points() {
        let q = p.position.as_dvec3();
        let d = f64::from(p.depth);
        assert!(d >= 0.0 && d <= depth + tol, "{what}: point depth {d}, contact depth {depth}");
        assert!(
            outside(a, q) <= depth / 2.0 + tol,
            "{what}: point {q} outside A by {}",
            outside(a, q)
        );
        assert!(
            outside(b, q) <= depth / 2.0 + tol,
            "{what}: point {q} outside B by {}",
            outside(b, q)
        );
    }
}

// ---------------------------------------------------------------------------
// Shapes and poses.

/// The eight corners of the box `[-h, h]`.
fn corners(h: Vec3) -> Vec<Vec3> {
    (0..8)
        .map(|i| {
            let s = |bit: u32, v: f32| if i & bit == 0 { -v } else { v };
            Vec3::new(s(1, h.x), s(2, h.y), s(4, h.z))
        })
        .collect()
}

/// `n` random points in the ball of radius `r` (rejection sampled).
fn cloud(rng: &mut Xoshiro256PlusPlus, n: usize, r: f32) -> Vec<Vec3> {
    let mut points = Vec::with_capacity(n);
    while points.len() < n {
        let p = Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - Vec3::ONE;
        if p.length_squared() <= 1.0 {
            points.push(p * r);
        }
    }
    points
}

/// A random vector in the cube `[-r, r]^3`.
fn random_vec(rng: &mut Xoshiro256PlusPlus, r: f32) -> Vec3 {
    (Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - Vec3::ONE) * r
}

/// Two hulls of point sets, both ways: bvol-narrow's and the reference's.
struct Pair {
    a: Polyhedron,
    b: Polyhedron,
    points_a: Vec<Vec3>,
    points_b: Vec<Vec3>,
}

impl Pair {
    fn new(points_a: Vec<Vec3>, points_b: Vec<Vec3>) -> Pair {
        let a = Polyhedron::from_points(&points_a).expect("solid test shape");
        let b = Polyhedron::from_points(&points_b).expect("solid test shape");
        Pair { a, b, points_a, points_b }
    }

    fn boxes(ha: Vec3, hb: Vec3) -> Pair {
        Pair::new(corners(ha), corners(hb))
    }

    /// hull_hull from a fresh cache, and the reference hulls at the poses.
    fn collide(&self, pa: &Pose, pb: &Pose) -> (Collision, WorldHull, WorldHull) {
        let hit = hull_hull(&self.a, pa, &self.b, pb, &mut WarmStart::default()).expect("finite");
        (hit, world_hull(&self.points_a, pa), world_hull(&self.points_b, pb))
    }
}

fn at(x: f32, y: f32, z: f32) -> Pose {
    Pose::new(Vec3::new(x, y, z), Quat::IDENTITY)
}

fn contact(hit: &Collision, what: &str) -> Contact {
    *hit.contact().unwrap_or_else(|| panic!("{what}: expected touching, got {hit:?}"))
}

/// Whether every expected point has a contact point within `tol` (and the counts match).
fn assert_points(c: &Contact, expected: &[DVec3], tol: f64, what: &str) {
    assert_eq!(c.points().len(), expected.len(), "{what}: points {:?}", c.points());
    for e in expected {
        let near = c
            .points()
            .iter()
            .map(|p| p.position.as_dvec3().distance(*e))
            .fold(f64::INFINITY, f64::min);
        assert!(near <= tol, "{what}: no contact point near {e} ({:?})", c.points());
    }
}

// ---------------------------------------------------------------------------
// Faces exactly touching.

/// Boxes whose faces exactly touch (exact in f32 and f64) touch at depth 0,
/// along the face normal exactly, with the corners of the faces' overlap.
#[test]
fn face_touching_boxes_touch_at_zero_depth() {
    let (ha, hb) = (Vec3::new(1.0, 0.5, 2.0), Vec3::new(0.5, 1.0, 0.25));
    let pair = Pair::boxes(ha, hb);
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            // B beside A along the axis, and shifted across it so that it overhangs A's face.
            let mut offset = Vec3::new(0.75, -0.25, 1.875);
            offset[axis] = sign * (ha[axis] + hb[axis]);
            let hit = pair.collide(&Pose::IDENTITY, &at(offset.x, offset.y, offset.z)).0;
            let what = format!("axis {axis} sign {sign}");
            let c = contact(&hit, &what);
            assert!(f64::from(c.depth) <= 1e-6 * 2.0, "{what}: depth {}", c.depth);
            let mut normal = Vec3::ZERO;
            normal[axis] = sign;
            assert_eq!(c.normal, normal, "{what}");
            // The overlap of the two faces, on the touching plane.
            let lo = (offset - hb).max(-ha).as_dvec3();
            let hi = (offset + hb).min(ha).as_dvec3();
            let plane = f64::from(sign * ha[axis]);
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let expected: Vec<DVec3> = (0..4)
                .map(|k| {
                    let mut p = DVec3::ZERO;
                    p[axis] = plane;
                    p[u] = if k & 1 == 0 { lo[u] } else { hi[u] };
                    p[v] = if k & 2 == 0 { lo[v] } else { hi[v] };
                    p
                })
                .collect();
            assert_points(&c, &expected, 1e-6, &what);
            assert!(c.points().iter().all(|p| p.depth == 0.0), "{what}: {:?}", c.points());
        }
    }
}

/// The same touching boxes turned together by random rotations: the f32
/// rounding of the placement leaves them within about 1e-7 of touching either
/// way; the answer must say so, with the normal along the turned face.
#[test]
fn turned_face_touching_boxes_are_within_rounding_of_touching() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
    let pair = Pair::boxes(Vec3::new(1.0, 0.5, 2.0), Vec3::new(0.5, 1.0, 0.25));
    for case in 0..200 {
        let q = random_rotation(&mut rng);
        let offset = Vec3::new(rng.random::<f32>() - 0.5, 1.5, rng.random::<f32>() - 0.5);
        let shift = random_vec(&mut rng, 10.0);
        let (pa, pb) = (Pose::new(shift, q), Pose::new(shift + q * offset, q));
        let (hit, wa, wb) = pair.collide(&pa, &pb);
        let what = format!("case {case}");
        let truth = check_against_brute(&hit, &wa, &wb, &what);
        assert!(truth.abs() < 1e-6 * reach(&wa, &wb), "{what}: reference {truth}");
        if let Collision::Touching(c) = hit {
            let up = (q * Vec3::Y).as_dvec3();
            assert!(c.normal.as_dvec3().distance(up) < 1e-6, "{what}: normal {} vs {up}", c.normal);
            assert_eq!(c.points().len(), 4, "{what}: {:?}", c.points());
        }
    }
}

// ---------------------------------------------------------------------------
// Resting contact.

/// A small box sunk 0.01 into a big one's top: normal +Y exactly, depth 0.01,
/// four points at the small box's bottom corners (inside the big top face),
/// each midway between the surfaces at depth 0.01; also with the small box
/// turned about the vertical by random angles, and with the boxes swapped.
#[test]
fn box_resting_on_box_has_the_four_corners() {
    let (big, small) = (Vec3::new(2.0, 0.5, 2.0), Vec3::new(0.5, 0.25, 0.5));
    let pair = Pair::boxes(big, small);
    let swapped = Pair::boxes(small, big);
    let sink = 0.01f32;
    let y = big.y + small.y - sink;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(2);
    for case in 0..100 {
        let angle = if case == 0 { 0.0 } else { rng.random::<f32>() * std::f32::consts::TAU };
        let q = Quat::from_rotation_y(angle);
        let centre = Vec3::new(0.3, y, -0.4);
        let top = Pose::new(centre, q);
        // The small box's bottom corners, exactly in f64, halfway down to the big top face.
        let r = rotation_f64(q);
        let expected: Vec<DVec3> = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
            .iter()
            .map(|&(sx, sz)| {
                let local = DVec3::new(sx * 0.5, -0.25, sz * 0.5);
                let p = r * local + centre.as_dvec3();
                DVec3::new(p.x, (p.y + f64::from(big.y)) / 2.0, p.z)
            })
            .collect();
        let depth = f64::from(big.y) - (f64::from(y) - 0.25);
        for (hit, normal, what) in [
            (pair.collide(&Pose::IDENTITY, &top).0, Vec3::Y, "big below as A"),
            (swapped.collide(&top, &Pose::IDENTITY).0, -Vec3::Y, "small on top as A"),
        ] {
            let what = format!("case {case} angle {angle}: {what}");
            let c = contact(&hit, &what);
            assert_eq!(c.normal, normal, "{what}");
            assert!(
                (f64::from(c.depth) - depth).abs() < 1e-6,
                "{what}: depth {} vs {depth}",
                c.depth
            );
            assert_points(&c, &expected, 1e-6, &what);
            for p in c.points() {
                assert!((f64::from(p.depth) - depth).abs() < 1e-6, "{what}: {p:?}");
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Parallel and nearly parallel edges.

/// Roof ridges: a box turned 45 degrees about X (ridge along X on top) and
/// another above it, ridge down, tilted by 0 or 1e-7..1e-3 radians about the
/// vertical (ridges nearly parallel) or about the other horizontal axis, or
/// crossed at random angles; gaps from deep overlap to just apart. The
/// verdict must match the exact f64 reference outside the band, and every
/// answer must be consistent with the exact geometry.
#[test]
fn parallel_and_nearly_parallel_edges_agree_with_brute_force_sat() {
    let h = Vec3::new(1.0, 0.5, 0.5);
    let pair = Pair::boxes(h, h);
    let ridge = (0.5f64 * 2f64.sqrt()) as f32; // height of the ridge over the centre
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
    let tilts = [0.0f32, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3];
    let gaps = [-1e-1f32, -1e-3, -1e-4, -2e-5, 2e-5, 1e-4, 1e-3, 1e-1];
    let mut compared = 0;
    for &tilt in &tilts {
        for &gap in &gaps {
            for about in [Vec3::Y, Vec3::Z, Vec3::X] {
                for k in 0..6 {
                    let turn = Quat::from_rotation_x(std::f32::consts::FRAC_PI_4);
                    let twist = Quat::from_axis_angle(about, if k % 2 == 0 { tilt } else { -tilt });
                    let along = if k < 2 { 0.0 } else { rng.random::<f32>() - 0.5 };
                    let pb = Pose::new(Vec3::new(along, 2.0 * ridge + gap, 0.0), twist * turn);
                    let (hit, wa, wb) = pair.collide(&Pose::new(Vec3::ZERO, turn), &pb);
                    let what = format!("tilt {tilt} about {about} gap {gap} k {k}");
                    let truth = check_against_brute(&hit, &wa, &wb, &what);
                    compared += usize::from(truth.abs() > BAND * wa.size);
                }
            }
        }
    }
    // Crossed ridges at random angles: an edge-edge contact.
    for case in 0..300 {
        let turn = Quat::from_rotation_x(std::f32::consts::FRAC_PI_4);
        let angle = rng.random::<f32>() * std::f32::consts::PI;
        let gap = (rng.random::<f32>() - 0.5) * 0.02;
        let pb =
            Pose::new(Vec3::new(0.0, 2.0 * ridge + gap, 0.0), Quat::from_rotation_y(angle) * turn);
        let (hit, wa, wb) = pair.collide(&Pose::new(Vec3::ZERO, turn), &pb);
        let what = format!("crossed ridges case {case} angle {angle} gap {gap}");
        let truth = check_against_brute(&hit, &wa, &wb, &what);
        compared += usize::from(truth.abs() > BAND * wa.size);
    }
    assert!(compared > 700, "only {compared} verdicts outside the band");
}

/// Random convex hulls (4 to 60 points, some boxes) at random poses, most of
/// them near each other: every answer against the exact reference.
#[test]
fn random_hull_pairs_agree_with_brute_force_sat() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(4);
    let mut counts = [0usize; 2];
    for case in 0..600 {
        let shape = |rng: &mut Xoshiro256PlusPlus| -> Vec<Vec3> {
            if rng.random::<f32>() < 0.25 {
                corners(Vec3::new(rng.random(), rng.random(), rng.random()) + 0.05)
            } else {
                let n = 4 + (rng.random::<u32>() % 57) as usize;
                cloud(rng, n, 1.0)
            }
        };
        let pair = Pair::new(shape(&mut rng), shape(&mut rng));
        let pa = Pose::new(random_vec(&mut rng, 1.0), random_rotation(&mut rng));
        let pb = Pose::new(pa.position + random_vec(&mut rng, 1.5), random_rotation(&mut rng));
        let (hit, wa, wb) = pair.collide(&pa, &pb);
        check_against_brute(&hit, &wa, &wb, &format!("case {case}"));
        counts[usize::from(hit.is_touching())] += 1;
    }
    assert!(counts[0] > 100 && counts[1] > 100, "apart/touching {counts:?}");
}

/// Random hull pairs slid along a random direction to just touching (found
/// by bisection on the exact reference), then moved apart or together by 3e-5
/// to 1e-2 of their size: the verdict must match the reference on every
/// side of touching, outside the band.
#[test]
fn near_touching_pairs_agree_with_brute_force_sat() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(14);
    let mut compared = [0usize; 2];
    for case in 0..120 {
        let n = 4 + (rng.random::<u32>() % 24) as usize;
        let points_a =
            if case % 4 == 0 { corners(Vec3::new(0.7, 0.2, 0.5)) } else { cloud(&mut rng, n, 1.0) };
        let pair = Pair::new(points_a, cloud(&mut rng, 12, 0.6));
        let pa = Pose::new(random_vec(&mut rng, 1.0), random_rotation(&mut rng));
        let qb = random_rotation(&mut rng);
        let u = (random_rotation(&mut rng) * Vec3::X).as_dvec3();
        let wa = world_hull(&pair.points_a, &pa);
        let at = |t: f64| Pose::new((pa.position.as_dvec3() + u * t).as_vec3(), qb);
        // Apart at 4, overlapping at 0: bisect the exact separation's sign.
        let (mut lo, mut hi) = (0.0, 4.0);
        for _ in 0..40 {
            let mid = (lo + hi) / 2.0;
            if brute_force_sat(&wa, &world_hull(&pair.points_b, &at(mid))) > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let size = wa.size.max(world_hull(&pair.points_b, &Pose::IDENTITY).size);
        for step in [-1e-2, -1e-3, -1e-4, -3e-5, 3e-5, 1e-4, 1e-3, 1e-2] {
            let pb = at(hi + step * size);
            let (hit, wa, wb) = pair.collide(&pa, &pb);
            let truth = check_against_brute(&hit, &wa, &wb, &format!("case {case} step {step}"));
            if truth.abs() > BAND * size {
                compared[usize::from(hit.is_touching())] += 1;
            }
        }
    }
    assert!(compared[0] > 300 && compared[1] > 300, "apart/touching compared {compared:?}");
}

/// The preference for faces over edges and for A's faces over B's picks a
/// feature at most its slack, 2e-5 of the size, shallower than the least
/// penetration (`hull_hull`'s docs). Its worst case: a 2 x 2 x 0.02 slab at
/// the identity under each mesh's hull (radius 1) turned at random and
/// resting on it within 1e-4 of touching, where the slab's top face, the
/// hull's faces and their edge pairs are all nearly tied.
#[test]
fn a_resting_contact_is_within_the_preference_of_the_least_depth() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(27);
    let slab = corners(Vec3::new(1.0, 0.01, 1.0));
    let mut worst: f64 = 0.0;
    for name in common::shapes::MESHES {
        let hull = common::shapes::mesh_hull(name, 1.0).points;
        let pair = Pair::new(slab.clone(), hull.clone());
        for case in 0..40 {
            let q = random_rotation(&mut rng);
            let lowest = hull.iter().map(|&p| (q * p).y).fold(f32::INFINITY, f32::min);
            let sunk = -1e-6 + 1e-4 * rng.random::<f32>();
            let (x, z) = (rng.random::<f32>() - 0.5, rng.random::<f32>() - 0.5);
            let pb = Pose::new(Vec3::new(x, 0.01 - lowest - sunk, z), q);
            let (hit, wa, wb) = pair.collide(&Pose::IDENTITY, &pb);
            let what = format!("{name} case {case}");
            let truth = check_against_brute(&hit, &wa, &wb, &what);
            if let (Some(c), true) = (hit.contact(), truth < 0.0) {
                let size = wa.size.max(wb.size);
                worst = worst.max((f64::from(c.depth) + truth) / size);
            }
        }
    }
    assert!(worst > 0.0, "no contact deeper than the least: the preference was never tried");
}

// ---------------------------------------------------------------------------
// Deep penetration, identical poses, scales.

/// A small cube mostly inside a big one: the depth is the exact minimal
/// translation (0.65 out through the big cube's +X face), with the small
/// cube's -X face corners as the points, halfway to that face.
#[test]
fn deep_penetration_depth_is_the_minimal_translation() {
    let pair = Pair::boxes(Vec3::ONE, Vec3::splat(0.25));
    let (hit, wa, wb) = pair.collide(&Pose::IDENTITY, &at(0.6, 0.0, 0.0));
    let c = contact(&hit, "deep");
    assert_eq!(c.normal, Vec3::X);
    assert!((c.depth - 0.65).abs() < 1e-6, "depth {}", c.depth);
    assert!((-brute_force_sat(&wa, &wb) - 0.65).abs() < 1e-7);
    let expected: Vec<DVec3> = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
        .iter()
        .map(|&(sy, sz)| DVec3::new((0.35 + 1.0) / 2.0, sy * 0.25, sz * 0.25))
        .collect();
    assert_points(&c, &expected, 1e-6, "deep");
    // Turned and moved together: the same depth, along the turned +X.
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    for case in 0..100 {
        let q = random_rotation(&mut rng);
        let shift = random_vec(&mut rng, 5.0);
        let pb = Pose::new(shift + q * Vec3::new(0.6, 0.0, 0.0), q);
        let (hit, wa, wb) = pair.collide(&Pose::new(shift, q), &pb);
        let what = format!("deep case {case}");
        let c = contact(&hit, &what);
        assert!((c.depth - 0.65).abs() < 1e-5, "{what}: depth {}", c.depth);
        assert!(c.normal.distance(q * Vec3::X) < 1e-5, "{what}: normal {}", c.normal);
        check_against_brute(&hit, &wa, &wb, &what);
    }
}

/// Two unit cubes at the same pose overlap completely: depth 1, the true
/// minimal translation, along one of their face normals. (parry3d 0.31.1
/// answers depth 0 here; see shared/PEER_NOTES.md.) A slab on a slab at the
/// same pose: its thickness.
#[test]
fn identical_poses_give_the_full_depth() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(6);
    for (h, depth) in [(Vec3::splat(0.5), 1.0f32), (Vec3::new(1.0, 0.01, 1.0), 0.02)] {
        let pair = Pair::boxes(h, h);
        for case in 0..50 {
            let pose = if case == 0 {
                Pose::IDENTITY
            } else {
                Pose::new(random_vec(&mut rng, 100.0), random_rotation(&mut rng))
            };
            let (hit, wa, wb) = pair.collide(&pose, &pose);
            let what = format!("half {h} case {case}");
            let c = contact(&hit, &what);
            assert!((c.depth - depth).abs() < 1e-5 * depth.max(1.0), "{what}: depth {}", c.depth);
            let faces = [Vec3::X, Vec3::Y, Vec3::Z].map(|e| pose.rotation * e);
            assert!(
                faces
                    .iter()
                    .any(|f| c.normal.abs_diff_eq(*f, 1e-5) || c.normal.abs_diff_eq(-*f, 1e-5)),
                "{what}: normal {} not a face normal",
                c.normal
            );
            check_against_brute(&hit, &wa, &wb, &what);
        }
    }
}

/// The same pairs at scale 1e-3, 1 and 1e3 (shapes and placements scaled):
/// the same verdicts, and distances, depths and points scaled, normals equal.
/// (parry3d 0.31.1 returned no contact for thousands of intersecting pairs at
/// 1e-3 scale; see shared/PEER_NOTES.md.)
#[test]
fn tiny_and_huge_scales_scale_the_answer() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    let mut touching = 0;
    for case in 0..300 {
        let n = 4 + (rng.random::<u32>() % 30) as usize;
        let base_a = cloud(&mut rng, n, 1.0);
        let base_b = if case % 3 == 0 {
            corners(Vec3::new(0.3, 0.6, 0.9))
        } else {
            cloud(&mut rng, 12, 0.8)
        };
        let (qa, qb) = (random_rotation(&mut rng), random_rotation(&mut rng));
        let (ta, tb) = (random_vec(&mut rng, 1.0), random_vec(&mut rng, 1.0));
        let mut reference: Option<(Collision, f64)> = None;
        for scale in [1.0f32, 1e-3, 1e3] {
            let s = |v: &Vec<Vec3>| v.iter().map(|p| *p * scale).collect::<Vec<_>>();
            let pair = Pair::new(s(&base_a), s(&base_b));
            let (hit, wa, wb) =
                pair.collide(&Pose::new(ta * scale, qa), &Pose::new(tb * scale, qb));
            let what = format!("case {case} scale {scale}");
            let truth = check_against_brute(&hit, &wa, &wb, &what);
            let Some((first, first_truth)) = reference else {
                reference = Some((hit, truth));
                continue;
            };
            if first_truth.abs() <= BAND * wa.size / f64::from(scale) {
                continue;
            }
            let scale = f64::from(scale);
            match (first, hit) {
                (Collision::Separated { .. }, Collision::Separated { .. }) => {}
                (Collision::Touching(c1), Collision::Touching(c2)) => {
                    touching += 1;
                    assert!(
                        c1.normal.distance(c2.normal) < 1e-4,
                        "{what}: normals {} {}",
                        c1.normal,
                        c2.normal
                    );
                    let (d1, d2) = (f64::from(c1.depth), f64::from(c2.depth) / scale);
                    assert!((d1 - d2).abs() < 1e-5 * (1.0 + d1), "{what}: depths {d1} {d2}");
                    assert_eq!(c1.points().len(), c2.points().len(), "{what}");
                    for (p1, p2) in c1.points().iter().zip(c2.points()) {
                        let p2 = p2.position.as_dvec3() / scale;
                        assert!(
                            p1.position.as_dvec3().distance(p2) < 1e-4,
                            "{what}: {p1:?} vs {p2}"
                        );
                    }
                }
                (first, hit) => panic!("{what}: {first:?} at scale 1, {hit:?} here"),
            }
        }
    }
    assert!(touching > 100, "only {touching} touching pairs compared");
}

// ---------------------------------------------------------------------------
// Warm start.

/// Seeded random pairs moving slowly (drifting and turning a little each
/// step) past and into each other: every step, the answer with a cache kept
/// across steps equals the answer with a fresh cache when touching, and is
/// also apart (along an axis that really separates them) when apart. Its
/// distance is the gap along that axis, measured, or a lower bound of it
/// from the motion since the gap was last measured: then along the same axis,
/// and short of that gap by no more than the bodies can have moved (each
/// body's origin, plus its farthest vertex turning about it).
#[test]
fn warm_start_never_changes_the_answer() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(8);
    let (mut early, mut bounded) = (0, 0);
    let mut steps = 0;
    for run in 0..60 {
        let pa_points =
            if run % 4 == 0 { corners(Vec3::new(0.5, 0.3, 0.7)) } else { cloud(&mut rng, 30, 1.0) };
        let pb_points =
            if run % 3 == 0 { corners(Vec3::splat(0.4)) } else { cloud(&mut rng, 20, 0.7) };
        let pair = Pair::new(pa_points, pb_points);
        let (mut pa, mut pb) = (
            Pose::new(Vec3::ZERO, random_rotation(&mut rng)),
            Pose::new(random_vec(&mut rng, 3.0), random_rotation(&mut rng)),
        );
        // Head roughly at A, slowly, turning a little.
        let velocity = -pb.position * (0.004 + 0.004 * rng.random::<f32>());
        let spin_a = Quat::from_axis_angle(random_rotation(&mut rng) * Vec3::X, 0.01);
        let spin_b = Quat::from_axis_angle(random_rotation(&mut rng) * Vec3::X, 0.02);
        let mut warm = WarmStart::default();
        let mut measured: Option<(Vec3, f64, Pose, Pose)> = None;
        for step in 0..300 {
            let kept = hull_hull(&pair.a, &pa, &pair.b, &pb, &mut warm).expect("finite");
            let cold =
                hull_hull(&pair.a, &pa, &pair.b, &pb, &mut WarmStart::default()).expect("finite");
            let what = format!("run {run} step {step}");
            match (kept, cold) {
                (Collision::Touching(_), _) | (_, Collision::Touching(_)) => {
                    assert_eq!(kept, cold, "{what}")
                }
                (Collision::Separated { axis, distance }, Collision::Separated { .. }) => {
                    early += usize::from(kept != cold);
                    let (wa, wb) =
                        (world_hull(&pair.points_a, &pa), world_hull(&pair.points_b, &pb));
                    let gap = gap_along(&wa, &wb, axis.as_dvec3());
                    let (distance, tol) = (f64::from(distance), TOL * reach(&wa, &wb));
                    assert!(gap > 0.0, "{what}: warm axis {axis} does not separate ({gap})");
                    assert!(distance <= gap + tol, "{what}: distance {distance}, gap {gap}");
                    if distance >= gap - tol {
                        measured = Some((axis, gap, pa, pb));
                    } else {
                        // Both turn every step, so a bound falls short of the gap.
                        bounded += 1;
                        let (then, gap_then, pa_then, pb_then) = measured.expect("measured");
                        assert_eq!(axis, then, "{what}: bounded along another axis");
                        let moved = motion(&pair.points_a, &pa_then, &pa)
                            + motion(&pair.points_b, &pb_then, &pb);
                        let least = gap_then - moved - tol;
                        assert!(distance >= least, "{what}: {distance} from {gap_then}");
                    }
                }
            }
            steps += 1;
            pa.rotation = (spin_a * pa.rotation).normalize();
            pb = Pose::new(pb.position + velocity, (spin_b * pb.rotation).normalize());
        }
    }
    assert!(early > 0, "the cache never answered on its own in {steps} steps");
    assert!(bounded > 0, "the motion never answered on its own in {steps} steps");
}

/// The test shapes (meshes' hulls, boxes, slabs, rods, sampled spheres,
/// random hulls) at three scales, resting face on face and creeping down
/// through touching, turning by 1e-5 rad a step: at every step the warm call
/// gives exactly the cold call's contact, where features are nearly tied
/// and the cached witnesses differ most from a cold call's.
#[test]
fn warm_start_gives_the_cold_contact_on_resting_shapes() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(28);
    let mut touching = 0;
    for scale in [1e-3f32, 1.0, 1e3] {
        let shapes = common::shapes::all(scale);
        for sa in shapes.iter().step_by(2) {
            for sb in shapes.iter().step_by(5) {
                let top = sa.points.iter().map(|p| p.y).fold(f32::MIN, f32::max);
                let bottom = sb.points.iter().map(|p| p.y).fold(f32::MAX, f32::min);
                let mut pa = Pose::IDENTITY;
                let shift = random_vec(&mut rng, 0.3) * scale;
                let above = top - bottom + 1e-4 * scale;
                let mut pb = Pose::new(Vec3::new(shift.x, above, shift.z), Quat::IDENTITY);
                let spin_a = Quat::from_axis_angle(random_rotation(&mut rng) * Vec3::X, 1e-5);
                let spin_b = Quat::from_axis_angle(random_rotation(&mut rng) * Vec3::X, 1e-5);
                let mut warm = WarmStart::default();
                for step in 0..120 {
                    let kept = hull_hull(&sa.poly, &pa, &sb.poly, &pb, &mut warm).expect("finite");
                    let cold = hull_hull(&sa.poly, &pa, &sb.poly, &pb, &mut WarmStart::default())
                        .expect("finite");
                    if cold.is_touching() {
                        touching += 1;
                        assert_eq!(kept, cold, "{} on {}, step {step}", sb.name, sa.name);
                    }
                    pa.rotation = (spin_a * pa.rotation).normalize();
                    let down = Vec3::new(0.0, -2e-6 * scale, 0.0);
                    pb = Pose::new(pb.position + down, (spin_b * pb.rotation).normalize());
                }
            }
        }
    }
    assert!(touching > 1000, "only {touching} touching steps");
}

/// A warm start made with other shapes changes no answer: two small boxes
/// far apart leave a large gap in the cache, and two large boxes at the same
/// poses, overlapping, are still found touching (the gap measured is the
/// small boxes', and no motion since would bound the large ones' by it).
/// Clones of the small boxes are the same shapes, and the cache answers.
#[test]
fn warm_start_of_other_shapes_is_ignored() {
    let small = Polyhedron::from_points(&corners(Vec3::splat(0.5))).expect("a box");
    let large = Polyhedron::from_points(&corners(Vec3::splat(2.0))).expect("a box");
    let poses = [Pose::IDENTITY, Pose::new(Vec3::new(2.2, 0.1, 0.0), Quat::from_rotation_y(0.3))];
    let mut warm = WarmStart::default();
    let far = hull_hull(&small, &poses[0], &small, &poses[1], &mut warm).expect("finite");
    assert!(!far.is_touching());
    for (a, b) in [(&large, &large), (&small, &large), (&large, &small)] {
        let mut kept = warm;
        let got = hull_hull(a, &poses[0], b, &poses[1], &mut kept).expect("finite");
        let cold = hull_hull(a, &poses[0], b, &poses[1], &mut WarmStart::default());
        assert_eq!(got, cold.expect("finite"));
        assert!(got.is_touching());
    }
    // A clone is the same shape: its cache answers for it, from the motion
    // bound alone (nothing moved): the same axis, and the gap less what
    // storing it rounded off, so a little below the gap measured.
    let twin = small.clone();
    let again = hull_hull(&twin, &poses[0], &twin, &poses[1], &mut warm).expect("finite");
    let (Collision::Separated { axis: a0, distance: d0 }, Collision::Separated { axis, distance }) =
        (far, again)
    else {
        panic!("apart: {far:?}, {again:?}");
    };
    assert_eq!(axis, a0);
    assert!(distance < d0 && distance > d0 - 1e-5, "{distance} for {d0}: not the bound's");
}

/// A warm start that caches one of two faces tied for the least
/// penetration gives the face a cold call gives, not its own: a box pressed
/// into a hull's vertical edge, square to it, is as deep through the hull's
/// +x face as through its +y face (the same numbers either way). Shifted a
/// little off the tie, each side picks one face, and each of those warm
/// starts is then used at the tie; one of them holds the face a cold call
/// does not pick there.
#[test]
fn warm_start_on_tied_faces_gives_the_cold_face() {
    // A box with a point above its top, so not a box to the closed-form
    // queries: its side faces are still exactly x = +-1 and y = +-1.
    let mut points = corners(Vec3::ONE);
    points.push(Vec3::new(0.0, 0.0, 1.5));
    let hull = Polyhedron::from_points(&points).expect("a solid");
    let cube = Polyhedron::cuboid(Vec3::splat(0.5)).expect("a box");
    let tie = at(1.3, 1.3, 0.0);
    let cold = hull_hull(&hull, &Pose::IDENTITY, &cube, &tie, &mut WarmStart::default());
    let cold = cold.expect("finite");
    let normal = contact(&cold, "at the tie").normal;
    assert!(normal == Vec3::X || normal == Vec3::Y, "{normal}: not one of the tied faces");
    let mut cached = Vec::new();
    for off_tie in [at(1.3, 1.25, 0.0), at(1.25, 1.3, 0.0)] {
        let mut warm = WarmStart::default();
        let off = hull_hull(&hull, &Pose::IDENTITY, &cube, &off_tie, &mut warm).expect("finite");
        cached.push(contact(&off, "off the tie").normal);
        let got = hull_hull(&hull, &Pose::IDENTITY, &cube, &tie, &mut warm).expect("finite");
        assert_eq!(got, cold, "with the warm start from {off_tie:?}");
    }
    assert_eq!(cached, [Vec3::X, Vec3::Y], "each side off the tie picks its own face");
}

/// How far any vertex of the points' hull can have moved from pose `then`
/// to `now`: the origin's move, plus the chord that the farthest vertex from
/// the origin sweeps through the angle between the rotations.
fn motion(points: &[Vec3], then: &Pose, now: &Pose) -> f64 {
    let far = points.iter().map(|p| p.as_dvec3().length()).fold(0.0, f64::max);
    let angle =
        then.rotation.as_dquat().normalize().angle_between(now.rotation.as_dquat().normalize());
    (now.position.as_dvec3() - then.position.as_dvec3()).length() + 2.0 * far * (angle / 2.0).sin()
}

/// Flat point sets are taken, [`FLAT_THICKNESS`] of their size thick: a
/// square tile and a triangle, at scales 1e-3, 1 and 1e3, turned at random,
/// against a cube coming at them from either side, square on or turned,
/// from 1e-3 of the size apart to 1e-3 deep. Every answer is checked against
/// the exact reference for the tile moved half the thickness to each side of
/// its plane, and a touching normal points to the side the cube is on.
#[test]
fn flat_shapes_touch_on_either_face() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(29);
    let square = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let triangle = [(-1.0, -1.0), (1.0, -0.5), (0.0, 1.0)];
    let mut sides = [0usize; 2];
    for scale in [1e-3f32, 1.0, 1e3] {
        for outline in [&square[..], &triangle[..]] {
            let turn = random_rotation(&mut rng);
            let n = turn * Vec3::Y;
            let flat: Vec<Vec3> =
                outline.iter().map(|&(x, z)| turn * Vec3::new(x, 0.0, z) * scale).collect();
            // The set's size: the sum of its half extents along the axes.
            let (lo, hi) = flat
                .iter()
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(l, h), &q| (l.min(q), h.max(q)));
            let half =
                n.as_dvec3() * 0.5 * FLAT_THICKNESS * f64::from(((hi - lo) * 0.5).element_sum());
            let thick: Vec<Vec3> = flat
                .iter()
                .flat_map(|q| [(q.as_dvec3() + half).as_vec3(), (q.as_dvec3() - half).as_vec3()])
                .collect();
            let tile = Polyhedron::from_points(&flat).expect("a flat set is taken");
            assert_eq!(tile.vertices().len(), 2 * flat.len(), "{scale}: each point on both faces");
            let cube = Polyhedron::cuboid(Vec3::splat(0.3 * scale)).expect("a cube");
            let cube_points = corners(Vec3::splat(0.3 * scale));
            for case in 0..40 {
                let side = if case % 2 == 0 { 1.0 } else { -1.0 };
                let q = if case % 4 < 2 { turn } else { random_rotation(&mut rng) };
                let low = cube_points
                    .iter()
                    .map(|&c| (q * c).dot(n * side))
                    .fold(f32::INFINITY, f32::min);
                let gap = rng.random_range(-1e-3..1e-3) * scale;
                let along = (rng.random::<f32>() - 0.5) * scale;
                let at = n * side * (gap - low) + turn * Vec3::new(along, 0.0, 0.0);
                let pose = Pose::new(at, q);
                let hit =
                    hull_hull(&tile, &Pose::IDENTITY, &cube, &pose, &mut WarmStart::default())
                        .expect("finite");
                let (wa, wb) =
                    (world_hull(&thick, &Pose::IDENTITY), world_hull(&cube_points, &pose));
                check_against_brute(&hit, &wa, &wb, &format!("{scale} {outline:?} case {case}"));
                if let Collision::Touching(c) = hit {
                    assert!(
                        c.normal.dot(n) * side > 0.0,
                        "{scale} case {case}: normal {} on side {side}",
                        c.normal
                    );
                    sides[usize::from(side > 0.0)] += 1;
                }
            }
        }
    }
    assert!(sides[0] > 20 && sides[1] > 20, "touching on each side: {sides:?}");
    // Stretched a thousandfold along its plane, a tile's slab would be flat
    // at its new size: it is thickened again.
    let tile: Vec<Vec3> = square.iter().map(|&(x, z)| Vec3::new(x, 0.0, z)).collect();
    let part = Part::Hull(Box::new(HullPart::from_points(&tile).expect("a flat set is taken")));
    let Part::Hull(wide) = part.scaled(Vec3::new(1e3, 1.0, 1e3)).expect("stretched") else {
        panic!("a hull scales to a hull")
    };
    assert_eq!(wide.hull.dimension(), 3);
    let depth = wide.polyhedron.vertices().iter().map(|v| v.y).fold(f32::MIN, f32::max);
    let expected = 0.5 * FLAT_THICKNESS * 2e3;
    assert!((f64::from(depth) - expected).abs() < 1e-2 * expected, "half thickness {depth}");
}

// ---------------------------------------------------------------------------
// Bad input.

/// A point, points on a line, flat points that cannot be thickened, no
/// points, non-finite points and bad half extents are typed errors; a flat
/// hull handed over as it is, too.
#[test]
fn bad_shapes_are_typed_errors() {
    let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    assert_eq!(Polyhedron::from_points(&[]).unwrap_err(), ShapeError::Empty);
    let one = [p(1.0, 2.0, 3.0)];
    assert_eq!(Polyhedron::from_points(&one).unwrap_err(), ShapeError::Degenerate { dimension: 0 });
    let twice = [p(1.0, 2.0, 3.0); 5];
    assert_eq!(
        Polyhedron::from_points(&twice).unwrap_err(),
        ShapeError::Degenerate { dimension: 0 }
    );
    let line = [p(0.0, 0.0, 0.0), p(1.0, 1.0, 1.0), p(2.0, 2.0, 2.0)];
    assert_eq!(
        Polyhedron::from_points(&line).unwrap_err(),
        ShapeError::Degenerate { dimension: 1 }
    );
    // Flat, but too far from the origin for the thickness to show in f32.
    let far = [p(0.0, 0.0, 1e9), p(1.0, 0.0, 1e9), p(0.0, 1.0, 1e9)];
    assert_eq!(Polyhedron::from_points(&far).unwrap_err(), ShapeError::Degenerate { dimension: 2 });
    let three = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    let nan = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, f32::NAN, 0.0), p(0.0, 0.0, 1.0)];
    assert_eq!(Polyhedron::from_points(&nan).unwrap_err(), ShapeError::NonFinite { index: 2 });
    let inf = [p(0.0, 0.0, 0.0), p(f32::INFINITY, 0.0, 0.0), p(0.0, 1.0, 0.0), p(0.0, 0.0, 1.0)];
    assert_eq!(Polyhedron::from_points(&inf).unwrap_err(), ShapeError::NonFinite { index: 1 });
    let hull = ConvexHull::new(&three).expect("finite");
    assert_eq!(Polyhedron::from_hull(&hull).unwrap_err(), ShapeError::Degenerate { dimension: 2 });
    for h in [
        Vec3::ZERO,
        Vec3::new(1.0, -1.0, 1.0),
        Vec3::new(1.0, 1.0, f32::NAN),
        Vec3::splat(f32::INFINITY),
    ] {
        assert_eq!(Polyhedron::cuboid(h).unwrap_err(), ShapeError::BadHalfExtents, "{h}");
    }
    // The messages say what is wrong and where.
    assert!(ShapeError::NonFinite { index: 2 }.to_string().contains('2'));
    assert!(ShapeError::Degenerate { dimension: 2 }.to_string().contains("non-coplanar"));
}

/// Non-finite poses and shapes are typed errors naming the body, for every
/// test; never a panic, never a NaN.
#[test]
fn bad_poses_and_shapes_are_typed_errors() {
    let cube = Polyhedron::cuboid(Vec3::ONE).expect("cube");
    let obb = Obb { center: Vec3::ZERO, axes: Mat3::IDENTITY, half_extents: Vec3::ONE };
    let ball = Sphere::new(Vec3::ZERO, 1.0);
    let good = Pose::IDENTITY;
    let bad_poses = [
        Pose::new(Vec3::new(f32::NAN, 0.0, 0.0), Quat::IDENTITY),
        Pose::new(Vec3::new(0.0, f32::INFINITY, 0.0), Quat::IDENTITY),
        Pose::new(Vec3::ZERO, Quat::from_xyzw(0.0, f32::NAN, 0.0, 1.0)),
        Pose::new(Vec3::ZERO, Quat::from_xyzw(0.0, 0.0, 0.0, 0.0)),
    ];
    for bad in &bad_poses {
        for (pa, pb, body) in [(bad, &good, Body::A), (&good, bad, Body::B)] {
            let want = Err(NarrowError::NonFinitePose { body });
            assert_eq!(hull_hull(&cube, pa, &cube, pb, &mut WarmStart::default()), want, "{bad:?}");
            assert_eq!(obb_obb(&obb, pa, &obb, pb), want);
            assert_eq!(sphere_hull(&ball, pa, &cube, pb), want);
            assert_eq!(sphere_obb(&ball, pa, &obb, pb), want);
            assert_eq!(sphere_sphere(&ball, pa, &ball, pb), want);
        }
    }
    let bad_boxes = [
        Obb { center: Vec3::new(f32::NAN, 0.0, 0.0), ..obb },
        Obb { axes: Mat3::from_diagonal(Vec3::new(1.0, f32::INFINITY, 1.0)), ..obb },
        Obb { half_extents: Vec3::new(1.0, f32::NAN, 1.0), ..obb },
        Obb { half_extents: Vec3::new(1.0, -1.0, 1.0), ..obb },
    ];
    for bad in &bad_boxes {
        let err = |body| Err(NarrowError::NonFiniteShape { body });
        assert_eq!(obb_obb(bad, &good, &obb, &good), err(Body::A), "{bad:?}");
        assert_eq!(obb_obb(&obb, &good, bad, &good), err(Body::B), "{bad:?}");
        assert_eq!(sphere_obb(&ball, &good, bad, &good), err(Body::B), "{bad:?}");
    }
    let bad_balls = [
        Sphere::new(Vec3::new(0.0, 0.0, f32::NAN), 1.0),
        Sphere::new(Vec3::ZERO, f32::INFINITY),
        Sphere::new(Vec3::ZERO, f32::NAN),
        Sphere::new(Vec3::ZERO, -1.0),
    ];
    for bad in &bad_balls {
        let err = |body| Err(NarrowError::NonFiniteShape { body });
        assert_eq!(sphere_hull(bad, &good, &cube, &good), err(Body::A), "{bad:?}");
        assert_eq!(sphere_obb(bad, &good, &obb, &good), err(Body::A), "{bad:?}");
        assert_eq!(sphere_sphere(bad, &good, &ball, &good), err(Body::A), "{bad:?}");
        assert_eq!(sphere_sphere(&ball, &good, bad, &good), err(Body::B), "{bad:?}");
    }
    assert!(NarrowError::NonFinitePose { body: Body::B }.to_string().contains('B'));
}

/// Found by the contact fuzz target under libFuzzer: two capsules, one at
/// f32's largest position, were "separated" by an infinite distance. Every
/// pair test now refuses a position beyond `MAX_COORDINATE`, naming the
/// body, and up to it gives finite answers.
#[test]
fn positions_beyond_the_coordinate_limit_are_typed_errors() {
    let cube = Polyhedron::cuboid(Vec3::ONE).expect("cube");
    let obb = Obb { center: Vec3::ZERO, axes: Mat3::IDENTITY, half_extents: Vec3::ONE };
    let ball = Sphere::new(Vec3::ZERO, 1.0);
    let rod = Capsule::new(0.1, 1.0);
    let good = Pose::IDENTITY;
    for x in [1.0000001e18, 1e30, f32::MAX, -f32::MAX] {
        let far = Pose::new(Vec3::new(0.0, x, 0.0), Quat::IDENTITY);
        for (pa, pb, body) in [(&far, &good, Body::A), (&good, &far, Body::B)] {
            let want = Err(NarrowError::PoseOutOfRange { body });
            assert_eq!(hull_hull(&cube, pa, &cube, pb, &mut WarmStart::default()), want, "{x}");
            assert_eq!(obb_obb(&obb, pa, &obb, pb), want, "{x}");
            assert_eq!(sphere_hull(&ball, pa, &cube, pb), want, "{x}");
            assert_eq!(sphere_obb(&ball, pa, &obb, pb), want, "{x}");
            assert_eq!(sphere_sphere(&ball, pa, &ball, pb), want, "{x}");
            assert_eq!(capsule_capsule(&rod, pa, &rod, pb), want, "{x}");
            assert_eq!(capsule_sphere(&rod, pa, &ball, pb), want, "{x}");
            assert_eq!(capsule_hull(&rod, pa, &cube, pb), want, "{x}");
        }
    }
    let limit = Pose::new(Vec3::splat(bvol_volumes::MAX_COORDINATE), Quat::IDENTITY);
    let hits = [
        hull_hull(&cube, &limit, &cube, &good, &mut WarmStart::default()),
        capsule_capsule(&rod, &limit, &rod, &good),
        sphere_sphere(&ball, &good, &ball, &limit),
    ];
    for hit in hits {
        assert!(finite(&hit.unwrap()), "at the limit");
    }
    assert!(NarrowError::PoseOutOfRange { body: Body::A }.to_string().contains("1e18"));
}

/// Whether every number in an answer is finite.
fn finite(hit: &Collision) -> bool {
    match hit {
        Collision::Separated { axis, distance } => axis.is_finite() && distance.is_finite(),
        Collision::Touching(c) => {
            c.normal.is_finite()
                && c.depth.is_finite()
                && c.points().iter().all(|p| p.position.is_finite() && p.depth.is_finite())
        }
    }
}

/// Legal but extreme input: flat and zero boxes, zero spheres, coincident
/// centres, poses at the coordinate limit, unnormalised rotations. Every answer is
/// finite and its normal unit.
#[test]
fn extreme_finite_input_gives_finite_answers() {
    let flat =
        Obb { center: Vec3::ZERO, axes: Mat3::IDENTITY, half_extents: Vec3::new(1.0, 0.0, 1.0) };
    let point = Obb { half_extents: Vec3::ZERO, ..flat };
    let cube = Obb { half_extents: Vec3::ONE, ..flat };
    let skewed = Obb { axes: Mat3::from_cols(Vec3::X, Vec3::X, Vec3::Z), ..cube };
    let boxes = [flat, point, cube, skewed];
    let balls =
        [Sphere::new(Vec3::ZERO, 0.0), Sphere::new(Vec3::ZERO, 1.0), Sphere::new(Vec3::ONE, 1e-30)];
    let hull = Polyhedron::cuboid(Vec3::splat(1e-30)).expect("tiny cube");
    let big = Polyhedron::cuboid(Vec3::splat(1e30)).expect("huge cube");
    let poses = [
        Pose::IDENTITY,
        Pose::new(Vec3::splat(bvol_volumes::MAX_COORDINATE), Quat::IDENTITY),
        Pose::new(Vec3::new(0.0, 1.0, 0.0), Quat::from_xyzw(0.0, 0.0, 0.0, 1e-20)),
        Pose::new(Vec3::new(0.5, 0.0, 0.0), Quat::from_xyzw(3.0, 0.0, 4.0, 0.0)),
    ];
    let unit = |hit: &Collision| match hit {
        Collision::Separated { axis, .. } => (axis.length() - 1.0).abs() < 1e-5,
        Collision::Touching(c) => (c.normal.length() - 1.0).abs() < 1e-5,
    };
    for pa in &poses {
        for pb in &poses {
            let mut all = Vec::new();
            for a in &boxes {
                for b in &boxes {
                    all.push(obb_obb(a, pa, b, pb));
                }
                for s in &balls {
                    all.push(sphere_obb(s, pa, a, pb));
                }
            }
            for s in &balls {
                for t in &balls {
                    all.push(sphere_sphere(s, pa, t, pb));
                }
                for h in [&hull, &big] {
                    all.push(sphere_hull(s, pa, h, pb));
                }
            }
            for h in [&hull, &big] {
                for g in [&hull, &big] {
                    all.push(hull_hull(h, pa, g, pb, &mut WarmStart::default()));
                }
            }
            for hit in all {
                let hit = hit.expect("finite input");
                assert!(finite(&hit) && unit(&hit), "{pa:?} {pb:?}: {hit:?}");
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Boxes.

/// A random box pair: half extents, poses, and the boxes' own centres and axes.
fn random_boxes(rng: &mut Xoshiro256PlusPlus) -> (Obb, Pose, Obb, Pose) {
    let obb = |rng: &mut Xoshiro256PlusPlus| Obb {
        center: Vec3::ZERO,
        axes: Mat3::IDENTITY,
        half_extents: Vec3::new(rng.random(), rng.random(), rng.random()) + 0.05,
    };
    let (a, b) = (obb(rng), obb(rng));
    let pa = Pose::new(random_vec(rng, 1.0), random_rotation(rng));
    let pb = Pose::new(pa.position + random_vec(rng, 1.2), random_rotation(rng));
    (a, pa, b, pb)
}

/// The box `obb` (its half extents, about its origin) placed by `pose`, as
/// the exact reference sees it.
fn world_box(obb: &Obb, pose: &Pose) -> WorldHull {
    world_hull(&corners(obb.half_extents), pose)
}

/// obb_obb and hull_hull on Polyhedron::cuboid of the same boxes at the same
/// poses: the same answer (the box test is the hull test on a box made on the
/// spot). With the boxes' own centre and axes folded into the pose instead,
/// the same verdict outside the band, depth and normal within 1e-5.
#[test]
fn obb_obb_agrees_with_hull_hull_on_cuboids() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(9);
    for case in 0..2000 {
        let (a, pa, b, pb) = random_boxes(&mut rng);
        let boxes = obb_obb(&a, &pa, &b, &pb).expect("finite");
        let (ca, cb) = (
            Polyhedron::cuboid(a.half_extents).unwrap(),
            Polyhedron::cuboid(b.half_extents).unwrap(),
        );
        let hulls = hull_hull(&ca, &pa, &cb, &pb, &mut WarmStart::default()).expect("finite");
        assert_eq!(boxes, hulls, "case {case}");
        // The same boxes given by their own centre and axes, inside a shifted pose.
        let (qa, qb) = (random_rotation(&mut rng), random_rotation(&mut rng));
        let (sa, sb) = (random_vec(&mut rng, 3.0), random_vec(&mut rng, 3.0));
        let inner = |o: &Obb, q: Quat, s: Vec3| Obb {
            center: q.inverse() * s,
            axes: Mat3::from_quat(q.inverse()),
            half_extents: o.half_extents,
        };
        let outer = |p: &Pose, q: Quat, s: Vec3| {
            Pose::new(p.position - p.rotation * (q * (q.inverse() * s)), p.rotation * q)
        };
        let folded = obb_obb(
            &inner(&a, qa, sa),
            &outer(&pa, qa, sa),
            &inner(&b, qb, sb),
            &outer(&pb, qb, sb),
        )
        .expect("finite");
        let (wa, wb) = (world_box(&a, &pa), world_box(&b, &pb));
        let truth = brute_force_sat(&wa, &wb);
        if truth.abs() > BAND * wa.size.max(wb.size) {
            let what = format!("case {case} folded");
            match (boxes, folded) {
                (Collision::Separated { .. }, Collision::Separated { .. }) => {}
                (Collision::Touching(c1), Collision::Touching(c2)) => {
                    assert!((c1.depth - c2.depth).abs() < 1e-5, "{what}: {c1:?} {c2:?}");
                    assert!(c1.normal.distance(c2.normal) < 1e-5, "{what}: {c1:?} {c2:?}");
                }
                (x, y) => panic!("{what}: {x:?} vs {y:?}"),
            }
        }
    }
}

/// Two boxes take closed-form queries (every face and edge-pair axis read off
/// the half extents); the same boxes as hulls shifted off their origin
/// (compensated in the pose) take the general ones. Outside the band the
/// verdict is the same, and touching pairs get the same depth, normal and
/// manifold points to 1e-5 (of a reduced manifold, the deepest point).
#[test]
fn closed_form_box_queries_agree_with_the_general_ones() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(12);
    let mut touching = 0;
    for case in 0..4000 {
        let (a, pa, b, pb) = random_boxes(&mut rng);
        let (ca, cb) = (
            Polyhedron::cuboid(a.half_extents).unwrap(),
            Polyhedron::cuboid(b.half_extents).unwrap(),
        );
        let closed = hull_hull(&ca, &pa, &cb, &pb, &mut WarmStart::default()).expect("finite");
        let shift = Vec3::new(0.25, -0.5, 0.125);
        let shifted = |h: Vec3| {
            let points: Vec<Vec3> = corners(h).iter().map(|&p| p + shift).collect();
            Polyhedron::from_points(&points).unwrap()
        };
        let back = |p: &Pose| Pose::new(p.position - p.rotation * shift, p.rotation);
        let (ga, gb) = (shifted(a.half_extents), shifted(b.half_extents));
        let general =
            hull_hull(&ga, &back(&pa), &gb, &back(&pb), &mut WarmStart::default()).expect("finite");
        let (wa, wb) = (world_box(&a, &pa), world_box(&b, &pb));
        if brute_force_sat(&wa, &wb).abs() <= BAND * wa.size.max(wb.size) {
            continue;
        }
        match (closed, general) {
            (Collision::Separated { .. }, Collision::Separated { .. }) => {}
            (Collision::Touching(c1), Collision::Touching(c2)) => {
                touching += 1;
                let what = format!("case {case}: {c1:?} {c2:?}");
                assert!((c1.depth - c2.depth).abs() < 1e-5, "{what}");
                assert!(c1.normal.distance(c2.normal) < 1e-5, "{what}");
                assert_eq!(c1.points().len(), c2.points().len(), "{what}");
                // Four points may be a reduction of more, whose picks after
                // the deepest can differ on near-ties (the clipped polygons
                // start at different corners): then only the deepest is compared.
                let compared = if c1.points().len() < 4 { c1.points() } else { &c1.points()[..1] };
                for p in compared {
                    let near = c2.points().iter().any(|q| q.position.distance(p.position) < 1e-5);
                    assert!(near, "{what}");
                }
            }
            (x, y) => panic!("case {case}: {x:?} vs {y:?}"),
        }
    }
    assert!(touching > 1000, "{touching} touching pairs compared");
}

/// obb_obb's verdict against the exact reference and against Obb::overlaps
/// (the 15-axis yes/no test of bvol-volumes) on the world boxes, outside the band.
#[test]
fn obb_obb_verdict_agrees_with_obb_overlaps() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(10);
    let mut compared = 0;
    for case in 0..3000 {
        let (a, pa, b, pb) = random_boxes(&mut rng);
        let hit = obb_obb(&a, &pa, &b, &pb).expect("finite");
        let (wa, wb) = (world_box(&a, &pa), world_box(&b, &pb));
        let truth = check_against_brute(&hit, &wa, &wb, &format!("case {case}"));
        if truth.abs() > BAND * wa.size.max(wb.size) {
            compared += 1;
            let overlaps = a.transformed(&pa).overlaps(&b.transformed(&pb));
            assert_eq!(hit.is_touching(), overlaps, "case {case}: {hit:?}, reference {truth}");
        }
    }
    assert!(compared > 2900, "{compared}");
}

// ---------------------------------------------------------------------------
// Spheres.

/// The exact answer for a sphere about `c` of radius `r` against the box
/// `[-h, h]` (all in the box's frame, f64): clamp for the closest point
/// outside; inside, the least distance to a face plane. Returns the signed
/// gap (`> 0` apart, else minus the depth) and the unit normal from the
/// sphere into the box.
fn exact_sphere_box(c: DVec3, r: f64, h: DVec3) -> (f64, DVec3) {
    let q = c.clamp(-h, h);
    if q != c {
        let d = (q - c).length();
        return (d - r, (q - c) / d);
    }
    let (mut best, mut normal) = (f64::INFINITY, DVec3::ZERO);
    for k in 0..3 {
        for s in [-1.0, 1.0] {
            let inside = h[k] - s * c[k]; // distance to the face at s h_k
            if inside < best {
                let mut n = DVec3::ZERO;
                n[k] = -s;
                (best, normal) = (inside, n);
            }
        }
    }
    (-(best + r), normal)
}

/// sphere_obb and sphere_hull (on the cuboid of the same box) against the
/// exact clamp: verdict outside the band, gap or depth, normal, and the point
/// midway between the surfaces.
#[test]
fn sphere_against_box_matches_the_exact_closest_point() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
    let mut touching = 0;
    for case in 0..3000 {
        let h = Vec3::new(rng.random(), rng.random(), rng.random()) + 0.05;
        let obb = Obb { center: Vec3::ZERO, axes: Mat3::IDENTITY, half_extents: h };
        let hull = Polyhedron::cuboid(h).expect("box");
        let ball = Sphere::new(random_vec(&mut rng, 0.2), rng.random::<f32>() * 0.8);
        let (pa, pb) = (
            Pose::new(random_vec(&mut rng, 1.5), random_rotation(&mut rng)),
            Pose::new(random_vec(&mut rng, 0.3), random_rotation(&mut rng)),
        );
        // The centre in the box's frame, exactly.
        let rb = rotation_f64(pb.rotation);
        let centre = rotation_f64(pa.rotation) * ball.center.as_dvec3() + pa.position.as_dvec3();
        let local = rb.transpose() * (centre - pb.position.as_dvec3());
        let r = f64::from(ball.radius);
        let (gap, normal) = exact_sphere_box(local, r, h.as_dvec3());
        let normal = rb * normal;
        let tol = 1e-5;
        for (hit, what) in [
            (sphere_obb(&ball, &pa, &obb, &pb).expect("finite"), "sphere_obb"),
            (sphere_hull(&ball, &pa, &hull, &pb).expect("finite"), "sphere_hull"),
        ] {
            let what = format!("case {case} {what}");
            if gap.abs() < BAND {
                continue;
            }
            match hit {
                Collision::Separated { axis, distance } => {
                    assert!(gap > 0.0, "{what}: apart, exact gap {gap}");
                    assert!((f64::from(distance) - gap).abs() < tol, "{what}: {distance} vs {gap}");
                    assert!(axis.as_dvec3().distance(normal) < tol, "{what}: {axis} vs {normal}");
                }
                Collision::Touching(c) => {
                    touching += 1;
                    assert!(gap < 0.0, "{what}: touching, exact gap {gap}");
                    assert!(
                        (f64::from(c.depth) + gap).abs() < tol,
                        "{what}: {} vs {}",
                        c.depth,
                        -gap
                    );
                    assert!(
                        c.normal.as_dvec3().distance(normal) < tol,
                        "{what}: {} vs {normal}",
                        c.normal
                    );
                    assert_eq!(c.points().len(), 1, "{what}");
                    // Midway between the sphere's deepest point and the box's surface.
                    let expected = centre + normal * (r + gap / 2.0);
                    let p = c.points()[0];
                    assert!(
                        p.position.as_dvec3().distance(expected) < tol,
                        "{what}: {p:?} vs {expected}"
                    );
                    assert!((f64::from(p.depth) + gap).abs() < tol, "{what}");
                }
            }
        }
    }
    assert!(touching > 1000, "{touching}");
}

/// sphere_hull on random hulls against the closest point over all the hull's
/// triangles (Ericson 5.1.5) when the centre is outside, and the nearest face
/// plane when inside.
#[test]
fn sphere_hull_matches_the_closest_point_on_the_triangles() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(12);
    let mut touching = 0;
    for case in 0..1500 {
        let n = 4 + (rng.random::<u32>() % 40) as usize;
        let points = cloud(&mut rng, n, 1.0);
        let hull = ConvexHull::new(&points).expect("finite");
        let Ok(poly) = Polyhedron::from_hull(&hull) else { continue };
        let ball = Sphere::new(Vec3::ZERO, rng.random::<f32>() * 0.6);
        let pa = Pose::new(random_vec(&mut rng, 1.3), Quat::IDENTITY);
        let pb = Pose::new(random_vec(&mut rng, 0.2), random_rotation(&mut rng));
        let world = world_hull(&points, &pb);
        let rb = rotation_f64(pb.rotation);
        let tb = pb.position.as_dvec3();
        let centre = pa.position.as_dvec3();
        let r = f64::from(ball.radius);
        let depth_inside = -outside(&world, centre);
        let (gap, normal) = if depth_inside >= 0.0 {
            // Inside: out through the nearest face plane.
            let (n, _) = world
                .planes
                .iter()
                .copied()
                .max_by(|x, y| (x.0.dot(centre) - x.1).total_cmp(&(y.0.dot(centre) - y.1)))
                .unwrap();
            (-(depth_inside + r), -n)
        } else {
            let at = |i: u32| rb * hull.vertices()[i as usize].as_dvec3() + tb;
            let q = hull
                .triangles()
                .map(|[a, b, c]| closest_on_triangle(centre, at(a), at(b), at(c)))
                .min_by(|x, y| x.distance(centre).total_cmp(&y.distance(centre)))
                .unwrap();
            ((q - centre).length() - r, (q - centre).normalize())
        };
        let what = format!("case {case}");
        if gap.abs() < BAND {
            continue;
        }
        let tol = 1e-5;
        match sphere_hull(&ball, &pa, &poly, &pb).expect("finite") {
            Collision::Separated { axis, distance } => {
                assert!(gap > 0.0, "{what}: apart, exact gap {gap}");
                assert!((f64::from(distance) - gap).abs() < tol, "{what}: {distance} vs {gap}");
                assert!(axis.as_dvec3().distance(normal) < 1e-4, "{what}: {axis} vs {normal}");
            }
            Collision::Touching(c) => {
                touching += 1;
                assert!(gap < 0.0, "{what}: touching, exact gap {gap}");
                assert!((f64::from(c.depth) + gap).abs() < tol, "{what}: {} vs {}", c.depth, -gap);
                // Near a hull vertex or edge the normal turns fast; compare where it is well defined.
                if gap.abs() > 1e-3 {
                    assert!(
                        c.normal.as_dvec3().distance(normal) < 1e-3,
                        "{what}: {} vs {normal}",
                        c.normal
                    );
                }
            }
        }
    }
    assert!(touching > 300, "{touching}");
}

/// Spheres against spheres: the exact answer along the line of centres, and
/// concentric spheres along A's turned up axis, the documented fixed choice.
#[test]
fn sphere_sphere_is_exact_and_concentric_spheres_use_a_s_up() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(13);
    for case in 0..2000 {
        let (a, b) = (
            Sphere::new(random_vec(&mut rng, 0.5), rng.random()),
            Sphere::new(random_vec(&mut rng, 0.5), rng.random()),
        );
        let pa = Pose::new(random_vec(&mut rng, 1.0), random_rotation(&mut rng));
        let pb = Pose::new(random_vec(&mut rng, 1.0), random_rotation(&mut rng));
        let ca = rotation_f64(pa.rotation) * a.center.as_dvec3() + pa.position.as_dvec3();
        let cb = rotation_f64(pb.rotation) * b.center.as_dvec3() + pb.position.as_dvec3();
        let d = ca.distance(cb);
        let gap = d - f64::from(a.radius) - f64::from(b.radius);
        let n = (cb - ca) / d;
        let what = format!("case {case}");
        match sphere_sphere(&a, &pa, &b, &pb).expect("finite") {
            Collision::Separated { axis, distance } => {
                assert!(gap > 0.0, "{what}");
                assert!(
                    (f64::from(distance) - gap).abs() < 1e-6 && axis.as_dvec3().distance(n) < 1e-6,
                    "{what}"
                );
            }
            Collision::Touching(c) => {
                assert!(gap <= 0.0, "{what}");
                assert!(
                    (f64::from(c.depth) + gap).abs() < 1e-6
                        && c.normal.as_dvec3().distance(n) < 1e-6,
                    "{what}"
                );
                let mid = (ca + n * f64::from(a.radius) + cb - n * f64::from(b.radius)) / 2.0;
                assert!(c.points()[0].position.as_dvec3().distance(mid) < 1e-6, "{what}");
            }
        }
    }
    let q = Quat::from_rotation_z(0.5);
    let s = Sphere::new(Vec3::ZERO, 1.0);
    let hit = sphere_sphere(
        &s,
        &Pose::new(Vec3::ONE, q),
        &Sphere::new(Vec3::ZERO, 0.5),
        &Pose::new(Vec3::ONE, Quat::IDENTITY),
    );
    let c = contact(&hit.expect("finite"), "concentric");
    assert!(c.normal.distance(q * Vec3::Y) < 1e-6 && (c.depth - 1.5).abs() < 1e-6, "{c:?}");
}
