//! The separating-axis queries between two convex polyhedra (Gregorius, "The
//! Separating Axis Test between Convex Polyhedra", GDC 2013): the face axes of
//! each, and the edge-pair axes that are faces of their Minkowski difference.
//!
//! Everything runs in the space of the first shape, in f64, with the second
//! mapped in by one relative isometry: only the few directions and points that a
//! query touches are mapped, never the whole shape.

use glam::DVec3;

use crate::convex::Convex;
use crate::isometry::DIsometry3;
use crate::lanes::{Witness, runs, set_bits};
use crate::plane::Plane;

/// Edge pairs whose directions are closer to parallel than this sine of their
/// angle are skipped: their cross product is too short to be a direction, and
/// their Minkowski face is a sliver between face normals that the face queries
/// test. In f64 the cross product of edges from f32 points is good to about
/// 1e-16 of `|e1| |e2|`, so at 1e-8 its direction is good to 1e-8 radians, and
/// a skipped pair's axis lies within 1e-8 radians of a tested one: either way
/// the separation is off by at most about 1e-8 of the shapes' size.
pub(crate) const PARALLEL_SINE: f64 = 1e-8;

/// The common normal of an edge pair that the walk finds must lie on A's arc
/// (in its cap, whose cosine may fall short by this much to rounding), else
/// the pair is skipped. For edges close to parallel (yet above
/// [`PARALLEL_SINE`]) the arcs run along each other, rounding decides where
/// they cross, and the normal, set by the small angle between the edges, can
/// lie far off A's arc: the separation along it then says nothing (it can
/// call a teapot's hull apart from a box sunk into it); the sliver between
/// such arcs is the face queries'.
const ARC_SLACK: f64 = 1e-9;

/// An edge pair found by the walk is taken only if its edges are their
/// shapes' support points along its normal: if the gap measured from the
/// true support points falls short of the edges' own separation by more than
/// this (relative to the shapes' size), the walk crossed there by rounding
/// (edges near parallel, faces near coplanar) and the pair is skipped; its
/// sliver is the face queries'.
const SUPPORT_SLACK: f64 = 1e-6;

/// A face of the reference shape and how far the other shape is above it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FaceQuery {
    /// The face.
    pub face: u32,
    /// Least signed distance of the other shape's vertices above its plane:
    /// positive means this face's normal separates them.
    pub separation: f64,
    /// The other shape's vertex at that distance (its support point against the normal).
    pub support: u32,
}

/// An edge of A, an edge of B, and the separation along their common normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct EdgeQuery {
    /// Index into A's edge list.
    pub edge_a: u32,
    /// The half-edge of B.
    pub half_edge_b: u32,
    /// The gap between the shapes along `axis`, from their support points:
    /// the signed distance of B's edge beyond A's.
    pub separation: f64,
    /// Unit axis in A's space, pointing out of A (from A to B).
    pub axis: DVec3,
}

/// The separation of `other` above face `f` of `reference`, `rel` mapping
/// `other`'s space into `reference`'s: the least `n . x - offset` over the other
/// shape's vertices `x`, found by hill climbing from vertex `start`. The
/// search stops once the separation is known to be at most `bar` (`-inf` for
/// none), and then reports at most `bar`, not the least.
pub(crate) fn face_separation<R: Convex, O: Convex>(
    reference: &R,
    other: &O,
    rel: &DIsometry3,
    f: u32,
    start: u32,
    bar: f64,
) -> FaceQuery {
    let plane = reference.plane(f);
    // n . (R x + t) = (R^T n) . x + n . t: one direction mapped, not the vertices.
    let shift = plane.normal.dot(rel.translation) - plane.offset;
    let limit = bar - shift;
    let (support, low) = other.support_min(rel.unrotate(plane.normal), start, limit);
    let separation = low + shift;
    // Stopped early, the rounding of `limit` must not let the bound pass the bar.
    let separation = if low <= limit { separation.min(bar) } else { separation };
    FaceQuery { face: f, separation, support }
}

