//! LQ design: the book's LQR and LQ-servo gains (cdip_lqr_sim, cdip_lqr_servo_sim), the
//! Kalman frequency-domain identity, the cross term, sampled-data (Van Loan) LQR, LQE and
//! the errors of infeasible problems.

mod sys_support;

use pendulab_lti::design::{
    StateFeedback, lq_servo, lqe, lqr, lqr_sampled_data, sampled_data_cost,
};
use pendulab_lti::linalg::diag;
use pendulab_lti::matrix_functions::{expm, zoh_integrals};
use pendulab_lti::{CMat, Complex64, Continuous, Discretization, LtiError, Mat, StateSpace};
use sys_support::{cdip, mat};

fn cdip_sys() -> StateSpace<Continuous> {
    let (a, b) = cdip();
    StateSpace::continuous(a, b, mat(1, 4, &[1.0, 0.0, 0.0, 0.0]), Mat::zeros(1, 1)).unwrap()
}

#[test]
fn cdip_lqr_sim_book_gains() {
    // IP Toolbox cdip_lqr_sim.m: Q = diag(10, q2, 0, 0), R = 1, book gains (u = +K x).
    let sys = cdip_sys();
    let cases = [
        (10.0, [3.16228, 13.47175, 4.48137, 2.26289]),
        (50.0, [3.16228, 15.81695, 4.72006, 2.44448]),
        (100.0, [3.16228, 18.12126, 4.93879, 2.61065]),
    ];
    for (q2, book) in cases {
        let q = diag(&[10.0, q2, 0.0, 0.0]);
        let r = mat(1, 1, &[1.0]);
        let l = lqr(&sys, &q, &r, None).unwrap();
        let kb = StateFeedback::new(l.gain.clone()).unwrap().book_gain();
        // Printed to 5 decimals: half a unit of the last digit.
        for j in 0..4 {
            assert!((kb[(0, j)] - book[j]).abs() < 5e-6, "q2={q2}: {kb}");
        }
        // Independent closed form for the cart-position gain: the Kalman identity
        // |1 + K(sI − A)⁻¹B|² = 1 + |Q^½(sI − A)⁻¹B|²/R at s → 0, where both sides are
        // dominated by the integrator 1/s of z, gives K_z² = q₁/R, i.e. K_z = −√10 for
        // u = −Kx (the book's +3.16228). Relative 1e-9 (a limit of a well-conditioned
        // identity, no rounding amplification).
        assert!((l.gain[(0, 0)] + 10f64.sqrt()).abs() < 1e-9 * 10f64.sqrt());
        // Issue acceptance: relative residual ≤ 1e-12 on the book systems; stable loop.
        assert!(l.residual <= 1e-12, "residual {:e}", l.residual);
        assert!(l.closed_loop_poles.iter().all(|p| p.re < 0.0));
    }
}

#[test]
fn cdip_lqr_servo_sim_book_gains() {
    // IP Toolbox cdip_lqr_servo_sim.m: Q = diag(1, 5, 0, 0, 100), R = 1 on [x; w],
    // w = ∫(r − z): K1 = [10.39942, 17.76307, 6.79089, 3.04513], K2 = −10 (u = K1 x + K2 w).
    let sys = cdip_sys();
    let q = diag(&[1.0, 5.0, 0.0, 0.0, 100.0]);
    let s = lq_servo(&sys, &q, &mat(1, 1, &[1.0])).unwrap();
    let k1_book = -&s.state_gain;
    let k2_book = -&s.integral_gain;
    for (j, want) in [10.39942, 17.76307, 6.79089, 3.04513].iter().enumerate() {
        assert!((k1_book[(0, j)] - want).abs() < 5e-6, "{k1_book}");
    }
    // K2 = −√(q_w/R) = −10 by the same integrator argument (w is an integrator state).
    assert!((k2_book[(0, 0)] - (-10.0)).abs() < 1e-9 * 10.0, "{k2_book}");
    assert!(s.lqr.residual <= 1e-12);
}

