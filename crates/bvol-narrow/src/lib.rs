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
//!   One made with [`WarmStart::reusing`] also lets a touching pair that
//!   barely moved reuse its contact feature, within a stated depth bound.
//! - [`obb_obb`]: the same test and contact on two boxes, without allocating.
//! - [`sphere_hull`], [`sphere_obb`], [`sphere_sphere`]: closest points.
//! - [`capsule_capsule`], [`capsule_sphere`], [`capsule_hull`]: exact
//!   [`Capsule`]s (a segment swept by a ball), by the closest points of their
//!   core segment (Ericson, Real-Time Collision Detection 5.1.9) and, against
//!   a hull, the separating-axis test of the core; two contact points where a
//!   capsule lies along another or on a face.
//!
//! A body's convex [`Part`]s come in kinds: a hull ([`HullPart`]), a ball
//! ([`Sphere`](bvol_volumes::Sphere)) and a capsule ([`Capsule`]). Each kind
//! knows, in its own file, what a world asks of it whatever it meets
//! ([`PartKind`]: its bounds, support points, ray entry, the points its
//! body's bounds are fitted to, and its [`MassProperties`]). The pair tests
//! belong to pairs of kinds, one file each (`hull_hull.rs`, `sphere_hull.rs`,
//! `capsule_hull.rs`, ...), and [`collide_parts`] picks the one for two parts
//! from a table keyed by their kinds, turning a mirrored pair's answer round.
//! Adding a kind touches its own file (its type and its [`PartKind`]), one
//! file per kind it meets, the table's entries, and the variant with its
//! arms in `part.rs`; nothing else in the engine.
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
// A library prints nothing: its callers own stdout and stderr (and a
// scratch timer left in would otherwise go unnoticed).
#![warn(clippy::print_stdout, clippy::print_stderr)]

mod arc;
mod ball;
mod box_numbering;
mod box_sat;
mod capsule;
mod capsule_capsule;
mod capsule_hull;
mod capsule_sphere;
mod cluster;
mod collision;
mod convex;
mod cuboid;
mod error;
mod flat;
mod gjk;
mod grid;
mod hull_hull;
mod hull_part;
mod isometry;
mod lanes;
mod manifold;
mod mass;
mod near;
mod obb_obb;
mod pair_table;
mod part;
mod part_kind;
mod plane;
mod polyhedron;
mod rest;
mod rounding;
mod sat;
mod segment;
mod sphere_hull;
mod sphere_obb;
mod sphere_sphere;
mod topology;
mod warm;

pub use bvol_volumes::Pose;
pub use capsule::Capsule;
pub use capsule_capsule::capsule_capsule;
pub use capsule_hull::capsule_hull;
pub use capsule_sphere::capsule_sphere;
pub use collision::{Collision, Contact, ContactPoint};
pub use error::{Body, NarrowError, ShapeError};
pub use flat::FLAT_THICKNESS;
pub use hull_hull::hull_hull;
pub use hull_part::{HullPart, HullSource};
pub use manifold::MAX_POINTS;
pub use mass::MassProperties;
pub use near::contact_within;
pub use obb_obb::obb_obb;
pub use pair_table::collide_parts;
pub use part::Part;
pub use part_kind::PartKind;
pub use polyhedron::Polyhedron;
pub use sphere_hull::sphere_hull;
pub use sphere_obb::sphere_obb;
pub use sphere_sphere::sphere_sphere;
pub use warm::{MAX_REUSE, WarmStart};
