//! Step-response characteristics (MATLAB `stepinfo`, python-control `step_info`).
//!
//! # Definitions
//!
//! For samples `y(t₀), y(t₁), …` of a step response from the initial value `y_init` (default
//! 0) towards the final value `y_final` (default: the DC gain for a system, the last sample
//! for data), with `Δ = y_final − y_init` and `σ = sign Δ`, and the MATLAB defaults
//! `RiseTimeLimits = [0.1, 0.9]` and `SettlingTimeThreshold = 0.02`:
//!
//! - **rise time**: `t_hi − t_lo`, where `t_lo` (`t_hi`) is the first sample with
//!   `σ (y − y_init − 0.1 Δ) ≥ 0` (`0.9 Δ`);
//! - **settling time**: `t_s − t₀`, where `t_s` is the sample after the last one with
//!   `|y − y_final| ≥ 0.02 |Δ|` (`t₀` if there is none; `NaN` if the last sample is still
//!   outside the band: not settled within the data);
//! - **settling min / max**: the smallest and largest `y` from `t_hi` on;
//! - **overshoot** (percent): `100 · max(0, maxₖ σ (yₖ − y_final)) / |Δ|`;
//! - **undershoot** (percent): `100 · max(0, maxₖ −σ (yₖ − y_init)) / |Δ|`;
//! - **peak**: `maxₖ |yₖ|`, at the first sample attaining it (**peak time**, `t − t₀`).
//!
//! Times are read at samples, without interpolation (python-control's convention; MATLAB
//! interpolates linearly between samples, which differs by less than one sample period).
//! When `y_final` is not finite or `Δ = 0` (an unstable system, an integrator, a response
//! that does not move) every characteristic is `NaN` except the peak and its time.

use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::response::step;
use crate::state_space::StateSpace;

/// Options of [`stepinfo`] and [`stepinfo_data`] (MATLAB's names and defaults).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepInfoOptions {
    /// Fractions of `Δ` between which the rise time is measured (default `(0.1, 0.9)`).
    pub rise_time_limits: (f64, f64),
    /// Half-width of the settling band as a fraction of `|Δ|` (default `0.02`).
    pub settling_time_threshold: f64,
    /// The final value; `None`: the DC gain (system) or the last sample (data).
    pub y_final: Option<f64>,
    /// The initial value (default 0).
    pub y_init: f64,
}

impl Default for StepInfoOptions {
    fn default() -> Self {
        Self {
            rise_time_limits: (0.1, 0.9),
            settling_time_threshold: 0.02,
            y_final: None,
            y_init: 0.0,
        }
    }
}

/// Step-response characteristics (module documentation); times in seconds, overshoot and
/// undershoot in percent, values in the output's unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepInfo {
    /// Rise time (s).
    pub rise_time: f64,
    /// Settling time (s), `NaN` if not settled within the data.
    pub settling_time: f64,
    /// Smallest value after the rise.
    pub settling_min: f64,
    /// Largest value after the rise.
    pub settling_max: f64,
    /// Overshoot in percent of `|Δ|`.
    pub overshoot: f64,
    /// Undershoot in percent of `|Δ|`.
    pub undershoot: f64,
    /// Peak absolute value.
    pub peak: f64,
    /// Time of the peak (s, from `t₀`).
    pub peak_time: f64,
    /// The final value used.
    pub steady_state_value: f64,
}

