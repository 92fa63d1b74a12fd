//! Controllers as values implementing [`Controller`](crate::Controller).
//!
//! | controller | law | sample time |
//! |---|---|---|
//! | [`StaticStateFeedback`] | `u = −K (y − y_ref)` (library sign; [`StaticStateFeedback::from_book`] for `u = +K_book y`) | any |
//! | [`LqIntegralServo`] | `u = −K₁ y − K₂ w`, `w ≈ ∫(r − C_s y)` by an explicit [`IntegrationRule`] | fixed |
//! | [`DiscreteLinearController`] | any discrete system `ξ⁺ = Aξ + By`, `u = Cξ + Dy` (e.g. `reg`, a discretised compensator) | fixed |
//! | [`ObserverBased`] | `u = −K x̂` with a discrete full-order observer, prediction or current form | fixed |
//! | [`GainScheduled`] | `u = −K(ρ) (y − y_ref)`, `ρ = φ(y)` | any |
//! | [`Switching`] | mode A until a condition on `y` holds, then mode B (switch times recorded) | as its modes |
//! | [`Pid`] | P, PD, P–D, PI, PID, I–PD with a filtered derivative, Tustin or backward Euler | fixed |
//! | [`OpenLoop`] | `u_k = s(t_k)`: a preset command sequence, sampled and held | any |
//! | [`Saturated`] | any controller with its command clipped to `[lo, hi]` | as the inner one |
//!
//! Gains are stored row-major in flat vectors and applied without allocation.

/// The size accessors of a [`Controller`](crate::Controller) impl whose struct keeps its
/// measurement and command counts in fields `ny` and `nu`: `ny()`, `nu()`; with `sampled`,
/// also `sample_time() = Some(ts)` from a field `ts` \[s\]. Written inside the `impl` block.
macro_rules! sizes_from_fields {
    () => {
        fn ny(&self) -> usize {
            self.ny
        }
        fn nu(&self) -> usize {
            self.nu
        }
    };
    (sampled) => {
        sizes_from_fields!();
        fn sample_time(&self) -> Option<f64> {
            Some(self.ts)
        }
    };
}

mod linear;
mod open_loop;
mod pid;
mod scheduled;
mod state_feedback;

pub use linear::{DiscreteLinearController, EstimatorForm, ObserverBased};
pub use open_loop::OpenLoop;
pub use pid::{Pid, PidDiscretization, PidForm};
pub use scheduled::{GainScheduled, Mode, Saturated, Switching};
pub use state_feedback::{IntegrationRule, LqIntegralServo, StaticStateFeedback};

use crate::error::{Result, SimError};
use pendulab_lti::Mat;

/// Row-major copy of a matrix, checking finiteness.
pub(crate) fn row_major(what: &str, m: &Mat) -> Result<Vec<f64>> {
    let mut v = Vec::with_capacity(m.nrows() * m.ncols());
    for i in 0..m.nrows() {
        for j in 0..m.ncols() {
            let x = m[(i, j)];
            if !x.is_finite() {
                return Err(SimError::InvalidParameter {
                    what: format!("{what}[{i}, {j}]"),
                    value: x,
                    requirement: "must be finite",
                });
            }
            v.push(x);
        }
    }
    Ok(v)
}

/// `out = M v` for a row-major `rows × v.len()` matrix.
#[inline(always)]
pub(crate) fn mat_vec(m: &[f64], v: &[f64], out: &mut [f64]) {
    let n = v.len();
    for (i, o) in out.iter_mut().enumerate() {
        let row = &m[i * n..(i + 1) * n];
        *o = row.iter().zip(v).map(|(a, b)| a * b).sum();
    }
}

/// Checks a controller sample time.
pub(crate) fn check_ts(ts: f64) -> Result<()> {
    if !(ts.is_finite() && ts > 0.0) {
        return Err(SimError::InvalidSampleTime(ts));
    }
    Ok(())
}
