//! The test hulls: the five real meshes' hulls scaled to radius 1 about their
//! vertex mean, random hulls of 8 to 200 points on a sphere or in an ellipsoid,
//! and primitives (cube, regular tetrahedron, thin slab, long rod, 80-vertex
//! ball), each at a given scale, with their parry3d and reference forms.

use bvol_narrow::Polyhedron;
use bvol_volumes::ConvexHull;
use glam::{Quat, Vec3};
use parry3d::shape::ConvexPolyhedron;
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

use super::reference::RefHull;
use super::{mesh, random_in_ball, random_rotation, random_unit, to_parry};

/// One test hull in its three forms.
pub struct TestShape {
    /// What it is, for messages.
    pub name: String,
    /// The hull's vertices, local space (the input of every form).
    pub points: Vec<Vec3>,
    /// bvol-narrow's form.
    pub poly: Polyhedron,
    /// The exact f64 form.
    pub reference: RefHull,
    /// parry3d's form: the same polyhedron, its faces handed over (parry3d's
    /// own hull drops points within about 1e-6 of a face: 2 of wuson's).
    pub parry: ConvexPolyhedron,
    /// Largest distance of a vertex from the local origin.
    pub size: f64,
    /// The scale it was made at.
    pub scale: f32,
}

impl TestShape {
    /// The shape of the hull of `points` (which must be solid), made at `scale`.
    pub fn new(name: &str, scale: f32, points: &[Vec3]) -> TestShape {
        let name = format!("{name}@{scale}");
        let hull = ConvexHull::new(points).unwrap_or_else(|e| panic!("{name}: {e}"));
        let points = hull.vertices().to_vec();
        let parry_points: Vec<_> = points.iter().map(|&p| to_parry(p)).collect();
        let triangles: Vec<[u32; 3]> = hull.triangles().collect();
        let parry = ConvexPolyhedron::from_convex_mesh(parry_points, &triangles)
            .unwrap_or_else(|| panic!("{name}: parry3d takes no polyhedron"));
        let poly = Polyhedron::from_points(&points).unwrap_or_else(|e| panic!("{name}: {e}"));
        let reference = RefHull::new(&hull);
        let size = reference.radius();
        TestShape { name, points, poly, reference, parry, size, scale }
    }
}

/// The mesh names in tests/meshes.
pub const MESHES: [&str; 5] = ["teapot", "airplane", "bunny", "wuson", "duck"];

/// Points moved so that their mean is at the origin and scaled so that the
/// farthest is at `radius`.
pub fn normalised(points: &[Vec3], radius: f32) -> Vec<Vec3> {
    let mean = points.iter().copied().sum::<Vec3>() / points.len() as f32;
    let far = points.iter().map(|p| p.distance(mean)).fold(0.0, f32::max);
    points.iter().map(|&p| (p - mean) * (radius / far)).collect()
}

/// A mesh's hull scaled to radius `scale` about its vertex mean.
pub fn mesh_hull(name: &str, scale: f32) -> TestShape {
    let hull = ConvexHull::new(&mesh(name)).expect("mesh hull");
    TestShape::new(name, scale, &normalised(hull.vertices(), scale))
}

/// The box corners `(+-h.x, +-h.y, +-h.z)`.
pub fn box_corners(h: Vec3) -> Vec<Vec3> {
    (0..8)
        .map(|i| {
            h * Vec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            )
        })
        .collect()
}

/// `n` points spread evenly on the unit sphere (Fibonacci lattice).
pub fn fibonacci_sphere(n: usize) -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - z * z).sqrt();
            let phi = golden * i as f32;
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

/// The primitives at `scale`: cube of side 1, regular tetrahedron of radius 1,
/// slab 1 x 1 x 0.02, rod 0.05 x 0.05 x 2, and an 80-vertex ball of radius 1.
pub fn primitives(scale: f32) -> Vec<TestShape> {
    let s = 1.0 / 3f32.sqrt();
    let tetra =
        [Vec3::new(s, s, s), Vec3::new(s, -s, -s), Vec3::new(-s, s, -s), Vec3::new(-s, -s, s)];
    let scaled = |p: Vec<Vec3>| p.into_iter().map(|p| p * scale).collect::<Vec<_>>();
    vec![
        TestShape::new("cube", scale, &scaled(box_corners(Vec3::splat(0.5)))),
        TestShape::new("tetrahedron", scale, &scaled(tetra.to_vec())),
        TestShape::new("slab", scale, &scaled(box_corners(Vec3::new(0.5, 0.5, 0.01)))),
        TestShape::new("rod", scale, &scaled(box_corners(Vec3::new(0.025, 0.025, 1.0)))),
        TestShape::new("ball", scale, &scaled(fibonacci_sphere(80))),
    ]
}

/// Random hulls at `scale` (seeded): 8 to 200 points, on the unit sphere or in
/// an ellipsoid of random semi-axes 0.15 to 1 and random orientation, moved to
/// their mean and scaled to radius `scale`.
pub fn random_hulls(scale: f32) -> Vec<TestShape> {
    let mut rng = SmallRng::seed_from_u64(0x5a7_0001);
    [8, 10, 14, 20, 30, 50, 80, 120, 160, 200, 12, 40]
        .iter()
        .enumerate()
        .map(|(k, &n)| {
            let points: Vec<Vec3> = if k % 2 == 0 {
                (0..n).map(|_| random_unit(&mut rng)).collect()
            } else {
                let axes = Vec3::new(
                    rng.random_range(0.15..1.0),
                    rng.random_range(0.15..1.0),
                    rng.random_range(0.15..1.0),
                );
                let turn: Quat = random_rotation(&mut rng);
                (0..n).map(|_| turn * (random_in_ball(&mut rng, 1.0) * axes)).collect()
            };
            // About the vertex mean, which is inside: poses then place the
            // local origin inside the body.
            TestShape::new(&format!("random{n}"), scale, &normalised(&points, scale))
        })
        .collect()
}

/// Every test hull at `scale`: meshes, primitives and random hulls.
pub fn all(scale: f32) -> Vec<TestShape> {
    let mut shapes: Vec<TestShape> = MESHES.iter().map(|m| mesh_hull(m, scale)).collect();
    shapes.extend(primitives(scale));
    shapes.extend(random_hulls(scale));
    shapes
}
