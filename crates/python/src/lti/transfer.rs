//! `pendulab.pade`, `pendulab.thiran` and the MIMO `pendulab.TransferMatrix` (what `tf`
//! returns for lists of lists of coefficients, or for a MIMO state-space system).
//!
//! A `TransferMatrix` supports `+ - * /` and unary `-` with another `TransferMatrix`, a
//! `TransferFunction`, any system `pendulab.StateSpace` accepts, or a number (a `1 × 1`
//! gain); `*` is the matrix product (a `1 × 1` factor scales), `/` is right division
//! `G H⁻¹` (see pendulab-lti's `transfer_matrix`). Shape and sample-time mismatches raise
//! `pendulab.ShapeError` / `pendulab.InvalidArgumentError`, never crash.

use super::nogil;
use super::system::{StateSpace, Sys, TfSys, TransferFunction, system};
use crate::convert::{
    complex_matrix_to_numpy, complex_to_numpy, count, optional_count, slice_to_numpy,
};
use crate::errors::{Kind, lti, new_err};
use pendulab_lti::delay;
use pendulab_lti::{Complex64, Continuous, Discrete, FeedbackSign, Mat, TransferMatrix as Tm};
use pyo3::prelude::*;
use pyo3::types::{PyComplex, PyComplexMethods, PyList, PyTuple};

/// A transfer matrix in either time domain.
#[derive(Debug, Clone)]
pub enum TmSys {
    /// `G(s)`.
    Continuous(Tm<Continuous>),
    /// `G(z)` with sample time `ts`.
    Discrete(Tm<Discrete>),
}

/// Runs `$body` on two transfer matrices of the same domain; mixed domains raise.
macro_rules! both {
    ($a:expr, $b:expr, |$x:ident, $y:ident| $body:expr) => {
        match ($a, $b) {
            (TmSys::Continuous($x), TmSys::Continuous($y)) => {
                TmSys::Continuous($body.map_err(lti)?)
            }
            (TmSys::Discrete($x), TmSys::Discrete($y)) => TmSys::Discrete($body.map_err(lti)?),
            _ => return Err(mixed_domains()),
        }
    };
}

/// Runs `$body` on the transfer matrix of either domain.
macro_rules! with_tm {
    ($tm:expr, $x:ident => $body:expr) => {
        match $tm {
            TmSys::Continuous($x) => $body,
            TmSys::Discrete($x) => $body,
        }
    };
}

fn mixed_domains() -> PyErr {
    new_err(
        Kind::InvalidArgument,
        "cannot combine a continuous-time and a discrete-time system".into(),
        Some("SampleTimeMismatch"),
    )
}

impl TmSys {
    fn dt(&self) -> f64 {
        match self {
            TmSys::Continuous(_) => 0.0,
            TmSys::Discrete(t) => t.domain().ts(),
        }
    }

    /// The `1 × 1` gain `k` in this matrix's domain.
    fn gain_like(&self, k: f64) -> PyResult<TmSys> {
        let m = Mat::from_element(1, 1, k);
        Ok(match self {
            TmSys::Continuous(_) => TmSys::Continuous(Tm::gain(&m, Continuous).map_err(lti)?),
            TmSys::Discrete(t) => TmSys::Discrete(Tm::gain(&m, t.domain()).map_err(lti)?),
        })
    }

    /// The minimal state-space realisation.
    pub fn to_sys(&self) -> PyResult<Sys> {
        Ok(match self {
            TmSys::Continuous(t) => Sys::Continuous(t.to_state_space().map_err(lti)?),
            TmSys::Discrete(t) => Sys::Discrete(t.to_state_space().map_err(lti)?),
        })
    }

    /// The transfer matrix of a state-space system (each entry minimal).
    pub fn from_sys(sys: &Sys) -> PyResult<TmSys> {
        Ok(match sys {
            Sys::Continuous(s) => TmSys::Continuous(Tm::from_state_space(s).map_err(lti)?),
            Sys::Discrete(s) => TmSys::Discrete(Tm::from_state_space(s).map_err(lti)?),
        })
    }

