//! bvol embedded in a simulation loop of its own: boxes and balls fall onto a
//! floor, and each contact pushes the pair apart along its normal (a crude
//! position-based step, enough to show what bvol hands a simulation).
//!
//! `cargo run --release --example falling`

use std::sync::Arc;

use bvol::volumes::Pose;
use bvol::{BodyDesc, BodyId, BodyKind, EventKind, Shape, World};
use glam::{Quat, Vec3};

const DT: f32 = 1.0 / 60.0;
const GRAVITY: Vec3 = Vec3::new(0.0, -9.81, 0.0);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut world = World::new();
    let floor = Arc::new(Shape::cuboid(Vec3::new(20.0, 0.5, 20.0))?);
    world.add_body(BodyDesc::new(floor, Pose::IDENTITY).with_kind(BodyKind::Static))?;
    let shapes = [Arc::new(Shape::cuboid(Vec3::splat(0.4))?), Arc::new(Shape::ball(0.4)?)];
    // The simulation's own state: bvol only sees poses.
    let mut bodies: Vec<(BodyId, Vec3, Vec3)> = Vec::new(); // id, position, velocity
    for k in 0..200 {
        let position =
            Vec3::new((k % 10) as f32 - 4.5, 2.0 + (k / 10) as f32, (k % 7) as f32 - 3.0);
        let shape = shapes[k % 2].clone();
        let desc =
            BodyDesc::new(shape, Pose::new(position, Quat::IDENTITY)).with_user_data(k as u64);
        bodies.push((world.add_body(desc)?, position, Vec3::ZERO));
    }
    // From a body's slot back to the simulation's index (the floor has none).
    let mut index_of_slot = vec![None; bodies.len() + 1];
    for (i, b) in bodies.iter().enumerate() {
        index_of_slot[b.0.index() as usize] = Some(i);
    }
    for frame in 0..300 {
        for (_, position, velocity) in &mut bodies {
            *velocity += GRAVITY * DT;
            *position += *velocity * DT;
        }
        let ids: Vec<BodyId> = bodies.iter().map(|b| b.0).collect();
        let poses: Vec<Pose> = bodies.iter().map(|b| Pose::new(b.1, Quat::IDENTITY)).collect();
        world.set_poses(&ids, &poses)?;
        world.update();
        let mut began = 0;
        for event in world.events() {
            let Some(contact) = event.contact else { continue };
            began += usize::from(event.kind == EventKind::Began);
            // Push the dynamic bodies apart along the normal (from a to b),
            // and stop their approach.
            let (a, b) =
                (index_of_slot[event.a.index() as usize], index_of_slot[event.b.index() as usize]);
            let share = if a.is_some() && b.is_some() { 0.5 } else { 1.0 };
            let push = contact.normal * contact.depth * share;
            if let Some(i) = a {
                bodies[i].1 -= push;
                let approach = bodies[i].2.dot(contact.normal).max(0.0);
                bodies[i].2 -= contact.normal * approach;
            }
            if let Some(i) = b {
                bodies[i].1 += push;
                let approach = bodies[i].2.dot(contact.normal).min(0.0);
                bodies[i].2 -= contact.normal * approach;
            }
        }
        if frame % 30 == 0 {
            let s = world.stats();
            println!(
                "frame {frame:3}: {:4} candidates, {:4} after spheres, {:4} after OBBs, {:4} touching, {began:3} began, {:.2} ms",
                s.candidates,
                s.after_spheres,
                s.after_obbs,
                s.touching,
                s.total_time().as_secs_f64() * 1e3
            );
        }
    }
    let lowest = bodies.iter().map(|b| b.1.y).fold(f32::INFINITY, f32::min);
    println!("lowest body centre after 5 s: {lowest:.3} (the floor's top is at 0.5)");
    Ok(())
}
