//! LMI / SOS workloads: the book's LMI LQ servo (`lmi-servo`) and the gain-scheduled servo
//! SOS program (`sos-gain-schedule`), each timed build + solve; SDPs with a planted optimum
//! (`lmi-planted`), solved by both interior-point methods.

use super::{BenchReport, Budget, Timing, Workload, time};
use anyhow::{Result, bail};
use pendulab_lmi::synthesis::{
    GainScheduleSpec, LpvPlant, LqWeights, gain_scheduled_lq, lq_state_feedback,
};
use pendulab_lmi::{Backend, SolveOptions};
use pendulab_lti::{Mat, Vector};
use serde_json::json;

/// The workloads of this file.
pub fn workloads() -> Vec<Workload> {
    vec![
        Workload {
            name: "lmi-servo",
            description: "p2c122_ex4 LMI LQ servo (arm pendulum, 5 states): build + solve",
            run: lmi_servo,
        },
        Workload {
            name: "lmi-planted",
            description: "SDPs with a planted optimum, side 5–30, 4–100 variables: dense method vs Clarabel (ms/solve)",
            run: lmi_planted,
        },
        Workload {
            name: "sos-gain-schedule",
            description: "p2c15_ex7 gain-scheduled servo SOS program: build + γ minimisation + re-solve",
            run: sos_gain_schedule,
        },
    ]
}

/// The book's arm-type pendulum (`pendulab_plants::ArmPendulum::book`, table 3.7) in its LPV
/// form `ρ = 1 − cos θ1` (`docs/model.md` §2), augmented with ∫(r − θ1) (book eq. 6.40);
/// returns (Ã0, Ã1, B̃0, B̃1).
fn arm_servo() -> (Mat, Mat, Mat, Mat) {
    let lpv = pendulab_plants::ArmPendulum::book().lpv();
    let augment = |a: &Mat, integrate: bool| {
        let mut t = Mat::zeros(5, 5);
        t.view_mut((0, 0), (4, 4)).copy_from(a);
        if integrate {
            t[(4, 0)] = -1.0;
        }
        t
    };
    let pad = |b: &Mat| b.clone().insert_row(4, 0.0);
    (
        augment(&lpv.a0, true),
        augment(&lpv.a1, false),
        pad(&lpv.b0),
        pad(&lpv.b1),
    )
}

/// On-CPU time of this process so far (all its threads), in seconds: the sum of the first
/// field (nanoseconds run) of `/proc/self/task/*/schedstat`. `None` where that is unavailable
/// (not Linux, or schedstats disabled). On a shared, overloaded machine the wall-clock figure
/// includes the time spent waiting for a core; this one does not.
fn process_cpu_seconds() -> Option<f64> {
    let mut ns: u64 = 0;
    for task in std::fs::read_dir("/proc/self/task").ok()? {
        let path = task.ok()?.path().join("schedstat");
        let text = std::fs::read_to_string(path).ok()?;
        ns += text.split_whitespace().next()?.parse::<u64>().ok()?;
    }
    Some(ns as f64 * 1e-9)
}

/// [`time`] plus the process CPU time per call over the same calls (see
/// [`process_cpu_seconds`]; it includes the warm-up call).
fn time_with_cpu<F: FnMut()>(budget: &Budget, f: F) -> (Timing, Option<f64>) {
    let c0 = process_cpu_seconds();
    let timing = time(budget, f);
    let c1 = process_cpu_seconds();
    let cpu = c0
        .zip(c1)
        .map(|(a, b)| (b - a) / (timing.iterations + 1) as f64);
    (timing, cpu)
}

fn weights() -> (Mat, Mat) {
    (
        Mat::from_diagonal(&Vector::from_vec(vec![0.1, 1.0, 0.001, 0.001, 4.0])),
        Mat::from_element(1, 1, 1.0),
    )
}

