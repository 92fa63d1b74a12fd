//! The recursive filters of `pendulab_control::kalman` behind `pendulab.control`:
//!
//! | Python (`_native`) | Rust |
//! |---|---|
//! | `KalmanFilter(x0, P0)`: `predict(A, B, u, Q)`, `update(C, y, R, D, u)` | `KalmanFilter` |
//! | `NonlinearFilter(kind, sys, ts, x0, P0, Q, R, …)` (`"ekf"`, `"ukf"`) | `ExtendedKalmanFilter`, `UnscentedKalmanFilter` on a `SampledModel` of a [`Model`] |
//! | `control_filter_log(filter, t, u, y)` | `filter_log` |
//! | `control_encoder_covariance(q)`, `control_quantization_variance(q)`, `control_nees(x, x̂, P)` | the same names |
//!
//! Updates return a dict `residual` (`ν = y − ŷ`), `S` (innovation covariance), `K` (gain),
//! `nis` (`νᵀS⁻¹ν`). Units are the model's (SI, rad, V); covariances are per sample.

use nalgebra::DMatrix;
use pendulab_control::kalman::{
    ExtendedKalmanFilter, Innovation, KalmanFilter, Measurement, NonlinearFilter, SampledModel,
    SigmaPoints, UnscentedKalmanFilter, encoder_covariance, filter_log, nees,
    quantization_variance,
};
use pendulab_sim::Dynamics;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::{ce, control_error};
use crate::callable::{ErrorSlot, Model};
use crate::convert::{
    OneD, count, matrix, matrix_to_numpy, optional_count, slice_to_numpy, vector,
};
use crate::errors::{Kind, new_err};

/// An [`Innovation`] as the dict the module documentation describes.
fn innovation<'py>(py: Python<'py>, inn: &Innovation) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("residual", slice_to_numpy(py, &inn.residual))?;
    d.set_item("S", matrix_to_numpy(py, &inn.covariance))?;
    d.set_item("K", matrix_to_numpy(py, &inn.gain))?;
    d.set_item("nis", inn.nis)?;
    Ok(d)
}

fn vec_of(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    Ok(vector(obj, what)?.as_slice().to_vec())
}

fn square(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<DMatrix<f64>> {
    matrix(obj, what, OneD::Row)
}

/// The time-varying linear Kalman filter (`pendulab_control::kalman::KalmanFilter`).
#[pyclass(name = "KalmanFilter", module = "pendulab._native")]
pub struct NativeKalmanFilter {
    inner: KalmanFilter,
}

#[pymethods]
impl NativeKalmanFilter {
    /// The filter from the estimate `x0` and its covariance `P0` (positive definite).
    #[new]
    #[allow(non_snake_case)]
    fn new(x0: &Bound<'_, PyAny>, P0: &Bound<'_, PyAny>) -> PyResult<Self> {
        let x = vec_of(x0, "x0")?;
        let p = square(P0, "P0")?;
        Ok(Self {
            inner: ce(KalmanFilter::new(&x, &p))?,
        })
    }

    /// `x̄ = A x̂ + B u`, `P̄ = A P Aᵀ + Q` (`B = None`: no input).
    #[pyo3(signature = (A, B, u, Q))]
    #[allow(non_snake_case)]
    fn predict(
        &mut self,
        A: &Bound<'_, PyAny>,
        B: Option<&Bound<'_, PyAny>>,
        u: Option<&Bound<'_, PyAny>>,
        Q: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let a = square(A, "A")?;
        let (b, u) = match (B, u) {
            (Some(b), Some(u)) => (matrix(b, "B", OneD::Column)?, vec_of(u, "u")?),
            (None, None) => (DMatrix::zeros(a.nrows(), 0), Vec::new()),
            _ => {
                return Err(new_err(
                    Kind::InvalidArgument,
                    "predict: give both B and u, or neither".into(),
                    None,
                ));
            }
        };
        let q = square(Q, "Q")?;
        ce(self.inner.predict(&a, &b, &u, &q))
    }

    /// The update with `y = C x + D u + v`, `v ~ N(0, R)`; returns the innovation dict.
    #[pyo3(signature = (C, y, R, D = None, u = None))]
    #[allow(non_snake_case)]
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        C: &Bound<'py, PyAny>,
        y: &Bound<'py, PyAny>,
        R: &Bound<'py, PyAny>,
        D: Option<&Bound<'py, PyAny>>,
        u: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let c = square(C, "C")?;
        let yv = vec_of(y, "y")?;
        let r = square(R, "R")?;
        let du = match (D, u) {
            (Some(d), Some(u)) => Some((matrix(d, "D", OneD::Row)?, vec_of(u, "u")?)),
            (None, None) => None,
            _ => {
                return Err(new_err(
                    Kind::InvalidArgument,
                    "update: give both D and u, or neither".into(),
                    None,
                ));
            }
        };
        let inn = ce(self
            .inner
            .update(&c, du.as_ref().map(|(d, u)| (d, u.as_slice())), &yv, &r))?;
        innovation(py, &inn)
    }

    /// The estimate `x̂`.
    #[getter]
    fn x<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        slice_to_numpy(py, self.inner.state())
    }

    /// The error covariance `P`.
    #[getter]
    #[allow(non_snake_case)]
    fn P<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        matrix_to_numpy(py, self.inner.covariance())
    }
}

