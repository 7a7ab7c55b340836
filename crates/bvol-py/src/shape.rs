//! Shapes: a body's geometry, made once and shared by any number of bodies.

use std::path::PathBuf;
use std::sync::Arc;

use bvol::glam::Vec3;
use bvol::volumes::{ObbMethod, SphereMethod};
use bvol::{FitOptions, Shape};
use numpy::PyArray1;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::arrays::vectors;
use crate::errors::{shape_error, value_error};
use crate::fit::{PyOrientedBox, PySphere};

/// A body's geometry in its own frame: convex parts, with the bounding
/// sphere and oriented box of all of them. Made by `Shape.box`,
/// `Shape.sphere`, `Shape.capsule`, `Shape.convex` or `Shape.from_obj`, and
/// shared by every body given it.
#[pyclass(name = "Shape", module = "bvol", frozen)]
#[derive(Clone)]
pub(crate) struct PyShape(pub(crate) Arc<Shape>);

#[pymethods]
impl PyShape {
    /// A box centred on the origin, of the given (3,) half extents.
    #[staticmethod]
    #[pyo3(name = "box")]
    fn cuboid(half_extents: [f32; 3]) -> PyResult<Self> {
        Self::made(Shape::cuboid(Vec3::from_array(half_extents)))
    }

    /// A ball of `radius` centred on the origin.
    #[staticmethod]
    fn sphere(radius: f32) -> PyResult<Self> {
        Self::made(Shape::ball(radius))
    }

    /// A capsule along y: a segment from -half_height to half_height swept by
    /// a ball of `radius`.
    #[staticmethod]
    fn capsule(radius: f32, half_height: f32) -> PyResult<Self> {
        Self::made(Shape::capsule(radius, half_height))
    }

    /// The convex hull of the (N, 3) `points`; flat points are made a thin
    /// slab.
    #[staticmethod]
    fn convex(py: Python<'_>, points: &Bound<'_, PyAny>) -> PyResult<Self> {
        let points = vectors("points", points)?;
        let points = points.vectors();
        Self::made(py.detach(|| Shape::convex(points)))
    }

    /// Every object of a Wavefront OBJ file, one convex part each, its
    /// bounds fitted by `sphere_method` and `obb_method` (see
    /// `bounding_sphere` and `oriented_box`).
    #[staticmethod]
    #[pyo3(signature = (path, sphere_method = "exact", obb_method = "min-volume"))]
    fn from_obj(
        py: Python<'_>,
        path: PathBuf,
        sphere_method: &str,
        obb_method: &str,
    ) -> PyResult<Self> {
        let sphere: SphereMethod = sphere_method.parse().map_err(value_error)?;
        let obb: ObbMethod = obb_method.parse().map_err(value_error)?;
        let shape = py.detach(|| Shape::from_obj(&path, FitOptions { sphere, obb }));
        Self::made(shape)
    }

    /// The same shape scaled by `factor`: one number, or three, one per axis
    /// (a ball or capsule only uniformly).
    fn scaled(&self, factor: &Bound<'_, PyAny>) -> PyResult<Self> {
        let factor =
            match factor.extract::<f32>() {
                Ok(uniform) => Vec3::splat(uniform),
                Err(_) => Vec3::from_array(factor.extract::<[f32; 3]>().map_err(|_| {
                    PyTypeError::new_err("factor: expected a number or three numbers")
                })?),
            };
        Self::made(self.0.scaled(factor))
    }

    /// The shape's bounding sphere, in its own frame.
    #[getter]
    fn bounding_sphere(&self) -> PySphere {
        PySphere(self.0.sphere())
    }

    /// The shape's oriented bounding box, in its own frame.
    #[getter]
    fn oriented_box(&self) -> PyOrientedBox {
        PyOrientedBox(self.0.obb())
    }

    /// The volume enclosed.
    #[getter]
    fn volume(&self) -> f32 {
        self.0.mass_properties().volume
    }

    /// The centre of mass at uniform density, a (3,) float32 array.
    #[getter]
    fn center_of_mass<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        PyArray1::from_slice(py, &self.0.mass_properties().center.to_array())
    }

    fn __repr__(&self) -> String {
        format!("Shape(parts={}, volume={})", self.0.parts().len(), self.volume())
    }
}

impl PyShape {
    fn made(shape: Result<Shape, bvol::ShapeError>) -> PyResult<Self> {
        shape.map(|s| PyShape(Arc::new(s))).map_err(shape_error)
    }

    /// The shape a body is given as: exactly one of `vertices` (an (N, 3)
    /// array whose hull it is), `primitive` (`("box", half_extents)`,
    /// `("sphere", radius)` or `("capsule", radius, half_height)`) or
    /// `shape`.
    pub(crate) fn of_body(
        py: Python<'_>,
        vertices: Option<&Bound<'_, PyAny>>,
        primitive: Option<&Bound<'_, PyTuple>>,
        shape: Option<&PyShape>,
    ) -> PyResult<PyShape> {
        match (vertices, primitive, shape) {
            (Some(v), None, None) => Self::convex(py, v),
            (None, Some(p), None) => Self::primitive(p),
            (None, None, Some(s)) => Ok(s.clone()),
            _ => Err(PyValueError::new_err(
                "give a body exactly one of vertices=, primitive= or shape=",
            )),
        }
    }

    /// A shape from `("box", half_extents)`, `("sphere", radius)` or
    /// `("capsule", radius, half_height)`.
    fn primitive(spec: &Bound<'_, PyTuple>) -> PyResult<PyShape> {
        let bad = || {
            PyValueError::new_err(format!(
                "primitive={spec}: expected (\"box\", half_extents), (\"sphere\", radius) \
                 or (\"capsule\", radius, half_height)"
            ))
        };
        let kind: String = spec.get_item(0).and_then(|k| k.extract()).map_err(|_| bad())?;
        let args = spec.get_slice(1, spec.len());
        match kind.as_str() {
            "box" => Self::cuboid(args.extract::<([f32; 3],)>().map_err(|_| bad())?.0),
            "sphere" => Self::sphere(args.extract::<(f32,)>().map_err(|_| bad())?.0),
            "capsule" => {
                let (radius, half_height) = args.extract::<(f32, f32)>().map_err(|_| bad())?;
                Self::capsule(radius, half_height)
            }
            _ => Err(bad()),
        }
    }
}
