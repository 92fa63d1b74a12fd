//! `pendulab.StateSpace` and `pendulab.TransferFunction`, and how every LTI function reads its
//! system argument ([`system`]): a pendulab system, a python-control `StateSpace` (anything
//! with `.A .B .C .D` and `.dt`) or SISO `TransferFunction` (`.num`, `.den`, `.dt`), an
//! `(A, B, C, D)` or `(A, B, C, D, dt)` tuple, or a pendulab `TransferFunction`.
//!
//! Time domain: `dt = 0` or `None` is continuous time, `dt > 0` discrete time with that
//! sample time in seconds (python-control's convention; its `dt = True`, "discrete with
//! unspecified sample time", is refused: every discrete computation here needs the number).

use super::nogil;
use crate::convert::{OneD, complex_to_numpy, matrix, matrix_to_numpy, slice_to_numpy, vector};
use crate::errors::lti;
use nalgebra::DMatrix;
use pendulab_lti::{
    Continuous, Discrete, Discretization, Mat, StateSpace as Ss, TransferFunction as Tf,
};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyFloat, PyTuple};

/// A state-space system in either time domain.
#[derive(Debug, Clone)]
pub enum Sys {
    /// `ẋ = Ax + Bu`, `y = Cx + Du`.
    Continuous(Ss<Continuous>),
    /// `x[k+1] = Ax[k] + Bu[k]`, `y[k] = Cx[k] + Du[k]`, sample time `ts`.
    Discrete(Ss<Discrete>),
}

/// Runs `$body` with `$s` bound to the `StateSpace<D>` of either domain.
macro_rules! with_sys {
    ($sys:expr, $s:ident => $body:expr) => {
        match $sys {
            $crate::lti::system::Sys::Continuous($s) => $body,
            $crate::lti::system::Sys::Discrete($s) => $body,
        }
    };
}
pub(crate) use with_sys;

impl Sys {
    /// `(A, B, C, D)` with sample time `dt` (`None`/`0`: continuous).
    pub fn new(a: Mat, b: Mat, c: Mat, d: Mat, dt: Option<f64>) -> PyResult<Self> {
        Ok(match dt {
            None | Some(0.0) => Sys::Continuous(Ss::continuous(a, b, c, d).map_err(lti)?),
            Some(ts) => Sys::Discrete(Ss::discrete(a, b, c, d, ts).map_err(lti)?),
        })
    }

    /// The sample time (0 for continuous time, python-control's convention).
    pub fn dt(&self) -> f64 {
        match self {
            Sys::Continuous(_) => 0.0,
            Sys::Discrete(s) => s.ts(),
        }
    }
}

/// A SISO transfer function in either time domain.
#[derive(Debug, Clone)]
pub enum TfSys {
    /// `G(s)`.
    Continuous(Tf<Continuous>),
    /// `G(z)` with sample time `ts`.
    Discrete(Tf<Discrete>),
}

