//! The arcs of a convex shape's edges on its Gauss map, with the bounds that
//! let the edge query skip them (Gregorius, GDC 2013).

use glam::DVec3;

use crate::cluster::Cap;
use crate::plane::Plane;

/// An edge's arc on the Gauss map (the great-circle arc between its two
/// faces' normals), for the bounds that let the edge query skip it: its two
/// ends, the cap it lies in (about its midpoint, of its half angle), the unit
/// pole of its great circle, and how deep the shape's inner centre is behind
/// the edge along any direction of the arc.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Arc {
    /// The two face normals it joins, from the face of the edge's half-edge
    /// to its twin's: kept here so that the edge query reads them in one place.
    pub ends: (DVec3, DVec3),
    /// The cap about the arc's midpoint whose radius is its half angle.
    pub cap: Cap,
    /// Unit normal of the arc's plane (zero if the two normals coincide).
    pub pole: DVec3,
    /// The lesser of the inner centre's distances behind the two faces: along
    /// any direction `d` of the arc, `d . (edge - centre)` is at least this
    /// (`d` is a combination of the normals with weights summing to at least 1).
    pub inner: f64,
}

impl Arc {
    /// The arc of the edge between faces `p1` and `p2` (not opposite), of a
    /// shape with inner centre `centre`.
    pub fn new(p1: Plane, p2: Plane, centre: DVec3) -> Arc {
        let (n1, n2) = (p1.normal, p2.normal);
        let mid = (n1 + n2).normalize_or_zero();
        Arc {
            ends: (n1, n2),
            cap: Cap { axis: mid, cos: mid.dot(n1), sin: mid.cross(n1).length() },
            pole: n1.cross(n2).normalize_or_zero(),
            inner: (-p1.distance(centre)).min(-p2.distance(centre)),
        }
    }

    /// The greatest `d . w` over the directions `d` of the arc, exactly: `w`'s
    /// part in the arc's plane if its direction falls within the arc (its
    /// angle from the midpoint at most the half angle), else at the nearer end.
    pub fn max(&self, w: DVec3) -> f64 {
        let along = self.cap.axis.dot(w);
        let across = self.pole.dot(w);
        let in_plane2 = (w.length_squared() - across * across).max(0.0);
        if along > 0.0 && along * along >= self.cap.cos * self.cap.cos * in_plane2 {
            in_plane2.sqrt()
        } else {
            self.ends.0.dot(w).max(self.ends.1.dot(w))
        }
    }
}
