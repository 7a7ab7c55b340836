//! The quick spheres: about the AABB centre, about the centroid, and Ritter's
//! (1990). Each costs a pass or three over the points; none is minimal.

use glam::{DVec3, Vec3};

use super::extremes::extremes;
use crate::{Aabb, Sphere};

/// The sphere about the centre of the points' AABB; the radius comes from the
/// containment pass (squared distances, one square root).
pub(crate) fn aabb_center(points: &[Vec3]) -> Sphere {
    let b = Aabb::of_points(points);
    // Exact in f64: the sum of two f32 values halved.
    Sphere::enclosing((b.min.as_dvec3() + b.max.as_dvec3()) * 0.5, points)
}

/// The sphere about the mean of the points (summed in f64: a million f32
/// points lose next to nothing to rounding), to the farthest point.
pub(crate) fn centroid(points: &[Vec3]) -> Sphere {
    let sum = points.iter().fold(DVec3::ZERO, |s, p| s + p.as_dvec3());
    Sphere::enclosing(sum / points.len() as f64, points)
}

/// Ritter's sphere (J. Ritter, "An efficient bounding sphere", Graphics Gems,
/// 1990): of the 6 axis-extreme points, the pair farthest apart is the first
/// diameter; then one pass grows the sphere for each point outside.
pub(crate) fn ritter(points: &[Vec3]) -> Sphere {
    let pairs =
        extremes::<3>(points).map(|[lo, hi]| (points[lo].as_dvec3(), points[hi].as_dvec3()));
    let span = |(a, b): (DVec3, DVec3)| (b - a).length_squared();
    let (a, b) = pairs.into_iter().fold(pairs[0], |w, p| if span(p) > span(w) { p } else { w });
    let center = grow((a + b) * 0.5, (b - a).length() * 0.5, points);
    Sphere::enclosing(center, points)
}

/// Ritter's growing pass, shared with EPOS: for each point outside the sphere,
/// the smallest sphere holding the old one and the point (centre moved by
/// `(d - r) / 2` towards it, `r = (d + r) / 2`). Returns the final centre; the
/// caller's containment pass recomputes the radius.
///
/// The test is on squared distances, so only the few points that grow the
/// sphere pay for a square root.
pub(crate) fn grow(mut center: DVec3, mut radius: f64, points: &[Vec3]) -> DVec3 {
    let mut radius2 = radius * radius;
    for p in points {
        let to_p = p.as_dvec3() - center;
        let d2 = to_p.length_squared();
        if d2 > radius2 {
            let d = d2.sqrt();
            let grown = (radius + d) * 0.5;
            center += to_p * ((grown - radius) / d);
            radius = grown;
            radius2 = radius * radius;
        }
    }
    center
}
