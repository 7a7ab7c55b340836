//! The World's pipeline against brute force: the touching set of every frame
//! equals an all-pairs hull test, the events are the difference of touching
//! sets, the OBB stage removes candidates the boxes of the tree let through,
//! ray casts find the nearest body, bad input is a typed error, and the
//! result does not depend on the number of threads.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

use bvol::narrow::{Contact, WarmStart, collide_parts, contact_within};
use bvol::volumes::Aabb;
use bvol::volumes::{DPose, Pose, Ray};
use bvol::{
    BodyDesc, BodyId, BodyKind, Broadphase, BruteForce, ContactEvent, EventKind, FitOptions,
    MeshProblem, Shape, ShapeError, World, WorldConfig, WorldError,
};
use common::{mesh, random_pose, shapes_of_size};
use glam::{DVec3, Quat, Vec3, Vec4};
use proptest::prelude::*;
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

/// [`shapes_of_size`] at size 1.
fn shapes() -> Vec<Arc<Shape>> {
    shapes_of_size(1.0)
}

/// The touching pairs by brute force: every pair of bodies whose boxes
/// (computed here from the parts' support points along the world's axes, not
/// the world's bounds) overlap, tested part by part with the narrow phase's
/// pair table, no warm start.
fn brute_force(world: &World) -> BTreeSet<(u32, u32)> {
    let ids: Vec<BodyId> = world.bodies().collect();
    let boxes: Vec<(Vec3, Vec3)> = ids
        .iter()
        .map(|&id| {
            let pose = world.pose(id).unwrap();
            let shape = world.shape(id).unwrap();
            let mut lo = Vec3::INFINITY;
            let mut hi = Vec3::NEG_INFINITY;
            for part in shape.parts() {
                for axis in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z] {
                    let local = pose.rotation.inverse() * axis;
                    let w = pose.transform_point(part.support(local));
                    (lo, hi) = (lo.min(w), hi.max(w));
                }
            }
            let pad = 1e-4 * (hi - lo).max_element() + world.config().margin;
            (lo - pad, hi + pad)
        })
        .collect();
    let mut touching = BTreeSet::new();
    for i in 0..ids.len() {
        for j in i + 1..ids.len() {
            let (a, b) = (ids[i], ids[j]);
            let (ka, kb) = (world.kind(a).unwrap(), world.kind(b).unwrap());
            if ka != BodyKind::Dynamic && kb != BodyKind::Dynamic {
                continue;
            }
            let ((la, ha), (lb, hb)) = (boxes[i], boxes[j]);
            if la.cmpgt(hb).any() || lb.cmpgt(ha).any() {
                continue;
            }
            if touch(world, a, b) {
                touching.insert((a.index(), b.index()));
            }
        }
    }
    touching
}

/// Whether two bodies are in contact, part by part: touching, or apart
/// within the world's margin.
fn touch(world: &World, a: BodyId, b: BodyId) -> bool {
    touch_at(world, a, b, false)
}

/// [`touch`], tested on `b`'s f64 position relative to `a`'s if
/// `relative` (as a world given positions that are not f32's tests).
fn touch_at(world: &World, a: BodyId, b: BodyId, relative: bool) -> bool {
    let (mut pa, mut pb) = (world.pose(a).unwrap(), world.pose(b).unwrap());
    if relative {
        let (fa, fb) = (world.pose_f64(a).unwrap(), world.pose_f64(b).unwrap());
        pa.position = Vec3::ZERO;
        pb.position = (fb.position - fa.position).as_vec3();
    }
    let (sa, sb) = (world.shape(a).unwrap(), world.shape(b).unwrap());
    let margin = world.config().margin;
    sa.parts().iter().any(|x| {
        sb.parts().iter().any(|y| {
            let c = contact_within(x, &pa, y, &pb, margin, &mut WarmStart::default());
            c.unwrap().is_some()
        })
    })
}

/// A random world of `n` bodies in a cube dense enough for about one
/// contact a body, a tenth of them static.
fn random_world(n: usize, seed: u64) -> (World, Vec<BodyId>, SmallRng) {
    random_world_with(n, seed, WorldConfig::default())
}

/// [`random_world`], set up by `config`.
fn random_world_with(n: usize, seed: u64, config: WorldConfig) -> (World, Vec<BodyId>, SmallRng) {
    let mut rng = SmallRng::seed_from_u64(seed);
    let shapes = shapes();
    let side = (n as f32).cbrt() * 1.6;
    let mut world = World::with_config(config).unwrap();
    let mut ids = Vec::new();
    for k in 0..n {
        let shape = shapes[rng.random_range(0..shapes.len())].clone();
        let kind = if k % 10 == 0 { BodyKind::Static } else { BodyKind::Dynamic };
        let desc = BodyDesc::new(shape, random_pose(&mut rng, side)).with_kind(kind);
        ids.push(world.add_body(desc.with_user_data(k as u64)).unwrap());
    }
    (world, ids, rng)
}

/// Moves every dynamic body a little (and a few far), as a frame would.
fn step(world: &mut World, ids: &[BodyId], rng: &mut SmallRng) {
    step_some(world, ids, rng, 1.0);
}

/// Moves each dynamic body with probability `share`, as [`step`] does.
fn step_some(world: &mut World, ids: &[BodyId], rng: &mut SmallRng, share: f32) {
    let side = (ids.len() as f32).cbrt() * 1.6;
    let mut moved = Vec::new();
    let mut poses = Vec::new();
    for &id in ids {
        if world.kind(id).unwrap() != BodyKind::Dynamic || rng.random::<f32>() >= share {
            continue;
        }
        let pose = world.pose(id).unwrap();
        let next = if rng.random::<f32>() < 0.02 {
            random_pose(rng, side)
        } else {
            let d = (Vec3::new(rng.random(), rng.random(), rng.random()) - 0.5) * 0.3;
            let spin = Quat::from_rotation_y((rng.random::<f32>() - 0.5) * 0.2);
            Pose::new(pose.position + d, (spin * pose.rotation).normalize())
        };
        moved.push(id);
        poses.push(next);
    }
    world.set_poses(&moved, &poses).unwrap();
}

/// The touching pairs the world reports, from its events.
fn touching_of(world: &World) -> BTreeSet<(u32, u32)> {
    world
        .events()
        .iter()
        .filter(|e| e.kind != EventKind::Ended)
        .map(|e| (e.a.index(), e.b.index()))
        .collect()
}

/// The world a fresh one makes of `world`'s bodies at their poses now
/// (added in the same order, so in the same slots): every pair tested cold.
fn fresh_copy(world: &World, ids: &[BodyId]) -> World {
    let mut fresh = World::new();
    for &id in ids {
        let desc = BodyDesc::new(world.shape(id).unwrap().clone(), world.pose(id).unwrap());
        let desc =
            desc.with_kind(world.kind(id).unwrap()).with_user_data(world.user_data(id).unwrap());
        fresh.add_body(desc).unwrap();
    }
    fresh.update();
    fresh
}

/// Each touching pair's slots and contact, from a world's events.
fn contacts_of(world: &World) -> Vec<((u32, u32), Contact)> {
    let touching = world.events().iter().filter(|e| e.kind != EventKind::Ended);
    touching.map(|e| ((e.a.index(), e.b.index()), e.contact.expect("touching"))).collect()
}

