//! bvol: collision detection for rigid bodies.
//!
//! A body carries a bounding sphere and an oriented bounding box (OBB) fitted
//! to its shape; each frame they move with the body, merge into a bounding-
//! volume tree, the tree yields candidate pairs, and each pair goes through the
//! sphere test, the OBB test and a separating-axis test of the convex hulls,
//! which says how the bodies touch. A simulation embeds a [`World`]:
//!
//! ```
//! use std::sync::Arc;
//! use bvol::volumes::Pose;
//! use bvol::{BodyDesc, BodyKind, EventKind, Shape, World};
//! use glam::{Quat, Vec3};
//!
//! let mut world = World::new();
//! let floor = Arc::new(Shape::cuboid(Vec3::new(10.0, 0.5, 10.0))?);
//! let ball = Arc::new(Shape::ball(0.5)?);
//! world.add_body(BodyDesc::new(floor, Pose::IDENTITY).with_kind(BodyKind::Static))?;
//! let body = world.add_body(BodyDesc::new(ball, Pose::new(Vec3::Y * 2.0, Quat::IDENTITY)))?;
//! let mut touched = 0;
//! for step in 0..20 {
//!     let height = 2.0 - 0.1 * step as f32; // the simulation's own motion
//!     world.set_poses(&[body], &[Pose::new(Vec3::Y * height, Quat::IDENTITY)])?;
//!     world.update();
//!     for event in world.events().iter().filter(|e| e.kind == EventKind::Began) {
//!         let contact = event.contact.expect("a contact that began has one");
//!         assert!(height <= 1.0 && contact.normal.y > 0.99); // from the floor up
//!         touched += 1;
//!     }
//! }
//! assert_eq!(touched, 1);
//! println!("{:?}", world.stats()); // pairs and time of each stage
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Bodies touch when their shapes overlap or meet: touching exactly, a
//! contact of depth 0, counts (rapier, for one, does not count it).
//! [`World::contacts`] lists the pairs touching at the last update, with
//! their contacts, and [`World::contact`] answers for one pair.
//!
//! A world made with a [`margin`](WorldConfig::margin) also reports bodies
//! apart by at most that distance, with negative depths (what a solver's
//! speculative contacts need); one made with a [`reuse`](WorldConfig::reuse)
//! tolerance lets touching pairs that barely moved, as in a solver's
//! resting pile, reuse their contact features. Far from the origin, poses go in with f64
//! positions ([`World::set_poses_f64`]) and pairs are tested on positions
//! relative to one of their bodies. With the `serde` feature,
//! `World::snapshot` saves a world and `World::from_snapshot` loads it
//! to run on event for event.
//!
//! The vectors and quaternions are [`glam`]'s, re-exported as `bvol::glam`
//! so that a user's glam is the one bvol was built with.
//!
//! The parts are crates of their own, re-exported here: [`volumes`] (bounding
//! volumes, fitting, the convex hull), [`tree`] (the dynamic tree) and
//! [`narrow`] (the separating-axis tests). Fitting alone:
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

#![warn(missing_docs)]
// A library prints nothing: its callers own stdout and stderr (and a
// scratch timer left in would otherwise go unnoticed).
#![warn(clippy::print_stdout, clippy::print_stderr)]

mod bodies;
mod body;
mod broadphase;
mod config;
mod event;
mod limits;
mod mesh;
mod narrow_phase;
mod pipeline;
mod scratch;
mod shape;
#[cfg(feature = "serde")]
mod snapshot;
mod stats;
mod world;

pub use body::{BodyDesc, BodyId, BodyKind, WorldError};
pub use broadphase::{Broadphase, BruteForce};
pub use bvol_narrow as narrow;
pub use bvol_narrow::{Capsule, HullPart, MassProperties, Part};
pub use bvol_tree as tree;
pub use bvol_volumes as volumes;
pub use config::WorldConfig;
pub use event::{ContactEvent, EventKind};
pub use glam;
pub use limits::{MAX_COORDINATE, ROTATION_LENGTH_SQUARED};
pub use mesh::{Mesh, MeshError, MeshProblem, load_obj};
pub use shape::{FitOptions, Shape, ShapeError};
#[cfg(feature = "serde")]
pub use snapshot::{Snapshot, SnapshotError};
pub use stats::FrameStats;
pub use world::{RayHit, World};
