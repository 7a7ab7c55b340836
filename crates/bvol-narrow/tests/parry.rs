//! bvol-narrow's pair tests against parry3d 0.31.1 and an exact f64
//! separating-axis reference (tests/common/reference.rs), on more than a
//! million random pairs: 630 000 of hulls (the five real meshes' hulls, random
//! hulls, cube, tetrahedron, slab, rod, ball) at scales 1e-3, 1 and 1e3, in
//! families (random, near touching, face on face, nearly parallel edges,
//! identical poses, deep, moving with warm starts), and 512 000 sphere-hull,
//! sphere-box and box-box pairs.
//!
//! parry3d is not exact everywhere (PEER_NOTES.md): near touching, at
//! identical poses (it gives depth 0), at scale 1e-3 (where `contact` may find
//! nothing). Every disagreement with parry3d is settled by the reference: if
//! bvol agrees with it, the case is counted under the way parry3d is wrong
//! (its wrong verdicts by scale and by how far from touching they are), else
//! it is a failure. Each check prints its counts.
//!
//! Tolerances, relative to the larger body's size (its farthest vertex from its
//! local origin):
//! - against parry3d: depth [`DEPTH`], normal [`PARRY_NORMAL`] radians;
//! - against the reference: the depth, and the overlap along bvol's normal,
//!   within [`DEPTH`] of the least overlap (so the normal is a least-overlap
//!   axis: any such axis is right when several tie); and within [`EXACT`]: the
//!   verdict (inside that band of touching either answer is right: the inputs
//!   are f32 and so are bvol's outputs, whose rounding is a few ulps of the
//!   size), the depth against the overlap along the normal, the gap along a
//!   separating axis, and how far contact points stray from the bodies.

mod common;

use std::cell::OnceCell;
use std::f32::consts::FRAC_PI_4;
use std::fmt::Write as _;
use std::sync::OnceLock;
use std::time::Instant;

use bvol_narrow::{Collision, WarmStart, hull_hull, obb_obb, sphere_obb};
use bvol_volumes::{Obb, Pose, Sphere};
use common::reference::{Candidates, Exact, Pair, Place, Prepared, RefHull, Sat, SphereHull};
use common::shapes::{self, TestShape};
use common::tally::{Tally, run_chunks};
use common::{parry_pose, random_in_ball, random_rotation, random_unit, to_parry};
use glam::{DMat3, DQuat, DVec3, Mat3, Quat, Vec3};
use parry3d::query;
use parry3d::shape::{Ball, Cuboid, Shape};
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

/// Depth agreement with parry3d and with the least overlap of the exact
/// reference, relative to the size (bvol prefers a face over an edge, and A's
/// face over B's, when it is shallower by less than 2e-5 of its own measure of
/// size, so that resting contacts do not flicker).
const DEPTH: f64 = 1e-4;
/// Normal agreement with parry3d, radians.
const PARRY_NORMAL: f64 = 1e-3;
/// Agreement with the exact reference, relative to the size.
const EXACT: f64 = 1e-5;
/// The scales of the test shapes.
const SCALES: [f32; 3] = [1e-3, 1.0, 1e3];
/// One pair in this many of the random and deep families is also checked
/// against the reference (every near-touching one is).
const REFERENCE_EVERY: usize = 4;

/// The test hulls at each scale, built once.
fn scenes() -> &'static [Vec<TestShape>] {
    static SCENES: OnceLock<Vec<Vec<TestShape>>> = OnceLock::new();
    SCENES.get_or_init(|| SCALES.iter().map(|&s| shapes::all(s)).collect())
}

/// A test shape: a mesh hull with probability 1/12 (they are slow for parry3d
/// and the reference alike), otherwise a primitive or a random hull.
fn pick<'a>(rng: &mut SmallRng, shapes: &'a [TestShape]) -> &'a TestShape {
    let meshes = shapes::MESHES.len();
    if rng.random_range(0..12) == 0 {
        &shapes[rng.random_range(0..meshes)]
    } else {
        &shapes[rng.random_range(meshes..shapes.len())]
    }
}

/// `+-size * 10^U(-6, -2)`: a small push off exact touching.
fn nudge(rng: &mut SmallRng, size: f64) -> f64 {
    let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    sign * size * 10f64.powf(rng.random_range(-6.0..-2.0))
}

/// The f32 rotation nearest an f64 one.
fn to_quat(r: DQuat) -> Quat {
    r.normalize().as_quat().normalize()
}

// ---------------------------------------------------------------------------
// One pair, checked

/// Two placed bodies in all three forms, and what to call them.
struct Case<'a> {
    family: &'static str,
    /// parry3d's shapes and poses.
    a: &'a dyn Shape,
    b: &'a dyn Shape,
    parry_a: parry3d::math::Pose,
    parry_b: parry3d::math::Pose,
    /// The exact reference.
    exact: &'a dyn Exact,
    /// bvol's poses.
    pose_a: Pose,
    pose_b: Pose,
    /// The larger body's size.
    size: f64,
    /// The scale of the shapes.
    scale: f32,
    /// Whether the two bodies are the same shape at the same pose.
    identical: bool,
    /// Whether the call was cold: an apart answer's distance is then the gap
    /// measured along its axis. A warm call's may be a lower bound of that
    /// gap, from the motion since it was measured.
    cold: bool,
    /// What the bodies are.
    label: String,
}

impl Case<'_> {
    /// Everything needed to run the pair again.
    fn describe(&self) -> String {
        format!(
            "{} [{}] pose_a {:?} pose_b {:?}",
            self.label, self.family, self.pose_a, self.pose_b
        )
    }
}

