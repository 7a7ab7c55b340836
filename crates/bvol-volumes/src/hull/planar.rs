//! The hull of a flat point set: Andrew's monotone chain (Andrew, "Another
//! Efficient Algorithm for Convex Hulls in Two Dimensions", 1979) in 2-D
//! coordinates of the points' plane, strictly convex, then thinned by
//! Douglas-Peucker between two corners that are sure to stay (the one farthest
//! from the corners' mean, and the one farthest from it: a distance is largest at
//! a corner, never inside an edge), so boundary points within tolerance of a
//! straight edge are dropped and every dropped one stays within tolerance of the
//! edge that spans it. (Dropping by a tolerance inside the chain itself would not
//! do: where points within tolerance of a line are sorted out of their order
//! along it, the chain can drop an end of it.)

use glam::{DVec2, DVec3};

use super::{CentredPoints, douglas_peucker};

/// The convex polygon of the points projected on the plane with unit
/// normal `normal`; `axis` is a unit vector in that plane. Input indices,
/// counter-clockwise seen from the side `normal` points to; fewer than 3 if the
/// points are collinear within tolerance.
pub(super) fn polygon(centred: &CentredPoints, normal: DVec3, axis: DVec3) -> Vec<u32> {
    let other = normal.cross(axis);
    let flat = (0..centred.points.len() as u32).map(|i| {
        let p = centred.at(i);
        (DVec2::new(p.dot(axis), p.dot(other)), i)
    });
    let mut ring = convex_chain(flat.collect());
    if ring.len() < 3 {
        return ring;
    }
    let mean = ring.iter().map(|&i| centred.at(i)).sum::<DVec3>() / ring.len() as f64;
    let farthest = |from: DVec3, ring: &[u32]| {
        (0..ring.len())
            .map(|k| (k, centred.at(ring[k]).distance_squared(from)))
            .fold((0, -1.0), |m, x| if x.1 > m.1 { x } else { m })
            .0
    };
    let start = farthest(mean, &ring);
    ring.rotate_left(start);
    let other_end = farthest(centred.at(ring[0]), &ring);
    let mut pos: Vec<DVec3> = ring.iter().map(|&i| centred.at(i)).collect();
    pos.push(pos[0]);
    let mut keep = vec![true; pos.len()];
    douglas_peucker(&pos[..=other_end], centred.eps, &mut keep[..=other_end]);
    douglas_peucker(&pos[other_end..], centred.eps, &mut keep[other_end..]);
    ring.into_iter().zip(keep).filter_map(|(i, k)| k.then_some(i)).collect()
}

/// The corners of the 2-D convex hull of labelled points, strictly convex,
/// counter-clockwise from the lexicographically least point, as labels.
pub(super) fn convex_chain(mut flat: Vec<(DVec2, u32)>) -> Vec<u32> {
    if flat.len() < 2 {
        return flat.into_iter().map(|(_, i)| i).collect();
    }
    flat.sort_unstable_by(|a, b| {
        a.0.x.total_cmp(&b.0.x).then(a.0.y.total_cmp(&b.0.y)).then(a.1.cmp(&b.1))
    });
    let mut hull: Vec<(DVec2, u32)> = Vec::new();
    // Lower chain left to right, then the upper chain right to left, never
    // popping back into the lower one; the last point repeats the first.
    for &p in &flat {
        while hull.len() >= 2 && !turns_left(hull[hull.len() - 2].0, hull[hull.len() - 1].0, p.0) {
            hull.pop();
        }
        hull.push(p);
    }
    let right = hull.len() - 1;
    for &p in flat.iter().rev().skip(1) {
        while hull.len() > right + 1
            && !turns_left(hull[hull.len() - 2].0, hull[hull.len() - 1].0, p.0)
        {
            hull.pop();
        }
        hull.push(p);
    }
    hull.pop();
    hull.into_iter().map(|(_, i)| i).collect()
}

/// Whether `o, a, b` turn left (counter-clockwise), strictly.
fn turns_left(o: DVec2, a: DVec2, b: DVec2) -> bool {
    (a - o).perp_dot(b - o) > 0.0
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    #[test]
    fn square_with_inner_and_edge_points_keeps_its_corners_counter_clockwise() {
        let points: Vec<Vec3> =
            (0..5).flat_map(|i| (0..5).map(move |j| Vec3::new(i as f32, j as f32, 2.0))).collect();
        let centred = CentredPoints::new(&points);
        let ring = polygon(&centred, DVec3::Z, DVec3::X);
        let corners: Vec<Vec3> = ring.iter().map(|&i| points[i as usize]).collect();
        assert_eq!(
            corners,
            [
                Vec3::new(0.0, 0.0, 2.0),
                Vec3::new(4.0, 0.0, 2.0),
                Vec3::new(4.0, 4.0, 2.0),
                Vec3::new(0.0, 4.0, 2.0)
            ]
        );
    }

    #[test]
    fn collinear_points_give_two_ends() {
        let points: Vec<Vec3> = (0..7).map(|i| Vec3::new(i as f32, 2.0 * i as f32, 0.0)).collect();
        let centred = CentredPoints::new(&points);
        let axis = DVec3::new(1.0, 2.0, 0.0).normalize();
        assert_eq!(polygon(&centred, DVec3::Z, axis).len(), 2);
    }
}
