//! Meshes read from Wavefront OBJ files.

use std::path::PathBuf;

use numpy::{PyArray2, PyArrayMethods};
use pyo3::prelude::*;

use crate::arrays::{rows_array, vector_array};
use crate::errors::mesh_error;

/// One object of an OBJ file.
#[pyclass(name = "Mesh", module = "bvol", frozen, get_all)]
pub(crate) struct PyMesh {
    /// The object's name in the file, or "unnamed_object".
    name: String,
    /// Vertex positions, an (N, 3) float32 array.
    vertices: Py<PyArray2<f32>>,
    /// Triangles as indices into `vertices`, an (F, 3) uint32 array
    /// (polygons fan-triangulated).
    faces: Py<PyArray2<u32>>,
}

#[pymethods]
impl PyMesh {
    fn __repr__(&self, py: Python<'_>) -> String {
        let (v, f) = (self.vertices.bind(py).dims()[0], self.faces.bind(py).dims()[0]);
        format!("Mesh(name={:?}, {v} vertices, {f} faces)", self.name)
    }
}

/// Every object of the OBJ file at `path`: a list of `Mesh`. Texture
/// coordinates, normals and materials are not read. A file that cannot be
/// read raises `OSError`, one that is not a valid mesh `ValueError`.
#[pyfunction]
pub(crate) fn load_obj(py: Python<'_>, path: PathBuf) -> PyResult<Vec<PyMesh>> {
    let meshes = py.detach(|| bvol::load_obj(&path)).map_err(mesh_error)?;
    Ok(meshes
        .into_iter()
        .map(|m| PyMesh {
            name: m.name,
            vertices: vector_array(py, &m.positions).unbind(),
            faces: rows_array(py, &m.triangles).unbind(),
        })
        .collect())
}
