//! Matrix equations: Sylvester, Lyapunov (continuous and discrete), algebraic Riccati
//! (continuous and discrete, with cross term).
//!
//! Every solver returns its solution together with its **relative residual**: the Frobenius
//! norm of the equation's residual divided by the sum of the Frobenius norms of the equation's
//! terms evaluated at the solution. A backward-stable solver achieves a relative residual of a
//! small multiple of machine precision (≈ 1e-16) times a modest function of the dimension.
//!
//! | equation | function | MATLAB |
//! |---|---|---|
//! | `A X + X B = C` | [`sylvester()`] | `sylvester(A,B,C)` |
//! | `A X + X Aᵀ + Q = 0` | [`lyap`] | `lyap(A,Q)` |
//! | `A X Aᵀ − X + Q = 0` | [`dlyap`] | `dlyap(A,Q)` |
//! | `AᵀX + XA − (XB+N)R⁻¹(BᵀX+Nᵀ) + Q = 0` | [`care`] | `care`/`icare` |
//! | `AᵀXA − X − (AᵀXB+N)(BᵀXB+R)⁻¹(BᵀXA+Nᵀ) + Q = 0` | [`dare`] | `dare`/`idare` |

pub mod lyapunov;
pub mod riccati;
pub mod sylvester;
pub(crate) mod triangular;

pub use lyapunov::{dlyap, lyap};
pub use riccati::{RiccatiMethod, RiccatiOptions, RiccatiSolution, care, dare};
pub use sylvester::sylvester;

use crate::linalg::Mat;

/// Solution of a linear matrix equation with its relative residual.
#[derive(Debug, Clone, PartialEq)]
pub struct MatrixEquationSolution {
    /// The solution `X`.
    pub x: Mat,
    /// Relative residual `‖residual‖_F / Σ ‖term‖_F` (see the module documentation).
    pub residual: f64,
}

/// Relative residual helper: `‖res‖_F / Σ ‖terms‖_F`, or `‖res‖_F` when every term vanishes.
pub(crate) fn relative_residual(res: &Mat, term_norms: &[f64]) -> f64 {
    let r = res.norm();
    let s: f64 = term_norms.iter().sum();
    if s > 0.0 { r / s } else { r }
}
