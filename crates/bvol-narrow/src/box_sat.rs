//! The separating-axis queries between two boxes in closed form: the 15 axes
//! of Gottschalk, Lin & Manocha ("OBBTree", SIGGRAPH 1996; Ericson,
//! Real-Time Collision Detection 4.4.1) — the 3 face normals of each box and
//! the 9 cross products of their edge directions — each box's extent along
//! an axis read off its half extents and the relative rotation, with no
//! search. The answers are the general queries' (`sat.rs`) for the same
//! boxes: the face of each with the greatest separation and the edge pair
//! with the greatest, named by the shapes' own face, vertex and edge
//! numbers, so that the same preferences and manifolds follow.
//!
//! Every edge-direction pair of two boxes is a Minkowski face (once each way
//! along its cross product: each box's edges of one direction have arcs
//! that cover a whole great circle, and two great circles meet), so the
//! greatest edge separation is the greatest over the 9 cross products, taken
//! the way that points from A's centre towards B's.

use glam::DVec3;

use crate::box_numbering::BoxNumbering;
use crate::isometry::DIsometry3;
use crate::sat::{EdgeQuery, FaceQuery, PARALLEL_SINE};

/// What the closed-form queries found: the face of A and of B with the
/// greatest separation, and the edge pair with the greatest (`None` if every
/// pair of edge directions is parallel).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BoxQueries {
    /// A's face whose normal separates most, with B's lowest corner under it.
    pub face_a: FaceQuery,
    /// B's face whose normal separates most, with A's lowest corner under it.
    pub face_b: FaceQuery,
    /// The edge pair whose common normal separates most.
    pub edge: Option<EdgeQuery>,
}

/// The queries between box `a` and box `b`, `rel` mapping B's space into
/// A's (`x -> R x + t`).
///
/// Along a unit axis `u` (in A's space), A reaches `sum_k a_k |u_k|` from
/// its centre and B reaches `sum_k b_k |u . R e_k|` from its own, at `t`:
/// the gap is `|u . t|` less both reaches. For A's face normal `e_i` that is
/// `|t_i| - a_i - sum_k b_k |R_ik|`; for B's, the same with the roles
/// swapped; for edge directions `e_i` and `R e_j`, `u` is their unit cross
/// product, skipped when its length (their angle's sine) is at most
/// [`PARALLEL_SINE`], as the general edge query does.
pub(crate) fn box_queries(
    (ha, a): (DVec3, &BoxNumbering),
    (hb, b): (DVec3, &BoxNumbering),
    rel: &DIsometry3,
) -> BoxQueries {
    let (r, t) = (rel.rotation, rel.translation);
    let rows = r.transpose(); // rows[i] = row i of R: B's axes' i-th components
    let m = [rows.x_axis, rows.y_axis, rows.z_axis]; // m[i][j] = R[i][j]
    let abs_rows = m.map(DVec3::abs);
    let columns = [r.x_axis, r.y_axis, r.z_axis]; // B's axes in A's space
    // Plain arrays and fixed loops: they unroll into straight-line code
    // (indexing a `DVec3` by a variable checks the index each time).
    let (t3, ha3, hb3) = (t.to_array(), ha.to_array(), hb.to_array());
    // A's faces.
    let mut face_a = (0, f64::NEG_INFINITY);
    for i in 0..3 {
        let gap = t3[i].abs() - ha3[i] - abs_rows[i].dot(hb);
        if gap > face_a.1 {
            face_a = (i, gap);
        }
    }
    // B's faces: A's centre in B's space is `-R^T t`.
    let centre_a = -(rows * t);
    let centre3 = centre_a.to_array();
    let mut face_b = (0, f64::NEG_INFINITY);
    for j in 0..3 {
        let reach_a = columns[j].abs().dot(ha);
        let gap = centre3[j].abs() - hb3[j] - reach_a;
        if gap > face_b.1 {
            face_b = (j, gap);
        }
    }
    // Edge pairs. Along the unnormalised cross product `l = e_i x R e_j`
    // the reaches and the distance all scale by `|l|`: the gap is `(|l . t|
    // - reaches) / |l|`. Each term is read off R (Gottschalk et al., table
    // 1; Ericson 4.4.1): `l` has components `-R[i2][j]` at `i1` and
    // `R[i1][j]` at `i2` (`i1, i2` the axes after `i`), and `l . R e_k` is
    // 0, `R[i][j2]` and `-R[i][j1]` for `k = j, j1, j2`, R being a rotation.
    // Gaps are ranked by their signed squares over `|l|^2`, cross-multiplied:
    // no root or division until the winner.
    let (m, abs_m) = (m.map(|r| r.to_array()), abs_rows.map(|r| r.to_array()));
    // The best so far as (i, j, gap, signed square, |l|^2), chosen by
    // selects rather than branches: which pair wins is data, and a
    // mispredicted branch per pair cost more than the nine comparisons.
    let mut best = (0, 0, 0.0, f64::NEG_INFINITY, 1.0);
    for (i, abs_row) in abs_m.iter().enumerate() {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for (j, (&r1, &r2)) in m[i1].iter().zip(&m[i2]).enumerate() {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            let len2 = r1 * r1 + r2 * r2;
            let along = r1 * t3[i2] - r2 * t3[i1];
            let reach_a = ha3[i1] * r2.abs() + ha3[i2] * r1.abs();
            let reach_b = hb3[j1] * abs_row[j2] + hb3[j2] * abs_row[j1];
            let gap = along.abs() - reach_a - reach_b;
            let square = gap * gap.abs();
            let better = len2 > PARALLEL_SINE * PARALLEL_SINE && square * best.4 > best.3 * len2;
            best = if better { (i, j, gap, square, len2) } else { best };
        }
    }
    let edge = (best.3 > f64::NEG_INFINITY).then_some((best.0, best.1, best.2, best.4));
    let face =
        |features: &BoxNumbering, i: usize, along: f64| features.face[i][usize::from(along < 0.0)];
    // The other box's lowest corner against a face's normal `n` (in its space).
    let lowest = |features: &BoxNumbering, n: DVec3| features.vertex[BoxNumbering::highest(-n)];
    let (i, gap) = face_a;
    let normal_a = DVec3::AXES[i] * if t[i] < 0.0 { -1.0 } else { 1.0 };
    let face_a =
        FaceQuery { face: face(a, i, t[i]), separation: gap, support: lowest(b, rows * normal_a) };
    let (j, gap) = face_b;
    let normal_b = DVec3::AXES[j] * if centre_a[j] < 0.0 { -1.0 } else { 1.0 };
    let face_b = FaceQuery {
        face: face(b, j, centre_a[j]),
        separation: gap,
        support: lowest(a, r * normal_b),
    };
    let edge = edge.map(|(i, j, gap, len2)| {
        let l = DVec3::AXES[i].cross(columns[j]);
        let l = if l.dot(t) < 0.0 { -l } else { l };
        let length = len2.sqrt();
        let (u, separation) = (l / length, gap / length);
        // A's edge along e_i highest along u, B's along its e_j lowest.
        let top = BoxNumbering::highest(u);
        let ub = rows * u;
        let bottom = BoxNumbering::highest(-ub);
        EdgeQuery {
            edge_a: a.edge[top & !(1 << i)][top | (1 << i)],
            half_edge_b: b.half_edge[bottom & !(1 << j)][bottom | (1 << j)],
            separation,
            axis: u,
        }
    });
    BoxQueries { face_a, face_b, edge }
}

