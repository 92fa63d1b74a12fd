//! The cart-type inverted pendulum (cdip), book §3.1 (the model, parameters and conventions
//! in the project's words: `docs/model.md` §1).
//!
//! # Model
//! The cart (position `z`, metres) is driven by a DC motor through a belt; the pendulum
//! (angle `θ` from the **upward** vertical, radians, positive towards `+z`) swings freely on a
//! pivot on the cart. With `J = J_p + m_p l_p²` the inertia about the pivot:
//!
//! ```text
//! z̈ = −a_c ż + b_c v                                   (drive, eq. 3.21)
//! J θ̈ + m_p l_p cos θ · z̈ = m_p g l_p sin θ − μ_p θ̇    (pendulum, eq. 3.7)
//! ```
//!
//! State `x = [z, θ, ż, θ̇]`, input `u = v` (volts).
//!
//! # Derivation (Euler–Lagrange)
//! The pendulum's centre of mass is at `(z + l_p sin θ, l_p cos θ)`, so its velocity is
//! `(ż + l_p cos θ θ̇, −l_p sin θ θ̇)` and
//!
//! ```text
//! T = ½ M ż² + ½ m_p ((ż + l_p cos θ θ̇)² + (l_p sin θ θ̇)²) + ½ J_p θ̇²
//!   = ½ (M + m_p) ż² + m_p l_p cos θ ż θ̇ + ½ J θ̇²,
//! V = m_p g l_p cos θ,   D = ½ μ_p θ̇²  (Rayleigh dissipation of the pivot).
//! ```
//!
//! `d/dt ∂L/∂θ̇ − ∂L/∂θ + ∂D/∂θ̇ = 0` with `L = T − V` gives
//! `J θ̈ + m_p l_p cos θ z̈ − m_p l_p sin θ ż θ̇ + m_p l_p sin θ ż θ̇ − m_p g l_p sin θ + μ_p θ̇ = 0`,
//! the pendulum equation above (the `ż θ̇` terms cancel). The cart's own Euler–Lagrange
//! equation (with the motor force) is replaced by the identified drive law: the motor's
//! current loop makes the cart an acceleration source, the pendulum's reaction force is part
//! of what `a_c, b_c` describe. `tools/reference/plants_lagrange.py` repeats this derivation
//! with SymPy; the tests compare the two.
//!
//! # Energy
//! `E = ½ J θ̇² + m_p g l_p (1 + cos θ)` (0 hanging at rest, `2 m_p g l_p` upright at rest) is
//! the pendulum's energy in the frame moving with the cart. Along solutions
//! `dE/dt = −m_p l_p cos θ θ̇ z̈ − μ_p θ̇²`: the cart's acceleration pumps energy in, friction
//! takes it out (the basis of the swing-up of book part 2 ch. 3).
//!
//! This file holds the physics (parameters, state, equilibria, the plant, its linearisation
//! and energy) and the general [`Dynamics`] implementation; the fast paths' kernels for this
//! plant (the fixed-size and lane kernels' steps, the anchored-trig RK4 step and the kernel
//! type [`fast::FastCart`] that carries a sine/cosine strategy) are in [`fast`].

use pendulab_lti::{Continuous, Mat, StateSpace};
use pendulab_sim::Dynamics;

use crate::drive::Drive;
use crate::error::{PlantError, Requirement, check, check_point};
use crate::fixed_cart::FixedCartPendulum;
use crate::linear::{Jacobian, Posture, selection_matrix};
use crate::pendulum::{PendulumParams, PivotPendulum};

pub mod fast;

const MODEL: &str = "cart pendulum";

/// The physical parameters of the cart-type pendulum (book table 3.5).
///
/// Plain data: build a plant from it with [`CartPendulum::new`], which validates every field.
/// Field names follow the book's symbols.
///
/// ```
/// use pendulab_plants::{CartPendulum, CartPendulumParams};
/// // The book's rig with a 20 % heavier pendulum.
/// let p = CartPendulumParams { m_p: 1.2 * 0.107, ..CartPendulumParams::book() };
/// let plant = CartPendulum::new(p).unwrap();
/// assert!(plant.inertia_about_pivot() > CartPendulum::book().inertia_about_pivot());
/// ```
#[allow(non_snake_case)]
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CartPendulumParams {
    /// Velocity pole of the cart drive `a_c` \[1/s\] (≥ 0).
    pub a_c: f64,
    /// Gain of the cart drive `b_c` \[m/(s² V)\] (> 0).
    pub b_c: f64,
    /// Pendulum mass `m_p` \[kg\] (> 0).
    pub m_p: f64,
    /// Pivot to centre of mass `l_p` \[m\] (> 0).
    pub l_p: f64,
    /// Drawing length `L_p` (pivot to tip) \[m\] (> 0); geometry only.
    pub L_p: f64,
    /// Moment of inertia about the centre of mass `J_p` \[kg m²\] (> 0).
    pub J_p: f64,
    /// Viscous friction of the pivot `μ_p` \[N m s/rad\] (≥ 0; 0 removes friction).
    pub mu_p: f64,
    /// Gravitational acceleration `g` \[m/s²\] (> 0).
    pub g: f64,
}

