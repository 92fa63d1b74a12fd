//! H2 (LQG) synthesis by the two decoupled Riccati equations (Doyle, Glover, Khargonekar &
//! Francis, IEEE TAC 34(8), 1989; Zhou, Doyle & Glover, *Robust and Optimal Control*,
//! Theorem 14.7; MATLAB `h2syn`, python-control `h2syn`, SLICOT `SB10HD`).
//!
//! For the [`StandardPlant`] with `D₁₁ = 0` (otherwise `‖T_zw‖₂ = ∞` for every strictly
//! proper controller), `R₁ = D₁₂ᵀD₁₂ ≻ 0`, `R₂ = D₂₁D₂₁ᵀ ≻ 0`:
//!
//! - `X₂` solves the CARE `AᵀX + XA − (XB₂ + C₁ᵀD₁₂)R₁⁻¹(B₂ᵀX + D₁₂ᵀC₁) + C₁ᵀC₁ = 0`,
//!   `K_x = R₁⁻¹(B₂ᵀX₂ + D₁₂ᵀC₁)` (the optimal state feedback `u = −K_x x`);
//! - `Y₂` solves the dual CARE `AY + YAᵀ − (YC₂ᵀ + B₁D₂₁ᵀ)R₂⁻¹(C₂Y + D₂₁B₁ᵀ) + B₁B₁ᵀ = 0`,
//!   `L = (Y₂C₂ᵀ + B₁D₂₁ᵀ)R₂⁻¹` (the Kalman gain);
//! - the optimal controller (`u = K y`, `D₂₂ = 0`) is the observer-based
//!   `A_k = A − B₂K_x − LC₂`, `B_k = L`, `C_k = −K_x`, `D_k = 0`; `D₂₂ ≠ 0` by loop shifting
//!   ([`StandardPlant::shift_d22`]);
//! - the optimal cost is `‖T_zw‖₂² = tr(B₁ᵀX₂B₁) + tr(R₁K_xY₂K_xᵀ)` (equivalently
//!   `tr(C₁Y₂C₁ᵀ) + tr(R₂LᵀX₂L)`), the first term alone being the optimum of the
//!   state-feedback problem.
//!
//! Both Riccati equations are solved by [`care`] (LQ data: `[[C₁ᵀC₁, C₁ᵀD₁₂], [·, R₁]] ⪰ 0`).

use super::standard_plant::StandardPlant;
use crate::domain::Continuous;
use crate::equations::{RiccatiOptions, care};
use crate::error::Result;
use crate::linalg::Mat;
use crate::state_space::StateSpace;

/// The H2-optimal output-feedback controller.
#[derive(Debug, Clone, PartialEq)]
pub struct H2Controller {
    /// The controller `K` (`nmeas` inputs, `ncon` outputs, `n` states), `u = K y`.
    pub controller: StateSpace<Continuous>,
    /// `X₂` (control Riccati solution).
    pub x: Mat,
    /// `Y₂` (filter Riccati solution).
    pub y: Mat,
    /// `K_x` of the state feedback `u = −K_x x̂` (`ncon × n`).
    pub state_gain: Mat,
    /// The estimator gain `L` (`n × nmeas`): `x̂' = A x̂ + B₂u + L(y − C₂x̂)` (for `D₂₂ = 0`).
    pub estimator_gain: Mat,
    /// The optimal `‖T_zw‖₂` from the Riccati formula `√(tr(B₁ᵀX₂B₁) + tr(R₁K_xY₂K_xᵀ))`.
    pub norm: f64,
    /// The closed loop `T_zw = F_l(P, K)`.
    pub closed_loop: StateSpace<Continuous>,
}

