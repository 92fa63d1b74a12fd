//! Part 2 ch. 1 examples against independent references: closed forms, eigenvalues of
//! closed loops rebuilt here from the model formulas, SciPy's Riccati gain and CVXPY +
//! Clarabel (the committed fixture of pendulab-lmi, `tools/reference/lmi_reference.py`), and
//! the book's printed values.

mod common;
use common::*;

use pendulab_book::{ExampleOutput, Value};
use std::path::PathBuf;
use std::sync::OnceLock;

fn fixture() -> serde_json::Value {
    serde_json::from_str(include_str!("../../lmi/tests/fixtures/lmi_reference.json")).unwrap()
}

/// The Riccati servo gain of SciPy (library sign u = −Kx) in the book's sign.
fn k_lq_book() -> Vec<f64> {
    fixture()["p2c122_lq"]["K_riccati"][0]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| -v.as_f64().unwrap())
        .collect()
}

type M = nalgebra::DMatrix<f64>;

/// The arm pendulum (book table 3.7) linearised at θ1 = 0 with drive (a1, b1),
/// optionally with the LPV term ρ, augmented with ∫(r − θ1): written out from the formulas.
fn arm_servo(a1: f64, b1: f64, rho: f64) -> (M, M) {
    let (l1, m2, lc2, j2, mu2, g) = (0.227, 0.096, 0.195, 9.06e-4, 1.01e-4, 9.81);
    let al2 = j2 + m2 * lc2 * lc2;
    let al3 = m2 * l1 * lc2;
    let al5 = m2 * lc2 * g;
    let c = 1.0 - rho; // cos θ1
    let mut a = M::zeros(5, 5);
    a[(0, 2)] = 1.0;
    a[(1, 3)] = 1.0;
    a[(2, 2)] = -a1;
    a[(3, 1)] = al5 / al2;
    a[(3, 2)] = (mu2 + a1 * al3 * c) / al2;
    a[(3, 3)] = -mu2 / al2;
    a[(4, 0)] = -1.0;
    let mut b = M::zeros(5, 1);
    b[(2, 0)] = b1;
    b[(3, 0)] = -b1 * al3 * c / al2;
    (a, b)
}

/// Eigenvalues of A + B K_book (the book's u = +K x).
fn closed_loop(a: &M, b: &M, k_book: &[f64]) -> Vec<nalgebra::Complex<f64>> {
    let k = M::from_row_slice(1, k_book.len(), k_book);
    (a + b * k).complex_eigenvalues().iter().copied().collect()
}

fn max_re(p: &[nalgebra::Complex<f64>]) -> f64 {
    p.iter().map(|z| z.re).fold(f64::NEG_INFINITY, f64::max)
}

#[test]
fn p2c112_alpha_stability_is_feasible_with_a_valid_p() {
    let out = run("p2c112_ex1_alpha_stability");
    all_reproduced(&out);
    assert_eq!(out.get("feasible"), Some(&Value::Bool(true)));
    let Some(Value::Matrix(p)) = out.get("P") else {
        panic!("no P")
    };
    // Independent check: P ≻ 0 and AᵀP + PA + 2P ≺ 0 by 2 × 2 determinants and traces.
    let a = M::from_row_slice(2, 2, &[0.0, 1.0, -2.25, -2.25]);
    let pm = M::from_fn(2, 2, |i, j| p[i][j]);
    assert!((pm[(1, 1)] - 1.0).abs() < 1e-12, "P22 = 1 by construction");
    let l = a.transpose() * &pm + &pm * &a + &pm * 2.0;
    assert!(pm.trace() > 0.0 && pm.determinant() > 0.0);
    assert!(l.trace() < 0.0 && l.determinant() > 0.0);
}

