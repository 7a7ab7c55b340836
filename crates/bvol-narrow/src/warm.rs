//! The per-pair cache of the feature that decided the last call, re-tested
//! first on the next: a pair that was apart along an axis mostly still is.

use bvol_volumes::Pose;
use glam::{DVec3, Quat};

use crate::Polyhedron;
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
/// found along it; and, for a pair found apart, the gap measured then, its
/// axis in the world and the bodies' rotations. Keep one per pair, starting
/// from `WarmStart::default()`.
///
/// A pair found apart is first bounded from the bodies' motion alone: the
/// gap measured, less how far the bodies' origins came together along its
/// axis, less how far their farthest vertices from their origins can have
/// turned along it. While that stays above a margin, the call answers
/// [`Separated`](crate::Collision::Separated) along the same axis, with that
/// bound as the distance, reading nothing of the shapes: no rotation matrix,
/// no support point. Slowly moving pairs that are apart mostly end there.
/// Otherwise the call re-tests the cached feature's axis: if it still
/// separates the pair, by the margin, the call answers at once, after one
/// support point of each shape. Otherwise it runs the full query,
/// whose answer does not depend on the cache: the gap along the cached axis
/// and its support points only let it skip faces and edges that cannot be
/// picked, which makes touching pairs cheaper too. So the cache never changes
/// whether a pair is apart or touching, nor any contact; only which separating
/// axis a pair that is apart is reported with, and with what lower bound of
/// the gap along it. A cache from another pair of
/// shapes is harmless: features out of range are ignored. Two boxes (see
/// [`Polyhedron::cuboid`](crate::Polyhedron::cuboid)) do not re-test the
/// feature: their closed-form test of all 15 axes costs about what the retest
/// does.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WarmStart {
    pub(crate) feature: Feature,
    pub(crate) apart: Apart,
}

/// The last gap measured between a pair that was apart, and where the bodies
/// were then, to bound the gap from the bodies' motion alone: along a fixed
/// axis, a body's lowest point moves no further than its origin did plus the
/// furthest any of its points turned along the axis. The separating distance
/// of Bullet's `btConvexSeparatingDistanceUtil` (Coumans), with the turn
/// bounded along the axis only: a rotation about the axis moves no point
/// along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Apart {
    /// The separating axis, unit, in the world, from A to B.
    pub(crate) axis: DVec3,
    /// The gap measured along `axis`, less `axis . (p_B - p_A)` for the
    /// positions then: adding it for the positions now gives the gap had the
    /// bodies only moved, not turned. `-inf` when nothing is measured.
    base: f64,
    /// A's and B's rotations then.
    rotations: [Quat; 2],
    /// A's and B's shapes (their ids): the bound holds for these alone.
    shapes: [u64; 2],
}

impl Default for Apart {
    fn default() -> Self {
        Apart::NONE
    }
}

impl Apart {
    /// Nothing measured: bounds no gap.
    pub(crate) const NONE: Apart = Apart {
        axis: DVec3::ZERO,
        base: f64::NEG_INFINITY,
        rotations: [Quat::IDENTITY; 2],
        shapes: [u64::MAX; 2],
    };

    /// The gap `gap` measured along `axis` between shapes `a` and `b` at these poses.
    pub(crate) fn measured(
        axis: DVec3,
        gap: f64,
        (a, pose_a): (&Polyhedron, &Pose),
        (b, pose_b): (&Polyhedron, &Pose),
    ) -> Apart {
        let offset = offset(pose_a, pose_b);
        // Rounded down by as much as the sum may have rounded up.
        let rounding = ROUNDING * (gap.abs() + offset.abs().max_element());
        let base = gap - axis.dot(offset) - rounding;
        Apart { axis, base, rotations: [pose_a.rotation, pose_b.rotation], shapes: [a.id, b.id] }
    }

    /// A lower bound of the gap along [`Apart::axis`] between shapes `a` and
    /// `b` at these (finite) poses, if it is above `margin`; `None` for other
    /// shapes than measured. Rounding is allowed for: the f64 sums are off by
    /// a few units in the last place of the positions, the turns by a few of
    /// the reach.
    pub(crate) fn gap_above(
        &self,
        (a, pose_a): (&Polyhedron, &Pose),
        (b, pose_b): (&Polyhedron, &Pose),
        margin: f64,
    ) -> Option<f64> {
        if self.shapes != [a.id, b.id] {
            return None;
        }
        let reach = (a.reach, b.reach);
        let offset = offset(pose_a, pose_b);
        let rounding =
            ROUNDING * (self.base.abs() + offset.abs().max_element() + reach.0 + reach.1);
        // -inf when nothing was measured.
        let moved = self.base + self.axis.dot(offset) - rounding;
        if moved <= margin {
            return None;
        }
        let turned =
            reach.0 * self.turn(0, pose_a.rotation) + reach.1 * self.turn(1, pose_b.rotation);
        Some(moved - turned).filter(|&gap| gap > margin)
    }
}

/// Relative rounding allowed for in [`Apart`]'s f64 sums.
const ROUNDING: f64 = 16.0 * f64::EPSILON;

/// B's position less A's, in f64 (exact from f32).
fn offset(pose_a: &Pose, pose_b: &Pose) -> DVec3 {
    pose_b.position.as_dvec3() - pose_a.position.as_dvec3()
}

impl Apart {
    /// The furthest a point at unit distance from body `k`'s origin can have
    /// moved along the axis as the body turned from its rotation then to
    /// `now` (of any non-zero length). For a turn `T` by angle `t` about the
    /// unit `u` (the unit `now * then^-1` is `(sin(t/2) u, cos(t/2))`), a
    /// point `y` moves by `(T - I) y`, so along `n` by `((T^-1 - I) n) . y`:
    /// at most `|(T^-1 - I) n|`, which is `2 sin(t/2) |n x u|`, for a unit
    /// `y`. That is twice `n` cross the turn's vector part.
    fn turn(&self, k: usize, now: Quat) -> f64 {
        let (then, now) = (self.rotations[k].as_dquat(), now.as_dquat());
        let turn = now * then.conjugate();
        let across = self.axis.cross(DVec3::new(turn.x, turn.y, turn.z)).length_squared();
        2.0 * (across / (now.length_squared() * then.length_squared())).sqrt()
    }
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
/// the call alone: above [`margin`].
pub(crate) fn answers<A: Convex, B: Convex>(a: &A, b: &B, gap: f64) -> bool {
    gap > margin(a, b)
}

/// The gap that a cached axis must beat to answer alone (see [`MARGIN`]).
pub(crate) fn margin<A: Convex, B: Convex>(a: &A, b: &B) -> f64 {
    MARGIN * a.size().max(b.size())
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
