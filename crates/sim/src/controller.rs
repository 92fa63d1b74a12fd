//! The discrete controller interface shared by the simulator, the rig runtime and the designs.

/// A discrete-time controller called once per sample period.
///
/// At each sample instant `t_k = t_0 + k·ts` the caller hands the controller the measurement
/// `y_k` (what the sensor chain delivers: quantised encoder positions, estimated velocities, …)
/// and the controller writes the command `u_k`, which is held constant (zero-order hold) until
/// the next call. The reference, if any, is part of the controller (evaluated from `t`), so
/// the same value runs in the simulator and on the rig.
///
/// Contract:
/// - `y.len() == self.ny()`, `u.len() == self.nu()`.
/// - `update` is called with strictly increasing `t`; [`Controller::reset`] returns the
///   controller to its initial internal state (integrators, filters, switching mode).
/// - No allocation, I/O or sleeping inside `update`: it runs inside a 1 kHz loop.
pub trait Controller {
    /// Length of the measurement vector `y`.
    fn ny(&self) -> usize;
    /// Number of commands `u`.
    fn nu(&self) -> usize;
    /// Returns to the initial internal state.
    fn reset(&mut self);
    /// Computes `u_k` from the measurement `y_k` at time `t` (seconds).
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]);

    /// The sample time (s) the controller was designed for, if it has one (provided: `None`).
    ///
    /// Controllers with internal discrete dynamics (integrators, observers, filters) return
    /// `Some(ts)`; the sampled-data loop then refuses to run them at another rate.
    fn sample_time(&self) -> Option<f64> {
        None
    }

    /// Times (s) at which the controller switched mode since the last [`Controller::reset`]
    /// (provided: none). Switching controllers report them; the simulator copies them into its
    /// diagnostics.
    fn switch_times(&self) -> &[f64] {
        &[]
    }

    /// Replaces the controller's gain by `gain` while it runs, keeping everything else —
    /// internal state (integrators, mode), reference, sample time — as it is: a bumpless
    /// retune, e.g. after a redesign for new weights on the same plant. `gain` is laid out as
    /// the implementation documents (a state feedback's `K`, the LQ servo's `[K₁ K₂]`, row by
    /// row). Returns `Ok(true)` when the gain was replaced, `Ok(false)` when this controller
    /// has no gain to replace (provided: `Ok(false)`), so that the caller builds a new one.
    ///
    /// # Errors
    /// [`crate::SimError::DimensionMismatch`] for a gain of the wrong length,
    /// [`crate::SimError::InvalidParameter`] for a non-finite entry; the controller is then
    /// unchanged.
    fn retune(&mut self, gain: &[f64]) -> crate::Result<bool> {
        let _ = gain;
        Ok(false)
    }
}

/// `Controller` for pointers to a controller (`Box<T>`, `&mut T`): every method forwards to
/// the pointee (one body for both, which Rust requires to be written per pointer type).
macro_rules! forward_controller {
    ($($pointer:ty),+) => {$(
        impl<T: Controller + ?Sized> Controller for $pointer {
            fn ny(&self) -> usize {
                (**self).ny()
            }
            fn nu(&self) -> usize {
                (**self).nu()
            }
            fn reset(&mut self) {
                (**self).reset()
            }
            #[inline]
            fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
                (**self).update(t, y, u)
            }
            fn sample_time(&self) -> Option<f64> {
                (**self).sample_time()
            }
            fn switch_times(&self) -> &[f64] {
                (**self).switch_times()
            }
            fn retune(&mut self, gain: &[f64]) -> crate::Result<bool> {
                (**self).retune(gain)
            }
        }
    )+};
}

forward_controller!(Box<T>, &mut T);
