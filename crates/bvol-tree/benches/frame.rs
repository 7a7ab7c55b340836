//! One broadphase frame on 100 000 moving boxes, as a benchmark would run it:
//! every box handed over, `Tree::update`, then every overlapping pair (alone,
//! or through a `PairSet` with began / ended events), on 1 and 2 threads.
//! Also a batch build, and the update paths at a small fraction moved.
//!
//! `cargo bench -p bvol-tree --bench frame`. Scenes: boxes of sides 1 to 2.2
//! in a cube of side 2.5 n^(1/3) (about one overlapping pair per box), each
//! moving 0.1 per frame and bouncing off the walls; "teleport" also sends 1%
//! of the boxes anywhere each frame; "rest" moves only 0.1% of them.

use std::hint::black_box;
use std::time::Duration;

use bvol_tree::{Config, PairSet, Tree};
use bvol_volumes::Aabb;
use criterion::{Bencher, BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::Vec3;
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

const N: usize = 100_000;
/// Frames recorded per scene, replayed forwards then backwards so that the
/// motion stays continuous however many iterations criterion runs.
const FRAMES: usize = 24;

/// `FRAMES` frames of `N` boxes: all move, `moving` of them per frame move
/// (fraction), `teleport` of them jump anywhere.
fn scene(moving: f32, teleport: f32) -> Vec<Vec<Aabb>> {
    let mut rng = SmallRng::seed_from_u64(1);
    let world = (N as f32).cbrt() * 2.5;
    let place = |rng: &mut SmallRng| Vec3::new(rng.random(), rng.random(), rng.random()) * world;
    let mut pos: Vec<Vec3> = (0..N).map(|_| place(&mut rng)).collect();
    let half: Vec<Vec3> = (0..N)
        .map(|_| Vec3::splat(0.5) + Vec3::new(rng.random(), rng.random(), rng.random()) * 0.6)
        .collect();
    let mut vel: Vec<Vec3> = (0..N)
        .map(|_| (Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - 1.0) * 0.1)
        .collect();
    let mut frames = Vec::with_capacity(FRAMES);
    for _ in 0..FRAMES {
        for i in 0..N {
            let roll: f32 = rng.random();
            if roll < teleport {
                pos[i] = place(&mut rng);
            } else if roll < teleport + moving {
                pos[i] += vel[i];
                for a in 0..3 {
                    if !(0.0..=world).contains(&pos[i][a]) {
                        vel[i][a] = -vel[i][a];
                        pos[i][a] = pos[i][a].clamp(0.0, world);
                    }
                }
            }
        }
        frames.push(pos.iter().zip(&half).map(|(p, h)| Aabb::new(*p - *h, *p + *h)).collect());
    }
    frames
}

/// Frame indices 0, 1, ..., F-1, F-2, ..., 1, 0, 1, ...
fn replay(k: usize) -> usize {
    let period = 2 * (FRAMES - 1);
    let k = k % period;
    if k < FRAMES { k } else { period - k }
}

/// Each iteration: the next frame's update, then the pair set's.
fn with_pair_set(b: &mut Bencher, mut tree: Tree<Aabb>, frames: &[Vec<Aabb>]) {
    let mut set = PairSet::new();
    let mut k = 0;
    b.iter(|| {
        k += 1;
        tree.update(&frames[replay(k)]).unwrap();
        set.update(&mut tree);
        black_box(set.pairs().len())
    })
}

fn frames(c: &mut Criterion) {
    let scenes =
        [("uniform", scene(1.0, 0.0)), ("teleport", scene(1.0, 0.01)), ("rest", scene(0.001, 0.0))];
    for (name, frames) in &scenes {
        let mut group = c.benchmark_group(format!("frame/{name}"));
        group.sample_size(20).warm_up_time(Duration::from_secs(1));
        group.measurement_time(Duration::from_secs(4));
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            group.bench_function(BenchmarkId::new("update+pairs", threads), |b| {
                pool.install(|| {
                    let mut tree = Tree::from_bounds(&frames[0]).unwrap();
                    let mut out = Vec::new();
                    let mut k = 0;
                    b.iter(|| {
                        k += 1;
                        tree.update(&frames[replay(k)]).unwrap();
                        tree.pairs_into(&mut out);
                        black_box(out.len())
                    })
                })
            });
            group.bench_function(BenchmarkId::new("update+pair_set", threads), |b| {
                pool.install(|| with_pair_set(b, Tree::from_bounds(&frames[0]).unwrap(), frames))
            });
        }
        group.finish();
    }
}

/// The batch build of a level load, and the two update paths forced.
fn paths(c: &mut Criterion) {
    let uniform = scene(1.0, 0.0);
    let mut group = c.benchmark_group("build");
    group.sample_size(10);
    group.bench_function("from_bounds", |b| {
        b.iter(|| Tree::from_bounds(black_box(&uniform[0])).unwrap())
    });
    group.finish();
    let mut group = c.benchmark_group("update_path");
    group.sample_size(20).measurement_time(Duration::from_secs(3));
    for moving in [0.0003, 0.001, 0.01, 0.1] {
        let frames = scene(moving, 0.0);
        for (path, refit_fraction) in [("refit", 0.0), ("per_leaf", 2.0)] {
            let config = Config { refit_fraction, ..Config::default() };
            group.bench_function(BenchmarkId::new(path, moving), |b| {
                let leaves = frames[0].iter().enumerate().map(|(i, b)| (i as u32, *b));
                with_pair_set(b, Tree::build(config, leaves).unwrap(), &frames)
            });
        }
    }
    group.finish();
}

criterion_group!(benches, frames, paths);
criterion_main!(benches);
