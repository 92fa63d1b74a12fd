//! The cart-type inverted pendulum (cdip), SPEC §1.1 and book §3.1.
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

use pendulab_lti::{Continuous, Mat, StateSpace};
use pendulab_sim::Dynamics;
use pendulab_sim::fixed::{MulAdd, Separate};
use pendulab_sim::lanes::{
    COS_TAYLOR, ROTATE_LIMIT, SIN_TAYLOR, Trig, rotate_small, sin_cos_near_zero, sin_cos_offset,
};

use crate::drive::Drive;
use crate::error::{PlantError, Requirement, check, check_point};
use crate::fixed_cart::FixedCartPendulum;
use crate::linear::{Jacobian, Posture, selection_matrix};
use crate::pendulum::{PendulumParams, PivotPendulum};

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
#[derive(Debug, Clone, Copy, PartialEq)]
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

/// The state `x = [z, θ, ż, θ̇]` of the cart-type pendulum, named.
///
/// Converts to and from `[f64; 4]` in that order (`From` both ways).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CartPendulumState {
    /// Cart position `z` \[m\].
    pub z: f64,
    /// Pendulum angle `θ` from the upward vertical \[rad\] (`π`: hanging).
    pub theta: f64,
    /// Cart velocity `ż` \[m/s\].
    pub dz: f64,
    /// Pendulum angular velocity `θ̇` \[rad/s\].
    pub dtheta: f64,
}

impl CartPendulumState {
    /// The state as `[z, θ, ż, θ̇]`.
    pub fn to_array(self) -> [f64; 4] {
        [self.z, self.theta, self.dz, self.dtheta]
    }

    /// The state from `[z, θ, ż, θ̇]`.
    pub fn from_array(x: [f64; 4]) -> Self {
        Self {
            z: x[0],
            theta: x[1],
            dz: x[2],
            dtheta: x[3],
        }
    }

    /// The angle from the hanging position, `φ = θ − π` \[rad\] (book eq. 3.44; not wrapped).
    pub fn phi(&self) -> f64 {
        self.theta - std::f64::consts::PI
    }

    /// `true` if every component is finite.
    pub fn is_finite(&self) -> bool {
        self.to_array().iter().all(|v| v.is_finite())
    }
}

impl From<[f64; 4]> for CartPendulumState {
    fn from(x: [f64; 4]) -> Self {
        Self::from_array(x)
    }
}

impl From<CartPendulumState> for [f64; 4] {
    fn from(s: CartPendulumState) -> Self {
        s.to_array()
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
        CartPendulumState {
            z: self.z,
            theta: self.posture.angle(),
            dz: 0.0,
            dtheta: 0.0,
        }
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
    trig: Trig,
}

impl CartPendulum {
    /// Indices of the states the rig measures (encoders): `y = [z, θ]`.
    pub const MEASURED_STATES: [usize; 2] = [0, 1];

    /// [`Trig::Anchored`]: the largest `|θ|` \[rad\] at the start of an RK4 step whose sine and
    /// cosine come from a series (beyond it: libm). The CartPole-v1 environment's angles,
    /// |θ| ≤ 12° = 0.21 rad, lie within it.
    pub const ANCHORED_ANGLE_LIMIT: f64 = 0.25;