/// Step-response characteristics of sampled data `y(t)` (module documentation).
///
/// # Errors
/// [`LtiError::DimensionMismatch`] if `t` and `y` differ in length; [`LtiError::InvalidArgument`]
/// for an empty record, non-increasing times, limits outside `0 ≤ lo < hi ≤ 1` or a
/// threshold outside `(0, 1)`; [`LtiError::NonFinite`] for a non-finite sample.
pub fn stepinfo_data(t: &[f64], y: &[f64], options: &StepInfoOptions) -> Result<StepInfo> {
    if t.len() != y.len() {
        return Err(LtiError::DimensionMismatch {
            what: "stepinfo_data: y (one sample per time)".into(),
            expected: (t.len(), 1),
            found: (y.len(), 1),
        });
    }
    if t.is_empty() {
        return Err(LtiError::InvalidArgument(
            "stepinfo_data: empty record".into(),
        ));
    }
    for (i, (&ti, &yi)) in t.iter().zip(y).enumerate() {
        for (what, v) in [("t", ti), ("y", yi)] {
            if !v.is_finite() {
                return Err(LtiError::NonFinite {
                    what: format!("stepinfo_data: {what}"),
                    row: i,
                    col: 0,
                    value: v,
                });
            }
        }
    }
    if let Some(i) = t.windows(2).position(|w| w[1] <= w[0]) {
        return Err(LtiError::InvalidArgument(format!(
            "stepinfo_data: times must increase, t[{}] = {} ≥ t[{}] = {}",
            i,
            t[i],
            i + 1,
            t[i + 1]
        )));
    }
    let (lo, hi) = options.rise_time_limits;
    if !(0.0 <= lo && lo < hi && hi <= 1.0) {
        return Err(LtiError::InvalidArgument(format!(
            "stepinfo: rise time limits must satisfy 0 ≤ lo < hi ≤ 1, got ({lo}, {hi})"
        )));
    }
    let thr = options.settling_time_threshold;
    if !(thr > 0.0 && thr < 1.0) {
        return Err(LtiError::InvalidArgument(format!(
            "stepinfo: settling time threshold must be in (0, 1), got {thr}"
        )));
    }
    let t0 = t[0];
    let (pk, peak) =
        y.iter().enumerate().fold(
            (0, 0.0),
            |(bi, bv), (i, v)| {
                if v.abs() > bv { (i, v.abs()) } else { (bi, bv) }
            },
        );
    let y_final = options.y_final.unwrap_or(y[y.len() - 1]);
    let y_init = options.y_init;
    let delta = y_final - y_init;
    let nan = f64::NAN;
    let mut info = StepInfo {
        rise_time: nan,
        settling_time: nan,
        settling_min: nan,
        settling_max: nan,
        overshoot: nan,
        undershoot: nan,
        peak,
        peak_time: t[pk] - t0,
        steady_state_value: y_final,
    };
    if !(y_final.is_finite() && y_init.is_finite()) || delta == 0.0 {
        return Ok(info);
    }
    let sg = delta.signum();
    let first = |frac: f64| {
        y.iter()
            .position(|&v| sg * (v - y_init - frac * delta) >= 0.0)
    };
    let (i_lo, i_hi) = (first(lo), first(hi));
    if let (Some(a), Some(b)) = (i_lo, i_hi) {
        info.rise_time = t[b] - t[a];
    }
    let band = thr * delta.abs();
    let settled = match y.iter().rposition(|&v| (v - y_final).abs() >= band) {
        None => Some(0),
        Some(k) if k + 1 < y.len() => Some(k + 1),
        Some(_) => None,
    };
    if let Some(k) = settled {
        info.settling_time = t[k] - t0;
    }
    if let Some(b) = i_hi {
        info.settling_min = y[b..].iter().copied().fold(f64::INFINITY, f64::min);
        info.settling_max = y[b..].iter().copied().fold(f64::NEG_INFINITY, f64::max);
    }
    let os = y.iter().map(|&v| sg * (v - y_final)).fold(0.0, f64::max);
    info.overshoot = 100.0 * os / delta.abs();
    let us = y.iter().map(|&v| -sg * (v - y_init)).fold(0.0, f64::max);
    info.undershoot = 100.0 * us / delta.abs();
    Ok(info)
}

/// Step-response characteristics of every channel of a system, `[output][input]`, from its
/// step response ([`step`]) on the time grid `t` (module documentation). `y_final` defaults
/// to the channel's DC gain; for a system that is not asymptotically stable it is `NaN`, and
/// so are the characteristics (MATLAB returns `NaN` there too).
///
/// # Errors
/// As [`step`] and [`stepinfo_data`].
pub fn stepinfo<D: TimeDomain>(
    sys: &StateSpace<D>,
    t: &[f64],
    options: &StepInfoOptions,
) -> Result<Vec<Vec<StepInfo>>> {
    let responses = step(sys, t)?;
    let dc = if sys.is_stable()? {
        Some(sys.dc_gain()?)
    } else {
        None
    };
    (0..sys.ny())
        .map(|i| {
            (0..sys.nu())
                .map(|j| {
                    let y_final = options
                        .y_final
                        .unwrap_or_else(|| dc.as_ref().map_or(f64::NAN, |g| g[(i, j)]));
                    let o = StepInfoOptions {
                        y_final: Some(y_final),
                        ..*options
                    };
                    stepinfo_data(responses[j].t(), responses[j].y_signal(i), &o)
                })
                .collect()
        })
        .collect()
}
