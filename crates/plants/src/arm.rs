//! The arm-type inverted pendulum (adip), book part 1 §3.3 and table 3.7 (`docs/model.md` §2).
//!
//! # Model
//! A DC motor turns an arm of length `L₁` in a vertical plane; `θ₁` is the arm's angle from the
//! **upward** vertical (arm tip at `(L₁ sin θ₁, L₁ cos θ₁)`). A pendulum swings freely on the
//! arm's tip; `θ₂` is its **absolute** angle from the upward vertical (not relative to the arm).
//! With `α₂ = J₂ + m₂ l₂²`, `α₃ = m₂ L₁ l₂`, `α₅ = m₂ l₂ g`:
//!
//! ```text
//! θ̈₁ = −a₁ θ̇₁ + b₁ v                                                         (drive)
//! α₂ θ̈₂ + α₃ cos(θ₁ − θ₂) θ̈₁ = α₃ θ̇₁² sin(θ₁ − θ₂) + α₅ sin θ₂ + μ₂ (θ̇₁ − θ̇₂)   (pendulum)
//! ```
//!
//! State `x = [θ₁, θ₂, θ̇₁, θ̇₂]`, input `u = v` (volts). The drive is an acceleration source,
//! so the two equations are solved in turn: `θ̈₁` from the drive, then `θ̈₂`.
//!
//! # Derivation (Euler–Lagrange)
//! The pendulum's centre of mass is at `(L₁ sin θ₁ + l₂ sin θ₂, L₁ cos θ₁ + l₂ cos θ₂)`, so
//!
//! ```text
//! T = ½ J_arm θ̇₁² + ½ m₂ L₁² θ̇₁² + α₃ cos(θ₁ − θ₂) θ̇₁ θ̇₂ + ½ α₂ θ̇₂²,
//! V = m₂ g (L₁ cos θ₁ + l₂ cos θ₂) (+ the arm's own potential, a function of θ₁ only),
//! D = ½ μ₂ (θ̇₂ − θ̇₁)²   (viscous friction of the pendulum's joint, on the relative speed).
//! ```
//!
//! `d/dt ∂L/∂θ̇₂ = α₂ θ̈₂ + α₃ cos(θ₁ − θ₂) θ̈₁ − α₃ sin(θ₁ − θ₂) (θ̇₁ − θ̇₂) θ̇₁`,
//! `∂L/∂θ₂ = α₃ sin(θ₁ − θ₂) θ̇₁ θ̇₂ + α₅ sin θ₂`, `∂D/∂θ̇₂ = μ₂ (θ̇₂ − θ̇₁)`; their combination
//! is the pendulum equation above (the `θ̇₁ θ̇₂` terms cancel). The arm's equation is replaced by
//! the identified drive law, as for the cart. `tools/reference/plants_lagrange.py` repeats the
//! derivation with SymPy.
//!
//! # Linearisation and LPV form
//! At any arm angle `θ₁ = θ₁ₑ` with the pendulum upright (`θ₂ = 0`) and everything at rest
//! (`docs/model.md` §2):
//!
//! ```text
//! A = [[0, 0, 1, 0], [0, 0, 0, 1], [0, 0, −a₁, 0], [0, α₅/α₂, (μ₂ + a₁ α₃ cos θ₁ₑ)/α₂, −μ₂/α₂]],
//! B = [0, 0, b₁, −b₁ α₃ cos θ₁ₑ/α₂]ᵀ.
//! ```
//!
//! Only `cos θ₁ₑ` enters, affinely, so with `ρ = 1 − cos θ₁`: `A(ρ) = A₀ + ρ A₁`,
//! `B(ρ) = B₀ + ρ B₁` ([`ArmLpv`]), the model the gain-scheduled designs of book part 2 §1.5 use.
//!
//! # Energy
//! [`ArmPendulum::pendulum_energy`] `E₂ = ½ α₂ θ̇₂² + α₅ (1 + cos θ₂)` is the pendulum's energy in
//! the frame translating with the arm's tip (0 hanging at rest, `2 α₅` upright at rest); it is
//! constant when the arm is held and `μ₂ = 0`.

use pendulab_lti::{Continuous, Mat, StateSpace};
use pendulab_sim::Dynamics;

use crate::drive::Drive;
use crate::error::{PlantError, Requirement, check, check_derived, check_point};
use crate::linear::{Jacobian, Posture, selection_matrix};

const MODEL: &str = "arm pendulum";

