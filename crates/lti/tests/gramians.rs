//! Gramians against closed forms and the defining integral.

mod sys_support;

use pendulab_lti::analysis::{GramianKind, gramian};
use pendulab_lti::matrix_functions::van_loan_integral;
use pendulab_lti::{LtiError, Mat, StateSpace};
use sys_support::mat;

#[test]
fn first_order_closed_forms() {
    // ẋ = −a x + b u, y = c x: W_c = b²/(2a), W_o = c²/(2a); discrete x⁺ = a x + b u:
    // W_c = b²/(1 − a²).
    let (a, b, c) = (3.0f64, 2.0, 5.0);
    let sys = StateSpace::continuous(
        mat(1, 1, &[-a]),
        mat(1, 1, &[b]),
        mat(1, 1, &[c]),
        Mat::zeros(1, 1),
    )
    .unwrap();
    let wc = gramian(&sys, GramianKind::Controllability).unwrap();
    let wo = gramian(&sys, GramianKind::Observability).unwrap();
    assert!((wc.x[(0, 0)] - b * b / (2.0 * a)).abs() < 1e-15);
    assert!((wo.x[(0, 0)] - c * c / (2.0 * a)).abs() < 1e-14);
    let ad = 0.8f64;
    let dsys = StateSpace::discrete(
        mat(1, 1, &[ad]),
        mat(1, 1, &[b]),
        mat(1, 1, &[c]),
        Mat::zeros(1, 1),
        0.1,
    )
    .unwrap();
    let wd = gramian(&dsys, GramianKind::Controllability).unwrap();
    assert!((wd.x[(0, 0)] - b * b / (1.0 - ad * ad)).abs() < 1e-13);
}

#[test]
fn gramian_is_the_infinite_integral() {
    // W_c = ∫₀^∞ e^{At} B Bᵀ e^{Aᵀt} dt, built without any Lyapunov solver: the integral over
    // h = 0.01 s from one (well-conditioned) Van Loan exponential, then doubled 13 times by
    // W(2T) = W(T) + e^{AT} W(T) e^{AᵀT} up to 81.92 s. With poles ≤ −0.5 the tail beyond is
    // below e^{−81}, so both are the same matrix up to rounding in ~13 doubling steps.
    let a = mat(3, 3, &[-0.5, 2.0, 0.0, -2.0, -0.5, 1.0, 0.0, 0.0, -3.0]);
    let b = mat(3, 2, &[1.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
    let sys = StateSpace::continuous(a.clone(), b.clone(), Mat::identity(3, 3), Mat::zeros(3, 2))
        .unwrap();
    let wc = gramian(&sys, GramianKind::Controllability).unwrap();
    let (mut e, mut w) = {
        let (e, w) = van_loan_integral(&a.transpose(), &(&b * b.transpose()), 0.01).unwrap();
        (e.transpose(), w)
    };
    for _ in 0..13 {
        w = &w + &e * &w * e.transpose();
        e = &e * &e;
    }
    // Lyapunov operator condition ~1/(2·0.5) and 13 doublings: 1e-12 relative.
    assert!((&wc.x - &w).norm() < 1e-12 * w.norm(), "{}\n{}", wc.x, w);
    assert!(wc.residual < 1e-13);
}

#[test]
fn unstable_systems_have_no_gramian() {
    let sys = StateSpace::continuous(
        mat(1, 1, &[1.0]),
        mat(1, 1, &[1.0]),
        mat(1, 1, &[1.0]),
        Mat::zeros(1, 1),
    )
    .unwrap();
    assert!(matches!(
        gramian(&sys, GramianKind::Controllability),
        Err(LtiError::InvalidArgument(_))
    ));
}