#[test]
fn p2c121_optimum_matches_the_closed_form_and_the_printed_digits() {
    let out = run("p2c121_ex3_alpha_stability_opt");
    all_reproduced(&out);
    // Closed form (ε → 0, derived in pendulab-lmi's tests): ξ2 is the smaller root of
    // 233ξ2² − 524.25ξ2 + 292.25 = 0 and ξ1 = 2.25ξ2 − 0.25 − √((2.5 − 2ξ2)(2ξ2 − 2)).
    let x2: f64 = (524.25 - (524.25f64.powi(2) - 4.0 * 233.0 * 292.25).sqrt()) / 466.0;
    let x1 = 2.25 * x2 - 0.25 - ((2.5 - 2.0 * x2) * (2.0 * x2 - 2.0)).sqrt();
    // The margin ε = 1e-6 moves the optimum by O(ε‖dual‖) ≈ 1e-5.
    assert!((num(&out, "optimum") - (x1 + x2)).abs() < 1e-4);
    assert!((num(&out, "xi1") - x1).abs() < 1e-4);
    assert!((num(&out, "xi2") - x2).abs() < 1e-4);
}

#[test]
fn p2c122_lmi_servo_agrees_with_scipys_riccati_gain() {
    let out = run("p2c122_ex4_adip_oc_servo");
    let k_lmi = vector(&out, "Kt");
    let k_lq = vector(&out, "Kt_LQ");
    let k_ref = k_lq_book();
    let rel = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            .sqrt()
            / b.iter().map(|y| y * y).sum::<f64>().sqrt()
    };
    // pendulab's Riccati gain against SciPy's (both to ~1e-12 relative on this data).
    assert!(rel(&k_lq, &k_ref) < 1e-9, "{k_lq:?} vs {k_ref:?}");
    // The book: the LMI gain agrees "to ~3 digits" (margin ε and the solver tolerance
    // amplified by κ(X) ≈ 1e4).
    assert!(rel(&k_lmi, &k_ref) < 1e-3, "{k_lmi:?} vs {k_ref:?}");
    // Same optimum tr X as CVXPY + Clarabel (relative 1e-4, both at tolerance 1e-8).
    let tr = fixture()["p2c122_lq"]["trace_X"].as_f64().unwrap();
    assert!((num(&out, "trace_X") - tr).abs() < 1e-4 * tr);
}

#[test]
fn p2c122_multiobjective_poles_lie_in_the_region() {
    let out = run("p2c122_ex4_adip_oc_multiobjective_servo");
    all_reproduced(&out);
    let (a, b) = arm_servo(6.20, 15.8, 0.0);
    let poles = closed_loop(&a, &b, &vector(&out, "Kt"));
    for z in &poles {
        assert!(z.re < -2.0 && z.re > -16.0, "{z}");
        assert!(z.im.abs() < -z.re, "outside the π/4 sector: {z}");
    }
    // The reported poles are these (sorted by real part).
    let Some(Value::Complex(rep)) = out.get("poles") else {
        panic!()
    };
    assert_eq!(rep.len(), 5);
    for z in rep {
        assert!(
            poles
                .iter()
                .any(|p| (p.re - z.re).abs() + (p.im - z.im).abs() < 1e-6)
        );
    }
}

/// The p2c13 M-files' vertices in `mvert(2)` order (ρ1 min/ρ2 min, ρ1 max/ρ2 min, ...).
const VERTICES: [(f64, f64); 4] = [(3.41, 8.69), (8.99, 8.69), (3.41, 22.91), (8.99, 22.91)];

fn vertex_max_re(k_book: &[f64]) -> Vec<f64> {
    VERTICES
        .iter()
        .map(|&(a1, b1)| {
            let (a, b) = arm_servo(a1, b1, 0.0);
            max_re(&closed_loop(&a, &b, k_book))
        })
        .collect()
}

fn check_vertices(out: &ExampleOutput, gain: &str) -> Vec<f64> {
    let got = vector(out, "max_real_pole_per_vertex");
    let want = vertex_max_re(&vector(out, gain));
    for (g, w) in got.iter().zip(&want) {
        // Two eigenvalue routines on the same 5 × 5 matrices.
        assert!(
            (g - w).abs() < 1e-8 * w.abs().max(1.0),
            "{got:?} vs {want:?}"
        );
    }
    want
}

