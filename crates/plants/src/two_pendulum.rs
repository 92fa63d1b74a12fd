//! A cart carrying two pendulums side by side (book example 5.4, `p1c511_ex4_cdip`).
//!
//! # Derivation
//! Two pendulums `a`, `b` hang on pivots on the same cart (they do not touch each other).
//! Pendulum `i` has mass `m_i`, pivot-to-centre-of-mass distance `l_i`, inertia `J_i` about its
//! centre of mass and pivot friction `μ_i`; its centre of mass is at
//! `(z + l_i sin θ_i, l_i cos θ_i)`. The Lagrangian of cart and pendulums is
//!
//! ```text
//! T = ½ M ż² + Σᵢ [½ m_i ((ż + l_i cos θ_i θ̇_i)² + (l_i sin θ_i θ̇_i)²) + ½ J_i θ̇_i²]
//!   = ½ (M + m_a + m_b) ż² + Σᵢ [m_i l_i cos θ_i ż θ̇_i + ½ (J_i + m_i l_i²) θ̇_i²],
//! V = Σᵢ m_i g l_i cos θ_i,    D = Σᵢ ½ μ_i θ̇_i².
//! ```
//!
//! `T` has no `θ̇_a θ̇_b` term and `V` no `θ_a θ_b` term, so the Euler–Lagrange equation of each
//! angle involves only its own pendulum and the cart:
//!
//! ```text
//! (J_i + m_i l_i²) θ̈_i + m_i l_i cos θ_i z̈ = m_i g l_i sin θ_i − μ_i θ̇_i,   i ∈ {a, b},
//! ```
//!
//! exactly the single-pendulum equation (see [`crate::cart`]). As in the single-pendulum model
//! the cart's equation is replaced by the identified drive `z̈ = −a_c ż + b_c v` (an
//! acceleration source); the pendulums are coupled only through the common `z̈`.
//! State `x = [z, θ_a, θ_b, ż, θ̇_a, θ̇_b]`, input `v`.
//!
//! # Controllability
//! Linearised upright, the pendulums' blocks differ only through `(J_i + m_i l_i², m_i l_i,
//! μ_i)`. With identical pendulums `δ = θ_a − θ_b` obeys `J δ̈ = m g l δ − μ δ̇` whatever `v`
//! does, so `(δ, δ̇)` is uncontrollable (rank 4 of 6); different pendulums make the pair
//! controllable (book example 5.4).

use pendulab_lti::{Continuous, StateSpace};
use pendulab_sim::Dynamics;

use crate::cart::CartPendulumParams;
use crate::drive::Drive;
use crate::error::{PlantError, Requirement, check, check_point};
use crate::linear::{Jacobian, Posture};
use crate::pendulum::{PendulumParams, PivotPendulum};

const MODEL: &str = "two-pendulum cart";

/// Parameters of the cart with two pendulums (plain data; validated by
/// [`TwoPendulumCart::new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoPendulumCartParams {
    /// Velocity pole of the cart drive `a_c` \[1/s\] (≥ 0).
    pub a_c: f64,
    /// Gain of the cart drive `b_c` \[m/(s² V)\] (> 0).
    pub b_c: f64,
    /// Gravitational acceleration `g` \[m/s²\] (> 0).
    pub g: f64,
    /// Pendulum `a`.
    pub pendulum_a: PendulumParams,
    /// Pendulum `b`.
    pub pendulum_b: PendulumParams,
}

impl TwoPendulumCartParams {
    /// The cart of `base` with its pendulum as pendulum `a` and a geometrically similar copy
    /// scaled by `factor` as pendulum `b`: `m_b = k m_p`, `l_b = k l_p`, `L_b = k L_p`,
    /// `J_b = k³ J_p`, `μ_b = μ_p` (`k = factor`; validated by [`TwoPendulumCart::new`]).
    pub fn scaled(base: &CartPendulumParams, factor: f64) -> Self {
        let p = base.pendulum();
        Self {
            a_c: base.a_c,
            b_c: base.b_c,
            g: base.g,
            pendulum_a: p,
            pendulum_b: PendulumParams {
                m: factor * p.m,
                l: factor * p.l,
                L: factor * p.L,
                J: factor * factor * factor * p.J,
                mu: p.mu,
            },
        }
    }

