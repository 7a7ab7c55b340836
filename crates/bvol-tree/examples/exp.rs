use bvol_tree::Tree;
use bvol_volumes::Aabb;
use glam::Vec3;
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};
use std::time::Instant;

struct Scene { pos: Vec<Vec3>, vel: Vec<Vec3>, half: Vec<Vec3>, world: f32 }
impl Scene {
    fn new(n: usize, speed: f32, seed: u64) -> Self {
        let mut r = SmallRng::seed_from_u64(seed);
        let world = (n as f32).cbrt() * 2.5;
        let mut s = Scene { pos: vec![], vel: vec![], half: vec![], world };
        for _ in 0..n {
            s.pos.push(Vec3::new(r.random_range(0.0..world), r.random_range(0.0..world), r.random_range(0.0..world)));
            s.vel.push(Vec3::new(r.random_range(-1.0..1.0), r.random_range(-1.0..1.0), r.random_range(-1.0..1.0)) * speed);
            s.half.push(Vec3::new(r.random_range(0.5..1.1), r.random_range(0.5..1.1), r.random_range(0.5..1.1)));
        }
        s
    }
    fn step(&mut self) {
        for i in 0..self.pos.len() {
            let mut p = self.pos[i] + self.vel[i];
            for a in 0..3 {
                if p[a] < 0.0 || p[a] > self.world { self.vel[i][a] = -self.vel[i][a]; p[a] = p[a].clamp(0.0, self.world); }
            }
            self.pos[i] = p;
        }
    }
    fn bounds(&self) -> Vec<Aabb> { self.pos.iter().zip(&self.half).map(|(p, h)| Aabb::new(*p - *h, *p + *h)).collect() }
}

fn cpu_ms() -> f64 {
    let s = std::fs::read_to_string("/proc/thread-self/stat").unwrap();
    let f: Vec<&str> = s.rsplit(')').next().unwrap().split_whitespace().collect();
    (f[11].parse::<f64>().unwrap() + f[12].parse::<f64>().unwrap()) * 10.0
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(100_000);
    let speed: f32 = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(0.1);
    let frames: usize = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(200);
    let threads: usize = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(1);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let mut scene = Scene::new(n, speed, 1);
        let b = scene.bounds();
        let t = Instant::now();
        let mut tree = Tree::from_bounds(&b).unwrap();
        println!("build {:.2} ms  sah {:.1} mem/body {:.1}", t.elapsed().as_secs_f64() * 1e3, tree.sah_cost(), tree.memory_bytes() as f64 / n as f64);
        let mut out = Vec::new();
        let t = Instant::now();
        tree.pairs_into(&mut out);
        println!("pairs fresh {:.2} ms  count {}", t.elapsed().as_secs_f64() * 1e3, out.len());
        if std::env::var("REPEAT").is_ok() {
            let mut ts = vec![];
            let c = cpu_ms();
            for _ in 0..60 { let t = Instant::now(); tree.pairs_into(&mut out); ts.push(t.elapsed().as_secs_f64()*1e3); }
            let cpu = (cpu_ms() - c) / 60.0;
            ts.sort_by(f64::total_cmp);
            println!("pairs min {:.3} med {:.3} cpu {:.3}", ts[0], ts[ts.len()/2], cpu);
            let mut ts = vec![];
            let c = cpu_ms();
            for _ in 0..20 { let t = Instant::now(); tree.rebuild(); ts.push(t.elapsed().as_secs_f64()*1e3); }
            let cpu = (cpu_ms() - c) / 20.0;
            ts.sort_by(f64::total_cmp);
            println!("rebuild min {:.3} med {:.3} cpu {:.3}", ts[0], ts[ts.len()/2], cpu);
            return;
        }
        let (mut tr, mut tp) = (0.0, 0.0);
        for f in 1..=frames {
            scene.step();
            let b = scene.bounds();
            let t = Instant::now();
            tree.refit_from(&b);
            let every: usize = std::env::var("EVERY").ok().and_then(|v| v.parse().ok()).unwrap_or(0);
            if every > 0 && f % every == 0 { tree.rebuild(); }
            let t1 = Instant::now();
            tree.pairs_into(&mut out);
            let t2 = Instant::now();
            tr += (t1 - t).as_secs_f64() * 1e3; tp += (t2 - t1).as_secs_f64() * 1e3;
            if f % 20 == 0 {
                println!("frame {f}: refit {:.2} pairs {:.2} ms sah {:.1} pairs {}", tr / 20.0, tp / 20.0, tree.sah_cost(), out.len());
                tr = 0.0; tp = 0.0;
            }
        }
        let t = Instant::now();
        tree.rebuild();
        println!("rebuild {:.2} ms sah {:.1}", t.elapsed().as_secs_f64() * 1e3, tree.sah_cost());
        let t = Instant::now();
        tree.pairs_into(&mut out);
        println!("pairs after rebuild {:.2} ms", t.elapsed().as_secs_f64() * 1e3);
    });
}
#[allow(dead_code)]
fn unused() {}
