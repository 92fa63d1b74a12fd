//! Output feedback: the observer-based controller discretised for the sampled loop, and the
//! steady-state Kalman filter for noisy encoders (book ch. 7–8).
//!
//! The run-time controllers are `pendulab-sim`'s
//! ([`DiscreteLinearController`], [`ObserverBased`]); this module designs what they run:
//!
//! - [`output_feedback_controller`]: the book's observer-based controller
//!   `(A + BK_b + L_b C, −L_b, K_b)` — in `pendulab-lti`'s signs `u = −Kx`, observer `A − LC`:
//!   [`observer_controller`] `= (A − BK − LC, L, −K)` — discretised at the loop's sample time
//!   by any [`Discretization`] (ZOH: `p1c83_ex2`, Tustin: `p1c84_ex4`, both at 10 ms; at 1 ms
//!   it stands in for the continuous controller of `p1c74_ex1`).
//! - [`kalman_filter`]: the steady-state Kalman filter of a discrete model with process noise
//!   `G w` and measurement noise `v` — predictor gain `L` (from [`lqe`]'s dual DARE), filter gain
//!   `M = P Cᵀ(C P Cᵀ + R)⁻¹`, prior and posterior error covariances — and
//!   [`kalman_controller`]: `u = −K x̂` with the filter in current-estimate form
//!   (`x̄ₖ = A x̂ₖ₋₁ + B uₖ₋₁`, `x̂ₖ = x̄ₖ + M(yₖ − C x̄ₖ)`; Franklin, Powell & Workman, *Digital
//!   Control of Dynamic Systems*, §8.6 and §9.4), measuring only the encoders.

use crate::error::{ControlError, Result, check_matrix};
use pendulab_lti::design::{StateFeedback, lqe, observer_controller};
use pendulab_lti::{Complex64, Continuous, Discrete, Discretization, Mat, StateSpace};
use pendulab_sim::controllers::{DiscreteLinearController, EstimatorForm, ObserverBased};

/// The observer-based output-feedback controller of `plant` (continuous, `C` = the measured
/// outputs) for the state feedback `u = −Kx` and the full-order observer gain `L`
/// (`A − LC`), discretised with sample time `ts` by `method`, as a run-time controller from
/// the measurement `y` to the command `u`.
///
/// # Errors
/// Shape errors for `K` or `L` ([`observer_controller`]); the discretisation's errors; the
/// controller's construction errors.
pub fn output_feedback_controller(
    plant: &StateSpace<Continuous>,
    feedback: &StateFeedback,
    observer_gain: &Mat,
    ts: f64,
    method: Discretization,
) -> Result<DiscreteLinearController> {
    let ctrl = observer_controller(plant, feedback.gain(), observer_gain)?;
    let discrete = ctrl.c2d(ts, method)?;
    Ok(DiscreteLinearController::new(&discrete)?)
}

/// A steady-state Kalman filter design with its diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct SteadyStateKalman {
    /// Predictor gain `L = A P Cᵀ (C P Cᵀ + R)⁻¹` (`x̂ₖ₊₁ = A x̂ₖ + B uₖ + L(yₖ − C x̂ₖ)`, as
    /// [`lqe`] returns it).
    pub predictor_gain: Mat,
    /// Filter (measurement-update) gain `M = P Cᵀ (C P Cᵀ + R)⁻¹`.
    pub filter_gain: Mat,
    /// Prior (one-step prediction) error covariance `P` (the DARE solution).
    pub prior_covariance: Mat,
    /// Posterior error covariance `(I − M C) P` of `x̂ₖ` given `y₀ … yₖ`.
    pub posterior_covariance: Mat,
    /// Eigenvalues of the current-estimate error dynamics `(I − M C) A` (the same as those of
    /// `A − L C`).
    pub error_poles: Vec<Complex64>,
    /// Relative residual of the DARE.
    pub residual: f64,
}

/// The steady-state Kalman filter of `x⁺ = A x + B u + G w`, `y = C x + v`,
/// `E[wwᵀ] = Q_n`, `E[vvᵀ] = R_n` (uncorrelated), `D = 0` (MATLAB `kalman(sys, Qn, Rn)`, its
/// `M` and `P` outputs).
///
/// # Errors
/// [`ControlError::NotApplicable`] for `D ≠ 0`; shape errors; [`lqe`]'s errors (e.g. `(C, A)`
/// not detectable, `R_n` not positive definite).
#[doc(alias = "kalman")]
#[doc(alias = "dlqe")]
pub fn kalman_filter(
    sys: &StateSpace<Discrete>,
    g: &Mat,
    qn: &Mat,
    rn: &Mat,
) -> Result<SteadyStateKalman> {
    if sys.d().iter().any(|v| *v != 0.0) {
        return Err(ControlError::NotApplicable {
            reason: "the Kalman filter here needs D = 0 (measurements taken before the input acts)"
                .into(),
        });
    }
    let k = lqe(sys, g, qn, rn, None)?;
    let p = k.covariance;
    let c = sys.c();
    let s = c * &p * c.transpose() + rn;
    // M = P Cᵀ S⁻¹ with S = C P Cᵀ + R symmetric: Mᵀ = S⁻¹ (C P).
    let m = s
        .lu()
        .solve(&(c * &p))
        .ok_or_else(|| ControlError::Singular {
            what: "innovation covariance C P Cᵀ + R".into(),
            value: 0.0,
        })?
        .transpose();
    let n = sys.nx();
    let post = (Mat::identity(n, n) - &m * c) * &p;
    let post = (&post + post.transpose()) * 0.5;
    let err = (Mat::identity(n, n) - &m * c) * sys.a();
    let mut poles = pendulab_lti::linalg::eigenvalues(&err)?;
    pendulab_lti::linalg::sort_eigenvalues(&mut poles);
    Ok(SteadyStateKalman {
        predictor_gain: k.gain,
        filter_gain: m,
        prior_covariance: p,
        posterior_covariance: post,
        error_poles: poles,
        residual: k.residual,
    })
}

/// State feedback `u = −K x̂` on the Kalman filter's current estimate, for the discrete model
/// `plant` (its `C` = the encoder outputs the controller measures).
///
/// # Errors
/// [`ControlError::ShapeMismatch`] for a filter gain that is not `nx × ny`; the controller's
/// construction errors (gain shapes, `D ≠ 0`).
pub fn kalman_controller(
    plant: &StateSpace<Discrete>,
    feedback: &StateFeedback,
    kalman: &SteadyStateKalman,
) -> Result<ObserverBased> {
    check_matrix(
        "Kalman filter gain M",
        &kalman.filter_gain,
        plant.nx(),
        plant.ny(),
    )?;
    Ok(ObserverBased::new(
        plant,
        feedback.gain(),
        &kalman.filter_gain,
        EstimatorForm::Current,
    )?)
}
