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
//! | [`synthesis`] | `hinfsyn`, `h2syn`, `augw` |
//! | [`transfer`] | `TransferMatrix` (MIMO `tf`), `pade`, `thiran` |
//! | [`loop_analysis`] | `nyquist`, `nichols`, `rlocus`, `rlocfind`, `disk_margin`, `disk_margin_mimo`, `mu_diag_complex`, `sigma` |
//! | [`reduction`] | `stabsep`, `hsvd`, `balreal`, `balred`, `hinfnorm` |
//!
//! Every function converts its arguments ([`crate::convert`]), releases the GIL around the
//! pendulab-lti call and returns NumPy arrays or a small result class ([`results`]) that
//! unpacks like python-control's tuple. Gains follow `u = −K x` (the book's `u = +K x` has
//! `K_book = −K`).

pub mod analysis;
pub mod design;
pub mod equations;
pub mod loop_analysis;
pub mod reduction;
pub mod response;
pub mod results;
pub mod synthesis;
pub mod system;
pub mod transfer;

use pyo3::prelude::*;

/// Runs the pendulab-lti computation `f` with the GIL released (other Python threads run
/// meanwhile) and turns its error into the matching `pendulab` exception
/// ([`crate::errors::lti`]).
pub fn nogil<T, F>(py: Python<'_>, f: F) -> PyResult<T>
where
    F: pyo3::marker::Ungil + FnOnce() -> pendulab_lti::Result<T>,
    T: Send,
{
    py.detach(f).map_err(crate::errors::lti)
}

/// Adds each listed `#[pyfunction]` (first list) and `#[pyclass]` (second list) to `$m`.
macro_rules! add_all {
    ($m:ident; [$($f:path),* $(,)?]; [$($c:ty),* $(,)?]) => {{
        $($m.add_function(wrap_pyfunction!($f, $m)?)?;)*
        $($m.add_class::<$c>()?;)*
    }};
}

/// Adds this facet's functions and classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    use analysis::*;
    use design::*;
    use equations::*;
    use loop_analysis::*;
    use reduction::*;
    use response::*;
    use synthesis::*;
    use system::*;
    use transfer::*;
    add_all!(m;
        [hinfsyn, h2syn, augw,
         ss, tf, c2d, d2c, poles, zeros, dcgain, damp, ctrb_py, obsv_py, gram, lyap, dlyap, care, dare,
         lqr, dlqr, lqe, dlqe, place_py, acker_py, place_observer_py, lqi, lqr_sampled_data, reg,
         minimal_order_observer, lsim, lsim_split, step, impulse, initial, freqresp, bode, nyquist,
         nichols, rlocus, rlocfind, disk_margin, sigma, pade, thiran,
         disk_margin_mimo, mu_diag_complex_py, stabsep, hsvd, balreal, balred, hinfnorm];
        [HinfsynResult, H2synResult,
         StateSpace, TransferFunction, DampResult, MatrixEquationResult, RiccatiResult, LqrResult,
         LqeResult, PlaceResult, LqiResult, SampledDataLqrResult, MinimalObserverResult, LsimResult,
         LsimSplit, TimeResponse, FrequencyResponse, BodeResult, NyquistResult, NicholsResult,
         RootLocusResult, RlocfindResult, DiskMarginResult, SigmaResult, TransferMatrix,
         MimoDiskMarginResult, MuResult, StabsepResult, BalrealResult, HinfnormResult]);
    Ok(())
}
