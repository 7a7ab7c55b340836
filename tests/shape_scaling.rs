//! Primitives' bounds in closed form and scaled shapes, against independent
//! oracles: the fitters run on the same points, shapes built directly at the
//! scaled size, and the parts' surfaces sampled by their support points.

use bvol::narrow::{Collision, Polyhedron, Pose, WarmStart, collide_parts};
use bvol::volumes::{Obb, ObbMethod, Sphere, SphereMethod};
use bvol::{FitOptions, Mesh, Part, Shape, ShapeError};
use glam::{Quat, Vec3};
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

fn random_unit(rng: &mut SmallRng) -> Vec3 {
    loop {
        let v = Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - 1.0;
        if (0.01..=1.0).contains(&v.length_squared()) {
            return v.normalize();
        }
    }
}

fn random_pose(rng: &mut SmallRng, side: f32) -> Pose {
    let position = (Vec3::new(rng.random(), rng.random(), rng.random()) - 0.5) * side;
    let axis = random_unit(rng);
    Pose::new(position, Quat::from_axis_angle(axis, rng.random_range(0.0..6.3)))
}

/// Points on a part's surface: its support points along random directions
/// and the axes (a hull's vertices among them).
fn surface_samples(part: &Part, rng: &mut SmallRng) -> Vec<Vec3> {
    let axes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
    let random: Vec<Vec3> = (0..200).map(|_| random_unit(rng)).collect();
    axes.iter().chain(&random).map(|&d| part.support(d)).collect()
}

/// Whether the shape's sphere and box hold every surface sample of its parts,
/// to 1e-6 of the shape's size: a support point computed in f64 and rounded
/// to f32 may lie that far out of a bound that holds the part exactly.
fn bounds_hold_parts(shape: &Shape, rng: &mut SmallRng) -> bool {
    let Sphere { center, radius } = shape.sphere();
    let slack = 1e-6 * radius;
    let sphere = Sphere::new(center, radius + slack);
    let obb = shape.obb();
    let obb = Obb { half_extents: obb.half_extents + slack, ..obb };
    let samples: Vec<Vec3> = shape.parts().iter().flat_map(|p| surface_samples(p, rng)).collect();
    samples.iter().all(|&p| sphere.contains_point(p) && obb.contains_point(p))
}

/// Whether the shape's sphere and box hold its hulls' vertices exactly:
/// they are the parts' own f32 points, with no rounding of a sample's.
fn bounds_hold_vertices(shape: &Shape) -> bool {
    let vertices = shape.parts().iter().flat_map(|part| match part {
        Part::Hull(hull) => hull.polyhedron.vertices().to_vec(),
        _ => Vec::new(),
    });
    vertices
        .collect::<Vec<_>>()
        .iter()
        .all(|&p| shape.sphere().contains_point(p) && shape.obb().contains_point(p))
}

/// A short name of a shape's first part, for messages (a hull's debug form
/// runs to pages).
fn name(shape: &Shape) -> String {
    match &shape.parts()[0] {
        Part::Hull(hull) => format!("hull of {} vertices", hull.polyhedron.vertices().len()),
        part => format!("{part:?}"),
    }
}

/// `a` within `tolerance` of `b`, relative to `b`.
fn close(a: f32, b: f32, tolerance: f32) -> bool {
    (a - b).abs() <= tolerance * b.abs()
}

/// The same bounds within 1e-5 of their size.
fn assert_same_bounds(got: &Shape, want: &Shape, what: &str) {
    let (gs, ws) = (got.sphere(), want.sphere());
    assert!(close(gs.radius, ws.radius, 1e-5), "{what}: sphere {gs:?} vs {ws:?}");
    assert!(gs.center.distance(ws.center) <= 1e-5 * ws.radius, "{what}: {gs:?} vs {ws:?}");
    let (go, wo) = (got.obb(), want.obb());
    assert!(close(go.volume(), wo.volume(), 1e-5), "{what}: box {go:?} vs {wo:?}");
    assert!(go.center.distance(wo.center) <= 1e-5 * ws.radius, "{what}: {go:?} vs {wo:?}");
}

