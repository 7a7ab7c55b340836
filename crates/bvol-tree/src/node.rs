//! Internal nodes and child references.
//!
//! An internal node holds the bounds of its two children next to their
//! references (the layout of Wald's BVH2 nodes and of Embree): a traversal that
//! reaches a node decides for both children from one fetch, and a leaf's bound
//! sits in its parent's node, so pair finding never touches per-leaf memory.
//! Leaves are not nodes: a reference with the top bit set is a leaf's user id.

use std::fmt;

use crate::Bound;

/// Ids must be below this: they index the tree's per-id arrays directly,
/// and a child reference marks a leaf with bit 31 (and a staged rebuild's
/// deferred cluster with bit 30).
pub(crate) const ID_LIMIT: u32 = 1 << 28;
/// The parent recorded for the root (internal node or leaf).
pub(crate) const ROOT: u32 = u32::MAX - 1;
/// The parent recorded for a free node or an absent id.
pub(crate) const NONE: u32 = u32::MAX;

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
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node<B: Bound> {
    /// The children's bounds, side 0 and side 1.
    pub(crate) bounds: [B; 2],
    /// The children.
    pub(crate) child: [Ref; 2],
}

impl<B: Bound> Node<B> {
    /// A node with no children yet (a free node, or one a build fills later).
    pub(crate) fn empty() -> Self {
        Node { bounds: [B::default(); 2], child: [Ref::NONE; 2] }
    }

    /// The merge of both children's bounds: this node's tight bound.
    #[inline]
    pub(crate) fn merged(&self) -> B {
        self.bounds[0].merge(&self.bounds[1])
    }

    /// Which side holds `r` (side 1 if neither: callers know it is there).
    #[inline]
    pub(crate) fn side_of(&self, r: Ref) -> usize {
        usize::from(self.child[0] != r)
    }
}

/// Where a build writes an internal node: the whole [`Node`], or its child
/// references alone (a staged rebuild's topology, whose bounds the refit that
/// installs it fills in: 8 bytes a node instead of 56 for boxes).
pub(crate) trait NodeOut<B: Bound>: Send {
    /// Writes the node with children `child` of bounds `bounds`.
    fn set(&mut self, bounds: [B; 2], child: [Ref; 2]);
}

impl<B: Bound> NodeOut<B> for Node<B> {
    #[inline]
    fn set(&mut self, bounds: [B; 2], child: [Ref; 2]) {
        *self = Node { bounds, child };
    }
}

impl<B: Bound> NodeOut<B> for [Ref; 2] {
    #[inline]
    fn set(&mut self, _: [B; 2], child: [Ref; 2]) {
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
