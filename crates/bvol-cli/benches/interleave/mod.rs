//! Frames handed to several broadphases in turn, for the benchmarks that
//! compare them side by side: each frame of a scene goes to every one (the
//! first of them rotating from frame to frame), so that a drift in the
//! machine's speed, which on a shared host moves timings by half over
//! minutes, falls on all alike. Their pair sets are checked equal in every
//! frame.

use std::hint::black_box;
use std::time::Instant;

use bvol_cli::digest::PairDigest;
use bvol_cli::scenes::{Scene, SceneKind};

use crate::broadphases::Broadphase;

/// Untimed frames after the first: the builds settle, buffers grow.
const WARM: usize = 3;

/// A count from the environment variable `name`, or `default`.
pub fn env(name: &str, default: usize) -> usize {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

/// The scenes named on the command line after `--` (criterion's `--bench`
/// flag is ignored), or all of them.
pub fn scenes() -> Vec<SceneKind> {
    let asked: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with('-')).collect();
    SceneKind::ALL
        .into_iter()
        .filter(|k| asked.is_empty() || asked.iter().any(|a| a == k.name()))
        .collect()
}

/// What [`interleaved`] measured.
pub struct Timed {
    /// Each method's timed frames, in ms.
    pub frame_ms: Vec<Vec<f64>>,
    /// The pairs of a timed frame, on average.
    pub pairs: usize,
}

/// Runs `frames` timed frames of `kind` with `n` boxes, after [`WARM`]
/// untimed ones, through every method in turn, and panics where two
/// methods' pair sets differ.
pub fn interleaved(
    kind: SceneKind,
    n: usize,
    frames: usize,
    methods: &mut [Box<dyn Broadphase>],
) -> Timed {
    let k = methods.len();
    let mut frame_ms = vec![Vec::with_capacity(frames); k];
    let mut pairs = 0;
    let mut scene = Scene::new(kind, n, 1);
    for f in 0..=WARM + frames {
        let boxes = scene.step();
        let mut digests = vec![PairDigest::default(); k];
        for r in 0..k {
            let i = (r + f) % k;
            let started = Instant::now();
            let found = methods[i].frame(black_box(boxes));
            let ms = started.elapsed().as_secs_f64() * 1e3;
            digests[i] = PairDigest::of_pairs(found.iter().copied());
            if f > WARM {
                frame_ms[i].push(ms);
            }
        }
        if let Some(i) = digests.iter().position(|d| *d != digests[0]) {
            panic!("{kind}, frame {f}: method {i}'s pairs differ from method 0's");
        }
        if f > WARM {
            pairs += digests[0].count as usize;
        }
    }
    Timed { frame_ms, pairs: pairs / frames.max(1) }
}