/// The face of `reference` whose normal separates the shapes most, stopping
/// at the first that separates them (Gregorius's face query); faces that
/// cannot beat `floor` need not be found: if none can, the answer is face
/// `first`, which is always searched, first.
///
/// Most faces are skipped unseen, by two bounds on the other shape's
/// separation above a face's plane: it holds a ball about a centre `c`, so the
/// separation is at most the plane's distance to `c` less the radius; and it
/// holds the point `witness` (in the reference's space), so at most that
/// point's distance, which is close for faces facing the witness. A cluster
/// of faces is skipped at once when the same bounds fail for its cap (a
/// plane's distance to `p` is `n . (p - c_R)` less the depth of the
/// reference's inner centre `c_R` behind it). Only faces whose bounds beat
/// the best so far (and the floor) are searched, each from the previous
/// one's support point, and a search stops at the first vertex of the other
/// shape low enough to show that its face cannot beat them. Most would stop
/// at that first vertex, so its distance is a face's first bound, tested
/// before the witness's and the ball's and before the search is set up.
///
/// With `masks` (a cold pair sunk deep: the bounds are weak, and which faces
/// they rule out is new to the branch predictor; see `MASK_DEPTH` in
/// `hull_hull.rs`) the query takes the three bounds of a run of up to 64 faces
/// without a branch, as a bit mask of the faces left, then searches those;
/// else it tests each face's bounds in turn, which costs less when most
/// faces fall to the first. Either way a face that can beat
/// the bar is never ruled out, and faces are taken in the same order, so
/// the best face is the same (a mask can rule out a face that a later start
/// point would not have, whose search would only have moved that point).
pub(crate) fn face_query<R: Convex, O: Convex>(
    reference: &R,
    other: &O,
    rel: &DIsometry3,
    first: u32,
    floor: f64,
    witness: DVec3,
    masks: bool,
) -> FaceQuery {
    let (centre, radius) = other.inner_ball();
    let centre = rel.apply(centre);
    let inner = reference.inner_ball().0;
    let (ball, witnessed) = (centre - inner, witness - inner);
    let (ball_length, witnessed_length) = (ball.length(), witnessed.length());
    let dir = rel.unrotate(reference.plane(first).normal);
    let best = face_separation(reference, other, rel, first, other.seed(dir), f64::NEG_INFINITY);
    // That vertex in the reference's space: a point of the other shape too,
    // so its distance bounds a face's separation as the witness's does. A
    // face's search starts there and stops at once when that bound holds,
    // as most do; testing it here first spares the search's setup.
    let start_point = rel.apply(other.vertex(best.support));
    let mut search = FaceSearch { best, start: best.support, start_point, floor };
    let witnesses = [
        Witness { at: witnessed, length: witnessed_length, less: 0.0 },
        Witness { at: ball, length: ball_length, less: radius },
    ];
    if masks {
        // Sunk deep, the cluster bounds rule out few faces and mispredict:
        // every face's three bounds are taken on lanes, a run at a time.
        for run in runs(0..reference.topology().face_count() as u32) {
            if search.best.separation > 0.0 {
                break;
            }
            let start = search.start_point - inner;
            let starts = Witness { at: start, length: start.length(), less: 0.0 };
            let bounds = [starts, witnesses[0], witnesses[1]];
            let searched = if run.contains(&first) { 1 << (first - run.start) } else { 0 };
            let live = reference.faces_left(run.clone(), &bounds, search.bar()) & !searched;
            for f in set_bits(run.start, live) {
                // The bar may have risen and the start point moved since
                // the mask let the face through.
                let bar = search.bar();
                if search.best.separation <= 0.0
                    && reference.plane(f).distance(search.start_point) > bar
                {
                    search.face(reference, other, rel, f, bar);
                }
            }
        }
        return search.best;
    }
    let ball_bound = |plane: Plane| plane.distance(centre) - radius;
    for cluster in reference.face_clusters() {
        let bar = search.bar();
        if cluster.is_group()
            && (search.best.separation > 0.0
                || witnesses.iter().any(|w| w.bound(&cluster.cap, cluster.inner) <= bar))
        {
            continue;
        }
        // Warm or near touching, most faces fall to the first bound:
        // each face's bounds are tested in turn, cheapest first.
        for f in cluster.members {
            let bar = search.bar();
            let plane = reference.plane(f);
            if f != first
                && search.best.separation <= 0.0
                && plane.distance(search.start_point) > bar
                && plane.distance(witness) > bar
                && ball_bound(plane) > bar
            {
                search.face(reference, other, rel, f, bar);
            }
        }
    }
    search.best
}

