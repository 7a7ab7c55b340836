//! A capsule against a convex polyhedron: the separating-axis test of the
//! capsule's core (a segment) against the hull, then, when the core is
//! outside, the closest points of the two; the capsule touches where they
//! are less than its radius apart.

use glam::DVec3;

use crate::capsule::{END_SLOP, PARALLEL_SINE};
use crate::convex::Convex;
use crate::isometry::DIsometry3;
use crate::manifold::{Manifold, rim};
use crate::segment::Segment;
use crate::{Body, Capsule, Collision, NarrowError, Polyhedron, Pose};

/// Whether capsule `a` touches polyhedron `b`, and how: the normal points
/// from the capsule to the hull. Computed in the hull's space in f64, as
/// [`sphere_hull`](crate::sphere_hull) is.
///
/// The capsule's core is tested against the hull's face normals and the
/// cross products of the core with the hull's edges whose Gauss-map arcs
/// cross the core's great circle (Gregorius, GDC 2013; the core's Gauss map
/// is the circle square to it): the faces of their Minkowski difference.
/// - Core outside the hull: the closest points of the core and the hull's
///   faces (the core's ends projected on them, Ericson, Real-Time Collision
///   Detection 5.1.1, and the core against their edges, 5.1.9) give the
///   distance; the capsule touches by its radius less that distance, along
///   the line between them.
/// - Core inside: the least-penetration axis of that test is the normal, and
///   the depth its overlap plus the radius.
///
/// The manifold has two points where the capsule lies on a face (the core
/// parallel to it to about a degree, and the normal square to it): the core
/// clipped to the face's side planes (and to the hull when it is sunk in),
/// a point at each end of what is left, where both touch, each midway
/// between the capsule's surface below it and the face. Otherwise one point,
/// midway between the surfaces where they are deepest.
///
/// A box is a polyhedron here ([`Polyhedron::cuboid`]). A pose that is not
/// finite is [`NarrowError::NonFinitePose`]; a capsule with a non-finite
/// field or a negative size is [`NarrowError::NonFiniteShape`].
///
/// ```
/// use bvol_narrow::{Capsule, Polyhedron, Pose, capsule_hull};
/// use glam::{Quat, Vec3};
/// let floor = Polyhedron::cuboid(Vec3::new(2.0, 0.5, 2.0))?;
/// // A capsule of radius 0.25 lying along x on the floor, sunk 0.01 into it.
/// let capsule = Capsule::new(0.25, 1.0);
/// let lying = Pose::new(Vec3::new(0.0, 0.74, 0.0), Quat::from_rotation_z(1.5707964));
/// let contact = *capsule_hull(&capsule, &lying, &floor, &Pose::IDENTITY)?
///     .contact()
///     .expect("touching");
/// assert!((contact.normal + Vec3::Y).length() < 1e-6); // from the capsule down into the floor
/// assert!((contact.depth - 0.01).abs() < 1e-6);
/// // Below each end of its core, halfway between the two surfaces.
/// assert_eq!(contact.points().len(), 2);
/// for p in contact.points() {
///     assert!((p.position.x.abs() - 1.0).abs() < 1e-6 && (p.position.y - 0.495).abs() < 1e-6);
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn capsule_hull(
    a: &Capsule,
    pose_a: &Pose,
    b: &Polyhedron,
    pose_b: &Pose,
) -> Result<Collision, NarrowError> {
    let iso_a = DIsometry3::of_pose(pose_a, Body::A)?;
    a.check(Body::A)?;
    let iso_b = DIsometry3::of_pose(pose_b, Body::B)?;
    let core = a.core(&iso_b.relative(&iso_a));
    Ok(capsule_convex(&core, a.radius.into(), b, &iso_b))
}

/// A feature of the hull whose outward direction is a separating-axis test.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Feature {
    /// A face, by index.
    Face(u32),
    /// An edge.
    Edge,
}

/// One axis of the test: the hull's outward unit direction `normal`, the
/// hull's extent along it (`top`, the greatest `normal . x` over the hull)
/// and the core's least height above that (`separation`: `> 0` apart).
#[derive(Clone, Copy, Debug)]
struct Axis {
    normal: DVec3,
    top: f64,
    separation: f64,
    feature: Feature,
}

impl Axis {
    /// Height of `p` above the hull's extent along the axis.
    fn height(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.top
    }
}

