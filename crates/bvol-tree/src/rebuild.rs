//! Whole-tree construction: batch builds for level loads, full rebuilds,
//! and the install of a rebuild staged over frames.

use std::sync::atomic::{AtomicU32, Ordering};

use rayon::prelude::*;

use crate::build::Atom;
use crate::check::{check_bound, check_id};
use crate::error::TreeError;
use crate::leaves::in_run;
use crate::morton::{Clusters, build_morton};
use crate::node::{NONE, Node, ROOT, Ref};
use crate::tuning::{PASS_RUN, PREFETCH_AHEAD};
use crate::{Bound, Config, Tree, one_thread};

impl<B: Bound> Tree<B> {
    /// A tree over `bounds`, leaf `i` holding `bounds[i]` (ids `0..len`),
    /// built in one go with binned SAH: the way to load a level.
    pub fn from_bounds(bounds: &[B]) -> Result<Self, TreeError> {
        Self::build(Config::default(), bounds.iter().enumerate().map(|(i, b)| (i as u32, *b)))
    }

    /// A tree over `(id, bound)` leaves, built in one go with binned SAH
    /// (parallel with rayon; the same tree whatever the thread count).
    pub fn build(
        config: Config,
        leaves: impl IntoIterator<Item = (u32, B)>,
    ) -> Result<Self, TreeError> {
        let mut tree = Self::with_config(config);
        let mut atoms = Vec::new();
        for (id, bound) in leaves {
            check_id(id)?;
            check_bound(id, &bound)?;
            tree.grow_ids(id);
            if tree.leaf_parents[id as usize] != NONE {
                return Err(TreeError::DuplicateId { id });
            }
            tree.leaf_parents[id as usize] = ROOT; // claimed; set for real below
            tree.changes.mark(id);
            atoms.push(Atom::new(Ref::leaf(id), bound));
        }
        tree.len = atoms.len();
        tree.install(&mut atoms, Clusters::BySah);
        Ok(tree)
    }

    /// Adds many leaves at once: `leaves[k]` is `(id, bound)`. When they are
    /// at least as many as the leaves already in the tree, the whole tree is
    /// built again over old and new in one go, as by [`Tree::build`]: a level
    /// load costs one batch build instead of one insertion each, a fraction
    /// of their time, and the batch-built tree is better than one grown by
    /// insertions, so the updates that follow cost less too. Fewer are
    /// inserted one by one, as by [`Tree::insert`].
    ///
    /// Every id and bound is checked first: on error (a bad bound, an id out
    /// of range, already in the tree or given twice) nothing has changed.
    ///
    /// ```
    /// use bvol_tree::Tree;
    /// use bvol_volumes::Aabb;
    /// use glam::Vec3;
    /// let unit = |x: f32| Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0));
    /// let mut tree = Tree::new();
    /// tree.insert_many(&[(4, unit(0.0)), (9, unit(0.5)), (2, unit(5.0))])?;
    /// assert_eq!(tree.pairs(), vec![(4, 9)]);
    /// assert!(tree.insert_many(&[(7, unit(9.0)), (7, unit(9.0))]).is_err());
    /// assert_eq!(tree.len(), 3);
    /// # Ok::<(), bvol_tree::TreeError>(())
    /// ```
    pub fn insert_many(&mut self, leaves: &[(u32, B)]) -> Result<(), TreeError> {
        for &(id, bound) in leaves {
            check_id(id)?;
            check_bound(id, &bound)?;
            if self.contains(id) {
                return Err(TreeError::DuplicateId { id });
            }
        }
        // The id whose second mention comes first, if any.
        let mut order: Vec<(u32, usize)> = (0..).zip(leaves).map(|(k, l)| (l.0, k)).collect();
        order.sort_unstable();
        if let Some(k) = order.windows(2).filter(|w| w[0].0 == w[1].0).map(|w| w[1].1).min() {
            return Err(TreeError::DuplicateId { id: leaves[k].0 });
        }
        if leaves.len() < self.len {
            for &(id, bound) in leaves {
                self.insert(id, bound)?; // checked above: cannot fail
            }
            return Ok(());
        }
        let mut atoms = if self.is_empty() { Vec::new() } else { self.leaf_atoms() };
        atoms.reserve(leaves.len());
        for &(id, bound) in leaves {
            self.grow_ids(id);
            self.changes.mark(id);
            atoms.push(Atom::new(Ref::leaf(id), bound));
        }
        self.len += leaves.len();
        self.install(&mut atoms, Clusters::BySah);
        Ok(())
    }

