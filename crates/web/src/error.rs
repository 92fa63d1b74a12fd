//! The browser lab's error type.

use pendulab_control::scenario::ScenarioError;
use pendulab_control::spec::SpecError;
use pendulab_lti::LtiError;
use pendulab_plants::PlantError;
use pendulab_plants::spec::PlantSpecError;
use pendulab_sim::SimError;

/// What the lab refuses, naming the input at fault; the page shows the message.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum WebError {
    /// A design input has the wrong number of entries (`what`: `q`, `poles`, …).
    #[error("{what} has {got} entries, expected {expected}")]
    Length {
        /// The input.
        what: &'static str,
        /// Entries given.
        got: usize,
        /// Entries required.
        expected: usize,
    },
    /// A number outside its range.
    #[error("{what} = {value}: must be {range}")]
    OutOfRange {
        /// The input.
        what: &'static str,
        /// Its value.
        value: f64,
        /// The range, with unit.
        range: &'static str,
    },
    /// The design (LQR, servo or pole placement) failed.
    #[error("design: {0}")]
    Design(#[from] LtiError),
    /// The LMI design could not be posed (`pendulab_lmi`'s shape or range errors).
    #[error("LMI design: {0}")]
    LmiSetup(#[from] pendulab_lmi::LmiError),
    /// The LMIs were not solved: infeasible (with its certificate), or the solution failed its
    /// recheck.
    #[error("LMI design: {0}")]
    Lmi(String),
    /// A controller file the page was given is not one (`docs/rig/README.md`).
    #[error("controller file: {0}")]
    ControllerFile(String),
    /// The plant text is not a plant spec (`docs/model.md` §6).
    #[error("plant: {0}")]
    PlantSpec(#[from] PlantSpecError),
    /// The plant model refused its parameters.
    #[error("plant: {0}")]
    Plant(#[from] PlantError),
    /// The controller factory refused the spec.
    #[error("controller: {0}")]
    Controller(#[from] SpecError),
    /// The simulator refused its set-up or the state blew up (naming the time).
    #[error("simulation: {0}")]
    Simulation(#[from] SimError),
    /// A response run of [`pendulab_control::scenario::simulate`] failed.
    #[error("response: {0}")]
    Scenario(#[from] ScenarioError),
    /// The controller file could not be written.
    #[error("controller file: {0}")]
    Toml(#[from] toml::ser::Error),
}