impl CartPendulumParams {
    /// The book's rig (table 3.5): `a_c = 6.25 1/s`, `b_c = 4.36 m/(s² V)`, `m_p = 0.107 kg`,
    /// `l_p = 0.230 m`, `L_p = 0.380 m`, `J_p = 1.59·10⁻³ kg m²`,
    /// `μ_p = 2.35·10⁻⁴ N m s/rad`, `g = 9.81 m/s²`.
    pub const fn book() -> Self {
        Self {
            a_c: 6.25,
            b_c: 4.36,
            m_p: 0.107,
            l_p: 0.230,
            L_p: 0.380,
            J_p: 1.59e-3,
            mu_p: 2.35e-4,
            g: 9.81,
        }
    }

    /// Checks every field against the requirement written on it.
    ///
    /// # Errors
    /// [`PlantError::InvalidParameter`] naming the first offending parameter and its value.
    pub fn validate(&self) -> Result<(), PlantError> {
        check(MODEL, "a_c", self.a_c, Requirement::NonNegative)?;
        check(MODEL, "b_c", self.b_c, Requirement::Positive)?;
        self.pendulum()
            .validate_named(MODEL, ["m_p", "l_p", "L_p", "J_p", "mu_p"])?;
        check(MODEL, "g", self.g, Requirement::Positive)
    }

    /// The pendulum's parameters on their own.
    pub fn pendulum(&self) -> PendulumParams {
        PendulumParams {
            m: self.m_p,
            l: self.l_p,
            L: self.L_p,
            J: self.J_p,
            mu: self.mu_p,
        }
    }

    /// `J = J_p + m_p l_p²` \[kg m²\], the inertia about the pivot.
    pub fn inertia_about_pivot(&self) -> f64 {
        self.J_p + self.m_p * self.l_p * self.l_p
    }
}

impl Default for CartPendulumParams {
    /// The book's rig, [`CartPendulumParams::book`].
    fn default() -> Self {
        Self::book()
    }
}

crate::state::named_state! {
    /// The state `x = [z, θ, ż, θ̇]` of the cart-type pendulum, named.
    ///
    /// Converts to and from `[f64; 4]` in that order (`From` both ways).
    pub struct CartPendulumState, "[z, θ, ż, θ̇]" {
        /// Cart position `z` \[m\].
        z,
        /// Pendulum angle `θ` from the upward vertical \[rad\] (`π`: hanging).
        theta,
        /// Cart velocity `ż` \[m/s\].
        dz,
        /// Pendulum angular velocity `θ̇` \[rad/s\].
        dtheta,
    }
}

impl CartPendulumState {
    /// The angle from the hanging position, `φ = θ − π` \[rad\] (book eq. 3.44; not wrapped).
    pub fn phi(&self) -> f64 {
        self.theta - std::f64::consts::PI
    }
}

/// An equilibrium of the cart-type pendulum: the cart at rest anywhere on the rail, the
/// pendulum at rest upright or hanging, `v = 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartEquilibrium {
    /// Cart position `z` \[m\] (the linear model does not depend on it).
    pub z: f64,
    /// Upright (`θ = 0`) or hanging (`θ = π`).
    pub posture: Posture,
}

impl CartEquilibrium {
    /// Upright at `z = 0`.
    pub const fn upright() -> Self {
        Self {
            z: 0.0,
            posture: Posture::Upright,
        }
    }

    /// Hanging at `z = 0`.
    pub const fn hanging() -> Self {
        Self {
            z: 0.0,
            posture: Posture::Hanging,
        }
    }

    /// The equilibrium state `[z, θ_e, 0, 0]`.
    pub fn state(&self) -> CartPendulumState {
        CartPendulumState::from_array([self.z, self.posture.angle(), 0.0, 0.0])
    }
}

/// Where the parts of the cart-type pendulum are, in metres, for drawing: `x` along the rail,
/// `y` up, origin at the pivot's height at `z = 0`.
///
/// `pendulab-plot`'s `Animation::cart` takes the `z` and `θ` series directly; its
/// `CartGeometry { pendulum_length: params.L_p, .. }` uses the same convention (tip at
/// `(z + L_p sin θ, L_p cos θ)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartPose {
    /// The pivot on the cart, `(z, 0)`.
    pub pivot: [f64; 2],
    /// The pendulum's centre of mass, `(z + l_p sin θ, l_p cos θ)`.
    pub centre_of_mass: [f64; 2],
    /// The pendulum's tip, `(z + L_p sin θ, L_p cos θ)`.
    pub tip: [f64; 2],
}

