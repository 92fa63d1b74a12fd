//! The error type of `pendulab-lti`.
//!
//! Every variant carries what went wrong and where, so a message can be shown to a user as is.
//! Expected outcomes that are not failures (an unstable system, an uncontrollable pair) are
//! reported as values by the analysis functions, never as errors; errors are reserved for
//! inputs a computation cannot accept and for numerical breakdown.

use crate::linalg::Complex64;

/// Errors of the LTI core.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LtiError {
    /// A matrix has the wrong shape.
    #[error("{what}: expected a {}x{} matrix, found {}x{}", expected.0, expected.1, found.0, found.1)]
    DimensionMismatch {
        /// Which argument.
        what: String,
        /// Expected (rows, columns).
        expected: (usize, usize),
        /// Actual (rows, columns).
        found: (usize, usize),
    },
    /// A matrix that must be square is not.
    #[error("{what} must be square, found {rows}x{cols}")]
    NotSquare {
        /// Which argument.
        what: String,
        /// Rows found.
        rows: usize,
        /// Columns found.
        cols: usize,
    },
    /// A matrix entry is NaN or infinite.
    #[error("{what} has a non-finite entry {value} at row {row}, column {col} (0-based)")]
    NonFinite {
        /// Which argument.
        what: String,
        /// Row of the first offending entry (0-based).
        row: usize,
        /// Column of the first offending entry (0-based).
        col: usize,
        /// The offending value.
        value: f64,
    },
    /// A matrix that must be symmetric is not.
    #[error("{what} must be symmetric (‖M − Mᵀ‖_F = {asymmetry:e})")]
    NotSymmetric {
        /// Which argument.
        what: String,
        /// Frobenius norm of the antisymmetric part times two.
        asymmetry: f64,
    },
    /// A matrix that must be positive definite is not.
    #[error("{what} must be positive definite (smallest eigenvalue {min_eigenvalue:e})")]
    NotPositiveDefinite {
        /// Which argument.
        what: String,
        /// Its smallest eigenvalue.
        min_eigenvalue: f64,
    },
    /// A sample time is not a finite positive number.
    #[error("sample time must be finite and > 0 s, got {0}")]
    InvalidSampleTime(f64),
    /// Two discrete-time systems with different sample times were combined.
    #[error("sample times differ: {0} s and {1} s")]
    SampleTimeMismatch(f64, f64),
    /// The pair (A, B) has an uncontrollable mode that is not stable, so no stabilising
    /// feedback (and no stabilising Riccati solution) exists.
    #[error(
        "(A, B) is not stabilisable: the mode at {}{:+}j is uncontrollable (PBH margin {margin:e}) and not stable",
        eigenvalue.re, eigenvalue.im
    )]
    NotStabilizable {
        /// The offending eigenvalue of A.
        eigenvalue: Complex64,
        /// Smallest singular value of `[A − λI, B]` relative to `‖[A, B]‖`.
        margin: f64,
    },
    /// The pair (Q, A) has an unobservable mode on the stability boundary, so the Riccati
    /// equation has no stabilising solution.
    #[error(
        "(Q, A) is not detectable: the mode at {}{:+}j is unobservable through Q (PBH margin {margin:e}) and on or outside the stability boundary",
        eigenvalue.re, eigenvalue.im
    )]
    NotDetectable {
        /// The offending eigenvalue of A.
        eigenvalue: Complex64,
        /// Smallest singular value of `[A − λI; Q]` relative to `‖[A; Q]‖`.
        margin: f64,
    },
    /// The Hamiltonian matrix (continuous) or symplectic pencil (discrete) has eigenvalues on
    /// the imaginary axis (unit circle), so there is no stabilising Riccati solution.
    #[error(
        "the {what} has an eigenvalue on the stability boundary at {}{:+}j (distance {distance:e}); no stabilising solution exists",
        eigenvalue.re, eigenvalue.im
    )]
    BoundaryEigenvalue {
        /// "Hamiltonian matrix" or "symplectic pencil".
        what: String,
        /// The offending eigenvalue.
        eigenvalue: Complex64,
        /// Its distance to the imaginary axis (unit circle).
        distance: f64,
    },
    /// A matrix that must be inverted is singular to working precision.
    #[error("{what} is singular to working precision (reciprocal condition {rcond:e})")]
    Singular {
        /// Which matrix.
        what: String,
        /// Estimated reciprocal condition number.
        rcond: f64,
    },
    /// The equation has no unique solution because eigenvalues of its coefficients collide
    /// (e.g. λ_i(A) + λ_j(B) = 0 for the Sylvester equation AX + XB = C).
    #[error("{what} has no unique solution: {detail}")]
    NoUniqueSolution {
        /// Which equation.
        what: String,
        /// Which eigenvalues collide.
        detail: String,
    },
    /// An iterative algorithm did not converge.
    #[error("{algorithm} did not converge after {iterations} iterations")]
    NoConvergence {
        /// Which algorithm.
        algorithm: String,
        /// Iterations performed.
        iterations: usize,
    },
    /// A computed result failed its own accuracy check.
    #[error("{what}: relative residual {residual:e} exceeds {tolerance:e}")]
    Inaccurate {
        /// Which computation.
        what: String,
        /// Residual achieved.
        residual: f64,
        /// Tolerance required.
        tolerance: f64,
    },
    /// The pair (A, B) is not controllable, so its poles cannot be assigned arbitrarily.
    #[error(
        "(A, B) is not controllable: controllable subspace has dimension {controllable_dimension} of {nx}; uncontrollable mode at {}{:+}j",
        mode.re, mode.im
    )]
    NotControllable {
        /// Dimension of the controllable subspace (staircase form).
        controllable_dimension: usize,
        /// Number of states.
        nx: usize,
        /// One eigenvalue of the uncontrollable part.
        mode: Complex64,
    },
    /// A matrix has no real principal logarithm (an eigenvalue on the closed negative real
    /// axis), e.g. `d2c` of a discrete system with a pole at `z ≤ 0`.
    #[error(
        "{what} has an eigenvalue at {}{:+}j on the closed negative real axis: no real principal logarithm exists",
        eigenvalue.re, eigenvalue.im
    )]
    NoRealLogarithm {
        /// Which matrix.
        what: String,
        /// The offending eigenvalue.
        eigenvalue: Complex64,
    },
    /// A quantity is infinite because the system has a pole where it is evaluated
    /// (e.g. the DC gain with a pole at `s = 0` or `z = 1`).
    #[error("{what} is infinite: the system has a pole at {}{:+}j", pole.re, pole.im)]
    PoleAtEvaluationPoint {
        /// Which quantity.
        what: String,
        /// The pole.
        pole: Complex64,
    },
    /// A time vector is not uniformly spaced (or does not match the sample time).
    #[error(
        "time vector is not uniformly spaced: step {index} -> {} is {step} s, expected {expected} s",
        index + 1
    )]
    NonUniformTime {
        /// Index of the sample that starts the offending step.
        index: usize,
        /// The step found, in seconds.
        step: f64,
        /// The step expected, in seconds.
        expected: f64,
    },
    /// A transfer function whose numerator degree exceeds its denominator degree was used
    /// where a proper one is required (e.g. a state-space realisation).
    #[error(
        "{what}: transfer function is improper (numerator degree {num_degree} > denominator degree {den_degree})"
    )]
    Improper {
        /// Which operation.
        what: String,
        /// Numerator degree.
        num_degree: usize,
        /// Denominator degree.
        den_degree: usize,
    },
    /// An operation defined for single-input single-output systems got another shape.
    #[error("{what} needs a single-input single-output system, got {ny} outputs x {nu} inputs")]
    NotSiso {
        /// Which operation.
        what: String,
        /// Outputs.
        ny: usize,
        /// Inputs.
        nu: usize,
    },
    /// Any other invalid argument, with a message naming it.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
}

/// Result alias of the LTI core.
pub type Result<T> = std::result::Result<T, LtiError>;