#[test]
fn p2c13_nominal_lq_is_unstable_at_one_vertex_and_the_robust_design_is_not() {
    let lq = run("p2c13_ex5_adip_lqr_servo");
    all_reproduced(&lq);
    let k = vector(&lq, "Kt_LQ");
    for (x, y) in k.iter().zip(k_lq_book()) {
        assert!((x - y).abs() < 1e-9 * y.abs().max(1.0));
    }
    let m = check_vertices(&lq, "Kt_LQ");
    // The nominal LQ is unstable at vertex (a1 = 8.99, b1 = 8.69).
    assert!(m[1] > 0.0, "{m:?}");
    assert_eq!(lq.get("stable_at_all_vertices"), Some(&Value::Bool(false)));

    let nominal = run("p2c13_ex5_adip_oc_nominal_servo");
    let m = check_vertices(&nominal, "Kt");
    // Designed for the nominal model only: its poles there are in the region.
    let (a, b) = arm_servo(6.20, 15.8, 0.0);
    let p = closed_loop(&a, &b, &vector(&nominal, "Kt"));
    assert!(p.iter().all(|z| z.re < -2.0 && z.re > -40.0), "{p:?}");
    assert_eq!(m.len(), 4);

    let robust = run("p2c13_ex5_adip_oc_robust_servo");
    all_reproduced(&robust);
    let m = check_vertices(&robust, "Kt");
    // α = 2 at every vertex (β = 40 too).
    assert!(m.iter().all(|r| *r < -2.0), "{m:?}");
    for &(a1, b1) in &VERTICES {
        let (a, b) = arm_servo(a1, b1, 0.0);
        let p = closed_loop(&a, &b, &vector(&robust, "Kt"));
        assert!(p.iter().all(|z| z.re > -40.0));
    }
}

// p2c14_ex6: see p2c1_lmi.rs (the M-file's problem, its certificate and the saturating K).

#[test]
fn p2c15_constant_lq_servo_loses_the_pendulum_on_the_way_to_60_degrees() {
    let out = run("p2c15_ex7_adip_lqr_servo");
    let k = vector(&out, "Kt");
    for (x, y) in k.iter().zip(k_lq_book()) {
        assert!((x - y).abs() < 1e-9 * y.abs().max(1.0));
    }
    // The constant gain on the frozen models rebuilt here: stable at θ1 = 0, unstable at 60°
    // (ρ = 0.5) — two eigenvalue routines agree to 1e-8.
    for (name, rho, stable) in [
        ("max_real_pole_frozen_at_0deg", 0.0, true),
        ("max_real_pole_frozen_at_60deg", 0.5, false),
    ] {
        let (a, b) = arm_servo(6.20, 15.8, rho);
        let m = max_re(&closed_loop(&a, &b, &k));
        assert!(
            (num(&out, name) - m).abs() < 1e-8 * m.abs().max(1.0),
            "{name}"
        );
        assert_eq!(m < 0.0, stable, "{name}: {m}");
    }
    // So on the nonlinear plant the pendulum falls on the way to 60° (the run stops at
    // |θ2| > 90°), before r returns to 0 at 6 s.
    let fell = num(&out, "fell_at");
    assert!(fell > 0.0 && fell < 6.0, "{fell}");
}

/// The gain-scheduled example, run once per test binary (the SOS solve takes ~1–2 s), with
/// its figures in a temporary directory.
fn gs() -> &'static (ExampleOutput, TempDir, Vec<PathBuf>) {
    static GS: OnceLock<(ExampleOutput, TempDir, Vec<PathBuf>)> = OnceLock::new();
    GS.get_or_init(|| {
        let dir = TempDir::new("p2c1");
        let (out, files) = dir.run("p2c15_ex7_adip_oc_gs_servo", None);
        (out, dir, files)
    })
}

