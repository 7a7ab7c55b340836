//! Polyhedron against polyhedron: the separating-axis test with Gauss-map
//! pruning, then the contact of the feature it picks.

use glam::DVec3;

use crate::box_sat::box_queries;
use crate::convex::Convex;
use crate::isometry::DIsometry3;
use crate::manifold::{Manifold, edge_contact, face_contact, vertex_contact};
use crate::rest::Rest;
use crate::sat::{AxisGap, EdgeQuery, FaceQuery, centre_axis, centre_line, edge_query, face_query};
use crate::warm::{Apart, Feature, Last, WarmStart, answers, margin, retest};
use crate::{Body, Collision, NarrowError, Polyhedron, Pose};

/// A face of A is taken as the contact's feature when its separation is
/// within this (relative to the shapes' size) of the least penetration's,
/// else a face of B within it, else the least penetration's own feature,
/// which may be an edge pair. Resting contacts, where a face and an edge (or
/// two faces) are equally deep up to rounding, then keep one manifold from
/// frame to frame instead of flickering between them (Gregorius GDC 2013
/// prefers faces by an absolute tolerance). Not relative to the depth, as
/// Box2D's 0.98 is: that would report depths up to 2% above the least
/// penetration, and the depth must be the least one to within 1e-4 of the
/// shapes' size. A contact's depth is at most this much more than the least.
const PREFER_ABS: f64 = 2e-5;

/// How deep (along the centre line, relative to the shapes' size) a cold
/// pair must overlap for its face queries to take their bounds as bit
/// masks, a run of faces at a time without a branch each, instead of one
/// branch a face. Deep, the bounds are weak and which faces they rule out is
/// unpredictable, so branches mispredict and masks win. Near touching, and
/// on warm calls (whose witnesses lie near the contact), the first bound
/// rules out most faces, the branches are predictable, and masks would do
/// the work of every face for nothing. (The edge query always takes its cap
/// bounds as masks: see `edge_query`.)
const MASK_DEPTH: f64 = 0.25;

/// Whether two convex polyhedra touch, and how.
///
/// The separating-axis test of Gregorius (GDC 2013): the face normals of A,
/// then of B, then the common normals of the edge pairs whose Gauss-map arcs
/// cross (found by walking A's arcs across B's Gauss map), stopping at the
/// first axis that separates them. The line between the shapes' centres goes
/// first: it separates most pairs that are apart, and its support points and
/// gap bound the rest, so that most faces and arcs are skipped unsearched
/// (see the queries). Everything is computed in A's space in f64, with B
/// mapped in by one relative pose, so the decision near touching is exact to
/// f64 rounding of the f32 input.
///
/// Apart: [`Collision::Separated`] with that axis and the gap along it (a
/// lower bound of their distance), or a lower bound of the gap when the warm
/// start answered from the bodies' motion alone. Touching: the axis of least
/// penetration, preferring faces over edges and A's faces over B's within a
/// small tolerance (2e-5 of the shapes' size), so resting contacts do not
/// flicker: the depth is at most that much more than the least penetration.
/// A face contact clips the incident face of the other shape against the
/// reference face (up to 4 points), an edge contact has one point between
/// the edges.
///
/// `warm` carries the deciding feature and the last gap measured from call
/// to call (see [`WarmStart`]); it makes apart pairs cheap and never changes
/// whether a pair touches, nor, unless made with
/// [`WarmStart::reusing`], any contact.
///
/// A pose with a NaN or infinite component (or a zero rotation) is
/// [`NarrowError::NonFinitePose`].
///
/// ```
/// use bvol_narrow::{Collision, Polyhedron, Pose, WarmStart, hull_hull};
/// use glam::{Quat, Vec3};
/// let cube = Polyhedron::cuboid(Vec3::splat(0.5))?;
/// let (a, b) = (Pose::IDENTITY, Pose::new(Vec3::new(0.0, 0.9, 0.0), Quat::IDENTITY));
/// let mut warm = WarmStart::default();
/// let Collision::Touching(contact) = hull_hull(&cube, &a, &cube, &b, &mut warm)? else {
///     panic!("the cubes overlap by 0.1");
/// };
/// assert_eq!(contact.normal, Vec3::Y);
/// assert!((contact.depth - 0.1).abs() < 1e-6);
/// assert_eq!(contact.points().len(), 4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn hull_hull(
    a: &Polyhedron,
    pose_a: &Pose,
    b: &Polyhedron,
    pose_b: &Pose,
    warm: &mut WarmStart,
) -> Result<Collision, NarrowError> {
    DIsometry3::check(pose_a, Body::A)?;
    DIsometry3::check(pose_b, Body::B)?;
    match warm.last {
        Last::Apart(apart) => {
            if let Some(gap) = apart.gap_above((a, pose_a), (b, pose_b), margin(a, b)) {
                return Ok(Collision::separated(apart.axis.as_dvec3(), gap));
            }
        }
        Last::Touching(rest) => {
            if let Some(contact) = reuse((a, pose_a), (b, pose_b), warm, &rest) {
                return Ok(contact);
            }
        }
        Last::Nothing => {}
    }
    let (iso_a, iso_b) = (DIsometry3::of_checked(pose_a), DIsometry3::of_checked(pose_b));
    let answer = collide(a, &iso_a, b, &iso_b, warm);
    warm.last = match answer {
        Answer::Apart { axis, gap } => {
            Last::Apart(Apart::measured(axis, gap, (a, pose_a), (b, pose_b)))
        }
        // The queries can miss the greatest separation by up to the warm
        // start's margin (hill climbs on merged faces): allowed for.
        Answer::Touching { greatest, .. } if warm.reuse > 0.0 => {
            Last::Touching(Rest::measured(greatest + margin(a, b), (a, pose_a), (b, pose_b)))
        }
        Answer::Touching { .. } => Last::Nothing,
    };
    Ok(answer.collision())
}

