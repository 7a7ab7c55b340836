//! The node bound of a tree: what the tree needs of a bounding volume.

use std::fmt::{self, Debug};

use bvol_volumes::{Aabb, Ray, Sphere};
use glam::{Vec3, Vec3A};

use crate::{AabbPair, BoundPair, PairRefit};

/// Why a bound cannot go in a tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BoundError {
    /// A coordinate or the radius is NaN or infinite.
    NonFinite,
    /// `min > max` on an axis (0 = x, 1 = y, 2 = z).
    Inverted {
        /// The axis.
        axis: usize,
        /// The lower corner's coordinate on it.
        min: f32,
        /// The upper corner's coordinate on it.
        max: f32,
    },
    /// A sphere with a negative radius.
    NegativeRadius {
        /// The radius.
        radius: f32,
    },
}

impl fmt::Display for BoundError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BoundError::NonFinite => write!(f, "has a NaN or infinite coordinate"),
            BoundError::Inverted { axis, min, max } => {
                write!(f, "has min > max on axis {}: {min} > {max}", ["x", "y", "z"][*axis])
            }
            BoundError::NegativeRadius { radius } => write!(f, "has a negative radius {radius}"),
        }
    }
}

impl std::error::Error for BoundError {}

/// A bounding volume a [`Tree`](crate::Tree) can be built of.
///
/// Internal nodes hold the [`merge`](Bound::merge) of their children, so the
/// merge must contain both inputs exactly (after f32 rounding), and
/// [`contains`](Bound::contains) must agree with it: `a.merge(b).contains(a)`
/// always holds. [`overlaps`](Bound::overlaps) is closed: touching counts.
///
/// Implemented for [`Aabb`] (the fast choice) and [`Sphere`] (internal nodes
/// are exact minimal sphere merges; slower, kept to compare the two).
pub trait Bound: Copy + Default + PartialEq + Debug + Send + Sync + 'static {
    /// How an internal node stores its two children's bounds: `[Self; 2]`,
    /// or a layout the pair search reads faster ([`AabbPair`] for boxes).
    type Pair: BoundPair<Self>;
    /// The smallest bound of this kind holding both.
    fn merge(&self, other: &Self) -> Self;
    /// Whether the two overlap or touch.
    fn overlaps(&self, other: &Self) -> bool;
    /// Whether `other` lies inside or on this bound.
    fn contains(&self, other: &Self) -> bool;
    /// The surface area: the cost measure of the surface area heuristic
    /// (Goldsmith & Salmon 1987; MacDonald & Booth 1990). In f64 so that huge
    /// (finite) bounds give finite costs and cost sums never overflow.
    fn cost(&self) -> f64;
    /// The bound grown by `margin >= 0` on every side; itself if growing it
    /// would overflow to infinity.
    fn fattened(&self, margin: f32) -> Self;
    /// Why the bound cannot go in a tree: non-finite, inverted or negative.
    fn check(&self) -> Result<(), BoundError>;
    /// Whether [`check`](Self::check) passes, without branches: a frame's
    /// bounds are checked in bulk (folded with `&`), and the failing one is
    /// searched for with [`check`](Self::check) only when the fold fails.
    #[inline]
    fn is_valid(&self) -> bool {
        self.check().is_ok()
    }
    /// The centre, used to order and bin leaves when building.
    fn center(&self) -> Vec3;
    /// A characteristic size (largest half extent, or the radius), used to
    /// scale fat margins to the body.
    fn size(&self) -> f32;
    /// The axis-aligned box around it, used for binned SAH builds: boxes are
    /// merged in bins far faster than spheres, and rank splits as well.
    fn aabb(&self) -> Aabb;
    /// Where a ray enters the bound (`Some(0.0)` when it starts inside), or
    /// `None` when it misses or would enter beyond `max_t`.
    fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32>;
}

/// Two bounds as they are, side by side: the pair of any bound without a
/// layout of its own (spheres, and bounds defined outside the crate).
impl<B: Bound> BoundPair<B> for [B; 2] {
    #[inline]
    fn new(bounds: [B; 2]) -> Self {
        bounds
    }

    #[inline]
    fn get(&self, side: usize) -> B {
        self[side]
    }

    #[inline]
    fn set(&mut self, side: usize, bound: B) {
        self[side] = bound;
    }

    #[inline]
    fn merged(&self) -> B {
        self[0].merge(&self[1])
    }

    #[inline]
    fn overlaps(&self, other: &Self) -> u32 {
        (0..4).fold(0, |mask, k| mask | u32::from(self[k >> 1].overlaps(&other[k & 1])) << k)
    }

    #[inline]
    fn refit(
        &mut self,
        children: [Option<&Self>; 2],
        leaves: [Option<&B>; 2],
        hold: bool,
    ) -> PairRefit {
        let mut found = PairRefit::default();
        for side in 0..2 {
            if let Some(child) = children[side] {
                self[side] = child.merged();
                found.cost += self[side].cost();
            } else if let Some(&leaf) = leaves[side]
                && leaf != self[side]
            {
                found.moved |= 1 << side;
                let jumped = !leaf.overlaps(&self[side]);
                found.jumped |= u32::from(jumped) << side;
                if !(jumped && hold) {
                    self[side] = leaf;
                }
            }
        }
        found
    }
}

impl Bound for Aabb {
    type Pair = AabbPair;

    #[inline]
    fn merge(&self, other: &Self) -> Self {
        Aabb::merge(self, other)
    }

    /// Two SIMD comparisons and one mask test: branch-free, since a tree
    /// traversal mispredicts short-circuit branches about half the time.
    #[inline]
    fn overlaps(&self, other: &Self) -> bool {
        let lo = Vec3A::from(self.min).cmple(Vec3A::from(other.max));
        let hi = Vec3A::from(other.min).cmple(Vec3A::from(self.max));
        (lo & hi).all()
    }

