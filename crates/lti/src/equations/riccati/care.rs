//! The continuous algebraic Riccati equation.

use super::{
    ClosedLoopSchur, Computed, Domain, Finisher, Reduced, RiccatiMethod, RiccatiOptions,
    RiccatiSolution, empty_solution, reduce, scale_factor, solution_and_factor_from_subspace,
    solve_with_fallback, validate,
};
use crate::error::{LtiError, Result};
use crate::linalg::dense::Lu;
use crate::linalg::schur::real_schur;
use crate::linalg::{Mat, symmetrize};

/// Solves the CARE `AᵀX + XA − (XB + N)R⁻¹(BᵀX + Nᵀ) + Q = 0` for its stabilising solution
/// (MATLAB `icare`/`care`).
///
/// Inputs: `A` `n×n`, `B` `n×m`, `Q` `n×n` symmetric, `R` `m×m` symmetric positive definite,
/// optional cross term `N` `n×m`. The stabilising solution `X = Xᵀ` makes `A − BK` Hurwitz with
/// `K = R⁻¹(BᵀX + Nᵀ)` (control law `u = −Kx`); it exists and is unique iff `(A, B)` is
/// stabilisable and the Hamiltonian matrix
/// `H = [[Ã, −G], [−Q̃, −Ãᵀ]]` (`Ã = A − BR⁻¹Nᵀ`, `G = BR⁻¹Bᵀ`, `Q̃ = Q − NR⁻¹Nᵀ`) has no
/// eigenvalue on the imaginary axis — for LQR data (`[[Q, N], [Nᵀ, R]] ⪰ 0`) iff `(A, B)` is
/// stabilisable and `(Q̃, Ã)` has no unobservable mode on the imaginary axis.
///
/// Methods ([`RiccatiOptions::method`]):
/// - **Schur** (default first choice): Laub's method — real Schur form of `H`, stable
///   eigenvalues moved to the top-left by direct swapping (Bai–Demmel), `X = U₂₁U₁₁⁻¹` from the
///   stable invariant subspace (A. J. Laub, "A Schur method for solving algebraic Riccati
///   equations", IEEE TAC 24, 1979; SLICOT `SB02MD`).
/// - **Doubling**: structure-preserving doubling after a Cayley transform (Chu, Fan & Lin,
///   "A structure-preserving doubling algorithm for continuous-time algebraic Riccati
///   equations", Linear Algebra Appl. 396, 2005).
///
/// With [`RiccatiMethod::Auto`], problems with `n ≤ 8` states and `m ≤ n` inputs first go
/// through a fixed-size (stack-allocated) doubling + Newton path with strict acceptance
/// (relative residual ≤ `100·n·ε`, Hurwitz closed loop, `X ⪰ 0` when `Q̃ ⪰ 0`); the result then
/// reports [`RiccatiMethod::Doubling`]. When it declines, the methods above run as described.
///
/// The result is then refined by Kleinman–Newton steps in residual-correction form
/// (`(A−BK)ᵀΔ + Δ(A−BK) = −Res(X)`, kept only if the residual drops) and checked: relative
/// residual ≤ [`RESIDUAL_LIMIT`](super::RESIDUAL_LIMIT), all closed-loop poles in the open
/// left half-plane.
///
/// # Errors
/// - [`LtiError::DimensionMismatch`], [`LtiError::NotSquare`], [`LtiError::NonFinite`],
///   [`LtiError::NotSymmetric`] for malformed data;
/// - [`LtiError::NotPositiveDefinite`] if `R` is not positive definite;
/// - [`LtiError::NotStabilizable`] (an uncontrollable mode that is not stable, with its PBH
///   margin), [`LtiError::NotDetectable`] (an unobservable mode on the imaginary axis),
///   [`LtiError::BoundaryEigenvalue`] (Hamiltonian eigenvalue on the imaginary axis) when no
///   stabilising solution exists;
/// - [`LtiError::Singular`], [`LtiError::Inaccurate`], [`LtiError::NoConvergence`] on numerical
///   breakdown of every method tried.
#[doc(alias = "icare")]
pub fn care(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    options: &RiccatiOptions,
) -> Result<RiccatiSolution> {
    let dims = validate(a, b, q, r, n, true)?;
    if dims.n == 0 {
        return Ok(empty_solution(dims.m, RiccatiMethod::Schur));
    }
    if options.method == RiccatiMethod::Auto
        && dims.n <= super::small::SMALL_MAX
        && let Some(sol) = super::small::care_small(a, b, q, r, n, options)
    {
        return Ok(sol);
    }
    let red = reduce(a, b, q, r, n)?;
    let fin = Finisher {
        domain: Domain::Continuous,
        a,
        b,
        q,
        r,
        n,
        red: &red,
    };
    let candidates: Vec<RiccatiMethod> = match options.method {
        RiccatiMethod::Auto => vec![RiccatiMethod::Schur, RiccatiMethod::Doubling],
        m => vec![m],
    };
    solve_with_fallback(&fin, &candidates, options, |m| match m {
        RiccatiMethod::Schur | RiccatiMethod::Auto => care_schur(&red, options.scaling),
        RiccatiMethod::Doubling => care_doubling(&red, options.scaling).map(Into::into),
    })
}

