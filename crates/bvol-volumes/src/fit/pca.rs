//! STUB (helper replaces): PCA boxes.
use crate::Obb;
use glam::Vec3;
pub(crate) fn pca_points(_points: &[Vec3]) -> Obb { todo!() }
pub(crate) fn pca_hull(_points: &[Vec3]) -> Obb { todo!() }
