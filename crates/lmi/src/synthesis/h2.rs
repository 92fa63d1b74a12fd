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
//!
//! # Output feedback
//!
//! [`h2_output_feedback_lmi`]: the change of variables of Scherer, Gahinet & Chilali
//! ("Multiobjective output-feedback control via LMI optimization", IEEE TAC 42(7), 1997,
//! §IV.B with `D_k = 0`, which `D₁₁ = 0` allows and a finite H2 norm needs). A full-order
//! controller `(A_k, B_k, C_k, 0)` with `‖T_zw‖₂² < tr W` exists iff some symmetric `X`, `Y`,
//! `W` and `Â`, `B̂`, `Ĉ` satisfy
//!
//! ```text
//! [ He(AX + B₂Ĉ)   (Â + Aᵀ)ᵀ        B₁          ]
//! [ Â + Aᵀ         He(YA + B̂C₂)     YB₁ + B̂D₂₁  ]  ≺ 0,
//! [ B₁ᵀ            (YB₁ + B̂D₂₁)ᵀ    −I          ]
//!
//! [ X              I      (C₁X + D₁₂Ĉ)ᵀ ]
//! [ I              Y      C₁ᵀ           ]  ≻ 0
//! [ C₁X + D₁₂Ĉ     C₁     W             ]
//! ```
//!
//! (the closed-loop Gramian conditions transformed by `[[X, I], [Mᵀ, 0]]`, `X_cl =
//! [[Y, N], [Nᵀ, ·]]`, `MNᵀ = I − XY`). The problem minimises `tr W`; the controller is
//! reconstructed with `M = I`, `N = I − YX`: `C_k = Ĉ`, `B_k = N⁻¹B̂`,
//! `A_k = N⁻¹(Â − B̂C₂X − YB₂Ĉ − YAX)`, and `D₂₂ ≠ 0` by loop shifting
//! ([`StandardPlant::shift_d22`]). The optimum `√min tr W` is the Riccati value of
//! [`pendulab_lti::design::h2_syn`] (an independent algorithm).
//!
//! The problem is solved as [`super::hinf_lmi`]'s γ minimisation is (its module
//! documentation, "Conditioning"): in equilibrated coordinates, then in those that balance
//! the previous solve's `(X, Y)` (`X` transforming like `R`, `Y` like `S`; no level scaling),
//! up to three solves while `tr W` decreases. On the mixed-sensitivity plant of the Slycot
//! fixture (`Y` unbounded at the optimum) this takes Clarabel from 4e-3 to 3e-6 above the
//! Riccati optimum.

use super::coordinates::{Coordinates, Pass, refine};
use super::hinf::HinfLmiOptions;
use crate::error::{LmiError, Result};
use crate::expr::Expr;
use crate::problem::Problem;
use crate::solution::{Solution, Status};
use pendulab_lti::design::StandardPlant;
use pendulab_lti::{Continuous, Mat, StateSpace};

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
/// The gain is returned only if its own closed loop is stable with `‖T_zw‖₂` at most the
/// certified norm (relative slack 10⁻⁴, absolute `10·√margin`); otherwise `norm` and `gain`
/// are `None` and the status is [`Status::NumericalTrouble`] with the reason.
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
        let level = out
            .solution
            .objective
            .map_or(f64::NAN, |t| t.max(0.0).sqrt());
        // As for the H∞ gain: check the loop itself (stable, ‖T_zw‖₂ at most the certified
        // norm up to the solver's tolerances, with an absolute floor of 10·√margin for plants
        // whose optimum is 0).
        let floor = 10.0 * options.margin.sqrt();
        if let Some(reason) = super::hinf::state_feedback_loop_fails(plant, &gain, |cl| {
            let norm = pendulab_lti::norms::h2_norm(cl)?;
            Ok(
                (norm <= level * (1.0 + super::hinf::STATE_FEEDBACK_NORM_SLACK) + floor)
                    .then_some(())
                    .ok_or(format!("‖T_zw‖₂ = {norm:e} above the certified {level:e}")),
            )
        })? {
            out.status = Status::NumericalTrouble { reason };
            return Ok(out);
        }
        out.gain = Some(gain);
        out.norm = out.solution.objective.map(|t| t.max(0.0).sqrt());
        out.x = Some(xv);
    }
    Ok(out)
}