/// The same answer from the pair table against `probe` at random poses:
/// touching alike, depths and normals alike.
fn assert_same_contacts(got: &Shape, want: &Shape, probe: &Part, rng: &mut SmallRng) {
    let size = want.sphere().radius;
    let mut touching = 0;
    for _ in 0..200 {
        let (pose, probe_pose) = (random_pose(rng, size), random_pose(rng, 2.0 * size));
        for (a, b) in got.parts().iter().zip(want.parts()) {
            let mut warm = WarmStart::default();
            let x = collide_parts(a, &pose, probe, &probe_pose, &mut warm).unwrap();
            let mut warm = WarmStart::default();
            let y = collide_parts(b, &pose, probe, &probe_pose, &mut warm).unwrap();
            match (x, y) {
                (Collision::Touching(x), Collision::Touching(y)) => {
                    touching += 1;
                    assert!((x.depth - y.depth).abs() <= 1e-5 * size, "{x:?} vs {y:?}");
                    assert!(x.normal.angle_between(y.normal) < 1e-3, "{x:?} vs {y:?}");
                }
                (Collision::Separated { .. }, Collision::Separated { .. }) => {}
                (x, y) => panic!("scaled {x:?}, built at that size {y:?}"),
            }
        }
    }
    assert!(touching > 10, "too few touching poses to compare: {touching}");
}

fn random_points(rng: &mut SmallRng, n: usize) -> Vec<Vec3> {
    (0..n)
        .map(|_| random_unit(rng) * rng.random_range(0.3..1.0) * Vec3::new(1.0, 0.6, 1.4))
        .collect()
}

/// A box of half extents `half` about `centre`, as a mesh object.
fn box_mesh(name: &str, half: Vec3, centre: Vec3) -> Mesh {
    let corners = Polyhedron::cuboid(half).unwrap();
    let positions = corners.vertices().iter().map(|&v| v + centre).collect();
    Mesh { name: name.into(), positions, triangles: Vec::new() }
}

#[test]
fn primitives_closed_form_bounds_are_as_tight_as_fitted_ones_and_hold_them() {
    let mut rng = SmallRng::seed_from_u64(28);
    let mut shapes = Vec::new();
    for _ in 0..50 {
        let half = Vec3::new(rng.random(), rng.random(), rng.random()) * 3.0 + 0.01;
        shapes.push(Shape::cuboid(half).unwrap());
        shapes.push(Shape::ball(rng.random_range(0.01..3.0)).unwrap());
        let (r, h) = (rng.random_range(0.01..2.0), rng.random_range(0.0..3.0));
        shapes.push(Shape::capsule(r, h).unwrap());
    }
    for shape in &shapes {
        let [part] = shape.parts() else { panic!("one part") };
        // The fitters on the points the bounds were fitted to before.
        let points = part.fit_points();
        let sphere = part
            .enclosing_sphere()
            .unwrap_or_else(|| Sphere::fit(&points, SphereMethod::Exact).unwrap());
        let obb = Obb::fit(&points, ObbMethod::MinVolume).unwrap();
        let what = name(shape);
        assert!(shape.sphere().radius <= sphere.radius * (1.0 + 1e-6), "{what} sphere {sphere:?}");
        assert!(shape.obb().volume() <= obb.volume() * (1.0 + 1e-6), "{what} box {obb:?}");
        assert!(bounds_hold_parts(shape, &mut rng), "{what}");
    }
}

#[test]
fn a_uniformly_scaled_shape_is_the_shape_built_at_that_size() {
    let mut rng = SmallRng::seed_from_u64(29);
    let probe = Shape::convex(&random_points(&mut rng, 30)).unwrap().parts()[0].clone();
    for s in [0.01f32, 0.37, 1.0, 2.5, 1e3] {
        let factor = Vec3::splat(s);
        let half = Vec3::new(0.4, 1.1, 0.7);
        let points = random_points(&mut rng, 40);
        let scaled_points: Vec<Vec3> = points.iter().map(|&p| p * s).collect();
        let cases = [
            (Shape::cuboid(half).unwrap(), Shape::cuboid(half * s).unwrap()),
            (Shape::ball(0.8).unwrap(), Shape::ball(0.8 * s).unwrap()),
            (Shape::capsule(0.3, 0.9).unwrap(), Shape::capsule(0.3 * s, 0.9 * s).unwrap()),
            (Shape::convex(&points).unwrap(), Shape::convex(&scaled_points).unwrap()),
        ];
        for (shape, direct) in &cases {
            let scaled = shape.scaled(factor).unwrap();
            let what = format!("{} by {s}", name(shape));
            assert_same_bounds(&scaled, direct, &what);
            assert!(bounds_hold_parts(&scaled, &mut rng), "{what}");
            assert!(bounds_hold_vertices(&scaled), "{what}");
            let probe = probe.scaled(factor).unwrap();
            assert_same_contacts(&scaled, direct, &probe, &mut rng);
        }
    }
}

