//! The minimum-area rectangle around a planar point set: its convex hull
//! (Andrew's monotone chain, 1979), then rotating calipers over the hull's
//! edges (Toussaint 1983, "Solving geometric problems with the rotating
//! calipers"), since a minimum-area rectangle has a side flush with an edge of
//! the hull (Freeman & Shapira 1975). O(n log n) for the hull, O(h) after.

use glam::DVec2;

/// A rectangle around a point set: its area and the unit direction of one of
/// its sides (the other is perpendicular).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rect {
    /// Area, `>= 0`.
    pub area: f64,
    /// Unit direction of a side.
    pub side: DVec2,
}

/// The minimum-area rectangle around `points`, which it reorders. `hull` is
/// scratch space, reused between calls so that repeated fits do not allocate.
/// Fewer than three points in convex position give a zero-area rectangle along
/// their segment.
pub(crate) fn min_area_rect(points: &mut [DVec2], hull: &mut Vec<DVec2>) -> Rect {
    convex_hull(points, hull);
    calipers(hull)
}

/// The convex hull, counter-clockwise, without repeated or collinear vertices
/// (Andrew's monotone chain: the lower then the upper chain of the points
/// sorted by x, then y).
pub(crate) fn convex_hull(points: &mut [DVec2], hull: &mut Vec<DVec2>) {
    points.sort_unstable_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    hull.clear();
    for &p in points.iter() {
        push_convex(hull, p, 2);
    }
    let lower = hull.len() + 1;
    for &p in points.iter().rev().skip(1) {
        push_convex(hull, p, lower);
    }
    hull.pop(); // the first point again
}

/// Pushes `p` after removing the vertices that it would make non-convex (no
/// strict left turn), keeping at least `keep - 1` of them.
fn push_convex(hull: &mut Vec<DVec2>, p: DVec2, keep: usize) {
    while hull.len() >= keep {
        let (a, b) = (hull[hull.len() - 2], hull[hull.len() - 1]);
        if (b - a).perp_dot(p - a) > 0.0 {
            break;
        }
        hull.pop();
    }
    hull.push(p);
}

/// The minimum-area rectangle around a convex polygon (counter-clockwise,
/// distinct vertices): for each edge, the rectangle flush with it, its other
/// sides found by three calipers that only move forward (each is a local
/// maximum of a unimodal sequence on a convex polygon).
pub(crate) fn calipers(hull: &[DVec2]) -> Rect {
    let k = hull.len();
    if k < 3 {
        let side = match hull {
            [a, b] => (*b - *a).try_normalize().unwrap_or(DVec2::X),
            _ => DVec2::X,
        };
        return Rect { area: 0.0, side };
    }
    let at = |i: usize| hull[i % k];
    // Moves a caliper forward while `key` grows: strict, so it always stops.
    let climb = |mut i: usize, key: &dyn Fn(DVec2) -> f64| {
        while key(at(i + 1)) > key(at(i)) {
            i += 1;
        }
        i
    };
    let mut best = Rect { area: f64::INFINITY, side: DVec2::X };
    let (mut right, mut top, mut left) = (0, 0, 0);
    for i in 0..k {
        let Some(u) = (at(i + 1) - at(i)).try_normalize() else { continue };
        let w = u.perp(); // inward: the polygon lies to the left of its edges
        right = climb(right.max(i), &|p| p.dot(u));
        top = climb(top.max(right), &|p| p.dot(w));
        left = climb(left.max(top), &|p| -p.dot(u));
        let area = (at(right) - at(left)).dot(u) * (at(top) - at(i)).dot(w);
        if area < best.area {
            best = Rect { area, side: u };
        }
    }
    if best.area.is_finite() { best } else { Rect { area: 0.0, side: DVec2::X } }
}
