//! STUB (helper replaces): exact minimum sphere.
use crate::Sphere;
use glam::{DVec3, Vec3};
pub(crate) fn exact(_points: &[Vec3]) -> Sphere { todo!() }
pub(crate) fn min_sphere_f64(_points: &[DVec3]) -> (DVec3, f64) { todo!() }
