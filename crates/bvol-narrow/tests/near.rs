//! Contacts within a margin ([`contact_within`]) against parry3d 0.31.1's
//! `contact` with the same prediction distance, on random pairs of hulls
//! (the real meshes', random ones, primitives), balls and capsules placed
//! near touching: from 2% of their size deep to 13% apart, with a margin of
//! 10%.
//!
//! For every pair: the same verdict (touching, apart within the margin, or
//! farther), except within [`BAND`] of touching or of the margin, where
//! either answer is right. For a pair apart within the margin, a proof that
//! its distance and normal are right: the closest points lie in their
//! bodies (to [`INSIDE`], on the exact f64 face planes, or the ball's or
//! core's distance), so the bodies are at most that far apart, and each
//! body lies behind the plane through its point square to the normal, so
//! they are at least that far apart. Its distance is then compared with
//! parry3d's (within [`BAND`] counts as agreeing), and the test prints how
//! often parry3d's is off by more: its distances to balls and capsules by
//! up to 4e-3 of the size. A touching pair's contact is `collide_parts`'
//! own; where parry3d and it disagree on touching, the exact reference
//! (hull pairs, a ball and a hull, two balls) settles it, as in parry.rs.
//!
//! Scales 1 and 1e3 only: at 1e-3 parry3d's `contact` may find nothing
//! (PEER_NOTES.md, and `parry_finds_no_contact_at_scale_1e3` in parry.rs).

mod common;

use std::time::Instant;

use bvol_narrow::{Capsule, HullPart, Part, Pose, WarmStart, collide_parts, contact_within};
use bvol_volumes::Sphere;
use common::reference::{Pair, Place, SphereHull};
use common::shapes::{self, TestShape};
use common::tally::{Tally, run_chunks};
use common::{from_parry, parry_pose, random_in_ball, random_rotation, random_unit};
use glam::{DVec3, Vec3};
use parry3d::query;
use parry3d::shape::SharedShape;
use rand::RngExt;
use rand::rngs::SmallRng;

/// Verdict band and distance agreement with parry3d, relative to the size.
const BAND: f64 = 1e-4;
/// How far outside its body a closest point may lie, relative to the size.
const INSIDE: f64 = 1e-5;
/// Agreement with the exact reference on touching, relative to the size.
const EXACT: f64 = 1e-5;
/// The margin, relative to the larger body's size.
const MARGIN: f64 = 0.1;

/// A solid of any kind with its parry3d form.
struct Solid<'a> {
    part: Part,
    parry: SharedShape,
    kind: Kind<'a>,
    /// Farthest point from the local origin.
    size: f64,
}

enum Kind<'a> {
    Hull(&'a TestShape),
    /// A ball about the origin.
    Ball(f64),
    /// Radius and half height of a capsule along y.
    Capsule(f64, f64),
}

impl Solid<'_> {
    fn name(&self) -> String {
        match self.kind {
            Kind::Hull(t) => t.name.clone(),
            Kind::Ball(_) => "ball".into(),
            Kind::Capsule(..) => "capsule".into(),
        }
    }

    /// How far the world point `p` lies outside the solid placed at `place`
    /// (`<= 0` inside): over the exact face planes for a hull.
    fn excess(&self, place: &Place, p: DVec3) -> f64 {
        let q = place.local_point(p);
        match self.kind {
            Kind::Hull(t) => t.reference.plane_excess(place, p),
            Kind::Ball(r) => q.length() - r,
            Kind::Capsule(r, h) => DVec3::new(q.x, q.y - q.y.clamp(-h, h), q.z).length() - r,
        }
    }

    /// How far the solid placed at `place` reaches along the unit world
    /// direction `n`: its support value, exact on a hull's vertices.
    fn reach(&self, place: &Place, n: DVec3) -> f64 {
        let along = |p: DVec3| place.point(p).dot(n);
        match self.kind {
            Kind::Hull(t) => {
                t.reference.vertices().iter().map(|&v| along(v)).fold(f64::MIN, f64::max)
            }
            Kind::Ball(r) => along(DVec3::ZERO) + r,
            Kind::Capsule(r, h) => along(DVec3::Y * h).max(along(-DVec3::Y * h)) + r,
        }
    }

    fn is_hull(&self) -> bool {
        matches!(self.kind, Kind::Hull(_))
    }
}

/// Every hull at `scale`, a ball and a capsule.
fn solids(hulls: &[TestShape], scale: f32) -> Vec<Solid<'_>> {
    let mut all: Vec<Solid> = hulls
        .iter()
        .map(|t| Solid {
            part: Part::Hull(Box::new(HullPart::from_points(&t.points).expect("solid"))),
            parry: SharedShape::new(t.parry.clone()),
            kind: Kind::Hull(t),
            size: t.size,
        })
        .collect();
    let r = 0.5 * scale;
    all.push(Solid {
        part: Part::Ball(Sphere::new(Vec3::ZERO, r)),
        parry: SharedShape::ball(r),
        kind: Kind::Ball(r.into()),
        size: r.into(),
    });
    let (r, h) = (0.2 * scale, 0.6 * scale);
    all.push(Solid {
        part: Part::Capsule(Capsule::new(r, h)),
        parry: SharedShape::capsule_y(h, r),
        kind: Kind::Capsule(r.into(), h.into()),
        size: f64::from(r + h),
    });
    all
}