/// Angle between two unit vectors, accurate near 0.
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// Checks bvol's answer against the exact one: verdict outside the rounding
/// band, the gap along a separating axis, the depth, that the normal is a
/// least-overlap axis, and the exact one (to [`PARRY_NORMAL`]) unless another
/// ties with it.
fn against_exact(t: &mut Tally, case: &Case, got: &Collision, exact: &Sat) -> bool {
    let (sep, size) = (exact.separation, case.size);
    let band = EXACT * size;
    let mut problems = String::new();
    let mut tags = Vec::new();
    match *got {
        Collision::Separated { axis, distance } => {
            if sep < -band {
                tags.push("FAILURE: called apart, but touching");
                let _ = write!(problems, "called apart, exact depth {:.3e};", -sep / size);
            }
            let axis = axis.as_dvec3();
            let gap = case.exact.gap(axis.normalize());
            // How far the distance falls short of the gap.
            let short = gap - distance as f64;
            if (axis.length() - 1.0).abs() > 1e-5
                || distance <= 0.0
                || short < -band
                || (case.cold && short > band)
            {
                tags.push("FAILURE: the gap along the separating axis is not the distance given");
                let _ =
                    write!(problems, "axis {axis} distance {distance:e}, exact gap on it {gap:e};");
            }
            if case.cold {
                t.worst("exact: gap along bvol's axis", short.abs() / size);
            } else {
                t.worst("exact: distance over the gap along bvol's axis", -short / size);
            }
        }
        Collision::Touching(contact) => {
            if sep > band {
                tags.push("FAILURE: called touching, but apart");
                let _ = write!(problems, "called touching, exact gap {:.3e};", sep / size);
            }
            let depth = exact.depth();
            let n = contact.normal.as_dvec3();
            let overlap = -case.exact.gap(n.normalize());
            let depth_tol = DEPTH * size;
            if (contact.depth as f64 - depth).abs() > depth_tol {
                tags.push("FAILURE: depth not the exact one");
                let _ = write!(problems, "depth {:e}, exact {depth:e};", contact.depth);
            }
            if (n.length() - 1.0).abs() > 1e-5 || overlap > depth + depth_tol {
                tags.push("FAILURE: normal not a least-overlap axis");
                let _ = write!(problems, "normal {n} overlaps {overlap:e}, least {depth:e};");
            }
            let off = angle(n.normalize(), exact.axis);
            if off <= PARRY_NORMAL || !case.exact.tied(exact.axis, PARRY_NORMAL, depth_tol) {
                t.worst("exact: normal, rad, where the least-overlap axis is unique", off);
                if off > PARRY_NORMAL {
                    tags.push("FAILURE: normal not the exact one, which is unique");
                    let _ = write!(problems, "normal {n} is {off:e} rad off {};", exact.axis);
                }
            }
            if (contact.depth as f64 - overlap).abs() > band {
                tags.push("FAILURE: depth not the overlap along the normal");
                let _ = write!(
                    problems,
                    "depth {:e}, overlap along the normal {overlap:e};",
                    contact.depth
                );
            }
            t.worst("exact: depth", (contact.depth as f64 - depth).abs() / size);
            t.worst(
                "exact: depth against the overlap along the normal",
                (contact.depth as f64 - overlap).abs() / size,
            );
            t.worst("exact: overlap along bvol's normal over the least", (overlap - depth) / size);
        }
    }
    if sep.abs() <= band {
        t.note("exact: within the rounding band of touching (either verdict right)");
    }
    if problems.is_empty() {
        return true;
    }
    t.fail(tags, format!("{} exact separation {:.3e}: {problems}", case.describe(), sep / size));
    false
}

/// Every contact point lies in both bodies grown by the depth (and a
/// tolerance), its depth between 0 and the contact's.
fn check_manifold(t: &mut Tally, case: &Case, got: &Collision, grown: impl Fn(Body, DVec3) -> f64) {
    let Some(contact) = got.contact() else { return };
    let points = contact.points();
    let tol = EXACT * case.size;
    let depth = contact.depth as f64;
    let mut problems = String::new();
    let mut tags = Vec::new();
    if points.is_empty() || points.len() > 4 {
        tags.push("FAILURE: not 1 to 4 contact points");
        let _ = write!(problems, "{} points;", points.len());
    }
    for p in points {
        let x = p.position.as_dvec3();
        let (ea, eb) = (grown(Body::A, x), grown(Body::B, x));
        if ea > depth + tol || eb > depth + tol || !(-tol..=depth + tol).contains(&(p.depth as f64))
        {
            tags.push("FAILURE: contact point off the bodies");
            let _ = write!(problems, "point {p:?} outside A by {ea:e}, B by {eb:e};");
        }
        t.worst(
            "manifold: point outside a body, over the depth",
            (ea.max(eb) - depth).max(0.0) / case.size,
        );
    }
    t.note("manifold: contacts checked");
    if !problems.is_empty() {
        t.fail(tags, format!("{} depth {depth:e}: {problems}", case.describe()));
    }
}

/// Which body.
#[derive(Clone, Copy)]
enum Body {
    A,
    B,
}

/// Compares bvol's answer with parry3d's, settles each disagreement with the
/// reference, and checks against the reference anyway when `always` says so.
fn check_pair(t: &mut Tally, case: &Case, got: Collision, always: bool) {
    t.pairs += 1;
    let size = case.size;
    let hit = query::intersection_test(&case.parry_a, case.a, &case.parry_b, case.b)
        .expect("supported")
        .intersecting;
    let parry =
        query::contact(&case.parry_a, case.a, &case.parry_b, case.b, 0.0).expect("supported");
    let exact_cell = OnceCell::new();
    let exact = || *exact_cell.get_or_init(|| case.exact.sat());
    let disagreement = match (got.contact(), hit, parry) {
        (Some(_), false, _) | (None, true, _) => Some("verdict"),
        (Some(_), true, None) => Some("contact missing"),
        (Some(c), true, Some(p)) => {
            let depth_error = (c.depth + p.dist).abs() as f64 / size;
            let normal_error = angle(c.normal.as_dvec3().normalize(), from_parry64(p.normal1));
            if depth_error > DEPTH {
                Some("depth")
            } else if normal_error > PARRY_NORMAL {
                Some("normal")
            } else {
                t.worst("parry: depth (agreeing pairs)", depth_error);
                t.worst("parry: normal, rad (agreeing pairs)", normal_error);
                None
            }
        }
        (None, false, _) => None,
    };
    let right = if always || disagreement.is_some() {
        against_exact(t, case, &got, &exact())
    } else {
        true
    };
    let Some(kind) = disagreement else {
        t.note("parry: agrees");
        return;
    };
    if !right {
        return; // already a failure
    }
    let sat = exact();
    let category = match kind {
        "verdict" if got.is_touching() != (sat.separation <= 0.0) => {
            "bvol: verdict off within the rounding band of touching (either is right)".to_string()
        }
        "verdict" => format!(
            "parry: verdict wrong, scale {:e}, exact |gap| {} of the size",
            case.scale,
            decade(sat.separation.abs() / size)
        ),
        "contact missing" => {
            format!("parry: intersecting, but contact() finds none, scale {:e}", case.scale)
        }
        _ if case.identical && parry.is_some_and(|p| p.dist == 0.0) => {
            "parry: identical poses, depth 0".to_string()
        }
        _ => {
            let p = parry.expect("a contact");
            let n = from_parry64(p.normal1);
            let parry_overlap = -case.exact.gap(n);
            let depth_right = (-(p.dist as f64) - sat.depth()).abs() <= DEPTH * size;
            if !depth_right {
                format!("parry: depth off the exact one, scale {:e}", case.scale)
            } else if parry_overlap > sat.depth() + DEPTH * size {
                format!("parry: normal not a least-overlap axis, scale {:e}", case.scale)
            } else {
                "ambiguous: several least-overlap axes, each side took one".to_string()
            }
        }
    };
    t.example(category, || {
        format!("{} exact {:?} parry {:?} bvol {:?}", case.describe(), sat, parry, got)
    });
}

/// The decade of a relative gap, for the counts of parry3d's wrong verdicts.
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

/// A parry3d vector in f64.
fn from_parry64(v: parry3d::math::Vector) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

