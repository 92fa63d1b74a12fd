//! `care-n4` and `care-n100`: the continuous algebraic Riccati equation.
//!
//! - `care-n4`: the linearised cart pendulum of the book (table 3.5, `docs/model.md` §1),
//!   `Q = diag(100, 10, 1, 1)`, `R = 1`. Figure: microseconds per `care` call (default
//!   options: method choice, scaling, refinement, gain, closed-loop poles and residual
//!   included). For this size `care` takes its fixed-size doubling path (`method` in the
//!   check reports `Doubling`; the general ordered-Schur path reports `Schur`).
//! - `care-n100`: a random stabilisable system of order 100 with 10 inputs from a fixed seed
//!   (entries of `A` uniform in `[−1, 1)·3/√n`, so about half of the eigenvalues are unstable;
//!   `B` uniform in `[−1, 1)`; `Q = CᵀC/n + 0.1 I` with `C` random `n × n`; `R = I`). Figure:
//!   milliseconds per `care` call with default options. `Auto` first tries the bounded
//!   doubling method with strict acceptance (relative residual ≤ `100·n·ε`), which these
//!   data pass (`method` reports `Doubling`); the check also reports the ordered-Schur path
//!   (`RiccatiMethod::Schur`), timed in the same run, alternating with the default call.
//!
//! The `check` field recomputes the relative residual of the returned solution independently
//! of the solver (`care_residual`), the largest real part of the closed-loop poles (computed
//! again from `A − BK`) and, for `care-n4`, the closed-form first gain entry: `A e₁ = 0`
//! (the cart position does not enter the dynamics), so `e₁ᵀ(AᵀX + XA − XBR⁻¹BᵀX + Q)e₁ = 0`
//! gives `K₁² = q₁₁ = 100`.

use super::{BenchReport, Budget, time};
use anyhow::{Result, ensure};
use pendulab_lti::Mat;
use pendulab_lti::equations::riccati::care_residual;
use pendulab_lti::equations::{RiccatiMethod, RiccatiOptions, RiccatiSolution, care};
use pendulab_lti::linalg::eigenvalues;
use pendulab_lti::random::SplitMix64;
use serde_json::json;

/// The linearised cart pendulum (`docs/model.md` §1, book table 3.5 parameters).
fn cart_pendulum() -> (Mat, Mat) {
    let (ac, bc, mp, lp, jp, mup, g) = (6.25, 4.36, 0.107, 0.230, 1.59e-3, 2.35e-4, 9.81);
    let j = jp + mp * lp * lp;
    #[rustfmt::skip]
    let a = Mat::from_row_slice(4, 4, &[
        0.0, 0.0, 1.0, 0.0,
        0.0, 0.0, 0.0, 1.0,
        0.0, 0.0, -ac, 0.0,
        0.0, mp * g * lp / j, ac * mp * lp / j, -mup / j,
    ]);
    let b = Mat::from_row_slice(4, 1, &[0.0, 0.0, bc, -bc * mp * lp / j]);
    (a, b)
}

/// The `care-n100` data (see the module documentation).
pub fn random_problem(n: usize, m: usize, seed: u64) -> (Mat, Mat, Mat, Mat) {
    let mut g = SplitMix64::new(seed);
    let a = g.matrix(n, n) * (3.0 / (n as f64).sqrt());
    let b = g.matrix(n, m);
    let c = g.matrix(n, n);
    let q = c.transpose() * &c * (1.0 / n as f64) + Mat::identity(n, n) * 0.1;
    let q = (&q + q.transpose()) * 0.5;
    (a, b, q, Mat::identity(m, m))
}

/// Pools timing rounds: median of the round medians, fastest round's minimum, total calls.
fn merge(runs: &[super::Timing]) -> super::Timing {
    let mut medians: Vec<f64> = runs.iter().map(|t| t.median_s).collect();
    medians.sort_by(f64::total_cmp);
    super::Timing {
        iterations: runs.iter().map(|t| t.iterations).sum(),
        median_s: medians.get(medians.len() / 2).copied().unwrap_or(f64::NAN),
        min_s: runs.iter().map(|t| t.min_s).fold(f64::INFINITY, f64::min),
    }
}

/// Independent accuracy evidence for a solution.
fn evidence(a: &Mat, b: &Mat, q: &Mat, r: &Mat, sol: &RiccatiSolution) -> Result<(f64, f64)> {
    let residual = care_residual(a, b, q, r, None, &sol.x);
    let acl = a - b * &sol.gain;
    let poles = eigenvalues(&acl)?;
    let max_re = poles.iter().map(|p| p.re).fold(f64::NEG_INFINITY, f64::max);
    Ok((residual, max_re))
}

