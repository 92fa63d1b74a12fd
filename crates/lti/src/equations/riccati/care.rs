//! The continuous algebraic Riccati equation.

use super::smith::CayleySmith;
use super::{
    ClosedLoopSchur, Computed, Domain, Finisher, NewtonHint, Reduced, RiccatiMethod,
    RiccatiOptions, RiccatiSolution, empty_solution, reduce, scale_factor,
    solution_and_factor_from_subspace, solve_with_fallback_prior, validate,
};
use crate::error::{LtiError, Result};
use crate::linalg::dense::Lu;
use crate::linalg::schur::real_schur;
use crate::linalg::{Mat, symmetrize_in_place};

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
/// - **Schur**: Laub's method — real Schur form of `H`, stable
///   eigenvalues moved to the top-left by direct swapping (Bai–Demmel), `X = U₂₁U₁₁⁻¹` from the
///   stable invariant subspace (A. J. Laub, "A Schur method for solving algebraic Riccati
///   equations", IEEE TAC 24, 1979; SLICOT `SB02MD`).
/// - **Doubling**: structure-preserving doubling after a Cayley transform (Chu, Fan & Lin,
///   "A structure-preserving doubling algorithm for continuous-time algebraic Riccati
///   equations", Linear Algebra Appl. 396, 2005).
///
/// With [`RiccatiMethod::Auto`], the doubling method is tried first under strict acceptance:
/// relative residual ≤ `100·n·ε` after refinement, Hurwitz closed loop, and `X ⪰ 0` when
/// `Q̃ ⪰ 0` (LQR data); an accepted result reports [`RiccatiMethod::Doubling`].
/// - `n ≤ 8` states and `m ≤ n` inputs: a fixed-size (stack-allocated) doubling + Newton path.
/// - `n > 8`: the doubling method above with at most 11 doubling steps (enough for a
///   convergence rate up to `1 − 0.018`; a slower one — a Hamiltonian eigenvalue near the
///   imaginary axis relative to the shift — stops the attempt early, so that a declined
///   attempt costs a fraction of the Schur solve that follows), then the same refinement and
///   checks as every method.
///
/// When the attempt declines, the general path runs: Schur, then doubling (the first result
/// with residual ≤ [`GOOD_RESIDUAL`](super::GOOD_RESIDUAL), else the most accurate; a finished
/// doubling attempt is reused, not recomputed). It also produces every diagnostic error.
/// Explicit [`RiccatiMethod::Schur`] always runs Laub's method.
///
/// The result is then refined by Kleinman–Newton steps in residual-correction form
/// (`(A−BK)ᵀΔ + Δ(A−BK) = −Res(X)`, kept only if the residual drops; after doubling the
/// first step is solved by the Smith iteration under the doubling's Cayley shift, after
/// Laub's method on the Hamiltonian's Schur form, otherwise by Bartels–Stewart on a new
/// Schur form of `A − BK`) and checked: relative
/// residual ≤ [`RESIDUAL_LIMIT`](super::RESIDUAL_LIMIT), and the boundary verdict every method
/// ends in (the fixed-size path included): all closed-loop poles in the open left half-plane
/// and none within the reach of the solution's backward error of the imaginary axis (see
/// [`equations::riccati`](super), step 6).
///
/// `care` solves the equation for any symmetric `Q` (as MATLAB's `icare`); an indefinite `Q`
/// or `[[Q, N], [Nᵀ, R]]` is no LQ problem and is refused by
/// [`lqr`](crate::design::lqr), not here.
///
/// # Errors
/// - [`LtiError::DimensionMismatch`], [`LtiError::NotSquare`], [`LtiError::NonFinite`],
///   [`LtiError::NotSymmetric`] for malformed data;
/// - [`LtiError::NotPositiveDefinite`] if `R` is not positive definite;
/// - [`LtiError::NotStabilizable`] (an uncontrollable mode that is not stable, with its PBH
///   margin), [`LtiError::NotDetectable`] (an unobservable mode on the imaginary axis),
///   [`LtiError::BoundaryEigenvalue`] (Hamiltonian eigenvalues on or numerically near the
///   imaginary axis, listed) when no stabilising solution exists;
/// - [`LtiError::IllConditioned`] (with the condition estimate) when, above
///   [`FAIL_FAST_MIN_STATES`](super::FAIL_FAST_MIN_STATES) states, the stable-subspace basis
///   is singular to working precision (the solve stops early);
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
        && small_certified(a, b, q, r, n, &sol)
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
        certify: true,
    };
    // Auto for n > SMALL_MAX: a bounded doubling attempt with strict acceptance first.
    let mut prior = None;
    if options.method == RiccatiMethod::Auto && dims.n > super::small::SMALL_MAX {
        let attempt = care_doubling(&red, options.scaling, true)
            .and_then(|c| fin.finish_with(c, RiccatiMethod::Doubling, options));
        match attempt {
            Ok(sol) if strictly_acceptable(&red, &sol) => return Ok(sol),
            // Stopped at the attempt's iteration limit: the fallback runs the full iteration.
            Err(LtiError::NoConvergence { .. }) => {}
            // Anything else is exactly what the fallback's doubling candidate would compute.
            other => prior = Some((RiccatiMethod::Doubling, other)),
        }
    }
    let candidates: Vec<RiccatiMethod> = match options.method {
        RiccatiMethod::Auto => vec![RiccatiMethod::Schur, RiccatiMethod::Doubling],
        m => vec![m],
    };
    solve_with_fallback_prior(&fin, &candidates, options, prior, |m| match m {
        RiccatiMethod::Schur | RiccatiMethod::Auto => care_schur(&red, options.scaling),
        RiccatiMethod::Doubling => care_doubling(&red, options.scaling, false),
    })
}