fn lmi_servo(budget: &Budget) -> Result<BenchReport> {
    let (a, _, b, _) = arm_servo();
    let (q, r) = weights();
    let opts = SolveOptions::default();
    let design = lq_state_feedback(&a, &b, &q, &r, &opts)?;
    let Some(fb) = design.feedback.clone() else {
        bail!("the LMI LQ design did not solve: {:?}", design.status);
    };
    let (timing, cpu) = time_with_cpu(budget, || {
        let d = lq_state_feedback(&a, &b, &q, &r, &opts).expect("valid data");
        std::hint::black_box(d);
    });
    // The same design with Clarabel, timed right after in the same run (the ratio is the
    // figure to compare on a noisy machine), and how far its gain is from the headline's.
    let clarabel_opts = SolveOptions {
        backend: Backend::Clarabel,
        ..SolveOptions::default()
    };
    let clarabel = lq_state_feedback(&a, &b, &q, &r, &clarabel_opts)?;
    let Some(clarabel_fb) = clarabel.feedback.clone() else {
        bail!(
            "the LMI LQ design did not solve with Clarabel: {:?}",
            clarabel.status
        );
    };
    let t_clarabel = time(budget, || {
        let d = lq_state_feedback(&a, &b, &q, &r, &clarabel_opts).expect("valid data");
        std::hint::black_box(d);
    });
    let gain_difference = (&fb.gain - &clarabel_fb.gain).norm() / clarabel_fb.gain.norm();
    Ok(BenchReport {
        workload: "lmi-servo".into(),
        figure: timing.median_s * 1e3,
        unit: "ms/design".into(),
        check: json!({
            "timed": "lq_state_feedback with the default SolveOptions (Backend::Auto): build the LMI problem, one interior-point solve, recheck of every constraint, gain K = −L X⁻¹ and closed-loop poles",
            "backend": format!("{:?}", design.solution.backend),
            "clarabel_ms_per_design": t_clarabel.median_s * 1e3,
            "clarabel_iterations": clarabel.solution.iterations,
            "clarabel_over_headline": t_clarabel.median_s / timing.median_s,
            "gain_relative_difference_to_clarabel": gain_difference,
            "status": format!("{:?}", design.status),
            "all_checks_pass": design.solution.all_checks_pass(),
            "gain_u_eq_minus_Kx": fb.gain.iter().copied().collect::<Vec<f64>>(),
            "trace_X": fb.x.trace(),
            "iterations": design.solution.iterations,
            "solver_ms": design.solution.solver_seconds * 1e3,
            "setup_ms": design.solution.setup_seconds * 1e3,
            "same_problem_in_python_clarabel": "tools/reference/lmi_clarabel_python.py (data exported by crates/lmi/tests/conic_export.rs)",
            "closed_loop_max_real_pole": fb.closed_loop_poles[0].iter().map(|z| z.re).fold(f64::NEG_INFINITY, f64::max),
            "process_cpu_ms_per_design": cpu.map(|c| c * 1e3),
            "timing": timing,
        }),
    })
}

/// Planted SDPs (`pendulab_lmi::planted::planted_sdp`: dense coefficient matrices, optimum
/// known by construction) of growing size, each solved by the dense method and by Clarabel,
/// timed one after the other in the same run. Figure: the dense method's time per solve on
/// the largest shape.
fn lmi_planted(budget: &Budget) -> Result<BenchReport> {
    // (seed, side, variables, rank, blocks)
    let shapes = [
        (1, 5, 4, 2, 1),
        (2, 11, 20, 4, 1),
        (3, 20, 60, 8, 2),
        (4, 30, 100, 10, 1),
    ];
    let mut rows = Vec::new();
    let mut headline = 0.0;
    for (seed, side, variables, rank, blocks) in shapes {
        let planted = pendulab_lmi::planted::planted_sdp(seed, side, variables, rank, blocks)?;
        let mut row = serde_json::Map::new();
        row.insert("side".into(), json!(side));
        row.insert("variables".into(), json!(variables));
        row.insert("blocks".into(), json!(blocks));
        let mut ms = [0.0; 2];
        for (k, backend) in [Backend::Dense, Backend::Clarabel].into_iter().enumerate() {
            let opts = SolveOptions {
                backend,
                ..SolveOptions::default()
            };
            let sol = planted.problem.solve(&opts)?;
            let Some(objective) = sol.objective else {
                bail!(
                    "{backend:?} did not solve the planted SDP: {:?}",
                    sol.status
                );
            };
            let t = time(budget, || {
                std::hint::black_box(planted.problem.solve(&opts).expect("valid problem"));
            });
            ms[k] = t.median_s * 1e3;
            let name = format!("{backend:?}").to_lowercase();
            row.insert(
                name,
                json!({
                    "ms_per_solve": ms[k],
                    "iterations": sol.iterations,
                    "relative_error_to_planted_optimum": (objective - planted.optimum).abs() / planted.optimum.abs().max(1.0),
                    "all_checks_pass": sol.all_checks_pass(),
                }),
            );
        }
        row.insert("clarabel_over_dense".into(), json!(ms[1] / ms[0]));
        headline = ms[0];
        rows.push(serde_json::Value::Object(row));
    }
    Ok(BenchReport {
        workload: "lmi-planted".into(),
        figure: headline,
        unit: "ms/solve".into(),
        check: json!({
            "figure_measures": "Backend::Dense on one 30 × 30 LMI with 100 variables (the last shape)",
            "shapes": rows,
        }),
    })
}

