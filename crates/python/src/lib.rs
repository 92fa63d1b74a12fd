//! # pendulab-python — the extension module behind the `pendulab` Python package
//!
//! A thin layer: NumPy arrays in, the Rust crates compute, NumPy arrays out. No numerics live
//! here; every function converts its arguments, calls the library (with the GIL released
//! around anything that can take more than microseconds) and converts the result or the
//! library's typed error into a Python exception.
//!
//! The Python-facing API (names, docstrings, type stubs) is in `python/pendulab/`; this module
//! is imported as `pendulab._native`.

#![warn(missing_docs)]

use pyo3::prelude::*;

/// The `pendulab._native` module: registers each facet's functions and classes.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