/// A pose handed over unchanged moves nothing: the body is not placed
/// again, and a pair of two such bodies keeps its last answer untested.
/// Every frame the contacts are those a fresh world finds at the same
/// poses, bit for bit: after some bodies move, and after every pose is
/// handed over again unchanged (then no body counts as moved).
#[test]
fn unchanged_poses_keep_their_contacts() {
    let (mut world, ids, mut rng) = random_world(400, 31);
    world.update();
    let poses: Vec<Pose> = ids.iter().map(|&id| world.pose(id).unwrap()).collect();
    for frame in 0..6 {
        if frame % 2 == 0 {
            step_some(&mut world, &ids, &mut rng, 0.2);
        } else {
            let now: Vec<Pose> = ids.iter().map(|&id| world.pose(id).unwrap()).collect();
            world.set_poses(&ids, &now).unwrap();
        }
        let stats = *world.update();
        if frame % 2 == 1 {
            assert_eq!(stats.moved, 0, "frame {frame}: unchanged poses counted as moved");
            assert!(
                world.events().iter().all(|e| e.kind == EventKind::Persisting),
                "frame {frame}"
            );
        }
        let got = contacts_of(&world);
        assert!(got.len() > 50, "frame {frame}: only {} touching pairs", got.len());
        assert_eq!(got, contacts_of(&fresh_copy(&world, &ids)), "frame {frame}");
    }
    assert_ne!(poses, ids.iter().map(|&id| world.pose(id).unwrap()).collect::<Vec<_>>());
}

/// Every frame the pairs in contact (touching, and with a margin those
/// apart within it) are those of an all-pairs test, and the events their
/// differences: with no margin, and with one of a tenth of the bodies'
/// size, where the bodies' grown bounds must let every near pair through.
#[test]
fn touching_pairs_equal_brute_force_every_frame() {
    let runs = [
        (200, 12, 1, 0.0),
        (1000, 6, 2, 0.0),
        (5000, 3, 3, 0.0),
        (200, 12, 5, 0.1),
        (1000, 6, 6, 0.1),
    ];
    for (n, frames, seed, margin) in runs {
        let config = WorldConfig::default().with_margin(margin);
        let (mut world, ids, mut rng) = random_world_with(n, seed, config);
        let mut before = BTreeSet::new();
        let (mut total, mut near) = (0, 0);
        for f in 0..frames {
            let stats = *world.update();
            let now = touching_of(&world);
            assert_eq!(now, brute_force(&world), "n = {n}, margin {margin}");
            // Each stage passes on a subset of the one before.
            assert!(stats.candidates >= stats.after_spheres);
            assert!(stats.after_spheres >= stats.after_obbs);
            assert!(stats.after_obbs >= stats.touching + stats.near);
            assert_eq!(stats.touching + stats.near, now.len());
            let apart = world.contacts().filter(|(_, _, c)| !c.is_touching()).count();
            assert_eq!(stats.near, apart);
            // Events are the difference of the sets in contact.
            let kinds = |k: EventKind| -> BTreeSet<(u32, u32)> {
                let events = world.events().iter().filter(|e| e.kind == k);
                events.map(|e| (e.a.index(), e.b.index())).collect()
            };
            assert_eq!(kinds(EventKind::Began), &now - &before);
            assert_eq!(kinds(EventKind::Ended), &before - &now);
            assert_eq!(kinds(EventKind::Persisting), &now & &before);
            // Ordered by the bodies' slots, as documented, each pair once.
            let keys: Vec<_> = world.events().iter().map(|e| (e.a.index(), e.b.index())).collect();
            assert!(keys.is_sorted_by(|x, y| x < y), "n = {n}: events out of order");
            total += now.len();
            near += stats.near;
            before = now;
            // Most bodies moving, then few: the moving tree reads the slot
            // array, or is handed the list of those that moved.
            step_some(&mut world, &ids, &mut rng, [1.0, 0.05][f % 2]);
        }
        assert!(total > n / 4, "n = {n}: too few contacts ({total}) to prove much");
        assert_eq!(near > total / 20, margin > 0.0, "n = {n}: {near} near of {total}");
    }
}

#[test]
fn moving_b_along_the_normal_by_the_depth_separates_them() {
    let (mut world, _, _) = random_world(1000, 4);
    world.update();
    let mut checked = 0;
    for e in world.events() {
        let c = e.contact.unwrap();
        assert!((c.normal.length() - 1.0).abs() < 1e-4);
        // Moving B along the normal by more than the depth separates them,
        // when A and B are single parts.
        let (pa, pb) = (world.pose(e.a).unwrap(), world.pose(e.b).unwrap());
        let (sa, sb) = (world.shape(e.a).unwrap(), world.shape(e.b).unwrap());
        if let ([x], [y]) = (sa.parts(), sb.parts()) {
            let size = world.world_sphere(e.a).unwrap().radius;
            let apart = Pose::new(pb.position + c.normal * (c.depth + 1e-3 * size), pb.rotation);
            let test = collide_parts(x, &pa, y, &apart, &mut WarmStart::default());
            assert!(!test.unwrap().is_touching(), "{e:?}");
            checked += 1;
        }
    }
    assert!(checked > 50, "{checked}");
}

#[test]
fn obb_stage_removes_candidates_the_tree_lets_through() {
    // Long thin rods at random angles: their boxes and spheres overlap far
    // more often than they do.
    let mut rng = SmallRng::seed_from_u64(5);
    let rod = Arc::new(Shape::cuboid(Vec3::new(2.0, 0.05, 0.05)).unwrap());
    let bunny = Arc::new(Shape::from_obj(mesh("bunny"), FitOptions::default()).unwrap());
    let mut world = World::new();
    for k in 0..2000 {
        let shape = if k % 4 == 0 { bunny.clone() } else { rod.clone() };
        let mut pose = random_pose(&mut rng, 25.0);
        if k % 4 == 0 {
            pose.position *= 4.0; // bunnies are about 15 units across
        }
        world.add_body(BodyDesc::new(shape, pose)).unwrap();
    }
    let s = *world.update();
    let (c, sp, ob) = (s.candidates as f64, s.after_spheres as f64, s.after_obbs as f64);
    println!(
        "candidates {c}, spheres remove {:.1}%, OBBs remove {:.1}% of the rest, touching {}",
        100.0 * (1.0 - sp / c),
        100.0 * (1.0 - ob / sp),
        s.touching
    );
    assert!(s.after_obbs < s.after_spheres && s.after_spheres < s.candidates);
    assert!(ob < 0.8 * c, "the OBB stage should remove a good share of the candidates");
    assert_eq!(touching_of(&world), brute_force(&world));
}

/// The same events in the same order on one and two threads, through
/// frames where half the bodies fall asleep (their touching pairs among
/// themselves kept, untested) and wake again.
#[test]
fn same_events_on_one_and_two_threads() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| sleepers_scene(WorldConfig::default()))
    };
    let (one, two) = (run(1), run(2));
    assert!(one.0.len() > 1000);
    // Pairs of sleepers kept their contact while asleep.
    assert!(one.1 > 10, "{} kept pairs woke touching", one.1);
    assert_eq!(one, two);
}

