//! `care_compact` (the compact small-order CARE: sign function, Newton–Kleinman, Hessenberg
//! QR poles) against the general `care` and by the defining residual: the book's cart and arm
//! weights (the cart's servo on `[x; w]` too) and random stabilisable systems of every order
//! 1–6; the refusals hand over to the general solver (its errors, its solution). The warm
//! start `care_compact_from` on slider walks and perturbed random problems, from a
//! non-stabilising gain, and its refusals.

use pendulab_lti::Mat;
use pendulab_lti::equations::riccati::{
    COMPACT_MAX, CompactCare, care_compact, care_compact_from, care_residual,
};
use pendulab_lti::equations::{RiccatiOptions, care};
use pendulab_lti::linalg::diag;
use pendulab_lti::linalg::eigenvalues;
use pendulab_lti::random::SplitMix64;
use pendulab_lti::{Complex64, LtiError};
use pendulab_testkit::{arm, cart};
use riccati_support::{cart_servo, move_slider, rows};

mod riccati_support;

/// The compact result checked against the general solver on the same data: the relative
/// residual recomputed by `care_residual` ≤ 1e-12, the gain and `X` within 1e-10 of the
/// general solver's (relative, Frobenius), the poles those of `eig(A − BK)` (general
/// eigenvalue routine) within 1e-10 relative. Returns whether the compact path answered.
fn agrees(a: &Mat, b: &Mat, q: &Mat, r: &Mat, what: &str) -> bool {
    let c = care_compact(&rows(a), &rows(b), &rows(q), &rows(r), a.nrows()).unwrap();
    agrees_with(&c, a, b, q, r, what)
}

/// [`agrees`] for a result `c` already computed (by either entry point).
fn agrees_with(c: &CompactCare, a: &Mat, b: &Mat, q: &Mat, r: &Mat, what: &str) -> bool {
    let n = a.nrows();
    let g = care(a, b, q, r, None, &RiccatiOptions::default()).unwrap();
    let x = Mat::from_row_slice(n, n, c.x());
    let k = Mat::from_row_slice(b.ncols(), n, c.gain());
    let res = care_residual(a, b, q, r, None, &x);
    assert!(
        res <= 1e-12 && c.residual <= 1e-12,
        "{what}: residual {res:e} / {:e}",
        c.residual
    );
    let rel = |p: &Mat, q: &Mat| (p - q).norm() / q.norm().max(f64::MIN_POSITIVE);
    assert!(rel(&k, &g.gain) <= 1e-10, "{what}: gain {k} vs {}", g.gain);
    assert!(
        rel(&x, &g.x) <= 1e-10,
        "{what}: X differs by {:e}",
        rel(&x, &g.x)
    );
    assert_eq!((&x - x.transpose()).norm(), 0.0, "{what}: X not symmetric");
    let want = eigenvalues(&(a - b * &k)).unwrap();
    let scale = want.iter().map(|p| p.norm()).fold(1.0, f64::max);
    assert_eq!(c.poles().len(), n);
    for (p, w) in c.poles().iter().zip(&want) {
        assert!(
            (p - w).norm() <= 1e-10 * scale,
            "{what}: poles {:?} vs {want:?}",
            c.poles()
        );
    }
    assert!(c.poles().iter().all(|p| p.re < 0.0));
    !c.general
}

