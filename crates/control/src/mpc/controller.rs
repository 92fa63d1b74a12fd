//! The receding-horizon controller [`MpcController`]: a [`LinearMpc`] solved every sample on
//! the measured state, its first move applied (the LQ law, clipped to the input box, if a
//! solve fails), with counters of its solves.

use super::condensed::LinearMpc;
use super::qp::QpStatus;
use super::settings::{WarmStart, bounds_pair};
use crate::error::{ControlError, Result, check_param, check_vector};
use pendulab_sim::Controller;

/// Counters of an [`MpcController`]'s solves since its last reset.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MpcStatistics {
    /// QPs solved.
    pub solves: u64,
    /// Solves that ended [`QpStatus::Infeasible`] (the fallback law was applied).
    pub infeasible: u64,
    /// Solves that hit the iteration limit (the fallback law was applied).
    pub max_iterations_hit: u64,
    /// Most active-set iterations of one solve.
    pub max_iterations: usize,
    /// Active-set iterations summed over the solves.
    pub total_iterations: u64,
}

/// [`LinearMpc`] as a sampled-data [`Controller`]: it measures the full state `y = x` (a
/// setpoint `x_ref` subtracted), solves one warm-started QP at every loop sample and applies
/// the first move.
///
/// The prediction step `dt` is `periods_per_step` loop periods `ts`: the plan is re-solved every
/// period from the measured state (the first move held for the whole step in the prediction,
/// then replaced one period later), and the working set is shifted one stage every
/// `periods_per_step` samples ([`WarmStart::Shifted`], else [`WarmStart::Same`]). `u₋₁` of the
/// rate limit is the input applied at the previous sample. When a QP ends infeasible or at the
/// iteration limit the controller applies the fallback `u = clamp(−K x, u_min, u_max)` with the
/// terminal cost's LQ gain `K` ([`LinearMpc::lq_gain`]) and counts it
/// ([`MpcStatistics`]).
#[derive(Debug, Clone)]
pub struct MpcController {
    mpc: LinearMpc,
    ts: f64,
    periods_per_step: usize,
    counter: usize,
    x_ref: Vec<f64>,
    x: Vec<f64>,
    u_prev: Vec<f64>,
    u_min: Vec<f64>,
    u_max: Vec<f64>,
    stats: MpcStatistics,
}

impl MpcController {
    /// The controller of `mpc` at loop period `ts` \[s\], predicting with steps of
    /// `periods_per_step · ts` (the step `mpc` was discretised with), about the setpoint
    /// `x_ref` (`n_x` entries) with input bounds `u_min`, `u_max` for the fallback (those of
    /// the settings).
    ///
    /// # Errors
    /// [`ControlError::InvalidParameter`] for `ts` not positive or `periods_per_step` 0;
    /// [`ControlError::DimensionMismatch`]/[`ControlError::NonFinite`] for `x_ref`, bounds.
    pub fn new(
        mpc: LinearMpc,
        ts: f64,
        periods_per_step: usize,
        x_ref: &[f64],
        u_min: &[f64],
        u_max: &[f64],
    ) -> Result<Self> {
        check_param("ts", ts, ts > 0.0, "must be finite and > 0")?;
        if periods_per_step == 0 {
            return Err(ControlError::InvalidParameter {
                name: "periods_per_step".into(),
                value: 0.0,
                requirement: "must be ≥ 1".into(),
            });
        }
        check_vector("x_ref", x_ref, mpc.nx())?;
        bounds_pair("u_min", "u_max", u_min, u_max, mpc.nu())?;
        let (nx, nu) = (mpc.nx(), mpc.nu());
        Ok(Self {
            mpc,
            ts,
            periods_per_step,
            counter: 0,
            x_ref: x_ref.to_vec(),
            x: vec![0.0; nx],
            u_prev: vec![0.0; nu],
            u_min: u_min.to_vec(),
            u_max: u_max.to_vec(),
            stats: MpcStatistics::default(),
        })
    }

    /// The MPC (its last plan and QP).
    pub fn mpc(&self) -> &LinearMpc {
        &self.mpc
    }

    /// Counters since the last reset.
    pub fn statistics(&self) -> &MpcStatistics {
        &self.stats
    }
}

impl Controller for MpcController {
    fn ny(&self) -> usize {
        self.mpc.nx()
    }
    fn nu(&self) -> usize {
        self.mpc.nu()
    }
    fn reset(&mut self) {
        self.counter = 0;
        self.u_prev.iter_mut().for_each(|x| *x = 0.0);
        self.stats = MpcStatistics::default();
    }
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        for ((x, yi), r) in self.x.iter_mut().zip(y).zip(&self.x_ref) {
            *x = yi - r;
        }
        let warm = if self.counter == 0 {
            WarmStart::Cold
        } else if self.counter.is_multiple_of(self.periods_per_step) {
            WarmStart::Shifted
        } else {
            WarmStart::Same
        };
        self.counter += 1;
        let status = if self.x.iter().all(|x| x.is_finite()) {
            self.mpc.solve(&self.x, &self.u_prev, warm).ok()
        } else {
            None
        };
        self.stats.solves += 1;
        let iters = self.mpc.qp().iterations();
        self.stats.total_iterations += iters as u64;
        self.stats.max_iterations = self.stats.max_iterations.max(iters);
        match status {
            Some(QpStatus::Solved) => {
                u.copy_from_slice(&self.mpc.plan()[..self.mpc.nu()]);
            }
            other => {
                match other {
                    Some(QpStatus::Infeasible) => self.stats.infeasible += 1,
                    _ => self.stats.max_iterations_hit += 1,
                }
                let k = self.mpc.lq_gain();
                for (i, ui) in u.iter_mut().enumerate() {
                    let v: f64 = -(0..self.x.len())
                        .map(|c| k[(i, c)] * self.x[c])
                        .sum::<f64>();
                    *ui = if v.is_finite() {
                        v.clamp(self.u_min[i], self.u_max[i])
                    } else {
                        0.0
                    };
                }
            }
        }
        self.u_prev.copy_from_slice(u);
    }
    fn sample_time(&self) -> Option<f64> {
        Some(self.ts)
    }
}
