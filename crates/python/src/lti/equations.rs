//! Matrix equations: `lyap`, `dlyap`, `care`, `dare` (pendulab-lti's `equations` module).
//! Every solution carries its relative residual.

use super::analysis::MatrixEquationResult;
use super::nogil;
use super::results::{obj, result_class};
use crate::convert::{OneD, complex_to_numpy, matrix, matrix_to_numpy};
use crate::errors::{Kind, new_err};
use pendulab_lti::Mat;
use pendulab_lti::equations::{RiccatiOptions, RiccatiSolution};
use pyo3::prelude::*;

/// `lyap(A, Q, C=None)`: the continuous Lyapunov equation `A X + X Aᵀ + Q = 0`
/// (python-control / MATLAB `lyap`, Bartels–Stewart); with `C`, the Sylvester equation
/// `A X + X Q + C = 0`.
///
/// Raises `pendulab.LinAlgError` (variant `NoUniqueSolution`) when `λᵢ(A) + λⱼ(A) = 0` for
/// some pair.
#[pyfunction]
#[pyo3(signature = (A, Q, C = None))]
#[allow(non_snake_case)]
pub fn lyap(
    A: &Bound<'_, PyAny>,
    Q: &Bound<'_, PyAny>,
    C: Option<&Bound<'_, PyAny>>,
) -> PyResult<MatrixEquationResult> {
    let py = A.py();
    let a = matrix(A, "A", OneD::Row)?;
    let q = matrix(Q, "Q", OneD::Row)?;
    let sol = match C {
        None => nogil(py, || pendulab_lti::equations::lyap(&a, &q))?,
        Some(c) => {
            let c = -matrix(c, "C", OneD::Row)?;
            nogil(py, || pendulab_lti::equations::sylvester(&a, &q, &c))?
        }
    };
    MatrixEquationResult::from_solution(py, &sol)
}

/// `dlyap(A, Q)`: the discrete Lyapunov (Stein) equation `A X Aᵀ − X + Q = 0`
/// (python-control / MATLAB `dlyap`).
///
/// Raises `pendulab.LinAlgError` (variant `NoUniqueSolution`) when `λᵢ(A) λⱼ(A) = 1` for
/// some pair.
#[pyfunction]
#[allow(non_snake_case)]
pub fn dlyap(A: &Bound<'_, PyAny>, Q: &Bound<'_, PyAny>) -> PyResult<MatrixEquationResult> {
    let py = A.py();
    let a = matrix(A, "A", OneD::Row)?;
    let q = matrix(Q, "Q", OneD::Row)?;
    let sol = nogil(py, || pendulab_lti::equations::dlyap(&a, &q))?;
    MatrixEquationResult::from_solution(py, &sol)
}

result_class!(
    RiccatiResult, "RiccatiResult",
    "The stabilising solution of an algebraic Riccati equation; unpacks as python-control's `X, L, G` (solution, closed-loop eigenvalues, gain).",
    array none,
    unpack {
        x as "X": "The stabilising solution X (symmetric).",
        poles as "L": "Eigenvalues of A − B G (closed-loop poles), complex.",
        gain as "G": "The gain G (control law u = −G x): R⁻¹(BᵀX + Sᵀ) for the CARE, (BᵀXB + R)⁻¹(BᵀXA + Sᵀ) for the DARE.",
    }
    also {
        residual as "residual": "Relative residual of the equation at X.",
        method as "method": "The algorithm that produced X: 'Schur' or 'Doubling'.",
        refinement_steps as "refinement_steps": "Newton refinement steps applied.",
    }
);

impl RiccatiResult {
    /// From pendulab-lti's solution.
    pub fn from_solution(py: Python<'_>, s: &RiccatiSolution) -> PyResult<Self> {
        Ok(Self {
            x: matrix_to_numpy(py, &s.x).into_any().unbind(),
            poles: complex_to_numpy(py, &s.closed_loop_poles)
                .into_any()
                .unbind(),
            gain: matrix_to_numpy(py, &s.gain).into_any().unbind(),
            residual: obj(py, s.residual)?,
            method: obj(py, format!("{:?}", s.method))?,
            refinement_steps: obj(py, s.refinement_steps)?,
        })
    }
}

