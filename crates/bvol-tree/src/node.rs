//! Internal nodes and child references.
//!
//! An internal node holds the bounds of its two children next to their
//! references (the layout of Wald's BVH2 nodes and of Embree): a traversal that
//! reaches a node decides for both children from one fetch, and a leaf's bound
//! sits in its parent's node, so pair finding never touches per-leaf memory.
//! Leaves are not nodes: a reference with the top bit set is a leaf's user id.

use std::fmt;

use crate::{Bound, BoundPair};

/// Ids must be below this: they index the tree's per-id arrays directly,
/// and a child reference marks a leaf with bit 31 (and a staged rebuild's
/// deferred cluster with bit 30).
pub(crate) const ID_LIMIT: u32 = 1 << 28;
/// The parent recorded for the root (internal node or leaf).
pub(crate) const ROOT: u32 = u32::MAX - 1;
/// The parent recorded for a free node or an absent id.
pub(crate) const NONE: u32 = u32::MAX;
/// Where a visit side's selection bits start: bit 30 selects child 0, bit 31
/// child 1 (node indices are below [`ID_LIMIT`]).
pub(crate) const SELECT: u32 = 30;
/// The selection bits of a visit side with both children.
pub(crate) const BOTH: u32 = 0b11 << SELECT;

/// A child reference: an internal node's index, or a leaf's id with
/// [`Ref::LEAF`] set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct Ref(pub(crate) u32);

impl Ref {
    /// The bit that marks a leaf.
    pub(crate) const LEAF: u32 = 1 << 31;
    /// No reference (an empty tree's root, the end of the free list).
    pub(crate) const NONE: Ref = Ref(u32::MAX);

    /// The reference to the leaf of user id `id` (`id < ID_LIMIT`).
    #[inline]
    pub(crate) const fn leaf(id: u32) -> Ref {
        Ref(id | Self::LEAF)
    }

    /// The reference to internal node `index`.
    #[inline]
    pub(crate) const fn node(index: u32) -> Ref {
        Ref(index)
    }

    /// Whether this refers to a leaf.
    #[inline]
    pub(crate) const fn is_leaf(self) -> bool {
        self.0 & Self::LEAF != 0 && self.0 != Self::NONE.0
    }

    /// Whether this refers to an internal node.
    #[inline]
    pub(crate) const fn is_node(self) -> bool {
        self.0 & Self::LEAF == 0
    }

    /// The leaf's id or the node's index.
    #[inline]
    pub(crate) const fn index(self) -> u32 {
        self.0 & !Self::LEAF
    }
}

/// An internal node: two children and their bounds. A leaf child's bound is
/// the user's tight bound; an internal child's bound contains everything below
/// it (exactly their merge after a refit, larger after an enlargement).
///
/// One cache line: the pair search reads a node whole at every step, and a
/// node across two lines would cost two fetches.
///
/// A node also holds the visit side each child leads to in a pair search:
/// an internal child, its index with both its children selected; a leaf,
/// this node's own index with the leaf's side alone selected (its bound is
/// here). Worked out in the search, they were a tenth of its instructions;
/// stored, every change of a node's children or index rewrites them
/// ([`Node::place`]), and [`Tree::validate`](crate::Tree::validate) checks
/// them.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(crate) struct Node<B: Bound> {
    /// The children's bounds, side 0 and side 1.
    pair: B::Pair,
    /// The children. Whoever changes them calls [`Node::place`].
    pub(crate) child: [Ref; 2],
    /// The visit side each child leads to (see above).
    visit: [u32; 2],
}

impl<B: Bound> Node<B> {
    /// Node `at`, with children `child` of bounds `bounds`.
    #[inline]
    pub(crate) fn new(bounds: [B; 2], child: [Ref; 2], at: u32) -> Self {
        let mut node = Node { pair: B::Pair::new(bounds), child, visit: [0; 2] };
        node.place(at);
        node
    }

    /// A node with no children yet (a free node, or one a build fills later).
    pub(crate) fn empty() -> Self {
        Node { pair: B::Pair::new([B::default(); 2]), child: [Ref::NONE; 2], visit: [0; 2] }
    }

    /// Rewrites the visit sides for the node's children as node `at`.
    #[inline]
    pub(crate) fn place(&mut self, at: u32) {
        self.visit = Self::visits(self.child, at);
    }

    /// The visit sides of children `child` of node `at`.
    #[inline]
    fn visits(child: [Ref; 2], at: u32) -> [u32; 2] {
        debug_assert!(at < ID_LIMIT);
        let side = |i: usize| match child[i].is_node() {
            true => child[i].index() | BOTH,
            false => at | 1 << (SELECT as usize + i),
        };
        [side(0), side(1)]
    }

    /// Whether the visit sides are those of node `at`'s children.
    pub(crate) fn placed_at(&self, at: u32) -> bool {
        self.visit == Self::visits(self.child, at)
    }

    /// The visit sides the children lead to.
    #[inline(always)]
    pub(crate) fn visit(&self) -> [u32; 2] {
        self.visit
    }

    /// The bound of child `side`.
    #[inline]
    pub(crate) fn bound(&self, side: usize) -> B {
        self.pair.get(side)
    }

    /// The bounds of both children.
    #[inline]
    pub(crate) fn bounds(&self) -> [B; 2] {
        [self.pair.get(0), self.pair.get(1)]
    }

    /// Sets the bound of child `side`.
    #[inline]
    pub(crate) fn set_bound(&mut self, side: usize, bound: B) {
        self.pair.set(side, bound);
    }

    /// The children's bounds, to be refit ([`BoundPair::refit`]).
    #[inline]
    pub(crate) fn pair_mut(&mut self) -> &mut B::Pair {
        &mut self.pair
    }

    /// The children's bounds together, as the pair search tests them.
    #[inline]
    pub(crate) fn pair(&self) -> &B::Pair {
        &self.pair
    }

    /// The merge of both children's bounds: this node's tight bound.
    #[inline]
    pub(crate) fn merged(&self) -> B {
        self.pair.merged()
    }

    /// Which side holds `r` (side 1 if neither: callers know it is there).
    #[inline]
    pub(crate) fn side_of(&self, r: Ref) -> usize {
        usize::from(self.child[0] != r)
    }
}

/// Where a build writes an internal node: the whole [`Node`], or its child
/// references alone (a staged rebuild's topology, whose bounds the refit that
/// installs it fills in: 8 bytes a node instead of 64).
pub(crate) trait NodeOut<B: Bound>: Send {
    /// Writes node `at` with children `child` of bounds `bounds`.
    fn set(&mut self, bounds: [B; 2], child: [Ref; 2], at: u32);
}

impl<B: Bound> NodeOut<B> for Node<B> {
    #[inline]
    fn set(&mut self, bounds: [B; 2], child: [Ref; 2], at: u32) {
        *self = Node::new(bounds, child, at);
    }
}

impl<B: Bound> NodeOut<B> for [Ref; 2] {
    #[inline]
    fn set(&mut self, _: [B; 2], child: [Ref; 2], _: u32) {
        *self = child;
    }
}

/// Where a node is referred to from: the root slot, or one side of an
/// internal node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// The tree's root.
    Root,
    /// Child `side` (0 or 1) of internal node `node`.
    Child {
        /// Internal node index.
        node: u32,
        /// Which child.
        side: usize,
    },
}

impl fmt::Display for Slot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Slot::Root => write!(f, "the root slot"),
            Slot::Child { node, side } => write!(f, "child {side} of node {node}"),
        }
    }
}
