//! What each kind of part knows of itself, against references that do not
//! use it: mass properties against closed forms, a grid integration of the
//! part's inside and parry3d; ray entries against a march along the ray with
//! the exact inside test; support points, local bounds, fit points and the
//! enclosing sphere against points sampled on the surface.
//!
//! The inside tests are written here: a hull's face planes (of the exact f64
//! reference, or a box's own), a ball's distance to its centre, a capsule's
//! distance to its core segment.

mod common;

use std::f64::consts::PI;

use bvol_narrow::{Capsule, HullPart, MassProperties, Part, Polyhedron};
use bvol_volumes::{ConvexHull, Pose, Ray, Sphere};
use common::reference::{Place, RefHull};
use common::shapes::{self, TestShape};
use common::{random_in_ball, random_rotation, random_unit};
use glam::{DMat3, DVec3, Mat3, Quat, Vec3};
use parry3d::mass_properties::MassProperties as ParryMass;
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

/// A part under test with what the references need of it.
struct Case {
    name: String,
    part: Part,
    /// `<= 0` inside or on the part, `> 0` outside; the distance to the
    /// surface for round kinds, the greatest excess over a face plane for
    /// hulls (0 on the surface either way).
    inside: Box<dyn Fn(DVec3) -> f64>,
    /// Points on the surface.
    surface: Vec<DVec3>,
    /// The distance from the origin of the part's farthest point.
    size: f64,
    /// Its mass properties by parry3d, at unit density.
    parry: ParryMass,
}

fn hull_part(points: &[Vec3]) -> HullPart {
    HullPart {
        polyhedron: Polyhedron::from_points(points).unwrap(),
        hull: ConvexHull::new(points).unwrap(),
    }
}

/// Points on a hull's faces: its vertices and random points of its triangles.
fn hull_surface(rng: &mut SmallRng, hull: &ConvexHull, n: usize) -> Vec<DVec3> {
    let v: Vec<DVec3> = hull.vertices().iter().map(|p| p.as_dvec3()).collect();
    let triangles: Vec<[u32; 3]> = hull.triangles().collect();
    let mut out = v.clone();
    for _ in 0..n {
        let [a, b, c] = triangles[rng.random_range(0..triangles.len())].map(|i| v[i as usize]);
        let (s, t) = (rng.random::<f64>(), rng.random::<f64>());
        let (s, t) = if s + t > 1.0 { (1.0 - s, 1.0 - t) } else { (s, t) };
        out.push(a + (b - a) * s + (c - a) * t);
    }
    out
}

/// A hull case from its points, tested against `reference`'s face planes.
fn hull_case(rng: &mut SmallRng, name: &str, points: &[Vec3], reference: RefHull) -> Case {
    let part = hull_part(points);
    let surface = hull_surface(rng, &part.hull, 2000);
    let size = surface.iter().map(|p| p.length()).fold(0.0, f64::max);
    let parry_points: Vec<_> = part.hull.vertices().iter().map(|&p| common::to_parry(p)).collect();
    let triangles: Vec<[u32; 3]> = part.hull.triangles().collect();
    // The same triangles: parry3d's own convex polyhedron merges and drops
    // near-coplanar ones.
    let parry = ParryMass::from_trimesh(1.0, &parry_points, &triangles);
    let place = Place::of(&Pose::IDENTITY);
    Case {
        name: name.into(),
        part: Part::Hull(Box::new(part)),
        inside: Box::new(move |p| reference.plane_excess(&place, p)),
        surface,
        size,
        parry,
    }
}

/// A box of `half` extents turned by `rotation` about the origin and moved
/// to `centre`, with its exact planes.
fn box_case(rng: &mut SmallRng, half: Vec3, rotation: Quat, centre: Vec3) -> Case {
    let corners: Vec<Vec3> =
        shapes::box_corners(half).iter().map(|&p| rotation * p + centre).collect();
    let reference = RefHull::cuboid(half.as_dvec3());
    let place = Place::of(&Pose::new(centre, rotation));
    let mut case = hull_case(rng, "box", &corners, reference.clone());
    case.inside = Box::new(move |p| reference.plane_excess(&place, p));
    case
}