/// The events of [`same_events_on_one_and_two_threads`]'s scene, a world
/// set up by `config`, where half the bodies fall asleep and wake; and how
/// many pairs of sleepers woke touching.
fn sleepers_scene(config: WorldConfig) -> (Vec<ContactEvent>, usize) {
    let (mut world, ids, mut rng) = random_world_with(3000, 6, config);
    let sleepers: Vec<BodyId> = ids
        .iter()
        .copied()
        .filter(|&id| id.index() % 2 == 0 && world.kind(id).unwrap() == BodyKind::Dynamic)
        .collect();
    let mut all = Vec::new();
    let mut persisting_on_waking = 0;
    for f in 0..7 {
        let kind = match f {
            3 => BodyKind::Sleeping,
            5 => BodyKind::Dynamic,
            _ => world.kind(sleepers[0]).unwrap(),
        };
        sleepers.iter().for_each(|&id| world.set_kind(id, kind).unwrap());
        world.update();
        all.extend_from_slice(world.events());
        if f == 5 {
            let both = |e: &ContactEvent| sleepers.contains(&e.a) && sleepers.contains(&e.b);
            persisting_on_waking = world
                .events()
                .iter()
                .filter(|e| e.kind == EventKind::Persisting && both(e))
                .count();
        }
        step(&mut world, &ids, &mut rng);
    }
    (all, persisting_on_waking)
}

/// A world's own pool of one or two threads gives the events of rayon's
/// pool, the default.
#[test]
fn own_thread_pools_give_the_default_events() {
    let default = sleepers_scene(WorldConfig::default());
    assert!(default.0.len() > 1000 && default.1 > 10);
    for threads in [1, 2] {
        assert_eq!(
            sleepers_scene(WorldConfig::default().with_threads(threads)),
            default,
            "{threads}"
        );
    }
}

#[test]
fn bad_thread_counts_are_typed_errors() {
    assert_eq!(World::new().config(), &WorldConfig::default());
    assert_eq!(WorldConfig::default().threads, None);
    let one = WorldConfig::default().with_threads(1);
    assert_eq!(World::with_config(one).unwrap().config(), &one);
    for threads in [0, WorldConfig::MAX_THREADS + 1, usize::MAX] {
        let got = World::with_config(WorldConfig::default().with_threads(threads));
        assert_eq!(got.err(), Some(WorldError::BadThreads { threads }));
    }
}

#[test]
fn bad_margins_are_typed_errors() {
    assert_eq!(WorldConfig::default().margin, 0.0);
    for margin in [0.0, 1e-6, bvol::MAX_COORDINATE] {
        let config = WorldConfig::default().with_margin(margin);
        assert_eq!(World::with_config(config).unwrap().config().margin, margin);
    }
    for margin in [-1e-6, f32::NAN, f32::INFINITY, bvol::MAX_COORDINATE * 2.0] {
        let got = World::with_config(WorldConfig::default().with_margin(margin));
        let message = got.as_ref().err().map(ToString::to_string).unwrap_or_default();
        assert!(matches!(got, Err(WorldError::BadMargin { .. })), "{margin}");
        assert!(message.contains("WorldConfig::margin"), "{message}");
    }
}

/// A reuse tolerance that is negative, not finite or above the largest is
/// a typed error naming the setting; zero (the default) and the largest
/// are taken.
#[test]
fn bad_reuse_tolerances_are_typed_errors() {
    assert_eq!(WorldConfig::default().reuse, 0.0);
    for reuse in [0.0, 4e-5, bvol::narrow::MAX_REUSE] {
        let config = WorldConfig::default().with_reuse(reuse);
        assert_eq!(World::with_config(config).unwrap().config().reuse, reuse);
    }
    for reuse in [-1e-9, f32::NAN, f32::INFINITY, bvol::narrow::MAX_REUSE * 2.0] {
        let got = World::with_config(WorldConfig::default().with_reuse(reuse));
        let message = got.as_ref().err().map(ToString::to_string).unwrap_or_default();
        assert!(matches!(got, Err(WorldError::BadReuse { .. })), "{reuse}");
        assert!(message.contains("WorldConfig::reuse"), "{message}");
    }
}

/// A world that reuses contact features, against the same world without:
/// 400 bodies of every shape kind, moved as frames move them for four
/// frames, then jittering about where they are by up to 1e-6 and 1e-6 rad
/// (a solver's pile). Every frame both give the same events (the same
/// pairs, in the same order, of the same kinds: whether a pair touches
/// never depends on reuse), and each contact's depth is within the reuse's
/// bound of the other world's, `2e-5 + 2 * 4e-5` of the pair's size
/// (taken generously as the larger bounding sphere's diameter) on top of
/// the `2e-5` either may be above the least.
#[test]
fn reused_contacts_keep_the_events_and_the_depth_bound() {
    let (mut plain, ids, mut rng) = random_world(400, 31);
    let reuse = 4e-5;
    let (mut reusing, _, _) = random_world_with(400, 31, WorldConfig::default().with_reuse(reuse));
    let mut touching = 0;
    let mut base = Vec::new();
    for frame in 0..12 {
        if frame < 4 {
            step(&mut plain, &ids, &mut rng);
            base = ids.iter().map(|&id| plain.pose(id).unwrap()).collect();
        } else {
            let jittered: Vec<Pose> = base
                .iter()
                .map(|p| {
                    let jitter = (Vec3::new(rng.random(), rng.random(), rng.random()) - 0.5) * 2e-6;
                    let axis = Vec3::new(rng.random(), rng.random(), 1.0).normalize();
                    let wobble = Quat::from_axis_angle(axis, 1e-6);
                    Pose::new(p.position + jitter, (wobble * p.rotation).normalize())
                })
                .collect();
            plain.set_poses(&ids, &jittered).unwrap();
        }
        let poses: Vec<Pose> = ids.iter().map(|&id| plain.pose(id).unwrap()).collect();
        reusing.set_poses(&ids, &poses).unwrap();
        plain.update();
        reusing.update();
        let key = |e: &ContactEvent| (e.kind, e.a, e.b);
        let (want, got) = (plain.events(), reusing.events());
        assert_eq!(
            want.iter().map(key).collect::<Vec<_>>(),
            got.iter().map(key).collect::<Vec<_>>()
        );
        for (w, g) in want.iter().zip(got) {
            let (Some(cw), Some(cg)) = (w.contact, g.contact) else { continue };
            touching += 1;
            let size = |id| 2.0 * plain.shape(id).unwrap().sphere().radius;
            let bound = (2e-5 + 2e-5 + 2.0 * reuse) * size(w.a).max(size(w.b)) + 1e-6;
            assert!((cw.depth - cg.depth).abs() <= bound, "frame {frame}: {cw:?} against {cg:?}");
        }
    }
    assert!(touching > 1000, "only {touching} contacts compared");
}

