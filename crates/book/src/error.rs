//! Errors of the book examples.

/// Why an example could not run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BookError {
    /// No example has this id.
    #[error("unknown example id '{0}' (see `pendulab book list`)")]
    UnknownId(String),
    /// The example needs measured data that was not given.
    #[error("example '{id}' needs measured data: {what} (pass it with --data FILE.csv)")]
    NeedsData {
        /// Example id.
        id: String,
        /// What data, with the expected columns.
        what: String,
    },
    /// A computation inside the example failed.
    #[error("example '{id}': {message}")]
    Computation {
        /// Example id.
        id: String,
        /// What failed.
        message: String,
    },
    /// A figure could not be written.
    #[error("example '{id}': cannot write figure {path}: {message}")]
    Figure {
        /// Example id.
        id: String,
        /// Path of the figure.
        path: String,
        /// Why.
        message: String,
    },
}