/// A face query's state: the best face so far, and the other shape's vertex
/// the next face's search starts from, with that point in the reference's
/// space.
struct FaceSearch {
    best: FaceQuery,
    start: u32,
    start_point: DVec3,
    floor: f64,
}

impl FaceSearch {
    /// The bar a face must beat: the best so far, and the floor.
    fn bar(&self) -> f64 {
        self.best.separation.max(self.floor)
    }

    /// Searches face `f`, which its bounds have not ruled out, and keeps it
    /// if it beats `bar` (the current [`FaceSearch::bar`]).
    fn face<R: Convex, O: Convex>(
        &mut self,
        reference: &R,
        other: &O,
        rel: &DIsometry3,
        f: u32,
        bar: f64,
    ) {
        // Only a face beating the bar is searched to the end.
        let q = face_separation(reference, other, rel, f, self.start, bar);
        if q.support != self.start {
            self.start = q.support;
            self.start_point = rel.apply(other.vertex(q.support));
        }
        if q.separation > bar {
            self.best = q;
        }
    }
}

/// The edge pair of A and B with the greatest separation among those whose
/// Gauss-map arcs cross (the Minkowski faces), stopping at the first that
/// separates them; pairs that cannot beat `floor` need not be found. `None`
/// when no pair was found (no arcs cross, all crossing pairs are parallel, or
/// none can beat the floor).
///
/// Gregorius tests every pair with his IsMinkowskiFace triple products; that
/// is `E_A * E_B` tests, a third of a million for hulls of 200 vertices. This
/// walks instead: each arc of A, from one face normal `n1` to the other `n2`,
/// is followed across B's negated Gauss map, whose regions are B's vertices
/// (the region of `v` holds the directions `d` in which `v` is B's lowest
/// vertex, the least `d . v`). The walk starts in the region of B's support
/// point against `n1`; leaving a region through the boundary between `v` and
/// its neighbour `w` is crossing B's arc of edge `vw`, a Minkowski face.
/// Regions are convex and an arc is shorter than a half circle, so the walk
/// meets each region at most once: the work is the number of crossings, about
/// `E_A + E_B` in all, plus one step per edge of A.
///
/// Most arcs of A are skipped unwalked. Along any direction `d` of A's arc the
/// separation is `d . (B's lowest point) - d . (A's edge)`, and B's lowest
/// point is at most B's inner centre less its radius; so an arc can only beat
/// the bar if `d . (c_B - edge) - r_B` can, somewhere on it, and (B's lowest
/// point being at most as low as any of its points) if `d . (witness - edge)`
/// can, for a point `witness` of B in A's space ([`Arc::max`]). Cheaper bounds
/// go first: A's inner centre `c_A` is at least [`Arc::inner`] behind the edge
/// along the arc, and the arc lies in its cap, so `cap max of (c_B - c_A) -
/// inner - r_B` and `cap max of (witness - c_A) - inner` bound it too; and the
/// same with a cluster's cap and depth bound a whole cluster of arcs. Within a
/// cluster that its bounds leave, the two cap bounds are taken for a run of up
/// to 64 arcs at a time on f32 lanes, without a branch, as a bit mask of the
/// arcs left: which arcs they rule out changes from pair to pair, so a branch
/// an arc mispredicts, near touching as much as deep (unlike the face query's
/// first bound, the start point's distance, which rules out most faces of a
/// pair near touching). Of the arc's own bounds, the last arc's support point,
/// a point of B low along the arcs near that one, goes first: arcs are ordered
/// so that consecutive ones point alike, so it rules out most arcs before any
/// climb, and at the cost of one dot product. Last, before any step is walked,
/// B's support point against `n1`, where the walk starts, is a witness exact at
/// one end of the arc.
///
/// [`Arc::max`]: crate::arc::Arc::max
/// [`Arc::inner`]: crate::arc::Arc::inner
pub(crate) fn edge_query<A: Convex, B: Convex>(
    a: &A,
    b: &B,
    rel: &DIsometry3,
    floor: f64,
    witness: DVec3,
) -> Option<EdgeQuery> {
    let (ta, tb) = (a.topology(), b.topology());
    let centre_a = a.inner_ball().0;
    let (centre_b, radius_b) = b.inner_ball();
    let centre_b = rel.apply(centre_b);
    let (ball, witnessed) = (centre_b - centre_a, witness - centre_a);
    let (ball_length, witnessed_length) = (ball.length(), witnessed.length());
    let witnesses = [
        Witness { at: witnessed, length: witnessed_length, less: 0.0 },
        Witness { at: ball, length: ball_length, less: radius_b },
    ];
    let mut best: Option<EdgeQuery> = None;
    // B's support point against the last arc's start, and the point in A's space.
    let mut start: Option<(u32, DVec3)> = None;
    let slack = SUPPORT_SLACK * a.size().max(b.size());
    // The bar a pair must beat: the best so far, and the floor.
    let bar_of = |best: Option<EdgeQuery>| best.map_or(floor, |q| q.separation.max(floor));
    // One arc of A past its cap bounds: its own bounds, then the walk.
    // True when a separating pair was found (the query stops there).
    let arc_step = |e: u32, best: &mut Option<EdgeQuery>, start: &mut Option<(u32, DVec3)>| {
        let bar = bar_of(*best);
        let arc = a.arc(e);
        let h = ta.edges[e as usize];
        let tail = a.vertex(ta.half_edge(h).origin);
        // The last arc's support point is a point of B too, and low
        // along the arcs near that arc: it often rules this one out
        // before any climb.
        if start.is_some_and(|(_, p)| arc.max(p - tail) <= bar) {
            return false;
        }
        if arc.max(witness - tail) <= bar || arc.max(centre_b - tail) - radius_b <= bar {
            return false;
        }
        // The arc d(t) = (1 - t) n1 + t n2, seen from B's space; its walk
        // starts at B's support point against n1, climbed from the last.
        let (n1, n2) = arc.ends;
        let (d1, d2) = (rel.unrotate(n1), rel.unrotate(n2));
        let from = start.map_or_else(|| b.seed(d1), |(v, _)| v);
        let v0 = b.support_min(d1, from, f64::NEG_INFINITY).0;
        // That support point is a point of B, exact at the arc's start: a
        // tighter witness than the centre line's, before any step is
        // walked. A climb that stayed put is at the point tried above.
        if start.is_none_or(|(v, _)| v != v0) {
            let p0 = rel.apply(b.vertex(v0));
            *start = Some((v0, p0));
            if arc.max(p0 - tail) <= bar {
                return false;
            }
        }
        let dir_a = a.vertex(ta.head(h)) - tail;
        let (mut v, mut t) = (v0, 0.0);
        for _ in 0..tb.vertex_count() {
            let Some((exit_t, hb, w)) = region_exit(b, v, d1, d2, t) else { break };
            let (pb, eb) = (rel.apply(b.vertex(v)), rel.rotate(b.vertex(w) - b.vertex(v)));
            // Only a pair that can beat the bar (the best so far, and
            // the floor) is measured again from support points (two hill
            // climbs): a pair below the floor is never picked, so none is
            // kept.
            let bar = bar_of(*best);
            let beats = |s: f64| s > bar;
            let found = edge_separation(tail, dir_a, pb, eb, n1 + n2)
                .filter(|&(s, axis)| {
                    axis.dot(arc.cap.axis) >= arc.cap.cos - ARC_SLACK && beats(s + slack)
                })
                // A new best is measured again from both shapes' true
                // support points: the edges are those only if the
                // walk was exact, which rounding can spoil for edges
                // near parallel or faces near coplanar.
                .and_then(|(s, axis)| {
                    let gap = axis_gap(a, b, rel, axis, ta.half_edge(h).origin, v).gap;
                    (gap >= s - slack).then_some((gap, axis))
                });
            if let Some((separation, axis)) = found
                && beats(separation)
            {
                *best = Some(EdgeQuery { edge_a: e, half_edge_b: hb, separation, axis });
                if separation > 0.0 {
                    return true;
                }
            }
            (v, t) = (w, exit_t);
        }
        false
    };
    for cluster in a.edge_clusters() {
        let bar = bar_of(best);
        if cluster.is_group()
            && witnesses.iter().any(|w| w.bound(&cluster.cap, cluster.inner) <= bar)
        {
            continue;
        }
        for run in runs(cluster.members) {
            let live = a.arcs_left(run.clone(), &witnesses, bar_of(best));
            for e in set_bits(run.start, live) {
                if arc_step(e, &mut best, &mut start) {
                    return best;
                }
            }
        }
    }
    best
}

