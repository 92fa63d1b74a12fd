//! # pendulab-sim — simulation
//!
//! (Tour written below once the modules are complete.)
#![warn(missing_docs)]

pub mod actuator;
pub mod batch;
mod buffer;
mod controller;
pub mod controllers;
mod dynamics;
pub mod env;
mod error;
pub mod integrate;
pub mod linearize;
pub mod monitor;
pub mod quantizer;
pub mod sampled;
pub mod sensor;
pub mod signal;
pub mod systems;

pub use actuator::{Actuator, DisturbancePoint, Friction, WithDriveFriction};
pub use controller::Controller;
pub use dynamics::Dynamics;
pub use env::{Env, EnvConfig, Step};
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
