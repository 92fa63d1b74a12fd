//! Part 1 chapter 2 examples against closed forms of the linear loops, the final-value
//! theorem and the book's printed values. Table 3.5: a_c = 6.25, b_c = 4.36.

mod common;
use common::*;

use pendulab_lti::Complex64;

const AC: f64 = 6.25;
const BC: f64 = 4.36;

/// Roots of s² + p s + q with q > p²/4, upper one first.
fn pair(p: f64, q: f64) -> [Complex64; 2] {
    let w = (q - p * p / 4.0).sqrt();
    [Complex64::new(-p / 2.0, w), Complex64::new(-p / 2.0, -w)]
}

fn close(a: &[Complex64], b: &[Complex64], tol: f64) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).norm() < tol, "{x} vs {y}");
    }
}

/// Elementary symmetric functions of three roots: (Σλ, Σλiλj, Πλ).
fn vieta3(r: &[Complex64]) -> (f64, f64, f64) {
    assert_eq!(r.len(), 3);
    let s1 = r[0] + r[1] + r[2];
    let s2 = r[0] * r[1] + r[0] * r[2] + r[1] * r[2];
    let s3 = r[0] * r[1] * r[2];
    assert!(s1.im.abs() < 1e-9 && s2.im.abs() < 1e-9 && s3.im.abs() < 1e-9);
    (s1.re, s2.re, s3.re)
}

