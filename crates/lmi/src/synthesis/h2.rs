//! State-feedback H2 synthesis by LMIs (Feron, Balakrishnan, Boyd & El Ghaoui, "Numerical
//! methods for H2 related problems", ACC 1992; Boyd et al., *Linear Matrix Inequalities in
//! System and Control Theory*, SIAM 1994, §7.2.3), on the [`StandardPlant`] of
//! `pendulab-lti`.
//!
//! With `u = −K x`, `K = −L X⁻¹`, the closed loop `(A − B₂K, B₁, C₁ − D₁₂K)` (`D₁₁ = 0`) has
//! `‖T_zw‖₂² < tr W` iff some `X ≻ 0`, `L`, `W` satisfy
//!
//! ```text
//! He(AX + B₂L) + B₁B₁ᵀ ≺ 0,        [ W             C₁X + D₁₂L ]
//!                                  [ (C₁X + D₁₂L)ᵀ X          ] ≻ 0
//! ```
//!
//! (`X` bounds the controllability Gramian, `W` the output covariance `(C₁ − D₁₂K)X(·)ᵀ`).
//! [`h2_state_feedback_lmi`] minimises `tr W`; the optimum is the Riccati value
//! `tr(B₁ᵀX₂B₁)` of [`pendulab_lti::design::h2_state_feedback`].

use super::hinf::HinfLmiOptions;
use crate::error::{LmiError, Result};
use crate::expr::Expr;
use crate::problem::Problem;
use crate::solution::{Solution, Status};
use pendulab_lti::Mat;
use pendulab_lti::design::StandardPlant;

/// Result of [`h2_state_feedback_lmi`].
#[derive(Debug, Clone)]
pub struct H2StateFeedbackLmi {
    /// Status of the solve.
    pub status: Status,
    /// `√(min tr W)`, the guaranteed (and, at the optimum, attained) `‖T_zw‖₂` (None unless
    /// solved with all rechecks passing).
    pub norm: Option<f64>,
    /// `K` of `u = −K x` (None unless solved).
    pub gain: Option<Mat>,
    /// `X ≻ 0`.
    pub x: Option<Mat>,
    /// The solve.
    pub solution: Solution,
}

/// State-feedback H2 synthesis by LMIs (module documentation). Uses `A, B₁, B₂, C₁, D₁₂`;
/// `options.relax` is not used.
///
/// # Errors
/// [`LmiError::InvalidArgument`] for `D₁₁ ≠ 0` (infinite H2 norm), a plant without states
/// or controls, or a margin that is not positive; modelling and solver errors.
pub fn h2_state_feedback_lmi(
    plant: &StandardPlant,
    options: &HinfLmiOptions,
) -> Result<H2StateFeedbackLmi> {
    if !(options.margin.is_finite() && options.margin > 0.0) {
        return Err(LmiError::InvalidArgument {
            what: "margin".into(),
            reason: format!("must be finite and > 0, got {}", options.margin),
        });
    }
    let n = plant.nx();
    if n == 0 || plant.ncon() == 0 || plant.d11().iter().any(|v| *v != 0.0) {
        return Err(LmiError::InvalidArgument {
            what: "plant".into(),
            reason: "needs n ≥ 1 states, ncon ≥ 1 controls and D11 = 0 (else ‖T_zw‖₂ = ∞)".into(),
        });
    }
    let (a, b1, b2, c1, d12) = (plant.a(), plant.b1(), plant.b2(), plant.c1(), plant.d12());
    let mut p = Problem::new();
    let x = p.symmetric("X", n);
    let l = p.matrix("L", plant.ncon(), n);
    let w = p.symmetric("W", plant.nz());
    let y = a * &x + &b2 * &l;
    p.negative_definite(
        "He(AX + B₂L) + B₁B₁ᵀ ≺ 0",
        &(y.he() + Expr::constant(&(&b1 * b1.transpose()))),
        options.margin,
    )?;
    let cz = &c1 * &x + &d12 * &l;
    p.positive_definite(
        "[W, C₁X + D₁₂L; ·, X] ≻ 0",
        &Expr::block(&[&[&w, &cz], &[&cz.t(), &x]]),
        options.margin,
    )?;
    p.minimize(&w.trace())?;
    let solution = p.solve(&options.solve)?;
    let mut out = H2StateFeedbackLmi {
        status: solution.status.clone(),
        norm: None,
        gain: None,
        x: None,
        solution,
    };
    if out.solution.all_checks_pass() {
        let (gain, xv) = super::hinf::state_feedback_gain(&out.solution, &x, &l)?;
        out.gain = Some(gain);
        out.norm = out.solution.objective.map(|t| t.max(0.0).sqrt());
        out.x = Some(xv);
    }
    Ok(out)
}
