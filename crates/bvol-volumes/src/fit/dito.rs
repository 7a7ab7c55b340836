//! DiTO-k boxes (Larsson & Kallberg 2011, "Fast computation of tight-fitting
//! oriented bounding boxes", Game Engine Gems 2, chapter 1).
//!
//! One pass finds the extreme points along `N` fixed slab directions. On those
//! `2N` points alone: a large base triangle (the farthest pair of extremes and
//! the extreme farthest from their line) and the two tetrahedra raised on it
//! to the extremes farthest above and below its plane give up to seven
//! triangles; each triangle's edges give three axis triples (edge, normal,
//! their cross product). The triple whose box on the extremes is smallest
//! wins, and its box over all points is kept unless the AABB's is no larger
//! (the paper's final check). Cost: one pass for the extremes, two for the
//! final box.
//!
//! Boxes are ranked by volume, flat ones (zero volume up to rounding) first
//! and by surface area among themselves. The paper ranks by surface area
//! alone; on the real meshes the two agree to within a few percent, but area
//! prefers a thin rod to the flat box of a coplanar set (a flat box counts both
//! sides), and volume is what this crate's boxes are judged by.

use glam::{DMat3, DVec3, Vec3};

use super::extremes::extremes;
use crate::Obb;
use crate::obb::basis;

/// Relative distance below which a third point counts as on the base line, or
/// a fourth as on the base plane (the paper's degenerate cases). It only has to
/// keep normals away from rounding noise: f64 cross products of the exact
/// differences of f32 points stay accurate far below it.
const FLAT: f64 = 1e-9;

/// Width of the base triangle, relative to its length, below which the
/// extremes count as nearly collinear and the third vertex is sought among all
/// points.
const SLIVER: f64 = 1e-2;

/// Relative thickness below which a box counts as flat: above the f32
/// rounding of points (about 6e-8 of their coordinates) unless they lie far
/// from the origin for their size, far below real thin parts. Too large, and
/// a tilted box would rank as flat beside the plane's own.
const FLAT_BOX: f64 = 1e-6;

/// The DiTO box with `N` slab directions: DiTO-14 for `N = 7`, DiTO-26 for `N = 13`.
pub(crate) fn dito<const N: usize>(points: &[Vec3]) -> Obb {
    let extremes = Extremes::<N>::of(points);
    let aabb = DMat3::IDENTITY;
    let axes = extremes.best_axes(points);
    if axes == aabb {
        return Obb::on_basis(aabb, points);
    }
    let obb = Obb::on_basis(axes, points);
    if rank(obb.half_extents.as_dvec3() * 2.0) < rank(extremes.aabb_lengths()) {
        obb
    } else {
        Obb::on_basis(aabb, points)
    }
}

/// The extreme points of a set along each slab direction.
struct Extremes<const N: usize> {
    /// The points of least and greatest projection on each direction.
    lo_point: [DVec3; N],
    hi_point: [DVec3; N],
}

impl<const N: usize> Extremes<N> {
    /// The extreme points, from the shared one-pass search.
    fn of(points: &[Vec3]) -> Self {
        let at = extremes::<N>(points);
        let point = |j: usize| points[j].as_dvec3();
        Extremes { lo_point: at.map(|[lo, _]| point(lo)), hi_point: at.map(|[_, hi]| point(hi)) }
    }

    /// The AABB's side lengths: the first three directions are the axes, so
    /// their extreme points' coordinates are the AABB's; the differences of
    /// f32 values are exact in f64.
    fn aabb_lengths(&self) -> DVec3 {
        let (lo, hi) = (&self.lo_point, &self.hi_point);
        DVec3::new(hi[0].x - lo[0].x, hi[1].y - lo[1].y, hi[2].z - lo[2].z)
    }

