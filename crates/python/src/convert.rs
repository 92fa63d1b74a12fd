//! NumPy ↔ nalgebra conversions shared by every facet: any real dtype (float16/32/64,
//! longdouble, integers, booleans), any memory order and strides, nested lists and Python
//! scalars in; `float64` (or `complex128`) C-ordered arrays out. Shapes and finiteness are
//! checked with errors that name the argument ([`crate::errors`]).
//!
//! Input rules (python-control's `_ssmatrix` conventions):
//!
//! | input | [`matrix`] | [`vector`] |
//! |---|---|---|
//! | 0-d (a number) | 1 × 1 | length 1 |
//! | 1-d of length n | 1 × n ([`OneD::Row`]) or n × 1 ([`OneD::Column`]) | length n |
//! | 2-d r × c | r × c | length r·c if r = 1 or c = 1, else a `ShapeError` |
//! | ≥ 3-d | `ShapeError` | `ShapeError` |
//!
//! Complex input is refused (`InvalidArgumentError`) rather than silently dropping the
//! imaginary part; NaN and ±Inf are refused (`NotFiniteError`, naming the entry). Count
//! arguments (orders, horizons, numbers of samples, steps or threads) go through [`count`].

use crate::errors::{Kind, new_err};
use nalgebra::{DMatrix, DVector};
use numpy::ndarray::{Array2, Array3};
use numpy::{
    Complex64, IntoPyArray, PyArray1, PyArray2, PyArray3, PyArrayDescrMethods, PyArrayDyn,
    PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyFloat, PyInt};

/// How [`matrix`] shapes a 1-d input of length n.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OneD {
    /// A 1 × n row (python-control's default, e.g. for `C` and `D`).
    Row,
    /// An n × 1 column (e.g. `B` of a single-input system).
    Column,
}

static ASARRAY: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
static FLOAT64: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

/// `numpy.asarray(obj, dtype=numpy.<dtype_name>)` (the dtype object cached in `dtype`).
///
/// # Errors
/// `InvalidArgumentError` "`what` cannot be read as `as_what`: <NumPy's message>".
fn asarray<'py>(
    obj: &Bound<'py, PyAny>,
    dtype: &PyOnceLock<Py<PyAny>>,
    dtype_name: &str,
    what: &str,
    as_what: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let py = obj.py();
    let asarray = ASARRAY.get_or_try_init(py, || -> PyResult<Py<PyAny>> {
        Ok(py.import("numpy")?.getattr("asarray")?.unbind())
    })?;
    let dtype = dtype.get_or_try_init(py, || -> PyResult<Py<PyAny>> {
        Ok(py.import("numpy")?.getattr(dtype_name)?.unbind())
    })?;
    asarray.bind(py).call1((obj, dtype.bind(py))).map_err(|e| {
        new_err(
            Kind::InvalidArgument,
            format!("{what} cannot be read as {as_what}: {}", e.value(py)),
            None,
        )
    })
}

/// `obj` as a `float64` NumPy array: itself if it already is one, else
/// `numpy.asarray(obj, dtype=float64)`.
///
/// # Errors
/// `InvalidArgumentError` naming `what` if `obj` is complex or NumPy cannot convert it.
pub fn float_array<'py>(
    obj: &Bound<'py, PyAny>,
    what: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    if let Ok(a) = obj.cast::<PyArrayDyn<f64>>() {
        return Ok(a.clone());
    }
    if let Ok(a) = obj.cast::<PyUntypedArray>() {
        let kind = a.dtype().kind();
        if kind == b'c' {
            return Err(new_err(
                Kind::InvalidArgument,
                format!(
                    "{what} must be real, got a complex array (dtype {})",
                    a.dtype()
                ),
                None,
            ));
        }
    }
    let converted = asarray(obj, &FLOAT64, "float64", what, "a real array")?;
    converted.cast_into::<PyArrayDyn<f64>>().map_err(|e| {
        new_err(
            Kind::InvalidArgument,
            format!("{what} cannot be read as a real array: {e}"),
            None,
        )
    })
}

fn not_finite(what: &str, row: usize, col: usize, value: f64) -> PyErr {
    new_err(
        Kind::NotFinite,
        format!("{what} has a non-finite entry {value} at row {row}, column {col} (0-based)"),
        Some("NonFinite"),
    )
}

