//! Bounding volumes for collision detection: spheres, axis-aligned boxes,
//! oriented boxes and k-DOPs; fitting them to point sets by several methods,
//! merging, moving them by rigid poses, overlap and ray tests; and the 3-D
//! convex hull that the box fitters and the narrow phase build on.
//!
//! Bounds are stored in f32; fitting works in f64 inside and ends with a pass
//! that makes every bound hold every input point after rounding. Bad input (no
//! points, NaN or infinite coordinates) is a [`FitError`], never a panic or a
//! NaN bound.
//!
//! ```
//! use bvol_volumes::{Obb, ObbMethod, Pose, Sphere, SphereMethod};
//! use glam::{Quat, Vec3};
//!
//! let points = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE];
//! let sphere = Sphere::fit(&points, SphereMethod::Exact)?;
//! let obb = Obb::fit(&points, ObbMethod::MinVolume)?;
//! assert!(points.iter().all(|&p| sphere.contains_point(p) && obb.contains_point(p)));
//!
//! // Move both with a body, and test them against another body's.
//! let pose = Pose::new(Vec3::new(0.5, 0.0, 0.0), Quat::from_rotation_y(0.3));
//! let (s2, o2) = (sphere.transformed(&pose), obb.transformed(&pose));
//! assert!(sphere.overlaps(&s2) && obb.overlaps(&o2));
//! # Ok::<(), bvol_volumes::FitError>(())
//! ```

#![warn(missing_docs)]
// A library prints nothing: its callers own stdout and stderr (and a
// scratch timer left in would otherwise go unnoticed).
#![warn(clippy::print_stdout, clippy::print_stderr)]

mod aabb;
pub mod directions;
mod error;
mod fit;
mod hull;
mod kdop;
mod lane;
mod obb;
mod placed;
mod pose;
mod prefetch;
mod ray;
mod round;
mod sphere;

pub use aabb::Aabb;
pub use error::{FitError, HullError, MAX_COORDINATE, UnknownMethod};
pub use fit::{ObbMethod, SphereMethod};
pub use hull::ConvexHull;
pub use kdop::{Kdop, Kdop6, Kdop14, Kdop18, Kdop26};
pub use obb::Obb;
pub use placed::{BodyBounds, WorldBounds};
pub use pose::{DPose, Pose};
pub use prefetch::prefetch;
pub use ray::Ray;
pub use sphere::Sphere;
