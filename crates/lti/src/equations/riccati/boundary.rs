//! The one home of the stability-boundary verdict on a computed Riccati solution.
//!
//! The eigenvalues of the Hamiltonian matrix `H = [[Ã, −G], [−Q̃, −Ãᵀ]]` (continuous) are the
//! closed-loop poles `λ` of a solution `X` together with their mirror images `−λ̄`; those of
//! the symplectic pencil `L − zM`, `L = [[Ã, 0], [−Q̃, I]]`, `M = [[I, G], [0, Ãᵀ]]`
//! (discrete) are `λ` and `1/λ̄`. A stabilising solution exists only if none of them lies on
//! the imaginary axis (unit circle). Every method — Laub's Schur method, the doubling
//! methods, the fixed-size path, each followed by Newton refinement — ends in [`certify`],
//! which decides from the closed-loop poles of the refined solution:
//!
//! 1. a pole with margin `d(λ) ≤ 0` (`d = −Re λ` or `1 − |λ|`), or NaN, fails;
//! 2. a pole near the boundary fails when the solution cannot tell it from the boundary:
//!    the refined `X` has the relative residual `η` (its backward error: `X` solves exactly
//!    an equation whose data are changed by about `η` relative), and a relative change `η`
//!    of the pencil moves its eigenvalue `λ`, to first order, by at most
//!    `ρ(λ) = κ(λ)·η·(‖L‖_F + |λ|‖M‖_F)`, with the eigenvalue condition number
//!    `κ(λ) = ‖x‖‖y‖ / |yᴴMx|` (`x`, `y` right and left eigenvectors, `L = H`, `M = I` for
//!    the Hamiltonian). The pole is rejected when `d(λ) ≤ ρ(λ)`: an eigenvalue within the
//!    reach of the solution's own backward error could lie on the boundary. `L`, `M` are
//!    built from the scaled data (`Q̃/s`, `sG`) of the module's step 3. Whatever `κ`, a
//!    distance below [`BOUNDARY_ROUNDING`]`·ε·‖L‖_F` counts as on the boundary.
//!
//! A rounding-split double eigenvalue on the boundary (CAREX 2.5 at `ε = 0`: the computed
//! poles are `−3·10⁻⁸ ± j`, `d/ρ ≈ 0.1–0.7`) fails; a genuine near-boundary pole whose
//! eigenvalue is well conditioned passes however near it is, down to the rounding floor
//! (CAREX 2.8 at `ε = 10⁻⁶`: `−5·10⁻¹³ ± j`, `d/ρ ≈ 190`; DAREX 2.5 at `τ = 10⁸`:
//! `1 − 2·10⁻⁸`, `d/ρ ≈ 2·10⁸`).
//!
//! Computing `κ(λ)` costs a complex LU factorisation of order `n` (the right eigenvector,
//! from the structure) and one of order `2n` (the left one), so it is done only for the poles within [`BOUNDARY_SCREEN`] of the boundary
//! (relative to the largest pole magnitude in continuous time, absolute on the unit circle),
//! at most [`BOUNDARY_MAX_TESTED`] of them (nearest first; a conjugate pair counts once).

use super::{Domain, Reduced, scale_factor};
use crate::error::{LtiError, Result};
use crate::linalg::{CMat, Complex64, Mat};

/// Poles with margin `d(λ) ≤ BOUNDARY_SCREEN · max(1, max|λᵢ|)` (continuous) or
/// `1 − |λ| ≤ BOUNDARY_SCREEN` (discrete) get the conditioning test of the module
/// documentation; poles farther from the boundary are accepted without it.
pub const BOUNDARY_SCREEN: f64 = 1e-4;

/// A pole nearer the boundary than `BOUNDARY_ROUNDING · ε · ‖L‖_F` (`‖H‖_F` in continuous
/// time, of the scaled data) is on it numerically whatever its conditioning: a backward-stable
/// eigenvalue computation does not resolve smaller distances (this was the Schur method's
/// own test before the verdict had one home).
pub const BOUNDARY_ROUNDING: f64 = 100.0;

/// At most this many near-boundary poles (nearest first, one per conjugate pair) get the
/// conditioning test.
pub const BOUNDARY_MAX_TESTED: usize = 8;

/// The boundary verdict on the closed-loop poles of a refined solution `X` with closed loop
/// `A_cl = A − BK` (`solution = (X, A_cl)`; module documentation). `backward_error` is the relative residual of the refined solution.
///
/// # Errors
/// [`LtiError::BoundaryEigenvalue`] naming the offending poles and their mirror images.
pub(crate) fn certify(
    domain: Domain,
    red: &Reduced,
    solution: (&Mat, &Mat),
    poles: &[Complex64],
    backward_error: f64,
) -> Result<()> {
    let near = screen(domain, poles)?;
    judge(domain, red, solution, &near, backward_error)
}

