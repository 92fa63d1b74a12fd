//! Feature methods: parameters from a few read-outs of a response (book §2.2.1, §3.2.1).
//!
//! * **P-control step** ([`p_step`]; book `p1c321_cdip_id_cart`, `p1c332_adip_id_arm`). The
//!   drive `P(s) = b/(s(s + a))` under `v = k_P (r − y)` is the second-order loop
//!   `ω_n²/(s² + 2ζω_n s + ω_n²)` with `ω_n² = b k_P`, `2ζω_n = a`. From the peak time `T_p`
//!   and the overshoot `A = y_max − y_c` of a step to `y_c`:
//!   `γ = −ln(A/y_c)/T_p`, `δ = π/T_p`, `ω_n = √(γ² + δ²)`, `ζ = γ/ω_n`, `a = 2ζω_n`,
//!   `b = ω_n²/k_P`. Encoders make the top of the peak a plateau of equal samples: the peak
//!   time is the plateau's midpoint (as the book does).
//! * **Open-loop velocity steps** ([`velocity_step`], [`drive_from_velocity_steps`]; book
//!   `p1c221_id_cart`). A voltage step `u` gives `ẏ = K u (1 − e^{−t/T})`; `K` is the mean
//!   velocity over a late window divided by `u`, `T` the first time the velocity reaches
//!   `0.632 K u` (`1 − e^{−1}`); then `a = 1/T̄`, `b = K̄/T̄` over several steps.
//! * **Free oscillation** ([`free_oscillation`], [`pendulum_from_oscillation`]; book
//!   `p1c321_cdip_id_pend`, `p1c332_adip_id_pend`). Peaks of the decaying swing give the mean
//!   period `T̄` (peak to peak) and mean decay ratio `λ̄ = A_{i+1}/A_i`; then
//!   `γ = ln(1/λ̄)/T̄`, `δ = 2π/T̄`, `ω_n = √(γ² + δ²)`, `ζ = γ/ω_n`,
//!   `J = m g l/ω_n² − m l²`, `μ = 2ζω_n (J + m l²)`.
//!
//! **Why these are biased** (the book's own caveat, seed text): the step response of the real
//! cart is flattened near its peak by belt stretch, static and Coulomb friction, so the
//! plateau is wide and the overshoot small; Coulomb friction makes the free-oscillation decay
//! linear rather than geometric (the decay ratio then depends on the amplitude); and the
//! pendulum is nonlinear — at an amplitude `A` the period is longer than the small-swing one
//! by `(2/π) K(sin(A/2))` (complete elliptic integral), ≈ 2 % at 0.6 rad, which makes `J`
//! come out too large. [`PeriodCorrection::LargeAmplitude`] removes that last bias.
//!
//! **Peak detection** is robust to encoder steps: a cycle is delimited by downward crossings
//! of the rest level with hysteresis (the signal must rise above `+h` before a fall below `−h`
//! counts), so quantisation flicker around zero makes no spurious cycles; within a cycle the
//! peak is the maximum, timed at the midpoint of its plateau of equal samples.

use crate::error::{IdentError, Result, UNNAMED};

fn feature_error(what: String) -> IdentError {
    IdentError::FeatureNotFound {
        source_name: UNNAMED.into(),
        what,
    }
}

fn check_series(t: &[f64], y: &[f64], needed: usize) -> Result<()> {
    if t.len() != y.len() {
        return Err(IdentError::LengthMismatch {
            source_name: UNNAMED.into(),
            column: "signal".into(),
            expected: t.len(),
            found: y.len(),
        });
    }
    for (name, s) in [("t", t), ("signal", y)] {
        if let Some(k) = s.iter().position(|v| !v.is_finite()) {
            return Err(IdentError::NonFinite {
                source_name: UNNAMED.into(),
                column: name.into(),
                at: crate::error::SamplePos::index(k),
                value: s[k],
            });
        }
    }
    if let Some(k) = t.windows(2).position(|w| w[1] <= w[0]) {
        return Err(IdentError::TimeNotIncreasing {
            source_name: UNNAMED.into(),
            at: crate::error::SamplePos::index(k + 1),
            t: t[k + 1],
            previous: t[k],
        });
    }
    if t.len() < needed {
        return Err(IdentError::TooFewSamples {
            source_name: UNNAMED.into(),
            what: "the feature method".into(),
            needed,
            found: t.len(),
        });
    }
    Ok(())
}

