//! Singular values of the frequency response (MATLAB `sigma`, python-control
//! `singular_values_response`).
//!
//! `σ₁(ω) ≥ … ≥ σ_k(ω) ≥ 0`, `k = min(ny, nu)`, are the singular values of `G(jω)`
//! (continuous) or `G(e^{jωT})` (discrete) at each frequency, computed by
//! [`freqresp`] and the checked SVD ([`crate::linalg::svd`]). `σ₁` is the gain in the
//! worst input direction; its supremum over `ω` is the H∞ norm
//! ([`hinf_norm`](crate::norms::hinf_norm)).

use crate::domain::TimeDomain;
use crate::error::Result;
use crate::frequency_response::freqresp;
use crate::state_space::StateSpace;

/// Singular values over frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct SingularValues {
    /// Frequencies in rad/s.
    pub w: Vec<f64>,
    /// `values[k]` are the singular values at `w[k]`, descending (`min(ny, nu)` of them).
    pub values: Vec<Vec<f64>>,
}

/// The singular values of `G` at every `w` (module documentation).
///
/// # Errors
/// As [`freqresp`] (non-finite frequency, a frequency on a pole).
#[doc(alias = "singular_values_response")]
pub fn sigma<D: TimeDomain>(sys: &StateSpace<D>, w: &[f64]) -> Result<SingularValues> {
    let r = freqresp(sys, w)?;
    let values = r
        .response
        .iter()
        .map(|g| {
            if g.nrows() == 1 && g.ncols() == 1 {
                vec![g[(0, 0)].norm()]
            } else {
                crate::linalg::svd::svd(g)
                    .singular_values
                    .iter()
                    .copied()
                    .collect()
            }
        })
        .collect();
    Ok(SingularValues {
        w: w.to_vec(),
        values,
    })
}