/// The physical parameters of the arm-type pendulum (book table 3.7).
///
/// Plain data: build a plant with [`ArmPendulum::new`], which validates every field. Field
/// names follow the book's symbols.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArmPendulumParams {
    /// Velocity pole of the arm drive `a₁` \[1/s\] (≥ 0).
    pub a1: f64,
    /// Gain of the arm drive `b₁` \[rad/(s² V)\] (> 0).
    pub b1: f64,
    /// Arm length `L₁` (arm pivot to pendulum pivot) \[m\] (> 0).
    pub L1: f64,
    /// Pendulum mass `m₂` \[kg\] (> 0).
    pub m2: f64,
    /// Pendulum pivot to centre of mass `l₂` \[m\] (> 0).
    pub l2: f64,
    /// Pendulum drawing length `L₂` (pivot to tip) \[m\] (> 0); geometry only.
    pub L2: f64,
    /// Pendulum moment of inertia about its centre of mass `J₂` \[kg m²\] (> 0).
    pub J2: f64,
    /// Viscous friction of the pendulum's joint `μ₂` \[N m s/rad\] (≥ 0).
    pub mu2: f64,
    /// Gravitational acceleration `g` \[m/s²\] (> 0).
    pub g: f64,
}

impl ArmPendulumParams {
    /// The book's rig (table 3.7): `a₁ = 6.20 1/s`, `b₁ = 15.8 rad/(s² V)`, `L₁ = 0.227 m`,
    /// `m₂ = 0.096 kg`, `l₂ = 0.195 m`, `L₂ = 0.300 m`, `J₂ = 9.06·10⁻⁴ kg m²`,
    /// `μ₂ = 1.01·10⁻⁴ N m s/rad`, `g = 9.81 m/s²`.
    pub const fn book() -> Self {
        Self {
            a1: 6.20,
            b1: 15.8,
            L1: 0.227,
            m2: 0.096,
            l2: 0.195,
            L2: 0.300,
            J2: 9.06e-4,
            mu2: 1.01e-4,
            g: 9.81,
        }
    }

    /// Checks every field against the requirement written on it.
    ///
    /// # Errors
    /// [`PlantError::InvalidParameter`] naming the first offending parameter and its value.
    pub fn validate(&self) -> Result<(), PlantError> {
        check(MODEL, "a1", self.a1, Requirement::NonNegative)?;
        check(MODEL, "b1", self.b1, Requirement::Positive)?;
        check(MODEL, "L1", self.L1, Requirement::Positive)?;
        check(MODEL, "m2", self.m2, Requirement::Positive)?;
        check(MODEL, "l2", self.l2, Requirement::Positive)?;
        check(MODEL, "L2", self.L2, Requirement::Positive)?;
        check(MODEL, "J2", self.J2, Requirement::Positive)?;
        check(MODEL, "mu2", self.mu2, Requirement::NonNegative)?;
        check(MODEL, "g", self.g, Requirement::Positive)
    }

    /// `α₂ = J₂ + m₂ l₂²` \[kg m²\], the pendulum's inertia about its pivot.
    pub fn alpha2(&self) -> f64 {
        self.J2 + self.m2 * self.l2 * self.l2
    }

    /// `α₃ = m₂ L₁ l₂` \[kg m²\].
    pub fn alpha3(&self) -> f64 {
        self.m2 * self.L1 * self.l2
    }

    /// `α₅ = m₂ l₂ g` \[N m\].
    pub fn alpha5(&self) -> f64 {
        self.m2 * self.l2 * self.g
    }
}

impl Default for ArmPendulumParams {
    /// The book's rig, [`ArmPendulumParams::book`].
    fn default() -> Self {
        Self::book()
    }
}

crate::state::named_state! {
    /// The state `x = [θ₁, θ₂, θ̇₁, θ̇₂]` of the arm-type pendulum, named. `θ₂` is absolute.
    pub struct ArmPendulumState, "[θ₁, θ₂, θ̇₁, θ̇₂]" {
        /// Arm angle `θ₁` from the upward vertical \[rad\].
        theta1,
        /// Pendulum angle `θ₂` from the upward vertical (absolute) \[rad\].
        theta2,
        /// Arm angular velocity `θ̇₁` \[rad/s\].
        dtheta1,
        /// Pendulum angular velocity `θ̇₂` \[rad/s\].
        dtheta2,
    }
}

impl ArmPendulumState {
    /// The pendulum's angle relative to the arm, `θ₂ − θ₁` \[rad\].
    pub fn relative_angle(&self) -> f64 {
        self.theta2 - self.theta1
    }
}

