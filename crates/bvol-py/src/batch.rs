//! Tests on arrays of bounds, row against row, in one call: overlap masks
//! and ray entry distances, without a Python loop and without the GIL.

use bvol::glam::Mat3;
use bvol::volumes::{Obb, Ray, Sphere};
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::{Floats, floats, same_rows, vectors};

/// How far from orthonormal a box's axes may be: float32 rotations that
/// went through a few products.
const AXES_TOLERANCE: f32 = 1e-4;

/// Why a row with a NaN or an infinity is refused.
const NOT_FINITE: &str = "NaN or infinite value";

/// Whether sphere `i` of A overlaps (or touches) sphere `i` of B, for
/// every row: an (M,) bool array. Centres are (M, 3) arrays, radii (M,).
#[pyfunction]
pub(crate) fn spheres_overlap<'py>(
    py: Python<'py>,
    centers_a: &Bound<'py, PyAny>,
    radii_a: &Bound<'py, PyAny>,
    centers_b: &Bound<'py, PyAny>,
    radii_b: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<bool>>> {
    let a = spheres(("centers_a", centers_a), ("radii_a", radii_a))?;
    let b = spheres(("centers_b", centers_b), ("radii_b", radii_b))?;
    same_rows(&["centers_a", "centers_b"], &[a.len(), b.len()])?;
    let hits: Vec<bool> = py.detach(|| a.iter().zip(&b).map(|(a, b)| a.overlaps(b)).collect());
    Ok(PyArray1::from_vec(py, hits))
}

/// Whether box `i` of A overlaps (or touches) box `i` of B, for every row:
/// an (M,) bool array. Centres and half extents are (M, 3) arrays, axes
/// (M, 3, 3) with each box's unit axes as the columns, as
/// `OrientedBox.axes` gives them.
#[pyfunction]
#[allow(clippy::too_many_arguments)] // Python's signature: three arrays a side.
pub(crate) fn boxes_overlap<'py>(
    py: Python<'py>,
    centers_a: &Bound<'py, PyAny>,
    axes_a: &Bound<'py, PyAny>,
    half_extents_a: &Bound<'py, PyAny>,
    centers_b: &Bound<'py, PyAny>,
    axes_b: &Bound<'py, PyAny>,
    half_extents_b: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<bool>>> {
    let a = boxes(["centers_a", "axes_a", "half_extents_a"], [centers_a, axes_a, half_extents_a])?;
    let b = boxes(["centers_b", "axes_b", "half_extents_b"], [centers_b, axes_b, half_extents_b])?;
    same_rows(&["centers_a", "centers_b"], &[a.len(), b.len()])?;
    let hits: Vec<bool> = py.detach(|| a.iter().zip(&b).map(|(a, b)| a.overlaps(b)).collect());
    Ok(PyArray1::from_vec(py, hits))
}

/// Where ray `i` enters sphere `i`: an (M,) float32 array of ray
/// parameters `t` (distances for unit directions), 0 for a ray starting
/// inside, `inf` where the ray misses or enters beyond `max_t`.
#[pyfunction]
#[pyo3(signature = (origins, directions, centers, radii, max_t = f32::INFINITY))]
pub(crate) fn ray_spheres<'py>(
    py: Python<'py>,
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
    centers: &Bound<'py, PyAny>,
    radii: &Bound<'py, PyAny>,
    max_t: f32,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let rays = finite_rays(origins, directions)?;
    let spheres = spheres(("centers", centers), ("radii", radii))?;
    same_rows(&["origins", "centers"], &[rays.len(), spheres.len()])?;
    check_max_t(max_t)?;
    let entries = py.detach(|| entries(&rays, &spheres, |s, r| s.ray_entry(r, max_t)));
    Ok(PyArray1::from_vec(py, entries))
}

/// Where ray `i` enters box `i`: as [`ray_spheres`], for boxes given as
/// to [`boxes_overlap`].
#[pyfunction]
#[pyo3(signature = (origins, directions, centers, axes, half_extents, max_t = f32::INFINITY))]
pub(crate) fn ray_boxes<'py>(
    py: Python<'py>,
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
    centers: &Bound<'py, PyAny>,
    axes: &Bound<'py, PyAny>,
    half_extents: &Bound<'py, PyAny>,
    max_t: f32,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let rays = finite_rays(origins, directions)?;
    let boxes = boxes(["centers", "axes", "half_extents"], [centers, axes, half_extents])?;
    same_rows(&["origins", "centers"], &[rays.len(), boxes.len()])?;
    check_max_t(max_t)?;
    let entries = py.detach(|| entries(&rays, &boxes, |b, r| b.ray_entry(r, max_t)));
    Ok(PyArray1::from_vec(py, entries))
}

