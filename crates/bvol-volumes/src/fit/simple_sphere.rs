//! STUB (helper replaces): AABB-centre, centroid and Ritter spheres.
use crate::Sphere;
use glam::Vec3;
pub(crate) fn aabb_center(_points: &[Vec3]) -> Sphere { todo!() }
pub(crate) fn centroid(_points: &[Vec3]) -> Sphere { todo!() }
pub(crate) fn ritter(_points: &[Vec3]) -> Sphere { todo!() }
