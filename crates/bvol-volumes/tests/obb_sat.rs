//! The box-box separating-axis test against an independent exact check, on a
//! million random pairs: random, face-touching, nested, coplanar side by side,
//! and near-touching at near-parallel orientations (1e-7 to 1e-3 rad).
//!
//! The reference: two convex polytopes intersect iff an edge of one meets the
//! other (every vertex of the intersection polytope lies on an edge of A inside
//! B or on an edge of B inside A). Each of the 24 edges is clipped against the
//! other box's slabs in f64 (Liang-Barsky), with the boxes' exact corners from
//! the dual basis of their f32 axes. No separating axis is involved.

mod common;

use bvol_volumes::Obb;
use glam::{DMat3, DVec3, Mat3, Quat, Vec3};
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

/// The box's slab set in f64: centre, axes as rows (k = A^T (p - c)), half lengths, corners.
struct Exact {
    center: DVec3,
    to_local: DMat3,
    half: DVec3,
    corners: [DVec3; 8],
}

impl Exact {
    fn new(b: &Obb) -> Exact {
        let a = b.axes.as_dmat3();
        let dual = a.transpose().inverse();
        let (c, h) = (b.center.as_dvec3(), b.half_extents.as_dvec3());
        let corners = std::array::from_fn(|i| {
            let s = DVec3::new(
                if i & 1 == 0 { -h.x } else { h.x },
                if i & 2 == 0 { -h.y } else { h.y },
                if i & 4 == 0 { -h.z } else { h.z },
            );
            c + dual * s
        });
        Exact { center: c, to_local: a.transpose(), half: h, corners }
    }

    /// Whether the segment p..q meets the box (closed).
    fn segment_meets(&self, p: DVec3, q: DVec3) -> bool {
        let o = self.to_local * (p - self.center);
        let d = self.to_local * (q - p);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for i in 0..3 {
            if d[i] == 0.0 {
                if o[i].abs() > self.half[i] {
                    return false;
                }
                continue;
            }
            let (a, b) = ((-self.half[i] - o[i]) / d[i], (self.half[i] - o[i]) / d[i]);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
            if t0 > t1 {
                return false;
            }
        }
        true
    }

    /// The 12 edges as corner index pairs (corners differ in one bit).
    fn edges(&self) -> impl Iterator<Item = (DVec3, DVec3)> + '_ {
        (0..8).flat_map(move |i| {
            [1, 2, 4]
                .into_iter()
                .filter(move |bit| i & bit == 0)
                .map(move |bit| (self.corners[i], self.corners[i | bit]))
        })
    }
}

fn exact_intersect(a: &Obb, b: &Obb) -> bool {
    let (ea, eb) = (Exact::new(a), Exact::new(b));
    ea.edges().any(|(p, q)| eb.segment_meets(p, q))
        || eb.edges().any(|(p, q)| ea.segment_meets(p, q))
}

/// The box grown on every side by `pad`.
fn grown(b: &Obb, pad: f32) -> Obb {
    Obb { half_extents: b.half_extents + Vec3::splat(pad), ..*b }
}

struct Tally {
    pairs: usize,
    wrong_separated: Vec<(Obb, Obb)>,
    loose: Vec<(Obb, Obb)>,
    overlapping: usize,
}

impl Tally {
    /// Checks one pair, in both orders: a "separated" answer must be exact; an
    /// "overlapping" one must be right once both boxes grow by 3e-5 of their
    /// combined size (the test's documented conservative band).
    fn check(&mut self, a: Obb, b: Obb) {
        self.check_order(a, b);
        self.check_order(b, a);
    }

    fn check_order(&mut self, a: Obb, b: Obb) {
        self.pairs += 1;
        if !a.overlaps(&b) {
            if exact_intersect(&a, &b) {
                self.wrong_separated.push((a, b));
            }
            return;
        }
        self.overlapping += 1;
        let pad = 3e-5 * (a.half_extents.element_sum() + b.half_extents.element_sum());
        if !exact_intersect(&grown(&a, pad), &grown(&b, pad)) {
            self.loose.push((a, b));
        }
    }
}

fn random_box(rng: &mut SmallRng, center: Vec3, rotation: Quat) -> Obb {
    let h = Vec3::new(
        rng.random_range(0.01..2.0),
        rng.random_range(0.01..2.0),
        rng.random_range(0.01..2.0),
    );
    Obb { center, axes: Mat3::from_quat(rotation), half_extents: h }
}

fn random_vec(rng: &mut SmallRng, r: f32) -> Vec3 {
    Vec3::new(rng.random_range(-r..r), rng.random_range(-r..r), rng.random_range(-r..r))
}

