//! EPOS-k (T. Larsson, "Fast and tight fitting of bounding spheres", SIGRAD
//! 2008): the exact minimum sphere of the extreme points along `k / 2` fixed
//! directions, grown by Ritter's pass to hold the rest. Nearly as tight as the
//! exact sphere, at about the cost of Ritter's.

use glam::Vec3;

use super::extremes::extremes;
use super::min_sphere::{exact, min_sphere_f64};
use super::simple_sphere::grow;
use crate::Sphere;

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
