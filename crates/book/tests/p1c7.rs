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
