//! The design record: which model a controller was designed on (`designed_for`).
//!
//! Every kind of [`ControllerSpec`] takes an optional `designed_for` table, written by the
//! tool that designed the controller (e.g. `pendulab design …`) and read back wherever the
//! controller is run. In a rig controller file it is the `[controller.designed_for]` table:
//!
//! ```toml
//! [controller]
//! kind = "state-feedback"
//! k = [-3.16228, -13.47175, -4.48137, -2.26289]
//!
//! [controller.designed_for]
//! plant = "cart"                           # the plant kind the design assumed
//! operating_point = [0.0, 0.0, 0.0, 0.0]   # [q0, q1, dq0, dq1] it was linearised about
//! sample_time = 0.001                      # s; leave out for a continuous-time design
//! method = "lqr"                           # free text naming the design
//! inputs = { q = [10.0, 10.0, 0.0, 0.0], r = 1.0 }   # the method's inputs
//!
//! [controller.designed_for.parameters]     # the plant's parameters, as in a plant file
//! a_c = 6.25
//! # … every parameter of the plant
//!
//! [controller.designed_for.provenance]     # where they came from, as in a plant file
//! source = "book"
//! ```
//!
//! [`DesignRecord::check_plant`] compares the record with the plant a controller is about to
//! run on (a [`PlantSpec`]):
//!
//! - **another plant kind is an error** ([`SpecError::WrongPlant`], naming both): the gains of
//!   a cart design mean nothing on the arm (different states, units and signs);
//! - **different parameter values are warnings** ([`DesignWarning`]), returned for the front
//!   end to print: running a design on a plant other than its nominal model is how the book
//!   itself tests robustness (a design on table 3.5's values run on the identified rig, part 1
//!   ch. 3), so it must stay possible, but never unnoticed.
//!
//! Values are compared exactly: a record written from a plant file carries that file's
//! numbers bit for bit (TOML keeps every `f64` digit), so any difference is a different
//! parameter set. [`DesignRecord::check_sample_time`] likewise warns when the loop runs at
//! another period than the design assumed.

use super::{ControllerSpec, SpecError};
use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::{PlantParameters, PlantSpec, Provenance};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The model a controller was designed on (module documentation): the `designed_for` table
/// of a controller spec.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DesignRecord {
    /// The plant kind the design assumed (`"cart"` or `"arm"`).
    pub plant: PlantKind,
    /// The operating point the design linearised about, the plant's state
    /// `[q₀, q₁, q̇₀, q̇₁]` \[m or rad, rad, m/s or rad/s, rad/s\], `q₁` from upright (4 finite
    /// entries; `[0, 0, 0, 0]` for the upright balance, `[θ₁ₑ, 0, 0, 0]` for the arm at
    /// `θ₁ₑ`).
    pub operating_point: Vec<f64>,
    /// The loop period \[s\] the design assumed (finite, > 0): the period a discrete-time
    /// design was discretised at. Left out for a continuous-time design, which runs at any
    /// rate.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sample_time: Option<f64>,
    /// The design method, free text naming it (`"lqr"`, `"place"`, `"lq-servo"`,
    /// `"observer"`, `"book gain"`, …; non-empty).
    pub method: String,
    /// The method's inputs by name (e.g. `q`, `r` of an LQR, `poles` of a placement), each a
    /// number, a list or a list of rows, in the units of the method (default none).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub inputs: BTreeMap<String, DesignInput>,
    /// The plant's physical parameters the design used, named as in a plant file's
    /// `[parameters]` table (every parameter of `plant`, SI units).
    pub parameters: BTreeMap<String, f64>,
    /// Where those parameters came from, as in a plant file's `[provenance]` table.
    pub provenance: Provenance,
}

/// One input of a design method: a number, a list (a diagonal, a pole list) or a list of
/// rows (a full matrix; a complex pole as `[re, im]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum DesignInput {
    /// A number.
    Number(f64),
    /// A list of numbers.
    List(Vec<f64>),
    /// A list of rows.
    Rows(Vec<Vec<f64>>),
}

/// A difference between a controller's design record and the plant or loop it runs on that
/// is allowed but must be told (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub enum DesignWarning {
    /// A parameter differs from the value the design used.
    Parameter {
        /// `parameters.<name>`, as in a plant file.
        key: String,
        /// The value in the design record.
        designed: f64,
        /// The plant's value.
        plant: f64,
    },
    /// The loop runs at another period than the design assumed.
    SampleTime {
        /// The record's `sample_time` \[s\].
        designed: f64,
        /// The loop period \[s\].
        run: f64,
    },
}

impl std::fmt::Display for DesignWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DesignWarning::Parameter {
                key,
                designed,
                plant,
            } => write!(
                f,
                "{key}: the controller was designed with {designed}, the plant has {plant} ({:+.3} %)",
                100.0 * (plant - designed) / designed.abs().max(f64::MIN_POSITIVE)
            ),
            DesignWarning::SampleTime { designed, run } => write!(
                f,
                "sample time: the controller was designed for {designed} s, the loop runs at {run} s"
            ),
        }
    }
}

impl DesignRecord {
    /// The record of a design made on `plant` about `operating_point` (the plant's state
    /// layout), for loop period `sample_time` (`None`: continuous time), by `method` with its
    /// `inputs`: the plant's kind, parameters and provenance copied from `plant`.
    pub fn new(
        plant: &PlantSpec,
        operating_point: Vec<f64>,
        sample_time: Option<f64>,
        method: impl Into<String>,
        inputs: BTreeMap<String, DesignInput>,
    ) -> Self {
        Self {
            plant: plant.kind(),
            operating_point,
            sample_time,
            method: method.into(),
            inputs,
            parameters: plant.parameters().entries().into_iter().collect(),
            provenance: plant.provenance().clone(),
        }
    }

