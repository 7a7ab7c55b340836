//! Oriented bounding boxes.

use glam::{DMat3, DQuat, DVec3, Mat3, Mat3A, Vec3, Vec3A, Vec3Swizzles};

use crate::lane::{Lane, M3, V3};
use crate::pose::{ROTATION_ERROR, place_point};
use crate::ray::{Ray, SlabClip, ray_f64};
use crate::round::up_safe;
use crate::{Aabb, FitError, Pose, Sphere};

/// Slack added to every |R| entry of the box-box test so that near-parallel
/// edges, whose cross product is tiny and rounding-dominated, never give a
/// false separation (RAPID; Ericson, Real-Time Collision Detection 4.4.1). It
/// multiplies half lengths, so the test may call boxes apart by less than about
/// 1e-5 of their size touching, but never calls touching boxes apart.
const PARALLEL_EPSILON: f32 = 1e-5;

/// An oriented box: the points `p` with `|(p - center) . axes.col(i)| <= half_extents[i]`.
///
/// `axes` is a rotation matrix whose columns are the box's unit axes.
///
/// ```
/// use bvol_volumes::{Obb, ObbMethod};
/// use glam::Vec3;
/// let rod: Vec<Vec3> = (0..10).map(|i| Vec3::splat(i as f32)).collect();
/// let obb = Obb::fit(&rod, ObbMethod::MinVolume).unwrap();
/// assert!(rod.iter().all(|&p| obb.contains_point(p)));
/// assert!(obb.volume() < 1e-3); // a thin box along the diagonal
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Obb {
    /// Centre.
    pub center: Vec3,
    /// Unit axes as the columns of a rotation.
    pub axes: Mat3,
    /// Half the size along each axis, `>= 0`.
    pub half_extents: Vec3,
}

impl Default for Obb {
    fn default() -> Self {
        Obb { center: Vec3::ZERO, axes: Mat3::IDENTITY, half_extents: Vec3::ZERO }
    }
}

/// A right-handed orthonormal basis whose first axis is along `a` and second in
/// the plane of `a` and `b` (Gram-Schmidt); any orthonormal basis stands in for
/// degenerate input.
pub(crate) fn basis(a: DVec3, b: DVec3) -> DMat3 {
    let x = a.try_normalize().unwrap_or(DVec3::X);
    let y = (b - x * x.dot(b)).try_normalize().unwrap_or_else(|| x.any_orthonormal_vector());
    DMat3::from_cols(x, y, x.cross(y))
}

impl Obb {
    /// The tight box on the given axes (orthonormalised first: the first column
    /// is kept, the second made orthogonal to it, the third their cross product)
    /// holding every point.
    ///
    /// ```
    /// use bvol_volumes::Obb;
    /// use glam::{Mat3, Vec3};
    /// let obb = Obb::from_axes(Mat3::IDENTITY, &[Vec3::ZERO, Vec3::new(2.0, 4.0, 6.0)]).unwrap();
    /// assert_eq!(obb.center, Vec3::new(1.0, 2.0, 3.0));
    /// assert!(obb.half_extents.abs_diff_eq(Vec3::new(1.0, 2.0, 3.0), 1e-6));
    /// ```
    pub fn from_axes(axes: Mat3, points: &[Vec3]) -> Result<Obb, FitError> {
        crate::error::check_points(points)?;
        let m = basis(axes.x_axis.as_dvec3(), axes.y_axis.as_dvec3());
        Ok(Obb::on_basis(m, points))
    }

    /// The box from axes (DESIGN "The box from axes"): project on each axis,
    /// centre = sum of `(k_min + k_max) / 2 * axis`, half length `(k_max - k_min) / 2`;
    /// then the half lengths are recomputed about the f32 centre and rounded up,
    /// so every point stays inside after rounding. `m` must be orthonormal.
    pub(crate) fn on_basis(m: DMat3, points: &[Vec3]) -> Obb {
        Obb::on_basis_f64(m, || points.iter().map(|p| p.as_dvec3()))
    }