/// The answer for a capsule of core `core` and `radius`, in `shape`'s space,
/// which `to_world` maps to the world.
fn capsule_convex<S: Convex>(
    core: &Segment,
    radius: f64,
    shape: &S,
    to_world: &DIsometry3,
) -> Collision {
    let axis = deepest_axis(core, shape);
    let slop = END_SLOP * shape.size().max(0.5 * core.delta.length() + radius);
    if axis.separation > 0.0 {
        let (on_core, on_shape) = closest_to_core(core, shape, &axis);
        let offset = on_shape - on_core;
        let normal = offset.try_normalize().unwrap_or(-axis.normal);
        let gap = offset.length() - radius;
        if gap > 0.0 {
            return Collision::separated(to_world.rotate(normal), gap);
        }
        let flat = match axis.feature {
            Feature::Face(f) if normal.cross(axis.normal).length() <= PARALLEL_SINE => {
                lying_on_face(core, radius, shape, f, -gap, slop, false)
            }
            _ => None,
        };
        let manifold = flat.unwrap_or_else(|| {
            let mut one = Manifold::default();
            one.push((on_core + normal * radius + on_shape) * 0.5, -gap);
            one
        });
        return Collision::touching(to_world.rotate(normal), -gap, &manifold, to_world);
    }
    let depth = radius - axis.separation;
    let flat = match axis.feature {
        Feature::Face(f) => lying_on_face(core, radius, shape, f, depth, slop, true),
        Feature::Edge => None,
    };
    let manifold = flat.unwrap_or_else(|| deepest_point(core, radius, shape, &axis, slop));
    Collision::touching(to_world.rotate(-axis.normal), depth, &manifold, to_world)
}

/// The axis along which the core is least deep in the hull (or farthest
/// above it): the greatest separation over the face normals and the edge
/// axes. An edge's axis is the cross product of the core with it, where its
/// Gauss-map arc crosses the core's great circle (the normals of its two
/// faces on either side of the plane square to the core): the other edges
/// make no face of the Minkowski difference. Its extent is the hull's
/// support point, found from the edge, not read off the edge itself: a
/// merged face is flat only to the hull's tolerance.
fn deepest_axis<S: Convex>(core: &Segment, shape: &S) -> Axis {
    let ends = [core.start, core.end()];
    let lowest = |n: DVec3| n.dot(ends[0]).min(n.dot(ends[1]));
    let topology = shape.topology();
    let mut best = Axis {
        normal: DVec3::Y,
        top: 0.0,
        separation: f64::NEG_INFINITY,
        feature: Feature::Face(0),
    };
    for f in 0..topology.face_count() as u32 {
        let plane = shape.plane(f);
        let separation = lowest(plane.normal) - plane.offset;
        if separation > best.separation {
            best = Axis {
                normal: plane.normal,
                top: plane.offset,
                separation,
                feature: Feature::Face(f),
            };
        }
    }
    let d = core.delta;
    if d == DVec3::ZERO {
        return best;
    }
    for &h in &topology.edges {
        let half = topology.half_edge(h);
        let (n1, n2) = (shape.plane(half.face).normal, shape.plane(topology.twin_face(h)).normal);
        if n1.dot(d) * n2.dot(d) > 0.0 {
            continue;
        }
        let tail = shape.vertex(half.origin);
        let Some(normal) = d.cross(shape.vertex(topology.head(h)) - tail).try_normalize() else {
            continue; // parallel: the faces' normals hold the Minkowski faces
        };
        let normal = if normal.dot(n1 + n2) < 0.0 { -normal } else { normal };
        let low = lowest(normal);
        // The search may stop once the axis cannot beat the best.
        let (_, least) = shape.support_min(-normal, half.origin, best.separation - low);
        let separation = low + least;
        if separation > best.separation {
            best = Axis { normal, top: -least, separation, feature: Feature::Edge };
        }
    }
    best
}

/// The closest points of a core outside the hull and the hull, `(on core, on
/// hull)`. Where the core's lower end along a face axis projects inside the
/// face, that is the pair: the axis bounds the distance from below, and the
/// pair attains it. Otherwise every face whose plane the core is partly
/// above is read: the core's ends above it projected inside it, and the core
/// against its edges. The closest point of the hull to the core's closest
/// point lies on such a face, inside it or on its rim; where it is inside and
/// the core's point is not an end, the core runs parallel to the face and
/// an end or a rim crossing is as close.
fn closest_to_core<S: Convex>(core: &Segment, shape: &S, axis: &Axis) -> (DVec3, DVec3) {
    if let Feature::Face(f) = axis.feature {
        let end = if axis.height(core.start) <= axis.height(core.end()) {
            core.start
        } else {
            core.end()
        };
        let projected = end - axis.normal * axis.height(end);
        if inside_face(shape, f, projected) {
            return (end, projected);
        }
    }
    let mut closest = (f64::INFINITY, core.start, core.start);
    let mut keep = |on_core: DVec3, on_shape: DVec3| {
        let d = on_core.distance_squared(on_shape);
        if d < closest.0 {
            closest = (d, on_core, on_shape);
        }
    };
    for f in 0..shape.topology().face_count() as u32 {
        let plane = shape.plane(f);
        let mut above = false;
        for end in [core.start, core.end()] {
            let height = plane.distance(end);
            if height > 0.0 {
                above = true;
                let projected = end - plane.normal * height;
                if inside_face(shape, f, projected) {
                    keep(end, projected);
                }
            }
        }
        if above {
            for (corner, edge) in rim(shape, f) {
                let (on_core, on_edge) =
                    core.closest_points(&Segment { start: corner, delta: edge });
                keep(on_core, on_edge);
            }
        }
    }
    (closest.1, closest.2)
}

