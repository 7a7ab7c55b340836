//! A sphere against a convex polyhedron: the closest point of the hull to
//! the sphere's centre decides (Ericson, Real-Time Collision Detection
//! 5.1.2); the answer from that point, which a sphere against a box shares.

use bvol_volumes::Sphere;
use glam::DVec3;

use crate::ball::check_sphere;
use crate::convex::Convex;
use crate::isometry::DIsometry3;
use crate::manifold::{Manifold, rim};
use crate::{Body, Collision, NarrowError, Polyhedron, Pose};

/// Where a sphere's centre is with respect to a convex shape, in its space.
pub(crate) enum Nearest {
    /// Outside: the shape's closest point to it, and the outward normal of a
    /// face it is outside of, for when the two are too close for a direction.
    Outside { point: DVec3, fallback: DVec3 },
    /// Inside (or on the surface): the face plane it is least deep behind,
    /// at signed distance `separation <= 0`.
    Inside { normal: DVec3, separation: f64 },
}

/// Whether sphere `a` touches polyhedron `b`, and how: the normal points from
/// the sphere to the hull.
///
/// The centre is tested against every face plane of B. Inside them all, the
/// contact is through the face it is least deep behind; outside, the closest
/// point of the faces it sees (their polygons, or their edges) gives the
/// distance and the normal. One contact point, midway between the surfaces.
///
/// A pose that is not finite is [`NarrowError::NonFinitePose`]; a sphere with
/// a non-finite field or a negative radius is [`NarrowError::NonFiniteShape`].
///
/// ```
/// use bvol_narrow::{Polyhedron, Pose, sphere_hull};
/// use bvol_volumes::Sphere;
/// use glam::{Quat, Vec3};
/// let cube = Polyhedron::cuboid(Vec3::ONE)?;
/// let ball = Sphere::new(Vec3::ZERO, 0.5);
/// let above = Pose::new(Vec3::new(0.0, 1.25, 0.0), Quat::IDENTITY);
/// let contact = *sphere_hull(&ball, &above, &cube, &Pose::IDENTITY)?.contact().unwrap();
/// assert_eq!(contact.normal, -Vec3::Y); // from the ball down into the cube
/// assert!((contact.depth - 0.25).abs() < 1e-6);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sphere_hull(
    a: &Sphere,
    pose_a: &Pose,
    b: &Polyhedron,
    pose_b: &Pose,
) -> Result<Collision, NarrowError> {
    let iso_a = DIsometry3::of_pose(pose_a, Body::A)?;
    check_sphere(a, Body::A)?;
    let iso_b = DIsometry3::of_pose(pose_b, Body::B)?;
    let centre = iso_b.relative(&iso_a).apply(a.center.as_dvec3());
    Ok(sphere_contact(centre, a.radius.into(), nearest_on_convex(b, centre), &iso_b))
}

/// The answer for a sphere of `radius` about `centre`, both in the other
/// shape's space, given where the centre is; `to_world` maps that space to the world.
pub(crate) fn sphere_contact(
    centre: DVec3,
    radius: f64,
    nearest: Nearest,
    to_world: &DIsometry3,
) -> Collision {
    let (normal, gap, surface) = match nearest {
        Nearest::Outside { point, fallback } => {
            let offset = point - centre;
            let normal = offset.try_normalize().unwrap_or(-fallback);
            (normal, offset.length() - radius, point)
        }
        // Out through the face: the normal from the sphere into the shape is
        // against the face's, and the shape's surface is `-separation` away.
        Nearest::Inside { normal, separation } => {
            (-normal, separation - radius, centre - normal * separation)
        }
    };
    if gap > 0.0 {
        return Collision::separated(to_world.rotate(normal), gap);
    }
    // Midway between the sphere's deepest point and the shape's surface point.
    let mut manifold = Manifold::default();
    manifold.push((centre + normal * radius + surface) * 0.5, -gap);
    Collision::touching(to_world.rotate(normal), -gap, &manifold, to_world)
}

/// Where `centre` is with respect to a convex shape: outside some face plane,
/// the closest point of the faces whose planes it is outside (the closest
/// point of a convex solid to a point outside lies on a face that sees it);
/// inside all, the face it is least deep behind (first on ties).
fn nearest_on_convex<S: Convex>(shape: &S, centre: DVec3) -> Nearest {
    let faces = 0..shape.topology().face_count() as u32;
    let mut deepest = (0, f64::NEG_INFINITY);
    for f in faces.clone() {
        let s = shape.plane(f).distance(centre);
        if s > deepest.1 {
            deepest = (f, s);
        }
    }
    let plane = shape.plane(deepest.0);
    if deepest.1 <= 0.0 {
        return Nearest::Inside { normal: plane.normal, separation: deepest.1 };
    }
    // The solid lies behind every face plane, so the centre is at least the
    // deepest plane's distance from it: where its projection on that face
    // falls inside the face, that point is the nearest (a resting sphere's
    // usual case), and the other faces need no look.
    if let Some(point) = projection_inside(shape, deepest.0, centre) {
        return Nearest::Outside { point, fallback: plane.normal };
    }
    let mut closest = (centre - plane.normal * deepest.1, f64::INFINITY);
    for f in faces.filter(|&f| shape.plane(f).distance(centre) > 0.0) {
        let p = closest_on_face(shape, f, centre);
        let d = p.distance_squared(centre);
        if d < closest.1 {
            closest = (p, d);
        }
    }
    Nearest::Outside { point: closest.0, fallback: plane.normal }
}

/// The projection of `p` on face `f`'s plane, if it falls inside the face.
fn projection_inside<S: Convex>(shape: &S, f: u32, p: DVec3) -> Option<DVec3> {
    let plane = shape.plane(f);
    let projected = p - plane.normal * plane.distance(p);
    // Outside an edge's side plane (through it, square to the face, outward
    // for a counter-clockwise loop) means outside the polygon.
    let inside = rim(shape, f).all(|(a, e)| e.cross(plane.normal).dot(projected - a) <= 0.0);
    inside.then_some(projected)
}

/// The point of face `f`'s polygon closest to `p`: its projection on the
/// plane if that falls inside, else the closest point of its edges.
fn closest_on_face<S: Convex>(shape: &S, f: u32, p: DVec3) -> DVec3 {
    if let Some(projected) = projection_inside(shape, f, p) {
        return projected;
    }
    let mut closest = (p, f64::INFINITY);
    for (a, e) in rim(shape, f) {
        let len2 = e.length_squared();
        let t = if len2 > 0.0 { ((p - a).dot(e) / len2).clamp(0.0, 1.0) } else { 0.0 };
        let q = a + e * t;
        let d = q.distance_squared(p);
        if d < closest.1 {
            closest = (q, d);
        }
    }
    closest.0
}