    /// Rebuilds the whole tree from its leaves' tight bounds with binned SAH.
    /// O(n log n) in one call: for loads and tests. Per frame, use
    /// [`Tree::update`] or [`Tree::optimize`], whose work is bounded.
    pub fn rebuild(&mut self) {
        self.rebuild_with(Clusters::BySah);
    }

    /// Rebuilds the whole tree, its clusters finished as `finish` says.
    pub(crate) fn rebuild_with(&mut self, finish: Clusters) {
        let mut atoms = self.leaf_atoms();
        self.install(&mut atoms, finish);
    }

    /// Every leaf as an atom with its tight bound, in node order: runs of
    /// nodes on rayon tasks, each writing its leaves' atoms in place after
    /// the earlier runs' (whose leaves are counted first). The same atoms
    /// on any number of threads.
    fn leaf_atoms(&self) -> Vec<Atom<B>> {
        if self.root.is_leaf() {
            return vec![Atom::new(self.root, self.root_bound)];
        }
        // On one thread, one run, whose leaves are all the tree's: no count.
        let (size, counts): (_, Vec<usize>) = match one_thread() {
            true => (self.nodes.len().max(1), vec![self.len]),
            false => (PASS_RUN, self.leaves_a_run()),
        };
        let n = counts.iter().sum();
        let mut atoms = Vec::with_capacity(n);
        let mut rest = &mut atoms.spare_capacity_mut()[..n];
        let mut pieces = Vec::with_capacity(counts.len());
        for count in counts {
            let (piece, tail) = std::mem::take(&mut rest).split_at_mut(count);
            pieces.push(piece);
            rest = tail;
        }
        let written: usize = self
            .node_runs(size)
            .zip(pieces)
            .map(|((nodes, parents), piece)| {
                let atoms = in_run(nodes, parents).map(|(c, b)| Atom::new(c, b));
                piece.iter_mut().zip(atoms).map(|(p, a)| p.write(a)).count()
            })
            .sum();
        assert_eq!(written, n, "a run gave other leaves than it counted");
        // SAFETY: the first `n` atoms are written: each run wrote as many
        // as its piece holds (the leaves it counted), and the pieces tile
        // them.
        unsafe { atoms.set_len(n) };
        atoms
    }

    /// How many leaves have their parent in each run of [`PASS_RUN`] nodes,
    /// counted from the leaves' parent links on rayon tasks: four bytes a
    /// leaf, where counting them in the nodes read every node once more.
    fn leaves_a_run(&self) -> Vec<usize> {
        let nodes = self.nodes.len();
        let runs = nodes.div_ceil(PASS_RUN);
        let count = |links: &[u32]| {
            let mut counts = vec![0; runs];
            // Ids not in the tree have no parent node (`NONE`).
            for &p in links.iter().filter(|&&p| (p as usize) < nodes) {
                counts[p as usize / PASS_RUN] += 1;
            }
            counts
        };
        let add = |mut a: Vec<usize>, b: Vec<usize>| {
            a.iter_mut().zip(b).for_each(|(a, b)| *a += b);
            a
        };
        self.leaf_parents.par_chunks(PASS_RUN).map(count).reduce(|| vec![0; runs], add)
    }

    /// Replaces every node by a fresh build over `atoms` (all of them leaves),
    /// in preorder from node 0, with no free nodes, its clusters finished as
    /// `finish` says.
    pub(crate) fn install(&mut self, atoms: &mut Vec<Atom<B>>, finish: Clusters) {
        self.free = Ref::NONE;
        self.free_count = 0;
        match atoms.as_slice() {
            [] => {
                self.resize_nodes(0);
                self.root = Ref::NONE;
            }
            &[one] => {
                self.resize_nodes(0);
                self.root = one.r;
                self.root_bound = one.bound;
                self.set_parent(one.r, ROOT);
            }
            _ => {
                self.resize_nodes(atoms.len() - 1);
                self.root_bound = build_morton(atoms, &mut self.nodes, finish);
                self.root = Ref::node(0);
                self.relink_all();
            }
        }
        self.policy.rebuilt(self.sah_cost());
        self.preorder = true;
    }

