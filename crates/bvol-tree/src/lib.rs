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
//! - Threads: the work runs on the current rayon pool (run it inside
//!   `ThreadPool::install` to choose one), with the same results on any
//!   number of threads. The frame updates ([`Tree::update`],
//!   [`Tree::update_from`], and [`Tree::update_moved`] when it refits)
//!   keep the pool's other threads busy until they return, running the
//!   pool's pending work or spinning, so that each parallel pass after a
//!   serial stretch does not wait for a sleeping thread to wake.
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

#![warn(missing_docs)]
// A library prints nothing: its callers own stdout and stderr (and a
// scratch timer left in would otherwise go unnoticed).
#![warn(clippy::print_stdout, clippy::print_stderr)]

mod awake;
mod bound;
mod bound_pair;
mod build;
mod changes;
mod check;
mod config;
mod cross;
mod error;
mod leaves;
mod morton;
mod moves;
mod node;
mod pair_cache;
mod pair_set;
mod pairs;
mod paths;
mod policy;
mod query;
mod rebuild;
mod refit;
mod sort_pairs;
mod staged;
mod tree;
mod tuning;
mod update;
mod upkeep;
mod validate;

pub use bound::{Bound, BoundError};
pub use bound_pair::{AabbPair, BoundPair, PairRefit};
pub use config::Config;
pub use error::{TreeError, Violation};
pub use node::Slot;
pub use pair_cache::{CacheUpdate, PairCache};
pub use pair_set::PairSet;
pub use pairs::SearchStats;
pub use sort_pairs::sort_pairs;
pub use tree::{Move, Tree};
pub use update::UpdateStats;

/// Whether the work runs on one thread (the rayon pool it runs in has one):
/// the pair search and the refit then skip the parts and lists that tasks'
/// results are joined from, and give the same result.
fn one_thread() -> bool {
    rayon::current_num_threads() == 1
}
