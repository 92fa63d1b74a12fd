//! From a stable subspace to the solution, and what a method hands on to the refinement:
//! `X = U₂U₁⁻¹` with its conditioning check (Laub's method and the H∞ Riccati equations), the
//! [`Computed`] solution with its optional [`NewtonHint`], and the closed loop
//! [`ClosedLoopSchur`] of Laub's method, which gives a Newton step without a new Schur
//! decomposition.

use crate::error::{LtiError, Result};
use crate::linalg::{Mat, check_finite, symmetrize};

/// Basis `[U1; U2]` (`2n × n`, orthonormal columns) of a stable invariant/deflating subspace →
/// `X = U2 U1⁻¹` (symmetrised), with a conditioning check on `U1`.
pub(crate) fn solution_from_subspace(u1: &Mat, u2: &Mat) -> Result<Mat> {
    solution_and_factor_from_subspace(u1, u2).map(|(x, _)| x)
}

/// [`solution_from_subspace`], also returning the LU factorisation of `U1`.
pub(crate) fn solution_and_factor_from_subspace(
    u1: &Mat,
    u2: &Mat,
) -> Result<(Mat, crate::linalg::dense::Lu)> {
    let n = u1.nrows();
    let lu = crate::linalg::dense::Lu::new(u1);
    let rcond = lu.rcond();
    if rcond.is_nan() || rcond <= n as f64 * f64::EPSILON {
        return Err(LtiError::IllConditioned {
            what: format!(
                "the Riccati solution X = U2 U1⁻¹ ({n} states; condition number of the \
                 stable subspace basis block U1)"
            ),
            condition: 1.0 / rcond,
            limit: 1.0 / (n as f64 * f64::EPSILON),
        });
    }
    // U1ᵀ Xᵀ = U2ᵀ.
    let mut xt = u2.transpose();
    lu.solve_transpose_in_place(&mut xt);
    Ok((symmetrize(&xt), lu))
}

/// A computed (unrefined) solution, with what its method knows about its closed loop.
pub(crate) struct Computed {
    /// The solution.
    pub x: Mat,
    /// Data for a cheaper Newton step than the exact one (continuous time only).
    pub hint: Option<NewtonHint>,
}

/// What a method knows about the closed loop `A − BK(X)` of its solution, used by
/// [`Finisher::finish_with`](super::Finisher::finish_with) for a Newton step without a Schur
/// decomposition of `A − BK`.
pub(crate) enum NewtonHint {
    /// `A − BK(X) = U₁ T₁₁ U₁⁻¹` from the ordered Schur form of the Hamiltonian (Laub's
    /// method).
    Schur(ClosedLoopSchur),
    /// The Cayley shift under which the doubling method converged, for the Smith iteration
    /// (structure-preserving doubling).
    Smith(super::smith::CayleySmith),
}

impl From<Mat> for Computed {
    fn from(x: Mat) -> Self {
        Self { x, hint: None }
    }
}

/// The closed loop of a CARE solution from Laub's method: with `H [U₁; U₂] = [U₁; U₂] T₁₁`
/// (stable invariant subspace of the Hamiltonian, `T₁₁` quasi-upper-triangular) and
/// `X = U₂U₁⁻¹`, the first block row gives `(Ã − GX) U₁ = U₁ T₁₁`, i.e.
/// `A − BK = U₁ T₁₁ U₁⁻¹` (also for the scaled Hamiltonian, whose `U₁` and `T₁₁` are those
/// of `H`).
///
/// The Kleinman step `(A−BK)ᵀΔ + Δ(A−BK) = −Res` then becomes, with `Y = U₁ᵀ Δ U₁`, the
/// quasi-triangular Lyapunov equation `T₁₁ᵀ Y + Y T₁₁ = −U₁ᵀ Res U₁`, solved by the
/// Bartels–Stewart back substitution without a new Schur decomposition; `Δ = U₁⁻ᵀ Y U₁⁻¹`.
/// This is the exact Newton step up to rounding amplified by `cond(U₁)` (the step is kept only
/// if it lowers the residual, see [`Finisher::finish_with`](super::Finisher::finish_with)).
pub(crate) struct ClosedLoopSchur {
    /// `U₁`, the top block of the stable subspace basis.
    pub u1: Mat,
    /// LU factorisation of `U₁`.
    pub lu: crate::linalg::dense::Lu,
    /// `T₁₁`, the stable block of the ordered Schur form.
    pub t11: Mat,
}

impl ClosedLoopSchur {
    /// The Newton correction `Δ` for the residual matrix `res` (see the type documentation).
    pub(super) fn newton_step(&self, res: &Mat) -> Result<Mat> {
        let n = self.t11.nrows();
        let c = -(self.u1.transpose() * res * &self.u1);
        // T₁₁ᵀ is lower quasi-triangular; with the flip J (reversed identity),
        // S = J T₁₁ᵀ J is upper quasi-triangular and S (JYJ) + (JYJ) Sᵀ = J C J.
        let s = Mat::from_fn(n, n, |i, j| self.t11[(n - 1 - j, n - 1 - i)]);
        let mut f = symmetrize(&Mat::from_fn(n, n, |i, j| c[(n - 1 - i, n - 1 - j)]));
        crate::equations::triangular::solve_quasi_sylvester(
            &s,
            &s,
            crate::equations::triangular::RightCoef::TransposeOfUpper,
            &mut f,
        );
        let mut w = Mat::from_fn(n, n, |i, j| f[(n - 1 - i, n - 1 - j)]);
        // Δ = U₁⁻ᵀ Y U₁⁻¹: W = U₁⁻ᵀ Y, then Δᵀ = U₁⁻ᵀ Wᵀ.
        self.lu.solve_transpose_in_place(&mut w);
        let mut d = w.transpose();
        self.lu.solve_transpose_in_place(&mut d);
        check_finite("Newton correction from the Hamiltonian Schur form", &d)?;
        Ok(symmetrize(&d))
    }
}