// ---------------------------------------------------------------------------
// Hull pairs

/// The hull families.
#[derive(Clone, Copy, Debug)]
enum Family {
    /// Random rotations, B's origin within 1.2 times the sum of the radii.
    Random,
    /// Random rotations, B moved along a random direction to exact touching,
    /// then nudged by +-1e-6 to 1e-2 of the size.
    NearTouching,
    /// A face of B turned against a face of A, then touching and nudged.
    FaceOnFace,
    /// An edge of B turned parallel to an edge of A, off by 1e-7 to 1e-3 rad,
    /// the two facing each other, then touching and nudged.
    ParallelEdges,
    /// Same pose (the same shape half the time).
    Identical,
    /// B's origin within 0.3 of the smaller radius of A's.
    Deep,
}

impl Family {
    /// Its name in the counts.
    fn name(self) -> &'static str {
        match self {
            Family::Random => "random",
            Family::NearTouching => "near touching",
            Family::FaceOnFace => "face on face",
            Family::ParallelEdges => "parallel edges",
            Family::Identical => "identical poses",
            Family::Deep => "deep",
        }
    }
}

/// Moves B (at `pose_b`, touching A) along `u` to exact touching, then by `push`.
/// Returns B's new pose and the pair's candidate axes (unchanged by the move).
fn slide_to_touching(
    a: &TestShape,
    pose_a: &Pose,
    b: &TestShape,
    pose_b: Pose,
    u: DVec3,
    push: f64,
) -> (Pose, Candidates) {
    let pair = hull_pair(a, pose_a, b, &pose_b);
    let candidates = pair.candidates();
    let t = pair.touching_offset(u, &candidates);
    (
        Pose { position: (pose_b.position.as_dvec3() + u * (t + push)).as_vec3(), ..pose_b },
        candidates,
    )
}

/// Poses for a pair of the family, and the pair's candidate axes when they
/// were needed to place it.
fn poses(
    rng: &mut SmallRng,
    family: Family,
    a: &TestShape,
    b: &TestShape,
    scale: f32,
) -> (Pose, Pose, Option<Candidates>) {
    let pose_a = Pose::new(random_in_ball(rng, 2.0 * scale), random_rotation(rng));
    let size = a.size.max(b.size);
    let (ra, rb) = (a.size as f32, b.size as f32);
    match family {
        Family::Random => {
            let d = random_unit(rng) * rng.random_range(0.0..1.2 * (ra + rb));
            (pose_a, Pose::new(pose_a.position + d, random_rotation(rng)), None)
        }
        Family::NearTouching => {
            let start = Pose::new(pose_a.position, random_rotation(rng));
            let u = random_unit(rng).as_dvec3().normalize();
            let (pose_b, candidates) = slide_to_touching(a, &pose_a, b, start, u, nudge(rng, size));
            (pose_a, pose_b, Some(candidates))
        }
        Family::FaceOnFace => {
            let fa = rng.random_range(0..a.reference.face_count());
            let fb = rng.random_range(0..b.reference.face_count());
            let na = Place::of(&pose_a).rotation * a.reference.normal(fa);
            let turn = DQuat::from_rotation_arc(b.reference.normal(fb), -na);
            let twist = DQuat::from_axis_angle(na, rng.random_range(0.0..std::f64::consts::TAU));
            let start = Pose::new(pose_a.position, to_quat(twist * turn));
            // Out mostly along A's face normal, a little sideways.
            let side = random_unit(rng).as_dvec3().reject_from(na) * 0.3;
            let u = (na + side).normalize();
            let push = if rng.random_bool(0.3) {
                -rng.random_range(0.0..0.1) * size
            } else {
                nudge(rng, size)
            };
            let (pose_b, candidates) = slide_to_touching(a, &pose_a, b, start, u, push);
            (pose_a, pose_b, Some(candidates))
        }
        Family::ParallelEdges => {
            let ea = rng.random_range(0..a.reference.edge_count());
            let eb = rng.random_range(0..b.reference.edge_count());
            let ra = Place::of(&pose_a).rotation;
            let (da, [a1, a2]) = a.reference.edge(ea);
            let (db, [b1, b2]) = b.reference.edge(eb);
            // B's frame (edge, outward bisector) onto A's (edge, inward bisector).
            let frame = |d: DVec3, m: DVec3| {
                let d = d.normalize();
                let m = m.reject_from(d).normalize();
                DMat3::from_cols(d, m, d.cross(m))
            };
            let out_a = ra * (a1 + a2);
            let align = frame(ra * da, -out_a) * frame(db, b1 + b2).transpose();
            let tilt = DQuat::from_axis_angle(
                random_unit(rng).as_dvec3().normalize(),
                10f64.powf(rng.random_range(-7.0..-3.0)),
            );
            let start = Pose::new(pose_a.position, to_quat(tilt * DQuat::from_mat3(&align)));
            let push = nudge(rng, size);
            let (pose_b, candidates) =
                slide_to_touching(a, &pose_a, b, start, out_a.normalize(), push);
            (pose_a, pose_b, Some(candidates))
        }
        Family::Identical => (pose_a, pose_a, None),
        Family::Deep => {
            let d = random_in_ball(rng, 0.3 * ra.min(rb));
            (pose_a, Pose::new(pose_a.position + d, random_rotation(rng)), None)
        }
    }
}

/// The exact form of a hull pair.
fn hull_pair<'a>(a: &'a TestShape, pose_a: &Pose, b: &'a TestShape, pose_b: &Pose) -> Pair<'a> {
    Pair { a: &a.reference, pa: Place::of(pose_a), b: &b.reference, pb: Place::of(pose_b) }
}

/// Runs and checks one hull pair.
fn check_hulls(
    t: &mut Tally,
    family: &'static str,
    (a, pose_a): (&TestShape, Pose),
    (b, pose_b): (&TestShape, Pose),
    candidates: Option<Candidates>,
    warm: &mut WarmStart,
    always: bool,
) {
    let pair = hull_pair(a, &pose_a, b, &pose_b);
    let exact = Prepared::new(pair, candidates);
    let case = Case {
        family,
        a: &a.parry,
        b: &b.parry,
        exact: &exact,
        pose_a,
        pose_b,
        parry_a: parry_pose(&pose_a),
        parry_b: parry_pose(&pose_b),
        size: a.size.max(b.size),
        scale: a.scale,
        identical: std::ptr::eq(a, b) && pose_a == pose_b,
        cold: *warm == WarmStart::default(),
        label: format!("{} vs {}", a.name, b.name),
    };
    let got = match hull_hull(&a.poly, &pose_a, &b.poly, &pose_b, warm) {
        Ok(got) => got,
        Err(e) => return t.fail(vec!["FAILURE: error"], format!("{}: {e}", case.describe())),
    };
    check_manifold(t, &case, &got, |body, x| match body {
        Body::A => pair.a.plane_excess(&pair.pa, x),
        Body::B => pair.b.plane_excess(&pair.pb, x),
    });
    check_pair(t, &case, got, always);
}