#[test]
fn book_cart_and_arm_weights_match_the_general_solver() {
    let (a, b) = cart::upright();
    let (q, r) = cart::lqr_weights();
    assert!(agrees(&a, &b, &q, &r, "cart Q = diag(10, 10, 0, 0)"));
    // The arm with the IP Toolbox's `adip_lqr_sim` weights.
    let (a2, b2) = arm::ArmParams::book().linearization(0.0);
    assert!(agrees(
        &a2,
        &b2,
        &diag(&[5.0, 10.0, 0.1, 0.1]),
        &diag(&[1.0]),
        "arm"
    ));
    // The cart's LQ integral servo on [x; w], w = ∫(r − z): A_aug = [A 0; −C 0], B_aug = [B; 0].
    let (aa, bb) = cart_servo();
    assert!(agrees(
        &aa,
        &bb,
        &diag(&[1.0, 5.0, 0.0, 0.0, 100.0]),
        &diag(&[1.0]),
        "cart servo"
    ));
    // The sliders' extremes (weights over eight decades): the compact path answers the
    // moderate ones; very cheap control (R = 1e-3 against Q = 1e4, a strongly non-normal
    // closed loop) may go to the general solver, and either way the result agrees with it.
    for (qs, rs, compact) in [(1e-4, 1e3, true), (1e3, 1.0, true), (1e4, 1e-3, false)] {
        let q = diag(&[qs, qs, 0.0, 0.0]);
        let answered = agrees(
            &a,
            &b,
            &q,
            &diag(&[rs]),
            &format!("cart q = {qs}, r = {rs}"),
        );
        assert!(
            answered || !compact,
            "q = {qs}, r = {rs}: the general solver answered"
        );
    }
    // Q = 0 leaves the cart's pole at 0 undetectable: no stabilising solution, the general
    // solver's error.
    let e = care_compact(&rows(&a), &rows(&b), &[0.0; 16], &[1.0], 4).unwrap_err();
    assert!(matches!(e, LtiError::NotDetectable { .. }), "{e}");
}

/// A random stabilisable (generically controllable) `(A, B)` with `n` states and `m`
/// inputs, `Q = CᵀC` with a random `C` (rank ≤ n, so semidefinite) and a random `R ≻ 0`.
fn random_problem(rng: &mut SplitMix64, n: usize, m: usize) -> (Mat, Mat, Mat, Mat) {
    let a = rng.matrix(n, n) * 2.0;
    let b = rng.matrix(n, m);
    let c = rng.matrix(n.max(2) - 1, n);
    let s = rng.matrix(m, m);
    (
        a,
        b,
        c.transpose() * &c,
        &s * s.transpose() + Mat::identity(m, m) * 0.1,
    )
}

/// [`random_problem`]s of every order 1–6 with 1–3 inputs.
#[test]
fn random_small_systems_match_the_general_solver() {
    let mut rng = SplitMix64::new(20261206);
    let (mut compact, mut total) = (0, 0);
    for n in 1..=COMPACT_MAX {
        for m in 1..=n.min(3) {
            for trial in 0..12 {
                let (a, b, q, r) = random_problem(&mut rng, n, m);
                total += 1;
                if agrees(&a, &b, &q, &r, &format!("n = {n}, m = {m}, trial {trial}")) {
                    compact += 1;
                }
            }
        }
    }
    // The compact path answers (nearly) every one of these well-conditioned problems.
    assert!(
        compact * 10 >= total * 9,
        "compact path answered {compact} of {total}"
    );
}

/// The Hessenberg QR's complex pairs: a closed loop with known poles. `A` in controllable
/// companion form with `Q = 0` mirrors the unstable poles (`X` stabilising, `Q = 0`: the
/// closed-loop poles are the open-loop ones with the unstable ones reflected, `−conj λ`).
#[test]
fn zero_weight_reflects_the_unstable_poles() {
    // Open-loop poles 1 ± 2j, −3, 0.5: characteristic polynomial coefficients.
    let roots = [
        Complex64::new(1.0, 2.0),
        Complex64::new(1.0, -2.0),
        Complex64::new(-3.0, 0.0),
        Complex64::new(0.5, 0.0),
    ];
    let mut coeff = vec![Complex64::new(1.0, 0.0)];
    for z in roots {
        let mut next = vec![Complex64::new(0.0, 0.0); coeff.len() + 1];
        for (i, c) in coeff.iter().enumerate() {
            next[i] += c;
            next[i + 1] -= c * z;
        }
        coeff = next;
    }
    let mut a = Mat::zeros(4, 4);
    for i in 0..3 {
        a[(i, i + 1)] = 1.0;
    }
    for j in 0..4 {
        a[(3, j)] = -coeff[4 - j].re;
    }
    let mut b = Mat::zeros(4, 1);
    b[(3, 0)] = 1.0;
    let c = care_compact(&rows(&a), &rows(&b), &[0.0; 16], &[1.0], 4).unwrap();
    assert!(!c.general);
    let want = [(-0.5, 0.0), (-1.0, 2.0), (-1.0, -2.0), (-3.0, 0.0)];
    for (p, (re, im)) in c.poles().iter().zip(want) {
        assert!(
            (p - Complex64::new(re, im)).norm() <= 1e-9,
            "{:?}",
            c.poles()
        );
    }
}

