//! Bounding spheres: every method holds every point, whatever the shape, scale,
//! offset or rotation of the set; the exact sphere is the minimum one (against
//! brute-force enumeration, spheres known by construction, and the reference
//! radii of the real meshes) and never larger than another method's; bad input
//! is an error, not a panic.

mod common;

use std::f64::consts::PI;
use std::sync::OnceLock;

use bvol_volumes::{FitError, Sphere, SphereMethod};
use glam::{DQuat, DVec3, EulerRot, Vec3};
use proptest::prelude::*;

fn fit(points: &[Vec3], method: SphereMethod) -> Sphere {
    Sphere::fit(points, method).unwrap_or_else(|e| panic!("{method}: {e}"))
}

/// Fits by every method, checking that each sphere holds every point.
fn fit_all(points: &[Vec3]) -> Vec<(SphereMethod, Sphere)> {
    SphereMethod::ALL
        .iter()
        .map(|&m| {
            let s = fit(points, m);
            assert!(s.radius >= 0.0 && s.radius.is_finite() && s.center.is_finite(), "{m}: {s:?}");
            if let Some(p) = points.iter().find(|&&p| !s.contains_point(p)) {
                panic!("{m}: {s:?} misses {p:?}");
            }
            (m, s)
        })
        .collect()
}

/// How much storing the centre in f32 may add to a radius: the centre moves by
/// at most half an ulp per coordinate, and the radius is then rounded up.
fn rounding(s: &Sphere) -> f64 {
    2.0 * f32::EPSILON as f64 * (s.center.abs().max_element() as f64 + s.radius as f64)
}

/// The exact sphere is no larger than any other method's, up to rounding.
fn assert_exact_smallest(spheres: &[(SphereMethod, Sphere)]) {
    let exact = spheres.iter().find(|(m, _)| *m == SphereMethod::Exact).expect("exact").1;
    for (m, s) in spheres {
        assert!(
            exact.radius as f64 <= s.radius as f64 + rounding(&exact),
            "exact {} > {m} {}",
            exact.radius,
            s.radius
        );
    }
}

/// The radius of the minimum sphere by enumeration: every sphere through 1
/// point, through 2 (diametral), through 3 (their circumcircle's sphere, centre
/// in their plane) and through 4 (circumsphere); the smallest that holds all
/// points (to a relative 1e-9) is the minimum, which is always one of them.
fn brute_force_radius(points: &[Vec3]) -> f64 {
    let origin = points[0].as_dvec3();
    let p: Vec<DVec3> = points.iter().map(|q| q.as_dvec3() - origin).collect();
    let n = p.len();
    let mut best = f64::INFINITY;
    let mut consider = |c: DVec3, through: &[DVec3]| {
        let r = through.iter().map(|&q| (q - c).length()).fold(0.0, f64::max);
        if r < best && p.iter().all(|&q| (q - c).length() <= r * (1.0 + 1e-9)) {
            best = r;
        }
    };
    consider(p[0], &p[..1]);
    for i in 0..n {
        for j in i + 1..n {
            consider((p[i] + p[j]) * 0.5, &[p[i], p[j]]);
            for k in j + 1..n {
                if let Some(c) = circumcenter3(p[i], p[j], p[k]) {
                    consider(c, &[p[i], p[j], p[k]]);
                }
                for l in k + 1..n {
                    if let Some(c) = circumcenter4(p[i], p[j], p[k], p[l]) {
                        consider(c, &[p[i], p[j], p[k], p[l]]);
                    }
                }
            }
        }
    }
    best
}

/// Centre of the circle through 3 points, `None` if they are (nearly) collinear.
fn circumcenter3(a: DVec3, b: DVec3, c: DVec3) -> Option<DVec3> {
    let (u, v) = (b - a, c - a);
    let w = u.cross(v);
    let w2 = w.length_squared();
    (w2 > 1e-20 * u.length_squared() * v.length_squared())
        .then(|| a + (u.length_squared() * v - v.length_squared() * u).cross(w) / (2.0 * w2))
}

