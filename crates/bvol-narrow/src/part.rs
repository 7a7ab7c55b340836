//! One convex part of a body, of any kind, each call handed to its kind.

use bvol_volumes::{Aabb, Obb, Ray, Sphere};
use glam::Vec3;

use crate::{Capsule, HullPart, MassProperties, PartKind, ShapeError};

/// One convex part of a body, in the body's frame: what the narrow phase
/// tests, pair by pair of parts ([`collide_parts`](crate::collide_parts)).
///
/// Each method hands the call to the kind's [`PartKind`] implementation, in
/// the kind's own file. A new kind is a variant here, an arm in each method,
/// its file, its pair files and its entries in the pair table.
///
/// ```
/// use bvol_narrow::{Capsule, Part};
/// use glam::Vec3;
/// let rod = Part::Capsule(Capsule::new(0.5, 1.0)); // its core from y = -1 to 1
/// assert_eq!(rod.support(Vec3::Y), Vec3::new(0.0, 1.5, 0.0));
/// assert_eq!(rod.local_bounds().max, Vec3::new(0.5, 1.5, 0.5));
/// let volume = std::f32::consts::PI * (0.25 * 2.0 + 0.5f32.powi(3) * 4.0 / 3.0);
/// assert!((rod.mass_properties().volume - volume).abs() < 1e-6);
/// ```
#[derive(Clone, Debug)]
#[non_exhaustive]
pub enum Part {
    /// A convex polyhedron: the hull of a mesh object or a primitive.
    Hull(Box<HullPart>),
    /// An exact ball.
    Ball(Sphere),
    /// An exact capsule: a segment swept by a ball.
    Capsule(Capsule),
}

impl Part {
    /// The smallest axis-aligned box holding the part, rounded outward
    /// ([`PartKind::local_bounds`]).
    pub fn local_bounds(&self) -> Aabb {
        match self {
            Part::Hull(hull) => hull.local_bounds(),
            Part::Ball(ball) => ball.local_bounds(),
            Part::Capsule(capsule) => capsule.local_bounds(),
        }
    }

    /// A point of the part farthest along `direction`
    /// ([`PartKind::support`]).
    pub fn support(&self, direction: Vec3) -> Vec3 {
        match self {
            Part::Hull(hull) => hull.support(direction),
            Part::Ball(ball) => PartKind::support(ball, direction),
            Part::Capsule(capsule) => capsule.support(direction),
        }
    }

    /// The least `t` in `[0, max_t]` at which the ray is inside or on the
    /// part, 0 when it starts there ([`PartKind::ray_entry`]).
    pub fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32> {
        match self {
            Part::Hull(hull) => hull.ray_entry(ray, max_t),
            Part::Ball(ball) => ball.ray_entry(ray, max_t),
            Part::Capsule(capsule) => capsule.ray_entry(ray, max_t),
        }
    }

    /// Points whose convex hull holds the part ([`PartKind::fit_points`]).
    pub fn fit_points(&self) -> Vec<Vec3> {
        match self {
            Part::Hull(hull) => hull.fit_points(),
            Part::Ball(ball) => ball.fit_points(),
            Part::Capsule(capsule) => capsule.fit_points(),
        }
    }

    /// The smallest sphere holding the part, where the kind knows it in
    /// closed form ([`PartKind::enclosing_sphere`]).
    pub fn enclosing_sphere(&self) -> Option<Sphere> {
        match self {
            Part::Hull(hull) => hull.enclosing_sphere(),
            Part::Ball(ball) => ball.enclosing_sphere(),
            Part::Capsule(capsule) => capsule.enclosing_sphere(),
        }
    }

    /// The smallest sphere and box holding the part, where the kind knows
    /// both in closed form ([`PartKind::smallest_bounds`]).
    pub fn smallest_bounds(&self) -> Option<(Sphere, Obb)> {
        match self {
            Part::Hull(hull) => hull.smallest_bounds(),
            Part::Ball(ball) => ball.smallest_bounds(),
            Part::Capsule(capsule) => capsule.smallest_bounds(),
        }
    }

    /// The part scaled by `factor` along its axes, about its frame's origin
    /// ([`PartKind::scaled`]).
    pub fn scaled(&self, factor: Vec3) -> Result<Part, ShapeError> {
        Ok(match self {
            Part::Hull(hull) => Part::Hull(Box::new(hull.scaled(factor)?)),
            Part::Ball(ball) => Part::Ball(PartKind::scaled(ball, factor)?),
            Part::Capsule(capsule) => Part::Capsule(capsule.scaled(factor)?),
        })
    }

    /// Volume, centre of mass and inertia about it at unit density
    /// ([`PartKind::mass_properties`]).
    pub fn mass_properties(&self) -> MassProperties {
        match self {
            Part::Hull(hull) => hull.mass_properties(),
            Part::Ball(ball) => ball.mass_properties(),
            Part::Capsule(capsule) => capsule.mass_properties(),
        }
    }
}
