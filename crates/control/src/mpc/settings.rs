//! The MPC problem's settings ([`MpcSettings`]: horizon, weights, terminal weight, input,
//! rate and state bounds, QP options), the warm-start choice, and their checks.

use super::qp::QpOptions;
use crate::error::{ControlError, Result, check_param};
use pendulab_lti::Mat;

/// The terminal weight `P` of the MPC cost.
#[derive(Debug, Clone, PartialEq)]
pub enum Terminal {
    /// The stabilising solution of the DARE of `(A, B, Q, R)` (default): the unconstrained MPC
    /// law is then the infinite-horizon LQ law.
    Dare,
    /// A given symmetric positive semidefinite `n_x × n_x` weight.
    Weight(Mat),
}

/// Bounds `min ≤ x_{k,index} ≤ max` on one state over the predicted states `k = 1 … N`
/// (infinite for none on a side).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateBound {
    /// The state's index (0-based).
    pub index: usize,
    /// Lower bound (state's unit; `−∞` for none).
    pub min: f64,
    /// Upper bound (`+∞` for none).
    pub max: f64,
}

/// The MPC problem's settings (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct MpcSettings {
    /// Horizon `N` in prediction steps (1 to 1000).
    pub horizon: usize,
    /// State weight `Q` (`n_x × n_x`, symmetric).
    pub q: Mat,
    /// Input weight `R` (`n_u × n_u`, symmetric positive definite).
    pub r: Mat,
    /// Terminal weight.
    pub terminal: Terminal,
    /// Lower input bounds (`n_u` entries; `−∞` for none).
    pub u_min: Vec<f64>,
    /// Upper input bounds (`n_u` entries; `+∞` for none).
    pub u_max: Vec<f64>,
    /// Largest change of each input per prediction step, `|u_k − u_{k−1}| ≤ Δu_max`
    /// (`n_u` entries > 0, `+∞` for none), or `None`.
    pub du_max: Option<Vec<f64>>,
    /// State bounds over the predicted states.
    pub state_bounds: Vec<StateBound>,
    /// Options of the QP method.
    pub qp: QpOptions,
}

impl MpcSettings {
    /// Checks the settings against a model of `nx` states and `nu` inputs (the weights'
    /// shapes are checked by [`super::LinearMpc::new`] before).
    ///
    /// # Errors
    /// As [`super::LinearMpc::new`]: `horizon`, `R` not positive definite, the input, rate and
    /// state bounds.
    pub(super) fn check(&self, nx: usize, nu: usize) -> Result<()> {
        let n_h = self.horizon;
        if !(1..=1000).contains(&n_h) {
            return Err(ControlError::InvalidParameter {
                name: "horizon".into(),
                value: n_h as f64,
                requirement: "must be 1 to 1000 steps".into(),
            });
        }
        if self.r.clone().cholesky().is_none() {
            return Err(ControlError::Singular {
                what: "MPC weight R (not positive definite)".into(),
                value: 0.0,
            });
        }
        bounds_pair("u_min", "u_max", &self.u_min, &self.u_max, nu)?;
        if let Some(du) = &self.du_max {
            if du.len() != nu {
                return Err(ControlError::DimensionMismatch {
                    what: "du_max".into(),
                    expected: nu,
                    found: du.len(),
                });
            }
            for &v in du {
                check_param("du_max", v, v > 0.0, "must be > 0 (+∞ for no limit)")?;
            }
        }
        for (i, sb) in self.state_bounds.iter().enumerate() {
            let name = format!("state_bounds[{i}]");
            if sb.index >= nx {
                return Err(ControlError::InvalidParameter {
                    name: format!("{name}.index"),
                    value: sb.index as f64,
                    requirement: format!("must be below the state count {nx}"),
                });
            }
            bounds_pair(
                &format!("{name}.min"),
                &format!("{name}.max"),
                &[sb.min],
                &[sb.max],
                1,
            )?;
        }
        Ok(())
    }
}

/// Which working set a solve starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WarmStart {
    /// The empty set (the unconstrained optimum first).
    Cold,
    /// The last solve's active set as it is.
    Same,
    /// The last solve's active set moved one stage earlier (the stage-0 rows dropped): the
    /// receding horizon's guess one prediction step later.
    Shifted,
}

/// Checks a pair of bound vectors `lo ≤ hi` of length `n` (no NaN, `lo < +∞`, `hi > −∞`);
/// errors name the vector and entry.
pub(super) fn bounds_pair(
    lo_name: &str,
    hi_name: &str,
    lo: &[f64],
    hi: &[f64],
    n: usize,
) -> Result<()> {
    for (name, v) in [(lo_name, lo), (hi_name, hi)] {
        if v.len() != n {
            return Err(ControlError::DimensionMismatch {
                what: name.into(),
                expected: n,
                found: v.len(),
            });
        }
        if let Some((index, &value)) = v.iter().enumerate().find(|(_, x)| x.is_nan()) {
            return Err(ControlError::NonFinite {
                what: name.into(),
                index,
                value,
            });
        }
    }
    for i in 0..n {
        if lo[i] > hi[i] || lo[i] == f64::INFINITY || hi[i] == f64::NEG_INFINITY {
            return Err(ControlError::InvalidParameter {
                name: format!("{lo_name}[{i}]"),
                value: lo[i],
                requirement: format!("must be ≤ {hi_name}[{i}] = {} and below +∞", hi[i]),
            });
        }
    }
    Ok(())
}
