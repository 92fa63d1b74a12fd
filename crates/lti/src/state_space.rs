//! State-space systems `ẋ = A x + B u, y = C x + D u` (continuous) and
//! `x[k+1] = A x[k] + B u[k], y[k] = C x[k] + D u[k]` (discrete).

use crate::domain::{Continuous, Discrete, TimeDomain};
use crate::error::Result;
use crate::linalg::{Mat, check_finite, check_shape, check_square};

/// A linear time-invariant system in state-space form, in time domain `D`.
///
/// Invariants (checked once, at construction): `A` is `nx × nx`, `B` is `nx × nu`, `C` is
/// `ny × nx`, `D` is `ny × nu`, every entry finite. `nx = 0` (a static gain) is allowed.
#[doc(alias = "ss")]
#[derive(Debug, Clone, PartialEq)]
pub struct StateSpace<D: TimeDomain> {
    a: Mat,
    b: Mat,
    c: Mat,
    d: Mat,
    domain: D,
}

impl<D: TimeDomain> StateSpace<D> {
    /// Builds a system from its four matrices and its time domain.
    ///
    /// # Errors
    /// [`LtiError::NotSquare`](crate::LtiError::NotSquare) /
    /// [`LtiError::DimensionMismatch`](crate::LtiError::DimensionMismatch) naming the matrix
    /// whose shape is inconsistent, [`LtiError::NonFinite`](crate::LtiError::NonFinite) for NaN
    /// or infinite entries.
    pub fn new(a: Mat, b: Mat, c: Mat, d: Mat, domain: D) -> Result<Self> {
        check_square("A", &a)?;
        let nx = a.nrows();
        if b.nrows() != nx {
            check_shape("B", &b, nx, b.ncols())?;
        }
        let nu = b.ncols();
        if c.ncols() != nx {
            check_shape("C", &c, c.nrows(), nx)?;
        }
        let ny = c.nrows();
        check_shape("D", &d, ny, nu)?;
        check_finite("A", &a)?;
        check_finite("B", &b)?;
        check_finite("C", &c)?;
        check_finite("D", &d)?;
        Ok(Self { a, b, c, d, domain })
    }

    /// A static gain `y = D u` (no states).
    ///
    /// # Errors
    /// [`LtiError::NonFinite`](crate::LtiError::NonFinite).
    pub fn static_gain(d: Mat, domain: D) -> Result<Self> {
        let (ny, nu) = d.shape();
        Self::new(
            Mat::zeros(0, 0),
            Mat::zeros(0, nu),
            Mat::zeros(ny, 0),
            d,
            domain,
        )
    }

    /// State matrix `A` (`nx × nx`).
    pub fn a(&self) -> &Mat {
        &self.a
    }
    /// Input matrix `B` (`nx × nu`).
    pub fn b(&self) -> &Mat {
        &self.b
    }
    /// Output matrix `C` (`ny × nx`).
    pub fn c(&self) -> &Mat {
        &self.c
    }
    /// Feedthrough matrix `D` (`ny × nu`).
    pub fn d(&self) -> &Mat {
        &self.d
    }
    /// The time domain.
    pub fn domain(&self) -> D {
        self.domain
    }
    /// Number of states.
    pub fn nx(&self) -> usize {
        self.a.nrows()
    }
    /// Number of inputs.
    pub fn nu(&self) -> usize {
        self.b.ncols()
    }
    /// Number of outputs.
    pub fn ny(&self) -> usize {
        self.c.nrows()
    }
    /// Consumes the system, returning `(A, B, C, D)`.
    pub fn into_parts(self) -> (Mat, Mat, Mat, Mat) {
        (self.a, self.b, self.c, self.d)
    }
}

impl StateSpace<Continuous> {
    /// A continuous-time system `ẋ = A x + B u, y = C x + D u`.
    ///
    /// # Errors
    /// As [`StateSpace::new`].
    pub fn continuous(a: Mat, b: Mat, c: Mat, d: Mat) -> Result<Self> {
        Self::new(a, b, c, d, Continuous)
    }
}

impl StateSpace<Discrete> {
    /// A discrete-time system `x[k+1] = A x[k] + B u[k], y[k] = C x[k] + D u[k]` with sample
    /// time `ts` seconds.
    ///
    /// # Errors
    /// As [`StateSpace::new`], and [`LtiError::InvalidSampleTime`](crate::LtiError::InvalidSampleTime).
    pub fn discrete(a: Mat, b: Mat, c: Mat, d: Mat, ts: f64) -> Result<Self> {
        Self::new(a, b, c, d, Discrete::new(ts)?)
    }

    /// Sample time in seconds.
    pub fn ts(&self) -> f64 {
        self.domain.ts()
    }
}
