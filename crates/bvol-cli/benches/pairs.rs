//! The broadphase side by side: update + all pairs per frame on the generated
//! scenes, for every method of [`broadphases`], criterion timing each in turn.
//! Every method's pairs are checked equal before timing. On a shared machine
//! whose speed drifts over minutes, `pairs_interleaved` gives the steadier
//! ratios.
//!
//! `cargo bench --bench pairs`; N from `BVOL_BENCH_N` (default 100 000); every method on one thread.

mod broadphases;

use std::hint::black_box;
use std::time::{Duration, Instant};

use broadphases::{check_agreement, methods};
use bvol_cli::scenes::{Scene, SceneKind};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};

fn pairs(c: &mut Criterion) {
    let n: usize =
        std::env::var("BVOL_BENCH_N").ok().and_then(|v| v.parse().ok()).unwrap_or(100_000);
    for kind in SceneKind::ALL {
        check_agreement(kind, n.min(20_000));
        let mut group = c.benchmark_group(format!("pairs/{kind}"));
        group.sample_size(10).warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(3));
        for (name, make) in methods(n) {
            group.bench_function(BenchmarkId::new(name, n), |b| {
                // Each iteration is the next frame of one running scene; only
                // the broadphase's work is timed, not the scene's.
                let mut scene = Scene::new(kind, n, 1);
                let mut method = make();
                method.frame(scene.step());
                b.iter_custom(|iters| {
                    let mut total = Duration::ZERO;
                    for _ in 0..iters {
                        let boxes = scene.step();
                        let started = Instant::now();
                        black_box(method.frame(black_box(boxes)));
                        total += started.elapsed();
                    }
                    total
                });
            });
        }
        group.finish();
    }
}

criterion_group!(benches, pairs);
criterion_main!(benches);
