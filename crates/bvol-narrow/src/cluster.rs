//! Directions grouped into caps on the unit sphere, so that a query can pass
//! over a whole group of faces or edge arcs of the Gauss map with one test.

use std::ops::Range;

use glam::DVec3;

use crate::grid::seed_slot;

/// A cap of the unit sphere: the directions within an angle of an axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Cap {
    /// Unit axis.
    pub axis: DVec3,
    /// Cosine of the angular radius (`<= 0` for a half sphere or more).
    pub cos: f64,
    /// Sine of the angular radius.
    pub sin: f64,
}

impl Cap {
    /// The cap of radius `angle` (radians) about unit `axis`.
    pub fn new(axis: DVec3, angle: f64) -> Cap {
        Cap { axis, cos: angle.cos(), sin: angle.sin() }
    }

    /// The angular radius.
    fn angle(&self) -> f64 {
        self.sin.atan2(self.cos)
    }

    /// An upper bound of `d . w` over the cap's directions `d`, with `length =
    /// |w|`. Writing `d = axis cos(p) + u sin(p)` with `|p|` at most the
    /// radius, `d . w <= (axis . w) cos(p) + |w| sin(|p|)`: the axis's value
    /// (shrunk at most to its cosine share when negative) plus the radius's
    /// sine times the length. A cap of a half sphere or more gets `|w|`.
    pub fn max(&self, w: DVec3, length: f64) -> f64 {
        if self.cos <= 0.0 {
            return length;
        }
        let along = self.axis.dot(w);
        (if along >= 0.0 { along } else { along * self.cos }) + length * self.sin
    }

    /// The least cap about the mean of the caps' axes that holds them all,
    /// widened by a hair against rounding.
    fn around(caps: impl Iterator<Item = Cap> + Clone) -> Cap {
        let sum: DVec3 = caps.clone().map(|c| c.axis).sum();
        let axis = sum.try_normalize().or(caps.clone().next().map(|c| c.axis)).unwrap_or(DVec3::Z);
        let angle = caps
            .map(|c| axis.cross(c.axis).length().atan2(axis.dot(c.axis)) + c.angle())
            .fold(0.0, f64::max);
        Cap::new(axis, angle + 1e-9)
    }
}

/// A group of faces or edges whose directions (face normals, or edge arcs)
/// lie in one cap, with the least depth of the shape's inner centre behind
/// any of them: a query bounds the whole group by those two numbers.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Cluster {
    /// The cap holding every member's direction.
    pub cap: Cap,
    /// The least depth of the inner centre behind a member.
    pub inner: f64,
    /// The members: a run of face or edge indices.
    pub members: Range<u32>,
}

impl Cluster {
    /// Whether it has more than one member: the bounds of a lone member are
    /// as tight as its cluster's (its own direction, not a cap about it), so
    /// a query tests only those (every face and edge of a box is alone).
    pub fn is_group(&self) -> bool {
        self.members.len() > 1
    }
}

/// An order of items (faces by their normals, edges by their arcs' caps) in
/// which those of one of the 26 grid directions of [`seed_slot`] come
/// together, stably, and the clusters of that order, given each item's cap
/// and depth.
pub(crate) fn group(items: &[(Cap, f64)]) -> (Vec<u32>, Vec<Cluster>) {
    let mut order: Vec<u32> = (0..items.len() as u32).collect();
    order.sort_by_key(|&i| seed_slot(items[i as usize].0.axis));
    let mut clusters = Vec::new();
    let mut start = 0;
    while start < order.len() {
        let slot = seed_slot(items[order[start] as usize].0.axis);
        let end = start
            + order[start..]
                .iter()
                .take_while(|&&i| seed_slot(items[i as usize].0.axis) == slot)
                .count();
        let members = order[start..end].iter().map(|&i| items[i as usize]);
        clusters.push(Cluster {
            cap: Cap::around(members.clone().map(|m| m.0)),
            inner: members.map(|m| m.1).fold(f64::INFINITY, f64::min),
            members: start as u32..end as u32,
        });
        start = end;
    }
    (order, clusters)
}
