//! Narrow-phase speed, one thread: the box-box yes/no test, and hull-hull
//! contacts against parry3d's `contact` on the same pairs, cold (a fresh
//! warm start each call) and along slowly moving paths (one warm start kept
//! per pair). Both sides' verdicts are checked equal before timing, except
//! within 1e-3 of the size of touching, where parry3d is not exact
//! (PEER_NOTES.md); the exact f64 reference of the tests decides that band.
//!
//! `cargo bench -p bvol-narrow --bench narrow`.

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;
use std::time::Duration;

use bvol_narrow::{Collision, WarmStart, hull_hull, obb_obb};
use bvol_volumes::{Obb, Pose};
use common::reference::{Pair, Place};
use common::shapes::{self, TestShape};
use common::{parry_pose, random_rotation, random_unit, to_parry};
use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput, criterion_group, criterion_main};
use glam::{Mat3, Quat, Vec3};
use parry3d::query;
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

/// Pairs closer to touching than this, relative to the size, are not compared.
const NEAR_BAND: f64 = 1e-3;

/// Short runs: 20 samples over 3 s.
fn settings(group: &mut BenchmarkGroup<'_, WallTime>) {
    group.sample_size(20).warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(3));
}

/// Random world boxes (half extents 0.1 to 1, random axes), each pair's
/// centres up to 1.4 times the sum of their half diagonals apart: about half
/// of them overlap.
fn box_pairs(n: usize) -> Vec<(Obb, Obb)> {
    let mut rng = SmallRng::seed_from_u64(1);
    let random_box = |center: Vec3, rng: &mut SmallRng| {
        let mut side = || rng.random_range(0.1..1.0);
        let half_extents = Vec3::new(side(), side(), side());
        Obb { center, axes: Mat3::from_quat(random_rotation(rng)), half_extents }
    };
    (0..n)
        .map(|_| {
            let a = random_box(Vec3::ZERO, &mut rng);
            let b = random_box(Vec3::ZERO, &mut rng);
            let reach = a.half_extents.length() + b.half_extents.length();
            let center = random_unit(&mut rng) * rng.random_range(0.0..1.4 * reach);
            (a, Obb { center, ..b })
        })
        .collect()
}

/// `Obb::overlaps` on world boxes, in tests per second.
fn obb_overlaps(c: &mut Criterion) {
    let pairs = box_pairs(4096);
    let overlapping = pairs.iter().filter(|(a, b)| a.overlaps(b)).count();
    println!("obb pairs overlapping: {overlapping} of {}", pairs.len());
    let mut group = c.benchmark_group("obb_overlaps");
    settings(&mut group);
    group.throughput(Throughput::Elements(pairs.len() as u64));
    group.bench_function("bvol", |bench| {
        bench.iter(|| black_box(&pairs).iter().filter(|(a, b)| a.overlaps(b)).count())
    });
    group.finish();
}

/// Box-box contacts per second on the same random near pairs as
/// [`obb_overlaps`]: bvol's `obb_obb` (closed-form queries, then the face
/// clipping) against parry3d's `contact` on cuboids, verdicts checked equal
/// first outside the band where parry3d is not exact.
fn box_contacts(c: &mut Criterion) {
    let pairs = box_pairs(4096);
    let cuboid = |o: &Obb| parry3d::shape::Cuboid::new(to_parry(o.half_extents));
    // Each box's own centre and axes, as a pose for parry3d's cuboid.
    let pose = |o: &Obb| Pose::new(o.center, Quat::from_mat3(&o.axes));
    let parry = |(a, b): &(Obb, Obb)| {
        let (pa, pb) = (parry_pose(&pose(a)), parry_pose(&pose(b)));
        query::contact(&pa, &cuboid(a), &pb, &cuboid(b), 0.0).expect("supported")
    };
    let bvol =
        |(a, b): &(Obb, Obb)| obb_obb(a, &Pose::IDENTITY, b, &Pose::IDENTITY).expect("finite");
    let mut compared = 0;
    for p in &pairs {
        let got = bvol(p);
        let distance = match got {
            Collision::Separated { distance, .. } => distance,
            Collision::Touching(contact) => -contact.depth,
        };
        if distance.abs() as f64
            > NEAR_BAND * p.0.half_extents.length().max(p.1.half_extents.length()) as f64
        {
            assert_eq!(got.is_touching(), parry(p).is_some(), "{p:?}");
            compared += 1;
        }
    }
    println!("box contact pairs: {}, {compared} verdicts compared", pairs.len());
    let mut group = c.benchmark_group("box_contact");
    settings(&mut group);
    group.throughput(Throughput::Elements(pairs.len() as u64));
    group.bench_function("bvol", |bench| {
        bench.iter(|| black_box(&pairs).iter().filter(|p| bvol(p).is_touching()).count())
    });
    group.bench_function("parry3d", |bench| {
        bench.iter(|| black_box(&pairs).iter().filter(|p| parry(p).is_some()).count())
    });
    group.finish();
}