/// `chunks` chunks of `per_chunk` random hull pairs of each family.
fn hull_families(families: &[Family], chunks: usize, per_chunk: usize, seed: u64) -> Tally {
    run_chunks(chunks, seed, |rng, t| {
        for k in 0..per_chunk {
            let family = families[k % families.len()];
            let which = rng.random_range(0..SCALES.len());
            let (scene, scale) = (&scenes()[which], SCALES[which]);
            let a = pick(rng, scene);
            let b = if matches!(family, Family::Identical) && rng.random_bool(0.5) {
                a
            } else {
                pick(rng, scene)
            };
            let (pose_a, pose_b, candidates) = poses(rng, family, a, b, scale);
            let always =
                !matches!(family, Family::Random | Family::Deep) || k % REFERENCE_EVERY == 0;
            let mut cold = WarmStart::default();
            check_hulls(t, family.name(), (a, pose_a), (b, pose_b), candidates, &mut cold, always);
        }
    })
}

/// 256 000 hull pairs, random and deep (a quarter of them also against the
/// reference, besides every disagreement).
#[test]
fn hulls_random_and_deep() {
    let started = Instant::now();
    hull_families(&[Family::Random, Family::Deep], 64, 4000, 1)
        .finish("random and deep hull pairs", started);
}

/// 128 000 hull pairs slid to exact touching and nudged by 1e-6 to 1e-2 of
/// the size either way.
#[test]
fn hulls_near_touching() {
    let started = Instant::now();
    hull_families(&[Family::NearTouching], 64, 2000, 2).finish("near-touching hull pairs", started);
}

/// 128 000 hull pairs, face on face or with nearly parallel edges facing,
/// near touching.
#[test]
fn hulls_face_on_face_and_parallel_edges() {
    let started = Instant::now();
    hull_families(&[Family::FaceOnFace, Family::ParallelEdges], 64, 2000, 3)
        .finish("face-on-face and parallel-edge hull pairs", started);
}

/// 16 000 hull pairs at one pose, half of them a shape with itself.
#[test]
fn hulls_identical_poses() {
    let started = Instant::now();
    hull_families(&[Family::Identical], 16, 1000, 4)
        .finish("hull pairs at identical poses", started);
}

/// 102 400 steps of slowly moving hull pairs, each with one warm start kept
/// along its path: B starts near A and drifts by 1/100 of the size and 0.01
/// rad a step.
#[test]
fn hulls_moving_with_warm_starts() {
    let started = Instant::now();
    let steps = 40;
    run_chunks(64, 5, |rng, t| {
        for _ in 0..40 {
            let which = rng.random_range(0..SCALES.len());
            let (scene, scale) = (&scenes()[which], SCALES[which]);
            let (a, b) = (pick(rng, scene), pick(rng, scene));
            let (pose_a, mut pose_b, _) = poses(rng, Family::Random, a, b, scale);
            let size = a.size.max(b.size) as f32;
            let velocity = random_unit(rng) * 0.01 * size;
            let spin = Quat::from_axis_angle(random_unit(rng), 0.01);
            let mut warm = WarmStart::default();
            for k in 0..steps {
                let always = k % REFERENCE_EVERY == 0;
                check_hulls(t, "moving", (a, pose_a), (b, pose_b), None, &mut warm, always);
                pose_b =
                    Pose::new(pose_b.position + velocity, (spin * pose_b.rotation).normalize());
            }
        }
    })
    .finish("moving hull pairs with warm starts", started);
}

// ---------------------------------------------------------------------------
// Spheres and boxes

/// A box in its body's space: half extents 0.01 to 1, centre within 0.2 of
/// the origin, random axes; all times the scale.
fn random_obb(rng: &mut SmallRng, scale: f32) -> Obb {
    let mut side = || rng.random_range(0.01..1.0) * scale;
    let half_extents = Vec3::new(side(), side(), side());
    Obb {
        center: random_in_ball(rng, 0.2 * scale),
        axes: Mat3::from_quat(random_rotation(rng)),
        half_extents,
    }
}

/// Where a box's own frame is in the world: its centre and axes (made
/// orthonormal in f64, the first axis kept, as bvol-narrow documents), then
/// its pose.
fn obb_place(obb: &Obb, pose: &Pose) -> Place {
    let (x, y) = (obb.axes.x_axis.as_dvec3().normalize(), obb.axes.y_axis.as_dvec3());
    let y = y.reject_from(x).normalize();
    let rotation = DMat3::from_cols(x, y, x.cross(y));
    Place { rotation, position: obb.center.as_dvec3() }.then(&Place::of(pose))
}

/// parry3d's pose for a placement (rounded to f32).
fn parry_place(p: &Place) -> parry3d::math::Pose {
    parry_pose(&Pose::new(p.position.as_vec3(), to_quat(DQuat::from_mat3(&p.rotation))))
}

/// A box pair case's poses: the hull families' analogues (face on face and
/// parallel edges both as B's axes those of A off by 1e-7 to 1e-3 rad).
fn box_poses(rng: &mut SmallRng, family: Family, a: &Obb, b: &Obb, scale: f32) -> (Pose, Pose) {
    let pose_a = Pose::new(random_in_ball(rng, 2.0 * scale), random_rotation(rng));
    let (ra, rb) = (a.half_extents.length(), b.half_extents.length());
    let size = ra.max(rb) as f64;
    let place_a = obb_place(a, &pose_a);
    // B's box centred on A's, turned by `turn` (world rotation of B's box).
    let centred = |turn: DMat3| {
        let rotation = turn * b.axes.as_dmat3().transpose();
        let position = place_a.position - rotation * b.center.as_dvec3();
        Pose::new(position.as_vec3(), to_quat(DQuat::from_mat3(&rotation)))
    };
    let slide = |pose_b: Pose, u: DVec3, push: f64| {
        let (ha, hb) = (
            RefHull::cuboid(a.half_extents.as_dvec3()),
            RefHull::cuboid(b.half_extents.as_dvec3()),
        );
        let pair = Pair { a: &ha, pa: place_a, b: &hb, pb: obb_place(b, &pose_b) };
        let t = pair.touching_offset(u, &pair.candidates());
        Pose { position: (pose_b.position.as_dvec3() + u * (t + push)).as_vec3(), ..pose_b }
    };
    match family {
        Family::Random => {
            let d = random_unit(rng) * rng.random_range(0.0..1.2 * (ra + rb));
            (pose_a, Pose::new(place_a.position.as_vec3() + d, random_rotation(rng)))
        }
        Family::NearTouching => {
            let start = centred(DMat3::from_quat(random_rotation(rng).as_dquat()));
            let u = random_unit(rng).as_dvec3().normalize();
            (pose_a, slide(start, u, nudge(rng, size)))
        }
        Family::FaceOnFace | Family::ParallelEdges => {
            let tilt = DQuat::from_axis_angle(
                random_unit(rng).as_dvec3().normalize(),
                10f64.powf(rng.random_range(-7.0..-3.0)),
            );
            let start = centred(DMat3::from_quat(tilt) * place_a.rotation);
            let u = random_unit(rng).as_dvec3().normalize();
            (pose_a, slide(start, u, nudge(rng, size)))
        }
        Family::Identical => (pose_a, pose_a),
        Family::Deep => {
            let d = random_in_ball(rng, 0.3 * ra.min(rb));
            (pose_a, Pose::new(place_a.position.as_vec3() + d, random_rotation(rng)))
        }
    }
}