/// An equilibrium of the arm-type pendulum: the arm at rest at any angle `θ₁ₑ`, the pendulum
/// at rest upright (`θ₂ = 0`) or hanging (`θ₂ = π`), `v = 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmEquilibrium {
    /// Arm angle `θ₁ₑ` \[rad\].
    pub theta1: f64,
    /// The pendulum's posture.
    pub posture: Posture,
}

impl ArmEquilibrium {
    /// Pendulum upright with the arm at `θ₁ₑ` \[rad\].
    pub const fn upright(theta1: f64) -> Self {
        Self {
            theta1,
            posture: Posture::Upright,
        }
    }

    /// Pendulum hanging with the arm at `θ₁ₑ` \[rad\].
    pub const fn hanging(theta1: f64) -> Self {
        Self {
            theta1,
            posture: Posture::Hanging,
        }
    }

    /// The equilibrium state `[θ₁ₑ, θ₂ₑ, 0, 0]`.
    pub fn state(&self) -> ArmPendulumState {
        ArmPendulumState::from_array([self.theta1, self.posture.angle(), 0.0, 0.0])
    }
}

/// Where the parts of the arm-type pendulum are, in metres, for drawing (origin at the arm's
/// pivot, `y` up). `pendulab-plot`'s `ArmGeometry { arm_length: L₁, pendulum_length: L₂, .. }`
/// uses the same convention.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmPose {
    /// Arm tip = pendulum pivot, `(L₁ sin θ₁, L₁ cos θ₁)`.
    pub arm_tip: [f64; 2],
    /// Pendulum centre of mass, arm tip + `l₂ (sin θ₂, cos θ₂)`.
    pub centre_of_mass: [f64; 2],
    /// Pendulum tip, arm tip + `L₂ (sin θ₂, cos θ₂)`.
    pub pendulum_tip: [f64; 2],
}

/// The affine LPV model `A(ρ) = A₀ + ρ A₁`, `B(ρ) = B₀ + ρ B₁`, `ρ = 1 − cos θ₁ₑ ∈ [0, 2]`, of
/// the arm pendulum linearised upright (`docs/model.md` §2).
///
/// `A₀, B₀` are the `θ₁ₑ = 0` model; `A₁` has the single entry `(4, 3) = −a₁ α₃/α₂` and `B₁`
/// the single entry `(4) = +b₁ α₃/α₂` (1-based indices).
#[derive(Debug, Clone, PartialEq)]
pub struct ArmLpv {
    /// `A₀` (4 × 4).
    pub a0: Mat,
    /// `A₁` (4 × 4).
    pub a1: Mat,
    /// `B₀` (4 × 1).
    pub b0: Mat,
    /// `B₁` (4 × 1).
    pub b1: Mat,
}

impl ArmLpv {
    /// The scheduling parameter `ρ = 1 − cos θ₁` of an arm angle \[rad\].
    pub fn rho(theta1: f64) -> f64 {
        1.0 - theta1.cos()
    }

    /// `A(ρ) = A₀ + ρ A₁`.
    pub fn a(&self, rho: f64) -> Mat {
        &self.a0 + &self.a1 * rho
    }

    /// `B(ρ) = B₀ + ρ B₁`.
    pub fn b(&self, rho: f64) -> Mat {
        &self.b0 + &self.b1 * rho
    }

    /// The frozen model at `ρ` with `C = I`, `D = 0`.
    ///
    /// # Errors
    /// [`PlantError::NonFiniteOperatingPoint`] if `ρ` is not finite.
    pub fn state_space(&self, rho: f64) -> Result<StateSpace<Continuous>, PlantError> {
        check_point("rho", rho)?;
        Ok(StateSpace::continuous(
            self.a(rho),
            self.b(rho),
            Mat::identity(4, 4),
            Mat::zeros(4, 1),
        )?)
    }
}

/// The arm-type pendulum with validated parameters: nonlinear dynamics, Jacobians,
/// linearisation at any arm angle, LPV form, energy and geometry.
///
/// ```
/// use pendulab_plants::{ArmEquilibrium, ArmPendulum};
/// let plant = ArmPendulum::book();
/// let sys = plant.linearize(ArmEquilibrium::upright(std::f64::consts::FRAC_PI_4)).unwrap();
/// assert_eq!(sys.a()[(2, 2)], -6.20);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmPendulum {
    params: ArmPendulumParams,
    drive: Drive,
    alpha2: f64,
    inv_alpha2: f64,
    alpha3: f64,
    alpha5: f64,
}

impl ArmPendulum {
    /// Indices of the states the rig measures (encoders): `y = [θ₁, θ₂]`.
    pub const MEASURED_STATES: [usize; 2] = [0, 1];

