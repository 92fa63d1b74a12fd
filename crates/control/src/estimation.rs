//! Output feedback: linear controllers as [`Controller`]s, observer-based controllers
//! discretised for the sampled loop, and the steady-state Kalman filter (book ch. 7–8).
//!
//! - [`LinearController`]: any discrete state-space controller `x_c⁺ = A_c x_c + B_c y`,
//!   `u = C_c x_c + D_c y`, built directly or from a continuous one by `c2d` (ZOH, Tustin,
//!   … — [`Discretization`]). The book's observer-based controller
//!   `(A + BK_b + L_b C, −L_b, K_b)` (in `pendulab-lti`'s signs `u = −Kx`, `A − LC`:
//!   [`observer_controller`](pendulab_lti::design::observer_controller)) discretised at
//!   10 ms by ZOH (`p1c83_ex2`) or Tustin (`p1c84_ex4`) is
//!   [`LinearController::from_continuous`] of it.
//! - [`kalman_filter`]: the steady-state Kalman filter of a discrete model with process noise
//!   `G w` and measurement noise `v` — its predictor gain `L` (from
//!   [`lqe`]'s dual DARE), filter gain `M = P Cᵀ(C P Cᵀ + R)⁻¹`
//!   and the prior / posterior error covariances.
//! - [`KalmanFilter`] (the filter as a value, allocation-free) and
//!   [`EstimatedStateFeedback`] (`u = −K x̂` from noisy encoder readings, a [`Controller`]).

use crate::error::{ControlError, Result, check_matrix, check_vector};
use pendulab_lti::design::{StateFeedback, lqe};
use pendulab_lti::{Complex64, Continuous, Discrete, Discretization, Mat, StateSpace};
use pendulab_sim::Controller;

/// A discrete linear controller `x_c⁺ = A_c x_c + B_c y`, `u = C_c x_c + D_c y` as a
/// [`Controller`] (measurement `y`: the system's inputs; command `u`: its outputs). Its sample
/// time must be the loop's.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearController {
    a: Mat,
    b: Mat,
    c: Mat,
    d: Mat,
    ts: f64,
    state: Vec<f64>,
    next: Vec<f64>,
    initial: Vec<f64>,
}

impl LinearController {
    /// The controller `sys` (inputs = measurements, outputs = commands), starting from
    /// `x_c = 0`.
    pub fn new(sys: &StateSpace<Discrete>) -> Self {
        let n = sys.nx();
        Self {
            a: sys.a().clone(),
            b: sys.b().clone(),
            c: sys.c().clone(),
            d: sys.d().clone(),
            ts: sys.ts(),
            state: vec![0.0; n],
            next: vec![0.0; n],
            initial: vec![0.0; n],
        }
    }

    /// A continuous controller discretised with sample time `ts` by `method`
    /// (MATLAB `c2d(K, ts, method)`).
    ///
    /// # Errors
    /// The discretisation's errors (sample time, prewarp, singular Tustin pencil).
    pub fn from_continuous(
        sys: &StateSpace<Continuous>,
        ts: f64,
        method: Discretization,
    ) -> Result<Self> {
        Ok(Self::new(&sys.c2d(ts, method)?))
    }

    /// The controller as a discrete system.
    ///
    /// # Errors
    /// None in practice (the matrices were valid at construction).
    pub fn system(&self) -> Result<StateSpace<Discrete>> {
        Ok(StateSpace::discrete(
            self.a.clone(),
            self.b.clone(),
            self.c.clone(),
            self.d.clone(),
            self.ts,
        )?)
    }

    /// Sample time in seconds.
    pub fn sample_time(&self) -> f64 {
        self.ts
    }

    /// The controller state `x_c`.
    pub fn state(&self) -> &[f64] {
        &self.state
    }

    /// Sets the state the controller starts from (now and after every reset).
    ///
    /// # Errors
    /// Dimension/finiteness errors.
    pub fn set_initial_state(&mut self, x0: &[f64]) -> Result<()> {
        check_vector("controller initial state", x0, self.a.nrows())?;
        self.initial.copy_from_slice(x0);
        self.state.copy_from_slice(x0);
        Ok(())
    }
}

impl Controller for LinearController {
    fn ny(&self) -> usize {
        self.b.ncols()
    }

    fn nu(&self) -> usize {
        self.c.nrows()
    }

    fn reset(&mut self) {
        self.state.copy_from_slice(&self.initial);
    }

    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        let (n, p, m) = (self.a.nrows(), self.b.ncols(), self.c.nrows());
        for i in 0..m {
            let mut s = 0.0;
            for k in 0..n {
                s += self.c[(i, k)] * self.state[k];
            }
            for j in 0..p {
                s += self.d[(i, j)] * y[j];
            }
            u[i] = s;
        }
        for i in 0..n {
            let mut s = 0.0;
            for k in 0..n {
                s += self.a[(i, k)] * self.state[k];
            }
            for j in 0..p {
                s += self.b[(i, j)] * y[j];
            }
            self.next[i] = s;
        }
        std::mem::swap(&mut self.state, &mut self.next);
    }
}

