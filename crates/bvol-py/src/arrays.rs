//! numpy arrays in and out. In: float32 or float64, any strides, the shape
//! checked and named in the error; a C-ordered float32 array is read in
//! place, any other copied once into float32. Out: new arrays the caller
//! owns.

use bvol::glam::{DVec3, Vec3};
use numpy::ndarray::Ix2;
use numpy::{
    PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// A one-dimensional numpy array handed to Python.
pub(crate) type Array1<'py, T> = Bound<'py, PyArray1<T>>;
/// A two-dimensional numpy array handed to Python.
pub(crate) type Array2<'py, T> = Bound<'py, PyArray2<T>>;

/// The values of an `(N, *tail)` float array as float32, in C order.
pub(crate) enum Floats<'py> {
    /// A C-ordered float32 array, read where it is.
    InPlace(PyReadonlyArrayDyn<'py, f32>),
    /// Any other layout or float64: a copy.
    Copied(Vec<f32>),
}

impl Floats<'_> {
    /// Every value, row after row.
    pub(crate) fn values(&self) -> &[f32] {
        match self {
            Floats::InPlace(array) => {
                array.as_slice().expect("a C-ordered array was checked to read as one slice")
            }
            Floats::Copied(values) => values,
        }
    }

    /// The rows of an `(N, 3)` array as vectors.
    pub(crate) fn vectors(&self) -> &[Vec3] {
        bytemuck::cast_slice(self.values())
    }

    /// The rows of an `(N, C)` array.
    pub(crate) fn rows<const C: usize>(&self) -> &[[f32; C]] {
        self.values().as_chunks::<C>().0
    }
}

/// `obj`, named `name` in errors, as an array of shape `(N, *tail)`.
fn shaped<'a, 'py>(
    name: &str,
    obj: &'a Bound<'py, PyAny>,
    tail: &[usize],
) -> PyResult<&'a Bound<'py, PyUntypedArray>> {
    let expected = shape_text(tail);
    let Ok(array) = obj.cast::<PyUntypedArray>() else {
        let given = obj.get_type().name()?;
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a numpy array of shape {expected}, got {given}"
        )));
    };
    let shape = array.shape();
    if shape.len() != tail.len() + 1 || shape[1..] != *tail {
        return Err(PyValueError::new_err(format!(
            "{name}: expected shape {expected}, got {}",
            tuple_text(shape)
        )));
    }
    Ok(array)
}

/// The error for an array of neither float dtype.
fn not_floats(name: &str, array: &Bound<'_, PyUntypedArray>) -> PyErr {
    PyTypeError::new_err(format!(
        "{name}: expected float32 or float64 values, got {}",
        array.dtype()
    ))
}

/// Reads `obj`, named `name` in errors, as a float array of shape
/// `(N, *tail)`.
pub(crate) fn floats<'py>(
    name: &str,
    obj: &Bound<'py, PyAny>,
    tail: &[usize],
) -> PyResult<Floats<'py>> {
    let array = shaped(name, obj, tail)?;
    if let Ok(array) = obj.cast::<PyArrayDyn<f32>>() {
        let array = array.readonly();
        if array.is_c_contiguous() {
            return Ok(Floats::InPlace(array));
        }
        return Ok(Floats::Copied(copied(&array, |v| v)));
    }
    if let Ok(array) = obj.cast::<PyArrayDyn<f64>>() {
        return Ok(Floats::Copied(copied(&array.readonly(), narrow)));
    }
    Err(not_floats(name, array))
}

/// Reads `obj`, named `name` in errors, as an `(N, 3)` float array, each
/// row in f64 (float32 values widened exactly).
pub(crate) fn vectors_f64(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<Vec<DVec3>> {
    let array = shaped(name, obj, &[3])?;
    let values = if let Ok(array) = obj.cast::<PyArrayDyn<f64>>() {
        copied(&array.readonly(), |v| v)
    } else if let Ok(array) = obj.cast::<PyArrayDyn<f32>>() {
        copied(&array.readonly(), f64::from)
    } else {
        return Err(not_floats(name, array));
    };
    Ok(values.as_chunks::<3>().0.iter().map(|&v| DVec3::from_array(v)).collect())
}

/// An `(N, 3)` array of points or vectors.
pub(crate) fn vectors<'py>(name: &str, obj: &Bound<'py, PyAny>) -> PyResult<Floats<'py>> {
    floats(name, obj, &[3])
}