    /// From `num[i][j]`, `den[i][j]` coefficient lists and a sample time (`None`: continuous).
    pub fn from_lists(
        num: &[Vec<Vec<f64>>],
        den: &[Vec<Vec<f64>>],
        dt: Option<f64>,
    ) -> PyResult<TmSys> {
        Ok(match dt {
            None => TmSys::Continuous(Tm::from_coefficients(num, den, Continuous).map_err(lti)?),
            Some(ts) => TmSys::Discrete(
                Tm::from_coefficients(num, den, Discrete::new(ts).map_err(lti)?).map_err(lti)?,
            ),
        })
    }
}

/// A multi-input multi-output transfer function: `noutputs × ninputs` SISO entries
/// `num[i][j] / den[i][j]` (coefficients in descending powers of s or z), continuous
/// (`dt = 0`) or discrete (`dt > 0` s).
///
/// `TransferMatrix(num, den, dt=0)` with `num`, `den` lists of lists of coefficient lists
/// (python-control's MIMO `tf`), or `TransferMatrix(sys)` for any system (each entry the
/// transfer function of the minimal realisation of its channel).
#[pyclass(name = "TransferMatrix", module = "pendulab", frozen)]
pub struct TransferMatrix {
    /// The Rust transfer matrix.
    pub tm: TmSys,
}

impl TransferMatrix {
    fn wrap(py: Python<'_>, tm: TmSys) -> PyResult<Py<PyAny>> {
        Ok(Py::new(py, TransferMatrix { tm })?.into_any())
    }

    /// The right operand of an arithmetic operator, in this matrix's domain.
    fn operand(&self, other: &Bound<'_, PyAny>) -> PyResult<TmSys> {
        if let Ok(t) = other.cast::<TransferMatrix>() {
            return Ok(t.get().tm.clone());
        }
        if let Ok(t) = other.cast::<TransferFunction>() {
            return Ok(match &t.get().tf {
                TfSys::Continuous(g) => TmSys::Continuous(Tm::from_siso(g.clone())),
                TfSys::Discrete(g) => TmSys::Discrete(Tm::from_siso(g.clone())),
            });
        }
        if let Ok(k) = other.extract::<f64>() {
            return self.tm.gain_like(k);
        }
        TmSys::from_sys(&system(other)?)
    }
}

#[pymethods]
impl TransferMatrix {
    #[new]
    #[pyo3(signature = (num, den = None, dt = None))]
    fn py_new(
        num: &Bound<'_, PyAny>,
        den: Option<&Bound<'_, PyAny>>,
        dt: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let dt = super::system::sample_time(dt)?;
        let tm = match den {
            Some(den) => {
                let n: Vec<Vec<Vec<f64>>> = num.extract()?;
                let d: Vec<Vec<Vec<f64>>> = den.extract()?;
                TmSys::from_lists(&n, &d, dt)?
            }
            None => TmSys::from_sys(&system(num)?)?,
        };
        Ok(TransferMatrix { tm })
    }

