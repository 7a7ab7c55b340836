//! Exact capsules against parry3d 0.31.1 and an exact f64 oracle written
//! here, on 100 000 random pairs: capsule-capsule, capsule-ball, capsule-box
//! and capsule-hull (primitives and random hulls of 8 to 200 points), at
//! scales 1e-3, 1 and 1e3, in families from apart to deep: random, slid to
//! exact touching and nudged, deep, side by side nearly or exactly parallel,
//! lying on a face, at one pose.
//!
//! The oracle takes the f32 input as exact and works in f64 by other means
//! than bvol-narrow: the closest points of two segments as the least of the
//! ends' projections and the lines' interior solution; a segment against a
//! hull by the plain separating-axis test (every face normal, and the cross
//! product of the core with every edge, both ways; exact for a segment and a
//! polytope, the depth included) and, when apart, the least of the ends'
//! closest points on the surface's triangles (Ericson, Real-Time Collision
//! Detection 5.1.5) and of the core's closest points to every edge. A
//! capsule is its core grown by its radius, so its distance is the cores'
//! less the radii, and its depth the core's depth plus them.
//!
//! Every pair is checked against the oracle: the verdict outside a band of
//! [`BAND`] of the size about exact touching (inside it, either answer is
//! right: the inputs are f32); the depth, the distance and the gap along the
//! separating axis given within [`EXACT`]; the normal a least-overlap axis,
//! and within [`NORMAL`] rad of the exact one unless another axis ties with
//! it (the cores nearly meet, so the far side is as shallow; or, a core sunk
//! in a hull, another axis of the test overlaps as little, to [`DEPTH`]);
//! contact points in both bodies grown by the depth. Then against parry3d:
//! verdict outside the band, depth within [`DEPTH`] of the size, normal
//! within [`NORMAL`] rad where it does not tie. parry3d is not exact
//! everywhere (its capsule pairs are GJK and EPA in f32): each disagreement
//! is settled by the oracle, and, bvol agreeing with it, counted under the
//! way parry3d is wrong; where the oracle sides with parry3d it is a failure
//! (counted already by the oracle's check). Each test prints its counts.

mod common;

use std::sync::OnceLock;
use std::time::Instant;

use bvol_narrow::{
    Capsule, Collision, NarrowError, Polyhedron, capsule_capsule, capsule_hull, capsule_sphere,
    sphere_hull, sphere_sphere,
};
use bvol_volumes::{Pose, Sphere};
use common::reference::{Place, RefHull};
use common::shapes::{self, TestShape};
use common::tally::{Tally, run_chunks};
use common::{parry_pose, random_in_ball, random_rotation, random_unit, to_parry};
use glam::{DQuat, DVec3, Quat, Vec3};
use parry3d::query;
use parry3d::shape::{Ball, Cuboid, Shape};
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

/// Verdicts within this of exact touching, relative to the size, may go
/// either way.
const BAND: f64 = 1e-6;
/// Agreement with the oracle, relative to the size: depth, distance, the gap
/// along the separating axis, contact points.
const EXACT: f64 = 1e-5;
/// Depth agreement with parry3d, relative to the size; and how much less
/// than the least another axis must overlap to tie with it.
const DEPTH: f64 = 1e-4;
/// Normal agreement, radians.
const NORMAL: f64 = 1e-3;
/// The scales of the shapes.
const SCALES: [f32; 3] = [1e-3, 1.0, 1e3];

// ---------------------------------------------------------------------------
// The oracle

/// A capsule's core in the world, taken exactly from the f32 input, and its
/// radius. A ball is a core of zero length.
#[derive(Clone, Copy, Debug)]
struct Core {
    ends: [DVec3; 2],
    radius: f64,
}

impl Core {
    /// A capsule at a pose.
    fn capsule(capsule: &Capsule, pose: &Pose) -> Core {
        let place = Place::of(pose);
        let half = DVec3::new(0.0, capsule.half_height.into(), 0.0);
        Core { ends: [place.point(-half), place.point(half)], radius: capsule.radius.into() }
    }

    /// A sphere at a pose.
    fn ball(sphere: &Sphere, pose: &Pose) -> Core {
        let centre = Place::of(pose).point(sphere.center.as_dvec3());
        Core { ends: [centre; 2], radius: sphere.radius.into() }
    }

    /// Half its length plus its radius.
    fn size(&self) -> f64 {
        0.5 * self.ends[0].distance(self.ends[1]) + self.radius
    }

    /// The least and greatest `n . x` over the capsule.
    fn extent(&self, n: DVec3) -> (f64, f64) {
        let (a, b) = (n.dot(self.ends[0]), n.dot(self.ends[1]));
        (a.min(b) - self.radius, a.max(b) + self.radius)
    }

    /// How far `x` is outside the capsule (negative inside).
    fn excess(&self, x: DVec3) -> f64 {
        x.distance(nearest_on_segment(x, self.ends)) - self.radius
    }
}

/// The point of segment `[p, q]` nearest `x`.
fn nearest_on_segment(x: DVec3, [p, q]: [DVec3; 2]) -> DVec3 {
    let d = q - p;
    let len2 = d.length_squared();
    if len2 == 0.0 { p } else { p + d * ((x - p).dot(d) / len2).clamp(0.0, 1.0) }
}

/// The closest points of two segments, one on each: the nearest of the four
/// pairs of an end and its nearest point on the other segment, and of the
/// lines' closest points where both fall inside their segments.
fn closest_of_segments(s: [DVec3; 2], t: [DVec3; 2]) -> (DVec3, DVec3) {
    let mut pairs = vec![
        (s[0], nearest_on_segment(s[0], t)),
        (s[1], nearest_on_segment(s[1], t)),
        (nearest_on_segment(t[0], s), t[0]),
        (nearest_on_segment(t[1], s), t[1]),
    ];
    let (d1, d2, r) = (s[1] - s[0], t[1] - t[0], s[0] - t[0]);
    let (a, b, e) = (d1.dot(d1), d1.dot(d2), d2.dot(d2));
    let det = a * e - b * b;
    if det > 1e-300 {
        let (c, f) = (d1.dot(r), d2.dot(r));
        let (u, v) = ((b * f - c * e) / det, (a * f - b * c) / det);
        if (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v) {
            pairs.push((s[0] + d1 * u, t[0] + d2 * v));
        }
    }
    pairs.into_iter().min_by(|x, y| x.0.distance(x.1).total_cmp(&y.0.distance(y.1))).unwrap()
}

