//! The designs every front end performs on a plant's upright linearisation: the LQ regulator,
//! the LQ integral servo on the drive position `q₀` and pole placement, each giving the gain in
//! the library's sign (`u = −K x`), the closed-loop poles and the loop's model, with the inputs
//! a [`DesignRecord`](super::DesignRecord) records ([`weight_inputs`], [`pole_inputs`]). The
//! CLI's `pendulab design` and the browser lab call [`lqr_upright`], [`servo_upright`] and
//! [`place_upright`]; each checks its own inputs first (with its own flags or field
//! names in the errors) and writes its own controller file or spec from the result.
//!
//! The linearisation is the plant's own (`PlantParameters::linearize_upright`, `C = I`,
//! state `[q₀, q₁, q̇₀, q̇₁]`; `docs/model.md` §1–2); the designs are
//! `pendulab_lti::design::{lqr, lq_servo, place}`.

use super::DesignInput;
use pendulab_lti::design::{integral_augmentation, lq_servo, lqr, place};
use pendulab_lti::linalg::Complex64;
use pendulab_lti::{Continuous, LtiError, Mat, StateSpace};
use std::collections::BTreeMap;

/// The design record's `method` for the LQ integral servo of [`servo_upright`], as every front
/// end writes it: the `kind` of the controller it gives (`lq-servo`).
pub const SERVO_METHOD: &str = "lq-servo";

/// What the upright designs return.
#[derive(Debug, Clone, PartialEq)]
pub struct UprightDesign {
    /// The gain in library sign (`u = −K x`): `1 × 4`, or the servo's `[K₁ K₂]` (`1 × 5`,
    /// `u = −K₁ x − K₂ w`) \[V per unit of each state\].
    pub gain: Mat,
    /// The closed-loop poles (4, or 5 for the servo) \[1/s\].
    pub poles: Vec<Complex64>,
    /// The loop's `A`: the linearisation's, or the servo's augmentation on `[x; w]`.
    pub a: Mat,
    /// The loop's `B` (one input).
    pub b: Mat,
}

/// The LQ weights as a design record keeps them: `q` (a list) and `r` (a number).
pub fn weight_inputs(q: &[f64], r: f64) -> BTreeMap<String, DesignInput> {
    [
        ("q".to_string(), DesignInput::List(q.to_vec())),
        ("r".to_string(), DesignInput::Number(r)),
    ]
    .into()
}

/// Closed-loop poles as a design record keeps them: `poles`, rows `[re, im]`.
pub fn pole_inputs(poles: &[Complex64]) -> BTreeMap<String, DesignInput> {
    [(
        "poles".to_string(),
        DesignInput::Rows(poles.iter().map(|p| vec![p.re, p.im]).collect()),
    )]
    .into()
}

/// The servo's model: the linearisation `lin` with the drive position `q₀` as its one output
/// (`C = [1 0 0 0]`, `D = 0`), on which `lq_servo` integrates `r − q₀`.
///
/// # Errors
/// [`LtiError`] if `lin` does not have four states and one input.
pub fn drive_servo_model(lin: &StateSpace<Continuous>) -> Result<StateSpace<Continuous>, LtiError> {
    StateSpace::continuous(
        lin.a().clone(),
        lin.b().clone(),
        Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]),
        Mat::zeros(1, 1),
    )
}

fn diag(q: &[f64]) -> Mat {
    Mat::from_diagonal(&nalgebra::DVector::from_row_slice(q))
}

/// LQR on the upright linearisation `lin` (`[q₀, q₁, q̇₀, q̇₁]`): `Q = diag(q)` (4 entries,
/// finite, ≥ 0), `R = r` (finite, > 0) \[1/V²\], the cost `∫ xᵀQx + R u² dt`.
///
/// # Errors
/// The [`LtiError`] of `pendulab_lti::design::lqr` (no stabilising solution; a shape error
/// for `q` of the wrong length).
pub fn lqr_upright(
    lin: &StateSpace<Continuous>,
    q: &[f64],
    r: f64,
) -> Result<UprightDesign, LtiError> {
    let d = lqr(lin, &diag(q), &Mat::from_element(1, 1, r), None)?;
    Ok(UprightDesign {
        gain: d.gain,
        poles: d.closed_loop_poles,
        a: lin.a().clone(),
        b: lin.b().clone(),
    })
}

/// The LQ integral servo on `q₀` (book part 1 §6.3) on the upright linearisation `lin`: LQR on
/// `[x; w]`, `w = ∫(r − q₀) dt` ([`drive_servo_model`]), `Q = diag(q)` (5 entries), `R = r`;
/// the loop's model is the augmentation.
///
/// # Errors
/// As [`lqr_upright`].
pub fn servo_upright(
    lin: &StateSpace<Continuous>,
    q: &[f64],
    r: f64,
) -> Result<UprightDesign, LtiError> {
    let on_q0 = drive_servo_model(lin)?;
    let d = lq_servo(&on_q0, &diag(q), &Mat::from_element(1, 1, r))?;
    let (a, b) = integral_augmentation(&on_q0)?;
    Ok(UprightDesign {
        gain: d.lqr.gain,
        poles: d.lqr.closed_loop_poles,
        a,
        b,
    })
}

/// Pole placement on the upright linearisation `lin`: `eig(A − BK)` = `poles` (4, complex ones
/// with their conjugates) \[1/s\].
///
/// # Errors
/// The [`LtiError`] of `pendulab_lti::design::place`.
pub fn place_upright(
    lin: &StateSpace<Continuous>,
    poles: &[Complex64],
) -> Result<UprightDesign, LtiError> {
    let (a, b) = (lin.a().clone(), lin.b().clone());
    let d = place(&a, &b, poles)?;
    Ok(UprightDesign {
        gain: d.gain,
        poles: d.achieved_poles,
        a,
        b,
    })
}
