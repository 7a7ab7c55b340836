//! The broadphase side by side, frame by frame: each frame of a scene goes
//! to every method in turn (the order rotating from frame to frame), so that
//! a drift in the machine's speed, which on a shared host moves timings by
//! half over minutes, falls on all methods alike; and prints each method's
//! mean frame and its ratio to parry3d's. Pair sets are checked equal first.
//!
//! `cargo bench -p bvol-cli --bench pairs_interleaved [-- SCENE...]`; N from
//! `BVOL_BENCH_N` (default 100 000), frames timed from `BVOL_BENCH_FRAMES`
//! (default 30, after 3 untimed); every method on one thread.

mod broadphases;

use std::hint::black_box;
use std::time::Instant;

use broadphases::{Broadphase, check_agreement, methods};
use bvol_cli::scenes::{Scene, SceneKind};

/// Untimed frames after the first: the builds settle, buffers grow.
const WARM: usize = 3;

fn env(name: &str, default: usize) -> usize {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn main() {
    let n = env("BVOL_BENCH_N", 100_000);
    let frames = env("BVOL_BENCH_FRAMES", 30);
    // Scene names given after `--` (criterion's `--bench` flag is ignored).
    let asked: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with('-')).collect();
    let kinds = SceneKind::ALL
        .into_iter()
        .filter(|k| asked.is_empty() || asked.iter().any(|a| a == k.name()));
    println!("scene\tn\tframes\tpairs_per_frame\tmethod\tmean_ms\tvs_parry3d");
    for kind in kinds {
        check_agreement(kind, n.min(20_000));
        // Brute force and sweep-and-prune, each a second or more a frame
        // here, are left to `pairs`.
        let mut methods: Vec<(&str, Box<dyn Broadphase>)> = methods(n)
            .into_iter()
            .filter(|m| !["brute-force", "sweep-and-prune"].contains(&m.0))
            .map(|(name, make)| (name, make()))
            .collect();
        let mut total = vec![0.0f64; methods.len()];
        let mut pairs = 0usize;
        let mut scene = Scene::new(kind, n, 1);
        for f in 0..=WARM + frames {
            let boxes = scene.step();
            let k = methods.len();
            for r in 0..k {
                let i = (r + f) % k;
                let started = Instant::now();
                let found = methods[i].1.frame(black_box(boxes)).len();
                if f > WARM {
                    total[i] += started.elapsed().as_secs_f64() * 1e3;
                    if i == 0 {
                        pairs += found;
                    }
                }
            }
        }
        let parry = methods.iter().position(|m| m.0 == "parry3d").map(|i| total[i]);
        for ((name, _), total) in methods.iter().zip(&total) {
            let ratio = parry.map_or(String::from("-"), |p| format!("{:.2}", total / p));
            println!(
                "{kind}\t{n}\t{frames}\t{}\t{name}\t{:.3}\t{ratio}",
                pairs / frames,
                total / frames as f64
            );
        }
    }
}
