//! The error type of `pendulab-lmi`.
//!
//! Errors are reserved for problems that cannot be posed (wrong shapes, non-symmetric LMIs,
//! products that are not affine, non-finite data) and for solver breakdown that leaves no
//! answer. An infeasible LMI is *not* an error: it is [`crate::Status::Infeasible`] with a
//! certificate.

use pendulab_lti::LtiError;

/// Errors of the LMI layer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LmiError {
    /// Two operands of a matrix operation have incompatible shapes.
    #[error("shape mismatch in {op}: {}x{} and {}x{}", left.0, left.1, right.0, right.1)]
    ShapeMismatch {
        /// The operation (`"+"`, `"*"`, `"block row 2"`, ...).
        op: String,
        /// Shape of the left operand (rows, columns).
        left: (usize, usize),
        /// Shape of the right operand (rows, columns).
        right: (usize, usize),
    },
    /// A matrix that must be square is not.
    #[error("{what} must be square, found {rows}x{cols}")]
    NotSquare {
        /// What was being checked.
        what: String,
        /// Rows found.
        rows: usize,
        /// Columns found.
        cols: usize,
    },
    /// A matrix inequality whose expression is not symmetric.
    #[error(
        "{what} is not symmetric: entry ({row}, {col}) differs from its transpose by {difference:e}"
    )]
    NotSymmetric {
        /// The constraint or matrix.
        what: String,
        /// Row of the first asymmetric entry (0-based).
        row: usize,
        /// Column of the first asymmetric entry (0-based).
        col: usize,
        /// Size of the asymmetry found.
        difference: f64,
    },
    /// A matrix entry is NaN or infinite.
    #[error("{what} has a non-finite entry {value} at ({row}, {col}) (0-based)")]
    NonFinite {
        /// Which matrix or scalar.
        what: String,
        /// Row (0-based).
        row: usize,
        /// Column (0-based).
        col: usize,
        /// The offending value.
        value: f64,
    },
    /// A product of two expressions that both contain decision variables.
    #[error("the product in {op} multiplies two decision-dependent expressions: not affine")]
    NotAffine {
        /// The operation.
        op: String,
    },
    /// An expression combines variables (or parameters) of two different problems.
    #[error("{op} combines expressions of two different problems")]
    ForeignExpression {
        /// The operation.
        op: String,
    },
    /// A constraint or objective that must not depend on the parameters does.
    #[error(
        "{what} depends on the parameters; use Problem::sos for parameter-dependent matrix inequalities"
    )]
    ParameterDependent {
        /// The constraint or objective.
        what: String,
    },
    /// A parameter-only expression was expected (e.g. a monomial vector or an S-procedure
    /// polynomial) but the expression contains decision variables.
    #[error("{what} must not contain decision variables")]
    DecisionDependent {
        /// What was being checked.
        what: String,
    },
    /// An expression that is not a parameter was used as one.
    #[error("{what} is not a parameter (use Problem::parameter)")]
    NotAParameter {
        /// What was passed.
        what: String,
    },
    /// A numeric argument is out of its admissible range.
    #[error("invalid argument {what}: {reason}")]
    InvalidArgument {
        /// The argument.
        what: String,
        /// Why it was rejected.
        reason: String,
    },
    /// The solver could not be set up or crashed; no answer is available.
    #[error("the conic solver failed: {0}")]
    Solver(String),
    /// An error from the LTI core (shape checks, eigenvalues).
    #[error(transparent)]
    Lti(#[from] LtiError),
}

/// Result alias of this crate.
pub type Result<T, E = LmiError> = std::result::Result<T, E>;
