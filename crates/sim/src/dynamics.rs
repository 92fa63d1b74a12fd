//! The one simulation interface shared by linear systems, plants and closed loops.

/// Continuous-time dynamics `ẋ = f(t, x, u)`.
///
/// Everything pendulab simulates implements this trait: state-space systems, the pendulum
/// plants of `pendulab-plants`, closed loops. The integrators, the sampled-data loop and
/// `linearize` are written once against it.
///
/// Contract:
/// - `x.len() == self.nx()`, `u.len() == self.nu()`, `dx.len() == self.nx()`; callers in this
///   crate guarantee it, implementations may `debug_assert!` it.
/// - `derivative` is pure (no hidden state) and allocation-free, so it can sit in hot loops
///   and be called from several threads (`Sync` implementations).
/// - Units are those of the implementing model (SI, radians).
pub trait Dynamics {
    /// Number of states.
    fn nx(&self) -> usize;
    /// Number of inputs.
    fn nu(&self) -> usize;
    /// Writes `ẋ = f(t, x, u)` into `dx`.
    fn derivative(&self, t: f64, x: &[f64], u: &[f64], dx: &mut [f64]);
}

impl<T: Dynamics + ?Sized> Dynamics for &T {
    fn nx(&self) -> usize {
        (**self).nx()
    }
    fn nu(&self) -> usize {
        (**self).nu()
    }
    #[inline]
    fn derivative(&self, t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        (**self).derivative(t, x, u, dx)
    }
}
