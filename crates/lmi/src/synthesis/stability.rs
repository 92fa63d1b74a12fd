//! α-stability (decay rate) of an autonomous system by a Lyapunov LMI.

use crate::error::{LmiError, Result};
use crate::problem::Problem;
use crate::solution::{Solution, SolveOptions};
use pendulab_lti::Mat;

/// Result of [`alpha_stability`].
#[derive(Debug, Clone)]
pub struct AlphaStability {
    /// Whether a certificate `P` was found (status solved and all checks passed).
    pub feasible: bool,
    /// The Lyapunov matrix `P` (when feasible).
    pub p: Option<Mat>,
    /// The solver's answer (status, certificate of infeasibility, rechecks).
    pub solution: Solution,
}

/// α-stability test: find `P` with
///
/// ```text
/// P ⪰ ε I,    AᵀP + P A + 2α P ⪯ −ε I.
/// ```
///
/// Feasible iff every eigenvalue of `A` has `Re λ < −α` (then `V = xᵀPx` decays at least
/// like `e^{−2αt}`, and `‖x(t)‖ ≤ c e^{−αt}‖x(0)‖`). `margin` is `ε` (e.g. 1e-6); the
/// problem is homogeneous in `P`, so `ε` only fixes the scale. An infeasible test comes back
/// with [`Status::Infeasible`](crate::Status::Infeasible) and its certificate, not as an error.
///
/// # Errors
/// [`LmiError::NotSquare`] / [`LmiError::NonFinite`] for `A`, [`LmiError::InvalidArgument`]
/// for a non-finite `α` or a margin that is not positive; solver setup errors.
pub fn alpha_stability(
    a: &Mat,
    alpha: f64,
    margin: f64,
    options: &SolveOptions,
) -> Result<AlphaStability> {
    let n = a.nrows();
    if a.ncols() != n {
        return Err(LmiError::NotSquare {
            what: "A".into(),
            rows: n,
            cols: a.ncols(),
        });
    }
    crate::linalg::check_finite("A", a)?;
    if !alpha.is_finite() {
        return Err(LmiError::InvalidArgument {
            what: "alpha".into(),
            reason: format!("must be finite, got {alpha}"),
        });
    }
    let mut p = Problem::new();
    let pv = p.symmetric("P", n);
    p.positive_definite("P ≻ 0", &pv, margin)?;
    let lyap = (&a.transpose() * &pv).he() + pv.scale(2.0 * alpha);
    p.negative_definite("AᵀP + PA + 2αP ≺ 0", &lyap, margin)?;
    let solution = p.solve(options)?;
    let feasible = solution.all_checks_pass();
    let pm = if feasible {
        Some(solution.value(&pv)?)
    } else {
        None
    };
    Ok(AlphaStability {
        feasible,
        p: pm,
        solution,
    })
}

/// Result of [`max_decay_rate`].
#[derive(Debug, Clone)]
pub struct DecayRate {
    /// The largest `α` found feasible (to the bisection tolerance).
    pub alpha: f64,
    /// The Lyapunov matrix certifying `alpha`.
    pub p: Mat,
    /// Number of LMI solves.
    pub solves: usize,
}

/// The largest decay rate certified by a quadratic Lyapunov function: the supremum of `α`
/// for which [`alpha_stability`] is feasible (a generalised eigenvalue problem, solved by
/// bisection on `α` to the absolute tolerance `tol`). In exact arithmetic it equals
/// `−max Re λ(A)`, the spectral abscissa with its sign changed (for a strict margin the
/// bisection lands slightly below).
///
/// # Errors
/// As [`alpha_stability`]; [`LmiError::InvalidArgument`] for a non-positive `tol`, or when
/// even the lower bracket `α = −(‖A‖_F + 1)` is infeasible (which cannot happen for finite
/// `A`).
pub fn max_decay_rate(a: &Mat, margin: f64, tol: f64, options: &SolveOptions) -> Result<DecayRate> {
    if !(tol.is_finite() && tol > 0.0) {
        return Err(LmiError::InvalidArgument {
            what: "tol".into(),
            reason: format!("must be finite and > 0, got {tol}"),
        });
    }
    // Every eigenvalue satisfies |λ| ≤ ‖A‖_F, so α = −‖A‖_F − 1 is feasible and α = ‖A‖_F + 1
    // is not.
    let bound = a.norm() + 1.0;
    let (mut lo, mut hi) = (-bound, bound);
    let first = alpha_stability(a, lo, margin, options)?;
    let mut best = match first.p {
        Some(p) if first.feasible => p,
        _ => {
            return Err(LmiError::InvalidArgument {
                what: "A".into(),
                reason: format!(
                    "the LMI is infeasible even for α = {lo}: {:?}",
                    first.solution.status
                ),
            });
        }
    };
    let mut solves = 1;
    while hi - lo > tol {
        let mid = 0.5 * (lo + hi);
        let t = alpha_stability(a, mid, margin, options)?;
        solves += 1;
        match (t.feasible, t.p) {
            (true, Some(p)) => {
                lo = mid;
                best = p;
            }
            // Infeasible, or numerically undecided this close to the boundary.
            _ => hi = mid,
        }
    }
    Ok(DecayRate {
        alpha: lo,
        p: best,
        solves,
    })
}
