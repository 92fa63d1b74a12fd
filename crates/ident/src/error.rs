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
    #[error(
        "{source_name}: no column {} (columns present: {})",
        show_name(column, true),
        available.iter().map(|n| show_name(n, false)).collect::<Vec<_>>().join(", ")
    )]
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
    #[error("invalid {name} = {}: {reason}", num(*value))]
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
    #[error("{what} = {} is not physically meaningful: {reason}", num(*value))]
    Implausible {
        /// Which estimate.
        what: String,
        /// Its value.
        value: f64,
        /// Why it cannot be right.
        reason: String,
    },
    /// The time column's step or span is implausible for the unit it was read in (a column
    /// in milliseconds taken as seconds, say): see [`crate::data::MAX_SAMPLE_TIME`],
    /// [`crate::data::MIN_SAMPLE_TIME`] and [`crate::data::MAX_RECORD_SPAN`].
    #[error(
        "{source_name}: the time column, read in {unit} ({}), has {reason}; {hint}",
        if *declared { "declared" } else { "no unit declared" }
    )]
    ImplausibleTime {
        /// File name or label of the data.
        source_name: String,
        /// The unit the time stamps were read in.
        unit: crate::data::TimeUnit,
        /// Whether the unit was declared (header or call) rather than assumed.
        declared: bool,
        /// The uniform step, seconds.
        step: f64,
        /// The record's span `t_last − t_0`, seconds.
        span: f64,
        /// Which bound the step or span violates.
        reason: String,
        /// What to do about it (declare the unit).
        hint: String,
    },
    /// A known physical constant lies outside its documented plausible range (see
    /// [`crate::regression::MASS_RANGE`], [`crate::regression::LENGTH_RANGE`],
    /// [`crate::regression::GRAVITY_RANGE`]).
    #[error(
        "{name} = {} {unit} is outside its plausible range [{}, {}] {unit} ({reason})",
        num(*value),
        num(*min),
        num(*max)
    )]
    ConstantOutOfRange {
        /// The constant (e.g. `m_p`).
        name: String,
        /// The value given.
        value: f64,
        /// Its unit.
        unit: String,
        /// Smallest plausible value.
        min: f64,
        /// Largest plausible value.
        max: f64,
        /// What the range covers.
        reason: String,
    },
    /// The regressor is badly conditioned: its column-scaled condition number exceeds
    /// [`crate::least_squares::MAX_CONDITION`], so the estimate carries no trustworthy digit.
    #[error(
        "badly conditioned regressor [{}]: condition number {scaled_condition:.3e} with columns scaled to unit norm exceeds {limit:.3e} (2-norm condition {condition:.3e}); the data do not determine the parameters separately — use a longer or richer record",
        columns.join(", ")
    )]
    IllConditioned {
        /// Names of the regressor columns.
        columns: Vec<String>,
        /// Its 2-norm condition number.
        condition: f64,
        /// The condition number with every column scaled to unit norm.
        scaled_condition: f64,
        /// The largest accepted scaled condition number.
        limit: f64,
    },
    /// A computed estimate or diagnostic (standard error, condition number) is NaN or
    /// infinite: the computation overflowed or divided by zero, so it is not a result.
    #[error("{what} = {value} is not a finite number: {reason}")]
    NonFiniteResult {
        /// Which number.
        what: String,
        /// Its value.
        value: f64,
        /// Where it came from and what it suggests.
        reason: String,
    },
    /// A method option does not suit the data: a filter time constant or a differentiator
    /// window too long for the record, too short for the sample time, or too long for the
    /// dynamics (see [`crate::regression::LsOptions::check_data`]).
    #[error("{option} = {} {unit} does not suit the data: {reason}", num(*value))]
    UnsuitedOption {
        /// The option (e.g. `prefilter time constant T_f`).
        option: String,
        /// Its value.
        value: f64,
        /// Its unit (`s`, `samples`).
        unit: String,
        /// The bound it violates, with the numbers.
        reason: String,
    },
    /// An error from the LTI core (simulation for validation, discretisation).
    #[error(transparent)]
    Lti(#[from] LtiError),
}

/// A number as it appears in a message: plain decimal between 10⁻⁴ and 10⁹ (and 0),
/// scientific notation otherwise (`1e-300`, not three hundred zeros).
pub(crate) fn num(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-4..1e9).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A derived number (a span, a bound) in a message: four significant digits.
pub(crate) fn short(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || !x.is_finite() {
        format!("{x}")
    } else if (1e-3..1e6).contains(&a) {
        let digits = (3 - a.log10().floor() as i32).max(0) as usize;
        let t = format!("{x:.digits$}");
        if t.contains('.') {
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            t
        }
    } else {
        format!("{x:.3e}")
    }
}

/// A name as it appears in a message: plain when it consists of letters, digits, ASCII
/// punctuation and inner spaces (in single quotes if `quoted`, `'v'`); otherwise always in
/// double quotes with invisible and control characters escaped (`"\u{feff}t"`), so a
/// byte-order mark, a zero-width space or a trailing blank shows.
pub fn show_name(name: &str, quoted: bool) -> String {
    let visible = !name.is_empty()
        && name.trim() == name
        && name
            .chars()
            .all(|c| c.is_alphanumeric() || c.is_ascii_punctuation() || c == ' ');
    match (visible, quoted) {
        (true, true) => format!("'{name}'"),
        (true, false) => name.to_string(),
        (false, _) => format!("\"{}\"", name.escape_debug()),
    }
}

/// Result alias of this crate.
pub type Result<T, E = IdentError> = std::result::Result<T, E>;

/// Label used for data that did not come with a name.
pub(crate) const UNNAMED: &str = "data";
