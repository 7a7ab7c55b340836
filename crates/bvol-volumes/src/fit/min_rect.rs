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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The area of the rectangle with a side along `u` (unit) around `points`.
    fn area_along(points: &[DVec2], u: DVec2) -> f64 {
        let range = |d: DVec2| {
            let k = points.iter().map(|p| p.dot(d));
            k.clone().fold(f64::NEG_INFINITY, f64::max) - k.fold(f64::INFINITY, f64::min)
        };
        range(u) * range(u.perp())
    }

    fn points(max: usize) -> impl Strategy<Value = Vec<DVec2>> {
        prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0).prop_map(|(x, y)| DVec2::new(x, y)), 1..max)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// Against brute force: some minimum rectangle is flush with the line of
        /// two of the points, so the least area over all pairs is the optimum.
        #[test]
        fn matches_brute_force(points in points(40), snap in any::<bool>()) {
            // Snapped to a coarse grid: duplicates and collinear runs.
            let points: Vec<DVec2> =
                if snap { points.iter().map(|p| (*p * 4.0).round()).collect() } else { points };
            let mut brute = f64::INFINITY;
            for a in &points {
                for b in &points {
                    if let Some(u) = (*b - *a).try_normalize() {
                        brute = brute.min(area_along(&points, u));
                    }
                }
            }
            let rect = min_area_rect(&mut points.clone(), &mut Vec::new());
            if brute.is_finite() {
                prop_assert!((rect.area - brute).abs() <= 1e-12 + 1e-9 * brute, "{} vs {brute}", rect.area);
            } else {
                prop_assert_eq!(rect.area, 0.0); // every point the same
            }
            prop_assert!((rect.side.length() - 1.0).abs() < 1e-12);
            let along = area_along(&points, rect.side);
            prop_assert!((along - rect.area).abs() <= 1e-12 + 1e-9 * along, "{along} vs {}", rect.area);
        }

        /// The hull is convex, counter-clockwise, made of input points, and holds them all.
        #[test]
        fn hull_holds_every_point(points in points(60)) {
            let mut hull = Vec::new();
            convex_hull(&mut points.clone(), &mut hull);
            prop_assert!(hull.iter().all(|h| points.contains(h)));
            for i in 0..hull.len() {
                let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
                for p in &points {
                    prop_assert!((b - a).perp_dot(*p - a) >= -1e-12, "{p} right of {a} {b}");
                }
            }
        }
    }
}
