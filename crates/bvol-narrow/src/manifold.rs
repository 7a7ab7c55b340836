//! Contact manifolds: the points where two touching polyhedra press into each
//! other, from clipping a face against a face (Sutherland-Hodgman, as in
//! Box2D's and Bullet's box and hull manifolds), or from the closest points of
//! two edges (Ericson, Real-Time Collision Detection 5.1.9).

use std::cell::RefCell;

use glam::DVec3;

use crate::convex::Convex;
use crate::isometry::DIsometry3;
use crate::plane::Plane;
use crate::segment::Segment;

/// Incident points above the reference plane by less than this, relative to
/// the shapes' size, still count as touching: f64 rounding of exactly
/// resting faces puts some corners a hair above, and a manifold that lost
/// corners to that would flicker.
const TOUCH_SLOP: f64 = 1e-9;

/// The most points a manifold, and so a [`Contact`](crate::Contact), holds:
/// enough to hold a face resting on a face.
pub const MAX_POINTS: usize = 4;

thread_local! {
    /// Two polygons' worth of corners per thread, reused by every face
    /// contact for its clipping: fresh stack arrays for faces of any size
    /// cost more to clear than the clipping itself.
    static POLYGONS: RefCell<(Vec<DVec3>, Vec<DVec3>)> =
        const { RefCell::new((Vec::new(), Vec::new())) };
}

/// A contact manifold in the reference shape's space: up to four points,
/// each midway between the surfaces, with its depth.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Manifold {
    /// Points midway between the surfaces, with their depths (`>= 0`).
    pub points: [(DVec3, f64); MAX_POINTS],
    /// How many of `points` are used.
    pub count: usize,
}

impl Manifold {
    /// Adds a point (beyond [`MAX_POINTS`] it is dropped; callers reduce first).
    pub fn push(&mut self, position: DVec3, depth: f64) {
        if self.count < MAX_POINTS {
            self.points[self.count] = (position, depth.max(0.0));
            self.count += 1;
        }
    }
}

/// The manifold of a face contact: face `face` of `reference` against
/// `incident`, mapped into the reference's space by `rel`, whose vertex
/// `support` is its lowest below that face.
///
/// The incident face is the one round `support` most anti-parallel to the
/// reference normal; it is clipped against the planes through the reference
/// face's edges, square to the face, and the points at or below the reference
/// plane kept, each moved halfway up to the plane, then reduced to four.
/// Empty if no clipped point is at or below the plane: the incident shape
/// then reaches below the plane only beside the reference face, which is not
/// the axis of least penetration.
pub(crate) fn face_contact<R: Convex, I: Convex>(
    reference: &R,
    face: u32,
    incident: &I,
    rel: &DIsometry3,
    support: u32,
) -> Manifold {
    let plane = reference.plane(face);
    let slop = TOUCH_SLOP * reference.size().max(incident.size());
    POLYGONS.with_borrow_mut(|(polygon, scratch)| {
        let ti = incident.topology();
        polygon.clear();
        let facing = incident_face(incident, rel, plane.normal, support);
        let corners = ti.face_loop(facing).map(|h| incident.vertex(ti.half_edge(h).origin));
        polygon.extend(corners.map(|v| rel.apply(v)));
        for (p, edge) in rim(reference, face) {
            let side = edge.cross(plane.normal);
            clip(polygon, Plane { normal: side, offset: side.dot(p) }, scratch);
            std::mem::swap(polygon, scratch);
        }
        polygon.retain(|&p| plane.distance(p) <= slop);
        reduce(polygon, &plane)
    })
}

/// The one-point manifold at vertex `support` of `incident` (mapped by `rel`)
/// below face `face` of `reference`: midway between it and the plane, when
/// the vertex lies over the face. When it lies beside the face, the shapes
/// meet where an edge of the incident shape crosses the face's rim (nearly
/// parallel edges do this, and their pair can be too parallel for the edge
/// query): the point is then midway between the closest points of the
/// vertex's edges and the rim's (Ericson 5.1.9), the nearest such pair.
pub(crate) fn vertex_contact<R: Convex, I: Convex>(
    reference: &R,
    face: u32,
    incident: &I,
    rel: &DIsometry3,
    support: u32,
) -> Manifold {
    let plane = reference.plane(face);
    let s = rel.apply(incident.vertex(support));
    let rim: Vec<(DVec3, DVec3)> = rim(reference, face).collect();
    let over = rim.iter().all(|&(p, e)| e.cross(plane.normal).dot(s - p) <= 0.0);
    if over {
        return reduce(&[s], &plane);
    }
    let ti = incident.topology();
    let mut best = (f64::INFINITY, s);
    for &w in ti.neighbours(support) {
        let edge = rel.apply(incident.vertex(w)) - s;
        for &(p, e) in &rim {
            let (ca, cb) =
                Segment { start: p, delta: e }.closest_points(&Segment { start: s, delta: edge });
            let d = (ca - cb).length_squared();
            if d < best.0 {
                best = (d, (ca + cb) * 0.5);
            }
        }
    }
    reduce(&[best.1], &plane)
}

