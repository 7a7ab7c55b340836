//! Axis-aligned bounding boxes.

use glam::{DVec3, Vec3};

use crate::Pose;
use crate::ray::{Ray, SlabClip, ray_f64};
use crate::round::{down, up};

/// An axis-aligned box, `min <= max` on every axis (closed: faces included).
///
/// ```
/// use bvol_volumes::Aabb;
/// use glam::Vec3;
/// let a = Aabb::fit(&[Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0)]).unwrap();
/// assert_eq!(a.volume(), 6.0);
/// assert!(a.overlaps(&Aabb::new(Vec3::splat(1.0), Vec3::splat(5.0))));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Aabb {
    /// A box from its corners; `min <= max` is expected on every axis.
    pub const fn new(min: Vec3, max: Vec3) -> Self {
        Aabb { min, max }
    }

    /// The tight box of a non-empty point set: min and max of the coordinates.
    pub(crate) fn of_points(points: &[Vec3]) -> Aabb {
        let (min, max) =
            points.iter().fold((points[0], points[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        Aabb { min, max }
    }

    /// The box around f64 points, rounded outward to f32.
    pub(crate) fn around_f64(points: &[DVec3]) -> Aabb {
        let lo = points.iter().fold(DVec3::INFINITY, |a, &p| a.min(p));
        let hi = points.iter().fold(DVec3::NEG_INFINITY, |a, &p| a.max(p));
        Aabb::from_f64_outward(lo, hi)
    }

    /// The box of f64 corners, rounded outward to f32.
    pub(crate) fn from_f64_outward(min: DVec3, max: DVec3) -> Aabb {
        Aabb {
            min: Vec3::new(down(min.x), down(min.y), down(min.z)),
            max: Vec3::new(up(max.x), up(max.y), up(max.z)),
        }
    }

    /// Centre of the box.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Half the size of the box on each axis.
    pub fn half_extents(&self) -> Vec3 {
        (self.max - self.min) * 0.5
    }

    /// Whether `p` lies inside or on the box (exact).
    pub fn contains_point(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Whether `other` lies inside or on this box.
    pub fn contains(&self, other: &Aabb) -> bool {
        other.min.cmpge(self.min).all() && other.max.cmple(self.max).all()
    }

    /// Volume.
    ///
    /// In f32 it overflows to infinity past about 7e12 a side, well within
    /// the coordinates a body may have: [`volume_f64`](Self::volume_f64)
    /// does not.
    pub fn volume(&self) -> f32 {
        self.volume_f64() as f32
    }

    /// Volume, in f64.
    pub fn volume_f64(&self) -> f64 {
        let e = self.max.as_dvec3() - self.min.as_dvec3();
        e.x * e.y * e.z
    }

    /// Surface area.
    pub fn surface_area(&self) -> f32 {
        let e = self.max.as_dvec3() - self.min.as_dvec3();
        (2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)) as f32
    }

    /// The tight box around this box moved by a rigid pose (Arvo, Graphics Gems
    /// 1990: extents through |R|), computed in f64 and rounded outward.
    pub fn transformed(&self, pose: &Pose) -> Aabb {
        let (c, e) = (self.center_f64(), self.half_extents_f64());
        let r = pose.rotation_f64();
        let abs = glam::DMat3::from_cols(r.x_axis.abs(), r.y_axis.abs(), r.z_axis.abs());
        let (c, e) = (r * c + pose.position.as_dvec3(), abs * e);
        Aabb::from_f64_outward(c - e, c + e)
    }

    /// The smallest box holding both.
    pub fn merge(&self, other: &Aabb) -> Aabb {
        Aabb { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    /// Itself: an AABB is its own tight box.
    pub fn aabb(&self) -> Aabb {
        *self
    }

    /// Whether two boxes overlap or touch.
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// Squared distance from a point to the box (0 inside), in f64.
    pub(crate) fn distance_squared_f64(&self, p: DVec3) -> f64 {
        let q = p.clamp(self.min.as_dvec3(), self.max.as_dvec3());
        (p - q).length_squared()
    }

    /// Where a ray enters the box: `Some(0.0)` if it starts inside or on a face,
    /// `None` if it misses or would enter beyond `max_t`.
    pub fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32> {
        let (o, d, max_t) = ray_f64(ray, max_t)?;
        let (lo, hi) = (self.min.as_dvec3(), self.max.as_dvec3());
        let mut clip = SlabClip::new(max_t);
        for i in 0..3 {
            if !clip.clip(o[i], d[i], lo[i], hi[i]) {
                return None;
            }
        }
        Some(clip.entry())
    }

    fn center_f64(&self) -> DVec3 {
        (self.min.as_dvec3() + self.max.as_dvec3()) * 0.5
    }

    fn half_extents_f64(&self) -> DVec3 {
        (self.max.as_dvec3() - self.min.as_dvec3()) * 0.5
    }
}
