//! Recursive state estimation: the time-varying Kalman filter, the extended (EKF) and the
//! unscented (UKF) Kalman filter for any [`Dynamics`] with a measurement map. (The
//! steady-state filter and the controllers built on it are in [`crate::estimation`].)
//!
//! # Model
//! Discrete time, sample `k`, the input held over each sample (zero-order hold):
//!
//! ```text
//! x_{k+1} = Φ(t_k, x_k, u_k) + w_k,   w_k ~ N(0, Q)      (Q: per-sample covariance)
//! y_k     = h(t_k, x_k, u_k) + v_k,   v_k ~ N(0, R)
//! ```
//!
//! - [`KalmanFilter`]: `Φ = A_k x + B_k u`, `h = C_k x + D_k u` with matrices that may change
//!   every sample (the time-varying filter; with constant matrices it converges to the
//!   steady-state filter of [`kalman_filter`](crate::estimation::kalman_filter)).
//! - [`ExtendedKalmanFilter`] and [`UnscentedKalmanFilter`] on a [`SampledModel`]: `Φ` is
//!   `pendulab-sim`'s RK4 ([`rk4_step_slice`]) over the sample time in `substeps` equal steps,
//!   the input held; `h` picks measured states ([`Measurement::States`], the encoders) or is the
//!   system's output map ([`Measurement::Output`]).
//!
//! Every filter alternates a *prediction* `x̄ = E[x_{k+1}]`, `P̄` and an *update* with `y`:
//! innovation `ν = y − ŷ`, its covariance `S = P_yy + R`, gain `K = P_xy S⁻¹`,
//! `x̂ = x̄ + K ν`, `P = P̄ − K S Kᵀ` (symmetrised). The EKF takes `P_xy = P̄ Hᵀ`,
//! `P_yy = H P̄ Hᵀ` with `F = ∂Φ/∂x`, `H = ∂h/∂x` at the current estimate, by `pendulab-sim`'s
//! Richardson-extrapolated central differences ([`jacobians`]; exact up to rounding for a
//! linear system, so the EKF of a linear system is its Kalman filter). The UKF propagates
//! sigma points instead (below).
//!
//! # Unscented transform (Julier & Uhlmann 1997; scaled form, Wan & van der Merwe 2000)
//! For a mean `m` and covariance `P` of dimension `n`, with `λ = α² (n + κ) − n`, the `2n + 1`
//! sigma points are `X₀ = m`, `X_{±i} = m ± (√((n + λ) P))_i` (columns of the Cholesky
//! factor), with weights `W₀ᵐ = λ/(n + λ)`, `W₀ᶜ = W₀ᵐ + 1 − α² + β`,
//! `Wᵢᵐ = Wᵢᶜ = 1/(2(n + λ))`. `α` sets the spread, `β = 2` is optimal for Gaussian priors,
//! `κ ≥ 0` keeps the covariance positive semi-definite. Defaults ([`SigmaPoints::default`]):
//! `α = 1, β = 2, κ = 0` (`λ = 0`: the points at `±√n` standard deviations, all weights
//! non-negative). The mean and covariance of a linear map of the points are exact for any
//! `α, β, κ`, so the UKF of a linear system is its Kalman filter; sigma points are drawn
//! afresh from `(x̄, P̄)` for the update.
//!
//! # Encoder quantisation as measurement noise
//! An encoder of resolution `q` reports `q · round(x/q)`; when the signal moves over several
//! counts between samples the rounding error is close to uniform on `[−q/2, q/2]` and nearly
//! white, with variance `q²/12` (Widrow's quantisation noise model;
//! [`quantization_variance`]). That is the `R` entry of an encoder with no other noise. The
//! model is optimistic at rest (the error is then a constant, not noise) and the angles are
//! treated as plain numbers (means are arithmetic, not wrapped).
//!
//! # Consistency
//! [`Innovation::nis`] is the normalised innovation squared `νᵀ S⁻¹ ν` (χ² with `n_y` degrees
//! of freedom for a consistent filter); [`nees`] the normalised estimation error squared
//! `(x − x̂)ᵀ P⁻¹ (x − x̂)` against a known true state (χ² with `n_x`).