#[cfg(test)]
mod tests {
    use glam::{DMat3, DQuat, Vec3};

    use super::*;
    use crate::Polyhedron;
    use crate::convex::Convex;
    use crate::sat::tests::next;

    /// The greatest of `min over B - max over A` along `axis`, from every
    /// vertex of both (B's mapped by `rel`).
    fn vertex_gap(a: &Polyhedron, b: &Polyhedron, rel: &DIsometry3, axis: DVec3) -> f64 {
        let high_a = a.points.iter().map(|&v| axis.dot(v)).fold(f64::NEG_INFINITY, f64::max);
        let low_b = b.points.iter().map(|&v| axis.dot(rel.apply(v))).fold(f64::INFINITY, f64::min);
        low_b - high_a
    }

    /// The greatest separation over the faces of `reference`, from every
    /// vertex of `other` (mapped by `rel`).
    fn brute_faces(reference: &Polyhedron, other: &Polyhedron, rel: &DIsometry3) -> f64 {
        (0..6)
            .map(|f| {
                let plane = reference.plane(f);
                other
                    .points
                    .iter()
                    .map(|&v| plane.distance(rel.apply(v)))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The greatest gap over both directions of every edge pair's cross
    /// product (skipping pairs closer to parallel than the queries do).
    fn brute_edges(a: &Polyhedron, b: &Polyhedron, rel: &DIsometry3) -> Option<f64> {
        let direction = |p: &Polyhedron, h: u32| {
            p.vertex(p.topology.head(h)) - p.vertex(p.topology.half_edge(h).origin)
        };
        let mut best: Option<f64> = None;
        for &ha in &a.topology.edges {
            for &hb in &b.topology.edges {
                let cross = direction(a, ha).cross(rel.rotate(direction(b, hb)));
                let (da, db) = (direction(a, ha).length(), direction(b, hb).length());
                if cross.length() <= PARALLEL_SINE * da * db {
                    continue;
                }
                let u = cross.normalize();
                let gap = vertex_gap(a, b, rel, u).max(vertex_gap(a, b, rel, -u));
                best = Some(best.map_or(gap, |x| x.max(gap)));
            }
        }
        best
    }

    /// On random boxes, apart and overlapping: the closed-form queries give
    /// the greatest separations that every vertex of both boxes gives along
    /// every face normal and edge cross product, and name faces, vertices
    /// and edges that attain them.
    #[test]
    fn closed_form_matches_every_vertex_along_every_axis() {
        let mut state = 7;
        for case in 0..2000 {
            let mut half = || {
                Vec3::new(0.05, 0.05, 0.05)
                    + 2.0
                        * Vec3::new(
                            next(&mut state) as f32,
                            next(&mut state) as f32,
                            next(&mut state) as f32,
                        )
            };
            let (a, b) = (Polyhedron::cuboid(half()).unwrap(), Polyhedron::cuboid(half()).unwrap());
            let mut q = || next(&mut state) - 0.5;
            let rotation = DQuat::from_xyzw(q(), q(), q(), q()).normalize();
            // Every fifth case turned by a quarter turn: parallel edges.
            let rotation = if case % 5 == 0 {
                DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2)
            } else {
                rotation
            };
            let rel = DIsometry3 {
                rotation: DMat3::from_quat(rotation),
                translation: DVec3::new(q(), q(), q()) * 6.0,
            };
            let inv = rel.relative(&DIsometry3::IDENTITY);
            let got = box_queries(a.as_box().unwrap(), b.as_box().unwrap(), &rel);
            let tolerance = 1e-12 * (a.size + b.size);
            let close = |x: f64, y: f64| (x - y).abs() <= tolerance;
            for (q, reference, other, map) in
                [(got.face_a, &a, &b, &rel), (got.face_b, &b, &a, &inv)]
            {
                let brute = brute_faces(reference, other, map);
                assert!(close(q.separation, brute), "case {case}: {q:?} vs {brute}");
                // The named face and support point attain it.
                let at = reference.plane(q.face).distance(map.apply(other.vertex(q.support)));
                assert!(close(at, q.separation), "case {case}: {q:?} vs {at}");
            }
            match (got.edge, brute_edges(&a, &b, &rel)) {
                (Some(e), Some(brute)) => {
                    assert!(
                        close(e.separation, brute),
                        "case {case}: edges {} vs {brute}",
                        e.separation
                    );
                    // The named edges are both shapes' supports along the axis.
                    let ha = a.topology.edges[e.edge_a as usize];
                    let ends_a = [a.topology.half_edge(ha).origin, a.topology.head(ha)];
                    let ends_b = [
                        b.topology.half_edge(e.half_edge_b).origin,
                        b.topology.head(e.half_edge_b),
                    ];
                    let high_a =
                        a.points.iter().map(|&v| e.axis.dot(v)).fold(f64::NEG_INFINITY, f64::max);
                    let low_b = b
                        .points
                        .iter()
                        .map(|&v| e.axis.dot(rel.apply(v)))
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        ends_a.iter().all(|&v| close(e.axis.dot(a.vertex(v)), high_a)),
                        "case {case}"
                    );
                    assert!(
                        ends_b.iter().all(|&v| close(e.axis.dot(rel.apply(b.vertex(v))), low_b)),
                        "case {case}"
                    );
                }
                (None, None) => {}
                (got, brute) => panic!("case {case}: {got:?} vs {brute:?}"),
            }
        }
    }

    /// A box's numbering only for a box centred on its origin, square to its
    /// axes; any other hull takes the general queries.
    #[test]
    fn only_axis_boxes_are_numbered() {
        let corners = |shift: Vec3| -> Vec<Vec3> {
            (0..8)
                .map(|i| {
                    Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2) as f32) * 2.0 - 1.0
                        + shift
                })
                .collect()
        };
        assert!(Polyhedron::from_points(&corners(Vec3::ZERO)).unwrap().as_box().is_some());
        assert!(Polyhedron::from_points(&corners(Vec3::X * 0.5)).unwrap().as_box().is_none());
        let turned: Vec<Vec3> =
            corners(Vec3::ZERO).iter().map(|&p| glam::Quat::from_rotation_z(0.3) * p).collect();
        assert!(Polyhedron::from_points(&turned).unwrap().as_box().is_none());
        let wedge = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE];
        assert!(Polyhedron::from_points(&wedge).unwrap().as_box().is_none());
    }
}
