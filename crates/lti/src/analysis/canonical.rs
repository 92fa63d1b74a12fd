//! Canonical forms of single-input or single-output systems (the book's 可制御正準形 and
//! 可観測正準形; MATLAB `canon(…,'companion')`): the similarity transformation, the
//! characteristic coefficients and how well-conditioned the transformation is.

use super::{cond2, controllability_staircase, ctrb};
use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::linalg::Mat;
use crate::polynomial::Polynomial;
use crate::state_space::StateSpace;

/// A similarity transformation to a canonical form, `x = T x̂`:
/// `Â = T⁻¹ A T`, `B̂ = T⁻¹ B`, `Ĉ = C T`, `D̂ = D`.
#[derive(Debug, Clone, PartialEq)]
pub struct CanonicalForm<D: TimeDomain> {
    /// The system in canonical coordinates.
    pub system: StateSpace<D>,
    /// The transformation `T` (`x = T x̂`).
    pub t: Mat,
    /// Coefficients `[a₀, a₁, …, aₙ₋₁]` of the characteristic polynomial
    /// `sⁿ + aₙ₋₁ sⁿ⁻¹ + … + a₀`.
    pub characteristic_coefficients: Vec<f64>,
    /// `‖A T − T Â‖_F / (‖A‖_F ‖T‖_F)`: how exactly `T` maps `A` to the canonical `Â`.
    pub residual: f64,
    /// 2-norm condition number of `T` (the canonical forms are notoriously ill-conditioned
    /// for larger `n`; this says how much).
    pub condition: f64,
}

/// Controllable canonical form of a single-input system (MATLAB `canon(sys,'companion')`
/// transposed; the book's 可制御正準形): `x = T x̂` with
/// `Â = [[0, 1, 0, …], …, [0, …, 0, 1], [−a₀, −a₁, …, −aₙ₋₁]]`, `B̂ = [0, …, 0, 1]ᵀ`.
///
/// `T = M_c W` with `M_c = [B, AB, …, Aⁿ⁻¹B]` and `W` the Hankel matrix of the
/// characteristic coefficients, `W = [[a₁, a₂, …, aₙ₋₁, 1], [a₂, …, 1, 0], …, [1, 0, …, 0]]`.
/// The characteristic polynomial comes from the eigenvalues of `A` (more accurate than the
/// Faddeev–Leverrier recursion). `Â` is returned in its exact companion structure; the
/// [`residual`](CanonicalForm::residual) says how well `T` realises it.
///
/// # Errors
/// [`LtiError::InvalidArgument`] unless `nu = 1`; [`LtiError::NotControllable`] if `(A, B)`
/// is not controllable.
#[doc(alias = "canon")]
pub fn controllable_canonical_form<D: TimeDomain>(sys: &StateSpace<D>) -> Result<CanonicalForm<D>> {
    if sys.nu() != 1 {
        return Err(LtiError::InvalidArgument(format!(
            "controllable canonical form needs a single input, system has {}",
            sys.nu()
        )));
    }
    let n = sys.nx();
    let st = controllability_staircase(sys.a(), sys.b(), None)?;
    if st.controllable_dimension < n {
        return Err(LtiError::NotControllable {
            controllable_dimension: st.controllable_dimension,
            nx: n,
            mode: st
                .uncontrollable_modes()?
                .first()
                .copied()
                .unwrap_or_default(),
        });
    }
    let charpoly = Polynomial::from_roots(&sys.poles()?)?;
    // Coefficients a_k of s^k, k = 0..n−1 (monic, so a_n = 1).
    let coeff: Vec<f64> = (0..n).map(|k| charpoly.coefficient_of_power(k)).collect();
    let mut w = Mat::zeros(n, n);
    for i in 0..n {
        for j in 0..n - i {
            let k = i + j + 1; // coefficient index a_{i+j+1}, with a_n = 1
            w[(i, j)] = if k == n { 1.0 } else { coeff[k] };
        }
    }
    let t = ctrb(sys.a(), sys.b())? * w;
    let mut ahat = Mat::zeros(n, n);
    for i in 0..n.saturating_sub(1) {
        ahat[(i, i + 1)] = 1.0;
    }
    for j in 0..n {
        ahat[(n - 1, j)] = -coeff[j];
    }
    let mut bhat = Mat::zeros(n, 1);
    if n > 0 {
        bhat[(n - 1, 0)] = 1.0;
    }
    let chat = sys.c() * &t;
    let residual = if n == 0 {
        0.0
    } else {
        (sys.a() * &t - &t * &ahat).norm() / (sys.a().norm().max(f64::MIN_POSITIVE) * t.norm())
    };
    let condition = cond2(&t);
    Ok(CanonicalForm {
        system: StateSpace::new(ahat, bhat, chat, sys.d().clone(), sys.domain())?,
        t,
        characteristic_coefficients: coeff,
        residual,
        condition,
    })
}

/// Observable canonical form of a single-output system, the dual of
/// [`controllable_canonical_form`]: `x = T x̂` with `Â` the transpose of the controllable
/// companion matrix and `Ĉ = [0, …, 0, 1]`. `T = W_d⁻ᵀ` where `W_d` is the controllable-form
/// transformation of `(Aᵀ, Cᵀ)`.
///
/// # Errors
/// [`LtiError::InvalidArgument`] unless `ny = 1`; [`LtiError::NotControllable`] (of the
/// dual pair, i.e. `(C, A)` unobservable).
pub fn observable_canonical_form<D: TimeDomain>(sys: &StateSpace<D>) -> Result<CanonicalForm<D>> {
    if sys.ny() != 1 {
        return Err(LtiError::InvalidArgument(format!(
            "observable canonical form needs a single output, system has {}",
            sys.ny()
        )));
    }
    let dual = StateSpace::new(
        sys.a().transpose(),
        sys.c().transpose(),
        sys.b().transpose(),
        sys.d().transpose(),
        sys.domain(),
    )?;
    let f = controllable_canonical_form(&dual)?;
    let td = &f.t;
    let n = sys.nx();
    let t = td
        .transpose()
        .lu()
        .solve(&Mat::identity(n, n))
        .ok_or(LtiError::Singular {
            what: "observable canonical transformation".into(),
            rcond: 0.0,
        })?;
    let ahat = f.system.a().transpose();
    let bhat = td.transpose() * sys.b();
    let chat = f.system.b().transpose();
    let residual = if n == 0 {
        0.0
    } else {
        (sys.a() * &t - &t * &ahat).norm() / (sys.a().norm().max(f64::MIN_POSITIVE) * t.norm())
    };
    Ok(CanonicalForm {
        system: StateSpace::new(ahat, bhat, chat, sys.d().clone(), sys.domain())?,
        condition: f.condition,
        t,
        characteristic_coefficients: f.characteristic_coefficients,
        residual,
    })
}