fn finite_param(name: &str, v: f64, positive: bool) -> Result<()> {
    if v.is_finite() && (!positive || v > 0.0) {
        Ok(())
    } else {
        Err(IdentError::InvalidParameter {
            name: name.into(),
            value: v,
            reason: if positive {
                "must be finite and > 0".into()
            } else {
                "must be finite".into()
            },
        })
    }
}

/// A peak of a sampled signal: the maximum of a stretch and its plateau of equal samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// Peak time, s: midpoint of the plateau's first and last sample times.
    pub t: f64,
    /// Peak value (unit of the signal).
    pub value: f64,
    /// Index of the first sample of the plateau.
    pub first: usize,
    /// Index of the last sample of the plateau.
    pub last: usize,
}

/// The maximum of `y[lo..hi]` and the run of samples equal to it that starts there.
fn peak_in(t: &[f64], y: &[f64], lo: usize, hi: usize) -> Peak {
    let mut first = lo;
    for k in lo..hi {
        if y[k] > y[first] {
            first = k;
        }
    }
    let value = y[first];
    let mut last = first;
    while last + 1 < hi && y[last + 1] == value {
        last += 1;
    }
    Peak {
        t: 0.5 * (t[first] + t[last]),
        value,
        first,
        last,
    }
}

/// Options of [`p_step`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PStepOptions {
    /// Time of the reference step, s (book: 1 s into the recording).
    pub step_time: f64,
    /// Step target `y_c` (book: 0.2 m for the cart, 1 rad for the arm).
    pub target: f64,
    /// Proportional gain `k_P` of the loop `v = k_P (r − y)` (book: 10 cart, 3 arm), V per
    /// unit of `y`.
    pub k_p: f64,
}

/// Drive parameters from a P-control step response.
#[derive(Debug, Clone, PartialEq)]
pub struct PStepEstimate {
    /// The response peak (times are absolute, as in the data).
    pub peak: Peak,
    /// Peak time `T_p` measured from the step, s.
    pub tp: f64,
    /// Overshoot `A = y_max − y_c` (unit of `y`; the book's `Amax`).
    pub overshoot: f64,
    /// Relative overshoot `A/(y_c − y_0)` with `y_0` the value at the step.
    pub overshoot_ratio: f64,
    /// Decay rate `γ = −ln(A/(y_c − y_0))/T_p`, 1/s.
    pub gamma: f64,
    /// Damped frequency `δ = π/T_p`, rad/s.
    pub delta: f64,
    /// Natural frequency `ω_n`, rad/s.
    pub omega_n: f64,
    /// Damping ratio `ζ`.
    pub zeta: f64,
    /// `a = 2ζω_n`, 1/s.
    pub a: f64,
    /// `b = ω_n²/k_P`.
    pub b: f64,
}

