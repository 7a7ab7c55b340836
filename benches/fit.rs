//! Fitting speed: every fitter on 1k, 100k and 1M random points (throughput in
//! points per second), and the near-minimum OBB of the real bunny mesh.
//!
//! `cargo bench --bench fit`; one thread.

use std::hint::black_box;
use std::time::Duration;

use bvol::volumes::{Aabb, Kdop6, Kdop14, Kdop18, Kdop26, Obb, ObbMethod, Sphere, SphereMethod};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

/// `n` points uniform in a box of sides 1, 2 and 3, in random order.
fn cloud(n: usize) -> Vec<Vec3> {
    let mut rng = SmallRng::seed_from_u64(n as u64);
    (0..n)
        .map(|_| Vec3::new(rng.random(), 2.0 * rng.random::<f32>(), 3.0 * rng.random::<f32>()))
        .collect()
}

fn fitters(c: &mut Criterion) {
    for n in [1_000, 100_000, 1_000_000] {
        let points = cloud(n);
        let mut group = c.benchmark_group(format!("fit/{n}"));
        group.throughput(Throughput::Elements(n as u64));
        group.sample_size(10).warm_up_time(Duration::from_millis(300));
        group.measurement_time(Duration::from_secs(1));
        for &m in SphereMethod::ALL {
            group.bench_function(BenchmarkId::new("sphere", m), |b| {
                b.iter(|| Sphere::fit(black_box(&points), m).unwrap())
            });
        }
        for &m in ObbMethod::ALL {
            group.bench_function(BenchmarkId::new("obb", m), |b| {
                b.iter(|| Obb::fit(black_box(&points), m).unwrap())
            });
        }
        group.bench_function("aabb", |b| b.iter(|| Aabb::fit(black_box(&points)).unwrap()));
        group.bench_function("kdop/6", |b| b.iter(|| Kdop6::fit(black_box(&points)).unwrap()));
        group.bench_function("kdop/14", |b| b.iter(|| Kdop14::fit(black_box(&points)).unwrap()));
        group.bench_function("kdop/18", |b| b.iter(|| Kdop18::fit(black_box(&points)).unwrap()));
        group.bench_function("kdop/26", |b| b.iter(|| Kdop26::fit(black_box(&points)).unwrap()));
        group.finish();
    }
}

fn bunny(c: &mut Criterion) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/meshes/bunny.obj");
    let points = bvol::load_obj(path).unwrap().remove(0).positions;
    let mut group = c.benchmark_group("fit/bunny");
    group.sample_size(10).measurement_time(Duration::from_secs(2));
    for &m in ObbMethod::ALL {
        group.bench_function(BenchmarkId::new("obb", m), |b| {
            b.iter(|| Obb::fit(black_box(&points), m).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, fitters, bunny);
criterion_main!(benches);
