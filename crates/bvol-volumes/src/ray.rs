//! Rays, and the slab interval clip they all share.

use glam::{DVec3, Vec3};

/// A ray `origin + t * direction` for `t >= 0`.
///
/// Distances returned by the ray tests are values of `t`: lengths when
/// `direction` is a unit vector. A zero direction component is fine (the ray
/// runs parallel to those slabs); a zero or non-finite direction never hits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Where it goes; need not be normalised.
    pub direction: Vec3,
}

impl Ray {
    /// A ray from `origin` along `direction`.
    pub const fn new(origin: Vec3, direction: Vec3) -> Self {
        Ray { origin, direction }
    }

    /// Whether the ray can hit anything: finite origin, finite non-zero direction.
    pub(crate) fn is_valid(&self) -> bool {
        self.origin.is_finite() && self.direction.is_finite() && self.direction != Vec3::ZERO
    }
}

/// The running parameter interval `[enter, exit]` of a ray inside a set of slabs
/// (Kay & Kajiya 1986; Ericson, Real-Time Collision Detection 5.3.3).
///
/// Each slab is given as the ray's coordinate `o` and rate `d` along the slab
/// normal, and the slab's `[lo, hi]`. A zero rate is handled as its own case, so
/// no `0 * inf` NaN is formed and a ray lying in a face plane counts as inside.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SlabClip {
    enter: f64,
    exit: f64,
}

impl SlabClip {
    pub(crate) fn new(max_t: f64) -> Self {
        SlabClip { enter: 0.0, exit: max_t }
    }

    /// Narrows the interval by one slab; returns false once it is empty.
    #[inline]
    pub(crate) fn clip(&mut self, o: f64, d: f64, lo: f64, hi: f64) -> bool {
        if d == 0.0 {
            return o >= lo && o <= hi;
        }
        let (t0, t1) = ((lo - o) / d, (hi - o) / d);
        let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        self.enter = self.enter.max(near);
        self.exit = self.exit.min(far);
        self.enter <= self.exit
    }

    /// The entry parameter, rounded down so the reported hit is never late.
    pub(crate) fn entry(&self) -> f32 {
        crate::round::down(self.enter).max(0.0)
    }
}

/// Origin and direction in f64, or `None` for a ray that cannot hit anything.
pub(crate) fn ray_f64(ray: &Ray, max_t: f32) -> Option<(DVec3, DVec3, f64)> {
    if !ray.is_valid() || max_t.is_nan() || max_t < 0.0 {
        return None;
    }
    Some((ray.origin.as_dvec3(), ray.direction.as_dvec3(), max_t as f64))
}
