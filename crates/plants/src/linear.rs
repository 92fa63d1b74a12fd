//! Shared pieces of the linear models: the two upright/hanging postures and the Jacobian of a
//! single-input model at one point.

use pendulab_lti::{Continuous, Mat, StateSpace};

use crate::error::PlantError;

/// Where a pendulum rests at an equilibrium.
///
/// Angles are measured from the **upward** vertical throughout the crate, so the upright rest is
/// `θ = 0` and the hanging rest `θ = π`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Posture {
    /// Inverted, `θ = 0` (unstable without control).
    Upright,
    /// Hanging, `θ = π` (stable).
    Hanging,
}

impl Posture {
    /// The pendulum angle of this posture in radians: `0` (upright) or `π` (hanging).
    pub fn angle(self) -> f64 {
        match self {
            Posture::Upright => 0.0,
            Posture::Hanging => std::f64::consts::PI,
        }
    }

    /// `cos θ` of this posture, exactly `+1` or `−1` (used by the linearisations so that
    /// `sin π ≈ 1.2e-16` never leaks into a model).
    pub fn cos(self) -> f64 {
        match self {
            Posture::Upright => 1.0,
            Posture::Hanging => -1.0,
        }
    }
}

/// The Jacobian of a single-input model `ẋ = f(x, u)` at one point `(x₀, u₀)`:
/// `A = ∂f/∂x`, `B = ∂f/∂u`, so that `ẋ ≈ f(x₀, u₀) + A (x − x₀) + B (u − u₀)`.
///
/// Fixed-size, allocation-free; convert with [`Jacobian::a_matrix`],
/// [`Jacobian::to_state_space`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jacobian<const N: usize> {
    /// `∂f/∂x`: `a[i][j] = ∂fᵢ/∂xⱼ`.
    pub a: [[f64; N]; N],
    /// `∂f/∂u`: `b[i] = ∂fᵢ/∂u`.
    pub b: [f64; N],
}

impl<const N: usize> Jacobian<N> {
    /// `A` as an `N × N` matrix.
    pub fn a_matrix(&self) -> Mat {
        Mat::from_fn(N, N, |i, j| self.a[i][j])
    }

    /// `B` as an `N × 1` matrix.
    pub fn b_matrix(&self) -> Mat {
        Mat::from_fn(N, 1, |i, _| self.b[i])
    }

    /// The linear model `δẋ = A δx + B δu`, `y = δx` (`C = I`, `D = 0`).
    ///
    /// # Errors
    /// [`PlantError::Lti`] if an entry is not finite.
    pub fn to_state_space(&self) -> Result<StateSpace<Continuous>, PlantError> {
        Ok(StateSpace::continuous(
            self.a_matrix(),
            self.b_matrix(),
            Mat::identity(N, N),
            Mat::zeros(N, 1),
        )?)
    }

    /// The linear model with the outputs `y = δx[i]` for `i` in `outputs` (rows of the
    /// identity), `D = 0`.
    ///
    /// # Errors
    /// [`PlantError::OutputIndex`] if an index is `≥ N`; [`PlantError::Lti`] if an entry is
    /// not finite.
    pub fn to_state_space_with_outputs(
        &self,
        outputs: &[usize],
    ) -> Result<StateSpace<Continuous>, PlantError> {
        Ok(StateSpace::continuous(
            self.a_matrix(),
            self.b_matrix(),
            selection_matrix(outputs, N)?,
            Mat::zeros(outputs.len(), 1),
        )?)
    }
}

/// The `k × n` matrix whose rows pick the states `indices` (rows of the identity).
pub(crate) fn selection_matrix(indices: &[usize], n: usize) -> Result<Mat, PlantError> {
    let mut c = Mat::zeros(indices.len(), n);
    for (row, &i) in indices.iter().enumerate() {
        if i >= n {
            return Err(PlantError::OutputIndex { index: i, nx: n });
        }
        c[(row, i)] = 1.0;
    }
    Ok(c)
}
