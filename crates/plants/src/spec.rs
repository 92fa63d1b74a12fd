//! The plant specification: which pendulum, its parameters and where they came from, and the
//! rig it runs on — one value, read and written as a plant file (`docs/model.md` §6).
//!
//! A [`PlantSpec`] is plain data (serde). Front ends read it from TOML or JSON, the controller
//! factory designs on its parameters and the simulator runs its plant through its rig part.
//! A plant file reads:
//!
//! ```toml
//! kind = "cart"                 # or "arm"
//!
//! [parameters]                  # the fields of CartPendulumParams (or ArmPendulumParams), SI
//! a_c = 6.25
//! b_c = 4.36
//! # … every field, none may be missing
//!
//! [provenance]
//! source = "book"               # or "identified" (file, sha256, window, standard_errors) or "user"
//!
//! [rig]                         # RigSpec: sample time, amplifier, D/A, encoders, limits
//! nx = 4
//! sample_time = 0.001
//! # …
//! ```
//!
//! Every read is validated ([`PlantSpec::validate`]): an unknown key, a missing key or a value
//! out of range is an error naming the key (`parameters.m_p`, `rig.encoders[1].step`,
//! `provenance.window`, …); TOML syntax errors also give the line.
//!
//! ```
//! use pendulab_plants::rig::PlantKind;
//! use pendulab_plants::spec::PlantSpec;
//! # fn main() -> Result<(), pendulab_plants::spec::PlantSpecError> {
//! let book = PlantSpec::book(PlantKind::Arm);
//! let text = book.to_toml()?;
//! assert_eq!(PlantSpec::from_toml(&text)?, book);
//! // A key of the other plant is refused by name.
//! let bad = text.replace("a1 =", "a_c =");
//! assert!(PlantSpec::from_toml(&bad).unwrap_err().to_string().contains("a_c"));
//! # Ok(()) }
//! ```

use crate::rig::{PlantKind, RigSpec};
use crate::{
    ArmEquilibrium, ArmPendulum, ArmPendulumParams, CartEquilibrium, CartPendulum,
    CartPendulumParams, PlantError,
};
use pendulab_lti::{Continuous, StateSpace};
use serde::de::value::MapDeserializer;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The physical parameters of one of the two plants (`[parameters]` of a plant file; which
/// one is the file's `kind`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PlantParameters {
    /// The cart-type pendulum (book table 3.5; `docs/model.md` §1).
    Cart(CartPendulumParams),
    /// The arm-type pendulum (book table 3.7; `docs/model.md` §2).
    Arm(ArmPendulumParams),
}

impl PlantParameters {
    /// The book's values for `kind` (tables 3.5 and 3.7).
    pub fn book(kind: PlantKind) -> Self {
        match kind {
            PlantKind::Cart => PlantParameters::Cart(CartPendulumParams::book()),
            PlantKind::Arm => PlantParameters::Arm(ArmPendulumParams::book()),
        }
    }

    /// Which plant.
    pub fn kind(&self) -> PlantKind {
        match self {
            PlantParameters::Cart(_) => PlantKind::Cart,
            PlantParameters::Arm(_) => PlantKind::Arm,
        }
    }

    /// The parameters as `(name, value)` pairs, named as in a plant file (the book's symbols),
    /// in the order of the struct's fields.
    pub fn entries(&self) -> Vec<(String, f64)> {
        let value = match self {
            PlantParameters::Cart(p) => toml::Value::try_from(p),
            PlantParameters::Arm(p) => toml::Value::try_from(p),
        };
        // A struct of f64 fields always serialises to a table of floats.
        match value {
            Ok(toml::Value::Table(t)) => t
                .into_iter()
                .filter_map(|(k, v)| v.as_float().map(|x| (k, x)))
                .collect(),
            _ => Vec::new(),
        }
    }