/// Where the arc `d(t) = (1 - t) d1 + t d2`, from `t` on, leaves the region of
/// B's vertex `v`: the least `t' >= t` at which a neighbour `w` becomes lower
/// (`d(t') . (w - v) < 0` after it), with the half-edge `v -> w` and `w`;
/// `None` if `v` stays lowest to the end. `d . (w - v)` is linear in `t`,
/// from `alpha` at 0 to `beta` at 1; a neighbour already lower at `t`
/// (rounding) is left at once.
fn region_exit<B: Convex>(b: &B, v: u32, d1: DVec3, d2: DVec3, t: f64) -> Option<(f64, u32, u32)> {
    let topology = b.topology();
    let x = b.vertex(v);
    let mut exit: Option<(f64, u32, u32)> = None;
    for (&h, &w) in topology.outgoing(v).iter().zip(topology.neighbours(v)) {
        let step = b.vertex(w) - x;
        let beta = d2.dot(step);
        if beta >= 0.0 {
            continue;
        }
        let alpha = d1.dot(step);
        let at = if alpha > 0.0 { (alpha / (alpha - beta)).max(t) } else { t };
        if exit.is_none_or(|(best, _, _)| at < best) {
            exit = Some((at, h, w));
        }
    }
    exit
}

/// The gap between two shapes along an axis, from their support points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct AxisGap {
    /// Unit axis in A's space, from A to B.
    pub axis: DVec3,
    /// `min over B - max over A` along the axis: positive when it separates them.
    pub gap: f64,
    /// A's highest vertex along the axis, in A's space.
    pub high_a: DVec3,
    /// B's lowest vertex along the axis, in A's space.
    pub low_b: DVec3,
    /// The indices of those two vertices.
    pub supports: (u32, u32),
}

