//! # pendulab-control — nonlinear and digital control
#![warn(missing_docs)]

pub mod cgmres;
pub mod error;
pub mod estimation;
pub mod gmres;
pub mod nmpc;
pub mod quantizer;
pub mod sliding_mode;
pub mod swing_up;

pub use error::{ControlError, Result};