/// Each ray's entry into its bound, `inf` for a miss.
fn entries<T: Sync>(
    rays: &[Ray],
    bounds: &[T],
    entry: impl Fn(&T, &Ray) -> Option<f32>,
) -> Vec<f32> {
    rays.iter().zip(bounds).map(|(r, b)| entry(b, r).unwrap_or(f32::INFINITY)).collect()
}

/// Spheres from their centres and radii.
fn spheres(
    (centers_name, centers): (&str, &Bound<'_, PyAny>),
    (radii_name, radii): (&str, &Bound<'_, PyAny>),
) -> PyResult<Vec<Sphere>> {
    let centers = vectors(centers_name, centers)?;
    let radii = floats(radii_name, radii, &[])?;
    same_rows(&[centers_name, radii_name], &[centers.vectors().len(), radii.values().len()])?;
    finite(centers_name, &centers)?;
    for (i, &r) in radii.values().iter().enumerate() {
        if !(r.is_finite() && r >= 0.0) {
            return Err(bad_row(radii_name, i, "a radius must be finite and at least 0"));
        }
    }
    Ok(centers.vectors().iter().zip(radii.values()).map(|(&c, &r)| Sphere::new(c, r)).collect())
}

/// Boxes from their centres, axes and half extents.
fn boxes(
    names: [&str; 3],
    [centers, axes, half_extents]: [&Bound<'_, PyAny>; 3],
) -> PyResult<Vec<Obb>> {
    let centers = vectors(names[0], centers)?;
    let axes = floats(names[1], axes, &[3, 3])?;
    let half_extents = vectors(names[2], half_extents)?;
    finite(names[0], &centers)?;
    let (centers, axes) = (centers.vectors(), axes.rows::<9>());
    same_rows(&names, &[centers.len(), axes.len(), half_extents.vectors().len()])?;
    let mut boxes = Vec::with_capacity(centers.len());
    for (i, ((&center, rows), &half)) in
        centers.iter().zip(axes).zip(half_extents.vectors()).enumerate()
    {
        let axes = Mat3::from_cols_array(rows).transpose();
        if !is_orthonormal(axes) {
            return Err(bad_row(names[1], i, "the columns must be orthonormal axes"));
        }
        if !(half.is_finite() && half.min_element() >= 0.0) {
            return Err(bad_row(names[2], i, "half extents must be finite and at least 0"));
        }
        boxes.push(Obb { center, axes, half_extents: half });
    }
    Ok(boxes)
}

/// Rays from their (R, 3) origins and directions, as given: a ray with a
/// NaN or infinity hits nothing.
pub(crate) fn rays(
    origins: &Bound<'_, PyAny>,
    directions: &Bound<'_, PyAny>,
) -> PyResult<Vec<Ray>> {
    let origins = vectors("origins", origins)?;
    let directions = vectors("directions", directions)?;
    same_rows(&["origins", "directions"], &[origins.vectors().len(), directions.vectors().len()])?;
    Ok(origins.vectors().iter().zip(directions.vectors()).map(|(&o, &d)| Ray::new(o, d)).collect())
}

/// Rays as [`rays`] reads them, every one finite.
fn finite_rays(origins: &Bound<'_, PyAny>, directions: &Bound<'_, PyAny>) -> PyResult<Vec<Ray>> {
    let rays = rays(origins, directions)?;
    if let Some(i) = rays.iter().position(|r| !r.origin.is_finite()) {
        return Err(bad_row("origins", i, NOT_FINITE));
    }
    if let Some(i) = rays.iter().position(|r| !r.direction.is_finite()) {
        return Err(bad_row("directions", i, NOT_FINITE));
    }
    Ok(rays)
}

/// An error naming the first row of `rows` with a NaN or infinity.
fn finite(name: &str, rows: &Floats<'_>) -> PyResult<()> {
    match rows.vectors().iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(bad_row(name, i, NOT_FINITE)),
    }
}

/// Whether the columns of `m` are unit vectors at right angles, to
/// [`AXES_TOLERANCE`].
fn is_orthonormal(m: Mat3) -> bool {
    let gram = m.transpose() * m;
    gram.is_finite() && gram.abs_diff_eq(Mat3::IDENTITY, AXES_TOLERANCE)
}

/// `max_t` is a ray parameter: not NaN, at least 0.
pub(crate) fn check_max_t(max_t: f32) -> PyResult<()> {
    if max_t >= 0.0 {
        Ok(())
    } else {
        Err(PyValueError::new_err(format!("max_t = {max_t}: must be at least 0")))
    }
}

/// A `ValueError` naming row `i` of the array `name`.
fn bad_row(name: &str, i: usize, why: &str) -> PyErr {
    PyValueError::new_err(format!("{name}[{i}]: {why}"))
}