    /// Installs a staged rebuild's `topology` (each internal node's
    /// children, in preorder from the root) in place of every node, each
    /// leaf keeping its bound; a refit must follow, for the internal nodes'.
    /// The topology holds every leaf (an insert or a removal drops it): as
    /// many internal nodes as the tree has in use, at most its array.
    pub(crate) fn install_topology(&mut self, topology: &[[Ref; 2]]) {
        debug_assert_eq!(topology.len() + 1, self.len);
        // Each leaf's bound, gathered in node order (a sequential read) and
        // found again by the place noted in its parent link: the nodes are
        // then overwritten in place, in preorder, from the topology. Read by
        // id from the old nodes instead, the bounds would come scattered,
        // and a fresh node array would fault its pages in.
        let mut held = Vec::with_capacity(self.len);
        for (c, bound) in in_run(&self.nodes, &self.parents) {
            self.leaf_parents[c.index() as usize] = held.len() as u32;
            held.push(bound);
        }
        self.preorder_arrays(topology.len());
        for (x, &child) in topology.iter().enumerate() {
            for c in topology.get(x + PREFETCH_AHEAD).into_iter().flatten() {
                if c.is_leaf() {
                    bvol_volumes::prefetch(&held[self.leaf_parents[c.index() as usize] as usize]);
                }
            }
            let leaf = |c: Ref| match c.is_leaf() {
                true => held[self.leaf_parents[c.index() as usize] as usize],
                false => B::default(),
            };
            self.nodes[x] = Node::new([leaf(child[0]), leaf(child[1])], child, x as u32);
            for c in child {
                self.set_parent(c, x as u32);
            }
        }
    }

    /// Makes the arrays those of a tree of `n` internal nodes laid out in
    /// preorder from the root at node 0, none free, as a caller is about to
    /// write them over the first `n` nodes: the rest are dropped, and every
    /// parent link is left for the caller to set but the root's.
    fn preorder_arrays(&mut self, n: usize) {
        self.nodes.truncate(n);
        self.parents.clear();
        self.parents.resize(n, NONE);
        self.parents[0] = ROOT;
        self.enlarged.clear();
        self.enlarged.resize(n, false);
        self.free = Ref::NONE;
        self.free_count = 0;
        self.root = Ref::node(0);
        self.preorder = true;
        self.reshaped = false;
    }

    /// Resizes the node arrays to `n` nodes, releasing spare capacity, for
    /// a build that writes every node and parent link: the old ones are
    /// left to be overwritten rather than cleared first.
    fn resize_nodes(&mut self, n: usize) {
        self.nodes.truncate(n);
        self.nodes.resize(n, Node::empty());
        self.nodes.shrink_to(n);
        self.parents.truncate(n);
        self.parents.resize(n, NONE);
        self.parents.shrink_to(n);
        self.enlarged.clear();
        self.enlarged.resize(n, false);
        self.enlarged.shrink_to(n);
    }

    /// Sets every parent link from the child references, for a tree rooted
    /// at node 0 with no free nodes: runs of nodes on rayon tasks, each
    /// setting its children's links (every link is some one node's to set).
    fn relink_all(&mut self) {
        self.parents[0] = ROOT;
        let (parents, leaf_parents) = (shared(&mut self.parents), shared(&mut self.leaf_parents));
        self.nodes.par_chunks(PASS_RUN).enumerate().for_each(|(run, nodes)| {
            for (x, node) in (run * PASS_RUN..).zip(nodes) {
                for c in node.child {
                    let links = if c.is_leaf() { leaf_parents } else { parents };
                    links[c.index() as usize].store(x as u32, Ordering::Relaxed);
                }
            }
        });
    }

    /// The surface-area cost of the tree: the areas of the internal nodes'
    /// bounds as stored (what a traversal tests) summed, over the root's: the
    /// expected number of internal nodes a random ray visits (MacDonald &
    /// Booth 1990). 0 for fewer than 2 leaves.
    pub fn sah_cost(&self) -> f64 {
        if !self.root.is_node() {
            return 0.0;
        }
        let root_area = self.root_bound.cost();
        if root_area <= 0.0 {
            return 0.0;
        }
        // Summed by runs of nodes in parallel, and the runs' sums in order:
        // the same sum on any number of threads.
        let runs = self.node_runs(PASS_RUN);
        let sums: Vec<f64> = runs
            .map(|(nodes, parents)| {
                let in_use = nodes.iter().zip(parents).filter(|(_, p)| **p != NONE);
                let children = in_use.flat_map(|(n, _)| n.child.into_iter().zip(n.bounds()));
                children.filter(|(c, _)| c.is_node()).map(|(_, b)| b.cost()).sum::<f64>()
            })
            .collect();
        let inner: f64 = sums.iter().sum();
        (root_area + inner) / root_area
    }
}