    /// Numerators as a list (outputs) of lists (inputs) of coefficient arrays.
    #[getter]
    fn num<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        self.coefficients(py, true)
    }
    /// Denominators (monic) as a list of lists of coefficient arrays.
    #[getter]
    fn den<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        self.coefficients(py, false)
    }
    /// Sample time in seconds; 0 for continuous time.
    #[getter]
    fn dt(&self) -> f64 {
        self.tm.dt()
    }
    /// Number of inputs m.
    #[getter]
    fn ninputs(&self) -> usize {
        with_tm!(&self.tm, t => t.nu())
    }
    /// Number of outputs p.
    #[getter]
    fn noutputs(&self) -> usize {
        with_tm!(&self.tm, t => t.ny())
    }
    /// `(noutputs, ninputs)`.
    #[getter]
    fn shape(&self) -> (usize, usize) {
        with_tm!(&self.tm, t => t.shape())
    }
    /// `G(s)` at a complex point as a `(noutputs, ninputs)` complex array.
    fn __call__<'py>(&self, py: Python<'py>, s: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let s = match s.cast::<PyComplex>() {
            Ok(c) => Complex64::new(c.real(), c.imag()),
            Err(_) => Complex64::new(s.extract::<f64>()?, 0.0),
        };
        Ok(complex_matrix_to_numpy(py, &with_tm!(&self.tm, t => t.eval(s))).into_any())
    }
    fn __add__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let o = self.operand(other)?;
        Self::wrap(py, both!(&self.tm, &o, |a, b| a.try_add(b)))
    }
    fn __radd__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let o = self.operand(other)?;
        Self::wrap(py, both!(&o, &self.tm, |a, b| a.try_add(b)))
    }
    fn __sub__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let o = self.operand(other)?;
        Self::wrap(py, both!(&self.tm, &o, |a, b| a.try_sub(b)))
    }
    fn __rsub__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let o = self.operand(other)?;
        Self::wrap(py, both!(&o, &self.tm, |a, b| a.try_sub(b)))
    }
    fn __mul__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let o = self.operand(other)?;
        Self::wrap(py, both!(&self.tm, &o, |a, b| a.try_mul(b)))
    }
    fn __rmul__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let o = self.operand(other)?;
        Self::wrap(py, both!(&o, &self.tm, |a, b| a.try_mul(b)))
    }
    fn __truediv__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let o = self.operand(other)?;
        Self::wrap(py, both!(&self.tm, &o, |a, b| a.try_div(b)))
    }
    fn __neg__(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Self::wrap(
            py,
            match &self.tm {
                TmSys::Continuous(t) => TmSys::Continuous(t.neg()),
                TmSys::Discrete(t) => TmSys::Discrete(t.neg()),
            },
        )
    }
    /// The closed loop `(I − sign·G K)⁻¹ G` (python-control / MATLAB `feedback(G, K, sign)`,
    /// `sign = -1` negative feedback); `K` defaults to the identity gain 1 for a SISO loop.
    #[pyo3(signature = (other = None, sign = -1))]
    fn feedback(
        &self,
        py: Python<'_>,
        other: Option<&Bound<'_, PyAny>>,
        sign: i32,
    ) -> PyResult<Py<PyAny>> {
        let k = match other {
            Some(o) => self.operand(o)?,
            None => self.tm.gain_like(1.0)?,
        };
        let sign = match sign {
            -1 => FeedbackSign::Negative,
            1 => FeedbackSign::Positive,
            s => {
                return Err(new_err(
                    Kind::InvalidArgument,
                    format!("feedback sign must be -1 or +1, got {s}"),
                    None,
                ));
            }
        };
        let tm = &self.tm;
        let out = nogil(py, || {
            Ok(match (tm, &k) {
                (TmSys::Continuous(a), TmSys::Continuous(b)) => {
                    Some(TmSys::Continuous(a.feedback(b, sign)?))
                }
                (TmSys::Discrete(a), TmSys::Discrete(b)) => {
                    Some(TmSys::Discrete(a.feedback(b, sign)?))
                }
                _ => None,
            })
        })?;
        Self::wrap(py, out.ok_or_else(mixed_domains)?)
    }
    /// Each entry with its common pole-zero pairs cancelled.
    fn minreal(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let tm = &self.tm;
        let out = nogil(py, || {
            Ok(match tm {
                TmSys::Continuous(t) => TmSys::Continuous(t.minreal()?),
                TmSys::Discrete(t) => TmSys::Discrete(t.minreal()?),
            })
        })?;
        Self::wrap(py, out)
    }
    /// A minimal state-space realisation (its order is the McMillan degree).
    fn to_ss(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let tm = &self.tm;
        let sys = py.detach(|| tm.to_sys())?;
        StateSpace::wrap(py, sys)
    }
    /// Zeros, poles and gain per entry: a list of lists of `(zeros, poles, k)`.
    fn zpk<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let z = with_tm!(&self.tm, t => t.to_zpk()).map_err(lti)?;
        let rows = PyList::empty(py);
        for row in z {
            let r = PyList::empty(py);
            for (zeros, poles, k) in row {
                r.append(PyTuple::new(
                    py,
                    [
                        complex_to_numpy(py, &zeros).into_any(),
                        complex_to_numpy(py, &poles).into_any(),
                        k.into_pyobject(py)?.into_any(),
                    ],
                )?)?;
            }
            rows.append(r)?;
        }
        Ok(rows)
    }
    fn __repr__(&self) -> String {
        let (s, dt) = (with_tm!(&self.tm, t => t.to_string()), self.tm.dt());
        format!("TransferMatrix(dt={dt},\n{s})")
    }
}

