//! The convex hull against independent checks: every point behind every face
//! plane, faces planar and convex, every edge in two faces with opposite
//! directions, Euler's formula, vertices that are input points on at least three
//! faces, support values against brute force, and volumes against exact shapes
//! and the tetrahedra fan; on random clouds at any scale, offset and rotation,
//! on points on a sphere, grids, degenerate sets and the real meshes.

mod common;

use std::collections::{HashMap, HashSet};
use std::f64::consts::PI;

use bvol_volumes::{ConvexHull, FitError, HullError};
use glam::{DVec3, Quat, Vec3};
use proptest::prelude::*;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

/// The test's own distance allowance: 16 f32 ulps of the set's size (its half
/// extents about the box centre, summed), a few times the rounding of f32 input.
fn allowance(points: &[Vec3]) -> f64 {
    let (lo, hi) =
        points.iter().fold((points[0], points[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let half = (hi.as_dvec3() - lo.as_dvec3()) * 0.5;
    16.0 * f64::from(f32::EPSILON) * (half.x + half.y + half.z)
}

/// The loop of face `f` as f64 points.
fn face_points(hull: &ConvexHull, f: usize) -> Vec<DVec3> {
    hull.face(f).iter().map(|&v| hull.vertices()[v as usize].as_dvec3()).collect()
}

/// Twice the area vector of a polygon (Newell), independent of the hull's own.
fn area_vector(poly: &[DVec3]) -> DVec3 {
    (0..poly.len()).fold(DVec3::ZERO, |s, k| s + poly[k].cross(poly[(k + 1) % poly.len()]))
}

/// Checks everything a hull of `points` must be, whatever its dimension; returns
/// the worst distance of a point in front of a face plane, over the allowance.
fn validate(hull: &ConvexHull, points: &[Vec3]) -> f64 {
    let tol = allowance(points);
    assert!(hull.tolerance() <= tol && hull.tolerance() >= 0.0);
    // Vertices: input points, each once.
    let input: HashSet<[u32; 3]> = points.iter().map(|p| p.to_array().map(f32::to_bits)).collect();
    let mut seen = HashSet::new();
    for v in hull.vertices() {
        let key = v.to_array().map(f32::to_bits);
        assert!(input.contains(&key), "{v} is not an input point");
        assert!(seen.insert(key), "{v} repeats");
    }
    let edges: Vec<[u32; 2]> = hull.edges().collect();
    assert_eq!(edges.len(), hull.edge_count());
    assert!(edges.iter().all(|[a, b]| a < b && (*b as usize) < hull.vertices().len()));
    assert_eq!(edges.iter().collect::<HashSet<_>>().len(), edges.len(), "an edge repeats");
    // Support values: in any direction the hull reaches as far as the points.
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    for _ in 0..16 {
        let d = DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let reach = |set: &[Vec3]| {
            set.iter().map(|p| d.dot(p.as_dvec3())).fold(f64::NEG_INFINITY, f64::max)
        };
        assert!(reach(hull.vertices()) >= reach(points) - tol * d.length());
    }
    match hull.dimension() {
        0 => {
            assert_eq!((hull.vertices().len(), hull.face_count(), edges.len()), (1, 0, 0));
            assert!(points.iter().all(|&p| p == hull.vertices()[0]));
            0.0
        }
        1 => validate_segment(hull, points, tol),
        2 => validate_flat(hull, points, tol),
        _ => validate_solid(hull, points, tol),
    }
}

fn validate_segment(hull: &ConvexHull, points: &[Vec3], tol: f64) -> f64 {
    assert_eq!((hull.vertices().len(), hull.face_count()), (2, 0));
    assert_eq!(hull.edges().collect::<Vec<_>>(), [[0, 1]]);
    assert_eq!((hull.volume(), hull.surface_area()), (0.0, 0.0));
    let [a, b] = [0, 1].map(|i| hull.vertices()[i].as_dvec3());
    let mut worst: f64 = 0.0;
    for p in points {
        let t = ((p.as_dvec3() - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
        worst = worst.max((p.as_dvec3() - (a + t * (b - a))).length() / tol);
    }
    assert!(worst <= 1.0, "a point is {worst} allowances off the segment");
    worst
}

/// Distances of every point in front of the planes of faces `faces`, and of
/// their vertices off them; faces convex and wound counter-clockwise about their
/// unit normals. Returns the worst distance in front, over `tol`.
fn check_faces(hull: &ConvexHull, points: &[Vec3], tol: f64) -> f64 {
    let mut worst: f64 = 0.0;
    for f in 0..hull.face_count() {
        let poly = face_points(hull, f);
        let n = hull.face_normal(f);
        assert!(poly.len() >= 3 && (n.length() - 1.0).abs() < 1e-9, "face {f}");
        assert!(area_vector(&poly).dot(n) > 0.0, "face {f} is wound clockwise");
        let offset = poly.iter().map(|p| n.dot(*p)).sum::<f64>() / poly.len() as f64;
        assert!((hull.face_offset(f) - offset).abs() <= tol, "face {f} offset");
        for p in &poly {
            assert!((n.dot(*p) - offset).abs() <= tol, "face {f} not planar");
        }
        for p in points {
            worst = worst.max((n.dot(p.as_dvec3()) - offset) / tol);
        }
        assert!(is_convex(&poly, n, tol), "face {f} not convex: {poly:?}");
    }
    assert!(worst <= 1.0, "a point is {worst} allowances in front of a face");
    worst
}

/// Whether a loop is convex within `tol` seen along `n`: at each vertex it turns
/// left, or right by no more than `tol` (the vertex's distance inside the chord
/// of its neighbours), and every vertex lies within `tol` of a supporting line
/// of the loop (a line through two of its vertices with all of them on its
/// left), so small dents cannot add up.
fn is_convex(poly: &[DVec3], n: DVec3, tol: f64) -> bool {
    let (u, v) = n.any_orthonormal_pair();
    let flat: Vec<glam::DVec2> = poly
        .iter()
        .map(|&p| glam::DVec2::new((p - poly[0]).dot(u), (p - poly[0]).dot(v)))
        .collect();
    let m = flat.len();
    let local = (0..m).all(|i| {
        let (p, v, q) = (flat[(i + m - 1) % m], flat[i], flat[(i + 1) % m]);
        (q - p).perp_dot(v - p) <= tol * q.distance(p)
    });
    let size = flat.iter().fold(0.0f64, |s, p| s.max(p.length()));
    let mut supporting = Vec::new();
    for i in 0..m {
        for j in 0..m {
            let (a, b) = (flat[i], flat[j]);
            let len = a.distance(b);
            if len > 0.0 && flat.iter().all(|&k| (b - a).perp_dot(k - a) >= -1e-12 * size * len) {
                supporting.push((a, b));
            }
        }
    }
    let near_boundary = flat
        .iter()
        .all(|&k| supporting.iter().any(|&(a, b)| (b - a).perp_dot(k - a) <= tol * a.distance(b)));
    local && near_boundary
}

fn validate_flat(hull: &ConvexHull, points: &[Vec3], tol: f64) -> f64 {
    assert_eq!(hull.face_count(), 2);
    let (front, back) = (hull.face(0), hull.face(1));
    assert!(front.len() >= 3);
    assert_eq!(front.iter().rev().collect::<Vec<_>>(), back.iter().collect::<Vec<_>>());
    assert!((hull.face_normal(0) + hull.face_normal(1)).length() < 1e-9);
    assert_eq!(hull.vertices().len(), front.len());
    assert_eq!(hull.edge_count(), front.len());
    assert_eq!(hull.volume(), 0.0);
    // Both sides: twice the polygon's area, which is planar only within
    // tolerance, so defined only to about the tolerance times its perimeter.
    let poly = face_points(hull, 0);
    let perimeter: f64 =
        (0..poly.len()).map(|k| poly[k].distance(poly[(k + 1) % poly.len()])).sum();
    let area = area_vector(&poly).length();
    assert!((hull.surface_area() - area).abs() <= 2.0 * tol * perimeter + 1e-12 * area);
    check_faces(hull, points, tol)
}

fn validate_solid(hull: &ConvexHull, points: &[Vec3], tol: f64) -> f64 {
    let (v, f) = (hull.vertices().len(), hull.face_count());
    // Every directed edge once, its reverse once: each edge in two faces, opposite ways.
    let mut directed = HashMap::new();
    for face in 0..f {
        let loop_ = hull.face(face);
        for k in 0..loop_.len() {
            let e = (loop_[k], loop_[(k + 1) % loop_.len()]);
            assert!(directed.insert(e, face).is_none(), "edge {e:?} twice in one direction");
        }
    }
    for (&(a, b), &face) in &directed {
        let other = directed.get(&(b, a)).unwrap_or_else(|| panic!("edge {a}-{b} has one face"));
        assert_ne!(*other, face);
    }
    let e = directed.len() / 2;
    assert_eq!(e, hull.edge_count());
    assert_eq!(v as i64 - e as i64 + f as i64, 2, "Euler: V {v} E {e} F {f}");
    // Each vertex a corner of at least three faces, on their planes.
    let mut faces_at = vec![0; v];
    for face in 0..f {
        hull.face(face).iter().for_each(|&i| faces_at[i as usize] += 1);
    }
    assert!(faces_at.iter().all(|&k| k >= 3), "a vertex lies on fewer than 3 faces");
    let worst = check_faces(hull, points, tol);
    // A solid's face planes are planes of the exact hull: every point behind
    // each, but for f64 rounding of coordinates this large.
    let rounding = 64.0
        * f64::EPSILON
        * points.iter().fold(0.0f64, |m, p| m.max(p.abs().max_element() as f64));
    for face in 0..f {
        let (n, d) = (hull.face_normal(face), hull.face_offset(face));
        for p in points {
            assert!(n.dot(p.as_dvec3()) - d <= rounding, "{p} in front of face {face}");
        }
    }
    // Volume: the tetrahedra fan from an interior point, and the surface area
    // from the faces' area vectors, both computed here. A face is planar only
    // within tolerance, so the two may differ by about the tolerance times the
    // surface area (volume) or times the edge lengths (area).
    let centre = hull.vertices().iter().map(|p| p.as_dvec3()).sum::<DVec3>() / v as f64;
    let (mut volume, mut area, mut perimeter) = (0.0, 0.0, 0.0);
    for face in 0..f {
        let rel: Vec<DVec3> = face_points(hull, face).iter().map(|p| *p - centre).collect();
        volume += area_vector(&rel).dot(rel[0]) / 6.0;
        area += area_vector(&rel).length() / 2.0;
        perimeter += (0..rel.len()).map(|k| rel[k].distance(rel[(k + 1) % rel.len()])).sum::<f64>();
    }
    assert!(volume > 0.0);
    let rounding = 1e-12 * area.powf(1.5);
    assert!(
        (hull.volume() - volume).abs() <= tol * area + rounding,
        "{} vs {volume}",
        hull.volume()
    );
    assert!((hull.surface_area() - area).abs() <= tol * perimeter + 1e-12 * area);
    worst
}

/// Builds, validates and returns the hull.
fn hull_of(points: &[Vec3]) -> ConvexHull {
    let hull = ConvexHull::new(points).unwrap();
    validate(&hull, points);
    hull
}

fn cube_corners() -> Vec<Vec3> {
    (0..8).map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2) as f32)).collect()
}

/// Points of an n x n x n integer grid.
fn grid(n: i32) -> Vec<Vec3> {
    (0..n)
        .flat_map(|i| {
            (0..n).flat_map(move |j| (0..n).map(move |k| Vec3::new(i as f32, j as f32, k as f32)))
        })
        .collect()
}

fn random_points(n: usize, seed: u64, on_sphere: bool) -> Vec<Vec3> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            loop {
                let p = Vec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
                if p.length_squared() <= 1.0 && p.length_squared() > 1e-3 {
                    break if on_sphere { p.normalize() } else { p };
                }
            }
        })
        .collect()
}