/// Drive `a`, `b` from the step response `y(t)` of the P-control loop (see the module docs).
///
/// The step size is `y_c − y_0` with `y_0` the response at the step time (the book takes
/// `y_0 = 0`; the rig recordings start within an encoder step of zero, so the two agree).
///
/// # Errors
/// [`IdentError::InvalidParameter`] for non-finite options or `k_P ≤ 0`;
/// [`IdentError::WindowOutsideData`] if the step time is not inside the data;
/// [`IdentError::FeatureNotFound`] if the response does not overshoot the target (ζ ≥ 1: the
/// method does not apply), peaks at the end of the data (the record is too short), already
/// left its initial value at the step time, or starts moving so late after the step time
/// (more than a quarter of the peak time) that the step time is evidently wrong.
#[doc(alias = "p1c321_cdip_id_cart")]
#[doc(alias = "p1c332_adip_id_arm")]
pub fn p_step(t: &[f64], y: &[f64], opts: &PStepOptions) -> Result<PStepEstimate> {
    check_series(t, y, 3)?;
    finite_param("step time", opts.step_time, false)?;
    finite_param("target", opts.target, false)?;
    finite_param("k_P", opts.k_p, true)?;
    let n = t.len();
    let (first, last) = (t[0], t[n - 1]);
    if opts.step_time < first - 1e-9 || opts.step_time >= last {
        return Err(IdentError::WindowOutsideData {
            source_name: UNNAMED.into(),
            t0: opts.step_time,
            t1: last,
            data_start: first,
            data_end: last,
        });
    }
    let k0 = t.partition_point(|&v| v < opts.step_time - 1e-9);
    let y0 = y[k0];
    let step = opts.target - y0;
    if step == 0.0 {
        return Err(feature_error(format!(
            "the response is already at the target {} at the step time",
            opts.target
        )));
    }
    // Work with the response oriented upwards, so a negative step is handled alike.
    let s = step.signum();
    let yo: Vec<f64> = y.iter().map(|v| s * v).collect();
    let peak = peak_in(t, &yo, k0, n);
    if peak.last == n - 1 {
        return Err(feature_error(format!(
            "the response still rises at the end of the data (t = {last} s): no peak to read"
        )));
    }
    let overshoot = s * (peak.value - s * opts.target);
    if overshoot <= 0.0 {
        return Err(feature_error(format!(
            "the response does not overshoot the target {} (peak {} at t = {} s): a loop with ζ ≥ 1 \
             has no peak time or overshoot to read",
            opts.target,
            s * peak.value,
            peak.t
        )));
    }
    let tp = peak.t - opts.step_time;
    // Onset: first sample that has moved 5 % of the step from y0.
    let onset = (k0..n)
        .find(|&k| (y[k] - y0).abs() >= 0.05 * step.abs())
        .map(|k| t[k] - opts.step_time)
        .unwrap_or(f64::INFINITY);
    if onset > 0.25 * tp {
        return Err(feature_error(format!(
            "the response starts moving {onset:.4} s after the step time {} s but peaks {tp:.4} s \
             after it: the step time looks wrong",
            opts.step_time
        )));
    }
    let ratio = overshoot / step.abs();
    if ratio >= 1.0 {
        return Err(feature_error(format!(
            "overshoot {overshoot} is not smaller than the step {}: not a damped response",
            step.abs()
        )));
    }
    let gamma = -ratio.ln() / tp;
    let delta = std::f64::consts::PI / tp;
    let omega_n = gamma.hypot(delta);
    let zeta = gamma / omega_n;
    Ok(PStepEstimate {
        peak: Peak {
            value: s * peak.value,
            ..peak
        },
        tp,
        overshoot,
        overshoot_ratio: ratio,
        gamma,
        delta,
        omega_n,
        zeta,
        a: 2.0 * zeta * omega_n,
        b: omega_n * omega_n / opts.k_p,
    })
}

/// Options of [`velocity_step`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityStepOptions {
    /// Time of the voltage step, s.
    pub step_time: f64,
    /// Step size `u` (volts).
    pub input: f64,
    /// Window `[t_a, t_b]` after the step (s) over which the steady velocity is averaged
    /// (book: 1.4–1.5 s).
    pub gain_window: (f64, f64),
}

/// Gain and time constant read from one open-loop velocity step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityStep {
    /// Step size `u`.
    pub input: f64,
    /// Steady velocity over the gain window (unit of `y` per second).
    pub final_velocity: f64,
    /// Gain `K` = steady velocity / `u`.
    pub gain: f64,
    /// Time constant `T`: first time after the step at which the velocity reaches
    /// `(1 − e^{−1})·K u` ≈ `0.632 K u`, s.
    pub time_constant: f64,
}

