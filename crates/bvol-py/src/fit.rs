//! Fitting bounds to points, and the bounds Python gets back.

use bvol::glam::Vec3;
use bvol::volumes::{
    Aabb, ConvexHull, FitError, Kdop6, Kdop14, Kdop18, Kdop26, Obb, ObbMethod, Sphere, SphereMethod,
};
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::{Array2, rows_array, vector_array, vectors};
use crate::errors::value_error;

/// The `#[pymethods]` of a bound's class: `volume` and `contains`, from the
/// wrapped bound's `volume_f64` and `contains_point`, then the class's own.
macro_rules! bound_methods {
    ($class:ident, $($methods:tt)*) => {
        #[pymethods]
        impl $class {
            /// The volume, in float64.
            #[getter]
            fn volume(&self) -> f64 {
                self.0.volume_f64()
            }

            /// Whether each of the (N, 3) `points` lies inside or on the
            /// bound: an (N,) bool array.
            fn contains<'py>(
                &self,
                py: Python<'py>,
                points: &Bound<'py, PyAny>,
            ) -> PyResult<Bound<'py, PyArray1<bool>>> {
                contains(py, points, |p| self.0.contains_point(p))
            }

            $($methods)*
        }
    };
}

/// A bounding sphere: the points within `radius` of `center`.
#[pyclass(name = "Sphere", module = "bvol", frozen)]
pub(crate) struct PySphere(pub(crate) Sphere);

bound_methods! {
    PySphere,
    /// The centre, a (3,) float32 array.
    #[getter]
    fn center<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        PyArray1::from_slice(py, &self.0.center.to_array())
    }

    /// The radius.
    #[getter]
    fn radius(&self) -> f32 {
        self.0.radius
    }

    fn __repr__(&self) -> String {
        format!("Sphere(center={:?}, radius={:?})", self.0.center.to_array(), self.0.radius)
    }
}

/// An oriented bounding box: the points `p` with
/// `abs((p - center) @ axes[:, i]) <= half_extents[i]`.
#[pyclass(name = "OrientedBox", module = "bvol", frozen)]
pub(crate) struct PyOrientedBox(pub(crate) Obb);

bound_methods! {
    PyOrientedBox,
    /// The centre, a (3,) float32 array.
    #[getter]
    fn center<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        PyArray1::from_slice(py, &self.0.center.to_array())
    }

    /// The unit axes as the columns of a (3, 3) float32 rotation matrix.
    #[getter]
    fn axes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        rows_array(py, &self.0.axes.transpose().to_cols_array_2d())
    }

    /// Half the size along each axis, a (3,) float32 array.
    #[getter]
    fn half_extents<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        PyArray1::from_slice(py, &self.0.half_extents.to_array())
    }

    /// The eight corners, an (8, 3) float32 array: corner `i` on the
    /// positive side of axis 0, 1 and 2 where bit 0, 1 and 2 of `i` are set.
    fn corners<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        vector_array(py, &self.0.corners_f64().map(|c| c.as_vec3()))
    }

    fn __repr__(&self) -> String {
        let o = &self.0;
        format!(
            "OrientedBox(center={:?}, axes={:?}, half_extents={:?})",
            o.center.to_array(),
            o.axes.transpose().to_cols_array_2d(),
            o.half_extents.to_array()
        )
    }
}

/// An axis-aligned box from `min` to `max`.
#[pyclass(name = "Aabb", module = "bvol", frozen)]
pub(crate) struct PyAabb(pub(crate) Aabb);

bound_methods! {
    PyAabb,
    /// The lower corner, a (3,) float32 array.
    #[getter]
    fn min<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        PyArray1::from_slice(py, &self.0.min.to_array())
    }

    /// The upper corner, a (3,) float32 array.
    #[getter]
    fn max<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        PyArray1::from_slice(py, &self.0.max.to_array())
    }

    fn __repr__(&self) -> String {
        format!("Aabb(min={:?}, max={:?})", self.0.min.to_array(), self.0.max.to_array())
    }
}

/// A k-DOP of one of the sizes bvol has.
#[derive(Clone, Copy)]
pub(crate) enum AnyKdop {
    K6(Kdop6),
    K14(Kdop14),
    K18(Kdop18),
    K26(Kdop26),
}

/// Calls `$body` with `$dop` bound to the k-DOP inside `$any`, whatever its size.
macro_rules! with_kdop {
    ($any:expr, $dop:ident => $body:expr) => {
        match $any {
            AnyKdop::K6($dop) => $body,
            AnyKdop::K14($dop) => $body,
            AnyKdop::K18($dop) => $body,
            AnyKdop::K26($dop) => $body,
        }
    };
}

impl AnyKdop {
    fn volume_f64(&self) -> f64 {
        with_kdop!(self, dop => dop.volume_f64())
    }

    fn contains_point(&self, p: Vec3) -> bool {
        with_kdop!(self, dop => dop.contains_point(p))
    }
}

/// A discrete oriented polytope: the points whose projection on each slab
/// direction `directions[i]` lies within `[min[i], max[i]]`.
#[pyclass(name = "Kdop", module = "bvol", frozen)]
pub(crate) struct PyKdop(AnyKdop);

