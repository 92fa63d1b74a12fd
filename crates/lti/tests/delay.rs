//! Padé and Thiran delay approximations against closed forms and python-control's `pade`
//! (fixture of `tools/reference/tf_python.py`, python-control 0.10.2).

use pendulab_lti::delay::{pade, thiran, thiran_with_order};
use pendulab_lti::{Complex64, LtiError, TransferFunction};
use pendulab_testkit::json::vector;
use std::path::Path;

fn fixture() -> serde_json::Value {
    pendulab_testkit::json::read(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/tf_reference.json"),
    )
}

#[test]
fn pade_first_order_is_the_closed_form() {
    // (1 − sT/2)/(1 + sT/2) = (−s + 2/T)/(s + 2/T).
    for t in [0.01, 0.3, 2.5] {
        let g = pade(t, 1).unwrap();
        let want = TransferFunction::continuous(&[-1.0, 2.0 / t], &[1.0, 2.0 / t]).unwrap();
        for (x, y) in g.num().coefficients().iter().zip(want.num().coefficients()) {
            assert!((x - y).abs() <= 1e-14 * y.abs().max(1.0), "{g}");
        }
        assert_eq!(g.den().coefficients(), want.den().coefficients());
    }
}

#[test]
fn pade_matches_python_control() {
    let f = fixture();
    for case in f["pade"].as_array().unwrap() {
        let t = case["T"].as_f64().unwrap();
        let n = case["n"].as_u64().unwrap() as usize;
        let g = pade(t, n).unwrap();
        for (ours, key) in [(g.num(), "num"), (g.den(), "den")] {
            let want = vector(&case[key]);
            assert_eq!(ours.coefficients().len(), want.len(), "T = {t}, n = {n}");
            for (x, y) in ours.coefficients().iter().zip(&want) {
                assert!(
                    (x - y).abs() <= 1e-13 * y.abs().max(1.0),
                    "T = {t}, n = {n} {key}: {x} vs {y}"
                );
            }
        }
    }
}

#[test]
fn pade_is_all_pass_with_phase_error_of_order_2n_plus_1() {
    let t = 0.7;
    // ωT per order: small enough for the leading term to dominate, large enough for the
    // error at ω/2 to stay far above rounding (≥ 1e-14).
    for (n, wt) in [(1, 0.2), (2, 0.2), (3, 0.5), (4, 1.0), (5, 1.0)] {
        let g = pade(t, n).unwrap();
        // Phase error at ω and ω/2: the ratio tends to 2^{2n+1} as ω → 0.
        let err = |w: f64| {
            let v = g.eval(Complex64::new(0.0, w));
            assert!((v.norm() - 1.0).abs() < 1e-13, "all-pass at {w}");
            (v * Complex64::from_polar(1.0, w * t)).arg()
        };
        let w = wt / t;
        let ratio = err(w) / err(w / 2.0);
        let want = 2f64.powi(2 * n as i32 + 1);
        assert!(
            (ratio / want - 1.0).abs() < 0.03,
            "n = {n}: ratio {ratio}, want {want}"
        );
    }
}

#[test]
fn pade_rejects_bad_arguments_and_zero_delay_is_unity() {
    assert!(matches!(pade(-0.1, 2), Err(LtiError::InvalidArgument(_))));
    assert!(matches!(
        pade(f64::NAN, 2),
        Err(LtiError::InvalidArgument(_))
    ));
    assert!(matches!(
        pade(f64::INFINITY, 2),
        Err(LtiError::InvalidArgument(_))
    ));
    assert!(matches!(pade(0.1, 0), Err(LtiError::InvalidArgument(_))));
    let g = pade(0.0, 3).unwrap();
    assert_eq!(g.num().coefficients(), &[1.0]);
    assert_eq!(g.den().coefficients(), &[1.0]);
}