/// Reads a sample time: `None`, `0`, `0.0` and `False` mean continuous time.
pub(crate) fn sample_time(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<f64>> {
    let Some(obj) = obj else { return Ok(None) };
    if obj.is_none() {
        return Ok(None);
    }
    if obj.is_instance_of::<pyo3::types::PyBool>() {
        return if obj.is_truthy()? {
            Err(crate::errors::new_err(
                crate::errors::Kind::InvalidArgument,
                "dt = True (discrete time with an unspecified sample time) is not supported: give the sample time in seconds".into(),
                Some("InvalidSampleTime"),
            ))
        } else {
            Ok(None)
        };
    }
    let dt: f64 = obj.extract()?;
    Ok(if dt == 0.0 { None } else { Some(dt) })
}

/// Builds a system from the four matrices (1-d `B` of length `n` is a column, 1-d `C` a row,
/// as python-control reads them) and a sample time object.
fn from_matrices(
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    c: &Bound<'_, PyAny>,
    d: &Bound<'_, PyAny>,
    dt: Option<&Bound<'_, PyAny>>,
) -> PyResult<Sys> {
    let a = matrix(a, "A", OneD::Row)?;
    let n = a.nrows();
    let b_one_d = if n == 1 { OneD::Row } else { OneD::Column };
    let b = matrix(b, "B", b_one_d)?;
    let c = matrix(c, "C", OneD::Row)?;
    // A scalar D = 0 (python-control's default) stands for the zero matrix of the right shape.
    let d = if d.is_exact_instance_of::<PyFloat>() || d.is_exact_instance_of::<pyo3::types::PyInt>()
    {
        let v: f64 = d.extract()?;
        if v == 0.0 {
            DMatrix::zeros(c.nrows(), b.ncols())
        } else {
            DMatrix::from_element(1, 1, v)
        }
    } else {
        matrix(d, "D", OneD::Row)?
    };
    Sys::new(a, b, c, d, sample_time(dt)?)
}

/// A state-space system in any of the accepted forms (see the module docs).
///
/// # Errors
/// `TypeError` for anything else; the matrices' shape and finiteness errors.
pub fn system(obj: &Bound<'_, PyAny>) -> PyResult<Sys> {
    if let Ok(s) = obj.cast::<StateSpace>() {
        return Ok(s.get().sys.clone());
    }
    if let Ok(t) = obj.cast::<TransferFunction>() {
        return t.get().to_sys();
    }
    if let Ok(t) = obj.cast::<super::transfer::TransferMatrix>() {
        return t.get().tm.to_sys();
    }
    if let Ok(t) = obj.cast::<PyTuple>() {
        return match t.len() {
            4 | 5 => from_matrices(
                &t.get_item(0)?,
                &t.get_item(1)?,
                &t.get_item(2)?,
                &t.get_item(3)?,
                t.get_item(4).ok().as_ref(),
            ),
            k => Err(PyTypeError::new_err(format!(
                "a system tuple must be (A, B, C, D) or (A, B, C, D, dt), got {k} items"
            ))),
        };
    }
    if obj.hasattr("A")? && obj.hasattr("B")? && obj.hasattr("C")? && obj.hasattr("D")? {
        let dt = obj.getattr("dt").ok();
        return from_matrices(
            &obj.getattr("A")?,
            &obj.getattr("B")?,
            &obj.getattr("C")?,
            &obj.getattr("D")?,
            dt.as_ref(),
        );
    }
    if obj.hasattr("num")? && obj.hasattr("den")? {
        return siso_tf_like(obj)?.to_sys();
    }
    Err(PyTypeError::new_err(format!(
        "expected a system: pendulab.StateSpace or TransferFunction, a python-control StateSpace or SISO TransferFunction, or an (A, B, C, D[, dt]) tuple; got {}",
        obj.get_type().name()?
    )))
}

/// A SISO python-control `TransferFunction` (`.num[0][0]`, `.den[0][0]` in descending powers,
/// `.dt`) as a pendulab one.
///
/// # Errors
/// `ShapeError` for a MIMO transfer function; the coefficients' errors.
fn siso_tf_like(obj: &Bound<'_, PyAny>) -> PyResult<TransferFunction> {
    let siso = |name: &str| -> PyResult<Bound<'_, PyAny>> {
        let rows = obj.getattr(name)?;
        if rows.len()? != 1 || rows.get_item(0)?.len()? != 1 {
            return Err(crate::errors::new_err(
                crate::errors::Kind::Shape,
                format!(
                    "transfer function {name}: only single-input single-output transfer functions are read"
                ),
                Some("NotSiso"),
            ));
        }
        rows.get_item(0)?.get_item(0)
    };
    let dt = obj.getattr("dt").ok();
    TransferFunction::py_new(&siso("num")?, &siso("den")?, dt.as_ref())
}

/// Whether `obj` is a system (as opposed to a matrix) for functions that take either, e.g.
/// `lqr(sys, Q, R)` versus `lqr(A, B, Q, R)`.
pub fn is_system(obj: &Bound<'_, PyAny>) -> bool {
    obj.is_instance_of::<StateSpace>()
        || obj.is_instance_of::<TransferFunction>()
        || obj.is_instance_of::<super::transfer::TransferMatrix>()
        || obj
            .cast::<PyTuple>()
            .is_ok_and(|t| t.len() == 4 || t.len() == 5)
        || obj.hasattr("A").unwrap_or(false) && obj.hasattr("B").unwrap_or(false)
        || obj.hasattr("num").unwrap_or(false) && obj.hasattr("den").unwrap_or(false)
}

