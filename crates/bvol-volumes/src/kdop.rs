//! Discrete oriented polytopes (k-DOPs): the intersection of k/2 slabs along
//! fixed directions (Klosowski et al. 1998; Ericson, Real-Time Collision
//! Detection 4.6).

use glam::{DVec3, Vec3};

use crate::directions::{as_dvec3, directions};
use crate::ray::{Ray, SlabClip, ray_f64};
use crate::round::{down, up};
use crate::{Aabb, FitError, Pose};

/// A k-DOP with `N = k / 2` slabs along [`Kdop::DIRECTIONS`]: the points `p` with
/// `min[i] <= d_i . p <= max[i]` for every direction `d_i`. The directions are
/// unnormalised (components -1, 0, 1), so slab values are sums of coordinates.
///
/// Use the aliases [`Kdop6`], [`Kdop14`], [`Kdop18`] and [`Kdop26`]; other `N` do
/// not compile.
///
/// ```
/// use bvol_volumes::{Aabb, Kdop14};
/// use glam::Vec3;
/// let tetra = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
/// let dop = Kdop14::fit(&tetra).unwrap();
/// assert!(tetra.iter().all(|&p| dop.contains_point(p)));
/// // The corner diagonal (1, 1, 1) cuts the unit cube down to the tetrahedron.
/// assert!((dop.volume() - 1.0 / 6.0).abs() < 1e-6);
/// assert_eq!(dop.aabb(), Aabb::new(Vec3::ZERO, Vec3::ONE));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kdop<const N: usize> {
    /// Lower bound of each slab.
    pub min: [f32; N],
    /// Upper bound of each slab.
    pub max: [f32; N],
}

/// The 6-DOP: an axis-aligned box.
pub type Kdop6 = Kdop<3>;
/// The 14-DOP: axes and the 4 cube-corner diagonals.
pub type Kdop14 = Kdop<7>;
/// The 18-DOP: axes and the 6 cube-edge diagonals.
pub type Kdop18 = Kdop<9>;
/// The 26-DOP: axes, corner and edge diagonals.
pub type Kdop26 = Kdop<13>;

impl<const N: usize> Kdop<N> {
    /// The slab directions, in the order of `min` and `max`.
    pub const DIRECTIONS: [[i8; 3]; N] = directions::<N>();

    /// The tight k-DOP of a point set: per slab, min and max of the projections,
    /// computed in f64 and rounded outward.
    pub fn fit(points: &[Vec3]) -> Result<Self, FitError> {
        crate::error::check_points(points)?;
        Ok(Self::fit_f64(points.iter().map(|p| p.as_dvec3()), 0.0))
    }

    /// The k-DOP of points known to within `slack` (a distance): each slab
    /// widened by it before rounding outward.
    fn fit_f64(points: impl Iterator<Item = DVec3>, slack: f64) -> Self {
        let dirs = Self::DIRECTIONS.map(as_dvec3);
        let (mut lo, mut hi) = ([f64::INFINITY; N], [f64::NEG_INFINITY; N]);
        for p in points {
            for i in 0..N {
                let s = dirs[i].dot(p);
                lo[i] = lo[i].min(s);
                hi[i] = hi[i].max(s);
            }
        }
        let widen = |i: usize| slack * dirs[i].length();
        Kdop {
            min: std::array::from_fn(|i| down(lo[i] - widen(i))),
            max: std::array::from_fn(|i| up(hi[i] + widen(i))),
        }
    }

    /// Whether `p` lies inside or on every slab (evaluated in f64).
    pub fn contains_point(&self, p: Vec3) -> bool {
        let p = p.as_dvec3();
        (0..N).all(|i| {
            let s = as_dvec3(Self::DIRECTIONS[i]).dot(p);
            self.min[i] as f64 <= s && s <= self.max[i] as f64
        })
    }

    /// Whether two k-DOPs overlap or touch: k/2 interval tests. Disjoint slabs
    /// prove separation; overlap on every slab is conservative (the polytopes may
    /// still be apart along some other direction).
    pub fn overlaps(&self, other: &Self) -> bool {
        (0..N).all(|i| self.min[i] <= other.max[i] && other.min[i] <= self.max[i])
    }

