//! The hull of a flat point set: Andrew's monotone chain (Andrew, "Another
//! Efficient Algorithm for Convex Hulls in Two Dimensions", 1979) in 2-D
//! coordinates of the points' plane. A point stays a corner only if it lies more
//! than the tolerance outside the chord of its neighbours, so collinear and
//! near-collinear boundary points are dropped.

use glam::{DVec2, DVec3};

use super::Frame;

/// The convex polygon of the frame's points projected on the plane with unit
/// normal `normal`; `axis` is a unit vector in that plane. Input indices,
/// counter-clockwise seen from the side `normal` points to; fewer than 3 if the
/// points are collinear within tolerance.
pub(super) fn polygon(frame: &Frame, normal: DVec3, axis: DVec3) -> Vec<u32> {
    let other = normal.cross(axis);
    let mut flat: Vec<(DVec2, u32)> = (0..frame.points.len() as u32)
        .map(|i| {
            let p = frame.at(i);
            (DVec2::new(p.dot(axis), p.dot(other)), i)
        })
        .collect();
    flat.sort_by(|a, b| a.0.x.total_cmp(&b.0.x).then(a.0.y.total_cmp(&b.0.y)).then(a.1.cmp(&b.1)));
    let eps = frame.eps;
    let mut hull: Vec<(DVec2, u32)> = Vec::new();
    // Lower chain left to right, then the upper chain right to left, never
    // popping back into the lower one; the last point repeats the first.
    for &p in &flat {
        while hull.len() >= 2 && !is_corner(hull[hull.len() - 2].0, hull[hull.len() - 1].0, p.0, eps) {
            hull.pop();
        }
        hull.push(p);
    }
    let lower = hull.len() + 1;
    for &p in flat.iter().rev().skip(1) {
        while hull.len() >= lower && !is_corner(hull[hull.len() - 2].0, hull[hull.len() - 1].0, p.0, eps) {
            hull.pop();
        }
        hull.push(p);
    }
    hull.pop();
    hull.into_iter().map(|(_, i)| i).collect()
}

/// Whether `a` lies more than `eps` to the right of the directed line `o -> b`,
/// i.e. `o, a, b` turn left by more than the tolerance.
fn is_corner(o: DVec2, a: DVec2, b: DVec2, eps: f64) -> bool {
    (a - o).perp_dot(b - o) > eps * (b - o).length()
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    #[test]
    fn square_with_inner_and_edge_points_keeps_its_corners_counter_clockwise() {
        let points: Vec<Vec3> = (0..5).flat_map(|i| (0..5).map(move |j| Vec3::new(i as f32, j as f32, 2.0))).collect();
        let frame = Frame::new(&points);
        let ring = polygon(&frame, DVec3::Z, DVec3::X);
        let corners: Vec<Vec3> = ring.iter().map(|&i| points[i as usize]).collect();
        assert_eq!(
            corners,
            [Vec3::new(0.0, 0.0, 2.0), Vec3::new(4.0, 0.0, 2.0), Vec3::new(4.0, 4.0, 2.0), Vec3::new(0.0, 4.0, 2.0)]
        );
    }

    #[test]
    fn collinear_points_give_two_ends() {
        let points: Vec<Vec3> = (0..7).map(|i| Vec3::new(i as f32, 2.0 * i as f32, 0.0)).collect();
        let frame = Frame::new(&points);
        let axis = DVec3::new(1.0, 2.0, 0.0).normalize();
        assert_eq!(polygon(&frame, DVec3::Z, axis).len(), 2);
    }
}
