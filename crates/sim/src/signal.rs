//! Test signals: step, ramp, pulse, pulse train, sine, piecewise-constant and piecewise-linear
//! signals, and their sums; and the [`Input`] trait that turns them (or a closure) into the
//! input vector `u(t)` of an open-loop simulation.
//!
//! A [`Signal`] is a scalar function of time `s(t)` (units of whatever it drives: volts,
//! metres, radians). It is a validated sum of elementary terms, evaluated without allocation.
//!
//! **Switch instants.** Discontinuous terms are right-continuous (a step at `τ` has its new
//! value at `t = τ`). Sampled loops evaluate signals at `t_k = t_0 + k·ts`, which can fall a
//! rounding error short of a switch placed on the grid (`1000 · 0.001` need not equal `1.0`
//! in every case), so an instant within `1e-12 · max(1, |τ|)` s before `τ` counts as reaching
//! it (and, for a pulse train, within `1e-9` periods of an edge).

use crate::error::{Result, SimError, check_finite, check_len, check_positive};

/// Relative snapping tolerance for switch instants (see the module documentation).
const INSTANT_SNAP: f64 = 1e-12;
/// Snapping tolerance of pulse-train edges, in periods.
const PERIOD_SNAP: f64 = 1e-9;

/// `true` once `t` has reached the switch instant `tau` (with the documented snapping).
#[inline]
pub(crate) fn reached(t: f64, tau: f64) -> bool {
    t >= tau - INSTANT_SNAP * tau.abs().max(1.0)
}

#[derive(Debug, Clone, PartialEq)]
enum Term {
    Constant(f64),
    Step {
        time: f64,
        amplitude: f64,
    },
    Ramp {
        start: f64,
        slope: f64,
    },
    PulseTrain {
        start: f64,
        period: f64,
        width: f64,
        amplitude: f64,
    },
    Sine {
        amplitude: f64,
        omega: f64,
        phase: f64,
    },
    PiecewiseConstant {
        times: Vec<f64>,
        values: Vec<f64>,
    },
    PiecewiseLinear {
        times: Vec<f64>,
        values: Vec<f64>,
    },
}

impl Term {
    #[inline]
    fn value(&self, t: f64) -> f64 {
        match self {
            Term::Constant(c) => *c,
            Term::Step { time, amplitude } => {
                if reached(t, *time) {
                    *amplitude
                } else {
                    0.0
                }
            }
            Term::Ramp { start, slope } => {
                if t > *start {
                    slope * (t - start)
                } else {
                    0.0
                }
            }
            Term::PulseTrain {
                start,
                period,
                width,
                amplitude,
            } => {
                let rel = (t - start) / period;
                if rel < -PERIOD_SNAP {
                    return 0.0;
                }
                let k = (rel + PERIOD_SNAP).floor();
                let phase = rel - k;
                if phase < width / period - PERIOD_SNAP {
                    *amplitude
                } else {
                    0.0
                }
            }
            Term::Sine {
                amplitude,
                omega,
                phase,
            } => amplitude * (omega * t + phase).sin(),
            Term::PiecewiseConstant { times, values } => {
                // Number of breakpoints reached: index of the active value + 1.
                let n = times.partition_point(|&tau| reached(t, tau));
                if n == 0 { 0.0 } else { values[n - 1] }
            }
            Term::PiecewiseLinear { times, values } => {
                let n = times.len();
                if t <= times[0] {
                    return values[0];
                }
                if t >= times[n - 1] {
                    return values[n - 1];
                }
                // times[i] <= t < times[i + 1].
                let i = times.partition_point(|&tau| tau <= t) - 1;
                let (t0, t1) = (times[i], times[i + 1]);
                let w = (t - t0) / (t1 - t0);
                values[i] + w * (values[i + 1] - values[i])
            }
        }
    }

    fn scale(&mut self, k: f64) {
        match self {
            Term::Constant(c) => *c *= k,
            Term::Step { amplitude, .. } => *amplitude *= k,
            Term::Ramp { slope, .. } => *slope *= k,
            Term::PulseTrain { amplitude, .. } => *amplitude *= k,
            Term::Sine { amplitude, .. } => *amplitude *= k,
            Term::PiecewiseConstant { values, .. } | Term::PiecewiseLinear { values, .. } => {
                values.iter_mut().for_each(|v| *v *= k)
            }
        }
    }
}

