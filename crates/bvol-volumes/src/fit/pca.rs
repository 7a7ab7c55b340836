//! Principal-component boxes: the box on the eigenvectors of a covariance
//! matrix (Gottschalk, Lin & Manocha 1996, "OBBTree"; Ericson, Real-Time
//! Collision Detection 4.4.3).
//!
//! The covariance of the points alone is pulled toward wherever the mesh is
//! densely sampled. The covariance of the convex hull's surface, each triangle
//! integrated over its area (Gottschalk 2000, PhD thesis, 3.3), depends on the
//! shape alone and is far more robust.

use glam::{DMat3, DVec3, Vec3};

use super::eigen::symmetric_eigen;
use crate::{ConvexHull, Obb};

/// The box on the principal axes of the points' covariance.
pub(crate) fn pca_points(points: &[Vec3]) -> Obb {
    Obb::on_basis(points_axes(points.iter().map(|p| p.as_dvec3())), points)
}

/// The box on the principal axes of the convex hull's surface.
pub(crate) fn pca_hull(points: &[Vec3]) -> Obb {
    match ConvexHull::new(points) {
        Ok(hull) => Obb::on_basis(hull_axes(&hull), points),
        // The fitters get checked input, which the hull accepts; keep the
        // plain principal axes should that ever change.
        Err(_) => pca_points(points),
    }
}

/// The principal axes of a convex hull's surface: eigenvectors of the
/// area-weighted covariance of its triangles. A flat hull's triangles cover
/// its polygon, whose covariance has the plane's normal as the eigenvector of
/// eigenvalue zero; a hull without area (a segment or a point) falls back on
/// its vertices, whose major axis is along the segment.
pub(crate) fn hull_axes(hull: &ConvexHull) -> DMat3 {
    let vertices = hull.vertices();
    // Work about a point inside the hull, so that far-off inputs keep their
    // precision in the sums of squares.
    let origin = vertices.iter().fold(DVec3::ZERO, |s, p| s + p.as_dvec3()) / vertices.len() as f64;
    let at = |i: u32| vertices[i as usize].as_dvec3() - origin;
    let (mut area, mut first, mut second) = (0.0, DVec3::ZERO, DMat3::ZERO);
    for [a, b, c] in hull.triangles() {
        let (p, q, r) = (at(a), at(b), at(c));
        let weight = 0.5 * (q - p).cross(r - p).length();
        let m = (p + q + r) / 3.0;
        // The second moment of a triangle about the origin, over its area:
        // (9 m m^T + p p^T + q q^T + r r^T) / 12 (Ericson 4.4.3).
        let moment = (outer(m, m) * 9.0 + outer(p, p) + outer(q, q) + outer(r, r)) / 12.0;
        area += weight;
        first += m * weight;
        second += moment * weight;
    }
    if area > 0.0 {
        let mean = first / area;
        principal_axes(second / area - outer(mean, mean))
    } else {
        points_axes(vertices.iter().map(|p| p.as_dvec3()))
    }
}

/// The principal axes of a point set's covariance, about its mean.
fn points_axes<I: Iterator<Item = DVec3> + Clone>(points: I) -> DMat3 {
    let (sum, n) = points.clone().fold((DVec3::ZERO, 0.0), |(s, n), p| (s + p, n + 1.0));
    let mean = sum / n;
    let cov = points.fold(DMat3::ZERO, |c, p| c + outer(p - mean, p - mean));
    principal_axes(cov)
}

/// The eigenvectors of a covariance matrix, major axis first, as a rotation.
fn principal_axes(cov: DMat3) -> DMat3 {
    symmetric_eigen(cov).1
}

/// The outer product `a b^T`.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}
