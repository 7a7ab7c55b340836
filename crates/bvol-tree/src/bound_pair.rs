//! The two child bounds of an internal node, stored together in the layout
//! the pair search reads them in.

use std::fmt::Debug;

use bvol_volumes::Aabb;
use glam::{BVec4A, Vec2, Vec3, Vec4, Vec4Swizzles};

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
    /// Refits the pair of one internal node (the tree's refit pass, children
    /// before parents): side `s` takes the merge of `children[s]`, the pair
    /// of an internal child, when given; else the leaf bound `leaves[s]`,
    /// when given; else it keeps its bound. A leaf side whose bound changed
    /// has moved; one whose new bound does not even overlap the old one has
    /// jumped, and keeps the old one when `hold` (the tree reinserts it
    /// after the refit).
    fn refit(
        &mut self,
        children: [Option<&Self>; 2],
        leaves: [Option<&B>; 2],
        hold: bool,
    ) -> PairRefit;
}

/// What [`BoundPair::refit`] found in one pair.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairRefit {
    /// The leaf sides whose bound changed: bit `s` for side `s`.
    pub moved: u32,
    /// The moved sides whose new bound does not overlap the old one.
    pub jumped: u32,
    /// The summed cost ([`Bound::cost`](crate::Bound::cost)) of the sides
    /// set from internal children.
    pub cost: f64,
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

    /// On the lanes, with no box taken out of them: each side's source
    /// spread over both sides, then the sides taken from theirs.
    #[inline(always)]
    fn refit(
        &mut self,
        children: [Option<&Self>; 2],
        leaves: [Option<&Aabb>; 2],
        hold: bool,
    ) -> PairRefit {
        let old = self.lanes;
        let side = |s: usize| match (children[s], leaves[s]) {
            (Some(child), _) => child.merged_both(),
            (None, Some(leaf)) => AabbPair::both(leaf),
            (None, None) => old,
        };
        let mut now = AabbPair::take_sides(1, side(0), side(1));
        let internal = u32::from(children[0].is_some()) | u32::from(children[1].is_some()) << 1;
        let moved = AabbPair::differs(now, old) & !internal;
        let mut jumped = 0;
        if moved != 0 {
            jumped = moved & !AabbPair::overlap_sides(now, old);
            if hold {
                now = AabbPair::take_sides(jumped, old, now);
            }
        }
        self.lanes = now;
        let cost = match internal {
            0 => 0.0,
            _ => {
                let [c0, c1] = self.costs();
                let take = |s: u32, c: f64| if internal & s != 0 { c } else { 0.0 };
                take(1, c0) + take(2, c1)
            }
        };
        PairRefit { moved, jumped, cost }
    }
}

impl AabbPair {
    /// `bound` on both sides: its first four coordinates, and its last
    /// four, each spread over two lanes.
    #[inline(always)]
    fn both(bound: &Aabb) -> [Vec4; 3] {
        let (min, max) = (bound.min, bound.max);
        let first = Vec4::new(min.x, min.y, min.z, max.x);
        let last = Vec4::new(min.z, max.x, max.y, max.z);
        [first.xxyy(), first.zzww(), last.zzww()]
    }

    /// The merge of both sides on both sides: each vector against itself
    /// with the sides swapped, as in [`merged`](BoundPair::merged).
    #[inline(always)]
    fn merged_both(&self) -> [Vec4; 3] {
        let [l0, l1, l2] = self.lanes;
        let (mid_lo, mid_hi) = (l1.min(l1.yxwz()), l1.max(l1.yxwz()));
        let lower_half = BVec4A::new(true, true, false, false);
        [l0.min(l0.yxwz()), Vec4::select(lower_half, mid_lo, mid_hi), l2.max(l2.yxwz())]
    }

