//! The extreme points of a set along the fixed slab directions, in one pass:
//! the first step of Ritter's sphere, EPOS (Larsson 2008) and DiTO (Larsson &
//! Kallberg 2011), and the pass their speed rests on.

use glam::{Vec3, Vec4};

use crate::directions::directions;

/// Points per block of the extreme-point pass.
const BLOCK: usize = 64;

/// For each of the `N` directions of [`directions`], the indices of the points
/// with the smallest and the largest projection on it, in one pass.
///
/// The pass keeps only running minima and maxima per block of points, in SIMD
/// lanes; the rare block that improves on a direction's extreme is scanned
/// again, on that direction alone, for the point's index. The projections are
/// done in f32: rounding can only pick a point a hair short of the true
/// extreme, which every caller's final containment pass over all points covers.
pub(crate) fn extremes<const N: usize>(points: &[Vec3]) -> [[usize; 2]; N] {
    let lanes = Lanes::<N>::new();
    let mut lo = [f32::INFINITY; N];
    let mut hi = [f32::NEG_INFINITY; N];
    let mut at = [[0; 2]; N];
    for (b, block) in points.chunks(BLOCK).enumerate() {
        let (block_lo, block_hi) = lanes.bounds(block);
        for k in 0..N {
            let (g, j) = (k / 4, k % 4);
            if block_lo[g][j] < lo[k] {
                lo[k] = block_lo[g][j];
                at[k][0] = b * BLOCK + lanes.find(block, k, lo[k]);
            }
            if block_hi[g][j] > hi[k] {
                hi[k] = block_hi[g][j];
                at[k][1] = b * BLOCK + lanes.find(block, k, hi[k]);
            }
        }
    }
    at
}

/// The `N` directions four to a SIMD vector, one vector per coordinate, zero
/// past the last direction: a point's projections on four directions cost
/// three multiplications (exact, the components being -1, 0 and 1) and two
/// additions.
struct Lanes<const N: usize> {
    x: [Vec4; 4],
    y: [Vec4; 4],
    z: [Vec4; 4],
}

impl<const N: usize> Lanes<N> {
    /// Vectors in use: 13 directions at most fill 4.
    const GROUPS: usize = N.div_ceil(4);

    fn new() -> Self {
        let dirs = const { directions::<N>() };
        let lane = |axis: usize| -> [Vec4; 4] {
            std::array::from_fn(|g| {
                Vec4::from_array(std::array::from_fn(|j| {
                    dirs.get(4 * g + j).map_or(0.0, |d| d[axis] as f32)
                }))
            })
        };
        Lanes { x: lane(0), y: lane(1), z: lane(2) }
    }

    /// The projections of `p` on directions `4 g .. 4 g + 4`.
    #[inline(always)]
    fn project(&self, g: usize, p: Vec3) -> Vec4 {
        self.x[g] * p.x + self.y[g] * p.y + self.z[g] * p.z
    }

    /// The least and greatest projections of a block on every direction.
    #[inline(always)]
    fn bounds(&self, block: &[Vec3]) -> ([Vec4; 4], [Vec4; 4]) {
        let mut lo = [Vec4::INFINITY; 4];
        let mut hi = [Vec4::NEG_INFINITY; 4];
        for &p in block {
            for g in 0..Self::GROUPS {
                let s = self.project(g, p);
                lo[g] = lo[g].min(s);
                hi[g] = hi[g].max(s);
            }
        }
        (lo, hi)
    }

    /// The position in `block` of the first point whose projection on
    /// direction `k` is `value`. [`Lanes::bounds`] took `value` from this block
    /// by the same arithmetic, so the point is there; 0 would still be a valid
    /// index if it were not.
    fn find(&self, block: &[Vec3], k: usize, value: f32) -> usize {
        block.iter().position(|&p| self.project(k / 4, p)[k % 4] == value).unwrap_or(0)
    }
}
