//! Part 2 ch. 2 examples against independent references: the book's gains, a
//! closed form, and SciPy (`tools/reference/book_p2c2.py`: Van Loan by the block matrix
//! exponential, checked by Simpson quadrature; `solve_discrete_are` with the cross term; the
//! I–PD loop on the exact ZOH sampling of the drive).

mod common;
use common::*;

#[test]
fn p2c234_dynamic_quantizer_beats_static_rounding() {
    let out = run("p2c234_ex1_cdip_odq");
    // K = [3.16228, 13.47175, 4.48137, 2.26289] (IP Toolbox cdip_lqr_sim.m, 5 decimals).
    all_reproduced(&out);
    assert_eq!(num(&out, "quantizer_order"), 2.0);
    let (s, q) = (
        vector(&out, "deviation_static"),
        vector(&out, "deviation_odq"),
    );
    // The book's comparison: the optimal dynamic quantizer keeps the nonlinear loop close to
    // the unquantised one where static rounding leaves a large offset. Its linear worst-case
    // bound is ≈ 20× smaller; demand 10× on both outputs of the nonlinear runs.
    for j in 0..2 {
        assert!(
            q[j] * 10.0 < s[j],
            "output {j}: ODQ {}, static {}",
            q[j],
            s[j]
        );
    }
    assert!(num(&out, "worst_case_bound_odq") * 10.0 < num(&out, "worst_case_bound_static"));
}

#[test]
fn p2c242_ipd_gains_and_overshoots() {
    let out = run("p2c242_ex2_cart_ipd");
    // k_I = 3583.7, k_P = 430.05, k_D = 15.768 (book part 2 §2.4.2, 5 significant digits).
    all_reproduced(&out);
    let g = vector(&out, "gains");
    assert!((g[1] - 430.05).abs() < 0.005 && (g[2] - 15.768).abs() < 0.0005);
    // Continuous: closed loop ω_n³/(s + ω_n)³ — a triple real pole and no zero, so the step
    // response is monotone: no overshoot (to the accuracy of the exact sampling, 1e-9 %).
    assert!(num(&out, "overshoot_continuous") < 1e-6);
    // Discrete at 25 ms (Tustin integral and derivative): SciPy's exact ZOH sampling gives
    // 30.94677414909583 % at the samples. The loop is unstable (spectral radius 1.22, so
    // perturbations grow ×1.22⁴⁰ ≈ 3e3 over the 40 samples): the PID type's derivative filter
    // T_f = 1 ps (it needs T_f > 0; ~1e-10 relative) and RK4 at 1 ms on the drive (~1e-13)
    // end up ~1e-6 relative apart; tolerance 1e-3 % (3e-5 relative).
    let os = num(&out, "overshoot_discrete");
    assert!((os - 30.94677414909583).abs() < 1e-3, "{os}");
    // That loop is unstable: SciPy's eigenvalues of the same closed loop give a spectral
    // radius 1.220970845594806 (two eigenvalue routines on a 5 × 5 matrix: 1e-9).
    let rho = num(&out, "discrete_spectral_radius");
    assert!((rho - 1.220970845594806).abs() < 1e-9, "{rho}");
}

#[test]
fn p2c244_sampled_data_lqr_matches_scipy() {
    let out = run("p2c244_ex3_cdip_sampled_data_lqr_sim");
    // SciPy, library sign (u = −K_d x): [-1.5778974127092174, -9.363318455665842,
    // -3.049762687384925, -1.5949349557822252]; the book's sign is the negative.
    let want = [
        1.5778974127092174,
        9.363318455665842,
        3.049762687384925,
        1.5949349557822252,
    ];
    let kd = vector(&out, "Kd");
    for (x, y) in kd.iter().zip(want) {
        // Two Riccati solvers and two Van Loan exponentials: 1e-9 relative.
        assert!((x - y).abs() < 1e-9 * y, "{kd:?}");
    }
    let rd = num(&out, "Rd");
    assert!((rd - 0.10088709658222006).abs() < 1e-12, "{rd}");
    // R_d ≥ R ts: the held input also drives the state cost.
    assert!(rd > 0.1);
    // The book's comparison on the nonlinear plant from 15°: K_d costs less than K held at
    // 0.1 s (measured with the same Van Loan weights; K_d is the optimum on the linear model).
    let (jd, jh) = (num(&out, "cost_Kd"), num(&out, "cost_K_held"));
    assert!(jd > 0.0 && jd < jh, "K_d {jd}, K held {jh}");
    // The continuous gain is the book's (cdip_lqr_sim.m, q2 = 10; ch. 2 ex. 1 uses the same LQR).
    let k = vector(&out, "K");
    for (x, y) in k.iter().zip([3.16228, 13.47175, 4.48137, 2.26289]) {
        assert!((x - y).abs() <= 5e-6);
    }
}

#[test]
fn p2c242_writes_its_figure() {
    let dir = TempDir::new("p2c2");
    let (_, files) = dir.run("p2c242_ex2_cart_ipd", None);
    assert_eq!(files.len(), 2);
    assert_figures_larger(&files, 5_000);
    let png = std::fs::read(dir.path().join("p2c242_ex2_cart_ipd_response.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
}
