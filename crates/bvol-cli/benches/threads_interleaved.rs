//! One thread against several, block by block: the frames of a scene go to
//! bvol on a one-thread pool and on a pool of `BVOL_BENCH_THREADS` in
//! blocks in turn ([`interleaved`]), as a user's frame runs (the tree's
//! update, then its pairs brought up to date in a `PairCache`), so that a
//! drift in the machine's speed falls on both alike; and prints each one's
//! median and mean frame, the speedup of the median, and the median of the
//! frames' own speedups (each frame's one-thread time over its time on the
//! pool, taken a block apart: a slow minute of the host slows both). The
//! pair sets are checked equal in every frame, and against brute force and
//! the peers on a smaller world first.
//!
//! On a shared host the second core's share moves from minute to minute,
//! so between the scene's rounds of blocks three fixed loads that split
//! perfectly go to the same kinds of pools in the same way ([`Ceiling`]):
//! a chain of dependent arithmetic, sums over a slice that stays in the
//! core's first-level cache, and sums over an array the size of a 100
//! 000-box tree's nodes, read from the shared cache and memory as the
//! tree's passes read theirs. Their speedups, printed beside the scene's
//! (`compute`, `core`, `memory`), are what the host gave two threads while
//! that scene ran. A dependent chain leaves most of a core idle, so it runs
//! as fast on the two hardware threads of one physical core as on two
//! cores; the sums keep a core's units busy and do not. Where the host puts
//! both virtual processors on one physical core, `compute` stays near 2x
//! while `core` falls to about 1.2x, and so does every scene. So the
//! speedup is also printed over the rounds of blocks alone that the core
//! load, timed just before and just after, found on two physical cores
//! (`two_cores`, the frames' own median speedup there, over `rounds` of
//! all; `-` when none was): what the code gains from a second core where
//! the host gives it one.
//!
//! `cargo bench -p bvol-cli --bench threads_interleaved [-- SCENE...]`; N from
//! `BVOL_BENCH_N` (default 100 000), frames timed from `BVOL_BENCH_FRAMES`
//! (default 30, after 3 untimed), threads from `BVOL_BENCH_THREADS`
//! (default 2).

mod broadphases;
mod interleave;

use std::hint::black_box;
use std::time::Instant;

use broadphases::{Broadphase, BvolTree, check_agreement};
use bvol_cli::scenes::SceneKind;
use interleave::{BLOCK, env, interleaved, median, scenes};
use rayon::prelude::*;

fn main() {
    let n = env("BVOL_BENCH_N", 100_000);
    let frames = env("BVOL_BENCH_FRAMES", 30);
    let threads = env("BVOL_BENCH_THREADS", 2);
    println!(
        "scene\tn\tframes\tpairs_per_frame\tthreads\tmedian_ms\tmean_ms\tspeedup\t\
         frame_speedup\tcompute\tcore\tmemory\ttwo_cores\trounds"
    );
    let mut ceiling = Ceiling::new(threads);
    for kind in scenes(&SceneKind::ALL) {
        check_agreement(kind, n.min(20_000));
        let mut methods: Vec<Box<dyn Broadphase>> =
            vec![Box::new(BvolTree::new(true, 1)), Box::new(BvolTree::new(true, threads))];
        let timed = interleaved(kind, n, frames, &mut methods, || ceiling.sample());
        let (rounds, on_two) = two_cores(&timed.frame_ms, &ceiling.core_rounds());
        let [compute, core, memory] = ceiling.speedups();
        let ones = &timed.frame_ms[0];
        for (t, ms) in [1, threads].into_iter().zip(&timed.frame_ms) {
            let mean = ms.iter().sum::<f64>() / ms.len() as f64;
            println!(
                "{kind}\t{n}\t{frames}\t{}\t{t}\t{:.3}\t{mean:.3}\t{:.2}\t{:.2}\t{:.2}\t{:.2}\t{:.2}\t{}\t{}/{}",
                timed.pairs,
                median(ms),
                median(ones) / median(ms),
                frame_speedup(ones, ms),
                if t == 1 { 1.0 } else { compute },
                if t == 1 { 1.0 } else { core },
                if t == 1 { 1.0 } else { memory },
                match (on_two, t) {
                    (None, _) => "-".to_string(),
                    (Some(_), 1) => "1.00".to_string(),
                    (Some(speedup), _) => format!("{speedup:.2}"),
                },
                rounds.0,
                rounds.1,
            );
        }
    }
}

/// The [`Ceiling`]'s `core` load at or above this speedup ran on two
/// physical cores; one core's two hardware threads give it about 1.2x.
const TWO_CORES: f64 = 1.8;

/// The median of the frames' own speedups on the pool (`frame_ms[1]`, as
/// [`frame_speedup`]) over the rounds of blocks that the core load, timed
/// just before and just after the round (`core[b - 1]` and `core[b]`),
/// found on two physical cores; with those rounds' count and the count of
/// all. None when no round was. Each frame against itself: heap's rounds
/// on two cores may hold its falling frames on one pool's side of the
/// median and its settled ones on the other's.
fn two_cores(frame_ms: &[Vec<f64>], core: &[f64]) -> ((usize, usize), Option<f64>) {
    let good = |b: usize| core[b] >= TWO_CORES && (b == 0 || core[b - 1] >= TWO_CORES);
    let kept = |ms: &Vec<f64>| -> Vec<f64> {
        let rounds = ms.chunks(BLOCK - 1).enumerate();
        rounds.filter(|(b, _)| good(*b)).flat_map(|(_, round)| round.iter().copied()).collect()
    };
    let count = (0..core.len()).filter(|&b| good(b)).count();
    let speedup = (count > 0).then(|| frame_speedup(&kept(&frame_ms[0]), &kept(&frame_ms[1])));
    ((count, core.len()), speedup)
}