#[test]
fn hulls_and_cuboids_scale_per_axis_as_if_built_at_that_size() {
    let mut rng = SmallRng::seed_from_u64(30);
    for factor in [Vec3::new(2.0, 0.5, 1.0), Vec3::new(0.1, 3.0, 7.5), Vec3::new(1.0, 1.0, 0.2)] {
        let half = Vec3::new(0.4, 1.1, 0.7);
        let cuboid = Shape::cuboid(half).unwrap().scaled(factor).unwrap();
        let direct = Shape::cuboid(half * factor).unwrap();
        let probe = Part::Ball(Sphere::new(Vec3::ZERO, 0.3 * direct.sphere().radius));
        assert_same_bounds(&cuboid, &direct, &format!("cuboid by {factor}"));
        assert_same_contacts(&cuboid, &direct, &probe, &mut rng);

        let points = random_points(&mut rng, 40);
        let scaled_points: Vec<Vec3> = points.iter().map(|&p| p * factor).collect();
        let hull = Shape::convex(&points).unwrap().scaled(factor).unwrap();
        let direct = Shape::convex(&scaled_points).unwrap();
        assert_same_bounds(&hull, &direct, &format!("hull by {factor}"));
        assert!(bounds_hold_parts(&hull, &mut rng), "hull by {factor}");
        assert!(bounds_hold_vertices(&hull), "hull by {factor}");
        assert_same_contacts(&hull, &direct, &probe, &mut rng);
    }
}

#[test]
fn a_scaled_shape_of_several_parts_keeps_its_fits_and_holds_its_parts() {
    let mut rng = SmallRng::seed_from_u64(31);
    let meshes = [
        box_mesh("a", Vec3::new(0.5, 0.25, 0.75), Vec3::new(-1.0, 0.5, 0.0)),
        box_mesh("b", Vec3::new(0.2, 0.6, 0.3), Vec3::new(1.5, -0.5, 0.25)),
    ];
    let fit = FitOptions { sphere: SphereMethod::Ritter, obb: ObbMethod::PcaPoints };
    let shape = Shape::from_meshes(&meshes, fit).unwrap();
    for factor in [Vec3::splat(3.0), Vec3::new(0.5, 2.0, 1.5)] {
        let scaled = shape.scaled(factor).unwrap();
        assert!(bounds_hold_parts(&scaled, &mut rng), "by {factor}");
        assert!(bounds_hold_vertices(&scaled), "by {factor}");
        let moved: Vec<Mesh> = meshes
            .iter()
            .map(|m| Mesh {
                positions: m.positions.iter().map(|&p| p * factor).collect(),
                ..m.clone()
            })
            .collect();
        let direct = Shape::from_meshes(&moved, fit).unwrap();
        if factor.x != factor.y {
            // Fitted anew by the same methods as the shape was.
            assert_same_bounds(&scaled, &direct, &format!("by {factor}"));
        } else {
            // Scaled as they were: the fitted sphere and box grow by the factor.
            let want = shape.sphere().radius * factor.x;
            assert!(close(scaled.sphere().radius, want, 1e-5), "{:?}", scaled.sphere());
            assert!(close(scaled.obb().volume(), shape.obb().volume() * 27.0, 1e-5));
        }
        let a = &direct.parts()[0];
        assert_same_contacts(&scaled, &direct, a, &mut rng);
    }
}

#[test]
fn bad_factors_are_typed_errors() {
    let shapes = [
        Shape::cuboid(Vec3::ONE).unwrap(),
        Shape::ball(1.0).unwrap(),
        Shape::capsule(0.5, 1.0).unwrap(),
        Shape::tetrahedron(1.0).unwrap(),
    ];
    let bad = [
        Vec3::splat(f32::NAN),
        Vec3::new(1.0, f32::NAN, 1.0),
        Vec3::ZERO,
        Vec3::splat(-1.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::splat(f32::INFINITY),
        Vec3::splat(f32::NEG_INFINITY),
        Vec3::splat(1e30),
        Vec3::splat(f32::MAX),
    ];
    for shape in &shapes {
        for factor in bad {
            let got = shape.scaled(factor);
            assert!(
                matches!(got, Err(ShapeError::BadScale { factor: f }) if f.to_array().map(f32::to_bits) == factor.to_array().map(f32::to_bits)),
                "{:?} by {factor}: {got:?}",
                name(shape)
            );
        }
    }
    // A factor that leaves a part a speck in f32 answers without panicking,
    // and what it builds is bounded.
    let mut rng = SmallRng::seed_from_u64(32);
    for shape in &shapes {
        for s in [1e-30, f32::MIN_POSITIVE, 1e-44] {
            if let Ok(speck) = shape.scaled(Vec3::splat(s)) {
                assert!(bounds_hold_parts(&speck, &mut rng), "{} by {s}", name(shape));
            }
        }
    }
    // A round part with unequal factors is named.
    for shape in &shapes[1..3] {
        let got = shape.scaled(Vec3::new(1.0, 2.0, 1.0));
        assert!(
            matches!(&got, Err(ShapeError::Part { part, reason: bvol::narrow::ShapeError::NonUniformScale }) if part == "part 0"),
            "{got:?}"
        );
    }
}
