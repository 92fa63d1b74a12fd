//! The Newton (Kleinman) correction of a doubling solution by the Cayley-transformed Smith
//! iteration, without a Schur decomposition of the closed loop.
//!
//! The Kleinman step for a CARE solution `X₀` with closed loop `F = A − BK(X₀)` solves the
//! Lyapunov equation `FᵀΔ + ΔF = −Res(X₀)`. With a shift `p > 0`, `M = (F − pI)⁻¹` and the
//! Cayley transform `S = (F + pI)(F − pI)⁻¹ = I + 2pM`, the equation is equivalent to the Stein
//! equation
//!
//! ```text
//! Δ − SᵀΔS = C_p,    C_p = 2p Mᵀ Res M
//! ```
//!
//! (expand `SᵀΔS` with `S = I + 2pM`: `Δ − SᵀΔS = −2pMᵀ(ΔF + FᵀΔ)M`). For a Hurwitz `F` every
//! eigenvalue of `S`, `(λ + p)/(λ − p)`, lies inside the unit circle and
//! `Δ = Σ_k (Sᵀ)ᵏ C_p Sᵏ`, summed by Smith's doubling (R. A. Smith, "Matrix equation
//! XA + BX = C", SIAM J. Appl. Math. 16, 1968; Penzl, "A cyclic low-rank Smith method for
//! large sparse Lyapunov equations", SIAM J. Sci. Comput. 21, 2000, §2):
//!
//! ```text
//! Δ_{j+1} = Δ_j + S_jᵀ Δ_j S_j,    S_{j+1} = S_j²,    Δ_0 = C_p, S_0 = S,
//! ```
//!
//! so that `Δ_j` holds the first `2ʲ` terms and `Δ − Δ_j = S_jᵀ Δ S_j`: the relative truncation
//! error is at most `‖S_j‖_F²`, which the iteration monitors.
//!
//! **Why this suits the doubling method.** The structure-preserving doubling algorithm with
//! Cayley shift `γ` converges at the rate `max |(λ + γ)/(λ − γ)|` over the stable Hamiltonian
//! eigenvalues — which are the eigenvalues of the closed loop `F`. With `p = γ` Smith's
//! iteration contracts at exactly that rate, so it needs no more doublings than the Riccati
//! iteration just took; and a Newton correction only needs a few correct digits (the error of
//! `Δ` enters the new residual linearly, multiplied by the size of the old one), so the
//! iteration stops at [`SMITH_TOL`]. Every product is a matrix–matrix product (about
//! `6n³` flops per doubling after a `≈ 5n³` set-up), which is cheaper than the real Schur
//! decomposition of `F` that the exact step needs.
//!
//! The step is an approximation: [`Finisher::finish_with`](super::Finisher::finish_with)
//! keeps it only if it lowers the residual and otherwise runs the exact step.

use crate::error::{LtiError, Result};
use crate::linalg::dense::Lu;
use crate::linalg::{Mat, check_finite, symmetrize_in_place};

/// Bound on the relative truncation error `‖Δ − Δ_j‖_F/‖Δ‖_F ≤ ‖S_j‖_F²` at which the Smith
/// iteration stops. The new Riccati residual after a step with a relative error `e` in `Δ` is
/// about `e·‖L_F‖‖L_F⁻¹‖` times the old one (`L_F` the Lyapunov operator), so `1e-8` leaves
/// the step exact to rounding level for operators with condition up to `~10⁴` relative to
/// the residual decrease a Newton step needs, and costs at most one doubling more than `1e-4`
/// (the error squares at every doubling).
pub(crate) const SMITH_TOL: f64 = 1e-8;

/// At most this many doublings (`2¹²` terms of the series): a slower contraction means the
/// closed loop has eigenvalues near the axis relative to the shift, and the exact step is the
/// better tool.
pub(crate) const SMITH_MAX_DOUBLINGS: usize = 12;

/// `‖S_j‖_F²` beyond this (transient growth of a highly non-normal closed loop) ends the
/// iteration: the rounding errors of the sum would be amplified by as much.
const SMITH_GROWTH_LIMIT: f64 = 1e8;

/// The Cayley shift of a doubling solution, for its Newton correction (module documentation).
#[derive(Debug, Clone, Copy)]
pub(crate) struct CayleySmith {
    /// The shift `p > 0` (the doubling method's `γ`, in the units of the eigenvalues of `F`).
    pub shift: f64,
}