/// Body B of a pair, exactly.
#[derive(Clone, Copy)]
enum Other<'a> {
    /// A capsule or a ball.
    Core(Core),
    /// A hull at a placement.
    Hull { hull: &'a RefHull, place: Place },
}

/// A capsule (A) and another body (B), exactly.
#[derive(Clone, Copy)]
struct Pair<'a> {
    a: Core,
    b: Other<'a>,
}

/// The oracle's answer.
#[derive(Clone, Copy, Debug)]
struct Exact {
    /// The distance of the surfaces when apart, minus the depth when not.
    separation: f64,
    /// The unit axis from A to B: between the closest points of the cores
    /// when they are apart, else of least overlap.
    axis: DVec3,
    /// The distance of A's core from B's core or hull; `None` when A's core
    /// is inside a hull.
    cores_apart_by: Option<f64>,
}

impl Exact {
    fn depth(&self) -> f64 {
        (-self.separation).max(0.0)
    }
}

impl Pair<'_> {
    /// The larger body's size.
    fn size(&self) -> f64 {
        let b = match self.b {
            Other::Core(c) => c.size(),
            Other::Hull { hull, .. } => hull.radius(),
        };
        self.a.size().max(b)
    }

    /// The gap of B beyond A along unit `n` (minus their overlap).
    fn gap(&self, n: DVec3) -> f64 {
        let below = match self.b {
            Other::Core(c) => c.extent(n).0,
            Other::Hull { hull, place } => hull.extent(&place, n).0,
        };
        below - self.a.extent(n).1
    }

    /// How far `x` is outside A and outside B (B's face planes for a hull).
    fn excess(&self, x: DVec3) -> (f64, f64) {
        let b = match self.b {
            Other::Core(c) => c.excess(x),
            Other::Hull { hull, place } => hull.plane_excess(&place, x),
        };
        (self.a.excess(x), b)
    }

    /// The separating-axis candidates of A's core against a hull: its face
    /// normals and the cross products of the core with its edges, world, each
    /// with the greatest gap of the hull beyond the core along it or against it
    /// (that way round). The greatest is the core's exact separation, or
    /// minus its depth.
    fn core_axes(&self, hull: &RefHull, place: &Place) -> Vec<(f64, DVec3)> {
        let d = self.a.ends[1] - self.a.ends[0];
        let faces = (0..hull.face_count()).map(|f| place.rotation * hull.normal(f));
        let edges = (0..hull.edge_count()).filter_map(|e| {
            let edge = place.rotation * hull.edge(e).0;
            let n = d.cross(edge);
            (n.length() > 1e-12 * d.length() * edge.length()).then(|| n.normalize())
        });
        let core = Core { radius: 0.0, ..self.a };
        faces
            .chain(edges)
            .map(|n| {
                let (lo, hi) = hull.extent(place, n);
                let (c_lo, c_hi) = core.extent(n);
                if lo - c_hi >= c_lo - hi { (lo - c_hi, n) } else { (c_lo - hi, -n) }
            })
            .collect()
    }

    /// The closest points of A's core and B's core or hull, when apart.
    fn closest(&self) -> Option<(DVec3, DVec3)> {
        match self.b {
            Other::Core(c) => {
                let (p, q) = closest_of_segments(self.a.ends, c.ends);
                (p != q).then_some((p, q))
            }
            Other::Hull { hull, place } => {
                let best = self.core_axes(hull, &place).into_iter().map(|(g, _)| g);
                if best.fold(f64::NEG_INFINITY, f64::max) <= 0.0 {
                    return None;
                }
                let local = self.a.ends.map(|p| place.local_point(p));
                let mut pairs: Vec<(DVec3, DVec3)> =
                    local.iter().map(|&p| (p, hull.closest_on_surface(p))).collect();
                for f in 0..hull.face_count() {
                    let face = hull.face(f);
                    for (k, &i) in face.iter().enumerate() {
                        let j = face[(k + 1) % face.len()];
                        let edge = [hull.vertices()[i as usize], hull.vertices()[j as usize]];
                        pairs.push(closest_of_segments(local, edge));
                    }
                }
                let (p, q) = pairs
                    .into_iter()
                    .min_by(|x, y| x.0.distance(x.1).total_cmp(&y.0.distance(y.1)))
                    .unwrap();
                Some((place.point(p), place.point(q)))
            }
        }
    }

    /// The exact answer.
    fn exact(&self) -> Exact {
        let radii = self.a.radius + if let Other::Core(c) = self.b { c.radius } else { 0.0 };
        if let Some((p, q)) = self.closest() {
            let d = p.distance(q);
            return Exact { separation: d - radii, axis: (q - p) / d, cores_apart_by: Some(d) };
        }
        match self.b {
            // The cores meet: any direction square to both is least deep.
            Other::Core(c) => {
                let (da, db) = (self.a.ends[1] - self.a.ends[0], c.ends[1] - c.ends[0]);
                let axis = da
                    .cross(db)
                    .try_normalize()
                    .or_else(|| da.try_normalize().map(|d| d.any_orthonormal_vector()))
                    .unwrap_or(DVec3::Y);
                Exact { separation: -radii, axis, cores_apart_by: Some(0.0) }
            }
            Other::Hull { hull, place } => {
                let axes = self.core_axes(hull, &place);
                let (gap, axis) = axes.into_iter().max_by(|x, y| x.0.total_cmp(&y.0)).unwrap();
                Exact { separation: gap - radii, axis, cores_apart_by: None }
            }
        }
    }

    /// Whether another axis than the exact one, more than `angle` from it,
    /// overlaps by at most `tol` more: the cores within `tol` of meeting (the
    /// direction between them is lost to rounding, and the far side is nearly
    /// as shallow), or another axis of a sunk core's test within `tol`.
    fn tied(&self, exact: &Exact, angle: f64, tol: f64) -> bool {
        match (exact.cores_apart_by, self.b) {
            (Some(d), _) => d <= tol,
            (None, Other::Hull { hull, place }) => {
                let best = exact.separation + self.a.radius;
                self.core_axes(hull, &place)
                    .into_iter()
                    .any(|(g, n)| g >= best - tol && angle_between(n, exact.axis) > angle)
            }
            (None, Other::Core(_)) => true,
        }
    }
}

/// The angle between two unit vectors, accurate near 0.
fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

// ---------------------------------------------------------------------------
// One pair, checked