/// Every family, for boxes.
const BOX_FAMILIES: [Family; 6] = [
    Family::Random,
    Family::NearTouching,
    Family::FaceOnFace,
    Family::ParallelEdges,
    Family::Identical,
    Family::Deep,
];

/// 192 000 box pairs of `obb_obb` in the hull families' analogues.
#[test]
fn boxes() {
    let started = Instant::now();
    run_chunks(128, 6, |rng, t| {
        for k in 0..1500 {
            let family = BOX_FAMILIES[k % BOX_FAMILIES.len()];
            let scale = SCALES[rng.random_range(0..SCALES.len())];
            let a = random_obb(rng, scale);
            let b = if matches!(family, Family::Identical) { a } else { random_obb(rng, scale) };
            let (pose_a, pose_b) = box_poses(rng, family, &a, &b, scale);
            let (place_a, place_b) = (obb_place(&a, &pose_a), obb_place(&b, &pose_b));
            let (ha, hb) = (
                RefHull::cuboid(a.half_extents.as_dvec3()),
                RefHull::cuboid(b.half_extents.as_dvec3()),
            );
            let pair = Pair { a: &ha, pa: place_a, b: &hb, pb: place_b };
            let (ca, cb) =
                (Cuboid::new(to_parry(a.half_extents)), Cuboid::new(to_parry(b.half_extents)));
            let case = Case {
                family: family.name(),
                a: &ca,
                b: &cb,
                exact: &pair,
                pose_a,
                pose_b,
                parry_a: parry_place(&place_a),
                parry_b: parry_place(&place_b),
                size: ha.radius().max(hb.radius()),
                scale,
                identical: matches!(family, Family::Identical),
                cold: true,
                label: format!("box {a:?} vs box {b:?}"),
            };
            let got = match obb_obb(&a, &pose_a, &b, &pose_b) {
                Ok(got) => got,
                Err(e) => {
                    t.fail(vec!["FAILURE: error"], format!("{}: {e}", case.describe()));
                    continue;
                }
            };
            check_manifold(t, &case, &got, |body, x| match body {
                Body::A => ha.plane_excess(&place_a, x),
                Body::B => hb.plane_excess(&place_b, x),
            });
            check_pair(t, &case, got, true);
        }
    })
    .finish("box-box pairs", started);
}

/// A point on the hull's surface and a unit direction in its normal cone
/// (local): inside a face, on an edge or at a vertex, a third of the time each.
/// A sphere centred `s` along that direction from the point is `s` from the hull.
fn surface_point(rng: &mut SmallRng, hull: &RefHull) -> (DVec3, DVec3) {
    let f = rng.random_range(0..hull.face_count());
    let face = hull.face(f);
    let at = |i: u32| hull.vertices()[i as usize];
    let faces_with = |v: &[u32]| -> Vec<usize> {
        (0..hull.face_count()).filter(|&g| v.iter().all(|i| hull.face(g).contains(i))).collect()
    };
    let blend = |rng: &mut SmallRng, normals: &[DVec3]| -> DVec3 {
        normals.iter().map(|&n| n * rng.random_range(0.01..1.0)).sum::<DVec3>().normalize()
    };
    match rng.random_range(0..3) {
        0 => {
            let weights: Vec<f64> = face.iter().map(|_| rng.random_range(0.01..1.0)).collect();
            let total: f64 = weights.iter().sum();
            let q = face.iter().zip(&weights).map(|(&i, w)| at(i) * (w / total)).sum();
            (q, hull.normal(f))
        }
        1 => {
            let k = rng.random_range(0..face.len());
            let ends = [face[k], face[(k + 1) % face.len()]];
            let q = at(ends[0]).lerp(at(ends[1]), rng.random_range(0.0..1.0));
            let normals: Vec<DVec3> = faces_with(&ends).iter().map(|&g| hull.normal(g)).collect();
            (q, blend(rng, &normals))
        }
        _ => {
            let v = face[rng.random_range(0..face.len())];
            let normals: Vec<DVec3> = faces_with(&[v]).iter().map(|&g| hull.normal(g)).collect();
            (at(v), blend(rng, &normals))
        }
    }
}

/// Sphere families: random (the centre within 1.2 times the sum of the radii
/// of B's origin), near touching (a surface point, the centre out along its
/// normal cone by the radius, nudged), deep (within 0.3 of the smaller radius
/// of B's origin), and centred on B's origin.
fn sphere_pose(
    rng: &mut SmallRng,
    family: Family,
    sphere: &Sphere,
    hull: &RefHull,
    place_b: &Place,
) -> Pose {
    let (r, rb) = (sphere.radius as f64, hull.radius());
    let center = match family {
        Family::Random => {
            place_b.position + random_unit(rng).as_dvec3() * rng.random_range(0.0..1.2 * (r + rb))
        }
        Family::NearTouching => {
            let (q, n) = surface_point(rng, hull);
            place_b.point(q + n * (r + nudge(rng, r.max(rb))))
        }
        Family::Deep => place_b.position + random_in_ball(rng, 0.3 * r.min(rb) as f32).as_dvec3(),
        _ => place_b.position,
    };
    let rotation = random_rotation(rng);
    let offset = DMat3::from_quat(rotation.as_dquat()) * sphere.center.as_dvec3();
    Pose::new((center - offset).as_vec3(), rotation)
}

/// The sphere families (see [`sphere_pose`]).
const SPHERE_FAMILIES: [Family; 4] =
    [Family::Random, Family::NearTouching, Family::Deep, Family::Identical];

/// Runs and checks one sphere against a hull or box (`b`, its exact form
/// `hull` at `place_b`).
fn check_sphere(
    t: &mut Tally,
    family: Family,
    (sphere, pose_a): (&Sphere, Pose),
    (b, pose_b, place_b): (&dyn Shape, Pose, Place),
    hull: &RefHull,
    (label, scale): (String, f32),
    test: impl FnOnce() -> Result<Collision, bvol_narrow::NarrowError>,
) {
    let center = Place::of(&pose_a).point(sphere.center.as_dvec3());
    let radius = sphere.radius as f64;
    let exact = SphereHull { center, radius, hull, place: place_b };
    let ball = Ball::new(sphere.radius);
    let case = Case {
        family: family.name(),
        a: &ball,
        b,
        exact: &exact,
        pose_a,
        pose_b,
        parry_a: parry_pose(&Pose::new(center.as_vec3(), Quat::IDENTITY)),
        parry_b: parry_place(&place_b),
        size: radius.max(hull.radius()),
        scale,
        identical: false,
        cold: true,
        label: format!("sphere {sphere:?} vs {label}"),
    };
    let got = match test() {
        Ok(got) => got,
        Err(e) => return t.fail(vec!["FAILURE: error"], format!("{}: {e}", case.describe())),
    };
    check_manifold(t, &case, &got, |body, x| match body {
        Body::A => x.distance(center) - radius,
        Body::B => hull.plane_excess(&place_b, x),
    });
    check_pair(t, &case, got, true);
}