/// The median of the frames' own speedups: each one-thread frame's time
/// over its time on the pool.
fn frame_speedup(ones: &[f64], ms: &[f64]) -> f64 {
    let ratios: Vec<f64> = ones.iter().zip(ms).map(|(one, this)| one / this).collect();
    median(&ratios)
}

/// Tasks each of the [`Ceiling`]'s loads is split into, as the tree's
/// passes split theirs.
const TASKS: usize = 64;

/// Steps of arithmetic in one task of the [`Ceiling`]'s arithmetic load.
const STEPS: u64 = 20_000;

/// Words in a task's slice of the [`Ceiling`]'s core load: 16 KiB, half
/// a first-level data cache.
const SLICE: usize = 2048;

/// Passes over its slice in one task of the [`Ceiling`]'s core load.
const PASSES: usize = 200;

/// Words in the array of the [`Ceiling`]'s memory load: 8 MiB, about a
/// 100 000-box tree's nodes, more than the private caches hold.
const WORDS: usize = 1 << 20;

/// Fixed loads in equal tasks with nothing shared, timed on a one-thread
/// pool and on the benchmark's in blocks in turn, as the frames are: the
/// speedup the host gives two threads of work that loses nothing to its
/// split, for dependent arithmetic ([`compute`]), for a core's units
/// kept busy ([`core`]) and for reading memory ([`memory`]).
struct Ceiling {
    pools: [rayon::ThreadPool; 2],
    words: Vec<u64>,
    /// Each load's runs since the last [`Ceiling::speedups`], in ms, on
    /// each pool: [`compute`]'s, [`core`]'s, then [`memory`]'s.
    ms: [[Vec<f64>; 2]; 3],
    /// Samples taken: which pool goes first turns with each.
    samples: usize,
}

impl Ceiling {
    fn new(threads: usize) -> Self {
        let pool = |t| rayon::ThreadPoolBuilder::new().num_threads(t).build().unwrap();
        let words = (0..WORDS as u64).collect();
        Ceiling { pools: [pool(1), pool(threads)], words, ms: Default::default(), samples: 0 }
    }

    /// Times a block of each load on each pool, each block's first run
    /// untimed.
    fn sample(&mut self) {
        let words = &self.words;
        let core = || core(&words[..TASKS * SLICE]);
        let loads: [&(dyn Fn() -> u64 + Sync); 3] = [&compute, &core, &|| memory(words)];
        for r in 0..2 {
            let p = (r + self.samples) % 2;
            for (load, ms) in loads.iter().zip(&mut self.ms) {
                for run in 0..BLOCK {
                    let started = Instant::now();
                    black_box(self.pools[p].install(load));
                    if run > 0 {
                        ms[p].push(started.elapsed().as_secs_f64() * 1e3);
                    }
                }
            }
        }
        self.samples += 1;
    }

    /// The core load's speedup in each sample since the last
    /// [`Ceiling::speedups`], in order: the median of its runs on the
    /// one-thread pool over the median on the benchmark's.
    fn core_rounds(&self) -> Vec<f64> {
        let [ones, ms] = &self.ms[1];
        let runs = |v: &[f64]| v.chunks(BLOCK - 1).map(median).collect::<Vec<_>>();
        runs(ones).iter().zip(runs(ms)).map(|(one, this)| one / this).collect()
    }

    /// Each load's frame speedup on the benchmark's pool over the samples
    /// since the last call, which are then dropped.
    fn speedups(&mut self) -> [f64; 3] {
        let speedups = self.ms.each_ref().map(|[ones, ms]| frame_speedup(ones, ms));
        self.ms = Default::default();
        speedups
    }
}

/// The core load: each task sums its [`SLICE`] of `words` [`PASSES`]
/// times, in eight independent lanes: no wait on memory or on a previous
/// step, only on the core's units.
fn core(words: &[u64]) -> u64 {
    let task = |slice: &[u64]| {
        let mut lanes = [0u64; 8];
        for _ in 0..PASSES {
            for chunk in black_box(slice).chunks_exact(8) {
                for (lane, &w) in lanes.iter_mut().zip(chunk) {
                    *lane = lane.wrapping_add(w);
                }
            }
        }
        lanes.into_iter().fold(0, u64::wrapping_add)
    };
    let slices = words.par_chunks(SLICE).with_max_len(1);
    slices.map(task).reduce(|| 0, u64::wrapping_add)
}

/// The memory load: the sum of `words`, a slice a task.
fn memory(words: &[u64]) -> u64 {
    let slices = words.par_chunks(WORDS / TASKS).with_max_len(1);
    slices.map(|s| s.iter().copied().fold(0, u64::wrapping_add)).reduce(|| 0, u64::wrapping_add)
}

/// The arithmetic load: [`TASKS`] chains of [`STEPS`] steps of [`mix`].
fn compute() -> u64 {
    let task = |k: usize| (0..STEPS).fold(k as u64, |x, _| mix(x));
    (0..TASKS).into_par_iter().with_max_len(1).map(task).reduce(|| 0, u64::wrapping_add)
}

/// A step of splitmix64 (Steele et al., "Fast splittable pseudorandom
/// number generators", 2014): arithmetic only, no memory.
fn mix(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}