/// An output-feedback H2 controller from [`h2_output_feedback_lmi`].
#[derive(Debug, Clone, PartialEq)]
pub struct H2LmiController {
    /// The controller `K` (`n` states, `nmeas` inputs, `ncon` outputs), `u = K y`.
    pub controller: StateSpace<Continuous>,
    /// The closed loop `F_l(P, K)`: `‖T_zw‖₂ ≤` the certified `norm`.
    pub closed_loop: StateSpace<Continuous>,
    /// `X` of the solve.
    pub x: Mat,
    /// `Y` of the solve.
    pub y: Mat,
}

/// Result of [`h2_output_feedback_lmi`].
#[derive(Debug, Clone)]
pub struct H2OutputFeedbackLmi {
    /// Status of the solve.
    pub status: Status,
    /// `√(min tr W)`, the certified bound of the closed loop's `‖T_zw‖₂` (None unless solved
    /// with all rechecks passing).
    pub norm: Option<f64>,
    /// The controller (None unless solved).
    pub design: Option<H2LmiController>,
    /// The solve with the smallest `tr W` (else the last one tried); its variables are
    /// those of the scaled problem ([`h2_output_feedback_lmi`]).
    pub solution: Solution,
}

/// The variables of the output-feedback H2 LMIs.
struct H2Vars {
    x: Expr,
    y: Expr,
    ahat: Expr,
    bhat: Expr,
    chat: Expr,
}

/// The output-feedback H2 LMIs of `plant` (`D₂₂ = 0`), minimising `tr W`, solved.
fn h2_output_lmis(plant: &StandardPlant, options: &HinfLmiOptions) -> Result<(Solution, H2Vars)> {
    let n = plant.nx();
    let (a, b1, b2, c1, c2, d12, d21) = (
        plant.a(),
        plant.b1(),
        plant.b2(),
        plant.c1(),
        plant.c2(),
        plant.d12(),
        plant.d21(),
    );
    let mut p = Problem::new();
    let x = p.symmetric("X", n);
    let y = p.symmetric("Y", n);
    let w = p.symmetric("W", plant.nz());
    let ah = p.matrix("Ahat", n, n);
    let bh = p.matrix("Bhat", n, plant.nmeas());
    let ch = p.matrix("Chat", plant.ncon(), n);
    let e11 = (a * &x + &b2 * &ch).he();
    let e21 = &ah + Expr::constant(&a.transpose());
    let e22 = (&y * a + &bh * &c2).he();
    let e31 = Expr::constant(&b1.transpose());
    let e32 = (&y * &b1 + &bh * &d21).t();
    let e33 = Expr::identity(plant.nw()) * -1.0;
    p.negative_definite(
        "[He(AX + B₂Ĉ), ·, ·; Â + Aᵀ, He(YA + B̂C₂), ·; B₁ᵀ, (YB₁ + B̂D₂₁)ᵀ, −I] ≺ 0",
        &Expr::block(&[
            &[&e11, &e21.t(), &e31.t()],
            &[&e21, &e22, &e32.t()],
            &[&e31, &e32, &e33],
        ]),
        options.margin,
    )?;
    let cz = &c1 * &x + &d12 * &ch;
    let i = Expr::identity(n);
    let c1e = Expr::constant(&c1);
    p.positive_definite(
        "[X, I, ·; I, Y, ·; C₁X + D₁₂Ĉ, C₁, W] ≻ 0",
        &Expr::block(&[&[&x, &i, &cz.t()], &[&i, &y, &c1e.t()], &[&cz, &c1e, &w]]),
        options.margin,
    )?;
    p.minimize(&w.trace())?;
    let solution = p.solve(&options.solve)?;
    Ok((
        solution,
        H2Vars {
            x,
            y,
            ahat: ah,
            bhat: bh,
            chat: ch,
        },
    ))
}

