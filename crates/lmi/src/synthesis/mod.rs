//! Ready LMI syntheses for state-feedback control, each a documented function with its
//! problem statement:
//!
//! - [`alpha_stability`] / [`max_decay_rate`]: Lyapunov certificates of decay rate α;
//! - [`state_feedback`] (and the shorthands [`lq_state_feedback`],
//!   [`multiobjective_state_feedback`], [`robust_state_feedback`],
//!   [`saturated_state_feedback`]): the LMI LQ (guaranteed-cost) gain, D-stability pole
//!   regions (Chilali–Gahinet), polytopic robustness over plant vertices and input-saturation
//!   (invariant-ellipsoid) conditions, all with a common Lyapunov matrix `X` and gain factor
//!   `L`, `K = −L X⁻¹`;
//! - [`gain_scheduled_lq`]: parameter-dependent `X(ρ)`, `L(ρ)` with bounded `ρ̇`, SOS
//!   multipliers, γ minimisation, `K(ρ) = −L(ρ) X(ρ)⁻¹` as a callable ([`GainSchedule`]);
//! - [`hinf_lmi`] (output feedback, Gahinet–Apkarian projected LMIs and controller
//!   reconstruction), [`hinf_state_feedback_lmi`] and [`h2_state_feedback_lmi`]: H∞ and H2
//!   synthesis on `pendulab-lti`'s standard plant.
//!
//! Convention: the control law is `u = −K x` throughout (the textbook writes `u = +K̃ x`
//! with `K̃ = L X⁻¹`, i.e. `K̃ = −K`).

mod coordinates;
mod gain_schedule;
mod h2;
mod hinf;
mod scaling;
mod stability;
mod state_feedback;

pub use gain_schedule::{
    GainSchedule, GainScheduleSpec, LpvPlant, ScheduledGain, gain_scheduled_lq,
};
pub use h2::{
    H2LmiController, H2OutputFeedbackLmi, H2StateFeedbackLmi, h2_output_feedback_lmi,
    h2_state_feedback_lmi,
};
pub use hinf::{
    HinfLmi, HinfLmiController, HinfLmiOptions, HinfStateFeedbackLmi, hinf_lmi, hinf_lmi_at,
    hinf_state_feedback_lmi,
};
pub use stability::{AlphaStability, DecayRate, alpha_stability, max_decay_rate};
pub use state_feedback::{
    Feedback, InputBound, LqWeights, Refinement, StateFeedbackDesign, StateFeedbackSpec,
    StateScaling, Vertex, lq_state_feedback, multiobjective_state_feedback, robust_state_feedback,
    saturated_state_feedback, state_feedback,
};

use crate::error::{LmiError, Result};
use crate::expr::Expr;
use pendulab_lti::{Complex64, Mat};

/// An LMI region of the complex plane (Chilali & Gahinet, "H∞ design with pole placement
/// constraints: an LMI approach", IEEE TAC 41(3), 1996): `D = {z : L + z M + z̄ Mᵀ ≺ 0}`.
/// All eigenvalues of `A_cl` lie in `D` iff some `X ≻ 0` satisfies
/// `L ⊗ X + M ⊗ (A_cl X) + Mᵀ ⊗ (A_cl X)ᵀ ≺ 0`; with `A_cl X = A X + B L` this is an LMI in
/// `(X, L)`.
#[derive(Debug, Clone, PartialEq)]
pub enum Region {
    /// `Re z < −α`: decay rate at least `α` (`L = 2α`, `M = 1`).
    DecayRate {
        /// `α` (1/s).
        alpha: f64,
    },
    /// `Re z > −β`: no pole faster than `β` (`L = −2β`, `M = −1`).
    SpeedLimit {
        /// `β > 0` (1/s).
        beta: f64,
    },
    /// The conic sector `|Im z| < tan θ · (−Re z)` around the negative real axis, i.e.
    /// damping ratio at least `cos θ` (`L = 0`, `M = [[sin θ, cos θ], [−cos θ, sin θ]]`).
    Sector {
        /// Half-angle `θ ∈ (0, π/2)` (rad).
        theta: f64,
    },
    /// The open disk `|z + q| < r` (`L = [[−r, q], [q, −r]]`, `M = [[0, 1], [0, 0]]`).
    Disk {
        /// Centre `−q` on the real axis (`q` is the distance to the left of the origin).
        center: f64,
        /// Radius `r > 0`.
        radius: f64,
    },
    /// A general LMI region `{z : L + z M + z̄ Mᵀ ≺ 0}` (`L` symmetric, `M` square, same size).
    General {
        /// `L`.
        l: Mat,
        /// `M`.
        m: Mat,
    },
}

