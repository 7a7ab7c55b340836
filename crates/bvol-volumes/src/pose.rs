//! Rigid poses: a rotation followed by a translation.

use glam::{DMat3, DVec3, Quat, Vec3, Vec4};

use crate::lane::{Lane, M3, V3};

/// A bound on the error of each entry of [`rotation`]'s matrix, in units of
/// f32's epsilon: the normalisation errs by about 2, each entry of the
/// matrix (sums of three products of two components) by about 4 more, and
/// the rotation's entries are at most 1. 16 leaves room to spare.
pub(crate) const ROTATION_ERROR: f32 = 16.0 * f32::EPSILON;

/// A rigid pose: points map as `rotation * p + position`.
///
/// ```
/// use bvol_volumes::Pose;
/// use glam::{Quat, Vec3};
/// let pose = Pose::new(Vec3::X, Quat::from_rotation_z(std::f32::consts::FRAC_PI_2));
/// assert!((pose.transform_point(Vec3::X) - Vec3::new(1.0, 1.0, 0.0)).length() < 1e-6);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Translation, applied after the rotation.
    pub position: Vec3,
    /// Rotation; expected to be a unit quaternion. Any other is normalised
    /// where used: in f64 exactly, in f32 (the placed bounds) only while its
    /// squared length neither overflows nor loses its digits (bvol's World
    /// takes squared lengths from 1e-18 to 1e18).
    pub rotation: Quat,
}

/// A rigid pose whose position is f64: where a body far from the origin
/// is, to the precision it needs (a world keeps its bodies' positions so;
/// see bvol's `World::set_poses_f64`).
///
/// ```
/// use bvol_volumes::DPose;
/// use glam::{DVec3, Quat};
/// let far = DPose::new(DVec3::new(1e8 + 0.25, 0.0, 0.0), Quat::IDENTITY);
/// assert_eq!(far.to_pose().position.x, 1e8); // f32 steps are 8 there
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DPose {
    /// Translation, applied after the rotation.
    pub position: DVec3,
    /// Rotation, as [`Pose::rotation`].
    pub rotation: Quat,
}

impl DPose {
    /// A pose from a position and a rotation.
    pub const fn new(position: DVec3, rotation: Quat) -> Self {
        DPose { position, rotation }
    }

    /// The pose with its position rounded to f32.
    pub fn to_pose(self) -> Pose {
        Pose::new(self.position.as_vec3(), self.rotation)
    }
}

impl From<Pose> for DPose {
    fn from(pose: Pose) -> Self {
        DPose::new(pose.position.as_dvec3(), pose.rotation)
    }
}

impl Default for Pose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Pose {
    /// The pose that leaves every point where it is.
    pub const IDENTITY: Pose = Pose { position: Vec3::ZERO, rotation: Quat::IDENTITY };

    /// A pose from a position and a rotation.
    pub const fn new(position: Vec3, rotation: Quat) -> Self {
        Pose { position, rotation }
    }

    /// Whether every component is finite and the rotation is not zero.
    ///
    /// ```
    /// use bvol_volumes::Pose;
    /// use glam::{Quat, Vec3};
    /// assert!(Pose::IDENTITY.is_finite());
    /// assert!(!Pose::new(Vec3::new(0.0, f32::NAN, 0.0), Quat::IDENTITY).is_finite());
    /// assert!(!Pose::new(Vec3::ZERO, Quat::from_xyzw(0.0, 0.0, f32::INFINITY, 1.0)).is_finite());
    /// assert!(!Pose::new(Vec3::ZERO, Quat::from_xyzw(0.0, 0.0, 0.0, 0.0)).is_finite());
    /// ```
    #[inline]
    pub fn is_finite(&self) -> bool {
        // 0 x is 0 for a finite x and NaN for an infinite or NaN one: one
        // lane-wise test for all seven (a world checks every pose it is given).
        let (q, p) = (Vec4::from(self.rotation), self.position.extend(0.0));
        (q * 0.0 + p * 0.0).cmpeq(Vec4::ZERO).all() && q.length_squared() > 0.0
    }

    /// Maps a point from local to world space.
    pub fn transform_point(&self, p: Vec3) -> Vec3 {
        self.rotation * p + self.position
    }

    /// Rotates a direction from local to world space.
    pub fn transform_vector(&self, v: Vec3) -> Vec3 {
        self.rotation * v
    }

    /// The pose that undoes this one.
    pub fn inverse(&self) -> Pose {
        let r = self.rotation.inverse();
        Pose { position: -(r * self.position), rotation: r }
    }