/// Group delay at ω = 0 of `B(z)/A(z)` (coefficients in descending powers of `z`, equal
/// lengths after padding): with `b_k`, `a_k` the coefficients of `z^{−k}`,
/// `τ(0) = Σ k b_k / Σ b_k − Σ k a_k / Σ a_k`.
fn dc_group_delay(g: &TransferFunction<pendulab_lti::Discrete>) -> f64 {
    let (num, den) = (g.num().coefficients(), g.den().coefficients());
    let len = num.len().max(den.len());
    let moment = |c: &[f64]| {
        let pad = len - c.len();
        let (mut s0, mut s1) = (0.0, 0.0);
        for (i, &v) in c.iter().enumerate() {
            let k = (pad + i) as f64;
            s0 += v;
            s1 += k * v;
        }
        s1 / s0
    };
    moment(num) - moment(den)
}

#[test]
fn thiran_first_order_is_the_closed_form() {
    // N = 1: a₁ = (1 − d)/(1 + d), H = (a₁ z + 1)/(z + a₁).
    for d in [0.3, 0.5, 0.9] {
        let ts = 0.01;
        let g = thiran(d * ts, ts).unwrap();
        let a1 = (1.0 - d) / (1.0 + d);
        let (num, den) = (g.num().coefficients(), g.den().coefficients());
        assert!(
            (num[0] - a1).abs() < 1e-14 && (num[1] - 1.0).abs() < 1e-14,
            "{g}"
        );
        assert!(
            (den[0] - 1.0).abs() < 1e-15 && (den[1] - a1).abs() < 1e-14,
            "{g}"
        );
    }
}

#[test]
fn thiran_group_delay_at_dc_is_the_delay_and_maximally_flat() {
    let ts = 0.002;
    for (tau, order) in [
        (0.0057, None),
        (0.0031, None),
        (0.0123, Some(2)),
        (0.0091, Some(3)),
    ] {
        let g = match order {
            None => thiran(tau, ts).unwrap(),
            Some(n) => thiran_with_order(tau, ts, n).unwrap(),
        };
        let d = tau / ts;
        assert!((dc_group_delay(&g) - d).abs() < 1e-10, "{tau}: {g}");
        // All-pass part: |H| = 1 on the unit circle; stable.
        let v = g.eval(Complex64::from_polar(1.0, 0.7));
        assert!((v.norm() - 1.0).abs() < 1e-12);
        assert!(g.is_stable().unwrap());
        // Maximal flatness: the phase error against e^{−jωd} shrinks as ω^{2N+1}.
        let n = order.unwrap_or(d.ceil() as usize) as i32;
        let err = |w: f64| {
            (g.eval(Complex64::from_polar(1.0, w)) * Complex64::from_polar(1.0, w * d)).arg()
        };
        let ratio = err(0.1) / err(0.05);
        let want = 2f64.powi(2 * n + 1);
        assert!(
            (ratio / want - 1.0).abs() < 0.05,
            "{tau}: {ratio} vs {want}"
        );
    }
}

#[test]
fn thiran_integer_delay_is_a_pure_delay_and_errors_are_typed() {
    let g = thiran(0.03, 0.01).unwrap();
    assert_eq!(g.num().coefficients(), &[1.0]);
    assert_eq!(g.den().coefficients(), &[1.0, 0.0, 0.0, 0.0]);
    // Order 1 with a delay of 3.4 samples: z^{−3} times a first-order filter for d = 0.4.
    let g = thiran_with_order(0.034, 0.01, 1).unwrap();
    assert_eq!(g.den().degree(), 4);
    assert!(matches!(
        thiran(-1.0, 0.1),
        Err(LtiError::InvalidArgument(_))
    ));
    assert!(matches!(
        thiran(0.1, 0.0),
        Err(LtiError::InvalidSampleTime(_))
    ));
    assert!(matches!(
        thiran_with_order(0.015, 0.01, 3),
        Err(LtiError::InvalidArgument(_))
    ));
    assert!(matches!(
        thiran_with_order(0.015, 0.01, 0),
        Err(LtiError::InvalidArgument(_))
    ));
}