    /// Reads the parameters of `kind` from `(name, value)` pairs: every field of the plant's
    /// parameter struct exactly once, no other name.
    ///
    /// # Errors
    /// [`PlantSpecError::Parameters`] naming a missing or unknown key.
    pub fn from_entries(
        kind: PlantKind,
        entries: impl IntoIterator<Item = (String, f64)>,
    ) -> Result<Self, PlantSpecError> {
        let de = MapDeserializer::<_, serde::de::value::Error>::new(entries.into_iter());
        let read = match kind {
            PlantKind::Cart => CartPendulumParams::deserialize(de).map(PlantParameters::Cart),
            PlantKind::Arm => ArmPendulumParams::deserialize(de).map(PlantParameters::Arm),
        };
        read.map_err(|e| PlantSpecError::Parameters {
            kind,
            detail: e.to_string(),
        })
    }

    /// Checks every parameter against its requirement (`CartPendulumParams::validate`,
    /// `ArmPendulumParams::validate`).
    ///
    /// # Errors
    /// [`PlantSpecError::Parameter`] naming the key `parameters.<name>`.
    pub fn validate(&self) -> Result<(), PlantSpecError> {
        match self {
            PlantParameters::Cart(p) => p.validate(),
            PlantParameters::Arm(p) => p.validate(),
        }
        .map_err(PlantSpecError::from_plant)
    }

    /// The plant's linearisation about the upright pendulum (deviation variables, `C = I`),
    /// for the arm at the arm angle `q0` \[rad\]; the cart's linearisation does not depend
    /// on the cart position, so `q0` is ignored there (`docs/model.md` §1–2).
    ///
    /// # Errors
    /// [`PlantError`] for invalid parameters or a non-finite `q0`.
    pub fn linearize_upright(&self, q0: f64) -> Result<StateSpace<Continuous>, PlantError> {
        match self {
            PlantParameters::Cart(p) => {
                CartPendulum::new(*p)?.linearize(CartEquilibrium::upright())
            }
            PlantParameters::Arm(p) => ArmPendulum::new(*p)?.linearize(ArmEquilibrium::upright(q0)),
        }
    }
}

/// Where a plant's parameters came from (`[provenance]`, tag `source`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "source", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Provenance {
    /// `source = "book"`: the book's table (3.5 for the cart, 3.7 for the arm); the parameters
    /// must equal those values. No other key.
    Book {},
    /// `source = "identified"`: estimated from a recorded run.
    Identified {
        /// The data file as the user named it (non-empty).
        file: String,
        /// SHA-256 of the file's bytes, 64 hexadecimal digits (as `sha256sum` prints it).
        sha256: String,
        /// The time window used, `[start, end]` \[s\] (finite, `0 ≤ start < end`).
        window: [f64; 2],
        /// One standard error per estimated parameter, keyed by parameter name (units of the
        /// parameter; finite, ≥ 0). Key optional, default none.
        #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
        standard_errors: BTreeMap<String, f64>,
        /// The identification method (free text, e.g. `"least squares, part 1 §3.2"`). Key
        /// optional.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        method: Option<String>,
    },
    /// `source = "user"`: values the user wrote.
    User {
        /// Free text (key optional).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        note: Option<String>,
    },
}

/// A plant and its rig (module documentation): the plant's parameters with their provenance,
/// and the rig part ([`RigSpec`]). Built by [`PlantSpec::book`], [`PlantSpec::new`] or read from a
/// file; always valid once built (serde's `Deserialize` validates as [`PlantSpec::new`] does).
#[derive(Debug, Clone, PartialEq)]
pub struct PlantSpec {
    parameters: PlantParameters,
    provenance: Provenance,
    rig: RigSpec,
}

/// The plant file's layout, as read (`kind`, `parameters`, `provenance`, `rig`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPlantSpec {
    kind: PlantKind,
    parameters: BTreeMap<String, f64>,
    provenance: Provenance,
    rig: RigSpec,
}

/// The plant file's layout, as written.
#[derive(Serialize)]
struct OutPlantSpec<'a> {
    kind: PlantKind,
    parameters: OutParameters<'a>,
    provenance: &'a Provenance,
    rig: &'a RigSpec,
}

