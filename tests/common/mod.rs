//! Shared by the world tests: the mesh files, a mix of shapes, random poses.
#![allow(dead_code)] // each test binary uses its own part of this module

use std::path::PathBuf;
use std::sync::Arc;

use bvol::volumes::Pose;
use bvol::{FitOptions, Shape};
use glam::{Quat, Vec3};
use rand::RngExt;
use rand::rngs::SmallRng;

/// The path of a mesh of tests/meshes.
pub fn mesh(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/meshes").join(format!("{name}.obj"))
}

/// A mix of shapes of size about `s`: boxes, a rod, a tetrahedron, a
/// capsule, a ball, the bunny's hull scaled down, a two-part shape (two
/// objects of one file), and scaled copies of some (`Shape::scaled`,
/// uniform and per axis).
pub fn shapes_of_size(s: f32) -> Vec<Arc<Shape>> {
    let bunny = bvol::load_obj(mesh("bunny")).unwrap();
    let small: Vec<Vec3> = bunny[0].positions.iter().map(|&p| p * 0.1 * s).collect();
    let mut two = bvol::Mesh { name: "left".into(), ..Default::default() };
    two.positions = vec![Vec3::ZERO, Vec3::X * s, Vec3::Y * s, Vec3::Z * s];
    let mut right = two.clone();
    right.name = "right".into();
    right.positions.iter_mut().for_each(|p| *p += Vec3::new(1.5 * s, 0.0, 0.0));
    vec![
        Shape::cuboid(Vec3::splat(0.5 * s)).unwrap(),
        Shape::cuboid(Vec3::new(1.5, 0.1, 0.1) * s).unwrap(),
        Shape::tetrahedron(0.7 * s).unwrap(),
        Shape::capsule(0.3 * s, 0.5 * s).unwrap(),
        Shape::ball(0.5 * s).unwrap(),
        Shape::convex(&small).unwrap(),
        Shape::from_meshes(&[two.clone(), right.clone()], FitOptions::default()).unwrap(),
        // Scaled shapes: a box stretched per axis, the bunny's hull scaled
        // uniformly (its bounds scaled, not refitted), a capsule, and the
        // two-part shape stretched per axis.
        Shape::cuboid(Vec3::splat(0.5 * s)).unwrap().scaled(Vec3::new(0.6, 1.8, 1.0)).unwrap(),
        Shape::convex(&small).unwrap().scaled(Vec3::splat(1.5)).unwrap(),
        Shape::capsule(0.3 * s, 0.5 * s).unwrap().scaled(Vec3::splat(0.8)).unwrap(),
        Shape::from_meshes(&[two, right], FitOptions::default())
            .unwrap()
            .scaled(Vec3::new(1.0, 0.5, 2.0))
            .unwrap(),
    ]
    .into_iter()
    .map(Arc::new)
    .collect()
}

pub fn random_pose(rng: &mut SmallRng, side: f32) -> Pose {
    let p = Vec3::new(rng.random(), rng.random(), rng.random()) * side;
    let q = Quat::from_xyzw(
        rng.random::<f32>() - 0.5,
        rng.random::<f32>() - 0.5,
        rng.random::<f32>() - 0.5,
        rng.random::<f32>() - 0.5,
    );
    Pose::new(p, q.normalize())
}
