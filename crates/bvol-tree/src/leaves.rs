//! A tree's leaves, read-only: where each one hangs and its bound. The
//! tree reads its own leaves through this view, and hands it to the staged
//! rebuild, which reads the leaves of the tree it rebuilds.

use crate::Bound;
use crate::node::{NONE, Node, ROOT, Ref};
use crate::tuning::PREFETCH_AHEAD;

/// The leaves of a tree: its node arrays and per-id parent links, borrowed.
#[derive(Clone, Copy)]
pub(crate) struct Leaves<'a, B: Bound> {
    /// Internal nodes; a leaf's bound sits in its parent's.
    pub(crate) nodes: &'a [Node<B>],
    /// Per internal node: its parent, [`ROOT`], or [`NONE`] when free.
    pub(crate) parents: &'a [u32],
    /// Per id: the internal node holding the leaf, [`ROOT`], or [`NONE`].
    pub(crate) leaf_parents: &'a [u32],
    /// The root's bound: the leaf's own when the root is a leaf.
    pub(crate) root_bound: B,
    /// Number of leaves.
    pub(crate) len: usize,
}

impl<B: Bound> Leaves<'_, B> {
    /// The tight bound of leaf `id`, if it is in the tree.
    #[inline]
    pub(crate) fn bound(&self, id: u32) -> Option<B> {
        match *self.leaf_parents.get(id as usize)? {
            NONE => None,
            ROOT => Some(self.root_bound),
            p => {
                let node = &self.nodes[p as usize];
                Some(node.bound(node.side_of(Ref::leaf(id))))
            }
        }
    }

    /// Every leaf in an internal node, with its bound, in node order: a
    /// sequential read of the nodes.
    pub(crate) fn in_node_order(&self) -> impl Iterator<Item = (u32, B)> + '_ {
        in_run(self.nodes, self.parents).map(|(c, b)| (c.index(), b))
    }

    /// Asks for the node that holds leaf `id`'s bound, to be read soon:
    /// reads in an order other than the tree's wait on memory for each.
    #[inline]
    pub(crate) fn prefetch(&self, id: u32) {
        if let Some(&p) = self.leaf_parents.get(id as usize)
            && let Some(node) = self.nodes.get(p as usize)
        {
            bvol_volumes::prefetch(node);
        }
    }

    /// For a loop reading the bounds of leaves `ids` in turn, at `ids[k]`
    /// now: asks for the node of the leaf [`PREFETCH_AHEAD`] places on,
    /// and for the parent link of the one twice as far, which that request
    /// will read (ids in an order other than the tree's wait on memory for
    /// both, past the caches).
    #[inline]
    pub(crate) fn prefetch_ahead(&self, ids: &[u32], k: usize) {
        if let Some(&far) = ids.get(k + 2 * PREFETCH_AHEAD)
            && let Some(link) = self.leaf_parents.get(far as usize)
        {
            bvol_volumes::prefetch(link);
        }
        if let Some(&later) = ids.get(k + PREFETCH_AHEAD) {
            self.prefetch(later);
        }
    }
}

/// The leaves hanging from a run of internal `nodes` (with their
/// `parents`, free nodes skipped), with their bounds, in node order.
pub(crate) fn in_run<'a, B: Bound>(
    nodes: &'a [Node<B>],
    parents: &'a [u32],
) -> impl Iterator<Item = (Ref, B)> + 'a {
    leaves_of(nodes.iter().zip(parents))
}

/// [`in_run`], asking at each node for the bounds in `all` of the leaves
/// [`PREFETCH_AHEAD`] nodes on ([`ask_leaf_bounds`]), for a loop that
/// reads them by id.
pub(crate) fn in_run_asking<'a, B: Bound>(
    nodes: &'a [Node<B>],
    parents: &'a [u32],
    all: &'a [B],
) -> impl Iterator<Item = (Ref, B)> + 'a {
    let asked = nodes.iter().enumerate().map(move |(k, node)| {
        if let Some(ahead) = nodes.get(k + PREFETCH_AHEAD) {
            ask_leaf_bounds(ahead, all);
        }
        node
    });
    leaves_of(asked.zip(parents))
}

/// The leaf children of the nodes in use among `nodes`, each with its
/// parent link, with their bounds.
fn leaves_of<'a, B: Bound>(
    nodes: impl Iterator<Item = (&'a Node<B>, &'a u32)>,
) -> impl Iterator<Item = (Ref, B)> {
    let in_use = nodes.filter(|(_, p)| **p != NONE);
    let children = in_use.flat_map(|(n, _)| n.child.into_iter().zip(n.bounds()));
    children.filter(|(c, _)| c.is_leaf())
}

/// Asks for the bounds in `all` of the leaves among `node`'s children, to be
/// read a few nodes later. An internal child asks for the first bound: no
/// branch on which it is, which no predictor could learn.
#[inline]
pub(crate) fn ask_leaf_bounds<B: Bound>(node: &Node<B>, all: &[B]) {
    for c in node.child {
        let id = if c.is_node() { 0 } else { c.index() as usize };
        if let Some(b) = all.get(id) {
            bvol_volumes::prefetch(b);
        }
    }
}