#[test]
fn p1c211_pcont() {
    let out = run("p1c211_pcont");
    references_reproduced(&out);
    // Poles of s² + a_c s + b_c k_P, closed form; roots() is backward stable: 1e-12.
    for kp in [5.0, 10.0, 20.0] {
        close(
            &cplx(&out, &format!("poles_kP{kp}")),
            &pair(AC, BC * kp),
            1e-12,
        );
    }
    // Peak of the step response of ω_n²/(s² + 2ζω_n s + ω_n²), 0.1 (1 + e^{−ζπ/√(1−ζ²)}).
    // The simulation adds the 1 ms hold (half a sample of delay, +0.3 % of the step at
    // k_P = 20), the encoder (±2.4e-5 m) and the D/A: 1e-3 m (1 % of the step).
    for (kp, zmax) in [5.0, 10.0, 20.0].iter().zip(vector(&out, "z_max")) {
        let zeta = AC / (2.0 * (BC * kp).sqrt());
        let peak = 0.1 * (1.0 + (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp());
        assert!((zmax - peak).abs() < 1e-3, "k_P = {kp}: {zmax} vs {peak}");
    }
}

#[test]
fn p1c212_pdcont() {
    let out = run("p1c212_pdcont");
    close(
        &cplx(&out, "poles_kD01"),
        &pair(AC + BC * 0.1, BC * 10.0),
        1e-12,
    );
    close(
        &cplx(&out, "poles_kD08"),
        &pair(AC + BC * 0.8, BC * 10.0),
        1e-12,
    );
    // Type-1 loop: zero steady-state error for a step (final-value theorem). Left: the encoder
    // (4.8e-5 m) and the D/A step (1.5e-4 V over k_P = 10): 1e-4 m.
    for z in vector(&out, "z_final") {
        assert!((z - 0.1).abs() < 1e-4, "{z}");
    }
}

#[test]
fn p1c213_picont() {
    let out = run("p1c213_picont");
    // P control under the input disturbance d = −0.1 V: e∞ = −d/k_P = 0.01 m (final-value
    // theorem); encoder and D/A quantisation leave 1e-4 m.
    assert!((num(&out, "e_final_kI0") - 0.01).abs() < 1e-4);
    for ki in [5.0, 25.0] {
        // s³ + a_c s² + b_c k_P s + b_c k_I: Vieta's formulas (independent of the root
        // finder), to 1e-9 relative.
        let (s1, s2, s3) = vieta3(&cplx(&out, &format!("poles_kI{ki}")));
        assert!((s1 + AC).abs() < 1e-9);
        assert!((s2 - BC * 10.0).abs() < 1e-9 * BC * 10.0);
        assert!((s3 + BC * ki).abs() < 1e-9 * BC * ki);
        // The integral removes the offset: after 10 s the slowest mode (k_I = 5: −0.538 1/s)
        // has decayed to e^{−5.4} ≈ 0.5 % of ~0.01 m; 2e-4 m.
        let e = num(&out, &format!("e_final_kI{ki}"));
        assert!(e.abs() < 2e-4, "k_I = {ki}: e = {e}");
    }
}

#[test]
fn p1c213_pidcont() {
    let out = run("p1c213_pidcont");
    let (kp, kd, ki) = (10.0, 0.8, 5.0);
    let (s1, s2, s3) = vieta3(&cplx(&out, "poles"));
    assert!((s1 + AC + BC * kd).abs() < 1e-9);
    assert!((s2 - BC * kp).abs() < 1e-9 * BC * kp);
    assert!((s3 + BC * ki).abs() < 1e-9 * BC * ki);
    // As for PI: the slowest pole −0.568 1/s leaves < 0.5 % of the 0.01 m offset at 10 s.
    assert!(num(&out, "e_final").abs() < 2e-4);
}

#[test]
fn p1c213_pidbode() {
    let out = run("p1c213_pidbode");
    let (kp, ti, td) = (10.0, 2.0, 0.08);
    assert!((num(&out, "TI") - ti).abs() < 1e-15);
    assert!((num(&out, "TD") - td).abs() < 1e-15);
    // The defining property of the gain crossover, evaluated here independently:
    // |P(jω_c) C(jω_c)| = 1; the phase margin is 180° + ∠P(jω_c)C(jω_c).
    let wc = num(&out, "wc");
    let s = Complex64::new(0.0, wc);
    let l = BC / (s * (s + AC)) * kp * (1.0 + 1.0 / (ti * s) + td * s);
    assert!((l.norm() - 1.0).abs() < 1e-9, "|L| = {}", l.norm());
    let pm = 180.0 + l.arg().to_degrees();
    assert!((num(&out, "phase_margin") - pm).abs() < 1e-6);
    // And it is the only crossover: |L| decreases through 1 there.
    let s2 = Complex64::new(0.0, 1.01 * wc);
    let l2 = BC / (s2 * (s2 + AC)) * kp * (1.0 + 1.0 / (ti * s2) + td * s2);
    assert!(l2.norm() < 1.0);
}

#[test]
fn p1c221_id_cart() {
    let out = run("p1c221_id_cart");
    references_reproduced(&out);
    // The simulated drive is table 3.5: K = b_c/a_c = 0.6976, T = 1/a_c = 0.16 s. K is a
    // difference of encoder positions over 0.1 s (±2 counts = ±1e-3 m/s, 0.14 % of 0.7 m/s):
    // 0.2 %. T is the first crossing of a velocity carrying ±q/(2 ts) = ±0.024 m/s of
    // quantisation noise where it rises at ~1.6 m/s²: ±15 ms at most; the mean of four
    // within ±8 ms (5 %).
    for k in vector(&out, "K") {
        assert!((k / (BC / AC) - 1.0).abs() < 2e-3, "K = {k}");
    }
    for t in vector(&out, "T") {
        assert!((t - 1.0 / AC).abs() < 0.015, "T = {t}");
    }
    assert!((num(&out, "ac_unrounded") / AC - 1.0).abs() < 0.05);
    assert!((num(&out, "bc_unrounded") / BC - 1.0).abs() < 0.05);
    // On the exact position the recipe reads T on the 1 ms grid (±1 ms, 0.6 %) and K to
    // rounding: the table values.
    assert!((num(&out, "ac_unquantised") / AC - 1.0).abs() < 0.007);
    assert!((num(&out, "bc_unquantised") / BC - 1.0).abs() < 0.007);
}

#[test]
fn p1c223_pcont() {
    let out = run("p1c223_pcont");
    let z = std::f64::consts::FRAC_1_SQRT_2;
    // k_P = ω_n²/b_c (speed matching), a_c ω_n/(2 b_c ζ) (partial model matching).
    assert!((num(&out, "kP_speed_wn5") - 25.0 / BC).abs() < 1e-12);
    assert!((num(&out, "kP_speed_wn10") - 100.0 / BC).abs() < 1e-12);
    assert!((num(&out, "kP_partial_wn10") - AC * 10.0 / (2.0 * BC * z)).abs() < 1e-12);
}

#[test]
fn p1c224_p_dcont() {
    let out = run("p1c224_p_dcont");
    let z = std::f64::consts::FRAC_1_SQRT_2;
    for wn in [5.0f64, 10.0] {
        let kp = num(&out, &format!("kP_wn{wn}"));
        let kd = num(&out, &format!("kD_wn{wn}"));
        // Closed loop of the P–D law: s² + (a_c + b_c k_D) s + b_c k_P must equal the
        // reference model's s² + 2ζω_n s + ω_n² coefficient by coefficient.
        assert!((AC + BC * kd - 2.0 * z * wn).abs() < 1e-12);
        assert!((BC * kp - wn * wn).abs() < 1e-12);
    }
}

#[test]
fn p1c224_i_pdcont() {
    let out = run("p1c224_i_pdcont");
    let wn = 10.0f64;
    for (name, a2, a1) in [
        ("gains_binomial", 3.0, 3.0),
        ("gains_butterworth", 2.0, 2.0),
        ("gains_itae", 2.15, 1.75),
    ] {
        let g = vector(&out, name);
        let (ki, kp, kd) = (g[0], g[1], g[2]);
        // s³ + (a_c + b_c k_D) s² + b_c k_P s + b_c k_I = s³ + α₂ω_n s² + α₁ω_n² s + ω_n³.
        assert!((AC + BC * kd - a2 * wn).abs() < 1e-12, "{name}");
        assert!((BC * kp - a1 * wn * wn).abs() < 1e-10, "{name}");
        assert!((BC * ki - wn.powi(3)).abs() < 1e-10, "{name}");
    }
}

#[test]
fn p1c23_crane() {
    let out = run("p1c23_crane");
    // Without the damping term the cart loop does not see the pendulum (the drive is an
    // acceleration source): the poles are the Butterworth I–PD poles ω_n·{−1, −½ ± j√3/2}
    // and those of the hanging pendulum with the cart held, (−ζ_p ± j√(1 − ζ_p²)) ω_np
    // (eq. 4.41) with ω_np = √(m_p g l_p/J), ζ_p = μ_p/(2 ω_np J), J = J_p + m_p l_p².
    let (mp, lp, jp, mup, g) = (0.107f64, 0.230f64, 1.59e-3, 2.35e-4, 9.81);
    let j = jp + mp * lp * lp;
    let wnp = (mp * g * lp / j).sqrt();
    let zp = mup / (2.0 * wnp * j);
    let wd = wnp * (1.0 - zp * zp).sqrt();
    let h = 3f64.sqrt() / 2.0;
    let expected = [
        Complex64::new(-zp * wnp, wd),
        Complex64::new(-zp * wnp, -wd),
        Complex64::new(-5.0, 10.0 * h),
        Complex64::new(-5.0, -10.0 * h),
        Complex64::new(-10.0, 0.0),
    ];
    // Eigenvalues of a 5×5 with entries up to 200: 1e-9.
    close(&cplx(&out, "poles_without"), &expected, 1e-9);
    // The book's point: feeding the swing back damps it. The slowest (pendulum) pair moves
    // left, and the simulated residual swing after the cart has arrived is smaller.
    let slowest = |v: Vec<Complex64>| v.iter().map(|z| z.re).fold(f64::NEG_INFINITY, f64::max);
    let with = slowest(cplx(&out, "poles_with"));
    assert!(with < 5.0 * slowest(cplx(&out, "poles_without")), "{with}");
    assert!(cplx(&out, "poles_with").iter().all(|z| z.re < 0.0));
    assert!(num(&out, "phi_max_after_1s_with") < num(&out, "phi_max_after_1s_without"));
}

#[test]
fn chapter_2_figures_are_written() {
    let dir = TempDir::new("p1c2");
    let ctx = dir.ctx(None);
    for id in [
        "p1c211_pcont",
        "p1c213_pidbode",
        "p1c221_id_cart",
        "p1c23_crane",
    ] {
        let out = run_in(id, &ctx).unwrap();
        assert!(out.figures.len() >= 2, "{id}");
        assert_figures_larger(&out, 2000);
        if id == "p1c23_crane" {
            assert!(out.figures.iter().any(|f| f.extension().unwrap() == "gif"));
        }
    }
}