/// A scalar signal `s(t)`: a sum of elementary terms.
///
/// Build one with the constructors and add them with `+` (or [`Signal::sum`]); scale with
/// `*` by an `f64`. Every constructor validates its parameters.
///
/// ```
/// use pendulab_sim::Signal;
/// # fn main() -> Result<(), pendulab_sim::SimError> {
/// // A 0.2 m step at t = 1 s plus a 1 Hz, 0.01 m sine.
/// let r = Signal::step(1.0, 0.2)? + Signal::sine(0.01, 2.0 * std::f64::consts::PI, 0.0)?;
/// assert_eq!(r.value(0.5), 0.01 * (std::f64::consts::PI).sin());
/// # Ok(()) }
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Signal {
    terms: Vec<Term>,
}

impl Signal {
    /// The zero signal `s(t) = 0`.
    pub fn zero() -> Self {
        Self { terms: Vec::new() }
    }

    /// A constant `s(t) = c`.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] if `c` is not finite.
    pub fn constant(c: f64) -> Result<Self> {
        check_finite("constant value", c)?;
        Ok(Self::from(Term::Constant(c)))
    }

    /// A step `s(t) = amplitude` for `t ≥ time`, `0` before.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] for non-finite parameters.
    pub fn step(time: f64, amplitude: f64) -> Result<Self> {
        check_finite("step time", time)?;
        check_finite("step amplitude", amplitude)?;
        Ok(Self::from(Term::Step { time, amplitude }))
    }

    /// A ramp `s(t) = slope · (t − start)` for `t > start`, `0` before (units per second).
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] for non-finite parameters.
    pub fn ramp(start: f64, slope: f64) -> Result<Self> {
        check_finite("ramp start", start)?;
        check_finite("ramp slope", slope)?;
        Ok(Self::from(Term::Ramp { start, slope }))
    }

    /// One rectangular pulse: `amplitude` on `[start, start + width)`, `0` elsewhere.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] for non-finite parameters or `width ≤ 0`.
    pub fn pulse(start: f64, width: f64, amplitude: f64) -> Result<Self> {
        check_finite("pulse start", start)?;
        check_positive("pulse width", width)?;
        check_finite("pulse amplitude", amplitude)?;
        Self::piecewise_constant(&[start, start + width], &[amplitude, 0.0])
    }

    /// A pulse train (Simulink's Pulse Generator): `amplitude` on
    /// `[start + k·period, start + k·period + width)` for `k = 0, 1, …`, `0` elsewhere and
    /// before `start`.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] unless `period > 0`, `0 < width < period` and all are
    /// finite.
    pub fn pulse_train(start: f64, period: f64, width: f64, amplitude: f64) -> Result<Self> {
        check_finite("pulse train start", start)?;
        check_positive("pulse train period", period)?;
        check_positive("pulse train width", width)?;
        check_finite("pulse train amplitude", amplitude)?;
        if width >= period {
            return Err(SimError::InvalidParameter {
                what: "pulse train width".into(),
                value: width,
                requirement: "must be shorter than the period",
            });
        }
        Ok(Self::from(Term::PulseTrain {
            start,
            period,
            width,
            amplitude,
        }))
    }

    /// A sinusoid `s(t) = amplitude · sin(omega · t + phase)` (`omega` in rad/s, `phase` in
    /// rad).
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] for non-finite parameters.
    pub fn sine(amplitude: f64, omega: f64, phase: f64) -> Result<Self> {
        check_finite("sine amplitude", amplitude)?;
        check_finite("sine angular frequency", omega)?;
        check_finite("sine phase", phase)?;
        Ok(Self::from(Term::Sine {
            amplitude,
            omega,
            phase,
        }))
    }

    /// A piecewise-constant signal: `0` before `times[0]`, `values[i]` on
    /// `[times[i], times[i+1])`, the last value after the last time.
    ///
    /// # Errors
    /// [`SimError::DimensionMismatch`] if the lengths differ; [`SimError::InvalidArgument`]
    /// if there are no breakpoints or the times are not finite and strictly increasing;
    /// [`SimError::InvalidParameter`] for non-finite values.
    pub fn piecewise_constant(times: &[f64], values: &[f64]) -> Result<Self> {
        check_breakpoints(times, values)?;
        Ok(Self::from(Term::PiecewiseConstant {
            times: times.to_vec(),
            values: values.to_vec(),
        }))
    }

    /// A piecewise-linear signal through `(times[i], values[i])`, held at the first value
    /// before `times[0]` and at the last after the last time (MATLAB `interp1` with clamped
    /// ends).
    ///
    /// # Errors
    /// As [`Signal::piecewise_constant`].
    pub fn piecewise_linear(times: &[f64], values: &[f64]) -> Result<Self> {
        check_breakpoints(times, values)?;
        Ok(Self::from(Term::PiecewiseLinear {
            times: times.to_vec(),
            values: values.to_vec(),
        }))
    }

    /// The sum of several signals.
    pub fn sum<I: IntoIterator<Item = Signal>>(signals: I) -> Self {
        let mut terms = Vec::new();
        for s in signals {
            terms.extend(s.terms);
        }
        Self { terms }
    }

    /// The signal multiplied by `k`.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] if `k` is not finite.
    pub fn scaled(mut self, k: f64) -> Result<Self> {
        check_finite("signal scale", k)?;
        self.terms.iter_mut().for_each(|term| term.scale(k));
        Ok(self)
    }

    /// The value `s(t)`.
    #[inline]
    pub fn value(&self, t: f64) -> f64 {
        self.terms.iter().map(|term| term.value(t)).sum()
    }
}