impl CayleySmith {
    /// The Newton correction `Δ` with `FᵀΔ + ΔF = −res` (module documentation).
    ///
    /// # Errors
    /// [`LtiError::Singular`] if `F − pI` is numerically singular; [`LtiError::NoConvergence`]
    /// if `‖S_j‖_F²` does not fall below [`SMITH_TOL`] within [`SMITH_MAX_DOUBLINGS`] doublings
    /// or grows beyond `10⁸` (e.g. `F` not Hurwitz); [`LtiError::NonFinite`] for a non-finite
    /// result. Each makes the caller fall back to the exact step.
    pub(crate) fn newton_step(&self, f: &Mat, res: &Mat) -> Result<Mat> {
        let n = f.nrows();
        let p = self.shift;
        let mut fp = f.clone();
        for i in 0..n {
            fp[(i, i)] -= p;
        }
        let lu = Lu::new(&fp);
        let rcond = lu.rcond();
        if rcond.is_nan() || rcond < 1e3 * f64::EPSILON {
            return Err(LtiError::Singular {
                what: "F − pI in the Smith iteration of the Newton step".into(),
                rcond,
            });
        }
        // M = (F − pI)⁻¹, S₀ = I + 2pM, Δ₀ = C_p = 2p Mᵀ Res M.
        let m = lu.inverse();
        let mut work = Mat::zeros(n, n);
        work.gemm(1.0, res, &m, 0.0);
        let mut st = m.transpose();
        let mut delta = Mat::zeros(n, n);
        delta.gemm(2.0 * p, &st, &work, 0.0);
        let mut s = m * (2.0 * p);
        for i in 0..n {
            s[(i, i)] += 1.0;
        }
        let mut next = Mat::zeros(n, n);
        for doubling in 0..SMITH_MAX_DOUBLINGS {
            // Δ ← Δ + Sᵀ Δ S (with Sᵀ kept as a copy so both products run as plain gemm).
            s.transpose_to(&mut st);
            work.gemm(1.0, &delta, &s, 0.0);
            delta.gemm(1.0, &st, &work, 1.0);
            // Truncation error of the sum so far: ‖S_{j+1}‖_F² with S_{j+1} = S_j², bounded
            // first by ‖S_j‖_F⁴ (no product needed when that already suffices).
            let s2 = s.norm_squared();
            if s2 * s2 <= SMITH_TOL {
                return finish(delta);
            }
            next.gemm(1.0, &s, &s, 0.0);
            std::mem::swap(&mut s, &mut next);
            let s2 = s.norm_squared();
            if s2 <= SMITH_TOL {
                return finish(delta);
            }
            if s2.is_nan() || s2 > SMITH_GROWTH_LIMIT {
                return Err(LtiError::NoConvergence {
                    algorithm: "Smith iteration of the Newton step (‖Sʲ‖ grows)".into(),
                    iterations: doubling + 1,
                });
            }
        }
        Err(LtiError::NoConvergence {
            algorithm: "Smith iteration of the Newton step".into(),
            iterations: SMITH_MAX_DOUBLINGS,
        })
    }
}

/// Symmetrises the sum (it is symmetric up to rounding) and checks it is finite.
fn finish(mut delta: Mat) -> Result<Mat> {
    symmetrize_in_place(&mut delta);
    check_finite("Newton correction from the Smith iteration", &delta)?;
    Ok(delta)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::testing::splitmix_matrix as test_matrix;

    /// A Hurwitz matrix: a random matrix shifted so that its rightmost eigenvalue is at `−1`.
    fn hurwitz(n: usize, seed: u64) -> Mat {
        let m = test_matrix(n, n, seed);
        let right = crate::linalg::eigenvalues(&m)
            .unwrap()
            .iter()
            .map(|l| l.re)
            .fold(f64::NEG_INFINITY, f64::max);
        &m - Mat::identity(n, n) * (right + 1.0)
    }

    #[test]
    fn smith_step_solves_the_kleinman_equation_to_its_tolerance() {
        for (n, seed) in [(1, 11), (5, 12), (30, 13), (100, 14)] {
            let f = hurwitz(n, seed);
            let r = {
                let m = test_matrix(n, n, seed + 50);
                (&m + m.transpose()) * 0.5
            };
            // Shift: the geometric mean of the extreme eigenvalue magnitudes, the usual
            // single-shift choice (Penzl 2000, §2.2).
            let mags: Vec<f64> = crate::linalg::eigenvalues(&f)
                .unwrap()
                .iter()
                .map(|l| l.norm())
                .collect();
            let lo = mags.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = mags.iter().copied().fold(0.0, f64::max);
            let d = CayleySmith {
                shift: (lo * hi).sqrt(),
            }
            .newton_step(&f, &r)
            .unwrap();
            // The exact solution by Bartels–Stewart on a real Schur form (an independent
            // algorithm). The Smith sum stops at a relative truncation error ≤ SMITH_TOL; the
            // rounding of the set-up and of the products adds O(κ(F − pI)·n·ε), far below it.
            let exact = crate::equations::lyap(&f.transpose(), &r).unwrap().x;
            let diff = (&d - &exact).norm() / exact.norm();
            assert!(diff <= SMITH_TOL, "n = {n}: differs by {diff:e}");
        }
    }

    #[test]
    fn smith_step_refuses_an_unstable_closed_loop() {
        // One eigenvalue at +1: |(1 + p)/(1 − p)| > 1 for every p > 0, so ‖Sʲ‖ grows.
        let n = 6;
        let f = hurwitz(n, 21) + Mat::identity(n, n) * 2.0;
        let r = Mat::identity(n, n);
        let e = CayleySmith { shift: 1.7 }.newton_step(&f, &r).unwrap_err();
        assert!(
            matches!(e, LtiError::NoConvergence { .. }),
            "unexpected error {e:?}"
        );
    }

    #[test]
    fn smith_step_refuses_a_shift_at_an_eigenvalue() {
        // F − pI singular: F = diag(−1, 1.5) shifted by p = 1.5.
        let f = Mat::from_row_slice(2, 2, &[-1.0, 0.0, 0.0, 1.5]);
        let e = CayleySmith { shift: 1.5 }
            .newton_step(&f, &Mat::identity(2, 2))
            .unwrap_err();
        assert!(matches!(e, LtiError::Singular { .. }), "unexpected {e:?}");
    }
}