/// A pair in bvol's, parry3d's and the oracle's forms.
struct Case<'a> {
    family: &'static str,
    pair: Pair<'a>,
    pose_a: Pose,
    pose_b: Pose,
    parry_a: parry3d::shape::Capsule,
    parry_b: &'a dyn Shape,
    /// parry3d's pose of B (a ball's is its centre's).
    parry_pose_b: parry3d::math::Pose,
    scale: f32,
    label: String,
}

impl<'a> Case<'a> {
    /// Capsule `a` at `pose_a` against B at `pose_b` (`parry_b` at
    /// `parry_pose_b` in parry3d's form), exactly `pair`.
    fn new(
        family: Family,
        pair: Pair<'a>,
        (a, pose_a): (&Capsule, Pose),
        (pose_b, parry_b, parry_pose_b): (Pose, &'a dyn Shape, parry3d::math::Pose),
        (scale, label): (f32, String),
    ) -> Case<'a> {
        let parry_a = parry3d::shape::Capsule::new_y(a.half_height, a.radius);
        let family = family.name();
        Case { family, pair, pose_a, pose_b, parry_a, parry_b, parry_pose_b, scale, label }
    }

    fn describe(&self) -> String {
        format!(
            "{} [{}] pose_a {:?} pose_b {:?}",
            self.label, self.family, self.pose_a, self.pose_b
        )
    }
}

/// Checks bvol's answer against the oracle, then against parry3d.
fn check(t: &mut Tally, case: &Case, got: Result<Collision, NarrowError>) {
    t.pairs += 1;
    let got = match got {
        Ok(got) => got,
        Err(e) => return t.fail(vec!["FAILURE: an error"], format!("{}: {e}", case.describe())),
    };
    let exact = case.pair.exact();
    let right = against_exact(t, case, &got, &exact);
    check_points(t, case, &got);
    against_parry(t, case, &got, &exact, right);
}

/// The oracle's checks (see the file's doc); whether they all passed.
fn against_exact(t: &mut Tally, case: &Case, got: &Collision, exact: &Exact) -> bool {
    let size = case.pair.size();
    let (band, tol) = (BAND * size, EXACT * size);
    let sep = exact.separation;
    let mut problems = String::new();
    let mut first = None;
    let mut fail = |what: &'static str, detail: String| {
        first.get_or_insert(what);
        problems.push_str(&detail);
    };
    match *got {
        Collision::Separated { axis, distance } => {
            let distance = f64::from(distance);
            if sep < -band {
                fail("called apart, but touching", format!("exact depth {:.3e};", -sep / size));
            }
            let along = case.pair.gap(axis.as_dvec3().normalize());
            if (distance - along).abs() > tol || (distance - sep).abs() > tol + band {
                fail(
                    "the distance is not the gap along the axis",
                    format!("distance {distance:e}, gap on the axis {along:e}, exact {sep:e};"),
                );
            }
            t.worst("exact: distance", (distance - sep).abs() / size);
        }
        Collision::Touching(contact) => {
            if sep > band {
                fail("called touching, but apart", format!("exact gap {:.3e};", sep / size));
            }
            let (depth, n) = (f64::from(contact.depth), contact.normal.as_dvec3());
            let overlap = -case.pair.gap(n.normalize());
            if (depth - exact.depth()).abs() > tol || (depth - overlap).abs() > tol {
                fail(
                    "depth",
                    format!(
                        "depth {depth:e}, exact {:e}, along the normal {overlap:e};",
                        exact.depth()
                    ),
                );
            }
            if (n.length() - 1.0).abs() > 1e-5 || overlap > exact.depth() + tol {
                fail(
                    "normal not a least-overlap axis",
                    format!("normal {n} overlaps {overlap:e}, least {:e};", exact.depth()),
                );
            }
            let off = angle_between(n.normalize(), exact.axis);
            if case.pair.tied(exact, NORMAL, DEPTH * size) {
                t.note("exact: normal tied (either right)");
            } else {
                t.worst("exact: normal, rad (not tied)", off);
                if off > NORMAL {
                    fail("normal", format!("normal {n} is {off:e} rad off {};", exact.axis));
                }
            }
            t.worst("exact: depth", (depth - exact.depth()).abs() / size);
            t.worst(
                "exact: overlap along the normal over the least",
                (overlap - exact.depth()) / size,
            );
        }
    }
    if sep.abs() <= band {
        t.note("exact: within the band of touching (either verdict right)");
    }
    match first {
        None => true,
        Some(what) => {
            t.fail(vec![what], format!("{} exact {exact:?}: {problems}", case.describe()));
            false
        }
    }
}

/// Every contact point lies in both bodies grown by the depth, its depth
/// between 0 and the contact's.
fn check_points(t: &mut Tally, case: &Case, got: &Collision) {
    let Some(contact) = got.contact() else { return };
    let depth = f64::from(contact.depth);
    let tol = EXACT * case.pair.size();
    let points = contact.points();
    t.note(format!("manifold: {} point(s), {}", points.len(), case.family));
    if !(1..=2).contains(&points.len()) {
        return t.fail(
            vec!["FAILURE: not 1 or 2 contact points"],
            format!("{} {contact:?}", case.describe()),
        );
    }
    for p in points {
        let (ea, eb) = case.pair.excess(p.position.as_dvec3());
        let within = (-tol..=depth + tol).contains(&f64::from(p.depth));
        if !within || ea.max(eb) > depth + tol {
            let report =
                format!("{} {contact:?}: {p:?} outside A by {ea:e}, B by {eb:e}", case.describe());
            return t.fail(vec!["FAILURE: contact point off the bodies"], report);
        }
        t.worst(
            "manifold: point outside a body, over the depth",
            (ea.max(eb) - depth).max(0.0) / case.pair.size(),
        );
    }
}

