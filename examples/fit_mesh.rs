//! Fit a bounding sphere and an OBB to a mesh, move them with a body, and test
//! them against a second body's: the first steps of bvol's frame, by hand.
//!
//! `cargo run --release --example fit_mesh [MESH.obj]`

use bvol::volumes::{Obb, ObbMethod, Pose, Sphere, SphereMethod};
use glam::{Quat, Vec3};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).unwrap_or_else(|| "tests/meshes/duck.obj".into());
    let meshes = bvol::load_obj(&path)?;
    let points: Vec<Vec3> = meshes.iter().flat_map(|m| m.positions.iter().copied()).collect();

    // Fitted once, in the body's own frame.
    let sphere = Sphere::fit(&points, SphereMethod::Exact)?;
    let obb = Obb::fit(&points, ObbMethod::MinVolume)?;
    println!("{path}: {} vertices", points.len());
    println!("sphere: centre {}, radius {}", sphere.center, sphere.radius);
    println!(
        "obb: centre {}, half extents {}, volume {}",
        obb.center,
        obb.half_extents,
        obb.volume()
    );

    // Two bodies with the same shape, side by side: cheapest test first.
    let a = Pose::new(Vec3::ZERO, Quat::IDENTITY);
    let b = Pose::new(Vec3::X * 1.5 * sphere.radius, Quat::from_rotation_y(1.0));
    let spheres_touch = sphere.transformed(&a).overlaps(&sphere.transformed(&b));
    let boxes_touch = spheres_touch && obb.transformed(&a).overlaps(&obb.transformed(&b));
    println!("spheres overlap: {spheres_touch}; boxes overlap: {boxes_touch}");
    Ok(())
}