/// A pair that falls asleep touching is still listed, with the contact it
/// had when last tested, until a body moves it apart; its contact is the
/// event's, and reversing the bodies turns the normal.
#[test]
fn contacts_list_resting_pairs_with_their_last_contact() {
    let (mut world, a, b) = stacked_cubes();
    world.update();
    let began = world.events()[0].contact.unwrap();
    let listed = |w: &World| w.contacts().collect::<Vec<_>>();
    assert_eq!(listed(&world), [(a, b, began)]);
    world.set_kind(a, BodyKind::Sleeping).unwrap();
    world.set_kind(b, BodyKind::Sleeping).unwrap();
    for _ in 0..3 {
        world.update();
        assert!(world.events().is_empty());
        assert_eq!(listed(&world), [(a, b, began)], "kept asleep");
        assert_eq!(world.contact(a, b), Ok(Some(began)));
        let reversed = world.contact(b, a).unwrap().unwrap();
        assert_eq!((reversed.normal, reversed.depth), (-began.normal, began.depth));
    }
    world.set_kind(b, BodyKind::Dynamic).unwrap();
    world.set_pose(b, Pose::new(Vec3::Y * 3.0, Quat::IDENTITY)).unwrap();
    world.update();
    assert_eq!(listed(&world), []);
    assert_eq!(world.contact(b, a), Ok(None));
    world.remove_body(a).unwrap();
    assert_eq!(world.contact(a, b), Err(WorldError::UnknownBody(a)));
    assert_eq!(world.contact(b, a), Err(WorldError::UnknownBody(a)));
}

/// The nearest of `ids` that `ray` meets within `max_t`, by brute force:
/// every body's shape in its own frame (ties to the lower slot).
fn nearest(
    world: &World,
    ids: impl Iterator<Item = BodyId>,
    ray: &Ray,
    max_t: f32,
) -> Option<(f32, BodyId)> {
    ids.filter_map(|id| {
        let inv = world.pose(id).unwrap().inverse();
        let local = Ray::new(inv.transform_point(ray.origin), inv.transform_vector(ray.direction));
        Some((world.shape(id).unwrap().ray_entry(&local, max_t)?, id))
    })
    .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.index().cmp(&b.1.index())))
}

#[test]
fn ray_cast_finds_the_nearest_body() {
    let (mut world, ids, mut rng) = random_world(500, 7);
    world.update();
    let side = 500f32.cbrt() * 1.6;
    let mut hits = 0;
    for _ in 0..300 {
        let origin = Vec3::new(rng.random(), rng.random(), rng.random()) * side * 1.5 - side * 0.25;
        let to = Vec3::new(rng.random(), rng.random(), rng.random()) * side;
        let ray = Ray::new(origin, (to - origin).normalize());
        let expected = nearest(&world, ids.iter().copied(), &ray, 1e3);
        let got = world.ray_cast(&ray, 1e3);
        match (got, expected) {
            (Some(h), Some((t, id))) => {
                assert!((h.t - t).abs() <= 1e-4 * t.max(1.0), "{h:?} vs {t} {id}");
                assert_eq!(h.user_data, world.user_data(h.body).unwrap());
                hits += 1;
            }
            (None, None) => {}
            other => panic!("{other:?}"),
        }
    }
    assert!(hits > 100, "{hits}");
}

#[test]
fn bad_input_is_a_typed_error_and_changes_nothing() {
    let mut world = World::new();
    let cube = Arc::new(Shape::cuboid(Vec3::splat(0.5)).unwrap());
    let a = world.add_body(BodyDesc::new(cube.clone(), Pose::IDENTITY)).unwrap();
    let nan = Pose::new(Vec3::new(f32::NAN, 0.0, 0.0), Quat::IDENTITY);
    assert!(matches!(
        world.add_body(BodyDesc::new(cube.clone(), nan)),
        Err(WorldError::BadPose { .. })
    ));
    let zero = Pose::new(Vec3::ZERO, Quat::from_xyzw(0.0, 0.0, 0.0, 0.0));
    let b = world
        .add_body(BodyDesc::new(cube.clone(), Pose::new(Vec3::X * 0.9, Quat::IDENTITY)))
        .unwrap();
    let err = world.set_poses(&[a, b], &[Pose::IDENTITY, zero]).unwrap_err();
    assert_eq!(err, WorldError::BadPose { body: b, pose: zero });
    assert_eq!(world.pose(b).unwrap().position, Vec3::X * 0.9, "nothing moved");
    assert_eq!(
        world.set_poses(&[a], &[]).unwrap_err(),
        WorldError::LengthMismatch { bodies: 1, poses: 0 }
    );
    world.update();
    assert_eq!(touching_of(&world).len(), 1);
    world.remove_body(b).unwrap();
    assert_eq!(world.remove_body(b), Err(WorldError::UnknownBody(b)));
    assert_eq!(world.pose(b), Err(WorldError::UnknownBody(b)));
    // The slot is reused; the old handle stays dead.
    let c = world.add_body(BodyDesc::new(cube, Pose::new(Vec3::X * 5.0, Quat::IDENTITY))).unwrap();
    assert_eq!(c.index(), b.index());
    assert!(world.pose(b).is_err());
    world.update();
    let ended: Vec<_> = world.events().iter().map(|e| (e.kind, e.a, e.b)).collect();
    assert_eq!(ended, vec![(EventKind::Ended, a, b)]);
    // Shapes: degenerate parts and bad sizes. A flat part is taken (made
    // thin: the narrow crate's tests check its contacts); a line is not.
    let flat = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE.with_z(0.0)];
    assert!(Shape::convex(&flat).is_ok());
    let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
    assert!(matches!(Shape::convex(&line), Err(ShapeError::Part { .. })));
    assert!(matches!(Shape::ball(-1.0), Err(ShapeError::BadSize { .. })));
    assert!(matches!(Shape::capsule(f32::NAN, 1.0), Err(ShapeError::BadSize { .. })));
    assert!(matches!(Shape::cuboid(Vec3::ZERO), Err(ShapeError::BadSize { .. })));
}

