//! A dynamic bounding-volume tree: leaves carry user ids and tight bounds
//! ([`Aabb`](bvol_volumes::Aabb) or [`Sphere`](bvol_volumes::Sphere), see
//! [`Bound`]); internal nodes hold the merge of their children.
//!
//! - Build and change: [`Tree::from_bounds`] / [`Tree::build`] (a level
//!   load: Morton-sorted clusters joined by binned SAH), [`Tree::insert`],
//!   [`Tree::remove`], [`Tree::set_bound`] (fat slack: small moves cost
//!   nothing; escapes enlarge the ancestors; jumps reinsert), [`Tree::refit`],
//!   [`Tree::rebuild`], and [`Tree::optimize`], the bounded per-frame upkeep.
//! - One frame with every bound at once: [`Tree::update`] picks per-leaf
//!   moves or a whole-tree refit by the fraction of leaves that moved.
//! - Ask: [`Tree::pairs`] (every overlapping pair of tight bounds, in parallel,
//!   the same `Vec` on any number of threads), [`Tree::pairs_with`] (dynamic
//!   against static), [`Tree::ray_cast`] / [`Tree::ray_cast_all`],
//!   [`Tree::query`]; [`PairSet`] keeps the pairs across frames and reports
//!   which began and ended.
//! - Check: [`Tree::validate`] returns the first broken invariant.
//!
//! A frame of a broadphase that is handed every body's box every frame:
//!
//! ```
//! use bvol_tree::{PairSet, Tree};
//! use bvol_volumes::Aabb;
//! use glam::Vec3;
//!
//! let boxes = |t: f32| -> Vec<Aabb> {
//!     (0..100)
//!         .map(|i| {
//!             let p = Vec3::new((i % 10) as f32 * 1.5 + t, (i / 10) as f32 * 1.5, 0.0);
//!             Aabb::new(p, p + Vec3::ONE)
//!         })
//!         .collect()
//! };
//! let mut tree = Tree::from_bounds(&boxes(0.0))?; // frame 0: one batch build
//! let mut pairs = PairSet::new();
//! pairs.update(&mut tree);
//! assert!(pairs.pairs().is_empty()); // 1.5 apart: no box touches another
//! for frame in 1..=3 {
//!     let mut b = boxes(0.0);
//!     b[0] = Aabb::new(b[0].min + Vec3::X * 0.25 * frame as f32, b[0].max + Vec3::X * 0.25 * frame as f32);
//!     tree.update(&b)?; // finds what moved, updates the tree
//!     pairs.update(&mut tree); // retests only pairs of leaves that moved
//! }
//! assert_eq!(pairs.pairs(), &[(0, 1)]); // box 0 reached box 1 at frame 2
//! assert_eq!(pairs.began(), &[]); // ... and began touching then, not now
//! # Ok::<(), bvol_tree::TreeError>(())
//! ```

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
mod staged;
mod tree;
mod update;
mod upkeep;
mod validate;

pub use bound::Bound;
pub use error::{BoundError, Slot, TreeError, Violation};
pub use pair_set::PairSet;
pub use tree::{Move, Tree};
pub use update::UpdateStats;

/// Tuning of a [`Tree`]. The defaults were measured on 100 000 moving boxes
/// (`benches/frame.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config {
    /// Fat margin as a fraction of a leaf's size (largest half extent, or
    /// radius), added when a leaf is inserted or escapes its slack. Default
    /// 0.1, Box2D's 0.1 m margin for bodies of about a metre.
    pub fat_size: f32,
    /// Fat margin in multiples of the distance the leaf's centre just moved,
    /// so fast bodies get room for their next frames. Default 2.
    pub fat_motion: f32,
    /// Fraction of leaves moved at or above which [`Tree::update`] refits the
    /// whole tree instead of updating leaves one by one. Default 0.001: with
    /// every bound handed over, finding what moved reads all of them anyway,
    /// so the refit (one more pass) wins from about 0.1% moved (per frame,
    /// with the pair set: 1.7 ms per-leaf against 2.9 ms refit at 0.03%
    /// moved, equal at 0.1%, 4.3 against 2.3 ms at 1%).
    pub refit_fraction: f32,
    /// SAH cost growth, relative to the cost after the last whole build,
    /// that [`Tree::update`]'s refit path lets the tree reach before it
    /// rebuilds it. Default 0.3: boxes moving 0.1 of their size per frame
    /// reach it about every 20 frames; 0.1 and 0.2 rebuilt more often for no
    /// gain. The rebuild is staged over the next frames, so none pays for
    /// all of it, and starts at 0.35 of this growth so that it is installed
    /// about when the tree would have reached it; where leaves teleport so
    /// often that a staged rebuild would find many placed where they were,
    /// it starts at this growth and takes three steps a frame.
    pub drift: f64,
    /// Most atoms (leaves and kept subtrees) one [`Tree::optimize`] call
    /// places: the bound on the per-frame upkeep work. Default 4096, about
    /// 1 ms (a call placing 1 100 atoms of a 100 000-leaf tree took 0.27 ms).
    pub rebuild_budget: usize,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            fat_size: 0.1,
            fat_motion: 2.0,
            refit_fraction: 0.001,
            drift: 0.3,
            rebuild_budget: 4096,
        }
    }
}