use crate::error::{ControlError, Result, check_matrix, check_param, check_vector};
use nalgebra::{DMatrix, DVector};
use pendulab_lti::Mat;
use pendulab_sim::{Dynamics, LinearizeOptions, Rk4Work, jacobians, rk4_step_slice};

/// The variance `q²/12` \[unit²\] of an encoder's rounding error for the resolution `q`
/// \[m or rad per count\] (uniform error on `[−q/2, q/2]`; see the module documentation).
///
/// # Errors
/// [`ControlError::InvalidParameter`] unless `q` is positive and finite.
pub fn quantization_variance(q: f64) -> Result<f64> {
    check_param("encoder resolution q", q, q > 0.0, "positive")?;
    Ok(q * q / 12.0)
}

/// `R = diag(q_i²/12)`: the measurement covariance of encoders of resolutions `q_i` with no
/// other noise.
///
/// # Errors
/// As [`quantization_variance`].
pub fn encoder_covariance(resolutions: &[f64]) -> Result<Mat> {
    let v: Vec<f64> = resolutions
        .iter()
        .map(|&q| quantization_variance(q))
        .collect::<Result<_>>()?;
    Ok(Mat::from_diagonal(&DVector::from_vec(v)))
}

/// The normalised estimation error squared `(x − x̂)ᵀ P⁻¹ (x − x̂)` (χ² with `n` degrees of
/// freedom for a consistent estimate).
///
/// # Errors
/// Shape and finiteness errors; [`ControlError::Singular`] if `P` is not positive definite.
pub fn nees(x_true: &[f64], x_hat: &[f64], p: &Mat) -> Result<f64> {
    let n = x_hat.len();
    check_vector("estimate x̂", x_hat, n)?;
    check_vector("true state x", x_true, n)?;
    check_matrix("covariance P", p, n, n)?;
    let e = DVector::from_iterator(n, x_true.iter().zip(x_hat).map(|(a, b)| a - b));
    let chol = cholesky("covariance P", p)?;
    Ok(e.dot(&chol.solve(&e)))
}

fn cholesky(what: &str, m: &Mat) -> Result<nalgebra::Cholesky<f64, nalgebra::Dyn>> {
    m.clone().cholesky().ok_or_else(|| ControlError::Singular {
        what: format!("{what} (not positive definite)"),
        value: 0.0,
    })
}

/// What one measurement update did.
#[derive(Debug, Clone, PartialEq)]
pub struct Innovation {
    /// `ν = y − ŷ`.
    pub residual: Vec<f64>,
    /// `S = P_yy + R`, the innovation covariance.
    pub covariance: Mat,
    /// The gain `K = P_xy S⁻¹` (`n_x × n_y`).
    pub gain: Mat,
    /// `νᵀ S⁻¹ ν` (normalised innovation squared).
    pub nis: f64,
}

/// The common update `x̂ = x̄ + K ν`, `P = P̄ − K S Kᵀ`, `K = P_xy S⁻¹`.
fn apply_update(
    x: &mut DVector<f64>,
    p: &mut Mat,
    pxy: &Mat,
    s: Mat,
    nu: DVector<f64>,
) -> Result<Innovation> {
    let chol = cholesky("innovation covariance S", &s)?;
    // K = P_xy S⁻¹ ⇔ Kᵀ = S⁻¹ P_xyᵀ (S symmetric).
    let k = chol.solve(&pxy.transpose()).transpose();
    let nis = nu.dot(&chol.solve(&nu));
    *x += &k * &nu;
    let updated = &*p - &k * &s * k.transpose();
    *p = (&updated + updated.transpose()) * 0.5;
    if let Some(v) = x.iter().chain(p.iter()).find(|v| !v.is_finite()) {
        return Err(ControlError::NonFinite {
            what: "filter estimate after the update".into(),
            index: 0,
            value: *v,
        });
    }
    Ok(Innovation {
        residual: nu.as_slice().to_vec(),
        covariance: s,
        gain: k,
        nis,
    })
}

