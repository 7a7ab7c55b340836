//! What every kind of part knows of itself, whatever it meets.

use bvol_volumes::{Aabb, Obb, Ray, Sphere};
use glam::Vec3;

use crate::{MassProperties, ShapeError};

/// What a world asks of a kind of convex part, in the part's own frame: its
/// bounds, its support points, where a ray enters it, the points its
/// body's bounds are fitted to, and its mass. Each kind implements it in its
/// own file; [`Part`](crate::Part) hands each call to its kind.
///
/// The pair tests are not here: they belong to pairs of kinds, one file each,
/// picked by [`collide_parts`](crate::collide_parts).
pub trait PartKind {
    /// The smallest axis-aligned box holding the part, rounded outward to
    /// f32.
    fn local_bounds(&self) -> Aabb;

    /// A point of the part farthest along `direction` (the support mapping
    /// of Gilbert, Johnson & Keerthi 1988); any of its points when
    /// `direction` is zero or not finite.
    fn support(&self, direction: Vec3) -> Vec3;

    /// The least `t` in `[0, max_t]` at which the ray is inside or on the
    /// part: 0 when it starts there, `None` when it misses, enters beyond
    /// `max_t`, or has a non-finite or zero direction, a non-finite origin, or
    /// a negative or NaN `max_t`.
    fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32>;

    /// Points whose convex hull holds the part: a body's bounding sphere and
    /// box fitted to them hold the part (a fitted bound holds its points, so
    /// their hull, so the part).
    fn fit_points(&self) -> Vec<Vec3>;

    /// The smallest sphere holding the part where the kind knows it in closed
    /// form (rounded up), so that a body of this part alone is bounded by it
    /// rather than by a sphere fitted to [`fit_points`](Self::fit_points);
    /// `None` where it must be fitted.
    fn enclosing_sphere(&self) -> Option<Sphere>;

    /// The smallest sphere and the smallest box holding the part where the
    /// kind knows both in closed form (rounded up), so that a body of this
    /// part alone, with the tightest fits asked for, takes them rather than
    /// fitting its bounds to [`fit_points`](Self::fit_points); `None` where
    /// they must be fitted.
    fn smallest_bounds(&self) -> Option<(Sphere, Obb)>;

    /// The part scaled by `factor` along its frame's axes, about its origin:
    /// [`ShapeError::NonUniformScale`] for unequal factors where the kind
    /// would no longer be itself (a ball would be an ellipsoid), the
    /// polyhedron's errors where a hull scaled is not a solid. The factor is
    /// the caller's to check (finite, positive, keeping the part in range).
    fn scaled(&self, factor: Vec3) -> Result<Self, ShapeError>
    where
        Self: Sized;

    /// Volume, centre of mass and inertia about it at unit density.
    fn mass_properties(&self) -> MassProperties;
}