/// The bench hulls: 20 to 210 vertices (teapot, airplane and wuson among them).
fn hulls() -> Vec<TestShape> {
    shapes::all(1.0).into_iter().filter(|s| (20..=210).contains(&s.points.len())).collect()
}

/// Two hulls and their poses.
struct Posed<'a> {
    a: &'a TestShape,
    b: &'a TestShape,
    pose_a: Pose,
    pose_b: Pose,
}

impl Posed<'_> {
    /// bvol's answer, with the pair's warm start.
    fn bvol(&self, warm: &mut WarmStart) -> Collision {
        hull_hull(&self.a.poly, &self.pose_a, &self.b.poly, &self.pose_b, warm).expect("finite")
    }

    /// parry3d's contact, without prediction.
    fn parry(&self) -> Option<parry3d::query::Contact> {
        let (pa, pb) = (parry_pose(&self.pose_a), parry_pose(&self.pose_b));
        query::contact(&pa, &self.a.parry, &pb, &self.b.parry, 0.0).expect("supported")
    }

    /// Exact separation over the size, from the tests' f64 reference.
    fn exact_separation(&self) -> f64 {
        let pair = Pair {
            a: &self.a.reference,
            pa: Place::of(&self.pose_a),
            b: &self.b.reference,
            pb: Place::of(&self.pose_b),
        };
        pair.sat().separation / self.a.size.max(self.b.size)
    }
}

/// Asserts bvol's verdict (with `warm`) equals parry3d's and the exact one,
/// away from touching; returns whether the pair was compared.
fn check(p: &Posed, warm: &mut WarmStart) -> bool {
    let sep = p.exact_separation();
    if sep.abs() <= NEAR_BAND {
        return false;
    }
    let (pa, pb) = (parry_pose(&p.pose_a), parry_pose(&p.pose_b));
    let parry = query::intersection_test(&pa, &p.a.parry, &pb, &p.b.parry).expect("supported");
    let got = p.bvol(warm).is_touching();
    assert_eq!(got, parry.intersecting, "{} vs {}: parry3d disagrees", p.a.name, p.b.name);
    assert_eq!(got, sep <= 0.0, "{} vs {}: the exact verdict disagrees", p.a.name, p.b.name);
    true
}

/// Random near pairs: B's origin within 1.1 times the sum of the radii.
fn near_pairs(hulls: &[TestShape], n: usize) -> Vec<Posed<'_>> {
    let mut rng = SmallRng::seed_from_u64(2);
    (0..n)
        .map(|_| {
            let a = &hulls[rng.random_range(0..hulls.len())];
            let b = &hulls[rng.random_range(0..hulls.len())];
            let reach = (a.size + b.size) as f32;
            let offset = random_unit(&mut rng) * rng.random_range(0.0..1.1 * reach);
            let pose_a = Pose::new(Vec3::ZERO, random_rotation(&mut rng));
            Posed { a, b, pose_a, pose_b: Pose::new(offset, random_rotation(&mut rng)) }
        })
        .collect()
}