/// The contact along the feature of the pair's last full test (in `warm`,
/// recorded in `rest`), if the pair moved by at most the warm start's reuse
/// tolerance since and still overlaps by more than it moved (see
/// [`WarmStart`]); `None` sends the call to the full test.
fn reuse(
    (a, pose_a): (&Polyhedron, &Pose),
    (b, pose_b): (&Polyhedron, &Pose),
    warm: &WarmStart,
    rest: &Rest,
) -> Option<Collision> {
    let size = a.size().max(b.size());
    let tolerance = f64::from(warm.reuse) * size;
    let moved = rest.motion((a, pose_a), (b, pose_b)).filter(|&m| m <= tolerance)?;
    // The greatest separation over all axes now is at most this: below
    // zero, the pair still touches.
    let greatest = rest.least() + moved;
    if greatest >= 0.0 {
        return None;
    }
    let (iso_a, iso_b) = (DIsometry3::of_checked(pose_a), DIsometry3::of_checked(pose_b));
    let (rel, inv) = (iso_a.relative(&iso_b), iso_b.relative(&iso_a));
    let pair = Pair { a, iso_a: &iso_a, b, iso_b: &iso_b, rel: &rel, inv: &inv };
    let choice = pair.measure(warm.feature)?;
    // Its depth is at most this above the least penetration depth now.
    let above = greatest - choice.separation();
    let within = choice.separation() <= 0.0 && above <= PREFER_ABS * size + 2.0 * tolerance;
    within.then(|| pair.contact(choice)).flatten()
}

/// A test's answer in f64, before it is rounded for the caller.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Answer {
    /// Apart along `axis` (unit, world space, from A to B) by `gap > 0`.
    Apart {
        /// The separating axis.
        axis: DVec3,
        /// The gap along it.
        gap: f64,
    },
    /// Touching, with the contact and the greatest separation over all
    /// axes (minus the least penetration depth).
    Touching {
        /// The contact.
        collision: Collision,
        /// The greatest separation.
        greatest: f64,
    },
}

impl Answer {
    /// The answer as the caller gets it.
    pub(crate) fn collision(self) -> Collision {
        match self {
            Answer::Apart { axis, gap } => Collision::separated(axis, gap),
            Answer::Touching { collision, .. } => collision,
        }
    }
}

