//! Snapshots (feature `serde`): a world saved as JSON at some frame and
//! loaded runs on with exactly the original's events and contacts, frame
//! after frame, through moves, removals, additions and kind changes, with
//! and without a margin, the loaded one on two threads; and data no world
//! saved is a typed error, never a panic.

mod common;

use std::sync::Arc;

use bvol::volumes::{Aabb, Pose, Ray};
use bvol::{BodyDesc, BodyId, BodyKind, Shape, Snapshot, SnapshotError, World, WorldConfig};
use common::{random_pose, shapes_of_size};
use glam::{Quat, Vec3};
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};
use serde_json::Value;

/// One edit of a frame, the same for the original and the loaded world.
enum Op {
    Move(Vec<BodyId>, Vec<Pose>),
    Remove(BodyId),
    Add(usize, Pose, BodyKind),
    Kind(BodyId, BodyKind),
}

/// A frame's edits on `world`'s bodies: most dynamic bodies move a little,
/// a body goes, one comes, one changes kind.
fn edits(world: &World, rng: &mut SmallRng, side: f32, shapes: usize) -> Vec<Op> {
    let ids: Vec<BodyId> = world.bodies().collect();
    let moving = ids.iter().filter(|&&id| world.kind(id).unwrap() == BodyKind::Dynamic);
    let moving: Vec<BodyId> = moving.filter(|_| rng.random::<f32>() < 0.7).copied().collect();
    let poses = moving
        .iter()
        .map(|&id| {
            let p = world.pose(id).unwrap();
            let d = (Vec3::new(rng.random(), rng.random(), rng.random()) - 0.5) * 0.2;
            Pose::new(p.position + d, (Quat::from_rotation_y(0.05) * p.rotation).normalize())
        })
        .collect();
    let kinds = [BodyKind::Dynamic, BodyKind::Static, BodyKind::Sleeping];
    vec![
        Op::Move(moving, poses),
        Op::Remove(ids[rng.random_range(0..ids.len())]),
        Op::Add(rng.random_range(0..shapes), random_pose(rng, side), kinds[rng.random_range(0..3)]),
        Op::Kind(ids[rng.random_range(0..ids.len())], kinds[rng.random_range(0..3)]),
    ]
}

fn apply(world: &mut World, ops: &[Op], shapes: &[Arc<Shape>]) {
    for op in ops {
        match op {
            Op::Move(ids, poses) => world.set_poses(ids, poses).unwrap(),
            // The body may be gone already: the same error on both worlds.
            Op::Remove(id) => world.remove_body(*id).unwrap_or(()),
            Op::Add(shape, pose, kind) => {
                let desc = BodyDesc::new(shapes[*shape].clone(), *pose).with_kind(*kind);
                world.add_body(desc.with_user_data(7)).unwrap();
            }
            Op::Kind(id, kind) => world.set_kind(*id, *kind).unwrap_or(()),
        }
    }
}

/// The bodies whose boxes meet `region`, sorted.
fn queried(world: &World, region: &Aabb) -> Vec<BodyId> {
    let mut found = Vec::new();
    world.query(region, |id| found.push(id));
    found.sort();
    found
}

/// A world saved as JSON and loaded back.
fn reloaded(world: &World) -> World {
    let text = serde_json::to_string(&world.snapshot()).unwrap();
    World::from_snapshot(&serde_json::from_str::<Snapshot>(&text).unwrap()).unwrap()
}

#[test]
fn a_loaded_world_runs_on_with_the_same_events() {
    let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let shapes = shapes_of_size(1.0);
    for (margin, save_at, seed) in [(0.0, 3, 1), (0.0, 0, 2), (0.05, 4, 3)] {
        let config = WorldConfig::default().with_margin(margin);
        let mut world = World::with_config(config).unwrap();
        let mut rng = SmallRng::seed_from_u64(seed);
        let n = 300;
        let side = (n as f32).cbrt() * 1.6;
        for k in 0..n {
            let kind = match k % 10 {
                0 => BodyKind::Static,
                1 => BodyKind::Sleeping,
                _ => BodyKind::Dynamic,
            };
            let desc = BodyDesc::new(shapes[k % shapes.len()].clone(), random_pose(&mut rng, side));
            world.add_body(desc.with_kind(kind).with_user_data(k as u64)).unwrap();
        }
        let mut loaded = None;
        let mut compared = 0;
        for frame in 0..10 {
            let ops = edits(&world, &mut rng, side, shapes.len());
            apply(&mut world, &ops, &shapes);
            if frame == save_at {
                let copy = reloaded(&world);
                // Before any update it answers queries as the original,
                // from the bounds of the last update.
                for k in 0..20 {
                    let from = Vec3::new(-1.0, k as f32 * 0.6, 0.3 * k as f32);
                    let ray = Ray::new(from, Vec3::new(1.0, 0.1, 0.05).normalize());
                    assert_eq!(copy.ray_cast(&ray, 100.0), world.ray_cast(&ray, 100.0));
                    let region = Aabb::new(from, from + Vec3::splat(2.0));
                    assert_eq!(queried(&copy, &region), queried(&world, &region));
                }
                loaded = Some(copy);
            } else if let Some(copy) = loaded.as_mut() {
                apply(copy, &ops, &shapes);
            }
            world.update();
            if let Some(copy) = loaded.as_mut() {
                two.install(|| copy.update());
                let (got, want) = (copy.events(), world.events());
                let first = got.iter().zip(want).position(|(x, y)| x != y);
                assert!(
                    got == want,
                    "frame {frame}, margin {margin}: {} events against {}, first differing {:?}",
                    got.len(),
                    want.len(),
                    first.map(|k| (got[k], want[k]))
                );
                let (a, b): (Vec<_>, Vec<_>) =
                    (copy.contacts().collect(), world.contacts().collect());
                assert_eq!(a, b, "frame {frame}");
                assert_eq!(copy.bodies().collect::<Vec<_>>(), world.bodies().collect::<Vec<_>>());
                compared += world.events().len();
            }
        }
        assert!(compared > 500, "only {compared} events compared");
    }
}

