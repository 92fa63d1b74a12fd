//! The Sylvester equation `A X + X B = C`.

use super::MatrixEquationSolution;
use crate::error::Result;
use crate::linalg::Mat;

/// Solves `A X + X B = C` (MATLAB `sylvester(A, B, C)`).
pub fn sylvester(a: &Mat, b: &Mat, c: &Mat) -> Result<MatrixEquationSolution> {
    let _ = (a, b, c);
    todo!("Bartels–Stewart on real Schur forms of A and B")
}
