//! The persistent pair set: a tree's overlapping pairs kept across frames,
//! with the pairs that began and ended at each update.

use crate::{Bound, Tree, sort_pairs};

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
    starts: Vec<u32>,
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
        if !changes.few(tree.len()) {
            tree.pairs_into(&mut self.fresh);
            self.sort_fresh(tree.leaf_parents.len());
            diff(&self.pairs, &self.fresh, &mut self.ended, &mut self.began);
            std::mem::swap(&mut self.pairs, &mut self.fresh);
        } else {
            tree.changed_pairs(&mut self.fresh);
            self.sort_fresh(tree.leaf_parents.len());
            // The old pairs touching a changed leaf are the candidates to end
            // (moved aside, in order); the others are kept as they are.
            self.sorted.clear();
            changes.drop_touched(&mut self.pairs, |pair| self.sorted.push(pair));
            diff(&self.sorted, &self.fresh, &mut self.ended, &mut self.began);
            self.sorted.clear();
            merge(&self.pairs, &self.fresh, &mut self.sorted);
            std::mem::swap(&mut self.pairs, &mut self.sorted);
        }
        tree.changes.clear();
    }

    /// Sorts `fresh`, whose ids are below `ids`, by `(a, b)`.
    fn sort_fresh(&mut self, ids: usize) {
        sort_pairs(&self.fresh, ids, &mut self.starts, &mut self.sorted);
        std::mem::swap(&mut self.fresh, &mut self.sorted);
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