/// The edges round face `face` of `shape`, in loop order: each as its start
/// and its vector to the next corner.
pub(crate) fn rim<S: Convex>(shape: &S, face: u32) -> impl Iterator<Item = (DVec3, DVec3)> + '_ {
    let topology = shape.topology();
    topology.face_loop(face).map(move |h| {
        let p = shape.vertex(topology.half_edge(h).origin);
        (p, shape.vertex(topology.head(h)) - p)
    })
}

/// The face round vertex `v` of `shape` whose normal, mapped by `rel`, is most
/// anti-parallel to `normal` (first on ties).
fn incident_face<I: Convex>(shape: &I, rel: &DIsometry3, normal: DVec3, v: u32) -> u32 {
    let dir = rel.unrotate(normal);
    let topology = shape.topology();
    let mut best = (u32::MAX, f64::INFINITY);
    for &h in topology.outgoing(v) {
        let f = topology.half_edge(h).face;
        let d = shape.plane(f).normal.dot(dir);
        if d < best.1 {
            best = (f, d);
        }
    }
    best.0
}

/// One Sutherland-Hodgman pass: the part of `polygon` on the inner side of
/// `plane` (`distance <= 0`) into `out`. The side normal need not be unit: the
/// crossing parameter is a ratio of distances.
fn clip(points: &[DVec3], plane: Plane, out: &mut Vec<DVec3>) {
    out.clear();
    let Some(&last) = points.last() else { return };
    let (mut a, mut da) = (last, plane.distance(last));
    for &b in points {
        let db = plane.distance(b);
        if (da <= 0.0) != (db <= 0.0) {
            // Signs differ, so da - db is not zero.
            out.push(a + (b - a) * (da / (da - db)));
        }
        if db <= 0.0 {
            out.push(b);
        }
        (a, da) = (b, db);
    }
}

/// At most four of the `points` below `plane` that keep the manifold's
/// reach (the usual reduction of Bullet and Box2D): the deepest; the one
/// farthest from it; the one making the largest triangle with those two; the
/// one adding the most area outside that triangle. Each moves halfway up to
/// the plane, and its depth is its distance below it.
fn reduce(points: &[DVec3], plane: &Plane) -> Manifold {
    let mut manifold = Manifold::default();
    let mut keep = |p: DVec3| {
        let d = plane.distance(p);
        manifold.push(p - plane.normal * (d * 0.5), -d);
    };
    if points.len() <= MAX_POINTS {
        points.iter().for_each(|&p| keep(p));
        return manifold;
    }
    let n = plane.normal;
    let argmax = |score: &dyn Fn(DVec3) -> f64| {
        let mut best = (0, f64::NEG_INFINITY);
        for (i, &p) in points.iter().enumerate() {
            let s = score(p);
            if s > best.1 {
                best = (i, s);
            }
        }
        best
    };
    let p0 = points[argmax(&|p| -plane.distance(p)).0];
    let (i1, far) = argmax(&|p| p.distance_squared(p0));
    let p1 = points[i1];
    // Twice the signed area of (p0, p1, p) seen along the normal.
    let area = |a: DVec3, b: DVec3, p: DVec3| (b - a).cross(p - a).dot(n);
    let (i2, twice) = argmax(&|p| area(p0, p1, p).abs());
    keep(p0);
    if far <= 0.0 {
        return manifold;
    }
    keep(p1);
    if twice <= 0.0 {
        return manifold;
    }
    let p2 = points[i2];
    keep(p2);
    // Wind the triangle counter-clockwise, then take the point farthest
    // outside any of its edges.
    let (p1, p2) = if area(p0, p1, p2) > 0.0 { (p1, p2) } else { (p2, p1) };
    let (i3, outside) = argmax(&|p| (-area(p0, p1, p)).max(-area(p1, p2, p)).max(-area(p2, p0, p)));
    if outside > 0.0 {
        keep(points[i3]);
    }
    manifold
}

/// The contact of two edges, `pa + s ea` and `pb + t eb` for `s, t` in `[0, 1]`:
/// one point, midway between their closest points (Ericson 5.1.9), with the
/// given depth.
pub(crate) fn edge_contact(pa: DVec3, ea: DVec3, pb: DVec3, eb: DVec3, depth: f64) -> Manifold {
    let (ca, cb) =
        Segment { start: pa, delta: ea }.closest_points(&Segment { start: pb, delta: eb });
    let mut manifold = Manifold::default();
    manifold.push((ca + cb) * 0.5, depth);
    manifold
}
