//! The error type of `pendulab-plants`.
//!
//! Every variant says which parameter or quantity is wrong, its value and what was required,
//! so the message can be shown to a user as is.

use pendulab_lti::LtiError;

/// What a parameter must satisfy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Requirement {
    /// Finite and `> 0`.
    Positive,
    /// Finite and `≥ 0`.
    NonNegative,
    /// Finite (any sign).
    Finite,
}

impl std::fmt::Display for Requirement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Requirement::Positive => "finite and > 0",
            Requirement::NonNegative => "finite and >= 0",
            Requirement::Finite => "finite",
        })
    }
}

/// Errors of the plant models.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PlantError {
    /// A physical parameter violates its requirement (NaN, infinite, negative mass, …).
    #[error("{model}: parameter {name} = {value} must be {requirement}")]
    InvalidParameter {
        /// Which model's parameter set (`"cart pendulum"`, `"arm pendulum"`, …).
        model: &'static str,
        /// The parameter's name as in the book (`"m_p"`, `"J2"`, …).
        name: &'static str,
        /// The offending value.
        value: f64,
        /// What it must satisfy.
        requirement: Requirement,
    },
    /// A quantity derived from valid parameters is not representable (e.g. `m_p g l_p`
    /// overflows for absurdly large inputs).
    #[error("{model}: derived quantity {name} = {value} is not finite and positive")]
    DerivedQuantity {
        /// Which model.
        model: &'static str,
        /// The derived quantity (`"J = J_p + m_p l_p^2"`, …).
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// An operating point given by the caller is not finite.
    #[error("{what} = {value} must be finite")]
    NonFiniteOperatingPoint {
        /// Which coordinate (`"z"`, `"theta1"`, …).
        what: &'static str,
        /// The offending value.
        value: f64,
    },
    /// An output index names no state.
    #[error("output index {index} is out of range for a model with {nx} states")]
    OutputIndex {
        /// The offending index (0-based).
        index: usize,
        /// Number of states.
        nx: usize,
    },
    /// Building a linear model failed in the LTI core.
    #[error(transparent)]
    Lti(#[from] LtiError),
}

/// Checks one parameter.
pub(crate) fn check(
    model: &'static str,
    name: &'static str,
    value: f64,
    requirement: Requirement,
) -> Result<(), PlantError> {
    let ok = value.is_finite()
        && match requirement {
            Requirement::Positive => value > 0.0,
            Requirement::NonNegative => value >= 0.0,
            Requirement::Finite => true,
        };
    if ok {
        Ok(())
    } else {
        Err(PlantError::InvalidParameter {
            model,
            name,
            value,
            requirement,
        })
    }
}

/// Checks a derived quantity (must be finite and `> 0`).
pub(crate) fn check_derived(
    model: &'static str,
    name: &'static str,
    value: f64,
) -> Result<f64, PlantError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(PlantError::DerivedQuantity { model, name, value })
    }
}

/// Checks an operating-point coordinate.
pub(crate) fn check_point(what: &'static str, value: f64) -> Result<(), PlantError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(PlantError::NonFiniteOperatingPoint { what, value })
    }
}