impl Region {
    /// The characteristic matrices `(L, M)`.
    ///
    /// # Errors
    /// [`LmiError::InvalidArgument`] for parameters outside their ranges.
    pub fn matrices(&self) -> Result<(Mat, Mat)> {
        let bad = |what: &str, v: f64| LmiError::InvalidArgument {
            what: format!("region {what}"),
            reason: format!("out of range: {v}"),
        };
        Ok(match self {
            Region::DecayRate { alpha } => {
                if !alpha.is_finite() {
                    return Err(bad("alpha", *alpha));
                }
                (
                    Mat::from_element(1, 1, 2.0 * alpha),
                    Mat::from_element(1, 1, 1.0),
                )
            }
            Region::SpeedLimit { beta } => {
                if !(beta.is_finite() && *beta > 0.0) {
                    return Err(bad("beta", *beta));
                }
                (
                    Mat::from_element(1, 1, -2.0 * beta),
                    Mat::from_element(1, 1, -1.0),
                )
            }
            Region::Sector { theta } => {
                if !(theta.is_finite() && *theta > 0.0 && *theta < std::f64::consts::FRAC_PI_2) {
                    return Err(bad("theta", *theta));
                }
                let (s, c) = theta.sin_cos();
                (Mat::zeros(2, 2), Mat::from_row_slice(2, 2, &[s, c, -c, s]))
            }
            Region::Disk { center, radius } => {
                if !(center.is_finite() && radius.is_finite() && *radius > 0.0) {
                    return Err(bad("disk", *radius));
                }
                (
                    Mat::from_row_slice(2, 2, &[-radius, *center, *center, -radius]),
                    Mat::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]),
                )
            }
            Region::General { l, m } => {
                let k = l.nrows();
                if l.shape() != (k, k) || m.shape() != (k, k) || k == 0 {
                    return Err(LmiError::ShapeMismatch {
                        op: "general LMI region (L, M square of the same size)".into(),
                        left: l.shape(),
                        right: m.shape(),
                    });
                }
                crate::linalg::check_finite("region L", l)?;
                crate::linalg::check_finite("region M", m)?;
                (l.clone(), m.clone())
            }
        })
    }

    /// The D-stability matrix `L ⊗ X + M ⊗ Y + Mᵀ ⊗ Yᵀ` for `Y = A_cl X` (to be `≺ 0`).
    pub(crate) fn lmi(&self, x: &Expr, y: &Expr) -> Result<Expr> {
        let (l, m) = self.matrices()?;
        let e = Expr::kron(&Expr::constant(&l), x)
            + Expr::kron(&Expr::constant(&m), y)
            + Expr::kron(&Expr::constant(&m.transpose()), &y.t());
        e.check()?;
        Ok(e)
    }

    /// Whether `z` lies in the (open) region: `L + z M + z̄ Mᵀ ≺ 0` (a Hermitian matrix).
    pub fn contains(&self, z: Complex64) -> bool {
        let Ok((l, m)) = self.matrices() else {
            return false;
        };
        if !(z.re.is_finite() && z.im.is_finite()) {
            return false;
        }
        // Hermitian H = L + z M + z̄ Mᵀ = Hr + i Hi; H ≺ 0 iff [[Hr, −Hi], [Hi, Hr]] ≺ 0.
        let hr = &l + &m * z.re + m.transpose() * z.re;
        let hi = &m * z.im - m.transpose() * z.im;
        let k = l.nrows();
        let mut big = Mat::zeros(2 * k, 2 * k);
        big.view_mut((0, 0), (k, k)).copy_from(&hr);
        big.view_mut((k, k), (k, k)).copy_from(&hr);
        big.view_mut((k, 0), (k, k)).copy_from(&hi);
        big.view_mut((0, k), (k, k)).copy_from(&(-&hi));
        let big = crate::linalg::sym(&big);
        big.symmetric_eigenvalues().iter().all(|v| *v < 0.0)
    }
}