bound_methods! {
    PyKdop,
    /// The number of faces: 6, 14, 18 or 26.
    #[getter]
    fn k(&self) -> usize {
        with_kdop!(&self.0, dop => 2 * dop.min.len())
    }

    /// The slab directions (not normalised), a (k/2, 3) float32 array.
    #[getter]
    fn directions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        let directions: Vec<[f32; 3]> = with_kdop!(&self.0, dop => directions_of(dop));
        rows_array(py, &directions)
    }

    /// The lower bound on each slab, a (k/2,) float32 array.
    #[getter]
    fn min<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        with_kdop!(&self.0, dop => PyArray1::from_slice(py, &dop.min))
    }

    /// The upper bound on each slab, a (k/2,) float32 array.
    #[getter]
    fn max<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        with_kdop!(&self.0, dop => PyArray1::from_slice(py, &dop.max))
    }

    fn __repr__(&self) -> String {
        with_kdop!(&self.0, dop => format!("Kdop(k={}, min={:?}, max={:?})", 2 * dop.min.len(), dop.min, dop.max))
    }
}

/// The slab directions of a k-DOP with `N` slabs, as floats.
fn directions_of<const N: usize>(_: &bvol::volumes::Kdop<N>) -> Vec<[f32; 3]> {
    bvol::volumes::Kdop::<N>::DIRECTIONS.iter().map(|d| d.map(f32::from)).collect()
}

/// `test` on each of the (N, 3) `points`, without the GIL.
fn contains<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    test: impl Fn(Vec3) -> bool + Sync,
) -> PyResult<Bound<'py, PyArray1<bool>>> {
    let points = vectors("points", points)?;
    let points = points.vectors();
    let inside: Vec<bool> = py.detach(|| points.iter().map(|&p| test(p)).collect());
    Ok(PyArray1::from_vec(py, inside))
}

/// Fits with `fit` to the (N, 3) `points`, without the GIL.
fn fitted<'py, T: Send>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    fit: impl FnOnce(&[Vec3]) -> Result<T, FitError> + Send,
) -> PyResult<T> {
    let points = vectors("points", points)?;
    let points = points.vectors();
    py.detach(|| fit(points)).map_err(value_error)
}

/// The bounding sphere of the (N, 3) float32 or float64 `points` (rounded
/// to float32 first), by `method`: "exact" (the minimum sphere), "ritter",
/// "epos6", "epos14", "epos26", "aabb" or "centroid".
#[pyfunction]
#[pyo3(signature = (points, method = "exact"))]
pub(crate) fn bounding_sphere<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    method: &str,
) -> PyResult<PySphere> {
    let method: SphereMethod = method.parse().map_err(value_error)?;
    fitted(py, points, |p| Sphere::fit(p, method)).map(PySphere)
}

/// The oriented bounding box of the (N, 3) `points` (rounded to float32
/// first), by `method`: "min-volume" (near-minimum volume), "dito14",
/// "dito26", "pca-hull" or "pca-points".
#[pyfunction]
#[pyo3(signature = (points, method = "min-volume"))]
pub(crate) fn oriented_box<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    method: &str,
) -> PyResult<PyOrientedBox> {
    let method: ObbMethod = method.parse().map_err(value_error)?;
    fitted(py, points, |p| Obb::fit(p, method)).map(PyOrientedBox)
}

/// The axis-aligned bounding box of the (N, 3) `points` (rounded to
/// float32 first).
#[pyfunction]
pub(crate) fn aabb<'py>(py: Python<'py>, points: &Bound<'py, PyAny>) -> PyResult<PyAabb> {
    fitted(py, points, Aabb::fit).map(PyAabb)
}

/// The k-DOP (k = 6, 14, 18 or 26) of the (N, 3) `points` (rounded to
/// float32 first).
#[pyfunction]
#[pyo3(signature = (points, k = 26))]
pub(crate) fn kdop<'py>(py: Python<'py>, points: &Bound<'py, PyAny>, k: usize) -> PyResult<PyKdop> {
    let dop = match k {
        6 => fitted(py, points, |p| Kdop6::fit(p).map(AnyKdop::K6)),
        14 => fitted(py, points, |p| Kdop14::fit(p).map(AnyKdop::K14)),
        18 => fitted(py, points, |p| Kdop18::fit(p).map(AnyKdop::K18)),
        26 => fitted(py, points, |p| Kdop26::fit(p).map(AnyKdop::K26)),
        _ => Err(PyValueError::new_err(format!("k = {k}: expected 6, 14, 18 or 26"))),
    };
    dop.map(PyKdop)
}

/// The convex hull of the (N, 3) `points` (rounded to float32 first): its
/// vertices, a (V, 3) float32 array, and its faces as triangles of vertex
/// indices, an (F, 3) uint32 array, wound counter-clockwise seen from
/// outside. A flat point set gives its polygon's triangles once for each
/// side; a segment or a point, none.
#[pyfunction]
pub(crate) fn convex_hull<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
) -> PyResult<(Array2<'py, f32>, Array2<'py, u32>)> {
    let (vertices, triangles) = fitted(py, points, |p| {
        let hull = ConvexHull::new(p)?;
        Ok((hull.vertices().to_vec(), hull.triangles().collect::<Vec<_>>()))
    })?;
    Ok((vector_array(py, &vertices), rows_array(py, &triangles)))
}
