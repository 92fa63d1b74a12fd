//! What the real rigs add to the models, as plain numbers (`docs/model.md` §3).
//!
//! A [`RigSpec`] lists, for one rig, the sample time, the amplifier's input range and D/A
//! converter, the encoders (which state each measures and its resolution) and the velocity
//! estimators (which position feeds which velocity, with the pseudo-differentiator's time
//! constant). The simulator builds its sensor and actuator chain from these numbers; nothing
//! here simulates anything.
//!
//! ```
//! use pendulab_plants::RigSpec;
//! let rig = RigSpec::cart();
//! assert_eq!(rig.dac.step(), 10.0 / 65536.0);
//! assert_eq!(rig.encoders[1].state, 1); // θ
//! assert_eq!(rig.encoders[1].step, 2.0 * std::f64::consts::PI / 14400.0);
//! ```

use std::f64::consts::PI;

/// The D/A converter that produces the motor command.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DacSpec {
    /// Resolution in bits (16 on both rigs).
    pub bits: u32,
    /// Lowest output voltage \[V\].
    pub min: f64,
    /// Highest output voltage \[V\].
    pub max: f64,
}

impl DacSpec {
    /// The voltage step `(max − min) / 2^bits` \[V\] (`10/2¹⁶ V ≈ 0.153 mV` on both rigs).
    pub fn step(&self) -> f64 {
        (self.max - self.min) / 2f64.powi(self.bits as i32)
    }
}

/// One incremental encoder: the state it measures and its resolution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EncoderSpec {
    /// What it measures (`"z"`, `"theta"`, `"theta1"`, `"theta2"`).
    pub name: &'static str,
    /// Index of the measured state in the plant's state vector.
    pub state: usize,
    /// Resolution: one count corresponds to `step` \[m or rad\].
    pub step: f64,
}

/// One velocity estimate as the rig computes it: the derivative of an encoder position passed
/// through `1/(T s + 1)` (a "pseudo-differentiator" `s/(T s + 1)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityEstimatorSpec {
    /// Index of the position state it differentiates.
    pub position_state: usize,
    /// Index of the velocity state it estimates.
    pub velocity_state: usize,
    /// Filter time constant `T` \[s\] (0.02 s on both rigs).
    pub time_constant: f64,
}

/// The numbers of one real rig (`docs/model.md` §3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigSpec {
    /// Which rig (`"cart"`, `"arm"`).
    pub name: &'static str,
    /// Number of plant states (4 on both rigs).
    pub nx: usize,
    /// Controller sample time with zero-order hold \[s\] (1 ms).
    pub sample_time: f64,
    /// The command saturates at `±input_limit` \[V\] (5 V).
    pub input_limit: f64,
    /// The D/A converter (16 bits over ±5 V).
    pub dac: DacSpec,
    /// The encoders, one per measured position state.
    pub encoders: [EncoderSpec; 2],
    /// The velocity estimators, one per velocity state.
    pub velocity_estimators: [VelocityEstimatorSpec; 2],
}

const DAC: DacSpec = DacSpec {
    bits: 16,
    min: -5.0,
    max: 5.0,
};
const PSEUDO_DIFFERENTIATOR_T: f64 = 0.02;

impl RigSpec {
    /// The cart-type rig: state `[z, θ, ż, θ̇]`; cart encoder `4.8414·10⁻⁵ m` per count,
    /// pendulum encoder `2π/14400 rad` per count; velocities of states 2 and 3 from positions
    /// 0 and 1.
    pub fn cart() -> Self {
        Self {
            name: "cart",
            nx: 4,
            sample_time: 1e-3,
            input_limit: 5.0,
            dac: DAC,
            encoders: [
                EncoderSpec {
                    name: "z",
                    state: 0,
                    step: 4.8414e-5,
                },
                EncoderSpec {
                    name: "theta",
                    state: 1,
                    step: 2.0 * PI / 14400.0,
                },
            ],
            velocity_estimators: Self::estimators(),
        }
    }

    /// The arm-type rig: state `[θ₁, θ₂, θ̇₁, θ̇₂]`; arm encoder `2π/200000 rad` per count,
    /// pendulum encoder `2π/14400 rad` per count; velocities of states 2 and 3 from positions
    /// 0 and 1.
    pub fn arm() -> Self {
        Self {
            name: "arm",
            nx: 4,
            sample_time: 1e-3,
            input_limit: 5.0,
            dac: DAC,
            encoders: [
                EncoderSpec {
                    name: "theta1",
                    state: 0,
                    step: 2.0 * PI / 200_000.0,
                },
                EncoderSpec {
                    name: "theta2",
                    state: 1,
                    step: 2.0 * PI / 14400.0,
                },
            ],
            velocity_estimators: Self::estimators(),
        }
    }

    fn estimators() -> [VelocityEstimatorSpec; 2] {
        [
            VelocityEstimatorSpec {
                position_state: 0,
                velocity_state: 2,
                time_constant: PSEUDO_DIFFERENTIATOR_T,
            },
            VelocityEstimatorSpec {
                position_state: 1,
                velocity_state: 3,
                time_constant: PSEUDO_DIFFERENTIATOR_T,
            },
        ]
    }

    /// Indices of the measured position states, in encoder order.
    pub fn measured_states(&self) -> [usize; 2] {
        [self.encoders[0].state, self.encoders[1].state]
    }
}

/// Which rig: the cart-type or the arm-type pendulum. The one rig enum of the workspace:
/// the emulator, the runtime, the log and the controller factory
/// (`pendulab_control::spec::build`) all take it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlantKind {
    /// The cart-type pendulum, state `[z, θ, ż, θ̇]`.
    Cart,
    /// The arm-type pendulum, state `[θ₁, θ₂, θ̇₁, θ̇₂]`.
    Arm,
}

impl PlantKind {
    /// The rig's numbers (encoders, D/A, sample time).
    pub fn spec(self) -> RigSpec {
        match self {
            PlantKind::Cart => RigSpec::cart(),
            PlantKind::Arm => RigSpec::arm(),
        }
    }

    /// `"cart"` or `"arm"`.
    pub fn name(self) -> &'static str {
        match self {
            PlantKind::Cart => "cart",
            PlantKind::Arm => "arm",
        }
    }

    /// Parses `"cart"` or `"arm"`.
    ///
    /// # Errors
    /// [`UnknownPlant`] for any other name.
    pub fn parse(s: &str) -> Result<Self, UnknownPlant> {
        match s {
            "cart" => Ok(PlantKind::Cart),
            "arm" => Ok(PlantKind::Arm),
            other => Err(UnknownPlant(other.to_string())),
        }
    }
}

/// A plant name other than `"cart"` or `"arm"` ([`PlantKind::parse`]), as written.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("plant '{0}': expected 'cart' or 'arm'")]
pub struct UnknownPlant(pub String);

#[cfg(test)]
mod plant_kind_tests {
    use super::*;

    #[test]
    fn names_parse_back_and_others_are_refused_by_name() {
        for p in [PlantKind::Cart, PlantKind::Arm] {
            assert_eq!(PlantKind::parse(p.name()), Ok(p));
            assert_eq!(p.spec().name, p.name());
        }
        let e = PlantKind::parse("boat").unwrap_err();
        assert_eq!(e.to_string(), "plant 'boat': expected 'cart' or 'arm'");
    }
}