/// [`hull_hull`] for any two convex shapes placed by f64 isometries.
pub(crate) fn collide<A: Convex, B: Convex>(
    a: &A,
    iso_a: &DIsometry3,
    b: &B,
    iso_b: &DIsometry3,
    warm: &mut WarmStart,
) -> Answer {
    // B's space into A's.
    let rel = iso_a.relative(iso_b);
    let (feature, answer) = query(a, iso_a, b, iso_b, &rel, warm.feature);
    warm.feature = feature;
    answer
}

/// The test from the cached feature `cached`: the deciding feature (the
/// cached one again when its axis answers alone) and the answer.
fn query<A: Convex, B: Convex>(
    a: &A,
    iso_a: &DIsometry3,
    b: &B,
    iso_b: &DIsometry3,
    rel: &DIsometry3,
    cached: Feature,
) -> (Feature, Answer) {
    let slack = PREFER_ABS * a.size().max(b.size());
    // Two boxes take closed-form queries of all 15 axes, which cost about
    // what re-testing one cached axis does: they skip the retest, which
    // would only add to the cost of touching pairs.
    if let (Some(box_a), Some(box_b)) = (a.as_box(), b.as_box()) {
        let q = box_queries(box_a, box_b, rel);
        let pair = Pair { a, iso_a, b, iso_b, rel, inv: &iso_b.relative(iso_a) };
        // Apart: along the axis that separates them most.
        let choices = [Choice::FaceA(q.face_a), Choice::FaceB(q.face_b)];
        let apart = choices
            .into_iter()
            .chain(q.edge.map(Choice::Edges))
            .filter(|c| c.separation() > 0.0)
            .max_by(|x, y| x.separation().total_cmp(&y.separation()));
        return match apart {
            Some(choice) => pair.separated(choice),
            None => pair.decide(q.face_a, q.face_b, q.edge, slack),
        };
    }
    let retested = retest(cached, a, iso_a, b, iso_b, rel);
    if let Some(c) = retested.filter(|c| answers(a, b, c.gap)) {
        return (cached, Answer::Apart { axis: iso_a.rotate(c.axis), gap: c.gap });
    }
    full_query(a, iso_a, b, iso_b, rel, retested, slack)
}

/// The full test of two shapes that are not both boxes: the deciding
/// feature and the answer. `cached` is the gap along the cached axis, if
/// any: a lower bound of the greatest separation, and witnesses near the
/// contact, that let the queries skip more, never changing the answer.
fn full_query<A: Convex, B: Convex>(
    a: &A,
    iso_a: &DIsometry3,
    b: &B,
    iso_b: &DIsometry3,
    rel: &DIsometry3,
    cached: Option<AxisGap>,
    slack: f64,
) -> (Feature, Answer) {
    // The line between the centres first: cold, it separates most pairs that
    // are apart, and its support points are the witnesses below. Warm, the
    // cached axis's support points are, and of the centre line only its
    // direction is taken (the face queries start from it as a cold call's
    // do, so that ties between faces are broken alike): its two hill climbs
    // are spared, the cached witnesses lying nearer the contact.
    let centres = match cached {
        None => centre_axis(a, b, rel, None),
        Some(w) => centre_line(a, b, rel).map(|axis| AxisGap { axis, gap: f64::NEG_INFINITY, ..w }),
    };
    if let Some(c) = centres.filter(|c| c.gap > 0.0) {
        let (support_a, support_b) = c.supports;
        let feature = Feature::Centres { support_a, support_b };
        return (feature, Answer::Apart { axis: iso_a.rotate(c.axis), gap: c.gap });
    }
    let inv = &iso_b.relative(iso_a);
    let pair = Pair { a, iso_a, b, iso_b, rel, inv };
    // Touching or close. The greatest separation over the candidate axes is
    // at least the gap along any axis, the centre line's and the cached
    // one's included; the preferences pick a feature at most their slack
    // below the greatest; so features below this floor (a second slack
    // lower, room for the gaps' rounding) can never be picked, and the
    // queries need not find them (the answer is the same as if they did).
    let c = centres.unwrap_or(AxisGap {
        axis: DVec3::Y,
        gap: f64::NEG_INFINITY,
        high_a: a.inner_ball().0,
        low_b: rel.apply(b.inner_ball().0),
        supports: (0, 0),
    });
    // Each face query starts from the face most facing the other shape; the
    // support points along the cached axis, near last call's contact, or
    // else along the centre line, are the witnesses of the bounds.
    let w = cached.unwrap_or(c);
    let floor = c.gap.max(w.gap) - 2.0 * slack;
    // A cold pair sunk deep into each other leaves many faces to the
    // bounds, which rule them out by data the branch predictor has not
    // seen: there the face queries take their bounds as masks (see
    // MASK_DEPTH).
    let masks = cached.is_none() && c.gap < -MASK_DEPTH * a.size().max(b.size());
    let face_a = face_query(a, b, rel, a.face_seed(c.axis), floor, w.low_b, masks);
    if face_a.separation > 0.0 {
        return pair.separated(Choice::FaceA(face_a));
    }
    let first_b = b.face_seed(-rel.unrotate(c.axis));
    let floor_b = floor.max(face_a.separation);
    let face_b = face_query(b, a, inv, first_b, floor_b, inv.apply(w.high_a), masks);
    if face_b.separation > 0.0 {
        return pair.separated(Choice::FaceB(face_b));
    }
    let deepest_face = face_a.separation.max(face_b.separation);
    let edge = edge_query(a, b, rel, floor.max(deepest_face), w.low_b);
    if let Some(e) = edge.filter(|e| e.separation > 0.0) {
        return pair.separated(Choice::Edges(e));
    }
    pair.decide(face_a, face_b, edge, slack)
}