/// Checks a measurement against its noise covariance and returns `y` as a vector.
fn check_measurement(y: &[f64], r: &Mat) -> Result<DVector<f64>> {
    let m = r.nrows();
    check_vector("measurement y", y, m)?;
    check_matrix("measurement noise R", r, m, m)?;
    Ok(DVector::from_column_slice(y))
}

/// An estimate `x̂` with its error covariance `P`, checked.
fn initial(x0: &[f64], p0: &Mat) -> Result<(DVector<f64>, Mat)> {
    let n = x0.len();
    check_vector("initial estimate x̂₀", x0, n)?;
    check_matrix("initial covariance P₀", p0, n, n)?;
    cholesky("initial covariance P₀", p0)?;
    Ok((DVector::from_column_slice(x0), p0.clone()))
}

/// The time-varying linear Kalman filter: `predict` with `(A_k, B_k, u_k, Q_k)`, `update` with
/// `(C_k, D_k, u_k, y_k, R_k)` (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct KalmanFilter {
    x: DVector<f64>,
    p: Mat,
}

impl KalmanFilter {
    /// A filter starting from `x̂₀` with covariance `P₀` (positive definite).
    ///
    /// # Errors
    /// Shape or finiteness errors; [`ControlError::Singular`] if `P₀` is not positive definite.
    pub fn new(x0: &[f64], p0: &Mat) -> Result<Self> {
        let (x, p) = initial(x0, p0)?;
        Ok(Self { x, p })
    }

    /// The current estimate `x̂`.
    pub fn state(&self) -> &[f64] {
        self.x.as_slice()
    }

    /// The current error covariance `P`.
    pub fn covariance(&self) -> &Mat {
        &self.p
    }

    /// `x̄ = A x̂ + B u`, `P̄ = A P Aᵀ + Q`.
    ///
    /// # Errors
    /// Shape and finiteness errors naming `A`, `B`, `u`, `Q`.
    pub fn predict(&mut self, a: &Mat, b: &Mat, u: &[f64], q: &Mat) -> Result<()> {
        let n = self.x.len();
        check_matrix("A", a, n, n)?;
        check_matrix("B", b, n, b.ncols())?;
        check_vector("input u", u, b.ncols())?;
        check_matrix("process noise Q", q, n, n)?;
        self.x = a * &self.x + b * DVector::from_column_slice(u);
        let p = a * &self.p * a.transpose() + q;
        self.p = (&p + p.transpose()) * 0.5;
        Ok(())
    }

    /// The update with `y = C x + D u + v`, `v ~ N(0, R)` (`d = None`: `D = 0`).
    ///
    /// # Errors
    /// Shape and finiteness errors; [`ControlError::Singular`] if `C P Cᵀ + R` is not positive
    /// definite.
    pub fn update(
        &mut self,
        c: &Mat,
        d: Option<(&Mat, &[f64])>,
        y: &[f64],
        r: &Mat,
    ) -> Result<Innovation> {
        let n = self.x.len();
        let yv = check_measurement(y, r)?;
        check_matrix("C", c, r.nrows(), n)?;
        let mut y_hat = c * &self.x;
        if let Some((d, u)) = d {
            check_matrix("D", d, r.nrows(), d.ncols())?;
            check_vector("input u", u, d.ncols())?;
            y_hat += d * DVector::from_column_slice(u);
        }
        let pxy = &self.p * c.transpose();
        let s = c * &pxy + r;
        apply_update(&mut self.x, &mut self.p, &pxy, s, yv - y_hat)
    }
}

/// What the nonlinear filters measure.
#[derive(Debug, Clone, PartialEq)]
pub enum Measurement {
    /// The listed states (encoders): `y = [x_i]`.
    States(Vec<usize>),
    /// The system's output map `y = h(t, x, u)` ([`Dynamics::output`]).
    Output,
}

/// A continuous [`Dynamics`] sampled for the nonlinear filters: `Φ` is RK4 over `ts` in
/// `substeps` steps with the input held, `h` is the [`Measurement`], `Q` and `R` the per-sample
/// process and measurement noise covariances.
#[derive(Debug, Clone)]
pub struct SampledModel<S> {
    sys: S,
    ts: f64,
    substeps: usize,
    measurement: Measurement,
    q: Mat,
    r: Mat,
}