impl From<Term> for Signal {
    fn from(term: Term) -> Self {
        Self { terms: vec![term] }
    }
}

impl std::ops::Add for Signal {
    type Output = Signal;
    fn add(mut self, rhs: Signal) -> Signal {
        self.terms.extend(rhs.terms);
        self
    }
}

impl std::ops::Neg for Signal {
    type Output = Signal;
    fn neg(mut self) -> Signal {
        self.terms.iter_mut().for_each(|term| term.scale(-1.0));
        self
    }
}

impl std::ops::Sub for Signal {
    type Output = Signal;
    fn sub(self, rhs: Signal) -> Signal {
        self + (-rhs)
    }
}

fn check_breakpoints(times: &[f64], values: &[f64]) -> Result<()> {
    check_len(
        "signal values (one per breakpoint)",
        values.len(),
        times.len(),
    )?;
    if times.is_empty() {
        return Err(SimError::InvalidArgument(
            "a piecewise signal needs at least one breakpoint".into(),
        ));
    }
    if let Some(i) = times.iter().position(|t| !t.is_finite()) {
        return Err(SimError::InvalidArgument(format!(
            "breakpoint {i} is not finite ({})",
            times[i]
        )));
    }
    if let Some(i) = times.windows(2).position(|w| w[1] <= w[0]) {
        return Err(SimError::InvalidArgument(format!(
            "breakpoints must increase strictly: times[{i}] = {} >= times[{}] = {}",
            times[i],
            i + 1,
            times[i + 1]
        )));
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(SimError::InvalidParameter {
            what: format!("signal value {i}"),
            value: values[i],
            requirement: "must be finite",
        });
    }
    Ok(())
}

/// An input vector `u(t)` for open-loop simulation.
///
/// Implemented by a single [`Signal`] (one input), by slices and vectors of signals (one per
/// input), by [`ZeroInput`], and by [`FnInput`] (any closure).
pub trait Input {
    /// Number of inputs.
    fn nu(&self) -> usize;
    /// Writes `u(t)` into `u` (`u.len() == self.nu()`).
    fn eval(&self, t: f64, u: &mut [f64]);
}

impl Input for Signal {
    fn nu(&self) -> usize {
        1
    }
    #[inline]
    fn eval(&self, t: f64, u: &mut [f64]) {
        u[0] = self.value(t);
    }
}

impl Input for [Signal] {
    fn nu(&self) -> usize {
        self.len()
    }
    #[inline]
    fn eval(&self, t: f64, u: &mut [f64]) {
        for (ui, s) in u.iter_mut().zip(self) {
            *ui = s.value(t);
        }
    }
}

impl Input for Vec<Signal> {
    fn nu(&self) -> usize {
        self.len()
    }
    #[inline]
    fn eval(&self, t: f64, u: &mut [f64]) {
        self.as_slice().eval(t, u)
    }
}

impl<T: Input + ?Sized> Input for &T {
    fn nu(&self) -> usize {
        (**self).nu()
    }
    #[inline]
    fn eval(&self, t: f64, u: &mut [f64]) {
        (**self).eval(t, u)
    }
}

/// The zero input of a given width.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ZeroInput(pub usize);

