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

/// One bounding plane `normal . x <= offset` of the polytope.
#[derive(Clone, Copy)]
struct Plane {
    normal: DVec3,
    offset: f64,
}

impl<const N: usize> Kdop<N> {
    /// The slab directions, in the order of `min` and `max`.
    pub const DIRECTIONS: [[i8; 3]; N] = directions::<N>();

    /// The tight k-DOP of a point set: per slab, min and max of the projections,
    /// computed in f64 and rounded outward.
    pub fn fit(points: &[Vec3]) -> Result<Self, FitError> {
        crate::error::check_points(points)?;
        Ok(Self::fit_f64(points.iter().map(|p| p.as_dvec3())))
    }

    fn fit_f64(points: impl Iterator<Item = DVec3>) -> Self {
        let dirs = Self::DIRECTIONS.map(as_dvec3);
        let (mut lo, mut hi) = ([f64::INFINITY; N], [f64::NEG_INFINITY; N]);
        for p in points {
            for i in 0..N {
                let s = dirs[i].dot(p);
                lo[i] = lo[i].min(s);
                hi[i] = hi[i].max(s);
            }
        }
        Kdop { min: lo.map(down), max: hi.map(up) }
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
    pub fn transformed(&self, pose: &Pose) -> Self {
        Self::fit_f64(self.vertices_f64().into_iter().map(|v| pose.apply_f64(v)))
    }

    /// The tight box around the polytope, rounded outward.
    pub fn aabb(&self) -> Aabb {
        Aabb::around_f64(&self.vertices_f64())
    }

    /// Volume of the polytope: the sum over faces of area x distance from an
    /// interior point / 3.
    pub fn volume(&self) -> f32 {
        let vertices = self.vertices_f64();
        let inner = vertices.iter().sum::<DVec3>() / vertices.len() as f64;
        let volume: f64 = self
            .faces(&vertices)
            .map(|(plane, area)| area * (plane.offset - plane.normal.dot(inner)) / 3.0)
            .sum();
        volume as f32
    }

    /// Surface area of the polytope (a flat k-DOP counts both sides).
    pub fn surface_area(&self) -> f32 {
        let vertices = self.vertices_f64();
        self.faces(&vertices).map(|(_, area)| area).sum::<f64>() as f32
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

    /// The 2N bounding planes, normals unit length.
    fn planes(&self) -> impl Iterator<Item = Plane> + '_ {
        (0..N).flat_map(move |i| {
            let n = as_dvec3(Self::DIRECTIONS[i]);
            let len = n.length();
            [
                Plane { normal: n / len, offset: self.max[i] as f64 / len },
                Plane { normal: -n / len, offset: -(self.min[i] as f64) / len },
            ]
        })
    }

    /// A tolerance for "on the plane", relative to the polytope's size and place.
    fn tolerance(&self) -> f64 {
        let scale = self.min.iter().chain(&self.max).fold(0.0f64, |m, v| m.max(v.abs() as f64));
        1e-9 * scale.max(f64::MIN_POSITIVE)
    }

    /// The polytope's vertices: every feasible intersection of three planes,
    /// each once (O(k^3 k), fine for k <= 26). Integer directions make every
    /// 3x3 determinant an exact integer, so singular triples are skipped exactly.
    fn vertices_f64(&self) -> Vec<DVec3> {
        let planes: Vec<Plane> = self.planes().collect();
        let tol = self.tolerance();
        let mut out: Vec<DVec3> = Vec::new();
        for a in 0..planes.len() {
            for b in a + 1..planes.len() {
                for c in b + 1..planes.len() {
                    let Some(x) = intersect(planes[a], planes[b], planes[c]) else {
                        continue;
                    };
                    let feasible = planes.iter().all(|p| p.normal.dot(x) <= p.offset + tol);
                    if feasible && out.iter().all(|v| (*v - x).abs().max_element() > tol) {
                        out.push(x);
                    }
                }
            }
        }
        out
    }

    /// Each face as its plane and its polygon's area (vertices on the plane,
    /// ordered by angle about their centroid).
    fn faces<'a>(&'a self, vertices: &'a [DVec3]) -> impl Iterator<Item = (Plane, f64)> + 'a {
        let tol = self.tolerance();
        self.planes().filter_map(move |plane| {
            let on: Vec<DVec3> = vertices
                .iter()
                .copied()
                .filter(|v| (plane.normal.dot(*v) - plane.offset).abs() <= tol)
                .collect();
            (on.len() >= 3).then(|| (plane, polygon_area(plane.normal, on)))
        })
    }
}

/// The point on three planes, or `None` where they do not meet in one point.
fn intersect(a: Plane, b: Plane, c: Plane) -> Option<DVec3> {
    let (bc, ca, ab) =
        (b.normal.cross(c.normal), c.normal.cross(a.normal), a.normal.cross(b.normal));
    let det = a.normal.dot(bc);
    (det.abs() > 1e-12).then(|| (bc * a.offset + ca * b.offset + ab * c.offset) / det)
}

/// Area of a convex polygon given as unordered points on a plane with unit normal `n`.
fn polygon_area(n: DVec3, mut points: Vec<DVec3>) -> f64 {
    let centre = points.iter().sum::<DVec3>() / points.len() as f64;
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let angle = |p: &DVec3| (*p - centre).dot(v).atan2((*p - centre).dot(u));
    points.sort_by(|p, q| angle(p).total_cmp(&angle(q)));
    let twice: DVec3 = (0..points.len())
        .map(|i| (points[i] - centre).cross(points[(i + 1) % points.len()] - centre))
        .sum();
    0.5 * twice.dot(n).abs()
}