/// The gap between `a` and `b` (B mapped into A's space by `rel`) along the
/// unit `axis` (in A's space, from A to B), from their support points, hill
/// climbing from `start_a` and `start_b`.
pub(crate) fn axis_gap<A: Convex, B: Convex>(
    a: &A,
    b: &B,
    rel: &DIsometry3,
    axis: DVec3,
    start_a: u32,
    start_b: u32,
) -> AxisGap {
    let (va, low_a) = a.support_min(-axis, start_a, f64::NEG_INFINITY);
    let (vb, low_b) = b.support_min(rel.unrotate(axis), start_b, f64::NEG_INFINITY);
    let gap = low_b + axis.dot(rel.translation) + low_a;
    AxisGap { axis, gap, high_a: a.vertex(va), low_b: rel.apply(b.vertex(vb)), supports: (va, vb) }
}

/// The line from A's inner centre to B's as an axis, with the gap along it:
/// a cheap first guess that separates most pairs that are apart, and whose
/// support points bound the separations of the faces and edges facing
/// along it. Hill climbing starts from `starts` (A's, B's), or from seeds.
/// `None` for concentric shapes.
pub(crate) fn centre_axis<A: Convex, B: Convex>(
    a: &A,
    b: &B,
    rel: &DIsometry3,
    starts: Option<(u32, u32)>,
) -> Option<AxisGap> {
    let axis = centre_line(a, b, rel)?;
    let (start_a, start_b) = starts.unwrap_or_else(|| (a.seed(-axis), b.seed(rel.unrotate(axis))));
    Some(axis_gap(a, b, rel, axis, start_a, start_b))
}

