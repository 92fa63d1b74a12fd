//! The cart-type rig's pendulum with the cart held fixed (book §4.3, eqs 4.39–4.45).
//!
//! With `z̈ ≡ 0` the pendulum equation becomes `J θ̈ = m_p g l_p sin θ − μ_p θ̇`,
//! `J = J_p + m_p l_p²`. Linearised at the hanging rest (`φ = θ − π`, eq. 4.39) and at the
//! upright rest (eq. 4.43):
//!
//! ```text
//! hanging: d/dt [φ, φ̇] = [[0, 1], [−ω_np², −2 ζ_p ω_np]] [φ, φ̇],
//!          eigenvalues (−ζ_p ± √(ζ_p² − 1)) ω_np          (eq. 4.41, stable)
//! upright: d/dt [θ, θ̇] = [[0, 1], [+ω_np², −2 ζ_p ω_np]] [θ, θ̇],
//!          eigenvalues (−ζ_p ± √(ζ_p² + 1)) ω_np          (eq. 4.45, one unstable)
//! ```
//!
//! with `ω_np = √(m_p g l_p / J)` and `ζ_p = μ_p / (2 ω_np J)` (eq. 4.42).

use pendulab_lti::{Complex64, Continuous, Mat, StateSpace};
use pendulab_sim::Dynamics;

use crate::cart::CartPendulumParams;
use crate::error::PlantError;
use crate::linear::Posture;
use crate::pendulum::PivotPendulum;

/// The pendulum of the cart-type rig with the cart held: state `x = [θ, θ̇]` (θ from the
/// upward vertical), no input.
///
/// ```
/// use pendulab_plants::{CartPendulum, Posture};
/// let p = CartPendulum::book().fixed_cart();
/// let [l1, l2] = p.eigenvalues(Posture::Upright);
/// assert!(l1.re > 0.0 && l2.re < 0.0); // a saddle: the upright pendulum falls
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedCartPendulum {
    pendulum: PivotPendulum,
}

impl FixedCartPendulum {
    /// The fixed-cart pendulum of a cart-pendulum parameter set (the drive parameters are
    /// validated too but not used).
    ///
    /// # Errors
    /// As [`CartPendulum::new`](crate::CartPendulum::new).
    pub fn new(params: &CartPendulumParams) -> Result<Self, PlantError> {
        Ok(crate::CartPendulum::new(*params)?.fixed_cart())
    }

    pub(crate) fn from_parts(pendulum: PivotPendulum) -> Self {
        Self { pendulum }
    }

    /// `ω_np = √(m_p g l_p / J)` \[rad/s\] (eq. 4.42).
    pub fn natural_frequency(&self) -> f64 {
        (self.pendulum.mgl / self.pendulum.j).sqrt()
    }

    /// `ζ_p = μ_p / (2 ω_np J)` (dimensionless, eq. 4.42).
    pub fn damping_ratio(&self) -> f64 {
        self.pendulum.mu / (2.0 * self.natural_frequency() * self.pendulum.j)
    }

    /// `ẋ = [θ̇, (m_p g l_p sin θ − μ_p θ̇)/J]` for `x = [θ, θ̇]`.
    #[inline]
    pub fn derivative_array(&self, x: &[f64; 2]) -> [f64; 2] {
        let (s, c) = x[0].sin_cos();
        [x[1], self.pendulum.acceleration(s, c, x[1], 0.0)]
    }

    /// The linearisation (eq. 4.40 hanging, in `[φ, φ̇]`; eq. 4.44 upright, in `[θ, θ̇]`):
    /// `A = [[0, 1], [±m_p g l_p/J, −μ_p/J]]`, `C = I`; no input (`B` is `2 × 0`).
    ///
    /// # Errors
    /// [`PlantError::Lti`] only if the model cannot be represented.
    pub fn linearize(&self, posture: Posture) -> Result<StateSpace<Continuous>, PlantError> {
        let p = &self.pendulum;
        let a = Mat::from_row_slice(2, 2, &[0.0, 1.0, posture.cos() * p.mgl / p.j, -p.mu / p.j]);
        Ok(StateSpace::continuous(
            a,
            Mat::zeros(2, 0),
            Mat::identity(2, 2),
            Mat::zeros(2, 0),
        )?)
    }

    /// The eigenvalues of the linearisation in closed form, `(−ζ_p ± √(ζ_p² − 1)) ω_np`
    /// hanging (eq. 4.41) and `(−ζ_p ± √(ζ_p² + 1)) ω_np` upright (eq. 4.45); the `+` root
    /// first (complex when hanging and under-damped, `ζ_p < 1`).
    pub fn eigenvalues(&self, posture: Posture) -> [Complex64; 2] {
        let (w, z) = (self.natural_frequency(), self.damping_ratio());
        // ζ² ∓ 1: −1 hanging, +1 upright (cos θ_e = −1, +1).
        let root = Complex64::new(z * z + posture.cos(), 0.0).sqrt();
        [(-z + root) * w, (-z - root) * w]
    }

    /// The pendulum's energy `E = ½ J θ̇² + m_p g l_p (1 + cos θ)` \[J\]; constant along
    /// solutions when `μ_p = 0`.
    pub fn energy(&self, x: &[f64; 2]) -> f64 {
        self.pendulum.energy(x[0], x[1])
    }
}

impl Dynamics for FixedCartPendulum {
    fn nx(&self) -> usize {
        2
    }
    fn nu(&self) -> usize {
        0
    }
    #[inline]
    fn derivative(&self, _t: f64, x: &[f64], _u: &[f64], dx: &mut [f64]) {
        debug_assert!(x.len() == 2 && dx.len() == 2);
        let f = self.derivative_array(&[x[0], x[1]]);
        dx[..2].copy_from_slice(&f);
    }
}
