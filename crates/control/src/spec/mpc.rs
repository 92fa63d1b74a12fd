//! `kind = "mpc"`: constrained linear MPC about the upright rest ([`crate::mpc`]).
//!
//! The prediction model is the plant's upright linearisation (its own parameters; the arm at
//! `θ₁ₑ = 0`) sampled by ZOH at `step`; every loop period the controller solves the condensed
//! QP over `horizon` steps from the measured `y = [q₀, q₁, q̇₀, q̇₁]` and applies the first move
//! ([`MpcController`]). Limits: `|u| ≤ u_max` always, `|q₀| ≤ travel_limit` over the predicted
//! states and `|u_k − u_{k−1}| ≤ du_max` per step when given. The terminal weight is the DARE
//! solution, so without active limits the law is the discrete LQR of `q`, `r`.
//!
//! | key | default | range |
//! |---|---|---|
//! | `horizon` | 20 | prediction steps, 1 to [`HORIZON_MAX`] |
//! | `step` | 0.01 s | a whole number (1 to 1000) of loop periods |
//! | `q` | `[100, 100, 0, 0]` | 4 entries ≥ 0, `diag(Q)` on `[q₀, q₁, q̇₀, q̇₁]` |
//! | `r` | 0.01 1/V² | > 0 |
//! | `u_max` | 5 V (the rigs' D/A range) | > 0 |
//! | `travel_limit` | none | > 0 (m or rad) |
//! | `du_max` | none | > 0 (V per step) |

use super::{SpecError, diag, finite};
use crate::mpc::{LinearMpc, MpcController, MpcSettings, QpOptions, StateBound, Terminal};
use pendulab_lti::Mat;
use pendulab_plants::spec::PlantParameters;
use pendulab_sim::Controller;

/// Longest horizon a file may ask for (steps): the condensed Hessian is `N × N` and the QP is
/// solved every loop period.
pub const HORIZON_MAX: usize = 200;

kind_keys! {
    /// Keys of `kind = "mpc"` (module documentation of [`crate::spec::mpc`]).
    pub struct MpcSpec {
        /// Horizon `N` in prediction steps (1 to [`HORIZON_MAX`]; default 20).
        pub horizon: Option<usize>,
        /// Prediction step \[s\], a whole number of loop periods (default 0.01).
        pub step: Option<f64>,
        /// `diag(Q)` on `[q₀, q₁, q̇₀, q̇₁]` (4 entries ≥ 0; default `[100, 100, 0, 0]`).
        pub q: Option<Vec<f64>>,
        /// `R` \[1/V²\] (> 0; default 0.01).
        pub r: Option<f64>,
        /// Input bound `|u| ≤ u_max` \[V\] (> 0; default 5).
        pub u_max: Option<f64>,
        /// Track bound `|q₀| ≤ travel_limit` on the predicted states \[m or rad\] (> 0; none by
        /// default).
        pub travel_limit: Option<f64>,
        /// Rate bound `|u_k − u_{k−1}| ≤ du_max` per prediction step \[V\] (> 0; none by default).
        pub du_max: Option<f64>,
    }
}

/// Default `horizon`.
pub const HORIZON_DEFAULT: usize = 20;
/// Default `step` \[s\].
pub const STEP_DEFAULT: f64 = 0.01;
/// Default `q`.
pub const Q_DEFAULT: [f64; 4] = [100.0, 100.0, 0.0, 0.0];
/// Default `r` \[1/V²\].
pub const R_DEFAULT: f64 = 0.01;
/// Default `u_max` \[V\].
pub const U_MAX_DEFAULT: f64 = 5.0;

impl MpcSpec {
    /// The MPC settings the keys describe and the loop periods per prediction step, at loop
    /// period `ts` \[s\].
    ///
    /// # Errors
    /// [`SpecError`] naming the key: out of range, not finite, `q` of the wrong length or
    /// negative, `step` not a whole number of periods.
    pub fn settings(&self, ts: f64) -> Result<(MpcSettings, usize), SpecError> {
        let positive = |key: &'static str, v: f64| -> Result<f64, SpecError> {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(SpecError::OutOfRange {
                    key,
                    value: v,
                    range: "(0, ∞)".into(),
                })
            }
        };
        let horizon = self.horizon.unwrap_or(HORIZON_DEFAULT);
        if !(1..=HORIZON_MAX).contains(&horizon) {
            return Err(SpecError::OutOfRange {
                key: "controller.horizon",
                value: horizon as f64,
                range: format!("[1, {HORIZON_MAX}] steps"),
            });
        }
        let step = positive("controller.step", self.step.unwrap_or(STEP_DEFAULT))?;
        let periods = (step / ts).round();
        if !((1.0..=1000.0).contains(&periods) && (periods * ts - step).abs() <= 1e-9 * step) {
            return Err(SpecError::OutOfRange {
                key: "controller.step",
                value: step,
                range: format!("whole multiples of the loop period {ts} s, 1 to 1000 of them"),
            });
        }
        let q = diag("controller.q", self.q.as_deref().unwrap_or(&Q_DEFAULT), 4)?;
        let r = positive("controller.r", self.r.unwrap_or(R_DEFAULT))?;
        let u_max = positive("controller.u_max", self.u_max.unwrap_or(U_MAX_DEFAULT))?;
        let mut state_bounds = Vec::new();
        if let Some(t) = self.travel_limit {
            let t = positive("controller.travel_limit", t)?;
            state_bounds.push(StateBound {
                index: 0,
                min: -t,
                max: t,
            });
        }
        let du_max = match self.du_max {
            Some(v) => Some(vec![positive("controller.du_max", v)?]),
            None => None,
        };
        finite("controller.q", q.as_slice())?;
        Ok((
            MpcSettings {
                horizon,
                q,
                r: Mat::from_element(1, 1, r),
                terminal: Terminal::Dare,
                u_min: vec![-u_max],
                u_max: vec![u_max],
                du_max,
                state_bounds,
                qp: QpOptions::default(),
            },
            periods as usize,
        ))
    }
}

/// The running MPC of `c` on `plant` at loop period `ts`.
pub(super) fn mpc(
    plant: &PlantParameters,
    c: &MpcSpec,
    ts: f64,
) -> Result<Box<dyn Controller>, SpecError> {
    let (settings, periods) = c.settings(ts)?;
    let lin = super::upright(plant)?;
    let dt = periods as f64 * ts;
    let mpc = LinearMpc::sampled(&lin, dt, &settings)?;
    let u_max = settings.u_max.clone();
    Ok(Box::new(MpcController::new(
        mpc,
        ts,
        periods,
        &[0.0; 4],
        &settings.u_min,
        &u_max,
    )?))
}