    /// The lanes of the sides in `sides` (bit `s` for side `s`) from
    /// `from`, the others from `rest`. Side 0 is lanes 0 and 2 of every
    /// vector, side 1 lanes 1 and 3.
    #[inline(always)]
    fn take_sides(sides: u32, from: [Vec4; 3], rest: [Vec4; 3]) -> [Vec4; 3] {
        let (a, b) = (sides & 1 != 0, sides & 2 != 0);
        let mask = BVec4A::new(a, b, a, b);
        [0, 1, 2].map(|k| Vec4::select(mask, from[k], rest[k]))
    }

    /// Which sides of `a` hold other bounds than the same side of `b`: bit
    /// `s` for side `s`.
    #[inline(always)]
    fn differs(a: [Vec4; 3], b: [Vec4; 3]) -> u32 {
        let lanes = (a[0].cmpne(b[0]) | a[1].cmpne(b[1]) | a[2].cmpne(b[2])).bitmask();
        u32::from(lanes & 0b0101 != 0) | u32::from(lanes & 0b1010 != 0) << 1
    }

    /// Which sides of `a` overlap the same side of `b`: bit `s` for side
    /// `s`. Lower x and y against upper x and y on one vector each, lower z
    /// against upper z on the lanes of side 0 and 1.
    #[inline(always)]
    fn overlap_sides(a: [Vec4; 3], b: [Vec4; 3]) -> u32 {
        let hi_xy = |l: [Vec4; 3]| Vec4::new(l[1].z, l[1].w, l[2].x, l[2].y);
        let z = |l: [Vec4; 3]| Vec4::new(l[1].x, l[1].y, l[2].z, l[2].w);
        let xy = a[0].cmple(hi_xy(b)) & b[0].cmple(hi_xy(a));
        let (za, zb) = (z(a), z(b));
        let lanes = (xy.bitmask() & (xy.bitmask() >> 2))
            & (za.cmple(zb.zwxy()).bitmask() & zb.cmple(za.zwxy()).bitmask());
        lanes & 0b11
    }

    /// Both sides' costs, from their extents in f64 as [`Aabb`]'s cost
    /// takes them.
    #[inline(always)]
    fn costs(&self) -> [f64; 2] {
        let [l0, l1, l2] = self.lanes;
        let extent = |hi: Vec2, lo: Vec2| hi.as_dvec2() - lo.as_dvec2();
        let x = extent(l1.zw(), l0.xy());
        let y = extent(l2.xy(), l0.zw());
        let z = extent(l2.zw(), l1.xy());
        let cost = 2.0 * (x * y + y * z + z * x);
        [cost.x, cost.y]
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

        /// The box pair's refit on lanes does what the boxes' own does
        /// (`[Aabb; 2]`, the refit of any bound, side by side): the sides
        /// it sets, the moves and jumps it finds, the cost to the bit. Each
        /// side from an internal child's pair, a leaf's bound, or neither;
        /// jumps held or not.
        #[test]
        fn box_pairs_refit_as_the_boxes_do(
            old in (aabb(), aabb()),
            children in (aabb(), aabb(), aabb(), aabb()),
            leaves in (aabb(), aabb()),
            kinds in (0..3u8, 0..3u8),
            hold: bool,
        ) {
            let old = [old.0, old.1];
            let children = [[children.0, children.1], [children.2, children.3]];
            let leaves = [leaves.0, leaves.1];
            let kinds = [kinds.0, kinds.1];
            let child = |s: usize| (kinds[s] == 0).then_some(s);
            let leaf = |s: usize| (kinds[s] == 1).then_some(&leaves[s]);
            let mut boxes = old;
            let lanes_children = children.map(AabbPair::new);
            let expected = boxes.refit(
                [child(0).map(|s| &children[s]), child(1).map(|s| &children[s])],
                [leaf(0), leaf(1)],
                hold,
            );
            let mut lanes = AabbPair::new(old);
            let found = lanes.refit(
                [child(0).map(|s| &lanes_children[s]), child(1).map(|s| &lanes_children[s])],
                [leaf(0), leaf(1)],
                hold,
            );
            prop_assert_eq!(found, expected);
            prop_assert_eq!([lanes.get(0), lanes.get(1)], boxes);
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