    /// Checks the record on its own: `operating_point` 4 finite entries, `sample_time`
    /// finite and > 0, `method` non-empty, the inputs finite, and `parameters` exactly the
    /// parameter names of `plant`.
    ///
    /// # Errors
    /// [`SpecError::DesignRecord`] naming the key (`controller.designed_for.…`).
    pub fn validate(&self) -> Result<(), SpecError> {
        let bad = |key: &str, detail: String| SpecError::DesignRecord {
            key: format!("{KEY}.{key}"),
            detail,
        };
        if self.operating_point.len() != 4 || self.operating_point.iter().any(|x| !x.is_finite()) {
            return Err(bad(
                "operating_point",
                format!(
                    "{:?}: must be 4 finite entries [q0, q1, dq0, dq1]",
                    self.operating_point
                ),
            ));
        }
        if let Some(ts) = self.sample_time
            && !(ts.is_finite() && ts > 0.0)
        {
            return Err(bad(
                "sample_time",
                format!("{ts}: must be finite and > 0 s"),
            ));
        }
        if self.method.trim().is_empty() {
            return Err(bad("method", "must name the design method".into()));
        }
        for (name, input) in &self.inputs {
            let finite = match input {
                DesignInput::Number(x) => x.is_finite(),
                DesignInput::List(v) => v.iter().all(|x| x.is_finite()),
                DesignInput::Rows(r) => r.iter().flatten().all(|x| x.is_finite()),
            };
            if !finite {
                return Err(bad(&format!("inputs.{name}"), "must be finite".into()));
            }
        }
        if let Some((name, value)) = self.parameters.iter().find(|(_, v)| !v.is_finite()) {
            return Err(bad(
                &format!("parameters.{name}"),
                format!("{value}: must be finite"),
            ));
        }
        PlantParameters::from_entries(
            self.plant,
            self.parameters.iter().map(|(k, v)| (k.clone(), *v)),
        )
        .map_err(|e| bad("parameters", e.to_string()))?;
        Ok(())
    }

    /// Checks the record against the plant a controller is to run on (module
    /// documentation): the record must be valid ([`DesignRecord::validate`]) and name the
    /// plant's kind; each parameter whose value differs from the plant's is returned as a
    /// [`DesignWarning::Parameter`], in the order of the plant's parameters (empty: the
    /// design's model is the plant's).
    ///
    /// # Errors
    /// [`SpecError::WrongPlant`] naming both plants when the kinds differ;
    /// [`SpecError::DesignRecord`] for an invalid record.
    pub fn check_plant(&self, plant: &PlantSpec) -> Result<Vec<DesignWarning>, SpecError> {
        self.check_kind(plant.kind())?;
        self.validate()?;
        Ok(plant
            .parameters()
            .entries()
            .into_iter()
            .filter_map(|(name, value)| {
                let designed = self.parameters[&name];
                (designed != value).then(|| DesignWarning::Parameter {
                    key: format!("parameters.{name}"),
                    designed,
                    plant: value,
                })
            })
            .collect())
    }

    /// Checks only the plant kind (for a front end that knows the kind but not the
    /// parameters, such as a rig controller file's `plant`).
    ///
    /// # Errors
    /// [`SpecError::WrongPlant`] naming both plants when they differ.
    pub fn check_kind(&self, plant: PlantKind) -> Result<(), SpecError> {
        if self.plant != plant {
            return Err(SpecError::WrongPlant {
                designed: self.plant,
                plant,
            });
        }
        Ok(())
    }

    /// A [`DesignWarning::SampleTime`] when the record names a sample time and the loop
    /// period `ts` \[s\] differs from it by more than one part in 10⁹ (a period written as
    /// `1/rate_hz` and read back); `None` otherwise (also for a continuous-time design).
    pub fn check_sample_time(&self, ts: f64) -> Option<DesignWarning> {
        let designed = self.sample_time?;
        ((ts - designed).abs() > 1e-9 * designed)
            .then_some(DesignWarning::SampleTime { designed, run: ts })
    }
}

/// The record's key in a controller file, for error messages.
const KEY: &str = "controller.designed_for";

impl ControllerSpec {
    /// The design record (`designed_for`), if the spec has one.
    pub fn designed_for(&self) -> Option<&DesignRecord> {
        self.record_slot_ref().as_ref()
    }

    /// Sets (or with `None` removes) the design record.
    pub fn set_designed_for(&mut self, record: Option<DesignRecord>) {
        *self.record_slot() = record;
    }

    /// The spec with its design record set to `record`.
    pub fn with_designed_for(mut self, record: DesignRecord) -> Self {
        self.set_designed_for(Some(record));
        self
    }

    /// [`DesignRecord::check_plant`] of the spec's record on `plant`; no record, no warning.
    ///
    /// # Errors
    /// As [`DesignRecord::check_plant`].
    pub fn check_plant(&self, plant: &PlantSpec) -> Result<Vec<DesignWarning>, SpecError> {
        match self.designed_for() {
            Some(r) => r.check_plant(plant),
            None => Ok(Vec::new()),
        }
    }

    /// [`DesignRecord::check_kind`] of the spec's record; no record, no error.
    ///
    /// # Errors
    /// As [`DesignRecord::check_kind`].
    pub fn check_kind(&self, plant: PlantKind) -> Result<(), SpecError> {
        match self.designed_for() {
            Some(r) => r.check_kind(plant),
            None => Ok(()),
        }
    }
}