#[test]
fn bad_input_is_an_error() {
    assert_eq!(ConvexHull::new(&[]).unwrap_err(), FitError::Empty);
    let points = [Vec3::ZERO, Vec3::X, Vec3::new(0.0, f32::NAN, 0.0), Vec3::Y];
    assert_eq!(ConvexHull::new(&points).unwrap_err(), FitError::NonFinite { index: 2 });
    let points = [Vec3::ZERO, Vec3::splat(f32::INFINITY)];
    assert_eq!(ConvexHull::new(&points).unwrap_err(), FitError::NonFinite { index: 1 });
}

#[test]
fn cube_is_six_quads() {
    let mut points = cube_corners();
    points.push(Vec3::splat(0.5));
    let hull = hull_of(&points);
    assert_eq!(
        (hull.dimension(), hull.vertices().len(), hull.edge_count(), hull.face_count()),
        (3, 8, 12, 6)
    );
    assert!((0..6).all(|f| hull.face(f).len() == 4));
    assert!(!hull.vertices().contains(&Vec3::splat(0.5)));
    assert_eq!(hull.volume(), 1.0);
    assert_eq!(hull.surface_area(), 6.0);
    // The normals are the six axis directions.
    let normals: HashSet<[i64; 3]> =
        (0..6).map(|f| hull.face_normal(f).round().as_i64vec3().to_array()).collect();
    assert_eq!(normals.len(), 6);
    assert!((0..6).all(|f| (hull.face_normal(f).abs().max_element() - 1.0).abs() < 1e-15));
}

