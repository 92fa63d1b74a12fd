//! # pendulab-sim — simulation
//!
//! The [`Dynamics`] trait shared by state-space systems, plants and closed loops.
#![warn(missing_docs)]

mod dynamics;

pub use dynamics::Dynamics;