    #[inline]
    fn contains(&self, other: &Self) -> bool {
        Aabb::contains(self, other)
    }

    #[inline]
    fn cost(&self) -> f64 {
        let e = self.max.as_dvec3() - self.min.as_dvec3();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    fn fattened(&self, margin: f32) -> Self {
        let m = Vec3::splat(margin);
        let fat = Aabb::new(self.min - m, self.max + m);
        if fat.min.is_finite() && fat.max.is_finite() { fat } else { *self }
    }

    fn check(&self) -> Result<(), BoundError> {
        if self.is_valid() {
            return Ok(());
        }
        if !(self.min.is_finite() && self.max.is_finite()) {
            return Err(BoundError::NonFinite);
        }
        match (0..3).find(|&axis| self.min[axis] > self.max[axis]) {
            Some(axis) => {
                Err(BoundError::Inverted { axis, min: self.min[axis], max: self.max[axis] })
            }
            None => Ok(()),
        }
    }

    /// On SIMD lanes: `x * 0` is 0 for a finite `x` and NaN otherwise, and
    /// `min <= max` fails for NaN: a few lane-wise operations where testing
    /// each number in turn would branch six times.
    #[inline]
    fn is_valid(&self) -> bool {
        let (min, max) = (Vec3A::from(self.min), Vec3A::from(self.max));
        ((min * 0.0 + max * 0.0).cmpeq(Vec3A::ZERO) & min.cmple(max)).all()
    }

    /// Halves first: `(min + max) / 2` overflows for boxes past 1.7e38.
    #[inline]
    fn center(&self) -> Vec3 {
        self.min * 0.5 + self.max * 0.5
    }

    fn size(&self) -> f32 {
        self.half_extents().max_element()
    }

    #[inline]
    fn aabb(&self) -> Aabb {
        *self
    }

    fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32> {
        Aabb::ray_entry(self, ray, max_t)
    }
}

impl Bound for Sphere {
    type Pair = [Sphere; 2];

    /// The exact minimal merge (the larger one when it holds the other).
    fn merge(&self, other: &Self) -> Self {
        Sphere::merge(self, other)
    }

    fn overlaps(&self, other: &Self) -> bool {
        Sphere::overlaps(self, other)
    }

    /// In f64, by the same expression [`Sphere::merge`] bounds its result with,
    /// so a merge always contains its inputs by this test.
    fn contains(&self, other: &Self) -> bool {
        let d = (other.center.as_dvec3() - self.center.as_dvec3()).length();
        d + other.radius as f64 <= self.radius as f64
    }

    fn cost(&self) -> f64 {
        let r = self.radius as f64;
        4.0 * std::f64::consts::PI * r * r
    }

    fn fattened(&self, margin: f32) -> Self {
        let radius = self.radius + margin;
        if radius.is_finite() { Sphere::new(self.center, radius) } else { *self }
    }

    /// On SIMD lanes, as [`Aabb`]'s.
    #[inline]
    fn is_valid(&self) -> bool {
        let zero = Vec3A::from(self.center) * 0.0 + self.radius * 0.0;
        zero.cmpeq(Vec3A::ZERO).all() & (self.radius >= 0.0)
    }

    fn check(&self) -> Result<(), BoundError> {
        if !(self.center.is_finite() && self.radius.is_finite()) {
            return Err(BoundError::NonFinite);
        }
        if self.radius < 0.0 {
            return Err(BoundError::NegativeRadius { radius: self.radius });
        }
        Ok(())
    }

    fn center(&self) -> Vec3 {
        self.center
    }

    fn size(&self) -> f32 {
        self.radius
    }

    fn aabb(&self) -> Aabb {
        Sphere::aabb(self)
    }

    fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32> {
        Sphere::ray_entry(self, ray, max_t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Finite, signed zeros, extremes, infinities and NaN.
    const SPECIAL: [f32; 9] = [
        0.0,
        -0.0,
        1.5,
        -2.0,
        f32::MAX,
        f32::MIN_POSITIVE / 2.0,
        f32::INFINITY,
        -f32::INFINITY,
        f32::NAN,
    ];

    /// `is_valid` against the rule written out number by number, on every
    /// box whose six numbers are drawn from [`SPECIAL`].
    #[test]
    fn box_is_valid_exactly_when_finite_and_ordered() {
        let mut n = [0usize; 6];
        loop {
            let v = n.map(|k| SPECIAL[k]);
            let b = Aabb { min: Vec3::new(v[0], v[1], v[2]), max: Vec3::new(v[3], v[4], v[5]) };
            let want = v.iter().all(|x| x.is_finite()) && (0..3).all(|k| v[k] <= v[k + 3]);
            assert_eq!(b.is_valid(), want, "{b:?}");
            assert_eq!(Bound::check(&b).is_ok(), want, "{b:?}");
            let Some(k) = n.iter().position(|&k| k + 1 < SPECIAL.len()) else { break };
            n[k] += 1;
            n[..k].fill(0);
        }
    }

    /// The same for spheres: finite centre and radius, radius not negative.
    #[test]
    fn sphere_is_valid_exactly_when_finite_and_not_negative() {
        for x in SPECIAL {
            for y in SPECIAL {
                for r in SPECIAL {
                    let s = Sphere { center: Vec3::new(x, y, 1.0), radius: r };
                    let want = x.is_finite() && y.is_finite() && r.is_finite() && r >= 0.0;
                    assert_eq!(s.is_valid(), want, "{s:?}");
                    assert_eq!(Bound::check(&s).is_ok(), want, "{s:?}");
                }
            }
        }
    }
}
