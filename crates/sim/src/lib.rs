//! # pendulab-sim — simulation
//!
//! One simulation interface for linear systems, the pendulum plants and closed loops, the
//! integrators, the sampled-data loop that behaves like the real rig, and batch runs.
//!
//! | what | where | notes |
//! |---|---|---|
//! | `ẋ = f(t, x, u)` (+ optional output map) | [`Dynamics`] | implemented by `StateSpace<Continuous>`, [`FnDynamics`], [`StateFeedbackLoop`], [`Driven`], [`WithDriveFriction`], the plants of `pendulab-plants` |
//! | a discrete controller (measurement in, held command out) | [`Controller`] | ready-made ones in [`controllers`] |
//! | linearisation by finite differences | [`linearize()`], [`jacobians`] | central differences, Richardson-extrapolated by default (error ~1e-12) |
//! | open-loop simulation, events | [`simulate`], [`Integrator`], [`Event`] | RK4 (fixed step) or Dormand–Prince 5(4) with PI control, dense output, Brent event location |
//! | allocation-free RK4 kernels | [`rk4_step`] (`[f64; N]`), [`rk4_step_slice`] | |
//! | the sampled-data loop | [`SampledLoop`], [`SampledOptions`] | ZOH at `t_k = t₀ + k·ts`, substeps never cross a sample, computation [`Delay`] |
//! | the rig's imperfections | [`SensorChain`] (encoders, pseudo-differentiator, noise), [`Actuator`] (saturation, D/A, disturbances, friction), [`Quantizer`] | each off by default, one call each |
//! | book rig presets (plain, with quantizer) from plain numbers | [`rig::RigChains`], [`SampledLoop::with_rig`] | |
//! | test signals | [`Signal`] | step, ramp, pulse, pulse train, sine, piecewise, sums |
//! | a run as data: initial state, reference and disturbance, duration, imperfections on/off | [`scenario::ScenarioSpec`] | serde/TOML, errors naming the key; run by `pendulab_control::scenario::simulate` |
//! | per-sample summaries, safety stops | [`Monitor`], [`StayWithin`], [`MaxAbs`], [`SettlingTime`] | |
//! | batch runs on all cores | [`batch`] | grids of initial states, seeded Monte Carlo, region-of-attraction maps |
//! | the fast paths: a fixed-size closed loop compiled once per state size (and again for FMA), SIMD lanes for batch studies, and their strategy switches (multiply–add, sine/cosine) | [`fast`] | behind one module; the general API above never needs it |
//! | a Gymnasium-style environment | [`Env`], [`EnvConfig`], [`FixedEnv`] | `reset(seed)`, `step(u)`; CartPole-v1 settings on the cart rig; `FixedEnv` steps a [`fast::FixedDynamics`] plant with its own RK4 step |
//! | errors | [`SimError`] | typed, naming what and where (and the time of a blow-up) |
//!
//! Conventions: SI units and radians; state feedback is `u = −K x` (the textbook's
//! `u = +K_book x` converts through [`controllers::StaticStateFeedback::from_book`]); the
//! sampled loop records, per sample, `x(t_k)`, the plant input computed at `t_k` and the
//! measurement `y_k`. Expected outcomes (a run stopped by a monitor, a terminal event) are
//! statuses in the results; errors are for bad input and numerical breakdown.
//!
//! ```
//! use pendulab_lti::{Mat, StateSpace};
//! use pendulab_sim::controllers::StaticStateFeedback;
//! use pendulab_sim::{Actuator, SampledLoop, SampledOptions, SensorChain};
//! # fn main() -> Result<(), pendulab_sim::SimError> {
//! // A double integrator (position, velocity) under u = −K y at 1 kHz, with the rig's
//! // ±5 V / 16-bit amplifier, a 1 µm encoder and the pseudo-differentiator for the velocity.
//! let plant = StateSpace::continuous(
//!     Mat::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]),
//!     Mat::from_row_slice(2, 1, &[0.0, 1.0]),
//!     Mat::identity(2, 2),
//!     Mat::zeros(2, 1),
//! )?;
//! let k = StaticStateFeedback::new(Mat::from_row_slice(1, 2, &[4.0, 4.0]))?;
//! let mut cl = SampledLoop::new(plant, k, SampledOptions { t_final: 5.0, ..Default::default() })?
//!     .with_sensor(SensorChain::encoders(&[(0, 1e-6)])?.pseudo_differentiator(0.02)?)?
//!     .with_actuator(Actuator::rig(5.0, 16)?)?;
//! let run = cl.run(&[0.1, 0.0])?;
//! assert!(run.diagnostics.final_state[0].abs() < 1e-4);
//! assert_eq!(run.trajectory.len(), 5001);
//! # Ok(()) }
//! ```
#![warn(missing_docs)]

pub mod actuator;
pub mod batch;
mod buffer;
mod controller;
pub mod controllers;
mod dynamics;
pub mod env;
mod error;
pub mod fast;
pub mod integrate;
pub mod linearize;
pub mod monitor;
pub mod quantizer;
pub mod rig;
pub mod sampled;
pub mod scenario;
pub mod sensor;
pub mod signal;
pub mod systems;

pub use actuator::{Actuator, DisturbancePoint, Friction, WithDriveFriction};
pub use controller::Controller;
pub use dynamics::Dynamics;
pub use env::{Env, EnvConfig, FixedEnv, Step};
pub use error::{Result, SimError};
pub use integrate::rk4::{Rk4Work, rk4_step, rk4_step_slice};
pub use integrate::{
    Direction, Event, EventHit, IntegrationStats, Integrator, OdeOptions, Output, Simulation,
    Status, simulate, simulate_free,
};
pub use linearize::{
    DifferenceScheme, Jacobians, Linearization, LinearizeOptions, jacobians, linearize,
};
pub use monitor::{Flow, FnMonitor, MaxAbs, Monitor, SettlingTime, StayWithin};
pub use quantizer::{Quantizer, Rounding};
pub use sampled::{
    Delay, Record, RunStatus, SampledDiagnostics, SampledLoop, SampledOptions, SampledRun,
};
pub use sensor::{Differentiation, PseudoDifferentiator, SensorChain};
pub use signal::{FnInput, Input, Signal, ZeroInput};
pub use systems::{Driven, FnDynamics, StateFeedbackLoop};

/// The former path of [`fast::FixedDynamics`], kept for callers not yet moved to [`fast`].
#[doc(hidden)]
pub mod fixed {
    pub use crate::fast::FixedDynamics;
}
