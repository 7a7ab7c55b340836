//! bvol: collision detection for rigid bodies.
//!
//! A body carries a bounding sphere and an oriented bounding box fitted to its
//! mesh; each frame these move with the body, merge into a bounding-volume tree,
//! and separating-axis tests decide the candidate pairs. This crate is the
//! engine's face; the bounding volumes live in [`volumes`] (the `bvol-volumes`
//! crate), re-exported here.
//!
//! ```
//! use bvol::volumes::{Obb, ObbMethod, Sphere, SphereMethod};
//!
//! let meshes = bvol::load_obj("tests/meshes/bunny.obj")?;
//! let points = &meshes[0].positions;
//! let sphere = Sphere::fit(points, SphereMethod::Exact)?;
//! let obb = Obb::fit(points, ObbMethod::MinVolume)?;
//! assert!(points.iter().all(|&p| sphere.contains_point(p) && obb.contains_point(p)));
//! assert!(obb.volume() < sphere.volume());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod digest;
mod mesh;
pub mod scenes;
mod trace;

pub use bvol_volumes as volumes;
pub use digest::PairDigest;
pub use mesh::{Mesh, MeshError, MeshProblem, load_obj};
pub use trace::{BoxTrace, TraceError, TraceWriter};