/// The boundary verdict of every method ([`super::boundary`]) on a result of the fixed-size
/// path; `false` sends the problem to the general path, whose finisher reaches the verdict
/// again and whose fallback names the cause. The reduced data and the residual matrix are
/// formed only when a pole is near enough the axis to need them.
fn small_certified(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    sol: &RiccatiSolution,
) -> bool {
    let Ok(near) = super::boundary::screen(Domain::Continuous, &sol.closed_loop_poles) else {
        return false;
    };
    if near.is_empty() {
        return true;
    }
    let Ok(red) = reduce(a, b, q, r, n) else {
        return false;
    };
    let acl = a - b * &sol.gain;
    super::boundary::judge(
        Domain::Continuous,
        &red,
        (&sol.x, &acl),
        &near,
        sol.residual,
    )
    .is_ok()
}

/// Strict acceptance of the first doubling attempt of [`RiccatiMethod::Auto`] (the rules of
/// the fixed-size path): relative residual at most `100·n·ε` after refinement (the closed
/// loop is Hurwitz, checked by the finisher) and, for LQR data (`Q̃ ⪰ 0`), `X ⪰ 0` — the
/// stabilising solution then is `X = ∫ e^{Fᵀt}(Q̃ + KᵀRK)e^{Ft} dt ⪰ 0`. Semidefiniteness
/// is tested to `100·n·ε` relative (Cholesky of `M + 100·n·ε‖M‖_F I`).
fn strictly_acceptable(red: &Reduced, sol: &RiccatiSolution) -> bool {
    let n = red.a.nrows();
    let tol = STRICT_FACTOR * n as f64 * f64::EPSILON;
    if sol.residual.is_nan() || sol.residual > tol {
        return false;
    }
    if sol
        .closed_loop_poles
        .iter()
        .any(|p| p.re.is_nan() || p.re >= 0.0)
    {
        return false;
    }
    let psd = |m: &Mat| {
        let shifted = m + Mat::identity(n, n) * (tol * m.norm());
        shifted.cholesky().is_some()
    };
    !psd(&red.q) || psd(&sol.x)
}

