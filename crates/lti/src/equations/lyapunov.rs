//! Continuous and discrete Lyapunov equations.

use super::MatrixEquationSolution;
use crate::error::Result;
use crate::linalg::Mat;

/// Solves the continuous Lyapunov equation `A X + X Aᵀ + Q = 0` (MATLAB `lyap(A, Q)`).
pub fn lyap(a: &Mat, q: &Mat) -> Result<MatrixEquationSolution> {
    let _ = (a, q);
    todo!("Bartels–Stewart on the real Schur form")
}

/// Solves the discrete Lyapunov (Stein) equation `A X Aᵀ − X + Q = 0` (MATLAB `dlyap(A, Q)`).
#[doc(alias = "stein")]
pub fn dlyap(a: &Mat, q: &Mat) -> Result<MatrixEquationSolution> {
    let _ = (a, q);
    todo!("Bartels–Stewart-type solver on the real Schur form")
}