/// Output-feedback H2 synthesis by LMIs (module documentation, "Output feedback"), up to
/// three solves in successively balanced coordinates; `options.relax` is not used. `solution`
/// is the solve that gave the smallest `tr W` (its variables those of the scaled problem).
///
/// # Errors
/// [`LmiError::InvalidArgument`] for `D₁₁ ≠ 0` (infinite H2 norm), a plant without states,
/// controls or measurements, or a margin that is not positive, and when `I − YX` of the
/// solution is singular (no reconstruction); modelling and
/// solver errors; [`LmiError::Lti`] from the loop shift and the closed loop.
#[doc(alias = "h2syn")]
pub fn h2_output_feedback_lmi(
    plant: &StandardPlant,
    options: &HinfLmiOptions,
) -> Result<H2OutputFeedbackLmi> {
    if !(options.margin.is_finite() && options.margin > 0.0) {
        return Err(LmiError::InvalidArgument {
            what: "margin".into(),
            reason: format!("must be finite and > 0, got {}", options.margin),
        });
    }
    let n = plant.nx();
    if n == 0 || plant.ncon() == 0 || plant.nmeas() == 0 || plant.d11().iter().any(|v| *v != 0.0) {
        return Err(LmiError::InvalidArgument {
            what: "plant".into(),
            reason: "needs n ≥ 1 states, ncon ≥ 1 controls, nmeas ≥ 1 measurements and D11 = 0 \
                     (else ‖T_zw‖₂ = ∞)"
                .into(),
        });
    }
    let design_plant = plant.without_d22()?;
    let refined = refine(Coordinates::equilibrated(&design_plant), false, |coords| {
        let scaled = coords.plant(&design_plant)?;
        let (solution, vars) = h2_output_lmis(&scaled, options)?;
        let pair = match (solution.value(&vars.x), solution.value(&vars.y)) {
            (Ok(x), Ok(y)) => Some((x, y)),
            _ => None,
        };
        Ok(Pass {
            objective: solution.objective,
            accepted: solution.all_checks_pass(),
            pair,
            data: (solution, vars, scaled),
        })
    })?;
    let (coords, (solution, vars, scaled)) = match refined {
        Ok((_, coords, data)) => (coords, data),
        Err((solution, _, _)) => {
            return Ok(H2OutputFeedbackLmi {
                status: solution.status.clone(),
                norm: None,
                design: None,
                solution,
            });
        }
    };
    let mut out = H2OutputFeedbackLmi {
        status: solution.status.clone(),
        norm: None,
        design: None,
        solution,
    };
    let sol = &out.solution;
    let n = scaled.nx();
    let (a, b2, c2) = (scaled.a(), scaled.b2(), scaled.c2());
    let xv = crate::linalg::sym(&sol.value(&vars.x)?);
    let yv = crate::linalg::sym(&sol.value(&vars.y)?);
    let (ahv, bhv, chv) = (
        sol.value(&vars.ahat)?,
        sol.value(&vars.bhat)?,
        sol.value(&vars.chat)?,
    );
    let nmat = (Mat::identity(n, n) - &yv * &xv).lu();
    let singular = || LmiError::InvalidArgument {
        what: "I − YX".into(),
        reason: "singular at the solution: the controller cannot be reconstructed".into(),
    };
    let bk = nmat.solve(&bhv).ok_or_else(singular)?;
    let ak = nmat
        .solve(&(&ahv - &bhv * &c2 * &xv - &yv * &b2 * &chv - &yv * a * &xv))
        .ok_or_else(singular)?;
    let k0 = StateSpace::continuous(ak, bk, chv, Mat::zeros(plant.ncon(), plant.nmeas()))?;
    let k0 = coords.controller(&k0)?;
    let (xv, yv) = (coords.r(&xv), coords.s(&yv));
    let controller = plant.shift_d22(k0)?;
    let closed_loop = plant.close_loop(&controller)?;
    out.norm = out.solution.objective.map(|t| t.max(0.0).sqrt());
    out.design = Some(H2LmiController {
        controller,
        closed_loop,
        x: xv,
        y: yv,
    });
    Ok(out)
}