    /// The smallest k-DOP holding both: per slab min and max.
    pub fn merge(&self, other: &Self) -> Self {
        Kdop {
            min: std::array::from_fn(|i| self.min[i].min(other.min[i])),
            max: std::array::from_fn(|i| self.max[i].max(other.max[i])),
        }
    }

    /// The k-DOP holding this one moved by a rigid pose. The slab directions
    /// are fixed in space, so a rotated k-DOP is fitted again, to its moved
    /// vertices.
    ///
    /// The vertices are found relative to the axis box's centre and moved in
    /// f64, each step rounding at the scale of the largest coordinate: a
    /// k-DOP 1e13 long keeps its 0.1-wide side only to about 1e-3. Each slab
    /// is widened by a bound of that rounding (16 f64 epsilons of the
    /// coordinates' scale, far below f32's own rounding of ordinary bounds),
    /// so that the moved k-DOP holds what this one holds.
    pub fn transformed(&self, pose: &Pose) -> Self {
        let half = (0..3).map(|i| self.max[i] as f64 - self.min[i] as f64).fold(0.0, f64::max);
        let scale =
            self.centre().abs().max_element() + half + pose.position.abs().max_element() as f64;
        let moved = self.vertices_f64().into_iter().map(|v| pose.apply_f64(v));
        Self::fit_f64(moved, 16.0 * f64::EPSILON * scale)
    }

    /// The box of the axis slabs (the first three directions): it holds the
    /// polytope, and is its tight box for a fitted, merged or transformed
    /// k-DOP, whose axis slabs touch it. Read off the slabs rather than the
    /// polytope's vertices, which, kept relative to the box's centre, lose
    /// the narrow side's digits of a k-DOP 1e13 long and 0.1 wide. Empty
    /// (min +inf, max -inf) where a slab is inverted.
    pub fn aabb(&self) -> Aabb {
        if (0..N).any(|i| self.min[i] > self.max[i]) {
            return Aabb::around_f64(&[]);
        }
        let corner = |v: &[f32; N]| Vec3::new(v[0], v[1], v[2]);
        Aabb::new(corner(&self.min), corner(&self.max))
    }

    /// Volume of the polytope: the sum over faces of area x distance from an
    /// interior point / 3 (the divergence theorem; Ericson 2005, 4.6).
    ///
    /// In f32 it overflows to infinity past about 7e12 a side, well within
    /// the coordinates a body may have: [`volume_f64`](Self::volume_f64)
    /// does not.
    pub fn volume(&self) -> f32 {
        self.volume_f64() as f32
    }

    /// Volume of the polytope, in f64.
    ///
    /// A face's area sums products of its vertices' coordinates, so its
    /// rounding error grows with the polytope's aspect ratio (about f64
    /// epsilon times it, relative): a flat k-DOP 1e18 wide could come out
    /// with a volume of 1e36. The polytope lies in the box of its axis
    /// slabs, whose volume is exact, so the sum is clamped to `0..=` that.
    pub fn volume_f64(&self) -> f64 {
        let faces = self.faces();
        let vertices: Vec<DVec3> = faces.iter().flat_map(|f| f.polygon.iter().copied()).collect();
        let inner = vertices.iter().sum::<DVec3>() / vertices.len().max(1) as f64;
        let sum: f64 =
            faces.iter().map(|f| f.area() * f.normal.dot(f.polygon[0] - inner) / 3.0).sum();
        let side = |i: usize| self.max[i] as f64 - self.min[i] as f64;
        sum.clamp(0.0, (side(0) * side(1) * side(2)).max(0.0))
    }

    /// Surface area of the polytope (a flat k-DOP counts both sides).
    pub fn surface_area(&self) -> f32 {
        self.faces().iter().map(Face::area).sum::<f64>() as f32
    }

    /// Where a ray enters the k-DOP: `Some(0.0)` if it starts inside or on a
    /// face, `None` if it misses or would enter beyond `max_t`.
    pub fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32> {
        let (o, d, max_t) = ray_f64(ray, max_t)?;
        let mut clip = SlabClip::new(max_t);
        for i in 0..N {
            let n = as_dvec3(Self::DIRECTIONS[i]);
            if !clip.clip(n.dot(o), n.dot(d), self.min[i] as f64, self.max[i] as f64) {
                return None;
            }
        }
        Some(clip.entry())
    }