/// Step 1 of the verdict and the screening: an error for a pole on or beyond the boundary
/// as computed, else the poles that need the conditioning test ([`judge`]), nearest first,
/// one per conjugate pair, at most [`BOUNDARY_MAX_TESTED`].
///
/// # Errors
/// [`LtiError::BoundaryEigenvalue`] with tolerance 0.
pub(crate) fn screen(domain: Domain, poles: &[Complex64]) -> Result<Vec<Complex64>> {
    let beyond: Vec<Complex64> = poles
        .iter()
        .copied()
        .filter(|&p| !inside(domain.stability_margin(p), 0.0))
        .collect();
    if !beyond.is_empty() {
        return Err(error(
            domain,
            format!("{} (closed loop of the computed solution)", kind(domain)),
            &beyond,
            0.0,
        ));
    }
    let scale = match domain {
        Domain::Continuous => poles.iter().map(|p| p.norm()).fold(1.0, f64::max),
        Domain::Discrete => 1.0,
    };
    let mut near: Vec<Complex64> = poles
        .iter()
        .copied()
        .filter(|p| p.im >= 0.0 && domain.stability_margin(*p) <= BOUNDARY_SCREEN * scale)
        .collect();
    near.sort_by(|p, q| {
        domain
            .stability_margin(*p)
            .total_cmp(&domain.stability_margin(*q))
    });
    near.truncate(BOUNDARY_MAX_TESTED);
    Ok(near)
}

/// Step 2 of the verdict for the screened poles `near` (see the module documentation);
/// `backward_error` is the relative residual of the refined solution.
///
/// # Errors
/// [`LtiError::BoundaryEigenvalue`] naming the offending poles and their mirror images,
/// with the reach `ρ(λ)` of the nearest as the tolerance.
pub(crate) fn judge(
    domain: Domain,
    red: &Reduced,
    solution: (&Mat, &Mat),
    near: &[Complex64],
    backward_error: f64,
) -> Result<()> {
    let (x, acl) = solution;
    // A residual above the acceptance limit (or NaN) is the finisher's accuracy failure
    // (`Inaccurate`), not a verdict on the boundary.
    if near.is_empty() || backward_error.is_nan() || backward_error > super::RESIDUAL_LIMIT {
        return Ok(());
    }
    let s = scale_factor(red, true);
    let (l, m) = pencil(domain, red, s);
    let xs = x / s;
    let (ln, mn) = (l.norm(), m.norm());
    let mut offending = Vec::new();
    let mut tolerance = 0.0;
    for &p in near {
        let reach = (condition(&l, &m, acl, &xs, p) * backward_error * (ln + p.norm() * mn))
            .max(BOUNDARY_ROUNDING * f64::EPSILON * ln);
        if !inside(domain.stability_margin(p), reach) {
            if offending.is_empty() {
                tolerance = reach;
            }
            offending.push(p);
            if p.im != 0.0 {
                offending.push(p.conj());
            }
        }
    }
    if offending.is_empty() {
        return Ok(());
    }
    Err(error(
        domain,
        format!(
            "{} (closed-loop poles of the computed solution within the reach \
             ρ(λ) of its backward error)",
            kind(domain)
        ),
        &offending,
        tolerance,
    ))
}

/// `margin > bound`, false when either is NaN.
fn inside(margin: f64, bound: f64) -> bool {
    margin.partial_cmp(&bound) == Some(std::cmp::Ordering::Greater)
}

/// "Hamiltonian matrix" or "symplectic pencil".
pub(crate) fn kind(domain: Domain) -> &'static str {
    match domain {
        Domain::Continuous => "Hamiltonian matrix",
        Domain::Discrete => "symplectic pencil",
    }
}

/// The mirror image of `λ` in the stability boundary: `−λ̄` or `1/λ̄`.
fn mirror(domain: Domain, l: Complex64) -> Complex64 {
    match domain {
        Domain::Continuous => -l.conj(),
        Domain::Discrete => {
            if l.norm() > 0.0 {
                Complex64::new(1.0, 0.0) / l.conj()
            } else {
                Complex64::new(f64::INFINITY, 0.0)
            }
        }
    }
}

/// [`LtiError::BoundaryEigenvalue`] for closed-loop poles `poles` (their mirror images are
/// listed with them).
pub(crate) fn error(domain: Domain, what: String, poles: &[Complex64], tolerance: f64) -> LtiError {
    let nearest = poles
        .iter()
        .copied()
        .min_by(|p, q| {
            domain
                .stability_margin(*p)
                .abs()
                .total_cmp(&domain.stability_margin(*q).abs())
        })
        .unwrap_or_default();
    let mut eigenvalues = Vec::with_capacity(2 * poles.len());
    for &p in poles {
        eigenvalues.push(p);
        eigenvalues.push(mirror(domain, p));
    }
    LtiError::BoundaryEigenvalue {
        what,
        eigenvalue: nearest,
        distance: domain.stability_margin(nearest).abs(),
        eigenvalues,
        tolerance,
    }
}