/// parry3d's answer against bvol's: each disagreement settled by the oracle.
fn against_parry(t: &mut Tally, case: &Case, got: &Collision, exact: &Exact, right: bool) {
    let size = case.pair.size();
    let pa = parry_pose(&case.pose_a);
    let pb = &case.parry_pose_b;
    let hit = query::intersection_test(&pa, &case.parry_a, pb, case.parry_b)
        .expect("supported")
        .intersecting;
    let contact = query::contact(&pa, &case.parry_a, pb, case.parry_b, 0.0).expect("supported");
    let far = exact.separation.abs() > BAND * size;
    let kind = match (got.contact(), contact) {
        _ if far && got.is_touching() != hit => Some("verdict"),
        (Some(_), None) if hit => Some("touching, but contact() finds none"),
        (Some(c), Some(p)) => {
            let depth_error = (f64::from(c.depth) + f64::from(p.dist)).abs() / size;
            let n = DVec3::new(p.normal1.x.into(), p.normal1.y.into(), p.normal1.z.into());
            let normal_error = angle_between(c.normal.as_dvec3().normalize(), n);
            let tied = case.pair.tied(exact, NORMAL, DEPTH * size);
            if depth_error > DEPTH {
                Some("depth")
            } else if normal_error > NORMAL && !tied {
                Some("normal")
            } else {
                t.worst("parry: depth (agreeing)", depth_error);
                if !tied {
                    t.worst("parry: normal, rad (agreeing, not tied)", normal_error);
                }
                None
            }
        }
        _ => None,
    };
    let Some(kind) = kind else {
        return t.note("parry: agrees");
    };
    if !right {
        return t.note(format!("parry: disagrees, and bvol is wrong ({kind})"));
    }
    let how_far = decade(exact.separation.abs() / size);
    let where_ = match exact.cores_apart_by {
        _ if kind == "verdict" => format!("exact |gap| {how_far} of the size"),
        Some(d) => format!("cores apart by {} of the size", decade(d / size)),
        None => "core sunk in the hull".to_string(),
    };
    // How wrong a normal is: along it, the bodies overlap more than the
    // least, or (a flat minimum: a curved surface) it is off the unique
    // least-overlap axis by more than the bar, yet overlaps within DEPTH.
    let kind = match contact {
        Some(p) if kind == "normal" => {
            let n = DVec3::new(p.normal1.x.into(), p.normal1.y.into(), p.normal1.z.into());
            if -case.pair.gap(n.normalize()) > exact.depth() + DEPTH * size {
                "normal, not a least-overlap axis"
            } else {
                "normal, off the unique least-overlap axis"
            }
        }
        _ => kind,
    };
    let what = format!("parry wrong ({kind}), scale {:e}, {where_}", case.scale);
    t.example(what, || {
        format!("{} exact {exact:?} parry {contact:?} bvol {got:?}", case.describe())
    });
}

/// The decade of a relative length, for the counts.
fn decade(x: f64) -> &'static str {
    match x {
        x if x < 1e-6 => "< 1e-6",
        x if x < 1e-5 => "1e-6..1e-5",
        x if x < 1e-4 => "1e-5..1e-4",
        x if x < 1e-3 => "1e-4..1e-3",
        x if x < 1e-2 => "1e-3..1e-2",
        _ => ">= 1e-2",
    }
}

// ---------------------------------------------------------------------------
// Random shapes and poses

/// The families of poses.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Family {
    /// B's origin within 1.2 times the sum of the sizes of A's.
    Random,
    /// B placed apart, then moved along the line between the closest points
    /// of the cores to exact touching, nudged by 1e-6 to 1e-2 of the size
    /// either way.
    NearTouching,
    /// B's origin within 0.3 of the smaller size of A's.
    Deep,
    /// Two capsules side by side, exactly parallel or off by 1e-7 to 1e-2
    /// rad, near touching or sunk in each other.
    Parallel,
    /// The capsule lying on a face of the hull, its core parallel to it or off
    /// by 1e-7 to 1e-2 rad, near touching, sunk, or its core below the face.
    Lying,
    /// The same pose.
    Identical,
}

impl Family {
    fn name(self) -> &'static str {
        match self {
            Family::Random => "random",
            Family::NearTouching => "near touching",
            Family::Deep => "deep",
            Family::Parallel => "parallel",
            Family::Lying => "lying on a face",
            Family::Identical => "identical poses",
        }
    }
}

/// A capsule at `scale`: radius 0.05 to 1, half height 0 (one in ten) or up to 1.
fn random_capsule(rng: &mut SmallRng, scale: f32) -> Capsule {
    let half_height = if rng.random_bool(0.1) { 0.0 } else { rng.random_range(0.0..1.0) * scale };
    Capsule::new(rng.random_range(0.05..1.0) * scale, half_height)
}

/// `+-size * 10^U(-6, -2)`: a small push off exact touching.
fn nudge(rng: &mut SmallRng, size: f64) -> f64 {
    let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    sign * size * 10f64.powf(rng.random_range(-6.0..-2.0))
}

/// A rotation by 0 (a third of the time) or 1e-7 to 1e-2 rad about a random axis.
fn small_tilt(rng: &mut SmallRng) -> DQuat {
    if rng.random_bool(1.0 / 3.0) {
        return DQuat::IDENTITY;
    }
    let angle = 10f64.powf(rng.random_range(-7.0..-2.0));
    DQuat::from_axis_angle(random_unit(rng).as_dvec3().normalize(), angle)
}

/// The f32 rotation nearest an f64 one.
fn to_quat(r: DQuat) -> Quat {
    r.normalize().as_quat().normalize()
}

/// B's pose moved so that its core (or hull) is `target` from A's core along
/// the line between their closest points (they must be apart): a move along
/// that line keeps the same closest points.
fn slide(pair: &Pair, pose_b: Pose, target: f64) -> Pose {
    let (p, q) = pair.closest().expect("apart");
    let d = p.distance(q);
    let position = pose_b.position.as_dvec3() - (q - p) / d * (d - target);
    Pose { position: position.as_vec3(), ..pose_b }
}

/// A pose for B from a family that places B about A alone (random, deep,
/// near touching, identical), for a B of `size`, with `pair_at` making the
/// exact pair for a pose of B and `radii` the sum of the radii.
fn pose_about<'h>(
    rng: &mut SmallRng,
    family: Family,
    (a, pose_a): (&Capsule, &Pose),
    size: f64,
    radii: f64,
    pair_at: impl Fn(&Pose) -> Pair<'h>,
) -> Pose {
    let size_a = f64::from(a.half_height + a.radius);
    let reach = |rng: &mut SmallRng, r: f64| (random_unit(rng) * r as f32, random_rotation(rng));
    match family {
        Family::Random => {
            let r = rng.random_range(0.0..1.2) * (size_a + size);
            let (d, rotation) = reach(rng, r);
            Pose::new(pose_a.position + d, rotation)
        }
        Family::Deep => {
            let d = random_in_ball(rng, (0.3 * size_a.min(size)) as f32);
            Pose::new(pose_a.position + d, random_rotation(rng))
        }
        Family::NearTouching => {
            let (d, rotation) = reach(rng, 1.5 * (size_a + size));
            let start = Pose::new(pose_a.position + d, rotation);
            slide(&pair_at(&start), start, radii + nudge(rng, size_a.max(size)))
        }
        _ => *pose_a,
    }
}

