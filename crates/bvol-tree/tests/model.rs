//! Model-based property tests: random sequences of tree operations, checked
//! after every step against a plain list of (id, bound) and brute force.

mod common;

use bvol_tree::{Config, Move, PairCache, PairSet, Tree, TreeError};
use bvol_volumes::{Aabb, Ray, Sphere};
use common::{Mix, TestBound, any_bound, brute_cross, brute_pairs, brute_ray};
use glam::Vec3;
use proptest::prelude::*;

/// Ids range over `0..IDS`.
const IDS: u32 = 40;

#[derive(Clone, Debug)]
enum Op<B> {
    Insert(u32, B),
    /// Several at once (ids may repeat, or be in the tree already).
    InsertMany(Vec<(u32, B)>),
    Remove(u32),
    /// A small move: shifted by half grid steps.
    Nudge(u32, [i8; 3]),
    /// A new bound anywhere (a teleport when it lands clear of the old one).
    Set(u32, B),
    /// A frame update over ids `0..len`: each present leaf moves with
    /// probability `percent`%, a tenth of those teleport; absent ids are new.
    Frame {
        len: u32,
        percent: u8,
        seed: u64,
    },
    /// The leaves that moved handed over by id: each present leaf moves
    /// with probability `percent`%, a tenth of those teleport.
    Moved {
        percent: u8,
        seed: u64,
    },
    /// A frame update over a slice of ids `0..len` that also holds ids not
    /// in the tree (their entries not valid bounds, which must not be
    /// read): each present leaf moves with probability `percent`%, a tenth
    /// of those teleport.
    From {
        len: u32,
        percent: u8,
        seed: u64,
    },
    Rebuild,
    Refit,
    Optimize,
    /// Queries that change nothing.
    Region(B),
    Cast {
        origin: [i8; 3],
        direction: [i8; 3],
        max_t: Option<u8>,
    },
    Cross(Vec<B>),
    /// Brings the pair set up to date (it may skip several steps).
    Sync,
}

fn op<B: TestBound>() -> impl Strategy<Value = Op<B>> {
    let id = 0..IDS;
    let small = prop::array::uniform3(-3i8..=3);
    prop_oneof![
        6 => (id.clone(), any_bound::<B>()).prop_map(|(i, b)| Op::Insert(i, b)),
        2 => prop::collection::vec((id.clone(), any_bound::<B>()), 0..24).prop_map(Op::InsertMany),
        2 => id.clone().prop_map(Op::Remove),
        6 => (id.clone(), small).prop_map(|(i, d)| Op::Nudge(i, d)),
        2 => (id.clone(), any_bound::<B>()).prop_map(|(i, b)| Op::Set(i, b)),
        3 => (0..=IDS, 0u8..=100, any::<u64>()).prop_map(|(len, percent, seed)| Op::Frame { len, percent, seed }),
        3 => (0u8..=100, any::<u64>()).prop_map(|(percent, seed)| Op::Moved { percent, seed }),
        3 => (0..=IDS, 0u8..=100, any::<u64>()).prop_map(|(len, percent, seed)| Op::From { len, percent, seed }),
        1 => Just(Op::Rebuild),
        1 => Just(Op::Refit),
        1 => Just(Op::Optimize),
        1 => any_bound::<B>().prop_map(Op::Region),
        1 => (prop::array::uniform3(-4i8..16), prop::array::uniform3(-3i8..=3), prop::option::of(0u8..20))
            .prop_map(|(origin, direction, max_t)| Op::Cast { origin, direction, max_t }),
        1 => prop::collection::vec(any_bound::<B>(), 0..12).prop_map(Op::Cross),
        6 => Just(Op::Sync),
    ]
}

/// A leaf's bound after a random move: mostly a small shift, a tenth of the
/// time a jump far away.
fn moved<B: TestBound>(b: B, rng: &mut Mix) -> B {
    if rng.below(10) == 0 {
        b.shifted(Vec3::new(rng.range(-40.0, 40.0), rng.range(-40.0, 40.0), 0.0))
    } else {
        b.shifted(Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)))
    }
}

