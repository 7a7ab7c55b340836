//! Separating-axis tests that say how two convex bodies touch: whether they
//! are apart (and along which axis), or touching, with the contact normal, the
//! depth and a manifold of up to four contact points.
//!
//! - [`hull_hull`]: convex polyhedra ([`Polyhedron`], built once per shape from
//!   a point set or a [`ConvexHull`](bvol_volumes::ConvexHull)), by the
//!   separating-axis test of Gregorius (GDC 2013): face normals of both, and
//!   the edge pairs whose Gauss-map arcs cross, found by walking the arcs of
//!   one across the Gauss map of the other; faces and arcs that cannot decide
//!   are skipped by cheap bounds, in clusters. A per-pair [`WarmStart`] keeps
//!   the deciding feature and the last gap measured: a pair that stays apart
//!   is mostly answered from the bodies' motion alone (the gap less how far
//!   they can have come together), else at the cost of two support points.
//! - [`obb_obb`]: the same test and contact on two boxes, without allocating.
//! - [`sphere_hull`], [`sphere_obb`], [`sphere_sphere`]: closest points.
//! - [`capsule_capsule`], [`capsule_sphere`], [`capsule_hull`]: exact
//!   [`Capsule`]s (a segment swept by a ball), by the closest points of their
//!   core segment (Ericson, Real-Time Collision Detection 5.1.9) and, against
//!   a hull, the separating-axis test of the core; two contact points where a
//!   capsule lies along another or on a face.
//!
//! Shapes are in their body's local space; a [`Pose`] places each in the
//! world. The tests compute in the first body's space in f64, so the verdict
//! near touching is exact up to f64 rounding of the f32 input. Normals point
//! from the first body (A) to the second (B). Bad input is a typed error
//! ([`ShapeError`] when a shape is built, [`NarrowError`] when a pair is
//! tested), never a panic or a NaN.
//!
//! A small box resting on a big one, sunk 0.01 into it:
//!
//! ```
//! use bvol_narrow::{Collision, Polyhedron, Pose, WarmStart, hull_hull};
//! use glam::{Quat, Vec3};
//!
//! let floor = Polyhedron::cuboid(Vec3::new(2.0, 0.5, 2.0))?;
//! let crate_ = Polyhedron::cuboid(Vec3::new(0.5, 0.25, 0.5))?;
//! let on_floor = Pose::new(Vec3::new(0.0, 0.74, 0.0), Quat::from_rotation_y(0.3));
//! let mut warm = WarmStart::default(); // keep one per pair, from frame to frame
//! let hit = hull_hull(&floor, &Pose::IDENTITY, &crate_, &on_floor, &mut warm)?;
//! let Collision::Touching(contact) = hit else { panic!("resting boxes touch") };
//! assert_eq!(contact.normal, Vec3::Y); // from the floor up into the crate
//! assert!((contact.depth - 0.01).abs() < 1e-6);
//! // The crate's four bottom corners, halfway between the two surfaces.
//! assert_eq!(contact.points().len(), 4);
//! for p in contact.points() {
//!     assert!((p.position.y - 0.495).abs() < 1e-6 && (p.depth - 0.01).abs() < 1e-6);
//!     println!("contact at {} depth {}", p.position, p.depth);
//! }
//!
//! // Lifted clear, the pair is apart, along the floor's top face normal.
//! let lifted = Pose::new(Vec3::new(0.0, 1.0, 0.0), Quat::IDENTITY);
//! let hit = hull_hull(&floor, &Pose::IDENTITY, &crate_, &lifted, &mut warm)?;
//! assert!(!hit.is_touching());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

mod arc;
mod box_numbering;
mod box_sat;
mod boxes;
mod capsule;
mod capsule_capsule;
mod capsule_hull;
mod capsule_sphere;
mod cluster;
mod collision;
mod convex;
mod cuboid;
mod error;
mod grid;
mod hull;
mod isometry;
mod lanes;
mod manifold;
mod plane;
mod polyhedron;
mod sat;
mod segment;
mod sphere;
mod topology;
mod warm;

pub use boxes::obb_obb;
pub use bvol_volumes::Pose;
pub use capsule::Capsule;
pub use capsule_capsule::capsule_capsule;
pub use capsule_hull::capsule_hull;
pub use capsule_sphere::capsule_sphere;
pub use collision::{Collision, Contact, ContactPoint};
pub use error::{Body, NarrowError, ShapeError};
pub use hull::hull_hull;
pub use polyhedron::Polyhedron;
pub use sphere::{sphere_hull, sphere_obb, sphere_sphere};
pub use warm::WarmStart;