/// A sphere in its body's space: centre within 0.2 of the origin, radius 0.05
/// to 1; all times the scale.
fn random_sphere(rng: &mut SmallRng, scale: f32) -> Sphere {
    Sphere { center: random_in_ball(rng, 0.2 * scale), radius: rng.random_range(0.05..1.0) * scale }
}

/// 128 000 sphere-hull pairs of `sphere_hull`.
#[test]
fn spheres_against_hulls() {
    let started = Instant::now();
    run_chunks(128, 7, |rng, t| {
        for k in 0..1000 {
            let family = SPHERE_FAMILIES[k % SPHERE_FAMILIES.len()];
            let which = rng.random_range(0..SCALES.len());
            let (scene, scale) = (&scenes()[which], SCALES[which]);
            let b = pick(rng, scene);
            let sphere = random_sphere(rng, scale);
            let pose_b = Pose::new(random_in_ball(rng, 2.0 * scale), random_rotation(rng));
            let place_b = Place::of(&pose_b);
            let pose_a = sphere_pose(rng, family, &sphere, &b.reference, &place_b);
            let test = || bvol_narrow::sphere_hull(&sphere, &pose_a, &b.poly, &pose_b);
            let label = (b.name.clone(), scale);
            check_sphere(
                t,
                family,
                (&sphere, pose_a),
                (&b.parry, pose_b, place_b),
                &b.reference,
                label,
                test,
            );
        }
    })
    .finish("sphere-hull pairs", started);
}

/// 192 000 sphere-box pairs of `sphere_obb`.
#[test]
fn spheres_against_boxes() {
    let started = Instant::now();
    run_chunks(128, 8, |rng, t| {
        for k in 0..1500 {
            let family = SPHERE_FAMILIES[k % SPHERE_FAMILIES.len()];
            let scale = SCALES[rng.random_range(0..SCALES.len())];
            let obb = random_obb(rng, scale);
            let sphere = random_sphere(rng, scale);
            let pose_b = Pose::new(random_in_ball(rng, 2.0 * scale), random_rotation(rng));
            let place_b = obb_place(&obb, &pose_b);
            let hull = RefHull::cuboid(obb.half_extents.as_dvec3());
            let pose_a = sphere_pose(rng, family, &sphere, &hull, &place_b);
            let cuboid = Cuboid::new(to_parry(obb.half_extents));
            let test = || sphere_obb(&sphere, &pose_a, &obb, &pose_b);
            let label = (format!("box {obb:?}"), scale);
            check_sphere(
                t,
                family,
                (&sphere, pose_a),
                (&cuboid, pose_b, place_b),
                &hull,
                label,
                test,
            );
        }
    })
    .finish("sphere-box pairs", started);
}

// ---------------------------------------------------------------------------
// Where parry3d 0.31.1 is wrong (PEER_NOTES.md), and bvol is exact

/// Unit cubes, B `gap` above A along z, both turned by the same rotation.
fn stacked_cubes(gap: f32, scale: f32) -> (TestShape, Pose, Pose) {
    let cube = TestShape::new("cube", scale, &shapes::box_corners(Vec3::splat(0.5 * scale)));
    let turn = Quat::from_rotation_x(0.1);
    let pose_b = Pose::new(turn * Vec3::new(0.0, 0.0, (1.0 + gap) * scale), turn);
    (cube, Pose::new(Vec3::ZERO, turn), pose_b)
}

/// A unit cube 2e-4 clear of another (a random pair of poses found by
/// search, exact gap 1.99e-4): parry3d calls them intersecting.
#[test]
fn parry_calls_a_cube_2e4_clear_of_a_cube_intersecting() {
    let cube = TestShape::new("cube", 1.0, &shapes::box_corners(Vec3::splat(0.5)));
    let pose_a =
        Pose::new(Vec3::ZERO, Quat::from_xyzw(-0.42070624, 0.069317795, 0.570678, 0.7018033));
    let pose_b = Pose::new(
        Vec3::new(-0.42159978, -0.93119675, 0.5158997),
        Quat::from_xyzw(0.07020679, 0.8652773, 0.49598187, 0.01918807),
    );
    let exact = hull_pair(&cube, &pose_a, &cube, &pose_b).sat();
    assert!((exact.separation - 1.9915e-4).abs() < 1e-8, "{exact:?}");
    let got =
        hull_hull(&cube.poly, &pose_a, &cube.poly, &pose_b, &mut WarmStart::default()).unwrap();
    let Collision::Separated { axis, distance } = got else { panic!("{got:?}") };
    assert!((distance as f64 - exact.separation).abs() < 1e-8, "{distance}");
    assert!(angle(axis.as_dvec3(), exact.axis) < 1e-6, "{axis}");
    let (pa, pb) = (parry_pose(&pose_a), parry_pose(&pose_b));
    assert!(query::intersection_test(&pa, &cube.parry, &pb, &cube.parry).unwrap().intersecting);
}

/// Identical cubes at one pose: depth 1 (any face normal), parry3d says 0.
#[test]
fn parry_gives_depth_0_for_identical_cubes() {
    let (cube, pose, _) = stacked_cubes(0.0, 1.0);
    let got = hull_hull(&cube.poly, &pose, &cube.poly, &pose, &mut WarmStart::default()).unwrap();
    let contact = got.contact().expect("touching");
    assert!((contact.depth - 1.0).abs() < 1e-6, "{contact:?}");
    let parry =
        query::contact(&parry_pose(&pose), &cube.parry, &parry_pose(&pose), &cube.parry, 0.0);
    assert_eq!(parry.unwrap().expect("a contact").dist, 0.0);
}

/// Cubes of side 1e-3 overlapping by a tenth of that: parry3d's
/// `intersection_test` says yes, its `contact` finds none.
#[test]
fn parry_finds_no_contact_at_scale_1e3() {
    let (cube, pose_a, pose_b) = stacked_cubes(-0.1, 1e-3);
    let got =
        hull_hull(&cube.poly, &pose_a, &cube.poly, &pose_b, &mut WarmStart::default()).unwrap();
    let contact = got.contact().expect("touching");
    assert!((contact.depth - 1e-4).abs() < 1e-9, "{contact:?}");
    let (pa, pb) = (parry_pose(&pose_a), parry_pose(&pose_b));
    assert!(query::intersection_test(&pa, &cube.parry, &pb, &cube.parry).unwrap().intersecting);
    assert!(query::contact(&pa, &cube.parry, &pb, &cube.parry, 0.0).unwrap().is_none());
}