fn sos_gain_schedule(budget: &Budget) -> Result<BenchReport> {
    let (a0, a1, b0, b1) = arm_servo();
    let (q, r) = weights();
    let rho_bar = 1.0 - 65f64.to_radians().cos();
    let spec = GainScheduleSpec {
        rho_range: (0.0, rho_bar),
        rho0_range: (0.0, rho_bar),
        rho_dot_bound: 0.75,
        lq: LqWeights { q, r },
        margin: 1e-6,
        gamma_relax: 0.06,
        balance: true,
    };
    let plant = LpvPlant { a0, a1, b0, b1 };
    let opts = SolveOptions::default();
    let gs = gain_scheduled_lq(&plant, &spec, &opts)?;
    let Some(schedule) = gs.schedule.clone() else {
        bail!("the gain-scheduling design did not solve: {:?}", gs.status);
    };
    let opt = &gs.optimization;
    let refined = gs.refined.as_ref();
    let solver_s = opt.solver_seconds + refined.map_or(0.0, |s| s.solver_seconds);
    let (timing, cpu) = time_with_cpu(budget, || {
        let d = gain_scheduled_lq(&plant, &spec, &opts).expect("valid data");
        std::hint::black_box(d);
    });
    Ok(BenchReport {
        workload: "sos-gain-schedule".into(),
        figure: timing.median_s * 1e3,
        unit: "ms/design".into(),
        check: json!({
            "timed": "gain_scheduled_lq: build the SOS program (coefficient matching, Gram blocks), Clarabel γ minimisation, re-solve as a feasibility problem at γ ≤ 1.06 γ*, rechecks of every constraint and SOS residual, schedule extraction",
            "gamma_star": gs.gamma_star,
            "gamma_star_reference_256bit": 222.0,
            "gamma_of_design": schedule.gamma,
            "status": format!("{:?}", gs.status),
            "all_checks_pass": refined.is_some_and(|s| s.all_checks_pass()),
            "sos_relative_residual_max": refined.map(|s| s.sos_checks.iter().map(|c| c.relative_residual).fold(0.0, f64::max)),
            "K_at_rho_max": schedule.gain(rho_bar)?.iter().copied().collect::<Vec<f64>>(),
            "K_at_0": schedule.gain(0.0)?.iter().copied().collect::<Vec<f64>>(),
            "iterations": [opt.iterations, refined.map_or(0, |s| s.iterations)],
            "clarabel_solve_ms_total": solver_s * 1e3,
            "clarabel_solve_ms_per_solve": [opt.solver_seconds * 1e3, refined.map_or(0.0, |s| s.solver_seconds * 1e3)],
            "process_cpu_ms_per_design": cpu.map(|c| c * 1e3),
            "setup_ms_total": (opt.setup_seconds + refined.map_or(0.0, |s| s.setup_seconds)) * 1e3,
            "total_over_solver_time": timing.median_s / solver_s,
            "refinement_steps": opts.refinement_steps,
            "kkt_factorisation": opts.kkt_solver.method(opt.dims.kkt_dimension()),
            "same_problem_in_python_clarabel": "tools/reference/lmi_clarabel_python.py (data exported by crates/lmi/tests/conic_export.rs)",
            "dims": {
                "variables": opt.dims.variables,
                "equalities": opt.dims.equalities,
                "psd_sizes": opt.dims.psd_sizes,
                "nonzeros": opt.dims.nonzeros,
            },
            "timing": timing,
        }),
    })
}
