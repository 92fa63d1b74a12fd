//! The classic cart-pole of reinforcement learning (Barto, Sutton & Anderson 1983), as
//! Gymnasium's `CartPole-v1` writes it: a frictionless cart with a uniform pole, pushed by a
//! force of `±force_mag`, advanced by one explicit Euler step of `tau` per action.
//!
//! This is not the book's cart rig ([`crate::CartPendulum`], driven by a voltage through an
//! identified drive); it is the benchmark model, kept so that pendulab can offer a drop-in
//! `CartPole-v1` whose trajectories equal Gymnasium's step for step.
//!
//! # Model
//! State (Gymnasium's order) `s = [x, ẋ, θ, θ̇]`: cart position \[m\], cart velocity \[m/s\],
//! pole angle from the upward vertical \[rad\], its rate \[rad/s\]. With the cart mass `m_c`,
//! the pole mass `m_p`, `M = m_c + m_p`, the pole's **half** length `l` (its centre of mass;
//! inertia about the pivot `(4/3) m_p l²`) and the force `F` \[N\]:
//!
//! ```text
//! temp = (F + m_p l θ̇² sin θ) / M
//! θ̈    = (g sin θ − cos θ · temp) / (l (4/3 − m_p cos² θ / M))
//! ẍ    = temp − m_p l θ̈ cos θ / M
//! ```
//!
//! the solution for `(ẍ, θ̈)` of the Euler–Lagrange equations
//! `M ẍ + m_p l cos θ θ̈ − m_p l sin θ θ̇² = F` and `(4/3) m_p l² θ̈ + m_p l cos θ ẍ = m_p g l sin θ`.
//!
//! One step (`kinematics_integrator = "euler"`, Gymnasium's default) is
//! `s ← s + τ [ẋ, ẍ, θ̇, θ̈]`; the semi-implicit variant updates the velocities first and the
//! positions with the new velocities. Every operation is written in the order Gymnasium's
//! `cartpole.py` performs it, so that the same state and force give the same bits.
//!
//! # Episode limits
//! An episode ends (terminates) when `|x| > x_threshold` (2.4 m) or `|θ| > θ_threshold`
//! (`12 · 2π / 360` rad); [`ClassicCartPole::is_terminal`] tells.

use crate::error::{PlantError, Requirement, check};

const MODEL: &str = "classic cart-pole";

/// How one step integrates (Gymnasium's `kinematics_integrator`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CartPoleIntegrator {
    /// Explicit Euler: positions advance with the old velocities (`"euler"`, the default).
    #[default]
    Euler,
    /// Semi-implicit Euler: velocities first, then positions with the new velocities.
    SemiImplicitEuler,
}

/// The parameters of the classic cart-pole (Gymnasium's names in the docs; SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClassicCartPoleParams {
    /// Gravitational acceleration `g` \[m/s²\] (> 0).
    pub gravity: f64,
    /// Cart mass `m_c` \[kg\] (> 0).
    pub masscart: f64,
    /// Pole mass `m_p` \[kg\] (> 0).
    pub masspole: f64,
    /// Half the pole's length `l` (pivot to centre of mass) \[m\] (> 0).
    pub length: f64,
    /// Magnitude of the push `F` \[N\] (> 0); action 1 pushes with `+F`, action 0 with `−F`.
    pub force_mag: f64,
    /// Time per step `τ` \[s\] (> 0).
    pub tau: f64,
    /// Termination bound on `|x|` \[m\] (> 0).
    pub x_threshold: f64,
    /// Termination bound on `|θ|` \[rad\] (> 0).
    pub theta_threshold: f64,
    /// Explicit or semi-implicit Euler.
    pub integrator: CartPoleIntegrator,
}

impl ClassicCartPoleParams {
    /// Gymnasium's `CartPole-v1`: `g = 9.8`, `m_c = 1.0`, `m_p = 0.1`, `l = 0.5`,
    /// `F = 10`, `τ = 0.02`, `x_threshold = 2.4`, `θ_threshold = 12 · 2π / 360`, Euler.
    pub fn gymnasium() -> Self {
        Self {
            gravity: 9.8,
            masscart: 1.0,
            masspole: 0.1,
            length: 0.5,
            force_mag: 10.0,
            tau: 0.02,
            x_threshold: 2.4,
            // As Gymnasium computes it: (12 · 2) · π / 360.
            theta_threshold: 24.0 * std::f64::consts::PI / 360.0,
            integrator: CartPoleIntegrator::Euler,
        }
    }

    /// Checks every field (finite and positive).
    ///
    /// # Errors
    /// [`PlantError::InvalidParameter`] naming the first offending field and its value.
    pub fn validate(&self) -> Result<(), PlantError> {
        for (name, value) in [
            ("gravity", self.gravity),
            ("masscart", self.masscart),
            ("masspole", self.masspole),
            ("length", self.length),
            ("force_mag", self.force_mag),
            ("tau", self.tau),
            ("x_threshold", self.x_threshold),
            ("theta_threshold", self.theta_threshold),
        ] {
            check(MODEL, name, value, Requirement::Positive)?;
        }
        Ok(())
    }
}