#[test]
fn grid_cube_keeps_only_its_corners() {
    // Points on the faces, on the edges and inside: 8 vertices, 6 faces.
    let points = grid(5);
    let hull = hull_of(&points);
    assert_eq!((hull.vertices().len(), hull.edge_count(), hull.face_count()), (8, 12, 6));
    assert_eq!(hull.volume(), 64.0);
    let corners: HashSet<[u32; 3]> =
        hull.vertices().iter().map(|v| v.to_array().map(f32::to_bits)).collect();
    let expected: HashSet<[u32; 3]> =
        cube_corners().iter().map(|c| (*c * 4.0).to_array().map(f32::to_bits)).collect();
    assert_eq!(corners, expected);
}

#[test]
fn cube_with_random_inner_points_has_the_cube_volume() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
    for n in [0, 1, 10, 1000] {
        let mut points: Vec<Vec3> = (0..n)
            .map(|_| {
                Vec3::new(
                    rng.random_range(0.0..1.0),
                    rng.random_range(0.0..1.0),
                    rng.random_range(0.0..1.0),
                )
            })
            .collect();
        points.extend(cube_corners().iter().map(|c| *c * 2.0 - 0.5));
        let hull = hull_of(&points);
        assert_eq!((hull.vertices().len(), hull.face_count()), (8, 6));
        assert!((hull.volume() - 8.0).abs() < 1e-12);
    }
}