/// A feature whose axis decides the test.
#[derive(Clone, Copy, Debug)]
enum Choice {
    /// A face of A.
    FaceA(FaceQuery),
    /// A face of B.
    FaceB(FaceQuery),
    /// An edge of each.
    Edges(EdgeQuery),
}

impl Choice {
    /// The separation along its axis.
    fn separation(&self) -> f64 {
        match self {
            Choice::FaceA(q) | Choice::FaceB(q) => q.separation,
            Choice::Edges(e) => e.separation,
        }
    }
}

/// Two shapes placed in the world and seen from each other.
struct Pair<'a, A, B> {
    a: &'a A,
    iso_a: &'a DIsometry3,
    b: &'a B,
    iso_b: &'a DIsometry3,
    /// B's space into A's.
    rel: &'a DIsometry3,
    /// A's space into B's.
    inv: &'a DIsometry3,
}

impl<A: Convex, B: Convex> Pair<'_, A, B> {
    /// The touching answer from the queries' best features (none of which
    /// separates the shapes): the preferred feature gives the contact if its
    /// manifold has points; a preferred face may not be the axis of least
    /// penetration, and then its clipped face can lie wholly above the
    /// reference plane. The least penetration's own feature always touches
    /// along its axis.
    fn decide(
        &self,
        face_a: FaceQuery,
        face_b: FaceQuery,
        edge: Option<EdgeQuery>,
        slack: f64,
    ) -> (Feature, Answer) {
        let deepest_face = face_a.separation.max(face_b.separation);
        let least = match edge {
            Some(e) if e.separation > deepest_face => Choice::Edges(e),
            _ if face_b.separation > face_a.separation => Choice::FaceB(face_b),
            _ => Choice::FaceA(face_a),
        };
        // The first of A's face, B's face and the edges within the slack of
        // the least penetration, each measured against the least itself: a
        // chain of preferences (faces over the edge within the slack, A's
        // face over B's within it) let the two slacks add up.
        let within = least.separation() - slack;
        let preferred = if face_a.separation >= within {
            Choice::FaceA(face_a)
        } else if face_b.separation >= within {
            Choice::FaceB(face_b)
        } else {
            least
        };
        let greatest = least.separation();
        self.touching(preferred, greatest)
            .or_else(|| self.touching(least, greatest))
            .unwrap_or_else(|| self.touching_at_support(least, greatest))
    }

    /// The cached feature's query measured again at these poses (see
    /// [`retest`]); `None` for the centre line, nothing cached, a feature
    /// out of range or edges now parallel.
    fn measure(&self, feature: Feature) -> Option<Choice> {
        let g = retest(feature, self.a, self.iso_a, self.b, self.iso_b, self.rel)?;
        match feature {
            Feature::FaceA { face, .. } => {
                Some(Choice::FaceA(FaceQuery { face, separation: g.gap, support: g.supports.1 }))
            }
            Feature::FaceB { face, .. } => {
                Some(Choice::FaceB(FaceQuery { face, separation: g.gap, support: g.supports.0 }))
            }
            Feature::Edges { edge_a, half_edge_b } => Some(Choice::Edges(EdgeQuery {
                edge_a,
                half_edge_b,
                separation: g.gap,
                axis: g.axis,
            })),
            Feature::None | Feature::Centres { .. } => None,
        }
    }

    /// The cache entry of a choice.
    fn feature(&self, choice: Choice) -> Feature {
        match choice {
            Choice::FaceA(q) => Feature::FaceA { face: q.face, support: q.support },
            Choice::FaceB(q) => Feature::FaceB { face: q.face, support: q.support },
            Choice::Edges(e) => Feature::Edges { edge_a: e.edge_a, half_edge_b: e.half_edge_b },
        }
    }

    /// The choice's unit axis in the world, from A to B, and its separation.
    fn axis(&self, choice: Choice) -> (DVec3, f64) {
        match choice {
            Choice::FaceA(q) => (self.iso_a.rotate(self.a.plane(q.face).normal), q.separation),
            // B's outward normal points from B to A.
            Choice::FaceB(q) => (-self.iso_b.rotate(self.b.plane(q.face).normal), q.separation),
            Choice::Edges(e) => (self.iso_a.rotate(e.axis), e.separation),
        }
    }

    /// Apart along the choice's axis.
    fn separated(&self, choice: Choice) -> (Feature, Answer) {
        let (axis, gap) = self.axis(choice);
        (self.feature(choice), Answer::Apart { axis, gap })
    }

    /// Touching along the choice's axis, with its manifold and the greatest
    /// separation; `None` if a face's clipped incident face has no point at
    /// or below the reference plane.
    fn touching(&self, choice: Choice, greatest: f64) -> Option<(Feature, Answer)> {
        let collision = self.contact(choice)?;
        Some((self.feature(choice), Answer::Touching { collision, greatest }))
    }

    /// The contact along the choice's axis, with its manifold; `None` as
    /// for [`Pair::touching`].
    fn contact(&self, choice: Choice) -> Option<Collision> {
        let (manifold, to_world) = self.manifold(choice, false);
        (manifold.count > 0).then(|| self.collision(choice, &manifold, to_world))
    }

    /// Touching along a face's axis at the other shape's lowest vertex: for
    /// when rounding leaves the clipped face of even the least penetration
    /// just above its reference plane.
    fn touching_at_support(&self, choice: Choice, greatest: f64) -> (Feature, Answer) {
        let (manifold, to_world) = self.manifold(choice, true);
        let collision = self.collision(choice, &manifold, to_world);
        (self.feature(choice), Answer::Touching { collision, greatest })
    }

    /// The choice's manifold, in the space that the returned isometry maps to
    /// the world: for a face, the clipped incident face, or (`at_support`) the
    /// other shape's lowest vertex alone; for an edge pair, its one point.
    fn manifold(&self, choice: Choice, at_support: bool) -> (Manifold, &DIsometry3) {
        match choice {
            Choice::FaceA(q) => {
                (face_manifold(self.a, q, self.b, self.rel, at_support), self.iso_a)
            }
            Choice::FaceB(q) => {
                (face_manifold(self.b, q, self.a, self.inv, at_support), self.iso_b)
            }
            Choice::Edges(e) => (self.edge_manifold(e), self.iso_a),
        }
    }

    /// The contact of an edge pair, in A's space.
    fn edge_manifold(&self, e: EdgeQuery) -> Manifold {
        let (ta, tb) = (self.a.topology(), self.b.topology());
        let h = ta.edges[e.edge_a as usize];
        let tail = self.a.vertex(ta.half_edge(h).origin);
        let pb = self.b.vertex(tb.half_edge(e.half_edge_b).origin);
        edge_contact(
            tail,
            self.a.vertex(ta.head(h)) - tail,
            self.rel.apply(pb),
            self.rel.rotate(self.b.vertex(tb.head(e.half_edge_b)) - pb),
            -e.separation,
        )
    }

    /// The touching answer for a choice and its manifold (in the space
    /// `to_world` maps).
    fn collision(&self, choice: Choice, manifold: &Manifold, to_world: &DIsometry3) -> Collision {
        let (normal, separation) = self.axis(choice);
        Collision::touching(normal, -separation, manifold, to_world)
    }
}

