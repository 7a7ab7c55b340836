//! The two child bounds of an internal node, stored together in the layout
//! the pair search reads them in.

use std::fmt::Debug;

use bvol_volumes::Aabb;
use glam::{Vec3, Vec4, Vec4Swizzles};

/// Two bounds side by side (side 0 and side 1): how an internal node of a
/// [`Tree`](crate::Tree) stores its children's bounds.
///
/// The pair search tests two nodes' children against each other, four
/// tests a step, and that step is most of its time; a bound's pair type
/// lays the two bounds out for it. `[B; 2]` serves any bound; boxes use
/// [`AabbPair`], laid out axis by axis so that the four tests run on SIMD
/// lanes.
pub trait BoundPair<B>: Copy + Debug + Send + Sync + 'static {
    /// The pair holding `bounds[0]` on side 0 and `bounds[1]` on side 1.
    fn new(bounds: [B; 2]) -> Self;
    /// The bound on `side` (0 or 1).
    fn get(&self, side: usize) -> B;
    /// Replaces the bound on `side` (0 or 1).
    fn set(&mut self, side: usize, bound: B);
    /// The merge of both bounds.
    fn merged(&self) -> B;
    /// Which of the four pairs of this pair's and `other`'s bounds overlap:
    /// bit `2 i + j` for side `i` of `self` against side `j` of `other`.
    fn overlaps(&self, other: &Self) -> u32;
}

/// Two boxes stored axis by axis, the two side by side on each: lower x of
/// side 0 and side 1, lower y, lower z, then the upper corner's the same
/// way, in three 16-byte vectors. One shuffle a vector puts the four pairs
/// of two nodes' children on four lanes (side `i` of one node repeated,
/// `[0, 0, 1, 1]`, against the other's alternating, `[0, 1, 0, 1]`), so
/// that the four overlap tests are six lane comparisons and one mask (the
/// layout of Wald et al.'s SIMD BVH nodes, "Ray Tracing Deformable Scenes
/// Using Dynamic Bounding Volume Hierarchies", 2007, applied to pairs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AabbPair {
    /// `[min x0, min x1, min y0, min y1]`, `[min z0, min z1, max x0, max x1]`,
    /// `[max y0, max y1, max z0, max z1]`.
    lanes: [Vec4; 3],
}

impl BoundPair<Aabb> for AabbPair {
    #[inline]
    fn new([a, b]: [Aabb; 2]) -> Self {
        AabbPair {
            lanes: [
                Vec4::new(a.min.x, b.min.x, a.min.y, b.min.y),
                Vec4::new(a.min.z, b.min.z, a.max.x, b.max.x),
                Vec4::new(a.max.y, b.max.y, a.max.z, b.max.z),
            ],
        }
    }

    #[inline]
    fn get(&self, side: usize) -> Aabb {
        let [l0, l1, l2] = self.lanes;
        Aabb {
            min: Vec3::new(l0[side], l0[2 + side], l1[side]),
            max: Vec3::new(l1[2 + side], l2[side], l2[2 + side]),
        }
    }

    #[inline]
    fn set(&mut self, side: usize, bound: Aabb) {
        let [l0, l1, l2] = &mut self.lanes;
        (l0[side], l0[2 + side], l1[side]) = (bound.min.x, bound.min.y, bound.min.z);
        (l1[2 + side], l2[side], l2[2 + side]) = (bound.max.x, bound.max.y, bound.max.z);
    }

    /// Each vector against itself with the sides swapped: the lower
    /// corner's lanes take the minimum, the upper's the maximum.
    #[inline]
    fn merged(&self) -> Aabb {
        let [l0, l1, l2] = self.lanes;
        let lo = l0.min(l0.yxwz());
        let (mid_lo, mid_hi) = (l1.min(l1.yxwz()), l1.max(l1.yxwz()));
        let hi = l2.max(l2.yxwz());
        Aabb { min: Vec3::new(lo.x, lo.z, mid_lo.x), max: Vec3::new(mid_hi.z, hi.x, hi.z) }
    }

    #[inline]
    fn overlaps(&self, other: &Self) -> u32 {
        let [a0, a1, a2] = self.lanes;
        let [b0, b1, b2] = other.lanes;
        // Lane 2 i + j: side i of `self`, side j of `other`.
        let lo_a = [a0.xxyy(), a0.zzww(), a1.xxyy()];
        let hi_a = [a1.zzww(), a2.xxyy(), a2.zzww()];
        let lo_b = [b0.xyxy(), b0.zwzw(), b1.xyxy()];
        let hi_b = [b1.zwzw(), b2.xyxy(), b2.zwzw()];
        let mut hit = lo_a[0].cmple(hi_b[0]) & lo_b[0].cmple(hi_a[0]);
        for axis in 1..3 {
            hit &= lo_a[axis].cmple(hi_b[axis]) & lo_b[axis].cmple(hi_a[axis]);
        }
        hit.bitmask()
    }
}

impl Default for AabbPair {
    fn default() -> Self {
        AabbPair::new([Aabb::default(); 2])
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    fn aabb() -> impl Strategy<Value = Aabb> {
        let corner = || {
            (-4i8..4, -4i8..4, -4i8..4)
                .prop_map(|(x, y, z)| Vec3::new(x as f32, y as f32, z as f32) * 0.5)
        };
        (corner(), corner()).prop_map(|(a, b)| Aabb::new(a.min(b), a.max(b)))
    }

    proptest! {
        /// The box pair's lanes give what the two boxes give one by one:
        /// the sides, their merge, each of the four overlap tests (on a
        /// half-unit grid, so that touching boxes are frequent).
        #[test]
        fn box_pairs_agree_with_the_boxes(a in aabb(), b in aabb(), c in aabb(), d in aabb(), e in aabb()) {
            let pair = AabbPair::new([a, b]);
            prop_assert_eq!([pair.get(0), pair.get(1)], [a, b]);
            prop_assert_eq!(pair.merged(), a.merge(&b));
            let other = AabbPair::new([c, d]);
            let each = (0..4).fold(0, |m, k| m | u32::from([a, b][k >> 1].overlaps(&[c, d][k & 1])) << k);
            prop_assert_eq!(pair.overlaps(&other), each);
            let mut changed = pair;
            changed.set(1, e);
            prop_assert_eq!(changed, AabbPair::new([a, e]));
        }
    }

    /// Both pairs' masks, checked bit by bit on boxes that are chosen to
    /// overlap in exactly one of the four pairings.
    #[test]
    fn the_mask_names_side_of_self_then_side_of_other() {
        let at = |x: f32| Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0));
        let (near, far) = (at(0.0), at(10.0));
        for k in 0..4 {
            let (i, j) = (k >> 1, k & 1);
            let mine = if i == 0 { [near, far] } else { [far, near] };
            let theirs = if j == 0 { [at(0.5), at(20.0)] } else { [at(20.0), at(0.5)] };
            assert_eq!(mine.overlaps(&theirs), 1 << k, "side {i} against side {j}");
            assert_eq!(AabbPair::new(mine).overlaps(&AabbPair::new(theirs)), 1 << k);
        }
    }
}