#[test]
fn regular_solids_have_their_volumes() {
    // Regular tetrahedron on alternate cube corners, edge 2 sqrt 2: volume 8/3.
    let tetra = [
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(1.0, -1.0, -1.0),
        Vec3::new(-1.0, 1.0, -1.0),
        Vec3::new(-1.0, -1.0, 1.0),
    ];
    let hull = hull_of(&tetra);
    assert_eq!((hull.vertices().len(), hull.edge_count(), hull.face_count()), (4, 6, 4));
    assert!((hull.volume() - 8.0 / 3.0).abs() < 1e-12);
    assert!((hull.surface_area() - 4.0 * 3f64.sqrt() / 4.0 * 8.0).abs() < 1e-12);
    // Regular octahedron |x| + |y| + |z| <= 1 with its centre: volume 4/3.
    let mut octa: Vec<Vec3> = [Vec3::X, Vec3::Y, Vec3::Z].iter().flat_map(|&a| [a, -a]).collect();
    octa.push(Vec3::ZERO);
    let hull = hull_of(&octa);
    assert_eq!((hull.vertices().len(), hull.edge_count(), hull.face_count()), (6, 12, 8));
    assert!((hull.volume() - 4.0 / 3.0).abs() < 1e-12);
    assert!(!hull.vertices().contains(&Vec3::ZERO));
}

#[test]
fn sphere_volume_converges_from_below() {
    let ball = 4.0 / 3.0 * PI;
    let mut last = 0.0;
    for (n, within) in [(100, 0.2), (1000, 0.03), (5000, 0.006)] {
        let points = random_points(n, n as u64, true);
        let hull = hull_of(&points);
        assert_eq!(hull.dimension(), 3);
        let v = hull.volume();
        assert!(v < ball && v > last && v > ball * (1.0 - within), "{n} points: {v}");
        last = v;
        // Every point is on the sphere, so each is a vertex of the hull but for
        // a few that lie within tolerance of a face of their close neighbours.
        assert!(
            hull.vertices().len() >= n - n / 100,
            "{n} points: {} vertices",
            hull.vertices().len()
        );
    }
}

#[test]
fn centroid_never_becomes_a_vertex() {
    for seed in 0..50 {
        let mut points = random_points(30, seed, seed % 2 == 0);
        let centroid = points.iter().sum::<Vec3>() / points.len() as f32;
        points.insert(seed as usize % 30, centroid);
        let hull = hull_of(&points);
        assert!(!hull.vertices().contains(&centroid));
    }
}