    /// Book example 5.4 (`p1c511_ex4_cdip`): the book's cart and pendulum plus a pendulum
    /// scaled by 1.2 ([`TwoPendulumCartParams::scaled`] with `k = 1.2`).
    pub fn book_example() -> Self {
        Self::scaled(&CartPendulumParams::book(), 1.2)
    }

    /// Two copies of the book's pendulum on the book's cart (the uncontrollable case).
    pub fn identical() -> Self {
        Self::scaled(&CartPendulumParams::book(), 1.0)
    }

    /// Checks every field (requirements as documented on the fields and on
    /// [`PendulumParams`]).
    ///
    /// # Errors
    /// [`PlantError::InvalidParameter`] naming the first offending parameter.
    pub fn validate(&self) -> Result<(), PlantError> {
        check(MODEL, "a_c", self.a_c, Requirement::NonNegative)?;
        check(MODEL, "b_c", self.b_c, Requirement::Positive)?;
        check(MODEL, "g", self.g, Requirement::Positive)?;
        self.pendulum_a
            .validate_named(MODEL, ["m_a", "l_a", "L_a", "J_a", "mu_a"])?;
        self.pendulum_b
            .validate_named(MODEL, ["m_b", "l_b", "L_b", "J_b", "mu_b"])
    }
}

/// The state `x = [z, θ_a, θ_b, ż, θ̇_a, θ̇_b]`, named (angles from the upward vertical).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TwoPendulumCartState {
    /// Cart position \[m\].
    pub z: f64,
    /// Angle of pendulum `a` \[rad\].
    pub theta_a: f64,
    /// Angle of pendulum `b` \[rad\].
    pub theta_b: f64,
    /// Cart velocity \[m/s\].
    pub dz: f64,
    /// Angular velocity of pendulum `a` \[rad/s\].
    pub dtheta_a: f64,
    /// Angular velocity of pendulum `b` \[rad/s\].
    pub dtheta_b: f64,
}

impl TwoPendulumCartState {
    /// The state as an array in the documented order.
    pub fn to_array(self) -> [f64; 6] {
        [
            self.z,
            self.theta_a,
            self.theta_b,
            self.dz,
            self.dtheta_a,
            self.dtheta_b,
        ]
    }

    /// The state from an array in the documented order.
    pub fn from_array(x: [f64; 6]) -> Self {
        Self {
            z: x[0],
            theta_a: x[1],
            theta_b: x[2],
            dz: x[3],
            dtheta_a: x[4],
            dtheta_b: x[5],
        }
    }
}

impl From<[f64; 6]> for TwoPendulumCartState {
    fn from(x: [f64; 6]) -> Self {
        Self::from_array(x)
    }
}

impl From<TwoPendulumCartState> for [f64; 6] {
    fn from(s: TwoPendulumCartState) -> Self {
        s.to_array()
    }
}

/// The cart with two pendulums: nonlinear dynamics, Jacobian, linearisation, energy.
///
/// ```
/// use pendulab_plants::{Posture, TwoPendulumCart, TwoPendulumCartParams};
/// let plant = TwoPendulumCart::new(TwoPendulumCartParams::book_example()).unwrap();
/// let sys = plant.linearize(0.0, Posture::Upright, Posture::Upright).unwrap();
/// assert_eq!(sys.nx(), 6);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoPendulumCart {
    params: TwoPendulumCartParams,
    drive: Drive,
    a: PivotPendulum,
    b: PivotPendulum,
}

