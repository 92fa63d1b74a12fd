//! The conic problems the two benchmark designs hand Clarabel (p2c122_ex4 LMI LQ servo,
//! p2c15_ex7 gain-scheduled SOS servo), captured with `capture_conic_problems`.
//!
//! `captured_problem_is_the_problem_solved` re-solves the captured data with Clarabel
//! directly: the export is complete exactly when that solve retraces the original (same
//! iterations, same objective). The ignored test writes the data as JSON for
//! `tools/reference/lmi_clarabel_python.py`, which solves the identical problems with the
//! Python build of Clarabel:
//!
//! ```text
//! PENDULAB_CONIC_DIR=$PWD/target/conic cargo test --release -p pendulab-lmi \
//!     --test conic_export -- --ignored
//! ```

mod common;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettingsBuilder, DefaultSolver, IPSolver, SupportedConeT};
use pendulab_lmi::synthesis::gain_scheduled_lq;
use pendulab_lmi::synthesis::lq_state_feedback;
use pendulab_lmi::{Backend, ConicProblem, SolveOptions, capture_conic_problems};

/// Clarabel for every solve (under `Backend::Auto` the small servo LMI is solved by the
/// dense method, which records nothing).
fn clarabel() -> SolveOptions {
    SolveOptions {
        backend: Backend::Clarabel,
        ..SolveOptions::default()
    }
}
use serde_json::json;

fn servo_problems() -> Vec<ConicProblem> {
    let (a, b) = common::arm(common::A1, common::B1, 0.0);
    let (at, bt) = common::augment(&a, &b);
    let (q, r) = common::servo_weights();
    let (d, got) = capture_conic_problems(|| lq_state_feedback(&at, &bt, &q, &r, &clarabel()));
    assert!(d.unwrap().solution.all_checks_pass());
    got
}

fn gain_schedule_problems() -> Vec<ConicProblem> {
    let (spec, plant) = common::book_gain_schedule();
    let (gs, got) = capture_conic_problems(|| gain_scheduled_lq(&plant, &spec, &clarabel()));
    assert!(gs.unwrap().schedule.is_some());
    got
}

/// Solves `c` with Clarabel from the captured data alone: (status, iterations, obj_val).
fn resolve(c: &ConicProblem) -> (String, u32, f64) {
    let a = CscMatrix::new(
        c.m,
        c.n,
        c.a_colptr.clone(),
        c.a_rowval.clone(),
        c.a_nzval.clone(),
    );
    let p = CscMatrix::<f64>::zeros((c.n, c.n));
    let cones: Vec<SupportedConeT<f64>> = c
        .cones
        .iter()
        .map(|&(kind, d)| match kind {
            "zero" => SupportedConeT::ZeroConeT(d),
            "nonneg" => SupportedConeT::NonnegativeConeT(d),
            "psd_triangle" => SupportedConeT::PSDTriangleConeT(d),
            other => panic!("unexpected cone {other}"),
        })
        .collect();
    let mut s = DefaultSettingsBuilder::default();
    s.verbose(false);
    s.chordal_decomposition_merge_method(c.merge_method.to_string());
    for &(name, v) in &c.settings {
        match name {
            "max_iter" => s.max_iter(v as u32),
            "tol_gap_abs" => s.tol_gap_abs(v),
            "tol_gap_rel" => s.tol_gap_rel(v),
            "tol_feas" => s.tol_feas(v),
            "tol_infeas_abs" => s.tol_infeas_abs(v),
            "tol_infeas_rel" => s.tol_infeas_rel(v),
            "chordal_decomposition_enable" => s.chordal_decomposition_enable(v != 0.0),
            "time_limit" => s.time_limit(v),
            "iterative_refinement_enable" => s.iterative_refinement_enable(v != 0.0),
            "iterative_refinement_max_iter" => s.iterative_refinement_max_iter(v as u32),
            other => panic!("unexpected setting {other}"),
        };
    }
    let mut solver = DefaultSolver::new(&p, &c.q, &a, &c.b, &cones, s.build().unwrap()).unwrap();
    solver.solve();
    let sol = &solver.solution;
    (format!("{:?}", sol.status), sol.iterations, sol.obj_val)
}

#[test]
fn captured_problem_is_the_problem_solved() {
    let got = servo_problems();
    // lq_state_feedback makes one solve (its refinement re-solve runs only when inaccurate).
    assert_eq!(got.len(), 1, "one Clarabel solve");
    let c = &got[0];
    assert_eq!(c.b.len(), c.m);
    assert_eq!(c.q.len(), c.n);
    assert_eq!(c.a_colptr.len(), c.n + 1);
    let rows: usize = c
        .cones
        .iter()
        .map(|&(k, d)| {
            if k == "psd_triangle" {
                d * (d + 1) / 2
            } else {
                d
            }
        })
        .sum();
    assert_eq!(rows, c.m, "cones cover every row of A");
    let (status, iterations, obj) = resolve(c);
    assert_eq!(status, c.status);
    // The same data and settings through the same deterministic code path retrace the
    // same iterates: equal iteration count, objective equal to rounding (1e-12 relative).
    assert_eq!(iterations, c.iterations);
    assert!(
        (obj - c.obj_val).abs() <= 1e-12 * c.obj_val.abs().max(1.0),
        "{obj} vs {}",
        c.obj_val
    );
}

fn to_json(c: &ConicProblem) -> serde_json::Value {
    json!({
        "m": c.m,
        "n": c.n,
        "A": {"colptr": c.a_colptr, "rowval": c.a_rowval, "nzval": c.a_nzval},
        "b": c.b,
        "q": c.q,
        "cones": c.cones.iter().map(|&(k, d)| json!([k, d])).collect::<Vec<_>>(),
        "settings": c.settings.iter().map(|&(k, v)| (k.to_string(), json!(v))).collect::<serde_json::Map<_, _>>(),
        "merge_method": c.merge_method,
        "rust": {
            "status": c.status,
            "iterations": c.iterations,
            "solve_time": c.solve_time,
            "obj_val": c.obj_val,
            "r_prim": c.r_prim,
            "r_dual": c.r_dual,
        },
    })
}

#[test]
#[ignore = "writes the benchmark problems as JSON (set PENDULAB_CONIC_DIR)"]
fn export_benchmark_problems() {
    let dir = std::env::var("PENDULAB_CONIC_DIR")
        .unwrap_or_else(|_| env!("CARGO_TARGET_TMPDIR").to_string());
    std::fs::create_dir_all(&dir).unwrap();
    for (name, problems) in [
        ("lmi_servo", servo_problems()),
        ("sos_gain_schedule", gain_schedule_problems()),
    ] {
        let v = json!({
            "workload": name,
            "clarabel_rust": "0.11.1",
            "solves": problems.iter().map(to_json).collect::<Vec<_>>(),
        });
        let path = std::path::Path::new(&dir).join(format!("{name}.json"));
        std::fs::write(&path, serde_json::to_string(&v).unwrap()).unwrap();
        println!("wrote {}", path.display());
    }
}
