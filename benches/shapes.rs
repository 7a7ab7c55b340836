//! Making shapes: 1 000 boxes of distinct sizes, balls, capsules, and
//! scaled copies of a box and of the bunny's hull (throughput in shapes per
//! second). A world of many distinct bodies pays this once a body.
//!
//! `cargo bench --bench shapes`; one thread.

use std::hint::black_box;
use std::time::Duration;

use bvol::{FitOptions, Shape};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;

/// Shapes made per measured call.
const N: usize = 1_000;

/// The `i`-th of `N` distinct sizes near 1.
fn size(i: usize) -> f32 {
    1.0 + i as f32 * 1e-3
}

fn shapes(c: &mut Criterion) {
    let mut group = c.benchmark_group("shapes");
    group.throughput(Throughput::Elements(N as u64));
    group.sample_size(10).warm_up_time(Duration::from_millis(300));
    group.measurement_time(Duration::from_secs(2));
    let each = |make: &dyn Fn(f32) -> Shape| (0..N).map(|i| make(size(i))).collect::<Vec<_>>();
    group.bench_function("cuboid", |b| {
        b.iter(|| each(&|s| Shape::cuboid(black_box(Vec3::new(s, 0.5, 0.25))).unwrap()))
    });
    group.bench_function("ball", |b| b.iter(|| each(&|s| Shape::ball(black_box(s)).unwrap())));
    group.bench_function("capsule", |b| {
        b.iter(|| each(&|s| Shape::capsule(black_box(0.5), black_box(s)).unwrap()))
    });
    let cube = Shape::cuboid(Vec3::splat(0.5)).unwrap();
    group.bench_function("cuboid scaled per axis", |b| {
        b.iter(|| each(&|s| cube.scaled(black_box(Vec3::new(s, 1.0, 2.0))).unwrap()))
    });
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/meshes/bunny.obj");
    let bunny = Shape::from_obj(path, FitOptions::default()).unwrap();
    group.bench_function("bunny hull scaled uniformly", |b| {
        b.iter(|| each(&|s| bunny.scaled(black_box(Vec3::splat(s))).unwrap()))
    });
    group.finish();
}

criterion_group!(benches, shapes);
criterion_main!(benches);