    /// [`Obb::on_basis`] for f64 points, given as a re-playable iterator.
    pub(crate) fn on_basis_f64<I: Iterator<Item = DVec3>>(m: DMat3, points: impl Fn() -> I) -> Obb {
        let axes = m.as_mat3();
        let a = axes.as_dmat3();
        let at = a.transpose();
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for p in points() {
            let k = at * p;
            lo = lo.min(k);
            hi = hi.max(k);
        }
        let center = (a * ((lo + hi) * 0.5)).as_vec3();
        let c = center.as_dvec3();
        let h = points().fold(DVec3::ZERO, |h, p| h.max((at * (p - c)).abs()));
        let half_extents = Vec3::new(up_safe(h.x), up_safe(h.y), up_safe(h.z));
        Obb { center, axes, half_extents }
    }

    /// Whether `p` lies inside or on the box, evaluated in f64.
    pub fn contains_point(&self, p: Vec3) -> bool {
        let k = self.axes.as_dmat3().transpose() * (p.as_dvec3() - self.center.as_dvec3());
        k.abs().cmple(self.half_extents.as_dvec3()).all()
    }

    /// Volume, `8 hx hy hz`.
    ///
    /// In f32 it overflows to infinity past about 7e12 a side, well within
    /// the coordinates a body may have: [`volume_f64`](Self::volume_f64)
    /// does not.
    pub fn volume(&self) -> f32 {
        self.volume_f64() as f32
    }

    /// Volume, `8 hx hy hz`, in f64.
    pub fn volume_f64(&self) -> f64 {
        let h = self.half_extents.as_dvec3();
        8.0 * h.x * h.y * h.z
    }

    /// Surface area.
    pub fn surface_area(&self) -> f32 {
        let h = self.half_extents.as_dvec3();
        (8.0 * (h.x * h.y + h.y * h.z + h.z * h.x)) as f32
    }

    /// The eight corners, exact in f64: the slab set's vertices, through the dual
    /// basis, so they hold even where the f32 axes are not exactly orthonormal.
    /// Corner `i` is on the positive side of axis 0, 1 and 2 where bit 0, 1
    /// and 2 of `i` are set.
    ///
    /// ```
    /// use bvol_volumes::Obb;
    /// use glam::{Mat3, Vec3};
    /// let obb = Obb { center: Vec3::X, axes: Mat3::IDENTITY, half_extents: Vec3::new(1.0, 2.0, 3.0) };
    /// let corners = obb.corners_f64();
    /// assert_eq!(corners[0].to_array(), [0.0, -2.0, -3.0]);
    /// assert_eq!(corners[7].to_array(), [2.0, 2.0, 3.0]);
    /// ```
    pub fn corners_f64(&self) -> [DVec3; 8] {
        let dual = self.axes.as_dmat3().transpose().inverse();
        let (c, h) = (self.center.as_dvec3(), self.half_extents.as_dvec3());
        std::array::from_fn(|i| {
            let s = DVec3::new(
                if i & 1 == 0 { -h.x } else { h.x },
                if i & 2 == 0 { -h.y } else { h.y },
                if i & 4 == 0 { -h.z } else { h.z },
            );
            c + dual * s
        })
    }

    /// The box moved by a rigid pose, in f32 (this runs for every moved body
    /// every frame). The half lengths grow by bounds on the rounding of the
    /// new centre and of the rotated axes (an axis off by `e` moves a point
    /// of the box by at most `|e| |h|` along it), so the exact image of the
    /// old box stays inside.
    pub fn transformed(&self, pose: &Pose) -> Obb {
        let (r, position) = pose.lane();
        let local = (self.center.into(), self.axes.into(), self.half_extents.into());
        let (center, axes, half_extents) = place(&r, position, local);
        Obb { center: center.into(), axes: axes.into(), half_extents: half_extents.into() }
    }

    /// A box holding both: centre between them, axes from the halfway rotation of
    /// the two (quaternions of agreeing sign), extents fitted to the 16 corners.
    pub fn merge(&self, other: &Obb) -> Obb {
        let q0 = DQuat::from_mat3(&self.axes.as_dmat3()).normalize();
        let mut q1 = DQuat::from_mat3(&other.axes.as_dmat3()).normalize();
        if q0.dot(q1) < 0.0 {
            q1 = -q1;
        }
        let m = DMat3::from_quat((q0 + q1).normalize());
        let m = basis(m.x_axis, m.y_axis);
        let corners: Vec<DVec3> =
            self.corners_f64().into_iter().chain(other.corners_f64()).collect();
        Obb::on_basis_f64(m, || corners.iter().copied())
    }

    /// The tight box around this box, rounded outward.
    pub fn aabb(&self) -> Aabb {
        Aabb::around_f64(&self.corners_f64())
    }