/// Up to the limits a world takes, its pairs are the exact test's: a
/// rotation's quaternion at both ends of `ROTATION_LENGTH_SQUARED` (which
/// the f32 bounds normalise), and bodies of size 1e17 near
/// `MAX_COORDINATE`. Beyond them, poses, points and sizes are typed errors
/// and nothing changes. Before the limits, a quaternion with components of
/// 1e20 (its squared length beyond f32's range) made bounds that ignored
/// the rotation, one with components of 1e-20 bounds turned by more than
/// their rounding allowance, and a shape near f32's largest value bounds
/// that overflowed: the first and last lost pairs.
#[test]
fn coordinates_and_rotations_up_to_the_limits() {
    let long = Arc::new(Shape::cuboid(Vec3::new(2.0, 0.5, 0.5)).unwrap());
    let small = Arc::new(Shape::cuboid(Vec3::splat(0.3)).unwrap());
    // The long box turned 45 degrees about z reaches the small one; unturned
    // it does not.
    let turn = Quat::from_rotation_z(std::f32::consts::FRAC_PI_4);
    let aside = Pose::new(Vec3::new(1.2, 1.2, 0.0), Quat::IDENTITY);
    for scale in [1.01e-9f32, 1.0, 0.99e9] {
        let mut world = World::new();
        let q = Quat::from_vec4(Vec4::from(turn) * scale);
        assert!(bvol::ROTATION_LENGTH_SQUARED.contains(&q.length_squared()), "{scale}");
        let a = world.add_body(BodyDesc::new(long.clone(), Pose::new(Vec3::ZERO, q))).unwrap();
        let b = world.add_body(BodyDesc::new(small.clone(), aside)).unwrap();
        world.update();
        assert!(touch(&world, a, b), "{scale}: the exact test");
        assert_eq!(touching_of(&world), BTreeSet::from([(a.index(), b.index())]), "{scale}");
    }
    let huge = Arc::new(Shape::cuboid(Vec3::splat(1e17)).unwrap());
    for x in [-9e17f32, 8e17] {
        let mut world = World::new();
        let at = |x: f32| Pose::new(Vec3::new(x, 0.0, 1e18), turn);
        let a = world.add_body(BodyDesc::new(huge.clone(), at(x))).unwrap();
        let b = world.add_body(BodyDesc::new(huge.clone(), at(x + 1.9e17))).unwrap();
        world.update();
        assert!(touch(&world, a, b), "{x}: the exact test");
        assert_eq!(touching_of(&world), BTreeSet::from([(a.index(), b.index())]), "{x}");
    }
    // Beyond: typed errors, and nothing moves.
    let mut world = World::new();
    let a = world.add_body(BodyDesc::new(small.clone(), aside)).unwrap();
    let far = Pose::new(Vec3::new(0.0, 2e18, 0.0), Quat::IDENTITY);
    let long_q = Pose::new(Vec3::ZERO, Quat::from_vec4(Vec4::from(turn) * 1e10));
    let short_q = Pose::new(Vec3::ZERO, Quat::from_vec4(Vec4::from(turn) * 1e-10));
    for pose in [far, long_q, short_q] {
        assert_eq!(world.set_pose(a, pose), Err(WorldError::BadPose { body: a, pose }));
        let added = world.add_body(BodyDesc::new(small.clone(), pose));
        assert!(matches!(added, Err(WorldError::BadPose { .. })), "{pose:?}");
        assert_eq!(world.pose(a).unwrap(), aside);
    }
    assert_eq!(world.len(), 1);
    let points = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.0, 0.0, -2e18)];
    let err = Shape::convex(&points).unwrap_err();
    assert_eq!(err, ShapeError::OutOfRange { part: "points".into(), point: 3 });
    assert!(err.to_string().contains("point 3"), "{err}");
    assert!(matches!(Shape::cuboid(Vec3::splat(2e18)), Err(ShapeError::BadSize { .. })));
    assert!(matches!(Shape::ball(2e18), Err(ShapeError::BadSize { .. })));
    assert!(matches!(Shape::capsule(1.0, 2e18), Err(ShapeError::BadSize { .. })));
    assert!(matches!(Shape::tetrahedron(2e18), Err(ShapeError::BadSize { .. })));
}

/// A body moved and then removed before the next update leaves nothing
/// behind: no tree leaf, no candidate pair, only its contact's end; and a
/// body added into its slot in the same frame takes its place.
#[test]
fn bodies_moved_then_removed_leave_no_leaf() {
    let mut world = World::new();
    let cube = Arc::new(Shape::cuboid(Vec3::splat(0.5)).unwrap());
    let at = |x: f32| Pose::new(Vec3::X * x, Quat::IDENTITY);
    let a = world.add_body(BodyDesc::new(cube.clone(), at(0.0))).unwrap();
    let b = world.add_body(BodyDesc::new(cube.clone(), at(0.9))).unwrap();
    world.update();
    assert_eq!(touching_of(&world), BTreeSet::from([(a.index(), b.index())]));
    world.set_poses(&[a, b], &[at(0.1), at(0.8)]).unwrap();
    world.remove_body(b).unwrap();
    assert_eq!(world.update().candidates, 0, "the removed body left a leaf");
    let ended: Vec<_> = world.events().iter().map(|e| (e.kind, e.a, e.b)).collect();
    assert_eq!(ended, vec![(EventKind::Ended, a, b)]);
    // Moved, removed, and its slot taken again before the update.
    world.set_pose(a, at(0.2)).unwrap();
    let c = world.add_body(BodyDesc::new(cube.clone(), at(5.0))).unwrap();
    world.set_pose(c, at(5.5)).unwrap();
    world.remove_body(c).unwrap();
    let d = world.add_body(BodyDesc::new(cube, at(1.0))).unwrap();
    assert_eq!(d.index(), b.index());
    assert_eq!(world.update().candidates, 1);
    assert_eq!(touching_of(&world), BTreeSet::from([(a.index(), d.index())]));
}

