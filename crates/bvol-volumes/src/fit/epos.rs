//! EPOS-k (T. Larsson, "Fast and tight fitting of bounding spheres", SIGRAD
//! 2008): the exact minimum sphere of the extreme points along `k / 2` fixed
//! directions, grown by Ritter's pass to hold the rest. Nearly as tight as the
//! exact sphere, at about the cost of Ritter's.

use glam::Vec3;

use super::min_sphere::{exact, min_sphere_f64};
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

/// For each of the `N` directions of [`directions`], the indices of the points
/// with the smallest and the largest projection on it, in one pass.
///
/// The projections are sums and differences of coordinates (the directions'
/// components are -1, 0 and 1), done in f32: rounding can only pick a point a
/// hair short of the true extreme, which the growing pass then covers.
pub(crate) fn extremes<const N: usize>(points: &[Vec3]) -> [[usize; 2]; N] {
    let dirs = const { directions::<N>() };
    let mut lo = [f32::INFINITY; N];
    let mut hi = [f32::NEG_INFINITY; N];
    let mut at = [[0; 2]; N];
    for (i, &p) in points.iter().enumerate() {
        for k in 0..N {
            let s = project(dirs[k], p);
            if s < lo[k] {
                lo[k] = s;
                at[k][0] = i;
            }
            if s > hi[k] {
                hi[k] = s;
                at[k][1] = i;
            }
        }
    }
    at
}

/// `d . p` without multiplications. The direction is a constant once the loop
/// above is unrolled, so the match folds away; a zero component adds `-0.0`,
/// the one float that adding leaves every value unchanged by, so it folds too.
#[inline(always)]
fn project(d: [i8; 3], p: Vec3) -> f32 {
    let term = |d: i8, x: f32| match d {
        1 => x,
        -1 => -x,
        _ => -0.0,
    };
    term(d[0], p.x) + term(d[1], p.y) + term(d[2], p.z)
}