/// A linear time-invariant system in state-space form,
/// `dx/dt = A x + B u, y = C x + D u` (continuous, `dt = 0`) or
/// `x[k+1] = A x[k] + B u[k], y[k] = C x[k] + D u[k]` (discrete, sample time `dt` s).
///
/// `StateSpace(A, B, C, D, dt=0)`, `StateSpace(sys)` (a pendulab or python-control system, or
/// a pendulab TransferFunction). A 1-d `B` of length n is a column, a 1-d `C` a row; `D = 0`
/// stands for the zero matrix. Matrices are checked for shape and finiteness.
#[pyclass(name = "StateSpace", module = "pendulab", frozen)]
pub struct StateSpace {
    /// The Rust system.
    pub sys: Sys,
}

impl StateSpace {
    /// Wraps a system as a Python object.
    pub fn wrap(py: Python<'_>, sys: Sys) -> PyResult<Py<PyAny>> {
        Ok(Py::new(py, StateSpace { sys })?.into_any())
    }
}

#[pymethods]
impl StateSpace {
    #[new]
    #[pyo3(signature = (*args, dt = None))]
    fn py_new(args: &Bound<'_, PyTuple>, dt: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let sys = match args.len() {
            1 => {
                let mut s = system(&args.get_item(0)?)?;
                if dt.is_some() {
                    let (a, b, c, d) = with_sys!(s, x => x.into_parts());
                    s = Sys::new(a, b, c, d, sample_time(dt)?)?;
                }
                s
            }
            4 => from_matrices(
                &args.get_item(0)?,
                &args.get_item(1)?,
                &args.get_item(2)?,
                &args.get_item(3)?,
                dt,
            )?,
            5 if dt.is_none() => from_matrices(
                &args.get_item(0)?,
                &args.get_item(1)?,
                &args.get_item(2)?,
                &args.get_item(3)?,
                Some(&args.get_item(4)?),
            )?,
            k => {
                return Err(PyTypeError::new_err(format!(
                    "StateSpace takes (A, B, C, D[, dt]) or (sys), got {k} positional arguments"
                )));
            }
        };
        Ok(StateSpace { sys })
    }

    /// State matrix `A` (n × n).
    #[getter(A)]
    fn a<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        matrix_to_numpy(py, with_sys!(&self.sys, s => s.a())).into_any()
    }
    /// Input matrix `B` (n × m).
    #[getter(B)]
    fn b<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        matrix_to_numpy(py, with_sys!(&self.sys, s => s.b())).into_any()
    }
    /// Output matrix `C` (p × n).
    #[getter(C)]
    fn c<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        matrix_to_numpy(py, with_sys!(&self.sys, s => s.c())).into_any()
    }
    /// Feedthrough matrix `D` (p × m).
    #[getter(D)]
    fn d<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        matrix_to_numpy(py, with_sys!(&self.sys, s => s.d())).into_any()
    }
    /// Sample time in seconds; 0 for continuous time.
    #[getter]
    fn dt(&self) -> f64 {
        self.sys.dt()
    }
    /// Number of states n.
    #[getter]
    fn nstates(&self) -> usize {
        with_sys!(&self.sys, s => s.nx())
    }
    /// Number of inputs m.
    #[getter]
    fn ninputs(&self) -> usize {
        with_sys!(&self.sys, s => s.nu())
    }
    /// Number of outputs p.
    #[getter]
    fn noutputs(&self) -> usize {
        with_sys!(&self.sys, s => s.ny())
    }
    /// True for continuous time.
    fn isctime(&self) -> bool {
        matches!(self.sys, Sys::Continuous(_))
    }
    /// True for discrete time.
    fn isdtime(&self) -> bool {
        matches!(self.sys, Sys::Discrete(_))
    }
    /// Poles: the eigenvalues of A (complex array), see `pendulab.poles`.
    fn poles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let sys = &self.sys;
        let p = nogil(py, || with_sys!(sys, s => s.poles()))?;
        Ok(complex_to_numpy(py, &p).into_any())
    }
    /// Invariant zeros (complex array), see `pendulab.zeros`.
    fn zeros<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let sys = &self.sys;
        let z = nogil(py, || with_sys!(sys, s => s.zeros()))?;
        Ok(complex_to_numpy(py, &z).into_any())
    }
    /// DC gain, see `pendulab.dcgain`.
    fn dcgain(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        super::analysis::dcgain(slf.as_any())
    }
    /// Discretised copy: python-control's name for `pendulab.c2d(sys, Ts, method)`.
    #[pyo3(signature = (Ts, method = "zoh", prewarp_frequency = None))]
    #[allow(non_snake_case)]
    fn sample(
        slf: &Bound<'_, Self>,
        Ts: f64,
        method: &str,
        prewarp_frequency: Option<f64>,
    ) -> PyResult<Py<PyAny>> {
        c2d(slf.as_any(), Ts, method, prewarp_frequency)
    }
    fn __repr__(&self) -> String {
        let (nx, nu, ny) = with_sys!(&self.sys, s => (s.nx(), s.nu(), s.ny()));
        let (a, b, c, d) = with_sys!(&self.sys, s => (s.a(), s.b(), s.c(), s.d()));
        let dt = match &self.sys {
            Sys::Continuous(_) => String::new(),
            Sys::Discrete(s) => format!(", dt={}", s.ts()),
        };
        format!(
            "StateSpace(states={nx}, inputs={nu}, outputs={ny}{dt},\nA={a:?},\nB={b:?},\nC={c:?},\nD={d:?})",
            a = a.as_slice(),
            b = b.as_slice(),
            c = c.as_slice(),
            d = d.as_slice()
        )
    }
}

