//! `kind = "nmpc"`: the arm pendulum's C/GMRES swing-up (book part 2 §3.3,
//! `p2c33_adip_nmpc_swing_up`; [`crate::nmpc::arm_swing_up_controller`]).
//!
//! The controller measures the full state `[θ₁, θ₂, θ̇₁, θ̇₂]` (the rig's 4 entries), predicts
//! on the plant's own nonlinear model (the [`PlantSpec`](pendulab_plants::spec::PlantSpec)'s
//! parameters) and updates at the loop period. Every key is optional and defaults to the
//! book's setting ([`ArmSwingUpSettings::book`]); `zeta` defaults to `1/ts` (1000 1/s at the
//! book's 1 ms). The problem is the arm's: on the cart the kind is refused
//! ([`SpecError::NotForPlant`]). It swings up from the hanging rest, so a run has no angle
//! window, and ends balancing upright (pendulum centre 0).

use super::{SpecError, finite};
use crate::cgmres::Horizon;
use crate::nmpc::{ArmSwingUpSettings, arm_swing_up_controller};
use pendulab_plants::ArmPendulum;
use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::PlantParameters;
use pendulab_sim::Controller;

kind_keys! {
    /// Keys of `kind = "nmpc"` (module documentation of [`crate::spec::nmpc`]); each defaults to
    /// [`ArmSwingUpSettings::book`].
    pub struct NmpcSpec {
        /// Final horizon length `T_f` \[s\] of `T(t) = T_f(1 − e^{−αt})` (> 0; book 0.5).
        pub horizon: Option<f64>,
        /// Horizon growth rate `α` \[1/s\] (> 0; book 0.5).
        pub horizon_rate: Option<f64>,
        /// Divisions `N` of the horizon (1 to 1000; book 25).
        pub divisions: Option<usize>,
        /// Stage weights `diag(Q)` on `[θ₁, θ₂, θ̇₁, θ̇₂]` (4 entries ≥ 0; book `[1, 1, 0, 0]`).
        pub q: Option<Vec<f64>>,
        /// Terminal weights `diag(Q_f)` (4 entries ≥ 0; book `[3, 1, 0, 0]`).
        pub qf: Option<Vec<f64>>,
        /// Input weight `r` \[1/V²\] (> 0; default 0.1, see [`ArmSwingUpSettings::book`]).
        pub r: Option<f64>,
        /// Input bound `u_max` \[V\] (> 0; book 2.5).
        pub u_max: Option<f64>,
        /// Weight of the dummy input of the bound (> 0; default 0.1).
        pub dummy_weight: Option<f64>,
        /// GMRES iterations per update `kmax` (1 to 100; book 5).
        pub gmres_iterations: Option<usize>,
        /// Stabilisation `ζ` \[1/s\] (> 0, `ζ·ts ≤ 1`; default `1/ts`).
        pub zeta: Option<f64>,
    }
}

impl NmpcSpec {
    /// The solver settings the keys describe at loop period `ts` \[s\] (the book's where a
    /// key is left out).
    ///
    /// # Errors
    /// [`SpecError`] naming the key: out of range, not finite, or a weight list of the wrong
    /// length.
    pub fn settings(&self, ts: f64) -> Result<ArmSwingUpSettings, SpecError> {
        let mut s = ArmSwingUpSettings::book();
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
        let count = |key: &'static str, v: usize, max: usize| -> Result<usize, SpecError> {
            if (1..=max).contains(&v) {
                Ok(v)
            } else {
                Err(SpecError::OutOfRange {
                    key,
                    value: v as f64,
                    range: format!("[1, {max}]"),
                })
            }
        };
        let weights = |key: &str, w: &[f64]| -> Result<[f64; 4], SpecError> {
            let m = super::diag(key, w, 4)?;
            Ok([m[(0, 0)], m[(1, 1)], m[(2, 2)], m[(3, 3)]])
        };
        let Horizon::Growing {
            mut final_length,
            mut rate,
        } = s.solver.horizon
        else {
            unreachable!("the book's horizon grows")
        };
        if let Some(v) = self.horizon {
            final_length = positive("controller.horizon", v)?;
        }
        if let Some(v) = self.horizon_rate {
            rate = positive("controller.horizon_rate", v)?;
        }
        s.solver.horizon = Horizon::Growing { final_length, rate };
        if let Some(v) = self.divisions {
            s.solver.grid_points = count("controller.divisions", v, 1000)?;
        }
        if let Some(v) = self.gmres_iterations {
            s.solver.gmres_iterations = count("controller.gmres_iterations", v, 100)?;
        }
        if let Some(q) = &self.q {
            s.q = weights("controller.q", q)?;
        }
        if let Some(q) = &self.qf {
            s.qf = weights("controller.qf", q)?;
        }
        if let Some(v) = self.r {
            s.r = positive("controller.r", v)?;
        }
        if let Some(v) = self.u_max {
            s.u_max = positive("controller.u_max", v)?;
        }
        if let Some(v) = self.dummy_weight {
            s.dummy_weight = positive("controller.dummy_weight", v)?;
        }
        let zeta = self.zeta.unwrap_or(1.0 / ts);
        finite("controller.zeta", &[zeta])?;
        if !(zeta > 0.0 && zeta * ts <= 1.0 + 1e-12) {
            return Err(SpecError::OutOfRange {
                key: "controller.zeta",
                value: zeta,
                range: format!("(0, 1/ts] = (0, {}] 1/s", 1.0 / ts),
            });
        }
        s.solver.zeta = zeta;
        s.ts = ts;
        Ok(s)
    }
}

/// The running C/GMRES controller of `c` on the arm `plant` at loop period `ts`.
pub(super) fn nmpc(
    plant: &PlantParameters,
    c: &NmpcSpec,
    ts: f64,
) -> Result<Box<dyn Controller>, SpecError> {
    let PlantParameters::Arm(p) = plant else {
        return Err(SpecError::NotForPlant {
            kind: super::ControllerSpec::NMPC,
            plant: plant.kind(),
            only: PlantKind::Arm,
        });
    };
    let settings = c.settings(ts)?;
    let arm = ArmPendulum::new(*p).map_err(|source| SpecError::Linearisation {
        at: "arm plant".into(),
        source,
    })?;
    Ok(Box::new(arm_swing_up_controller(arm, &settings)?))
}
