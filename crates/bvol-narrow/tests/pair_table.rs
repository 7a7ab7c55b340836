//! The pair table against the routines it picks: every pair of kinds, in
//! both orders, answers as the routine for its kinds called directly (the
//! mirrored order with the normal reversed), and an error names the body in
//! the caller's order.

mod common;

use bvol_narrow::{
    Body, Capsule, Collision, HullPart, NarrowError, Part, Polyhedron, Pose, WarmStart,
    capsule_capsule, capsule_hull, capsule_sphere, collide_parts, hull_hull, sphere_hull,
    sphere_sphere,
};
use bvol_volumes::{ConvexHull, Sphere};
use common::{random_in_ball, random_rotation};
use glam::Vec3;
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

/// One part of each kind, about the size of 1.
fn parts(rng: &mut SmallRng) -> [Part; 3] {
    let points: Vec<Vec3> = (0..20).map(|_| random_in_ball(rng, 1.0)).collect();
    let hull = HullPart {
        polyhedron: Polyhedron::from_points(&points).unwrap(),
        hull: ConvexHull::new(&points).unwrap(),
    };
    let centre = random_in_ball(rng, 0.2);
    [
        Part::Hull(Box::new(hull)),
        Part::Ball(Sphere::new(centre, rng.random_range(0.2..1.0))),
        Part::Capsule(Capsule::new(rng.random_range(0.1..0.6), rng.random_range(0.0..1.0))),
    ]
}

/// The routine for `a` against `b` called directly, where the table has
/// one for that order.
fn direct(a: &Part, pa: &Pose, b: &Part, pb: &Pose) -> Option<Result<Collision, NarrowError>> {
    let mut warm = WarmStart::default();
    Some(match (a, b) {
        (Part::Hull(x), Part::Hull(y)) => {
            hull_hull(&x.polyhedron, pa, &y.polyhedron, pb, &mut warm)
        }
        (Part::Ball(x), Part::Hull(y)) => sphere_hull(x, pa, &y.polyhedron, pb),
        (Part::Ball(x), Part::Ball(y)) => sphere_sphere(x, pa, y, pb),
        (Part::Capsule(x), Part::Hull(y)) => capsule_hull(x, pa, &y.polyhedron, pb),
        (Part::Capsule(x), Part::Ball(y)) => capsule_sphere(x, pa, y, pb),
        (Part::Capsule(x), Part::Capsule(y)) => capsule_capsule(x, pa, y, pb),
        _ => return None,
    })
}

#[test]
fn every_pair_of_kinds_answers_as_its_routine_in_either_order() {
    let mut rng = SmallRng::seed_from_u64(25);
    let (mut touching, mut mirrored) = (0, 0);
    for _ in 0..2000 {
        let parts = parts(&mut rng);
        let pa = Pose::new(random_in_ball(&mut rng, 0.5), random_rotation(&mut rng));
        let pb = Pose::new(random_in_ball(&mut rng, 2.5), random_rotation(&mut rng));
        for a in &parts {
            for b in &parts {
                let got = collide_parts(a, &pa, b, &pb, &mut WarmStart::default()).unwrap();
                let expected = match direct(a, &pa, b, &pb) {
                    Some(answer) => answer.unwrap(),
                    None => {
                        mirrored += 1;
                        direct(b, &pb, a, &pa).expect("one order has a routine").unwrap().flipped()
                    }
                };
                assert_eq!(got, expected, "{a:?} at {pa:?} against {b:?} at {pb:?}");
                touching += usize::from(got.is_touching());
            }
        }
    }
    assert!(mirrored == 2000 * 3, "{mirrored}");
    assert!(touching > 2000 && touching < 16000, "{touching}");
}

#[test]
fn errors_name_the_body_in_the_callers_order() {
    let mut rng = SmallRng::seed_from_u64(1);
    let parts = parts(&mut rng);
    let bad = Pose::new(Vec3::NAN, glam::Quat::IDENTITY);
    for a in &parts {
        for b in &parts {
            let mut warm = WarmStart::default();
            let got = collide_parts(a, &bad, b, &Pose::IDENTITY, &mut warm);
            assert_eq!(got, Err(NarrowError::NonFinitePose { body: Body::A }), "{a:?} {b:?}");
            let got = collide_parts(a, &Pose::IDENTITY, b, &bad, &mut warm);
            assert_eq!(got, Err(NarrowError::NonFinitePose { body: Body::B }), "{a:?} {b:?}");
        }
    }
    let bad_ball = Part::Ball(Sphere::new(Vec3::ZERO, -1.0));
    let bad_capsule = Part::Capsule(Capsule::new(f32::NAN, 1.0));
    for bad in [&bad_ball, &bad_capsule] {
        for good in &parts {
            let mut warm = WarmStart::default();
            let got = collide_parts(good, &Pose::IDENTITY, bad, &Pose::IDENTITY, &mut warm);
            assert_eq!(got, Err(NarrowError::NonFiniteShape { body: Body::B }), "{good:?}");
            let got = collide_parts(bad, &Pose::IDENTITY, good, &Pose::IDENTITY, &mut warm);
            assert_eq!(got, Err(NarrowError::NonFiniteShape { body: Body::A }), "{good:?}");
        }
    }
}