/// [`LtiError::BoundaryEigenvalue`] when an ordered Schur form does not have `n` eigenvalues
/// strictly inside the stable region (`found` of them): the `2·max(1, |n − found|)`
/// eigenvalues nearest the boundary are named.
pub(crate) fn count_error(domain: Domain, ev: &[Complex64], n: usize, found: usize) -> LtiError {
    let mut sorted = ev.to_vec();
    sorted.sort_by(|p, q| {
        domain
            .stability_margin(*p)
            .abs()
            .total_cmp(&domain.stability_margin(*q).abs())
    });
    sorted.truncate(2 * n.abs_diff(found).max(1));
    let nearest = sorted.first().copied().unwrap_or_default();
    LtiError::BoundaryEigenvalue {
        what: format!(
            "{} ({found} of its {} eigenvalues strictly inside the stable region, {n} needed)",
            kind(domain),
            ev.len()
        ),
        eigenvalue: nearest,
        distance: domain.stability_margin(nearest).abs(),
        eigenvalues: sorted,
        tolerance: 0.0,
    }
}

/// The scaled pencil `(L, M)`: `(H, I)` with `H = [[Ã, −sG], [−Q̃/s, −Ãᵀ]]` (continuous),
/// `([[Ã, 0], [−Q̃/s, I]], [[I, sG], [0, Ãᵀ]])` (discrete).
fn pencil(domain: Domain, red: &Reduced, s: f64) -> (Mat, Mat) {
    let n = red.a.nrows();
    let mut l = Mat::zeros(2 * n, 2 * n);
    let mut m = Mat::identity(2 * n, 2 * n);
    l.view_mut((0, 0), (n, n)).copy_from(&red.a);
    l.view_mut((n, 0), (n, n)).copy_from(&(&red.q * (-1.0 / s)));
    match domain {
        Domain::Continuous => {
            l.view_mut((0, n), (n, n)).copy_from(&(&red.g * -s));
            l.view_mut((n, n), (n, n)).copy_from(&(-red.a.transpose()));
        }
        Domain::Discrete => {
            m.view_mut((0, n), (n, n)).copy_from(&(&red.g * s));
            m.view_mut((n, n), (n, n)).copy_from(&red.a.transpose());
        }
    }
    (l, m)
}

/// Eigenvalue condition number `‖x‖‖y‖/|yᴴMx|` of the pencil `L − zM` at the closed-loop
/// pole `z` of the solution `X_s` (of the scaled equation). The right eigenvector is taken
/// from the structure, `x = [v; X_s v]` with `A_cl v = z v` (the columns of `[I; X_s]` span the
/// pencil's stable deflating subspace, on which it acts as `A_cl`), `v` by inverse iteration
/// on the `n × n` closed loop; the left eigenvector `y` by inverse iteration on
/// `(L − zM)ᴴ`. Should `y` still contain a component along the left eigenvector of the
/// mirror eigenvalue, that component is `M`-orthogonal to `x`, so it can only enlarge the
/// estimate (the verdict errs towards "on the boundary"). `+∞` when `yᴴMx` vanishes.
fn condition(l: &Mat, m: &Mat, acl: &Mat, xs: &Mat, z: Complex64) -> f64 {
    let n = acl.nrows();
    let k = l.nrows();
    let to_c = |a: &Mat| -> CMat { a.map(|v| Complex64::new(v, 0.0)) };
    let start = |i: usize| Complex64::new(1.0 + (i % 7) as f64 * 0.25, (i % 5) as f64 * 0.125);
    let Some(v) = inverse_iteration(&to_c(acl), &CMat::identity(n, n), z, start) else {
        return f64::INFINITY;
    };
    let xv = to_c(xs) * &v;
    let mut x = CMat::zeros(k, 1);
    x.view_mut((0, 0), (n, 1)).copy_from(&v);
    x.view_mut((n, 0), (n, 1)).copy_from(&xv);
    let (lc, mc) = (to_c(l), to_c(m));
    let Some(y) = inverse_iteration(&lc.adjoint(), &mc.adjoint(), z.conj(), |i| start(k - 1 - i))
    else {
        return f64::INFINITY;
    };
    let ymx = (y.adjoint() * &mc * &x)[(0, 0)].norm();
    let c = x.norm() * y.norm() / ymx;
    if c.is_finite() { c } else { f64::INFINITY }
}

/// Four steps of inverse iteration `u ← (P − zQ)⁻¹ Q u` (normalised) from `start`; `None`
/// when a solve breaks down. An exactly singular `P − zQ` (`z` an exact eigenvalue) is
/// shifted by a few ulps of its scale.
fn inverse_iteration(
    p: &CMat,
    q: &CMat,
    z: Complex64,
    start: impl Fn(usize) -> Complex64,
) -> Option<CMat> {
    let k = p.nrows();
    let scale = p.norm() + z.norm() * q.norm();
    let mut shift = z;
    for attempt in 0..3 {
        let lu = (p - q * shift).lu();
        let mut u = CMat::from_fn(k, 1, |i, _| start(i));
        let mut ok = true;
        for _ in 0..4 {
            match lu.solve(&(q * &u)) {
                Some(w) if w.norm().is_finite() && w.norm() > 0.0 => {
                    let nw = w.norm();
                    u = w / Complex64::new(nw, 0.0);
                }
                _ => {
                    ok = false;
                    break;
                }
            }
        }
        if ok {
            return Some(u);
        }
        shift = z + Complex64::new(scale * f64::EPSILON * 4f64.powi(attempt + 1), 0.0);
    }
    None
}
