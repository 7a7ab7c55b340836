//! Bounding spheres.

use glam::{DVec3, Vec3};

use crate::lane::{Lane, M3, V3};
use crate::pose::place_point;
use crate::ray::{Ray, ray_f64};
use crate::round::{down, up_safe};
use crate::{Aabb, Pose};

/// A sphere: every point within `radius` of `center`.
///
/// ```
/// use bvol_volumes::{Sphere, SphereMethod};
/// use glam::Vec3;
/// let points = [Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.5, 0.0)];
/// let s = Sphere::fit(&points, SphereMethod::Exact).unwrap();
/// assert!(points.iter().all(|&p| s.contains_point(p)));
/// assert!((s.radius - 1.0).abs() < 1e-6);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius, `>= 0`.
    pub radius: f32,
}

impl Sphere {
    /// A sphere from its centre and radius.
    pub const fn new(center: Vec3, radius: f32) -> Self {
        Sphere { center, radius }
    }

    /// The smallest f32 sphere about `center` (rounded to f32) that holds every
    /// point: the last pass every fitter ends with, so containment survives
    /// rounding whatever the fitter did before.
    pub(crate) fn enclosing(center: DVec3, points: &[Vec3]) -> Sphere {
        let c = center.as_vec3();
        let cd = c.as_dvec3();
        let r2 = points.iter().map(|p| (p.as_dvec3() - cd).length_squared()).fold(0.0, f64::max);
        Sphere { center: c, radius: up_safe(r2.sqrt()) }
    }

    /// Whether `p` lies inside or on the sphere; evaluated in f64, so it is exact
    /// for the stored f32 values up to f64 rounding.
    pub fn contains_point(&self, p: Vec3) -> bool {
        let r = self.radius as f64;
        (p.as_dvec3() - self.center.as_dvec3()).length_squared() <= r * r
    }

    /// Volume, `4/3 pi r^3`.
    ///
    /// In f32 it overflows to infinity past about 7e12 a side, well within
    /// the coordinates a body may have: [`volume_f64`](Self::volume_f64)
    /// does not.
    pub fn volume(&self) -> f32 {
        self.volume_f64() as f32
    }

    /// Volume, `4/3 pi r^3`, in f64.
    pub fn volume_f64(&self) -> f64 {
        let r = self.radius as f64;
        4.0 / 3.0 * std::f64::consts::PI * r * r * r
    }

    /// Surface area, `4 pi r^2`.
    pub fn surface_area(&self) -> f32 {
        let r = self.radius as f64;
        (4.0 * std::f64::consts::PI * r * r) as f32
    }

    /// The sphere moved by a rigid pose, in f32 (a few dozen operations: this
    /// runs for every moved body every frame). The radius grows by a bound on
    /// the rounding of the new centre, so the exact image of the old sphere
    /// stays inside.
    pub fn transformed(&self, pose: &Pose) -> Sphere {
        let (r, position) = pose.lane();
        let (center, radius) = place(&r, position, self.center.into(), self.radius);
        Sphere { center: center.into(), radius }
    }

    /// The smallest sphere holding both: the larger one if it holds the other,
    /// else radius `(L + r0 + r1) / 2` on the line of centres, `L` their distance.
    ///
    /// ```
    /// use bvol_volumes::Sphere;
    /// use glam::Vec3;
    /// let m = Sphere::new(Vec3::ZERO, 1.0).merge(&Sphere::new(Vec3::new(4.0, 0.0, 0.0), 1.0));
    /// assert_eq!(m.center, Vec3::new(2.0, 0.0, 0.0));
    /// assert!(m.radius >= 3.0 && m.radius - 3.0 < 1e-6); // rounded up, never down
    /// ```
    pub fn merge(&self, other: &Sphere) -> Sphere {
        let (c0, r0) = (self.center.as_dvec3(), self.radius as f64);
        let (c1, r1) = (other.center.as_dvec3(), other.radius as f64);
        let l = (c1 - c0).length();
        if l + r1 <= r0 {
            return *self;
        }
        if l + r0 <= r1 {
            return *other;
        }
        let r = (l + r0 + r1) / 2.0;
        let c = (c0 + (c1 - c0) * ((r - r0) / l)).as_vec3().as_dvec3();
        let radius = ((c - c0).length() + r0).max((c - c1).length() + r1);
        Sphere { center: c.as_vec3(), radius: up_safe(radius) }
    }

    /// The tight box around the sphere, rounded outward.
    pub fn aabb(&self) -> Aabb {
        let (c, r) = (self.center.as_dvec3(), self.radius as f64);
        Aabb::from_f64_outward(c - DVec3::splat(r), c + DVec3::splat(r))
    }

    /// Whether two spheres overlap or touch.
    pub fn overlaps(&self, other: &Sphere) -> bool {
        let r = self.radius as f64 + other.radius as f64;
        (self.center.as_dvec3() - other.center.as_dvec3()).length_squared() <= r * r
    }

    /// Whether the sphere overlaps or touches a box.
    pub fn overlaps_aabb(&self, aabb: &Aabb) -> bool {
        aabb.distance_squared_f64(self.center.as_dvec3()) <= (self.radius as f64).powi(2)
    }

    /// Where a ray enters the sphere: `Some(0.0)` if it starts inside, `None` if it
    /// misses or would enter beyond `max_t`. Uses the numerically stable form
    /// (Haines et al., Ray Tracing Gems ch. 7): the discriminant from the distance
    /// of the centre to the ray's line, and the near root without cancellation.
    pub fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32> {
        let (o, d, max_t) = ray_f64(ray, max_t)?;
        let (f, r) = (o - self.center.as_dvec3(), self.radius as f64);
        let c = f.length_squared() - r * r;
        if c <= 0.0 {
            return Some(0.0);
        }
        let a = d.length_squared();
        let b = -f.dot(d);
        if b <= 0.0 {
            return None; // outside and heading away
        }
        let disc = r * r - (f + d * (b / a)).length_squared();
        if disc < 0.0 {
            return None;
        }
        let q = b + (a * disc).sqrt();
        let t = c / q;
        (t <= max_t).then(|| down(t).max(0.0))
    }
}

/// A sphere's centre and radius moved by rotation `r` (from
/// [`rotation`](crate::pose::rotation)) and translation `position`: the
/// radius grows by the bound on the centre's rounding, then by an ulp.
#[inline(always)]
pub(crate) fn place<L: Lane>(r: &M3<L>, position: V3<L>, center: V3<L>, radius: L) -> (V3<L>, L) {
    let (center, slip) = place_point(r, position, center);
    (center, (radius + slip).next_up())
}