/// The H2-optimal state feedback.
#[derive(Debug, Clone, PartialEq)]
pub struct H2StateFeedback {
    /// `K` of `u = −K x`.
    pub gain: Mat,
    /// `X₂`.
    pub x: Mat,
    /// The optimal `‖T_zw‖₂ = √tr(B₁ᵀX₂B₁)`.
    pub norm: f64,
    /// The closed loop `ẋ = (A − B₂K)x + B₁w`, `z = (C₁ − D₁₂K)x`.
    pub closed_loop: StateSpace<Continuous>,
}

/// The H2-optimal output-feedback controller (module documentation).
///
/// # Errors
/// [`LtiError::SynthesisAssumption`](crate::LtiError::SynthesisAssumption) for a plant
/// violating an assumption of [`StandardPlant::check_assumptions`] (with `D₁₁ = 0`); the
/// errors of [`care`].
#[doc(alias = "h2syn")]
pub fn h2_syn(plant: &StandardPlant) -> Result<H2Controller> {
    plant.check_assumptions(true)?;
    let (kx, x, r1) = control_riccati(plant)?;
    let (b1, b2, c2, d21) = (plant.b1(), plant.b2(), plant.c2(), plant.d21());
    let r2 = &d21 * d21.transpose();
    let yr = care(
        &plant.a().transpose(),
        &c2.transpose(),
        &crate::linalg::symmetrize(&(&b1 * b1.transpose())),
        &r2,
        Some(&(&b1 * d21.transpose())),
        &RiccatiOptions::default(),
    )?;
    let l = yr.gain.transpose();
    let y = yr.x;
    let cost = (b1.transpose() * &x * &b1).trace() + (&r1 * &kx * &y * kx.transpose()).trace();
    let k0 = StateSpace::continuous(
        plant.a() - &b2 * &kx - &l * &c2,
        l.clone(),
        -&kx,
        Mat::zeros(plant.ncon(), plant.nmeas()),
    )?;
    let controller = plant.shift_d22(k0)?;
    let closed_loop = plant.close_loop(&controller)?;
    Ok(H2Controller {
        controller,
        x,
        y,
        state_gain: kx,
        estimator_gain: l,
        norm: cost.max(0.0).sqrt(),
        closed_loop,
    })
}

/// The H2-optimal state feedback `u = −K x` (full information): `X₂` and `K_x` of the module
/// documentation. Only `A, B₁, B₂, C₁, D₁₁, D₁₂` of the plant are used.
///
/// # Errors
/// [`LtiError::SynthesisAssumption`](crate::LtiError::SynthesisAssumption) for `D₁₁ ≠ 0`,
/// `D₁₂` not of full column rank or `P₁₂` with an imaginary-axis zero; the errors of
/// [`care`] (e.g. [`LtiError::NotStabilizable`](crate::LtiError::NotStabilizable)).
pub fn h2_state_feedback(plant: &StandardPlant) -> Result<H2StateFeedback> {
    plant.check_d11(true)?;
    plant.check_d12_rank()?;
    plant.check_p12_zeros()?;
    let (k, x, _) = control_riccati(plant)?;
    let b1 = plant.b1();
    let norm = (b1.transpose() * &x * &b1).trace().max(0.0).sqrt();
    let closed_loop = StateSpace::continuous(
        plant.a() - plant.b2() * &k,
        b1,
        plant.c1() - plant.d12() * &k,
        plant.d11(),
    )?;
    Ok(H2StateFeedback {
        gain: k,
        x,
        norm,
        closed_loop,
    })
}

/// `(K_x, X₂, R₁)` of the control Riccati equation.
fn control_riccati(plant: &StandardPlant) -> Result<(Mat, Mat, Mat)> {
    let (b2, c1, d12) = (plant.b2(), plant.c1(), plant.d12());
    let r1 = d12.transpose() * &d12;
    let sol = care(
        plant.a(),
        &b2,
        &crate::linalg::symmetrize(&(c1.transpose() * &c1)),
        &r1,
        Some(&(c1.transpose() * &d12)),
        &RiccatiOptions::default(),
    )?;
    Ok((sol.gain, sol.x, r1))
}
