//! The discrete algebraic Riccati equation.

use super::care::sda_iterate;
use super::{
    Domain, Finisher, Reduced, RiccatiMethod, RiccatiOptions, RiccatiSolution, empty_solution,
    reduce, scale_factor, solution_from_subspace, solve_with_fallback, validate,
};
use crate::error::{LtiError, Result};
use crate::linalg::Mat;
use crate::linalg::dense::Lu;
use crate::linalg::schur::real_schur;

/// Solves the DARE `AᵀXA − X − (AᵀXB + N)(BᵀXB + R)⁻¹(BᵀXA + Nᵀ) + Q = 0` for its
/// stabilising solution (MATLAB `idare`/`dare`).
///
/// Inputs: `A` `n×n` (may be singular), `B` `n×m`, `Q` `n×n` symmetric, `R` `m×m` symmetric
/// positive semidefinite (it may be singular, e.g. `R = 0`, as long as `BᵀXB + R` is
/// invertible at the solution), optional cross term `N` `n×m`. The stabilising solution `X = Xᵀ` makes
/// `A − BK` Schur-stable (spectral radius < 1) with `K = (BᵀXB + R)⁻¹(BᵀXA + Nᵀ)` (control
/// law `u = −Kx`); for LQR data it exists iff `(A, B)` is stabilisable and `(Q̃, Ã)` has no
/// unobservable mode on the unit circle (`Ã = A − BR⁻¹Nᵀ`, `Q̃ = Q − NR⁻¹Nᵀ`).
///
/// Methods ([`RiccatiOptions::method`]):
/// - **Doubling** (default first choice): structure-preserving doubling (Chu, Fan, Lin & Wang
///   2004), `A` may be singular;
/// - **Schur**: ordered real Schur form of the symplectic matrix (Laub 1979), requires `Ã`
///   invertible.
///
/// **Singular `R`.** The substitution `X = Y + ρI` maps the DARE to the DARE in `Y` with data
/// `(A, B, Q + ρ(AᵀA − I), R + ρBᵀB, N + ρAᵀB)`: the same symplectic pencil up to a
/// congruence, the same gain `K`, hence the same closed loop, and `Y` is stabilising iff `X`
/// is. With `ρ = max(‖R‖, ‖Q‖, 1)/‖BᵀB‖` (Frobenius norms) the shifted input weight is positive
/// definite whenever some `X` makes `BᵀXB + R` invertible (no direction `v` has
/// `Bv = 0 = Rv`), so the methods below apply to it; the result is refined and checked against
/// the original equation.
///
/// The result is refined by Hewer–Newton steps in residual-correction form
/// (`(A−BK)ᵀΔ(A−BK) − Δ = −Res(X)`, kept only if the residual drops) and checked: relative
/// residual ≤ [`RESIDUAL_LIMIT`](super::RESIDUAL_LIMIT), and the boundary verdict of every
/// method: all closed-loop poles inside the unit circle and none within the reach of the
/// solution's backward error of it (see [`equations::riccati`](super), step 6). Any symmetric
/// `Q` is solved for; [`lqr`](crate::design::lqr) refuses weights that are no LQ cost.
///
/// # Errors
/// As [`care`](super::care), with the unit circle in place of the imaginary axis;
/// [`LtiError::NotPositiveDefinite`] if `R` is indefinite or if `R + ρBᵀB` is singular (then
/// `BᵀXB + R` is singular for every `X`); [`LtiError::Singular`] from the Schur method when
/// `Ã` is singular; [`LtiError::IllConditioned`] as for [`care`](super::care).
#[doc(alias = "idare")]
pub fn dare(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    options: &RiccatiOptions,
) -> Result<RiccatiSolution> {
    let dims = validate(a, b, q, r, n, false)?;
    if dims.n == 0 {
        return Ok(empty_solution(dims.m, RiccatiMethod::Doubling));
    }
    if dims.m > 0 && r.clone().cholesky().is_none() {
        return dare_singular_r(a, b, q, r, n, options);
    }
    let red = reduce(a, b, q, r, n)?;
    let fin = Finisher {
        domain: Domain::Discrete,
        a,
        b,
        q,
        r,
        n,
        red: &red,
        certify: true,
    };
    let candidates: Vec<RiccatiMethod> = match options.method {
        RiccatiMethod::Auto => vec![RiccatiMethod::Doubling, RiccatiMethod::Schur],
        m => vec![m],
    };
    solve_with_fallback(&fin, &candidates, options, |m| match m {
        RiccatiMethod::Doubling | RiccatiMethod::Auto => {
            dare_doubling(&red, options.scaling).map(Into::into)
        }
        RiccatiMethod::Schur => dare_schur(&red, options.scaling).map(Into::into),
    })
}