impl<S: Dynamics> SampledModel<S> {
    /// The model of `sys` sampled at `ts` \[s\] with `substeps` RK4 steps per sample.
    ///
    /// # Errors
    /// [`ControlError::InvalidParameter`] for `ts` not positive or `substeps = 0`;
    /// [`ControlError::InconsistentSpec`] for a measured state out of range or
    /// [`Measurement::Output`] on a system without an output map; shape and finiteness
    /// errors for `Q` (`nx × nx`) and `R` (`ny × ny`).
    pub fn new(
        sys: S,
        ts: f64,
        substeps: usize,
        measurement: Measurement,
        q: &Mat,
        r: &Mat,
    ) -> Result<Self> {
        check_param("sample time ts", ts, ts > 0.0, "positive")?;
        check_param("RK4 substeps", substeps as f64, substeps >= 1, "at least 1")?;
        let nx = sys.nx();
        let ny = match &measurement {
            Measurement::States(idx) => {
                if let Some(&i) = idx.iter().find(|&&i| i >= nx) {
                    return Err(ControlError::InconsistentSpec {
                        what: "measurement".into(),
                        reason: format!("measured state {i} is out of range (nx = {nx})"),
                    });
                }
                idx.len()
            }
            Measurement::Output => sys.ny(),
        };
        if ny == 0 {
            return Err(ControlError::InconsistentSpec {
                what: "measurement".into(),
                reason: "nothing is measured (no state listed, or no output map)".into(),
            });
        }
        check_matrix("process noise Q", q, nx, nx)?;
        check_matrix("measurement noise R", r, ny, ny)?;
        Ok(Self {
            sys,
            ts,
            substeps,
            measurement,
            q: q.clone(),
            r: r.clone(),
        })
    }

    /// The sample time \[s\].
    pub fn ts(&self) -> f64 {
        self.ts
    }

    /// The number of measured values.
    pub fn ny(&self) -> usize {
        self.r.nrows()
    }

    /// The continuous system.
    pub fn system(&self) -> &S {
        &self.sys
    }

    /// `Φ(t, x, u)`: the state one sample later.
    pub fn propagate(&self, t: f64, x: &[f64], u: &[f64]) -> Vec<f64> {
        let mut xs = x.to_vec();
        let mut work = Rk4Work::new(xs.len());
        let h = self.ts / self.substeps as f64;
        for i in 0..self.substeps {
            rk4_step_slice(&self.sys, t + i as f64 * h, &mut xs, u, h, &mut work);
        }
        xs
    }

    /// `h(t, x, u)`: the noise-free measurement.
    pub fn measure(&self, t: f64, x: &[f64], u: &[f64]) -> Vec<f64> {
        match &self.measurement {
            Measurement::States(idx) => idx.iter().map(|&i| x[i]).collect(),
            Measurement::Output => {
                let mut y = vec![0.0; self.sys.ny()];
                self.sys.output(t, x, u, &mut y);
                y
            }
        }
    }

    fn check_input(&self, u: &[f64]) -> Result<()> {
        check_vector("input u", u, self.sys.nu())
    }
}

/// `Φ` and `h` of a [`SampledModel`] as a [`Dynamics`] (its "derivative" is `Φ`), so that
/// `pendulab-sim`'s finite differences give `F = ∂Φ/∂x` and `H = ∂h/∂x` in one call.
struct FlowMap<'a, S> {
    model: &'a SampledModel<S>,
}

impl<S: Dynamics> Dynamics for FlowMap<'_, S> {
    fn nx(&self) -> usize {
        self.model.sys.nx()
    }
    fn nu(&self) -> usize {
        self.model.sys.nu()
    }
    fn derivative(&self, t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        dx.copy_from_slice(&self.model.propagate(t, x, u));
    }
    fn ny(&self) -> usize {
        self.model.ny()
    }
    fn output(&self, t: f64, x: &[f64], u: &[f64], y: &mut [f64]) {
        y.copy_from_slice(&self.model.measure(t, x, u));
    }
}

fn non_finite(what: &str, v: &[f64]) -> Result<()> {
    crate::error::check_finite_slice(what, v)
}

