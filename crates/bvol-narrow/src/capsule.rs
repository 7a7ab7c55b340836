//! Capsules: a segment swept by a ball, tested exactly (where a hull of
//! points on its caps would only approximate them).

use std::f64::consts::PI;

use bvol_volumes::{Aabb, Obb, Ray, Sphere};
use glam::{DMat3, DVec2, DVec3, Mat3, Vec3};

use crate::ball::uniform;
use crate::isometry::DIsometry3;
use crate::segment::Segment;
use crate::{Body, MassProperties, NarrowError, PartKind, ShapeError};

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

    /// The balls about its core's ends, bottom then top: the capsule is their
    /// hull.
    fn end_balls(&self) -> [Sphere; 2] {
        [-1.0, 1.0].map(|s| Sphere::new(Vec3::Y * (s * self.half_height), self.radius))
    }

    /// Where a ray from `o` along `d` enters the capsule's side, between the
    /// planes of its core's ends: the nearer root of the ray against the
    /// cylinder of its radius about the core's line (Ericson, Real-Time
    /// Collision Detection 5.3.7, in the stable form of `Sphere::ray_entry`),
    /// if the ray starts outside that cylinder and the root lies between the
    /// planes. A ray that starts within the cylinder, or meets it beyond the
    /// planes, can only enter the capsule through an end ball: where it
    /// crosses a plane within the radius it is inside that ball.
    fn side_entry(&self, o: DVec3, d: DVec3) -> Option<f64> {
        let (f, d2) = (DVec2::new(o.x, o.z), DVec2::new(d.x, d.z));
        let (a, r) = (d2.length_squared(), f64::from(self.radius));
        let c = f.length_squared() - r * r;
        let b = -f.dot(d2);
        if a == 0.0 || c <= 0.0 || b <= 0.0 {
            return None;
        }
        let disc = r * r - (f + d2 * (b / a)).length_squared();
        if disc < 0.0 {
            return None;
        }
        let t = c / (b + (a * disc).sqrt());
        ((o.y + t * d.y).abs() <= f64::from(self.half_height)).then_some(t)
    }
}

impl PartKind for Capsule {
    /// The box of its two end balls.
    fn local_bounds(&self) -> Aabb {
        let [low, high] = self.end_balls();
        low.aabb().merge(&high.aabb())
    }

    /// The end of the core on `direction`'s side (the top on a tie) moved by
    /// the radius along `direction`, in f64; that end when `direction` has
    /// no length.
    fn support(&self, direction: Vec3) -> Vec3 {
        let d = direction.as_dvec3();
        let h = f64::from(self.half_height);
        let end = DVec3::new(0.0, if d.y < 0.0 { -h } else { h }, 0.0);
        let unit = d.try_normalize().unwrap_or(DVec3::ZERO);
        (end + unit * f64::from(self.radius)).as_vec3()
    }

    /// 0 when the ray starts within the radius of the core; else the nearest
    /// of where it enters the side and the two end balls, the capsule being
    /// their union.
    fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32> {
        let valid = ray.origin.is_finite() && ray.direction.is_finite();
        if !(valid && ray.direction != Vec3::ZERO && max_t >= 0.0) {
            return None;
        }
        let (o, d) = (ray.origin.as_dvec3(), ray.direction.as_dvec3());
        let h = f64::from(self.half_height);
        let core = DVec3::new(0.0, o.y.clamp(-h, h), 0.0);
        if o.distance_squared(core) <= f64::from(self.radius).powi(2) {
            return Some(0.0);
        }
        let side = self.side_entry(o, d).filter(|&t| t <= f64::from(max_t)).map(|t| t as f32);
        let [low, high] = self.end_balls();
        [side, low.ray_entry(ray, max_t), high.ray_entry(ray, max_t)]
            .into_iter()
            .flatten()
            .min_by(f32::total_cmp)
    }

    /// The corners of its box, which is the hull of its end balls' cubes:
    /// their hull holds the capsule (points on the capsule itself would not
    /// do, their hull lying inside it). Round parts are thus bounded as
    /// loosely as their box, unless alone ([`enclosing_sphere`]).
    ///
    /// [`enclosing_sphere`]: PartKind::enclosing_sphere
    fn fit_points(&self) -> Vec<Vec3> {
        let Aabb { min, max } = self.local_bounds();
        (0..8)
            .map(|i| Vec3::select(glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0), max, min))
            .collect()
    }

    /// The sphere about the core's middle reaching the ends' caps: the merge
    /// of the end balls.
    fn enclosing_sphere(&self) -> Option<Sphere> {
        let [low, high] = self.end_balls();
        Some(low.merge(&high))
    }

    /// Its smallest sphere ([`enclosing_sphere`]) and its box: a box turned
    /// off the capsule's axis must reach further across it to hold its caps.
    ///
    /// [`enclosing_sphere`]: PartKind::enclosing_sphere
    fn smallest_bounds(&self) -> Option<(Sphere, Obb)> {
        let Aabb { min, max } = self.local_bounds();
        let half_extents = max.max(-min);
        let obb = Obb { center: Vec3::ZERO, axes: Mat3::IDENTITY, half_extents };
        self.enclosing_sphere().map(|sphere| (sphere, obb))
    }

    /// Its radius and core scaled, by one factor on every axis.
    fn scaled(&self, factor: Vec3) -> Result<Capsule, ShapeError> {
        uniform(factor).map(|s| Capsule::new(self.radius * s, self.half_height * s))
    }

    /// A cylinder of the core's length and two half balls, each of these
    /// with its centroid `3r/8` beyond the core's end and its own inertia
    /// across, about the flat face's centre, that of a ball of its mass:
    /// about the core's axis `m_c r²/2 + m_b 2r²/5`, across it
    /// `m_c (r²/4 + h²/3) + m_b (2r²/5 + h² + 3hr/4)`, with `m_c = 2π r² h`
    /// and `m_b = 4/3 π r³` (the hemispheres moved from their centroids by
    /// the parallel axis theorem: Opsenica, "Capsule Inertia Tensor",
    /// GameDev.net 2014, as Jolt's `CapsuleShape` uses).
    fn mass_properties(&self) -> MassProperties {
        let (r, h) = (f64::from(self.radius), f64::from(self.half_height));
        let (cylinder, balls) = (2.0 * PI * r * r * h, 4.0 / 3.0 * PI * r.powi(3));
        let along = cylinder * r * r / 2.0 + balls * 0.4 * r * r;
        let across =
            cylinder * (r * r / 4.0 + h * h / 3.0) + balls * (0.4 * r * r + h * h + 0.75 * h * r);
        let inertia = DMat3::from_diagonal(DVec3::new(across, along, across));
        MassProperties::from_f64(cylinder + balls, DVec3::ZERO, inertia)
    }
}
