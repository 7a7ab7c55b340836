//! The tree: storage, and the per-leaf operations insert, remove and move.

use std::collections::BTreeSet;

use rayon::prelude::*;

use crate::Bound;
use crate::changes::Changes;
use crate::check::{check_bound, check_id};
use crate::config::Config;
use crate::error::TreeError;
use crate::leaves::Leaves;
use crate::node::{ID_LIMIT, NONE, Node, ROOT, Ref, Slot};
use crate::policy::Policy;

/// A dynamic bounding-volume tree over leaves that carry user ids.
///
/// # Ids
/// A leaf is named by a `u32` id chosen by the user, typically the index of
/// the body in the user's own arrays. The tree keeps 4 bytes per id value up
/// to the largest id inserted (no hashing on any path), so keep ids dense:
/// `0..n`. Ids must be below [`Tree::ID_LIMIT`].
///
/// # Bounds
/// Each leaf keeps the user's *tight* bound, and every pair and query answer
/// is decided on tight bounds: [`Tree::pairs`] returns exactly the pairs of
/// overlapping (or touching) tight bounds. Internal nodes contain their
/// children's bounds; after a leaf escapes, its ancestors are enlarged by a
/// *fat* margin (relative to the body's size and its last motion, see
/// [`Config`]), so that small later moves inside that slack cost nothing.
///
/// # One frame
/// Either hand the tree every bound of the frame with [`Tree::update`] (it
/// finds what moved and picks per-leaf updates or a full refit by the
/// fraction that moved), or call [`Tree::set_bound`] for each moved leaf and
/// then [`Tree::optimize`] once. Then ask for pairs ([`Tree::pairs`], or a
/// [`PairSet`](crate::PairSet) for began / ended events).
///
/// ```
/// use bvol_tree::Tree;
/// use bvol_volumes::Aabb;
/// use glam::Vec3;
///
/// let unit = |x: f32| Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0));
/// let mut tree = Tree::new();
/// tree.insert(0, unit(0.0))?;
/// tree.insert(1, unit(0.5))?;
/// tree.insert(2, unit(5.0))?;
/// assert_eq!(tree.pairs(), vec![(0, 1)]);
/// tree.set_bound(2, unit(1.5))?; // touches 1
/// assert_eq!(tree.pairs().len(), 2);
/// tree.validate()?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct Tree<B: Bound> {
    /// Internal nodes; free ones are chained through `child[0]`.
    pub(crate) nodes: Vec<Node<B>>,
    /// Per internal node: its parent, [`ROOT`], or [`NONE`] when free.
    pub(crate) parents: Vec<u32>,
    /// Per internal node: enlarged since the last rebuild of its region.
    pub(crate) enlarged: Vec<bool>,
    /// Per id: the internal node holding the leaf, [`ROOT`], or [`NONE`].
    pub(crate) leaf_parents: Vec<u32>,
    /// The root, [`Ref::NONE`] when empty.
    pub(crate) root: Ref,
    /// The root's bound (meaningless when empty).
    pub(crate) root_bound: B,
    /// Head of the free-node list.
    pub(crate) free: Ref,
    /// Number of free nodes.
    pub(crate) free_count: usize,
    /// Number of leaves.
    pub(crate) len: usize,
    /// Ids changed since the last [`PairSet`](crate::PairSet) update.
    pub(crate) changes: Changes,
    /// Tuning.
    pub(crate) config: Config,
    /// The update policy's state: which path, when to rebuild.
    pub(crate) policy: Policy<B>,
    /// Whether the nodes are laid out in preorder from the root at node 0,
    /// none free (true after a whole build or a relayout, false after any
    /// other change of shape).
    pub(crate) preorder: bool,
    /// Whether the shape changed since the last refit.
    pub(crate) reshaped: bool,
    /// Refits in a row through which the shape held.
    pub(crate) held: u32,
    /// How many nodes the last refit out of preorder found late: refitting
    /// in blocks, those with a child in another block, refit again after
    /// the pass; along a walk, those after a child of theirs in the array.
    /// How far the layout has strayed from preorder.
    pub(crate) late: usize,
    /// How many more nodes the last refit out of preorder found late than
    /// the one before it: a few a frame piled up over frames, or many at
    /// once.
    pub(crate) late_gain: usize,
    /// Scratch of the refit path: the ids it found moved.
    pub(crate) moved: Vec<u32>,
    /// Scratch of the refit path: the ids it found jumped clear of their
    /// bound.
    pub(crate) jumped: Vec<u32>,
}

