//! A dynamic bounding-volume tree (being written).

mod bound;
mod build;
mod changes;
mod error;
mod morton;
mod node;
mod pair_set;
mod pairs;
mod query;
mod rebuild;
mod tree;
mod update;
mod upkeep;
mod validate;

pub use bound::Bound;
pub use pair_set::PairSet;
pub use error::{BoundError, Slot, TreeError, Violation};
pub use tree::{Move, Tree};
pub use update::Frame;

/// Tuning of a [`Tree`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config {
    /// Fat margin as a fraction of a leaf's size (largest half extent, or radius).
    pub fat_size: f32,
    /// Fat margin in multiples of the distance the leaf's centre just moved.
    pub fat_motion: f32,
    /// Fraction of leaves moved above which [`Tree::update`] refits the whole tree.
    pub refit_fraction: f32,
    /// SAH cost growth (relative to the cost after the last whole build)
    /// above which [`Tree::update`]'s refit path rebuilds the tree.
    pub drift: f64,
    /// Most atoms one [`Tree::optimize`] call places.
    pub rebuild_budget: usize,
}

impl Default for Config {
    fn default() -> Self {
        Config { fat_size: 0.1, fat_motion: 2.0, refit_fraction: 0.3, drift: 0.3, rebuild_budget: 4096 }
    }
}
