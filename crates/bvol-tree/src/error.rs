//! Typed errors: bad input to the tree, and broken invariants found by
//! [`Tree::validate`](crate::Tree::validate).

use std::fmt;

use crate::bound::BoundError;
use crate::node::{ID_LIMIT, Slot};

/// Why a tree operation was refused. The tree is left as it was.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TreeError {
    /// The bound given for `id` is not valid.
    InvalidBound {
        /// The leaf's id (for a slice of bounds, the index in it).
        id: u32,
        /// What is wrong with it.
        reason: BoundError,
    },
    /// `id` is not in the tree.
    UnknownId {
        /// The id.
        id: u32,
    },
    /// `id` is already in the tree, or given twice in one call.
    DuplicateId {
        /// The id.
        id: u32,
    },
    /// `id` is at or above [`Tree::ID_LIMIT`](crate::Tree::ID_LIMIT).
    IdOutOfRange {
        /// The id.
        id: u32,
    },
}

impl fmt::Display for TreeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TreeError::InvalidBound { id, reason } => write!(f, "the bound of id {id} {reason}"),
            TreeError::UnknownId { id } => write!(f, "id {id} is not in the tree"),
            TreeError::DuplicateId { id } => {
                write!(f, "id {id} is already in the tree, or given twice")
            }
            TreeError::IdOutOfRange { id } => write!(
                f,
                "id {id} is too large: ids index the tree's per-id arrays and must be below {}",
                ID_LIMIT
            ),
        }
    }
}

impl std::error::Error for TreeError {}

/// The first broken invariant [`Tree::validate`](crate::Tree::validate) found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Violation {
    /// A stored bound is not valid (non-finite, inverted).
    BadBound {
        /// Where it is stored.
        slot: Slot,
        /// What is wrong with it.
        reason: BoundError,
    },
    /// The bound stored for an internal node does not contain one of its
    /// children's bounds.
    NotContained {
        /// Where the parent's bound is stored.
        slot: Slot,
        /// The internal node.
        node: u32,
        /// Its child that sticks out.
        side: usize,
    },
    /// An internal node's parent link does not point back to where it hangs.
    BadParent {
        /// The node.
        node: u32,
        /// The parent recorded for it.
        recorded: u32,
    },
    /// A leaf's recorded parent is not where it hangs.
    BadLeafParent {
        /// The leaf's id.
        id: u32,
        /// Where it was found.
        slot: Slot,
    },
    /// An internal node is reached twice (a cycle or a shared child), or is
    /// reached while on the free list, or is out of range.
    BadLink {
        /// The node.
        node: u32,
    },
    /// An internal node's stored visit sides (what its children lead to in
    /// a pair search) are not those of its children at its index.
    StaleVisits {
        /// The node.
        node: u32,
    },
    /// The number of leaves reached differs from the number of ids recorded.
    LeafCount {
        /// Leaves reached from the root.
        reached: usize,
        /// Ids recorded as present.
        recorded: usize,
    },
    /// Internal nodes in use plus free ones do not add up to the node array.
    NodeCount {
        /// Internal nodes reached from the root.
        reached: usize,
        /// Nodes on the free list.
        free: usize,
        /// Length of the node array.
        total: usize,
    },
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Violation::BadBound { slot, reason } => write!(f, "the bound in {slot} {reason}"),
            Violation::NotContained { slot, node, side } => write!(
                f,
                "the bound of node {node} (in {slot}) does not contain its child {side}'s bound"
            ),
            Violation::BadParent { node, recorded } => {
                write!(f, "node {node} records parent {recorded}, which does not hold it")
            }
            Violation::BadLeafParent { id, slot } => {
                write!(f, "leaf {id} hangs in {slot} but records another parent")
            }
            Violation::BadLink { node } => {
                write!(f, "node {node} is reached twice, is free, or is out of range")
            }
            Violation::StaleVisits { node } => {
                write!(f, "node {node} stores visits that are not its children's")
            }
            Violation::LeafCount { reached, recorded } => {
                write!(f, "{reached} leaves reached from the root but {recorded} ids recorded")
            }
            Violation::NodeCount { reached, free, total } => write!(
                f,
                "{reached} internal nodes in use and {free} free, but {total} in the array"
            ),
        }
    }
}

impl std::error::Error for Violation {}
