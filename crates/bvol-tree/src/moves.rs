//! The per-leaf kernels of an update: finding which leaves moved, moving
//! them one by one, and reinserting those that jumped clear of their bound.

use rayon::prelude::*;

use crate::leaves::{in_run, in_run_asking};
use crate::node::{Ref, Slot};
use crate::tuning::{FAR_LEAVES, PASS_RUN, REMOVE_AHEAD, SIBLINGS_A_TASK};
use crate::update::UpdateStats;
use crate::{Bound, Move, Tree};

impl<B: Bound> Tree<B> {
    /// The ids `< bounds.len()` whose bound differs from the tree's, in node
    /// order: runs of nodes on rayon tasks, their lists joined in order.
    ///
    /// A tree of [`FAR_LEAVES`] or more leaves asks for the user's bounds
    /// of the leaves [`PREFETCH_AHEAD`](crate::tuning::PREFETCH_AHEAD)
    /// nodes on, as the refit does: their ids are in the user's order, and
    /// past the caches each read would wait on memory.
    pub(crate) fn scan(&self, bounds: &[B]) -> Vec<u32> {
        if self.root.is_leaf() {
            let id = self.root.index();
            let moved = bounds.get(id as usize).is_some_and(|b| *b != self.root_bound);
            return if moved { vec![id] } else { Vec::new() };
        }
        let far = self.len >= FAR_LEAVES;
        let parts: Vec<Vec<u32>> = self
            .node_runs(PASS_RUN)
            .map(|(nodes, parents)| match far {
                true => moved_among(in_run_asking(nodes, parents, bounds), bounds),
                false => moved_among(in_run(nodes, parents), bounds),
            })
            .collect();
        parts.concat()
    }

    /// The per-leaf path: each `(id, bound)` of `moved` updated on its own,
    /// as by [`Tree::set_bound`], then the bounded upkeep.
    pub(crate) fn move_each(
        &mut self,
        moved: impl ExactSizeIterator<Item = (u32, B)>,
        stats: &mut UpdateStats,
    ) {
        stats.moved = moved.len();
        for (id, bound) in moved {
            if self.move_leaf(id, bound) == Move::Reinserted {
                stats.reinserted += 1;
            }
            self.changes.mark(id);
        }
        stats.rebuilt = self.optimize();
    }

    /// Gives the leaves that `jumped` the new bounds a refit held back.
    pub(crate) fn place_jumped(&mut self, jumped: &[(u32, B)]) {
        for &(id, bound) in jumped {
            let p = self.leaf_parents[id as usize];
            let node = &mut self.nodes[p as usize];
            node.set_bound(node.side_of(Ref::leaf(id)), bound);
        }
    }

    /// Reinserts the leaves placed where they no longer are: this frame's
    /// `jumped`, with their new bounds (the refit kept their old), and the
    /// `stale` ids of an install, sorted, that are not among them. All are
    /// taken out before any goes back: inserted while others still stretch
    /// their ancestors, each would be placed by bounds that are not there,
    /// and the tree would end far costlier than a fresh build.
    pub(crate) fn reinsert(&mut self, jumped: &[(u32, B)], stale: &[u32], stats: &mut UpdateStats) {
        // This frame's jumps, sorted, to tell the stale leaves among them:
        // only an install has stale leaves.
        let mut now: Vec<u32> = Vec::new();
        if !stale.is_empty() {
            now.extend(jumped.iter().map(|j| j.0));
            now.sort_unstable();
        }
        let ids: Vec<u32> = jumped.iter().map(|j| j.0).chain(stale.iter().copied()).collect();
        let mut out = jumped.to_vec();
        for (k, &id) in ids.iter().enumerate() {
            if let Some(&later) = ids.get(k + REMOVE_AHEAD) {
                self.leaves().prefetch(later);
            }
            // A jump keeps its new bound; a stale leaf keeps the one it has.
            if k < jumped.len() {
                self.remove_leaf(id);
            } else if now.binary_search(&id).is_err() {
                out.push((id, self.remove_leaf(id)));
            }
        }
        if out.is_empty() {
            return;
        }
        if self.root == Ref::NONE {
            // An emptied tree (a handful of leaves, all taken out) is
            // refilled one by one, each placed among those before it.
            for &(id, bound) in &out {
                self.insert_leaf(id, bound, &bound);
            }
        } else {
            self.insert_all(&out);
        }
        stats.reinserted += out.len();
    }

    /// Inserts the leaves `out` (with their bounds) into a tree that is not
    /// empty. Where each goes is looked for on rayon tasks, in the tree
    /// without any of them: a leaf's search reads only the tree, and it
    /// would otherwise run on one thread while the others wait. A slot
    /// another took first still holds (the new node there covers what it
    /// held), so the tree is valid, and the same on any number of threads.
    fn insert_all(&mut self, out: &[(u32, B)]) {
        let slots: Vec<Slot> = out
            .par_iter()
            .with_min_len(SIBLINGS_A_TASK)
            .map(|(_, bound)| self.find_best_sibling(bound))
            .collect();
        // The new nodes take the free ones in an order that a refit over
        // the node array meets children first ([`Tree::alloc_node_among`]).
        let mut spare = self.take_free();
        for (&(id, bound), slot) in out.iter().zip(slots) {
            self.insert_leaf_at(id, bound, &bound, slot, Some(&mut spare));
        }
        for &x in spare.iter().rev() {
            self.free_node(x);
        }
    }
}

/// The ids among `leaves` (with the tree's bounds) `< bounds.len()` whose
/// bound there differs, in order.
fn moved_among<B: Bound>(leaves: impl Iterator<Item = (Ref, B)>, bounds: &[B]) -> Vec<u32> {
    let moved = leaves.filter(|(c, b)| bounds.get(c.index() as usize).is_some_and(|new| new != b));
    moved.map(|(c, _)| c.index()).collect()
}

#[cfg(test)]
mod tests {
    use bvol_volumes::Aabb;
    use glam::Vec3;

    use super::*;

    /// A scan of a tree large enough to ask for bounds ahead finds exactly
    /// the leaves whose bound changed, by id, on one thread and two alike.
    #[test]
    fn a_scan_asking_ahead_finds_the_leaves_that_moved() {
        let n = FAR_LEAVES as u32;
        // A 512-wide grid of unit cubes; the ids spread over it by a
        // multiplier prime to the count, so that the tree's order is not
        // theirs.
        let cube = |id: u32| {
            let cell = id.wrapping_mul(40_503) % n;
            let at = Vec3::new((cell % 512) as f32, (cell / 512) as f32, 0.0);
            Aabb::new(at, at + Vec3::ONE)
        };
        let bounds: Vec<Aabb> = (0..n).map(cube).collect();
        let tree = Tree::from_bounds(&bounds).unwrap();
        let mut next = bounds.clone();
        for id in (0..n).step_by(97) {
            next[id as usize].max.x += 0.25;
        }
        // In increasing order, as the found ids are put in to compare.
        let want: Vec<u32> =
            (0..n).filter(|&id| next[id as usize] != bounds[id as usize]).collect();
        assert_eq!(want.len(), (n as usize).div_ceil(97));
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let mut found = pool.install(|| tree.scan(&next));
            found.sort_unstable();
            assert_eq!(found, want, "{threads} threads");
        }
        // Ids past the slice are left out, not read.
        let mut short = tree.scan(&next[..1000]);
        short.sort_unstable();
        assert_eq!(short, want.iter().copied().filter(|&id| id < 1000).collect::<Vec<_>>());
    }
}