/// The Riccati data `(A, B, Q, R, S)` with python-control's defaults (`R = I`).
#[allow(clippy::type_complexity)]
fn riccati_data(
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    q: &Bound<'_, PyAny>,
    r: Option<&Bound<'_, PyAny>>,
    s: Option<&Bound<'_, PyAny>>,
    e: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Mat, Mat, Mat, Mat, Option<Mat>)> {
    if e.is_some_and(|e| !e.is_none()) {
        return Err(new_err(
            Kind::InvalidArgument,
            "E: descriptor (generalised) Riccati equations are not supported".into(),
            None,
        ));
    }
    let a = matrix(a, "A", OneD::Row)?;
    let b_one_d = if a.nrows() == 1 {
        OneD::Row
    } else {
        OneD::Column
    };
    let b = matrix(b, "B", b_one_d)?;
    let q = matrix(q, "Q", OneD::Row)?;
    let r = match r {
        Some(r) if !r.is_none() => matrix(r, "R", OneD::Row)?,
        _ => Mat::identity(b.ncols(), b.ncols()),
    };
    let s = match s {
        Some(s) if !s.is_none() => Some(matrix(s, "S", b_one_d)?),
        _ => None,
    };
    Ok((a, b, q, r, s))
}

/// The signature shared by pendulab-lti's `care` and `dare`.
type RiccatiSolver = fn(
    &Mat,
    &Mat,
    &Mat,
    &Mat,
    Option<&Mat>,
    &RiccatiOptions,
) -> pendulab_lti::Result<RiccatiSolution>;

/// Reads the data, runs `solver` without the GIL and wraps its solution.
fn solve_riccati(
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    q: &Bound<'_, PyAny>,
    r: Option<&Bound<'_, PyAny>>,
    s: Option<&Bound<'_, PyAny>>,
    e: Option<&Bound<'_, PyAny>>,
    solver: RiccatiSolver,
) -> PyResult<RiccatiResult> {
    let py = a.py();
    let (a, b, q, r, s) = riccati_data(a, b, q, r, s, e)?;
    let sol = nogil(py, || {
        solver(&a, &b, &q, &r, s.as_ref(), &RiccatiOptions::default())
    })?;
    RiccatiResult::from_solution(py, &sol)
}

/// Defines a `#[pyfunction]` `$name(A, B, Q, R=None, S=None, E=None)` that solves its
/// Riccati equation with pendulab-lti's `$solver` through [`solve_riccati`].
macro_rules! riccati_pyfunction {
    ($(#[$doc:meta])* $name:ident => $solver:path) => {
        $(#[$doc])*
        #[pyfunction]
        #[pyo3(signature = (A, B, Q, R = None, S = None, E = None))]
        #[allow(non_snake_case)]
        pub fn $name(
            A: &Bound<'_, PyAny>,
            B: &Bound<'_, PyAny>,
            Q: &Bound<'_, PyAny>,
            R: Option<&Bound<'_, PyAny>>,
            S: Option<&Bound<'_, PyAny>>,
            E: Option<&Bound<'_, PyAny>>,
        ) -> PyResult<RiccatiResult> {
            solve_riccati(A, B, Q, R, S, E, $solver)
        }
    };
}

riccati_pyfunction!(
    /// `care(A, B, Q, R=None, S=None, E=None)`: the stabilising solution of the continuous
    /// algebraic Riccati equation `AᵀX + XA − (XB + S)R⁻¹(BᵀX + Sᵀ) + Q = 0` (R = I when
    /// omitted), with `G = R⁻¹(BᵀX + Sᵀ)` and the eigenvalues `L` of `A − BG`.
    ///
    /// Solved by the doubling or Schur method with Newton refinement and a certificate that the
    /// closed loop is stable (pendulab-lti `care`); `Q` may be indefinite. Raises
    /// `pendulab.NotStabilizableError` when no stabilising solution exists,
    /// `pendulab.InvalidArgumentError` for a non-symmetric `Q`/`R` or `R` not positive definite.
    care => pendulab_lti::equations::care
);

riccati_pyfunction!(
    /// `dare(A, B, Q, R, S=None, E=None)`: the stabilising solution of the discrete algebraic
    /// Riccati equation `AᵀXA − X − (AᵀXB + S)(BᵀXB + R)⁻¹(BᵀXA + Sᵀ) + Q = 0`, with
    /// `G = (BᵀXB + R)⁻¹(BᵀXA + Sᵀ)` and the eigenvalues `L` of `A − BG`.
    ///
    /// Raises as `care`; `R` may be singular if `BᵀXB + R` is invertible at the solution.
    dare => pendulab_lti::equations::dare
);