/// A filter of a [`SampledModel`]: the EKF and the UKF.
pub trait NonlinearFilter {
    /// The current estimate `x̂`.
    fn state(&self) -> &[f64];
    /// The current error covariance `P`.
    fn covariance(&self) -> &Mat;
    /// The sample time of the model \[s\].
    fn ts(&self) -> f64;
    /// Prediction over one sample from `t` with the input `u` held.
    ///
    /// # Errors
    /// Shape or finiteness errors; [`ControlError::Sim`] for a non-finite model.
    fn predict(&mut self, t: f64, u: &[f64]) -> Result<()>;
    /// Update with the measurement `y` taken at `t` (with the input `u` acting then).
    ///
    /// # Errors
    /// Shape or finiteness errors; [`ControlError::Singular`] for a covariance that is not
    /// positive definite.
    fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<Innovation>;
}

/// The extended Kalman filter (see the module documentation).
#[derive(Debug, Clone)]
pub struct ExtendedKalmanFilter<S> {
    model: SampledModel<S>,
    x: DVector<f64>,
    p: Mat,
    differences: LinearizeOptions,
}

impl<S: Dynamics> ExtendedKalmanFilter<S> {
    /// An EKF of `model` starting from `x̂₀`, `P₀`; Jacobians by `pendulab-sim`'s default
    /// differences (Richardson, two extrapolations).
    ///
    /// # Errors
    /// Shape or finiteness errors; [`ControlError::Singular`] if `P₀` is not positive definite.
    pub fn new(model: SampledModel<S>, x0: &[f64], p0: &Mat) -> Result<Self> {
        check_vector("initial estimate x̂₀", x0, model.sys.nx())?;
        let (x, p) = initial(x0, p0)?;
        Ok(Self {
            model,
            x,
            p,
            differences: LinearizeOptions::default(),
        })
    }

    /// Uses `differences` for the Jacobians `F`, `H`.
    pub fn with_differences(mut self, differences: LinearizeOptions) -> Self {
        self.differences = differences;
        self
    }

    /// The model.
    pub fn model(&self) -> &SampledModel<S> {
        &self.model
    }
}

/// The [`NonlinearFilter`] getters of a filter on a [`SampledModel`] (fields `x`, `p`,
/// `model`): the estimate, its covariance and the model's sample time.
macro_rules! model_filter_getters {
    () => {
        fn state(&self) -> &[f64] {
            self.x.as_slice()
        }
        fn covariance(&self) -> &Mat {
            &self.p
        }
        fn ts(&self) -> f64 {
            self.model.ts
        }
    };
}

impl<S: Dynamics> NonlinearFilter for ExtendedKalmanFilter<S> {
    model_filter_getters!();

    fn predict(&mut self, t: f64, u: &[f64]) -> Result<()> {
        self.model.check_input(u)?;
        let flow = FlowMap { model: &self.model };
        let j = jacobians(&flow, t, self.x.as_slice(), u, &self.differences)?;
        let x = self.model.propagate(t, self.x.as_slice(), u);
        non_finite("predicted state", &x)?;
        self.x = DVector::from_vec(x);
        let p = &j.a * &self.p * j.a.transpose() + &self.model.q;
        self.p = (&p + p.transpose()) * 0.5;
        Ok(())
    }

    fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<Innovation> {
        self.model.check_input(u)?;
        let yv = check_measurement(y, &self.model.r)?;
        let flow = FlowMap { model: &self.model };
        let h = match &self.model.measurement {
            // Exact selection rows (no differences needed).
            Measurement::States(idx) => {
                let mut h = DMatrix::zeros(idx.len(), self.x.len());
                for (r, &i) in idx.iter().enumerate() {
                    h[(r, i)] = 1.0;
                }
                h
            }
            Measurement::Output => jacobians(&flow, t, self.x.as_slice(), u, &self.differences)?.c,
        };
        let y_hat = self.model.measure(t, self.x.as_slice(), u);
        non_finite("predicted measurement", &y_hat)?;
        let pxy = &self.p * h.transpose();
        let s = &h * &pxy + &self.model.r;
        apply_update(
            &mut self.x,
            &mut self.p,
            &pxy,
            s,
            yv - DVector::from_vec(y_hat),
        )
    }
}

