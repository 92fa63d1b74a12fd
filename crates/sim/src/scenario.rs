//! The scenario specification: what a simulation run does to a closed loop — where it starts,
//! the reference and disturbance signals it applies, how long and how fast it samples, and
//! which of the rig's imperfections are on (`docs/model.md` §6).
//!
//! A [`ScenarioSpec`] is plain data (serde), generic over the plant: the initial state is a
//! vector in the plant's state layout, the reference is the signal for the drive position
//! `q₀` (the output a servo tracks), the disturbance is added to the plant input. Front ends
//! read it from TOML or JSON; `pendulab_control::scenario::simulate` runs it. A scenario file
//! reads:
//!
//! ```toml
//! initial_state = [0.0, 0.1, 0.0, 0.0]   # plant state layout, SI units and rad
//! duration = 5.0                          # s
//! reference = { kind = "step", time = 1.0, amplitude = 0.2 }
//! disturbance = { kind = "zero" }         # V, added to the plant input
//!
//! [imperfections]                         # all off unless written
//! quantization = true
//! pseudo_differentiator = true
//! saturation = true
//! dac = true
//! delay_samples = 1
//! noise = { std = [0.0, 0.0, 0.0, 0.0], seed = 7 }
//! ```
//!
//! ```
//! use pendulab_sim::scenario::{ScenarioSpec, SignalSpec};
//! # fn main() -> Result<(), pendulab_sim::scenario::ScenarioSpecError> {
//! let s = ScenarioSpec::from_toml(
//!     "initial_state = [0.0, 0.1, 0.0, 0.0]\nduration = 5.0\n\
//!      reference = { kind = \"step\", time = 1.0, amplitude = 0.2 }\n",
//! )?;
//! assert_eq!(s.reference, SignalSpec::Step { time: 1.0, amplitude: 0.2 });
//! assert_eq!(s.reference.to_signal("scenario.reference")?.value(1.5), 0.2);
//! // Keys are checked by name.
//! let e = ScenarioSpec::from_toml("initial_state = [0.0]\nduration = -1.0\n").unwrap_err();
//! assert!(e.to_string().contains("scenario.duration"));
//! # Ok(()) }
//! ```

use crate::error::SimError;
use crate::signal::Signal;
use serde::{Deserialize, Serialize};

/// Most substeps of the plant integrator per sample ([`ScenarioSpec::substeps`]).
pub const SUBSTEPS_MAX: usize = 1000;
/// Most whole samples of computation delay ([`Imperfections::delay_samples`]).
pub const DELAY_SAMPLES_MAX: usize = 1000;

/// A scalar signal of time as data (`{ kind = "…", … }`); [`SignalSpec::to_signal`] builds the
/// [`Signal`]. Units are those of what it drives (m or rad for a reference, V for a
/// disturbance). Switches are right-continuous (the new value holds from the switch time on).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum SignalSpec {
    /// `kind = "zero"`: `s(t) = 0` (the default).
    #[default]
    Zero,
    /// `kind = "constant"`: `s(t) = value` (finite).
    Constant {
        /// The value.
        value: f64,
    },
    /// `kind = "step"`: `0` before `time` \[s\], `amplitude` from then on (both finite).
    Step {
        /// Switch time \[s\].
        time: f64,
        /// Value after the switch.
        amplitude: f64,
    },
    /// `kind = "steps"`: a sequence of steps, `0` before `times[0]`, `values[i]` from
    /// `times[i]` \[s\] on (equal lengths, at least one; times finite and increasing).
    Steps {
        /// Switch times \[s\].
        times: Vec<f64>,
        /// Value held from each switch time.
        values: Vec<f64>,
    },
    /// `kind = "sine"`: `offset + amplitude · sin(omega · t + phase)`.
    Sine {
        /// Amplitude (finite).
        amplitude: f64,
        /// Angular frequency `ω` \[rad/s\] (finite).
        omega: f64,
        /// Phase `φ` \[rad\] (key optional, default 0).
        #[serde(default)]
        phase: f64,
        /// Constant added (key optional, default 0).
        #[serde(default)]
        offset: f64,
    },
}

impl SignalSpec {
    /// The signal, validated; `key` names it in errors (`scenario.reference`, …).
    ///
    /// # Errors
    /// [`ScenarioSpecError::Signal`] naming `key` for a non-finite number, step lists of
    /// different lengths, no steps, or times not increasing.
    pub fn to_signal(&self, key: &str) -> Result<Signal, ScenarioSpecError> {
        let wrap = |source| ScenarioSpecError::Signal {
            key: key.to_string(),
            source,
        };
        match self {
            SignalSpec::Zero => Ok(Signal::zero()),
            SignalSpec::Constant { value } => Signal::constant(*value).map_err(wrap),
            SignalSpec::Step { time, amplitude } => Signal::step(*time, *amplitude).map_err(wrap),
            SignalSpec::Steps { times, values } => {
                Signal::piecewise_constant(times, values).map_err(wrap)
            }
            SignalSpec::Sine {
                amplitude,
                omega,
                phase,
                offset,
            } => Ok(Signal::sine(*amplitude, *omega, *phase).map_err(wrap)?
                + Signal::constant(*offset).map_err(wrap)?),
        }
    }