impl TwoPendulumCart {
    /// A plant from validated parameters.
    ///
    /// # Errors
    /// [`PlantError::InvalidParameter`] naming the offending parameter;
    /// [`PlantError::DerivedQuantity`] on overflow.
    pub fn new(params: TwoPendulumCartParams) -> Result<Self, PlantError> {
        params.validate()?;
        Ok(Self {
            params,
            drive: Drive::new(params.a_c, params.b_c)?,
            a: PivotPendulum::new(&params.pendulum_a, params.g, MODEL)?,
            b: PivotPendulum::new(&params.pendulum_b, params.g, MODEL)?,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &TwoPendulumCartParams {
        &self.params
    }

    /// `ẋ = f(x, v)` (allocation-free).
    #[inline]
    pub fn derivative_array(&self, x: &[f64; 6], v: f64) -> [f64; 6] {
        let ddz = self.drive.acceleration(x[3], v);
        let (sa, ca) = x[1].sin_cos();
        let (sb, cb) = x[2].sin_cos();
        [
            x[3],
            x[4],
            x[5],
            ddz,
            self.a.acceleration(sa, ca, x[4], ddz),
            self.b.acceleration(sb, cb, x[5], ddz),
        ]
    }

    /// The analytic Jacobian at any point (entries as for
    /// [`CartPendulum::jacobian`](crate::CartPendulum::jacobian), once per pendulum).
    pub fn jacobian(&self, x: &[f64; 6], v: f64) -> Jacobian<6> {
        let ddz = self.drive.acceleration(x[3], v);
        let (sa, ca) = x[1].sin_cos();
        let (sb, cb) = x[2].sin_cos();
        self.jacobian_from([sa, sb], [ca, cb], ddz)
    }

    fn jacobian_from(&self, s: [f64; 2], c: [f64; 2], ddz: f64) -> Jacobian<6> {
        let (a, b) = (self.drive.a(), self.drive.b());
        let mut jac = Jacobian {
            a: [[0.0; 6]; 6],
            b: [0.0; 6],
        };
        for i in 0..3 {
            jac.a[i][i + 3] = 1.0;
        }
        jac.a[3][3] = -a;
        jac.b[3] = b;
        for (k, p) in [self.a, self.b].iter().enumerate() {
            let (d_theta, d_dtheta, d_ddz) = p.partials(s[k], c[k], ddz);
            let row = 4 + k;
            jac.a[row][1 + k] = d_theta;
            jac.a[row][4 + k] = d_dtheta;
            jac.a[row][3] = -a * d_ddz;
            jac.b[row] = b * d_ddz;
        }
        jac
    }

    /// The linearisation at the cart at rest at `z` with each pendulum at rest upright or
    /// hanging, in deviation variables, `C = I`, `D = 0`.
    ///
    /// # Errors
    /// [`PlantError::NonFiniteOperatingPoint`] if `z` is not finite.
    pub fn linearize(
        &self,
        z: f64,
        posture_a: Posture,
        posture_b: Posture,
    ) -> Result<StateSpace<Continuous>, PlantError> {
        check_point("z", z)?;
        self.jacobian_from([0.0, 0.0], [posture_a.cos(), posture_b.cos()], 0.0)
            .to_state_space()
    }

    /// The sum of both pendulums' energies `Σᵢ ½ (J_i + m_i l_i²) θ̇_i² + m_i g l_i (1 + cos θ_i)`
    /// \[J\].
    pub fn energy(&self, x: &TwoPendulumCartState) -> f64 {
        self.a.energy(x.theta_a, x.dtheta_a) + self.b.energy(x.theta_b, x.dtheta_b)
    }
}

impl Dynamics for TwoPendulumCart {
    fn nx(&self) -> usize {
        6
    }
    fn nu(&self) -> usize {
        1
    }
    #[inline]
    fn derivative(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        debug_assert!(x.len() == 6 && u.len() == 1 && dx.len() == 6);
        let f = self.derivative_array(&[x[0], x[1], x[2], x[3], x[4], x[5]], u[0]);
        dx[..6].copy_from_slice(&f);
    }
}
