//! Controller and observer design.
//!
//! | task | function | MATLAB |
//! |---|---|---|
//! | LQ regulator (continuous/discrete, cross term) | [`lqr`] | `lqr`, `dlqr` |
//! | single-input LQ regulator, diagonal `Q`, per weight in `O(n²)` (symmetric root locus) | [`SymmetricRootLocus`] | — |
//! | sampled-data LQR (Van Loan cost discretisation) | [`lqr_sampled_data`], [`sampled_data_cost`] | `lqrd` |
//! | pole placement (robust, multi-input) | [`place`] | `place` |
//! | Ackermann's formula | [`acker`] | `acker` |
//! | observer gain by duality | [`place_observer`] | `place(A',C',p)'` |
//! | steady-state Kalman gain | [`lqe`] | `lqe`, `kalman` |
//! | LQ integral servo | [`integral_augmentation`], [`lq_servo`] | — |
//! | observer-based output feedback | [`observer_controller`] | `reg` |
//! | minimal-order (Gopinath) observer | [`minimal_order_observer`] | — |
//! | standard plant `P = [A B₁ B₂; C₁ D₁₁ D₁₂; C₂ D₂₁ D₂₂]`, its assumptions, `F_l(P, K)` | [`StandardPlant`] | `lft` |
//! | H∞ synthesis (Riccati, DGKF), γ-iteration, state feedback | [`hinf_syn`], [`hinf_syn_optimal`], [`hinf_state_feedback`] | `hinfsyn` |
//! | H2 synthesis (Riccati), state feedback | [`h2_syn`], [`h2_state_feedback`] | `h2syn` |
//! | mixed-sensitivity augmented plant | [`augw`] | `augw` |
//!
//! **Sign convention.** Every gain here is for `u = −K x` (closed loop `A − BK`), observer
//! gains for `A − LC`. The textbook writes `u = +K x` with `K_book = −K`;
//! [`StateFeedback`] converts explicitly ([`StateFeedback::from_book`],
//! [`StateFeedback::book_gain`]).

mod augw;
mod h2;
mod hinf;
mod lqr;
mod place;
mod servo;
mod standard_plant;
mod symmetric_root_locus;

pub use augw::augw;
pub use h2::{H2Controller, H2StateFeedback, h2_state_feedback, h2_syn};
pub use hinf::{
    GammaIteration, GammaOptimal, HinfCondition, HinfController, HinfRiccati, HinfStateFeedback,
    IMAGINARY_TOLERANCE, PSD_TOLERANCE, RESIDUAL_TOLERANCE, hinf_state_feedback,
    hinf_state_feedback_optimal, hinf_syn, hinf_syn_optimal,
};

pub use lqr::{
    Kalman, LQ_WEIGHT_TOLERANCE, Lqr, SampledDataCost, SampledDataLqr, lqe, lqr, lqr_sampled_data,
    lqr_with_options, sampled_data_cost,
};
pub use place::{PlacementMethod, PolePlacement, acker, place, place_observer};
pub use servo::{
    LqServo, ReducedOrderObserver, integral_augmentation, lq_servo, minimal_order_observer,
    observer_controller,
};
pub use standard_plant::{PlantAssumption, RANK_TOLERANCE, StandardPlant};
pub use symmetric_root_locus::{SRL_MAX, SRL_TOLERANCE, SrlSolution, SymmetricRootLocus};

use crate::domain::TimeDomain;
use crate::error::Result;
use crate::linalg::Mat;
use crate::state_space::StateSpace;

/// A static state feedback **`u = −K x`** (+ an external input `v`: `u = −K x + v`).
///
/// This type is where the sign convention lives. The textbook (and its MATLAB code, `K =
/// −lqr(...)`) writes `u = +K_book x`; convert with [`StateFeedback::from_book`] and
/// [`StateFeedback::book_gain`], never by flipping signs ad hoc.
#[derive(Debug, Clone, PartialEq)]
pub struct StateFeedback {
    gain: Mat,
}

impl StateFeedback {
    /// Feedback `u = −K x` with the library's gain `K` (`m × n`).
    ///
    /// # Errors
    /// [`LtiError::NonFinite`](crate::LtiError::NonFinite) for NaN/∞ entries.
    pub fn new(k: Mat) -> Result<Self> {
        crate::linalg::check_finite("K", &k)?;
        Ok(Self { gain: k })
    }

    /// Feedback from the textbook's gain (`u = +K_book x`): `K = −K_book`.
    ///
    /// # Errors
    /// As [`StateFeedback::new`].
    pub fn from_book(k_book: &Mat) -> Result<Self> {
        Self::new(-k_book)
    }

    /// The gain `K` of `u = −K x`.
    pub fn gain(&self) -> &Mat {
        &self.gain
    }

    /// The textbook's gain `K_book = −K` (`u = +K_book x`).
    pub fn book_gain(&self) -> Mat {
        -&self.gain
    }

    /// The control `u = −K x` for one state.
    ///
    /// # Errors
    /// [`LtiError::DimensionMismatch`](crate::LtiError::DimensionMismatch) if `x` has the
    /// wrong length.
    pub fn control(&self, x: &[f64]) -> Result<Vec<f64>> {
        if x.len() != self.gain.ncols() {
            return Err(crate::LtiError::DimensionMismatch {
                what: "state for the feedback law".into(),
                expected: (self.gain.ncols(), 1),
                found: (x.len(), 1),
            });
        }
        Ok((0..self.gain.nrows())
            .map(|i| -(0..x.len()).map(|j| self.gain[(i, j)] * x[j]).sum::<f64>())
            .collect())
    }

    /// The closed loop with external input `v` (`u = −K x + v`):
    /// `A − BK`, `B`, `C − DK`, `D`.
    ///
    /// # Errors
    /// [`LtiError::DimensionMismatch`](crate::LtiError::DimensionMismatch) if `K` is not
    /// `nu × nx` for `sys`.
    pub fn closed_loop<D: TimeDomain>(&self, sys: &StateSpace<D>) -> Result<StateSpace<D>> {
        lqr::check_gain(sys, &self.gain, "K")?;
        StateSpace::new(
            sys.a() - sys.b() * &self.gain,
            sys.b().clone(),
            sys.c() - sys.d() * &self.gain,
            sys.d().clone(),
            sys.domain(),
        )
    }
}
