//! Point sets, through every fitter and the convex hull.

use arbitrary::{Result, Unstructured};
use bvol::glam::{DVec3, Quat, Vec3};
use bvol::volumes::{
    Aabb, ConvexHull, FitError, Kdop, Kdop6, Kdop14, Kdop18, Kdop26, MAX_COORDINATE, Obb,
    ObbMethod, Pose, Sphere, SphereMethod,
};

use crate::checks::{behind_every_face, finite, one_line_error};
use crate::floats;

/// Most points in a set.
const MAX_POINTS: usize = 200;

/// Fits every bound to the points `data` spells. A set that is empty or has
/// a NaN, infinite or out-of-range coordinate is refused with that error
/// (naming the first such point); any other gives
/// finite bounds that contain every point, and a hull with every point
/// behind (or within tolerance of) every face.
pub fn run(data: &[u8]) {
    let Ok(points) = points(&mut Unstructured::new(data)) else { return };
    let beyond = |p: &Vec3| !p.abs().cmple(Vec3::splat(MAX_COORDINATE)).all();
    let expected = match points.iter().position(beyond) {
        Some(index) if points[index].is_finite() => Some(FitError::OutOfRange { index }),
        Some(index) => Some(FitError::NonFinite { index }),
        None => points.is_empty().then_some(FitError::Empty),
    };
    let check = |what: &str, result: std::result::Result<(), FitError>| match (&expected, result) {
        (None, Ok(())) => {}
        (Some(e), Err(got)) => {
            assert_eq!(&got, e, "{what}: wrong error");
            one_line_error(&got.to_string(), None);
        }
        (e, got) => panic!("{what}: expected {e:?}, got {got:?}"),
    };
    for &m in SphereMethod::ALL {
        check(&format!("sphere {m}"), Sphere::fit(&points, m).map(|s| sphere(&s, &points)));
    }
    for &m in ObbMethod::ALL {
        check(&format!("obb {m}"), Obb::fit(&points, m).map(|o| obb(&o, &points)));
    }
    check("aabb", Aabb::fit(&points).map(|b| aabb(&b, &points)));
    check("6-dop", Kdop6::fit(&points).map(|k| kdop(&k, &points)));
    check("14-dop", Kdop14::fit(&points).map(|k| kdop(&k, &points)));
    check("18-dop", Kdop18::fit(&points).map(|k| kdop(&k, &points)));
    check("26-dop", Kdop26::fit(&points).map(|k| kdop(&k, &points)));
    check("hull", ConvexHull::new(&points).map(|h| hull(&h, &points)));
}

/// Up to [`MAX_POINTS`] points (no more than the bytes left can spell): a
/// cloud near the origin, scaled and moved by any amount, a few replaced by
/// any value; sometimes all on a plane, on a line, or repeated.
fn points(u: &mut Unstructured) -> Result<Vec<Vec3>> {
    let n = u.int_in_range(0..=MAX_POINTS.min(u.len() / 3))?;
    let (scale, offset) =
        (floats::size(u)?, floats::rarely_wild(u, 4, floats::vec3, |_| Ok(Vec3::ZERO))?);
    let mut points = (0..n)
        .map(|_| {
            floats::rarely_wild(u, 32, floats::vec3, |u| Ok(floats::position(u)? * scale + offset))
        })
        .collect::<Result<Vec<_>>>()?;
    match u.int_in_range(0u8..=5)? {
        0 => points.iter_mut().for_each(|p| p.z = offset.z),
        1 => points.iter_mut().for_each(|p| *p = Vec3::splat(p.x)),
        2 => points = points.iter().cycle().take(points.len() * 3).copied().collect(),
        _ => {}
    }
    Ok(points)
}

fn sphere(s: &Sphere, points: &[Vec3]) {
    finite(s.center, "a sphere's centre");
    assert!(s.radius.is_finite() && s.radius >= 0.0, "radius {}", s.radius);
    assert!(s.volume_f64().is_finite(), "a sphere's volume");
    points.iter().for_each(|&p| assert!(s.contains_point(p), "{p} outside {s:?}"));
}

fn obb(o: &Obb, points: &[Vec3]) {
    finite(o.center, "a box's centre");
    finite(o.half_extents, "a box's half extents");
    assert!(o.axes.is_finite(), "a box's axes");
    assert!(o.volume_f64().is_finite(), "a box's volume");
    points.iter().for_each(|&p| assert!(o.contains_point(p), "{p} outside {o:?}"));
}

fn aabb(b: &Aabb, points: &[Vec3]) {
    finite(b.min, "a box's corner");
    finite(b.max, "a box's corner");
    assert!(b.volume_f64().is_finite(), "a box's volume");
    points.iter().for_each(|&p| assert!(b.contains_point(p), "{p} outside {b:?}"));
}

fn kdop<const N: usize>(k: &Kdop<N>, points: &[Vec3]) {
    let volume = k.volume_f64();
    assert!(volume.is_finite() && volume >= 0.0, "a k-DOP's volume {volume}");
    let aabb = Aabb::fit(points).expect("fits where the k-DOP does").volume_f64();
    assert!(volume <= aabb, "a k-DOP's volume {volume} past its points' box's {aabb}: {k:?}");
    points.iter().for_each(|&p| assert!(k.contains_point(p), "{p} outside {k:?}"));
    let around = k.aabb();
    points.iter().for_each(|&p| assert!(around.contains_point(p), "{p} outside {around:?}, {k:?}"));
    let moved = k.transformed(&Pose::new(Vec3::new(0.5, -2.0, 1.0), Quat::IDENTITY));
    let shift = |p: Vec3| p.as_dvec3() + DVec3::new(0.5, -2.0, 1.0);
    for &p in points {
        let at = shift(p);
        let inside = (0..N).all(|i| {
            let s = DVec3::from(Kdop::<N>::DIRECTIONS[i].map(f64::from)).dot(at);
            moved.min[i] as f64 <= s && s <= moved.max[i] as f64
        });
        assert!(inside, "{p}, moved by a translation, outside the moved {moved:?} of {k:?}");
    }
}

fn hull(h: &ConvexHull, points: &[Vec3]) {
    h.vertices().iter().for_each(|&v| finite(v, "a hull vertex"));
    assert!(h.volume().is_finite() && h.volume() >= 0.0, "hull volume {}", h.volume());
    behind_every_face(h, points);
}