    /// The value the signal settles at, if it has one: `0`, the constant, the step's
    /// amplitude, the last step's value; `None` for a sine.
    pub fn final_value(&self) -> Option<f64> {
        match self {
            SignalSpec::Zero => Some(0.0),
            SignalSpec::Constant { value } => Some(*value),
            SignalSpec::Step { amplitude, .. } => Some(*amplitude),
            SignalSpec::Steps { values, .. } => values.last().copied(),
            SignalSpec::Sine { .. } => None,
        }
    }

    /// Whether this is [`SignalSpec::Zero`].
    pub fn is_zero(&self) -> bool {
        matches!(self, SignalSpec::Zero)
    }
}

/// Gaussian measurement noise (`noise = { std = […], seed = … }`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseSpec {
    /// Standard deviation per measurement channel (units of the channel; finite, ≥ 0; one per
    /// channel, 4 on the book rigs).
    pub std: Vec<f64>,
    /// Seed of the ChaCha8 generator: the same seed gives the same run.
    pub seed: u64,
}

/// The imperfections a run switches on (`[imperfections]`); every key optional, every rig
/// effect off by default (the ideal loop `y = x`, command = plant input, no delay). Which
/// numbers they use (encoder steps, ±limit, D/A bits, friction) is the plant's rig part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Imperfections {
    /// Encoder quantisation of the measured positions.
    pub quantization: bool,
    /// Velocities by the rig's pseudo-differentiator of the (quantised) positions, instead of
    /// the exact velocities.
    pub pseudo_differentiator: bool,
    /// Command saturation at the rig's input limit.
    pub saturation: bool,
    /// D/A quantisation of the command.
    pub dac: bool,
    /// The rig's drive friction (dead zone or Coulomb, in volts); the rig part must have one.
    pub drive_friction: bool,
    /// The model's viscous pivot friction (`μ_p` or `μ₂`); on by default, `false` sets it to 0.
    pub pivot_friction: bool,
    /// Whole samples between a measurement and its command reaching the plant
    /// (0 to [`DELAY_SAMPLES_MAX`]).
    pub delay_samples: usize,
    /// Measurement noise (key optional, default none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub noise: Option<NoiseSpec>,
}

impl Default for Imperfections {
    fn default() -> Self {
        Self {
            quantization: false,
            pseudo_differentiator: false,
            saturation: false,
            dac: false,
            drive_friction: false,
            pivot_friction: true,
            delay_samples: 0,
            noise: None,
        }
    }
}

impl Imperfections {
    /// The ideal loop (the default): no rig effect, no delay, no noise, the model's pivot
    /// friction.
    pub fn ideal() -> Self {
        Self::default()
    }

    /// The rig's plant "with quantizer" (`docs/model.md` §3): encoder quantisation,
    /// pseudo-differentiated velocities, saturation and D/A; no friction, delay or noise.
    pub fn with_quantizer() -> Self {
        Self {
            quantization: true,
            pseudo_differentiator: true,
            saturation: true,
            dac: true,
            ..Self::default()
        }
    }
}

fn one() -> usize {
    1
}

/// A simulation scenario (module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScenarioSpec {
    /// Initial plant state, in the plant's state layout (e.g. `[z, θ, ż, θ̇]` in m, rad, m/s,
    /// rad/s); finite, its length the plant's state count.
    pub initial_state: Vec<f64>,
    /// Reference of the drive position `q₀` \[m or rad\] (key optional, default zero).
    #[serde(default, skip_serializing_if = "SignalSpec::is_zero")]
    pub reference: SignalSpec,
    /// Input disturbance \[V\], added to the plant input after the amplifier (not saturated
    /// or quantised) (key optional, default zero).
    #[serde(default, skip_serializing_if = "SignalSpec::is_zero")]
    pub disturbance: SignalSpec,
    /// Length of the run \[s\] (finite, > 0).
    pub duration: f64,
    /// Controller sample time \[s\] (finite, > 0); key optional, default: the plant's rig.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sample_time: Option<f64>,
    /// Classical RK4 steps of the plant per sample (1 to [`SUBSTEPS_MAX`]; default 1).
    #[serde(default = "one")]
    pub substeps: usize,
    /// Which imperfections are on (default none).
    #[serde(default)]
    pub imperfections: Imperfections,
}