/// Builds the (scaled) Hamiltonian `[[Ã, −sG], [−Q̃/s, −Ãᵀ]]`.
pub(crate) fn hamiltonian(red: &Reduced, s: f64) -> Mat {
    let n = red.a.nrows();
    let mut h = Mat::zeros(2 * n, 2 * n);
    h.view_mut((0, 0), (n, n)).copy_from(&red.a);
    h.view_mut((0, n), (n, n)).copy_from(&(&red.g * -s));
    h.view_mut((n, 0), (n, n)).copy_from(&(&red.q * (-1.0 / s)));
    h.view_mut((n, n), (n, n)).copy_from(&(-red.a.transpose()));
    h
}

/// Laub's ordered-Schur method on the Hamiltonian (unrefined solution, with the Schur data of
/// its closed loop for the refinement).
pub(crate) fn care_schur(red: &Reduced, scaling: bool) -> Result<Computed> {
    let n = red.a.nrows();
    let s = scale_factor(red, scaling);
    let h = hamiltonian(red, s);
    let hnorm = h.norm();
    let mut sch = real_schur(&h)?;
    let ev = sch.eigenvalues();
    let closest = ev
        .iter()
        .copied()
        .min_by(|x, y| x.re.abs().total_cmp(&y.re.abs()))
        .unwrap_or_default();
    // Eigenvalues on the axis to rounding level (a Hamiltonian eigenvalue pair ±λ straddling
    // the axis at distance ≲ 100·ε‖H‖ cannot be separated).
    let boundary = || LtiError::BoundaryEigenvalue {
        what: "Hamiltonian matrix".into(),
        eigenvalue: closest,
        distance: closest.re.abs(),
    };
    if closest.re.abs() <= 100.0 * f64::EPSILON * hnorm {
        return Err(boundary());
    }
    let k = sch.reorder(|l| l.re < 0.0)?;
    if k != n {
        return Err(boundary());
    }
    let z = sch.z();
    let u1 = z.view((0, 0), (n, n)).into_owned();
    let u2 = z.view((n, 0), (n, n)).into_owned();
    let (x, lu) = solution_and_factor_from_subspace(&u1, &u2)?;
    let t11 = sch.t().view((0, 0), (n, n)).into_owned();
    Ok(Computed {
        x: x * s,
        hint: Some(ClosedLoopSchur { u1, lu, t11 }),
    })
}