/// Where B, turned by `pose_b`'s rotation, touches A along `u` from A's
/// position: bisected on bvol's verdict, the bodies' origins being inside
/// them (so touching at 0) and their sizes bounding them (apart beyond the
/// sum).
fn touching_at(a: &Solid, pose_a: &Pose, b: &Solid, pose_b: &Pose, u: Vec3) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.01 * (a.size + b.size));
    for _ in 0..60 {
        let t = 0.5 * (lo + hi);
        let at =
            Pose::new((pose_a.position.as_dvec3() + u.as_dvec3() * t).as_vec3(), pose_b.rotation);
        let hit = collide_parts(&a.part, pose_a, &b.part, &at, &mut WarmStart::default());
        if hit.expect("valid").is_touching() {
            lo = t;
        } else {
            hi = t;
        }
    }
    lo
}

/// The exact separation of two placed solids (the distance, or minus the
/// depth), where the reference has it: hull against hull (whose separation
/// when apart is only a lower bound of the distance, but whose sign is
/// exact), a ball against a hull, two balls.
fn exact_separation(a: &Solid, pose_a: &Pose, b: &Solid, pose_b: &Pose) -> Option<f64> {
    let (pa, pb) = (Place::of(pose_a), Place::of(pose_b));
    let sphere_hull = |r: f64, centre: &Place, hull: &TestShape, place: Place| {
        let center = centre.point(DVec3::ZERO);
        SphereHull { center, radius: r, hull: &hull.reference, place }.sat().separation
    };
    match (&a.kind, &b.kind) {
        (Kind::Hull(x), Kind::Hull(y)) => {
            Some(Pair { a: &x.reference, pa, b: &y.reference, pb }.sat().separation)
        }
        (Kind::Ball(r), Kind::Hull(y)) => Some(sphere_hull(*r, &pa, y, pb)),
        (Kind::Hull(x), Kind::Ball(r)) => Some(sphere_hull(*r, &pb, x, pa)),
        (Kind::Ball(r), Kind::Ball(q)) => Some(pa.position.distance(pb.position) - r - q),
        _ => None,
    }
}

/// A random solid: a mesh hull one time in twelve (slow for parry3d).
fn pick<'a, 'b>(rng: &mut SmallRng, all: &'b [Solid<'a>]) -> &'b Solid<'a> {
    let meshes = shapes::MESHES.len();
    if rng.random_range(0..12) == 0 {
        &all[rng.random_range(0..meshes)]
    } else {
        &all[rng.random_range(meshes..all.len())]
    }
}