/// The test hulls at each scale: the primitives and the random hulls.
fn hulls() -> &'static [Vec<TestShape>] {
    static HULLS: OnceLock<Vec<Vec<TestShape>>> = OnceLock::new();
    HULLS.get_or_init(|| {
        SCALES
            .iter()
            .map(|&s| shapes::primitives(s).into_iter().chain(shapes::random_hulls(s)).collect())
            .collect()
    })
}

/// A pose for capsule `a` lying on a random face of `hull` at `place_b`:
/// its core parallel to the face (or off by a small tilt), above a random
/// point of the face, at the radius (nudged), sunk up to the radius, or with
/// its core below the face.
fn lying_on(rng: &mut SmallRng, a: &Capsule, hull: &RefHull, place_b: &Place) -> Pose {
    let f = rng.random_range(0..hull.face_count());
    let face = hull.face(f);
    let weights: Vec<f64> = face.iter().map(|_| rng.random_range(0.01..1.0)).collect();
    let total: f64 = weights.iter().sum();
    let on_face: DVec3 =
        face.iter().zip(&weights).map(|(&i, w)| hull.vertices()[i as usize] * (w / total)).sum();
    let normal = place_b.rotation * hull.normal(f);
    let along =
        place_b.rotation * random_unit(rng).as_dvec3().reject_from(hull.normal(f)).normalize();
    let along = small_tilt(rng) * along;
    let r = f64::from(a.radius);
    let size = hull.radius().max(f64::from(a.radius + a.half_height));
    let height = match rng.random_range(0..3) {
        0 => r + nudge(rng, size),
        1 => r * rng.random_range(0.0..1.0),
        _ => -rng.random_range(0.0..0.05) * size,
    };
    let shift = along * f64::from(a.half_height) * rng.random_range(-0.5..0.5);
    let centre = place_b.point(on_face) + normal * height + shift;
    let spin = DQuat::from_rotation_y(rng.random_range(0.0..std::f64::consts::TAU));
    Pose::new(centre.as_vec3(), to_quat(DQuat::from_rotation_arc(DVec3::Y, along) * spin))
}

// ---------------------------------------------------------------------------
// The random pairs

/// 32 000 capsule-capsule pairs.
#[test]
fn capsules_against_capsules() {
    let started = Instant::now();
    let families = [Family::Random, Family::NearTouching, Family::Deep, Family::Parallel];
    run_chunks(64, 1, |rng, t| {
        for k in 0..500 {
            let family = if k % 50 == 49 { Family::Identical } else { families[k % 4] };
            let scale = SCALES[rng.random_range(0..3)];
            let a = random_capsule(rng, scale);
            let b = if family == Family::Identical && rng.random_bool(0.5) {
                a
            } else {
                random_capsule(rng, scale)
            };
            let pose_a = Pose::new(random_in_ball(rng, 2.0 * scale), random_rotation(rng));
            let size_b = f64::from(b.half_height + b.radius);
            let radii = f64::from(a.radius + b.radius);
            let pair_at = |pose: &Pose| Pair {
                a: Core::capsule(&a, &pose_a),
                b: Other::Core(Core::capsule(&b, pose)),
            };
            let pose_b = if family == Family::Parallel {
                side_by_side(rng, (&a, &pose_a), &b)
            } else {
                pose_about(rng, family, (&a, &pose_a), size_b, radii, pair_at)
            };
            let parry_b = parry3d::shape::Capsule::new_y(b.half_height, b.radius);
            let case = Case::new(
                family,
                pair_at(&pose_b),
                (&a, pose_a),
                (pose_b, &parry_b, parry_pose(&pose_b)),
                (scale, format!("{a:?} vs {b:?}")),
            );
            check(t, &case, capsule_capsule(&a, &pose_a, &b, &pose_b));
        }
    })
    .finish("capsule-capsule pairs", started);
}

/// B's pose beside capsule A, parallel to it (or off by a small tilt),
/// shifted along it, near touching or sunk in it.
fn side_by_side(rng: &mut SmallRng, (a, pose_a): (&Capsule, &Pose), b: &Capsule) -> Pose {
    let place_a = Place::of(pose_a);
    let axis = place_a.rotation * DVec3::Y;
    let across = random_unit(rng).as_dvec3().reject_from(axis).normalize();
    let radii = f64::from(a.radius + b.radius);
    let size = f64::from(a.half_height + a.radius).max(f64::from(b.half_height + b.radius));
    let push = if rng.random_bool(0.5) {
        nudge(rng, size)
    } else {
        -rng.random_range(0.0..0.5) * f64::from(a.radius.min(b.radius))
    };
    let reach = f64::from(a.half_height + b.half_height);
    let shift = axis * reach * rng.random_range(-1.0..1.0);
    let position = place_a.position + across * (radii + push) + shift;
    let rotation = small_tilt(rng) * pose_a.rotation.as_dquat();
    Pose::new(position.as_vec3(), to_quat(rotation))
}

/// 20 000 capsule-ball pairs.
#[test]
fn capsules_against_balls() {
    let started = Instant::now();
    let families = [Family::Random, Family::NearTouching, Family::Deep];
    run_chunks(40, 2, |rng, t| {
        for k in 0..500 {
            let family = families[k % 3];
            let scale = SCALES[rng.random_range(0..3)];
            let a = random_capsule(rng, scale);
            let b =
                Sphere::new(random_in_ball(rng, 0.2 * scale), rng.random_range(0.05..1.0) * scale);
            let pose_a = Pose::new(random_in_ball(rng, 2.0 * scale), random_rotation(rng));
            let size_b = f64::from(b.center.length() + b.radius);
            let radii = f64::from(a.radius + b.radius);
            let pair_at = |pose: &Pose| Pair {
                a: Core::capsule(&a, &pose_a),
                b: Other::Core(Core::ball(&b, pose)),
            };
            let pose_b = pose_about(rng, family, (&a, &pose_a), size_b, radii, pair_at);
            let centre = Place::of(&pose_b).point(b.center.as_dvec3());
            let parry_b = Ball::new(b.radius);
            let case = Case::new(
                family,
                pair_at(&pose_b),
                (&a, pose_a),
                (pose_b, &parry_b, parry_pose(&Pose::new(centre.as_vec3(), Quat::IDENTITY))),
                (scale, format!("{a:?} vs {b:?}")),
            );
            check(t, &case, capsule_sphere(&a, &pose_a, &b, &pose_b));
        }
    })
    .finish("capsule-ball pairs", started);
}