/// Centre of the sphere through 4 points (Cramer's rule), `None` if they are
/// (nearly) coplanar.
fn circumcenter4(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Option<DVec3> {
    let (u, v, w) = (b - a, c - a, d - a);
    let det = u.dot(v.cross(w));
    (det.abs() > 1e-10 * u.length() * v.length() * w.length()).then(|| {
        a + (u.length_squared() * v.cross(w)
            + v.length_squared() * w.cross(u)
            + w.length_squared() * u.cross(v))
            / (2.0 * det)
    })
}

/// A rigid motion and scale applied to points in f64, then rounded to f32.
#[derive(Clone, Copy, Debug)]
struct Placement {
    rotation: DQuat,
    scale: f64,
    offset: DVec3,
}

impl Placement {
    fn place(&self, p: DVec3) -> Vec3 {
        (self.rotation * p * self.scale + self.offset).as_vec3()
    }
}

/// Random rotations, scales 1e-4..1e4, offsets up to `max_offset` (in units of
/// the scale when `relative`).
fn placement(max_offset: f64, relative: bool) -> impl Strategy<Value = Placement> {
    let angle = -PI..PI;
    (
        (angle.clone(), angle.clone(), angle),
        -4.0f64..4.0,
        (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
    )
        .prop_map(move |((a, b, c), e, (x, y, z))| {
            let scale = 10f64.powf(e);
            let reach = if relative { max_offset * scale } else { max_offset };
            Placement {
                rotation: DQuat::from_euler(EulerRot::ZYX, a, b, c),
                scale,
                offset: DVec3::new(x, y, z) * reach,
            }
        })
}

fn coords() -> impl Strategy<Value = DVec3> {
    (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// The shapes of point sets, before placement.
#[derive(Clone, Copy, Debug)]
enum Shape {
    Cloud,
    Duplicates,
    Collinear,
    Coplanar,
    Cospherical,
    Cocircular,
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        Just(Shape::Cloud),
        Just(Shape::Duplicates),
        Just(Shape::Collinear),
        Just(Shape::Coplanar),
        Just(Shape::Cospherical),
        Just(Shape::Cocircular),
    ]
}

/// Points of a shape, in the unit cube, from raw random coordinates.
fn shaped(shape: Shape, raw: &[DVec3]) -> Vec<DVec3> {
    match shape {
        Shape::Cloud => raw.to_vec(),
        Shape::Duplicates => vec![raw[0]; raw.len()],
        Shape::Collinear => raw.iter().map(|p| DVec3::new(p.x, 0.3 * p.x, -0.5 * p.x)).collect(),
        Shape::Coplanar => raw.iter().map(|p| DVec3::new(p.x, p.y, 0.0)).collect(),
        Shape::Cospherical => raw.iter().map(|p| p.try_normalize().unwrap_or(DVec3::Y)).collect(),
        Shape::Cocircular => {
            raw.iter().map(|p| DVec3::new((p.x * PI).cos(), (p.x * PI).sin(), 0.0)).collect()
        }
    }
}

/// Checks the properties every set has, whatever its shape.
fn check_set(shape: Shape, points: &[Vec3]) {
    let spheres = fit_all(points);
    assert_exact_smallest(&spheres);
    let exact = fit(points, SphereMethod::Exact);
    match shape {
        Shape::Duplicates => {
            for (m, s) in &spheres {
                assert_eq!(s.radius, 0.0, "{m}");
            }
        }
        Shape::Collinear => {
            // Half the longest pairwise distance, up to the f32 rounding of the
            // points off their line and of the centre.
            let half = points
                .iter()
                .flat_map(|a| points.iter().map(move |b| a.as_dvec3().distance(b.as_dvec3())))
                .fold(0.0, f64::max)
                / 2.0;
            let size = points.iter().map(|p| p.abs().max_element()).fold(0.0, f32::max) as f64;
            let tol = 1e-6 * half + 4.0 * f32::EPSILON as f64 * size;
            assert!((exact.radius as f64 - half).abs() <= tol, "{} vs {half}", exact.radius);
        }
        _ => {}
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    /// Every method holds every point of random, duplicate, collinear, coplanar
    /// and cospherical sets under any rotation, scale 1e-4..1e4 and offset up
    /// to 1e6; the exact sphere is the smallest; duplicates give radius 0 and
    /// collinear sets half their length.
    #[test]
    fn every_method_holds_every_point(
        shape in shape(),
        raw in prop::collection::vec(coords(), 1..120),
        place in placement(1e6, false),
    ) {
        let points: Vec<Vec3> = shaped(shape, &raw).into_iter().map(|p| place.place(p)).collect();
        check_set(shape, &points);
    }
}

/// Small sets near the origin: offsets of at most 2 sizes.
fn small_set() -> impl Strategy<Value = (Shape, Vec<Vec3>)> {
    (shape(), prop::collection::vec(coords(), 1..=12), placement(2.0, true)).prop_map(
        |(shape, raw, place)| {
            (shape, shaped(shape, &raw).into_iter().map(|p| place.place(p)).collect())
        },
    )
}

/// `n` points inside the ball of radius `0.9 r` about `c`.
fn inside(c: DVec3, r: f64, raw: &[DVec3]) -> Vec<DVec3> {
    raw.iter().map(|&p| c + p.clamp_length_max(1.0) * 0.9 * r).collect()
}

/// The sphere's radius is `want` to 1e-6 of it, once the f32 rounding of the
/// centre is allowed for (it matters only where the set is small beside its
/// distance from the origin).
fn assert_radius(s: &Sphere, want: f64, what: &str) {
    let got = s.radius as f64;
    assert!((got - want).abs() <= 1e-6 * want + rounding(s), "{what}: {got} vs {want}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// The exact sphere matches brute-force enumeration on small sets of every
    /// shape (cospherical ones included) to 1e-6 of the radius.
    #[test]
    fn exact_matches_brute_force((shape, points) in small_set()) {
        let exact = fit(&points, SphereMethod::Exact);
        let brute = brute_force_radius(&points);
        assert_radius(&exact, brute, &format!("{shape:?}"));
        check_set(shape, &points);
    }

    /// Sets whose minimum sphere is known by construction, fixed by 2, 3 or 4
    /// points on a sphere of radius `r` (a diameter, an acute triangle on a
    /// great circle, a tetrahedron holding the centre), the rest inside: both
    /// the exact sphere and the brute force find `r`.
    #[test]
    fn exact_finds_spheres_fixed_by_2_3_or_4_points(
        support in 2usize..=4,
        (c, r) in (coords(), -3.0f64..3.0).prop_map(|(c, e)| (c * 10f64.powf(e), 10f64.powf(e))),
        rotation in placement(0.0, false).prop_map(|p| p.rotation),
        jitter in prop::array::uniform4((-0.2f64..0.2, -0.2f64..0.2, -0.2f64..0.2)),
        raw in prop::collection::vec(coords(), 0..=8),
    ) {
        let third = std::f64::consts::TAU / 3.0;
        let dirs: Vec<DVec3> = match support {
            2 => vec![DVec3::X, -DVec3::X],
            // Arcs between neighbours stay below pi: the triangle is acute.
            3 => (0..3)
                .map(|i| {
                    let t = third * i as f64 + jitter[i].0;
                    DVec3::new(t.cos(), t.sin(), 0.0)
                })
                .collect(),
            // A regular tetrahedron, its corners moved by at most ~0.14: the
            // centre (inradius 1/3) stays inside.
            _ => [(1.0, 1.0, 1.0), (1.0, -1.0, -1.0), (-1.0, 1.0, -1.0), (-1.0, -1.0, 1.0)]
                .iter()
                .zip(jitter)
                .map(|(&(x, y, z), (a, b, d))| {
                    (DVec3::new(x, y, z).normalize() + DVec3::new(a, b, d) * 0.4).normalize()
                })
                .collect(),
        };
        let mut points: Vec<DVec3> = dirs.iter().map(|&d| c + rotation * d * r).collect();
        points.extend(inside(c, r, &raw));
        let points: Vec<Vec3> = points.iter().map(|p| p.as_vec3()).collect();
        let brute = brute_force_radius(&points);
        assert!((brute - r).abs() <= 1e-6 * r, "brute force: {brute} vs {r}");
        assert_radius(&fit(&points, SphereMethod::Exact), r, "exact");
        check_set(Shape::Cloud, &points);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    /// Corners, edge and face centres of a cube, scaled by a power of two and
    /// moved by a multiple of the scale, all exact in f32: exact ties,
    /// cocircular and coplanar quadruples, repeats. The exact sphere still
    /// matches brute force, and every method holds every point.
    #[test]
    fn exact_handles_exact_ties(
        raw in prop::collection::vec(coords(), 1..=12),
        e in -10i32..10,
        shift in (-8i32..8, -8i32..8, -8i32..8),
    ) {
        let scale = 2f64.powi(e);
        let shift = DVec3::new(shift.0 as f64, shift.1 as f64, shift.2 as f64);
        let points: Vec<Vec3> =
            raw.iter().map(|p| ((p.round() + shift) * scale).as_vec3()).collect();
        assert_radius(&fit(&points, SphereMethod::Exact), brute_force_radius(&points), "lattice");
        check_set(Shape::Cloud, &points);
    }
}

/// The shipped meshes with their reference rows, loaded once.
fn meshes() -> &'static [(common::Reference, Vec<Vec3>)] {
    static MESHES: OnceLock<Vec<(common::Reference, Vec<Vec3>)>> = OnceLock::new();
    MESHES.get_or_init(|| {
        common::references()
            .into_iter()
            .map(|r| {
                let points = common::mesh(&r.name);
                (r, points)
            })
            .collect()
    })
}

/// On the real meshes as shipped: the exact radius matches the reference
/// minimum sphere to 1e-6, Ritter's is never smaller, and every method holds
/// every vertex. Prints each method's radius over the exact one.
#[test]
fn real_meshes_match_their_reference_radii() {
    for (reference, points) in meshes() {
        let spheres = fit_all(points);
        assert_exact_smallest(&spheres);
        let want = reference.min_sphere_radius;
        let exact = fit(points, SphereMethod::Exact);
        assert_radius(&exact, want, &reference.name);
        let exact = exact.radius as f64;
        let ritter = fit(points, SphereMethod::Ritter).radius as f64;
        // The reference radii hold to 1e-6, as the exact sphere checks.
        assert!(ritter >= want * (1.0 - 1e-6), "{}: ritter {ritter} < {want}", reference.name);
        let ratios: Vec<String> =
            spheres.iter().map(|(m, s)| format!("{m} {:.4}", s.radius as f64 / exact)).collect();
        println!(
            "{:9} exact {exact:.9} (ref {want}), ritter ref {:.4}: {}",
            reference.name,
            reference.ritter_radius / exact,
            ratios.join(", ")
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// The real meshes moved, turned and scaled: every method still holds every
    /// vertex, and the exact radius is the reference one times the scale, up to
    /// 1e-6 and the f32 rounding of the moved vertices and of the centre.
    #[test]
    fn real_meshes_placed_anywhere(mesh in 0usize..5, place in placement(1e6, false)) {
        let (reference, original) = &meshes()[mesh];
        let points: Vec<Vec3> = original.iter().map(|p| place.place(p.as_dvec3())).collect();
        let spheres = fit_all(&points);
        assert_exact_smallest(&spheres);
        let size = points.iter().map(|p| p.abs().max_element()).fold(0.0, f32::max) as f64;
        let want = reference.min_sphere_radius * place.scale;
        let exact = fit(&points, SphereMethod::Exact).radius as f64;
        let tol = 1e-6 * want + 4.0 * f32::EPSILON as f64 * size;
        prop_assert!((exact - want).abs() <= tol, "{}: {exact} vs {want}", reference.name);
    }
}

#[test]
fn empty_and_non_finite_input_are_errors() {
    let nan = [Vec3::ZERO, Vec3::X, Vec3::new(0.0, f32::NAN, 0.0)];
    let inf = [Vec3::new(f32::INFINITY, 0.0, 0.0)];
    for &m in SphereMethod::ALL {
        assert_eq!(Sphere::fit(&[], m), Err(FitError::Empty), "{m}");
        assert_eq!(Sphere::fit(&nan, m), Err(FitError::NonFinite { index: 2 }), "{m}");
        assert_eq!(Sphere::fit(&inf, m), Err(FitError::NonFinite { index: 0 }), "{m}");
    }
}

#[test]
fn one_point_has_radius_zero() {
    for p in [Vec3::ZERO, Vec3::new(1e6, -3.5, 1e-4)] {
        for (m, s) in fit_all(&[p]) {
            assert_eq!((s.center, s.radius), (p, 0.0), "{m}");
        }
    }
}