fn config() -> impl Strategy<Value = Config> {
    (
        prop_oneof![Just(0.0f32), Just(0.1), Just(0.5)],
        prop_oneof![Just(0.0f32), Just(2.0)],
        prop_oneof![Just(0.0f32), Just(0.3), Just(2.0)],
        prop_oneof![Just(0.0f64), Just(0.3), Just(1e9)],
        prop_oneof![Just(2usize), Just(5), Just(4096)],
    )
        .prop_map(|(fat_size, fat_motion, refit_fraction, drift, rebuild_budget)| Config {
            fat_size,
            fat_motion,
            refit_fraction,
            drift,
            rebuild_budget,
        })
}

/// The tree and its model side by side.
struct Check<B: TestBound> {
    tree: Tree<B>,
    model: Vec<Option<B>>,
    set: PairSet,
    cache: PairCache,
    last: Vec<(u32, u32)>,
}

impl<B: TestBound> Check<B> {
    fn new(config: Config) -> Self {
        Check {
            tree: Tree::with_config(config),
            model: vec![None; IDS as usize],
            set: PairSet::new(),
            cache: PairCache::new(),
            last: Vec::new(),
        }
    }

    fn leaves(&self) -> Vec<(u32, B)> {
        self.model.iter().enumerate().filter_map(|(i, b)| b.map(|b| (i as u32, b))).collect()
    }

