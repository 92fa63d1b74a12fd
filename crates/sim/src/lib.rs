//! # pendulab-sim — simulation
//!
//! - [`Dynamics`]: continuous-time dynamics `ẋ = f(t, x, u)`, shared by state-space systems,
//!   plants and closed loops.
//! - [`Controller`]: a discrete controller called once per sample with the measurement, its
//!   command held until the next sample; shared by the simulator and the rig runtime.
#![warn(missing_docs)]

mod controller;
mod dynamics;

pub use controller::Controller;
pub use dynamics::Dynamics;