/// The cart-type pendulum with validated parameters: nonlinear dynamics, Jacobians,
/// linearisations at the upright and hanging equilibria, energy and geometry.
///
/// ```
/// use pendulab_plants::{CartEquilibrium, CartPendulum};
/// use pendulab_sim::Dynamics;
/// let plant = CartPendulum::book();
/// // Nonlinear: hanging at rest, 1 V on the motor accelerates the cart at b_c.
/// let f = plant.derivative_array(&[0.0, std::f64::consts::PI, 0.0, 0.0], 1.0);
/// assert_eq!(f[2], 4.36);
/// // Linear: the upright model, C = I.
/// let sys = plant.linearize(CartEquilibrium::upright()).unwrap();
/// assert_eq!((sys.nx(), sys.nu(), sys.ny()), (4, 1, 4));
/// assert_eq!((plant.nx(), plant.nu()), (4, 1));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartPendulum {
    params: CartPendulumParams,
    drive: Drive,
    pendulum: PivotPendulum,
}

impl CartPendulum {
    /// Indices of the states the rig measures (encoders): `y = [z, θ]`.
    pub const MEASURED_STATES: [usize; 2] = [0, 1];

    /// A plant from validated parameters.
    ///
    /// # Errors
    /// [`PlantError::InvalidParameter`] naming the offending parameter (NaN, infinite,
    /// non-positive mass, length, inertia, drive gain or `g`; negative friction or `a_c`);
    /// [`PlantError::DerivedQuantity`] if `J`, `m_p l_p` or `m_p g l_p` overflow.
    pub fn new(params: CartPendulumParams) -> Result<Self, PlantError> {
        params.validate()?;
        Ok(Self {
            params,
            drive: Drive::new(params.a_c, params.b_c)?,
            pendulum: PivotPendulum::new(&params.pendulum(), params.g, MODEL)?,
        })
    }

    /// The book's rig ([`CartPendulumParams::book`]).
    pub fn book() -> Self {
        match Self::new(CartPendulumParams::book()) {
            Ok(p) => p,
            // The book's values are finite and positive; this arm is unreachable.
            Err(_) => unreachable!("the book's cart-pendulum parameters are valid"),
        }
    }

    /// The parameters.
    pub fn params(&self) -> &CartPendulumParams {
        &self.params
    }

    /// The cart drive `z̈ = −a_c ż + b_c v` on its own.
    pub fn drive(&self) -> Drive {
        self.drive
    }

    /// `J = J_p + m_p l_p²` \[kg m²\].
    pub fn inertia_about_pivot(&self) -> f64 {
        self.pendulum.j
    }

    /// The same pendulum with the cart held fixed (book eqs 4.39–4.45).
    pub fn fixed_cart(&self) -> FixedCartPendulum {
        FixedCartPendulum::from_parts(self.pendulum)
    }

    /// `ẋ = f(x, v)` for `x = [z, θ, ż, θ̇]`: fixed-size and allocation-free, for hot loops.
    #[inline(always)]
    pub fn derivative_array(&self, x: &[f64; 4], v: f64) -> [f64; 4] {
        self.derivative_with(x, v, x[1].sin_cos())
    }

    /// The right-hand side with `(sin θ, cos θ)` given (the fast paths' kernels supply their
    /// own): the operations of [`CartPendulum::derivative_array`] after the sine and cosine.
    #[inline(always)]
    pub(crate) fn derivative_with(&self, x: &[f64; 4], v: f64, (s, c): (f64, f64)) -> [f64; 4] {
        let ddz = self.drive.acceleration(x[2], v);
        [x[2], x[3], ddz, self.pendulum.acceleration(s, c, x[3], ddz)]
    }

    /// The analytic Jacobian `A = ∂f/∂x`, `B = ∂f/∂v` at any point `(x, v)` (not only at
    /// equilibria). With `z̈ = −a_c ż + b_c v`:
    ///
    /// ```text
    /// ∂θ̈/∂θ = (m_p g l_p cos θ + m_p l_p sin θ z̈) / J,   ∂θ̈/∂ż = a_c m_p l_p cos θ / J,
    /// ∂θ̈/∂θ̇ = −μ_p / J,                                  ∂θ̈/∂v = −b_c m_p l_p cos θ / J.
    /// ```
    pub fn jacobian(&self, x: &[f64; 4], v: f64) -> Jacobian<4> {
        let ddz = self.drive.acceleration(x[2], v);
        let (s, c) = x[1].sin_cos();
        self.jacobian_from(s, c, ddz)
    }