/// One random pair near touching, checked.
fn check_one(rng: &mut SmallRng, all: &[Solid], scale: f32, t: &mut Tally) {
    let (a, b) = (pick(rng, all), pick(rng, all));
    let size = a.size.max(b.size);
    let pose_a = Pose::new(random_in_ball(rng, 2.0 * scale), random_rotation(rng));
    let turned = Pose::new(Vec3::ZERO, random_rotation(rng));
    let u = random_unit(rng);
    let gap = rng.random_range(-0.02..0.13) * size;
    let at = touching_at(a, &pose_a, b, &turned, u) + gap;
    let pose_b =
        Pose::new((pose_a.position.as_dvec3() + u.as_dvec3() * at).as_vec3(), turned.rotation);
    let margin = (MARGIN * size) as f32;
    t.pairs += 1;
    let describe = || {
        let (x, y) = (a.name(), b.name());
        format!("{x} at {pose_a:?}, {y} at {pose_b:?}, gap {gap:e}, size {size:e}")
    };
    let mut warm = WarmStart::default();
    let got = contact_within(&a.part, &pose_a, &b.part, &pose_b, margin, &mut warm).expect("valid");
    let (pa, pb) = (parry_pose(&pose_a), parry_pose(&pose_b));
    let parry = query::contact(&pa, &*a.parry, &pb, &*b.parry, margin).expect("supported");
    // Within the band of touching or of the margin, either verdict is right.
    // parry3d may give a pair a little beyond the prediction distance: its
    // verdict is its distance's.
    let dist = parry.map_or(f64::INFINITY, |c| f64::from(c.dist));
    let theirs = if dist <= f64::from(margin) { parry } else { None };
    let near_edge = |d: f64| d.abs() <= BAND * size || (d - f64::from(margin)).abs() <= BAND * size;
    let agree = match (got, theirs) {
        (None, None) => true,
        (Some(c), Some(p)) => c.is_touching() == (p.dist <= 0.0) || near_edge(dist),
        (Some(c), None) => near_edge(-f64::from(c.depth)),
        (None, Some(_)) => near_edge(dist),
    };
    let touching_wrong = match (got, theirs) {
        (Some(c), Some(p)) => c.is_touching() != (p.dist <= 0.0),
        (Some(c), None) => c.is_touching(),
        _ => false,
    };
    if !agree && touching_wrong {
        // Touching or not is collide_parts' verdict, which parry.rs settles
        // by the exact reference: settled here too where one is at hand.
        let exact = exact_separation(a, &pose_a, b, &pose_b);
        let touching = got.is_some_and(|c| c.is_touching());
        if exact.is_some_and(|sep| (sep <= EXACT * size) == touching || sep.abs() <= EXACT * size) {
            return t.note("parry3d wrong on touching (settled exactly)");
        }
    }
    if !agree {
        let said = format!("bvol {:?}, parry3d {:?}", got.map(|c| c.depth), parry.map(|c| c.dist));
        t.fail(vec!["verdict"], format!("{}: {said}, margin {margin:e}", describe()));
        return;
    }
    let Some(c) = got else { return t.note("beyond the margin") };
    if c.is_touching() {
        let cold = collide_parts(&a.part, &pose_a, &b.part, &pose_b, &mut WarmStart::default());
        if cold.expect("valid").contact() != Some(&c) {
            t.fail(vec!["touching contact is not collide_parts'"], describe());
        }
        return t.note("touching");
    }
    let kinds = if a.is_hull() && b.is_hull() { "hulls" } else { "with a ball or capsule" };
    t.note(format!("apart within the margin: {kinds}"));
    let d = -f64::from(c.depth);
    let n = c.normal.as_dvec3();
    let [point] = c.points() else { return t.fail(vec!["points"], describe()) };
    let mid = point.position.as_dvec3();
    let (on_a, on_b) = (mid - n * (d * 0.5), mid + n * (d * 0.5));
    // The points lie in the bodies (so the distance is at most `d`), and the
    // planes through them square to the normal have each body on its side
    // (so it is at least `d`): then `d` is the distance and `n` its direction.
    let (place_a, place_b) = (Place::of(&pose_a), Place::of(&pose_b));
    let inside = a.excess(&place_a, on_a).max(b.excess(&place_b, on_b));
    let beyond = (a.reach(&place_a, n) - n.dot(on_a)).max(b.reach(&place_b, -n) + n.dot(on_b));
    t.worst("closest point outside its body / size", inside.max(0.0) / size);
    t.worst("body beyond its closest point's plane / size", beyond.max(0.0) / size);
    let unit = (n.length() - 1.0).abs() <= 1e-6;
    if inside > INSIDE * size || beyond > INSIDE * size || point.depth != c.depth || !unit {
        return t.fail(vec!["closest points"], describe());
    }
    let Some(p) = parry.filter(|p| p.dist > 0.0) else { return };
    let error = (d - dist).abs() / size;
    if error > BAND {
        // bvol's distance is proved above: parry3d's is off.
        return t.note(format!("parry3d's distance off by more than {BAND:e}: {kinds}"));
    }
    t.worst("distance against parry3d / size (agreeing)", error);
    if dist > 1e-3 * size {
        t.worst(
            "normal against parry3d, rad (agreeing)",
            n.angle_between(from_parry(p.normal1).as_dvec3()),
        );
    }
}

#[test]
fn contacts_within_a_margin_match_parry() {
    for scale in [1.0f32, 1e3] {
        let started = Instant::now();
        let hulls = shapes::all(scale);
        let all = solids(&hulls, scale);
        let tally = run_chunks(48, 0x4ea5 + scale as u64, |rng, t| {
            for _ in 0..800 {
                check_one(rng, &all, scale, t);
            }
        });
        tally.finish(&format!("contact_within against parry3d at scale {scale}"), started);
    }
}

#[test]
fn bad_margins_are_typed_errors() {
    let ball = Part::Ball(Sphere::new(Vec3::ZERO, 1.0));
    let far = Pose::new(Vec3::X * 5.0, glam::Quat::IDENTITY);
    for margin in [-1e-3, f32::NAN, f32::INFINITY] {
        let got =
            contact_within(&ball, &Pose::IDENTITY, &ball, &far, margin, &mut WarmStart::default());
        assert_eq!(got, Err(bvol_narrow::NarrowError::BadMargin), "{margin}");
    }
    let got = contact_within(&ball, &Pose::IDENTITY, &ball, &far, 3.0, &mut WarmStart::default());
    let c = got.unwrap().expect("3 apart, within 3");
    assert_eq!((c.depth, c.normal, c.points()[0].position), (-3.0, Vec3::X, Vec3::X * 2.5));
}