#[derive(Serialize)]
#[serde(untagged)]
enum OutParameters<'a> {
    Cart(&'a CartPendulumParams),
    Arm(&'a ArmPendulumParams),
}

impl PlantSpec {
    /// The book's plant of `kind`: the parameters of table 3.5 or 3.7, `source = "book"`, the
    /// book rig ([`RigSpec::book`]).
    pub fn book(kind: PlantKind) -> Self {
        Self {
            parameters: PlantParameters::book(kind),
            provenance: Provenance::Book {},
            rig: RigSpec::book(kind),
        }
    }

    /// A plant from its parts, validated ([`PlantSpec::validate`]).
    ///
    /// # Errors
    /// As [`PlantSpec::validate`].
    pub fn new(
        parameters: PlantParameters,
        provenance: Provenance,
        rig: RigSpec,
    ) -> Result<Self, PlantSpecError> {
        let spec = Self {
            parameters,
            provenance,
            rig,
        };
        spec.validate()?;
        Ok(spec)
    }

    /// Which plant.
    pub fn kind(&self) -> PlantKind {
        self.parameters.kind()
    }

    /// The physical parameters.
    pub fn parameters(&self) -> &PlantParameters {
        &self.parameters
    }

    /// Where the parameters came from.
    pub fn provenance(&self) -> &Provenance {
        &self.provenance
    }

    /// The rig part.
    pub fn rig(&self) -> &RigSpec {
        &self.rig
    }

    /// Checks the parameters (each against its requirement), the rig part
    /// ([`RigSpec::validate`]) and the provenance: book values for `source = "book"`; for
    /// `identified`, a non-empty file name, a 64-digit hexadecimal SHA-256, a window
    /// `0 ≤ start < end` and standard errors (finite, ≥ 0) only of the plant's parameters.
    ///
    /// # Errors
    /// [`PlantSpecError`] naming the key.
    pub fn validate(&self) -> Result<(), PlantSpecError> {
        self.parameters.validate()?;
        self.rig.validate(self.kind())?;
        match &self.provenance {
            Provenance::Book {} => {
                let book = PlantParameters::book(self.kind()).entries();
                for ((key, value), (_, expected)) in self.parameters.entries().into_iter().zip(book)
                {
                    if value != expected {
                        return Err(PlantSpecError::NotBook {
                            key: format!("parameters.{key}"),
                            value,
                            expected,
                        });
                    }
                }
            }
            Provenance::Identified {
                file,
                sha256,
                window,
                standard_errors,
                ..
            } => {
                if file.trim().is_empty() {
                    return Err(PlantSpecError::Provenance {
                        key: "provenance.file",
                        detail: "must name the data file".into(),
                    });
                }
                if sha256.len() != 64 || !sha256.chars().all(|c| c.is_ascii_hexdigit()) {
                    return Err(PlantSpecError::Provenance {
                        key: "provenance.sha256",
                        detail: format!("'{sha256}' is not 64 hexadecimal digits"),
                    });
                }
                let [a, b] = *window;
                if !(a.is_finite() && b.is_finite() && a >= 0.0 && a < b) {
                    return Err(PlantSpecError::Provenance {
                        key: "provenance.window",
                        detail: format!("[{a}, {b}] must be finite with 0 <= start < end (s)"),
                    });
                }
                let names: Vec<String> =
                    self.parameters.entries().into_iter().map(|e| e.0).collect();
                for (name, &se) in standard_errors {
                    if !names.contains(name) {
                        return Err(PlantSpecError::Provenance {
                            key: "provenance.standard_errors",
                            detail: format!(
                                "'{name}' is no parameter of the {} plant (expected one of {})",
                                self.kind().name(),
                                names.join(", ")
                            ),
                        });
                    }
                    if !(se.is_finite() && se >= 0.0) {
                        return Err(PlantSpecError::Invalid {
                            key: format!("provenance.standard_errors.{name}"),
                            value: se,
                            range: "finite and >= 0",
                        });
                    }
                }
            }
            Provenance::User { .. } => {}
        }
        Ok(())
    }

    /// The plant file as TOML text (module documentation), which [`PlantSpec::from_toml`]
    /// reads back to an equal value.
    ///
    /// # Errors
    /// [`PlantSpecError::Write`] if the TOML writer refuses a value (e.g. a non-finite number
    /// it cannot write; none for a validated spec).
    pub fn to_toml(&self) -> Result<String, PlantSpecError> {
        toml::to_string(&self.out()).map_err(PlantSpecError::Write)
    }

    /// Reads and validates a plant file.
    ///
    /// # Errors
    /// [`PlantSpecError::Toml`] for syntax errors, unknown, missing or mistyped keys (naming
    /// the key and line); the errors of [`PlantSpec::validate`].
    pub fn from_toml(text: &str) -> Result<Self, PlantSpecError> {
        let raw: RawPlantSpec = toml::from_str(text).map_err(PlantSpecError::Toml)?;
        Self::try_from(raw)
    }

    fn out(&self) -> OutPlantSpec<'_> {
        OutPlantSpec {
            kind: self.kind(),
            parameters: match &self.parameters {
                PlantParameters::Cart(p) => OutParameters::Cart(p),
                PlantParameters::Arm(p) => OutParameters::Arm(p),
            },
            provenance: &self.provenance,
            rig: &self.rig,
        }
    }
}

