//! The book's linear-analysis examples (book part 1 ch. 2, 4–7): eigenvalues,
//! stability, controllability/observability, canonical form, closed-loop poles and
//! steady-state errors by the final-value theorem.

mod sys_support;

use pendulab_lti::analysis::{
    controllability_staircase, controllable_canonical_form, ctrb, obsv, pbh_controllability, rank,
};
use pendulab_lti::interconnect::{FeedbackSign, feedback_tf, series_tf};
use pendulab_lti::{Continuous, Mat, StateSpace, TransferFunction};
use sys_support::{AC, BC, G, JP, LP, MP, MUP, assert_same_poles, c, cdip, mat};

fn ss_a(a: Mat) -> StateSpace<Continuous> {
    let n = a.nrows();
    StateSpace::continuous(a, Mat::zeros(n, 1), Mat::zeros(1, n), Mat::zeros(1, 1)).unwrap()
}

#[test]
fn cdip_open_loop_eigenvalues() {
    // docs/model.md §1: open-loop eigenvalues 0, −6.25, +5.7543, −5.7867 (4 decimals).
    let (a, b) = cdip();
    let sys = StateSpace::continuous(a, b, Mat::identity(4, 4), Mat::zeros(4, 1)).unwrap();
    assert_same_poles(
        &sys.poles().unwrap(),
        &[c(0.0, 0.0), c(-6.25, 0.0), c(5.7543, 0.0), c(-5.7867, 0.0)],
        5e-5,
    );
    assert!(!sys.is_stable().unwrap());
    // Cart fixed, upright: (−ζ ± √(ζ² + 1)) ω_np (book eq. 4.45), with ω_np = √(m g l/J),
    // ζ = μ/(2 ω_np J): the θ-block of A is exactly that second-order system.
    let j = JP + MP * LP * LP;
    let wn = (MP * G * LP / j).sqrt();
    let z = MUP / (2.0 * wn * j);
    let want = [
        (-z + (z * z + 1.0).sqrt()) * wn,
        (-z - (z * z + 1.0).sqrt()) * wn,
    ];
    let blk = mat(2, 2, &[0.0, 1.0, MP * G * LP / j, -MUP / j]);
    assert_same_poles(
        &ss_a(blk).poles().unwrap(),
        &[c(want[0], 0.0), c(want[1], 0.0)],
        1e-12,
    );
}

#[test]
fn p1c43_stability1() {
    let a = mat(
        5,
        5,
        &[
            0.0, -1.0, 0.0, 0.0, -1.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 1.0, 0.0, 1.0, 0.0, 1.0,
            -1.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, -1.0,
        ],
    );
    let sys = ss_a(a);
    // Book: 0.906 ± 0.934j, 1, −0.426, −1.387 (3 decimals: half a unit, 5e-4).
    assert_same_poles(
        &sys.poles().unwrap(),
        &[
            c(0.906, 0.934),
            c(0.906, -0.934),
            c(1.0, 0.0),
            c(-0.426, 0.0),
            c(-1.387, 0.0),
        ],
        5e-4 * 2f64.sqrt(),
    );
    assert!(!sys.is_stable().unwrap());
    assert!(sys.stability_margin().unwrap() > 0.9);
}

#[test]
fn p1c43_stability2_eigenvalues() {
    let a = mat(
        5,
        5,
        &[
            -1.0, -1.0, -1.0, -1.0, 0.0, 1.0, -1.0, -1.0, 0.0, -1.0, 1.0, 0.0, 0.0, -1.0, 0.0, 1.0,
            -1.0, 1.0, 0.0, -1.0, -1.0, 1.0, -1.0, 1.0, 0.0,
        ],
    );
    let sys = ss_a(a);
    // Book: −0.0220 ± 1.8470j, −0.7737 ± 1.5071j, −0.4085 (4 decimals).
    assert_same_poles(
        &sys.poles().unwrap(),
        &[
            c(-0.0220, 1.8470),
            c(-0.0220, -1.8470),
            c(-0.7737, 1.5071),
            c(-0.7737, -1.5071),
            c(-0.4085, 0.0),
        ],
        5e-5 * 2f64.sqrt(),
    );
    assert!(sys.is_stable().unwrap());
}