fn ball_case(rng: &mut SmallRng, ball: Sphere) -> Case {
    let (c, r) = (ball.center.as_dvec3(), f64::from(ball.radius));
    let surface = (0..2000).map(|_| c + random_unit(rng).as_dvec3().normalize() * r).collect();
    let mut parry = ParryMass::from_ball(1.0, ball.radius);
    parry.local_com = common::to_parry(ball.center);
    Case {
        name: format!("ball {ball:?}"),
        part: Part::Ball(ball),
        inside: Box::new(move |p| p.distance(c) - r),
        surface,
        size: c.length() + r,
        parry,
    }
}

/// The point of the segment from `(0, -h, 0)` to `(0, h, 0)` nearest `p`.
fn on_core(p: DVec3, h: f64) -> DVec3 {
    DVec3::new(0.0, p.y.clamp(-h, h), 0.0)
}

fn capsule_case(rng: &mut SmallRng, capsule: Capsule) -> Case {
    let (r, h) = (f64::from(capsule.radius), f64::from(capsule.half_height));
    // Half on the side (where there is one), half on the caps.
    let surface = (0..2000)
        .map(|k| {
            let u = random_unit(rng).as_dvec3().normalize();
            if k % 2 == 0 && h > 0.0 {
                let across = DVec3::new(u.x, 0.0, u.z).normalize();
                DVec3::new(0.0, rng.random_range(-h..=h), 0.0) + across * r
            } else {
                DVec3::new(0.0, h.copysign(u.y), 0.0) + u * r
            }
        })
        .collect();
    let end = common::to_parry(Vec3::Y * capsule.half_height);
    let parry = ParryMass::from_capsule(1.0, -end, end, capsule.radius);
    Case {
        name: format!("capsule {capsule:?}"),
        part: Part::Capsule(capsule),
        inside: Box::new(move |p| p.distance(on_core(p, h)) - r),
        surface,
        size: h + r,
        parry,
    }
}

/// Every kind: boxes (one turned and moved), a random hull, the bunny's hull,
/// balls, capsules (one of no length, one long and thin).
fn cases() -> Vec<Case> {
    let mut rng = SmallRng::seed_from_u64(25);
    let random: Vec<Vec3> =
        (0..40).map(|_| random_in_ball(&mut rng, 1.5) + Vec3::new(0.5, -0.3, 0.2)).collect();
    let random_reference = RefHull::new(&ConvexHull::new(&random).unwrap());
    let bunny = shapes::mesh_hull("bunny", 1.0);
    let TestShape { points, reference, .. } = bunny;
    let turned = random_rotation(&mut rng);
    vec![
        box_case(&mut rng, Vec3::new(0.3, 0.7, 1.1), Quat::IDENTITY, Vec3::ZERO),
        box_case(&mut rng, Vec3::new(0.5, 0.2, 0.9), turned, Vec3::new(2.0, -1.0, 0.5)),
        hull_case(&mut rng, "random hull", &random, random_reference),
        hull_case(&mut rng, "bunny hull", &points, reference),
        ball_case(&mut rng, Sphere::new(Vec3::ZERO, 1.0)),
        ball_case(&mut rng, Sphere::new(Vec3::new(0.5, -1.0, 2.0), 0.8)),
        capsule_case(&mut rng, Capsule::new(0.4, 0.9)),
        capsule_case(&mut rng, Capsule::new(0.7, 0.0)),
        capsule_case(&mut rng, Capsule::new(0.05, 2.0)),
    ]
}

/// The largest entry of a matrix's magnitude.
fn max_abs(m: DMat3) -> f64 {
    m.to_cols_array().iter().fold(0.0, |a, x| a.max(x.abs()))
}