/// The extended or unscented Kalman filter of a [`Model`] (`pendulab_control::kalman`).
#[pyclass(name = "NonlinearFilter", module = "pendulab._native", unsendable)]
pub struct NativeNonlinearFilter {
    filter: Box<dyn NonlinearFilter>,
    errors: ErrorSlot,
    dims: (usize, usize, usize),
}

impl NativeNonlinearFilter {
    /// Runs `f` on the filter; a callable's recorded failure takes precedence.
    fn run<T>(
        &mut self,
        f: impl FnOnce(&mut dyn NonlinearFilter) -> pendulab_control::Result<T>,
    ) -> PyResult<T> {
        self.errors.clear();
        let r = f(self.filter.as_mut());
        self.errors.or(r, control_error)
    }
}

#[pymethods]
impl NativeNonlinearFilter {
    /// `kind` `"ekf"` or `"ukf"` of `sys` (a plant, `"cart"`/`"arm"`, or a callable `f(x, u)`
    /// with `nu` inputs and the output map `h`) sampled at `ts` (s) with `substeps` RK4 steps
    /// per sample; `measured` lists the measured states (default for the plants: the encoders
    /// `[0, 1]`; for a callable, `h` is measured if `measured` is not given).
    #[new]
    #[pyo3(signature = (kind, sys, ts, x0, P0, Q, R, measured = None, h = None, nu = None,
        substeps = 1, alpha = 1.0, beta = 2.0, kappa = 0.0))]
    #[allow(non_snake_case, clippy::too_many_arguments)]
    fn new(
        kind: &str,
        sys: &Bound<'_, PyAny>,
        ts: f64,
        x0: &Bound<'_, PyAny>,
        P0: &Bound<'_, PyAny>,
        Q: &Bound<'_, PyAny>,
        R: &Bound<'_, PyAny>,
        measured: Option<Vec<usize>>,
        h: Option<&Bound<'_, PyAny>>,
        #[pyo3(from_py_with = optional_count)] nu: Option<usize>,
        #[pyo3(from_py_with = count)] substeps: usize,
        alpha: f64,
        beta: f64,
        kappa: f64,
    ) -> PyResult<Self> {
        let x = vec_of(x0, "x0")?;
        let p0 = square(P0, "P0")?;
        let q = square(Q, "Q")?;
        let r = square(R, "R")?;
        let model = Model::from_py(sys, h, &x, &vec![0.0; nu.unwrap_or(0)])?;
        if let Some(n) = nu
            && n != model.nu()
        {
            return Err(new_err(
                Kind::InvalidArgument,
                format!("nu = {n}: the plant has {} input(s)", model.nu()),
                None,
            ));
        }
        let measurement = match (measured, &model) {
            (Some(idx), _) => Measurement::States(idx),
            (None, Model::Callable(_)) if h.is_some() => Measurement::Output,
            (None, Model::Callable(_)) => {
                return Err(new_err(
                    Kind::InvalidArgument,
                    "give the measured states (measured=[...]) or the output map h".into(),
                    None,
                ));
            }
            (None, _) => Measurement::States(vec![0, 1]),
        };
        let errors = model.errors();
        let dims = (model.nx(), model.nu(), 0);
        let sampled = ce(SampledModel::new(model, ts, substeps, measurement, &q, &r))?;
        let dims = (dims.0, dims.1, sampled.ny());
        let filter: Box<dyn NonlinearFilter> = match kind {
            "ekf" => Box::new(ce(ExtendedKalmanFilter::new(sampled, &x, &p0))?),
            "ukf" => {
                let sigma = SigmaPoints { alpha, beta, kappa };
                Box::new(ce(UnscentedKalmanFilter::new(sampled, &x, &p0, sigma))?)
            }
            other => {
                return Err(new_err(
                    Kind::InvalidArgument,
                    format!("kind {other:?}: expected \"ekf\" or \"ukf\""),
                    None,
                ));
            }
        };
        Ok(Self {
            filter,
            errors,
            dims,
        })
    }

    /// Prediction over one sample from `t` (s) with the input `u` held.
    fn predict(&mut self, t: f64, u: &Bound<'_, PyAny>) -> PyResult<()> {
        let u = vec_of(u, "u")?;
        self.run(|f| f.predict(t, &u))
    }

    /// The update with the measurement `y` taken at `t` (the input `u` acting then); returns
    /// the innovation dict.
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        t: f64,
        u: &Bound<'py, PyAny>,
        y: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let u = vec_of(u, "u")?;
        let y = vec_of(y, "y")?;
        let inn = self.run(|f| f.update(t, &u, &y))?;
        innovation(py, &inn)
    }

    /// The estimate `x̂`.
    #[getter]
    fn x<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        slice_to_numpy(py, self.filter.state())
    }

    /// The error covariance `P`.
    #[getter]
    #[allow(non_snake_case)]
    fn P<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        matrix_to_numpy(py, self.filter.covariance())
    }

    /// The sample time (s).
    #[getter]
    fn ts(&self) -> f64 {
        self.filter.ts()
    }

    /// `(nx, nu, ny)`: states, inputs, measured values.
    #[getter]
    fn dims(&self) -> (usize, usize, usize) {
        self.dims
    }
}