    /// The box of the axis slabs' centre: the polytope's vertices are kept
    /// relative to it, so that a polytope far longer than it is wide (or far
    /// from the origin) keeps its narrow side's digits.
    fn centre(&self) -> DVec3 {
        let mid = |i: usize| 0.5 * (self.min[i] as f64 + self.max[i] as f64);
        DVec3::new(mid(0), mid(1), mid(2))
    }

    /// The polytope's faces, relative to [`centre`](Self::centre): the box of
    /// the axis slabs (the first three directions) clipped by every other
    /// slab's two planes in turn (Sutherland and Hodgman 1974, on each face;
    /// the points cut out of the faces make the new face). Each vertex is
    /// interpolated along an edge, never solved from three planes, so an edge
    /// along one axis keeps its other coordinates exactly: no tolerance, and
    /// no cancellation at any aspect ratio. Empty where a slab is inverted.
    fn faces(&self) -> Vec<Face> {
        if (0..N).any(|i| self.min[i] > self.max[i]) {
            return Vec::new();
        }
        let c = self.centre();
        let half = |i: usize| 0.5 * (self.max[i] as f64 - self.min[i] as f64);
        let mut faces = box_faces(DVec3::new(half(0), half(1), half(2)));
        for i in 3..N {
            let n = as_dvec3(Self::DIRECTIONS[i]);
            let (hi, lo) = (self.max[i] as f64 - n.dot(c), self.min[i] as f64 - n.dot(c));
            for (normal, offset) in [(n, hi), (-n, -lo)] {
                faces = clip(faces, normal, offset);
            }
        }
        faces
    }

    /// The polytope's vertices, each once. A polytope of no area (the k-DOP
    /// of points on a line, or of one point) has no faces for the clipping
    /// to keep: it is given by its axis box's corners, which hold it (and,
    /// the axis slabs being tight to the points fitted, are its box).
    fn vertices_f64(&self) -> Vec<DVec3> {
        let c = self.centre();
        let faces = self.faces();
        let inverted = (0..N).any(|i| self.min[i] > self.max[i]);
        if faces.is_empty() && !inverted {
            let corner = |k: usize, i: usize| {
                if k >> i & 1 == 0 { self.min[i] as f64 } else { self.max[i] as f64 }
            };
            return (0..8).map(|k| DVec3::new(corner(k, 0), corner(k, 1), corner(k, 2))).collect();
        }
        let mut out: Vec<DVec3> = Vec::new();
        for v in faces.iter().flat_map(|f| f.polygon.iter()) {
            let v = *v + c;
            if !out.contains(&v) {
                out.push(v);
            }
        }
        out
    }
}

/// A face of a polytope: a convex polygon, vertices in order, and its
/// outward unit normal.
struct Face {
    normal: DVec3,
    polygon: Vec<DVec3>,
}

impl Face {
    fn area(&self) -> f64 {
        let p = &self.polygon;
        let twice: DVec3 = (1..p.len() - 1).map(|i| (p[i] - p[0]).cross(p[i + 1] - p[0])).sum();
        0.5 * twice.dot(self.normal).abs()
    }
}

/// The six faces of the box `-half..=half`.
fn box_faces(h: DVec3) -> Vec<Face> {
    let corner = |i: usize| {
        DVec3::new(
            if i & 1 == 0 { -h.x } else { h.x },
            if i & 2 == 0 { -h.y } else { h.y },
            if i & 4 == 0 { -h.z } else { h.z },
        )
    };
    // Corner indices of each face, in order around it.
    let faces: [(DVec3, [usize; 4]); 6] = [
        (DVec3::NEG_X, [0, 4, 6, 2]),
        (DVec3::X, [1, 3, 7, 5]),
        (DVec3::NEG_Y, [0, 1, 5, 4]),
        (DVec3::Y, [2, 6, 7, 3]),
        (DVec3::NEG_Z, [0, 2, 3, 1]),
        (DVec3::Z, [4, 5, 7, 6]),
    ];
    faces.map(|(normal, ids)| Face { normal, polygon: ids.map(corner).to_vec() }).into()
}

