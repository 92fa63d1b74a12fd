//! The error type of `pendulab-sim`.
//!
//! Errors are for inputs a simulation cannot accept (bad times, shapes, parameters, NaN initial
//! states) and for numerical breakdown during integration (a state that becomes non-finite, a
//! step size that underflows). Expected outcomes — a run stopped by a safety limit, a terminal
//! event — are statuses in the result, never errors.

use pendulab_lti::LtiError;

/// Errors of the simulator.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// A sample time is not finite and positive.
    #[error("sample time must be finite and > 0 s, got {0}")]
    InvalidSampleTime(f64),
    /// An integration step is not finite and positive.
    #[error("{what} must be finite and > 0 s, got {value}")]
    InvalidStep {
        /// Which step (e.g. "RK4 step dt").
        what: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A fixed integration step does not divide the sample time into a whole number of substeps.
    #[error(
        "the RK4 step dt = {dt} s does not divide the sample time ts = {ts} s \
         (ts/dt = {ratio}); choose dt = ts/n"
    )]
    StepDoesNotDivide {
        /// The fixed step.
        dt: f64,
        /// The sample time.
        ts: f64,
        /// Their ratio.
        ratio: f64,
    },
    /// A time interval is empty, reversed or not finite.
    #[error("invalid time span: {what} (t0 = {t0}, t_final = {t_final})")]
    InvalidTimeSpan {
        /// What is wrong.
        what: &'static str,
        /// Start time.
        t0: f64,
        /// End time.
        t_final: f64,
    },
    /// An initial state entry is NaN or infinite.
    #[error("initial state entry {index} is not finite ({value})")]
    NonFiniteInitialState {
        /// Index of the first offending entry.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// A vector or matrix has the wrong size.
    #[error("{what}: expected length {expected}, found {found}")]
    DimensionMismatch {
        /// Which argument.
        what: String,
        /// Expected length.
        expected: usize,
        /// Actual length.
        found: usize,
    },
    /// A parameter is outside its admissible range.
    #[error("{what} = {value} is invalid: {requirement}")]
    InvalidParameter {
        /// Which parameter.
        what: String,
        /// The offending value.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// A non-numeric argument is malformed (e.g. unsorted breakpoints).
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// The state became NaN or infinite during integration.
    #[error("state entry {index} became non-finite ({value}) at t = {t} s")]
    NonFiniteState {
        /// Time at which it was detected (end of the failing step).
        t: f64,
        /// Index of the first offending state.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// A controller or input function produced a NaN or infinite command.
    #[error("command entry {index} is not finite ({value}) at t = {t} s")]
    NonFiniteCommand {
        /// Time of the sample.
        t: f64,
        /// Index of the first offending command.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The adaptive step size fell below what the floating-point time grid can resolve.
    #[error("step size underflow at t = {t} s (h = {h:e} s): the problem is too stiff or singular")]
    StepSizeUnderflow {
        /// Time reached.
        t: f64,
        /// The rejected step size.
        h: f64,
    },
    /// The adaptive integrator hit its step budget.
    #[error("maximum number of steps ({max_steps}) reached at t = {t} s")]
    MaxStepsExceeded {
        /// Time reached.
        t: f64,
        /// The budget.
        max_steps: usize,
    },
    /// A controller declares a sample time different from the loop's.
    #[error(
        "the controller was designed for ts = {controller} s but the loop samples at ts = {sampled} s"
    )]
    SampleTimeMismatch {
        /// The controller's sample time.
        controller: f64,
        /// The loop's sample time.
        sampled: f64,
    },
    /// An error of the LTI core (shapes, non-finite matrices, discretisation).
    #[error(transparent)]
    Lti(#[from] LtiError),
}

/// Result type of `pendulab-sim`.
pub type Result<T, E = SimError> = std::result::Result<T, E>;

/// Checks that a state vector is finite (initial states).
pub(crate) fn check_initial_state(x0: &[f64], nx: usize) -> Result<()> {
    check_len("initial state", x0.len(), nx)?;
    if let Some((index, &value)) = x0.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(SimError::NonFiniteInitialState { index, value });
    }
    Ok(())
}

/// Checks a length.
pub(crate) fn check_len(what: &str, found: usize, expected: usize) -> Result<()> {
    if found != expected {
        return Err(SimError::DimensionMismatch {
            what: what.to_string(),
            expected,
            found,
        });
    }
    Ok(())
}

/// Checks that a parameter is finite and `> 0`.
pub(crate) fn check_positive(what: &str, value: f64) -> Result<()> {
    if !(value.is_finite() && value > 0.0) {
        return Err(SimError::InvalidParameter {
            what: what.to_string(),
            value,
            requirement: "must be finite and > 0",
        });
    }
    Ok(())
}

/// Checks that a parameter is finite and `≥ 0`.
pub(crate) fn check_nonnegative(what: &str, value: f64) -> Result<()> {
    if !(value.is_finite() && value >= 0.0) {
        return Err(SimError::InvalidParameter {
            what: what.to_string(),
            value,
            requirement: "must be finite and >= 0",
        });
    }
    Ok(())
}

/// Checks a vector's length (named `what`) and that every entry is finite (a bad one named
/// `"{entry} {i}"`).
pub(crate) fn check_finite_vector(
    what: &str,
    entry: &str,
    values: &[f64],
    expected: usize,
) -> Result<()> {
    check_len(what, values.len(), expected)?;
    // The name is formatted only for the bad entry (a controller's retune calls this between
    // samples).
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => check_finite(&format!("{entry} {i}"), values[i]),
        None => Ok(()),
    }
}

/// Checks that a value is finite.
pub(crate) fn check_finite(what: &str, value: f64) -> Result<()> {
    if !value.is_finite() {
        return Err(SimError::InvalidParameter {
            what: what.to_string(),
            value,
            requirement: "must be finite",
        });
    }
    Ok(())
}

/// Returns the first non-finite entry of a state, as an error at time `t`.
#[inline]
pub(crate) fn check_state(t: f64, x: &[f64]) -> Result<()> {
    // Fast path: the sum of finite numbers is finite unless it overflows, which we then
    // inspect entry by entry.
    let s: f64 = x.iter().sum();
    if s.is_finite() {
        return Ok(());
    }
    match x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        Some((index, &value)) => Err(SimError::NonFiniteState { t, index, value }),
        None => Ok(()),
    }
}