/// Rows of `obj` (one per sample; a 1-d array is one value per sample) as vectors of `width`.
fn rows(
    obj: &Bound<'_, PyAny>,
    what: &str,
    samples: usize,
    width: usize,
) -> PyResult<Vec<Vec<f64>>> {
    let m = matrix(obj, what, OneD::Column)?;
    if m.nrows() != samples || m.ncols() != width {
        return Err(new_err(
            Kind::Shape,
            format!(
                "{what} must have one row of {width} per sample ({samples} × {width}), got {} × {}",
                m.nrows(),
                m.ncols()
            ),
            None,
        ));
    }
    Ok((0..samples)
        .map(|k| m.row(k).iter().copied().collect())
        .collect())
}

/// `control_filter_log(filter, t, u, y)`: `filter_log` — the first sample an update only,
/// each later one a prediction from the previous sample then the update. Returns a dict
/// `states` (N × nx, after each update), `variances` (N × nx, the diagonal of `P`), `nis` (N).
#[pyfunction]
pub fn control_filter_log<'py>(
    py: Python<'py>,
    filter: &mut NativeNonlinearFilter,
    t: &Bound<'py, PyAny>,
    u: &Bound<'py, PyAny>,
    y: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let t = vec_of(t, "t")?;
    let (nx, nu, ny) = filter.dims;
    let u = rows(u, "u", t.len(), nu)?;
    let y = rows(y, "y", t.len(), ny)?;
    let run = filter.run(|f| filter_log(f, &t, &u, &y))?;
    let table = |v: &[Vec<f64>]| DMatrix::from_fn(v.len(), nx, |i, j| v[i][j]);
    let d = PyDict::new(py);
    d.set_item("states", matrix_to_numpy(py, &table(&run.states)))?;
    d.set_item("variances", matrix_to_numpy(py, &table(&run.variances)))?;
    d.set_item("nis", slice_to_numpy(py, &run.nis))?;
    Ok(d)
}

/// `control_quantization_variance(q)`: `q²/12` for the encoder resolution `q`.
#[pyfunction]
pub fn control_quantization_variance(q: f64) -> PyResult<f64> {
    ce(quantization_variance(q))
}

/// `control_encoder_covariance(q)`: `diag(q_i²/12)` for the resolutions `q`.
#[pyfunction]
pub fn control_encoder_covariance<'py>(
    py: Python<'py>,
    q: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
    let q = vec_of(q, "q")?;
    Ok(matrix_to_numpy(py, &ce(encoder_covariance(&q))?))
}

/// `control_nees(x_true, x_hat, P)`: `(x − x̂)ᵀ P⁻¹ (x − x̂)`.
#[pyfunction]
#[allow(non_snake_case)]
pub fn control_nees(
    x_true: &Bound<'_, PyAny>,
    x_hat: &Bound<'_, PyAny>,
    P: &Bound<'_, PyAny>,
) -> PyResult<f64> {
    let x = vec_of(x_true, "x_true")?;
    let xh = vec_of(x_hat, "x_hat")?;
    ce(nees(&x, &xh, &square(P, "P")?))
}
