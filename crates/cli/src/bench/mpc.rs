//! `mpc-qp`: one warm-started QP of the cart pendulum's constrained linear MPC.
//!
//! The controller is `kind = "mpc"` with its defaults (horizon 20 steps of 10 ms, `Q =
//! diag(100, 100, 0, 0)`, `R = 0.01`, `|u| ≤ 5 V`) and a track limit `|z| ≤ 0.08 m`: 20
//! unknowns, 80 inequality rows. Each timed run is the closed loop on the nonlinear cart from
//! 10° for 5 s in `pendulab-sim`'s sampled-data loop (5001 updates at 1 kHz, the plant stepped
//! by RK4), the voltage limit active for the first ~0.1 s and the track limit near it; every
//! controller update (forming the QP's vectors, the dual active-set solve warm-started from the
//! shifted active set, the first move) is timed on its own. Figure: the median time per update
//! over all runs \[µs\]; the check holds the 99th percentile and the worst update (a preempted
//! update counts whole), the same QPs solved cold by the same method and by Clarabel
//! (`pendulab_lmi::solve_qp`, tolerance 1e-10, setup included; every 10th QP of the first
//! run), the largest distance between the plans, and the closed loop's outcome.

use super::{BenchReport, Budget};
use anyhow::{Result, bail};
use pendulab_control::inspect::{Inspected, Update};
use pendulab_control::mpc::{LinearMpc, MpcController, QpStatus, WarmStart};
use pendulab_control::spec::MpcSpec;
use pendulab_lti::Mat;
use pendulab_plants::{CartEquilibrium, CartPendulum};
use pendulab_sim::{SampledLoop, SampledOptions};
use serde_json::json;
use std::time::Instant;

const TS: f64 = 1e-3;
const T_FINAL: f64 = 5.0;
const TRACK: f64 = 0.08;
const CLARABEL_EVERY: usize = 10;

/// A kept QP: `g`, `w`, the warm-started plan, the measurement.
type Kept = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);

/// What the timed runs keep: each update's time, and every `CLARABEL_EVERY`-th QP's data
/// if `keep`.
struct Timing {
    seconds: Vec<f64>,
    kept: Vec<Kept>,
    keep: bool,
}

/// The inspector of the timed MPC (`pendulab_control::inspect`).
fn time_update(s: &mut Timing, c: &MpcController, up: &Update<'_>) {
    s.seconds.push(up.seconds);
    if s.keep && s.seconds.len() % CLARABEL_EVERY == 1 {
        let mpc = c.mpc();
        let (g, w) = mpc.last_qp_vectors();
        s.kept
            .push((g.to_vec(), w.to_vec(), mpc.plan().to_vec(), up.y.to_vec()));
    }
}

fn spec() -> MpcSpec {
    MpcSpec {
        travel_limit: Some(TRACK),
        ..Default::default()
    }
}

fn build() -> Result<(LinearMpc, MpcController, f64)> {
    let (settings, periods) = spec().settings(TS)?;
    let lin = CartPendulum::book().linearize(CartEquilibrium::upright())?;
    let mpc = LinearMpc::sampled(&lin, periods as f64 * TS, &settings)?;
    let u_max = settings.u_max[0];
    let ctrl = MpcController::new(
        mpc.clone(),
        TS,
        periods,
        &[0.0; 4],
        &settings.u_min,
        &settings.u_max,
    )?;
    Ok((mpc, ctrl, u_max))
}

struct Run {
    seconds: Vec<f64>,
    kept: Vec<Kept>,
    mean_iterations: f64,
    max_iterations: usize,
    fallbacks: u64,
    max_abs_u: f64,
    max_abs_z: f64,
    final_state: Vec<f64>,
}

fn run_once(keep: bool) -> Result<Run> {
    let (_, ctrl, _) = build()?;
    let x0 = [0.0, 10f64.to_radians(), 0.0, 0.0];
    let mut l = SampledLoop::new(
        CartPendulum::book(),
        Inspected::new(
            ctrl,
            Timing {
                seconds: Vec::with_capacity(5001),
                kept: Vec::new(),
                keep,
            },
            time_update,
        ),
        SampledOptions {
            t_final: T_FINAL,
            ..Default::default()
        },
    )?;
    let r = l.run(&x0)?;
    let x = r.trajectory.x();
    let max_abs_z = (0..x.nrows()).map(|k| x[(k, 0)].abs()).fold(0.0, f64::max);
    let max_abs_u = r.commands.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let c = l.controller();
    let s = *c.inner.statistics();
    Ok(Run {
        seconds: c.state.seconds.clone(),
        kept: c.state.kept.clone(),
        mean_iterations: s.total_iterations as f64 / s.solves.max(1) as f64,
        max_iterations: s.max_iterations,
        fallbacks: s.infeasible + s.max_iterations_hit,
        max_abs_u,
        max_abs_z,
        final_state: r.diagnostics.final_state,
    })
}

