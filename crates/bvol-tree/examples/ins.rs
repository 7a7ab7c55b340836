use bvol_tree::Tree;
use bvol_volumes::Aabb;
use glam::Vec3;
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};
fn main() {
    let n = 100_000;
    let mut r = SmallRng::seed_from_u64(1);
    let world = (n as f32).cbrt() * 2.5;
    let b: Vec<Aabb> = (0..n)
        .map(|_| {
            let p = Vec3::new(
                r.random_range(0.0..world),
                r.random_range(0.0..world),
                r.random_range(0.0..world),
            );
            Aabb::new(p - 0.8, p + 0.8)
        })
        .collect();
    let mut tree = Tree::from_bounds(&b[..n - 1000]).unwrap();
    println!("fresh {:.1}", tree.sah_cost());
    for i in n - 1000..n {
        tree.insert(i as u32, b[i]).unwrap();
    }
    println!("after 1000 inserts {:.1}", tree.sah_cost());
    tree.refit();
    println!("after refit {:.1}", tree.sah_cost());
    for i in 0..1000 {
        tree.remove(i as u32).unwrap();
    }
    println!("after 1000 removes {:.1}", tree.sah_cost());
    let t2 = Tree::from_bounds(&b).unwrap();
    println!("fresh all {:.1}", t2.sah_cost());
}
