//! The minimum-area rectangle around a planar point set: its convex hull
//! (Andrew's monotone chain, 1979), then rotating calipers over the hull's
//! edges (Toussaint 1983, "Solving geometric problems with the rotating
//! calipers"), since a minimum-area rectangle has a side flush with an edge of
//! the hull (Freeman & Shapira 1975). O(n log n) for the hull, O(h) after.

use glam::DVec2;

/// Edge length, relative to the polygon's extent, below which an edge is
/// rounding noise: far above the rounding of coordinates computed in f64
/// (about 1e-16 of the extent), far below anything a box's volume shows.
const NOISE: f64 = 1e-12;

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
fn convex_hull(points: &mut [DVec2], hull: &mut Vec<DVec2>) {
    // By value, so that -0.0 and 0.0 are one coordinate (total_cmp would split
    // them, and a point between them in the order would break the chains).
    let order = |a: f64, b: f64| a.partial_cmp(&b).unwrap_or(std::cmp::Ordering::Equal);
    points.sort_unstable_by(|a, b| order(a.x, b.x).then(order(a.y, b.y)));
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
fn calipers(hull: &[DVec2]) -> Rect {
    let k = hull.len();
    if k < 3 {
        let side = match hull {
            [a, b] => (*b - *a).try_normalize().unwrap_or(DVec2::X),
            _ => DVec2::X,
        };
        return Rect { area: 0.0, side };
    }
    // Edges shorter than this are rounding noise between near-duplicate
    // vertices: their direction means nothing, and the calipers skip them.
    let (lo, hi) = hull.iter().fold((hull[0], hull[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let noise = (NOISE * (hi - lo).max_element()).powi(2);
    let next = |i: usize| if i + 1 == k { 0 } else { i + 1 };
    // Moves a caliper forward while `key` grows: strict, so it always stops.
    let climb = |mut i: usize, key: DVec2| {
        while hull[next(i)].dot(key) > hull[i].dot(key) {
            i = next(i);
        }
        i
    };
    let (mut best_area, mut best_side) = (f64::INFINITY, DVec2::X);
    // Caliper positions, set on the first edge that is not noise.
    let mut calipers: Option<(usize, usize, usize)> = None;
    for i in 0..k {
        // Unnormalised: the scale of the edge cancels in the area.
        let u = hull[next(i)] - hull[i];
        if u.length_squared() <= noise {
            continue;
        }
        let w = u.perp(); // inward: the polygon lies to the left of its edges
        let (right, top, left) = match calipers {
            Some((right, top, left)) => (climb(right, u), climb(top, w), climb(left, -u)),
            None => {
                let right = climb(i, u);
                let top = climb(right, w);
                (right, top, climb(top, -u))
            }
        };
        calipers = Some((right, top, left));
        let area =
            (hull[right] - hull[left]).dot(u) * (hull[top] - hull[i]).dot(w) / u.length_squared();
        if area < best_area {
            (best_area, best_side) = (area, u);
        }
    }
    match calipers {
        Some(_) => Rect { area: best_area, side: best_side.normalize() },
        None => Rect { area: 0.0, side: DVec2::X }, // every vertex the same, to rounding
    }
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
        prop::collection::vec(
            (-1.0f64..1.0, -1.0f64..1.0).prop_map(|(x, y)| DVec2::new(x, y)),
            1..max,
        )
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
                    // Outside by no more than the rounding-level tolerance.
                    let distance = (b - a).perp_dot(*p - a) / (b - a).length();
                    prop_assert!(distance >= -4.0 * NOISE, "{p} right of {a} {b}");
                }
            }
        }
    }
}
