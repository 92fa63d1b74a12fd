//! Part 1 ch. 8 examples: ZOH and bilinear discretisation.
//!
//! Independent references: the book's printed coefficients (part 1 §8.3–8.4), closed forms of both
//! discretisations of 1/(s² + s + 1), SciPy 1.17.1 `cont2discrete` values printed by
//! `tools/reference/book_p1c5_reference.py`, and the eigenvalue maps of ZOH (z = e^{λ ts})
//! and Tustin (z = (1 + λ ts/2)/(1 − λ ts/2)).

mod common;
use common::*;

use pendulab_book::{ExampleOutput, Value};
use pendulab_lti::Complex64;

#[test]
fn p1c83_ex1_zero_order_hold() {
    let out = run("p1c83_ex1_zero_order_hold");
    let (n, d) = (vector(&out, "num"), vector(&out, "den"));
    // Book (4 decimals): (0.3403 z + 0.2417)/(z² − 0.7859 z + 0.3679).
    assert_abs(&n, &[0.3403, 0.2417], 5e-5, "num");
    assert_abs(&d, &[1.0, -0.7859, 0.3679], 5e-5, "den");
    // Closed form of the ZOH denominator: poles e^{(−1/2 ± j√3/2)}, so
    // z² − 2e^{−1/2} cos(√3/2) z + e^{−1}; SciPy for the numerator. 1e-10: expm to rounding.
    let a1 = -2.0 * (-0.5f64).exp() * (0.75f64.sqrt()).cos();
    assert_abs(&d, &[1.0, a1, (-1.0f64).exp()], 1e-10, "den closed form");
    assert_abs(&n, &[0.340299846608, 0.241686482894], 1e-10, "num (SciPy)");
    // DC gain preserved by ZOH: C[1] = C(0) = 1.
    assert!(((n[0] + n[1]) / (1.0 + d[1] + d[2]) - 1.0).abs() < 1e-12);
    all_reproduced(&out);
}

#[test]
fn p1c84_ex3_bilinear() {
    let out = run("p1c84_ex3_bilinear");
    let (n, d) = (vector(&out, "num"), vector(&out, "den"));
    // Closed form with s = 2(z − 1)/(z + 1), ts = 1: (z + 1)²/(7z² − 6z + 3).
    assert_abs(&n, &[1.0 / 7.0, 2.0 / 7.0, 1.0 / 7.0], 1e-13, "num");
    assert_abs(&d, &[1.0, -6.0 / 7.0, 3.0 / 7.0], 1e-13, "den");
    // Book (5 decimals).
    assert_abs(&n, &[0.14286, 0.28571, 0.14286], 5e-6, "num (book)");
    assert_abs(&d, &[1.0, -0.85714, 0.42857], 5e-6, "den (book)");
    all_reproduced(&out);
}

/// Every mapped continuous pole appears among the discrete ones.
fn assert_mapped(out: &ExampleOutput, map: impl Fn(Complex64) -> Complex64) {
    let cont = cplx(out, "controller_poles_continuous");
    let disc = cplx(out, "controller_poles");
    assert_eq!(cont.len(), disc.len());
    for p in cont {
        let z = map(p);
        // Eigenvalues of a 4×4 with well-separated poles: 1e-9.
        assert!(
            disc.iter().any(|d| (d - z).norm() < 1e-9),
            "{z} not in {disc:?}"
        );
    }
}

#[test]
fn p1c83_ex2_cdip_ob_design_zoh() {
    let out = run("p1c83_ex2_cdip_ob_design_zoh");
    assert_mapped(&out, |p| (p * 0.01).exp());
    // Balanced on the quantised rig within 1° after 2 s (slowest design pole −2.5).
    let Some(Value::Number(th)) = out.get("theta_max_after_2s_deg") else {
        panic!()
    };
    assert!(*th < 1.0, "{th}");
}

#[test]
fn p1c84_ex4_cdip_ob_design_bilinear() {
    let out = run("p1c84_ex4_cdip_ob_design_bilinear");
    let one = Complex64::new(1.0, 0.0);
    assert_mapped(&out, |p| (one + p * 0.005) / (one - p * 0.005));
    let Some(Value::Number(th)) = out.get("theta_max_after_2s_deg") else {
        panic!()
    };
    assert!(*th < 1.0, "{th}");
}

#[test]
fn figures_are_written() {
    let dir = TempDir::new("p1c8");
    for (id, n) in [
        ("p1c83_ex1_zero_order_hold", 2),
        ("p1c84_ex4_cdip_ob_design_bilinear", 4),
    ] {
        let (_, files) = dir.run(id, None);
        assert_eq!(files.len(), n, "{id}");
        assert_figures_larger(&files, 2000);
    }
}
