//! `reduction`: Hankel singular values against python-control/SciPy (fixture of
//! `tools/reference/lti_toolbox_reference.py`), `minreal`'s order against Slycot's TB01PD
//! and against the ranks of the controllability and observability matrices, and the
//! balanced realisation and truncation checked by their defining properties (equal diagonal
//! Gramians, the error bound, the matched DC gain).

mod toolbox_support;

use pendulab_lti::analysis::{GramianKind, gramian};
use pendulab_lti::frequency_response::{freqresp, logspace};
use pendulab_lti::linalg::CMat;
use pendulab_lti::norms::hinf_norm;
use pendulab_lti::reduction::{BalredMethod, balreal, balred, hsvd, minreal};
use pendulab_lti::{LtiError, Mat, StateSpace, TransferFunction, interconnect};

/// 50 systems (35 continuous, 15 discrete, orders 1–12): the Hankel singular values to
/// 1e-6 relative to σ₁ against SciPy's Gramians (square-root route); python-control's
/// `√eig(W_c W_o)` is stored too but not asserted: it loses the small values of lightly
/// damped systems (e.g. 19.1 for 15.24 with σ₁ = 4.07e4 in case 31) (entries the reference could not resolve, a negative eigenvalue of
/// `W_c W_o` by rounding, are null there and skipped).
#[test]
fn hsvd_matches_the_reference() {
    let cases = toolbox_support::cases("hsvd");
    assert_eq!(cases.len(), 50);
    for (k, case) in cases.iter().enumerate() {
        let sys = toolbox_support::system(case);
        let got = on_sys!(&sys, |s| hsvd(s).unwrap());
        let want: Vec<f64> = case["hsv"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|v| v.as_f64())
            .collect();
        assert_eq!(got.len(), case["hsv"].as_array().unwrap().len(), "case {k}");
        // The unresolved (null) entries are the smallest; the others descend from σ₁.
        let s1 = got[0];
        let mut want = want;
        want.sort_by(|a, b| b.total_cmp(a));
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() <= 1e-6 * s1, "case {k}: {got:?} vs {want:?}");
        }
    }
}

/// 30 non-minimal systems (a minimal part of order 1–6 plus 1–3 uncontrollable and 1–3
/// unobservable states, hidden by a random rotation): `minreal` returns Slycot's (TB01PD)
/// order, or one that differs only by states with negligible Hankel singular values (a near
/// cancellation decided differently at the two tools' tolerances), and the response is
/// unchanged.
#[test]
fn minreal_matches_slycot() {
    let cases = toolbox_support::cases("minreal");
    assert_eq!(cases.len(), 30);
    for (k, case) in cases.iter().enumerate() {
        let toolbox_support::Sys::C(sys) = toolbox_support::system(case) else {
            panic!("continuous cases only");
        };
        let want = case["order"].as_u64().unwrap() as usize;
        let r = minreal(&sys, None).unwrap();
        let m = r.system.nx();
        // Where the two staircases decide differently, the states one keeps and the other
        // drops are numerically negligible: their Hankel singular values are below 1e-7·σ₁.
        if m != want {
            let hsv = hsvd(&sys).unwrap();
            assert!(
                hsv[m.min(want)] <= 1e-7 * hsv[0],
                "case {k}: order {m} vs Slycot's {want}, σ = {hsv:?}"
            );
        }
        assert_eq!(r.removed_states, sys.nx() - m);
        let w = logspace(-2.0, 2.0, 40);
        let g0 = freqresp(&sys, &w).unwrap().response;
        let g1 = freqresp(&r.system, &w).unwrap().response;
        for (a, b) in g0.iter().zip(&g1) {
            assert!((a - b).norm() <= 1e-9 * a.norm().max(1.0), "case {k}");
        }
    }
}

