//! Analysis: `poles`, `zeros`, `dcgain`, `damp`, `ctrb`, `obsv`, `gram` (pendulab-lti's
//! `analysis` module).

use super::nogil;
use super::results::{obj, result_class};
use super::system::{Sys, system, with_sys};
use crate::convert::{OneD, complex_to_numpy, matrix, matrix_to_numpy, slice_to_numpy};
use pendulab_lti::Mat;
use pendulab_lti::analysis::{GramianKind, gramian};
use pyo3::prelude::*;

/// `poles(sys)`: the poles of `sys`, the eigenvalues of `A` (s or z plane), as a complex
/// array sorted by pendulab-lti's order (real part, then imaginary part).
#[pyfunction]
pub fn poles<'py>(sys: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let py = sys.py();
    let s = system(sys)?;
    let p = nogil(py, || with_sys!(&s, s => s.poles()))?;
    Ok(complex_to_numpy(py, &p).into_any())
}

/// `zeros(sys)`: the invariant (transmission) zeros, the finite s where
/// `[[sI − A, −B], [C, D]]` loses rank (MATLAB `tzero`), as a complex array.
#[pyfunction]
pub fn zeros<'py>(sys: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let py = sys.py();
    let s = system(sys)?;
    let z = nogil(py, || with_sys!(&s, s => s.zeros()))?;
    Ok(complex_to_numpy(py, &z).into_any())
}

/// `dcgain(sys)`: the steady-state gain `G(0) = D − C A⁻¹ B` (continuous) or
/// `G(1) = D + C (I − A)⁻¹ B` (discrete); a float for a SISO system, else a p × m array.
///
/// Raises `pendulab.LinAlgError` (variant `PoleAtEvaluationPoint`) if `sys` has a pole at
/// s = 0 (z = 1): the gain is infinite.
#[pyfunction]
pub fn dcgain(sys: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
    let py = sys.py();
    let s = system(sys)?;
    let g = nogil(py, || with_sys!(&s, s => s.dc_gain()))?;
    if g.nrows() == 1 && g.ncols() == 1 {
        obj(py, g[(0, 0)])
    } else {
        Ok(matrix_to_numpy(py, &g).into_any().unbind())
    }
}

result_class!(
    DampResult, "DampResult",
    "Natural frequencies, damping ratios and poles (MATLAB/python-control `damp`); unpacks as `wn, zeta, poles`.",
    array none,
    unpack {
        wn as "wn": "Natural frequencies ωₙ = |s| in rad/s (discrete poles mapped by s = ln(z)/dt).",
        zeta as "zeta": "Damping ratios ζ = −Re s/|s| (−1 for a pole at the origin, negative when unstable).",
        poles as "poles": "The poles (s or z), complex.",
    }
    also {
        time_constants as "time_constants": "Time constants τ = −1/Re s in seconds (inf for Re s = 0).",
    }
);

/// `damp(sys)`: natural frequency, damping ratio and time constant of every pole.
#[pyfunction]
pub fn damp(sys: &Bound<'_, PyAny>) -> PyResult<DampResult> {
    let py = sys.py();
    let s = system(sys)?;
    let d = nogil(py, || with_sys!(&s, s => s.damp()))?;
    let wn: Vec<f64> = d.iter().map(|x| x.natural_frequency).collect();
    let zeta: Vec<f64> = d.iter().map(|x| x.damping_ratio).collect();
    let tau: Vec<f64> = d.iter().map(|x| x.time_constant).collect();
    let p: Vec<_> = d.iter().map(|x| x.pole).collect();
    Ok(DampResult {
        wn: slice_to_numpy(py, &wn).into_any().unbind(),
        zeta: slice_to_numpy(py, &zeta).into_any().unbind(),
        poles: complex_to_numpy(py, &p).into_any().unbind(),
        time_constants: slice_to_numpy(py, &tau).into_any().unbind(),
    })
}

/// Reads `A` and the matrix `X` named `name` (a 1-D `X` read as `one_d`), runs pendulab-lti's
/// `f(A, X)` without the GIL and returns its matrix as a NumPy array.
fn with_a_and<'py>(
    a: &Bound<'py, PyAny>,
    x: &Bound<'py, PyAny>,
    name: &str,
    one_d: OneD,
    f: fn(&Mat, &Mat) -> pendulab_lti::Result<Mat>,
) -> PyResult<Bound<'py, PyAny>> {
    let py = a.py();
    let a = matrix(a, "A", OneD::Row)?;
    let x = matrix(x, name, one_d)?;
    let m = nogil(py, || f(&a, &x))?;
    Ok(matrix_to_numpy(py, &m).into_any())
}

/// `ctrb(A, B)`: the controllability matrix `[B, AB, …, Aⁿ⁻¹B]` (n × nm). For rank
/// decisions prefer `StateSpace` analysis: the columns `AᵏB` lose information in rounding.
#[pyfunction]
#[pyo3(name = "ctrb")]
pub fn ctrb_py<'py>(a: &Bound<'py, PyAny>, b: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    with_a_and(a, b, "B", OneD::Column, pendulab_lti::analysis::ctrb)
}

/// `obsv(A, C)`: the observability matrix `[C; CA; …; CAⁿ⁻¹]` (np × n).
#[pyfunction]
#[pyo3(name = "obsv")]
pub fn obsv_py<'py>(a: &Bound<'py, PyAny>, c: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    with_a_and(a, c, "C", OneD::Row, pendulab_lti::analysis::obsv)
}

result_class!(
    MatrixEquationResult, "MatrixEquationResult",
    "The solution X of a linear matrix equation with its relative residual ‖res‖_F / Σ‖terms‖_F; behaves as the array X (`numpy.asarray(result)`).",
    array x,
    unpack {
        x as "X": "The solution X.",
    }
    also {
        residual as "residual": "Relative residual of the equation at X.",
    }
);

impl MatrixEquationResult {
    /// From pendulab-lti's solution.
    pub fn from_solution(
        py: Python<'_>,
        s: &pendulab_lti::equations::MatrixEquationSolution,
    ) -> PyResult<Self> {
        Ok(Self {
            x: matrix_to_numpy(py, &s.x).into_any().unbind(),
            residual: obj(py, s.residual)?,
        })
    }
}

/// `gram(sys, type)`: the controllability (`type='c'`, `A W + W Aᵀ + B Bᵀ = 0`) or
/// observability (`type='o'`, `Aᵀ W + W A + Cᵀ C = 0`) gramian of a stable system (discrete:
/// the Stein equations `A W Aᵀ − W + B Bᵀ = 0`, `Aᵀ W A − W + Cᵀ C = 0`).
///
/// Raises `pendulab.InvalidArgumentError` for an unstable system or an unknown type.
#[pyfunction]
#[pyo3(signature = (sys, r#type))]
pub fn gram(sys: &Bound<'_, PyAny>, r#type: &str) -> PyResult<MatrixEquationResult> {
    let py = sys.py();
    let kind = match r#type {
        "c" => GramianKind::Controllability,
        "o" => GramianKind::Observability,
        other => {
            return Err(crate::errors::new_err(
                crate::errors::Kind::InvalidArgument,
                format!("gram type must be 'c' or 'o', got {other:?}"),
                None,
            ));
        }
    };
    let s = system(sys)?;
    let w = nogil(py, || match &s {
        Sys::Continuous(s) => gramian(s, kind),
        Sys::Discrete(s) => gramian(s, kind),
    })?;
    MatrixEquationResult::from_solution(py, &w)
}