/// The distance along `u` at which box `b` (its centre at a.center + s u) stops
/// touching `a`, by bisection on the exact check.
fn touching_distance(a: &Obb, b: &Obb, u: Vec3) -> f32 {
    let at = |s: f32| Obb { center: a.center + u * s, ..*b };
    let (mut lo, mut hi) = (0.0f32, 2.0 * (a.half_extents.length() + b.half_extents.length()));
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if exact_intersect(a, &at(mid)) { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

#[test]
fn obb_sat_never_separates_intersecting_boxes() {
    let mut rng = SmallRng::seed_from_u64(0x5A7_0BB);
    let mut tally = Tally { pairs: 0, wrong_separated: vec![], loose: vec![], overlapping: 0 };
    let scales = [1e-3f32, 1.0, 1e3];

    // Random pairs at random scales and offsets.
    for i in 0..250_000 {
        let (s, off) = (scales[i % 3], random_vec(&mut rng, 1e3));
        let qa = common::random_rotation(&mut rng);
        let a = random_box(&mut rng, off, qa);
        let (cb, qb) = (off + random_vec(&mut rng, 3.0), common::random_rotation(&mut rng));
        let b = random_box(&mut rng, cb, qb);
        let scaled = |o: Obb| Obb { center: o.center * s, half_extents: o.half_extents * s, ..o };
        tally.check(scaled(a), scaled(b));
    }
    // Face on face: b stacked on a's +z face, turned about that face's normal.
    for _ in 0..100_000 {
        let q = common::random_rotation(&mut rng);
        let c = random_vec(&mut rng, 10.0);
        let a = random_box(&mut rng, c, q);
        let turn = Quat::from_rotation_z(rng.random_range(0.0..std::f32::consts::TAU));
        let mut b = random_box(&mut rng, Vec3::ZERO, q * turn);
        let slide = Vec3::new(
            rng.random_range(-1.0..1.0) * a.half_extents.x,
            rng.random_range(-1.0..1.0) * a.half_extents.y,
            0.0,
        );
        b.center = a.center + q * (slide + Vec3::Z * (a.half_extents.z + b.half_extents.z));
        tally.check(a, b);
    }
    // Nested: b inside a, and coplanar: same orientation, side by side on a's +x face.
    for _ in 0..50_000 {
        let q = common::random_rotation(&mut rng);
        let c = random_vec(&mut rng, 10.0);
        let a = random_box(&mut rng, c, q);
        let inner = Obb { half_extents: a.half_extents * rng.random_range(0.01f32..0.9), ..a };
        let spin = Mat3::from_quat(common::random_rotation(&mut rng));
        let turned = Obb { axes: a.axes * spin, ..inner };
        tally.check(a, turned);
        let b = random_box(&mut rng, Vec3::ZERO, q);
        let side = Vec3::new(
            a.half_extents.x + b.half_extents.x,
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
        );
        tally.check(a, Obb { center: a.center + q * side, ..b });
    }
    // Near touching at near-parallel orientations: b turned from a by 1e-7..1e-3 rad,
    // placed at the exact touching distance along a random direction, then nudged in and out.
    for _ in 0..25_000 {
        let q = common::random_rotation(&mut rng);
        let c = random_vec(&mut rng, 10.0);
        let a = random_box(&mut rng, c, q);
        let angle = 10f32.powf(rng.random_range(-7.0..-3.0));
        let tilt = Quat::from_axis_angle(common::random_unit(&mut rng), angle);
        let b = random_box(&mut rng, Vec3::ZERO, q * tilt);
        let u = common::random_unit(&mut rng);
        let s = touching_distance(&a, &b, u);
        for nudge in [-1e-3f32, -1e-5, -1e-7, 0.0, 1e-7, 1e-5, 1e-3] {
            tally.check(a, Obb { center: a.center + u * (s * (1.0 + nudge)), ..b });
        }
    }
    // Edge on edge: a's +x+y edge against b's edge, crossed at a small angle.
    for _ in 0..10_000 {
        let a = random_box(&mut rng, Vec3::ZERO, Quat::IDENTITY);
        let angle = 10f32.powf(rng.random_range(-7.0..-3.0));
        let b0 = random_box(
            &mut rng,
            Vec3::ZERO,
            Quat::from_rotation_z(std::f32::consts::FRAC_PI_4) * Quat::from_rotation_x(angle),
        );
        let u = Vec3::new(1.0, 1.0, 0.0).normalize();
        let s = touching_distance(&a, &b0, u);
        for nudge in [-1e-6f32, 0.0, 1e-6] {
            tally.check(a, Obb { center: u * (s * (1.0 + nudge)), ..b0 });
        }
    }

    assert!(tally.pairs >= 1_000_000, "only {} ordered pairs", tally.pairs);
    assert!(
        tally.wrong_separated.is_empty(),
        "{} of {} pairs called separated while intersecting, e.g. {:?}",
        tally.wrong_separated.len(),
        tally.pairs,
        tally.wrong_separated.first()
    );
    assert!(
        tally.loose.is_empty(),
        "{} of {} overlapping answers are apart by more than 3e-5 of the size, e.g. {:?}",
        tally.loose.len(),
        tally.overlapping,
        tally.loose.first()
    );
    // Both answers must be well represented, or the test proves little.
    assert!(tally.overlapping > tally.pairs / 4 && tally.overlapping < tally.pairs * 9 / 10);
}