    /// All `2N` extreme points.
    fn points(&self) -> impl Iterator<Item = DVec3> + '_ {
        self.lo_point.iter().chain(&self.hi_point).copied()
    }

    /// The best axis triple on the extremes of `all`, or the identity when the
    /// AABB's axes do at least as well or all points coincide.
    fn best_axes(&self, all: &[Vec3]) -> DMat3 {
        let mut best = Best { axes: DMat3::IDENTITY, rank: rank(self.aabb_lengths()) };
        // Base triangle, first edge: the farthest pair of extremes along one direction.
        let Some((p0, p1)) = (0..N)
            .map(|i| (self.lo_point[i], self.hi_point[i]))
            .max_by(|a, b| a.0.distance_squared(a.1).total_cmp(&b.0.distance_squared(b.1)))
        else {
            return best.axes;
        };
        let length = p0.distance(p1);
        if length == 0.0 {
            return best.axes; // every point is the same: the AABB is exact
        }
        let e0 = (p1 - p0) / length;
        // Boxes are measured on the extremes (and on the third vertex below,
        // should it come from elsewhere).
        let mut measured: Vec<DVec3> = self.points().collect();
        // Third vertex: the extreme farthest from the line of p0 and p1.
        let line_distance = |q: DVec3| (q - p0).cross(e0).length();
        let mut p2 = farthest(measured.iter().copied(), line_distance);
        if line_distance(p2) <= SLIVER * length {
            // Degenerate case 2 of the paper: the extremes are collinear, and the
            // paper aligns the box with the line, any axes across it; a sliver
            // triangle's normal would be as arbitrary, set by rounding. The
            // points may still span a plane, so look for the third vertex among
            // all of them first (one more pass, in this rare case only).
            p2 = farthest(all.iter().map(|p| p.as_dvec3()), line_distance);
            if line_distance(p2) <= FLAT * length {
                best.consider(&measured, basis(e0, e0.any_orthonormal_vector()));
                return best.axes;
            }
            measured.push(p2);
        }
        best.triangle(&measured, p0, p1, p2);
        // The tetrahedra on the extremes farthest above and below the base plane;
        // the paper skips one whose apex lies in the plane (flat input).
        let n = (p1 - p0).cross(p2 - p0).normalize();
        let height = |q: DVec3| (q - p0).dot(n);
        let apexes = [
            farthest(measured.iter().copied(), height),
            farthest(measured.iter().copied(), |q| -height(q)),
        ];
        for apex in apexes {
            if height(apex).abs() > FLAT * length {
                best.triangle(&measured, apex, p0, p1);
                best.triangle(&measured, apex, p1, p2);
                best.triangle(&measured, apex, p2, p0);
            }
        }
        best.axes
    }
}

/// The best axis triple so far and its box's rank on the extremes.
struct Best {
    axes: DMat3,
    rank: (f64, f64),
}

impl Best {
    /// The three axis triples of a triangle: each edge, the normal, and their
    /// cross product.
    fn triangle(&mut self, points: &[DVec3], a: DVec3, b: DVec3, c: DVec3) {
        let Some(n) = (b - a).cross(c - a).try_normalize() else {
            return;
        };
        for edge in [b - a, c - b, a - c] {
            self.consider(points, basis(n, edge));
        }
    }

    /// Keeps `axes` if their box on `points` is smaller than the best so far.
    fn consider(&mut self, points: &[DVec3], axes: DMat3) {
        let at = axes.transpose();
        let (lo, hi) =
            points.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
                let k = at * p;
                (lo.min(k), hi.max(k))
            });
        let rank = rank(hi - lo);
        if rank < self.rank {
            *self = Best { axes, rank };
        }
    }
}

/// The point of `points` with the greatest `key` (the first of equals).
fn farthest<I: Iterator<Item = DVec3>>(points: I, key: impl Fn(DVec3) -> f64) -> DVec3 {
    points
        .map(|p| (key(p), p))
        .fold((f64::NEG_INFINITY, DVec3::ZERO), |best, c| if c.0 > best.0 { c } else { best })
        .1
}

/// How a box with side lengths `l` ranks, least first: by volume, then half
/// its surface area; a flat box (its thinnest side below `FLAT_BOX` of its
/// longest) has zero volume, so that rounding noise in a thickness never ranks
/// a flat box behind another.
fn rank(l: DVec3) -> (f64, f64) {
    let area = l.x * l.y + l.y * l.z + l.z * l.x;
    let volume = if l.min_element() <= FLAT_BOX * l.max_element() { 0.0 } else { l.x * l.y * l.z };
    (volume, area)
}
