//! One thread against several, frame by frame: each frame of a scene goes
//! to bvol on a one-thread pool and on a pool of `BVOL_BENCH_THREADS` in
//! turn (the order alternating from frame to frame), as a user's frame runs
//! (the tree's update, then its pairs brought up to date in a `PairCache`),
//! so that a drift in the machine's speed falls on both alike; and prints
//! each one's median and mean frame, the speedup of the median, and the
//! median of the frames' own speedups (each frame's one-thread time over its
//! time on the pool, taken a moment apart: a slow minute of the host slows
//! both). The pair sets are checked equal in every frame, and against brute
//! force and the peers on a smaller world first.
//!
//! `cargo bench -p bvol-cli --bench threads_interleaved [-- SCENE...]`; N from
//! `BVOL_BENCH_N` (default 100 000), frames timed from `BVOL_BENCH_FRAMES`
//! (default 30, after 3 untimed), threads from `BVOL_BENCH_THREADS`
//! (default 2).

mod broadphases;
mod interleave;

use broadphases::{Broadphase, BvolTree, check_agreement};
use interleave::{env, interleaved, scenes};

fn main() {
    let n = env("BVOL_BENCH_N", 100_000);
    let frames = env("BVOL_BENCH_FRAMES", 30);
    let threads = env("BVOL_BENCH_THREADS", 2);
    println!(
        "scene\tn\tframes\tpairs_per_frame\tthreads\tmedian_ms\tmean_ms\tspeedup\tframe_speedup"
    );
    for kind in scenes() {
        check_agreement(kind, n.min(20_000));
        let mut methods: Vec<Box<dyn Broadphase>> =
            vec![Box::new(BvolTree::new(true, 1)), Box::new(BvolTree::new(true, threads))];
        let timed = interleaved(kind, n, frames, &mut methods);
        let ones = &timed.frame_ms[0];
        for (t, ms) in [1, threads].into_iter().zip(&timed.frame_ms) {
            let mean = ms.iter().sum::<f64>() / ms.len() as f64;
            let ratios: Vec<f64> = ones.iter().zip(ms).map(|(one, this)| one / this).collect();
            println!(
                "{kind}\t{n}\t{frames}\t{}\t{t}\t{:.3}\t{mean:.3}\t{:.2}\t{:.2}",
                timed.pairs,
                median(ms),
                median(ones) / median(ms),
                median(&ratios)
            );
        }
    }
}

/// The median of `values` (the mean of the middle two when their number is
/// even).
fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let k = sorted.len();
    0.5 * (sorted[(k - 1) / 2] + sorted[k / 2])
}
