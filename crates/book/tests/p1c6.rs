//! Part 1 ch. 6 examples: P/PI control of the cart drive and the LQ integral servo.
//!
//! Independent references: the book's printed values (part 1 §6.2–6.3), closed forms of the
//! second/third-order loops, and SciPy 1.17.1 values printed by
//! `tools/reference/book_p1c5_reference.py`.

mod common;
use common::*;

use pendulab_lti::Complex64;

const AC: f64 = 6.25;
const BC: f64 = 4.36;

/// Every `want` has a computed pole within `tol`.
fn assert_poles(got: &[Complex64], want: &[(f64, f64)], tol: f64) {
    assert_eq!(got.len(), want.len());
    for &(re, im) in want {
        let w = Complex64::new(re, im);
        assert!(
            got.iter().any(|g| (g - w).norm() <= tol),
            "{w} not in {got:?}"
        );
    }
}

#[test]
fn p1c62_ex1_cart_p_step() {
    let out = run("p1c62_ex1_cart_p_step");
    // Book: −3.125 ± 5.817j (3 decimals: |Δ| ≤ 5e-4·√2).
    assert_poles(
        &cplx(&out, "poles"),
        &[(-3.125, 5.817), (-3.125, -5.817)],
        5e-4 * 2f64.sqrt(),
    );
    // Closed form s² + a s + b k_P: (−a ± j√(4 b k_P − a²))/2, to rounding of a 2×2 eigen-solve.
    let w = (4.0 * BC * 10.0 - AC * AC).sqrt() / 2.0;
    assert_poles(
        &cplx(&out, "poles"),
        &[(-AC / 2.0, w), (-AC / 2.0, -w)],
        1e-12,
    );
    assert_eq!(num(&out, "e_inf"), 0.0);
    all_reproduced(&out);
}

#[test]
fn p1c62_ex2_cart_pi_ramp() {
    let out = run("p1c62_ex2_cart_pi_ramp");
    let p = cplx(&out, "poles");
    // Book: −2.203 ± 5.534j, −1.843 (3 decimals).
    assert_poles(
        &p,
        &[(-2.203, 5.534), (-2.203, -5.534), (-1.843, 0.0)],
        5e-4 * 2f64.sqrt(),
    );
    // Vieta for s³ + a s² + b k_P s + b k_I: Σp = −a, Πp = −b k_I (to rounding).
    let sum: Complex64 = p.iter().sum();
    let prod: Complex64 = p.iter().product();
    assert!((sum.re + AC).abs() < 1e-12 && sum.im.abs() < 1e-12);
    assert!((prod.re + BC * 15.0).abs() < 1e-10 && prod.im.abs() < 1e-10);
    assert_eq!(num(&out, "e_inf"), 0.0);
    // The simulated ramp error is a transient of the slowest pole (−1.843) on a scale of
    // r0/k_I-ish millimetres: by 2.5 s, e^{-4.6} ≈ 1 % of it is left, far below 5 mm.
    assert!(num(&out, "e_final_sim").abs() < 5e-3);
    all_reproduced(&out);
}

#[test]
fn p1c62_ex3_cart_p_step_dis() {
    let out = run("p1c62_ex3_cart_p_step_dis");
    // Book eq. 6.21: e∞ = −d0/k_P = −0.3 m.
    assert!((num(&out, "e_inf") + 0.3).abs() < 1e-12);
    // The simulation settles there: 2.5 s after the step at decay rate 3.125 the transient is
    // ≤ 0.3·e^{-7.8}·(1 + a/ω) ≈ 2e-4 m; 1e-3 m allows for it.
    assert!((num(&out, "e_final_sim") + 0.3).abs() < 1e-3);
    all_reproduced(&out);
}

#[test]
fn p1c62_ex4_cart_pi_step_dis() {
    let out = run("p1c62_ex4_cart_pi_step_dis");
    assert_eq!(num(&out, "e_inf"), 0.0);
    // PI rejects the step disturbance; 2.5 s after it the slow pole −1.843 leaves
    // e^{-4.6} ≈ 1 % of the ~0.2 m peak deviation.
    assert!(
        num(&out, "e_final_sim").abs() < 5e-3,
        "{}",
        num(&out, "e_final_sim")
    );
    all_reproduced(&out);
}

#[test]
fn p1c63_ex5_cdip_lqr_servo() {
    let out = run("p1c63_ex5_cdip_lqr_servo");
    // SciPy solve_continuous_are on the augmented system, book convention; relative 1e-8.
    let k1 = vector(&out, "K1");
    for (g, w) in k1
        .iter()
        .zip([95.7226424968, 63.1560173536, 31.0005350531, 10.9139689166])
    {
        assert!((g - w).abs() <= 1e-8 * w, "{k1:?}");
    }
    // K2 = −√(q2/R) = −√20000 (w is an integrator state: Kalman identity at s → 0).
    let k2 = vector(&out, "K2");
    assert!((k2[0] + 20000f64.sqrt()).abs() < 1e-8 * 141.5, "{k2:?}");
    // Book: e∞ = 0 (integral action).
    assert!(num(&out, "e_inf").abs() < 1e-9);
    // The cart first moves the wrong way (book; unstable zero of z/v): a visible undershoot,
    // and the nonlinear loop still settles on r = 0.5 m despite the 5 V disturbance.
    let u = num(&out, "undershoot");
    assert!(u > 1e-3 && u < 0.5, "{u}");
    assert!(
        num(&out, "e_final_sim").abs() < 5e-3,
        "{}",
        num(&out, "e_final_sim")
    );
    all_reproduced(&out);
}

#[test]
fn figures_are_written() {
    let dir = TempDir::new("p1c6");
    // Response (SVG + PNG); the servo also animates the rig (GIF + SMIL SVG).
    for (id, n) in [
        ("p1c62_ex3_cart_p_step_dis", 2),
        ("p1c63_ex5_cdip_lqr_servo", 4),
    ] {
        let (_, files) = dir.run(id, None);
        assert_eq!(files.len(), n, "{id}");
        assert_figures_larger(&files, 2000);
    }
}