/// The manifold of a face query's face of `reference` against `incident`
/// (mapped into the reference's space by `rel`): clipped, or (`at_support`)
/// at the incident shape's lowest vertex alone.
fn face_manifold<R: Convex, I: Convex>(
    reference: &R,
    q: FaceQuery,
    incident: &I,
    rel: &DIsometry3,
    at_support: bool,
) -> Manifold {
    if at_support {
        vertex_contact(reference, q.face, incident, rel, q.support)
    } else {
        face_contact(reference, q.face, incident, rel, q.support)
    }
}

#[cfg(test)]
mod tests {
    use glam::{Quat, Vec3};

    use super::*;

    /// A tile and a cube resting on it, 0.01 deep; the cube jittered by
    /// `dx` along x and lifted by `up`.
    fn resting(up: f32, dx: f32) -> (Polyhedron, Polyhedron, Pose) {
        let tile = Polyhedron::cuboid(Vec3::new(2.0, 0.1, 2.0)).expect("a box");
        let cube = Polyhedron::cuboid(Vec3::splat(0.5)).expect("a box");
        (tile, cube, Pose::new(Vec3::new(dx, 0.59 + up, 0.0), Quat::IDENTITY))
    }

    /// What the reuse answers for the cube at `pose` from the record of the
    /// full test in `warm`.
    fn reused(
        tile: &Polyhedron,
        cube: &Polyhedron,
        pose: &Pose,
        warm: &WarmStart,
    ) -> Option<Collision> {
        let Last::Touching(rest) = warm.last else { panic!("no record: {:?}", warm.last) };
        reuse((tile, &Pose::IDENTITY), (cube, pose), warm, &rest)
    }

