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

/// The cart position of the book's `cart_model.slx` for a voltage step `u` at t = 0, in closed
/// form: `z̈ = −a_c ż + b_c v` from rest with `v` the 16-bit D/A value of `u`:
/// `z(t) = b_c v (t/a_c − (1 − e^{−a_c t})/a_c²)`.
fn cart_step_position(u: f64, t: f64) -> f64 {
    let q = 10.0 / 65536.0;
    let v = q * (u / q).round();
    BC * v * (t / AC - (1.0 - (-AC * t).exp()) / (AC * AC))
}

#[test]
fn p1c221_id_cart() {
    let out = run("p1c221_id_cart");
    // The book prints K = 6.98e-1, T = 1.60e-1, a = 6.250, b = 4.362 (p1c221_id_cart.m, lines
    // 72-77): reproduced.
    references_reproduced(&out);
    assert_eq!(num(&out, "Tave"), 0.160);
    assert_eq!(num(&out, "Kave"), 0.698);
    assert!((num(&out, "a") - 1.0 / 0.160).abs() < 1e-12);
    assert!((num(&out, "b") - 0.698 / 0.160).abs() < 1e-12);
    assert_eq!(num(&out, "ac"), num(&out, "a"));
    assert_eq!(num(&out, "bc"), num(&out, "b"));
    // cartident.m followed in plain Python on the closed-form response of cart_model.slx with
    // its encoder and D/A quantizers (tools/reference/book_mfiles_p1c2_p1c3.py, Python
    // 3.11.7): the simulated encoder counts are the same (the RK4 error, ~1e-14 m, moves no
    // count), so the K_i agree to rounding (1e-9) and the T_i, samples of the time grid,
    // exactly. One count moved anywhere in the 1.399-1.499 s window would shift K_i by
    // 2.4e-4.
    let k = [
        0.6974492079207907,
        0.697715511551156,
        0.6976888811881174,
        0.6972313231323124,
    ];
    let t = [0.154, 0.160, 0.161, 0.164];
    for i in 0..4 {
        let (ki, ti) = (
            num(&out, &format!("K{}", i + 1)),
            num(&out, &format!("T{}", i + 1)),
        );
        assert!((ki - k[i]).abs() < 1e-9, "K{}: {ki} vs {}", i + 1, k[i]);
        assert!((ti - t[i]).abs() < 1e-12, "T{}: {ti} vs {}", i + 1, t[i]);
    }
    // On the exact position the same recipe, evaluated here in closed form: K_i = mean of the
    // central differences over samples 1400-1500 (t = 1.399-1.499 s) over u; the velocity
    // K u (1 − e^{−a_c t}) crosses 0.632 K u at −ln(0.368)/a_c = 0.15995 s, so every T_i is the
    // sample before it, 0.159 s.
    let mut kbar = 0.0;
    for u in [0.8, 0.9, 1.0, 1.1] {
        let mut s = 0.0;
        for k in 1399..=1499 {
            let tk = k as f64 * 1e-3;
            s += (cart_step_position(u, tk + 1e-3) - cart_step_position(u, tk - 1e-3)) / 2e-3;
        }
        kbar += s / 101.0 / u / 4.0;
    }
    let kbar = (kbar * 1e3).round() / 1e3;
    let t_cross = -(1.0f64 - 0.632).ln() / AC;
    let tbar = (t_cross * 1e3).floor() / 1e3;
    assert!((num(&out, "ac_unquantised") - 1.0 / tbar).abs() < 1e-9);
    assert!((num(&out, "bc_unquantised") - kbar / tbar).abs() < 1e-9);
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
    // p1c224_i_pdcont.m: (alpha1, alpha2) = (3, 3), (2, 2), (2.15, 1.75) (lines 39-40, 54-55,
    // 68-69); kP = alpha1 ω_n²/b, kD = (alpha2 ω_n − a)/b (lines 43-44, 58-59, 72-73).
    for (name, alpha1, alpha2) in [
        ("gains_binomial", 3.0, 3.0),
        ("gains_butterworth", 2.0, 2.0),
        ("gains_itae", 2.15, 1.75),
    ] {
        let g = vector(&out, name);
        let (ki, kp, kd) = (g[0], g[1], g[2]);
        // s³ + (a_c + b_c k_D) s² + b_c k_P s + b_c k_I = s³ + α₂ω_n s² + α₁ω_n² s + ω_n³.
        assert!((AC + BC * kd - alpha2 * wn).abs() < 1e-12, "{name}");
        assert!((BC * kp - alpha1 * wn * wn).abs() < 1e-10, "{name}");
        assert!((BC * ki - wn.powi(3)).abs() < 1e-10, "{name}");
    }
    // The ITAE gains by hand: [1000/4.36, 215/4.36, 11.25/4.36] = [229.358, 49.312, 2.580].
    references_reproduced(&out);
    let itae = vector(&out, "gains_itae");
    for (g, want) in itae.iter().zip([229.358, 49.312, 2.580]) {
        assert!((g - want).abs() < 0.0005, "{itae:?}");
    }
    assert_eq!(vector(&out, "alpha1"), vec![3.0, 2.0, 2.15]);
    assert_eq!(vector(&out, "alpha2"), vec![3.0, 2.0, 1.75]);
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
    let ids = [
        "p1c211_pcont",
        "p1c213_pidbode",
        "p1c221_id_cart",
        "p1c23_crane",
    ];
    let files = assert_figures_written(&dir, &ids);
    // The crane example also animates its run.
    assert!(files[3].iter().any(|f| f.extension().unwrap() == "gif"));
}
