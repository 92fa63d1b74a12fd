//! The `lti` facet of the extension module: pendulab-lti with python-control's and MATLAB's
//! names, re-exported at the top level of the `pendulab` package.
//!
//! | submodule | Python names |
//! |---|---|
//! | [`system`] | `StateSpace`, `TransferFunction`, `ss`, `tf`, `c2d`, `d2c` |
//! | [`analysis`] | `poles`, `zeros`, `dcgain`, `damp`, `ctrb`, `obsv`, `gram` |
//! | [`equations`] | `lyap`, `dlyap`, `care`, `dare` |
//! | [`design`] | `lqr`, `dlqr`, `lqe`, `dlqe`, `place`, `acker`, `place_observer`, `lqi`, `lqr_sampled_data`, `reg`, `minimal_order_observer` |
//! | [`response`] | `lsim`, `lsim_split`, `step`, `impulse`, `initial`, `freqresp`, `bode` |
//!
//! Every function converts its arguments ([`crate::convert`]), releases the GIL around the
//! pendulab-lti call and returns NumPy arrays or a small result class ([`results`]) that
//! unpacks like python-control's tuple. Gains follow `u = −K x` (the book's `u = +K x` has
//! `K_book = −K`).

pub mod analysis;
pub mod design;
pub mod equations;
pub mod response;
pub mod results;
pub mod system;

use pyo3::prelude::*;

/// Adds this facet's functions and classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<system::StateSpace>()?;
    m.add_class::<system::TransferFunction>()?;
    m.add_function(wrap_pyfunction!(system::ss, m)?)?;
    m.add_function(wrap_pyfunction!(system::tf, m)?)?;
    m.add_function(wrap_pyfunction!(system::c2d, m)?)?;
    m.add_function(wrap_pyfunction!(system::d2c, m)?)?;

    m.add_function(wrap_pyfunction!(analysis::poles, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::zeros, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::dcgain, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::damp, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::ctrb_py, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::obsv_py, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::gram, m)?)?;
    m.add_class::<analysis::DampResult>()?;
    m.add_class::<analysis::MatrixEquationResult>()?;

    m.add_function(wrap_pyfunction!(equations::lyap, m)?)?;
    m.add_function(wrap_pyfunction!(equations::dlyap, m)?)?;
    m.add_function(wrap_pyfunction!(equations::care, m)?)?;
    m.add_function(wrap_pyfunction!(equations::dare, m)?)?;
    m.add_class::<equations::RiccatiResult>()?;

    m.add_function(wrap_pyfunction!(design::lqr, m)?)?;
    m.add_function(wrap_pyfunction!(design::dlqr, m)?)?;
    m.add_function(wrap_pyfunction!(design::lqe, m)?)?;
    m.add_function(wrap_pyfunction!(design::dlqe, m)?)?;
    m.add_function(wrap_pyfunction!(design::place_py, m)?)?;
    m.add_function(wrap_pyfunction!(design::acker_py, m)?)?;
    m.add_function(wrap_pyfunction!(design::place_observer_py, m)?)?;
    m.add_function(wrap_pyfunction!(design::lqi, m)?)?;
    m.add_function(wrap_pyfunction!(design::lqr_sampled_data, m)?)?;
    m.add_function(wrap_pyfunction!(design::reg, m)?)?;
    m.add_function(wrap_pyfunction!(design::minimal_order_observer, m)?)?;
    m.add_class::<design::LqrResult>()?;
    m.add_class::<design::LqeResult>()?;
    m.add_class::<design::PlaceResult>()?;
    m.add_class::<design::LqiResult>()?;
    m.add_class::<design::SampledDataLqrResult>()?;
    m.add_class::<design::MinimalObserverResult>()?;

    m.add_function(wrap_pyfunction!(response::lsim, m)?)?;
    m.add_function(wrap_pyfunction!(response::lsim_split, m)?)?;
    m.add_function(wrap_pyfunction!(response::step, m)?)?;
    m.add_function(wrap_pyfunction!(response::impulse, m)?)?;
    m.add_function(wrap_pyfunction!(response::initial, m)?)?;
    m.add_function(wrap_pyfunction!(response::freqresp, m)?)?;
    m.add_function(wrap_pyfunction!(response::bode, m)?)?;
    m.add_class::<response::LsimResult>()?;
    m.add_class::<response::LsimSplit>()?;
    m.add_class::<response::TimeResponse>()?;
    m.add_class::<response::FrequencyResponse>()?;
    m.add_class::<response::BodeResult>()?;
    Ok(())
}