/// The mass properties of the inside, by the midpoint rule on a grid of `n`
/// cells a side over the part's sampled box (grown by a cell): the volume
/// and centre, and the inertia about that centre.
fn grid_mass(case: &Case, n: usize) -> (f64, DVec3, DMat3) {
    let lo = case.surface.iter().fold(DVec3::INFINITY, |a, &p| a.min(p));
    let hi = case.surface.iter().fold(DVec3::NEG_INFINITY, |a, &p| a.max(p));
    let cell = (hi - lo) / (n - 2) as f64;
    let (lo, dv) = (lo - cell, cell.x * cell.y * cell.z);
    let (mut volume, mut moment, mut second) = (0.0, DVec3::ZERO, DMat3::ZERO);
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let p = lo + (DVec3::new(i as f64, j as f64, k as f64) + 0.5) * cell;
                if (case.inside)(p) <= 0.0 {
                    volume += dv;
                    moment += p * dv;
                    second += DMat3::from_cols(p * p.x, p * p.y, p * p.z) * dv;
                }
            }
        }
    }
    let centre = moment / volume;
    let covariance =
        second - DMat3::from_cols(centre * centre.x, centre * centre.y, centre * centre.z) * volume;
    let trace = covariance.x_axis.x + covariance.y_axis.y + covariance.z_axis.z;
    (volume, centre, DMat3::from_diagonal(DVec3::splat(trace)) - covariance)
}

/// How far two mass properties are apart: the volume relative to the
/// volume, the centre relative to `size`, the inertia relative to its
/// largest entry.
fn mass_errors(
    got: &MassProperties,
    volume: f64,
    centre: DVec3,
    inertia: DMat3,
    size: f64,
) -> [f64; 3] {
    [
        (f64::from(got.volume) - volume).abs() / volume,
        got.center.as_dvec3().distance(centre) / size,
        max_abs(got.inertia.as_dmat3() - inertia) / max_abs(inertia),
    ]
}

/// Errors for a message, two digits each.
fn figures(errors: [f64; 3]) -> String {
    errors.map(|e| format!("{e:.1e}")).join(" ")
}

#[test]
fn mass_properties_match_a_grid_integration_of_the_inside() {
    for case in cases() {
        let got = case.part.mass_properties();
        let (volume, centre, inertia) = grid_mass(&case, 120);
        let errors = mass_errors(&got, volume, centre, inertia, case.size);
        println!("{}: grid errors (volume, centre, inertia) {}", case.name, figures(errors));
        assert!(
            errors[0] < 1e-2 && errors[1] < 1e-3 && errors[2] < 2e-2,
            "{}: {errors:?}",
            case.name
        );
    }
}

#[test]
fn mass_properties_match_parry3d() {
    for case in cases() {
        let got = case.part.mass_properties();
        let theirs = &case.parry;
        let inertia = Mat3::from_cols_array(&theirs.reconstruct_inertia_matrix().to_cols_array());
        let centre = common::from_parry(theirs.local_com).as_dvec3();
        let errors =
            mass_errors(&got, f64::from(theirs.mass()), centre, inertia.as_dmat3(), case.size);
        println!("{}: parry3d errors (volume, centre, inertia) {}", case.name, figures(errors));
        assert!(errors.iter().all(|&e| e < 1e-4), "{}: {errors:?}", case.name);
    }
}

#[test]
fn box_and_ball_mass_properties_are_the_closed_forms() {
    let mut rng = SmallRng::seed_from_u64(1);
    for _ in 0..100 {
        let half = Vec3::new(rng.random(), rng.random(), rng.random()) + 0.1;
        let (rotation, centre) = (random_rotation(&mut rng), random_in_ball(&mut rng, 5.0));
        let case = box_case(&mut rng, half, rotation, centre);
        let got = case.part.mass_properties();
        // m (b² + c²) / 12 for sides a, b, c, about the box's own axes.
        let side = (half * 2.0).as_dvec3();
        let mass = side.x * side.y * side.z;
        let sq = side * side;
        let own = DVec3::new(sq.y + sq.z, sq.x + sq.z, sq.x + sq.y) * (mass / 12.0);
        let r = DMat3::from_quat(rotation.as_dquat());
        let inertia = r * DMat3::from_diagonal(own) * r.transpose();
        let errors = mass_errors(&got, mass, centre.as_dvec3(), inertia, case.size);
        assert!(errors.iter().all(|&e| e < 1e-5), "{half} {rotation} {centre}: {errors:?}");

        let (c, radius) = (random_in_ball(&mut rng, 5.0), rng.random_range(0.01..3.0f32));
        let got = Part::Ball(Sphere::new(c, radius)).mass_properties();
        let mass = 4.0 / 3.0 * PI * f64::from(radius).powi(3);
        let inertia = DMat3::from_diagonal(DVec3::splat(0.4 * mass * f64::from(radius).powi(2)));
        let errors = mass_errors(&got, mass, c.as_dvec3(), inertia, 1.0);
        assert!(errors.iter().all(|&e| e < 1e-6), "{c} {radius}: {errors:?}");
    }
}