    fn apply(&mut self, op: &Op<B>) -> Result<(), TestCaseError> {
        match op {
            Op::Insert(id, b) => {
                let got = self.tree.insert(*id, *b);
                if self.model[*id as usize].is_some() {
                    prop_assert_eq!(got, Err(TreeError::DuplicateId { id: *id }));
                } else {
                    prop_assert_eq!(got, Ok(()));
                    self.model[*id as usize] = Some(*b);
                }
            }
            Op::InsertMany(leaves) => {
                // The first id already in the tree, else the first given twice.
                let present = leaves.iter().find(|l| self.model[l.0 as usize].is_some());
                let twice =
                    (1..leaves.len()).find(|&k| leaves[..k].iter().any(|l| l.0 == leaves[k].0));
                let want = match (present, twice) {
                    (Some(&(id, _)), _) => Err(TreeError::DuplicateId { id }),
                    (None, Some(k)) => Err(TreeError::DuplicateId { id: leaves[k].0 }),
                    (None, None) => Ok(()),
                };
                let len = self.tree.len();
                prop_assert_eq!(self.tree.insert_many(leaves), want);
                if want.is_ok() {
                    leaves.iter().for_each(|&(id, b)| self.model[id as usize] = Some(b));
                } else {
                    prop_assert_eq!(self.tree.len(), len);
                }
            }
            Op::Remove(id) => {
                let got = self.tree.remove(*id);
                match self.model[*id as usize].take() {
                    Some(b) => prop_assert_eq!(got, Ok(b)),
                    None => prop_assert_eq!(got, Err(TreeError::UnknownId { id: *id })),
                }
            }
            Op::Nudge(id, d) => {
                let d = Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32) * 0.5;
                self.set_bound(*id, |b| b.shifted(d))?;
            }
            Op::Set(id, b) => self.set_bound(*id, |_| *b)?,
            Op::Frame { len, percent, seed } => self.frame(*len, *percent, *seed)?,
            Op::Moved { percent, seed } => self.moved(*percent, *seed)?,
            Op::From { len, percent, seed } => self.from(*len, *percent, *seed)?,
            Op::Rebuild => self.tree.rebuild(),
            Op::Refit => self.tree.refit(),
            Op::Optimize => {
                self.tree.optimize();
            }
            Op::Region(region) => {
                let mut got = Vec::new();
                self.tree.query(region, |id| got.push(id));
                got.sort_unstable();
                let want: Vec<u32> =
                    self.leaves().iter().filter(|(_, b)| b.touch(region)).map(|l| l.0).collect();
                prop_assert_eq!(got, want);
            }
            Op::Cast { origin, direction, max_t } => self.cast(origin, direction, *max_t)?,
            Op::Sync => self.sync()?,
            Op::Cross(other) => {
                let stat = Tree::from_bounds(other).unwrap();
                let theirs: Vec<(u32, B)> =
                    other.iter().enumerate().map(|(i, b)| (i as u32, *b)).collect();
                let mut got = self.tree.pairs_with(&stat);
                got.sort_unstable();
                prop_assert_eq!(&got, &brute_cross(&self.leaves(), &theirs));
                let mut back = stat.pairs_with(&self.tree);
                back.sort_unstable();
                prop_assert_eq!(back, brute_cross(&theirs, &self.leaves()));
            }
        }
        self.check()
    }

    /// `set_bound` against the model, including its reported outcome.
    fn set_bound(&mut self, id: u32, new: impl Fn(&B) -> B) -> Result<(), TestCaseError> {
        match self.model[id as usize] {
            None => {
                let got = self.tree.set_bound(id, new(&B::default()));
                prop_assert_eq!(got, Err(TreeError::UnknownId { id }));
            }
            Some(old) => {
                let b = new(&old);
                let got = self.tree.set_bound(id, b).unwrap();
                prop_assert_eq!(got == Move::Unchanged, b == old);
                self.model[id as usize] = Some(b);
            }
        }
        Ok(())
    }

    fn frame(&mut self, len: u32, percent: u8, seed: u64) -> Result<(), TestCaseError> {
        let mut rng = Mix(seed);
        let bounds: Vec<B> = (0..len as usize)
            .map(|i| match self.model[i] {
                Some(b) if rng.below(100) < percent as u64 => moved(b, &mut rng),
                Some(b) => b,
                None => B::make(
                    Vec3::new(rng.range(0.0, 12.0), rng.range(0.0, 12.0), rng.range(0.0, 12.0)),
                    Vec3::splat(rng.range(0.0, 3.0)),
                ),
            })
            .collect();
        let frame = self.tree.update(&bounds).unwrap();
        let inserted = self.model[..len as usize].iter().filter(|b| b.is_none()).count();
        prop_assert_eq!(frame.inserted, inserted);
        for (i, b) in bounds.iter().enumerate() {
            self.model[i] = Some(*b);
        }
        Ok(())
    }

    fn moved(&mut self, percent: u8, seed: u64) -> Result<(), TestCaseError> {
        let mut rng = Mix(seed);
        let mut moves = Vec::new();
        for (i, b) in self.model.iter().enumerate() {
            if let Some(b) = b
                && rng.below(100) < percent as u64
            {
                moves.push((i as u32, moved(*b, &mut rng)));
            }
        }
        let frame = self.tree.update_moved(&moves).unwrap();
        prop_assert_eq!(frame.moved, moves.len());
        for (id, b) in moves {
            self.model[id as usize] = Some(b);
        }
        // An absent id is an error that changes nothing.
        if let Some(absent) = (0..IDS).find(|&i| self.model[i as usize].is_none()) {
            let any = B::make(Vec3::ZERO, Vec3::ONE);
            prop_assert!(self.tree.update_moved(&[(absent, any)]).is_err());
        }
        Ok(())
    }

    fn from(&mut self, len: u32, percent: u8, seed: u64) -> Result<(), TestCaseError> {
        let mut rng = Mix(seed);
        let not_valid = B::make(Vec3::NAN, Vec3::ONE);
        let bounds: Vec<B> = (0..len as usize)
            .map(|i| match self.model[i] {
                Some(b) if rng.below(100) < percent as u64 => moved(b, &mut rng),
                Some(b) => b,
                None => not_valid,
            })
            .collect();
        // A present leaf's bound not valid: an error naming it, and nothing
        // changes (the check after the step compares the tree with the model).
        if let Some(id) = (0..len).find(|&i| self.model[i as usize].is_some()) {
            let mut bad = bounds.clone();
            bad[id as usize] = not_valid;
            let named = match self.tree.update_from(&bad) {
                Err(TreeError::InvalidBound { id, .. }) => Some(id),
                _ => None,
            };
            prop_assert_eq!(named, Some(id));
        }
        let frame = self.tree.update_from(&bounds).unwrap();
        let changed =
            (0..len as usize).filter(|&i| self.model[i].is_some_and(|b| b != bounds[i])).count();
        prop_assert_eq!(frame.inserted, 0);
        prop_assert_eq!(frame.moved, changed);
        for (i, b) in bounds.iter().enumerate() {
            if self.model[i].is_some() {
                self.model[i] = Some(*b);
            }
        }
        Ok(())
    }

    fn cast(
        &self,
        origin: &[i8; 3],
        direction: &[i8; 3],
        max_t: Option<u8>,
    ) -> Result<(), TestCaseError> {
        let v = |a: &[i8; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
        let ray = Ray::new(v(origin), v(direction));
        let max_t = max_t.map_or(f32::INFINITY, f32::from);
        let want = brute_ray(&self.leaves(), &ray, max_t);
        let mut all = Vec::new();
        self.tree.ray_cast_all(&ray, max_t, |id, t| all.push((id, t)));
        all.sort_unstable_by_key(|h| h.0);
        prop_assert_eq!(&all, &want);
        // Nearest by bound; then with a callback that misses odd ids and puts
        // even ids' bodies a little behind their bounds' entry.
        let nearest = |hits: &[(u32, f32)]| {
            hits.iter().copied().min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
        };
        prop_assert_eq!(self.tree.ray_cast(&ray, max_t, |_, t| Some(t)), nearest(&want));
        let body = |id: u32, t: f32| id.is_multiple_of(2).then_some(t + id as f32 * 0.25);
        let bodies: Vec<(u32, f32)> = want
            .iter()
            .filter_map(|&(id, t)| body(id, t).filter(|&d| d <= max_t).map(|d| (id, d)))
            .collect();
        prop_assert_eq!(self.tree.ray_cast(&ray, max_t, body), nearest(&bodies));
        Ok(())
    }

    /// Everything the tree says, against the model.
    fn check(&mut self) -> Result<(), TestCaseError> {
        if let Err(v) = self.tree.validate() {
            return Err(TestCaseError::fail(format!("invalid tree: {v}")));
        }
        let leaves = self.leaves();
        prop_assert_eq!(self.tree.len(), leaves.len());
        for id in 0..IDS {
            prop_assert_eq!(self.tree.bound(id), self.model[id as usize]);
        }
        self.check_nodes()?;
        let want = brute_pairs(&leaves);
        let mut got = self.tree.pairs();
        prop_assert!(got.iter().all(|(a, b)| a < b));
        got.sort_unstable();
        prop_assert_eq!(&got, &want);
        Ok(())
    }

    /// `visit_nodes`: one visit per internal node (a binary tree over n
    /// leaves has n - 1), the root first at depth 0, at most 2^d nodes at
    /// depth d, every node inside the root's bound.
    fn check_nodes(&self) -> Result<(), TestCaseError> {
        let mut visits = Vec::new();
        self.tree.visit_nodes(|depth, bound| visits.push((depth, *bound)));
        prop_assert_eq!(visits.len(), self.tree.len().saturating_sub(1));
        if let Some(&(depth, bound)) = visits.first() {
            prop_assert_eq!(depth, 0);
            prop_assert_eq!(Some(bound), self.tree.root_bound());
            let mut per_depth = vec![0usize; visits.len()];
            for (depth, b) in &visits {
                per_depth[*depth] += 1;
                prop_assert!(bound.contains(b));
            }
            prop_assert!(per_depth.iter().enumerate().all(|(d, &k)| k <= 1 << d.min(40)));
        }
        Ok(())
    }

    /// The pair set and the pair cache against the brute-force pairs now,
    /// and the set's events against the difference from the pairs at the
    /// previous sync. The cache reads a copy of the tree, whose change log
    /// is the same as the set's.
    fn sync(&mut self) -> Result<(), TestCaseError> {
        let want = brute_pairs(&self.leaves());
        let mut copy = self.tree.clone();
        self.cache.update(&mut copy);
        let mut cached = self.cache.pairs().to_vec();
        cached.sort_unstable();
        prop_assert_eq!(&cached, &want);
        self.set.update(&mut self.tree);
        prop_assert_eq!(self.set.pairs(), &want[..]);
        let began: Vec<_> =
            want.iter().filter(|p| self.last.binary_search(p).is_err()).copied().collect();
        let ended: Vec<_> =
            self.last.iter().filter(|p| want.binary_search(p).is_err()).copied().collect();
        prop_assert_eq!(self.set.began(), &began[..]);
        prop_assert_eq!(self.set.ended(), &ended[..]);
        self.last = want;
        Ok(())
    }
}

fn run<B: TestBound>(config: Config, ops: &[Op<B>]) -> Result<(), TestCaseError> {
    let mut check = Check::<B>::new(config);
    for op in ops {
        check.apply(op)?;
    }
    check.sync()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8000))]

    #[test]
    fn aabb_tree_matches_brute_force(config in config(), ops in prop::collection::vec(op::<Aabb>(), 1..60)) {
        run(config, &ops)?;
    }

    #[test]
    fn sphere_tree_matches_brute_force(config in config(), ops in prop::collection::vec(op::<Sphere>(), 1..60)) {
        run(config, &ops)?;
    }
}