/// Acceptance bound of the `Auto` doubling attempt on the relative residual, in units of
/// `n·ε` (as in the fixed-size path).
const STRICT_FACTOR: f64 = 100.0;

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
    let mut sch = real_schur(&h)?;
    let ev = sch.eigenvalues();
    // The stable invariant subspace needs exactly n eigenvalues strictly left of the axis;
    // whether those found are far enough from it is decided once, for every method, on the
    // refined solution (`boundary::certify`).
    let k = sch.reorder(|l| l.re < 0.0)?;
    if k != n {
        return Err(super::boundary::count_error(Domain::Continuous, &ev, n, k));
    }
    let z = sch.z();
    let u1 = z.view((0, 0), (n, n)).into_owned();
    let u2 = z.view((n, 0), (n, n)).into_owned();
    let (x, lu) = solution_and_factor_from_subspace(&u1, &u2)?;
    let t11 = sch.t().view((0, 0), (n, n)).into_owned();
    Ok(Computed {
        x: x * s,
        hint: Some(NewtonHint::Schur(ClosedLoopSchur { u1, lu, t11 })),
    })
}

/// Iteration limit of the doubling method when it is asked for explicitly.
pub(crate) const SDA_MAX_ITER: usize = 60;

/// Iteration limit of the first (doubling) attempt of [`RiccatiMethod::Auto`] for
/// `n > SMALL_MAX`: the error after `k` steps is about `r^(2^k)` with `r` the convergence rate,
/// so 11 steps reach rounding level for every `r ≤ 1 − 0.018` (`2¹¹ · 0.018 ≈ 37 ≈ −ln ε`).
/// A problem with a Hamiltonian eigenvalue closer to the axis (relative to the shift)
/// converges more slowly; the attempt then stops — as soon as the rate of decrease of `‖E_k‖`
/// shows it (see [`sda_iterate_limited`]), at the latest after 11 steps — and the
/// ordered-Schur method runs. The limit is where the two methods cost about the same: at
/// `n = 100` one step costs about 1/15 of the Schur method (`care-n100` converges in 7), and
/// CAREX 4.3 (`n = 60`, 11 steps) was measured no faster by doubling than by Schur.
pub(crate) const SDA_AUTO_MAX_ITER: usize = 11;

