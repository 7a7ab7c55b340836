//! A warm start that reuses touching pairs' features
//! ([`WarmStart::reusing`]) against the exact f64 reference: the same
//! verdict as a cold call at every step, and a contact whose depth is within
//! the documented bound of the least penetration depth and whose normal is
//! an axis along which the bodies overlap by that depth.

mod common;

use bvol_narrow::{Collision, MAX_REUSE, NarrowError, Pose, WarmStart, hull_hull};
use common::reference::{Pair, Place};
use common::shapes::{self, TestShape};
use common::{random_rotation, random_unit};
use glam::{Quat, Vec3};
use rand::SeedableRng;
use rand::rngs::Xoshiro256PlusPlus;

/// A contact's depth may be this much (relative to the size) above the least
/// penetration depth without reuse: `PREFER_ABS` in `hull_hull.rs`.
const SLACK: f64 = 2e-5;

/// Rounding allowed in the comparisons (f32 poses, depths and normals),
/// relative to the size.
const ROUNDING: f64 = 2e-6;

/// Half the diagonal of a shape's local bounding box: the size tolerances
/// are relative to.
fn size(shape: &TestShape) -> f64 {
    let (lo, hi) =
        shape.points.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    f64::from((hi - lo).length()) / 2.0
}

/// Checks one step: the reusing call's answer against the cold call's
/// verdict and the exact reference. Returns whether the pair touched.
fn check(
    (a, pose_a): (&TestShape, &Pose),
    (b, pose_b): (&TestShape, &Pose),
    warm: &mut WarmStart,
    what: &str,
) -> bool {
    let got = hull_hull(&a.poly, pose_a, &b.poly, pose_b, warm).expect("finite");
    let cold = hull_hull(&a.poly, pose_a, &b.poly, pose_b, &mut WarmStart::default());
    assert_eq!(got.is_touching(), cold.expect("finite").is_touching(), "{what}");
    let Collision::Touching(contact) = got else { return false };
    let pair =
        Pair { a: &a.reference, pa: Place::of(pose_a), b: &b.reference, pb: Place::of(pose_b) };
    let size = size(a).max(size(b));
    let least = -pair.sat().separation / size;
    let depth = f64::from(contact.depth) / size;
    let bound = SLACK + 2.0 * f64::from(warm.reuse_tolerance());
    assert!(depth >= least - ROUNDING, "{what}: depth {depth:e} below the least {least:e}");
    assert!(depth <= least + bound + ROUNDING, "{what}: depth {depth:e}, least {least:e}");
    // Along the normal the bodies overlap by the depth: pushed apart along
    // it by that much, they would just touch.
    let along = -pair.gap(contact.normal.as_dvec3().normalize()) / size;
    assert!((along - depth).abs() <= ROUNDING * 5.0, "{what}: overlap {along:e}, depth {depth:e}");
    true
}

/// The test shapes at three scales, set face on face (a face of B turned
/// onto a face of A, then tilted 1e-3 rad) and sunk 1e-5 to 1e-2 of the
/// size; then each step either jittered about that pose (by up to 1e-6 of the
/// size and 1e-6 rad, as a solver's resting pile) or crept along (1e-5 of
/// the size and 1e-5 rad a step, past the tolerance in a few steps), with
/// tolerances 4e-5 and the largest taken. Every step's verdict is the cold
/// call's and its contact keeps the documented bound.
#[test]
fn reused_contacts_stay_within_the_bound() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(27);
    let mut touching = 0;
    for scale in [1e-3f32, 1.0, 1e3] {
        let all = shapes::all(scale);
        for (i, a) in all.iter().enumerate().step_by(3) {
            for b in all.iter().skip(i % 4).step_by(4) {
                let (fa, fb) = (
                    rand::RngExt::random_range(&mut rng, 0..a.reference.face_count()),
                    rand::RngExt::random_range(&mut rng, 0..b.reference.face_count()),
                );
                let (na, nb) = (a.reference.normal(fa).as_vec3(), b.reference.normal(fb).as_vec3());
                let tilt = Quat::from_axis_angle(random_unit(&mut rng), 1e-3);
                let turn = tilt * Quat::from_rotation_arc(nb, -na);
                let start = Pose::new(Vec3::ZERO, turn);
                let pose_a = Pose::IDENTITY;
                let pair = Pair {
                    a: &a.reference,
                    pa: Place::of(&pose_a),
                    b: &b.reference,
                    pb: Place::of(&start),
                };
                let up = na.as_dvec3();
                let touching_at = pair.touching_offset(up, &pair.candidates());
                let s = size(a).max(size(b));
                let sunk = 10f64.powf(rand::RngExt::random_range(&mut rng, -5.0..-2.0)) * s;
                let rest = Pose::new((up * (touching_at - sunk)).as_vec3(), turn);
                for (k, tolerance) in [4e-5, MAX_REUSE].into_iter().enumerate() {
                    let mut warm = WarmStart::reusing(tolerance).expect("a tolerance");
                    let creep = k == 1;
                    let step = random_unit(&mut rng) * (1e-5 * s) as f32;
                    let spin = Quat::from_axis_angle(random_unit(&mut rng), 1e-5);
                    let mut pose_b = rest;
                    for frame in 0..40 {
                        let what = format!(
                            "{} on {}, tolerance {tolerance}, frame {frame}",
                            b.name, a.name
                        );
                        touching +=
                            usize::from(check((a, &pose_a), (b, &pose_b), &mut warm, &what));
                        pose_b = if creep {
                            Pose::new(pose_b.position + step, (spin * pose_b.rotation).normalize())
                        } else {
                            let jitter = random_unit(&mut rng) * (1e-6 * s) as f32;
                            let wobble = Quat::from_axis_angle(random_unit(&mut rng), 1e-6);
                            Pose::new(rest.position + jitter, (wobble * rest.rotation).normalize())
                        };
                    }
                }
            }
        }
    }
    assert!(touching > 5000, "only {touching} touching steps");
}

