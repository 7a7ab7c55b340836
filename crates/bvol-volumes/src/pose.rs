//! Rigid poses: a rotation followed by a translation.

use glam::{DMat3, DVec3, Quat, Vec3};

/// A bound on the error of each entry of [`Pose::rotation_f32`], in units of
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
    /// Rotation; expected to be a unit quaternion (it is normalised where used in f64).
    pub rotation: Quat,
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
    pub fn is_finite(&self) -> bool {
        self.position.is_finite() && self.rotation.is_finite() && self.rotation.length() > 0.0
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

    /// The rotation as an exactly orthonormal f64 matrix (the quaternion normalised in f64).
    pub(crate) fn rotation_f64(&self) -> DMat3 {
        DMat3::from_quat(self.rotation.as_dquat().normalize())
    }

    /// The rotation as an f32 matrix, from the quaternion normalised in f32:
    /// each entry within [`ROTATION_ERROR`] of the exact rotation's.
    #[inline]
    pub(crate) fn rotation_f32(&self) -> glam::Mat3 {
        glam::Mat3::from_quat(self.rotation.normalize())
    }

    /// The image of a local point in f32 under rotation `r` (this pose's
    /// [`rotation_f32`](Self::rotation_f32)), and a bound on its distance
    /// from the exact image: the rotation's error on the point's components,
    /// the rounding of the product and of the sum (twice the per-component
    /// bound covers the Euclidean norm and the rounding of the bound itself).
    #[inline]
    pub(crate) fn apply_f32(&self, r: &glam::Mat3, p: Vec3) -> (Vec3, f32) {
        let image = *r * p + self.position;
        let eps = f32::EPSILON;
        let slip = 2.0
            * ((ROTATION_ERROR + 5.0 * eps) * p.abs().element_sum()
                + eps * self.position.abs().element_sum());
        (image, slip)
    }

    /// The exact image of a local point, in f64.
    pub(crate) fn apply_f64(&self, p: DVec3) -> DVec3 {
        self.rotation_f64() * p + self.position.as_dvec3()
    }
}