/// The faces of a convex polytope cut by the half-space `n . x <= offset`
/// (`n` integer, exact): each face clipped, and the cut closed by a new face
/// of the points on the plane. Faces left with fewer than 3 vertices go.
fn clip(faces: Vec<Face>, n: DVec3, offset: f64) -> Vec<Face> {
    let mut cut = Vec::new();
    let mut out: Vec<Face> = faces
        .into_iter()
        .filter_map(|f| {
            let polygon = clip_polygon(&f.polygon, n, offset, &mut cut);
            (polygon.len() >= 3).then_some(Face { normal: f.normal, polygon })
        })
        .collect();
    if cut.len() >= 3 {
        let normal = n.normalize();
        out.push(Face { normal, polygon: in_order(normal, cut) });
    }
    out
}

/// One polygon clipped to `n . x <= offset`; the points on the plane (kept
/// vertices and crossings of edges) are added to `on_plane`, each once.
///
/// A vertex lies on several faces and an edge on two, so each face finds the
/// same points: kept twice over, a flat or point-like polytope (every vertex
/// on the plane) would double its vertices at every cut. A crossing is
/// interpolated from the edge's inside end, whichever face walks it, so both
/// faces find the same bits and one copy is kept.
fn clip_polygon(p: &[DVec3], n: DVec3, offset: f64, on_plane: &mut Vec<DVec3>) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(p.len() + 1);
    let mut keep = |x: DVec3| {
        if !on_plane.contains(&x) {
            on_plane.push(x);
        }
    };
    for (i, &a) in p.iter().enumerate() {
        let b = p[(i + 1) % p.len()];
        let (da, db) = (n.dot(a) - offset, n.dot(b) - offset);
        if da <= 0.0 {
            out.push(a);
        }
        if da == 0.0 {
            keep(a);
        }
        if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
            let ((inner, d_in), (outer, d_out)) =
                if da < 0.0 { ((a, da), (b, db)) } else { ((b, db), (a, da)) };
            let x = inner + (outer - inner) * (d_in / (d_in - d_out));
            out.push(x);
            keep(x);
        }
    }
    out
}

/// Points on a plane with unit normal `n`, ordered by angle about their
/// centroid: a convex polygon's vertices in order.
fn in_order(n: DVec3, mut points: Vec<DVec3>) -> Vec<DVec3> {
    let centre = points.iter().sum::<DVec3>() / points.len() as f64;
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let angle = |p: &DVec3| (*p - centre).dot(v).atan2((*p - centre).dot(u));
    points.sort_by(|p, q| angle(p).total_cmp(&angle(q)));
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points that make a degenerate 26-DOP: one point (every slab of zero
    /// width, so every vertex of every face lies on each cutting plane) and a
    /// flat square. Kept with every face that found them, the points on a
    /// cut would double the polytope's vertices at each of the 20 cuts (24 x
    /// 2^20 for one point; found by random point sets). By Euler's formula a
    /// convex polytope with F faces has at most 3F - 6 edges, so its faces
    /// list at most 6F - 12 vertices in all.
    #[test]
    fn degenerate_kdops_keep_few_vertices() {
        let square = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
        for p in [&[Vec3::new(2e6, 1e6, 1e6)][..], &[Vec3::new(0.0, 0.0, 1e6)], &square] {
            let k = Kdop26::fit(p).unwrap();
            let faces = k.faces();
            let listed: usize = faces.iter().map(|f| f.polygon.len()).sum();
            assert!(
                listed + 12 <= 6 * faces.len(),
                "{p:?}: {listed} vertices on {} faces",
                faces.len()
            );
            let aabb = Aabb::fit(p).unwrap();
            assert_eq!(k.aabb(), aabb, "{p:?}");
            assert_eq!(k.volume_f64(), 0.0, "{p:?}");
            let area = (aabb.max - aabb.min).x * (aabb.max - aabb.min).y * 2.0;
            assert!((k.surface_area() - area).abs() <= 1e-6, "{p:?}: {}", k.surface_area());
        }
    }
}