/// Random hulls turned at random and sunk into each other by up to a tenth
/// of their size, moving 1e-3 of the size and 2e-3 rad a frame (the
/// narrow-phase bench's slowly moving pairs) with the largest tolerance:
/// deep pairs reuse their feature for several frames, and every answer
/// still keeps the bound.
#[test]
fn deep_moving_pairs_keep_the_bound_at_the_largest_tolerance() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(2027);
    let all = shapes::all(1.0);
    let mut touching = 0;
    for (i, a) in all.iter().enumerate() {
        let b = &all[(i * 7 + 3) % all.len()];
        let s = size(a).max(size(b));
        let pose_a = Pose::new(Vec3::ZERO, random_rotation(&mut rng));
        let mut pose_b =
            Pose::new(random_unit(&mut rng) * (0.5 * s) as f32, random_rotation(&mut rng));
        let step = random_unit(&mut rng) * (1e-3 * s) as f32;
        let spin = Quat::from_axis_angle(random_unit(&mut rng), 2e-3);
        let mut warm = WarmStart::reusing(MAX_REUSE).expect("a tolerance");
        for frame in 0..30 {
            let what = format!("{} in {}, frame {frame}", b.name, a.name);
            touching += usize::from(check((a, &pose_a), (b, &pose_b), &mut warm, &what));
            pose_b = Pose::new(pose_b.position + step, (spin * pose_b.rotation).normalize());
        }
    }
    assert!(touching > 300, "only {touching} touching steps");
}

/// A tolerance that is negative, not finite or above the largest is a typed
/// error; zero and the largest are taken, and zero reuses nothing.
#[test]
fn bad_tolerances_are_refused() {
    for bad in [-1e-9, f32::NAN, f32::INFINITY, f32::NEG_INFINITY, MAX_REUSE * 1.001] {
        assert_eq!(WarmStart::reusing(bad), Err(NarrowError::BadTolerance), "{bad}");
    }
    assert!(NarrowError::BadTolerance.to_string().contains("tolerance"));
    assert_eq!(WarmStart::reusing(0.0), Ok(WarmStart::default()));
    assert_eq!(WarmStart::reusing(MAX_REUSE).map(|w| w.reuse_tolerance()), Ok(MAX_REUSE));
}

/// A box sliding off the edge of a tile at a constant height, sunk 1e-4 of
/// the size, with the largest tolerance: the tile's top face, the reused
/// feature, overlaps the box to the end, while the tile's side parts them.
/// Each step's verdict is the cold call's.
#[test]
fn a_box_sliding_off_an_edge_parts_when_a_cold_call_does() {
    let tile = TestShape::new("tile", 1.0, &shapes::box_corners(Vec3::new(2.0, 0.1, 2.0)));
    let cube = TestShape::new("cube", 1.0, &shapes::box_corners(Vec3::splat(0.5)));
    let height = 0.6 - 1e-4 * size(&tile) as f32;
    let mut warm = WarmStart::reusing(MAX_REUSE).expect("a tolerance");
    let (mut touching, mut apart) = (0, 0);
    for frame in 0..200 {
        let pose_b = Pose::new(Vec3::new(2.3 + 2e-3 * frame as f32, height, 0.3), Quat::IDENTITY);
        let what = format!("frame {frame}");
        if check((&tile, &Pose::IDENTITY), (&cube, &pose_b), &mut warm, &what) {
            touching += 1;
        } else {
            apart += 1;
        }
    }
    assert!(touching > 50 && apart > 50, "{touching} touching, {apart} apart");
}