    /// A plant from validated parameters.
    ///
    /// # Errors
    /// [`PlantError::InvalidParameter`] naming the offending parameter (NaN, infinite,
    /// non-positive length, mass, inertia, `b₁` or `g`; negative `a₁` or `μ₂`);
    /// [`PlantError::DerivedQuantity`] if `α₂`, `α₃` or `α₅` overflow.
    pub fn new(params: ArmPendulumParams) -> Result<Self, PlantError> {
        params.validate()?;
        let alpha2 = check_derived(MODEL, "alpha2 = J2 + m2 l2^2", params.alpha2())?;
        Ok(Self {
            params,
            drive: Drive::new(params.a1, params.b1)?,
            alpha2,
            inv_alpha2: check_derived(MODEL, "1 / alpha2", 1.0 / alpha2)?,
            alpha3: check_derived(MODEL, "alpha3 = m2 L1 l2", params.alpha3())?,
            alpha5: check_derived(MODEL, "alpha5 = m2 l2 g", params.alpha5())?,
        })
    }

    /// The book's rig ([`ArmPendulumParams::book`]).
    pub fn book() -> Self {
        match Self::new(ArmPendulumParams::book()) {
            Ok(p) => p,
            Err(_) => unreachable!("the book's arm-pendulum parameters are valid"),
        }
    }

    /// The parameters.
    pub fn params(&self) -> &ArmPendulumParams {
        &self.params
    }

    /// The arm drive `θ̈₁ = −a₁ θ̇₁ + b₁ v` on its own.
    pub fn drive(&self) -> Drive {
        self.drive
    }

    /// `ẋ = f(x, v)` for `x = [θ₁, θ₂, θ̇₁, θ̇₂]`: fixed-size and allocation-free.
    #[inline]
    pub fn derivative_array(&self, x: &[f64; 4], v: f64) -> [f64; 4] {
        let dd1 = self.drive.acceleration(x[2], v);
        let (s12, c12) = (x[0] - x[1]).sin_cos();
        let s2 = x[1].sin();
        let dd2 = (self.alpha3 * (x[2] * x[2] * s12 - c12 * dd1)
            + self.alpha5 * s2
            + self.params.mu2 * (x[2] - x[3]))
            * self.inv_alpha2;
        [x[2], x[3], dd1, dd2]
    }

    /// The analytic Jacobian `A = ∂f/∂x`, `B = ∂f/∂v` at any point. With
    /// `θ̈₁ = −a₁ θ̇₁ + b₁ v`, `s = sin(θ₁ − θ₂)`, `c = cos(θ₁ − θ₂)`:
    ///
    /// ```text
    /// ∂θ̈₂/∂θ₁ = α₃ (θ̇₁² c + s θ̈₁)/α₂,   ∂θ̈₂/∂θ₂ = (α₅ cos θ₂ − α₃ (θ̇₁² c + s θ̈₁))/α₂,
    /// ∂θ̈₂/∂θ̇₁ = (2 α₃ θ̇₁ s + μ₂ + a₁ α₃ c)/α₂,   ∂θ̈₂/∂θ̇₂ = −μ₂/α₂,   ∂θ̈₂/∂v = −b₁ α₃ c/α₂.
    /// ```
    pub fn jacobian(&self, x: &[f64; 4], v: f64) -> Jacobian<4> {
        let dd1 = self.drive.acceleration(x[2], v);
        let (s12, c12) = (x[0] - x[1]).sin_cos();
        self.jacobian_from(s12, c12, x[1].cos(), x[2], dd1)
    }

    fn jacobian_from(&self, s12: f64, c12: f64, c2: f64, d1: f64, dd1: f64) -> Jacobian<4> {
        let p = &self.params;
        let (al2, al3, al5) = (self.alpha2, self.alpha3, self.alpha5);
        let coupling = al3 * (d1 * d1 * c12 + s12 * dd1);
        Jacobian {
            a: [
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
                [0.0, 0.0, -p.a1, 0.0],
                [
                    coupling / al2,
                    (al5 * c2 - coupling) / al2,
                    (2.0 * al3 * d1 * s12 + p.mu2 + p.a1 * al3 * c12) / al2,
                    -p.mu2 / al2,
                ],
            ],
            b: [0.0, 0.0, p.b1, -p.b1 * al3 * c12 / al2],
        }
    }

