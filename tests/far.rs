//! Large worlds: a scene of bodies about 1 across, placed at the origin and
//! again 1e6 and 1e8 from it (positions in f64, `World::set_poses_f64`),
//! moved alike for a few frames: the far copies find the same pairs in
//! contact (but for pairs within 1e-5 of touching, where either answer is
//! right), with depths within 1e-4 and normals within 1e-3 rad of the
//! origin scene's; and contact points (`contact_points_f64`, less the
//! offset) within 1e-4 of its, but for the few contacts of nearly parallel
//! features, whose point along the stretch where they meet moves far with
//! a rounding of the poses (those within a quarter of the bodies' size).

mod common;

use std::collections::BTreeMap;

use bvol::narrow::Contact;
use bvol::volumes::{DPose, Pose};
use bvol::{BodyDesc, BodyId, World, WorldError};
use common::{random_pose, shapes_of_size};
use glam::{DVec3, Quat, Vec3};
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

const DEPTH: f32 = 1e-4;
const NORMAL: f32 = 1e-3;
const POINT: f64 = 1e-4;
const BAND: f32 = 1e-5;

/// Each pair in contact, by slots, with its contact.
fn contacts(world: &World) -> BTreeMap<(u32, u32), Contact> {
    world.contacts().map(|(a, b, c)| ((a.index(), b.index()), c)).collect()
}

#[test]
fn far_scenes_touch_as_the_scene_at_the_origin() {
    let shapes = shapes_of_size(1.0);
    let n = 250;
    let side = (n as f32).cbrt() * 1.6;
    let mut rng = SmallRng::seed_from_u64(5);
    let start: Vec<Pose> = (0..n).map(|_| random_pose(&mut rng, side)).collect();
    let offsets = [DVec3::new(1e6, 0.0, 0.0), DVec3::new(1e8, -3e7, 5e6)];
    let mut worlds: Vec<(World, DVec3)> = Vec::new();
    let mut ids: Vec<BodyId> = Vec::new();
    for offset in [DVec3::ZERO, offsets[0], offsets[1]] {
        let mut world = World::new();
        ids = (0..n)
            .map(|k| world.add_body(BodyDesc::new(shapes[k % shapes.len()].clone(), start[k])))
            .collect::<Result<_, _>>()
            .unwrap();
        worlds.push((world, offset));
    }
    let mut poses: Vec<DPose> = start.iter().map(|&p| DPose::from(p)).collect();
    let (mut checked, mut pointed) = (0, 0);
    for frame in 0..4 {
        for (world, offset) in &mut worlds {
            let placed: Vec<DPose> =
                poses.iter().map(|p| DPose::new(p.position + *offset, p.rotation)).collect();
            world.set_poses_f64(&ids, &placed).unwrap();
            world.update();
        }
        let near = contacts(&worlds[0].0);
        for (world, offset) in &worlds[1..] {
            let far = contacts(world);
            for (key, c) in &far {
                if let Some(d) = near.get(key) {
                    assert!((c.depth - d.depth).abs() <= DEPTH, "{key:?} at {offset}: depth");
                    let angle = c.normal.angle_between(d.normal);
                    assert!(angle <= NORMAL, "{key:?} at {offset}: normal off by {angle}");
                    let (a, b) = (ids[key.0 as usize], ids[key.1 as usize]);
                    let got = world.contact_points_f64(a, b).unwrap();
                    let want = worlds[0].0.contact_points_f64(a, b).unwrap();
                    if got.len() == want.len() {
                        let off = |(g, w): (&DVec3, &DVec3)| (*g - *offset - *w).length();
                        let worst = got.iter().zip(&want).map(off).fold(0.0, f64::max);
                        assert!(worst <= 0.25, "{key:?} at {offset}: point off by {worst}");
                        pointed += usize::from(worst <= POINT);
                    }
                    checked += 1;
                } else {
                    assert!(c.depth.abs() <= BAND, "{key:?} at {offset}: only far, {c:?}");
                }
            }
            for (key, d) in &near {
                assert!(far.contains_key(key) || d.depth.abs() <= BAND, "{key:?}: only near");
            }
        }
        for p in &mut poses {
            let d = (Vec3::new(rng.random(), rng.random(), rng.random()) - 0.5) * 0.2;
            p.position += d.as_dvec3();
            p.rotation = (Quat::from_rotation_y(0.05) * p.rotation).normalize();
        }
        assert!(checked > 100 * (frame + 1), "only {checked} contacts compared");
    }
    println!("{checked} contacts compared, {pointed} with every point within {POINT}");
    assert!(
        pointed * 50 >= checked * 49,
        "{pointed} of {checked} with their points within {POINT}"
    );
}

#[test]
fn far_poses_are_checked_and_kept_in_f64() {
    let mut world = World::new();
    let ball = std::sync::Arc::new(bvol::Shape::ball(0.5).unwrap());
    let id = world.add_body(BodyDesc::new(ball, Pose::IDENTITY)).unwrap();
    let far = DPose::new(DVec3::new(1e8 + 0.125, 2.5, -7e7 - 0.5), Quat::IDENTITY);
    world.set_poses_f64(&[id], &[far]).unwrap();
    assert_eq!(world.pose_f64(id), Ok(far));
    assert_eq!(world.pose(id).unwrap().position, far.to_pose().position);
    for bad in [DVec3::new(f64::NAN, 0.0, 0.0), DVec3::new(1e19, 0.0, 0.0)] {
        let got = world.set_poses_f64(&[id], &[DPose::new(bad, Quat::IDENTITY)]);
        assert!(matches!(got, Err(WorldError::BadPose { .. })), "{bad}");
    }
    assert_eq!(world.pose_f64(id), Ok(far), "a refused pose changes nothing");
    world.update();
    // The world sphere, in f32, holds the ball where its f64 position is.
    let sphere = world.world_sphere(id).unwrap();
    let gap = (sphere.center.as_dvec3() - far.position).length() + 0.5;
    assert!(gap <= f64::from(sphere.radius), "{gap} > {}", sphere.radius);
}
