//! The error type of `pendulab-ident`.
//!
//! Every variant names what is wrong and where: the data source (file name or label), the
//! column, and the sample (0-based index into the data set, with the 1-based line of the CSV
//! text when the data came from CSV). Identification never returns an estimate computed from
//! data it could not accept.

use pendulab_lti::LtiError;

/// Where a sample sits: its 0-based index and, for CSV data, its 1-based line in the text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SamplePos {
    /// 0-based sample index in the (possibly windowed) data.
    pub index: usize,
    /// 1-based line of the CSV text the sample came from, if known.
    pub line: Option<usize>,
}

impl std::fmt::Display for SamplePos {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            Some(l) => write!(f, "sample {} (line {l})", self.index),
            None => write!(f, "sample {}", self.index),
        }
    }
}

impl SamplePos {
    /// A position without a known CSV line.
    pub fn index(index: usize) -> Self {
        Self { index, line: None }
    }
}

/// Errors of parameter identification.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum IdentError {
    /// The CSV text could not be parsed.
    #[error("{source_name}: line {line}: {message}")]
    Csv {
        /// File name or label of the data.
        source_name: String,
        /// 1-based line of the text.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A required column is absent.
    #[error("{source_name}: no column '{column}' (columns present: {})", available.join(", "))]
    MissingColumn {
        /// File name or label of the data.
        source_name: String,
        /// The column asked for.
        column: String,
        /// The columns the data has.
        available: Vec<String>,
    },
    /// Two columns that must have the same length do not.
    #[error("{source_name}: column '{column}' has {found} samples, expected {expected}")]
    LengthMismatch {
        /// File name or label of the data.
        source_name: String,
        /// The offending column.
        column: String,
        /// Samples expected (those of the first column).
        expected: usize,
        /// Samples found.
        found: usize,
    },
    /// A value is NaN or infinite.
    #[error("{source_name}: column '{column}', {at}: value {value} is not finite")]
    NonFinite {
        /// File name or label of the data.
        source_name: String,
        /// The offending column.
        column: String,
        /// Where.
        at: SamplePos,
        /// The value.
        value: f64,
    },
    /// Time stamps do not increase.
    #[error("{source_name}: time does not increase at {at}: t = {t} s follows t = {previous} s")]
    TimeNotIncreasing {
        /// File name or label of the data.
        source_name: String,
        /// The first sample whose time is not greater than its predecessor's.
        at: SamplePos,
        /// Its time stamp in seconds.
        t: f64,
        /// The previous time stamp in seconds.
        previous: f64,
    },
    /// Time stamps are not uniformly spaced.
    #[error(
        "{source_name}: uneven sampling at {at}: step {step} s, expected {expected} s (the methods need a uniform grid)"
    )]
    UnevenTime {
        /// File name or label of the data.
        source_name: String,
        /// The sample that ends the offending step.
        at: SamplePos,
        /// The step found, seconds.
        step: f64,
        /// The uniform step expected, seconds.
        expected: f64,
    },
    /// Not enough samples for the method.
    #[error("{source_name}: {what} needs at least {needed} samples, got {found}")]
    TooFewSamples {
        /// File name or label of the data.
        source_name: String,
        /// Which computation.
        what: String,
        /// Samples needed.
        needed: usize,
        /// Samples available.
        found: usize,
    },
    /// A requested time window does not lie inside the data.
    #[error(
        "{source_name}: window [{t0} s, {t1} s] is not inside the data, which spans [{data_start} s, {data_end} s]"
    )]
    WindowOutsideData {
        /// File name or label of the data.
        source_name: String,
        /// Window start, seconds.
        t0: f64,
        /// Window end, seconds.
        t1: f64,
        /// First time stamp of the data.
        data_start: f64,
        /// Last time stamp of the data.
        data_end: f64,
    },
    /// A parameter (constant, option) is out of its domain.
    #[error("invalid {name} = {value}: {reason}")]
    InvalidParameter {
        /// Parameter name.
        name: String,
        /// The value given.
        value: f64,
        /// The condition it violates.
        reason: String,
    },
    /// The regressor matrix is rank deficient (or numerically so): its columns do not determine
    /// the parameters.
    #[error(
        "rank-deficient regressor [{}]: condition number {scaled_condition:.3e} with columns scaled to unit norm exceeds {limit:.3e} (2-norm condition {condition:.3e}); {detail}",
        columns.join(", ")
    )]
    RankDeficient {
        /// Names of the regressor columns.
        columns: Vec<String>,
        /// Its 2-norm condition number (∞ for an exactly singular one).
        condition: f64,
        /// The condition number with every column scaled to unit norm (the rank decision's
        /// measure).
        scaled_condition: f64,
        /// The largest scaled condition number accepted.
        limit: f64,
        /// Which combination of columns is (nearly) dependent.
        detail: String,
    },
    /// A feature (peak, crossing, oscillation) the method relies on is absent from the data.
    #[error("{source_name}: {what}")]
    FeatureNotFound {
        /// File name or label of the data.
        source_name: String,
        /// What was looked for and why it was not found.
        what: String,
    },
    /// An estimate is physically meaningless (e.g. a negative moment of inertia), so the data or
    /// the known constants do not fit the model.
    #[error("{what} = {value} is not physically meaningful: {reason}")]
    Implausible {
        /// Which estimate.
        what: String,
        /// Its value.
        value: f64,
        /// Why it cannot be right.
        reason: String,
    },
    /// An error from the LTI core (simulation for validation, discretisation).
    #[error(transparent)]
    Lti(#[from] LtiError),
}

/// Result alias of this crate.
pub type Result<T, E = IdentError> = std::result::Result<T, E>;

/// Label used for data that did not come with a name.
pub(crate) const UNNAMED: &str = "data";
