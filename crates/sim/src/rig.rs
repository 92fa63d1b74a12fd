//! Ready-made rig presets: the sensor and actuator chains of a real rig, from plain numbers.
//!
//! The book's Simulink library offers the plant "plain" and "with quantizer"; here the same
//! two presets are [`RigChains::plain`] (ideal full-state measurement, ideal actuator) and
//! [`RigChains::with_quantizer`] (encoders on the measured positions, pseudo-differentiated
//! velocities, input saturation and D/A quantisation), built from the numbers a rig
//! description gives — for the cart rig of `docs/model.md` §3 (`pendulab_plants::RigSpec::cart()`):
//!
//! ```
//! use pendulab_sim::rig::RigChains;
//! use std::f64::consts::PI;
//! # fn main() -> Result<(), pendulab_sim::SimError> {
//! let cart = RigChains::with_quantizer(
//!     4,
//!     &[(0, 4.8414e-5), (1, 2.0 * PI / 14400.0)], // encoders: (state, step)
//!     &[(0, 2, 0.02), (1, 3, 0.02)],               // velocities: (position, velocity, T)
//!     5.0,                                         // ±5 V
//!     16,                                          // 16-bit D/A over ±5 V
//! )?;
//! assert_eq!(cart.sensor.ny(), 4); // y = [Q(z), Q(θ), ż_est, θ̇_est], the layout of x
//! # Ok(()) }
//! ```
//!
//! Further imperfections (noise, friction, disturbances, a different differentiator
//! discretisation) are added to the returned chains with their own builder calls.

use crate::actuator::Actuator;
use crate::error::Result;
use crate::sensor::SensorChain;

/// A sensor chain and an actuator chain that together describe a rig.
#[derive(Debug, Clone, PartialEq)]
pub struct RigChains {
    /// From the true state to the controller's measurement.
    pub sensor: SensorChain,
    /// From the controller's command to the plant input.
    pub actuator: Actuator,
}

impl RigChains {
    /// The plain plant: `y = x` (all `nx` states, exact) and the ideal actuator.
    pub fn plain(nx: usize) -> Self {
        Self {
            sensor: SensorChain::full_state(nx),
            actuator: Actuator::ideal(),
        }
    }

    /// The plant "with quantizer": the measurement in the layout of the state
    /// ([`SensorChain::state_layout`]: encoders `(state, step)`, pseudo-differentiated
    /// velocities `(position state, velocity state, T)`, other states exact) and the
    /// amplifier ([`Actuator::rig`]: saturation `±input_limit`, `dac_bits`-bit D/A over that
    /// range).
    ///
    /// # Errors
    /// As [`SensorChain::state_layout`] and [`Actuator::rig`].
    pub fn with_quantizer(
        nx: usize,
        encoders: &[(usize, f64)],
        velocities: &[(usize, usize, f64)],
        input_limit: f64,
        dac_bits: u32,
    ) -> Result<Self> {
        Ok(Self {
            sensor: SensorChain::state_layout(nx, encoders, velocities)?,
            actuator: Actuator::rig(input_limit, dac_bits)?,
        })
    }
}