/// One capsule against a hull in its three forms (`poly`, `reference`,
/// `parry`), in a family.
fn capsule_against_hull(
    rng: &mut SmallRng,
    t: &mut Tally,
    family: Family,
    scale: f32,
    (poly, reference, parry): (&Polyhedron, &RefHull, &dyn Shape),
    label: &str,
) {
    let a = random_capsule(rng, scale);
    let size_b = reference.radius();
    let (pose_a, pose_b) = if family == Family::Lying {
        let pose_b = Pose::new(random_in_ball(rng, 2.0 * scale), random_rotation(rng));
        (lying_on(rng, &a, reference, &Place::of(&pose_b)), pose_b)
    } else {
        let pose_a = Pose::new(random_in_ball(rng, 2.0 * scale), random_rotation(rng));
        let pair_at = |pose: &Pose| Pair {
            a: Core::capsule(&a, &pose_a),
            b: Other::Hull { hull: reference, place: Place::of(pose) },
        };
        (pose_a, pose_about(rng, family, (&a, &pose_a), size_b, a.radius.into(), pair_at))
    };
    let pair = Pair {
        a: Core::capsule(&a, &pose_a),
        b: Other::Hull { hull: reference, place: Place::of(&pose_b) },
    };
    let case = Case::new(
        family,
        pair,
        (&a, pose_a),
        (pose_b, parry, parry_pose(&pose_b)),
        (scale, format!("{a:?} vs {label}")),
    );
    check(t, &case, capsule_hull(&a, &pose_a, poly, &pose_b));
}

/// The hull families.
const HULL_FAMILIES: [Family; 4] =
    [Family::Random, Family::NearTouching, Family::Deep, Family::Lying];

/// 24 000 capsule-box pairs: boxes of half extents 0.02 to 1 (times the
/// scale), as `Polyhedron::cuboid` and parry3d's `Cuboid`.
#[test]
fn capsules_against_boxes() {
    let started = Instant::now();
    run_chunks(48, 3, |rng, t| {
        for k in 0..500 {
            let scale = SCALES[rng.random_range(0..3)];
            let mut side = || rng.random_range(0.02..1.0) * scale;
            let half = Vec3::new(side(), side(), side());
            let poly = Polyhedron::cuboid(half).expect("a box");
            let reference = RefHull::cuboid(half.as_dvec3());
            let cuboid = Cuboid::new(to_parry(half));
            let shapes = (&poly, &reference, &cuboid as &dyn Shape);
            capsule_against_hull(
                rng,
                t,
                HULL_FAMILIES[k % 4],
                scale,
                shapes,
                &format!("box {half}"),
            );
        }
    })
    .finish("capsule-box pairs", started);
}

/// 24 000 capsule-hull pairs: the primitives (cube, tetrahedron, slab, rod,
/// 80-vertex ball) and random hulls of 8 to 200 points.
#[test]
fn capsules_against_hulls() {
    let started = Instant::now();
    run_chunks(48, 4, |rng, t| {
        for k in 0..500 {
            let which = rng.random_range(0..3);
            let scene = &hulls()[which];
            let hull = &scene[rng.random_range(0..scene.len())];
            let shapes = (&hull.poly, &hull.reference, &hull.parry as &dyn Shape);
            capsule_against_hull(rng, t, HULL_FAMILIES[k % 4], SCALES[which], shapes, &hull.name);
        }
    })
    .finish("capsule-hull pairs", started);
}

// ---------------------------------------------------------------------------
// Manifolds where capsules lie side by side or on a face

/// The contact of a pair that must touch.
fn touching(hit: Result<Collision, NarrowError>) -> bvol_narrow::Contact {
    *hit.expect("no error").contact().expect("touching")
}

/// The contact points' positions, sorted by x then y.
fn positions(contact: &bvol_narrow::Contact) -> Vec<Vec3> {
    let mut p: Vec<Vec3> = contact.points().iter().map(|p| p.position).collect();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p
}

/// Two capsules along x side by side (B 0.9 above A, shifted by 0.5 along
/// x): a point at each end of the stretch where they face each other, x
/// -0.5 to 1, midway between the surfaces; still two when B is turned by
/// 1e-3 rad, one when it is turned by 0.3 rad (crossing A) or lies end to end.
#[test]
fn parallel_capsules_touch_at_both_ends_of_their_overlap() {
    let along_x = Quat::from_rotation_z(-std::f32::consts::FRAC_PI_2);
    let a = Capsule::new(0.5, 1.0);
    let b = Capsule::new(0.5, 1.0);
    let pose_a = Pose::new(Vec3::ZERO, along_x);
    for (turn, count) in [(0.0, 2), (1e-3, 2), (0.3, 1)] {
        let pose_b = Pose::new(Vec3::new(0.5, 0.9, 0.0), Quat::from_rotation_y(turn) * along_x);
        let contact = touching(capsule_capsule(&a, &pose_a, &b, &pose_b));
        assert_eq!(contact.points().len(), count, "turned {turn}: {contact:?}");
        assert!((contact.depth - 0.1).abs() < 1e-6, "{contact:?}");
        assert!((contact.normal - Vec3::Y).length() < 1e-6, "{contact:?}");
        if turn == 0.0 {
            let p = positions(&contact);
            assert!((p[0] - Vec3::new(-0.5, 0.45, 0.0)).length() < 1e-6, "{p:?}");
            assert!((p[1] - Vec3::new(1.0, 0.45, 0.0)).length() < 1e-6, "{p:?}");
            assert!(contact.points().iter().all(|p| (p.depth - 0.1).abs() < 1e-6));
        }
    }
    // End to end along x: the caps touch at one point.
    let pose_b = Pose::new(Vec3::new(2.9, 0.0, 0.0), along_x);
    let contact = touching(capsule_capsule(&a, &pose_a, &b, &pose_b));
    assert_eq!(contact.points().len(), 1, "{contact:?}");
    assert!((contact.normal - Vec3::X).length() < 1e-6 && (contact.depth - 0.1).abs() < 1e-6);
}

