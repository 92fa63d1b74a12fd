//! The discrete algebraic Riccati equation.

use super::{RiccatiOptions, RiccatiSolution};
use crate::error::Result;
use crate::linalg::Mat;

/// Solves the DARE `AᵀXA − X − (AᵀXB + N)(BᵀXB + R)⁻¹(BᵀXA + Nᵀ) + Q = 0` for its
/// stabilising solution.
#[doc(alias = "idare")]
pub fn dare(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    options: &RiccatiOptions,
) -> Result<RiccatiSolution> {
    let _ = (a, b, q, r, n, options);
    todo!("ordered QZ on the extended symplectic pencil")
}
