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

    /// Number of outputs of the output map `y = h(t, x, u)` (provided: 0, no output map).
    ///
    /// Simulations record `y` in the `Trajectory` when it is non-zero; `linearize` returns
    /// `C = ∂h/∂x`, `D = ∂h/∂u` for it (and `C = I`, `D = 0` without an output map).
    fn ny(&self) -> usize {
        0
    }

    /// Writes `y = h(t, x, u)` into `y` (`y.len() == self.ny()`; provided: nothing to write).
    fn output(&self, t: f64, x: &[f64], u: &[f64], y: &mut [f64]) {
        let _ = (t, x, u, y);
    }
}

/// `Dynamics` for pointers to a system (`&T`, `Box<T>`): every method forwards to the pointee
/// (one body for both, which Rust requires to be written per pointer type).
macro_rules! forward_dynamics {
    ($($pointer:ty),+) => {$(
        impl<T: Dynamics + ?Sized> Dynamics for $pointer {
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
            fn ny(&self) -> usize {
                (**self).ny()
            }
            fn output(&self, t: f64, x: &[f64], u: &[f64], y: &mut [f64]) {
                (**self).output(t, x, u, y)
            }
        }
    )+};
}

forward_dynamics!(&T, Box<T>);