fn too_many_dims(what: &str, shape: &[usize], at_most: &str) -> PyErr {
    new_err(
        Kind::Shape,
        format!(
            "{what} must be {at_most}, got an array of {} dimensions with shape {shape:?}",
            shape.len()
        ),
        None,
    )
}

/// `obj` (0-d, 1-d or 2-d) as an `f64` matrix; a 1-d input is shaped by `one_d`.
///
/// # Errors
/// `ShapeError` for three or more dimensions, `NotFiniteError` for NaN/±Inf (naming row and
/// column of the matrix), `InvalidArgumentError` for complex or unconvertible input; each
/// message starts with `what`.
pub fn matrix(obj: &Bound<'_, PyAny>, what: &str, one_d: OneD) -> PyResult<DMatrix<f64>> {
    if obj.is_exact_instance_of::<PyFloat>() || obj.is_exact_instance_of::<PyInt>() {
        let v: f64 = obj.extract()?;
        if !v.is_finite() {
            return Err(not_finite(what, 0, 0, v));
        }
        return Ok(DMatrix::from_element(1, 1, v));
    }
    let array = float_array(obj, what)?;
    let readonly = array.try_readonly().map_err(|e| {
        new_err(
            Kind::InvalidArgument,
            format!("{what} cannot be read: {e}"),
            None,
        )
    })?;
    let view = readonly.as_array();
    let shape = view.shape().to_vec();
    let (rows, cols) = match (shape.len(), one_d) {
        (0, _) => (1, 1),
        (1, OneD::Row) => (1, shape[0]),
        (1, OneD::Column) => (shape[0], 1),
        (2, _) => (shape[0], shape[1]),
        _ => {
            return Err(too_many_dims(
                what,
                &shape,
                "a matrix (at most 2 dimensions)",
            ));
        }
    };
    // `iter` walks the array in logical (row-major) order whatever its memory layout.
    let mut data = Vec::with_capacity(rows * cols);
    for (k, &x) in view.iter().enumerate() {
        if !x.is_finite() {
            return Err(not_finite(what, k / cols, k % cols, x));
        }
        data.push(x);
    }
    Ok(DMatrix::from_row_slice(rows, cols, &data))
}

/// `obj` (0-d, 1-d, or 2-d with one row or one column) as an `f64` vector.
///
/// # Errors
/// `ShapeError` for a 2-d input with more than one row and column or ≥ 3 dimensions,
/// `NotFiniteError` for NaN/±Inf (naming the index), `InvalidArgumentError` for complex or
/// unconvertible input; each message starts with `what`.
pub fn vector(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<DVector<f64>> {
    if obj.is_exact_instance_of::<PyFloat>() || obj.is_exact_instance_of::<PyInt>() {
        let v: f64 = obj.extract()?;
        if !v.is_finite() {
            return Err(not_finite_at(what, 0, v));
        }
        return Ok(DVector::from_element(1, v));
    }
    let array = float_array(obj, what)?;
    let readonly = array.try_readonly().map_err(|e| {
        new_err(
            Kind::InvalidArgument,
            format!("{what} cannot be read: {e}"),
            None,
        )
    })?;
    let view = readonly.as_array();
    let shape = view.shape();
    let ok = match shape.len() {
        0 | 1 => true,
        2 => shape[0] <= 1 || shape[1] <= 1,
        _ => false,
    };
    if !ok {
        return Err(too_many_dims(
            what,
            shape,
            "a vector (0-d, 1-d, or 2-d with one row or one column)",
        ));
    }
    let data: Vec<f64> = view.iter().copied().collect();
    if let Some((k, v)) = data.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(not_finite_at(what, k, *v));
    }
    Ok(DVector::from_vec(data))
}

fn not_finite_at(what: &str, index: usize, value: f64) -> PyErr {
    new_err(
        Kind::NotFinite,
        format!("{what} has a non-finite entry {value} at index {index} (0-based)"),
        Some("NonFinite"),
    )
}

/// `m` as a C-ordered `float64` array of shape `(rows, cols)`.
pub fn matrix_to_numpy<'py>(py: Python<'py>, m: &DMatrix<f64>) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_fn((m.nrows(), m.ncols()), |(i, j)| m[(i, j)]).into_pyarray(py)
}