    /// A reusing warm start keeps a touching pair's record; the pair jittered
    /// by a little is answered from it, with the full test's contact there;
    /// moved past the tolerance, or overlapping by less than it moved, it is
    /// sent to the full test. A default warm start keeps no record.
    #[test]
    fn reuse_answers_while_the_pair_barely_moves() {
        let (tile, cube, pose) = resting(0.0, 0.0);
        let mut plain = WarmStart::default();
        hull_hull(&tile, &Pose::IDENTITY, &cube, &pose, &mut plain).expect("finite");
        assert_eq!(plain.last, Last::Nothing);
        let mut warm = WarmStart::reusing(4e-5).expect("a tolerance");
        let first = hull_hull(&tile, &Pose::IDENTITY, &cube, &pose, &mut warm).expect("finite");
        assert!(first.is_touching());
        // 4e-5 of the tile's half diagonal (2.83) is 1.1e-4.
        let (_, _, jittered) = resting(0.0, 1e-6);
        let cold = hull_hull(&tile, &Pose::IDENTITY, &cube, &jittered, &mut WarmStart::default());
        let got = reused(&tile, &cube, &jittered, &warm).expect("reused");
        assert_eq!(Ok(got), cold);
        let (_, _, moved) = resting(0.0, 2e-4);
        assert_eq!(reused(&tile, &cube, &moved, &warm), None);
        // Just touching (1e-6 deep), then jittered by more than that.
        let (_, _, grazing) = resting(0.01 - 1e-6, 0.0);
        hull_hull(&tile, &Pose::IDENTITY, &cube, &grazing, &mut warm).expect("finite");
        let (_, _, off) = resting(0.01 - 1e-6, 1e-5);
        assert_eq!(reused(&tile, &cube, &off, &warm), None);
    }
}