/// Checks the Kalman (return-difference) identity of an LQR with N = 0 at `s`:
/// `(I + K G)ᴴ R (I + K G) = R + Gᴴ Q G`, `G = (sI − A)⁻¹ B`.
fn kalman_identity_error(a: &Mat, b: &Mat, q: &Mat, r: &Mat, k: &Mat, s: Complex64) -> f64 {
    let n = a.nrows();
    let to_c = |m: &Mat| -> CMat { m.map(|v| Complex64::new(v, 0.0)) };
    let mut si = to_c(&(-a));
    for i in 0..n {
        si[(i, i)] += s;
    }
    let g = si.lu().solve(&to_c(b)).unwrap();
    let m = b.ncols();
    let rd = CMat::identity(m, m) + to_c(k) * &g;
    let lhs = rd.adjoint() * to_c(r) * &rd;
    let rhs = to_c(r) + g.adjoint() * to_c(q) * &g;
    (lhs - &rhs).norm() / rhs.norm()
}

#[test]
fn lqr_satisfies_the_kalman_identity() {
    // A frequency-domain property of the optimal gain that does not involve the Riccati
    // equation: checked on the cart pendulum with two made-up inputs.
    let (a, b1) = cdip();
    let b = Mat::from_fn(
        4,
        2,
        |i, j| if j == 0 { b1[(i, 0)] } else { 0.1 * i as f64 },
    );
    let q = diag(&[5.0, 20.0, 0.5, 0.1]);
    let r = mat(2, 2, &[1.0, 0.2, 0.2, 2.0]);
    let sys =
        StateSpace::continuous(a.clone(), b.clone(), Mat::zeros(0, 4), Mat::zeros(0, 2)).unwrap();
    let l = lqr(&sys, &q, &r, None).unwrap();
    for w in [0.1, 1.0, 3.0, 10.0, 100.0] {
        // Condition of the identity is modest (‖G‖ ≤ ~10 here): 1e-10 relative.
        let e = kalman_identity_error(&a, &b, &q, &r, &l.gain, Complex64::new(0.0, w));
        assert!(e < 1e-10, "w={w}: {e:e}");
    }
}

#[test]
fn cross_term_equals_the_completed_square() {
    // xᵀQx + uᵀRu + 2xᵀNu = xᵀ(Q − NR⁻¹Nᵀ)x + vᵀRv with u = v − R⁻¹Nᵀx, so
    // lqr(A, B, Q, R, N).K = lqr(A − BR⁻¹Nᵀ, B, Q − NR⁻¹Nᵀ, R).K + R⁻¹Nᵀ.
    let (a, b) = cdip();
    let q = diag(&[10.0, 10.0, 1.0, 1.0]);
    let r = mat(1, 1, &[2.0]);
    let n = mat(4, 1, &[0.5, -1.0, 0.2, 0.1]);
    let sys =
        StateSpace::continuous(a.clone(), b.clone(), Mat::zeros(0, 4), Mat::zeros(0, 1)).unwrap();
    let l1 = lqr(&sys, &q, &r, Some(&n)).unwrap();
    let rinv_nt = n.transpose() / 2.0;
    let a2 = &a - &b * &rinv_nt;
    let q2 = &q - &n * &rinv_nt;
    let sys2 = StateSpace::continuous(a2, b, Mat::zeros(0, 4), Mat::zeros(0, 1)).unwrap();
    let l2 = lqr(&sys2, &q2, &r, None).unwrap();
    let k2 = &l2.gain + rinv_nt;
    // Both are backward-stable solutions of equivalent equations: 1e-9 relative.
    assert!(
        (&l1.gain - &k2).norm() < 1e-9 * k2.norm(),
        "{} vs {}",
        l1.gain,
        k2
    );
    assert!((&l1.riccati - &l2.riccati).norm() < 1e-9 * l2.riccati.norm());
}

