//! Rigid frames in f64: where a shape's local space sits, and one shape's space
//! seen from another's.

use bvol_volumes::Pose;
use glam::{DMat3, DQuat, DVec3, Mat3, Vec3};

use crate::{Body, NarrowError};

/// A rigid map `x -> rotation * x + translation`, with an orthonormal f64 rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Frame {
    /// Orthonormal rotation.
    pub rotation: DMat3,
    /// Translation, applied after the rotation.
    pub translation: DVec3,
}

impl Frame {
    /// The map that leaves every point where it is.
    pub const IDENTITY: Frame = Frame { rotation: DMat3::IDENTITY, translation: DVec3::ZERO };

    /// The frame of a pose: the rotation of its quaternion taken as of unit
    /// length, in f64, so that the rotation is orthonormal to f64 rounding
    /// whatever f32 rounding did to the quaternion.
    pub fn of_pose(pose: &Pose, body: Body) -> Result<Frame, NarrowError> {
        if !pose.is_finite() {
            return Err(NarrowError::NonFinitePose { body });
        }
        // `is_finite` rejects a zero quaternion; in f64 the squares of f32
        // components cannot underflow, so the squared length is not zero
        // either, and each scaled product is at most 2.
        Ok(Frame {
            rotation: rotation_of(pose.rotation.as_dquat()),
            translation: pose.position.as_dvec3(),
        })
    }

    /// This frame followed by a box's own placement inside it: `center` and the
    /// columns of `axes`, made orthonormal by Gram-Schmidt (the first axis kept).
    /// A box is symmetric, so a left-handed `axes` places the same box.
    pub fn with_box(&self, center: Vec3, axes: Mat3) -> Frame {
        let x = axes.x_axis.as_dvec3().try_normalize().unwrap_or(DVec3::X);
        let y = axes.y_axis.as_dvec3();
        let y = (y - x * x.dot(y)).try_normalize().unwrap_or_else(|| x.any_orthonormal_vector());
        let local = DMat3::from_cols(x, y, x.cross(y));
        Frame { rotation: self.rotation * local, translation: self.apply(center.as_dvec3()) }
    }

    /// Maps a point.
    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.rotation * p + self.translation
    }

    /// Rotates a direction.
    pub fn rotate(&self, v: DVec3) -> DVec3 {
        self.rotation * v
    }

    /// Rotates a direction by the inverse rotation.
    pub fn unrotate(&self, v: DVec3) -> DVec3 {
        self.rotation.transpose() * v
    }

    /// The map from `other`'s local space to this frame's: `self^-1 * other`.
    pub fn relative(&self, other: &Frame) -> Frame {
        let r = self.rotation.transpose();
        Frame {
            rotation: r * other.rotation,
            translation: r * (other.translation - self.translation),
        }
    }
}

/// The rotation matrix of the quaternion `q`, of any non-zero length: the
/// unit quaternion's matrix with each product of two components scaled by
/// `2 / |q|^2` (Shoemake 1985), one division where normalising first takes
/// a square root and a division, to the same f64 rounding.
fn rotation_of(q: DQuat) -> DMat3 {
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

#[cfg(test)]
mod tests {
    use glam::Quat;
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
            let got = rotation_of(q.as_dquat());
            let want = DMat3::from_quat(q.as_dquat().normalize());
            let rounding = 50.0 * f64::EPSILON;
            prop_assert!(got.abs_diff_eq(want, rounding), "{got} against {want}");
            let square = got.transpose() * got;
            prop_assert!(square.abs_diff_eq(DMat3::IDENTITY, rounding), "{square}");
            prop_assert!((got.determinant() - 1.0).abs() < rounding);
        }
    }
}