/// Reads `K` and `T` from the position `y` (sampled every `ts` on the times `t`) after an
/// open-loop step of size `u` (book `cartident`): velocity by three-point differentiation,
/// `K` = mean velocity over the gain window / `u`, `T` = first time the velocity reaches
/// `(1 − e^{−1}) K u`.
///
/// # Errors
/// As [`crate::differentiate::three_point`]; [`IdentError::InvalidParameter`] for `u = 0` or a
/// bad window; [`IdentError::WindowOutsideData`] if the gain window is not inside the data;
/// [`IdentError::FeatureNotFound`] if the velocity never reaches the threshold.
#[doc(alias = "p1c221_id_cart")]
#[doc(alias = "cartident")]
pub fn velocity_step(t: &[f64], y: &[f64], opts: &VelocityStepOptions) -> Result<VelocityStep> {
    check_series(t, y, 3)?;
    finite_param("step time", opts.step_time, false)?;
    if !(opts.input.is_finite() && opts.input != 0.0) {
        return Err(IdentError::InvalidParameter {
            name: "input step u".into(),
            value: opts.input,
            reason: "must be finite and non-zero".into(),
        });
    }
    let (wa, wb) = opts.gain_window;
    if !(wa.is_finite() && wb.is_finite() && 0.0 <= wa && wa < wb) {
        return Err(IdentError::InvalidParameter {
            name: "gain window start".into(),
            value: wa,
            reason: format!("need 0 ≤ start < end, end = {wb}"),
        });
    }
    let n = t.len();
    let ts = (t[n - 1] - t[0]) / (n - 1) as f64;
    let (ta, tb) = (opts.step_time + wa, opts.step_time + wb);
    if ta < t[0] - 0.5 * ts || tb > t[n - 1] + 0.5 * ts {
        return Err(IdentError::WindowOutsideData {
            source_name: UNNAMED.into(),
            t0: ta,
            t1: tb,
            data_start: t[0],
            data_end: t[n - 1],
        });
    }
    let vel = crate::differentiate::three_point(y, ts)?;
    let eps = 1e-6 * ts;
    let lo = t.partition_point(|&v| v < ta - eps);
    let hi = t.partition_point(|&v| v <= tb + eps);
    let final_velocity = vel[lo..hi].iter().sum::<f64>() / (hi - lo) as f64;
    let gain = final_velocity / opts.input;
    let threshold = (1.0 - (-1.0f64).exp()) * final_velocity;
    let k0 = t.partition_point(|&v| v < opts.step_time - eps);
    let s = final_velocity.signum();
    let Some(k) = (k0..n).find(|&k| s * vel[k] >= s * threshold) else {
        return Err(feature_error(format!(
            "the velocity never reaches 63.2 % of its final value {final_velocity}"
        )));
    };
    Ok(VelocityStep {
        input: opts.input,
        final_velocity,
        gain,
        time_constant: t[k] - opts.step_time,
    })
}

/// Drive from several velocity steps.
#[derive(Debug, Clone, PartialEq)]
pub struct VelocityStepsEstimate {
    /// The individual steps.
    pub steps: Vec<VelocityStep>,
    /// Mean gain `K̄`.
    pub gain: f64,
    /// Mean time constant `T̄`, s.
    pub time_constant: f64,
    /// `a = 1/T̄`, 1/s.
    pub a: f64,
    /// `b = K̄/T̄`.
    pub b: f64,
}

/// `a = 1/T̄`, `b = K̄/T̄` from the mean gain and time constant of several steps (the book
/// averages four, 0.8–1.1 V; it also rounds the means to 1e-3, which is not done here).
///
/// # Errors
/// [`IdentError::TooFewSamples`] for no step; [`IdentError::Implausible`] for a mean time
/// constant that is not positive.
pub fn drive_from_velocity_steps(steps: &[VelocityStep]) -> Result<VelocityStepsEstimate> {
    if steps.is_empty() {
        return Err(IdentError::TooFewSamples {
            source_name: UNNAMED.into(),
            what: "velocity-step identification (steps)".into(),
            needed: 1,
            found: 0,
        });
    }
    let k = steps.iter().map(|s| s.gain).sum::<f64>() / steps.len() as f64;
    let tc = steps.iter().map(|s| s.time_constant).sum::<f64>() / steps.len() as f64;
    if tc <= 0.0 || tc.is_nan() {
        return Err(IdentError::Implausible {
            what: "mean time constant T".into(),
            value: tc,
            reason: "the velocity reached 63 % at or before the step".into(),
        });
    }
    Ok(VelocityStepsEstimate {
        steps: steps.to_vec(),
        gain: k,
        time_constant: tc,
        a: 1.0 / tc,
        b: k / tc,
    })
}

/// Options of [`free_oscillation`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OscillationOptions {
    /// Hysteresis `h` of the crossing detector (unit of the signal). `None` picks
    /// `max(2q, 0.02 max|y|)` with `q` the smallest non-zero change between successive samples
    /// (the encoder step on quantised data).
    pub hysteresis: Option<f64>,
}

