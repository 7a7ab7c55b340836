//! The broadphase side by side, block by block: a scene's frames go to every
//! method in short blocks in turn (`interleave::interleaved`), so that a
//! drift in the machine's speed, which on a shared host moves timings by
//! half over minutes, falls on all methods alike; and prints each method's
//! mean frame and its ratio to parry3d's. Pair sets are checked equal in
//! every frame, and against brute force on a smaller world first.
//!
//! `cargo bench -p bvol-cli --bench pairs_interleaved [-- SCENE...]`; N from
//! `BVOL_BENCH_N` (default 100 000), frames timed from `BVOL_BENCH_FRAMES`
//! (default 30, after 3 untimed); every method on one thread.

mod broadphases;
#[allow(dead_code, reason = "shared with the benchmarks that take medians, which use the rest")]
mod interleave;

use broadphases::{Broadphase, check_agreement, methods};
use bvol_cli::scenes::SceneKind;
use interleave::{env, interleaved, scenes};

fn main() {
    let n = env("BVOL_BENCH_N", 100_000);
    let frames = env("BVOL_BENCH_FRAMES", 30);
    println!("scene\tn\tframes\tpairs_per_frame\tmethod\tmean_ms\tvs_parry3d");
    for kind in scenes(&SceneKind::ALL) {
        check_agreement(kind, n.min(20_000));
        // Brute force and sweep-and-prune, each a second or more a frame
        // here, are left to `pairs`.
        let (names, mut methods): (Vec<&str>, Vec<Box<dyn Broadphase>>) = methods(n)
            .into_iter()
            .filter(|m| !["brute-force", "sweep-and-prune"].contains(&m.0))
            .map(|(name, make)| (name, make()))
            .unzip();
        let timed = interleaved(kind, n, frames, &mut methods, || {});
        let mean = |ms: &[f64]| ms.iter().sum::<f64>() / ms.len() as f64;
        let parry = names.iter().position(|&m| m == "parry3d").map(|i| mean(&timed.frame_ms[i]));
        for (name, ms) in names.iter().zip(&timed.frame_ms) {
            let ratio = parry.map_or(String::from("-"), |p| format!("{:.2}", mean(ms) / p));
            println!("{kind}\t{n}\t{frames}\t{}\t{name}\t{:.3}\t{ratio}", timed.pairs, mean(ms));
        }
    }
}