impl TryFrom<RawPlantSpec> for PlantSpec {
    type Error = PlantSpecError;
    fn try_from(raw: RawPlantSpec) -> Result<Self, PlantSpecError> {
        let parameters = PlantParameters::from_entries(raw.kind, raw.parameters)?;
        PlantSpec::new(parameters, raw.provenance, raw.rig)
    }
}

impl Serialize for PlantSpec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.out().serialize(s)
    }
}

impl<'de> Deserialize<'de> for PlantSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let raw = RawPlantSpec::deserialize(d)?;
        PlantSpec::try_from(raw).map_err(serde::de::Error::custom)
    }
}

/// What is wrong with a plant specification; each message names the key as written in a
/// plant file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlantSpecError {
    /// A number outside its range.
    #[error("{key} = {value}: must be {range}")]
    Invalid {
        /// The key (`rig.sample_time`, …).
        key: String,
        /// Its value.
        value: f64,
        /// The range, with unit.
        range: &'static str,
    },
    /// A physical parameter violates its requirement.
    #[error("{key}: {source}")]
    Parameter {
        /// `parameters.<name>` (or `parameters` for a derived quantity).
        key: String,
        /// The plant's error.
        source: PlantError,
    },
    /// A parameter key missing or unknown for the plant.
    #[error("parameters of the {} plant: {detail}", kind.name())]
    Parameters {
        /// Which plant the file says.
        kind: PlantKind,
        /// The reader's message (naming the key).
        detail: String,
    },
    /// An encoder that does not measure the plant's coordinate in its place.
    #[error("rig.encoders[{index}]: must measure coordinate '{expected}' (state {state})")]
    Encoder {
        /// The encoder's index.
        index: usize,
        /// The coordinate expected there.
        expected: &'static str,
        /// The state index expected there.
        state: usize,
    },
    /// `source = "book"` with parameters other than the book's.
    #[error(
        "{key} = {value} differs from the book's {expected} while provenance.source = \"book\" (use \"user\" or \"identified\")"
    )]
    NotBook {
        /// The parameter's key.
        key: String,
        /// Its value.
        value: f64,
        /// The book's value.
        expected: f64,
    },
    /// A provenance entry that is missing or malformed.
    #[error("{key}: {detail}")]
    Provenance {
        /// The key.
        key: &'static str,
        /// What is wrong.
        detail: String,
    },
    /// The text is not a plant file (syntax, unknown/missing/mistyped key; with the line).
    #[error("plant file: {0}")]
    Toml(toml::de::Error),
    /// The TOML writer refused a value.
    #[error("writing the plant file: {0}")]
    Write(toml::ser::Error),
}

impl PlantSpecError {
    fn from_plant(source: PlantError) -> Self {
        let key = match &source {
            PlantError::InvalidParameter { name, .. } => format!("parameters.{name}"),
            _ => "parameters".into(),
        };
        PlantSpecError::Parameter { key, source }
    }
}