/// Checks that arrays named in `names` have the same number of rows.
pub(crate) fn same_rows(names: &[&str], rows: &[usize]) -> PyResult<usize> {
    let n = rows.first().copied().unwrap_or(0);
    match rows.iter().position(|&m| m != n) {
        None => Ok(n),
        Some(i) => Err(PyValueError::new_err(format!(
            "{} has {} rows but {} has {n}",
            names[i], rows[i], names[0]
        ))),
    }
}

/// Every value of `array` through `f`, in C order: from one slice where the
/// array is C-ordered, else through a two-dimensional view where it has
/// two dimensions (an n-dimensional iterator pays for its generality on
/// every value).
fn copied<T: numpy::Element + Copy, U>(
    array: &PyReadonlyArrayDyn<'_, T>,
    f: impl Fn(T) -> U,
) -> Vec<U> {
    // `as_slice` also takes a Fortran-ordered array, in its memory order.
    if let (true, Ok(values)) = (array.is_c_contiguous(), array.as_slice()) {
        return values.iter().map(|&v| f(v)).collect();
    }
    let view = array.as_array();
    match view.view().into_dimensionality::<Ix2>() {
        Ok(rows) => rows.iter().map(|&v| f(v)).collect(),
        Err(_) => view.iter().map(|&v| f(v)).collect(),
    }
}

/// f64 to f32, keeping a finite value beyond f32's range finite (at f32's
/// largest), so that the range check calls it out of range rather than
/// infinite.
fn narrow(v: f64) -> f32 {
    let f = v as f32;
    if f.is_infinite() && v.is_finite() { f32::MAX.copysign(f) } else { f }
}

/// `(N, 3)` for a tail of `[3]`.
fn shape_text(tail: &[usize]) -> String {
    let dims: Vec<String> =
        std::iter::once("N".to_string()).chain(tail.iter().map(usize::to_string)).collect();
    tuple_text(&dims)
}

/// Python's way of writing a shape: `(5,)`, `(5, 2)`.
fn tuple_text(dims: &[impl ToString]) -> String {
    let dims: Vec<String> = dims.iter().map(ToString::to_string).collect();
    match dims.as_slice() {
        [one] => format!("({one},)"),
        _ => format!("({})", dims.join(", ")),
    }
}

/// Vectors as an `(N, 3)` float32 array.
pub(crate) fn vector_array<'py>(py: Python<'py>, vectors: &[Vec3]) -> Bound<'py, PyArray2<f32>> {
    rows_array(py, bytemuck::cast_slice::<Vec3, [f32; 3]>(vectors))
}

/// Rows as an `(N, C)` array.
pub(crate) fn rows_array<'py, T: numpy::Element + Copy, const C: usize>(
    py: Python<'py>,
    rows: &[[T; C]],
) -> Bound<'py, PyArray2<T>> {
    let flat = PyArray1::from_slice(py, rows.as_flattened());
    flat.reshape([rows.len(), C]).expect("N * C values make an (N, C) array")
}

/// Reads `obj`, named `name` in errors, as a one-dimensional array of
/// non-negative integers (any integer dtype).
pub(crate) fn integers(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<Vec<u64>> {
    let Ok(array) = obj.cast::<PyUntypedArray>() else {
        let given = obj.get_type().name()?;
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a numpy array of shape (N,), got {given}"
        )));
    };
    if array.ndim() != 1 {
        return Err(PyValueError::new_err(format!(
            "{name}: expected shape (N,), got {}",
            tuple_text(array.shape())
        )));
    }
    let values = widened::<u64>(obj)
        .or_else(|| widened::<i64>(obj))
        .or_else(|| widened::<u32>(obj))
        .or_else(|| widened::<i32>(obj))
        .ok_or_else(|| {
            PyTypeError::new_err(format!("{name}: expected integers, got {}", array.dtype()))
        })?;
    values
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            u64::try_from(v)
                .map_err(|_| PyValueError::new_err(format!("{name}[{i}] = {v}: negative")))
        })
        .collect()
}

/// The values of `obj` if it is a one-dimensional array of `T`, each
/// widened to `i128`, which holds every integer dtype read here.
fn widened<T: numpy::Element + Copy + Into<i128>>(obj: &Bound<'_, PyAny>) -> Option<Vec<i128>> {
    let array = obj.cast::<PyArray1<T>>().ok()?;
    Some(array.readonly().as_array().iter().map(|&v| v.into()).collect())
}
