//! Part 1 ch. 7 examples: observer-based output feedback, observability, detectability.
//!
//! Independent references: the book's gain and ranks (part 1 §7.4–7.5), the design specification
//! (observer poles 4× the state-feedback poles), and the separation principle.

mod common;
use common::*;

use pendulab_book::Value;
use pendulab_lti::Complex64;

#[test]
fn p1c74_ex1_cdip_ob_design() {
    let out = run("p1c74_ex1_cdip_ob_design");
    // Book example 7.1: K = [3.06513, 12.57293, 4.32424, 2.16707] (5 decimals: ±5e-6).
    let Some(Value::Vector(k)) = out.get("K") else {
        panic!()
    };
    for (g, w) in k.iter().zip([3.06513, 12.57293, 4.32424, 2.16707]) {
        assert!((g - w).abs() <= 5e-6, "{k:?}");
    }
    // Observer poles 4 × {−6.5 ± 1.5j, −4, −2.5}; placement to ~1e-12 relative on |λ| ≤ 27.
    let Some(Value::Complex(p)) = out.get("observer_poles") else {
        panic!()
    };
    for w in [(-26.0, 6.0), (-26.0, -6.0), (-16.0, 0.0), (-10.0, 0.0)] {
        let w = Complex64::new(w.0, w.1);
        assert!(p.iter().any(|g| (g - w).norm() < 1e-6), "{w} not in {p:?}");
    }
    // On the quantised rig the pendulum is balanced: within 1° of upright after 2 s (the
    // slowest designed pole −2.5 has decayed by e^{-5} from the 10° start).
    assert!(num(&out, "theta_max_after_2s_deg") < 1.0);
    assert!(num(&out, "z_max_abs") < 0.5);
    all_reproduced(&out);
}

#[test]
fn p1c74_ex2_cdip_mo() {
    let out = run("p1c74_ex2_cdip_Mo");
    // Book: rank M_o = 2 (y = z), 3 (y = θ).
    assert_eq!(num(&out, "rank_y_z"), 2.0);
    assert_eq!(num(&out, "rank_y_theta"), 3.0);
    all_reproduced(&out);
}

#[test]
fn p1c75_ex3_cdip_detectability() {
    let out = run("p1c75_ex3_cdip_detectability");
    // Book: neither output is detectable.
    assert_eq!(out.get("detectable_y_z"), Some(&Value::Bool(false)));
    assert_eq!(out.get("detectable_y_theta"), Some(&Value::Bool(false)));
    all_reproduced(&out);
}

#[test]
fn figures_are_written() {
    let dir = TempDir::new("p1c7");
    let (_, files) = dir.run("p1c74_ex1_cdip_ob_design", None);
    // Response (SVG + PNG), pole map (SVG + PNG), animation (GIF + SVG).
    assert_eq!(files.len(), 6);
    assert_figures_larger(&files, 2000);
}

#[test]
fn p1c74_ex1_two_output_l_is_not_unique_and_its_robustness_is_reported() {
    use pendulab_plants::{CartEquilibrium, CartPendulum};
    // SciPy's Tits–Yang robust placement of the same observer poles
    // (tools/reference/p1c74_knv0_scipy.py, SciPy 1.16.3) in the book's sign (A + L C).
    let fx: serde_json::Value =
        serde_json::from_str(include_str!("fixtures/p1c74_knv0_scipy.json")).unwrap();
    let l_scipy: Vec<Vec<f64>> = serde_json::from_value(fx["L"].clone()).unwrap();
    let lin = CartPendulum::book()
        .linearize_measured(CartEquilibrium::upright())
        .unwrap();
    let l = pendulab_lti::Mat::from_fn(4, 2, |i, j| l_scipy[i][j]);
    let eig = pendulab_lti::linalg::eigenvalues(&(lin.a() + &l * lin.c())).unwrap();
    // It places eig(A + LC) = 4 pc (|λ| ≤ 27, SciPy to ~1e-12).
    for w in [(-26.0, 6.0), (-26.0, -6.0), (-16.0, 0.0), (-10.0, 0.0)] {
        let w = Complex64::new(w.0, w.1);
        assert!(
            eig.iter().any(|g| (g - w).norm() < 1e-6),
            "{w} not in {eig:?}"
        );
    }
    let out = run("p1c74_ex1_cdip_ob_design");
    let Some(Value::Matrix(ours)) = out.get("L") else {
        panic!()
    };
    let max_diff = |a: &[Vec<f64>], b: &[Vec<f64>]| {
        a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    // Pendulab's KNV method 0 and SciPy's Tits–Yang, two robust placements, find the same L.
    assert!(max_diff(ours, &l_scipy) < 1e-3, "{ours:?} vs {l_scipy:?}");
    // Octave's place (SLICOT) returns another L that places the same poles: the gain is not
    // unique, so the M-file's display depends on the place it runs.
    let text = include_str!("data/octave/p1c74_ex1_cdip_ob_design.txt");
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip_while(|l| l.trim() != "L =")
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .take(4)
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect();
    let lo = pendulab_lti::Mat::from_fn(4, 2, |i, j| rows[i][j]);
    let eig = pendulab_lti::linalg::eigenvalues(&(lin.a() + &lo * lin.c())).unwrap();
    for w in [(-26.0, 6.0), (-26.0, -6.0), (-16.0, 0.0), (-10.0, 0.0)] {
        let w = Complex64::new(w.0, w.1);
        assert!(
            eig.iter().any(|g| (g - w).norm() < 1e-6),
            "{w} not in {eig:?}"
        );
    }
    assert!(max_diff(ours, &rows) > 1.0, "Octave's L is pendulab's");
    // Its robustness is reported: κ₂(V) ≥ 1 and Henrici's departure from normality ≥ 0.
    let kappa = num(&out, "observer_eigenvector_condition");
    let dep = num(&out, "observer_departure_from_normality");
    assert!(kappa >= 1.0 && kappa.is_finite(), "{kappa}");
    assert!(dep > 0.0 && dep.is_finite(), "{dep}");
    let note = out
        .notes
        .iter()
        .find(|n| n.contains("Not compared: L, and Ac, Bc"))
        .unwrap();
    assert!(note.contains("Kautsky–Nichols–Van Dooren (1985)") && note.contains("Tits–Yang"));
    assert!(
        out.comparisons()
            .iter()
            .any(|c| c.name == "L" && c.reproduced)
    );
    assert!(
        out.uncompared
            .iter()
            .any(|u| u.what.contains("L, and Ac, Bc"))
    );
}
