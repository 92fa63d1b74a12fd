//! What the real rigs add to the models, as plain numbers (`docs/model.md` §3).
//!
//! A [`RigSpec`] lists, for one rig, the sample time, the amplifier's input range and D/A
//! converter, the encoders (which state each measures, its resolution and zero), the velocity
//! estimators (which position feeds which velocity, with the pseudo-differentiator's time
//! constant), the drive's friction, and the travel and angle limits of a run. It is the rig
//! part of a [`crate::spec::PlantSpec`] and reads and writes as the `[rig]` table of a plant
//! file (serde; `docs/model.md` §6). The simulator builds its sensor and actuator chains from
//! these numbers ([`RigSpec::chains`]); nothing here simulates anything.
//!
//! ```
//! use pendulab_plants::RigSpec;
//! let rig = RigSpec::cart();
//! assert_eq!(rig.dac.step(), 10.0 / 65536.0);
//! assert_eq!(rig.encoders[1].state, 1); // θ
//! assert_eq!(rig.encoders[1].step, 2.0 * std::f64::consts::PI / 14400.0);
//! ```

use crate::spec::PlantSpecError;
use pendulab_sim::actuator::Friction;
use pendulab_sim::rig::RigChains;
use pendulab_sim::scenario::Imperfections;
use pendulab_sim::{Actuator, SensorChain, SimError};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The D/A converter that produces the motor command (`[rig.dac]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
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

/// The coordinate an encoder measures, as written in a plant file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Coordinate {
    /// The cart position `z` \[m\] (cart rig, state 0).
    Z,
    /// The cart rig's pendulum angle `θ` \[rad\] (state 1).
    Theta,
    /// The arm angle `θ₁` \[rad\] (arm rig, state 0).
    Theta1,
    /// The arm rig's pendulum angle `θ₂` \[rad\] (state 1).
    Theta2,
}

impl Coordinate {
    /// `"z"`, `"theta"`, `"theta1"` or `"theta2"`.
    pub fn name(self) -> &'static str {
        match self {
            Coordinate::Z => "z",
            Coordinate::Theta => "theta",
            Coordinate::Theta1 => "theta1",
            Coordinate::Theta2 => "theta2",
        }
    }

    /// The two measured coordinates of a rig, drive first.
    pub fn of(kind: PlantKind) -> [Coordinate; 2] {
        match kind {
            PlantKind::Cart => [Coordinate::Z, Coordinate::Theta],
            PlantKind::Arm => [Coordinate::Theta1, Coordinate::Theta2],
        }
    }
}

/// One incremental encoder (`[[rig.encoders]]`): the state it measures, its resolution and
/// its zero.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EncoderSpec {
    /// What it measures.
    pub coordinate: Coordinate,
    /// Index of the measured state in the plant's state vector.
    pub state: usize,
    /// Resolution: one count corresponds to `step` \[m or rad\] (> 0).
    pub step: f64,
    /// The coordinate's value at count 0 \[m or rad\] (key optional, default 0): the rig
    /// reports `zero_offset + step · count`. The book rigs' pendulum encoders are powered up
    /// with the pendulum hanging, so they count from `θ = π` (the rig emulator's convention,
    /// `docs/model.md` §3); the drive encoders count from the start position (0). The
    /// simulator quantises on the grid through 0, which is the same grid when the offset is a
    /// whole number of counts (π is 7200 counts of `2π/14400`); [`RigSpec::validate`] requires
    /// that.
    #[serde(default)]
    pub zero_offset: f64,
}

/// One velocity estimate as the rig computes it (`[[rig.velocity_estimators]]`): the
/// derivative of an encoder position passed through `1/(T s + 1)` (a "pseudo-differentiator"
/// `s/(T s + 1)`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VelocityEstimatorSpec {
    /// Index of the position state it differentiates.
    pub position_state: usize,
    /// Index of the velocity state it estimates.
    pub velocity_state: usize,
    /// Filter time constant `T` \[s\] (0.02 s on both rigs).
    pub time_constant: f64,
}

/// Friction of the drive in voltage-equivalent units (`[rig.friction]`, tag `model`), as
/// `pendulab_sim::Friction` applies it on the motor command (`docs/model.md` §3: the book
/// notes the drive's static and Coulomb friction, part 1 §3.2, but tables 3.5 and 3.7 give no
/// values; the book rigs have none here).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "kebab-case", deny_unknown_fields)]
pub enum DriveFriction {
    /// `model = "dead-zone"`: commands within `±width` \[V\] (≥ 0) do not move the drive.
    DeadZone {
        /// Half-width of the dead zone \[V\] (≥ 0).
        width: f64,
    },
    /// `model = "coulomb"`: Karnopp stick–slip friction on the drive velocity (state 2).
    Coulomb {
        /// Sliding level `V_c` \[V\] (≥ 0).
        coulomb: f64,
        /// Break-away level `V_s` \[V\] (≥ `coulomb`).
        stiction: f64,
        /// Band of drive velocity counted as stopped \[m/s or rad/s\] (> 0).
        velocity_band: f64,
    },
}

/// The numbers of one real rig (`docs/model.md` §3), the `[rig]` table of a plant file.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigSpec {
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
    /// Friction of the drive (key optional; none on the book rigs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<DriveFriction>,
    /// A run stops when the drive position `|q₀|` exceeds this \[m or rad\] (> 0; the rig
    /// runtime's defaults, 0.4 m on the cart rig and 3 rad on the arm rig, `docs/model.md`
    /// §3).
    pub travel_limit: f64,
    /// A balance run counts as failed when the pendulum angle leaves `±angle_window_deg` of
    /// upright \[°\] (in (0, 90]; the rig runtime's default 30°).
    pub angle_window_deg: f64,
}

const DAC: DacSpec = DacSpec {
    bits: 16,
    min: -5.0,
    max: 5.0,
};
const PSEUDO_DIFFERENTIATOR_T: f64 = 0.02;
/// The rig runtime's default window about upright \[°\] (`docs/model.md` §3).
const ANGLE_WINDOW_DEG: f64 = 30.0;

impl RigSpec {
    /// The cart-type rig: state `[z, θ, ż, θ̇]`; cart encoder `4.8414·10⁻⁵ m` per count,
    /// pendulum encoder `2π/14400 rad` per count counting from the hanging rest; velocities of
    /// states 2 and 3 from positions 0 and 1; no drive friction; travel ±0.4 m, window ±30°.
    pub fn cart() -> Self {
        Self {
            nx: 4,
            sample_time: 1e-3,
            input_limit: 5.0,
            dac: DAC,
            encoders: [
                EncoderSpec {
                    coordinate: Coordinate::Z,
                    state: 0,
                    step: 4.8414e-5,
                    zero_offset: 0.0,
                },
                EncoderSpec {
                    coordinate: Coordinate::Theta,
                    state: 1,
                    step: 2.0 * PI / 14400.0,
                    zero_offset: PI,
                },
            ],
            velocity_estimators: Self::estimators(),
            friction: None,
            travel_limit: 0.4,
            angle_window_deg: ANGLE_WINDOW_DEG,
        }
    }

    /// The arm-type rig: state `[θ₁, θ₂, θ̇₁, θ̇₂]`; arm encoder `2π/200000 rad` per count,
    /// pendulum encoder `2π/14400 rad` per count counting from the hanging rest; velocities of
    /// states 2 and 3 from positions 0 and 1; no drive friction; travel ±3 rad, window ±30°.
    pub fn arm() -> Self {
        Self {
            nx: 4,
            sample_time: 1e-3,
            input_limit: 5.0,
            dac: DAC,
            encoders: [
                EncoderSpec {
                    coordinate: Coordinate::Theta1,
                    state: 0,
                    step: 2.0 * PI / 200_000.0,
                    zero_offset: 0.0,
                },
                EncoderSpec {
                    coordinate: Coordinate::Theta2,
                    state: 1,
                    step: 2.0 * PI / 14400.0,
                    zero_offset: PI,
                },
            ],
            velocity_estimators: Self::estimators(),
            friction: None,
            travel_limit: 3.0,
            angle_window_deg: ANGLE_WINDOW_DEG,
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

    /// The book rig of `kind` ([`RigSpec::cart`] or [`RigSpec::arm`]).
    pub fn book(kind: PlantKind) -> Self {
        match kind {
            PlantKind::Cart => Self::cart(),
            PlantKind::Arm => Self::arm(),
        }
    }

    /// The angle window \[rad\] (`angle_window_deg` in radians).
    pub fn angle_window(&self) -> f64 {
        self.angle_window_deg.to_radians()
    }

    /// Checks every number against the range written on its field, for a rig of `kind`
    /// (whose encoders must measure `kind`'s coordinates, [`Coordinate::of`]).
    ///
    /// # Errors
    /// [`PlantSpecError::Invalid`] naming the key (`rig.sample_time`, `rig.encoders[1].step`, …),
    /// its value and the range.
    pub fn validate(&self, kind: PlantKind) -> Result<(), PlantSpecError> {
        let bad = |key: String, value: f64, range: &'static str| PlantSpecError::Invalid {
            key,
            value,
            range,
        };
        let positive = |key: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(bad(key.into(), v, "finite and > 0"))
            }
        };
        if self.nx != 4 {
            return Err(bad("rig.nx".into(), self.nx as f64, "4 (both rigs)"));
        }
        positive("rig.sample_time", self.sample_time)?;
        positive("rig.input_limit", self.input_limit)?;
        if !(1..=32).contains(&self.dac.bits) {
            return Err(bad("rig.dac.bits".into(), self.dac.bits as f64, "1 to 32"));
        }
        for (key, v) in [("rig.dac.min", self.dac.min), ("rig.dac.max", self.dac.max)] {
            if !v.is_finite() {
                return Err(bad(key.into(), v, "finite"));
            }
        }
        if self.dac.max <= self.dac.min {
            return Err(bad("rig.dac.max".into(), self.dac.max, "above rig.dac.min"));
        }
        let coords = Coordinate::of(kind);
        for (i, e) in self.encoders.iter().enumerate() {
            if e.coordinate != coords[i] || e.state != i {
                return Err(PlantSpecError::Encoder {
                    index: i,
                    expected: coords[i].name(),
                    state: i,
                });
            }
            positive(&format!("rig.encoders[{i}].step"), e.step)?;
            let counts = e.zero_offset / e.step;
            if !(e.zero_offset.is_finite() && (counts - counts.round()).abs() < 1e-6) {
                return Err(bad(
                    format!("rig.encoders[{i}].zero_offset"),
                    e.zero_offset,
                    "finite, a whole number of encoder steps",
                ));
            }
        }
        for (i, v) in self.velocity_estimators.iter().enumerate() {
            if v.position_state != i || v.velocity_state != i + 2 {
                return Err(bad(
                    format!("rig.velocity_estimators[{i}].velocity_state"),
                    v.velocity_state as f64,
                    "position i feeds velocity i + 2 (states [q0, q1, q0', q1'])",
                ));
            }
            positive(
                &format!("rig.velocity_estimators[{i}].time_constant"),
                v.time_constant,
            )?;
        }
        match self.friction {
            None => {}
            Some(DriveFriction::DeadZone { width }) if !(width.is_finite() && width >= 0.0) => {
                return Err(bad("rig.friction.width".into(), width, "finite and >= 0"));
            }
            Some(DriveFriction::DeadZone { .. }) => {}
            Some(DriveFriction::Coulomb {
                coulomb,
                stiction,
                velocity_band,
            }) => {
                if !(coulomb.is_finite() && coulomb >= 0.0) {
                    return Err(bad(
                        "rig.friction.coulomb".into(),
                        coulomb,
                        "finite and >= 0",
                    ));
                }
                if !(stiction.is_finite() && stiction >= coulomb) {
                    return Err(bad(
                        "rig.friction.stiction".into(),
                        stiction,
                        "finite and >= rig.friction.coulomb",
                    ));
                }
                positive("rig.friction.velocity_band", velocity_band)?;
            }
        }
        positive("rig.travel_limit", self.travel_limit)?;
        let w = self.angle_window_deg;
        if !(w.is_finite() && w > 0.0 && w <= 90.0) {
            return Err(bad("rig.angle_window_deg".into(), w, "(0, 90] degrees"));
        }
        Ok(())
    }

    /// The sensor and actuator chains of this rig with the `effects` a scenario switches on:
    /// encoders `(state, step)` when `quantization`, pseudo-differentiated velocities when
    /// `pseudo_differentiator` (else exact), saturation `±input_limit` and the D/A (its
    /// `bits` over `[min, max]`, as `pendulab_sim::Actuator::rig` for `min = −max`) when
    /// `saturation`/`dac`, the drive friction (on input 0, velocity state 2) when
    /// `drive_friction`, the seeded measurement noise when given. The delay and the pivot
    /// friction are the loop's and the model's, not the chains'. With
    /// [`Imperfections::with_quantizer`] this is `RigChains::with_quantizer` of the rig's
    /// numbers.
    ///
    /// # Errors
    /// [`SimError`] from the chains' builders for numbers they refuse (none for a rig that
    /// passed [`RigSpec::validate`]; a noise list of the wrong length);
    /// [`SimError::InvalidArgument`] for `drive_friction` on a rig without friction.
    pub fn chains(&self, effects: &Imperfections) -> Result<RigChains, SimError> {
        let encoders: Vec<(usize, f64)> = if effects.quantization {
            self.encoders.iter().map(|e| (e.state, e.step)).collect()
        } else {
            Vec::new()
        };
        let sensor = if effects.pseudo_differentiator {
            let velocities: Vec<(usize, usize, f64)> = self
                .velocity_estimators
                .iter()
                .map(|v| (v.position_state, v.velocity_state, v.time_constant))
                .collect();
            SensorChain::state_layout(self.nx, &encoders, &velocities)?
        } else {
            SensorChain::state_layout(self.nx, &encoders, &[])?
        };
        let sensor = match &effects.noise {
            Some(n) => sensor.noise(&n.std, n.seed)?,
            None => sensor,
        };
        let mut actuator = Actuator::ideal();
        if effects.saturation {
            actuator = actuator.saturation(self.input_limit)?;
        }
        if effects.dac {
            let q = pendulab_sim::Quantizer::from_bits(self.dac.bits, self.dac.max - self.dac.min)?;
            actuator = actuator.dac(q)?;
        }
        if effects.drive_friction {
            let f = match self.friction {
                None => {
                    return Err(SimError::InvalidArgument(
                        "drive friction switched on for a rig without rig.friction".into(),
                    ));
                }
                Some(DriveFriction::DeadZone { width }) => Friction::DeadZone { input: 0, width },
                Some(DriveFriction::Coulomb {
                    coulomb,
                    stiction,
                    velocity_band,
                }) => Friction::Coulomb {
                    input: 0,
                    velocity_state: self.velocity_estimators[0].velocity_state,
                    coulomb,
                    stiction,
                    velocity_band,
                },
            };
            actuator = actuator.friction(f);
        }
        Ok(RigChains { sensor, actuator })
    }
}

/// Which rig: the cart-type or the arm-type pendulum. The one rig enum of the workspace:
/// the emulator, the runtime, the log and the controller factory
/// (`pendulab_control::spec::build`) all take it; written `"cart"` or `"arm"` in a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PlantKind {
    /// The cart-type pendulum, state `[z, θ, ż, θ̇]`.
    Cart,
    /// The arm-type pendulum, state `[θ₁, θ₂, θ̇₁, θ̇₂]`.
    Arm,
}

impl PlantKind {
    /// The rig's numbers (encoders, D/A, sample time): [`RigSpec::book`].
    pub fn spec(self) -> RigSpec {
        RigSpec::book(self)
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
            assert_eq!(p.spec().encoders.map(|e| e.coordinate), Coordinate::of(p));
        }
        let e = PlantKind::parse("boat").unwrap_err();
        assert_eq!(e.to_string(), "plant 'boat': expected 'cart' or 'arm'");
    }
}
