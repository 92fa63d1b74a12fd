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
    /// A weight that must be positive semidefinite is not: its smallest eigenvalue is below
    /// `−tolerance`, where the tolerance covers the rounding of a semidefinite matrix formed
    /// in floating point (see [`lqr`](crate::design::lqr) for the definition).
    #[error(
        "{what} must be positive semidefinite for an LQ problem (smallest eigenvalue {min_eigenvalue:e}, below the rounding tolerance -{tolerance:e})"
    )]
    NotPositiveSemidefinite {
        /// Which matrix, e.g. `"Q"` or `"[Q N; Nᵀ R]"`.
        what: String,
        /// Its smallest eigenvalue.
        min_eigenvalue: f64,
        /// The tolerance: eigenvalues down to `−tolerance` count as rounding of zero.
        tolerance: f64,
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
        "no stabilising solution: (A, B) is not stabilisable: the mode at {}{:+}j is uncontrollable (PBH margin {margin:e}) and not stable",
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
        "no stabilising solution: (Q, A) is not detectable: the mode at {}{:+}j is unobservable through Q (PBH margin {margin:e}) and on or outside the stability boundary, so the Hamiltonian (symplectic pencil) has eigenvalues there: {}{:+}j and {}{:+}j",
        eigenvalue.re, eigenvalue.im,
        eigenvalue.re, eigenvalue.im,
        eigenvalue.re, -eigenvalue.im
    )]
    NotDetectable {
        /// The offending eigenvalue of A.
        eigenvalue: Complex64,
        /// Smallest singular value of `[A − λI; Q]` relative to `‖[A; Q]‖`.
        margin: f64,
    },
    /// The Hamiltonian matrix (continuous) or symplectic pencil (discrete) has eigenvalues on
    /// the imaginary axis (unit circle), or so near it that the computed solution cannot
    /// separate them from it, so there is no (certifiably) stabilising Riccati solution. The
    /// criterion is documented at [`equations::riccati`](crate::equations::riccati).
    #[error(
        "no stabilising solution: the {what} has eigenvalues on or numerically near the stability boundary: {} (nearest at distance {distance:e}, within the tolerance {tolerance:e})",
        format_eigenvalues(eigenvalues)
    )]
    BoundaryEigenvalue {
        /// "Hamiltonian matrix" or "symplectic pencil", with the method or stage that found it.
        what: String,
        /// The offending eigenvalue nearest the boundary.
        eigenvalue: Complex64,
        /// Its distance to the imaginary axis (unit circle).
        distance: f64,
        /// Every offending eigenvalue (for a computed solution: the near-boundary closed-loop
        /// poles and their mirror images `−λ̄` (continuous) or `1/λ̄` (discrete)).
        eigenvalues: Vec<Complex64>,
        /// The distance below which an eigenvalue counts as on the boundary (`0` when it is
        /// on or beyond it as computed).
        tolerance: f64,
    },
    /// A problem is too ill-conditioned to be solved reliably in double precision: its
    /// estimated condition number exceeds the limit, so the solver stops early instead of
    /// trying every method.
    #[error(
        "{what} is too ill-conditioned to solve reliably: estimated condition number {condition:e} exceeds {limit:e}"
    )]
    IllConditioned {
        /// Which problem or matrix, and how the estimate was formed.
        what: String,
        /// The estimated condition number.
        condition: f64,
        /// The limit it exceeds.
        limit: f64,
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
    /// A standard plant violates an assumption of the H∞/H2 Riccati syntheses
    /// ([`StandardPlant::check_assumptions`](crate::design::StandardPlant::check_assumptions)).
    #[error("the standard plant violates the synthesis assumption {assumption}: {detail}")]
    SynthesisAssumption {
        /// The assumption that fails.
        assumption: crate::design::PlantAssumption,
        /// What was found (rank, zero, mode).
        detail: String,
    },
    /// No controller reaches the H∞ level `γ`: the existence condition that failed
    /// ([`design::hinf_syn`](crate::design::hinf_syn)).
    #[error("no controller achieves ‖T_zw‖∞ < γ = {gamma}: {condition}")]
    HinfInfeasible {
        /// The level tried.
        gamma: f64,
        /// The first condition that fails.
        condition: crate::design::HinfCondition,
    },
    /// Any other invalid argument, with a message naming it.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
}

/// `a+bj, c+dj, …` for an error message (at most eight values, then a count).
fn format_eigenvalues(ev: &[Complex64]) -> String {
    let mut parts: Vec<String> = ev
        .iter()
        .take(8)
        .map(|l| format!("{:e}{:+e}j", l.re, l.im))
        .collect();
    if ev.len() > 8 {
        parts.push(format!("and {} more", ev.len() - 8));
    }
    parts.join(", ")
}

/// Result alias of the LTI core.
pub type Result<T> = std::result::Result<T, LtiError>;