/// Period and decay of a free oscillation about zero.
#[derive(Debug, Clone, PartialEq)]
pub struct Oscillation {
    /// The positive peaks, in time order.
    pub peaks: Vec<Peak>,
    /// Peak-to-peak periods `T_i`, s.
    pub periods: Vec<f64>,
    /// Decay ratios `λ_i = A_{i+1}/A_i`.
    pub decay_ratios: Vec<f64>,
    /// Mean period `T̄`, s.
    pub period: f64,
    /// Mean decay ratio `λ̄`.
    pub decay_ratio: f64,
    /// Standard error of `T̄` (sample standard deviation / √count); `None` for one period.
    pub period_std_error: Option<f64>,
    /// Standard error of `λ̄`; `None` for one period.
    pub decay_ratio_std_error: Option<f64>,
    /// The hysteresis used, unit of the signal.
    pub hysteresis: f64,
}

impl Oscillation {
    /// `(γ, δ, ω_n, ζ)` of the linear second-order model with this mean period and decay
    /// ratio: `γ = ln(1/λ̄)/T̄`, `δ = 2π/T̄`, `ω_n = √(γ² + δ²)`, `ζ = γ/ω_n`.
    pub fn second_order(&self) -> (f64, f64, f64, f64) {
        second_order(self.period, self.decay_ratio)
    }
}

fn second_order(period: f64, ratio: f64) -> (f64, f64, f64, f64) {
    let gamma = (1.0 / ratio).ln() / period;
    let delta = 2.0 * std::f64::consts::PI / period;
    let omega_n = gamma.hypot(delta);
    (gamma, delta, omega_n, gamma / omega_n)
}

fn mean_and_se(v: &[f64]) -> (f64, Option<f64>) {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    if v.len() < 2 {
        return (mean, None);
    }
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, Some((var / n).sqrt()))
}

/// Peaks, periods and decay ratios of a free oscillation `y(t)` about zero (the rest
/// position; rig angles are measured from it). See the module docs for the detector.
///
/// # Errors
/// [`IdentError::LengthMismatch`], [`IdentError::NonFinite`],
/// [`IdentError::TimeNotIncreasing`], [`IdentError::TooFewSamples`] for bad series;
/// [`IdentError::InvalidParameter`] for a negative hysteresis; [`IdentError::FeatureNotFound`]
/// if fewer than two full cycles' peaks are found (no period to measure) or a peak is not
/// positive.
#[doc(alias = "p1c321_cdip_id_pend")]
#[doc(alias = "p1c332_adip_id_pend")]
pub fn free_oscillation(t: &[f64], y: &[f64], opts: &OscillationOptions) -> Result<Oscillation> {
    check_series(t, y, 3)?;
    let h = match opts.hysteresis {
        Some(h) => {
            if !(h.is_finite() && h >= 0.0) {
                return Err(IdentError::InvalidParameter {
                    name: "hysteresis".into(),
                    value: h,
                    reason: "must be finite and ≥ 0".into(),
                });
            }
            h
        }
        None => {
            let q = y
                .windows(2)
                .map(|w| (w[1] - w[0]).abs())
                .filter(|d| *d > 0.0)
                .fold(f64::INFINITY, f64::min);
            let amp = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let q = if q.is_finite() { q } else { 0.0 };
            (2.0 * q).max(0.02 * amp)
        }
    };
    // Cycle boundaries: downward crossings (from above +h to below −h).
    let mut bounds = Vec::new();
    if y[0] < -h {
        bounds.push(0);
    }
    let mut armed = false;
    for (k, &v) in y.iter().enumerate() {
        if v > h {
            armed = true;
        } else if armed && v < -h {
            bounds.push(k);
            armed = false;
        }
    }
    let peaks: Vec<Peak> = bounds
        .windows(2)
        .map(|w| peak_in(t, y, w[0], w[1]))
        .collect();
    if peaks.len() < 2 {
        return Err(feature_error(format!(
            "found {} full oscillation cycle(s) (crossing hysteresis {h}); at least 2 peaks are \
             needed for a period",
            peaks.len()
        )));
    }
    if let Some(p) = peaks.iter().find(|p| p.value <= 0.0) {
        return Err(feature_error(format!(
            "peak at t = {} s is {} — not above the rest position 0",
            p.t, p.value
        )));
    }
    let periods: Vec<f64> = peaks.windows(2).map(|w| w[1].t - w[0].t).collect();
    let ratios: Vec<f64> = peaks.windows(2).map(|w| w[1].value / w[0].value).collect();
    let (period, period_se) = mean_and_se(&periods);
    let (ratio, ratio_se) = mean_and_se(&ratios);
    Ok(Oscillation {
        peaks,
        periods,
        decay_ratios: ratios,
        period,
        decay_ratio: ratio,
        period_std_error: period_se,
        decay_ratio_std_error: ratio_se,
        hysteresis: h,
    })
}

