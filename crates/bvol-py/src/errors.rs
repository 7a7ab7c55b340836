//! bvol's errors as Python exceptions, with the Rust API's one-line
//! messages: unknown bodies are `KeyError`, files that cannot be read
//! `OSError`, every other bad value `ValueError`.

use std::fmt::Display;

use bvol::{MeshError, MeshProblem, ShapeError, WorldError};
use pyo3::PyErr;
use pyo3::exceptions::{PyKeyError, PyOSError, PyValueError};

/// A `ValueError` saying `error`.
pub(crate) fn value_error(error: impl Display) -> PyErr {
    PyValueError::new_err(error.to_string())
}

/// A world call's error.
pub(crate) fn world_error(error: WorldError) -> PyErr {
    match error {
        WorldError::UnknownBody(_) => PyKeyError::new_err(error.to_string()),
        _ => value_error(error),
    }
}

/// A mesh file's error.
pub(crate) fn mesh_error(error: MeshError) -> PyErr {
    match error.problem {
        MeshProblem::Read(_) | MeshProblem::NotAFile => PyOSError::new_err(error.to_string()),
        _ => value_error(error),
    }
}

/// A shape's error.
pub(crate) fn shape_error(error: ShapeError) -> PyErr {
    match error {
        ShapeError::Mesh(error) => mesh_error(error),
        _ => value_error(error),
    }
}
