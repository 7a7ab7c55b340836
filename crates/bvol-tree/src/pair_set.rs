//! The persistent pair set: a tree's overlapping pairs kept across frames,
//! with the pairs that began and ended at each update.

use rayon::prelude::*;

use crate::{Bound, Tree};

/// Changed ids per task of the incremental path.
const CHUNK: usize = 256;
/// Above this fraction of changed leaves, an update recomputes every pair
/// (one tree self-search) instead of querying each changed leaf: the
/// queries' cost grows with the leaves changed, and reaches the full
/// search's a little above this fraction (chosen by measurement on
/// `benches/frame.rs`).
const FULL_FRACTION: f32 = 0.15;

/// The overlapping pairs of one [`Tree`], kept up to date frame to frame,
/// with the pairs that began and ended at the last update. All three lists
/// are sorted, pairs `(a, b)` with `a < b`.
///
/// [`PairSet::update`] reads the tree's change log (ids inserted, moved or
/// removed since the last update) and retests only pairs touching those ids;
/// pairs between unchanged leaves are kept without a test. When many leaves
/// changed it recomputes all pairs instead, which is then cheaper.
///
/// ```
/// use bvol_tree::{PairSet, Tree};
/// use bvol_volumes::Aabb;
/// use glam::Vec3;
///
/// let at = |x: f32| Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0));
/// let mut tree = Tree::from_bounds(&[at(0.0), at(0.5), at(3.0)])?;
/// let mut pairs = PairSet::new();
/// pairs.update(&mut tree);
/// assert_eq!((pairs.pairs(), pairs.began()), (&[(0, 1)][..], &[(0, 1)][..]));
/// tree.set_bound(2, at(1.0))?; // now touches 0 and 1
/// pairs.update(&mut tree);
/// assert_eq!(pairs.began(), &[(0, 2), (1, 2)]);
/// tree.set_bound(0, at(-5.0))?; // leaves 1 and 2
/// pairs.update(&mut tree);
/// assert_eq!(pairs.ended(), &[(0, 1), (0, 2)]);
/// assert_eq!(pairs.pairs(), &[(1, 2)]);
/// # Ok::<(), bvol_tree::TreeError>(())
/// ```
#[derive(Clone, Debug, Default)]
pub struct PairSet {
    pairs: Vec<(u32, u32)>,
    began: Vec<(u32, u32)>,
    ended: Vec<(u32, u32)>,
    /// Reused buffers: the new pairs of an update, and scratch for sorting
    /// and merging.
    fresh: Vec<(u32, u32)>,
    sorted: Vec<(u32, u32)>,
    starts: Vec<usize>,
}

impl PairSet {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// The current pairs, sorted.
    pub fn pairs(&self) -> &[(u32, u32)] {
        &self.pairs
    }

    /// The pairs that began at the last update, sorted.
    pub fn began(&self) -> &[(u32, u32)] {
        &self.began
    }

    /// The pairs that ended at the last update, sorted.
    pub fn ended(&self) -> &[(u32, u32)] {
        &self.ended
    }

    /// Brings the set up to date with `tree` and clears the tree's change
    /// log. Deterministic: the same lists whatever the thread count.
    pub fn update<B: Bound>(&mut self, tree: &mut Tree<B>) {
        let changes = &tree.changes;
        let full = changes.all() || changes.ids().len() as f32 > FULL_FRACTION * tree.len() as f32;
        if full {
            tree.pairs_into(&mut self.fresh);
            self.sort_fresh();
            diff(&self.pairs, &self.fresh, &mut self.ended, &mut self.began);
            std::mem::swap(&mut self.pairs, &mut self.fresh);
        } else {
            self.changed_pairs(tree);
            // The old pairs touching a changed leaf are the candidates to end
            // (moved aside, in order); the others are kept as they are.
            self.sorted.clear();
            self.pairs.retain(|&(a, b)| {
                let touched = changes.is_marked(a) || changes.is_marked(b);
                if touched {
                    self.sorted.push((a, b));
                }
                !touched
            });
            diff(&self.sorted, &self.fresh, &mut self.ended, &mut self.began);
            self.sorted.clear();
            merge(&self.pairs, &self.fresh, &mut self.sorted);
            std::mem::swap(&mut self.pairs, &mut self.sorted);
        }
        tree.changes.clear();
    }

    /// Fills `fresh`, sorted, with the pairs that touch a changed leaf: each
    /// changed leaf queries the tree, and a pair of two changed leaves is kept
    /// from the query of the smaller id only.
    fn changed_pairs<B: Bound>(&mut self, tree: &Tree<B>) {
        let changes = &tree.changes;
        let parts: Vec<Vec<(u32, u32)>> = changes
            .ids()
            .par_chunks(CHUNK)
            .map(|ids| {
                let mut found = Vec::new();
                for &id in ids {
                    let Some(bound) = tree.bound(id) else { continue };
                    tree.query(&bound, |other| {
                        if other != id && (!changes.is_marked(other) || id < other) {
                            found.push((id.min(other), id.max(other)));
                        }
                    });
                }
                found
            })
            .collect();
        self.fresh.clear();
        for part in parts {
            self.fresh.extend_from_slice(&part);
        }
        self.sort_fresh();
    }

    /// Sorts `fresh` by `(a, b)`: two stable counting sorts, on `b` then on
    /// `a` (an LSD radix sort with one digit per id). O(pairs + largest id),
    /// against O(p log p) for a comparison sort; the buffers are kept, so a
    /// frame allocates nothing.
    fn sort_fresh(&mut self) {
        let Some(top) = self.fresh.iter().map(|p| p.1).max() else { return };
        for key in [|p: &(u32, u32)| p.1, |p: &(u32, u32)| p.0] {
            let starts = &mut self.starts;
            starts.clear();
            starts.resize(top as usize + 2, 0);
            for p in &self.fresh {
                starts[key(p) as usize + 1] += 1;
            }
            for i in 1..starts.len() {
                starts[i] += starts[i - 1];
            }
            self.sorted.clear();
            self.sorted.resize(self.fresh.len(), (0, 0));
            for p in &self.fresh {
                let slot = &mut starts[key(p) as usize];
                self.sorted[*slot] = *p;
                *slot += 1;
            }
            std::mem::swap(&mut self.fresh, &mut self.sorted);
        }
    }
}

/// Given sorted `old` and `new`, fills `gone` with `old \ new` and `come`
/// with `new \ old`, both sorted.
fn diff(
    old: &[(u32, u32)],
    new: &[(u32, u32)],
    gone: &mut Vec<(u32, u32)>,
    come: &mut Vec<(u32, u32)>,
) {
    gone.clear();
    come.clear();
    let (mut i, mut j) = (0, 0);
    while i < old.len() && j < new.len() {
        match old[i].cmp(&new[j]) {
            std::cmp::Ordering::Less => {
                gone.push(old[i]);
                i += 1;
            }
            std::cmp::Ordering::Greater => {
                come.push(new[j]);
                j += 1;
            }
            std::cmp::Ordering::Equal => {
                i += 1;
                j += 1;
            }
        }
    }
    gone.extend_from_slice(&old[i..]);
    come.extend_from_slice(&new[j..]);
}

/// Merges two sorted, disjoint lists, appending to `out`.
fn merge(a: &[(u32, u32)], b: &[(u32, u32)], out: &mut Vec<(u32, u32)>) {
    out.reserve(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if a[i] < b[j] {
            out.push(a[i]);
            i += 1;
        } else {
            out.push(b[j]);
            j += 1;
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
}