/// A single-input single-output transfer function `G = num/den` (coefficients in descending
/// powers of s or z, MATLAB's order), continuous (`dt = 0`) or discrete (`dt > 0` s). The
/// pair is normalised so that `den` is monic.
///
/// `TransferFunction(num, den, dt=0)`.
#[pyclass(name = "TransferFunction", module = "pendulab", frozen)]
pub struct TransferFunction {
    /// The Rust transfer function.
    pub tf: TfSys,
}

impl TransferFunction {
    /// The state-space realisation (controllable canonical form of pendulab-lti).
    pub fn to_sys(&self) -> PyResult<Sys> {
        Ok(match &self.tf {
            TfSys::Continuous(t) => Sys::Continuous(t.to_state_space().map_err(lti)?),
            TfSys::Discrete(t) => Sys::Discrete(t.to_state_space().map_err(lti)?),
        })
    }
}

#[pymethods]
impl TransferFunction {
    #[new]
    #[pyo3(signature = (num, den, dt = None))]
    fn py_new(
        num: &Bound<'_, PyAny>,
        den: &Bound<'_, PyAny>,
        dt: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let num = vector(num, "num")?;
        let den = vector(den, "den")?;
        let tf = match sample_time(dt)? {
            None => TfSys::Continuous(
                Tf::from_coefficients(num.as_slice(), den.as_slice(), Continuous).map_err(lti)?,
            ),
            Some(ts) => {
                TfSys::Discrete(Tf::discrete(num.as_slice(), den.as_slice(), ts).map_err(lti)?)
            }
        };
        Ok(TransferFunction { tf })
    }
    /// Numerator coefficients, descending powers.
    #[getter]
    fn num<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let c = match &self.tf {
            TfSys::Continuous(t) => t.num().coefficients(),
            TfSys::Discrete(t) => t.num().coefficients(),
        };
        slice_to_numpy(py, c).into_any()
    }
    /// Denominator coefficients, descending powers (monic).
    #[getter]
    fn den<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let c = match &self.tf {
            TfSys::Continuous(t) => t.den().coefficients(),
            TfSys::Discrete(t) => t.den().coefficients(),
        };
        slice_to_numpy(py, c).into_any()
    }
    /// Sample time in seconds; 0 for continuous time.
    #[getter]
    fn dt(&self) -> f64 {
        match &self.tf {
            TfSys::Continuous(_) => 0.0,
            TfSys::Discrete(t) => t.ts(),
        }
    }
    /// Poles: the roots of `den` (complex array).
    fn poles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let p = match &self.tf {
            TfSys::Continuous(t) => t.poles(),
            TfSys::Discrete(t) => t.poles(),
        }
        .map_err(lti)?;
        Ok(complex_to_numpy(py, &p).into_any())
    }
    /// Zeros: the roots of `num` (complex array).
    fn zeros<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let z = match &self.tf {
            TfSys::Continuous(t) => t.zeros(),
            TfSys::Discrete(t) => t.zeros(),
        }
        .map_err(lti)?;
        Ok(complex_to_numpy(py, &z).into_any())
    }
    /// DC gain `G(0)` (continuous) or `G(1)` (discrete).
    ///
    /// Raises `pendulab.LinAlgError` for a pole at s = 0 (z = 1).
    fn dcgain(&self) -> PyResult<f64> {
        match &self.tf {
            TfSys::Continuous(t) => t.dc_gain(),
            TfSys::Discrete(t) => t.dc_gain(),
        }
        .map_err(lti)
    }
    /// The state-space realisation as a `pendulab.StateSpace`.
    fn to_ss(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        StateSpace::wrap(py, self.to_sys()?)
    }
    fn __repr__(&self) -> String {
        let (num, den, dt) = match &self.tf {
            TfSys::Continuous(t) => (t.num().coefficients(), t.den().coefficients(), 0.0),
            TfSys::Discrete(t) => (t.num().coefficients(), t.den().coefficients(), t.ts()),
        };
        format!("TransferFunction(num={num:?}, den={den:?}, dt={dt})")
    }
}

