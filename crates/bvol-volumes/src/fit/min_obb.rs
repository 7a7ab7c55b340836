//! STUB (helper replaces): near-minimum-volume box.
use crate::Obb;
use glam::Vec3;
pub(crate) fn min_volume(_points: &[Vec3]) -> Obb { todo!() }