impl Input for ZeroInput {
    fn nu(&self) -> usize {
        self.0
    }
    #[inline]
    fn eval(&self, _t: f64, u: &mut [f64]) {
        u.fill(0.0);
    }
}

/// An input given by a closure `f(t, u)` writing `nu` values.
#[derive(Clone, Copy)]
pub struct FnInput<F> {
    nu: usize,
    f: F,
}

impl<F: Fn(f64, &mut [f64])> FnInput<F> {
    /// Wraps `f`, which writes `u(t)` into a slice of length `nu`.
    pub fn new(nu: usize, f: F) -> Self {
        Self { nu, f }
    }
}

impl<F> std::fmt::Debug for FnInput<F> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FnInput").field("nu", &self.nu).finish()
    }
}

impl<F: Fn(f64, &mut [f64])> Input for FnInput<F> {
    fn nu(&self) -> usize {
        self.nu
    }
    #[inline]
    fn eval(&self, t: f64, u: &mut [f64]) {
        (self.f)(t, u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_is_right_continuous_and_snaps_on_grid() {
        let s = Signal::step(1.0, 2.0).unwrap();
        assert_eq!(s.value(0.999), 0.0);
        assert_eq!(s.value(1.0), 2.0);
        // A grid instant a rounding error short of the step counts as reaching it.
        assert_eq!(s.value(1.0 - 4.0 * f64::EPSILON), 2.0);
        // ...but not a genuinely earlier instant (1 ns before).
        assert_eq!(s.value(1.0 - 1e-9), 0.0);
    }

    #[test]
    fn pulse_train_edges() {
        let p = Signal::pulse_train(0.5, 1.0, 0.25, 3.0).unwrap();
        let cases = [
            (0.0, 0.0),
            (0.5, 3.0),
            (0.74, 3.0),
            (0.75, 0.0),
            (1.49, 0.0),
            (1.5, 3.0),
            (100.5, 3.0),
            (100.75, 0.0),
        ];
        for (t, v) in cases {
            assert_eq!(p.value(t), v, "t = {t}");
        }
        assert!(Signal::pulse_train(0.0, 1.0, 1.0, 1.0).is_err());
        assert!(Signal::pulse_train(0.0, 0.0, 0.5, 1.0).is_err());
    }

    #[test]
    fn piecewise_signals() {
        let c = Signal::piecewise_constant(&[1.0, 2.0, 3.0], &[5.0, -1.0, 0.5]).unwrap();
        assert_eq!(c.value(0.0), 0.0);
        assert_eq!(c.value(1.0), 5.0);
        assert_eq!(c.value(2.5), -1.0);
        assert_eq!(c.value(10.0), 0.5);
        let l = Signal::piecewise_linear(&[0.0, 1.0, 3.0], &[0.0, 2.0, -2.0]).unwrap();
        assert_eq!(l.value(-1.0), 0.0);
        assert_eq!(l.value(0.5), 1.0);
        assert_eq!(l.value(2.0), 0.0);
        assert_eq!(l.value(5.0), -2.0);
        assert!(Signal::piecewise_linear(&[0.0, 0.0], &[1.0, 2.0]).is_err());
        assert!(Signal::piecewise_linear(&[0.0, 1.0], &[1.0]).is_err());
        assert!(Signal::piecewise_linear(&[], &[]).is_err());
        assert!(Signal::piecewise_constant(&[f64::NAN], &[1.0]).is_err());
    }

    #[test]
    fn sums_scaling_and_ramp() {
        let s = (Signal::ramp(1.0, 2.0).unwrap() - Signal::constant(1.0).unwrap())
            .scaled(3.0)
            .unwrap();
        assert_eq!(s.value(0.0), -3.0);
        assert_eq!(s.value(2.0), 3.0 * (2.0 - 1.0));
        let p = Signal::pulse(1.0, 0.5, 4.0).unwrap();
        assert_eq!(p.value(1.2), 4.0);
        assert_eq!(p.value(1.5), 0.0);
        let w = Signal::sine(2.0, 3.0, 0.5).unwrap();
        assert_eq!(w.value(0.7), 2.0 * (3.0f64 * 0.7 + 0.5).sin());
        assert!(Signal::sine(f64::INFINITY, 1.0, 0.0).is_err());
        assert_eq!(
            Signal::sum([w.clone(), p.clone()]).value(1.2),
            w.value(1.2) + 4.0
        );
    }
}
