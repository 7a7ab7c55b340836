//! Segments in f64: a capsule's core, and the edges its routines meet.

use glam::DVec3;

/// The points `start + t * delta` for `t` in `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Segment {
    /// One end.
    pub start: DVec3,
    /// From that end to the other.
    pub delta: DVec3,
}

impl Segment {
    /// The segment from `start` to `end`.
    pub fn new(start: DVec3, end: DVec3) -> Segment {
        Segment { start, delta: end - start }
    }

    /// The other end.
    pub fn end(&self) -> DVec3 {
        self.start + self.delta
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f64) -> DVec3 {
        self.start + self.delta * t
    }

    /// The parameter of the point nearest `p` (Ericson, Real-Time Collision
    /// Detection 5.1.2): the projection on the line, clamped to the ends.
    pub fn nearest_to(&self, p: DVec3) -> f64 {
        let len2 = self.delta.length_squared();
        if len2 > 0.0 { ((p - self.start).dot(self.delta) / len2).clamp(0.0, 1.0) } else { 0.0 }
    }

    /// The closest points of this segment and `other`, one on each (Ericson
    /// 5.1.9, `ClosestPtSegmentSegment`): the lines' closest points, each
    /// parameter clamped to its segment and the other recomputed from it.
    /// Zero-length and parallel segments are handled; a tiny positive
    /// divisor only gives a parameter that the clamp brings back.
    pub fn closest_points(&self, other: &Segment) -> (DVec3, DVec3) {
        let (d1, d2) = (self.delta, other.delta);
        let r = self.start - other.start;
        let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
        let (s, t) = if a <= 0.0 {
            (0.0, other.nearest_to(self.start))
        } else if e <= 0.0 {
            (self.nearest_to(other.start), 0.0)
        } else {
            let (b, c) = (d1.dot(d2), d1.dot(r));
            let denom = a * e - b * b;
            // Parallel lines (denom 0): any s will do; 0 is Ericson's choice.
            let s = if denom > 0.0 { ((b * f - c * e) / denom).clamp(0.0, 1.0) } else { 0.0 };
            let t = (b * s + f) / e;
            if t < 0.0 {
                ((-c / a).clamp(0.0, 1.0), 0.0)
            } else if t > 1.0 {
                (((b - c) / a).clamp(0.0, 1.0), 1.0)
            } else {
                (s, t)
            }
        };
        (self.at(s), other.at(t))
    }
}