    /// [`Trig::Anchored`]: the largest stage offset `|d|` \[rad\] (`(h/2)·θ̇` or `h·θ̇`) whose
    /// sine and cosine come from the step's first ones by the addition theorem (beyond it:
    /// libm at the stage angle). A step of `h = 20 ms` stays within it up to |θ̇| = 6.25 rad/s.
    pub const ANCHORED_SHIFT_LIMIT: f64 = 0.125;

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
            trig: Trig::Libm,
        })
    }

    /// The same plant with its right-hand side ([`CartPendulum::derivative_array`] and the
    /// [`Dynamics`] implementation) evaluating `sin θ, cos θ` by `trig`.
    ///
    /// The default is [`Trig::Libm`] (`f64::sin_cos`). [`Trig::Polynomial`] is an opt-in for
    /// hot loops such as reinforcement-learning environments: about 45 fewer instructions per
    /// right-hand side (of ~140), every sine and cosine within 2 ulp + 4·10⁻¹⁷·max(1, |θ|)
    /// of libm for `|θ| ≤ 10⁵` (libm beyond), so `θ̈` differs from the libm plant's by a
    /// few ulp of its terms (see [`Trig`]); simulations are then not bit-identical to
    /// libm-based references. [`Trig::Anchored`] changes only the RK4 step of the
    /// fixed-size closed-loop kernel (`pendulab_sim::fixed`, e.g. `SampledLoop::fixed`) and
    /// of `pendulab_sim::env::FixedEnv`: the stages share their sines and cosines — series
    /// near upright (within [`CartPendulum::ANCHORED_ANGLE_LIMIT`]) for the angles fixed by
    /// the step's start, the addition theorem for what the later stages add — each within
    /// 2 ulp + 6·10⁻¹⁷ of libm for steps of at most 2⁻⁸ s (whose step uses fused
    /// multiply–adds where the kernel's FMA-compiled loop runs it), 2 ulp + 1.1·10⁻¹⁶ for
    /// longer ones, and the pendulum's constants are divided by `J` beforehand. In the 1 ms
    /// loop of the `sim-rk4` bench that is about 270 (FMA-compiled loop) or 370 (baseline
    /// loop) instructions per step instead of 610 to 630 with libm (callgrind, loop and
    /// recording included). Every other evaluation of this plant uses libm; Jacobians,
    /// linearisations, energy and geometry always do.
    pub fn with_trig(mut self, trig: Trig) -> Self {
        self.trig = trig;
        self
    }

    /// How the right-hand side evaluates `sin θ, cos θ` ([`CartPendulum::with_trig`]).
    pub fn trig(&self) -> Trig {
        self.trig
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
        let ddz = self.drive.acceleration(x[2], v);
        let (s, c) = self.trig.sin_cos(x[1]);
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
    /// with `C = I`, `D = 0`. At the upright rest (SPEC §1.1, `J = J_p + m_p l_p²`):
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

/// The right-hand side on arrays for the fixed-size closed-loop kernel
/// ([`pendulab_sim::fixed`]): the operations of [`CartPendulum::derivative_array`], which the
/// [`Dynamics`] implementation also evaluates, so the kernel reproduces `SampledLoop` bit for
/// bit — except with [`Trig::Anchored`], whose RK4 step evaluates its sines and cosines by
/// series near upright and shares work between the stages, with the pendulum's constants
/// divided by `J` beforehand. Two variants, by the step length:
///
/// - steps of at most 2⁻⁸ s (the 1 ms loops): `narrow_anchored_step`, written once for both
///   multiply–adds of [`FixedDynamics::rk4_step_fixed_with`](pendulab_sim::fixed::FixedDynamics::rk4_step_fixed_with)
///   (the kernel's FMA-compiled loop takes it with fused multiply–adds): series sines and
///   cosines at three angles fixed by the step's start, the third and fourth stages'
///   accelerations by a rotation through the small offsets their angles add, and every
///   stage's θ̇-dependence folded into one multiply–add; each sine and cosine within
///   1.5 ulp + 2.5·10⁻¹⁷ of libm's at its angle, the rotations within 1.5 ulp of theirs
///   (see there);
/// - longer steps (e.g. the 20 ms of the CartPole-v1 environment,
///   `pendulab_sim::env::FixedEnv`, whose angles up to 12° and stage offsets `(h/2)·θ̇`,
///   `h·θ̇` mostly exceed 1/32): `anchored_step`, the first angle's sine and cosine by one
///   series within [`CartPendulum::ANCHORED_ANGLE_LIMIT`] of upright (`wide_angle_series`)
///   and the later stages' from them by the addition theorem with `wide_shift_series` for
///   offsets up to [`CartPendulum::ANCHORED_SHIFT_LIMIT`] (libm beyond), within
///   2 ulp + 6·10⁻¹⁷ and 2 ulp + 1.1·10⁻¹⁶ of libm's. One series rather than tiers,
///   because an episode's random angles would mispredict the choice between tiers about
///   every third step (measured: 52 against 60 ns per environment step). This variant
///   always uses separate multiplications and additions.
impl pendulab_sim::fixed::FixedDynamics<4> for CartPendulum {
    #[inline(always)]
    fn derivative_fixed(&self, x: &[f64; 4], u: f64) -> [f64; 4] {
        // The body of `derivative_array`, forced inline into the kernel's RK4 stages.
        let ddz = self.drive.acceleration(x[2], u);
        let (s, c) = self.trig.sin_cos(x[1]);
        [x[2], x[3], ddz, self.pendulum.acceleration(s, c, x[3], ddz)]
    }

    /// The operations of [`pendulab_sim::fixed::rk4_fixed`], the sines and cosines aside;
    /// with [`Trig::Anchored`] the anchored step with separate multiplications and additions.
    #[inline(always)]
    fn rk4_step_fixed(&self, x: &mut [f64; 4], u: f64, h: f64) {
        self.rk4_step_fixed_with::<Separate>(x, u, h);
    }

    /// As [`pendulab_sim::fixed::FixedDynamics::rk4_step_fixed`]; with [`Trig::Anchored`]
    /// and steps of at most 2⁻⁸ s, the multiply–adds of the anchored step by `F`.
    #[inline(always)]
    fn rk4_step_fixed_with<F: MulAdd>(&self, x: &mut [f64; 4], u: f64, h: f64) {
        if self.trig != Trig::Anchored {
            return pendulab_sim::fixed::rk4_fixed(self, x, u, h);
        }
        if h <= NARROW_STEP_LIMIT {
            *x = self.narrow_anchored_step::<F>(x, u, h);
        } else {
            let theta = x[1];
            let (s, c) = anchor_sin_cos(theta);
            *x = self.anchored_step(x, u, h, (s, c), |d| stage_sin_cos(theta, d, s, c));
        }
    }
}

/// Steps up to this length (s) take `narrow_anchored_step` (its stage offsets stay within
/// the rotation's range for accelerations up to `2⁻¹⁴/(h²/2)`, 122 rad/s² at 1 ms); longer
/// ones `anchored_step` with the wide series (see the `FixedDynamics` implementation).
const NARROW_STEP_LIMIT: f64 = 1.0 / 256.0;

const WIDE_ANGLE_LIMIT: f64 = CartPendulum::ANCHORED_ANGLE_LIMIT;
const WIDE_SHIFT_LIMIT: f64 = CartPendulum::ANCHORED_SHIFT_LIMIT;

/// The sine and cosine of an anchored RK4 step's first angle for steps longer than 2⁻⁸ s:
/// [`wide_angle_series`] for `|θ| ≤` [`WIDE_ANGLE_LIMIT`], libm beyond (and for NaN); within
/// 2 ulp + 6·10⁻¹⁷ of libm (checked in this module's tests over the whole range). One series
/// for the whole range: the random angles of an environment's episodes would mispredict the
/// choice between narrower series about every third step.
#[inline(always)]
fn anchor_sin_cos(theta: f64) -> (f64, f64) {
    if theta.abs() <= WIDE_ANGLE_LIMIT {
        wide_angle_series(theta)
    } else {
        theta.sin_cos()
    }
}

/// `(sin(θ + d), cos(θ + d))` of an RK4 stage angle from `(s, c) = (sin θ, cos θ)` for steps
/// longer than 2⁻⁸ s: the addition theorem of [`sin_cos_offset`] with
/// [`wide_shift_series`] for `|d| ≤` [`WIDE_SHIFT_LIMIT`] (one series for the whole range,
/// as [`anchor_sin_cos`]), libm's `(θ + d).sin_cos()` beyond (and for NaN).
#[inline(always)]
fn stage_sin_cos(theta: f64, d: f64, s: f64, c: f64) -> (f64, f64) {
    if d.abs() <= WIDE_SHIFT_LIMIT {
        let (sd, cm1) = wide_shift_series(d);
        (s + (s * cm1 + c * sd), c + (c * cm1 - s * sd))
    } else {
        (theta + d).sin_cos()
    }
}

/// `(sin x, cos x)` for `|x| ≤ 1/4` by their Taylor series to `x¹¹` and `x¹²` (the first
/// omitted terms, `x¹³/13! < 2.5·10⁻¹⁸` and `x¹⁴/14! < 5·10⁻²⁰`, are far below half an ulp),
/// the polynomials in `z = x²` evaluated in Estrin's pairing: `sin x = x + x·z·P(z)`,
/// `cos x = 1 + z·Q(z)`. The correction terms are at most `x³/6 < 2.7·10⁻³` and
/// `x²/2 ≤ 1/32`, so their few roundings cost ≲ 2·10⁻¹⁷ and the final addition half an ulp.
#[inline(always)]
fn wide_angle_series(x: f64) -> (f64, f64) {
    const S: [f64; 5] = SIN_TAYLOR;
    const C: [f64; 6] = COS_TAYLOR;
    let z = x * x;
    let z2 = z * z;
    let p = (S[0] + S[1] * z) + z2 * ((S[2] + S[3] * z) + S[4] * z2);
    let q = (C[0] + C[1] * z) + z2 * ((C[2] + C[3] * z) + z2 * (C[4] + C[5] * z));
    (x + (x * z) * p, 1.0 + z * q)
}

/// `(sin d, cos d − 1)` for `|d| ≤ 1/8` by their Taylor series to `d⁹` and `d¹⁰` (the first
/// omitted terms, `d¹¹/11! < 3·10⁻¹⁸` and `d¹²/12! < 2·10⁻²⁰`), Estrin's pairing in `z = d²`;
/// as the series of `pendulab_sim::lanes::sin_cos_offset` with two more terms each.
#[inline(always)]
fn wide_shift_series(d: f64) -> (f64, f64) {
    // The first four and five coefficients.
    const S: [f64; 5] = SIN_TAYLOR;
    const C: [f64; 6] = COS_TAYLOR;
    let z = d * d;
    let z2 = z * z;
    let p = (S[0] + S[1] * z) + z2 * (S[2] + S[3] * z);
    let q = (C[0] + C[1] * z) + z2 * ((C[2] + C[3] * z) + C[4] * z2);
    (d + (d * z) * p, z * q)
}

impl CartPendulum {
    /// One classic RK4 step of [`Trig::Anchored`] for steps of at most 2⁻⁸ s, with the
    /// multiply–adds `a·b + c` of `F`. With `x = [z, θ, v, ω]` (`v = ż`, `ω = θ̇`),
    /// `G = m_p g l_p/J`, `M = μ_p/J`, `L = m_p l_p/J`, `α = a_c`, `β = b_c` and the stage
    /// values of RK4 (`v_k`, `ω_k`, `θ_k` the stage states, `a_k = z̈`, `b_k = θ̈` their
    /// derivatives), the stages substituted into one another give
    ///
    /// ```text
    /// a₁ = βu − αv,        a₂ = a₁ − α(h/2)a₁,   a₃ = a₁ − α(h/2)a₂,   a₄ = a₁ − αh·a₃
    /// b₁ = G sin θ − Mω − L cos θ · a₁
    /// b₂ = (G sin θ₂ − Mω − L cos θ₂ · a₂) − M(h/2)·b₁,               θ₂ = θ + (h/2)ω
    /// b₃ = (G sin θ₃ − Mω − L cos θ₃ · a₃) − M(h/2)·b₂,   θ₃ = θ₂ + e₃,  e₃ = (h²/4)·b₁
    /// b₄ = (G sin θ₄ − Mω − L cos θ₄ · a₄) − Mh·b₃,       θ₄ = θ₄' + e₄, e₄ = (h²/2)·b₂,
    ///                                                      θ₄' = θ + hω
    /// z' = (z + hv) + (h²/6)·(a₁ + a₂ + a₃),   θ' = θ₄' + (h²/6)·(b₁ + b₂ + b₃)
    /// v' = v + (h/6)·((a₁ + a₄) + 2(a₂ + a₃)),  ω' = (ω + (h/6)·(b₁ + 2b₂ + 2b₃)) + (h/6)·b₄
    /// ```
    ///
    /// (the damping `−Mω_k = −Mω − M·c_k h·b_{k−1}` folded into one multiply–add per stage;
    /// `v_k`, `ω_k` never formed). The sines and cosines of the three angles fixed by the
    /// step's start, `θ`, `θ₂` and `θ₄'` (each rounded once with [`Fused`](pendulab_sim::fixed::Fused), twice
    /// with [`Separate`] — as the general loop rounds `θ₂`), come from
    /// [`sin_cos_near_zero`] (series within 1/4 rad of upright, libm beyond), each within
    /// 1.5 ulp + 2.5·10⁻¹⁷ of libm's, off the chain that runs through `u` and `θ̈`. The third
    /// and fourth stages' angles add `e = e₃, e₄` (|e| ~ 10⁻⁵ at 1 ms), and by the addition
    /// theorem `G sin(θ_b + e) − L a cos(θ_b + e) = P cos e + Q sin e` with
    /// `P = G sin θ_b − L a cos θ_b`, `Q = G cos θ_b + L a sin θ_b`, so their accelerations are
    /// [`rotate_small`]`(P, Q, e, −Mω)`: three operations after `e` instead of a stage sine
    /// and cosine and the products after them. It is within 1.5 ulp + 6·10⁻¹⁹·(|P| + |Q|) of
    /// the exact rotation for `|e| ≤` [`ROTATE_LIMIT`] (2⁻¹⁴); larger offsets (|θ̈| above
    /// 244 or 122 rad/s² at 1 ms) and NaN take the stage sine and cosine from
    /// [`sin_cos_offset`] instead. Every stage's acceleration is thus that of sines and
    /// cosines within 1.5 ulp + 2.5·10⁻¹⁷ of libm's at the stage angle (up to the rounding of
    /// the base angle, half an ulp of `θ` or two), plus a few roundings of its terms.
    #[inline(always)]
    fn narrow_anchored_step<F: MulAdd>(&self, x: &[f64; 4], u: f64, h: f64) -> [f64; 4] {
        let ma = F::mul_add;
        let [z, theta, v, w] = *x;
        let (alpha, beta) = (self.drive.a(), self.drive.b());
        let (g, m, l) = (self.pendulum.mgl_j, self.pendulum.mu_j, self.pendulum.ml_j);
        let h2 = 0.5 * h;
        let hq = h2 * h2;
        let hh = hq + hq;
        let h6 = h * (1.0 / 6.0);
        let hs = h * h6;
        let (ah2, mh2) = (alpha * h2, m * h2);
        // The three angles fixed by the step's start (off the chain through `u`).
        let (s1, c1) = sin_cos_near_zero::<F>(theta);
        let theta2 = ma(h2, w, theta);
        let (s2, c2) = sin_cos_near_zero::<F>(theta2);
        let theta4 = ma(h, w, theta);
        let (s4, c4) = sin_cos_near_zero::<F>(theta4);
        let mw = m * w;
        // Stages 1 and 2.
        let a1 = ma(beta, u, -(alpha * v));
        let b1 = ma(-(l * c1), a1, ma(g, s1, -mw));
        let a2 = ma(-ah2, a1, a1);
        let (gs2, lc2) = (g * s2, l * c2);
        let b2 = ma(-mh2, b1, ma(-lc2, a2, gs2 - mw));
        // Stage 3: the acceleration at θ₂ rotated by e₃.
        let a3 = ma(-ah2, a2, a1);
        let e3 = hq * b1;
        let k3 = if e3.abs() <= ROTATE_LIMIT {
            let p = ma(-lc2, a3, gs2);
            let q = ma(l * s2, a3, g * c2);
            rotate_small::<F>(p, q, e3, -mw)
        } else {
            let (s3, c3) = sin_cos_offset(theta2, e3, s2, c2);
            ma(-(l * c3), a3, ma(g, s3, -mw))
        };
        let b3 = ma(-mh2, b2, k3);
        // Stage 4: the acceleration at θ + hω rotated by e₄.
        let a4 = ma(-(ah2 + ah2), a3, a1);
        let e4 = hh * b2;
        let k4 = if e4.abs() <= ROTATE_LIMIT {
            let p = ma(-(l * c4), a4, g * s4);
            let q = ma(l * s4, a4, g * c4);
            rotate_small::<F>(p, q, e4, -mw)
        } else {
            let (s4e, c4e) = sin_cos_offset(theta4, e4, s4, c4);
            ma(-(l * c4e), a4, ma(g, s4e, -mw))
        };
        let b4 = ma(-(mh2 + mh2), b3, k4);
        // The four updates in different shapes: alike ones would be paired into vector
        // registers, which makes z wait for θ (measured: the controller's sum, which starts
        // with z, then sits on the chain).
        [
            ma(h, v, z) + hs * ((a1 + a2) + a3),
            ma(hs, (b1 + b2) + b3, theta4),
            ma(h6, (a1 + a4) + 2.0 * (a2 + a3), v),
            ma(h6, b4, ma(h6, (b1 + 2.0 * b2) + 2.0 * b3, w)),
        ]
    }

    /// One RK4 step of [`Trig::Anchored`] for steps longer than 2⁻⁸ s (the operations of
    /// [`pendulab_sim::fixed::rk4_fixed`] with the pendulum's constants divided by `J`
    /// beforehand and the last stage's term added last), given `(s, c)`, the sine and cosine
    /// of the step's first angle `θ` ([`anchor_sin_cos`]: a series near upright, libm
    /// beyond); `shift(d)` returns those of a stage angle `θ + d` ([`stage_sin_cos`]) for the
    /// offsets
    /// themselves, `d = (h/2)·θ̇₁, (h/2)·θ̇₂, h·θ̇₃` — never recovered from a rounded angle,
    /// which keeps the round trip `(θ + d) − θ` off the step's dependency chain. The later
    /// offsets are formed as `(h/2)·x₃ + (h/2)²·k₁` and `h·x₃ + (h²/2)·k₂` (`k` the stages'
    /// `θ̈`) rather than from the stage's `θ̇`: one operation less on the chain (3 % per 1 ms
    /// loop step, measured), the same offset to an ulp of it.
    #[inline(always)]
    fn anchored_step(
        &self,
        x: &[f64; 4],
        u: f64,
        h: f64,
        (s, c): (f64, f64),
        shift: impl Fn(f64) -> (f64, f64),
    ) -> [f64; 4] {
        let f = |dz: f64, dth: f64, (s, c): (f64, f64)| {
            let ddz = self.drive.acceleration(dz, u);
            (ddz, self.pendulum.acceleration_prescaled(s, c, dth, ddz))
        };
        let half = 0.5 * h;
        let (quarter, hh) = (half * half, h * half);
        let (dz1, dth1) = (x[2], x[3]);
        let (hx, hhx) = (half * dth1, h * dth1);
        let (a1, b1) = f(dz1, dth1, (s, c));
        let (dz2, dth2) = (x[2] + half * a1, x[3] + half * b1);
        let (a2, b2) = f(dz2, dth2, shift(hx));
        let (dz3, dth3) = (x[2] + half * a2, x[3] + half * b2);
        let (a3, b3) = f(dz3, dth3, shift(hx + quarter * b1));
        let (dz4, dth4) = (x[2] + h * a3, x[3] + h * b3);
        let (a4, b4) = f(dz4, dth4, shift(hhx + hh * b2));
        let sixth = h / 6.0;
        // The last stage's term added last and on its own (one operation less after it).
        [
            (x[0] + sixth * (dz1 + 2.0 * dz2 + 2.0 * dz3)) + sixth * dz4,
            (x[1] + sixth * (dth1 + 2.0 * dth2 + 2.0 * dth3)) + sixth * dth4,
            (x[2] + sixth * (a1 + 2.0 * a2 + 2.0 * a3)) + sixth * a4,
            (x[3] + sixth * (b1 + 2.0 * b2 + 2.0 * b3)) + sixth * b4,
        ]
    }
}

/// The right-hand side for `L` states at once (structure of arrays) for
/// [`pendulab_sim::lanes`]: the same operations as [`CartPendulum::derivative_array`], in the
/// same order, per lane, with the sines and cosines from `M`.
impl<const L: usize> pendulab_sim::lanes::LaneDynamics<4, L> for CartPendulum {
    #[inline(always)]
    fn derivative_lanes<M: pendulab_sim::lanes::SinCos>(
        &self,
        x: &[[f64; L]; 4],
        u: &[f64; L],
    ) -> [[f64; L]; 4] {
        let (s, c) = M::sin_cos(&x[1]);
        let mut ddz = [0.0; L];
        let mut ddtheta = [0.0; L];
        for l in 0..L {
            ddz[l] = self.drive.acceleration(x[2][l], u[l]);
            ddtheta[l] = self.pendulum.acceleration(s[l], c[l], x[3][l], ddz[l]);
        }
        [x[2], x[3], ddz, ddtheta]
    }

    /// With `M::ANCHORED` (`pendulab_sim::lanes::AnchoredSinCos`), the lane form of the
    /// [`Trig::Anchored`] step (`anchored_step`): the step's first sines and cosines by
    /// `M`, the later stages' from them for the stages' offsets
    /// ([`pendulab_sim::lanes::sin_cos_offset_lanes`]), the pendulum's constants divided by
    /// `J` beforehand. If a stage offset of any lane is beyond the series' range, the whole
    /// step is taken by [`pendulab_sim::lanes::rk4_lanes`] instead. Other `M`: that plain step.
    #[inline(always)]
    fn rk4_step_lanes<M: pendulab_sim::lanes::SinCos>(
        &self,
        x: &mut [[f64; L]; 4],
        u: &[f64; L],
        h: &[f64; L],
    ) {
        if M::ANCHORED
            && let Some(next) = self.anchored_step_lanes::<M, L>(x, u, h)
        {
            *x = next;
            return;
        }
        pendulab_sim::lanes::rk4_lanes::<Self, M, 4, L>(self, x, u, h);
    }
}

impl CartPendulum {
    /// [`CartPendulum::anchored_step`] for `L` lanes; `None` when a stage offset is out of
    /// the series' range in some lane.
    #[inline(always)]
    fn anchored_step_lanes<M: pendulab_sim::lanes::SinCos, const L: usize>(
        &self,
        x: &[[f64; L]; 4],
        u: &[f64; L],
        h: &[f64; L],
    ) -> Option<[[f64; L]; 4]> {
        use pendulab_sim::lanes::sin_cos_offset_lanes;
        use std::array::from_fn;
        let (s, c) = M::sin_cos(&x[1]);
        let accel = |dz: &[f64; L], dth: &[f64; L], (ss, cc): &([f64; L], [f64; L])| {
            let a: [f64; L] = from_fn(|l| self.drive.acceleration(dz[l], u[l]));
            let b: [f64; L] = from_fn(|l| {
                self.pendulum
                    .acceleration_prescaled(ss[l], cc[l], dth[l], a[l])
            });
            (a, b)
        };
        let half: [f64; L] = from_fn(|l| 0.5 * h[l]);
        let (dz1, dth1) = (x[2], x[3]);
        let (a1, b1) = accel(&dz1, &dth1, &(s, c));
        let dz2: [f64; L] = from_fn(|l| x[2][l] + half[l] * a1[l]);
        let dth2: [f64; L] = from_fn(|l| x[3][l] + half[l] * b1[l]);
        let sc2 = sin_cos_offset_lanes(&from_fn::<f64, L, _>(|l| half[l] * dth1[l]), &s, &c)?;
        let (a2, b2) = accel(&dz2, &dth2, &sc2);
        let dz3: [f64; L] = from_fn(|l| x[2][l] + half[l] * a2[l]);
        let dth3: [f64; L] = from_fn(|l| x[3][l] + half[l] * b2[l]);
        let sc3 = sin_cos_offset_lanes(&from_fn::<f64, L, _>(|l| half[l] * dth2[l]), &s, &c)?;
        let (a3, b3) = accel(&dz3, &dth3, &sc3);
        let dz4: [f64; L] = from_fn(|l| x[2][l] + h[l] * a3[l]);
        let dth4: [f64; L] = from_fn(|l| x[3][l] + h[l] * b3[l]);
        let sc4 = sin_cos_offset_lanes(&from_fn::<f64, L, _>(|l| h[l] * dth3[l]), &s, &c)?;
        let (a4, b4) = accel(&dz4, &dth4, &sc4);
        let sixth: [f64; L] = from_fn(|l| h[l] / 6.0);
        // As in `anchored_step`: the last stage's term added last.
        let step = |x: &[f64; L], k1: &[f64; L], k2: &[f64; L], k3: &[f64; L], k4: &[f64; L]| {
            from_fn::<f64, L, _>(|l| {
                (x[l] + sixth[l] * (k1[l] + 2.0 * k2[l] + 2.0 * k3[l])) + sixth[l] * k4[l]
            })
        };
        Some([
            step(&x[0], &dz1, &dz2, &dz3, &dz4),
            step(&x[1], &dth1, &dth2, &dth3, &dth4),
            step(&x[2], &a1, &a2, &a3, &a4),
            step(&x[3], &b1, &b2, &b3, &b4),
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pendulab_sim::rk4_step;

    /// The spacing of doubles at `v` (ulp); the smallest normal spacing at zero.
    fn ulp(v: f64) -> f64 {
        let a = v.abs();
        if a == 0.0 {
            return f64::MIN_POSITIVE;
        }
        f64::from_bits(a.to_bits() + 1) - a
    }

    /// Uniform numbers in `[lo, hi)` from a 64-bit LCG (Knuth's MMIX constants).
    fn uniform(state: &mut u64, lo: f64, hi: f64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((*state >> 11) as f64 / (1u64 << 53) as f64)
    }

    /// The anchored step's first sine and cosine against libm's (the independent reference)
    /// over `|θ| ≤ 0.3`: within the bound of `Trig::Anchored`, 2 ulp + 6·10⁻¹⁷ (libm < 1
    /// ulp, the truncated series < 3·10⁻¹⁸, the correction's roundings ≲ 2·10⁻¹⁷, the final
    /// addition half an ulp), and exactly libm's beyond the wide series' range.
    #[test]
    fn anchor_sine_and_cosine_are_within_the_anchored_bound_of_libm() {
        let mut state = 1u64;
        let mut worst = 0.0f64;
        let mut points: Vec<f64> = (0..400_000)
            .map(|_| uniform(&mut state, -0.3, 0.3))
            .collect();
        // The range's end and tiny angles (where the series' leading term rules).
        for b in [WIDE_ANGLE_LIMIT, 1e-3, 1e-9, 1e-300] {
            for v in [
                b,
                f64::from_bits(b.to_bits() + 1),
                f64::from_bits(b.to_bits() - 1),
            ] {
                points.extend([v, -v]);
            }
        }
        for x in points {
            let (s, c) = anchor_sin_cos(x);
            let (rs, rc) = x.sin_cos();
            if x.abs() > WIDE_ANGLE_LIMIT {
                assert_eq!((s, c), (rs, rc), "{x:e}");
                continue;
            }
            for (got, want) in [(s, rs), (c, rc)] {
                let bound = 2.0 * ulp(want) + 6e-17;
                let err = (got - want).abs();
                assert!(err <= bound, "{x:e}: {got:e} vs {want:e}");
                worst = worst.max(err / bound);
            }
        }
        // Not vacuous: the rounding shows.
        assert!(worst > 0.05, "worst error / bound {worst}");
    }

    /// The stage sines and cosines from the anchor's (`stage_sin_cos`) against libm at the
    /// stage angle `x = fl(θ + d)`, corrected to first order by the rounding error of that sum
    /// (`r = (θ + d) − x`, exact by Knuth's TwoSum; `sin(x + r) = sin x + r cos x` up to
    /// `r²/2 < 10⁻³²`): anchors over several periods and near zero, offsets within 1/32 and
    /// up to 1/8 (the wide series) and beyond (libm). Bound: 2 ulp + 6·10⁻¹⁷ for offsets
    /// within 1/32 (the documented bound of `sin_cos_offset`, whose argument holds for the
    /// longer series as well: its truncation is smaller); beyond, the correction term
    /// `s·(cos d − 1) + c·sin d` reaches |d| + d²/2 < 0.133 and its three roundings add up to
    /// 3 · 2⁻⁵³ · 0.133 < 5·10⁻¹⁷ more, so 2 ulp + 1.1·10⁻¹⁶ there.
    #[test]
    fn stage_sine_and_cosine_are_within_the_anchored_bound_of_libm() {
        let mut state = 2u64;
        let mut worst = [0.0f64; 2];
        for i in 0..1_000_000 {
            let a = match i % 3 {
                0 => uniform(&mut state, -20.0, 20.0),
                1 => uniform(&mut state, -1e-3, 1e-3),
                _ => uniform(&mut state, -0.25, 0.25),
            };
            let d = match i % 4 {
                0 => uniform(&mut state, -1e-3, 1e-3),
                1 => uniform(&mut state, -1.0 / 32.0, 1.0 / 32.0),
                _ => uniform(&mut state, -0.15, 0.15),
            };
            let (s, c) = a.sin_cos();
            let (gs, gc) = stage_sin_cos(a, d, s, c);
            let x = a + d;
            let bb = x - a;
            let r = (a - (x - bb)) + (d - bb);
            let (xs, xc) = x.sin_cos();
            if d.abs() > WIDE_SHIFT_LIMIT {
                assert_eq!((gs, gc), (xs, xc), "a = {a:e}, d = {d:e}");
                continue;
            }
            let (rs, rc) = (xs + r * xc, xc - r * xs);
            let tier = usize::from(d.abs() > pendulab_sim::lanes::SHIFT_LIMIT);
            let extra = [6e-17, 1.1e-16][tier];
            for (got, want) in [(gs, rs), (gc, rc)] {
                let bound = 2.0 * ulp(want) + extra;
                let err = (got - want).abs();
                assert!(err <= bound, "a = {a:e}, d = {d:e}: {got:e} vs {want:e}");
                worst[tier] = worst[tier].max(err / bound);
            }
        }
        assert!(
            worst[0] > 0.05 && worst[1] > 0.05,
            "worst error / bound {worst:?}"
        );
    }

    /// The polynomial sine/cosine changes `θ̈` only through `sin θ` and `cos θ`: by at most
    /// their error (2 ulp + 4·10⁻¹⁷·max(1, |θ|), `Trig`'s documented bound against libm)
    /// times the terms they multiply, plus the rounding of the few operations after them
    /// (a few ulp of the largest term). The reference is the libm plant.
    #[test]
    fn polynomial_trig_right_hand_side_is_within_the_documented_bound_of_libm() {
        let libm = CartPendulum::book();
        let poly = CartPendulum::book().with_trig(Trig::Polynomial);
        assert_eq!((libm.trig(), poly.trig()), (Trig::Libm, Trig::Polynomial));
        let p = libm.params();
        let j = libm.inertia_about_pivot();
        let (mgl, ml) = (p.m_p * p.g * p.l_p, p.m_p * p.l_p);
        let mut worst = 0.0f64;
        for i in -40_000..=40_000 {
            let theta = i as f64 * 5e-4 + 1e-7;
            let x = [0.1, theta, -0.7, 3.0];
            let v = 2.5;
            let a = libm.derivative_array(&x, v);
            let b = poly.derivative_array(&x, v);
            assert_eq!(a[..3], b[..3]);
            let ddz = a[2].abs();
            let terms = (mgl + p.mu_p * 3.0 + ml * ddz) / j;
            let trig_err = 2.0 * f64::EPSILON + 4e-17 * theta.abs().max(1.0);
            let bound = (mgl + ml * ddz) / j * trig_err + 8.0 * f64::EPSILON * terms;
            let d = (a[3] - b[3]).abs();
            assert!(d <= bound, "θ = {theta}: |Δθ̈| = {d:e} > {bound:e}");
            worst = worst.max(d / bound);
        }
        // Not bit-identical everywhere (else the option would be pointless to document).
        assert!(worst > 0.0);
    }

    /// The LQR gain of the book's `cdip_lqr_sim` design (Q = diag(10, 10, 0, 0), R = 1) on
    /// `plant` linearised upright: a stabilising feedback for the kernel tests.
    fn cdip_lqr_gain(plant: &CartPendulum) -> Mat {
        let sys = plant.linearize(CartEquilibrium::upright()).unwrap();
        let mut q = Mat::zeros(4, 4);
        (q[(0, 0)], q[(1, 1)]) = (10.0, 10.0);
        pendulab_lti::design::lqr(&sys, &q, &Mat::identity(1, 1), None)
            .unwrap()
            .gain
    }

    /// The fixed-size kernel reproduces the general sampled-data loop bit for bit with this
    /// plant (the reference is `SampledLoop::run`, which evaluates `Dynamics::derivative`),
    /// with either sine/cosine and on either multiply–add path (the provided RK4 step has no
    /// multiply–adds to fuse), under a stabilising feedback (the LQR gain of the book's
    /// `cdip_lqr_sim` design, Q = diag(10, 10, 0, 0), R = 1) from 15°.
    #[test]
    fn fixed_kernel_runs_are_bit_identical_to_the_general_loop() {
        use pendulab_sim::controllers::StaticStateFeedback;
        use pendulab_sim::fixed::MulAddPath;
        use pendulab_sim::{SampledLoop, SampledOptions};
        for trig in [Trig::Libm, Trig::Polynomial] {
            let plant = CartPendulum::book().with_trig(trig);
            let k = cdip_lqr_gain(&plant);
            let opts = SampledOptions::default();
            let mut g =
                SampledLoop::new(plant, StaticStateFeedback::new(k).unwrap(), opts).unwrap();
            let x0 = [0.0, 15f64.to_radians(), 0.0, 0.0];
            let b = g.run(&x0).unwrap();
            for path in [MulAddPath::Fused, MulAddPath::Separate] {
                let mut f = g.fixed::<4>().unwrap().with_multiply_add(path);
                let a = f.run(&x0).unwrap();
                assert_eq!(a, b, "{trig:?}, {path:?}");
                assert!(a.diagnostics.final_state[1].abs() < 1e-6);
            }
        }
    }

    /// The narrow anchored step (`h ≤ 2⁻⁸ s`) with either multiply–add against the classic
    /// RK4 step of the libm plant (`rk4_fixed`: the generic stage code on the plain right-hand
    /// side, an independent implementation) from the same state, over random states
    /// (|θ| ≤ 0.6 — every series tier and libm beyond 1/4 —, |θ̇| ≤ 5, |ż| ≤ 1, |v| ≤ 10 V,
    /// so |z̈| ≤ a_c|ż| + b_c|v| < 50 m/s²) and step lengths 0.25 ms, 1 ms and 2⁻⁸ s (where
    /// |θ̈| > 16 rad/s² puts the third stage's offset beyond the rotation's range).
    ///
    /// Bound. Each stage's θ̈ differs from the libm step's by: its sine and cosine, within
    /// 1.5 ulp + 2.5·10⁻¹⁷ of libm's (≤ 1.9·10⁻¹⁶) at an angle that differs from the libm
    /// step's stage angle by their roundings (≤ 3 ulp of |θ| < 1, 3.3·10⁻¹⁶); the rotation
    /// (1.5 ulp of its result) and a few roundings of the terms on either side (≤ 4·2⁻⁵³ of
    /// their sum); the cart's stage accelerations a few roundings of b_c|v| + a_c|ż|, which
    /// enter through L cos θ. Altogether at most (G + L|z̈|)·10⁻¹⁵ with G = m_p g l_p/J,
    /// L = m_p l_p/J, i.e. 2.0·10⁻¹³ 1/s² here; RK4's weights sum to one, so the velocities
    /// move by at most h times that (the positions by h² times). Both steps round their
    /// updates a few times at the size of the state: 4 ulp of it. So each component within
    /// 4 ulp(x'_i) + h·2·10⁻¹³. Not vacuous: the worst difference uses a sizeable part of it;
    /// both the rotation and its fallback (`sin_cos_offset`) run.
    #[test]
    fn narrow_anchored_step_is_within_rounding_of_the_libm_step() {
        use pendulab_sim::fixed::{FixedDynamics, Fused, MulAdd, Separate, rk4_fixed};
        fn run<F: MulAdd>() {
            let anchored = CartPendulum::book().with_trig(Trig::Anchored);
            let libm = CartPendulum::book();
            let mut state = 3u64;
            let mut worst = 0.0f64;
            let (mut rotated, mut fallback) = (0usize, 0usize);
            for i in 0..200_000 {
                let h = [2.5e-4, 1e-3, 1.0 / 256.0][i % 3];
                let x = [
                    uniform(&mut state, -0.5, 0.5),
                    uniform(&mut state, -0.6, 0.6),
                    uniform(&mut state, -1.0, 1.0),
                    uniform(&mut state, -5.0, 5.0),
                ];
                let u = uniform(&mut state, -10.0, 10.0);
                let (mut a, mut b) = (x, x);
                anchored.rk4_step_fixed_with::<F>(&mut a, u, h);
                rk4_fixed(&libm, &mut b, u, h);
                for j in 0..4 {
                    let tol = 4.0 * ulp(b[j]) + h * 2e-13;
                    let d = (a[j] - b[j]).abs();
                    assert!(
                        d <= tol,
                        "{:?}: h = {h}, x = {x:?}, u = {u}: state {j}, {d:e}",
                        F::PATH
                    );
                    worst = worst.max(d / tol);
                }
                // Which way the third stage went: e₃ = (h²/4)·θ̈₁.
                let e3 = 0.25 * h * h * libm.derivative_array(&x, u)[3];
                if e3.abs() <= ROTATE_LIMIT * 0.99 {
                    rotated += 1;
                } else if e3.abs() > ROTATE_LIMIT * 1.01 {
                    fallback += 1;
                }
            }
            eprintln!(
                "{:?}: worst difference / tolerance {worst}; rotated {rotated}, fallback {fallback}",
                F::PATH
            );
            assert!(worst > 0.05, "{worst}");
            assert!(rotated > 10_000 && fallback > 1000, "{rotated} {fallback}");
        }
        run::<Fused>();
        run::<Separate>();
        // The two strategies do round differently (the fused one once per multiply–add),
        // which shows in some steps' results (most differences in θ̈ stay below half an ulp
        // of the state after the factor h: 35 of these 1000 steps differ).
        let anchored = CartPendulum::book().with_trig(Trig::Anchored);
        let mut state = 4u64;
        let differ = (0..1000)
            .filter(|_| {
                let x = [
                    0.1,
                    uniform(&mut state, -0.3, 0.3),
                    0.2,
                    uniform(&mut state, -2.0, 2.0),
                ];
                let (mut a, mut b) = (x, x);
                anchored.rk4_step_fixed_with::<Fused>(&mut a, 1.5, 1e-3);
                anchored.rk4_step_fixed_with::<Separate>(&mut b, 1.5, 1e-3);
                a != b
            })
            .count();
        assert!(differ > 10, "{differ}");
    }

    /// With `Trig::Anchored` the kernel runs `narrow_anchored_step` (1 ms steps) on either
    /// multiply–add path; the general loop (which evaluates the plain right-hand side, libm
    /// for this variant) is the reference. Each stage's θ̈ is within
    /// (m_p g l_p + m_p l_p |z̈|)/J · 10⁻¹⁵ of the libm step's from the same state (derived in
    /// `narrow_anchored_step_is_within_rounding_of_the_libm_step`), ≈ 10⁻¹³ here (|z̈| < 20
    /// m/s²: |ż| < 0.8 m/s, |v| < 3.6 V), which moves the state by h times that per step, and
    /// the updates round at a few ulp of the state (≤ 3·10⁻¹⁶ for |x| < 1): 10⁴ steps of 1 ms
    /// add up to at most 4·10⁻¹² without any help from the loop's damping; 1e-13 is asserted
    /// on the ~0.26 rad swing (the stable loop keeps the sum near a few steps' worth).
    #[test]
    fn anchored_trig_kernel_stays_within_rounding_of_the_libm_loop() {
        use pendulab_sim::controllers::StaticStateFeedback;
        use pendulab_sim::fixed::MulAddPath;
        use pendulab_sim::{SampledLoop, SampledOptions};
        let plant = CartPendulum::book().with_trig(Trig::Anchored);
        let k = cdip_lqr_gain(&plant);
        let feedback = StaticStateFeedback::new(k).unwrap();
        let opts = SampledOptions::default();
        let g = SampledLoop::new(plant, feedback.clone(), opts.clone()).unwrap();
        let mut libm = SampledLoop::new(CartPendulum::book(), feedback, opts).unwrap();
        let x0 = [0.0, 15f64.to_radians(), 0.0, 0.0];
        let b = libm.run(&x0).unwrap();
        // The plain right-hand side of the anchored plant is libm's.
        assert_eq!(g.clone().run(&x0).unwrap(), b);
        let mut runs = Vec::new();
        for path in [MulAddPath::Fused, MulAddPath::Separate] {
            let a = g
                .fixed::<4>()
                .unwrap()
                .with_multiply_add(path)
                .run(&x0)
                .unwrap();
            let (xa, xb) = (a.trajectory.x(), b.trajectory.x());
            assert_eq!(xa.shape(), xb.shape());
            let dev = (xa - xb).abs().max();
            assert!(dev < 1e-13, "{path:?}: max deviation {dev:e}");
            assert!(a.diagnostics.final_state[1].abs() < 1e-6);
            runs.push(a);
        }
        // The two paths differ where the processor has FMA (the fused path then rounds
        // differently), not otherwise.
        let fused = g.fixed::<4>().unwrap().multiply_add() == MulAddPath::Fused;
        assert_eq!(runs[0] != runs[1], fused);
    }

    /// The lane kernel with `AnchoredSinCos` (the cart's own lane RK4 step) against the
    /// lane kernel with libm (bit-identical to the general loop) on a grid of initial states
    /// that includes falling runs, at 1 kHz (stage offsets in the series' range) and at
    /// 50 Hz (large offsets: some steps fall back to the plain step), over 0.5 s (states
    /// still O(1)) and 10 s: the same outcome (upright or not, steps run) for every run, and
    /// final states — of the fallen runs the first sample past the bound — within 1e-11.
    /// Per step the two kernels differ by a few roundings of θ̈ (stage sines within
    /// 2 ulp + 6·10⁻¹⁷, prescaled constants), ~1e-15 of the state; the largest difference
    /// seen is 2e-13, and 1e-11 leaves that growth a factor 50 while an O(h²) error in a
    /// stage formula (≥ 1e-6 per step) stays far above it.
    #[test]
    fn anchored_lane_kernel_agrees_with_the_libm_lanes() {
        use pendulab_sim::lanes::{AnchoredSinCos, LaneOptions, LibmSinCos, run_feedback_lanes};
        let plant = CartPendulum::book();
        let k = cdip_lqr_gain(&plant);
        let gain = [k[(0, 0)], k[(0, 1)], k[(0, 2)], k[(0, 3)]];
        let mut x0s = Vec::new();
        for i in 0..6 {
            for j in 0..6 {
                let th = -1.2 + 2.4 * i as f64 / 5.0;
                let w = -3.0 + 6.0 * j as f64 / 5.0;
                x0s.push([0.0, th, 0.0, w]);
            }
        }
        for (ts, t_final) in [(1e-3, 0.5), (1e-3, 10.0), (0.02, 0.5), (0.02, 10.0)] {
            let options = LaneOptions {
                ts,
                t_final,
                substeps: 1,
                stay_within: Some((1, std::f64::consts::FRAC_PI_2)),
            };
            let a = run_feedback_lanes::<_, AnchoredSinCos, 4, 8>(&plant, &gain, &options, &x0s)
                .unwrap();
            let b =
                run_feedback_lanes::<_, LibmSinCos, 4, 8>(&plant, &gain, &options, &x0s).unwrap();
            let held = a.iter().filter(|o| o.held).count();
            assert!(held > 0 && held < a.len(), "grid has both outcomes: {held}");
            let mut worst = 0.0f64;
            for (ra, rb) in a.iter().zip(&b) {
                assert_eq!((ra.held, ra.steps), (rb.held, rb.steps), "ts = {ts}");
                for i in 0..4 {
                    worst = worst.max((ra.final_state[i] - rb.final_state[i]).abs());
                }
            }
            eprintln!("ts = {ts}, {t_final} s: largest final-state difference {worst:e}");
            assert!(worst < 1e-11, "ts = {ts}, {t_final} s: {worst:e}");
        }
    }

    /// Ten seconds of 20 ms RK4 steps (the environment's step) from a large swing of the
    /// hanging, damped pendulum under a varying voltage: the libm and polynomial plants agree
    /// to 1e-11 (per-step differences are ~1e-16 relative; the stable hanging motion keeps
    /// their sum far below this tolerance, which allows a 10⁴-fold growth).
    #[test]
    fn polynomial_trig_trajectories_stay_close_to_libm() {
        let libm = CartPendulum::book();
        let poly = CartPendulum::book().with_trig(Trig::Polynomial);
        let mut xa = [0.0, std::f64::consts::PI - 1.0, 0.0, 0.0];
        let mut xb = xa;
        for k in 0..500 {
            let t = k as f64 * 0.02;
            let v = 2.0 * (3.0 * t).sin();
            rk4_step(&libm, t, &mut xa, &[v], 0.02);
            rk4_step(&poly, t, &mut xb, &[v], 0.02);
        }
        for i in 0..4 {
            assert!((xa[i] - xb[i]).abs() < 1e-11, "state {i}: {xa:?} vs {xb:?}");
        }
    }
}