#[test]
fn degenerate_sets() {
    // One point, and duplicates of it.
    for n in [1, 2, 5] {
        let hull = hull_of(&vec![Vec3::new(1.5, -2.0, 1e6); n]);
        assert_eq!((hull.dimension(), hull.vertices().len()), (0, 1));
    }
    // Two points; collinear points with duplicates: the ends.
    let hull = hull_of(&[Vec3::X, Vec3::Y]);
    assert_eq!((hull.dimension(), hull.edge_count()), (1, 1));
    let line: Vec<Vec3> =
        [3, 0, 7, 7, 2, -4, 0].iter().map(|&t| Vec3::new(1.0, 2.0, 3.0) * t as f32).collect();
    let hull = hull_of(&line);
    assert_eq!(hull.dimension(), 1);
    assert_eq!(hull.vertices(), [Vec3::new(7.0, 14.0, 21.0), Vec3::new(-4.0, -8.0, -12.0)]);
    // Three points: a triangle, both sides.
    let hull = hull_of(&[Vec3::ZERO, Vec3::X, Vec3::Y]);
    assert_eq!((hull.dimension(), hull.face_count(), hull.edge_count()), (2, 2, 3));
    assert!((hull.surface_area() - 1.0).abs() < 1e-15);
    // A square with points inside and on its sides: 4 vertices, 2 faces.
    let square: Vec<Vec3> =
        (0..5).flat_map(|i| (0..5).map(move |j| Vec3::new(i as f32, 7.0, j as f32))).collect();
    let hull = hull_of(&square);
    assert_eq!(
        (hull.dimension(), hull.vertices().len(), hull.face_count(), hull.edge_count()),
        (2, 4, 2, 4)
    );
    assert_eq!((hull.volume(), hull.surface_area()), (0.0, 32.0));
    let n = hull.face_normal(0);
    assert!(n.abs().y == 1.0 && n.x == 0.0 && n.z == 0.0);
}

#[test]
fn scaling_by_two_and_shifting_exactly_keep_the_faces() {
    // Scaling by a power of two and shifting a small-integer grid are exact in
    // f32, so the hull must be the same up to that map.
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
    let points: Vec<Vec3> = (0..300)
        .map(|_| {
            Vec3::new(
                rng.random_range(-8..=8) as f32,
                rng.random_range(-8..=8) as f32,
                rng.random_range(-8..=8) as f32,
            )
        })
        .collect();
    let base = hull_of(&points);
    for (scale, shift) in [(1.0 / 1024.0, 0.0), (4096.0, 0.0), (1.0, 65536.0), (0.25, -1000.0)] {
        let moved: Vec<Vec3> = points.iter().map(|p| *p * scale + shift).collect();
        let hull = hull_of(&moved);
        let mapped: Vec<Vec3> = base.vertices().iter().map(|p| *p * scale + shift).collect();
        assert_eq!(hull.vertices(), mapped);
        let faces =
            |h: &ConvexHull| (0..h.face_count()).map(|f| h.face(f).to_vec()).collect::<Vec<_>>();
        assert_eq!(faces(&hull), faces(&base));
    }
}

#[test]
fn same_input_same_hull() {
    let points = random_points(2000, 5, false);
    let (a, b) = (hull_of(&points), hull_of(&points));
    assert_eq!(a.vertices(), b.vertices());
    assert!(
        (0..a.face_count()).all(|f| a.face(f) == b.face(f) && a.face_normal(f) == b.face_normal(f))
    );
}

#[test]
fn real_meshes() {
    for r in common::references() {
        let points = common::mesh(&r.name);
        let hull = ConvexHull::new(&points).unwrap();
        let worst = validate(&hull, &points);
        assert_eq!(hull.dimension(), 3);
        // The hull lies inside every box holding the points, and inside their
        // smallest sphere.
        let v = hull.volume();
        assert!(v > 0.0 && v <= r.best_known_obb_volume && v <= r.aabb_volume, "{}: {v}", r.name);
        assert!(v <= 4.0 / 3.0 * PI * r.min_sphere_radius.powi(3));
        // Same hull at another scale and offset: f32 rounding moves each point by
        // about 2^-24 of the size, so the vertices stay, and a merge decision may
        // flip only where faces meet within that of the tolerance: a face of one
        // hull is then the union of faces of the other.
        for (scale, shift) in [(1e-4f32, 0.0f32), (1e4, 0.0), (1.0, 10.0)] {
            let moved: Vec<Vec3> = points.iter().map(|p| *p * scale + shift).collect();
            let other = ConvexHull::new(&moved).unwrap();
            validate(&other, &moved);
            let mapped: Vec<Vec3> = hull.vertices().iter().map(|p| *p * scale + shift).collect();
            assert_eq!(other.vertices(), mapped, "{} at scale {scale} shift {shift}", r.name);
            let flips = same_faces_up_to_merging(&hull, &other);
            eprintln!(
                "{} at scale {scale} shift {shift}: {flips} faces merged differently",
                r.name
            );
        }
        let counts = (hull.vertices().len(), hull.edge_count(), hull.face_count());
        eprintln!("{}: (V, E, F) {counts:?}, worst point {worst:.3} allowances in front", r.name);
    }
}

