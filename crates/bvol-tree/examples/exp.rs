use bvol_tree::{Config, PairSet, Tree};
use bvol_volumes::Aabb;
use glam::Vec3;
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};
use std::time::Instant;

struct Scene {
    pos: Vec<Vec3>,
    vel: Vec<Vec3>,
    half: Vec<Vec3>,
    world: f32,
    rng: SmallRng,
}
impl Scene {
    fn new(n: usize, speed: f32, seed: u64) -> Self {
        let mut r = SmallRng::seed_from_u64(seed);
        let world = (n as f32).cbrt() * 2.5;
        let mut s = Scene {
            pos: vec![],
            vel: vec![],
            half: vec![],
            world,
            rng: SmallRng::seed_from_u64(seed + 1),
        };
        for _ in 0..n {
            s.pos.push(Vec3::new(
                r.random_range(0.0..world),
                r.random_range(0.0..world),
                r.random_range(0.0..world),
            ));
            s.vel.push(
                Vec3::new(
                    r.random_range(-1.0..1.0),
                    r.random_range(-1.0..1.0),
                    r.random_range(-1.0..1.0),
                ) * speed,
            );
            s.half.push(Vec3::new(
                r.random_range(0.5..1.1),
                r.random_range(0.5..1.1),
                r.random_range(0.5..1.1),
            ));
        }
        s
    }
    fn step(&mut self, fraction: f32, teleport: f32) {
        for i in 0..self.pos.len() {
            if teleport > 0.0 && self.rng.random::<f32>() < teleport {
                let w = self.world;
                self.pos[i] = Vec3::new(
                    self.rng.random_range(0.0..w),
                    self.rng.random_range(0.0..w),
                    self.rng.random_range(0.0..w),
                );
                continue;
            }
            if fraction < 1.0 && self.rng.random::<f32>() >= fraction {
                continue;
            }
            let mut p = self.pos[i] + self.vel[i];
            for a in 0..3 {
                if p[a] < 0.0 || p[a] > self.world {
                    self.vel[i][a] = -self.vel[i][a];
                    p[a] = p[a].clamp(0.0, self.world);
                }
            }
            self.pos[i] = p;
        }
    }
    fn bounds(&self, out: &mut Vec<Aabb>) {
        out.clear();
        out.extend(self.pos.iter().zip(&self.half).map(|(p, h)| Aabb::new(*p - *h, *p + *h)));
    }
}

fn arg<T: std::str::FromStr>(i: usize, d: T) -> T {
    std::env::args().nth(i).and_then(|s| s.parse().ok()).unwrap_or(d)
}

fn main() {
    let n: usize = arg(1, 100_000);
    let speed: f32 = arg(2, 0.1);
    let frames: usize = arg(3, 100);
    let threads: usize = arg(4, 1);
    let fraction: f32 = arg(5, 1.0);
    let teleport: f32 = arg(6, 0.0);
    let mode: String = arg(7, "set".to_string());
    let refit_fraction: f32 = arg(8, Config::default().refit_fraction);
    let drift: f64 = arg(9, Config::default().drift);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let mut scene = Scene::new(n, speed, 1);
        let mut b = Vec::new();
        scene.bounds(&mut b);
        let config = Config { refit_fraction, drift, ..Config::default() };
        let t = Instant::now();
        let mut tree = Tree::build(config, b.iter().enumerate().map(|(i, b)| (i as u32, *b))).unwrap();
        let mut set = PairSet::new();
        let mut out = Vec::new();
        if mode == "set" { set.update(&mut tree); } else { tree.pairs_into(&mut out); }
        let build_ms = t.elapsed().as_secs_f64() * 1e3;
        if mode == "rep" {
            let mut ts = vec![];
            for _ in 0..40 { let t = Instant::now(); tree.pairs_into(&mut out); ts.push(t.elapsed().as_secs_f64() * 1e3); }
            ts.sort_by(f64::total_cmp);
            let mut rs = vec![];
            for _ in 0..10 { let t = Instant::now(); tree.rebuild(); rs.push(t.elapsed().as_secs_f64() * 1e3); }
            rs.sort_by(f64::total_cmp);
            let mut fs = vec![];
            for _ in 0..20 { let t = Instant::now(); tree.refit(); fs.push(t.elapsed().as_secs_f64() * 1e3); }
            fs.sort_by(f64::total_cmp);
            println!("pairs {} min {:.2} med {:.2} | rebuild min {:.2} med {:.2} | refit min {:.2} med {:.2} | sah {:.1}", out.len(), ts[0], ts[20], rs[0], rs[5], fs[0], fs[10], tree.sah_cost());
            return;
        }
        let mut times = vec![];
        let (mut tu, mut tp) = (0.0, 0.0);
        let (mut refits, mut rebuilds, mut pairs) = (0, 0, 0usize);
        for _ in 1..frames {
            scene.step(fraction, teleport);
            scene.bounds(&mut b);
            let t = Instant::now();
            let f = tree.update(&b).unwrap();
            let t1 = Instant::now();
            if mode == "set" { set.update(&mut tree); pairs += set.pairs().len(); } else { tree.pairs_into(&mut out); pairs += out.len(); }
            let t2 = Instant::now();
            refits += f.refit as usize; rebuilds += (f.rebuilt > 0) as usize;
            tu += (t1 - t).as_secs_f64() * 1e3; tp += (t2 - t1).as_secs_f64() * 1e3;
            times.push((t2 - t).as_secs_f64() * 1e3);
        }
        let mean = times.iter().sum::<f64>() / times.len() as f64;
        let mut s = times.clone(); s.sort_by(f64::total_cmp);
        let fr = (frames - 1) as f64;
        println!("n {n} threads {threads} build {build_ms:.1} median {:.2} mean {mean:.2} max {:.2} | update {:.2} pairs {:.2} | refits {refits} rebuilds {rebuilds} avg_pairs {:.0} mem/body {:.1}",
            s[s.len()/2], s[s.len()-1], tu / fr, tp / fr, pairs as f64 / fr, tree.memory_bytes() as f64 / n as f64);
    });
}