/// `v` as a 1-d `float64` array.
pub fn vector_to_numpy<'py>(py: Python<'py>, v: &DVector<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v.as_slice())
}

/// `v` as a 1-d `float64` array.
pub fn slice_to_numpy<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v)
}

/// Complex values as a 1-d `complex128` array.
pub fn complex_to_numpy<'py>(py: Python<'py>, v: &[Complex64]) -> Bound<'py, PyArray1<Complex64>> {
    PyArray1::from_slice(py, v)
}

/// A complex matrix as a C-ordered `complex128` array of shape `(rows, cols)`.
pub fn complex_matrix_to_numpy<'py>(
    py: Python<'py>,
    m: &DMatrix<Complex64>,
) -> Bound<'py, PyArray2<Complex64>> {
    Array2::from_shape_fn((m.nrows(), m.ncols()), |(i, j)| m[(i, j)]).into_pyarray(py)
}

/// A `(d0, d1, d2)` `float64` array with entries `f(i, j, k)` (e.g. outputs × inputs × times).
pub fn array3_to_numpy<'py>(
    py: Python<'py>,
    shape: (usize, usize, usize),
    f: impl FnMut((usize, usize, usize)) -> f64,
) -> Bound<'py, PyArray3<f64>> {
    Array3::from_shape_fn(shape, f).into_pyarray(py)
}

/// A `(d0, d1, d2)` `complex128` array with entries `f(i, j, k)` (e.g. outputs × inputs ×
/// frequencies).
pub fn complex_array3_to_numpy<'py>(
    py: Python<'py>,
    shape: (usize, usize, usize),
    f: impl FnMut((usize, usize, usize)) -> Complex64,
) -> Bound<'py, PyArray3<Complex64>> {
    Array3::from_shape_fn(shape, f).into_pyarray(py)
}

static COMPLEX128: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

/// `obj` (a number, a 1-d sequence or array of real or complex numbers) as complex values,
/// e.g. the poles requested from `place`.
///
/// # Errors
/// `ShapeError` for ≥ 2 dimensions, `NotFiniteError` for NaN/±Inf parts (naming the index),
/// `InvalidArgumentError` if NumPy cannot read `obj` as complex numbers; messages start with
/// `what`.
pub fn complex_vector(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Complex64>> {
    let converted = asarray(obj, &COMPLEX128, "complex128", what, "complex numbers")?;
    let array = converted
        .cast_into::<PyArrayDyn<Complex64>>()
        .map_err(|e| new_err(Kind::InvalidArgument, format!("{what}: {e}"), None))?;
    if array.ndim() > 1 {
        return Err(too_many_dims(what, array.shape(), "a 1-d sequence"));
    }
    let readonly = array
        .try_readonly()
        .map_err(|e| new_err(Kind::InvalidArgument, format!("{what}: {e}"), None))?;
    let values: Vec<Complex64> = readonly.as_array().iter().copied().collect();
    if let Some((k, v)) = values
        .iter()
        .enumerate()
        .find(|(_, v)| !(v.re.is_finite() && v.im.is_finite()))
    {
        return Err(new_err(
            Kind::NotFinite,
            format!("{what} has a non-finite entry {v} at index {k} (0-based)"),
            Some("NonFinite"),
        ));
    }
    Ok(values)
}

/// A count argument (an order, a horizon, a number of samples, steps or threads), for
/// `#[pyo3(from_py_with = count)]`: a Python integer ≥ 0. A negative one raises
/// `pendulab.InvalidArgumentError` rather than the `OverflowError` of a plain unsigned
/// argument (PyO3 notes the argument's name on either error); a non-integer raises
/// `TypeError`.
pub fn count(obj: &Bound<'_, PyAny>) -> PyResult<usize> {
    if let Ok(v) = obj.extract::<i64>()
        && v < 0
    {
        return Err(new_err(
            Kind::InvalidArgument,
            format!("expected an integer ≥ 0, got {v}"),
            None,
        ));
    }
    obj.extract()
}

/// [`count`] for an optional argument: `None` stays `None`.
pub fn optional_count(obj: &Bound<'_, PyAny>) -> PyResult<Option<usize>> {
    if obj.is_none() {
        Ok(None)
    } else {
        count(obj).map(Some)
    }
}