impl Default for ClassicCartPoleParams {
    /// [`ClassicCartPoleParams::gymnasium`].
    fn default() -> Self {
        Self::gymnasium()
    }
}

/// The classic cart-pole with validated parameters (see the module documentation).
///
/// ```
/// use pendulab_plants::ClassicCartPole;
/// let plant = ClassicCartPole::gymnasium();
/// // At rest upright, a push of +10 N accelerates the cart forwards and tips the pole back.
/// let [dx, ddx, dth, ddth] = plant.derivative(&[0.0; 4], 10.0);
/// assert_eq!((dx, dth), (0.0, 0.0));
/// assert!(ddx > 0.0 && ddth < 0.0);
/// let s = plant.step(&[0.0; 4], 1);
/// assert_eq!(s[1], 0.02 * ddx);
/// assert!(!plant.is_terminal(&s));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClassicCartPole {
    params: ClassicCartPoleParams,
    total_mass: f64,
    polemass_length: f64,
}

impl ClassicCartPole {
    /// A plant from validated parameters.
    ///
    /// # Errors
    /// [`PlantError::InvalidParameter`] naming the offending field (NaN, infinite, or not
    /// positive).
    pub fn new(params: ClassicCartPoleParams) -> Result<Self, PlantError> {
        params.validate()?;
        Ok(Self {
            params,
            total_mass: params.masspole + params.masscart,
            polemass_length: params.masspole * params.length,
        })
    }

    /// Gymnasium's `CartPole-v1` ([`ClassicCartPoleParams::gymnasium`]).
    pub fn gymnasium() -> Self {
        match Self::new(ClassicCartPoleParams::gymnasium()) {
            Ok(p) => p,
            Err(_) => unreachable!("Gymnasium's cart-pole parameters are valid"),
        }
    }

    /// The parameters.
    pub fn params(&self) -> &ClassicCartPoleParams {
        &self.params
    }

    /// The force \[N\] of a discrete action: `+force_mag` for 1, `−force_mag` otherwise
    /// (Gymnasium's `force_mag if action == 1 else -force_mag`).
    pub fn force(&self, action: u8) -> f64 {
        if action == 1 {
            self.params.force_mag
        } else {
            -self.params.force_mag
        }
    }

    /// `ṡ = [ẋ, ẍ, θ̇, θ̈]` at state `s = [x, ẋ, θ, θ̇]` under the force `force` \[N\]
    /// (the module documentation's equations, in Gymnasium's order of operations).
    #[inline(always)]
    pub fn derivative(&self, s: &[f64; 4], force: f64) -> [f64; 4] {
        let p = &self.params;
        let (x_dot, theta, theta_dot) = (s[1], s[2], s[3]);
        let costheta = theta.cos();
        let sintheta = theta.sin();
        let temp =
            (force + self.polemass_length * (theta_dot * theta_dot) * sintheta) / self.total_mass;
        let thetaacc = (p.gravity * sintheta - costheta * temp)
            / (p.length * (4.0 / 3.0 - p.masspole * (costheta * costheta) / self.total_mass));
        let xacc = temp - self.polemass_length * thetaacc * costheta / self.total_mass;
        [x_dot, xacc, theta_dot, thetaacc]
    }

    /// One step of `τ` under the force `force` \[N\] by the configured integrator.
    #[inline(always)]
    pub fn step_force(&self, s: &[f64; 4], force: f64) -> [f64; 4] {
        let tau = self.params.tau;
        let [_, xacc, _, thetaacc] = self.derivative(s, force);
        let [x, x_dot, theta, theta_dot] = *s;
        match self.params.integrator {
            CartPoleIntegrator::Euler => [
                x + tau * x_dot,
                x_dot + tau * xacc,
                theta + tau * theta_dot,
                theta_dot + tau * thetaacc,
            ],
            CartPoleIntegrator::SemiImplicitEuler => {
                let x_dot = x_dot + tau * xacc;
                let theta_dot = theta_dot + tau * thetaacc;
                [x + tau * x_dot, x_dot, theta + tau * theta_dot, theta_dot]
            }
        }
    }

    /// One step of `τ` under a discrete action (1 pushes right, anything else left;
    /// [`ClassicCartPole::force`]).
    #[inline(always)]
    pub fn step(&self, s: &[f64; 4], action: u8) -> [f64; 4] {
        self.step_force(s, self.force(action))
    }

    /// `true` when the episode ends at `s`: `x < −x_threshold`, `x > x_threshold`,
    /// `θ < −θ_threshold` or `θ > θ_threshold` (Gymnasium's four comparisons, so a NaN
    /// component, for which all are false, does not end the episode there either).
    #[inline(always)]
    pub fn is_terminal(&self, s: &[f64; 4]) -> bool {
        let p = &self.params;
        s[0] < -p.x_threshold
            || s[0] > p.x_threshold
            || s[2] < -p.theta_threshold
            || s[2] > p.theta_threshold
    }
}
