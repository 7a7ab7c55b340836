//! The per-pair cache of the feature that decided the last call, re-tested
//! first on the next: a pair that was apart along an axis mostly still is.

use crate::convex::Convex;
use crate::frame::Frame;
use crate::sat::{AxisGap, axis_gap, centre_axis, edge_separation, face_separation};
use crate::topology::Topology;

/// A cached axis must separate the shapes by more than this, relative to their
/// size, for the call to answer from it alone. The full query can miss a
/// separation by a little (hill climbing on faces merged within the hull's
/// tolerance, about 4e-7 of the size; near-parallel edges skipped, 1e-8), so a
/// cached axis separating by less might be one the full query would not
/// confirm. Above this margin it would, so the cache never changes whether a
/// pair is apart; below it the full query answers.
const MARGIN: f64 = 1e-6;

/// The feature whose axis decided the last call of a pair.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum Feature {
    /// Nothing cached.
    #[default]
    None,
    /// The line between the shapes' inner centres, and the support points
    /// along it, where hill climbing starts.
    Centres {
        /// A's highest vertex along the line.
        support_a: u32,
        /// B's lowest vertex along the line.
        support_b: u32,
    },
    /// A face of A, and B's lowest vertex against it.
    FaceA {
        /// The face of A.
        face: u32,
        /// B's support point against its normal, where hill climbing starts.
        support: u32,
    },
    /// A face of B, and A's lowest vertex against it.
    FaceB {
        /// The face of B.
        face: u32,
        /// A's support point against its normal, where hill climbing starts.
        support: u32,
    },
    /// An edge of A and a half-edge of B.
    Edges {
        /// Index into A's edge list.
        edge_a: u32,
        /// A half-edge of B.
        half_edge_b: u32,
    },
}

/// What [`hull_hull`](crate::hull_hull) remembers of a pair between calls: the
/// feature whose axis decided the last call (the line between the shapes'
/// centres, a face of either, or an edge of each) and the support points
/// found along it. Keep one per pair, starting from `WarmStart::default()`.
///
/// A call re-tests that axis first: if it still separates the pair, by a
/// margin, the call answers [`Separated`](crate::Collision::Separated) at once,
/// after one support point of each shape. Otherwise it runs the full query,
/// whose answer does not depend on the cache: the gap along the cached axis
/// and its support points only let it skip faces and edges that cannot be
/// picked, which makes touching pairs cheaper too. So the cache never changes
/// whether a pair is apart or touching, nor any contact; only which separating
/// axis a pair that is apart is reported with. A cache from another pair of
/// shapes is harmless: features out of range are ignored. Two boxes (see
/// [`Polyhedron::cuboid`](crate::Polyhedron::cuboid)) do not read it: their
/// closed-form test of all 15 axes costs about what the retest does.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WarmStart {
    pub(crate) feature: Feature,
}

/// The cached feature's axis and the exact gap along it between `a` and `b`
/// (placed by their frames; `rel` maps B's space into A's), from true
/// support points, with a point of each shape at the gap's ends; `None` if
/// nothing usable is cached. A gap above [`answers`]'s margin settles the
/// call; any gap is a lower bound of the greatest separation over all axes,
/// and its points are witnesses near the contact, which a touching pair's
/// full query may start from.
pub(crate) fn retest<A: Convex, B: Convex>(
    feature: Feature,
    a: &A,
    frame_a: &Frame,
    b: &B,
    frame_b: &Frame,
    rel: &Frame,
) -> Option<AxisGap> {
    let (ta, tb) = (a.topology(), b.topology());
    let (na, nb) = (ta.vertex_count() as u32, tb.vertex_count() as u32);
    let (fa, fb) = (ta.face_count() as u32, tb.face_count() as u32);
    let exact = f64::NEG_INFINITY;
    // A corner of a face: a highest point of its shape along the normal.
    let corner = |t: &Topology, f: u32| t.half_edge(t.face_edges[f as usize]).origin;
    match feature {
        Feature::None => None,
        Feature::Centres { support_a, support_b } if support_a < na && support_b < nb => {
            centre_axis(a, b, rel, Some((support_a, support_b)))
        }
        Feature::FaceA { face, support } if face < fa && support < nb => {
            let q = face_separation(a, b, rel, face, support, exact);
            let on_face = corner(ta, face);
            Some(AxisGap {
                axis: a.plane(face).normal,
                gap: q.separation,
                high_a: a.vertex(on_face),
                low_b: rel.apply(b.vertex(q.support)),
                supports: (on_face, q.support),
            })
        }
        Feature::FaceB { face, support } if face < fb && support < na => {
            let q = face_separation(b, a, &frame_b.relative(frame_a), face, support, exact);
            let on_face = corner(tb, face);
            Some(AxisGap {
                axis: -rel.rotate(b.plane(face).normal),
                gap: q.separation,
                high_a: a.vertex(q.support),
                low_b: rel.apply(b.vertex(on_face)),
                supports: (q.support, on_face),
            })
        }
        Feature::Edges { edge_a, half_edge_b }
            if (edge_a as usize) < ta.edges.len()
                && (half_edge_b as usize) < tb.half_edges.len() =>
        {
            edge_gap(a, b, rel, edge_a, half_edge_b)
        }
        _ => None,
    }
}

/// Whether a cached axis's gap separates `a` and `b` by enough to answer
/// the call alone (see [`MARGIN`]).
pub(crate) fn answers<A: Convex, B: Convex>(a: &A, b: &B, gap: f64) -> bool {
    gap > MARGIN * a.size().max(b.size())
}

/// The gap between `a` and `b` along the common normal of A's edge `edge_a`
/// and B's half-edge `half_edge_b`, oriented out of A as the edge query does,
/// from true support points of both shapes (the pair need no longer be a
/// Minkowski face for the axis to separate them). `None` if the edges are
/// now parallel.
fn edge_gap<A: Convex, B: Convex>(
    a: &A,
    b: &B,
    rel: &Frame,
    edge_a: u32,
    half_edge_b: u32,
) -> Option<AxisGap> {
    let (ta, tb) = (a.topology(), b.topology());
    let h = ta.edges[edge_a as usize];
    let edge = ta.half_edge(h);
    let outward = a.plane(edge.face).normal + a.plane(ta.twin_face(h)).normal;
    let tail = a.vertex(edge.origin);
    let vb = tb.half_edge(half_edge_b).origin;
    let pb = b.vertex(vb);
    let eb = rel.rotate(b.vertex(tb.head(half_edge_b)) - pb);
    let (_, axis) = edge_separation(tail, a.vertex(ta.head(h)) - tail, rel.apply(pb), eb, outward)?;
    Some(axis_gap(a, b, rel, axis, edge.origin, vb))
}