/// Checks that two hulls on the same vertices have the same faces, but for faces
/// one merged and the other did not: each face of either that the other lacks is
/// within one face of the other, or is tiled by faces of the other within it.
/// Returns the number of such faces.
fn same_faces_up_to_merging(a: &ConvexHull, b: &ConvexHull) -> usize {
    let sets = |h: &ConvexHull| -> Vec<HashSet<u32>> {
        (0..h.face_count()).map(|f| h.face(f).iter().copied().collect()).collect()
    };
    let (sa, sb) = (sets(a), sets(b));
    let mut flips = 0;
    for (mine, theirs) in [(&sa, &sb), (&sb, &sa)] {
        for face in mine.iter().filter(|f| !theirs.contains(f)) {
            flips += 1;
            let merged = theirs.iter().any(|g| face.is_subset(g));
            let parts: HashSet<u32> =
                theirs.iter().filter(|g| g.is_subset(face)).flatten().copied().collect();
            assert!(
                merged || parts == *face,
                "face {face:?} is neither merged nor split in the other hull"
            );
        }
    }
    flips
}

fn rotation() -> impl Strategy<Value = Quat> {
    (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_filter_map(
        "zero quaternion",
        |(x, y, z, w)| {
            let q = glam::Vec4::new(x, y, z, w).try_normalize()?;
            Some(Quat::from_vec4(q))
        },
    )
}

fn scale() -> impl Strategy<Value = f32> {
    (-4.0f32..4.0).prop_map(|e| 10f32.powf(e))
}

fn offset() -> impl Strategy<Value = Vec3> {
    prop_oneof![
        Just(Vec3::ZERO),
        (-1e6f32..1e6, -1e6f32..1e6, -1e6f32..1e6).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    ]
}

/// Random clouds, points on a sphere, integer grid points (many coplanar and
/// collinear), and slabs and needles thin enough to be flat or straight within
/// tolerance or not; with duplicates.
fn cloud(max: usize) -> impl Strategy<Value = Vec<Vec3>> {
    let unit = (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z));
    let sphere = unit.clone().prop_filter_map("origin", |p| p.try_normalize());
    let lattice = (-2i32..=2, -2i32..=2, -2i32..=2)
        .prop_map(|(x, y, z)| Vec3::new(x as f32, y as f32, z as f32));
    let thin = (prop::collection::vec(unit.clone(), 1..max), -8.0f32..-4.0, any::<bool>())
        .prop_map(|(p, e, needle)| {
            let t = 10f32.powf(e);
            let squash = if needle { Vec3::new(1.0, t, t) } else { Vec3::new(1.0, 1.0, t) };
            p.iter().map(|&q| q * squash).collect()
        });
    let points = prop_oneof![
        prop::collection::vec(unit, 1..max),
        prop::collection::vec(sphere, 1..max),
        prop::collection::vec(lattice, 1..max),
        thin,
    ];
    (points, 0usize..4).prop_map(|(mut p, dups)| {
        for k in 0..dups.min(p.len()) {
            let q = p[k * 7 % p.len()];
            p.push(q);
        }
        p
    })
}