/// The unit direction from A's inner centre to B's, in A's space; `None`
/// for concentric shapes.
pub(crate) fn centre_line<A: Convex, B: Convex>(a: &A, b: &B, rel: &DIsometry3) -> Option<DVec3> {
    (rel.apply(b.inner_ball().0) - a.inner_ball().0).try_normalize()
}

/// The separation of edge `(pb, pb + eb)` beyond edge `(pa, pa + ea)` along
/// their common normal, oriented along `outward` (a direction out of A at its
/// edge, the sum of its two face normals), with that unit axis; `None` for
/// edges closer to parallel than [`PARALLEL_SINE`]. Exact for edges on a
/// Minkowski face, where both edges are their shapes' support points along the axis.
pub(crate) fn edge_separation(
    pa: DVec3,
    ea: DVec3,
    pb: DVec3,
    eb: DVec3,
    outward: DVec3,
) -> Option<(f64, DVec3)> {
    let cross = ea.cross(eb);
    let len2 = cross.length_squared();
    let limit = PARALLEL_SINE * PARALLEL_SINE * ea.length_squared() * eb.length_squared();
    if len2 <= limit {
        return None;
    }
    let axis = cross / len2.sqrt();
    let axis = if axis.dot(outward) < 0.0 { -axis } else { axis };
    Some((axis.dot(pb - pa), axis))
}

#[cfg(test)]
pub(crate) mod tests {
    use glam::{DMat3, DQuat, Vec3};

    use super::*;
    use crate::Polyhedron;