impl ScenarioSpec {
    /// The ideal scenario: from `initial_state` for `duration` \[s\], zero reference and
    /// disturbance, the rig's sample time, one RK4 step per sample, no imperfections.
    pub fn new(initial_state: Vec<f64>, duration: f64) -> Self {
        Self {
            initial_state,
            reference: SignalSpec::Zero,
            disturbance: SignalSpec::Zero,
            duration,
            sample_time: None,
            substeps: 1,
            imperfections: Imperfections::default(),
        }
    }

    /// Checks every number against the range written on its field (the initial state's
    /// length is checked against the plant by the runner).
    ///
    /// # Errors
    /// [`ScenarioSpecError`] naming the key (`scenario.duration`,
    /// `scenario.initial_state[1]`, `scenario.reference`, …).
    pub fn validate(&self) -> Result<(), ScenarioSpecError> {
        let bad = |key: String, value: f64, range: &'static str| ScenarioSpecError::Invalid {
            key,
            value,
            range,
        };
        if self.initial_state.is_empty() {
            return Err(ScenarioSpecError::Empty("scenario.initial_state"));
        }
        if let Some((i, &v)) = self
            .initial_state
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite())
        {
            return Err(bad(format!("scenario.initial_state[{i}]"), v, "finite"));
        }
        if !(self.duration.is_finite() && self.duration > 0.0) {
            return Err(bad(
                "scenario.duration".into(),
                self.duration,
                "finite and > 0 s",
            ));
        }
        if let Some(ts) = self.sample_time
            && !(ts.is_finite() && ts > 0.0)
        {
            return Err(bad("scenario.sample_time".into(), ts, "finite and > 0 s"));
        }
        if !(1..=SUBSTEPS_MAX).contains(&self.substeps) {
            return Err(bad(
                "scenario.substeps".into(),
                self.substeps as f64,
                "1 to 1000",
            ));
        }
        let imp = &self.imperfections;
        if imp.delay_samples > DELAY_SAMPLES_MAX {
            return Err(bad(
                "scenario.imperfections.delay_samples".into(),
                imp.delay_samples as f64,
                "0 to 1000",
            ));
        }
        if let Some(n) = &imp.noise {
            if n.std.is_empty() {
                return Err(ScenarioSpecError::Empty("scenario.imperfections.noise.std"));
            }
            if let Some((i, &v)) = n
                .std
                .iter()
                .enumerate()
                .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
            {
                return Err(bad(
                    format!("scenario.imperfections.noise.std[{i}]"),
                    v,
                    "finite and >= 0",
                ));
            }
        }
        self.reference.to_signal("scenario.reference")?;
        self.disturbance.to_signal("scenario.disturbance")?;
        Ok(())
    }

    /// The scenario as TOML text, which [`ScenarioSpec::from_toml`] reads back to an equal
    /// value.
    ///
    /// # Errors
    /// [`ScenarioSpecError::Write`] if the TOML writer refuses a value (a non-finite number).
    pub fn to_toml(&self) -> Result<String, ScenarioSpecError> {
        toml::to_string(self).map_err(ScenarioSpecError::Write)
    }

    /// Reads and validates a scenario file.
    ///
    /// # Errors
    /// [`ScenarioSpecError::Toml`] for syntax errors and unknown, missing or mistyped keys
    /// (naming key and line); the errors of [`ScenarioSpec::validate`].
    pub fn from_toml(text: &str) -> Result<Self, ScenarioSpecError> {
        let spec: Self = toml::from_str(text).map_err(ScenarioSpecError::Toml)?;
        spec.validate()?;
        Ok(spec)
    }
}

/// What is wrong with a scenario; each message names the key as written in a scenario file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ScenarioSpecError {
    /// A number outside its range.
    #[error("{key} = {value}: must be {range}")]
    Invalid {
        /// The key.
        key: String,
        /// Its value.
        value: f64,
        /// The range, with unit.
        range: &'static str,
    },
    /// A list that must not be empty.
    #[error("{0}: must not be empty")]
    Empty(&'static str),
    /// A signal that cannot be built.
    #[error("{key}: {source}")]
    Signal {
        /// The signal's key.
        key: String,
        /// The signal constructor's error.
        source: SimError,
    },
    /// The text is not a scenario file (syntax, unknown/missing/mistyped key; with the line).
    #[error("scenario file: {0}")]
    Toml(toml::de::Error),
    /// The TOML writer refused a value.
    #[error("writing the scenario file: {0}")]
    Write(toml::ser::Error),
}