    fn jacobian_from(&self, s: f64, c: f64, ddz: f64) -> Jacobian<4> {
        let (d_theta, d_dtheta, d_ddz) = self.pendulum.partials(s, c, ddz);
        let (a, b) = (self.drive.a(), self.drive.b());
        Jacobian {
            a: [
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
                [0.0, 0.0, -a, 0.0],
                [0.0, d_theta, -a * d_ddz, d_dtheta],
            ],
            b: [0.0, 0.0, b, b * d_ddz],
        }
    }

    /// The linearisation at an equilibrium, in deviation variables `δx = x − x_e`, `δv = v`,
    /// with `C = I`, `D = 0`. At the upright rest (book §3.1;
    /// `docs/model.md` §1; `J = J_p + m_p l_p²`):
    ///
    /// ```text
    /// A = [[0, 0, 1, 0], [0, 0, 0, 1], [0, 0, −a_c, 0], [0, m_p g l_p/J, a_c m_p l_p/J, −μ_p/J]],
    /// B = [0, 0, b_c, −b_c m_p l_p/J]ᵀ;
    /// ```
    ///
    /// hanging, the signs of the `m_p g l_p` and `m_p l_p` entries flip (`cos π = −1`) and
    /// `δθ = φ = θ − π`.
    ///
    /// # Errors
    /// [`PlantError::NonFiniteOperatingPoint`] if `eq.z` is not finite.
    pub fn linearize(&self, eq: CartEquilibrium) -> Result<StateSpace<Continuous>, PlantError> {
        self.equilibrium_jacobian(eq)?.to_state_space()
    }

    /// As [`CartPendulum::linearize`] with the measured outputs `y = [δz, δθ]`
    /// ([`CartPendulum::MEASURED_STATES`], `C = [[1, 0, 0, 0], [0, 1, 0, 0]]`).
    ///
    /// # Errors
    /// As [`CartPendulum::linearize`].
    pub fn linearize_measured(
        &self,
        eq: CartEquilibrium,
    ) -> Result<StateSpace<Continuous>, PlantError> {
        self.equilibrium_jacobian(eq)?
            .to_state_space_with_outputs(&Self::MEASURED_STATES)
    }

    /// The Jacobian at an equilibrium, with `sin θ_e = 0` and `cos θ_e = ±1` exactly.
    ///
    /// # Errors
    /// As [`CartPendulum::linearize`].
    pub fn equilibrium_jacobian(&self, eq: CartEquilibrium) -> Result<Jacobian<4>, PlantError> {
        check_point("z", eq.z)?;
        Ok(self.jacobian_from(0.0, eq.posture.cos(), 0.0))
    }

    /// `C = [[1, 0, 0, 0], [0, 1, 0, 0]]`: the rows picking the measured `z` and `θ`.
    pub fn measured_output_matrix() -> Mat {
        match selection_matrix(&Self::MEASURED_STATES, 4) {
            Ok(c) => c,
            Err(_) => unreachable!("indices 0 and 1 exist in a 4-state model"),
        }
    }

    /// The pendulum's energy `E = ½ J θ̇² + m_p g l_p (1 + cos θ)` \[J\] (see the module docs).
    pub fn energy(&self, x: &CartPendulumState) -> f64 {
        self.pendulum.energy(x.theta, x.dtheta)
    }

    /// The energy of the upright rest, `2 m_p g l_p` \[J\] (the swing-up target).
    pub fn upright_energy(&self) -> f64 {
        2.0 * self.pendulum.mgl
    }

    /// Positions of pivot, centre of mass and tip for drawing.
    pub fn pose(&self, x: &CartPendulumState) -> CartPose {
        let (s, c) = x.theta.sin_cos();
        let (l, big_l) = (self.params.l_p, self.params.L_p);
        CartPose {
            pivot: [x.z, 0.0],
            centre_of_mass: [x.z + l * s, l * c],
            tip: [x.z + big_l * s, big_l * c],
        }
    }
}

impl Dynamics for CartPendulum {
    fn nx(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    // Forced inline: the RK4 stages of the loops and the environment's step then see the
    // arithmetic (a call per stage costs ~15 % of the step).
    #[inline(always)]
    fn derivative(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        debug_assert!(x.len() == 4 && u.len() == 1 && dx.len() == 4);
        let f = self.derivative_array(&[x[0], x[1], x[2], x[3]], u[0]);
        dx[..4].copy_from_slice(&f);
    }
}
