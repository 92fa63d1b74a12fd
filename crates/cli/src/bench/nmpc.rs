//! `nmpc-update`: one C/GMRES update of the arm pendulum's swing-up controller.
//!
//! The book's NMPC (§3.3): 4 states, the input with its dummy input and multiplier (3 unknowns
//! per stage), 25 grid points (75 unknowns), `kmax = 5` GMRES iterations with forward-difference
//! Jacobian products, `T(t) = 0.5(1 − e^{−0.5t})`, 1 ms updates. Each timed run is the whole
//! closed-loop swing-up from `[π, π, 0, 0]` over 10 s in `pendulab-sim`'s sampled-data loop
//! (10 000 updates, the plant stepped by RK4 at 1 ms between them), so the figure averages over
//! the phases of the swing (bound active, horizon growing, balancing). The solver is
//! initialised before the run (a small Newton problem at `T = 0`, not a continuation update).
//! Figure: mean microseconds per update (the median over the runs); the check holds the worst
//! single update, the outcome of the swing-up and the solver's optimality residuals. The
//! machine's load shows in the worst single update (a preempted update counts whole); the mean
//! is robust to it.

use super::{BenchReport, Budget};
use anyhow::{Result, bail};
use pendulab_control::cgmres::TimedController;
use pendulab_control::nmpc::{ArmSwingUpSettings, arm_swing_up_controller};
use pendulab_plants::ArmPendulum;
use pendulab_sim::{SampledLoop, SampledOptions};
use serde_json::json;
use std::time::Instant;

const T_FINAL: f64 = 10.0;

struct Run {
    mean_s: f64,
    max_s: f64,
    updates: u64,
    max_abs_u: f64,
    final_state: Vec<f64>,
    swing_up_time: Option<f64>,
    max_residual: f64,
    last_residual: f64,
}

fn run_once() -> Result<Run> {
    let plant = ArmPendulum::book();
    let settings = ArmSwingUpSettings::book();
    let pi = std::f64::consts::PI;
    let x0 = [pi, pi, 0.0, 0.0];
    let mut inner = arm_swing_up_controller(plant, &settings)?;
    inner.initialize(0.0, &x0)?;
    let mut l = SampledLoop::new(
        plant,
        TimedController::new(inner),
        SampledOptions {
            t_final: T_FINAL,
            ..Default::default()
        },
    )?;
    let run = l.run(&x0)?;
    let (t, x) = (run.trajectory.t(), run.trajectory.x());
    // "Up": both angles within 5° of upright (unwrapped: the target is 0 itself) from then on.
    let tol = 5f64.to_radians();
    let mut swing_up_time = None;
    for k in (0..t.len()).rev() {
        if x[(k, 0)].abs() < tol && x[(k, 1)].abs() < tol {
            swing_up_time = Some(t[k]);
        } else {
            break;
        }
    }
    let max_abs_u = run.commands.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let timing = *l.controller().timing();
    let stats = *l.controller().inner().statistics();
    Ok(Run {
        mean_s: timing.mean_seconds(),
        max_s: timing.max_seconds,
        updates: timing.count,
        max_abs_u,
        final_state: run.diagnostics.final_state,
        swing_up_time,
        max_residual: stats.max_optimality_residual,
        last_residual: stats.last_optimality_residual,
    })
}

/// Runs the workload.
pub fn run(budget: &Budget) -> Result<BenchReport> {
    let start = Instant::now();
    let mut runs = Vec::new();
    while start.elapsed() < budget.min_time || runs.len() < 3 {
        runs.push(run_once()?);
    }
    let mut means: Vec<f64> = runs.iter().map(|r| r.mean_s).collect();
    means.sort_by(f64::total_cmp);
    let median = means[means.len() / 2];
    let first = &runs[0];
    let Some(swing_up_time) = first.swing_up_time else {
        bail!(
            "the swing-up failed: final state {:?} (the timing would be meaningless)",
            first.final_state
        );
    };
    Ok(BenchReport {
        workload: "nmpc-update".into(),
        figure: median * 1e6,
        unit: "us/update".into(),
        check: json!({
            "runs": runs.len(),
            "updates_per_run": first.updates,
            "unknowns": 75,
            "max_update_us": runs.iter().map(|r| r.max_s).fold(0.0, f64::max) * 1e6,
            "fastest_run_mean_us": means[0] * 1e6,
            "swing_up_time_s": swing_up_time,
            "max_abs_u_V": first.max_abs_u,
            "u_bound_V": 2.5,
            "final_state": first.final_state,
            "max_optimality_residual": first.max_residual,
            "final_optimality_residual": first.last_residual,
            "target_mean_us": 50.0,
            "sample_period_us": 1000.0,
        }),
    })
}