    /// The Jacobian at an equilibrium (`θ̇₁ = θ̇₂ = 0`, `v = 0`); upright it is exactly the
    /// `A`, `B` of the module docs; hanging, `α₅/α₂` changes sign and `cos(θ₁ₑ − π) = −cos θ₁ₑ`.
    ///
    /// # Errors
    /// [`PlantError::NonFiniteOperatingPoint`] if `eq.theta1` is not finite.
    pub fn equilibrium_jacobian(&self, eq: ArmEquilibrium) -> Result<Jacobian<4>, PlantError> {
        check_point("theta1", eq.theta1)?;
        let c12 = eq.posture.cos() * eq.theta1.cos();
        let s12 = eq.posture.cos() * eq.theta1.sin();
        Ok(self.jacobian_from(s12, c12, eq.posture.cos(), 0.0, 0.0))
    }

    /// The linearisation at an equilibrium in deviation variables, `C = I`, `D = 0`.
    ///
    /// # Errors
    /// As [`ArmPendulum::equilibrium_jacobian`].
    pub fn linearize(&self, eq: ArmEquilibrium) -> Result<StateSpace<Continuous>, PlantError> {
        self.equilibrium_jacobian(eq)?.to_state_space()
    }

    /// As [`ArmPendulum::linearize`] with the measured outputs `y = [δθ₁, δθ₂]`.
    ///
    /// # Errors
    /// As [`ArmPendulum::equilibrium_jacobian`].
    pub fn linearize_measured(
        &self,
        eq: ArmEquilibrium,
    ) -> Result<StateSpace<Continuous>, PlantError> {
        self.equilibrium_jacobian(eq)?
            .to_state_space_with_outputs(&Self::MEASURED_STATES)
    }

    /// `C = [[1, 0, 0, 0], [0, 1, 0, 0]]`: the rows picking the measured `θ₁` and `θ₂`.
    pub fn measured_output_matrix() -> Mat {
        match selection_matrix(&Self::MEASURED_STATES, 4) {
            Ok(c) => c,
            Err(_) => unreachable!("indices 0 and 1 exist in a 4-state model"),
        }
    }

    /// The LPV form of the upright linearisation (see [`ArmLpv`]).
    pub fn lpv(&self) -> ArmLpv {
        let p = &self.params;
        let (al2, al3) = (self.alpha2, self.alpha3);
        let j0 = self.jacobian_from(0.0, 1.0, 1.0, 0.0, 0.0);
        let mut a1 = Mat::zeros(4, 4);
        a1[(3, 2)] = -p.a1 * al3 / al2;
        let mut b1 = Mat::zeros(4, 1);
        b1[(3, 0)] = p.b1 * al3 / al2;
        ArmLpv {
            a0: j0.a_matrix(),
            a1,
            b0: j0.b_matrix(),
            b1,
        }
    }

    /// `α₂ = J₂ + m₂ l₂²` \[kg m²\].
    pub fn alpha2(&self) -> f64 {
        self.alpha2
    }

    /// `α₃ = m₂ L₁ l₂` \[kg m²\].
    pub fn alpha3(&self) -> f64 {
        self.alpha3
    }

    /// `α₅ = m₂ l₂ g` \[N m\].
    pub fn alpha5(&self) -> f64 {
        self.alpha5
    }

    /// The pendulum's energy `E₂ = ½ α₂ θ̇₂² + α₅ (1 + cos θ₂)` \[J\] (module docs).
    pub fn pendulum_energy(&self, x: &ArmPendulumState) -> f64 {
        0.5 * self.alpha2 * x.dtheta2 * x.dtheta2 + self.alpha5 * (1.0 + x.theta2.cos())
    }

    /// The energy of the pendulum upright at rest, `2 α₅` \[J\].
    pub fn upright_energy(&self) -> f64 {
        2.0 * self.alpha5
    }

    /// Positions of arm tip, pendulum centre of mass and pendulum tip for drawing.
    pub fn pose(&self, x: &ArmPendulumState) -> ArmPose {
        let p = &self.params;
        let (s1, c1) = x.theta1.sin_cos();
        let (s2, c2) = x.theta2.sin_cos();
        let tip = [p.L1 * s1, p.L1 * c1];
        ArmPose {
            arm_tip: tip,
            centre_of_mass: [tip[0] + p.l2 * s2, tip[1] + p.l2 * c2],
            pendulum_tip: [tip[0] + p.L2 * s2, tip[1] + p.L2 * c2],
        }
    }
}

impl Dynamics for ArmPendulum {
    fn nx(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    #[inline]
    fn derivative(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        debug_assert!(x.len() == 4 && u.len() == 1 && dx.len() == 4);
        let f = self.derivative_array(&[x[0], x[1], x[2], x[3]], u[0]);
        dx[..4].copy_from_slice(&f);
    }
}