/// The scaling parameters `α`, `β`, `κ` of the unscented transform (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SigmaPoints {
    /// Spread `α` (> 0; default 1).
    pub alpha: f64,
    /// Prior knowledge `β` (≥ 0; 2 for Gaussian priors, the default).
    pub beta: f64,
    /// Secondary scaling `κ` (`n + κ > 0`; default 0).
    pub kappa: f64,
}

impl Default for SigmaPoints {
    fn default() -> Self {
        Self {
            alpha: 1.0,
            beta: 2.0,
            kappa: 0.0,
        }
    }
}

impl SigmaPoints {
    /// `(n + λ, W₀ᵐ, W₀ᶜ, Wᵢ)` for dimension `n`.
    fn weights(&self, n: usize) -> (f64, f64, f64, f64) {
        let n = n as f64;
        let c = self.alpha * self.alpha * (n + self.kappa);
        let lambda = c - n;
        let w0m = lambda / c;
        (
            c,
            w0m,
            w0m + 1.0 - self.alpha * self.alpha + self.beta,
            0.5 / c,
        )
    }

    /// The `2n + 1` points of `(m, P)`.
    fn points(&self, m: &DVector<f64>, p: &Mat) -> Result<Vec<DVector<f64>>> {
        let n = m.len();
        let (c, ..) = self.weights(n);
        let l = cholesky("UKF covariance P", &(p * c))?.unpack();
        let mut pts = Vec::with_capacity(2 * n + 1);
        pts.push(m.clone());
        for i in 0..n {
            pts.push(m + l.column(i));
        }
        for i in 0..n {
            pts.push(m - l.column(i));
        }
        Ok(pts)
    }
}

/// The weighted mean of `pts` and the weighted deviations from it.
fn weighted_mean(pts: &[DVector<f64>], w0: f64, wi: f64) -> DVector<f64> {
    let mut mean = &pts[0] * w0;
    for p in &pts[1..] {
        mean += p * wi;
    }
    mean
}

/// `Σ W_i (a_i − ā)(b_i − b̄)ᵀ`.
fn weighted_cross(
    a: &[DVector<f64>],
    am: &DVector<f64>,
    b: &[DVector<f64>],
    bm: &DVector<f64>,
    w0: f64,
    wi: f64,
) -> Mat {
    let mut out = DMatrix::zeros(am.len(), bm.len());
    for (i, (ai, bi)) in a.iter().zip(b).enumerate() {
        let w = if i == 0 { w0 } else { wi };
        out += (ai - am) * (bi - bm).transpose() * w;
    }
    out
}

/// The unscented Kalman filter (see the module documentation).
#[derive(Debug, Clone)]
pub struct UnscentedKalmanFilter<S> {
    model: SampledModel<S>,
    x: DVector<f64>,
    p: Mat,
    sigma: SigmaPoints,
}

impl<S: Dynamics> UnscentedKalmanFilter<S> {
    /// A UKF of `model` starting from `x̂₀`, `P₀`, with the sigma-point scaling `sigma`.
    ///
    /// # Errors
    /// Shape or finiteness errors; [`ControlError::InvalidParameter`] for `α ≤ 0`, `β < 0` or
    /// `n + κ ≤ 0`; [`ControlError::Singular`] if `P₀` is not positive definite.
    pub fn new(model: SampledModel<S>, x0: &[f64], p0: &Mat, sigma: SigmaPoints) -> Result<Self> {
        check_vector("initial estimate x̂₀", x0, model.sys.nx())?;
        let n = x0.len() as f64;
        check_param("UKF alpha", sigma.alpha, sigma.alpha > 0.0, "positive")?;
        check_param("UKF beta", sigma.beta, sigma.beta >= 0.0, "non-negative")?;
        check_param(
            "UKF kappa",
            sigma.kappa,
            n + sigma.kappa > 0.0,
            "n + kappa > 0",
        )?;
        let (x, p) = initial(x0, p0)?;
        Ok(Self { model, x, p, sigma })
    }

    /// The model.
    pub fn model(&self) -> &SampledModel<S> {
        &self.model
    }
}