/// Whether the pendulum's large-amplitude period lengthening is corrected.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PeriodCorrection {
    /// The book: periods taken as those of the linearised pendulum.
    #[default]
    None,
    /// Each period is divided by `(2/π) K(sin(Ā/2))` (exact period of the undamped pendulum
    /// at amplitude `Ā`, the geometric mean of the cycle's two peaks, relative to the small-
    /// swing period; `K` the complete elliptic integral of the first kind).
    LargeAmplitude,
}

/// Complete elliptic integral of the first kind `K(k) = ∫₀^{π/2} dθ/√(1 − k² sin²θ)` by the
/// arithmetic–geometric mean, `K(k) = π/(2 AGM(1, √(1 − k²)))`, for `0 ≤ k < 1`.
pub fn elliptic_k(k: f64) -> f64 {
    let mut a = 1.0f64;
    let mut b = (1.0 - k * k).sqrt();
    for _ in 0..64 {
        if (a - b).abs() <= 1e-16 * a {
            break;
        }
        let an = 0.5 * (a + b);
        b = (a * b).sqrt();
        a = an;
    }
    std::f64::consts::PI / (2.0 * a)
}

/// Pendulum parameters from a free oscillation.
#[derive(Debug, Clone, PartialEq)]
pub struct PendulumFeatures {
    /// Mean period used, s (corrected if asked).
    pub period: f64,
    /// Mean decay ratio used.
    pub decay_ratio: f64,
    /// Natural frequency `ω_n`, rad/s.
    pub omega_n: f64,
    /// Damping ratio `ζ`.
    pub zeta: f64,
    /// Moment of inertia about the centre of mass `J = m g l/ω_n² − m l²`, kg m².
    pub j: f64,
    /// Viscous friction `μ = 2ζω_n (J + m l²)`, N m s/rad.
    pub mu: f64,
    /// Standard errors of `J` and `μ` propagated (first order) from those of the mean period
    /// and decay ratio; `None` with a single period.
    pub std_errors: Option<(f64, f64)>,
}