/// What the compact path refuses goes to the general solver, which answers with its own error
/// (or solution); lengths that do not fit are refused at once.
#[test]
fn refusals_hand_over_to_the_general_solver() {
    let (a, b) = cart::upright();
    let (q, r) = cart::lqr_weights();
    let (av, bv, qv, rv) = (rows(&a), rows(&b), rows(&q), rows(&r));
    // Not stabilisable: the unstable pendulum mode made uncontrollable (B = e₁ drives only z).
    let b0 = [1.0, 0.0, 0.0, 0.0];
    let general = care(
        &a,
        &Mat::from_row_slice(4, 1, &b0),
        &q,
        &r,
        None,
        &RiccatiOptions::default(),
    );
    let compact = care_compact(&av, &b0, &qv, &rv, 4);
    assert!(general.is_err());
    assert_eq!(
        std::mem::discriminant(&compact.unwrap_err()),
        std::mem::discriminant(&general.unwrap_err())
    );
    // A closed-loop pole on the imaginary axis: the undamped oscillator with Q = 0.
    let osc = [0.0, 1.0, -1.0, 0.0];
    let e = care_compact(&osc, &[0.0, 1.0], &[0.0; 4], &[1.0], 2).unwrap_err();
    let g = care(
        &Mat::from_row_slice(2, 2, &osc),
        &Mat::from_row_slice(2, 1, &[0.0, 1.0]),
        &Mat::zeros(2, 2),
        &Mat::identity(1, 1),
        None,
        &RiccatiOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        std::mem::discriminant(&e),
        std::mem::discriminant(&g),
        "{e} vs {g}"
    );
    // R not positive definite; Q not symmetric; a non-finite entry: the general errors.
    assert!(matches!(
        care_compact(&av, &bv, &qv, &[-1.0], 4),
        Err(LtiError::NotPositiveDefinite { .. })
    ));
    let mut qa = qv.clone();
    qa[1] = 1.0;
    assert!(matches!(
        care_compact(&av, &bv, &qa, &rv, 4),
        Err(LtiError::NotSymmetric { .. })
    ));
    let mut an = av.clone();
    an[3] = f64::NAN;
    assert!(matches!(
        care_compact(&an, &bv, &qv, &rv, 4),
        Err(LtiError::NonFinite { .. })
    ));
    // Shapes: n above COMPACT_MAX, B longer than n × n, a short Q.
    let big = vec![0.0; 49];
    assert!(matches!(
        care_compact(&big, &[1.0; 7], &big, &[1.0], 7),
        Err(LtiError::InvalidArgument(_))
    ));
    assert!(matches!(
        care_compact(&av, &[1.0; 20], &qv, &rv, 4),
        Err(LtiError::InvalidArgument(_))
    ));
    assert!(matches!(
        care_compact(&av, &bv, &qv[..15], &rv, 4),
        Err(LtiError::InvalidArgument(_))
    ));
    assert!(matches!(
        care_compact(&[], &[], &[], &[], 0),
        Err(LtiError::InvalidArgument(_))
    ));
}

