//! IP Toolbox samples on the quantised rig at 1 ms.
//!
//! Independent references: the IP Toolbox samples' gains and pendulum dips, closed forms
//! (integrator gains √(q/R)), SciPy 1.17.1 values printed by
//! `tools/reference/book_p1c5_reference.py`, and for the PD samples a linear model of the
//! drive alone (the drive is an acceleration source, so the hanging pendulum does not act on
//! it) simulated exactly by `pendulab_lti::response::lsim`.

mod common;
use common::*;

use pendulab_lti::response::{LsimOptions, lsim, time_vector};
use pendulab_lti::{Mat, StateSpace};

/// Peak over the first 2 s of the drive coordinate of `q̈ = −a q̇ + b v`,
/// `v = k_P (r − q) − f`, `T_f ḟ = k_D q̇ − f` (continuous P–D with the filtered derivative),
/// for the step r = `amp`.
fn linear_pd_peak(a: f64, b: f64, kp: f64, kd: f64, amp: f64) -> f64 {
    let tf = 0.02;
    let am = Mat::from_row_slice(
        3,
        3,
        &[0.0, 1.0, 0.0, -b * kp, -a, -b, 0.0, kd / tf, -1.0 / tf],
    );
    let bm = Mat::from_row_slice(3, 1, &[0.0, b * kp, 0.0]);
    let sys = StateSpace::continuous(
        am,
        bm,
        Mat::from_row_slice(1, 3, &[1.0, 0.0, 0.0]),
        Mat::zeros(1, 1),
    )
    .unwrap();
    let t = time_vector(2.0, 1e-3).unwrap();
    let u = Mat::from_element(t.len(), 1, amp);
    let tr = lsim(&sys, &u, &t, None, &LsimOptions::default()).unwrap();
    tr.y_signal(0)
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max)
}

#[test]
fn cdip_pdcont_sim() {
    let out = run("cdip_pdcont_sim");
    // Linear drive model (a_c = 6.25, b_c = 4.36): the sampled, quantised loop differs by the
    // 1 ms hold and Tustin filter (O(ts) of the 0.4 m step, ~1 mm) and the 48 µm encoder.
    let want = linear_pd_peak(6.25, 4.36, 10.0, 0.75, 0.4);
    let got = num(&out, "peak_m");
    assert!((got - want).abs() < 2e-3, "{got} vs {want}");
    // The cart's accelerations swing the hanging pendulum (nearly undamped, μ_p = 2.35e-4)
    // without throwing it over the top.
    let swing = num(&out, "pendulum_swing_max_deg");
    assert!(swing > 1.0 && swing < 180.0, "{swing}");
}

#[test]
fn adip_pdcont_sim() {
    let out = run("adip_pdcont_sim");
    // Linear arm drive (a1 = 6.20, b1 = 15.8), peak in degrees; 0.5° for hold/filter/encoder.
    let want = linear_pd_peak(6.20, 15.8, 4.0, 0.25, std::f64::consts::PI / 3.0).to_degrees();
    let got = num(&out, "peak_deg");
    assert!((got - want).abs() < 0.5, "{got} vs {want}");
    let swing = num(&out, "pendulum_swing_max_deg");
    assert!(swing > 1.0 && swing < 90.0, "{swing}");
}

#[test]
fn cdip_lqr_sim() {
    let out = run("cdip_lqr_sim");
    // cdip_lqr_sim.m displays K (5 decimals).
    for (name, k) in [
        ("K_q10", [3.16228, 13.47175, 4.48137, 2.26289]),
        ("K_q50", [3.16228, 15.81695, 4.72006, 2.44448]),
        ("K_q100", [3.16228, 18.12126, 4.93879, 2.61065]),
    ] {
        let got = vector(&out, name);
        for (g, w) in got.iter().zip(k) {
            assert!((g - w).abs() <= 5e-6, "{name}: {got:?}");
        }
        // K_z = √(q1/R) = √10 (z is an integrator state).
        assert!((got[0] - 10f64.sqrt()).abs() < 1e-9);
    }
    // All three balance the pendulum from 15° on the quantised rig: within 1° after 3 s.
    for th in vector(&out, "theta_max_after_3s_deg") {
        assert!(th < 1.0, "{th}");
    }
    all_reproduced(&out);
}

#[test]
fn cdip_lqr_servo_sim() {
    let out = run("cdip_lqr_servo_sim");
    let k1 = vector(&out, "K1");
    for (g, w) in k1.iter().zip([10.39942, 17.76307, 6.79089, 3.04513]) {
        assert!((g - w).abs() <= 5e-6, "{k1:?}");
    }
    // K2 = −√(q_w/R) = −10.
    assert!((vector(&out, "K2")[0] + 10.0).abs() < 1e-9);
    // Integral action: the cart is back on r = 0.5 m 4 s after the 0.5 V disturbance.
    let e = num(&out, "e_final_sim_m");
    assert!(e.abs() < 5e-3, "{e}");
    all_reproduced(&out);
}

#[test]
fn adip_lqr_sim() {
    let out = run("adip_lqr_sim");
    // SciPy (book convention), relative 1e-8; K_θ1 = √q1 (θ1 is an integrator state).
    let want = [
        (
            "K_q1",
            1.0,
            [1.0, 16.7896554038, 1.35112989061, 2.61195416025],
        ),
        (
            "K_q5",
            5.0,
            [2.2360679775, 21.0210375251, 1.86621420556, 3.28297937648],
        ),
        (
            "K_q20",
            20.0,
            [4.472135955, 28.1474067935, 2.75132747896, 4.40921763692],
        ),
    ];
    for (name, q1, k) in want {
        let got = vector(&out, name);
        assert_rel(&got, &k, 1e-8, name);
        assert!((got[0] - f64::sqrt(q1)).abs() < 1e-9, "{name}");
    }
    // adip_lqr_sim: the pendulum dips ≈ −2°, −4°, −6.7° (read off the book's figure;
    // ±0.5°).
    let dips = vector(&out, "theta2_min_deg");
    for (g, w) in dips.iter().zip([-2.0, -4.0, -6.7]) {
        assert!((g - w).abs() <= 0.5, "{dips:?}");
    }
    all_reproduced(&out);
}

#[test]
fn adip_lqr_servo_sim() {
    let out = run("adip_lqr_servo_sim");
    assert_rel(
        &vector(&out, "K1"),
        &[4.30243129422, 23.2865132903, 2.24630367297, 3.62759203381],
        1e-8,
        "K1",
    );
    // K2 = −√(q_w/R) = −5.
    assert!((vector(&out, "K2")[0] + 5.0).abs() < 1e-9);
    let e = num(&out, "e_final_sim_deg");
    assert!(e.abs() < 0.5, "{e}");
}

#[test]
fn figures_and_animations_are_written() {
    let dir = TempDir::new("toolbox");
    for id in ["cdip_lqr_sim", "adip_lqr_sim"] {
        let (_, files) = dir.run(id, None);
        // Pole map and response (SVG + PNG each) and animation (GIF + SMIL SVG).
        assert_eq!(files.len(), 6, "{id}");
        assert_figures_larger(&files, 5000);
        let gif = files
            .iter()
            .find(|f| f.extension().is_some_and(|e| e == "gif"))
            .unwrap();
        assert_eq!(&std::fs::read(gif).unwrap()[..6], b"GIF89a");
    }
}