/// `J`, `μ` of a pendulum of mass `m` (kg) with its centre of mass `l` (m) from the pivot, from
/// its free oscillation under gravity `g` (m/s²).
///
/// # Errors
/// [`IdentError::InvalidParameter`] for non-positive constants; [`IdentError::Implausible`]
/// if the decay ratio is not in (0, 1] (the swing grows, or peaks have the wrong sign) or the
/// period implies `J ≤ 0` (the constants do not fit the measured period).
pub fn pendulum_from_oscillation(
    osc: &Oscillation,
    m: f64,
    l: f64,
    g: f64,
    correction: PeriodCorrection,
) -> Result<PendulumFeatures> {
    finite_param("mass m", m, true)?;
    finite_param("length l", l, true)?;
    finite_param("g", g, true)?;
    let period = match correction {
        PeriodCorrection::None => osc.period,
        PeriodCorrection::LargeAmplitude => {
            let corrected: Vec<f64> = osc
                .peaks
                .windows(2)
                .zip(&osc.periods)
                .map(|(w, t)| {
                    let amp = (w[0].value * w[1].value).sqrt();
                    let k = (0.5 * amp).sin().min(1.0 - 1e-12);
                    t / (2.0 / std::f64::consts::PI * elliptic_k(k))
                })
                .collect();
            corrected.iter().sum::<f64>() / corrected.len() as f64
        }
    };
    let ratio = osc.decay_ratio;
    if !(ratio > 0.0 && ratio <= 1.0) {
        return Err(IdentError::Implausible {
            what: "mean decay ratio".into(),
            value: ratio,
            reason: "a damped pendulum's peaks shrink (0 < λ ≤ 1)".into(),
        });
    }
    let params = |period: f64, ratio: f64| {
        let (_, _, wn, zeta) = second_order(period, ratio);
        let j = m * g * l / (wn * wn) - m * l * l;
        let mu = 2.0 * zeta * wn * (j + m * l * l);
        (wn, zeta, j, mu)
    };
    let (omega_n, zeta, j, mu) = params(period, ratio);
    if j <= 0.0 || j.is_nan() {
        return Err(IdentError::Implausible {
            what: "J".into(),
            value: j,
            reason: format!(
                "the period {period} s is shorter than a point mass's 2π√(l/g) = {} s: check m, l, g",
                2.0 * std::f64::consts::PI * (l / g).sqrt()
            ),
        });
    }
    let std_errors = match (osc.period_std_error, osc.decay_ratio_std_error) {
        (Some(se_t), Some(se_l)) => {
            // Central differences of (J, μ) in T̄ and λ̄.
            let ht = 1e-6 * period;
            let hl = 1e-6 * ratio.min(1.0 - ratio).max(1e-9);
            let (_, _, jtp, mtp) = params(period + ht, ratio);
            let (_, _, jtm, mtm) = params(period - ht, ratio);
            let (_, _, jlp, mlp) = params(period, ratio + hl);
            let (_, _, jlm, mlm) = params(period, ratio - hl);
            let (djt, dmt) = ((jtp - jtm) / (2.0 * ht), (mtp - mtm) / (2.0 * ht));
            let (djl, dml) = ((jlp - jlm) / (2.0 * hl), (mlp - mlm) / (2.0 * hl));
            Some((
                (djt * se_t).hypot(djl * se_l),
                (dmt * se_t).hypot(dml * se_l),
            ))
        }
        _ => None,
    };
    Ok(PendulumFeatures {
        period,
        decay_ratio: ratio,
        omega_n,
        zeta,
        j,
        mu,
        std_errors,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elliptic_k_known_values() {
        // K(0) = π/2; K(1/√2) = Γ(1/4)²/(4√π) = 1.854074677301372 (Abramowitz–Stegun 17.3).
        assert!((elliptic_k(0.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!(
            (elliptic_k(std::f64::consts::FRAC_1_SQRT_2) - 1.854_074_677_301_372).abs() < 1e-14
        );
    }

    #[test]
    fn p_step_on_exact_second_order_response() {
        // y = y_c (1 − e^{−ζω t}(cos ω_d t + ζ/√(1−ζ²) sin ω_d t)): peak at π/ω_d with overshoot
        // y_c e^{−ζπ/√(1−ζ²)}; sampled at 1 µs so the peak sample is within 0.5 µs of the peak.
        let (a, b, kp, yc): (f64, f64, f64, f64) = (6.25, 4.36, 10.0, 0.2);
        let wn: f64 = (b * kp).sqrt();
        let zeta = a / (2.0 * wn);
        let wd = wn * (1.0 - zeta * zeta).sqrt();
        let ts = 1e-6;
        let t: Vec<f64> = (0..1_200_000).map(|k| k as f64 * ts).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|&t| {
                let s = t - 0.1;
                if s <= 0.0 {
                    0.0
                } else {
                    yc * (1.0
                        - (-zeta * wn * s).exp()
                            * ((wd * s).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * s).sin()))
                }
            })
            .collect();
        let e = p_step(
            &t,
            &y,
            &PStepOptions {
                step_time: 0.1,
                target: yc,
                k_p: kp,
            },
        )
        .unwrap();
        // Peak time to ±0.5 µs of 0.54 s (~1e-6 relative), a flat maximum so the overshoot is
        // exact to ~1e-12: a and b to 1e-5.
        assert!((e.tp - std::f64::consts::PI / wd).abs() < 1e-6);
        assert!((e.a - a).abs() < 1e-5 * a, "{}", e.a);
        assert!((e.b - b).abs() < 1e-5 * b, "{}", e.b);
    }
}