/// `ss(A, B, C, D, dt=0)` or `ss(sys)`: a `pendulab.StateSpace` (python-control's `ss`).
#[pyfunction]
#[pyo3(signature = (*args, dt = None))]
pub fn ss(
    py: Python<'_>,
    args: &Bound<'_, PyTuple>,
    dt: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    Ok(Py::new(py, StateSpace::py_new(args, dt)?)?.into_any())
}

/// `tf(num, den, dt=0)`: a SISO `pendulab.TransferFunction`; `tf(sys)` of a SISO state-space
/// system (its transfer function `C (sI − A)⁻¹ B + D` as a polynomial ratio). With `num`,
/// `den` lists of lists of coefficient lists, or a MIMO `sys`, a `pendulab.TransferMatrix`.
#[pyfunction]
#[pyo3(signature = (num, den = None, dt = None))]
pub fn tf(
    py: Python<'_>,
    num: &Bound<'_, PyAny>,
    den: Option<&Bound<'_, PyAny>>,
    dt: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    let t = match den {
        Some(den) => match super::transfer::nested_coefficients(num) {
            Some(n) => {
                let d = super::transfer::nested_coefficients(den).ok_or_else(|| {
                    PyTypeError::new_err(
                        "tf: num is a list of lists of coefficient lists, den must be one too",
                    )
                })?;
                return super::transfer::wrap_lists(py, &n, &d, sample_time(dt)?);
            }
            None => TransferFunction::py_new(num, den, dt)?,
        },
        None => {
            let sys = system(num)?;
            if with_sys!(&sys, s => s.nu() != 1 || s.ny() != 1) {
                return super::transfer::wrap_sys(py, &sys);
            }
            let tf = match &sys {
                Sys::Continuous(s) => TfSys::Continuous(Tf::from_state_space(s).map_err(lti)?),
                Sys::Discrete(s) => TfSys::Discrete(Tf::from_state_space(s).map_err(lti)?),
            };
            TransferFunction { tf }
        }
    };
    Ok(Py::new(py, t)?.into_any())
}

/// Reads a discretisation method name (python-control's and MATLAB's spellings).
fn method(name: &str, prewarp: Option<f64>) -> PyResult<Discretization> {
    Ok(match name.to_ascii_lowercase().as_str() {
        "zoh" => Discretization::Zoh,
        "foh" => Discretization::Foh,
        "tustin" | "bilinear" | "gbt0.5" => Discretization::Tustin { prewarp },
        "euler" | "forward_diff" | "forward_euler" => Discretization::ForwardEuler,
        "backward_diff" | "backward_euler" => Discretization::BackwardEuler,
        "matched" => Discretization::Matched,
        "impulse" | "imp" => Discretization::Impulse,
        other => {
            return Err(crate::errors::new_err(
                crate::errors::Kind::InvalidArgument,
                format!(
                    "unknown discretisation method {other:?}: use 'zoh', 'foh', 'tustin' (or 'bilinear'), 'euler' (or 'forward_diff'), 'backward_diff', 'matched', 'impulse'"
                ),
                None,
            ));
        }
    })
}