#[test]
fn discrete_lqr_is_stable_and_accurate() {
    let sys = cdip_sys().c2d(0.01, Discretization::Zoh).unwrap();
    let q = diag(&[10.0, 10.0, 0.0, 0.0]);
    let l = lqr(&sys, &q, &mat(1, 1, &[1.0]), None).unwrap();
    assert!(l.residual <= 1e-12, "{:e}", l.residual);
    assert!(l.closed_loop_poles.iter().all(|p| p.norm() < 1.0));
    // Recompute eig(A − BK) independently.
    let ev = pendulab_lti::linalg::eigenvalues(&(sys.a() - sys.b() * &l.gain)).unwrap();
    sys_support::assert_same_poles(&ev, &l.closed_loop_poles, 1e-12);
}

#[test]
fn van_loan_weights_match_quadrature() {
    // W_d = ∫₀^T e^{Fᵀs} W e^{Fs} ds by composite Simpson with 2000 panels on a smooth
    // integrand (error ≈ T⁵ max|f⁗|/(180·2000⁴) < 1e-13 relative here), against the block
    // exponential of sampled_data_cost.
    let sys = cdip_sys();
    let q = diag(&[10.0, 10.0, 0.0, 0.0]);
    let r = mat(1, 1, &[1.0]);
    let ts = 0.1;
    let (dsys, cost) = sampled_data_cost(&sys, &q, &r, None, ts).unwrap();
    let mut f = Mat::zeros(5, 5);
    f.view_mut((0, 0), (4, 4)).copy_from(sys.a());
    f.view_mut((0, 4), (4, 1)).copy_from(sys.b());
    let mut w = Mat::zeros(5, 5);
    w.view_mut((0, 0), (4, 4)).copy_from(&q);
    w[(4, 4)] = 1.0;
    let panels = 2000;
    let h = ts / panels as f64;
    let mut acc = Mat::zeros(5, 5);
    for k in 0..=panels {
        let e = expm(&(&f * (k as f64 * h))).unwrap();
        let coef = if k == 0 || k == panels {
            1.0
        } else if k % 2 == 1 {
            4.0
        } else {
            2.0
        };
        acc += e.transpose() * &w * e * coef;
    }
    acc *= h / 3.0;
    let wd = {
        let mut m = Mat::zeros(5, 5);
        m.view_mut((0, 0), (4, 4)).copy_from(&cost.q);
        m.view_mut((0, 4), (4, 1)).copy_from(&cost.n);
        m.view_mut((4, 0), (1, 4)).copy_from(&cost.n.transpose());
        m.view_mut((4, 4), (1, 1)).copy_from(&cost.r);
        m
    };
    assert!((&wd - &acc).norm() < 1e-11 * acc.norm(), "{wd}\n{acc}");
    // R_d ≥ R·ts (the held input also excites the state cost) and the ZOH pair is exact.
    assert!(cost.r[(0, 0)] > ts);
    let (phi, gam) = zoh_integrals(sys.a(), sys.b(), ts).unwrap();
    assert!((dsys.a() - phi).norm() < 1e-14 * 10.0);
    assert!((dsys.b() - gam).norm() < 1e-14 * 10.0);
}

