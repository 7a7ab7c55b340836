//! STUB (helper replaces): 3-D convex hull (quickhull).
use glam::{DVec3, Vec3};
use crate::FitError;

/// A convex hull.
#[derive(Clone, Debug)]
pub struct ConvexHull {
    vertices: Vec<Vec3>,
}

impl ConvexHull {
    /// Builds the hull.
    pub fn new(_points: &[Vec3]) -> Result<ConvexHull, FitError> { todo!() }
    /// 0 point, 1 segment, 2 polygon, 3 solid.
    pub fn dimension(&self) -> u8 { todo!() }
    /// Hull vertices.
    pub fn vertices(&self) -> &[Vec3] { &self.vertices }
    /// Number of faces.
    pub fn face_count(&self) -> usize { todo!() }
    /// Face polygon.
    pub fn face(&self, _i: usize) -> &[u32] { todo!() }
    /// Face normal.
    pub fn face_normal(&self, _i: usize) -> DVec3 { todo!() }
    /// Triangles.
    pub fn triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ { std::iter::empty() }
    /// Edges.
    pub fn edges(&self) -> impl Iterator<Item = [u32; 2]> + '_ { std::iter::empty() }
    /// Volume.
    pub fn volume(&self) -> f64 { todo!() }
    /// Area.
    pub fn surface_area(&self) -> f64 { todo!() }
}
