//! The broadphases the pair benchmarks compare: bvol's tree (its pairs kept
//! in a `PairCache`, read where the cache keeps them; and, as `bvol-search`,
//! searched afresh), a sweep-and-prune baseline, parry3d's `Bvh` (used as its authors
//! advise: binned build, then per frame insert_or_update_partially,
//! optimize_incremental, refit and traverse_bvtt_single_tree) and, for small
//! N, brute force. Every one on one thread.

use bvol::tree::{PairCache, Tree};
use bvol::volumes::Aabb;
use bvol_cli::digest::PairDigest;
use bvol_cli::scenes::{Scene, SceneKind};
use parry3d::bounding_volume::Aabb as ParryAabb;
use parry3d::math::Vector;
use parry3d::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};

/// A broadphase: brought up to date with every box each frame, then all pairs,
/// where the broadphase keeps them (as its users read them: a copy into a
/// vector of the caller's would time a copy only some of them make).
pub trait Broadphase {
    fn frame(&mut self, boxes: &[Aabb]) -> &[(u32, u32)];
}

/// bvol's dynamic tree on a pool of its own (its builds and pair search
/// would otherwise use rayon's global pool): one thread like the others,
/// unless a benchmark of threads asks for more. Its pairs are kept in a
/// `PairCache` (`cache`) or searched afresh each frame.
pub struct BvolTree {
    tree: Option<Tree<Aabb>>,
    cache: Option<PairCache>,
    /// The search's pairs, without a cache.
    pairs: Vec<(u32, u32)>,
    pool: rayon::ThreadPool,
}

impl BvolTree {
    pub fn new(cache: bool, threads: usize) -> Self {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        BvolTree { tree: None, cache: cache.then(PairCache::new), pairs: Vec::new(), pool }
    }
}

impl Broadphase for BvolTree {
    fn frame(&mut self, boxes: &[Aabb]) -> &[(u32, u32)] {
        let (slot, cache, pairs) = (&mut self.tree, &mut self.cache, &mut self.pairs);
        self.pool.install(|| {
            let tree = match slot {
                Some(tree) => {
                    tree.update(boxes).expect("valid boxes");
                    tree
                }
                None => slot.insert(Tree::from_bounds(boxes).expect("valid boxes")),
            };
            match cache {
                Some(cache) => {
                    cache.update(tree);
                }
                None => {
                    tree.pairs_into(pairs);
                }
            }
        });
        match &self.cache {
            Some(cache) => cache.pairs(),
            None => &self.pairs,
        }
    }
}

/// Sort and sweep on x (Baraff 1992), the order kept between frames so the
/// sort starts nearly sorted.
#[derive(Default)]
struct SweepAndPrune(Vec<u32>, Vec<(u32, u32)>);

impl Broadphase for SweepAndPrune {
    fn frame(&mut self, boxes: &[Aabb]) -> &[(u32, u32)] {
        let pairs = &mut self.1;
        if self.0.len() != boxes.len() {
            self.0 = (0..boxes.len() as u32).collect();
        }
        self.0.sort_by(|&a, &b| boxes[a as usize].min.x.total_cmp(&boxes[b as usize].min.x));
        pairs.clear();
        for (k, &a) in self.0.iter().enumerate() {
            let ba = &boxes[a as usize];
            for &b in &self.0[k + 1..] {
                let bb = &boxes[b as usize];
                if bb.min.x > ba.max.x {
                    break;
                }
                if ba.overlaps(bb) {
                    pairs.push((a.min(b), a.max(b)));
                }
            }
        }
        pairs
    }
}

/// parry3d's `Bvh`, pairs filtered to the tight boxes.
#[derive(Default)]
struct Parry(Option<(Bvh, BvhWorkspace)>, Vec<(u32, u32)>);

fn parry_aabb(b: &Aabb) -> ParryAabb {
    ParryAabb::new(Vector::new(b.min.x, b.min.y, b.min.z), Vector::new(b.max.x, b.max.y, b.max.z))
}

impl Broadphase for Parry {
    fn frame(&mut self, boxes: &[Aabb]) -> &[(u32, u32)] {
        let pairs = &mut self.1;
        let (bvh, ws) = match &mut self.0 {
            Some((bvh, ws)) => {
                for (i, b) in boxes.iter().enumerate() {
                    bvh.insert_or_update_partially(parry_aabb(b), i as u32, 0.0);
                }
                bvh.optimize_incremental(ws);
                bvh.refit(ws);
                (bvh, ws)
            }
            None => {
                let leaves: Vec<ParryAabb> = boxes.iter().map(parry_aabb).collect();
                let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &leaves);
                let (bvh, ws) = self.0.insert((bvh, BvhWorkspace::default()));
                (bvh, ws)
            }
        };
        pairs.clear();
        bvh.traverse_bvtt_single_tree::<false>(ws, &mut |a, b| {
            if boxes[a as usize].overlaps(&boxes[b as usize]) {
                pairs.push((a.min(b), a.max(b)));
            }
        });
        pairs
    }
}

/// All pairs by testing every pair.
#[derive(Default)]
struct BruteForce(Vec<(u32, u32)>);

impl Broadphase for BruteForce {
    fn frame(&mut self, boxes: &[Aabb]) -> &[(u32, u32)] {
        let pairs = &mut self.0;
        pairs.clear();
        for a in 0..boxes.len() {
            for b in a + 1..boxes.len() {
                if boxes[a].overlaps(&boxes[b]) {
                    pairs.push((a as u32, b as u32));
                }
            }
        }
        pairs
    }
}

/// A named way to make a fresh broadphase.
pub type Method = (&'static str, fn() -> Box<dyn Broadphase>);

pub fn methods(n: usize) -> Vec<Method> {
    let mut out: Vec<Method> = vec![
        ("bvol", || Box::new(BvolTree::new(true, 1))),
        ("bvol-search", || Box::new(BvolTree::new(false, 1))),
        ("sweep-and-prune", || Box::new(SweepAndPrune::default())),
        ("parry3d", || Box::new(Parry::default())),
    ];
    if n <= 20_000 {
        out.push(("brute-force", || Box::<BruteForce>::default()));
    }
    out
}

/// The digest of a frame's pairs, in whatever order a method keeps them.
pub fn digest_of(pairs: &[(u32, u32)]) -> PairDigest {
    PairDigest::of_pairs(pairs.iter().copied())
}

/// Runs every method over the same first frames and insists on equal pair sets.
pub fn check_agreement(kind: SceneKind, n: usize) {
    let mut scene = Scene::new(kind, n, 1);
    let frames: Vec<Vec<Aabb>> = (0..4).map(|_| scene.step().to_vec()).collect();
    let mut reference = None;
    for (name, make) in methods(n) {
        let mut method = make();
        let mut digest = PairDigest::default();
        for boxes in &frames {
            digest += digest_of(method.frame(boxes));
        }
        match reference {
            None => reference = Some((name, digest)),
            Some((first, d)) => assert_eq!(d, digest, "{kind}: {name} disagrees with {first}"),
        }
    }
}
