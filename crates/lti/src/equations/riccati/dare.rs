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
/// positive definite, optional cross term `N` `n×m`. The stabilising solution `X = Xᵀ` makes
/// `A − BK` Schur-stable (spectral radius < 1) with `K = (BᵀXB + R)⁻¹(BᵀXA + Nᵀ)` (control
/// law `u = −Kx`); for LQR data it exists iff `(A, B)` is stabilisable and `(Q̃, Ã)` has no
/// unobservable mode on the unit circle (`Ã = A − BR⁻¹Nᵀ`, `Q̃ = Q − NR⁻¹Nᵀ`).
///
/// Methods ([`RiccatiOptions::method`]):
/// - **ExtendedPencil** (default first choice): ordered QZ on the extended symplectic pencil,
///   no inversion of `A` or `R` (Van Dooren 1981; SLICOT `SB02OD`);
/// - **Doubling**: structure-preserving doubling (Chu, Fan, Lin & Wang 2004), `A` may be
///   singular;
/// - **Schur**: ordered real Schur form of the symplectic matrix (Laub 1979), requires `Ã`
///   invertible.
///
/// The result is refined by Hewer–Newton steps in residual-correction form
/// (`(A−BK)ᵀΔ(A−BK) − Δ = −Res(X)`, kept only if the residual drops) and checked: relative
/// residual ≤ [`RESIDUAL_LIMIT`](super::RESIDUAL_LIMIT), all closed-loop poles inside the unit
/// circle.
///
/// # Errors
/// As [`care`](super::care), with the unit circle in place of the imaginary axis;
/// [`LtiError::Singular`] from the Schur method when `Ã` is singular.
#[doc(alias = "idare")]
pub fn dare(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    options: &RiccatiOptions,
) -> Result<RiccatiSolution> {
    let dims = validate(a, b, q, r, n, true)?;
    if dims.n == 0 {
        return Ok(empty_solution(dims.m, RiccatiMethod::Doubling));
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
    };
    let candidates: Vec<RiccatiMethod> = match options.method {
        RiccatiMethod::Auto => vec![RiccatiMethod::Doubling, RiccatiMethod::Schur],
        m => vec![m],
    };
    solve_with_fallback(&fin, &candidates, options, |m| match m {
        RiccatiMethod::Doubling | RiccatiMethod::Auto => dare_doubling(&red, options.scaling),
        RiccatiMethod::Schur => dare_schur(&red, options.scaling),
        RiccatiMethod::ExtendedPencil => super::pencil::dare_pencil(a, b, q, r, n, options.scaling),
    })
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
    let closest = ev
        .iter()
        .copied()
        .min_by(|x, y| (x.norm() - 1.0).abs().total_cmp(&(y.norm() - 1.0).abs()))
        .unwrap_or_default();
    let boundary = || LtiError::BoundaryEigenvalue {
        what: "symplectic matrix".into(),
        eigenvalue: closest,
        distance: (closest.norm() - 1.0).abs(),
    };
    if (closest.norm() - 1.0).abs() <= 100.0 * f64::EPSILON * sm.norm() {
        return Err(boundary());
    }
    let k = sch.reorder(|l| l.norm() < 1.0)?;
    if k != n {
        return Err(boundary());
    }
    let z = sch.z();
    let u1 = z.view((0, 0), (n, n)).into_owned();
    let u2 = z.view((n, 0), (n, n)).into_owned();
    Ok(solution_from_subspace(&u1, &u2)? * s)
}