/// Points of a random integer triangle's plane: exactly coplanar sets of any
/// orientation, or collinear ones when the triangle is.
fn coplanar(max: usize) -> impl Strategy<Value = Vec<Vec3>> {
    let int3 = || {
        (-3i32..=3, -3i32..=3, -3i32..=3)
            .prop_map(|(x, y, z)| Vec3::new(x as f32, y as f32, z as f32))
    };
    (int3(), int3(), int3(), prop::collection::vec((-4i32..=4, -4i32..=4), 1..max)).prop_map(
        |(o, u, v, st)| st.iter().map(|&(s, t)| o + u * s as f32 + v * t as f32).collect(),
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn moved_clouds_give_valid_hulls(points in cloud(200), q in rotation(), s in scale(), o in offset()) {
        let moved: Vec<Vec3> = points.iter().map(|&p| q * p * s + o).collect();
        hull_of(&moved);
        hull_of(&points);
    }

    #[test]
    fn coplanar_and_collinear_sets_stay_flat(points in coplanar(60), s in -3i32..3, o in -1000i32..1000) {
        // Power-of-two scales and integer shifts keep the set exactly coplanar.
        let moved: Vec<Vec3> = points.iter().map(|&p| p * 2f32.powi(s) + o as f32).collect();
        let hull = hull_of(&moved);
        prop_assert!(hull.dimension() <= 2);
    }

    #[test]
    fn inner_points_are_never_vertices(points in cloud(40), q in rotation()) {
        // Points pulled a quarter of the way to the centroid lie inside the
        // hull; those deeper than the allowance behind every face plane (all of
        // them but in thin hulls) must not become vertices.
        let points: Vec<Vec3> = points.iter().map(|&p| q * p).collect();
        let hull = hull_of(&points);
        if hull.dimension() == 3 {
            let tol = allowance(&points);
            let centroid = points.iter().sum::<Vec3>() / points.len() as f32;
            let deep = |p: Vec3| {
                (0..hull.face_count()).all(|f| hull.face_normal(f).dot(p.as_dvec3()) - hull.face_offset(f) < -tol)
            };
            let inner: Vec<Vec3> =
                hull.vertices().iter().map(|&v| centroid + (v - centroid) * 0.75).filter(|&p| deep(p)).collect();
            let mut more = points.clone();
            more.extend(&inner);
            let hull2 = hull_of(&more);
            let outer: HashSet<[u32; 3]> = points.iter().map(|p| p.to_array().map(f32::to_bits)).collect();
            prop_assert!(hull2.vertices().iter().all(|v| outer.contains(&v.to_array().map(f32::to_bits))));
        }
    }
}

/// Found by the fit fuzz target (cut down to five of its 261 points): a
/// needle 9e5 long with points a few units off it is flat to the hull's
/// tolerance; the plane fitted to its polygon tilted from the one the
/// points were found near, and left a point in front of it by more than
/// the tolerance. Every point is behind every face, to within it.
#[test]
fn a_flat_hull_keeps_every_point_behind_its_faces() {
    let points = [
        Vec3::new(8.71e-6, 5.0, 4.0),
        Vec3::new(5.0, 19102.648, -2.4079924),
        Vec3::new(5.04746, 0.102336526, -2.6604943),
        Vec3::new(4.8576202, -878009.94, -2.0012453),
        Vec3::new(5.0887504, 0.047223605, -2.2784264),
    ];
    let hull = ConvexHull::new(&points).unwrap();
    assert_eq!(hull.dimension(), 2);
    for f in 0..hull.face_count() {
        let (n, d) = (hull.face_normal(f), hull.face_offset(f));
        for p in &points {
            let height = n.dot(p.as_dvec3()) - d;
            assert!(height <= hull.tolerance(), "{p} {height} in front of face {f}");
        }
    }
}

/// Each face's plane by its loop turned to start at its least vertex: a
/// hull's faces whatever their order and starting corners.
fn faces_by_loop(hull: &ConvexHull) -> HashMap<Vec<u32>, (DVec3, f64)> {
    (0..hull.face_count())
        .map(|f| {
            let mut ring = hull.face(f).to_vec();
            let least = (0..ring.len()).min_by_key(|&k| ring[k]).unwrap_or(0);
            ring.rotate_left(least);
            (ring, (hull.face_normal(f), hull.face_offset(f)))
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// A box's hull in closed form is the hull quickhull builds from its
    /// corners: the same vertices in the same order, the same face loops,
    /// the same tolerance, and the same planes up to the last bits of
    /// quickhull's normalising (the closed form's are exact: the axes and
    /// the half extents); at any aspect from 1 to 1e12 and up to the
    /// coordinate limit, and, for half extents that are not all positive,
    /// finite and in range, the same answer.
    #[test]
    fn box_hulls_in_closed_form_equal_quickhulls(
        exponents in prop::array::uniform3(-6.0f64..6.0),
        special in prop::option::of((0..3usize, prop::sample::select(vec![
            0.0f32, -1.0, f32::NAN, f32::INFINITY, 1e18, 2e18, f32::MIN_POSITIVE,
        ]))),
    ) {
        let mut half = Vec3::from_array(exponents.map(|e| 10f64.powf(e) as f32));
        if let Some((axis, value)) = special {
            half[axis] = value;
        }
        let sign = |i: usize, bit: usize| if i & (1 << bit) == 0 { -1.0 } else { 1.0 };
        let corners: Vec<Vec3> =
            (0..8).map(|i| Vec3::new(sign(i, 0), sign(i, 1), sign(i, 2)) * half).collect();
        match (ConvexHull::cuboid(half), ConvexHull::new(&corners)) {
            (Ok(closed), Ok(built)) => {
                prop_assert_eq!(closed.dimension(), built.dimension());
                prop_assert_eq!(closed.vertices(), built.vertices());
                prop_assert_eq!(closed.tolerance(), built.tolerance());
                let (closed, built) = (faces_by_loop(&closed), faces_by_loop(&built));
                prop_assert_eq!(closed.len(), built.len());
                for (ring, (n, offset)) in &closed {
                    let Some(&(m, other)) = built.get(ring) else {
                        return Err(TestCaseError::fail(format!("face {ring:?} not in quickhull's")));
                    };
                    prop_assert!((*n - m).abs().max_element() <= 4.0 * f64::EPSILON, "{n} {m}");
                    prop_assert!((offset - other).abs() <= 4.0 * f64::EPSILON * offset.abs());
                }
            }
            (closed, built) => prop_assert_eq!(closed.err(), built.err()),
        }
    }
}

/// A hull's parts as `from_parts` takes them.
type Parts = (Vec<Vec3>, Vec<Vec<u32>>, Vec<DVec3>, Vec<f64>, f64);

fn parts_of(h: &ConvexHull) -> Parts {
    let n = h.face_count();
    (
        h.vertices().to_vec(),
        (0..n).map(|f| h.face(f).to_vec()).collect(),
        (0..n).map(|f| h.face_normal(f)).collect(),
        (0..n).map(|f| h.face_offset(f)).collect(),
        h.tolerance(),
    )
}

fn from_parts((v, f, n, o, t): Parts) -> Result<ConvexHull, HullError> {
    ConvexHull::from_parts(v, f, n, o, t)
}

/// Every mesh's hull, a grid's and a cube's come back from their parts as
/// they were; parts that break any of its checks are refused, naming the
/// first.
#[test]
fn hulls_come_back_from_their_parts() {
    let mut hulls: Vec<ConvexHull> =
        common::references().iter().map(|r| hull_of(&common::mesh(&r.name))).collect();
    hulls.push(hull_of(&grid(5)));
    hulls.push(ConvexHull::cuboid(Vec3::new(2.0, 0.5, 1e-3)).unwrap());
    for h in &hulls {
        let again = from_parts(parts_of(h)).unwrap();
        assert_eq!(parts_of(&again), parts_of(h));
        assert_eq!((again.dimension(), again.volume()), (3, h.volume()));
    }
    let good = parts_of(&hulls[0]);
    let broken = |edit: &dyn Fn(&mut Parts)| {
        let mut p = good.clone();
        edit(&mut p);
        from_parts(p).err()
    };
    assert_eq!(broken(&|p| p.0[3].x = f32::NAN), Some(HullError::BadVertex { index: 3 }));
    assert_eq!(broken(&|p| p.0[3].x = 2e18), Some(HullError::BadVertex { index: 3 }));
    assert_eq!(broken(&|p| p.1.truncate(3)), Some(HullError::FaceCount { faces: 3 }));
    assert_eq!(
        broken(&|p| {
            p.2.pop();
        }),
        Some(HullError::FaceCount { faces: good.1.len() })
    );
    assert_eq!(broken(&|p| p.1[2][0] = 1 << 30), Some(HullError::BadFace { face: 2 }));
    assert_eq!(broken(&|p| p.1[2].truncate(2)), Some(HullError::BadFace { face: 2 }));
    assert_eq!(broken(&|p| p.2[2] *= 1.01), Some(HullError::BadFace { face: 2 }));
    assert_eq!(broken(&|p| p.3[2] = f64::INFINITY), Some(HullError::BadFace { face: 2 }));
    assert_eq!(broken(&|p| p.3[2] -= 0.1), Some(HullError::NotConvex { face: 2 }));
    assert_eq!(broken(&|p| p.4 = -1.0), Some(HullError::BadTolerance));
    let message = broken(&|p| p.1[2][0] = 1 << 30).unwrap().to_string();
    assert!(message.contains("face 2"), "{message}");
}