/// Structure-preserving doubling for the CARE (unrefined solution).
///
/// Cayley transform with shift `γ > 0` (Chu, Fan & Lin 2005): with `A_γ = Ã − γI`,
/// `W = A_γᵀ + Q̃A_γ⁻¹G`, the initial symplectic pencil in first standard form is
/// `E₀ = I + 2γ(A_γ⁻¹ − A_γ⁻¹GW⁻¹Q̃A_γ⁻¹)`, `G₀ = 2γA_γ⁻¹GW⁻¹`, `H₀ = 2γW⁻¹Q̃A_γ⁻¹`; then
/// [`sda_iterate`] converges quadratically to `H_∞ = X` at rate
/// `max |(λ+γ)/(λ−γ)|` over the stable Hamiltonian eigenvalues.
pub(crate) fn care_doubling(red: &Reduced, scaling: bool) -> Result<Mat> {
    let n = red.a.nrows();
    let s = scale_factor(red, scaling);
    let g = &red.g * s;
    let q = &red.q * (1.0 / s);
    // A typical eigenvalue magnitude of the Hamiltonian.
    let mut gamma = (red.a.norm().max((g.norm() * q.norm()).sqrt()) / (n as f64).sqrt()).max(1e-3);
    let eye = Mat::identity(n, n);
    for _ in 0..4 {
        let ag = &red.a - &eye * gamma;
        let lu = Lu::new(&ag);
        if lu.rcond() < 1e3 * f64::EPSILON {
            gamma *= 2.0;
            continue;
        }
        let agi = lu.inverse();
        let agi_g = &agi * &g;
        let w = ag.transpose() + &q * &agi_g;
        let lw = Lu::new(&w);
        if lw.rcond() < 1e3 * f64::EPSILON {
            gamma *= 2.0;
            continue;
        }
        let wi = lw.inverse();
        let wi_q_agi = &wi * &q * &agi;
        let e0 = &eye + (&agi - &agi_g * &wi_q_agi) * (2.0 * gamma);
        let g0 = symmetrize(&(&agi_g * &wi * (2.0 * gamma)));
        let h0 = symmetrize(&(wi_q_agi * (2.0 * gamma)));
        return Ok(sda_iterate(e0, g0, h0)? * s);
    }
    Err(LtiError::Singular {
        what: "Cayley-transformed Hamiltonian in the doubling method".into(),
        rcond: 0.0,
    })
}

/// The structure-preserving doubling iteration on a symplectic pencil in first standard form
/// `[[E, 0], [−H, I]] − λ[[I, G], [0, Eᵀ]]` (Chu, Fan, Lin, Wang 2004):
/// `E ← E(I+GH)⁻¹E`, `G ← G + E(I+GH)⁻¹GEᵀ`, `H ← H + Eᵀ(I+HG)⁻¹HE`; `H` converges
/// quadratically to the stabilising solution when the pencil has no eigenvalue on the unit
/// circle.
pub(crate) fn sda_iterate(mut e: Mat, mut g: Mat, mut h: Mat) -> Result<Mat> {
    let n = e.nrows();
    let eye = Mat::identity(n, n);
    let max_iter = 60;
    let mut last_dh = f64::INFINITY;
    for _ in 0..max_iter {
        let w = &eye + &g * &h;
        let lu = Lu::new(&w);
        if lu.rcond() < f64::EPSILON {
            return Err(LtiError::Singular {
                what: "I + G_k H_k in the doubling iteration".into(),
                rcond: lu.rcond(),
            });
        }
        let wi = lu.inverse();
        let wi_e = &wi * &e;
        let wi_g = &wi * &g;
        let he = &h * &e;
        let wit_he = wi.transpose() * he;
        let e_new = &e * &wi_e;
        let g_new = symmetrize(&(&g + &e * wi_g * e.transpose()));
        let h_new = symmetrize(&(&h + e.transpose() * wit_he));
        let dh = (&h_new - &h).norm();
        let hn = h_new.norm();
        e = e_new;
        g = g_new;
        h = h_new;
        if !hn.is_finite() {
            break;
        }
        if dh <= 4.0 * f64::EPSILON * (n as f64).sqrt() * hn || e.norm() <= f64::EPSILON {
            return Ok(h);
        }
        // Rounding-level stagnation after quadratic convergence has set in.
        if dh <= 1e-10 * hn && dh >= 0.5 * last_dh {
            return Ok(h);
        }
        last_dh = dh;
    }
    Err(LtiError::NoConvergence {
        algorithm: "structure-preserving doubling".into(),
        iterations: max_iter,
    })
}