/// A capsule's mass properties by slices across its axis, each a disc of
/// radius `ρ(y)` (`r` along the core, `√(r² - (|y| - h)²)` on the caps):
/// area `πρ²`, inertia `πρ⁴/2` about the axis and `πρ⁴/4 + πρ² y²` across,
/// integrated by Simpson's rule on each of the three stretches.
fn capsule_by_slices(r: f64, h: f64) -> (f64, f64, f64) {
    let rho2 = |y: f64| (r * r - (y.abs() - h).max(0.0).powi(2)).max(0.0);
    let f = |y: f64| {
        let q = rho2(y);
        [PI * q, PI * q * q / 2.0, PI * q * q / 4.0 + PI * q * y * y]
    };
    let mut sums = [0.0; 3];
    for (a, b) in [(-h - r, -h), (-h, h), (h, h + r)] {
        let n = 2000;
        let step = (b - a) / n as f64;
        for k in 0..=n {
            let w = if k == 0 || k == n {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            let v = f(a + step * k as f64);
            for i in 0..3 {
                sums[i] += w * v[i] * step / 3.0;
            }
        }
    }
    (sums[0], sums[1], sums[2])
}

#[test]
fn capsule_mass_properties_are_the_integral_over_its_slices() {
    let mut rng = SmallRng::seed_from_u64(2);
    for k in 0..200 {
        let r = rng.random_range(0.01..2.0f32);
        let h = if k % 10 == 0 { 0.0 } else { rng.random_range(0.0..3.0f32) };
        let got = Part::Capsule(Capsule::new(r, h)).mass_properties();
        let (volume, along, across) = capsule_by_slices(r.into(), h.into());
        let inertia = DMat3::from_diagonal(DVec3::new(across, along, across));
        let errors = mass_errors(&got, volume, DVec3::ZERO, inertia, f64::from(r + h));
        assert!(errors.iter().all(|&e| e < 1e-6), "r {r} h {h}: {errors:?}");
    }
}

#[test]
fn shapes_of_several_parts_add_their_mass_by_parallel_axes() {
    // Two boxes side by side as two parts equal one box of their union.
    let mut rng = SmallRng::seed_from_u64(3);
    let half = Vec3::new(0.5, 0.25, 0.75);
    let left = box_case(&mut rng, half, Quat::IDENTITY, Vec3::new(-0.5, 0.0, 0.0));
    let right = box_case(&mut rng, half, Quat::IDENTITY, Vec3::new(0.5, 0.0, 0.0));
    let whole = box_case(&mut rng, Vec3::new(1.0, 0.25, 0.75), Quat::IDENTITY, Vec3::ZERO);
    let both = MassProperties::combine([left.part.mass_properties(), right.part.mass_properties()]);
    let one = whole.part.mass_properties();
    let errors = mass_errors(
        &both,
        one.volume.into(),
        one.center.as_dvec3(),
        one.inertia.as_dmat3(),
        whole.size,
    );
    assert!(errors.iter().all(|&e| e < 1e-6), "{errors:?}");
    // Moved off the origin, the inertia about a point adds m |d|² across d.
    let about = one.inertia_about(Vec3::new(0.0, 2.0, 0.0)).as_dmat3();
    let m = f64::from(one.volume);
    let expected = one.inertia.as_dmat3() + DMat3::from_diagonal(DVec3::new(4.0, 0.0, 4.0) * m);
    assert!(max_abs(about - expected) < 1e-5 * max_abs(expected), "{about} vs {expected}");
    assert_eq!(MassProperties::combine([]), MassProperties::default());
}

/// Ray parameters of a march along `ray` from 0 to `max_t` in `steps` steps.
fn march(max_t: f64, steps: usize) -> impl Iterator<Item = f64> {
    (0..=steps).map(move |k| max_t * k as f64 / steps as f64)
}

#[test]
fn ray_entries_are_where_a_march_first_meets_the_inside() {
    let mut rng = SmallRng::seed_from_u64(4);
    let mut hits = 0;
    for case in cases() {
        let size = case.size;
        let tol = 1e-5 * size;
        for k in 0..400 {
            // From outside towards a point near the part, or from inside.
            let from = if k % 8 == 0 {
                case.surface[k % case.surface.len()] * 0.9
            } else {
                random_unit(&mut rng).as_dvec3() * size * 3.0
            };
            let to = case.surface[rng.random_range(0..case.surface.len())]
                + random_in_ball(&mut rng, 0.3).as_dvec3() * size;
            let ray = Ray::new(from.as_vec3(), (to - from).normalize().as_vec3());
            let max_t = (8.0 * size) as f32;
            let at = |t: f64| ray.origin.as_dvec3() + ray.direction.as_dvec3() * t;
            let got = case.part.ray_entry(&ray, max_t);
            let step = f64::from(max_t) / 4000.0;
            // Every point of the march before the entry is outside.
            let before = got.map_or(f64::from(max_t), |t| f64::from(t) - step);
            let first_inside = march(f64::from(max_t), 4000)
                .filter(|&t| t < before)
                .find(|&t| (case.inside)(at(t)) < -tol);
            assert!(
                first_inside.is_none(),
                "{}: {ray:?} inside at {first_inside:?}, entry {got:?}",
                case.name
            );
            if let Some(t) = got {
                let t = f64::from(t);
                assert!(t >= 0.0 && t <= f64::from(max_t), "{}: {t}", case.name);
                let depth = (case.inside)(at(t));
                assert!(depth <= tol, "{}: {ray:?} entry {t} is {depth} outside", case.name);
                if t > 0.0 {
                    assert!(depth >= -tol, "{}: {ray:?} entry {t} is {depth} deep", case.name);
                }
                hits += 1;
            }
        }
        // A ray that stops short of the part, and bad rays, miss.
        let ray = Ray::new((DVec3::X * size * 3.0).as_vec3(), -Vec3::X);
        assert_eq!(case.part.ray_entry(&ray, (size * 0.5) as f32), None, "{}", case.name);
        assert_eq!(case.part.ray_entry(&Ray::new(Vec3::NAN, Vec3::X), 10.0), None);
        assert_eq!(case.part.ray_entry(&Ray::new(Vec3::ZERO, Vec3::ZERO), 10.0), None);
        assert_eq!(case.part.ray_entry(&ray, -1.0), None);
    }
    assert!(hits > 2000, "{hits}");
}

#[test]
fn support_points_are_the_farthest_of_the_surface() {
    let mut rng = SmallRng::seed_from_u64(5);
    for case in cases() {
        let tol = 1e-5 * case.size;
        for _ in 0..300 {
            let d = random_unit(&mut rng) * rng.random_range(0.1..10.0f32);
            let got = case.part.support(d).as_dvec3();
            let unit = d.as_dvec3().normalize();
            let best = case.surface.iter().map(|p| p.dot(unit)).fold(f64::MIN, f64::max);
            // On the part, and at least as far along as any sampled point.
            assert!((case.inside)(got) <= tol, "{}: {d} gives {got}", case.name);
            assert!(got.dot(unit) >= best - tol, "{}: {d} gives {got}, short of {best}", case.name);
        }
        let any = case.part.support(Vec3::ZERO).as_dvec3();
        assert!((case.inside)(any) <= tol, "{}: {any}", case.name);
    }
}

#[test]
fn local_bounds_are_the_tight_box_of_the_surface() {
    for case in cases() {
        let bounds = case.part.local_bounds();
        assert!(case.surface.iter().all(|p| bounds.contains_point(p.as_vec3())), "{}", case.name);
        // Each face touches the part: its support point along the axis.
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            let (hi, lo) = (case.part.support(axis), case.part.support(-axis));
            let slack = (bounds.max - hi).dot(axis).max((lo - bounds.min).dot(axis));
            assert!(f64::from(slack) <= 1e-6 * case.size, "{}: {axis} {slack}", case.name);
        }
    }
}