#[test]
fn sampled_data_lqr_cost_equals_the_continuous_cost() {
    // With u held at −K_d x_k over each interval, the continuous cost ∫(xᵀQx + uᵀRu)dt from
    // x₀ equals x₀ᵀ X_d x₀ (X_d the DARE solution with the Van Loan weights). The continuous
    // cost is computed here by Simpson quadrature along the exact trajectory (200 panels per
    // interval, error < 1e-10 relative), independently of the Van Loan formula.
    let sys = cdip_sys();
    let q = diag(&[10.0, 10.0, 0.0, 0.0]);
    let r = mat(1, 1, &[1.0]);
    let ts = 0.1;
    let d = lqr_sampled_data(&sys, &q, &r, None, ts).unwrap();
    let kd = &d.lqr.gain;
    let x0 = pendulab_lti::Vector::from_row_slice(&[0.0, 15f64.to_radians(), 0.0, 0.0]);
    let panels = 200;
    let h = ts / panels as f64;
    let step: Vec<(Mat, Mat)> = (0..=panels)
        .map(|k| zoh_integrals(sys.a(), sys.b(), k as f64 * h).unwrap())
        .collect();
    let mut x = x0.clone();
    let mut cost = 0.0;
    for _ in 0..300 {
        let u = -(kd * &x);
        for (k, (phi, gam)) in step.iter().enumerate() {
            let xt = phi * &x + gam * &u;
            let f = (xt.transpose() * &q * &xt)[(0, 0)] + (u.transpose() * &r * &u)[(0, 0)];
            let coef = if k == 0 || k == panels {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            cost += coef * f * h / 3.0;
        }
        x = &step[panels].0 * &x + &step[panels].1 * &u;
    }
    let predicted = (x0.transpose() * &d.lqr.riccati * &x0)[(0, 0)];
    assert!(
        (cost - predicted).abs() < 1e-9 * predicted,
        "{cost} vs {predicted}"
    );
}

#[test]
fn lqe_solves_the_filter_riccati_equation() {
    // Continuous Kalman gain for y = [z, θ]: P must satisfy
    // AP + PAᵀ − PCᵀR⁻¹CP + GQGᵀ = 0 (checked here directly), and A − LC must be stable.
    let (a, _) = cdip();
    let cm = mat(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let sys =
        StateSpace::continuous(a.clone(), Mat::zeros(4, 1), cm.clone(), Mat::zeros(2, 1)).unwrap();
    let g = Mat::identity(4, 4);
    let qn = diag(&[1e-4, 1e-4, 1e-2, 1e-2]);
    let rn = diag(&[1e-6, 1e-5]);
    let k = lqe(&sys, &g, &qn, &rn, None).unwrap();
    let p = &k.covariance;
    let rinv = rn.clone().try_inverse().unwrap();
    let res = &a * p + p * a.transpose() - p * cm.transpose() * &rinv * &cm * p + &qn;
    let scale = (&a * p).norm() * 2.0 + qn.norm();
    assert!(res.norm() < 1e-10 * scale, "{:e}", res.norm() / scale);
    assert!((&k.gain - p * cm.transpose() * &rinv).norm() < 1e-9 * k.gain.norm());
    assert!(k.estimator_poles.iter().all(|z| z.re < 0.0));
}

#[test]
fn infeasible_lqr_problems_are_typed_errors() {
    // p1c511_ex2: the mode at 1 is uncontrollable and unstable → not stabilisable.
    let a = mat(3, 3, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
    let b = mat(3, 1, &[0.0, 0.0, 1.0]);
    let sys = StateSpace::continuous(a, b, Mat::zeros(0, 3), Mat::zeros(0, 1)).unwrap();
    let e = lqr(&sys, &Mat::identity(3, 3), &mat(1, 1, &[1.0]), None).unwrap_err();
    assert!(
        matches!(
            e,
            LtiError::NotStabilizable { .. } | LtiError::BoundaryEigenvalue { .. }
        ),
        "{e}"
    );
    // R not positive definite; wrong shapes; NaN.
    let sys = cdip_sys();
    assert!(matches!(
        lqr(&sys, &Mat::identity(4, 4), &mat(1, 1, &[0.0]), None),
        Err(LtiError::NotPositiveDefinite { .. })
    ));
    assert!(matches!(
        lqr(&sys, &Mat::identity(3, 3), &mat(1, 1, &[1.0]), None),
        Err(LtiError::DimensionMismatch { .. })
    ));
    let mut q = Mat::identity(4, 4);
    q[(1, 1)] = f64::NAN;
    assert!(matches!(
        lqr(&sys, &q, &mat(1, 1, &[1.0]), None),
        Err(LtiError::NonFinite { .. })
    ));
}
