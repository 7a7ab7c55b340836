//! Face planes of convex shapes.

use glam::DVec3;

/// A face's plane: `normal . x = offset` on it, `normal` unit and outward.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Plane {
    /// Unit outward normal.
    pub normal: DVec3,
    /// Signed distance of the plane from the origin along `normal`.
    pub offset: f64,
}

impl Plane {
    /// Signed distance of `p` above the plane.
    pub fn distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }

    /// This plane of a face of the unit cube moved out to the same face of
    /// the box of half extents `half`: the cube's faces are axis-aligned, so
    /// scaling moves each out to `half` on its axis.
    pub fn scaled_to_box(self, half: DVec3) -> Plane {
        Plane { normal: self.normal, offset: self.normal.abs().dot(half) }
    }
}
