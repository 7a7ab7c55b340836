//! Rigid maps in f64: where a shape's local space sits, and one shape's space
//! seen from another's.

use bvol_volumes::Pose;
use glam::{DMat3, DVec3, Mat3, Vec3};

use crate::{Body, NarrowError};

/// A rigid map `x -> rotation * x + translation`, with an orthonormal f64
/// rotation: an isometry, as nalgebra and parry name it, in f64 and 3-D as
/// glam's `DMat3` and `DAffine3` are (a `DAffine3` whose matrix is a rotation,
/// inverted by its transpose).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DIsometry3 {
    /// Orthonormal rotation.
    pub rotation: DMat3,
    /// Translation, applied after the rotation.
    pub translation: DVec3,
}

impl DIsometry3 {
    /// The map that leaves every point where it is.
    pub const IDENTITY: DIsometry3 =
        DIsometry3 { rotation: DMat3::IDENTITY, translation: DVec3::ZERO };

    /// The isometry of a pose: its rotation in f64 ([`Pose::rotation_f64`]),
    /// orthonormal to f64 rounding whatever f32 rounding did to the
    /// quaternion.
    pub fn of_pose(pose: &Pose, body: Body) -> Result<DIsometry3, NarrowError> {
        DIsometry3::check(pose, body)?;
        Ok(DIsometry3::of_checked(pose))
    }

    /// [`NarrowError::NonFinitePose`] for a pose with a NaN or infinite
    /// component or a zero rotation; [`NarrowError::PoseOutOfRange`] for a
    /// position beyond [`MAX_COORDINATE`](bvol_volumes::MAX_COORDINATE) (at
    /// f32's largest, a gap came out infinite).
    pub fn check(pose: &Pose, body: Body) -> Result<(), NarrowError> {
        let limit = glam::Vec3::splat(bvol_volumes::MAX_COORDINATE);
        if !pose.is_finite() {
            Err(NarrowError::NonFinitePose { body })
        } else if !pose.position.abs().cmple(limit).all() {
            Err(NarrowError::PoseOutOfRange { body })
        } else {
            Ok(())
        }
    }

    /// The isometry of a pose that passed [`DIsometry3::check`].
    pub fn of_checked(pose: &Pose) -> DIsometry3 {
        DIsometry3 { rotation: pose.rotation_f64(), translation: pose.position.as_dvec3() }
    }

    /// This isometry followed by a box's own placement inside it: `center` and the
    /// columns of `axes`, made orthonormal by Gram-Schmidt (the first axis kept).
    /// A box is symmetric, so a left-handed `axes` places the same box.
    pub fn with_box(&self, center: Vec3, axes: Mat3) -> DIsometry3 {
        let x = axes.x_axis.as_dvec3().try_normalize().unwrap_or(DVec3::X);
        let y = axes.y_axis.as_dvec3();
        let y = (y - x * x.dot(y)).try_normalize().unwrap_or_else(|| x.any_orthonormal_vector());
        let local = DMat3::from_cols(x, y, x.cross(y));
        DIsometry3 { rotation: self.rotation * local, translation: self.apply(center.as_dvec3()) }
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

    /// The map from `other`'s local space to this isometry's: `self^-1 * other`.
    pub fn relative(&self, other: &DIsometry3) -> DIsometry3 {
        let r = self.rotation.transpose();
        DIsometry3 {
            rotation: r * other.rotation,
            translation: r * (other.translation - self.translation),
        }
    }
}
