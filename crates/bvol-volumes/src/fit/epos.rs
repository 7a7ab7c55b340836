//! EPOS-k (T. Larsson, "Fast and tight fitting of bounding spheres", SIGRAD
//! 2008): the exact minimum sphere of the extreme points along `k / 2` fixed
//! directions, grown by Ritter's pass to hold the rest. Nearly as tight as the
//! exact sphere, at about the cost of Ritter's.

use glam::{Vec3, Vec4};

use super::min_sphere::exact;
use super::min_sphere_f64;
use super::simple_sphere::grow;
use crate::Sphere;
use crate::directions::directions;

/// EPOS-k with `k = 2 N`: `N` = 3, 7 or 13 directions of
/// [`crate::directions::directions`] give EPOS-6, -14 and -26.
pub(crate) fn epos<const N: usize>(points: &[Vec3]) -> Sphere {
    // Larsson's algorithm 1: a set no larger than the extreme set gets its
    // exact sphere directly.
    if points.len() <= 2 * N {
        return exact(points);
    }
    let ends = extremes::<N>(points).map(|pair| pair.map(|i| points[i].as_dvec3()));
    let (center, radius) = min_sphere_f64(ends.as_flattened());
    Sphere::enclosing(grow(center, radius, points), points)
}

/// Points per block of the extreme-point pass.
const BLOCK: usize = 64;

/// For each of the `N` directions of [`directions`], the indices of the points
/// with the smallest and the largest projection on it, in one pass.
///
/// The pass keeps only running minima and maxima per block of points, in SIMD
/// lanes; the rare block that improves on a direction's extreme is scanned
/// again, on that direction alone, for the point's index. The projections are
/// done in f32: rounding can only pick a point a hair short of the true
/// extreme, which the growing pass then covers.
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
