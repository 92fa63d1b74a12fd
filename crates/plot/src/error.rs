//! The crate's error type.

use std::path::PathBuf;

/// Everything that can go wrong when a figure or an animation is built, rendered or written.
///
/// Errors name what was wrong and where: the panel (numbered from 0 in reading order), the series
/// (its label, or its position when it has none) and the offending sample.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// A series, grid or frame list holds no sample at all.
    #[error("{what}: no data")]
    Empty {
        /// The object that is empty, e.g. `panel 0, series "y1"`.
        what: String,
    },
    /// Two sequences that must pair up sample by sample have different lengths.
    #[error("{what}: lengths differ ({left} vs {right})")]
    LengthMismatch {
        /// The object whose sequences disagree, with the sequences' names.
        what: String,
        /// Length of the first sequence.
        left: usize,
        /// Length of the second sequence.
        right: usize,
    },
    /// A series has samples but none of them can be drawn (all non-finite, or all
    /// non-positive on a logarithmic axis).
    #[error("{what}: no drawable sample ({reason})")]
    NothingToDraw {
        /// The series.
        what: String,
        /// Why every sample was dropped.
        reason: String,
    },
    /// A value that must be finite (where NaN is not read as a gap) is NaN or infinite.
    #[error("{what}: sample {index} is not finite ({value})")]
    NonFinite {
        /// The sequence.
        what: String,
        /// Index of the first offending sample.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// An argument outside its documented range (axis limits, sizes, frame rates, ...).
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// A file could not be created or written.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// An image encoder failed (PNG or GIF).
    #[error("cannot encode {format}: {message}")]
    Encode {
        /// `"PNG"` or `"GIF"`.
        format: &'static str,
        /// The encoder's message.
        message: String,
    },
    /// The embedded font could not be parsed (a build defect, never user input).
    #[error("the embedded font cannot be read")]
    Font,
}

/// Shorthand for results of this crate.
pub type Result<T, E = PlotError> = std::result::Result<T, E>;
