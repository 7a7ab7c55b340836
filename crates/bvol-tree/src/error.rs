//! Typed errors: bad input to the tree, and broken invariants found by
//! [`Tree::validate`](crate::Tree::validate).

use std::fmt;

/// Why a bound cannot go in a tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BoundError {
    /// A coordinate or the radius is NaN or infinite.
    NonFinite,
    /// `min > max` on an axis (0 = x, 1 = y, 2 = z).
    Inverted {
        /// The axis.
        axis: usize,
        /// The lower corner's coordinate on it.
        min: f32,
        /// The upper corner's coordinate on it.
        max: f32,
    },
    /// A sphere with a negative radius.
    NegativeRadius {
        /// The radius.
        radius: f32,
    },
}

impl fmt::Display for BoundError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BoundError::NonFinite => write!(f, "has a NaN or infinite coordinate"),
            BoundError::Inverted { axis, min, max } => {
                write!(f, "has min > max on axis {}: {min} > {max}", ["x", "y", "z"][*axis])
            }
            BoundError::NegativeRadius { radius } => write!(f, "has a negative radius {radius}"),
        }
    }
}

impl std::error::Error for BoundError {}

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
                crate::tree::ID_LIMIT
            ),
        }
    }
}

impl std::error::Error for TreeError {}

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
