//! A controller that hands every update to an inspector: what a benchmark times and a test
//! checks, update by update, without changing what the wrapped controller does.
//!
//! [`Inspected`] forwards every [`Controller`] method to the wrapped controller; after each
//! `update` it calls the inspector with its own state, the wrapped controller (to read what
//! the update left behind, e.g. an MPC's last QP) and the [`Update`]: the time, the
//! measurement, the command and the wall-clock time the wrapped update took. The inspector
//! runs outside the timed span, so what it does is not counted. Used by the `mpc-qp`
//! benchmark (the update times and some QPs to solve again) and the MPC tests (the KKT
//! residuals of every solve).
//!
//! ```
//! use pendulab_control::inspect::Inspected;
//! use pendulab_sim::Controller;
//! use pendulab_sim::controllers::StaticStateFeedback;
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let k = pendulab_lti::Mat::from_row_slice(1, 2, &[1.0, 2.0]);
//! // Keep the command of every update.
//! let mut c = Inspected::new(StaticStateFeedback::new(k)?, Vec::new(), |kept, _, up| {
//!     kept.push(up.u[0])
//! });
//! let mut u = [0.0];
//! c.update(0.0, &[1.0, 1.0], &mut u);
//! assert_eq!(c.state, vec![-3.0]); // u = −K y
//! # Ok(()) }
//! ```

use pendulab_sim::Controller;
use std::time::Instant;

/// One update of an [`Inspected`] controller, as the wrapped controller left it.
#[derive(Debug, Clone, Copy)]
pub struct Update<'a> {
    /// The time of the update \[s\].
    pub t: f64,
    /// The measurement it was given.
    pub y: &'a [f64],
    /// The command it wrote.
    pub u: &'a [f64],
    /// The wall-clock time the wrapped controller's `update` took \[s\] (for benchmarks; never
    /// for a test's assertion).
    pub seconds: f64,
}

/// The inspector of an [`Inspected`] controller: its state, the wrapped controller after the
/// update, the update.
pub type Inspector<C, S> = fn(&mut S, &C, &Update<'_>);

/// `inner`, with `inspect(&mut state, &inner, &update)` called after every update (module
/// documentation). Every [`Controller`] method is `inner`'s; `reset` resets `inner` only, not
/// `state`.
pub struct Inspected<C, S> {
    /// The wrapped controller.
    pub inner: C,
    /// What the inspector keeps (read it after the run).
    pub state: S,
    inspect: Inspector<C, S>,
}

impl<C, S> Inspected<C, S> {
    /// Wraps `inner`; the inspector starts from `state`.
    pub fn new(inner: C, state: S, inspect: Inspector<C, S>) -> Self {
        Self {
            inner,
            state,
            inspect,
        }
    }
}

impl<C: std::fmt::Debug, S: std::fmt::Debug> std::fmt::Debug for Inspected<C, S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Inspected")
            .field("inner", &self.inner)
            .field("state", &self.state)
            .finish_non_exhaustive()
    }
}

impl<C: Controller, S> Controller for Inspected<C, S> {
    fn ny(&self) -> usize {
        self.inner.ny()
    }
    fn nu(&self) -> usize {
        self.inner.nu()
    }
    fn reset(&mut self) {
        self.inner.reset()
    }
    fn sample_time(&self) -> Option<f64> {
        self.inner.sample_time()
    }
    fn switch_times(&self) -> &[f64] {
        self.inner.switch_times()
    }
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        let start = Instant::now();
        self.inner.update(t, y, u);
        let seconds = start.elapsed().as_secs_f64();
        let update = Update { t, y, u, seconds };
        (self.inspect)(&mut self.state, &self.inner, &update);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pendulab_sim::controllers::StaticStateFeedback;

    #[test]
    fn forwards_every_method_and_inspects_each_update_after_it() {
        let k = pendulab_lti::Mat::from_row_slice(1, 2, &[1.0, 2.0]);
        let plain = StaticStateFeedback::new(k.clone()).unwrap();
        let mut c = Inspected::new(
            StaticStateFeedback::new(k).unwrap(),
            Vec::new(),
            |kept: &mut Vec<(f64, Vec<f64>, f64)>, _, up| {
                assert!(up.seconds >= 0.0);
                kept.push((up.t, up.y.to_vec(), up.u[0]))
            },
        );
        assert_eq!((c.ny(), c.nu()), (plain.ny(), plain.nu()));
        assert_eq!(c.sample_time(), plain.sample_time());
        let mut u = [0.0];
        c.update(0.5, &[1.0, -2.0], &mut u);
        c.reset();
        c.update(1.0, &[0.0, 1.0], &mut u);
        // u = −K y: −(1 − 4) = 3, then −2; reset leaves the inspector's state alone.
        assert_eq!(
            c.state,
            vec![(0.5, vec![1.0, -2.0], 3.0), (1.0, vec![0.0, 1.0], -2.0)]
        );
        assert_eq!(u[0], -2.0);
    }
}