    /// Whether two boxes overlap or touch: the 15-axis separating-axis test
    /// (Gottschalk, Lin & Manocha 1996; Ericson 4.4.1), with early exit and the
    /// parallel-edge epsilon, in the frame of `self`.
    pub fn overlaps(&self, other: &Obb) -> bool {
        let (a, b) = (self, other);
        let (ae, be) = (Vec3A::from(a.half_extents), Vec3A::from(b.half_extents));
        let at = Mat3A::from(a.axes).transpose();
        let r = at * Mat3A::from(b.axes); // r.col(j)[i] = a_i . b_j
        let t = at * Vec3A::from(b.center - a.center);
        let eps = Vec3A::splat(PARALLEL_EPSILON);
        let abs_r =
            Mat3A::from_cols(r.x_axis.abs() + eps, r.y_axis.abs() + eps, r.z_axis.abs() + eps);
        // Face axes of A: rb = sum_j be_j |r_ij| = row i of abs_r . be.
        if t.abs().cmpgt(ae + abs_r * be).any() {
            return false;
        }
        // Face axes of B: ra = sum_i ae_i |r_ij| = column j of abs_r . ae.
        let rows = r.transpose();
        let abs_rows = abs_r.transpose();
        if (rows * t).abs().cmpgt(abs_rows * ae + be).any() {
            return false;
        }
        // Edge axes a_i x b_j, the three j of one i at once (lane j; j1 and
        // j2 the next two round, by rotating the lanes):
        // ra = ae_i1 |r_i2 j| + ae_i2 |r_i1 j|, rb = be_j1 |r_i j2| + be_j2 |r_i j1|,
        // d = t_i2 r_i1 j - t_i1 r_i2 j.
        let (row, abs_row) = (
            [rows.x_axis, rows.y_axis, rows.z_axis],
            [abs_rows.x_axis, abs_rows.y_axis, abs_rows.z_axis],
        );
        for i in 0..3 {
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            let ra = ae[i1] * abs_row[i2] + ae[i2] * abs_row[i1];
            let rb = be.yzx() * abs_row[i].zxy() + be.zxy() * abs_row[i].yzx();
            let d = t[i2] * row[i1] - t[i1] * row[i2];
            if d.abs().cmpgt(ra + rb).any() {
                return false;
            }
        }
        true
    }

    /// Whether the box overlaps or touches a sphere: the distance from the sphere's
    /// centre to its closest point in the box (Ericson 5.1.4), in f64.
    pub fn overlaps_sphere(&self, sphere: &Sphere) -> bool {
        let k =
            self.axes.as_dmat3().transpose() * (sphere.center.as_dvec3() - self.center.as_dvec3());
        let h = self.half_extents.as_dvec3();
        (k - k.clamp(-h, h)).length_squared() <= (sphere.radius as f64).powi(2)
    }

    /// Where a ray enters the box (slab test in the box's frame): `Some(0.0)` if it
    /// starts inside or on a face, `None` if it misses or would enter beyond `max_t`.
    pub fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32> {
        let (o, d, max_t) = ray_f64(ray, max_t)?;
        let at = self.axes.as_dmat3().transpose();
        let (o, d) = (at * (o - self.center.as_dvec3()), at * d);
        let h = self.half_extents.as_dvec3();
        let mut clip = SlabClip::new(max_t);
        for i in 0..3 {
            if !clip.clip(o[i], d[i], -h[i], h[i]) {
                return None;
            }
        }
        Some(clip.entry())
    }
}

/// A box's centre, axes and half lengths moved by rotation `r` (from
/// [`rotation`](crate::pose::rotation)) and translation `position`: the half
/// lengths grow by the bound on the centre's rounding and by the rotated
/// axes' error on the box's reach, then by an ulp.
#[inline(always)]
pub(crate) fn place<L: Lane>(
    r: &M3<L>,
    position: V3<L>,
    (center, axes, half): (V3<L>, M3<L>, V3<L>),
) -> (V3<L>, M3<L>, V3<L>) {
    let (center, slip) = place_point(r, position, center);
    let turn = L::splat(4.0 * (ROTATION_ERROR + 3.0 * f32::EPSILON)) * half.sum();
    let pad = V3::splat(slip + turn);
    (center, r.mul_mat(&axes), half.add(pad).map(L::next_up))
}
