//! `margin-n10` and `hinf-n50`: loop analysis and the H∞ norm of `pendulab_lti`.
//!
//! Both systems come from SplitMix64 streams (fixed seeds) filled row by row, the same
//! construction `tools/bench_toolbox.py` repeats in Python to time python-control on the
//! identical systems: `A₀` uniform in `[−1, 1)`, shifted to `A = A₀ − (max Re λ(A₀) + 0.1) I`
//! (every pole at `Re λ ≤ −0.1`), `B`, `C` uniform, `D = 0`.
//!
//! - `margin-n10`: `stability_margins` of the 10-state SISO loop `L = k·C(sI − A)⁻¹B` (seed
//!   10) with `k = 10/G(0)` (DC loop gain +10, so the loop crosses unit gain). Figure: microseconds per call.
//!   The check lists the crossings and their defining residuals, `||L(jω)| − 1|` at the gain
//!   crossings and `|Im L(jω)|/|L(jω)|` at the phase crossings, evaluated again with
//!   `StateSpace::evaluate` (an LU solve, not the Hessenberg path of the search).
//! - `hinf-n50`: `hinf_norm` of a 50-state system with 2 inputs and 2 outputs (seed 50) at
//!   tolerance `1e-8`. Figure: milliseconds per call. The check gives the norm, the peak
//!   frequency, `σ_max(G(jω_peak))` evaluated again and the relative gap to the upper bound.

use super::{BenchReport, Budget, Workload, time};
use anyhow::Result;
use pendulab_lti::linalg::eigenvalues;
use pendulab_lti::margins::stability_margins;
use pendulab_lti::norms::hinf_norm;
use pendulab_lti::random::SplitMix64;
use pendulab_lti::{Complex64, Continuous, Mat, StateSpace};
use serde_json::json;

/// The workloads of this module.
pub fn workloads() -> Vec<Workload> {
    vec![
        Workload {
            name: "margin-n10",
            description: "stability_margins (all crossings) of a random stable 10-state SISO loop (us/call)",
            run: run_margin,
        },
        Workload {
            name: "hinf-n50",
            description: "H-infinity norm of a random stable 50-state 2x2 system, tol 1e-8 (ms/call)",
            run: run_hinf,
        },
    ]
}

/// An `r × c` matrix of `pendulab_lti::random::SplitMix64::symmetric` draws (uniform in
/// `[−1, 1)`), filled row by row: the generator's column-by-column `c × r` matrix, transposed.
fn rows(g: &mut SplitMix64, r: usize, c: usize) -> Mat {
    g.matrix(c, r).transpose()
}

/// The random stable system of the module documentation.
fn random_stable(seed: u64, n: usize, p: usize, m: usize) -> Result<StateSpace<Continuous>> {
    let mut g = SplitMix64::new(seed);
    let a0 = rows(&mut g, n, n);
    let b = rows(&mut g, n, m);
    let c = rows(&mut g, p, n);
    let shift = eigenvalues(&a0)?
        .iter()
        .map(|l| l.re)
        .fold(f64::NEG_INFINITY, f64::max);
    let a = a0 - Mat::identity(n, n) * (shift + 0.1);
    Ok(StateSpace::continuous(a, b, c, Mat::zeros(p, m))?)
}

fn run_margin(budget: &Budget) -> Result<BenchReport> {
    let g = random_stable(10, 10, 1, 1)?;
    let k = 10.0 / g.dc_gain()?[(0, 0)];
    let l = StateSpace::continuous(g.a().clone(), g.b().clone(), g.c() * k, g.d().clone())?;
    let m = stability_margins(&l)?;
    let at = |w: f64| -> Result<Complex64> { Ok(l.evaluate(Complex64::new(0.0, w))?[(0, 0)]) };
    let mut gain_residual: f64 = 0.0;
    for c in &m.gain_crossings {
        gain_residual = gain_residual.max((at(c.frequency)?.norm() - 1.0).abs());
    }
    let mut phase_residual: f64 = 0.0;
    for c in &m.phase_crossings {
        let v = at(c.frequency)?;
        phase_residual = phase_residual.max(v.im.abs() / v.norm());
    }
    let t = time(budget, || {
        std::hint::black_box(stability_margins(std::hint::black_box(&l)).ok());
    });
    Ok(BenchReport {
        workload: "margin-n10".into(),
        figure: t.median_s * 1e6,
        unit: "us/call".into(),
        check: json!({
            "gain_crossings": m.gain_crossings.iter()
                .map(|c| json!({"w": c.frequency, "pm_deg": c.phase_margin_deg, "delay_s": c.delay_margin}))
                .collect::<Vec<_>>(),
            "phase_crossings": m.phase_crossings.iter()
                .map(|c| json!({"w": c.frequency, "gm": c.gain_margin}))
                .collect::<Vec<_>>(),
            "max_gain_residual": gain_residual,
            "max_phase_residual": phase_residual,
            "timing": t,
        }),
    })
}

fn run_hinf(budget: &Budget) -> Result<BenchReport> {
    let g = random_stable(50, 50, 2, 2)?;
    let h = hinf_norm(&g, 1e-8)?;
    let s = g
        .evaluate(Complex64::new(0.0, h.peak_frequency))?
        .svd(false, false)
        .singular_values
        .max();
    let t = time(budget, || {
        std::hint::black_box(hinf_norm(std::hint::black_box(&g), 1e-8).ok());
    });
    Ok(BenchReport {
        workload: "hinf-n50".into(),
        figure: t.median_s * 1e3,
        unit: "ms/call".into(),
        check: json!({
            "norm": h.value,
            "peak_frequency": h.peak_frequency,
            "sigma_max_at_peak": s,
            "relative_gap_to_upper_bound": (h.upper_bound - h.value) / h.value,
            "iterations": h.iterations,
            "timing": t,
        }),
    })
}