#[test]
fn p1c511_ex1_and_ex2_controllability() {
    // Ex. 1: A = [[1, 0], [1, 1]], B = [1; 1]: M_c = [B, AB] = [[1, 1], [1, 2]], rank 2.
    let a = mat(2, 2, &[1.0, 0.0, 1.0, 1.0]);
    let b = mat(2, 1, &[1.0, 1.0]);
    let mc = ctrb(&a, &b).unwrap();
    assert_eq!(mc, mat(2, 2, &[1.0, 1.0, 1.0, 2.0]));
    assert_eq!(rank(&mc).rank, 2);
    assert_eq!(
        controllability_staircase(&a, &b, None)
            .unwrap()
            .controllable_dimension,
        2
    );
    // Ex. 2 (a = 1): A = [[1, 0, 0], [0, 0, 1], [0, 0, 0]], B = [0; 0; 1]: rank 2; the mode
    // at 1 is the uncontrollable one (its PBH margin is zero), and it is unstable.
    let a = mat(3, 3, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
    let b = mat(3, 1, &[0.0, 0.0, 1.0]);
    assert_eq!(rank(&ctrb(&a, &b).unwrap()).rank, 2);
    let st = controllability_staircase(&a, &b, None).unwrap();
    assert_eq!(st.controllable_dimension, 2);
    assert_same_poles(&st.uncontrollable_modes().unwrap(), &[c(1.0, 0.0)], 1e-15);
    let pbh = pbh_controllability(&a, &b).unwrap();
    let m1 = pbh
        .modes
        .iter()
        .find(|m| (m.eigenvalue - c(1.0, 0.0)).norm() < 1e-12)
        .unwrap();
    assert!(m1.margin < 1e-15);
    let sys = StateSpace::continuous(a, b, Mat::identity(3, 3), Mat::zeros(3, 1)).unwrap();
    assert!(!sys.is_controllable().unwrap());
    assert!(!sys.is_stabilizable().unwrap());
}

#[test]
fn p1c512_ex5_controllable_canonical_form() {
    // Example 5.1 → T = [[−1, 1], [0, 1]], Â = [[0, 1], [−1, 2]] with x = T x̂
    // (Â = T⁻¹AT, B̂ = T⁻¹B = [0; 1]). Here T = T⁻¹, so the check that also B̂ = [0; 1]
    // and A T = T Â pins the convention.
    let a = mat(2, 2, &[1.0, 0.0, 1.0, 1.0]);
    let b = mat(2, 1, &[1.0, 1.0]);
    let sys = StateSpace::continuous(
        a.clone(),
        b.clone(),
        mat(1, 2, &[1.0, 0.0]),
        Mat::zeros(1, 1),
    )
    .unwrap();
    let f = controllable_canonical_form(&sys).unwrap();
    // Exact small integers; characteristic polynomial from eigenvalues 1, 1 (a double root,
    // computed to ~1e-8 by the eigen-solver but symmetric, so the coefficients are exact to
    // rounding): 1e-12.
    assert!(
        (&f.t - mat(2, 2, &[-1.0, 1.0, 0.0, 1.0])).norm() < 1e-12,
        "{}",
        f.t
    );
    assert!((f.system.a() - mat(2, 2, &[0.0, 1.0, -1.0, 2.0])).norm() < 1e-12);
    assert_eq!(f.system.b(), &mat(2, 1, &[0.0, 1.0]));
    assert!((&a * &f.t - &f.t * f.system.a()).norm() < 1e-12);
    assert!((&f.t * f.system.b() - &b).norm() < 1e-12);
    assert!(f.residual < 1e-12);
}

#[test]
fn canonical_form_of_the_cart_pendulum_preserves_the_system() {
    // Invariants: same transfer function (frequency response), companion structure.
    let (a, b) = cdip();
    let sys =
        StateSpace::continuous(a, b, mat(1, 4, &[1.0, 0.0, 0.0, 0.0]), Mat::zeros(1, 1)).unwrap();
    let f = controllable_canonical_form(&sys).unwrap();
    for w in [0.3, 2.0, 9.0] {
        let s = c(0.0, w);
        let g0 = sys.evaluate(s).unwrap()[(0, 0)];
        let g1 = f.system.evaluate(s).unwrap()[(0, 0)];
        // T has condition f.condition; the transformation loses that many digits at most.
        assert!((g0 - g1).norm() < 1e-13 * f.condition * g0.norm());
    }
    // y = z is not observable (p1c74_ex2), so the observable form is refused; y = z + θ is.
    assert!(pendulab_lti::analysis::observable_canonical_form(&sys).is_err());
    let (a, b) = cdip();
    let sys =
        StateSpace::continuous(a, b, mat(1, 4, &[1.0, 1.0, 0.0, 0.0]), Mat::zeros(1, 1)).unwrap();
    let obs = pendulab_lti::analysis::observable_canonical_form(&sys).unwrap();
    assert_eq!(obs.system.c(), &mat(1, 4, &[0.0, 0.0, 0.0, 1.0]));
    let g0 = sys.evaluate(c(0.0, 1.0)).unwrap()[(0, 0)];
    let g1 = obs.system.evaluate(c(0.0, 1.0)).unwrap()[(0, 0)];
    assert!((g0 - g1).norm() < 1e-13 * obs.condition * g0.norm());
}

/// Cart drive P(s) = b_c/(s² + a_c s) (book ch. 6).
fn cart_drive() -> TransferFunction<Continuous> {
    TransferFunction::continuous(&[BC], &[1.0, AC, 0.0]).unwrap()
}

#[test]
fn p1c211_and_p1c62_ex1_p_control() {
    // Closed loop of k_P P: s² + a_c s + b_c k_P, poles (−a_c ± √(a_c² − 4 b_c k_P))/2.
    for kp in [5.0f64, 10.0, 20.0] {
        let c_tf = TransferFunction::gain(kp, Continuous).unwrap();
        let l = series_tf(&c_tf, &cart_drive()).unwrap();
        let one = TransferFunction::gain(1.0, Continuous).unwrap();
        let t = feedback_tf(&l, &one, FeedbackSign::Negative).unwrap();
        let disc = pendulab_lti::Complex64::new(AC * AC - 4.0 * BC * kp, 0.0).sqrt();
        let p1 = (c(-AC, 0.0) + disc) / 2.0;
        let p2 = (c(-AC, 0.0) - disc) / 2.0;
        assert_same_poles(&t.poles().unwrap(), &[p1, p2], 1e-12);
        if kp == 10.0 {
            // Book: −3.125 ± 5.817j (3 decimals).
            assert_same_poles(
                &t.poles().unwrap(),
                &[c(-3.125, 5.817), c(-3.125, -5.817)],
                5e-4,
            );
            // e∞ for r = 0.5 step: 0.5·S(0), S = 1/(1 + L) (final-value theorem); book: 0.
            let s = feedback_tf(&one, &l, FeedbackSign::Negative).unwrap();
            assert_eq!(0.5 * s.dc_gain().unwrap(), 0.0);
        }
    }
}

#[test]
fn p1c62_ex2_pi_ramp() {
    // C = k_P + k_I/s = (k_P s + k_I)/s, k_P = 10, k_I = 15: poles of
    // s³ + a_c s² + b_c k_P s + b_c k_I; book: −2.203 ± 5.534j, −1.843; ramp 0.1 t → e∞ = 0.
    let ctf = TransferFunction::continuous(&[10.0, 15.0], &[1.0, 0.0]).unwrap();
    let l = series_tf(&ctf, &cart_drive()).unwrap();
    let one = TransferFunction::gain(1.0, Continuous).unwrap();
    let t = feedback_tf(&l, &one, FeedbackSign::Negative).unwrap();
    assert_same_poles(
        &t.poles().unwrap(),
        &[c(-2.203, 5.534), c(-2.203, -5.534), c(-1.843, 0.0)],
        5e-4 * 2f64.sqrt(),
    );
    // Final-value theorem: e∞ = lim_{s→0} s · S(s) · 0.1/s² = 0.1 · (S(s)/s)|₀.
    let s_tf = feedback_tf(&one, &l, FeedbackSign::Negative).unwrap();
    let integ = TransferFunction::continuous(&[1.0], &[1.0, 0.0]).unwrap();
    let e = 0.1 * series_tf(&s_tf, &integ).unwrap().dc_gain().unwrap();
    assert_eq!(e, 0.0);
}

#[test]
fn p1c62_ex3_ex4_disturbance_steady_state_error() {
    // Input disturbance d0 = 3 V: e∞ = −d0 · [P/(1 + CP)](0). P control: −d0/k_P = −0.3 m
    // (book); PI: 0 (book; the integrator rejects a constant disturbance).
    let p = cart_drive();
    let c_p = TransferFunction::gain(10.0, Continuous).unwrap();
    let td = feedback_tf(&p, &c_p, FeedbackSign::Negative).unwrap();
    let e3 = -3.0 * td.dc_gain().unwrap();
    assert!((e3 - (-0.3)).abs() < 1e-14, "{e3}");
    let c_pi = TransferFunction::continuous(&[10.0, 15.0], &[1.0, 0.0]).unwrap();
    let td = feedback_tf(&p, &c_pi, FeedbackSign::Negative).unwrap();
    let e4 = -3.0 * td.dc_gain().unwrap();
    assert_eq!(e4, 0.0);
    // The same through state space: the disturbance-to-output closed loop's DC gain.
    let ps = p.to_state_space().unwrap();
    let cs = c_p.to_state_space().unwrap();
    let loop_ss = pendulab_lti::interconnect::feedback(&ps, &cs, FeedbackSign::Negative).unwrap();
    assert!((loop_ss.dc_gain().unwrap()[(0, 0)] - 0.1).abs() < 1e-14);
}

#[test]
fn p1c74_ex2_observability_ranks_and_p1c75_detectability() {
    let (a, b) = cdip();
    let cz = mat(1, 4, &[1.0, 0.0, 0.0, 0.0]);
    let cth = mat(1, 4, &[0.0, 1.0, 0.0, 0.0]);
    // Book: rank M_o = 2 for y = z, 3 for y = θ.
    assert_eq!(rank(&obsv(&a, &cz).unwrap()).rank, 2);
    assert_eq!(rank(&obsv(&a, &cth).unwrap()).rank, 3);
    for (cm, obs_dim) in [(&cz, 2), (&cth, 3)] {
        let st = controllability_staircase(&a.transpose(), &cm.transpose(), None).unwrap();
        assert_eq!(st.controllable_dimension, obs_dim);
        let sys =
            StateSpace::continuous(a.clone(), b.clone(), cm.clone(), Mat::zeros(1, 1)).unwrap();
        // Book p1c75: neither output makes the pair detectable (y = z misses the unstable
        // pendulum mode, y = θ misses the cart's integrator at 0).
        assert!(!sys.is_observable().unwrap());
        assert!(!sys.is_detectable().unwrap());
        assert!(sys.is_stabilizable().unwrap());
        assert!(sys.is_controllable().unwrap());
    }
    // With both outputs it is observable (hence detectable).
    let both = mat(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let sys = StateSpace::continuous(a, b, both, Mat::zeros(2, 1)).unwrap();
    assert!(sys.is_observable().unwrap() && sys.is_detectable().unwrap());
}

#[test]
fn p1c511_ex4_two_pendulums_on_one_cart() {
    // State [z, θ₁, θ₂, ż, θ̇₁, θ̇₂]; each pendulum J_i θ̈_i = m_i g l_i θ_i − μ θ̇_i − m_i l_i z̈
    // with z̈ = −a_c ż + b_c v (`docs/model.md` §1, linearised). Identical pendulums: θ₁ − θ₂ obeys
    // an input-free equation, so a 2-dimensional subspace is uncontrollable (rank 4).
    let build = |scale: f64| {
        let (m2, l2, j2p) = (MP * scale, LP * scale, JP * scale.powi(3));
        let mut a = Mat::zeros(6, 6);
        let mut b = Mat::zeros(6, 1);
        for k in 0..3 {
            a[(k, k + 3)] = 1.0;
        }
        a[(3, 3)] = -AC;
        b[(3, 0)] = BC;
        for (i, (m, l, jp)) in [(MP, LP, JP), (m2, l2, j2p)].into_iter().enumerate() {
            let j = jp + m * l * l;
            a[(4 + i, 1 + i)] = m * G * l / j;
            a[(4 + i, 4 + i)] = -MUP / j;
            a[(4 + i, 3)] = m * l * AC / j;
            b[(4 + i, 0)] = -m * l * BC / j;
        }
        (a, b)
    };
    let (a, b) = build(1.2);
    assert_eq!(
        controllability_staircase(&a, &b, None)
            .unwrap()
            .controllable_dimension,
        6
    );
    let (a, b) = build(1.0);
    assert_eq!(
        controllability_staircase(&a, &b, None)
            .unwrap()
            .controllable_dimension,
        4
    );
}

#[test]
fn damping_of_book_poles() {
    // k_P = 10 cart loop: s² + 6.25 s + 43.6 → ωn = √43.6, ζ = 6.25/(2√43.6) (closed form).
    let sys = cart_drive();
    let kp = TransferFunction::gain(10.0, Continuous).unwrap();
    let one = TransferFunction::gain(1.0, Continuous).unwrap();
    let cl = feedback_tf(&series_tf(&kp, &sys).unwrap(), &one, FeedbackSign::Negative)
        .unwrap()
        .to_state_space()
        .unwrap();
    for d in cl.damp().unwrap() {
        assert!((d.natural_frequency - 43.6f64.sqrt()).abs() < 1e-12);
        assert!((d.damping_ratio - 6.25 / (2.0 * 43.6f64.sqrt())).abs() < 1e-12);
        assert!((d.time_constant - 1.0 / 3.125).abs() < 1e-12);
    }
    // Discrete: a pole z = e^{s ts} maps back to s.
    let s = c(-3.125, 5.8167);
    let z = (s * 0.01).exp();
    let dsys = StateSpace::discrete(
        mat(2, 2, &[z.re, -z.im, z.im, z.re]),
        Mat::zeros(2, 1),
        Mat::zeros(1, 2),
        Mat::zeros(1, 1),
        0.01,
    )
    .unwrap();
    for d in dsys.damp().unwrap() {
        assert!((d.natural_frequency - s.norm()).abs() < 1e-10);
        assert!((d.damping_ratio - 3.125 / s.norm()).abs() < 1e-10);
    }
}

#[test]
fn controllability_decisions_are_scale_invariant() {
    // The cart pendulum in badly chosen units (every entry scaled by 1e-12 or 1e12) is still
    // controllable; p1c511_ex2 scaled likewise is still uncontrollable.
    let (a, b) = cdip();
    for s in [1e-12, 1e12] {
        let st = controllability_staircase(&(&a * s), &(&b * s), None).unwrap();
        assert_eq!(st.controllable_dimension, 4, "scale {s}");
        let a2 = mat(3, 3, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]) * s;
        let b2 = mat(3, 1, &[0.0, 0.0, 1.0]) * s;
        assert_eq!(
            controllability_staircase(&a2, &b2, None)
                .unwrap()
                .controllable_dimension,
            2
        );
    }
}
