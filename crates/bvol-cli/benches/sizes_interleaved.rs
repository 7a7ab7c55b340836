//! A world against one ten times larger, block by block: the frames of a
//! scene of N boxes and of the same scene of 10 N go to bvol on one thread
//! in blocks in turn, as `interleaved` hands frames to several methods, so
//! that a drift in the machine's speed, which on a shared host moves
//! timings by half over minutes, falls on both sizes alike; and prints
//! each size's median and mean frame and the ratio of the larger's to the
//! smaller's. Taken from two runs apart instead, the ratio moved with the
//! host's minute: the flat scene's read 5.5x in one pair of runs and 8.7x
//! in the next. Each scene's pair sets are checked against brute force and
//! the peers on a smaller world first.
//!
//! `cargo bench -p bvol-cli --bench sizes_interleaved [-- SCENE...]`; N
//! from `BVOL_BENCH_N` (default 100 000), frames timed from
//! `BVOL_BENCH_FRAMES` (default 30, after 3 untimed); scenes by default
//! `uniform` and `flat`.

mod broadphases;
#[allow(
    dead_code,
    reason = "shared with the benchmarks that hand one scene's frames to several methods, which use the rest"
)]
mod interleave;

use std::hint::black_box;
use std::time::Instant;

use broadphases::{Broadphase, BvolTree, check_agreement};
use bvol_cli::scenes::{Scene, SceneKind};
use interleave::{BLOCK, WARM, env, median, scenes};

/// How much larger the second world is.
const SCALE: usize = 10;

fn main() {
    let n = env("BVOL_BENCH_N", 100_000);
    let frames = env("BVOL_BENCH_FRAMES", 30);
    println!("scene\tn\tframes\tmedian_ms\tmean_ms\tmedian_ratio\tmean_ratio");
    for kind in scenes(&[SceneKind::Uniform, SceneKind::Flat]) {
        check_agreement(kind, n.min(20_000));
        let sizes = [n, SCALE * n];
        let timed = sized(kind, sizes, frames);
        let mean = |ms: &[f64]| ms.iter().sum::<f64>() / ms.len() as f64;
        for (size, ms) in sizes.iter().zip(&timed) {
            println!(
                "{kind}\t{size}\t{frames}\t{:.3}\t{:.3}\t{:.2}\t{:.2}",
                median(ms),
                mean(ms),
                median(ms) / median(&timed[0]),
                mean(ms) / mean(&timed[0]),
            );
        }
    }
}

/// Each size's timed frames of `kind`, in ms: after [`WARM`] untimed
/// frames, blocks of [`BLOCK`] frames to each size in turn (the first of
/// them rotating from block to block), each block's first frame untimed.
/// A scene steps before each of its frames, outside the timing: the
/// larger world's frames, made beforehand, would take gigabytes.
fn sized(kind: SceneKind, sizes: [usize; 2], frames: usize) -> [Vec<f64>; 2] {
    let mut worlds = sizes.map(|n| (Scene::new(kind, n, 1), BvolTree::new(true, 1)));
    for (scene, tree) in &mut worlds {
        for _ in 0..=WARM {
            tree.frame(scene.step());
        }
    }
    let mut ms = [Vec::with_capacity(frames), Vec::with_capacity(frames)];
    for b in 0..frames.div_ceil(BLOCK - 1) {
        for r in 0..2 {
            let i = (r + b) % 2;
            let (scene, tree) = &mut worlds[i];
            for f in 0..BLOCK {
                let boxes = scene.step();
                let started = Instant::now();
                black_box(tree.frame(black_box(boxes)));
                let elapsed = started.elapsed().as_secs_f64() * 1e3;
                if f > 0 && ms[i].len() < frames {
                    ms[i].push(elapsed);
                }
            }
        }
    }
    ms
}
