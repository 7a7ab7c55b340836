//! Frames handed to several broadphases in turn, for the benchmarks that
//! compare them side by side: a scene's frames go to every one in short
//! blocks, so that a drift in the machine's speed, which on a shared host
//! moves timings by half over minutes, falls on all alike. Their pair sets
//! are checked equal in every frame.

use std::hint::black_box;
use std::time::Instant;

use bvol::volumes::Aabb;
use bvol_cli::scenes::{Scene, SceneKind};

use crate::broadphases::{Broadphase, digest_of};

/// Untimed frames after the first: the builds settle, buffers grow.
pub const WARM: usize = 3;

/// A count from the environment variable `name`, or `default`.
pub fn env(name: &str, default: usize) -> usize {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

/// The scenes named on the command line after `--` (criterion's `--bench`
/// flag is ignored), or else `default`.
pub fn scenes(default: &[SceneKind]) -> Vec<SceneKind> {
    let asked: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with('-')).collect();
    match asked.is_empty() {
        true => default.to_vec(),
        false => {
            SceneKind::ALL.into_iter().filter(|k| asked.iter().any(|a| a == k.name())).collect()
        }
    }
}

/// The median of `values` (the mean of the middle two when their number is
/// even).
pub fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let k = sorted.len();
    0.5 * (sorted[(k - 1) / 2] + sorted[k / 2])
}

/// What [`interleaved`] measured.
pub struct Timed {
    /// Each method's timed frames, in ms.
    pub frame_ms: Vec<Vec<f64>>,
    /// The pairs of a timed frame, on average.
    pub pairs: usize,
}

/// Runs `frames` timed frames of `kind` with `n` boxes, after [`WARM`]
/// untimed ones, through every method, and panics where two methods' pair
/// sets differ. The methods take blocks of [`BLOCK`] frames in turn (the
/// first of them rotating from block to block), the scene's frames made
/// beforehand, so that a method's frames follow each other as a user's
/// do. Each block's first frame is untimed: a pool that sat idle while the
/// other methods ran wakes its threads in it. `between` runs after each
/// round of blocks, untimed: a benchmark times loads of its own there, in
/// the same minutes as the frames.
///
/// Frame by frame, a pool's frame paid for the others': on a two-core
/// virtual machine a load of arithmetic that splits perfectly ran 1.0-1.96x
/// (mostly 1.0-1.4x) as fast on two threads as on one when each run went to
/// a pool right after another pool's (whose idle worker still held a core),
/// and about 1.0x after a 5 ms pause (the second core, asleep, woke when
/// the work was done); in blocks it runs 1.8-2.0x as fast.
pub fn interleaved(
    kind: SceneKind,
    n: usize,
    frames: usize,
    methods: &mut [Box<dyn Broadphase>],
    mut between: impl FnMut(),
) -> Timed {
    let k = methods.len();
    let blocks = frames.div_ceil(BLOCK - 1);
    let mut scene = Scene::new(kind, n, 1);
    let all: Vec<Vec<Aabb>> = (0..=WARM + blocks * BLOCK).map(|_| scene.step().to_vec()).collect();
    let mut frame_ms = vec![Vec::with_capacity(frames); k];
    let mut digests = vec![Vec::with_capacity(all.len()); k];
    let (warm, timed) = all.split_at(WARM + 1);
    for (i, method) in methods.iter_mut().enumerate() {
        digests[i].extend(warm.iter().map(|boxes| digest_of(method.frame(boxes))));
    }
    for (b, block) in timed.chunks(BLOCK).enumerate() {
        for r in 0..k {
            let i = (r + b) % k;
            for (f, boxes) in block.iter().enumerate() {
                let started = Instant::now();
                let found = methods[i].frame(black_box(boxes));
                let ms = started.elapsed().as_secs_f64() * 1e3;
                if f > 0 && frame_ms[i].len() < frames {
                    frame_ms[i].push(ms);
                }
                digests[i].push(digest_of(found));
            }
        }
        between();
    }
    for (i, d) in digests.iter().enumerate() {
        if let Some(f) = (0..d.len()).find(|&f| d[f] != digests[0][f]) {
            panic!("{kind}, frame {f}: method {i}'s pairs differ from method 0's");
        }
    }
    let pairs: usize = digests[0][WARM + 1..].iter().map(|d| d.count as usize).sum();
    Timed { frame_ms, pairs: pairs / timed.len().max(1) }
}

/// Frames a method runs in turn in [`interleaved`], the first untimed.
pub const BLOCK: usize = 6;