    /// Gregorius's IsMinkowskiFace: whether the arc `a`-`b` and the arc
    /// `c`-`d` (B's normals already negated) cross, by triple products.
    fn is_minkowski_face(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> bool {
        let (bxa, dxc) = (b.cross(a), d.cross(c));
        let (cba, dba, adc, bdc) = (c.dot(bxa), d.dot(bxa), a.dot(dxc), b.dot(dxc));
        cba * dba < 0.0 && adc * bdc < 0.0 && cba * bdc > 0.0
    }

    /// Every pair of edges tested with IsMinkowskiFace, as Gregorius does: the
    /// greatest separation among the crossing pairs.
    fn brute_force_edge_query(a: &Polyhedron, b: &Polyhedron, rel: &DIsometry3) -> Option<f64> {
        let (ta, tb) = (a.topology(), b.topology());
        let mut best: Option<f64> = None;
        for &ha in &ta.edges {
            let ea = ta.half_edge(ha);
            let (n1, n2) = (a.plane(ea.face).normal, a.plane(ta.twin_face(ha)).normal);
            let pa = a.vertex(ea.origin);
            for &hb in &tb.edges {
                let eb = tb.half_edge(hb);
                let m1 = -rel.rotate(b.plane(eb.face).normal);
                let m2 = -rel.rotate(b.plane(tb.twin_face(hb)).normal);
                if !is_minkowski_face(n1, n2, m1, m2) {
                    continue;
                }
                let pb = b.vertex(eb.origin);
                let dir_b = rel.rotate(b.vertex(tb.head(hb)) - pb);
                let dir_a = a.vertex(ta.head(ha)) - pa;
                if let Some((s, _)) = edge_separation(pa, dir_a, rel.apply(pb), dir_b, n1 + n2) {
                    best = Some(best.map_or(s, |x: f64| x.max(s)));
                }
            }
        }
        best
    }

    /// A small deterministic generator (SplitMix64) for the unit tests.
    pub(crate) fn next(state: &mut u64) -> f64 {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn cloud(state: &mut u64, n: usize) -> Polyhedron {
        let points: Vec<Vec3> = (0..n)
            .map(|_| {
                let v = DVec3::new(next(state), next(state), next(state)) * 2.0 - 1.0;
                v.normalize_or_zero().as_vec3() * (0.5 + next(state) as f32 * 0.5)
            })
            .collect();
        Polyhedron::from_points(&points).expect("a solid cloud")
    }

    /// A random turn, and a shift of up to `reach` / 2 on each axis.
    fn random_isometry(state: &mut u64, reach: f64) -> DIsometry3 {
        let q = DQuat::from_xyzw(next(state), next(state), next(state), next(state))
            - DQuat::from_xyzw(0.5, 0.5, 0.5, 0.5);
        let shift = DVec3::new(next(state), next(state), next(state)) - 0.5;
        DIsometry3 { rotation: DMat3::from_quat(q.normalize()), translation: shift * reach }
    }

    /// The Gauss-map walk finds the same greatest edge separation as testing
    /// every pair with IsMinkowskiFace, on overlapping random hulls (where no
    /// early exit cuts either short).
    #[test]
    fn edge_walk_matches_every_pair_tested() {
        let mut state = 42;
        let mut compared = 0;
        for case in 0..400 {
            let (a, b) = (cloud(&mut state, 4 + case % 40), cloud(&mut state, 4 + case % 23));
            let rel = random_isometry(&mut state, 0.6);
            let witness = rel.apply(b.inner_ball().0);
            let walked = edge_query(&a, &b, &rel, f64::NEG_INFINITY, witness);
            let walked = walked.map(|q| q.separation);
            let every = brute_force_edge_query(&a, &b, &rel);
            match (walked, every) {
                (Some(w), Some(e)) if e <= 0.0 => {
                    assert!((w - e).abs() < 1e-12, "case {case}: walk {w}, every pair {e}");
                    compared += 1;
                }
                (Some(w), Some(e)) => assert!(w > 0.0, "case {case}: walk {w}, every pair {e}"),
                (w, e) => assert_eq!(w.is_some(), e.is_some(), "case {case}: {w:?} {e:?}"),
            }
        }
        assert!(compared > 300, "{compared}");
    }

    /// The face query finds the same face, separation and support point
    /// with its bounds on f32 lanes (masks) as with a branch a face, and
    /// that face's separation is the greatest of every face's, measured
    /// over every vertex, on random hulls from deep inside each other to
    /// apart.
    #[test]
    fn face_query_with_masks_matches_every_face_measured() {
        let mut state = 7;
        let mut separated = 0;
        for case in 0..400 {
            let (a, b) = (cloud(&mut state, 4 + case % 60), cloud(&mut state, 4 + case % 37));
            let rel = random_isometry(&mut state, (case % 4) as f64);
            let witness = rel.apply(b.inner_ball().0);
            let first = (case as u32 * 7) % a.topology().face_count() as u32;
            let query = |masks| face_query(&a, &b, &rel, first, f64::NEG_INFINITY, witness, masks);
            let (masked, branched) = (query(true), query(false));
            assert_eq!(masked, branched, "case {case}");
            let separation = |f: u32| {
                let plane = a.plane(f);
                let low = |v: &Vec3| plane.distance(rel.apply(v.as_dvec3()));
                b.vertices().iter().map(low).fold(f64::INFINITY, f64::min)
            };
            assert!((separation(masked.face) - masked.separation).abs() < 1e-12, "case {case}");
            if masked.separation > 0.0 {
                separated += 1;
                continue;
            }
            let best =
                (0..a.topology().face_count() as u32).map(separation).fold(f64::MIN, f64::max);
            assert!((best - masked.separation).abs() < 1e-12, "case {case}: {best} {masked:?}");
        }
        assert!((50..350).contains(&separated), "{separated} of 400 apart");
    }
}
