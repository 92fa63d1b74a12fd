//! Continuous and discrete Lyapunov equations.

use super::MatrixEquationSolution;
use super::sylvester::check_sum_collisions;
use super::triangular::{RightCoef, solve_quasi_stein, solve_quasi_sylvester};
use crate::Complex64;
use crate::error::{LtiError, Result};
use crate::linalg::schur::real_schur;
use crate::linalg::{Mat, check_finite, check_shape, check_square, symmetrize};

/// Solves the continuous Lyapunov equation `A X + X Aᵀ + Q = 0` (MATLAB `lyap(A, Q)`).
///
/// Bartels–Stewart: with `A = U S Uᵀ` (real Schur), `S Y + Y Sᵀ = −Uᵀ Q U` is solved by block
/// back substitution and `X = U Y Uᵀ`. One Schur decomposition, `O(n³)`.
///
/// The solution is unique iff `λ_i(A) + λ_j(A) ≠ 0` for all pairs (no eigenvalue on the
/// imaginary axis and no pair symmetric about it). If `A` is Hurwitz and `Q ⪰ 0`, then
/// `X ⪰ 0`. For the form `AᵀP + PA + Q = 0` used in stability analysis call `lyap(Aᵀ, Q)`.
/// If `Q` is exactly symmetric the returned `X` is exactly symmetric.
///
/// The returned `residual` is `‖AX + XAᵀ + Q‖_F / (‖AX‖_F + ‖XAᵀ‖_F + ‖Q‖_F)`.
///
/// # Errors
/// [`LtiError::NotSquare`], [`LtiError::DimensionMismatch`], [`LtiError::NonFinite`] for bad
/// input; [`LtiError::NoUniqueSolution`] naming the eigenvalues with
/// `|λ_i + λ_j| ≤ 100·ε·‖A‖_F`; [`LtiError::NoConvergence`] if the Schur decomposition fails.
pub fn lyap(a: &Mat, q: &Mat) -> Result<MatrixEquationSolution> {
    let what = "Lyapunov equation AX + XAᵀ + Q = 0";
    let tol = 100.0 * f64::EPSILON * 2.0 * a.norm();
    schur_frame(
        a,
        q,
        |ev| check_sum_collisions(what, ev, ev, tol),
        |s, f| solve_quasi_sylvester(s, s, RightCoef::TransposeOfUpper, f),
        |x| {
            let ax = a * x;
            let xat = x * a.transpose();
            let res = &ax + &xat + q;
            super::relative_residual(&res, &[ax.norm(), xat.norm(), q.norm()])
        },
    )
}

/// Solves the discrete Lyapunov (Stein) equation `A X Aᵀ − X + Q = 0` (MATLAB `dlyap(A, Q)`).
///
/// With `A = U S Uᵀ` (real Schur) the reduced equation `S Y Sᵀ − Y = −Uᵀ Q U` is solved column
/// block by column block from the last (Barraud 1977; Kitagawa 1977; SLICOT `SB03MX`), and
/// `X = U Y Uᵀ`. One Schur decomposition, `O(n³)`.
///
/// The solution is unique iff `λ_i(A) λ_j(A) ≠ 1` for all pairs. If `A` is Schur-stable and
/// `Q ⪰ 0`, then `X ⪰ 0`. If `Q` is exactly symmetric, so is `X`.
///
/// The returned `residual` is `‖AXAᵀ − X + Q‖_F / (‖AXAᵀ‖_F + ‖X‖_F + ‖Q‖_F)`.
///
/// # Errors
/// [`LtiError::NotSquare`], [`LtiError::DimensionMismatch`], [`LtiError::NonFinite`] for bad
/// input; [`LtiError::NoUniqueSolution`] naming the eigenvalues with
/// `|λ_i λ_j − 1| ≤ 100·ε·max(1, ‖A‖_F²)`; [`LtiError::NoConvergence`] if the Schur
/// decomposition fails.
#[doc(alias = "stein")]
pub fn dlyap(a: &Mat, q: &Mat) -> Result<MatrixEquationSolution> {
    let tol = 100.0 * f64::EPSILON * a.norm().powi(2).max(1.0);
    schur_frame(
        a,
        q,
        |ev| check_unit_products(ev, tol),
        solve_quasi_stein,
        |x| {
            let axa = a * x * a.transpose();
            let res = &axa - x + q;
            super::relative_residual(&res, &[axa.norm(), x.norm(), q.norm()])
        },
    )
}

/// Returns [`LtiError::NoUniqueSolution`] for the discrete Lyapunov equation if some
/// `|λ_i λ_j − 1| ≤ tol` (the eigenvalues `ev` of `A`), naming the closest pair.
fn check_unit_products(ev: &[Complex64], tol: f64) -> Result<()> {
    let mut worst: Option<(f64, usize, usize)> = None;
    for (i, x) in ev.iter().enumerate() {
        for (j, y) in ev.iter().enumerate() {
            let d = (x * y - 1.0).norm();
            if d <= tol && worst.is_none_or(|w| d < w.0) {
                worst = Some((d, i, j));
            }
        }
    }
    if let Some((d, i, j)) = worst {
        return Err(LtiError::NoUniqueSolution {
            what: "discrete Lyapunov equation AXAᵀ − X + Q = 0".into(),
            detail: format!(
                "eigenvalues {:.6e}{:+.6e}j and {:.6e}{:+.6e}j have product 1 (distance {d:.3e}; the operator is singular)",
                ev[i].re, ev[i].im, ev[j].re, ev[j].im
            ),
        });
    }
    Ok(())
}

/// The frame [`lyap`] and [`dlyap`] share: checks `A` (square) and `Q` (`n × n`), both finite;
/// returns the empty solution for `n = 0`; otherwise computes the real Schur form
/// `A = U S Uᵀ`, lets `check` refuse the eigenvalues of `A`, solves the reduced equation in
/// place by `solve(S, F)` from `F = −Uᵀ Q U` (its flag, whether a near-singular block was
/// perturbed, is not used), and returns `X = U F Uᵀ` (`F` and `X`
/// symmetrised when `Q` is exactly symmetric) with the relative residual `residual(X)`.
fn schur_frame(
    a: &Mat,
    q: &Mat,
    check: impl FnOnce(&[Complex64]) -> Result<()>,
    solve: impl FnOnce(&Mat, &mut Mat) -> bool,
    residual: impl FnOnce(&Mat) -> f64,
) -> Result<MatrixEquationSolution> {
    check_square("A", a)?;
    let n = a.nrows();
    check_shape("Q", q, n, n)?;
    check_finite("A", a)?;
    check_finite("Q", q)?;
    if n == 0 {
        return Ok(MatrixEquationSolution {
            x: Mat::zeros(0, 0),
            residual: 0.0,
        });
    }
    let sa = real_schur(a)?;
    check(&sa.eigenvalues())?;
    let (s, u) = sa.into_parts();
    let mut f = -(u.transpose() * q * &u);
    let symmetric = q == &q.transpose();
    if symmetric {
        f = symmetrize(&f);
    }
    solve(&s, &mut f);
    let mut x = &u * f * u.transpose();
    if symmetric {
        x = symmetrize(&x);
    }
    let residual = residual(&x);
    Ok(MatrixEquationSolution { x, residual })
}
