//! The Sylvester equation `A X + X B = C`.

use super::MatrixEquationSolution;
use super::triangular::{RightCoef, solve_quasi_sylvester};
use crate::error::{LtiError, Result};
use crate::linalg::schur::real_schur;
use crate::linalg::{Complex64, Mat, check_finite, check_shape, check_square};

/// Solves `A X + X B = C` (MATLAB `sylvester(A, B, C)`) by the Bartels–Stewart method.
///
/// `A` is `m × m`, `B` is `n × n`, `C` and `X` are `m × n`. With the real Schur forms
/// `A = U S Uᵀ`, `B = V T Vᵀ` the equation becomes `S Y + Y T = Uᵀ C V`, solved by block
/// back substitution over the 1×1/2×2 diagonal blocks, and `X = U Y Vᵀ` (Bartels & Stewart,
/// Comm. ACM 15, 1972). Cost `O(m³ + n³)`; the method is backward stable in the sense that the
/// relative residual is a modest multiple of machine precision.
///
/// The solution is unique iff `λ_i(A) + μ_j(B) ≠ 0` for all eigenvalue pairs.
///
/// The returned `residual` is `‖AX + XB − C‖_F / (‖AX‖_F + ‖XB‖_F + ‖C‖_F)`.
///
/// # Errors
/// - [`LtiError::NotSquare`], [`LtiError::DimensionMismatch`], [`LtiError::NonFinite`] for bad
///   input;
/// - [`LtiError::NoUniqueSolution`] naming the colliding eigenvalues when
///   `|λ_i + μ_j| ≤ 100·ε·(‖A‖_F + ‖B‖_F)` (a collision at rounding level);
/// - [`LtiError::NoConvergence`] if a Schur decomposition fails.
pub fn sylvester(a: &Mat, b: &Mat, c: &Mat) -> Result<MatrixEquationSolution> {
    check_square("A", a)?;
    check_square("B", b)?;
    let (m, n) = (a.nrows(), b.nrows());
    check_shape("C", c, m, n)?;
    check_finite("A", a)?;
    check_finite("B", b)?;
    check_finite("C", c)?;
    if m == 0 || n == 0 {
        return Ok(MatrixEquationSolution {
            x: Mat::zeros(m, n),
            residual: 0.0,
        });
    }
    let sa = real_schur(a)?;
    let sb = real_schur(b)?;
    let la = sa.eigenvalues();
    let lb = sb.eigenvalues();
    let tol = 100.0 * f64::EPSILON * (a.norm() + b.norm());
    check_sum_collisions("Sylvester equation AX + XB = C", &la, &lb, tol)?;
    let (s, u) = sa.into_parts();
    let (t, v) = sb.into_parts();
    let mut f = u.transpose() * c * &v;
    solve_quasi_sylvester(&s, &t, RightCoef::Upper, &mut f);
    let x = &u * f * v.transpose();
    let ax = a * &x;
    let xb = &x * b;
    let res = &ax + &xb - c;
    let residual = super::relative_residual(&res, &[ax.norm(), xb.norm(), c.norm()]);
    Ok(MatrixEquationSolution { x, residual })
}

/// Returns [`LtiError::NoUniqueSolution`] if some `|λ_i + μ_j| ≤ tol`.
pub(crate) fn check_sum_collisions(
    what: &str,
    la: &[Complex64],
    lb: &[Complex64],
    tol: f64,
) -> Result<()> {
    let mut worst: Option<(f64, Complex64, Complex64)> = None;
    for &x in la {
        for &y in lb {
            let d = (x + y).norm();
            if d <= tol && worst.is_none_or(|w| d < w.0) {
                worst = Some((d, x, y));
            }
        }
    }
    if let Some((d, x, y)) = worst {
        return Err(LtiError::NoUniqueSolution {
            what: what.to_string(),
            detail: format!(
                "eigenvalues {:.6e}{:+.6e}j and {:.6e}{:+.6e}j sum to {d:.3e} (the operator is singular)",
                x.re, x.im, y.re, y.im
            ),
        });
    }
    Ok(())
}
