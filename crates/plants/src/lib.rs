//! # pendulab-plants — the two pendulum rigs as models
//!
//! The cart-type (cdip) and arm-type (adip) inverted pendulums of 「倒立振子で学ぶ制御工学」,
//! exactly as the book writes them (part 1 ch. 3, tables 3.5 and 3.7; `docs/model.md`), in SI units
//! and radians, angles from the **upward** vertical (upright `0`, hanging `π`).
//!
//! | item | what it is |
//! |---|---|
//! | [`CartPendulumParams`], [`CartPendulum`], [`CartPendulumState`] | cart pendulum (book table 3.5): `z̈ = −a_c ż + b_c v`, `J θ̈ + m_p l_p cos θ z̈ = m_p g l_p sin θ − μ_p θ̇`; state `[z, θ, ż, θ̇]` ([`cart`]) |
//! | [`ArmPendulumParams`], [`ArmPendulum`], [`ArmPendulumState`], [`ArmLpv`] | arm pendulum (book table 3.7), `θ₂` absolute; state `[θ₁, θ₂, θ̇₁, θ̇₂]`; LPV form in `ρ = 1 − cos θ₁` ([`arm`]) |
//! | [`FixedCartPendulum`] | the cart rig's pendulum with the cart held: `ω_np`, `ζ_p`, closed-form eigenvalues (eqs 4.39–4.45) |
//! | [`TwoPendulumCart`], [`TwoPendulumCartParams`] | a cart with two pendulums (book example 5.4, `p1c511_ex4_cdip`) |
//! | [`Drive`] | the DC-motor drive `q̈ = −a q̇ + b v`, `P(s) = b/(s(s + a))`, for cart or arm |
//! | [`RigSpec`] | the real rigs' numbers: encoders, ±5 V, 16-bit D/A, pseudo-differentiator, 1 ms, friction, travel and angle limits; their sensor and actuator chains ([`RigSpec::chains`]) |
//! | [`PlantSpec`], [`PlantParameters`], [`Provenance`] | a plant as data: kind, parameters with provenance, rig part; TOML/serde with errors naming the key ([`spec`]) |
//! | [`wrap_angle`], [`wrap_about`] | pendulum angles wrapped to `(−π, π]` or about an equilibrium; the drive position is never wrapped ([`angle`]) |
//! | [`Jacobian`], [`Posture`] | the Jacobian of a model at a point; upright/hanging |
//! | [`PlantError`] | what is wrong with a parameter, naming it and its value |
//!
//! Each plant
//! - is built from plain parameter data by `new` (validated once: masses, lengths, inertias,
//!   drive gains and `g` finite and positive, frictions and drive poles finite and
//!   non-negative) or by `book()`;
//! - implements [`pendulab_sim::Dynamics`] (`ẋ = f(t, x, u)` on slices) and offers the same
//!   right-hand side on fixed-size arrays, `derivative_array(&x, v)`, allocation-free for hot
//!   loops;
//! - gives its analytic Jacobian at **any** point (`jacobian`) and its linearisation at an
//!   equilibrium as a [`pendulab_lti::StateSpace`] in deviation variables (`linearize`, with
//!   `C = I`; `linearize_measured` with the encoder outputs);
//! - gives the energy used by swing-up controllers and the positions of its parts for drawing
//!   (`pose`, matching `pendulab-plot`'s `CartGeometry`/`ArmGeometry` conventions).
//!
//! The derivations (Euler–Lagrange, with the drive as an acceleration source, as the book
//! identifies it) are written out in the module docs of [`cart`], [`arm`] and
//! [`two_pendulum`]; `tools/reference/plants_lagrange.py` repeats them with SymPy and the tests
//! compare both.
//!
//! ```
//! use pendulab_plants::{CartEquilibrium, CartPendulum, CartPendulumParams, CartPendulumState};
//! # fn main() -> Result<(), pendulab_plants::PlantError> {
//! let plant = CartPendulum::new(CartPendulumParams::book())?;
//! // The upright model and its open-loop poles 0, −6.25, +5.7543, −5.7867 (`docs/model.md` §1).
//! let sys = plant.linearize(CartEquilibrium::upright())?;
//! let poles = sys.poles()?;
//! assert!(poles.iter().any(|p| (p.re - 5.7543).abs() < 5e-5));
//! // The nonlinear right-hand side, and the energy of the hanging rest (zero).
//! let x = CartPendulumState { theta: std::f64::consts::PI, ..Default::default() };
//! let f = plant.derivative_array(&x.to_array(), 0.0);
//! assert!(f.iter().all(|v| v.abs() < 1e-12));
//! assert!(plant.energy(&x).abs() < 1e-15);
//! // Bad parameters are typed errors naming the parameter.
//! let bad = CartPendulumParams { m_p: -0.1, ..CartPendulumParams::book() };
//! assert!(CartPendulum::new(bad).unwrap_err().to_string().contains("m_p"));
//! # Ok(()) }
//! ```
#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod angle;
pub mod arm;
pub mod cart;
pub mod classic_cart_pole;
mod drive;
pub mod error;
mod fixed_cart;
mod linear;
mod pendulum;
pub mod rig;
pub mod spec;
mod state;
pub mod two_pendulum;

pub use angle::{wrap_about, wrap_angle};
pub use arm::{ArmEquilibrium, ArmLpv, ArmPendulum, ArmPendulumParams, ArmPendulumState, ArmPose};
pub use cart::{CartEquilibrium, CartPendulum, CartPendulumParams, CartPendulumState, CartPose};
pub use classic_cart_pole::{CartPoleIntegrator, ClassicCartPole, ClassicCartPoleParams};
pub use drive::Drive;
pub use error::{PlantError, Requirement};
pub use fixed_cart::FixedCartPendulum;
pub use linear::{Jacobian, Posture};
pub use pendulum::PendulumParams;
pub use rig::{Coordinate, DacSpec, DriveFriction, EncoderSpec, RigSpec, VelocityEstimatorSpec};
pub use spec::{PlantParameters, PlantSpec, PlantSpecError, Provenance};
pub use two_pendulum::{TwoPendulumCart, TwoPendulumCartParams, TwoPendulumCartState};
