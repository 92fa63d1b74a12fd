//! [`SpecError`]: what the controller factory refuses, each message naming the key as written
//! in a controller file.

use pendulab_lti::LtiError;
use pendulab_plants::PlantError;
use pendulab_plants::rig::PlantKind;

/// What [`build`](super::build) refuses. Each message names the key as written in a controller file
/// (`controller.…`), its value and what is wrong.
#[derive(Debug, thiserror::Error)]
pub enum SpecError {
    /// The loop period is not a positive finite number.
    #[error("sample time ts = {ts}: must be finite and > 0")]
    SampleTime {
        /// The period given \[s\].
        ts: f64,
    },
    /// An entry is NaN or infinite.
    #[error("{key}[{index}] = {value}: must be finite")]
    NotFinite {
        /// The key.
        key: String,
        /// The entry's index.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// A list has the wrong number of entries.
    #[error("{key} has {got} {entries}, expected {expected}")]
    Length {
        /// The key.
        key: String,
        /// `"entries"` or `"diagonal entries"`.
        entries: &'static str,
        /// Entries given.
        got: usize,
        /// Entries required.
        expected: usize,
    },
    /// The servo's (or the PID's) reference is not one value.
    #[error("controller.reference of a {kind} is one value (of q0), got {got}")]
    ServoReferenceLength {
        /// The controller's `kind`.
        kind: &'static str,
        /// Entries given.
        got: usize,
    },
    /// A diagonal weight entry is negative.
    #[error("{key}[{index}] = {value}: must be ≥ 0")]
    Negative {
        /// The key.
        key: String,
        /// The entry's index.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The input weight `r` is not positive and finite.
    #[error("{key}.r = {value}: must be finite and > 0")]
    InputWeight {
        /// The `lqr` key.
        key: String,
        /// Its `r`.
        value: f64,
    },
    /// A number outside its documented range.
    #[error("{key} = {value}: must be in {range}")]
    OutOfRange {
        /// The key.
        key: &'static str,
        /// Its value.
        value: f64,
        /// The range, with unit.
        range: String,
    },
    /// A required key is missing, or keys that exclude each other are given together.
    #[error("{key}: {expected}")]
    Keys {
        /// The table (`controller`, `controller (lq-servo)`, …).
        key: String,
        /// What it must hold.
        expected: &'static str,
    },
    /// An unknown scheduling variable.
    #[error("controller.schedule = '{0}': expected 'one-minus-cos-q0' or 'q0-squared'")]
    Schedule(String),
    /// A coefficient of `X(ρ)` that is not symmetric, or `X(0)` not positive definite.
    #[error("{key}: {detail}")]
    ScheduleMatrix {
        /// The key (`controller.x_coefficients[i]`).
        key: String,
        /// What is wrong.
        detail: String,
    },
    /// `design_points_deg` given for a plant or a schedule it does not apply to, or points
    /// that do not determine the interpolation.
    #[error("controller.design_points_deg{detail}")]
    DesignPoints {
        /// What is wrong (with the points when they are the problem).
        detail: String,
    },
    /// The book plant could not be linearised.
    #[error("linearising the {at}: {source}")]
    Linearisation {
        /// Which plant and where (`cart plant`, `arm at 60°`).
        at: String,
        /// The plant's error.
        source: PlantError,
    },
    /// An LQR or LQ-servo design failed.
    #[error("{what} failed: {source}")]
    Design {
        /// The design (`controller: LQR design`, `LQR design at θ₁ = 60°`, …).
        what: String,
        /// The design's error.
        source: LtiError,
    },
    /// The servo's design model could not be formed.
    #[error("servo model: {0}")]
    ServoModel(LtiError),
    /// A run-time controller refused its parameters.
    #[error("controller: {0}")]
    Controller(#[from] pendulab_sim::SimError),
    /// The swing-up controller refused its parameters.
    #[error("controller: {0}")]
    SwingUp(#[from] crate::ControlError),
    /// A reference given twice (scenario and spec) or to a kind that tracks none.
    #[error("controller ({kind}): {detail}")]
    Reference {
        /// The controller's `kind`.
        kind: &'static str,
        /// What is wrong.
        detail: &'static str,
    },
    /// The controller was designed for the other plant kind (its `designed_for.plant`).
    #[error(
        "controller.designed_for.plant = \"{}\": the controller was designed for the {} pendulum and cannot run on the {} pendulum",
        designed.name(), designed.name(), plant.name()
    )]
    WrongPlant {
        /// The plant kind of the design record.
        designed: PlantKind,
        /// The plant kind it was to run on.
        plant: PlantKind,
    },
    /// A kind that exists for one plant only, given for the other.
    #[error(
        "controller.kind = \"{kind}\": runs on the {} pendulum only, not on the {} pendulum",
        only.name(), plant.name()
    )]
    NotForPlant {
        /// The controller's `kind`.
        kind: &'static str,
        /// The plant it was to run on.
        plant: PlantKind,
        /// The plant it is made for.
        only: PlantKind,
    },
    /// The design record is malformed.
    #[error("{key}: {detail}")]
    DesignRecord {
        /// The key (`controller.designed_for.…`).
        key: String,
        /// What is wrong.
        detail: String,
    },
    /// The servo's reference signal could not be formed.
    #[error("controller.step_time = {time}: {source}")]
    Step {
        /// The step time \[s\].
        time: f64,
        /// The signal's error.
        source: pendulab_sim::SimError,
    },
}
