//! Capsules: a segment swept by a ball, tested exactly (where a hull of
//! points on its caps would only approximate them).

use glam::DVec3;

use crate::isometry::DIsometry3;
use crate::segment::Segment;
use crate::{Body, NarrowError};

/// Two cores (or a core and a face) this close to parallel, as the sine of
/// their angle, rest along a line: their contact takes a point at each end
/// of the stretch where they face each other, as Box2D's capsule routines do
/// (`b2CollideCapsules`, `b2CollidePolygons`), so that a capsule lying on
/// another or on a face does not rock about a single point.
pub(crate) const PARALLEL_SINE: f64 = 0.02;

/// A manifold end above the other surface by less than this, relative to the
/// shapes' size, still counts as touching: f64 rounding of a capsule resting
/// exactly leaves one end or the other a hair above.
pub(crate) const END_SLOP: f64 = 1e-9;

/// Closest points this near, relative to the span of the coordinates they
/// come from, are taken to meet: f64 rounding puts a placed core's ends off
/// by about 1e-16 of that span, so the line between points nearer than this
/// may point anywhere, even along the cores, where the overlap is their
/// whole length. A fixed direction square to them is then as shallow, to
/// twice their distance.
pub(crate) const MEET: f64 = 1e-9;

/// A capsule in its body's local space: the segment from
/// `(0, -half_height, 0)` to `(0, half_height, 0)` (its core), swept by a ball
/// of `radius`: every point within `radius` of the core. With `half_height`
/// 0 it is a ball, and its routines answer as the spheres' do.
///
/// Its fields are checked where it is tested: a NaN or infinite field, or a
/// negative one, is [`NarrowError::NonFiniteShape`]. A `radius` of 0 is the
/// bare segment.
///
/// ```
/// use bvol_narrow::{Capsule, Pose, capsule_capsule};
/// use glam::{Quat, Vec3};
/// // Two capsules of radius 0.5 and length 3 (2 between the cap centres), one
/// // lying across the other, 0.9 above it: they overlap by 0.1.
/// let capsule = Capsule::new(0.5, 1.0);
/// let lying = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
/// let above = Pose::new(Vec3::new(0.0, 0.0, 0.9), lying);
/// let contact = *capsule_capsule(&capsule, &Pose::IDENTITY, &capsule, &above)?
///     .contact()
///     .expect("touching");
/// assert!((contact.normal - Vec3::Z).length() < 1e-6);
/// assert!((contact.depth - 0.1).abs() < 1e-6);
/// # Ok::<(), bvol_narrow::NarrowError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capsule {
    /// Radius of the swept ball, `>= 0`.
    pub radius: f32,
    /// Half the length of the core along local y, `>= 0`.
    pub half_height: f32,
}

impl Capsule {
    /// The capsule of `radius` about the core from `(0, -half_height, 0)` to
    /// `(0, half_height, 0)`.
    pub const fn new(radius: f32, half_height: f32) -> Capsule {
        Capsule { radius, half_height }
    }

    /// [`NarrowError::NonFiniteShape`] unless both fields are finite and not negative.
    pub(crate) fn check(&self, body: Body) -> Result<(), NarrowError> {
        let ok = |x: f32| x.is_finite() && x >= 0.0;
        if ok(self.radius) && ok(self.half_height) {
            Ok(())
        } else {
            Err(NarrowError::NonFiniteShape { body })
        }
    }

    /// Its core in the space that `to` maps its local space into.
    pub(crate) fn core(&self, to: &DIsometry3) -> Segment {
        let half = DVec3::new(0.0, self.half_height.into(), 0.0);
        Segment::new(to.apply(-half), to.apply(half))
    }
}