impl TransferMatrix {
    fn coefficients<'py>(&self, py: Python<'py>, num: bool) -> PyResult<Bound<'py, PyList>> {
        let (rows, cols) = with_tm!(&self.tm, t => t.shape());
        let out = PyList::empty(py);
        for i in 0..rows {
            let r = PyList::empty(py);
            for j in 0..cols {
                let c = with_tm!(&self.tm, t => {
                    let g = t.get(i, j).expect("index inside the shape");
                    if num { g.num().coefficients().to_vec() } else { g.den().coefficients().to_vec() }
                });
                r.append(slice_to_numpy(py, &c))?;
            }
            out.append(r)?;
        }
        Ok(out)
    }
}

/// `pade(T, n=1)`: the `(n, n)` Padé approximant of the delay `e^{-sT}` as `(num, den)`
/// coefficient arrays in descending powers of s, den monic (python-control `pade(T, n)`;
/// closed-form coefficients, see pendulab-lti's `delay`).
///
/// Raises `pendulab.InvalidArgumentError` for `T < 0`, a non-finite `T` or `n ≤ 0`.
#[pyfunction]
#[pyo3(signature = (T, n = 1))]
#[allow(non_snake_case)]
pub fn pade<'py>(
    py: Python<'py>,
    T: f64,
    #[pyo3(from_py_with = count)] n: usize,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let g = delay::pade(T, n).map_err(lti)?;
    Ok((
        slice_to_numpy(py, g.num().coefficients()).into_any(),
        slice_to_numpy(py, g.den().coefficients()).into_any(),
    ))
}

/// `thiran(tau, Ts, order=None)`: the Thiran all-pass approximation of a delay of `tau`
/// seconds at sample time `Ts` as a discrete `TransferFunction` (MATLAB `thiran`: order
/// `ceil(tau/Ts)` by default; with `order`, the whole samples beyond it become `z^-m`).
/// Its group delay at DC is `tau/Ts` samples, maximally flat.
///
/// Raises `pendulab.InvalidArgumentError` for a negative delay or an order above
/// `ceil(tau/Ts)`.
#[pyfunction]
#[pyo3(signature = (tau, Ts, order = None))]
#[allow(non_snake_case)]
pub fn thiran(
    py: Python<'_>,
    tau: f64,
    Ts: f64,
    #[pyo3(from_py_with = optional_count)] order: Option<usize>,
) -> PyResult<Py<PyAny>> {
    let g = match order {
        None => delay::thiran(tau, Ts),
        Some(n) => delay::thiran_with_order(tau, Ts, n),
    }
    .map_err(lti)?;
    Ok(Py::new(
        py,
        TransferFunction {
            tf: TfSys::Discrete(g),
        },
    )?
    .into_any())
}

/// Reads `num` as lists of lists of coefficient lists (a MIMO `tf`), `None` if it is not.
pub fn nested_coefficients(num: &Bound<'_, PyAny>) -> Option<Vec<Vec<Vec<f64>>>> {
    num.extract::<Vec<Vec<Vec<f64>>>>().ok()
}

/// Wraps a transfer matrix built from lists as a Python object.
pub fn wrap_lists(
    py: Python<'_>,
    num: &[Vec<Vec<f64>>],
    den: &[Vec<Vec<f64>>],
    dt: Option<f64>,
) -> PyResult<Py<PyAny>> {
    TransferMatrix::wrap(py, TmSys::from_lists(num, den, dt)?)
}

/// The transfer matrix of a MIMO system as a Python object.
pub fn wrap_sys(py: Python<'_>, sys: &Sys) -> PyResult<Py<PyAny>> {
    TransferMatrix::wrap(py, TmSys::from_sys(sys)?)
}
