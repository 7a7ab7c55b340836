//! The invariants every target shares.

use bvol::glam::Vec3;
use bvol::volumes::ConvexHull;

/// An error message as a user sees it: something, in one line, with no trace
/// of a panic; naming `place` (a file or argument) when given.
pub fn one_line_error(message: &str, place: Option<&str>) {
    assert!(!message.trim().is_empty(), "empty error message");
    assert!(!message.contains('\n'), "error of more than one line: {message:?}");
    assert!(!message.contains("panicked"), "a panic reported as an error: {message:?}");
    if let Some(place) = place {
        assert!(message.contains(place), "error does not name {place:?}: {message:?}");
    }
}

/// A vector that is output: no NaN, no infinity.
pub fn finite(v: Vec3, what: &str) {
    assert!(v.is_finite(), "{what} is not finite: {v}");
}

/// A unit direction that is output.
pub fn unit(v: Vec3, what: &str) {
    finite(v, what);
    assert!((v.length() - 1.0).abs() < 1e-4, "{what} is not unit: {v} (length {})", v.length());
}

/// Every point behind every face plane of `hull`, to within its tolerance
/// (the hull's contract: a point that close in front counts as on it).
pub fn behind_every_face(hull: &ConvexHull, points: &[Vec3]) {
    for f in 0..hull.face_count() {
        let (n, d) = (hull.face_normal(f), hull.face_offset(f));
        assert!(n.is_finite() && d.is_finite(), "face {f}'s plane");
        for &p in points {
            let height = n.dot(p.as_dvec3()) - d;
            assert!(height <= hull.tolerance(), "{p} is {height} in front of face {f}");
        }
    }
}
