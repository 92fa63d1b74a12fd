//! Time domains: continuous time and discrete time with its sample time.
//!
//! The domain is a type parameter of [`StateSpace`](crate::StateSpace) and
//! [`TransferFunction`](crate::TransferFunction), so that a function that only makes sense in
//! one domain (`c2d` on continuous systems, `d2c` on discrete ones) exists only there, and a
//! function that works in both (`lqr`, `poles`, `is_stable`) is written once.

use crate::error::{LtiError, Result};
use crate::linalg::Complex64;

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Continuous {}
    impl Sealed for super::Discrete {}
}

/// A time domain: [`Continuous`] or [`Discrete`].
pub trait TimeDomain:
    Copy + Clone + std::fmt::Debug + PartialEq + Send + Sync + 'static + sealed::Sealed
{
    /// Sample time in seconds, `None` in continuous time.
    fn sample_time(&self) -> Option<f64>;

    /// Signed distance of a pole from the stability boundary: `Re λ` in continuous time,
    /// `|λ| − 1` in discrete time. Negative means asymptotically stable.
    fn stability_distance(&self, pole: Complex64) -> f64;

    /// Checks that two systems may be interconnected (equal sample times).
    ///
    /// # Errors
    /// [`LtiError::SampleTimeMismatch`] if both are discrete with different sample times.
    fn check_compatible(&self, other: &Self) -> Result<()>;
}

/// Continuous time (`ẋ = A x + B u`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Continuous;

impl TimeDomain for Continuous {
    fn sample_time(&self) -> Option<f64> {
        None
    }
    fn stability_distance(&self, pole: Complex64) -> f64 {
        pole.re
    }
    fn check_compatible(&self, _other: &Self) -> Result<()> {
        Ok(())
    }
}

/// Discrete time (`x[k+1] = A x[k] + B u[k]`) with sample time `ts` seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Discrete {
    ts: f64,
}

impl Discrete {
    /// Discrete time domain with sample time `ts` seconds.
    ///
    /// # Errors
    /// [`LtiError::InvalidSampleTime`] unless `ts` is finite and positive.
    pub fn new(ts: f64) -> Result<Self> {
        if ts.is_finite() && ts > 0.0 {
            Ok(Self { ts })
        } else {
            Err(LtiError::InvalidSampleTime(ts))
        }
    }

    /// Sample time in seconds.
    pub fn ts(&self) -> f64 {
        self.ts
    }
}

impl TimeDomain for Discrete {
    fn sample_time(&self) -> Option<f64> {
        Some(self.ts)
    }
    fn stability_distance(&self, pole: Complex64) -> f64 {
        pole.norm() - 1.0
    }
    fn check_compatible(&self, other: &Self) -> Result<()> {
        // Sample times that agree to rounding are the same.
        if (self.ts - other.ts).abs() <= 1e-12 * self.ts.max(other.ts) {
            Ok(())
        } else {
            Err(LtiError::SampleTimeMismatch(self.ts, other.ts))
        }
    }
}