#[test]
fn p2c15_gain_scheduled_servo_reaches_the_known_optimum() {
    let (out, _, _) = gs();
    let g = num(out, "gamma");
    // The M-file's gamma_obj = 1.06*double(gamma) (line 120) against the book's "γ = 236 程度"
    // (p. 164): about 236, within 0.5 % (SeDuMi's γ* stops ≈ 0.2 % above the optimum); to the
    // printed integer it differs (235.5), and the comparison says so.
    let go = num(out, "gamma_obj");
    assert!((go - 1.06 * g).abs() < 1e-9 * go);
    assert!((go - 236.0).abs() < 0.005 * 236.0, "{go}");
    let c = out.comparisons();
    assert_eq!(c.len(), 1);
    assert_eq!(c[0].reproduced, (go - 236.0).abs() <= 0.5);
    // CVXPY + Clarabel on a hand-written copy of the SOS program (fixture), 0.2 %.
    let g_ref = fixture()["p2c15_gain_schedule"]["gamma_star"]
        .as_f64()
        .unwrap();
    assert!((g - g_ref).abs() < 0.002 * g_ref, "{g} vs {g_ref}");
    assert!(num(out, "gamma_design") <= 1.06 * g * (1.0 + 1e-9));
    // At the optimum the gain at ρ̄ is well determined: CVXPY's agrees to 2 %
    // (both solvers stop at reduced accuracy on this boundary point; the fixture is in the
    // library sign).
    let k_ref: Vec<f64> = fixture()["p2c15_gain_schedule"]["K_at_rho_max_at_optimum"][0]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| -v.as_f64().unwrap())
        .collect();
    let k_opt = vector(out, "K_at_rho_max_at_optimum");
    let diff: f64 = k_opt
        .iter()
        .zip(&k_ref)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    let norm: f64 = k_ref.iter().map(|b| b * b).sum::<f64>().sqrt();
    assert!(diff < 0.02 * norm, "{k_opt:?} vs {k_ref:?}");
    // The scheduled gain stabilises the frozen LPV model at both ends of the ρ range.
    let rho_bar = 1.0 - 65f64.to_radians().cos();
    for (name, rho) in [("K_at_rho0", 0.0), ("K_at_rho_max", rho_bar)] {
        let (a, b) = arm_servo(6.20, 15.8, rho);
        let m = max_re(&closed_loop(&a, &b, &vector(out, name)));
        assert!(m < 0.0, "{name}: {m}");
    }
}

/// The acceptance issue 5 asks for: simulated on the nonlinear arm plant (quantised rig
/// preset), the scheduled servo keeps ρ and ρ̇ inside the design ranges and tracks
/// r = 60° → 0.
#[test]
fn p2c15_gain_scheduled_servo_stays_in_its_design_ranges_and_tracks() {
    let (out, _, _) = gs();
    let rho_bar = 1.0 - 65f64.to_radians().cos();
    let rho = vector(out, "rho_range_seen");
    let rho_dot = vector(out, "rho_dot_range_seen");
    assert!(
        rho[0] >= 0.0 && rho[1] <= rho_bar,
        "ρ in {rho:?}, design [0, {rho_bar}]"
    );
    // ρ = 1 − cos 60° = 0.5 is reached (it tracks 60°).
    assert!(rho[1] > 0.49, "{rho:?}");
    assert!(
        rho_dot[0] >= -0.75 && rho_dot[1] <= 0.75,
        "ρ̇ in {rho_dot:?}"
    );
    let e6 = num(out, "tracking_error_at_6s_deg");
    assert!(e6 < 1.0, "|θ1(6 s) − 60°| = {e6}°");
    let fin = vector(out, "final_state");
    assert!(
        fin[0].abs() < 1f64.to_radians() && fin[1].abs() < 1f64.to_radians(),
        "{fin:?}"
    );
}

#[test]
fn p2c15_gain_scheduled_servo_writes_its_figures() {
    let (_, dir, files) = gs();
    for what in ["gains", "response", "rho"] {
        for ext in ["svg", "png"] {
            let p = dir
                .path()
                .join(format!("p2c15_ex7_adip_oc_gs_servo_{what}.{ext}"));
            let len = std::fs::metadata(&p).map(|m| m.len()).unwrap_or(0);
            assert!(len > 5_000, "{} has {len} bytes", p.display());
            assert!(files.contains(&p));
        }
    }
    let gif = std::fs::read(dir.path().join("p2c15_ex7_adip_oc_gs_servo_animation.gif")).unwrap();
    assert!(gif.starts_with(b"GIF89a") && gif.len() > 10_000);
    let svg = std::fs::read_to_string(dir.path().join("p2c15_ex7_adip_oc_gs_servo_animation.svg"))
        .unwrap();
    assert!(svg.contains("<animate"));
    let png = std::fs::read(dir.path().join("p2c15_ex7_adip_oc_gs_servo_gains.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
}