/// `links` as atomics, for rayon tasks to set entries of: the same memory.
fn shared(links: &mut [u32]) -> &[AtomicU32] {
    const { assert!(align_of::<u32>() == align_of::<AtomicU32>()) };
    // SAFETY: an AtomicU32 has a u32's size and bit validity, and (checked
    // above) its alignment; `links` is borrowed mutably for as long as the
    // view, so no access but the view's atomic ones can race.
    unsafe { std::slice::from_raw_parts(links.as_mut_ptr().cast::<AtomicU32>(), links.len()) }
}

#[cfg(test)]
mod tests {
    use bvol_volumes::Aabb;
    use glam::Vec3;

    use super::*;
    use crate::build::{NoClusters, build};

    /// `n` unit boxes: scattered through a cube (about one pair a box), or
    /// gathered in 16 dense clusters; from a fixed linear congruential
    /// sequence.
    fn boxes(n: usize, clustered: bool) -> Vec<Aabb> {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let side = (n as f32 * 8.0).cbrt();
        let centres: Vec<Vec3> =
            (0..16).map(|_| Vec3::new(next(), next(), next()) * side).collect();
        (0..n)
            .map(|i| {
                let p = match clustered {
                    false => Vec3::new(next(), next(), next()) * side,
                    // The sum of three draws: bunched about the centre.
                    true => {
                        let spread = |_| (next() + next() + next() - 1.5) * side * 0.1;
                        centres[i % 16] + Vec3::from_array([0; 3].map(spread))
                    }
                };
                Aabb::new(p, p + Vec3::ONE)
            })
            .collect()
    }

    /// The leaves a rebuild gathers are the tree's, each once with its
    /// bound, and in the same order on two threads (runs counted from the
    /// parent links) as on one: with free nodes among the runs, and ids
    /// missing.
    #[test]
    fn leaf_atoms_are_the_same_on_one_thread_and_two() {
        let mut tree = Tree::from_bounds(&boxes(12_000, false)).unwrap();
        for id in (0..12_000).step_by(7) {
            tree.remove(id).unwrap();
        }
        assert!(tree.free_count > 0 && tree.nodes.len() > 2 * PASS_RUN);
        let gather = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let atoms = pool.install(|| tree.leaf_atoms());
            atoms.iter().map(|a| (a.r.index(), a.bound)).collect::<Vec<_>>()
        };
        let one = gather(1);
        assert_eq!(gather(2), one);
        let mut got = one;
        got.sort_unstable_by_key(|a| a.0);
        let want: Vec<_> = tree.ids().map(|id| (id, tree.bound(id).unwrap())).collect();
        assert_eq!(got, want);
    }

    /// A tree of no leaf or one rebuilds to itself, on one thread (one run
    /// of nodes, of none) as on two.
    #[test]
    fn an_empty_or_one_leaf_tree_rebuilds_on_any_thread_count() {
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut empty = Tree::<Aabb>::new();
                empty.rebuild();
                assert!(empty.is_empty() && empty.pairs().is_empty());
                let mut one = Tree::new();
                one.insert(3, Aabb::new(Vec3::ZERO, Vec3::ONE)).unwrap();
                one.rebuild();
                assert_eq!((one.len(), one.bound(3)), (1, Some(Aabb::new(Vec3::ZERO, Vec3::ONE))));
                one.validate().unwrap();
            });
        }
    }

    /// A load's tree (Morton-sorted clusters built by SAH) leaves a pair
    /// search nearly as few node pairs to visit as binned SAH over every
    /// leaf, the slower build it stands in for: 1.3% and 2.8% more here,
    /// where clusters split by code left 22% more on the scattered boxes.
    #[test]
    fn a_load_is_searched_about_as_fast_as_a_binned_sah_build() {
        for clustered in [false, true] {
            let boxes = boxes(20_000, clustered);
            let load = Tree::from_bounds(&boxes).unwrap();
            let mut sah = load.clone();
            let mut atoms = sah.leaf_atoms();
            sah.root_bound = build(&mut atoms, &mut sah.nodes, 0, &NoClusters).1;
            sah.relink_all();
            sah.validate().unwrap();
            let (mut a, mut b) = (Vec::new(), Vec::new());
            let (ours, theirs) = (load.pairs_into(&mut a), sah.pairs_into(&mut b));
            a.sort_unstable();
            b.sort_unstable();
            assert_eq!(a, b, "clustered {clustered}: other pairs");
            let ratio = ours.node_pairs as f64 / theirs.node_pairs as f64;
            assert!(ratio < 1.06, "clustered {clustered}: {ratio} times the node pairs");
        }
    }
}
