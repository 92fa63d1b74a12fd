//! The `gym` facet of the extension module (see the crate docs).

use pyo3::prelude::*;

/// Adds this facet's functions and classes to the module.
pub fn register(_m: &Bound<'_, PyModule>) -> PyResult<()> {
    Ok(())
}