/// Runs `care-n4`.
pub fn run_n4(budget: &Budget) -> Result<BenchReport> {
    let (a, b) = cart_pendulum();
    let q = Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(&[
        100.0, 10.0, 1.0, 1.0,
    ]));
    let r = Mat::identity(1, 1);
    let opts = RiccatiOptions::default();
    let mut last = None;
    let timing = time(budget, || {
        last = Some(care(&a, &b, &q, &r, None, &opts).expect("care-n4 solves"));
    });
    let sol = last.expect("ran at least once");
    let (residual, max_re) = evidence(&a, &b, &q, &r, &sol)?;
    ensure!(max_re < 0.0, "closed loop not stable: max Re = {max_re}");
    Ok(BenchReport {
        workload: "care-n4".into(),
        figure: timing.median_s * 1e6,
        unit: "us/solve".into(),
        check: json!({
            "n": 4,
            "m": 1,
            "system": "linearised cart pendulum (book table 3.5), Q = diag(100, 10, 1, 1), R = 1",
            "relative_residual": residual,
            "solver_reported_residual": sol.residual,
            "closed_loop_max_real_part": max_re,
            "closed_loop_stable": max_re < 0.0,
            "gain": sol.gain.iter().copied().collect::<Vec<_>>(),
            "gain_1_abs_minus_sqrt_q11": (sol.gain[(0, 0)].abs() - 10.0).abs(),
            "method": format!("{:?}", sol.method),
            "refinement_steps": sol.refinement_steps,
            "median_s_per_call": timing.median_s,
            "min_s_per_call": timing.min_s,
            "calls": timing.iterations,
            "peers_us": {"python-control 0.10.2 (SLICOT)": 157.0, "SciPy 1.17": 1042.0},
        }),
    })
}

/// Runs `care-n100`.
pub fn run_n100(budget: &Budget) -> Result<BenchReport> {
    let (n, m, seed) = (100, 10, 2024);
    let (a, b, q, r) = random_problem(n, m, seed);
    let opts = RiccatiOptions::default();
    let schur_opts = RiccatiOptions {
        method: RiccatiMethod::Schur,
        ..RiccatiOptions::default()
    };
    // Alternate the default call and the Schur path in short rounds so that both see the same
    // load of the (shared) machine.
    let half = Budget {
        min_time: budget.min_time / 10,
    };
    let mut last = None;
    let mut last_schur = None;
    let (mut runs, mut runs_schur) = (Vec::new(), Vec::new());
    for _ in 0..5 {
        runs.push(time(&half, || {
            last = Some(care(&a, &b, &q, &r, None, &opts).expect("care-n100 solves"));
        }));
        runs_schur.push(time(&half, || {
            last_schur =
                Some(care(&a, &b, &q, &r, None, &schur_opts).expect("care-n100 solves (Schur)"));
        }));
    }
    let timing = merge(&runs);
    let timing_schur = merge(&runs_schur);
    let sol = last.expect("ran at least once");
    let sol_schur = last_schur.expect("ran at least once");
    let residual_schur = care_residual(&a, &b, &q, &r, None, &sol_schur.x);
    // Two independent algorithms: agreement relative to ‖X‖.
    let x_difference = (&sol.x - &sol_schur.x).norm() / sol_schur.x.norm();
    let (residual, max_re) = evidence(&a, &b, &q, &r, &sol)?;
    let open_unstable = eigenvalues(&a)?.iter().filter(|p| p.re >= 0.0).count();
    ensure!(max_re < 0.0, "closed loop not stable: max Re = {max_re}");
    Ok(BenchReport {
        workload: "care-n100".into(),
        figure: timing.median_s * 1e3,
        unit: "ms/solve".into(),
        check: json!({
            "n": n,
            "m": m,
            "seed": seed,
            "open_loop_unstable_poles": open_unstable,
            "relative_residual": residual,
            "residual_target": 1e-10,
            "residual_ok": residual <= 1e-10,
            "solver_reported_residual": sol.residual,
            "closed_loop_max_real_part": max_re,
            "closed_loop_stable": max_re < 0.0,
            "method": format!("{:?}", sol.method),
            "refinement_steps": sol.refinement_steps,
            "median_s_per_call": timing.median_s,
            "min_s_per_call": timing.min_s,
            "calls": timing.iterations,
            "schur_path": {
                "median_s_per_call": timing_schur.median_s,
                "min_s_per_call": timing_schur.min_s,
                "calls": timing_schur.iterations,
                "relative_residual": residual_schur,
                "x_relative_difference_to_default": x_difference,
            },
            "peers_ms": {"python-control 0.10.2 (SLICOT)": 37.5, "SciPy 1.17": 86.0},
        }),
    })
}