/// The unscented transform of an estimate through a map: the sigma points, their images,
/// and the images' weighted mean and covariance.
struct Unscented {
    points: Vec<DVector<f64>>,
    images: Vec<DVector<f64>>,
    mean: DVector<f64>,
    covariance: Mat,
}

impl<S: Dynamics> UnscentedKalmanFilter<S> {
    /// The current estimate's sigma points through `f`; a non-finite image is an error
    /// naming `what`.
    fn transform(&self, what: &str, f: impl Fn(&[f64]) -> Vec<f64>) -> Result<Unscented> {
        let (_, w0m, w0c, wi) = self.sigma.weights(self.x.len());
        let points = self.sigma.points(&self.x, &self.p)?;
        let images: Vec<DVector<f64>> = points
            .iter()
            .map(|p| DVector::from_vec(f(p.as_slice())))
            .collect();
        for m in &images {
            non_finite(what, m.as_slice())?;
        }
        let mean = weighted_mean(&images, w0m, wi);
        let covariance = weighted_cross(&images, &mean, &images, &mean, w0c, wi);
        Ok(Unscented {
            points,
            images,
            mean,
            covariance,
        })
    }
}

impl<S: Dynamics> NonlinearFilter for UnscentedKalmanFilter<S> {
    model_filter_getters!();

    fn predict(&mut self, t: f64, u: &[f64]) -> Result<()> {
        self.model.check_input(u)?;
        let moved = self.transform("propagated sigma point", |p| self.model.propagate(t, p, u))?;
        let p = moved.covariance + &self.model.q;
        self.x = moved.mean;
        self.p = (&p + p.transpose()) * 0.5;
        Ok(())
    }

    fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<Innovation> {
        self.model.check_input(u)?;
        let yv = check_measurement(y, &self.model.r)?;
        let ys = self.transform("measured sigma point", |p| self.model.measure(t, p, u))?;
        let s = ys.covariance + &self.model.r;
        let (_, _, w0c, wi) = self.sigma.weights(self.x.len());
        let pxy = weighted_cross(&ys.points, &self.x, &ys.images, &ys.mean, w0c, wi);
        apply_update(&mut self.x, &mut self.p, &pxy, s, yv - ys.mean)
    }
}

/// A filter run over a log: the estimates after each update and the innovations' NIS.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterRun {
    /// `x̂_k` after the update with `y_k` (one row per sample).
    pub states: Vec<Vec<f64>>,
    /// The diagonal of `P_k` (one row per sample).
    pub variances: Vec<Vec<f64>>,
    /// `ν_kᵀ S_k⁻¹ ν_k` per sample.
    pub nis: Vec<f64>,
}

/// Runs `filter` over a log sampled at the model's sample time: sample `k` at `t_k`, the
/// input `u_k` applied from `t_k` to `t_{k+1}`, the measurement `y_k` at `t_k`. The first
/// sample is an update only; every later one a prediction from `t_{k−1}` with `u_{k−1}`, then
/// the update with `y_k`.
///
/// # Errors
/// [`ControlError::DimensionMismatch`] if `t`, `u`, `y` differ in length; the filter's errors.
pub fn filter_log<F: NonlinearFilter + ?Sized>(
    filter: &mut F,
    t: &[f64],
    u: &[Vec<f64>],
    y: &[Vec<f64>],
) -> Result<FilterRun> {
    for (what, len) in [("inputs u", u.len()), ("measurements y", y.len())] {
        if len != t.len() {
            return Err(ControlError::DimensionMismatch {
                what: what.into(),
                expected: t.len(),
                found: len,
            });
        }
    }
    let mut run = FilterRun {
        states: Vec::with_capacity(t.len()),
        variances: Vec::with_capacity(t.len()),
        nis: Vec::with_capacity(t.len()),
    };
    for k in 0..t.len() {
        if k > 0 {
            filter.predict(t[k - 1], &u[k - 1])?;
        }
        let inn = filter.update(t[k], &u[k], &y[k])?;
        run.states.push(filter.state().to_vec());
        run.variances
            .push(filter.covariance().diagonal().iter().copied().collect());
        run.nis.push(inn.nis);
    }
    Ok(run)
}