/// The warm start from the previous move's gain along slider walks (the browser lab's use):
/// the cart's LQR and its servo on `[x; w]`, weights moved in steps of a tenth of a decade
/// (and larger jumps) over several decades. Every result agrees with the general solver
/// (`agrees_with`: residual, gain, `X`, poles), and the warm path answers nearly every move
/// that the compact path answers from cold.
#[test]
fn warm_start_follows_slider_walks() {
    let (a, b) = cart::upright();
    let (aa, bb) = cart_servo();
    let (mut warm, mut total) = (0, 0);
    for (a, b, q0) in [
        (&a, &b, vec![10.0, 10.0, 0.0, 0.0]),
        (&aa, &bb, vec![1.0, 5.0, 0.0, 0.0, 100.0]),
    ] {
        let n = a.nrows();
        for (slider, step) in [(0, 0.1), (1, -0.1), (2, 0.25), (usize::MAX, 0.1)] {
            let (mut q, mut r) = (q0.clone(), 1.0);
            let mut k = care_compact(&rows(a), &rows(b), &rows(&diag(&q)), &[r], n)
                .unwrap()
                .gain()
                .to_vec();
            for mv in 0..30 {
                move_slider(&mut q, &mut r, slider, 10f64.powf(step));
                let c =
                    care_compact_from(&rows(a), &rows(b), &rows(&diag(&q)), &[r], n, &k).unwrap();
                agrees_with(
                    &c,
                    a,
                    b,
                    &diag(&q),
                    &diag(&[r]),
                    &format!("n = {n}, slider {slider}, move {mv}: q = {q:?}, r = {r}"),
                );
                // Count the moves the compact path answers from cold (the others, at the
                // extremes, are the general solver's either way).
                let cold = care_compact(&rows(a), &rows(b), &rows(&diag(&q)), &[r], n).unwrap();
                if !cold.general {
                    total += 1;
                    warm += usize::from(c.warm);
                }
                k = c.gain().to_vec();
            }
        }
    }
    assert!(
        warm * 20 >= total * 19,
        "warm path answered {warm} of {total}"
    );
}

/// Random stabilisable systems of every order 1–6: the solution for perturbed weights (`Q`
/// plus a random semidefinite term, `R` scaled by 1.3) from the unperturbed solution's gain
/// agrees with the general solver, mostly by the warm path.
#[test]
fn warm_start_on_perturbed_random_problems() {
    let mut rng = SplitMix64::new(20261207);
    let (mut warm, mut total) = (0, 0);
    for n in 1..=COMPACT_MAX {
        for m in 1..=n.min(3) {
            for trial in 0..8 {
                let (a, b, q, r) = random_problem(&mut rng, n, m);
                let Ok(c0) = care_compact(&rows(&a), &rows(&b), &rows(&q), &rows(&r), n) else {
                    continue;
                };
                let d = rng.matrix(n, n) * 0.3;
                let q1 = &q + d.transpose() * &d;
                let r1 = &r * 1.3;
                let c1 =
                    care_compact_from(&rows(&a), &rows(&b), &rows(&q1), &rows(&r1), n, c0.gain())
                        .unwrap();
                agrees_with(
                    &c1,
                    &a,
                    &b,
                    &q1,
                    &r1,
                    &format!("n = {n}, m = {m}, trial {trial}"),
                );
                total += 1;
                warm += usize::from(c1.warm);
            }
        }
    }
    assert!(total >= 80, "only {total} problems");
    assert!(
        warm * 10 >= total * 8,
        "warm path answered {warm} of {total}"
    );
}

/// A starting gain that does not stabilise `(A, B)` (zero on the unstable cart, its sign
/// flipped) gives the stabilising solution all the same, not through the warm path; a gain
/// of the wrong length or with a NaN is refused with the reason.
#[test]
fn warm_start_from_a_bad_gain() {
    let (a, b) = cart::upright();
    let (q, r) = cart::lqr_weights();
    let k = care_compact(&rows(&a), &rows(&b), &rows(&q), &rows(&r), 4).unwrap();
    let flipped: Vec<f64> = k.gain().iter().map(|v| -v).collect();
    for (k0, what) in [(vec![0.0; 4], "zero gain"), (flipped, "flipped gain")] {
        let c = care_compact_from(&rows(&a), &rows(&b), &rows(&q), &rows(&r), 4, &k0).unwrap();
        assert!(
            !c.warm,
            "{what}: the warm path accepted a non-stabilising start"
        );
        agrees_with(&c, &a, &b, &q, &r, what);
    }
    for k0 in [vec![1.0; 3], vec![1.0, f64::NAN, 0.0, 0.0]] {
        let e = care_compact_from(&rows(&a), &rows(&b), &rows(&q), &rows(&r), 4, &k0).unwrap_err();
        assert!(
            matches!(&e, LtiError::InvalidArgument(s) if s.contains("starting gain")),
            "{e}"
        );
    }
}