/// Slowly moving pairs: B starts 1/100 to 1/10 of the size clear of A and
/// sways along that direction by up to 0.8 of the gap while turning 0.002 rad
/// a step, so the pair stays apart but near.
fn moving_pairs(hulls: &[TestShape], pairs: usize, steps: usize) -> Vec<Vec<Posed<'_>>> {
    let mut rng = SmallRng::seed_from_u64(3);
    (0..pairs)
        .map(|_| {
            let a = &hulls[rng.random_range(0..hulls.len())];
            let b = &hulls[rng.random_range(0..hulls.len())];
            let pose_a = Pose::new(Vec3::ZERO, random_rotation(&mut rng));
            let start = Pose::new(Vec3::ZERO, random_rotation(&mut rng));
            let u = random_unit(&mut rng);
            let pair = Pair {
                a: &a.reference,
                pa: Place::of(&pose_a),
                b: &b.reference,
                pb: Place::of(&start),
            };
            let size = a.size.max(b.size);
            let gap = rng.random_range(0.01..0.1) * size;
            let touching = pair.touching_offset(u.as_dvec3().normalize(), &pair.candidates());
            let axis = random_unit(&mut rng);
            (0..steps)
                .map(|k| {
                    let sway = 0.8 * gap * (k as f64 * 0.05).sin();
                    let position = u * (touching + gap + sway) as f32;
                    let rotation = Quat::from_axis_angle(axis, 0.002 * k as f32) * start.rotation;
                    Posed { a, b, pose_a, pose_b: Pose::new(position, rotation) }
                })
                .collect()
        })
        .collect()
}

/// Hull-hull contacts per second, bvol and parry3d on the same pairs: random
/// near pairs cold (all, then those apart and those touching), and moving
/// pairs with and without warm starts.
fn hull_contacts(c: &mut Criterion) {
    let hulls = hulls();
    let pairs = near_pairs(&hulls, 512);
    let compared = pairs.iter().filter(|p| check(p, &mut WarmStart::default())).count();
    let touching = pairs.iter().filter(|p| p.bvol(&mut WarmStart::default()).is_touching()).count();
    println!("cold pairs: {} ({touching} touching), {compared} verdicts compared", pairs.len());
    let (apart, touching): (Vec<&Posed>, Vec<&Posed>) =
        pairs.iter().partition(|p| !p.bvol(&mut WarmStart::default()).is_touching());
    let mut group = c.benchmark_group("hull_contact_cold");
    settings(&mut group);
    for (name, set) in
        [("all", pairs.iter().collect::<Vec<_>>()), ("apart", apart), ("touching", touching)]
    {
        group.throughput(Throughput::Elements(set.len() as u64));
        group.bench_function(format!("bvol/{name}"), |bench| {
            bench.iter(|| {
                black_box(&set)
                    .iter()
                    .filter(|p| p.bvol(&mut WarmStart::default()).is_touching())
                    .count()
            })
        });
        group.bench_function(format!("parry3d/{name}"), |bench| {
            bench.iter(|| black_box(&set).iter().filter(|p| p.parry().is_some()).count())
        });
    }
    group.finish();

    let paths = moving_pairs(&hulls, 64, 100);
    let steps = paths.iter().map(Vec::len).sum::<usize>();
    let mut compared = 0;
    for path in &paths {
        let mut warm = WarmStart::default();
        compared += path.iter().filter(|p| check(p, &mut warm)).count();
    }
    let touching =
        paths.iter().flatten().filter(|p| p.bvol(&mut WarmStart::default()).is_touching()).count();
    println!(
        "moving pairs: {} paths, {steps} steps ({touching} touching), {compared} verdicts compared",
        paths.len()
    );
    let mut group = c.benchmark_group("hull_contact_moving");
    settings(&mut group);
    group.throughput(Throughput::Elements(steps as u64));
    group.bench_function("bvol_warm", |bench| {
        bench.iter(|| {
            let mut touching = 0;
            for path in black_box(&paths) {
                let mut warm = WarmStart::default();
                touching += path.iter().filter(|p| p.bvol(&mut warm).is_touching()).count();
            }
            touching
        })
    });
    group.bench_function("bvol_cold", |bench| {
        bench.iter(|| {
            let all = black_box(&paths).iter().flatten();
            all.filter(|p| p.bvol(&mut WarmStart::default()).is_touching()).count()
        })
    });
    group.bench_function("parry3d", |bench| {
        bench.iter(|| black_box(&paths).iter().flatten().filter(|p| p.parry().is_some()).count())
    });
    group.finish();
}

criterion_group!(benches, obb_overlaps, box_contacts, hull_contacts);
criterion_main!(benches);