// ---------------------------------------------------------------------------
// Hard cases: a hull against itself, a sliver box, near-parallel edges

/// The teapot's hull (every point of teapot.obj) against itself at one pose:
/// the overlap along any axis is the hull's width along it, so the depth must
/// be the width along the normal given, and the least width.
#[test]
fn teapot_against_itself_at_one_pose() {
    let teapot = TestShape::new("teapot", 1.0, &common::mesh("teapot"));
    let pose = Pose::IDENTITY;
    let got =
        hull_hull(&teapot.poly, &pose, &teapot.poly, &pose, &mut WarmStart::default()).unwrap();
    let contact = got.contact().expect("touching");
    let (lo, hi) =
        teapot.reference.extent_brute(&Place::of(&pose), contact.normal.as_dvec3().normalize());
    let exact = hull_pair(&teapot, &pose, &teapot, &pose).sat();
    assert!((contact.depth as f64 - (hi - lo)).abs() < 1e-4, "{contact:?}: width {}", hi - lo);
    assert!(
        (contact.depth as f64 - exact.depth()).abs() < 1e-4 * teapot.size,
        "{contact:?}: {exact:?}"
    );
}

/// The teapot's hull overlapping a box of half extents 4 by 0.0147 (parry3d
/// agrees to 1e-6): bvol must not call them apart.
#[test]
fn teapot_overlapping_a_box_is_not_apart() {
    let teapot = TestShape::new("teapot", 1.0, &common::mesh("teapot"));
    let cube = TestShape::new("box", 1.0, &shapes::box_corners(Vec3::splat(4.0)));
    let pose_a = Pose::new(
        Vec3::new(-0.10911265, -1.263396, 1.3389624),
        Quat::from_xyzw(-0.09242036, 0.35498393, 0.6369011, -0.67808694),
    );
    let pose_b = Pose::new(
        Vec3::new(-1.4513791, -9.037414, -12.37526),
        Quat::from_xyzw(0.8949247, 0.008425694, 0.35118866, 0.275146),
    );
    let exact = hull_pair(&teapot, &pose_a, &cube, &pose_b).sat();
    assert!((exact.depth() - 0.0147016).abs() < 1e-6, "{exact:?}");
    let got =
        hull_hull(&teapot.poly, &pose_a, &cube.poly, &pose_b, &mut WarmStart::default()).unwrap();
    let contact = got.contact().unwrap_or_else(|| panic!("called apart: {got:?}"));
    assert!((contact.depth as f64 - exact.depth()).abs() < 1e-4 * teapot.size, "{contact:?}");
}

/// The teapot's hull (radius 1) and a random 50-point hull with nearly
/// parallel edges facing, 6e-6 deep: every contact point must lie on both.
/// (The least penetration there is a face of A whose clipped incident face
/// stays above it, B's lowest vertex lying beside the face: the contact is
/// where B's edges cross the face's rim, not at that vertex, which lies
/// 3.5e-2 outside A.)
#[test]
fn nearly_parallel_edges_contact_points_lie_on_both() {
    let teapot = shapes::mesh_hull("teapot", 1.0);
    let other = shapes::random_hulls(1.0).swap_remove(5);
    assert_eq!(other.name, "random50@1");
    let pose_a = Pose::new(
        Vec3::new(0.054220848, 0.074214526, 0.3693062),
        Quat::from_xyzw(0.08913501, 0.3886919, -0.4449911, -0.80184567),
    );
    let pose_b = Pose::new(
        Vec3::new(0.5811451, -0.7471206, -0.009526354),
        Quat::from_xyzw(0.22306088, -0.5836725, 0.7652617, 0.15474094),
    );
    let pair = hull_pair(&teapot, &pose_a, &other, &pose_b);
    let got = hull_hull(&teapot.poly, &pose_a, &other.poly, &pose_b, &mut WarmStart::default());
    let contact = *got.unwrap().contact().expect("touching");
    assert!((contact.depth as f64 - pair.sat().depth()).abs() < 1e-6, "{contact:?}");
    for p in contact.points() {
        let x = p.position.as_dvec3();
        let off = pair.a.plane_excess(&pair.pa, x).max(pair.b.plane_excess(&pair.pb, x));
        assert!(off <= contact.depth as f64 + 1e-6, "{p:?} is {off:e} off: {contact:?}");
    }
}

// ---------------------------------------------------------------------------
// The reference itself, on known cases

/// The unit cube, exactly.
fn cube_ref() -> RefHull {
    RefHull::cuboid(DVec3::splat(0.5))
}

/// A placement from a position and rotation.
fn place(position: Vec3, rotation: Quat) -> Place {
    Place::of(&Pose::new(position, rotation))
}

/// Unturned, at `x` on the x axis.
fn at(x: f32) -> Place {
    place(Vec3::new(x, 0.0, 0.0), Quat::IDENTITY)
}

/// Two unit cubes on the x axis, `d` apart: gap `d - 1` along +x, depth `1 - d`.
#[test]
fn reference_cubes_face_to_face() {
    let c = cube_ref();
    for d in [1.25, 1.0, 0.7, 0.25] {
        let sat = Pair { a: &c, pa: at(0.0), b: &c, pb: at(d) }.sat();
        assert!((sat.separation - (d as f64 - 1.0)).abs() < 1e-15, "{d}: {sat:?}");
        assert_eq!(sat.axis, DVec3::X, "{d}");
        let sat = Pair { a: &c, pa: at(d), b: &c, pb: at(0.0) }.sat();
        assert_eq!(sat.axis, -DVec3::X, "{d}: from A to B");
    }
}

/// Identical cubes at one pose: depth 1 (parry3d says 0); slab on slab: 0.02.
#[test]
fn reference_identical_poses() {
    let c = cube_ref();
    let pose = place(Vec3::new(3.0, -2.0, 1.0), Quat::from_rotation_x(0.3));
    assert!((Pair { a: &c, pa: pose, b: &c, pb: pose }.sat().depth() - 1.0).abs() < 1e-12);
    let slab = RefHull::cuboid(DVec3::new(0.5, 0.5, 0.01));
    assert!((Pair { a: &slab, pa: pose, b: &slab, pb: pose }.sat().depth() - 0.02).abs() < 1e-12);
    // Every face axis of the cubes is minimal: six directions.
    let minimal = Pair { a: &c, pa: pose, b: &c, pb: pose }.minimal_axes(1e-9);
    let mut distinct: Vec<DVec3> = Vec::new();
    for n in minimal {
        if distinct.iter().all(|m| m.dot(n) < 0.999) {
            distinct.push(n);
        }
    }
    assert_eq!(distinct.len(), 6);
}