/// A capsule lying on a box's top face (along x, sunk 0.01): a point below
/// each end of its core; with an end over the box's edge, the second point
/// at the edge; sunk below its radius (the core under the face), still two;
/// tilted by 0.1 rad so that one end lifts off, one point.
#[test]
fn a_capsule_lying_on_a_box_touches_at_two_points() {
    let floor = Polyhedron::cuboid(Vec3::new(2.0, 0.5, 2.0)).unwrap();
    let capsule = Capsule::new(0.25, 1.0);
    let along_x = Quat::from_rotation_z(-std::f32::consts::FRAC_PI_2);
    let on = |x: f32, y: f32, turn: f32| {
        Pose::new(Vec3::new(x, y, 0.3), Quat::from_rotation_z(turn) * along_x)
    };
    let contact = touching(capsule_hull(&capsule, &on(0.0, 0.74, 0.0), &floor, &Pose::IDENTITY));
    assert_eq!(positions(&contact), [Vec3::new(-1.0, 0.495, 0.3), Vec3::new(1.0, 0.495, 0.3)]);
    // Over the edge at x = 2: the core clipped there.
    let contact = touching(capsule_hull(&capsule, &on(1.5, 0.74, 0.0), &floor, &Pose::IDENTITY));
    let p = positions(&contact);
    assert!((p[0] - Vec3::new(0.5, 0.495, 0.3)).length() < 1e-6, "{p:?}");
    assert!((p[1] - Vec3::new(2.0, 0.495, 0.3)).length() < 1e-6, "{p:?}");
    // The core 0.1 under the face: depth 0.35, each point halfway.
    let contact = touching(capsule_hull(&capsule, &on(0.0, 0.4, 0.0), &floor, &Pose::IDENTITY));
    assert!((contact.depth - 0.35).abs() < 1e-6 && (contact.normal + Vec3::Y).length() < 1e-6);
    let p = positions(&contact);
    assert!((p[0] - Vec3::new(-1.0, 0.325, 0.3)).length() < 1e-6, "{p:?}");
    assert!((p[1] - Vec3::new(1.0, 0.325, 0.3)).length() < 1e-6, "{p:?}");
    // Tilted: its low end touches, the other is 0.2 up.
    let contact = touching(capsule_hull(&capsule, &on(0.0, 0.74, 0.1), &floor, &Pose::IDENTITY));
    assert_eq!(contact.points().len(), 1, "{contact:?}");
}

/// A capsule lying on each face of the random hulls and primitives, its core
/// parallel to the face and well inside it, sunk by a tenth of its radius:
/// two points, each below an end of the core and as deep as the contact.
#[test]
fn a_capsule_lying_on_a_hull_face_touches_at_two_points() {
    let mut checked = 0;
    for hull in shapes::primitives(1.0).iter().chain(&shapes::random_hulls(1.0)) {
        let reference = &hull.reference;
        for f in 0..reference.face_count() {
            let face = reference.face(f);
            let corners: Vec<DVec3> =
                face.iter().map(|&i| reference.vertices()[i as usize]).collect();
            let centre = corners.iter().sum::<DVec3>() / corners.len() as f64;
            // The largest inscribed circle about the centre, roughly: the
            // nearest edge line.
            let n = reference.normal(f);
            let inner = (0..corners.len())
                .map(|k| {
                    let (p, q) = (corners[k], corners[(k + 1) % corners.len()]);
                    (centre - p).reject_from(q - p).length()
                })
                .fold(f64::INFINITY, f64::min);
            let along = (corners[0] - centre).reject_from(n).normalize();
            let half = 0.5 * inner;
            if half < 1e-3 {
                continue;
            }
            let capsule = Capsule::new(0.2, half as f32);
            let position = centre + n * 0.18;
            let pose =
                Pose::new(position.as_vec3(), to_quat(DQuat::from_rotation_arc(DVec3::Y, along)));
            let contact = touching(capsule_hull(&capsule, &pose, &hull.poly, &Pose::IDENTITY));
            assert_eq!(contact.points().len(), 2, "{} face {f}: {contact:?}", hull.name);
            for p in contact.points() {
                assert!(
                    (p.depth - contact.depth).abs() < 1e-5,
                    "{} face {f}: {contact:?}",
                    hull.name
                );
                let height = (p.position.as_dvec3() - centre).dot(n);
                assert!((height + 0.01).abs() < 1e-5, "{} face {f}: {contact:?}", hull.name);
            }
            checked += 1;
        }
    }
    assert!(checked > 500, "{checked}");
}

// ---------------------------------------------------------------------------
// Degenerate capsules, and bad input

/// A capsule of half height 0 is a ball: each routine gives the answer of
/// the sphere routine for the same balls (verdict, normal, depth or
/// distance, point), to f64 rounding of the f32 input.
#[test]
fn a_capsule_of_no_length_answers_as_a_sphere() {
    let mut rng = SmallRng::seed_from_u64(9);
    let cube = Polyhedron::cuboid(Vec3::splat(0.5)).unwrap();
    let hull = &hulls()[1][7];
    let same = |capsule: Collision, sphere: Collision| match (capsule, sphere) {
        (
            Collision::Separated { axis: a, distance: d },
            Collision::Separated { axis: b, distance: e },
        ) => {
            assert!((a - b).length() < 1e-6 && (d - e).abs() < 1e-6, "{capsule:?} {sphere:?}");
        }
        (Collision::Touching(c), Collision::Touching(s)) => {
            assert!((c.normal - s.normal).length() < 1e-6, "{c:?} {s:?}");
            assert!((c.depth - s.depth).abs() < 1e-6, "{c:?} {s:?}");
            assert_eq!(c.points().len(), s.points().len());
            let (p, q) = (c.points()[0], s.points()[0]);
            assert!((p.position - q.position).length() < 1e-5 && (p.depth - q.depth).abs() < 1e-6);
        }
        _ => panic!("verdicts differ: {capsule:?} {sphere:?}"),
    };
    for k in 0..3000 {
        let r = rng.random_range(0.05..1.0);
        let capsule = Capsule::new(r, 0.0);
        let ball = Sphere::new(Vec3::ZERO, r);
        let other = Sphere::new(random_in_ball(&mut rng, 0.2), rng.random_range(0.05..1.0));
        let pose_a = Pose::new(random_in_ball(&mut rng, 1.0), random_rotation(&mut rng));
        let pose_b = if k % 100 == 0 {
            pose_a
        } else {
            Pose::new(random_in_ball(&mut rng, 2.5), random_rotation(&mut rng))
        };
        let as_capsule = Capsule::new(other.radius, 0.0);
        let moved = Pose::new(pose_b.transform_point(other.center), pose_b.rotation);
        same(
            capsule_capsule(&capsule, &pose_a, &as_capsule, &moved).unwrap(),
            sphere_sphere(&ball, &pose_a, &other, &pose_b).unwrap(),
        );
        same(
            capsule_sphere(&capsule, &pose_a, &other, &pose_b).unwrap(),
            sphere_sphere(&ball, &pose_a, &other, &pose_b).unwrap(),
        );
        for b in [&cube, &hull.poly] {
            same(
                capsule_hull(&capsule, &pose_a, b, &pose_b).unwrap(),
                sphere_hull(&ball, &pose_a, b, &pose_b).unwrap(),
            );
        }
    }
}

