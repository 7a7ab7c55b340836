//! The per-pair cache of the last call: the gap a pair that was apart had,
//! bounded first from the bodies' motion alone, then the feature that decided
//! the call, re-tested: a pair that was apart along an axis mostly still is.

use bvol_volumes::Pose;
use glam::{DVec3, Quat, Vec3};

use crate::convex::Convex;
use crate::isometry::DIsometry3;
use crate::rest::Rest;
use crate::rounding::{ROUNDING, STORED, down, offset};
use crate::sat::{AxisGap, axis_gap, centre_axis, edge_separation, face_separation};
use crate::topology::Topology;
use crate::{NarrowError, Polyhedron};

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
/// support point of each shape. Otherwise it runs the full query, whose
/// answer does not depend on the cache: the gap along the cached axis and its
/// support points only let it skip faces and edges that cannot be picked,
/// which makes touching pairs cheaper too. So the cache never changes whether
/// a pair is apart or touching, nor (unless it reuses features, below) any
/// contact; only which separating axis a
/// pair that is apart is reported with, and with what lower bound of the gap
/// along it. A cache used with other shapes than it was made with is
/// harmless: the bound is kept with the shapes' ids (a clone shares its
/// original's) and is ignored for others, and features out of range are
/// ignored. Two boxes (see [`Polyhedron::cuboid`](crate::Polyhedron::cuboid))
/// do not re-test the feature: their closed-form test of all 15 axes costs
/// about what the retest does.
///
/// A warm start made with [`WarmStart::reusing`] also reuses a touching
/// pair's contact feature, as the persistent manifolds of Bullet and PhysX
/// do: it keeps, from the last full test of a pair found touching, the
/// greatest separation over all axes (minus the least penetration depth)
/// and the bodies' poses. While no point of either body has moved by more
/// than the tolerance (times the pair's size, the larger shape's half
/// diagonal) in the other's space since, and the pair still overlaps by
/// more than that motion, the call re-measures the feature that decided the
/// last full test (one hill climb for a face, one edge pair) and clips its
/// manifold, searching no other face or edge. Whether the pair touches is
/// then proved from the motion, so it is always a cold call's verdict; the
/// contact is along a feature whose depth is at most `2e-5 + 2 *
/// tolerance` of the size above the least penetration depth (a cold call's
/// is within `2e-5`), the same feature from frame to frame where a cold
/// call may now pick another about as deep. A pair resting in a solver's
/// pile, jittering by a rounding, is tested in full once and then reuses
/// its contact frame after frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WarmStart {
    pub(crate) feature: Feature,
    pub(crate) last: Last,
    /// The reuse tolerance, relative to the pair's size: 0 reuses nothing.
    pub(crate) reuse: f32,
}

/// The largest reuse tolerance [`WarmStart::reusing`] takes: 1% of the
/// size, beyond which a reused contact's depth could be off by several
/// percent of it.
pub const MAX_REUSE: f32 = 1e-2;

