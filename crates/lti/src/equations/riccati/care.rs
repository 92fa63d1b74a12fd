//! The continuous algebraic Riccati equation.

use super::{RiccatiOptions, RiccatiSolution};
use crate::error::Result;
use crate::linalg::Mat;

/// Solves the CARE `AᵀX + XA − (XB + N)R⁻¹(BᵀX + Nᵀ) + Q = 0` for its stabilising solution.
#[doc(alias = "icare")]
pub fn care(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    options: &RiccatiOptions,
) -> Result<RiccatiSolution> {
    let _ = (a, b, q, r, n, options);
    todo!("ordered Schur method on the Hamiltonian matrix")
}