/// `c2d(sys, Ts, method='zoh', prewarp_frequency=None)`: the discretisation of a continuous
/// system with sample time `Ts` seconds (python-control / MATLAB `c2d`).
///
/// Methods: `'zoh'` (`A_d = e^{A Ts}`, `B_d = ∫₀^{Ts} e^{As} ds B`), `'foh'` (triangle hold),
/// `'tustin'`/`'bilinear'` (`s = (2/Ts)(z − 1)/(z + 1)`, or prewarped at
/// `prewarp_frequency` rad/s), `'euler'`/`'forward_diff'`, `'backward_diff'`, `'matched'`
/// (pole-zero matching, SISO, low-frequency gain matched, all but one zero at infinity to
/// `z = -1` as MATLAB), `'impulse'` (impulse invariant, `h_d[k] = Ts h(k Ts)`, `D = 0`). A
/// `TransferFunction` gives a `TransferFunction`, any other system a `StateSpace`.
///
/// Raises `pendulab.InvalidArgumentError` for an unknown method, a discrete `sys` or a bad
/// `Ts`.
#[pyfunction]
#[pyo3(signature = (sys, Ts, method = "zoh", prewarp_frequency = None))]
#[allow(non_snake_case)]
pub fn c2d(
    sys: &Bound<'_, PyAny>,
    Ts: f64,
    method: &str,
    prewarp_frequency: Option<f64>,
) -> PyResult<Py<PyAny>> {
    let py = sys.py();
    let m = self::method(method, prewarp_frequency)?;
    if let Ok(t) = sys.cast::<TransferFunction>() {
        let TfSys::Continuous(t) = &t.get().tf else {
            return Err(not_continuous());
        };
        let d = nogil(py, || t.c2d(Ts, m))?;
        return Ok(Py::new(
            py,
            TransferFunction {
                tf: TfSys::Discrete(d),
            },
        )?
        .into_any());
    }
    let Sys::Continuous(s) = system(sys)? else {
        return Err(not_continuous());
    };
    let d = nogil(py, || s.c2d(Ts, m))?;
    StateSpace::wrap(py, Sys::Discrete(d))
}

fn not_continuous() -> PyErr {
    crate::errors::new_err(
        crate::errors::Kind::InvalidArgument,
        "c2d needs a continuous-time system (dt = 0)".into(),
        None,
    )
}

/// `d2c(sys, method='zoh', prewarp_frequency=None)`: the continuous system whose
/// discretisation by `method` is the discrete `sys` (MATLAB `d2c`; the principal matrix
/// logarithm for `'zoh'`/`'foh'`, the exact inverse map for the bilinear methods).
///
/// Raises `pendulab.LinAlgError` for a discrete pole on the closed negative real axis (no real
/// logarithm) and `pendulab.InvalidArgumentError` for a continuous `sys`.
#[pyfunction]
#[pyo3(signature = (sys, method = "zoh", prewarp_frequency = None))]
pub fn d2c(
    sys: &Bound<'_, PyAny>,
    method: &str,
    prewarp_frequency: Option<f64>,
) -> PyResult<Py<PyAny>> {
    let py = sys.py();
    let m = self::method(method, prewarp_frequency)?;
    let not_discrete = || {
        crate::errors::new_err(
            crate::errors::Kind::InvalidArgument,
            "d2c needs a discrete-time system (dt > 0)".into(),
            None,
        )
    };
    if let Ok(t) = sys.cast::<TransferFunction>() {
        let TfSys::Discrete(t) = &t.get().tf else {
            return Err(not_discrete());
        };
        let c = nogil(py, || t.d2c(m))?;
        return Ok(Py::new(
            py,
            TransferFunction {
                tf: TfSys::Continuous(c),
            },
        )?
        .into_any());
    }
    let Sys::Discrete(s) = system(sys)? else {
        return Err(not_discrete());
    };
    let c = nogil(py, || s.d2c(m))?;
    StateSpace::wrap(py, Sys::Continuous(c))
}
