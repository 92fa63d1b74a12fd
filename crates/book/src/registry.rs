//! The registry of book examples.

use crate::error::BookError;
use crate::output::ExampleOutput;

/// Everything an example may use when it runs.
#[derive(Debug, Clone, Default)]
pub struct RunContext {
    /// Whether to draw the figures and animations into [`ExampleOutput::figures`]; `false`
    /// computes the numbers only (and builds no figure).
    pub figures: bool,
    /// Contents of a measured-data CSV file (examples that take `--data`); `None` runs them on
    /// their shipped recording.
    pub data_csv: Option<String>,
}

/// One book example.
#[derive(Debug, Clone, Copy)]
pub struct Example {
    /// The book's MATLAB file stem, e.g. `p1c41_cdip_response`.
    pub id: &'static str,
    /// Short English title.
    pub title: &'static str,
    /// Part, chapter and section as the book numbers them, e.g. "Part 1 §4.1".
    pub section: &'static str,
    /// The parameter set used (e.g. "cart pendulum, table 3.5").
    pub parameters: &'static str,
    /// The measured data the example takes with `--data`: what, with the CSV columns (`None`:
    /// it takes none). An example whose recording ships in `data/rig/` runs on it when no file
    /// is given; one without shipped data returns [`BookError::NeedsData`] then.
    pub needs_data: Option<&'static str>,
    /// Runs the example.
    pub run: fn(&RunContext) -> Result<ExampleOutput, BookError>,
}

/// Every example, in book order.
pub fn registry() -> Vec<Example> {
    crate::chapters::all()
}

/// The example with this id.
///
/// # Errors
/// [`BookError::UnknownId`].
pub fn find(id: &str) -> Result<Example, BookError> {
    registry()
        .into_iter()
        .find(|e| e.id == id)
        .ok_or_else(|| BookError::UnknownId(id.to_string()))
}