/// A NaN or infinite pose, or a capsule or sphere with a NaN, infinite or
/// negative field, is a typed error naming the body, from every routine.
#[test]
fn bad_input_is_a_typed_error() {
    let good = Capsule::new(0.5, 1.0);
    let ball = Sphere::new(Vec3::ZERO, 1.0);
    let cube = Polyhedron::cuboid(Vec3::ONE).unwrap();
    let pose = Pose::IDENTITY;
    let nan = Pose::new(Vec3::new(f32::NAN, 0.0, 0.0), Quat::IDENTITY);
    let zero_turn = Pose::new(Vec3::ZERO, Quat::from_xyzw(0.0, 0.0, 0.0, 0.0));
    let pose_error = |body| Err(NarrowError::NonFinitePose { body });
    let shape_error = |body| Err(NarrowError::NonFiniteShape { body });
    use bvol_narrow::Body::{A, B};
    for bad in [nan, zero_turn] {
        assert_eq!(capsule_capsule(&good, &bad, &good, &pose), pose_error(A));
        assert_eq!(capsule_capsule(&good, &pose, &good, &bad), pose_error(B));
        assert_eq!(capsule_sphere(&good, &bad, &ball, &pose), pose_error(A));
        assert_eq!(capsule_sphere(&good, &pose, &ball, &bad), pose_error(B));
        assert_eq!(capsule_hull(&good, &bad, &cube, &pose), pose_error(A));
        assert_eq!(capsule_hull(&good, &pose, &cube, &bad), pose_error(B));
    }
    for bad in [
        Capsule::new(-0.5, 1.0),
        Capsule::new(0.5, -1.0),
        Capsule::new(f32::NAN, 1.0),
        Capsule::new(0.5, f32::INFINITY),
    ] {
        assert_eq!(capsule_capsule(&bad, &pose, &good, &pose), shape_error(A));
        assert_eq!(capsule_capsule(&good, &pose, &bad, &pose), shape_error(B));
        assert_eq!(capsule_sphere(&bad, &pose, &ball, &pose), shape_error(A));
        assert_eq!(capsule_hull(&bad, &pose, &cube, &pose), shape_error(A));
    }
    for bad in [Sphere::new(Vec3::ZERO, -1.0), Sphere::new(Vec3::NAN, 1.0)] {
        assert_eq!(capsule_sphere(&good, &pose, &bad, &pose), shape_error(B));
    }
}

// ---------------------------------------------------------------------------
// Where parry3d 0.31.1 is wrong, and bvol exact

/// Two capsules of size about 1e-3, apart by 1.99e-4 (a pair of the random
/// family): parry3d's `intersection_test` calls them intersecting and its
/// `distance` says 7.2e-4; the same pair scaled by 1000 it calls apart by
/// 198.7, which is what bvol and the oracle say of the small pair, times 1000.
#[test]
fn parry_calls_small_capsules_a_fifth_of_their_size_apart_intersecting() {
    let a = Capsule::new(0.000902502, 0.00040674544);
    let b = Capsule::new(0.00029942775, 0.0003590162);
    let pose_a = Pose::new(
        Vec3::new(0.0014257637, -0.00053870556, 0.0010619629),
        Quat::from_xyzw(-0.9648664, -0.07422866, 0.08856941, 0.23596281),
    );
    let pose_b = Pose::new(
        Vec3::new(0.0021292306, 0.0006417281, 1.6691047e-5),
        Quat::from_xyzw(0.037713375, 0.35346872, -0.2937628, 0.88732237),
    );
    let exact = Pair { a: Core::capsule(&a, &pose_a), b: Other::Core(Core::capsule(&b, &pose_b)) };
    let exact = exact.exact();
    let Collision::Separated { distance, .. } = capsule_capsule(&a, &pose_a, &b, &pose_b).unwrap()
    else {
        panic!("apart");
    };
    assert!((f64::from(distance) - exact.separation).abs() < 1e-10, "{distance} {exact:?}");
    assert!((exact.separation - 1.9861e-4).abs() < 1e-8, "{exact:?}");
    let parry = |scale: f32| {
        let capsule =
            |c: &Capsule| parry3d::shape::Capsule::new_y(c.half_height * scale, c.radius * scale);
        let place = |p: &Pose| parry_pose(&Pose::new(p.position * scale, p.rotation));
        let (pa, pb, ca, cb) = (place(&pose_a), place(&pose_b), capsule(&a), capsule(&b));
        let hit = query::intersection_test(&pa, &ca, &pb, &cb).unwrap().intersecting;
        (hit, query::distance(&pa, &ca, &pb, &cb).unwrap().distance)
    };
    let (hit, apart) = parry(1.0);
    assert!(hit && (apart - 7.2e-4).abs() < 1e-5, "{hit} {apart}");
    let (hit, apart) = parry(1000.0);
    assert!(!hit && (f64::from(apart) - 1000.0 * exact.separation).abs() < 1e-3, "{hit} {apart}");
}

/// Found by the contact fuzz target under libFuzzer: a capsule 7028 long
/// and 0.003 thick whose core runs along an edge of a small hull. The part
/// of the core inside the hull rounded to nothing, and the contact point
/// was put at the core's end, 3514 from the hull. It is now on that edge:
/// within the hull's box grown by the contact depth.
#[test]
fn a_long_core_grazing_a_hull_touches_it_where_it_grazes() {
    let hull = Polyhedron::from_points(&[
        Vec3::new(0.068541, 0.084227, -0.113552995),
        Vec3::new(-0.066154, -0.024552, 0.100936),
        Vec3::ZERO,
        Vec3::new(-0.5328125, 0.0, 0.0),
        Vec3::new(-3.41e-9, -0.5328125, 0.0),
    ])
    .unwrap();
    let capsule = Capsule::new(0.00274, 3514.0);
    let contact = touching(capsule_hull(&capsule, &Pose::IDENTITY, &hull, &Pose::IDENTITY));
    let (lo, hi) = (Vec3::new(-0.54, -0.54, -0.12), Vec3::new(0.07, 0.09, 0.11));
    for p in contact.points() {
        let grown = Vec3::splat(contact.depth + 1e-6);
        let inside = (lo - grown).cmple(p.position).all() && p.position.cmple(hi + grown).all();
        assert!(inside, "contact point {} is not at the hull", p.position);
    }
}