/// A saved world with a body removed (a free slot), a sleeping pile and a
/// static floor, as JSON.
fn saved_json() -> Value {
    let mut world = World::new();
    let cube = Arc::new(Shape::cuboid(Vec3::splat(0.5)).unwrap());
    let bunny = shapes_of_size(1.0)[5].clone();
    let floor = Arc::new(Shape::cuboid(Vec3::new(5.0, 0.5, 5.0)).unwrap());
    world.add_body(BodyDesc::new(floor, Pose::IDENTITY).with_kind(BodyKind::Static)).unwrap();
    let mut ids = Vec::new();
    for k in 0..6 {
        let pose = Pose::new(Vec3::new(k as f32 * 0.9, 0.95, 0.0), Quat::IDENTITY);
        let shape = if k % 2 == 0 { cube.clone() } else { bunny.clone() };
        ids.push(world.add_body(BodyDesc::new(shape, pose)).unwrap());
    }
    world.update();
    world.remove_body(ids[2]).unwrap();
    world.set_kind(ids[3], BodyKind::Sleeping).unwrap();
    world.update();
    serde_json::to_value(world.snapshot()).unwrap()
}

fn load(value: &Value) -> Result<World, SnapshotError> {
    World::from_snapshot(&serde_json::from_value::<Snapshot>(value.clone()).unwrap())
}

#[test]
fn bad_snapshots_are_typed_errors() {
    let good = saved_json();
    assert!(load(&good).is_ok());
    // Cut short anywhere, the format's reader refuses it.
    let text = good.to_string();
    for end in (0..text.len()).step_by(97) {
        assert!(serde_json::from_str::<Snapshot>(&text[..end]).is_err());
    }
    let edit = |f: &dyn Fn(&mut Value)| {
        let mut v = good.clone();
        f(&mut v);
        load(&v).err()
    };
    assert!(matches!(
        edit(&|v| v["version"] = 9.into()),
        Some(SnapshotError::Version { found: 9 })
    ));
    assert!(matches!(edit(&|v| v["margin"] = (-1.0).into()), Some(SnapshotError::Config(_))));
    // A face index beyond the vertices, then a vertex moved off its faces.
    let shape_of_hull = |v: &mut Value, f: &dyn Fn(&mut Value)| {
        for s in v["shapes"].as_array_mut().unwrap() {
            for p in s["parts"].as_array_mut().unwrap() {
                if let Some(h) = p.get_mut("Hull") {
                    f(h);
                    return;
                }
            }
        }
    };
    let far = edit(&|v| shape_of_hull(v, &|h| h["faces"][0][0] = 100_000.into()));
    assert!(matches!(far, Some(SnapshotError::Shape { .. })), "{far:?}");
    let off = edit(&|v| shape_of_hull(v, &|h| h["vertices"][0][1] = 7.5.into()));
    assert!(matches!(off, Some(SnapshotError::Shape { .. })), "{off:?}");
    let box_ = edit(&|v| v["shapes"][0]["parts"][0]["Cuboid"]["half_extents"][0] = (-1.0).into());
    assert!(matches!(box_, Some(SnapshotError::Shape { shape: 0, .. })), "{box_:?}");
    // A live body in a slot of even generation; a free slot not free; a
    // shape index out of range; a pose of zero rotation.
    let slot = |v: &mut Value| v["slots"][1][0] = 2.into();
    assert!(matches!(edit(&slot), Some(SnapshotError::Slot { slot: 1, .. })));
    let free = |v: &mut Value| v["free"][0] = 0.into();
    assert!(matches!(edit(&free), Some(SnapshotError::Slot { slot: 0, .. })));
    let shape = |v: &mut Value| v["slots"][1][1]["shape"] = 99.into();
    assert!(matches!(edit(&shape), Some(SnapshotError::Slot { slot: 1, .. })));
    let pose =
        |v: &mut Value| v["slots"][1][1]["rotation"] = serde_json::json!([0.0, 0.0, 0.0, 0.0]);
    assert!(matches!(edit(&pose), Some(SnapshotError::Slot { slot: 1, .. })));
    // Pairs out of order, or naming the removed body's slot.
    let swap = |v: &mut Value| v["pairs"].as_array_mut().unwrap().reverse();
    assert!(matches!(edit(&swap), Some(SnapshotError::Pair { .. })));
    let gone = |v: &mut Value| v["pairs"][0][1] = 3.into();
    assert!(matches!(edit(&gone), Some(SnapshotError::Pair { pair: 0 })));
    // An event of no kind, one whose contact is not unit.
    let kind = |v: &mut Value| v["events"][0]["kind"] = 5.into();
    assert!(matches!(edit(&kind), Some(SnapshotError::Event { event: 0 })));
    let normal =
        |v: &mut Value| v["events"][0]["contact"]["normal"] = serde_json::json!([0.0, 3.0, 0.0]);
    assert!(matches!(edit(&normal), Some(SnapshotError::Event { event: 0 })));
    // Every message names its place.
    for error in [edit(&slot), edit(&swap), edit(&kind)].into_iter().flatten() {
        assert!(error.to_string().starts_with("snapshot "), "{error}");
    }
}
