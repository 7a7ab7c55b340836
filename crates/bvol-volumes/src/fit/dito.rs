//! STUB (helper replaces): DiTO-k.
use crate::Obb;
use glam::Vec3;
pub(crate) fn dito<const N: usize>(_points: &[Vec3]) -> Obb { todo!() }