    /// The rotation as an f64 matrix, orthonormal to f64 rounding whatever
    /// f32 rounding did to the quaternion's length: the unit quaternion's
    /// matrix with each product of two components scaled by `2 / |q|^2`
    /// (Shoemake 1985), one division where normalising first takes a square
    /// root and a division. The rotation must not be zero (see
    /// [`is_finite`](Self::is_finite)).
    ///
    /// ```
    /// use bvol_volumes::Pose;
    /// use glam::{DMat3, DQuat, Quat, Vec3};
    /// let q = Quat::from_rotation_y(0.7) * 3.0; // any length
    /// let r = Pose::new(Vec3::ZERO, q).rotation_f64();
    /// let unit = DMat3::from_quat(DQuat::from_rotation_y(0.7));
    /// assert!(r.abs_diff_eq(unit, 1e-7)); // the f32 angle's rounding
    /// assert!((r.transpose() * r).abs_diff_eq(DMat3::IDENTITY, 1e-15));
    /// ```
    pub fn rotation_f64(&self) -> DMat3 {
        let q = self.rotation.as_dquat();
        // The squares of f32 components do not underflow in f64, so a
        // non-zero quaternion has a non-zero squared length, and each
        // scaled product below is at most 2.
        let s = 2.0 / q.length_squared();
        let (x, y, z, w) = (q.x, q.y, q.z, q.w);
        let (xs, ys, zs) = (x * s, y * s, z * s);
        let (wx, wy, wz) = (w * xs, w * ys, w * zs);
        let (xx, xy, xz) = (x * xs, x * ys, x * zs);
        let (yy, yz, zz) = (y * ys, y * zs, z * zs);
        DMat3::from_cols(
            DVec3::new(1.0 - (yy + zz), xy + wz, xz - wy),
            DVec3::new(xy - wz, 1.0 - (xx + zz), yz + wx),
            DVec3::new(xz + wy, yz - wx, 1.0 - (xx + yy)),
        )
    }

    /// This pose on one lane: its rotation (see [`rotation`]) and position.
    #[inline(always)]
    pub(crate) fn lane(&self) -> (M3<f32>, V3<f32>) {
        let q = self.rotation;
        (rotation([q.x, q.y, q.z, q.w]), self.position.into())
    }

    /// The exact image of a local point, in f64.
    pub(crate) fn apply_f64(&self, p: DVec3) -> DVec3 {
        self.rotation_f64() * p + self.position.as_dvec3()
    }
}

/// The rotation of quaternion `[x, y, z, w]` as an f32 matrix, from the
/// quaternion normalised in f32 (glam's `Mat3::from_quat` on the normalised
/// quaternion): each entry within [`ROTATION_ERROR`] of the exact rotation's.
#[inline(always)]
pub(crate) fn rotation<L: Lane>([x, y, z, w]: [L; 4]) -> M3<L> {
    let inv = L::splat(1.0) / (x * x + y * y + z * z + w * w).sqrt();
    let (x, y, z, w) = (x * inv, y * inv, z * inv, w * inv);
    let (x2, y2, z2) = (x + x, y + y, z + z);
    let (xx, xy, xz) = (x * x2, x * y2, x * z2);
    let (yy, yz, zz) = (y * y2, y * z2, z * z2);
    let (wx, wy, wz) = (w * x2, w * y2, w * z2);
    let one = L::splat(1.0);
    M3 {
        x_axis: V3 { x: one - (yy + zz), y: xy + wz, z: xz - wy },
        y_axis: V3 { x: xy - wz, y: one - (xx + zz), z: yz + wx },
        z_axis: V3 { x: xz + wy, y: yz - wx, z: one - (xx + yy) },
    }
}

/// The image of a local point `p` in f32 under rotation `r` (from
/// [`rotation`]) and translation `position`, and a bound on its distance
/// from the exact image: the rotation's error on the point's components, the
/// rounding of the product and of the sum (twice the per-component bound
/// covers the Euclidean norm and the rounding of the bound itself).
#[inline(always)]
pub(crate) fn place_point<L: Lane>(r: &M3<L>, position: V3<L>, p: V3<L>) -> (V3<L>, L) {
    let image = r.mul_vec(p).add(position);
    let eps = f32::EPSILON;
    let slip = L::splat(2.0)
        * (L::splat(ROTATION_ERROR + 5.0 * eps) * p.abs().sum()
            + L::splat(eps) * position.abs().sum());
    (image, slip)
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    proptest! {
        /// The matrix of a quaternion of any length is glam's matrix of the
        /// normalised quaternion, and orthonormal, to f64 rounding: each entry
        /// takes a few roundings, each of `R^T R`'s a few more, so a few tens
        /// of f64 epsilons (2.2e-16) bound both.
        #[test]
        fn rotation_of_any_length_is_the_unit_rotation(
            q in prop::array::uniform4(-1.0f32..1.0),
            scale in -15i32..=15,
        ) {
            let q = Quat::from_array(q) * 10f32.powi(scale);
            prop_assume!(q.is_finite() && q.length_squared() > 0.0);
            let got = Pose::new(Vec3::ZERO, q).rotation_f64();
            let want = DMat3::from_quat(q.as_dquat().normalize());
            let rounding = 50.0 * f64::EPSILON;
            prop_assert!(got.abs_diff_eq(want, rounding), "{got} against {want}");
            let square = got.transpose() * got;
            prop_assert!(square.abs_diff_eq(DMat3::IDENTITY, rounding), "{square}");
            prop_assert!((got.determinant() - 1.0).abs() < rounding);
        }
    }
}
