//! The error type of `pendulab-control`.
//!
//! Errors are reserved for inputs a design cannot accept (wrong sizes, non-finite or
//! out-of-range parameters, a structure that does not apply to the given system) and for
//! numerical breakdown that leaves no answer. Outcomes that are results — a quantizer whose
//! cost is large, a continuation whose optimality residual has not yet decayed — are reported
//! in the returned diagnostics, never as errors.

#[cfg(feature = "lmi")]
use pendulab_lmi::LmiError;
use pendulab_lti::LtiError;
use pendulab_plants::PlantError;
use pendulab_sim::SimError;

/// Errors of the control designs and controllers.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ControlError {
    /// A vector or matrix has the wrong size.
    #[error("{what}: expected size {expected}, found {found}")]
    DimensionMismatch {
        /// Which argument.
        what: String,
        /// Expected length (or rows × columns written as a product).
        expected: usize,
        /// Length found.
        found: usize,
    },
    /// A matrix has the wrong shape.
    #[error("{what}: expected a {}x{} matrix, found {}x{}", expected.0, expected.1, found.0, found.1)]
    ShapeMismatch {
        /// Which argument.
        what: String,
        /// Expected (rows, columns).
        expected: (usize, usize),
        /// Found (rows, columns).
        found: (usize, usize),
    },
    /// A scalar parameter is outside its admissible range.
    #[error("parameter {name} = {value} is invalid: {requirement}")]
    InvalidParameter {
        /// The parameter's name.
        name: String,
        /// The value given.
        value: f64,
        /// What it must satisfy.
        requirement: String,
    },
    /// A vector or matrix entry is NaN or infinite.
    #[error("{what} has a non-finite entry {value} at index {index}")]
    NonFinite {
        /// Which argument.
        what: String,
        /// Index of the first offending entry (column-major for matrices).
        index: usize,
        /// The value found.
        value: f64,
    },
    /// A scalar that must be inverted is (numerically) zero.
    #[error("{what} is singular (|value| = {value:e})")]
    Singular {
        /// What was to be inverted.
        what: String,
        /// Its magnitude (or reciprocal condition number).
        value: f64,
    },
    /// A design does not apply to the given system (e.g. the closed-form optimal quantizer
    /// needs a stable zero dynamics).
    #[error("not applicable: {reason}")]
    NotApplicable {
        /// Why.
        reason: String,
    },
    /// The initial solution of the receding-horizon problem could not be found.
    #[error(
        "C/GMRES initialisation did not converge: optimality residual {residual:e} after {iterations} Newton iterations (tolerance {tolerance:e})"
    )]
    InitialisationFailed {
        /// Norm of the optimality conditions at the last iterate.
        residual: f64,
        /// Newton iterations performed.
        iterations: usize,
        /// The tolerance asked for.
        tolerance: f64,
    },
    /// A linear program of a design did not return a solution.
    #[error("the linear program of {what} was not solved: {status}")]
    LinearProgram {
        /// Which design.
        what: String,
        /// The solver's status.
        status: String,
    },
    /// An iterative search (an operating point's Levenberg–Marquardt iteration) stopped
    /// without meeting its tolerance: no solution near the start, or none at all.
    #[error(
        "{what} did not converge: residual {residual:e} after {iterations} iterations (tolerance {tolerance:e}); {reason}"
    )]
    NoConvergence {
        /// Which search.
        what: String,
        /// Norm of the residual at the best iterate.
        residual: f64,
        /// Iterations performed.
        iterations: usize,
        /// The tolerance asked for.
        tolerance: f64,
        /// Why it stopped.
        reason: String,
    },
    /// A specification contradicts itself or the system (an index out of range or given
    /// twice, an output fixed on a system without an output map, everything fixed at a point
    /// that is not a solution).
    #[error("inconsistent {what}: {reason}")]
    InconsistentSpec {
        /// Which specification.
        what: String,
        /// What is inconsistent.
        reason: String,
    },
    /// An error of the LTI core (Riccati equations, discretisation, placement).
    #[error(transparent)]
    Lti(#[from] LtiError),
    /// An error of the LMI/LP layer.
    #[cfg(feature = "lmi")]
    #[error(transparent)]
    Lmi(#[from] LmiError),
    /// An error of a plant model (invalid parameters, non-finite operating point).
    #[error(transparent)]
    Plant(#[from] PlantError),
    /// An error of the simulation layer (a run-time controller's construction).
    #[error(transparent)]
    Sim(#[from] SimError),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, ControlError>;

/// Checks a slice has length `n` and finite entries.
pub(crate) fn check_vector(what: &str, v: &[f64], n: usize) -> Result<()> {
    if v.len() != n {
        return Err(ControlError::DimensionMismatch {
            what: what.to_string(),
            expected: n,
            found: v.len(),
        });
    }
    check_finite_slice(what, v)
}

/// Checks every entry of `v` is finite.
pub(crate) fn check_finite_slice(what: &str, v: &[f64]) -> Result<()> {
    if let Some((index, &value)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return Err(ControlError::NonFinite {
            what: what.to_string(),
            index,
            value,
        });
    }
    Ok(())
}

/// Checks a matrix has the given shape and finite entries.
pub(crate) fn check_matrix(
    what: &str,
    m: &pendulab_lti::Mat,
    rows: usize,
    cols: usize,
) -> Result<()> {
    if m.shape() != (rows, cols) {
        return Err(ControlError::ShapeMismatch {
            what: what.to_string(),
            expected: (rows, cols),
            found: m.shape(),
        });
    }
    check_finite_slice(what, m.as_slice())
}

/// Checks a scalar parameter is finite and satisfies `ok`.
pub(crate) fn check_param(name: &str, value: f64, ok: bool, requirement: &str) -> Result<()> {
    if !value.is_finite() || !ok {
        return Err(ControlError::InvalidParameter {
            name: name.to_string(),
            value,
            requirement: requirement.to_string(),
        });
    }
    Ok(())
}