/// A cube turned 45 degrees about z beside an unturned one: its corner edge is
/// sqrt(1/2) from its centre.
#[test]
fn reference_turned_cube() {
    let c = cube_ref();
    let turned = place(Vec3::new(1.5, 0.0, 0.0), Quat::from_rotation_z(FRAC_PI_4));
    let sat = Pair { a: &c, pa: at(0.0), b: &c, pb: turned }.sat();
    assert!((sat.separation - (1.0 - 0.5f64.sqrt())).abs() < 1e-7, "{sat:?}");
    assert!(sat.axis.dot(DVec3::X) > 1.0 - 1e-12);
}

/// Two cubes whose crossing edges face each other (A's along z, B's along y):
/// only the edge-edge axis x finds the gap `d - sqrt 2`; face axes say less.
#[test]
fn reference_edge_on_edge() {
    let c = cube_ref();
    let pa = place(Vec3::ZERO, Quat::from_rotation_z(FRAC_PI_4));
    for gap in [0.1f32, 0.0, -0.05] {
        let d = 2f32.sqrt() + gap;
        let pb = place(Vec3::new(d, 0.0, 0.0), Quat::from_rotation_y(FRAC_PI_4));
        let pair = Pair { a: &c, pa, b: &c, pb };
        let sat = pair.sat();
        let exact = d as f64 - 2f64.sqrt();
        assert!((sat.separation - exact).abs() < 1e-6, "{gap}: {sat:?}");
        assert!(sat.axis.dot(DVec3::X) > 1.0 - 1e-6, "{gap}: {sat:?}");
        let normals = (0..6).map(|f| c.normal(f));
        let faces: Vec<DVec3> = normals.flat_map(|n| [pa.rotation * n, pb.rotation * n]).collect();
        let faces_only = pair.sat_over(&faces);
        assert!(faces_only.separation < exact - 0.2, "face axes cannot see it");
    }
}

/// The fast reference (Gauss-map pruning, gaps read off the supporting
/// features, hill-climbing extents) gives the plain computation's verdict and
/// depth (every face normal and edge-pair cross product, both ways, extents
/// from every vertex) on random and near-touching pairs (half of these
/// nearly parallel), meshes included on one side. (Apart, the greatest gap is only a lower bound on the distance,
/// and axes that make no Minkowski face may give a better one.) Its touching
/// offset is checked too: a pair slid to touching is touching, up to the f32
/// rounding of the pose, and apart or not as it is pushed on or back.
#[test]
fn reference_shortcuts_agree_with_the_plain_computation() {
    let shapes = shapes::all(1.0);
    let small: Vec<&TestShape> = shapes.iter().filter(|s| s.points.len() <= 80).collect();
    let mut rng = SmallRng::seed_from_u64(7);
    let mut touching = 0;
    for k in 0..1000 {
        let a = if k % 10 == 0 {
            &shapes[rng.random_range(0..shapes.len())]
        } else {
            small[rng.random_range(0..small.len())]
        };
        let b = small[rng.random_range(0..small.len())];
        let pose_a = Pose::new(random_in_ball(&mut rng, 1.0), random_rotation(&mut rng));
        let (pose_b, push) = if k % 2 == 0 {
            (Pose::new(random_in_ball(&mut rng, 1.5), random_rotation(&mut rng)), None)
        } else {
            // Half of these nearly parallel to A (off by 1e-7 to 1e-3 rad).
            let tilt = Quat::from_axis_angle(
                random_unit(&mut rng),
                10f32.powf(rng.random_range(-7.0..-3.0)),
            );
            let turn = if k % 4 == 3 { tilt * pose_a.rotation } else { random_rotation(&mut rng) };
            let start = Pose::new(pose_a.position, turn);
            let push = if k % 8 == 1 { 0.0 } else { nudge(&mut rng, 1.0) };
            let u = random_unit(&mut rng).as_dvec3().normalize();
            (slide_to_touching(a, &pose_a, b, start, u, push).0, Some(push))
        };
        let pair = hull_pair(a, &pose_a, b, &pose_b);
        let (plain, fast) = (pair.sat_brute(), pair.sat());
        let same = if plain.separation > 0.0 {
            fast.separation > 0.0
        } else {
            touching += 1;
            (plain.separation - fast.separation).abs() < 1e-12
        };
        assert!(same, "{} {}: {plain:?} {fast:?}", a.name, b.name);
        let slid = match push {
            Some(push) if push.abs() < 1e-6 => plain.separation.abs() < 1e-6,
            Some(push) => (plain.separation > 0.0) == (push > 0.0),
            None => true,
        };
        assert!(slid, "{} {}: {plain:?} pushed {push:?}", a.name, b.name);
    }
    assert!(touching > 400, "{touching}");
}

/// Moving B by the touching offset leaves the pair exactly touching.
#[test]
fn reference_touching_offset() {
    let c = cube_ref();
    let pair = Pair { a: &c, pa: at(0.0), b: &c, pb: at(0.0) };
    let offset = pair.touching_offset(DVec3::X, &pair.candidates());
    assert!((offset - 1.0).abs() < 1e-15);
    let shapes = shapes::all(1.0);
    let mut rng = SmallRng::seed_from_u64(8);
    for _ in 0..200 {
        let a = &shapes[rng.random_range(0..shapes.len())];
        let b = &shapes[rng.random_range(0..shapes.len())];
        let pa = place(Vec3::ZERO, common::random_rotation(&mut rng));
        let pb = place(common::random_in_ball(&mut rng, 0.05), common::random_rotation(&mut rng));
        let u = common::random_unit(&mut rng).as_dvec3().normalize();
        let pair = Pair { a: &a.reference, pa, b: &b.reference, pb };
        let t = pair.touching_offset(u, &pair.candidates());
        let moved = Pair { pb: Place { position: pb.position + u * t, ..pb }, ..pair };
        assert!(moved.sat().separation.abs() < 1e-12, "{} {}", a.name, b.name);
    }
}

/// Sphere against a unit cube: beside a face, off a corner, and inside.
#[test]
fn reference_sphere_cube() {
    let c = cube_ref();
    let sphere =
        |x: DVec3, r: f64| SphereHull { center: x, radius: r, hull: &c, place: at(0.0) }.sat();
    let sat = sphere(DVec3::new(1.5, 0.0, 0.0), 0.5);
    assert!((sat.separation - 0.5).abs() < 1e-15 && sat.axis == -DVec3::X, "{sat:?}");
    let sat = sphere(DVec3::ONE, 0.25);
    assert!((sat.separation - (0.75f64.sqrt() - 0.25)).abs() < 1e-15);
    assert!((sat.axis + DVec3::ONE.normalize()).length() < 1e-15);
    let sat = sphere(DVec3::new(0.3, 0.0, 0.0), 0.1);
    assert!((sat.separation + 0.3).abs() < 1e-15 && sat.axis == -DVec3::X, "{sat:?}");
}