impl WarmStart {
    /// A warm start that reuses a touching pair's contact feature while the
    /// pair moves by at most `tolerance` of its size since its last full
    /// test (see [`WarmStart`]); `0` reuses nothing, as
    /// `WarmStart::default()`. A tolerance that is negative, not finite or
    /// above [`MAX_REUSE`] is [`NarrowError::BadTolerance`].
    ///
    /// ```
    /// use bvol_narrow::{Collision, Polyhedron, Pose, WarmStart, hull_hull};
    /// use glam::{Quat, Vec3};
    /// let tile = Polyhedron::cuboid(Vec3::new(2.0, 0.1, 2.0))?;
    /// let cube = Polyhedron::cuboid(Vec3::splat(0.5))?;
    /// let rests = |jitter: f32| Pose::new(Vec3::new(jitter, 0.59, 0.0), Quat::IDENTITY);
    /// let mut warm = WarmStart::reusing(4e-5)?;
    /// for frame in 0..10 {
    ///     // Sunk 0.01 into the tile, jittering by 1e-6.
    ///     let jitter = if frame % 2 == 0 { 1e-6 } else { -1e-6 };
    ///     let hit = hull_hull(&tile, &Pose::IDENTITY, &cube, &rests(jitter), &mut warm)?;
    ///     let contact = hit.contact().expect("resting on the tile");
    ///     assert_eq!(contact.normal, Vec3::Y);
    ///     assert!((contact.depth - 0.01).abs() < 1e-5);
    /// }
    /// assert!(WarmStart::reusing(-1.0).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn reusing(tolerance: f32) -> Result<WarmStart, NarrowError> {
        if !(0.0..=MAX_REUSE).contains(&tolerance) {
            return Err(NarrowError::BadTolerance);
        }
        Ok(WarmStart { reuse: tolerance, ..WarmStart::default() })
    }

    /// The reuse tolerance it was made with (`0` for none).
    pub fn reuse_tolerance(&self) -> f32 {
        self.reuse
    }
}

/// What a warm start knows of the pair's last full test besides its
/// feature.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) enum Last {
    /// Nothing: no test yet, or touching without reuse.
    #[default]
    Nothing,
    /// Apart, by a gap that bounds the next calls' from the motion.
    Apart(Apart),
    /// Touching, reused while the pair barely moves.
    Touching(Rest),
}

/// The last gap measured between a pair that was apart, and where the bodies
/// were then, to bound the gap from the bodies' motion alone: along a fixed
/// axis, a body's lowest point moves no further than its origin did plus the
/// furthest any of its points turned along the axis. The separating distance
/// of Bullet's `btConvexSeparatingDistanceUtil` (Coumans), with the turn
/// bounded along the axis only: a rotation about the axis moves no point
/// along it.
///
/// Stored in f32 (56 bytes: a pair's state is moved every frame): the
/// rotations as given, the gap rounded down, and the axis rounded, which the
/// bound allows for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Apart {
    /// The separating axis in the world, from A to B, unit to f32 rounding.
    pub(crate) axis: Vec3,
    /// A's and B's rotations then, as `[x, y, z, w]` (unaligned, to keep the
    /// state small).
    rotations: [[f32; 4]; 2],
    /// A lower bound of the gap along `axis` then, less `axis . (p_B - p_A)`
    /// for the positions then: adding it for the positions now gives the
    /// gap had the bodies only moved, not turned.
    base: f32,
    /// A's and B's shapes (their ids): the bound holds for these alone.
    shapes: [u32; 2],
}

impl Apart {
    /// The gap `gap` measured along the unit `axis` between shapes `a` and
    /// `b` at these poses.
    pub(crate) fn measured(
        axis: DVec3,
        gap: f64,
        (a, pose_a): (&Polyhedron, &Pose),
        (b, pose_b): (&Polyhedron, &Pose),
    ) -> Apart {
        let kept = axis.as_vec3();
        let n = kept.as_dvec3();
        let offset = offset(pose_a, pose_b);
        // Along the rounded axis (off by at most STORED) the gap is off by
        // at most that times how far apart two points of the shapes can be.
        let apart = offset.abs().element_sum() + a.reach + b.reach;
        let slack = STORED * apart + ROUNDING * gap.abs();
        Apart {
            axis: kept,
            rotations: [pose_a.rotation.to_array(), pose_b.rotation.to_array()],
            base: down(gap - slack - n.dot(offset)),
            shapes: [a.id, b.id],
        }
    }

