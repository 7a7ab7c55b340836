//! Flat point sets (a floor tile, a sheet, a decal) made solid, so that the
//! separating-axis tests, which need a polyhedron with a volume and a closed
//! Gauss map, take them with a contact on either face.

use bvol_volumes::{ConvexHull, FitError};
use glam::Vec3;

use crate::ShapeError;

/// The thickness a flat point set is given, relative to its size (the sum of
/// its half extents along the axes): centred on its plane, each face lies
/// half of this off the plane, which is all a contact's depth and the
/// touching verdict move by. About 80 times the hull's flatness tolerance
/// (3 f32 epsilons of the size), so that the thickened set is solid at f32
/// precision; parry3d takes such a set as a polygon of no thickness.
pub const FLAT_THICKNESS: f64 = 1e-5;

/// The hull of `points`; when they are flat, the hull of each point copied
/// [`FLAT_THICKNESS`] / 2 of the set's size to each side of its plane.
/// Errors as [`ConvexHull::new`]'s, as shape errors; a set that stays flat at
/// f32 precision (its plane too far from the origin for the thickness to
/// show) comes back flat, for the caller's [`ShapeError::Degenerate`].
pub(crate) fn solid_hull(points: &[Vec3]) -> Result<ConvexHull, ShapeError> {
    let hull = ConvexHull::new(points).map_err(shape_error)?;
    if hull.dimension() != 2 {
        return Ok(hull);
    }
    let size = hull.tolerance() / (3.0 * f64::from(f32::EPSILON));
    let half = hull.face_normal(0) * (0.5 * FLAT_THICKNESS * size);
    let sides: Vec<Vec3> = hull
        .vertices()
        .iter()
        .flat_map(|p| [(p.as_dvec3() + half).as_vec3(), (p.as_dvec3() - half).as_vec3()])
        .collect();
    let solid = ConvexHull::new(&sides).map_err(shape_error)?;
    Ok(if solid.dimension() == 3 { solid } else { hull })
}

/// A hull's fit error as a shape error.
pub(crate) fn shape_error(e: FitError) -> ShapeError {
    match e {
        FitError::Empty => ShapeError::Empty,
        FitError::NonFinite { index } => ShapeError::NonFinite { index },
        FitError::OutOfRange { index } => ShapeError::OutOfRange { index },
    }
}