impl<B: Bound> Default for Tree<B> {
    fn default() -> Self {
        Self::new()
    }
}

impl<B: Bound> Tree<B> {
    /// Ids must be below this (2^28): they index per-id arrays directly.
    pub const ID_LIMIT: u32 = ID_LIMIT;

    /// An empty tree with the default [`Config`].
    pub fn new() -> Self {
        Self::with_config(Config::default())
    }

    /// An empty tree with the given tuning.
    pub fn with_config(config: Config) -> Self {
        Tree {
            nodes: Vec::new(),
            parents: Vec::new(),
            enlarged: Vec::new(),
            leaf_parents: Vec::new(),
            root: Ref::NONE,
            root_bound: B::default(),
            free: Ref::NONE,
            free_count: 0,
            len: 0,
            changes: Changes::default(),
            config,
            policy: Policy::default(),
            preorder: true,
            reshaped: false,
            late: 0,
            late_gain: 0,
            held: 0,
            moved: Vec::new(),
            jumped: Vec::new(),
        }
    }

    /// The tuning in use.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Number of leaves.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the tree has no leaves.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Whether `id` is in the tree.
    pub fn contains(&self, id: u32) -> bool {
        self.leaf_parents.get(id as usize).is_some_and(|&p| p != NONE)
    }

    /// The tight bound of leaf `id`, if it is in the tree.
    pub fn bound(&self, id: u32) -> Option<B> {
        self.leaves().bound(id)
    }