/// A series connection with an exact pole-zero cancellation: `(s + 1)/(s + 2)` then
/// `1/(s + 1)` has one minimal state.
#[test]
fn minreal_removes_a_cancellation() {
    let g1 = TransferFunction::continuous(&[1.0, 1.0], &[1.0, 2.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let g2 = TransferFunction::continuous(&[1.0], &[1.0, 1.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let g = interconnect::series(&g1, &g2).unwrap();
    let r = minreal(&g, None).unwrap();
    assert_eq!(r.system.nx(), 1);
    assert!((r.system.a()[(0, 0)] + 2.0).abs() < 1e-12);
    assert!(matches!(
        minreal(&g, Some(-1.0)),
        Err(LtiError::InvalidArgument(_))
    ));
}

/// The matched-DC model keeps the DC gain `G(0)` (`G(1)` in discrete time).
fn assert_dc_matched<D: pendulab_lti::TimeDomain>(g: &StateSpace<D>, r: &StateSpace<D>) {
    let d0 = g.dc_gain().unwrap();
    let d1 = r.dc_gain().unwrap();
    assert!(
        (&d0 - &d1).norm() <= 1e-9 * d0.norm().max(1.0),
        "{d0} vs {d1}"
    );
}

fn max_error(
    a: &StateSpace<pendulab_lti::Continuous>,
    b: &StateSpace<pendulab_lti::Continuous>,
) -> f64 {
    let diff = interconnect::parallel(
        a,
        &StateSpace::continuous(b.a().clone(), b.b().clone(), -b.c(), -b.d()).unwrap(),
    )
    .unwrap();
    hinf_norm(&diff, 1e-8).unwrap().value
}

/// Balanced realisation: both Gramians equal `diag(σ)`; truncation and matched DC to every
/// order: `‖G − G_r‖∞ ≤ 2 Σ_{i>r} σᵢ` (with the H∞ norm of the error system), the error at
/// least `σ_{r+1}` (Glover's lower bound), the matched-DC model keeps `G(0)`.
#[test]
fn balanced_truncation_properties() {
    let mut rng = toolbox_support::Rng(5);
    for (n, p, m) in [(8, 1, 1), (10, 2, 3), (6, 3, 1)] {
        let g = toolbox_support::random_stable(&mut rng, n, p, m, 0.1);
        let b = balreal(&g).unwrap();
        let wc = gramian(&b.system, GramianKind::Controllability).unwrap().x;
        let wo = gramian(&b.system, GramianKind::Observability).unwrap().x;
        let sigma = Mat::from_diagonal(&nalgebra::DVector::from_vec(b.hsv.clone()));
        assert!((&wc - &sigma).norm() <= 1e-9 * b.hsv[0], "{wc} vs {sigma}");
        assert!((&wo - &sigma).norm() <= 1e-9 * b.hsv[0]);
        assert!((&b.t_inv * &b.t - Mat::identity(n, n)).norm() <= 1e-9);
        for r in 1..n {
            for method in [BalredMethod::Truncate, BalredMethod::MatchDc] {
                let red = balred(&g, r, method).unwrap();
                assert_eq!(red.system.nx(), r);
                assert!(red.system.is_stable().unwrap());
                let e = max_error(&g, &red.system);
                assert!(
                    e <= red.error_bound * (1.0 + 1e-6) + 1e-12,
                    "{r} {method:?}: {e} > {}",
                    red.error_bound
                );
                assert!(
                    e >= b.hsv[r] * (1.0 - 1e-6),
                    "{r} {method:?}: {e} < σ = {}",
                    b.hsv[r]
                );
                if method == BalredMethod::MatchDc {
                    assert_dc_matched(&g, &red.system);
                }
            }
        }
    }
}

/// Discrete systems: matched DC keeps `G(1)`; truncation's error obeys the same bound
/// (checked on a dense grid of the unit circle).
#[test]
fn discrete_balanced_reduction() {
    let mut rng = toolbox_support::Rng(8);
    let c = toolbox_support::random_stable(&mut rng, 7, 2, 2, 0.2);
    let d = pendulab_lti::discretization::Discretization::Zoh;
    let g = c.c2d(0.1, d).unwrap();
    let hsv = hsvd(&g).unwrap();
    for r in [2, 4] {
        for method in [BalredMethod::Truncate, BalredMethod::MatchDc] {
            let red = balred(&g, r, method).unwrap();
            let w = logspace(-3.0, (std::f64::consts::PI / 0.1).log10(), 4000);
            let e = freqresp(&g, &w)
                .unwrap()
                .response
                .iter()
                .zip(freqresp(&red.system, &w).unwrap().response)
                .map(|(a, b): (&CMat, CMat)| (a - b).svd(false, false).singular_values.max())
                .fold(0.0, f64::max);
            assert!(e <= red.error_bound * (1.0 + 1e-6), "{r} {method:?}: {e}");
            assert!((red.error_bound - 2.0 * hsv[r..].iter().sum::<f64>()).abs() <= 1e-12);
            if method == BalredMethod::MatchDc {
                assert_dc_matched(&g, &red.system);
            }
        }
    }
}

/// A pole on the stability boundary, non-minimal systems and impossible orders give typed
/// errors (unstable systems are reduced around their unstable part: `reduction_unstable.rs`).
#[test]
fn reduction_errors() {
    let unstable = TransferFunction::continuous(&[1.0], &[1.0, 0.0, -1.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    assert!(matches!(
        balred(&unstable, 0, BalredMethod::Truncate),
        Err(LtiError::InvalidArgument(_))
    ));
    let integrator = TransferFunction::continuous(&[1.0], &[1.0, 1.0, 0.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    assert!(matches!(
        hsvd(&integrator),
        Err(LtiError::InvalidArgument(_))
    ));
    let g1 = TransferFunction::continuous(&[1.0, 1.0], &[1.0, 2.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let g2 = TransferFunction::continuous(&[1.0], &[1.0, 1.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let nonminimal = interconnect::series(&g1, &g2).unwrap();
    assert!(matches!(
        balreal(&nonminimal),
        Err(LtiError::Singular { .. })
    ));
    assert!(matches!(
        balred(&nonminimal, 2, BalredMethod::Truncate),
        Err(LtiError::Singular { .. })
    ));
    assert_eq!(
        balred(&nonminimal, 1, BalredMethod::MatchDc)
            .unwrap()
            .system
            .nx(),
        1
    );
    assert!(matches!(
        balred(&nonminimal, 3, BalredMethod::Truncate),
        Err(LtiError::InvalidArgument(_))
    ));
}
