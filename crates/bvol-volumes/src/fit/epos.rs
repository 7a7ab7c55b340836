//! STUB (helper replaces): EPOS-k.
use crate::Sphere;
use glam::Vec3;
pub(crate) fn epos<const N: usize>(_points: &[Vec3]) -> Sphere { todo!() }