    /// The leaves, read-only.
    #[inline]
    pub(crate) fn leaves(&self) -> Leaves<'_, B> {
        Leaves {
            nodes: &self.nodes,
            parents: &self.parents,
            leaf_parents: &self.leaf_parents,
            root_bound: self.root_bound,
            len: self.len,
        }
    }

    /// The internal nodes with their parent links, in runs of `size` nodes
    /// for rayon tasks: a pass whose runs are fixed, and so whose result
    /// does not depend on the number of threads.
    pub(crate) fn node_runs(
        &self,
        size: usize,
    ) -> impl IndexedParallelIterator<Item = (&[Node<B>], &[u32])> + '_ {
        self.nodes.par_chunks(size).zip(self.parents.par_chunks(size))
    }

    /// The bound of the whole tree, `None` when empty.
    pub fn root_bound(&self) -> Option<B> {
        (self.root != Ref::NONE).then_some(self.root_bound)
    }

    /// The ids in the tree, in increasing order.
    pub fn ids(&self) -> impl Iterator<Item = u32> + '_ {
        self.leaf_parents.iter().enumerate().filter(|(_, p)| **p != NONE).map(|(i, _)| i as u32)
    }

    /// Adds leaf `id` with bound `bound`.
    ///
    /// The leaf goes next to the sibling that increases the surface-area cost
    /// least (greedy descent with a lower bound; Box2D v3's
    /// `b2FindBestSibling`), and its ancestors are enlarged by a fat margin.
    pub fn insert(&mut self, id: u32, bound: B) -> Result<(), TreeError> {
        check_id(id)?;
        check_bound(id, &bound)?;
        if self.contains(id) {
            return Err(TreeError::DuplicateId { id });
        }
        self.grow_ids(id);
        let fat = bound.fattened(self.margin(&bound, 0.0));
        self.insert_leaf(id, bound, &fat);
        self.len += 1;
        self.policy.drop_staged(); // its topology lacks the new leaf
        self.changes.mark(id);
        Ok(())
    }

    /// Removes leaf `id`, returning its bound. Its ancestors are shrunk back to
    /// the merge of their children.
    pub fn remove(&mut self, id: u32) -> Result<B, TreeError> {
        if !self.contains(id) {
            return Err(TreeError::UnknownId { id });
        }
        let bound = self.remove_leaf(id);
        self.len -= 1;
        self.policy.drop_staged(); // its topology holds the leaf
        self.changes.mark(id);
        Ok(bound)
    }

    /// Moves leaf `id`: sets its tight bound, and returns what that cost.
    ///
    /// A bound that stays inside its parent's bound (the leaf's slack: at
    /// least its fat bound) changes nothing else. One that escapes but still
    /// overlaps that slack enlarges the ancestors by a fat margin, marking
    /// them for [`Tree::optimize`]. One that lands clear of it (a teleport) is
    /// reinserted where it now belongs, so no ancestor is stretched across
    /// the gap.
    pub fn set_bound(&mut self, id: u32, bound: B) -> Result<Move, TreeError> {
        check_bound(id, &bound)?;
        if !self.contains(id) {
            return Err(TreeError::UnknownId { id });
        }
        let how = self.move_leaf(id, bound);
        if how != Move::Unchanged {
            self.changes.mark(id);
        }
        Ok(how)
    }

    /// The move of one leaf whose id is known to be present.
    pub(crate) fn move_leaf(&mut self, id: u32, bound: B) -> Move {
        let p = self.leaf_parents[id as usize];
        if p == ROOT {
            if self.root_bound == bound {
                return Move::Unchanged;
            }
            self.root_bound = bound;
            return Move::Inside;
        }
        let side = self.nodes[p as usize].side_of(Ref::leaf(id));
        let old = self.nodes[p as usize].bound(side);
        self.nodes[p as usize].set_bound(side, bound);
        if old == bound {
            return Move::Unchanged;
        }
        let slack = self.get(self.slot_of_node(p));
        if slack.contains(&bound) {
            return Move::Inside;
        }
        let motion = (bound.center() - old.center()).length();
        let fat = bound.fattened(self.margin(&bound, motion));
        if bound.overlaps(&slack) {
            self.enlarge_from(p, fat, true);
            Move::Enlarged
        } else {
            self.remove_leaf(id);
            self.insert_leaf(id, bound, &fat);
            self.policy.note_jump(id);
            Move::Reinserted
        }
    }

    /// The fat margin of a leaf: a fraction of its size plus a multiple of
    /// how far it just moved (Box2D's `aabbMargin` and v2.4's
    /// `aabbMultiplier`), so fast bodies get room for their next frames.
    pub(crate) fn margin(&self, bound: &B, motion: f32) -> f32 {
        let m = self.config.fat_size * bound.size() + self.config.fat_motion * motion;
        if m.is_finite() { m } else { 0.0 }
    }

    /// Links leaf `id` (tight `bound`, fat `fat`) in next to the best sibling.
    pub(crate) fn insert_leaf(&mut self, id: u32, bound: B, fat: &B) {
        if self.root == Ref::NONE {
            self.root = Ref::leaf(id);
            self.root_bound = bound;
            self.leaf_parents[id as usize] = ROOT;
            return;
        }
        let slot = self.find_best_sibling(fat);
        self.insert_leaf_at(id, bound, fat, slot, None);
    }

    /// Links leaf `id` (tight `bound`, fat `fat`) into a tree that is not
    /// empty, next to the node or leaf in `slot`: a new internal node takes
    /// the slot, from `spare` (free nodes) when given, see
    /// [`Tree::alloc_node_among`].
    pub(crate) fn insert_leaf_at(
        &mut self,
        id: u32,
        bound: B,
        fat: &B,
        slot: Slot,
        spare: Option<&mut BTreeSet<u32>>,
    ) {
        let leaf = Ref::leaf(id);
        let (sibling, sibling_bound) = (self.get_ref(slot), self.get(slot));
        let (bounds, child) = ([sibling_bound, bound], [sibling, leaf]);
        let p = match spare {
            Some(spare) => self.alloc_node_among(bounds, child, slot, spare),
            None => self.alloc_node(bounds, child),
        };
        self.set_parent(sibling, p);
        self.leaf_parents[id as usize] = p;
        let joined = sibling_bound.merge(fat);
        self.link(slot, Ref::node(p), joined);
        if let Slot::Child { node, .. } = slot {
            self.enlarge_from(node, joined, false);
        }
    }

    /// Unlinks leaf `id` (known present): its sibling takes its parent's place,
    /// and the ancestors are shrunk. Returns the leaf's tight bound.
    pub(crate) fn remove_leaf(&mut self, id: u32) -> B {
        let leaf = Ref::leaf(id);
        let p = self.leaf_parents[id as usize];
        self.leaf_parents[id as usize] = NONE;
        if p == ROOT {
            self.root = Ref::NONE;
            return self.root_bound;
        }
        let node = self.nodes[p as usize];
        let side = node.side_of(leaf);
        let (sibling, sibling_bound) = (node.child[1 - side], node.bound(1 - side));
        let slot = self.slot_of_node(p);
        self.link(slot, sibling, sibling_bound);
        self.free_node(p);
        if let Slot::Child { node: g, .. } = slot {
            self.tighten_from(g);
        }
        node.bound(side)
    }

    /// Makes node `x`'s own bound (and its ancestors') contain `bound`, the new
    /// bound of one of its children; stops at the first ancestor that already
    /// does. With `mark`, the enlarged nodes are flagged for the partial
    /// rebuild of [`Tree::optimize`], and so are their ancestors up to the
    /// root (Box2D v3's `b2DynamicTree_EnlargeProxy`): the rebuild collects
    /// the flagged region from the root down.
    pub(crate) fn enlarge_from(&mut self, mut x: u32, mut bound: B, mark: bool) {
        loop {
            let slot = self.slot_of_node(x);
            let current = self.get(slot);
            if current.contains(&bound) {
                break;
            }
            // Merge with the current bound, not only `bound`: a sphere that
            // holds two spheres need not hold their merge.
            bound = current.merge(&bound);
            self.set(slot, bound);
            if mark {
                self.enlarged[x as usize] = true;
            }
            match slot {
                Slot::Root => return,
                Slot::Child { node, .. } => x = node,
            }
        }
        if mark {
            self.mark_ancestors(x);
        }
    }

    /// Flags `x` and its ancestors as enlarged, stopping at a flagged one.
    fn mark_ancestors(&mut self, mut x: u32) {
        while x != ROOT && !self.enlarged[x as usize] {
            self.enlarged[x as usize] = true;
            x = self.parents[x as usize];
        }
    }

    /// Recomputes node `x`'s bound from its children, and its ancestors' while
    /// they change.
    pub(crate) fn tighten_from(&mut self, mut x: u32) {
        loop {
            let tight = self.nodes[x as usize].merged();
            let slot = self.slot_of_node(x);
            if self.get(slot) == tight {
                return;
            }
            self.set(slot, tight);
            match slot {
                Slot::Root => return,
                Slot::Child { node, .. } => x = node,
            }
        }
    }

    /// The slot that sibling search picks for a new leaf of fat bound `d`: the
    /// one whose new parent adds the least surface area to the tree, found by
    /// a greedy descent pruned with a lower bound on the cost below each child
    /// (Box2D v3 `b2FindBestSibling`, after Bittner et al. 2012).
    pub(crate) fn find_best_sibling(&self, d: &B) -> Slot {
        let (area_d, center_d) = (d.cost(), d.center());
        let mut base_area = self.root_bound.cost();
        let mut direct = self.root_bound.merge(d).cost();
        let mut inherited = 0.0;
        let (mut best, mut best_cost) = (Slot::Root, direct);
        let mut r = self.root;
        while r.is_node() {
            // Below this node, its bound grows by (direct - base_area).
            inherited += direct - base_area;
            let node = &self.nodes[r.index() as usize];
            // Both children are asked for while this node's costs are
            // worked out: the descent otherwise waits on each level's node.
            for c in node.child.into_iter().filter(|c| c.is_node()) {
                bvol_volumes::prefetch(&self.nodes[c.index() as usize]);
            }
            let mut lower = [f64::INFINITY; 2];
            let mut directs = [0.0; 2];
            let mut areas = [0.0; 2];
            for side in 0..2 {
                let b = &node.bound(side);
                directs[side] = b.merge(d).cost();
                let cost = directs[side] + inherited;
                if cost < best_cost {
                    (best, best_cost) = (Slot::Child { node: r.index(), side }, cost);
                }
                if node.child[side].is_node() {
                    areas[side] = b.cost();
                    lower[side] = inherited + directs[side] + (area_d - areas[side]).min(0.0);
                }
            }
            let side = if lower[0] == lower[1] {
                // Both contain `d`: no cost difference, go to the nearer one.
                let dist = |s: usize| (node.bound(s).center() - center_d).length_squared();
                usize::from(dist(1) < dist(0))
            } else {
                usize::from(lower[1] < lower[0])
            };
            // Also stops on a NaN cost (never for finite bounds).
            if lower[side].partial_cmp(&best_cost) != Some(std::cmp::Ordering::Less) {
                break;
            }
            (base_area, direct) = (areas[side], directs[side]);
            r = node.child[side];
        }
        best
    }

    /// Where internal node `x` hangs.
    #[inline]
    pub(crate) fn slot_of_node(&self, x: u32) -> Slot {
        match self.parents[x as usize] {
            ROOT => Slot::Root,
            p => Slot::Child { node: p, side: self.nodes[p as usize].side_of(Ref::node(x)) },
        }
    }

    /// The bound stored in a slot.
    #[inline]
    pub(crate) fn get(&self, slot: Slot) -> B {
        match slot {
            Slot::Root => self.root_bound,
            Slot::Child { node, side } => self.nodes[node as usize].bound(side),
        }
    }

    /// The reference stored in a slot.
    fn get_ref(&self, slot: Slot) -> Ref {
        match slot {
            Slot::Root => self.root,
            Slot::Child { node, side } => self.nodes[node as usize].child[side],
        }
    }

    /// Overwrites the bound stored in a slot.
    #[inline]
    pub(crate) fn set(&mut self, slot: Slot, bound: B) {
        match slot {
            Slot::Root => self.root_bound = bound,
            Slot::Child { node, side } => self.nodes[node as usize].set_bound(side, bound),
        }
    }

    /// Hangs `r` with bound `bound` in `slot`, and records the parent in `r`.
    pub(crate) fn link(&mut self, slot: Slot, r: Ref, bound: B) {
        match slot {
            Slot::Root => {
                self.root = r;
                self.root_bound = bound;
                self.set_parent(r, ROOT);
            }
            Slot::Child { node, side } => {
                let n = &mut self.nodes[node as usize];
                n.child[side] = r;
                n.set_bound(side, bound);
                n.place(node);
                self.set_parent(r, node);
            }
        }
    }

    /// Records `parent` (a node index or [`ROOT`]) as the parent of `r`.
    #[inline]
    pub(crate) fn set_parent(&mut self, r: Ref, parent: u32) {
        if r.is_leaf() {
            self.leaf_parents[r.index() as usize] = parent;
        } else {
            self.parents[r.index() as usize] = parent;
        }
    }

    /// A node from the free list, or a new one, with children `child` of
    /// bounds `bounds`; its parent is set by `link`.
    pub(crate) fn alloc_node(&mut self, bounds: [B; 2], child: [Ref; 2]) -> u32 {
        self.mark_reshaped();
        if self.free == Ref::NONE {
            let x = self.nodes.len() as u32;
            self.nodes.push(Node::new(bounds, child, x));
            self.parents.push(NONE);
            self.enlarged.push(false);
            return x;
        }
        let x = self.free.index();
        self.free = self.nodes[x as usize].child[0];
        self.free_count -= 1;
        self.nodes[x as usize] = Node::new(bounds, child, x);
        x
    }

    /// A node from `spare` (free nodes; a new one if none) for children
    /// `child` of bounds `bounds`, to be linked in at `slot`: the first
    /// after its parent, or the last when none is. A refit over the node
    /// array from last to first ([`Tree::refit_pass`]) meets a node so
    /// placed after its children whenever a free node allows (the first
    /// after the parent comes before an internal child too if any does),
    /// where the free list's first would come before a child of its for
    /// most insertions.
    fn alloc_node_among(
        &mut self,
        bounds: [B; 2],
        child: [Ref; 2],
        slot: Slot,
        spare: &mut BTreeSet<u32>,
    ) -> u32 {
        let parent = match slot {
            Slot::Child { node, .. } => node,
            Slot::Root => 0,
        };
        let first_after = spare.range(parent..).next().copied();
        let Some(x) = first_after.or_else(|| spare.last().copied()) else {
            return self.alloc_node(bounds, child);
        };
        spare.remove(&x);
        self.mark_reshaped();
        self.nodes[x as usize] = Node::new(bounds, child, x);
        x
    }

    /// Takes every free node off the free list.
    pub(crate) fn take_free(&mut self) -> BTreeSet<u32> {
        let mut spare = BTreeSet::new();
        while self.free != Ref::NONE {
            spare.insert(self.free.index());
            self.free = self.nodes[self.free.index() as usize].child[0];
        }
        self.free_count = 0;
        spare
    }

    /// Returns node `x` to the free list.
    pub(crate) fn free_node(&mut self, x: u32) {
        self.mark_reshaped();
        let mut empty = Node::empty();
        empty.child[0] = self.free;
        self.nodes[x as usize] = empty;
        self.parents[x as usize] = NONE;
        self.enlarged[x as usize] = false;
        self.free = Ref::node(x);
        self.free_count += 1;
    }

    /// Records a change of the tree's shape (nodes linked differently).
    pub(crate) fn mark_reshaped(&mut self) {
        self.preorder = false;
        self.reshaped = true;
    }

    /// Makes the per-id arrays long enough to hold `id`.
    pub(crate) fn grow_ids(&mut self, id: u32) {
        let needed = id as usize + 1;
        if self.leaf_parents.len() < needed {
            self.leaf_parents.resize(needed, NONE);
            self.changes.grow(needed);
        }
    }

    /// Bytes held by the tree and its bookkeeping (capacities, not lengths).
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.nodes.capacity() * size_of::<Node<B>>()
            + self.parents.capacity() * 4
            + self.enlarged.capacity()
            + self.leaf_parents.capacity() * 4
            + self.changes.memory_bytes()
            + (self.moved.capacity() + self.jumped.capacity()) * 4
            + self.policy.memory_bytes()
    }
}

/// How [`Tree::set_bound`] handled a move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Move {
    /// The bound was the same as before.
    Unchanged,
    /// It stayed inside its slack: only the leaf's bound was written.
    Inside,
    /// It escaped: ancestors were enlarged by a fat margin.
    Enlarged,
    /// It landed clear of its slack: the leaf was reinserted.
    Reinserted,
}