/// A steady-state Kalman filter design with its diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct SteadyStateKalman {
    /// Predictor gain `L = A P Cᵀ (C P Cᵀ + R)⁻¹` (`x̄ₖ₊₁ = A x̂ₖ⁻ … `, as `lqe`).
    pub predictor_gain: Mat,
    /// Filter (measurement-update) gain `M = P Cᵀ (C P Cᵀ + R)⁻¹`.
    pub filter_gain: Mat,
    /// Prior (one-step prediction) error covariance `P` (the DARE solution).
    pub prior_covariance: Mat,
    /// Posterior error covariance `(I − M C) P` of `x̂ₖ` given `y₀ … yₖ`.
    pub posterior_covariance: Mat,
    /// Eigenvalues of the error dynamics `(I − M C) A` (= those of `A − L C`).
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

/// The Kalman filter in current-estimate form (Franklin, Powell & Workman, *Digital Control of
/// Dynamic Systems*, §9.4): `x̄ₖ = A x̂ₖ₋₁ + B uₖ₋₁`, `x̂ₖ = x̄ₖ + M (yₖ − C x̄ₖ)`.
/// Allocation-free.
#[derive(Debug, Clone, PartialEq)]
pub struct KalmanFilter {
    a: Mat,
    b: Mat,
    c: Mat,
    m: Mat,
    estimate: Vec<f64>,
    prior: Vec<f64>,
    initial: Vec<f64>,
    innovation: Vec<f64>,
}

impl KalmanFilter {
    /// The filter of `sys` with gain `M` (`nx × ny`), starting from the prior `x̄₀ = 0`.
    ///
    /// # Errors
    /// Shape/finiteness errors for `M`.
    pub fn new(sys: &StateSpace<Discrete>, m: &Mat) -> Result<Self> {
        let (n, p) = (sys.nx(), sys.ny());
        check_matrix("filter gain M", m, n, p)?;
        Ok(Self {
            a: sys.a().clone(),
            b: sys.b().clone(),
            c: sys.c().clone(),
            m: m.clone(),
            estimate: vec![0.0; n],
            prior: vec![0.0; n],
            initial: vec![0.0; n],
            innovation: vec![0.0; p],
        })
    }

    /// Sets the prior `x̄₀` used at the first update (and after every reset).
    ///
    /// # Errors
    /// Dimension/finiteness errors.
    pub fn set_initial_prior(&mut self, x0: &[f64]) -> Result<()> {
        check_vector("filter initial prior", x0, self.a.nrows())?;
        self.initial.copy_from_slice(x0);
        self.prior.copy_from_slice(x0);
        Ok(())
    }

    /// Back to the initial prior.
    pub fn reset(&mut self) {
        self.prior.copy_from_slice(&self.initial);
    }

    /// Measurement update with `y` (then [`predict`](Self::predict) with the input applied):
    /// returns `x̂ₖ`.
    pub fn correct(&mut self, y: &[f64]) -> &[f64] {
        let (n, p) = (self.a.nrows(), self.c.nrows());
        for i in 0..p {
            let mut s = y[i];
            for k in 0..n {
                s -= self.c[(i, k)] * self.prior[k];
            }
            self.innovation[i] = s;
        }
        for i in 0..n {
            let mut s = self.prior[i];
            for j in 0..p {
                s += self.m[(i, j)] * self.innovation[j];
            }
            self.estimate[i] = s;
        }
        &self.estimate
    }

    /// Time update with the input `u` applied after the last correction:
    /// `x̄ₖ₊₁ = A x̂ₖ + B uₖ`.
    pub fn predict(&mut self, u: &[f64]) {
        let (n, m) = (self.a.nrows(), self.b.ncols());
        for i in 0..n {
            let mut s = 0.0;
            for k in 0..n {
                s += self.a[(i, k)] * self.estimate[k];
            }
            for j in 0..m {
                s += self.b[(i, j)] * u[j];
            }
            self.prior[i] = s;
        }
    }

    /// The current estimate `x̂ₖ` (after the last correction).
    pub fn estimate(&self) -> &[f64] {
        &self.estimate
    }
}

/// State feedback on the Kalman estimate, `uₖ = −K x̂ₖ`, as a [`Controller`] whose measurement
/// is the model's output `y` (e.g. noisy encoder positions).
#[derive(Debug, Clone, PartialEq)]
pub struct EstimatedStateFeedback {
    filter: KalmanFilter,
    gain: Mat,
}

impl EstimatedStateFeedback {
    /// `u = −K x̂` with `K` from `feedback` and the filter `filter`.
    ///
    /// # Errors
    /// [`ControlError::ShapeMismatch`] if `K` is not `nu × nx` for the filter's model.
    pub fn new(filter: KalmanFilter, feedback: &StateFeedback) -> Result<Self> {
        check_matrix("K", feedback.gain(), filter.b.ncols(), filter.a.nrows())?;
        Ok(Self {
            filter,
            gain: feedback.gain().clone(),
        })
    }

    /// The filter (its estimate).
    pub fn filter(&self) -> &KalmanFilter {
        &self.filter
    }
}

impl Controller for EstimatedStateFeedback {
    fn ny(&self) -> usize {
        self.filter.c.nrows()
    }

    fn nu(&self) -> usize {
        self.gain.nrows()
    }

    fn reset(&mut self) {
        self.filter.reset();
    }

    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        let n = self.gain.ncols();
        self.filter.correct(y);
        for i in 0..self.gain.nrows() {
            let mut s = 0.0;
            for k in 0..n {
                s -= self.gain[(i, k)] * self.filter.estimate[k];
            }
            u[i] = s;
        }
        self.filter.predict(u);
    }
}
