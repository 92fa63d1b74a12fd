//! The drive of either rig: a DC motor with its amplifier, seen from the voltage `v` to the
//! position `q` of the cart (metres) or of the arm (radians).

use pendulab_lti::{Continuous, Mat, StateSpace, TransferFunction};
use pendulab_sim::Dynamics;

use crate::error::{PlantError, Requirement, check};

/// The identified drive model `q̈ = −a q̇ + b v` (book eqs 3.21 and 3.29), i.e.
/// `P(s) = q(s)/v(s) = b / (s (s + a))`.
///
/// For the cart `q = z` \[m\], `a = a_c` \[1/s\], `b = b_c` \[m/(s² V)\]; for the arm `q = θ₁` \[rad\],
/// `a = a₁` \[1/s\], `b = b₁` \[rad/(s² V)\]. The drive is an **acceleration source**: the
/// reaction of the pendulum on the cart or arm is absorbed by the motor's current loop, which
/// is how the book identifies and uses it. State `x = [q, q̇]`, input `u = [v]` (volts).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    a: f64,
    b: f64,
}

impl Drive {
    /// A drive with velocity pole `a` \[1/s\] and gain `b` \[position unit/(s² V)\].
    ///
    /// # Errors
    /// [`PlantError::InvalidParameter`] unless `a ≥ 0` (`a = 0`: a pure double integrator)
    /// and `b > 0`, both finite.
    pub fn new(a: f64, b: f64) -> Result<Self, PlantError> {
        check("drive", "a", a, Requirement::NonNegative)?;
        check("drive", "b", b, Requirement::Positive)?;
        Ok(Self { a, b })
    }

    /// The velocity pole `a` \[1/s\].
    pub fn a(&self) -> f64 {
        self.a
    }

    /// The gain `b` \[position unit/(s² V)\].
    pub fn b(&self) -> f64 {
        self.b
    }

    /// The acceleration `q̈ = −a q̇ + b v` for velocity `dq` and voltage `v`.
    #[inline]
    pub fn acceleration(&self, dq: f64, v: f64) -> f64 {
        -self.a * dq + self.b * v
    }

    /// `ẋ = [q̇, −a q̇ + b v]` for `x = [q, q̇]`.
    #[inline]
    pub fn derivative_array(&self, x: &[f64; 2], v: f64) -> [f64; 2] {
        [x[1], self.acceleration(x[1], v)]
    }

    /// The state-space model `A = [[0, 1], [0, −a]]`, `B = [0; b]`, `C = [1, 0]` (the
    /// position is measured), `D = 0`.
    ///
    /// # Errors
    /// [`PlantError::Lti`] only if the model cannot be represented (never for a drive built
    /// by [`Drive::new`]).
    pub fn state_space(&self) -> Result<StateSpace<Continuous>, PlantError> {
        Ok(StateSpace::continuous(
            Mat::from_row_slice(2, 2, &[0.0, 1.0, 0.0, -self.a]),
            Mat::from_row_slice(2, 1, &[0.0, self.b]),
            Mat::from_row_slice(1, 2, &[1.0, 0.0]),
            Mat::zeros(1, 1),
        )?)
    }

    /// The transfer function `P(s) = b / (s² + a s)`.
    ///
    /// # Errors
    /// As [`Drive::state_space`].
    #[doc(alias = "tf")]
    pub fn transfer_function(&self) -> Result<TransferFunction<Continuous>, PlantError> {
        Ok(TransferFunction::continuous(
            &[self.b],
            &[1.0, self.a, 0.0],
        )?)
    }
}

impl Dynamics for Drive {
    fn nx(&self) -> usize {
        2
    }
    fn nu(&self) -> usize {
        1
    }
    #[inline]
    fn derivative(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        debug_assert!(x.len() == 2 && u.len() == 1 && dx.len() == 2);
        dx[0] = x[1];
        dx[1] = self.acceleration(x[1], u[0]);
    }
}
