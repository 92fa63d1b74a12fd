//! Monitors: per-sample observers of a sampled-data run that summarise it without storing it
//! and may stop it (a safety limit). Batch runs use them to classify thousands of runs.
//!
//! A [`Monitor`] sees, at `t₀` and at every sample instant, the true state, the measurement
//! and the plant input just computed. Ready-made: [`MaxAbs`], [`StayWithin`],
//! [`SettlingTime`], [`FnMonitor`] (a closure); `()` observes nothing; a pair `(A, B)`
//! feeds both and stops when either does.

/// Whether a run goes on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    /// Keep integrating.
    Continue,
    /// Stop at this sample (an expected outcome, reported as a status).
    Stop,
}

/// A per-sample observer of a sampled-data run.
pub trait Monitor {
    /// Observes sample `t` (s): true state `x`, measurement `y`, plant input `u` (after the
    /// actuator chain). Called at `t₀` and after every sample; no allocation expected.
    fn observe(&mut self, t: f64, x: &[f64], y: &[f64], u: &[f64]) -> Flow;
}

impl Monitor for () {
    #[inline]
    fn observe(&mut self, _t: f64, _x: &[f64], _y: &[f64], _u: &[f64]) -> Flow {
        Flow::Continue
    }
}

impl<M: Monitor + ?Sized> Monitor for &mut M {
    #[inline]
    fn observe(&mut self, t: f64, x: &[f64], y: &[f64], u: &[f64]) -> Flow {
        (**self).observe(t, x, y, u)
    }
}

impl<A: Monitor, B: Monitor> Monitor for (A, B) {
    #[inline]
    fn observe(&mut self, t: f64, x: &[f64], y: &[f64], u: &[f64]) -> Flow {
        let a = self.0.observe(t, x, y, u);
        let b = self.1.observe(t, x, y, u);
        if a == Flow::Stop || b == Flow::Stop {
            Flow::Stop
        } else {
            Flow::Continue
        }
    }
}

/// A monitor given by a closure `f(t, x, y, u) -> Flow`.
#[derive(Clone, Copy)]
pub struct FnMonitor<F>(pub F);

impl<F: FnMut(f64, &[f64], &[f64], &[f64]) -> Flow> Monitor for FnMonitor<F> {
    #[inline]
    fn observe(&mut self, t: f64, x: &[f64], y: &[f64], u: &[f64]) -> Flow {
        (self.0)(t, x, y, u)
    }
}

impl<F> std::fmt::Debug for FnMonitor<F> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("FnMonitor")
    }
}

/// Largest `|x_i|` over the run and when it occurred.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaxAbs {
    index: usize,
    /// The largest `|x_i|` seen so far.
    pub value: f64,
    /// The time of that sample (s).
    pub at: f64,
}

impl MaxAbs {
    /// Tracks state `index`.
    pub fn new(index: usize) -> Self {
        Self {
            index,
            value: 0.0,
            at: f64::NAN,
        }
    }
}

impl Monitor for MaxAbs {
    #[inline]
    fn observe(&mut self, t: f64, x: &[f64], _y: &[f64], _u: &[f64]) -> Flow {
        let v = x[self.index].abs();
        if v > self.value || self.at.is_nan() {
            self.value = v;
            self.at = t;
        }
        Flow::Continue
    }
}

/// Watches `|x_i| ≤ bound` (e.g. "the pendulum stayed upright": `|θ| ≤ π/2`) and, by
/// default, stops the run at the first violation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StayWithin {
    index: usize,
    bound: f64,
    stop: bool,
    /// Time of the first sample with `|x_i| > bound`, if any.
    pub violated_at: Option<f64>,
}

impl StayWithin {
    /// Watches `|x_index| ≤ bound`, stopping the run at the first violation.
    pub fn new(index: usize, bound: f64) -> Self {
        Self {
            index,
            bound,
            stop: true,
            violated_at: None,
        }
    }
    /// Records the first violation but lets the run go on.
    pub fn record_only(mut self) -> Self {
        self.stop = false;
        self
    }
    /// `true` if no sample violated the bound.
    pub fn held(&self) -> bool {
        self.violated_at.is_none()
    }
}

impl Monitor for StayWithin {
    #[inline]
    fn observe(&mut self, t: f64, x: &[f64], _y: &[f64], _u: &[f64]) -> Flow {
        let v = x[self.index];
        if v.abs() > self.bound || v.is_nan() {
            if self.violated_at.is_none() {
                self.violated_at = Some(t);
            }
            if self.stop {
                return Flow::Stop;
            }
        }
        Flow::Continue
    }
}

/// Settling time of `x_i` into the band `|x_i − target| ≤ band`: the first sample time after
/// which every sample stays in the band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SettlingTime {
    index: usize,
    target: f64,
    band: f64,
    entered: Option<f64>,
}

impl SettlingTime {
    /// Watches `|x_index − target| ≤ band`.
    pub fn new(index: usize, target: f64, band: f64) -> Self {
        Self {
            index,
            target,
            band,
            entered: None,
        }
    }
    /// The settling time (s), or `None` if the last sample was outside the band.
    pub fn settling_time(&self) -> Option<f64> {
        self.entered
    }
}

impl Monitor for SettlingTime {
    #[inline]
    fn observe(&mut self, t: f64, x: &[f64], _y: &[f64], _u: &[f64]) -> Flow {
        if (x[self.index] - self.target).abs() <= self.band {
            if self.entered.is_none() {
                self.entered = Some(t);
            }
        } else {
            self.entered = None;
        }
        Flow::Continue
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ready_made_monitors() {
        let xs = [0.0, 2.0, -3.0, 0.05, 0.5, 0.01, 0.02];
        let mut m = (
            MaxAbs::new(0),
            (
                StayWithin::new(0, 2.5).record_only(),
                SettlingTime::new(0, 0.0, 0.1),
            ),
        );
        for (k, &v) in xs.iter().enumerate() {
            assert_eq!(m.observe(k as f64, &[v], &[], &[]), Flow::Continue);
        }
        assert_eq!((m.0.value, m.0.at), (3.0, 2.0));
        assert_eq!(m.1.0.violated_at, Some(2.0));
        assert_eq!(m.1.1.settling_time(), Some(5.0));
        let mut s = StayWithin::new(0, 1.0);
        assert_eq!(s.observe(0.0, &[f64::NAN], &[], &[]), Flow::Stop);
    }
}