#[test]
fn fit_points_hold_the_part_and_the_enclosing_sphere_is_the_smallest() {
    for case in cases() {
        let hull = ConvexHull::new(&case.part.fit_points()).unwrap();
        let tol = 1e-6 * case.size;
        for p in &case.surface {
            let excess = (0..hull.face_count())
                .map(|f| hull.face_normal(f).dot(*p) - hull.face_offset(f))
                .fold(f64::MIN, f64::max);
            assert!(excess <= tol, "{}: {p} is {excess} outside the fit points", case.name);
        }
        let Some(sphere) = case.part.enclosing_sphere() else { continue };
        let (c, r) = (sphere.center.as_dvec3(), f64::from(sphere.radius));
        let farthest = case.surface.iter().map(|p| p.distance(c)).fold(0.0, f64::max);
        // Holds every point, and the farthest sampled is within a hair of it.
        assert!(
            farthest <= r * (1.0 + 1e-12) && r - farthest < 1e-3 * case.size,
            "{}: {farthest} {r}",
            case.name
        );
    }
}

/// A hull part's source builds it again to the bit: every test hull at
/// three scales, a mesh's raw points, a flat sheet (thickened), boxes, and
/// parts scaled per axis, each answering 40 random poses against a probe
/// exactly as the original does; a part put together by hand from a
/// polyhedron and a hull that do not match has none.
#[test]
fn hull_sources_build_their_parts_again() {
    let made = |points: &[Vec3]| HullPart::from_points(points).unwrap();
    let mut parts: Vec<HullPart> = Vec::new();
    for scale in [1e-3, 1.0, 1e3] {
        parts.extend(shapes::all(scale).iter().map(|t| made(&t.points)));
    }
    parts.push(made(&common::mesh("bunny")));
    let sheet = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)].map(|(x, z)| Vec3::new(x, 0.3, z));
    parts.push(made(&sheet));
    let cube = HullPart {
        polyhedron: Polyhedron::cuboid(Vec3::ONE).unwrap(),
        hull: ConvexHull::cuboid(Vec3::ONE).unwrap(),
    };
    for factor in [Vec3::new(2.0, 0.5, 1.0), Vec3::splat(3.0)] {
        for part in [cube.clone(), parts[3].clone()] {
            let Part::Hull(scaled) = Part::Hull(Box::new(part)).scaled(factor).unwrap() else {
                unreachable!()
            };
            parts.push(*scaled);
        }
    }
    parts.push(cube);
    let probe = Polyhedron::cuboid(Vec3::new(0.3, 0.2, 0.1)).unwrap();
    let mut rng = SmallRng::seed_from_u64(77);
    for (k, part) in parts.iter().enumerate() {
        let again =
            part.source().unwrap_or_else(|| panic!("part {k} has no source")).build().unwrap();
        assert_eq!(again.polyhedron.vertices(), part.polyhedron.vertices(), "part {k}");
        let size = part.polyhedron.vertices().iter().map(|v| v.length()).fold(0.0, f32::max);
        for _ in 0..40 {
            let at = Pose::new(random_in_ball(&mut rng, 1.2 * size), random_rotation(&mut rng));
            let answer = |p: &Polyhedron| {
                bvol_narrow::hull_hull(p, &Pose::IDENTITY, &probe, &at, &mut Default::default())
                    .unwrap()
            };
            assert_eq!(answer(&again.polyhedron), answer(&part.polyhedron), "part {k}");
        }
    }
    let tetra = made(&[Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z]);
    let mismatched =
        HullPart { polyhedron: Polyhedron::cuboid(Vec3::ONE).unwrap(), hull: tetra.hull };
    assert!(mismatched.source().is_none());
}