/// Whether `p`, on face `f`'s plane, is inside the face: behind the plane
/// through each edge square to the face (outward for a counter-clockwise loop).
fn inside_face<S: Convex>(shape: &S, f: u32, p: DVec3) -> bool {
    let normal = shape.plane(f).normal;
    rim(shape, f).all(|(corner, edge)| edge.cross(normal).dot(p - corner) <= 0.0)
}

/// The parameters of the part of `core` behind every plane `n . x = offset`
/// of `planes` (`n` need not be unit): Cyrus-Beck clipping (Ericson 5.3.8).
/// `None` when nothing is left.
fn clip(core: &Segment, planes: impl Iterator<Item = (DVec3, f64)>) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for (n, offset) in planes {
        let (start, rate) = (n.dot(core.start) - offset, n.dot(core.delta));
        if rate > 0.0 {
            hi = hi.min(-start / rate);
        } else if rate < 0.0 {
            lo = lo.max(-start / rate);
        } else if start > 0.0 {
            return None;
        }
        if lo > hi {
            return None;
        }
    }
    Some((lo, hi))
}

/// The part of the core inside the hull grown by `grow`, as parameters.
fn inside_hull<S: Convex>(core: &Segment, shape: &S, grow: f64) -> Option<(f64, f64)> {
    let faces = 0..shape.topology().face_count() as u32;
    clip(core, faces.map(|f| shape.plane(f)).map(|p| (p.normal, p.offset + grow)))
}

/// The two-point manifold of a capsule lying on face `f` (contact `depth`):
/// `None` unless the core is parallel to the face to [`PARALLEL_SINE`], its
/// part over the face (clipped to the planes through the face's edges square
/// to it, as Box2D clips a capsule against a polygon's reference face; when
/// `sunk`, also to the hull) has a length, and both ends of that part touch.
/// Each point is midway between the capsule's surface below the end and the
/// face, as deep as that.
fn lying_on_face<S: Convex>(
    core: &Segment,
    radius: f64,
    shape: &S,
    f: u32,
    depth: f64,
    slop: f64,
    sunk: bool,
) -> Option<Manifold> {
    let plane = shape.plane(f);
    let along = core.delta.try_normalize()?;
    if plane.normal.dot(along).abs() > PARALLEL_SINE {
        return None;
    }
    let sides = rim(shape, f).map(|(corner, edge)| {
        let side = edge.cross(plane.normal);
        (side, side.dot(corner))
    });
    let (mut lo, mut hi) = clip(core, sides)?;
    if sunk {
        let (a, b) = inside_hull(core, shape, 0.0)?;
        (lo, hi) = (lo.max(a), hi.min(b));
    }
    if lo >= hi {
        return None;
    }
    let mut manifold = Manifold::default();
    for t in [lo, hi] {
        let end = core.at(t);
        let height = plane.distance(end);
        let deep = radius - height;
        if !(-slop..=depth + slop).contains(&deep) {
            return None;
        }
        manifold.push(end - plane.normal * ((radius + height) * 0.5), deep.min(depth));
    }
    Some(manifold)
}

/// The one-point manifold of a core inside the hull: at the point of the
/// core inside the hull that is deepest along the axis (an end of the part
/// inside), midway between the capsule's surface below it and the hull's
/// extent along the axis. Every point from the core's point inside to the
/// contact point is within the contact depth of both bodies.
///
/// A core that only grazes the hull (through a vertex, along an edge) can
/// round to no part inside: then the part inside the hull grown by `slop`,
/// and only when that is empty too, the whole core. (Taking the whole core
/// at once put the contact of a capsule 7000 long through a hull's vertex
/// at the capsule's end, 3514 from the hull.)
fn deepest_point<S: Convex>(
    core: &Segment,
    radius: f64,
    shape: &S,
    axis: &Axis,
    slop: f64,
) -> Manifold {
    let inside = inside_hull(core, shape, 0.0).or_else(|| inside_hull(core, shape, slop));
    let (lo, hi) = inside.unwrap_or((0.0, 1.0));
    let (p, q) = (core.at(lo), core.at(hi));
    let deepest = if axis.height(p) <= axis.height(q) { p } else { q };
    let height = axis.height(deepest);
    let mut manifold = Manifold::default();
    manifold.push(deepest - axis.normal * ((radius + height) * 0.5), radius - height);
    manifold
}