fn quantile(sorted: &[f64], p: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

/// Runs the workload.
pub fn run(budget: &Budget) -> Result<BenchReport> {
    let start = Instant::now();
    let mut runs = vec![run_once(true)?];
    while start.elapsed() < budget.min_time || runs.len() < 3 {
        runs.push(run_once(false)?);
    }
    let first = &runs[0];
    if first.fallbacks > 0 || first.final_state.iter().any(|v| v.abs() > 1e-3) {
        bail!(
            "the MPC did not balance cleanly ({} fallbacks, final state {:?}): the timing would be meaningless",
            first.fallbacks,
            first.final_state
        );
    }
    let mut all: Vec<f64> = runs
        .iter()
        .flat_map(|r| r.seconds.iter().copied())
        .collect();
    all.sort_by(f64::total_cmp);
    let median = quantile(&all, 0.5);
    // The kept QPs again: cold by the same method, and by Clarabel.
    let (mut cold, _, _) = build()?;
    let (h, a): (Mat, Mat) = (cold.hessian().clone(), cold.constraint_matrix().clone());
    let mut cold_s = Vec::new();
    let mut clarabel_s = Vec::new();
    let mut clarabel_iterations = 0u64;
    let mut max_diff = 0.0f64;
    let mut active_max = 0usize;
    for (g, w, plan, y) in &first.kept {
        // The cold solve needs x₀ and u₋₁ only through g and w, which it recomputes from y;
        // u₋₁ enters only rate rows, which this case has none of.
        let t = Instant::now();
        let status = cold.solve(y, &[0.0], WarmStart::Cold)?;
        cold_s.push(t.elapsed().as_secs_f64());
        if status != QpStatus::Solved {
            bail!("a cold solve ended {status:?}");
        }
        active_max = active_max.max(cold.qp().active_set().len());
        let d = cold
            .plan()
            .iter()
            .zip(plan)
            .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
        if d > 1e-9 {
            bail!("cold and warm plans differ by {d:e}");
        }
        let t = Instant::now();
        let ans = pendulab_lmi::solve_qp(&h, g, &a, w, 1e-10)?;
        clarabel_s.push(t.elapsed().as_secs_f64());
        if !ans.solved {
            bail!("Clarabel: {}", ans.status);
        }
        clarabel_iterations += u64::from(ans.iterations);
        max_diff = ans
            .x
            .iter()
            .zip(plan)
            .fold(max_diff, |m, (p, q)| m.max((p - q).abs()));
    }
    cold_s.sort_by(f64::total_cmp);
    clarabel_s.sort_by(f64::total_cmp);
    let us = |s: f64| s * 1e6;
    Ok(BenchReport {
        workload: "mpc-qp".into(),
        figure: us(median),
        unit: "us/solve".into(),
        check: json!({
            "runs": runs.len(),
            "solves": all.len(),
            "unknowns": h.nrows(),
            "constraint_rows": a.nrows(),
            "p99_us": us(quantile(&all, 0.99)),
            "max_us": us(*all.last().unwrap_or(&0.0)),
            "mean_active_set_iterations": first.mean_iterations,
            "max_active_set_iterations": first.max_iterations,
            "largest_active_set": active_max,
            "cold_median_us": us(quantile(&cold_s, 0.5)),
            "cold_p99_us": us(quantile(&cold_s, 0.99)),
            "clarabel_qps": clarabel_s.len(),
            "clarabel_median_us": us(quantile(&clarabel_s, 0.5)),
            "clarabel_p99_us": us(quantile(&clarabel_s, 0.99)),
            "clarabel_mean_iterations": clarabel_iterations as f64 / clarabel_s.len().max(1) as f64,
            "max_plan_distance_to_clarabel": max_diff,
            "max_abs_u_V": first.max_abs_u,
            "max_abs_z_m": first.max_abs_z,
            "track_limit_m": TRACK,
            "final_state": first.final_state,
            "target_median_us": 200.0,
            "sample_period_us": 1000.0,
        }),
    })
}
