//! Spheres against hulls, boxes and spheres: the closest point of the other
//! shape to the sphere's centre decides (Ericson, Real-Time Collision
//! Detection 5.1.2 and 5.1.4).

use bvol_volumes::{Obb, Sphere};
use glam::DVec3;

use crate::boxes::check_obb;
use crate::convex::Convex;
use crate::isometry::DIsometry3;
use crate::manifold::{Manifold, rim};
use crate::{Body, Collision, NarrowError, Polyhedron, Pose};

/// Where a sphere's centre is with respect to a convex shape, in its space.
enum Nearest {
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

/// Whether sphere `a` touches box `b`, and how: the closest point of the box
/// is the centre clamped to it in the box's frame (Ericson 5.1.4); a centre
/// inside goes out through the nearest face. The normal points from the
/// sphere to the box.
///
/// Errors as for [`sphere_hull`], and a box with a non-finite field or a
/// negative half extent is [`NarrowError::NonFiniteShape`].
///
/// ```
/// use bvol_narrow::{Collision, Pose, sphere_obb};
/// use bvol_volumes::{Obb, Sphere};
/// use glam::{Mat3, Quat, Vec3};
/// let b = Obb { center: Vec3::ZERO, axes: Mat3::IDENTITY, half_extents: Vec3::ONE };
/// let ball = Sphere::new(Vec3::ZERO, 0.5);
/// let beside = Pose::new(Vec3::new(2.0, 0.0, 0.0), Quat::IDENTITY);
/// let hit = sphere_obb(&ball, &beside, &b, &Pose::IDENTITY)?;
/// assert_eq!(hit, Collision::Separated { axis: -Vec3::X, distance: 0.5 });
/// # Ok::<(), bvol_narrow::NarrowError>(())
/// ```
pub fn sphere_obb(
    a: &Sphere,
    pose_a: &Pose,
    b: &Obb,
    pose_b: &Pose,
) -> Result<Collision, NarrowError> {
    let iso_a = DIsometry3::of_pose(pose_a, Body::A)?;
    check_sphere(a, Body::A)?;
    let iso_b = DIsometry3::of_pose(pose_b, Body::B)?.with_box(b.center, b.axes);
    check_obb(b, Body::B)?;
    let centre = iso_b.relative(&iso_a).apply(a.center.as_dvec3());
    let nearest = nearest_on_box(centre, b.half_extents.as_dvec3());
    Ok(sphere_contact(centre, a.radius.into(), nearest, &iso_b))
}

/// Whether two spheres touch, and how: along the line of their centres, from
/// A's to B's. Concentric spheres have no such line; they touch along A's
/// local up axis (`pose_a.rotation * Vec3::Y`), a fixed choice that turns
/// with A.
///
/// Errors as for [`sphere_hull`], for either sphere.
///
/// ```
/// use bvol_narrow::{Pose, sphere_sphere};
/// use bvol_volumes::Sphere;
/// use glam::{Quat, Vec3};
/// let s = Sphere::new(Vec3::ZERO, 1.0);
/// let near = Pose::new(Vec3::new(1.5, 0.0, 0.0), Quat::IDENTITY);
/// let contact = *sphere_sphere(&s, &Pose::IDENTITY, &s, &near)?.contact().unwrap();
/// assert_eq!((contact.normal, contact.depth), (Vec3::X, 0.5));
/// assert_eq!(contact.points()[0].position, Vec3::new(0.75, 0.0, 0.0));
/// # Ok::<(), bvol_narrow::NarrowError>(())
/// ```
pub fn sphere_sphere(
    a: &Sphere,
    pose_a: &Pose,
    b: &Sphere,
    pose_b: &Pose,
) -> Result<Collision, NarrowError> {
    let iso_a = DIsometry3::of_pose(pose_a, Body::A)?;
    check_sphere(a, Body::A)?;
    let iso_b = DIsometry3::of_pose(pose_b, Body::B)?;
    check_sphere(b, Body::B)?;
    let ca = iso_a.apply(a.center.as_dvec3());
    let cb = iso_b.apply(b.center.as_dvec3());
    let (ra, rb) = (f64::from(a.radius), f64::from(b.radius));
    let offset = cb - ca;
    let distance = offset.length();
    let normal = offset.try_normalize().unwrap_or_else(|| iso_a.rotate(DVec3::Y));
    let gap = distance - ra - rb;
    if gap > 0.0 {
        return Ok(Collision::separated(normal, gap));
    }
    // Midway between A's surface point ca + ra n and B's cb - rb n.
    let mut manifold = Manifold::default();
    manifold.push((ca + normal * ra + cb - normal * rb) * 0.5, -gap);
    Ok(Collision::touching(normal, -gap, &manifold, &DIsometry3::IDENTITY))
}

/// Whether a sphere's fields are finite and its radius not negative.
fn check_sphere(sphere: &Sphere, body: Body) -> Result<(), NarrowError> {
    if sphere.center.is_finite() && sphere.radius.is_finite() && sphere.radius >= 0.0 {
        Ok(())
    } else {
        Err(NarrowError::NonFiniteShape { body })
    }
}

/// The answer for a sphere of `radius` about `centre`, both in the other
/// shape's space, given where the centre is; `to_world` maps that space to the world.
fn sphere_contact(
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

/// Where `centre` is with respect to the box `[-half, half]` (Ericson 5.1.4):
/// outside, the centre clamped to the box; inside, the face it is nearest,
/// on the axis with the least `half - |centre|` (first on ties).
fn nearest_on_box(centre: DVec3, half: DVec3) -> Nearest {
    let point = centre.clamp(-half, half);
    let excess = centre.abs() - half;
    let axis = (1..3).fold(0, |k, i| if excess[i] > excess[k] { i } else { k });
    let normal = DVec3::AXES[axis] * if centre[axis] < 0.0 { -1.0 } else { 1.0 };
    if point != centre {
        Nearest::Outside { point, fallback: normal }
    } else {
        Nearest::Inside { normal, separation: excess[axis] }
    }
}