/// Structure-preserving doubling for the CARE (unrefined solution). With `attempt`, the
/// bounded iteration of `Auto`'s first attempt ([`SDA_AUTO_MAX_ITER`] steps and the early
/// bail-out of [`sda_iterate_limited`]); otherwise up to [`SDA_MAX_ITER`] steps.
///
/// Cayley transform with shift `γ > 0` (Chu, Fan & Lin 2005): with `A_γ = Ã − γI`,
/// `W = A_γᵀ + Q̃A_γ⁻¹G`, the initial symplectic pencil in first standard form is
/// `E₀ = I + 2γ(A_γ⁻¹ − A_γ⁻¹GW⁻¹Q̃A_γ⁻¹)`, `G₀ = 2γA_γ⁻¹GW⁻¹`, `H₀ = 2γW⁻¹Q̃A_γ⁻¹`; then
/// [`sda_iterate`] converges quadratically to `H_∞ = X` at rate
/// `max |(λ+γ)/(λ−γ)|` over the stable Hamiltonian eigenvalues.
///
/// No inverse is formed: with `Z = A_γ⁻¹G` and `P = Q̃A_γ⁻¹ = (A_γ⁻ᵀQ̃)ᵀ` (LU solves),
/// `H₀ = 2γW⁻¹P`, `G₀ = 2γZW⁻¹ = 2γ(W⁻ᵀZᵀ)ᵀ` and
/// `E₀ = A_γ⁻¹(Ã + γI) − ZH₀` (since `I + 2γA_γ⁻¹ = A_γ⁻¹(A_γ + 2γI)`).
///
/// The shift is a typical eigenvalue magnitude of the Hamiltonian,
/// `γ = max(‖Ã‖_F, sqrt(‖G‖_F‖Q̃‖_F))/√n` (of the scaled data), doubled while `A_γ` or `W` is
/// numerically singular. On the `care-n100` data the iteration count is flat (8 steps
/// including the last, confirming one) for `γ` between 0.25 and 1.5 times this value and
/// grows for larger shifts.
pub(crate) fn care_doubling(red: &Reduced, scaling: bool, attempt: bool) -> Result<Computed> {
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
        // Z = A_γ⁻¹ G.
        let mut z = g.clone();
        lu.solve_in_place(&mut z);
        // W = A_γᵀ + Q̃ Z.
        let mut w = ag.transpose();
        w.gemm(1.0, &q, &z, 1.0);
        let lw = Lu::new(&w);
        if lw.rcond() < 1e3 * f64::EPSILON {
            gamma *= 2.0;
            continue;
        }
        // P = Q̃ A_γ⁻¹ = (A_γ⁻ᵀ Q̃)ᵀ (Q̃ symmetric).
        let mut pt = q.clone();
        lu.solve_transpose_in_place(&mut pt);
        // H₀ = 2γ W⁻¹ P.
        let mut h0 = pt.transpose();
        lw.solve_in_place(&mut h0);
        h0 *= 2.0 * gamma;
        symmetrize_in_place(&mut h0);
        // G₀ = 2γ (W⁻ᵀ Zᵀ)ᵀ.
        let mut g0t = z.transpose();
        lw.solve_transpose_in_place(&mut g0t);
        let mut g0 = g0t.transpose() * (2.0 * gamma);
        symmetrize_in_place(&mut g0);
        // E₀ = A_γ⁻¹(Ã + γI) − Z H₀.
        let mut e0 = &red.a + &eye * gamma;
        lu.solve_in_place(&mut e0);
        e0.gemm(-1.0, &z, &h0, 1.0);
        let x = sda_iterate_limited(e0, g0, h0, attempt)? * s;
        return Ok(Computed {
            x,
            hint: Some(NewtonHint::Smith(CayleySmith { shift: gamma })),
        });
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
///
/// One step, without inverses and with every product in a preallocated buffer
/// (`≈ 16⅔ n³` flops): `Wᵀ = I + HG` is LU-factored once, `[Y₁ Y₂] = W⁻¹[E G]` by the
/// (blocked) transposed solve with `2n` right-hand sides, then, using
/// `(I+HG)⁻¹H = H(I+GH)⁻¹`: `E ← EY₁`, `G ← G + (EY₂)Eᵀ`, `H ← H + Eᵀ(HY₁)`.
///
/// Stopping: the update `ΔH_k = E_kᵀ(HY₁)` is quadratic in `E_k`, so the next update is about
/// `‖ΔH_k‖·(‖E_{k+1}‖/‖E_k‖)²`; the iteration stops when that prediction (or the update
/// itself) is at rounding level relative to `‖H‖`, or after a stagnating step once the
/// update is below `1e-10·‖H‖`. More than [`SDA_MAX_ITER`] steps give
/// [`LtiError::NoConvergence`].
pub(crate) fn sda_iterate(e: Mat, g: Mat, h: Mat) -> Result<Mat> {
    sda_iterate_limited(e, g, h, false)
}

/// [`sda_iterate`]; with `attempt`, at most [`SDA_AUTO_MAX_ITER`] steps and an early
/// bail-out ([`LtiError::NoConvergence`]) when the iteration will not converge within them.
///
/// Bail-out rule (from step 4 on): with `ℓ_k = ln(‖E_{k−1}‖/‖E_k‖)`, an iteration in its
/// quadratic phase doubles `ℓ` every step and reaches rounding level (`ℓ ≈ −ln ε ≈ 36`) after
/// about `log₂(36/ℓ_k)` more steps; the attempt stops when `‖E‖` does not decrease
/// (`ℓ_k ≤ 0`) or when `k + log₂(36/ℓ_k)` exceeds the limit. The estimate is optimistic while
/// `ℓ` is not yet doubling (a spread of slow modes, e.g. CAREX 4.2, lowers `‖E‖` by a
/// constant factor per step), so it errs towards continuing. On `care-n100` it predicts 9.5
/// steps at step 4 (7 are taken); CAREX 4.2 (`n = 100`, not converged after 12) stops at
/// step 4.
pub(crate) fn sda_iterate_limited(
    mut e: Mat,
    mut g: Mat,
    mut h: Mat,
    attempt: bool,
) -> Result<Mat> {
    let max_iter = if attempt {
        SDA_AUTO_MAX_ITER
    } else {
        SDA_MAX_ITER
    };
    let n = e.nrows();
    let mut wt = Mat::zeros(n, n);
    let mut y = Mat::zeros(n, 2 * n);
    let mut t1 = Mat::zeros(n, n);
    let mut t2 = Mat::zeros(n, n);
    let mut et = Mat::zeros(n, n);
    let mut last_dh = f64::INFINITY;
    let mut e_norm = e.norm();
    let tol = 4.0 * f64::EPSILON * (n as f64).sqrt();
    for k in 1..=max_iter {
        // Wᵀ = I + H G.
        wt.gemm(1.0, &h, &g, 0.0);
        for i in 0..n {
            wt[(i, i)] += 1.0;
        }
        let lu = Lu::new(&wt);
        let rc = lu.rcond();
        if rc.is_nan() || rc < f64::EPSILON {
            return Err(LtiError::Singular {
                what: "I + G_k H_k in the doubling iteration".into(),
                rcond: rc,
            });
        }
        // [Y₁ Y₂] = W⁻¹ [E G].
        y.columns_mut(0, n).copy_from(&e);
        y.columns_mut(n, n).copy_from(&g);
        lu.solve_transpose_in_place(&mut y);
        e.transpose_to(&mut et);
        // ΔH = Eᵀ (H Y₁).
        t1.gemm(1.0, &h, &y.columns(0, n), 0.0);
        t2.gemm(1.0, &et, &t1, 0.0);
        let dh = t2.norm();
        h += &t2;
        symmetrize_in_place(&mut h);
        // G ← G + (E Y₂) Eᵀ.
        t1.gemm(1.0, &e, &y.columns(n, n), 0.0);
        g.gemm(1.0, &t1, &et, 1.0);
        symmetrize_in_place(&mut g);
        // E ← E Y₁.
        t1.gemm(1.0, &e, &y.columns(0, n), 0.0);
        std::mem::swap(&mut e, &mut t1);
        let hn = h.norm();
        let e_new = e.norm();
        if !hn.is_finite() || !e_new.is_finite() {
            break;
        }
        let predicted = if e_norm > 0.0 {
            dh * (e_new / e_norm).powi(2)
        } else {
            0.0
        };
        if dh <= tol * hn || predicted <= f64::EPSILON * hn || e_new <= f64::EPSILON {
            return Ok(h);
        }
        // Rounding-level stagnation after quadratic convergence has set in.
        if dh <= 1e-10 * hn && dh >= 0.5 * last_dh {
            return Ok(h);
        }
        last_dh = dh;
        if attempt && k >= 4 {
            let ell = (e_norm / e_new).ln();
            if ell.is_nan() || ell <= 0.0 || k as f64 + (36.0 / ell).log2() > max_iter as f64 {
                return Err(LtiError::NoConvergence {
                    algorithm: "structure-preserving doubling (bounded attempt)".into(),
                    iterations: k,
                });
            }
        }
        e_norm = e_new;
    }
    Err(LtiError::NoConvergence {
        algorithm: "structure-preserving doubling".into(),
        iterations: max_iter,
    })
}