    /// A lower bound of the gap along [`Apart::axis`] made unit, between
    /// shapes `a` and `b` at these (finite) poses, if it is above `margin`;
    /// `None` for other shapes than measured. Rounding is allowed for: the
    /// f64 sums are off by a few units in the last place of the positions,
    /// the turns by a few of the reach.
    pub(crate) fn gap_above(
        &self,
        (a, pose_a): (&Polyhedron, &Pose),
        (b, pose_b): (&Polyhedron, &Pose),
        margin: f64,
    ) -> Option<f64> {
        if self.shapes != [a.id, b.id] {
            return None;
        }
        let n = self.axis.as_dvec3();
        let offset = offset(pose_a, pose_b);
        let base = f64::from(self.base);
        let rounding = ROUNDING * (base.abs() + offset.abs().max_element() + a.reach + b.reach);
        let moved = base + n.dot(offset) - rounding;
        if moved <= margin {
            return None;
        }
        let turned =
            a.reach * self.turn(0, pose_a.rotation) + b.reach * self.turn(1, pose_b.rotation);
        // The axis is unit to within STORED: along the unit axis the gap is
        // at least this.
        Some((moved - turned) * (1.0 - STORED)).filter(|&gap| gap > margin)
    }

    /// The furthest a point at unit distance from body `k`'s origin can have
    /// moved along the axis `n` as the body turned from its rotation then to
    /// `now` (of any non-zero length). For a turn `T` by angle `t` about the
    /// unit `u` (the unit `now * then^-1` is `(sin(t/2) u, cos(t/2))`), a
    /// point `y` moves by `(T - I) y`, so along `n` by `((T^-1 - I) n) . y`:
    /// at most `|(T^-1 - I) n|`, which is `2 sin(t/2) |n x u|`, for a unit
    /// `y`. That is twice `n` cross the turn's vector part.
    fn turn(&self, k: usize, now: Quat) -> f64 {
        let (then, now) = (Quat::from_array(self.rotations[k]).as_dquat(), now.as_dquat());
        let turn = now * then.conjugate();
        let across = self.axis.as_dvec3().cross(DVec3::new(turn.x, turn.y, turn.z));
        2.0 * (across.length_squared() / (now.length_squared() * then.length_squared())).sqrt()
    }
}

/// The cached feature's axis and the exact gap along it between `a` and `b`
/// (placed by their isometries; `rel` maps B's space into A's), from true
/// support points, with a point of each shape at the gap's ends; `None` if
/// nothing usable is cached. A gap above [`answers`]'s margin settles the
/// call; any gap is a lower bound of the greatest separation over all axes,
/// and its points are witnesses near the contact, which a touching pair's
/// full query may start from.
pub(crate) fn retest<A: Convex, B: Convex>(
    feature: Feature,
    a: &A,
    iso_a: &DIsometry3,
    b: &B,
    iso_b: &DIsometry3,
    rel: &DIsometry3,
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
            let q = face_separation(b, a, &iso_b.relative(iso_a), face, support, exact);
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
    rel: &DIsometry3,
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The bound from motion holds for the shapes it was measured with and
    /// their clones (the same shapes), for no others; with nothing moved it
    /// is the gap measured, less the roundings of storing it.
    #[test]
    fn bound_is_for_the_shapes_measured() {
        let cube = Polyhedron::cuboid(Vec3::splat(0.5)).expect("a box");
        let other = Polyhedron::cuboid(Vec3::splat(0.5)).expect("a box");
        let turn = 0.3f32;
        let (pa, pb) = (Pose::IDENTITY, Pose::new(Vec3::X * 3.0, Quat::from_rotation_y(turn)));
        // B reaches back along x by half its width turned.
        let gap = 3.0 - 0.5 - 0.5 * f64::from(turn.cos() + turn.sin());
        let apart = Apart::measured(DVec3::X, gap, (&cube, &pa), (&cube, &pb));
        let twin = cube.clone();
        let bound = apart.gap_above((&twin, &pa), (&twin, &pb), 0.0).expect("the same shapes");
        assert!(bound <= gap && bound > gap - 1e-6, "{bound} for {gap}");
        assert_eq!(apart.gap_above((&other, &pa), (&cube, &pb), 0.0), None);
        assert_eq!(apart.gap_above((&cube, &pa), (&other, &pb), 0.0), None);
    }
}
