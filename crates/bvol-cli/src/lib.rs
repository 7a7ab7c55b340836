//! The benchmark tooling behind the `bvol` command line, apart from the
//! engine so that a program embedding `bvol` builds none of it:
//!
//! - [`scenes`]: generated broadphase scenes, N moving boxes deterministic
//!   from a seed (uniform, clustered, mixed, pile, teleport);
//! - [`trace`]: box traces, those frames recorded in a file any broadphase
//!   can replay (the layout of ../shared/SCENE_FORMAT.md);
//! - [`digest`]: the order-free digest of a pair set, so that two
//!   broadphases' pairs can be compared without storing them.
//!
//! ```
//! use bvol::tree::Tree;
//! use bvol_cli::digest::PairDigest;
//! use bvol_cli::scenes::{Scene, SceneKind};
//!
//! let mut scene = Scene::new(SceneKind::Uniform, 1000, 1);
//! let mut tree = Tree::from_bounds(scene.step())?;
//! let mut pairs = Vec::new();
//! tree.update(scene.step())?;
//! tree.pairs_into(&mut pairs);
//! println!("{}", PairDigest::of_pairs(pairs.iter().copied())); // count h1 h2
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod digest;
pub mod scenes;
pub mod trace;