/// The DARE with a singular positive semidefinite `R`, through the shift `X = Y + ρI`
/// described at [`dare`].
fn dare_singular_r(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    options: &RiccatiOptions,
) -> Result<RiccatiSolution> {
    let m = r.nrows();
    let ev = crate::linalg::symmetric_eigenvalues(r);
    let min = ev.first().copied().unwrap_or(0.0);
    let max = ev.last().copied().unwrap_or(0.0).abs();
    // Indefinite beyond rounding: not an LQ weight.
    if min.is_nan() || min < -(m as f64) * 10.0 * f64::EPSILON * max.max(f64::MIN_POSITIVE) {
        return Err(LtiError::NotPositiveDefinite {
            what: "R (the DARE needs R positive semidefinite)".into(),
            min_eigenvalue: min,
        });
    }
    let btb = b.transpose() * b;
    let rho = r.norm().max(q.norm()).max(1.0) / btb.norm().max(f64::MIN_POSITIVE);
    let r_s = crate::linalg::symmetrize(&(r + &btb * rho));
    if r_s.clone().cholesky().is_none() {
        return Err(LtiError::NotPositiveDefinite {
            what: "R + ρBᵀB (an input direction v has Bv = 0 and Rv = 0, so BᵀXB + R is \
                   singular for every X)"
                .into(),
            min_eigenvalue: crate::linalg::symmetric_eigenvalues(&r_s)
                .first()
                .copied()
                .unwrap_or(f64::NAN),
        });
    }
    let nx = a.nrows();
    let q_s = crate::linalg::symmetrize(&(q + (a.transpose() * a - Mat::identity(nx, nx)) * rho));
    let mut n_s = a.transpose() * b * rho;
    if let Some(nm) = n {
        n_s += nm;
    }
    // Solve the shifted problem without refinement; refinement and checks are done on the
    // original equation.
    let inner = RiccatiOptions {
        max_refinement_steps: 0,
        ..*options
    };
    let red = reduce(a, b, &q_s, &r_s, Some(&n_s))?;
    let shifted = Finisher {
        domain: Domain::Discrete,
        a,
        b,
        q: &q_s,
        r: &r_s,
        n: Some(&n_s),
        red: &red,
        certify: false,
    };
    let candidates: Vec<RiccatiMethod> = match options.method {
        RiccatiMethod::Auto => vec![RiccatiMethod::Doubling, RiccatiMethod::Schur],
        m => vec![m],
    };
    let y = solve_with_fallback(&shifted, &candidates, &inner, |m| match m {
        RiccatiMethod::Doubling | RiccatiMethod::Auto => {
            dare_doubling(&red, options.scaling).map(Into::into)
        }
        RiccatiMethod::Schur => dare_schur(&red, options.scaling).map(Into::into),
    })?;
    let x = &y.x + Mat::identity(nx, nx) * rho;
    let fin = Finisher {
        domain: Domain::Discrete,
        a,
        b,
        q,
        r,
        n,
        red: &red,
        certify: true,
    };
    fin.finish(x, y.method, options)
}

/// Structure-preserving doubling for the DARE: `E₀ = Ã`, `G₀ = sG`, `H₀ = Q̃/s`.
pub(crate) fn dare_doubling(red: &Reduced, scaling: bool) -> Result<Mat> {
    let s = scale_factor(red, scaling);
    Ok(sda_iterate(red.a.clone(), &red.g * s, &red.q * (1.0 / s))? * s)
}

/// Laub's method on the symplectic matrix
/// `S = [[Ã + GÃ⁻ᵀQ̃, −GÃ⁻ᵀ], [−Ã⁻ᵀQ̃, Ã⁻ᵀ]]` (eigenvalues inside the unit circle first).
pub(crate) fn dare_schur(red: &Reduced, scaling: bool) -> Result<Mat> {
    let n = red.a.nrows();
    let s = scale_factor(red, scaling);
    let g = &red.g * s;
    let q = &red.q * (1.0 / s);
    let lu = Lu::new(&red.a);
    let rc = lu.rcond();
    if rc < 1e3 * f64::EPSILON {
        return Err(LtiError::Singular {
            what: "A − BR⁻¹Nᵀ (the symplectic-matrix Schur method needs it invertible)".into(),
            rcond: rc,
        });
    }
    let ait = lu.inverse().transpose();
    let mut sm = Mat::zeros(2 * n, 2 * n);
    let g_ait = &g * &ait;
    sm.view_mut((0, 0), (n, n))
        .copy_from(&(&red.a + &g_ait * &q));
    sm.view_mut((0, n), (n, n)).copy_from(&(-&g_ait));
    sm.view_mut((n, 0), (n, n)).copy_from(&(-(&ait * &q)));
    sm.view_mut((n, n), (n, n)).copy_from(&ait);
    let mut sch = real_schur(&sm)?;
    let ev = sch.eigenvalues();
    // Exactly n eigenvalues strictly inside the unit circle are needed; their distance from
    // it is judged on the refined solution (`boundary::certify`).
    let k = sch.reorder(|l| l.norm() < 1.0)?;
    if k != n {
        return Err(super::boundary::count_error(Domain::Discrete, &ev, n, k));
    }
    let z = sch.z();
    let u1 = z.view((0, 0), (n, n)).into_owned();
    let u2 = z.view((n, 0), (n, n)).into_owned();
    Ok(solution_from_subspace(&u1, &u2)? * s)
}
