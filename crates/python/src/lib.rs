//! # pendulab-python — the extension module behind the `pendulab` Python package
//!
//! A thin layer: NumPy arrays in, the Rust crates compute, NumPy arrays out. No numerics live
//! here; every function converts its arguments ([`convert`]), calls the library (with the GIL
//! released around anything that can take more than microseconds) and converts the result or
//! the library's typed error ([`errors`]) into a Python object or exception.
//!
//! The Python-facing API (names, docstrings, type stubs) is in `python/pendulab/`; this module
//! is imported as `pendulab._native`, one submodule-like group of functions per facet:
//!
//! | module | Python | what |
//! |---|---|---|
//! | [`lti`] | `pendulab` (top level) | state space, analysis, equations, design, responses |
//! | [`plants`] | `pendulab.plants` | the cart and arm pendulums, linearisation, simulation |
//! | [`gym`] | `pendulab.gym` | Gymnasium environments and the native vector env |
//! | [`lmi`] | `pendulab.lmi` | the LMI syntheses with their certificates |
//! | [`ident`] | `pendulab.ident` | least-squares and feature identification |
//! | [`control`] | `pendulab.control` | sliding mode, swing-up, NMPC, ODQ, Kalman, the spec factory |
//! | [`book`] | `pendulab.book` | the book's examples and the lab report |
//! | [`batch`] | `pendulab.plants` | batch runs on all cores that honour Ctrl-C |
//! | [`render`] | `pendulab.gym` | the rigs drawn for `render_mode="rgb_array"` |
//! | [`callable`] | `pendulab.control` | a user's model as Python callables `f(x, u)`, `h(x, u)` |

#![warn(missing_docs)]

pub mod batch;
pub mod book;
pub mod callable;
pub mod control;
pub mod convert;
pub mod errors;
pub mod gym;
pub mod ident;
pub mod lmi;
pub mod lti;
pub mod plants;
pub mod render;
pub mod study;

use pyo3::prelude::*;

/// The `pendulab._native` module: registers each facet's functions and classes.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    lti::register(m)?;
    plants::register(m)?;
    gym::register(m)?;
    lmi::register(m)?;
    ident::register(m)?;
    control::register(m)?;
    book::register(m)?;
    batch::register(m)?;
    render::register(m)?;
    study::register(m)?;
    Ok(())
}
