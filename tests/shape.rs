//! Shapes built of parts: an exact capsule's bounds are its smallest sphere
//! and its box, and a shape's mass properties are its parts' added by
//! parallel axes, against closed forms.

use std::f64::consts::PI;

use bvol::{FitOptions, Mesh, Part, Shape};
use glam::{DMat3, DVec3, Vec3};

/// The largest entry of a matrix's magnitude.
fn max_abs(m: DMat3) -> f64 {
    m.to_cols_array().iter().fold(0.0, |a, x| a.max(x.abs()))
}

#[test]
fn a_capsule_is_exact_and_bounded_by_its_smallest_sphere_and_its_box() {
    for (r, h) in [(0.3, 0.5), (1.0, 0.0), (0.01, 3.0), (2.0, 1e-3)] {
        let shape = Shape::capsule(r, h).unwrap();
        assert!(matches!(shape.parts(), [Part::Capsule(c)] if c.radius == r && c.half_height == h));
        let sphere = shape.sphere();
        let exact = f64::from(r) + f64::from(h);
        assert_eq!(sphere.center, Vec3::ZERO);
        let slack = f64::from(sphere.radius) - exact;
        assert!((0.0..=1e-6 * exact).contains(&slack), "r {r} h {h}: sphere {sphere:?}");
        let obb = shape.obb();
        let volume = f64::from(2.0 * r) * f64::from(2.0 * r) * 2.0 * exact;
        let excess = f64::from(obb.volume()) / volume - 1.0;
        assert!((-1e-5..=1e-4).contains(&excess), "r {r} h {h}: box {obb:?}");
        // A ray along x through the middle enters at the surface.
        let ray = bvol::volumes::Ray::new(Vec3::new(-5.0, 0.5 * h, 0.0), Vec3::X);
        let t = shape.ray_entry(&ray, 10.0).unwrap();
        assert!((t - (5.0 - r)).abs() < 1e-5, "r {r} h {h}: {t}");
    }
}

/// The mass properties of a box of half extents `half` centred at `centre`,
/// about the origin's axes: `m (b² + c²) / 12` for sides `a, b, c`, about
/// its centre, moved to `centre` by parallel axes.
fn box_about_origin(half: DVec3, centre: DVec3) -> (f64, DMat3) {
    let side = half * 2.0;
    let mass = side.x * side.y * side.z;
    let sq = side * side;
    let own = DVec3::new(sq.y + sq.z, sq.x + sq.z, sq.x + sq.y) * (mass / 12.0);
    let shift = DMat3::from_diagonal(DVec3::splat(centre.length_squared()))
        - DMat3::from_cols(centre * centre.x, centre * centre.y, centre * centre.z);
    (mass, DMat3::from_diagonal(own) + shift * mass)
}

fn box_mesh(name: &str, half: Vec3, centre: Vec3) -> Mesh {
    let positions = (0..8)
        .map(|i| {
            let sign = Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2) as f32) * 2.0;
            centre + (sign - 1.0) * half
        })
        .collect();
    Mesh { name: name.into(), positions, triangles: Vec::new() }
}

#[test]
fn a_shapes_mass_properties_add_its_parts_by_parallel_axes() {
    // Two boxes apart: the masses add, the centre is the weighted mean, and
    // each box's inertia moves to it.
    let (ha, ca) = (DVec3::new(0.5, 0.25, 0.75), DVec3::new(-1.0, 0.5, 0.0));
    let (hb, cb) = (DVec3::new(0.2, 0.6, 0.3), DVec3::new(1.5, -0.5, 0.25));
    let meshes =
        [box_mesh("a", ha.as_vec3(), ca.as_vec3()), box_mesh("b", hb.as_vec3(), cb.as_vec3())];
    let shape = Shape::from_meshes(&meshes, FitOptions::default()).unwrap();
    let got = shape.mass_properties();
    let ((ma, ia), (mb, ib)) = (box_about_origin(ha, ca), box_about_origin(hb, cb));
    let mass = ma + mb;
    let centre = (ca * ma + cb * mb) / mass;
    // About the origin, then moved to the centre of mass.
    let shift = DMat3::from_diagonal(DVec3::splat(centre.length_squared()))
        - DMat3::from_cols(centre * centre.x, centre * centre.y, centre * centre.z);
    let inertia = ia + ib - shift * mass;
    assert!((f64::from(got.volume) / mass - 1.0).abs() < 1e-6, "{got:?}");
    assert!(got.center.as_dvec3().distance(centre) < 1e-6, "{got:?} vs {centre}");
    let error = max_abs(got.inertia.as_dmat3() - inertia) / max_abs(inertia);
    assert!(error < 1e-6, "{got:?} vs {inertia}: {error}");
    let about_origin = got.inertia_about(Vec3::ZERO).as_dmat3();
    assert!(max_abs(about_origin - (ia + ib)) < 1e-6 * max_abs(ia + ib), "{about_origin}");

    // A ball and a capsule: 4/3 π r³ with 2/5 m r², and the capsule's closed form.
    let ball = Shape::ball(0.7).unwrap().mass_properties();
    let m = 4.0 / 3.0 * PI * 0.7f64.powi(3);
    assert!((f64::from(ball.volume) / m - 1.0).abs() < 1e-6);
    let i = ball.inertia.as_dmat3();
    assert!(max_abs(i - DMat3::from_diagonal(DVec3::splat(0.4 * m * 0.49))) < 1e-6 * m);
    let capsule = Shape::capsule(0.5, 1.0).unwrap().mass_properties();
    let (cylinder, balls) = (PI * 0.25 * 2.0, 4.0 / 3.0 * PI * 0.125);
    assert!((f64::from(capsule.volume) / (cylinder + balls) - 1.0).abs() < 1e-6);
}