#[test]
fn obj_files_load_or_give_typed_errors_naming_the_file() {
    for name in ["teapot", "airplane", "bunny", "wuson", "duck"] {
        let shape = Shape::from_obj(mesh(name), FitOptions::default()).unwrap();
        assert!(!shape.parts().is_empty(), "{name}");
    }
    let dir = std::env::temp_dir().join(format!("bvol-world-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let cases = [
        (dir.join("missing.obj"), "read"),
        (file("broken.obj", "v 1 2\nf 1 2 3\n"), "parse"),
        (file("empty.obj", "o nothing\n"), "empty"),
        (file("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n"), "nan"),
        (file("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), "index"),
    ];
    for (path, what) in cases {
        match Shape::from_obj(&path, FitOptions::default()) {
            Err(ShapeError::Mesh(e)) => {
                assert_eq!(e.path, path, "{what}");
                assert!(e.to_string().contains(path.to_str().unwrap()), "{what}: {e}");
                if what == "nan" {
                    assert!(matches!(e.problem, MeshProblem::NonFinite { .. }));
                }
            }
            other => panic!("{what}: {other:?}"),
        }
    }
    let err = Shape::from_obj_object(mesh("bunny"), "no such", FitOptions::default()).unwrap_err();
    assert!(matches!(err, ShapeError::NoSuchObject { .. }), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Found by the obj fuzz target under libFuzzer: a face whose texture or
/// normal index is far out of range (`-3` with one `vt`) overflowed tobj's
/// bounds check (`vt * 2 + 1`) and panicked in a debug build. Texture
/// coordinates and normals are not read, so the triangle loads as if they
/// were not there.
#[test]
fn far_texture_and_normal_indices_are_not_read() {
    let dir = std::env::temp_dir().join(format!("bvol-far-index-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    for (name, rest) in [
        ("texcoord.obj", "vt 0 0\nf 1/-3 2/1 3/1\n"),
        ("normal.obj", "vn 0 0 1\nf 1//-3 2//1 3//1\n"),
        ("both.obj", "vt 0 0\nvn 0 0 1\nf 1/-3/-3 2/1/1 3/1/1\n"),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, format!("{triangle}{rest}")).unwrap();
        let meshes = bvol::load_obj(&path).unwrap();
        assert_eq!(meshes.len(), 1, "{name}");
        assert_eq!(meshes[0].positions, [Vec3::ZERO, Vec3::X, Vec3::Y], "{name}");
        assert_eq!(meshes[0].triangles, [[0, 1, 2]], "{name}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Two unit cubes, dynamic, the second 0.99 above the first: they overlap.
fn stacked_cubes() -> (World, BodyId, BodyId) {
    let mut world = World::new();
    let cube = Arc::new(Shape::cuboid(Vec3::splat(0.5)).unwrap());
    let a = world.add_body(BodyDesc::new(cube.clone(), Pose::IDENTITY)).unwrap();
    let b = world.add_body(BodyDesc::new(cube, Pose::new(Vec3::Y * 0.99, Quat::IDENTITY))).unwrap();
    (world, a, b)
}

#[test]
fn resting_pairs_keep_their_contact_until_they_move() {
    let (mut world, a, b) = stacked_cubes();
    let kinds = |w: &World| w.events().iter().map(|e| e.kind).collect::<Vec<_>>();
    world.update();
    assert_eq!(kinds(&world), [EventKind::Began]);
    world.set_kind(a, BodyKind::Sleeping).unwrap();
    world.set_kind(b, BodyKind::Sleeping).unwrap();
    world.update();
    assert_eq!(kinds(&world), [], "asleep: no test, no event");
    world.set_kind(b, BodyKind::Dynamic).unwrap();
    world.update();
    assert_eq!(kinds(&world), [EventKind::Persisting]);
    world.set_pose(b, Pose::new(Vec3::Y * 3.0, Quat::IDENTITY)).unwrap();
    world.update();
    assert_eq!(kinds(&world), [EventKind::Ended]);
}

#[test]
fn layers_and_masks_filter_pairs_both_ways() {
    // Three overlapping cubes: 0 on layer 1, 1 on layer 2 ignoring layer 1,
    // 2 on layer 4 colliding with everything.
    let mut world = World::new();
    let cube = || Arc::new(Shape::cuboid(Vec3::splat(0.5)).unwrap());
    let at = |x: f32| Pose::new(Vec3::X * x, Quat::IDENTITY);
    let pairs = |world: &World| -> BTreeSet<(BodyId, BodyId)> {
        let touching = world.events().iter().filter(|e| e.kind != EventKind::Ended);
        touching.map(|e| (e.a, e.b)).collect()
    };
    let a = world.add_body(BodyDesc::new(cube(), at(0.0)).with_filter(1, u32::MAX)).unwrap();
    let b = world.add_body(BodyDesc::new(cube(), at(0.3)).with_filter(2, !1)).unwrap();
    let c = world.add_body(BodyDesc::new(cube(), at(0.6)).with_filter(4, u32::MAX)).unwrap();
    world.update();
    // a-b: b's mask excludes a's layer; a-c and b-c collide.
    assert_eq!(pairs(&world), BTreeSet::from([(a, c), (b, c)]));
    assert_eq!(world.stats().candidates, 2, "filtered before the stages");
    // A body with a layer and colliding with all (c) filters nothing; with
    // the filtering one gone the others meet, and with a new one that
    // collides with nothing, they are turned away again.
    world.remove_body(c).unwrap();
    world.remove_body(b).unwrap();
    let d = world.add_body(BodyDesc::new(cube(), at(0.3))).unwrap();
    world.update();
    assert_eq!(pairs(&world), BTreeSet::from([(a, d)]));
    let e = world.add_body(BodyDesc::new(cube(), at(0.2)).with_filter(1, 0)).unwrap();
    world.update();
    assert_eq!(pairs(&world), BTreeSet::from([(a, d)]), "{e:?} collides with nothing");
    world.remove_body(e).unwrap();
    world.remove_body(a).unwrap();
    world.update();
    assert_eq!(world.stats().candidates, 0);
}

#[test]
fn ball_bounds_hold_the_ball_by_every_method() {
    let ball = Shape::ball(0.75).unwrap();
    let (mut rng, r) = (SmallRng::seed_from_u64(8), 0.75f32);
    let methods = [
        FitOptions::default(),
        FitOptions {
            sphere: bvol::volumes::SphereMethod::Ritter,
            obb: bvol::volumes::ObbMethod::PcaPoints,
        },
    ];
    for fit in methods {
        let shape = ball.with_fit(fit).unwrap();
        assert_eq!(shape.sphere().radius, r, "a lone ball's sphere is the ball");
        for _ in 0..2000 {
            let d = Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - 1.0;
            let p = d.normalize_or_zero() * r;
            assert!(shape.obb().contains_point(p), "{fit:?}: {p} outside {:?}", shape.obb());
        }
    }
}

/// One step of the model test below.
#[derive(Clone, Debug)]
enum Op {
    /// A body of `shapes()[shape]` (modulo their number) at a pose in the
    /// small cube, of kind `kind` (dynamic, static, sleeping) with filter
    /// number `filter`.
    Add { shape: usize, pose: Pose, kind: usize, filter: usize },
    /// Removes the live body `k` (modulo their number).
    Remove(usize),
    /// Sets live body `k`'s kind.
    SetKind(usize, usize),
    /// Moves live body `k` (whatever its kind).
    Move(usize, Pose),
    /// Moves every live body by a small step, in one `set_poses`.
    Nudge(Vec3),
    /// Puts every live body to sleep, as a pile that comes to rest does:
    /// the pairs touching then are kept untested.
    Sleep,
    /// Runs a frame and checks it, and a ray cast from `from` towards `to`.
    Update { from: Vec3, to: Vec3 },
    /// Saves the world as JSON and goes on with the world loaded from it
    /// (with the `serde` feature; without it, nothing).
    Reload,
}

const KINDS: [BodyKind; 3] = [BodyKind::Dynamic, BodyKind::Static, BodyKind::Sleeping];
/// (layers, mask): the default, a second layer ignoring the first, one that
/// collides with nothing, one on two layers.
const FILTERS: [(u32, u32); 4] = [(1, u32::MAX), (2, !1), (1, 0), (3, u32::MAX)];

fn any_pose() -> impl Strategy<Value = Pose> {
    (prop::array::uniform3(0.0f32..2.5), prop::array::uniform4(-1.0f32..1.0)).prop_map(|(p, q)| {
        let q = Quat::from_array(q);
        let q = if q.length() > 0.1 { q.normalize() } else { Quat::IDENTITY };
        Pose::new(Vec3::from_array(p), q)
    })
}

fn any_op() -> impl Strategy<Value = Op> {
    prop_oneof![
        4 => (any::<usize>(), any_pose(), 0..3usize, 0..4usize)
            .prop_map(|(shape, pose, kind, filter)| Op::Add { shape, pose, kind, filter }),
        1 => any::<usize>().prop_map(Op::Remove),
        1 => (any::<usize>(), 0..3usize).prop_map(|(k, kind)| Op::SetKind(k, kind)),
        2 => (any::<usize>(), any_pose()).prop_map(|(k, pose)| Op::Move(k, pose)),
        1 => prop::array::uniform3(-0.3f32..0.3).prop_map(|d| Op::Nudge(Vec3::from_array(d))),
        1 => Just(Op::Sleep),
        1 => Just(Op::Reload),
        3 => (prop::array::uniform3(-1.0f32..3.5), prop::array::uniform3(0.0f32..2.5))
            .prop_map(|(from, to)| Op::Update { from: from.into(), to: to.into() }),
    ]
}

/// What the world should report and keep, tracked beside it: the live
/// bodies with their filters, the pairs touching at the last update (kept
/// while neither body is dynamic, as the world keeps them), and the bodies
/// removed since.
#[derive(Default)]
struct Model {
    live: Vec<(BodyId, (u32, u32))>,
    touching: BTreeSet<(BodyId, BodyId)>,
    removed: Vec<BodyId>,
    /// Whether a position that is not an f32's was given: the world then
    /// tests pairs on relative positions.
    far: bool,
}

impl Model {
    /// The events the world's update should have given, as sorted keys.
    fn expected(&mut self, world: &World) -> BTreeSet<(BodyId, BodyId, u8)> {
        let mut events = BTreeSet::new();
        for &(a, b) in &self.touching {
            if self.removed.contains(&a) || self.removed.contains(&b) {
                events.insert((a, b, 2));
            }
        }
        let mut now = BTreeSet::new();
        for (i, &(x, (lx, mx))) in self.live.iter().enumerate() {
            for &(y, (ly, my)) in &self.live[i + 1..] {
                let (a, b) = if x.index() < y.index() { (x, y) } else { (y, x) };
                let was = self.touching.contains(&(a, b));
                let resting = |id| world.kind(id).unwrap() != BodyKind::Dynamic;
                if lx & my == 0 || ly & mx == 0 {
                    continue;
                }
                if resting(a) && resting(b) {
                    // Neither moves: not tested, no event, kept as it was.
                    if was {
                        now.insert((a, b));
                    }
                    continue;
                }
                let touches = touch_at(world, a, b, self.far);
                match (was, touches) {
                    (false, true) => events.insert((a, b, 0)),
                    (true, true) => events.insert((a, b, 1)),
                    (true, false) => events.insert((a, b, 2)),
                    (false, false) => false,
                };
                if touches {
                    now.insert((a, b));
                }
            }
        }
        self.touching = now;
        self.removed.clear();
        events
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Random sequences of adds (every shape, kind and filter), removals,
    /// kind changes, single moves and moves of all at once, and saving and
    /// loading the world (with the `serde` feature), on a world
    /// small and dense enough that most bodies touch, scaled to sizes of
    /// 1e-3, 1 and 1e3 and placed at the origin, 1e4 from it (where f32
    /// steps, about 1e-3, are coarser than the shapes of size 1e-3) or 1e8
    /// by f64 positions (`set_poses_f64`, the model then testing pairs on
    /// relative positions as the world does, and no rays), with
    /// no margin or one of 5% of the size: after every update the events
    /// are exactly those of an all-pairs hull test (within the margin)
    /// against the pairs touching at the update before (resting pairs kept
    /// untested, removed bodies' pairs ended, reused slots told apart by
    /// their handles), in slot order, with a contact on each but the ended;
    /// `contacts()` and `contact(a, b)` agree with the model and the events
    /// (see `check_contacts`); and a ray cast finds the nearest body that
    /// every shape tested finds.
    #[test]
    fn events_match_an_all_pairs_model_through_any_edits(
        ops in prop::collection::vec(any_op(), 1..40),
        size in prop::sample::select(vec![1e-3f32, 1.0, 1e3]),
        far in prop::sample::select(vec![0.0f32, 1e4, 1e8]),
        margin in prop::sample::select(vec![0.0f32, 0.05]),
    ) {
        // The whole world scaled by `size`, and moved `far` from the origin:
        // at 1e8 by f64 positions.
        let shapes = shapes_of_size(size);
        let f64_poses = far >= 1e8;
        let at = |p: Vec3| p * size + Vec3::splat(far);
        let place = |p: Pose| Pose::new(at(p.position), p.rotation);
        let at_f64 = |p: DVec3| p * f64::from(size) + DVec3::splat(f64::from(far));
        // Moves bodies, by f64 positions at 1e8, telling the model when one
        // is not an f32's.
        let moves = |world: &mut World, model: &mut Model, ids: &[BodyId], poses: &[DPose]| {
            if f64_poses {
                model.far |= poses.iter().any(|p| p.to_pose().position.as_dvec3() != p.position);
                world.set_poses_f64(ids, poses).unwrap();
            } else {
                let poses: Vec<Pose> = poses.iter().map(|p| p.to_pose()).collect();
                world.set_poses(ids, &poses).unwrap();
            }
        };
        let placed = |p: Pose| DPose::new(at_f64(p.position.as_dvec3()), p.rotation);
        let mut world = World::with_config(WorldConfig::default().with_margin(margin * size)).unwrap();
        let mut model = Model::default();
        // Each body's user data, distinct, kept after it is removed.
        let mut users = BTreeMap::new();
        for op in ops {
            let pick = |k: usize, model: &Model| model.live[k % model.live.len()].0;
            match op {
                Op::Add { shape, pose, kind, filter } => {
                    let (layers, mask) = FILTERS[filter];
                    let desc = BodyDesc::new(shapes[shape % shapes.len()].clone(), place(pose));
                    let data = 1_000_003 * users.len() as u64 + 17;
                    let desc = desc.with_kind(KINDS[kind]).with_filter(layers, mask);
                    let id = world.add_body(desc.with_user_data(data)).unwrap();
                    moves(&mut world, &mut model, &[id], &[placed(pose)]);
                    model.live.push((id, (layers, mask)));
                    users.insert(id, data);
                }
                Op::Remove(k) if !model.live.is_empty() => {
                    let id = pick(k, &model);
                    world.remove_body(id).unwrap();
                    model.live.retain(|&(x, _)| x != id);
                    model.removed.push(id);
                    prop_assert!(world.contacts().all(|(a, b, _)| a != id && b != id));
                    let other = model.live.first().map_or(id, |&(x, _)| x);
                    prop_assert_eq!(world.contact(other, id), Err(WorldError::UnknownBody(id)));
                }
                Op::SetKind(k, kind) if !model.live.is_empty() => {
                    world.set_kind(pick(k, &model), KINDS[kind]).unwrap();
                }
                Op::Move(k, pose) if !model.live.is_empty() => {
                    let id = pick(k, &model);
                    moves(&mut world, &mut model, &[id], &[placed(pose)]);
                }
                Op::Nudge(d) => {
                    let ids: Vec<BodyId> = model.live.iter().map(|&(id, _)| id).collect();
                    let step = (d * size).as_dvec3();
                    let poses: Vec<DPose> = ids
                        .iter()
                        .map(|&id| {
                            let p = world.pose_f64(id).unwrap();
                            DPose::new(p.position + step, p.rotation)
                        })
                        .collect();
                    moves(&mut world, &mut model, &ids, &poses);
                }
                Op::Sleep => {
                    for &(id, _) in &model.live {
                        world.set_kind(id, BodyKind::Sleeping).unwrap();
                    }
                }
                Op::Reload => {
                    #[cfg(feature = "serde")]
                    {
                        let text = serde_json::to_string(&world.snapshot()).unwrap();
                        world = World::from_snapshot(&serde_json::from_str(&text).unwrap()).unwrap();
                    }
                }
                Op::Update { from, to } => {
                    world.update();
                    let kind = |k: EventKind| match k {
                        EventKind::Began => 0,
                        EventKind::Persisting => 1,
                        EventKind::Ended => 2,
                    };
                    let got: Vec<(BodyId, BodyId, u8)> =
                        world.events().iter().map(|e| (e.a, e.b, kind(e.kind))).collect();
                    prop_assert!(
                        got.windows(2).all(|w| (w[0].0.index(), w[0].1.index())
                            <= (w[1].0.index(), w[1].1.index())),
                        "events out of slot order: {got:?}"
                    );
                    prop_assert!(world.events().iter().all(|e| e.a.index() < e.b.index()
                        && e.contact.is_some() == (e.kind != EventKind::Ended)));
                    let set: BTreeSet<_> = got.iter().copied().collect();
                    prop_assert_eq!(set.len(), got.len(), "an event twice");
                    prop_assert_eq!(set, model.expected(&world));
                    check_contacts(&world, &model, &users)?;
                    let (from, to) = (at(from), at(to));
                    // Rays are f32: at 1e8 their steps are coarser than the bodies.
                    let ray = (to - from).try_normalize().filter(|_| !f64_poses);
                    if let Some(ray) = ray.map(|d| Ray::new(from, d)) {
                        let ids = model.live.iter().map(|&(id, _)| id);
                        let want = nearest(&world, ids, &ray, 10.0 * size).map(|(t, _)| t);
                        let got = world.ray_cast(&ray, 10.0 * size).map(|h| h.t);
                        prop_assert_eq!(got.is_some(), want.is_some(), "{:?} vs {:?}", got, want);
                        if let (Some(t), Some(want)) = (got, want) {
                            let tolerance = 1e-4 * want.max(size);
                            prop_assert!((t - want).abs() <= tolerance, "{t} vs {want}");
                        }
                    }
                }
                _ => {}
            }
        }
    }
}

/// After an update: `contacts()` lists, in slot order, exactly the pairs
/// the model says touch; `contact(a, b)` is the event's contact for each
/// pair tested (its normal turned when asked the other way round) and
/// `Some` for exactly the model's touching pairs; each event carries the
/// user data its bodies were given (the removed ones' included).
fn check_contacts(
    world: &World,
    model: &Model,
    users: &BTreeMap<BodyId, u64>,
) -> Result<(), TestCaseError> {
    let listed: Vec<(BodyId, BodyId, Contact)> = world.contacts().collect();
    let key = |(a, b, _): &(BodyId, BodyId, Contact)| (a.index(), b.index());
    prop_assert!(listed.windows(2).all(|w| key(&w[0]) < key(&w[1])), "out of order: {listed:?}");
    let pairs: BTreeSet<(BodyId, BodyId)> = listed.iter().map(|&(a, b, _)| (a, b)).collect();
    prop_assert_eq!(&pairs, &model.touching);
    for &(a, b, c) in &listed {
        prop_assert_eq!(world.contact(a, b), Ok(Some(c)));
    }
    for e in world.events() {
        prop_assert_eq!((e.user_data_a, e.user_data_b), (users[&e.a], users[&e.b]));
        if let Some(c) = e.contact {
            prop_assert_eq!(world.contact(e.a, e.b), Ok(Some(c)));
            let r = world.contact(e.b, e.a).unwrap().unwrap();
            prop_assert_eq!((r.normal, r.depth, r.points()), (-c.normal, c.depth, c.points()));
        }
    }
    for (i, &(x, _)) in model.live.iter().enumerate() {
        prop_assert_eq!(world.user_data(x), Ok(users[&x]));
        for &(y, _) in &model.live[i + 1..] {
            let pair = if x.index() < y.index() { (x, y) } else { (y, x) };
            let touching = model.touching.contains(&pair);
            prop_assert_eq!(world.contact(x, y).unwrap().is_some(), touching);
            prop_assert_eq!(world.contact(y, x).unwrap().is_some(), touching);
        }
    }
    Ok(())
}

/// Applies one edit to `world`, whose live bodies are `live`, and returns
/// the body it removed. `Update` is the caller's.
fn apply<B: Broadphase>(
    op: &Op,
    world: &mut World<B>,
    live: &mut Vec<BodyId>,
    shapes: &[Arc<Shape>],
) -> Option<BodyId> {
    let pick = |k: usize, live: &[BodyId]| live[k % live.len()];
    match *op {
        Op::Add { shape, pose, kind, filter } => {
            let (layers, mask) = FILTERS[filter];
            let desc = BodyDesc::new(shapes[shape % shapes.len()].clone(), pose);
            let id = world.add_body(desc.with_kind(KINDS[kind]).with_filter(layers, mask));
            live.push(id.unwrap());
        }
        Op::Remove(k) if !live.is_empty() => {
            let id = pick(k, live);
            world.remove_body(id).unwrap();
            live.retain(|&x| x != id);
            return Some(id);
        }
        Op::SetKind(k, kind) if !live.is_empty() => {
            world.set_kind(pick(k, live), KINDS[kind]).unwrap();
        }
        Op::Move(k, pose) if !live.is_empty() => world.set_pose(pick(k, live), pose).unwrap(),
        Op::Nudge(d) => {
            let poses: Vec<Pose> = live
                .iter()
                .map(|&id| world.pose(id).unwrap())
                .map(|p| Pose::new(p.position + d, p.rotation))
                .collect();
            world.set_poses(live, &poses).unwrap();
        }
        Op::Sleep => live.iter().for_each(|&id| world.set_kind(id, BodyKind::Sleeping).unwrap()),
        _ => {}
    }
    None
}

/// Every body whose box meets `region`, by the world's query, sorted.
fn queried<B: Broadphase>(world: &World<B>, region: &Aabb) -> Vec<BodyId> {
    let mut found = Vec::new();
    world.query(region, |id| found.push(id));
    found.sort();
    found
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// The dynamic tree and the brute-force broadphase, each in a world
    /// given the same random edits (adds of every shape, kind and filter,
    /// removals, kind changes, moves): after every update the two give the
    /// same events (kinds, bodies, contacts, order), the same counts at
    /// every stage, the same nearest ray hit, and the same bodies in a
    /// region.
    #[test]
    fn tree_and_brute_force_worlds_agree_through_any_edits(
        ops in prop::collection::vec(any_op(), 1..48),
    ) {
        let shapes = shapes();
        let mut tree = World::new();
        let mut brute = World::<BruteForce>::default();
        let (mut in_tree, mut in_brute) = (Vec::new(), Vec::new());
        for op in &ops {
            let removed = apply(op, &mut tree, &mut in_tree, &shapes);
            prop_assert_eq!(removed, apply(op, &mut brute, &mut in_brute, &shapes));
            prop_assert_eq!(&in_tree, &in_brute);
            let &Op::Update { from, to } = op else { continue };
            let (a, b) = (*tree.update(), *brute.update());
            let counts = |s: &bvol::FrameStats| {
                (s.moved, s.candidates, s.after_spheres, s.after_obbs, s.touching)
            };
            prop_assert_eq!(counts(&a), counts(&b));
            prop_assert_eq!(tree.events(), brute.events());
            if let Some(ray) = (to - from).try_normalize().map(|d| Ray::new(from, d)) {
                prop_assert_eq!(tree.ray_cast(&ray, 10.0), brute.ray_cast(&ray, 10.0));
            }
            let region = Aabb::new(from.min(to), from.max(to));
            prop_assert_eq!(queried(&tree, &region), queried(&brute, &region));
        }
    }
}
