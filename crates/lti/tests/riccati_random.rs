//! CARE and DARE on random stabilisable systems of order 10, 50, 100 (fixed seeds): the
//! defining residual, closed-loop stability, symmetry/semidefiniteness of X, and agreement of
//! two independent algorithms (ordered Schur vs structure-preserving doubling).

mod equations_support;

use equations_support::*;
use pendulab_lti::Mat;
use pendulab_lti::equations::riccati::{care_residual, dare_residual};
use pendulab_lti::equations::{RiccatiMethod, RiccatiOptions, care, dare};

fn opts(method: RiccatiMethod) -> RiccatiOptions {
    RiccatiOptions {
        method,
        ..Default::default()
    }
}

/// Issue acceptance: relative residual ≤ 1e-10 and A − BK stable on orders 10, 50, 100.
#[test]
fn care_random_orders_10_50_100() {
    for (i, &(n, m)) in [(10, 2), (50, 5), (100, 10)].iter().enumerate() {
        for cross in [false, true] {
            let (a, b, q, r, nn) = lq_data(100 + i as u64, n, m, cross);
            let sol = care(&a, &b, &q, &r, nn.as_ref(), &RiccatiOptions::default()).unwrap();
            // Recomputed independently of the solver's own residual.
            let res = care_residual(&a, &b, &q, &r, nn.as_ref(), &sol.x);
            assert!(
                res <= 1e-10 && sol.residual <= 1e-10,
                "n={n} cross={cross}: {res:e}"
            );
            let acl = &a - &b * &sol.gain;
            let poles = pendulab_lti::linalg::eigenvalues(&acl).unwrap();
            assert!(
                poles.iter().all(|p| p.re < 0.0),
                "n={n}: closed loop unstable"
            );
            assert!((&sol.x - sol.x.transpose()).norm() == 0.0);
            // LQ data ⇒ X ⪰ 0 (up to rounding relative to ‖X‖).
            let min = pendulab_lti::linalg::symmetric_eigenvalues(&sol.x)[0];
            assert!(min >= -1e-10 * sol.x.norm(), "n={n}: X not PSD ({min:e})");
        }
    }
}

#[test]
fn dare_random_orders_10_50_100() {
    for (i, &(n, m)) in [(10, 2), (50, 5), (100, 10)].iter().enumerate() {
        for cross in [false, true] {
            let (a, b, q, r, nn) = lq_data(200 + i as u64, n, m, cross);
            // Spectral radius ≈ 1.5: unstable but moderate.
            let a = a * 0.5;
            let sol = dare(&a, &b, &q, &r, nn.as_ref(), &RiccatiOptions::default()).unwrap();
            let res = dare_residual(&a, &b, &q, &r, nn.as_ref(), &sol.x);
            assert!(
                res <= 1e-10 && sol.residual <= 1e-10,
                "n={n} cross={cross}: {res:e}"
            );
            let acl = &a - &b * &sol.gain;
            let poles = pendulab_lti::linalg::eigenvalues(&acl).unwrap();
            assert!(
                poles.iter().all(|p| p.norm() < 1.0),
                "n={n}: closed loop unstable"
            );
            let min = pendulab_lti::linalg::symmetric_eigenvalues(&sol.x)[0];
            assert!(min >= -1e-10 * sol.x.norm(), "n={n}: X not PSD ({min:e})");
        }
    }
}

/// Two independent algorithms (Hamiltonian/symplectic ordered Schur vs doubling) agree. With
/// these well-conditioned data (Riccati condition numbers ≲ 10³) both are accurate to ≈ 1e-13,
/// so 1e-9 relative agreement leaves a wide margin.
#[test]
fn methods_agree() {
    for (seed, n, m) in [(300u64, 6usize, 2usize), (301, 20, 3), (302, 40, 4)] {
        let (a, b, q, r, nn) = lq_data(seed, n, m, true);
        let x1 = care(&a, &b, &q, &r, nn.as_ref(), &opts(RiccatiMethod::Schur))
            .unwrap()
            .x;
        let x2 = care(&a, &b, &q, &r, nn.as_ref(), &opts(RiccatiMethod::Doubling))
            .unwrap()
            .x;
        assert!((&x1 - &x2).norm() <= 1e-9 * x1.norm(), "care n={n}");
        let a = a * 0.5;
        let x1 = dare(&a, &b, &q, &r, nn.as_ref(), &opts(RiccatiMethod::Schur))
            .unwrap()
            .x;
        let x2 = dare(&a, &b, &q, &r, nn.as_ref(), &opts(RiccatiMethod::Doubling))
            .unwrap()
            .x;
        assert!((&x1 - &x2).norm() <= 1e-9 * x1.norm(), "dare n={n}");
    }
}

/// Scalar closed forms: 2ax − b²x²/r + q = 0 ⇒ x = r(a + √(a² + b²q/r))/b²; and the DARE
/// x = a²x − a²b²x²/(b²x + r) + q, whose positive root solves b²x² + (r − a²r − qb²)x − qr = 0.
#[test]
fn scalar_closed_forms() {
    for &(a, b, q, r) in &[
        (1.0, 1.0, 1.0, 1.0),
        (-2.0, 0.5, 3.0, 0.1),
        (5.0, 2.0, 0.0, 1.0),
        (0.0, 1.0, 4.0, 1.0),
    ] {
        let m = |v: f64| Mat::from_element(1, 1, v);
        let x = care(&m(a), &m(b), &m(q), &m(r), None, &RiccatiOptions::default())
            .unwrap()
            .x[(0, 0)];
        let e = r * (a + (a * a + b * b * q / r).sqrt()) / (b * b);
        assert!(
            (x - e).abs() <= 1e-14 * e.abs().max(1.0),
            "care {a} {b} {q} {r}: {x} vs {e}"
        );
        let x = dare(&m(a), &m(b), &m(q), &m(r), None, &RiccatiOptions::default())
            .unwrap()
            .x[(0, 0)];
        let (qa, qb, qc) = (b * b, r - a * a * r - q * b * b, -q * r);
        let e = (-qb + (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa);
        assert!(
            (x - e).abs() <= 1e-13 * e.abs().max(1.0),
            "dare {a} {b} {q} {r}: {x} vs {e}"
        );
    }
}
