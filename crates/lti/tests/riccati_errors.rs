//! Riccati error cases: every failure is a typed error naming what and where, never a panic.

use pendulab_lti::equations::{RiccatiMethod, RiccatiOptions, care, dare};
use pendulab_lti::{LtiError, Mat};

fn d(v: &[f64]) -> Mat {
    Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(v))
}

const METHODS: [RiccatiMethod; 3] = [
    RiccatiMethod::Auto,
    RiccatiMethod::Schur,
    RiccatiMethod::Doubling,
];

fn all_opts() -> impl Iterator<Item = RiccatiOptions> {
    METHODS.into_iter().map(|method| RiccatiOptions {
        method,
        ..Default::default()
    })
}

/// A = diag(1, −1), B = [0; 1]: the mode at +1 is uncontrollable and unstable. The error must
/// name it (eigenvalue 1, PBH margin at rounding level).
#[test]
fn uncontrollable_unstable_mode() {
    let a = d(&[1.0, -1.0]);
    let b = Mat::from_column_slice(2, 1, &[0.0, 1.0]);
    for q in [Mat::identity(2, 2), d(&[0.0, 1.0])] {
        for o in all_opts() {
            match care(&a, &b, &q, &Mat::identity(1, 1), None, &o) {
                Err(LtiError::NotStabilizable { eigenvalue, margin }) => {
                    assert!((eigenvalue.re - 1.0).abs() < 1e-12 && eigenvalue.im == 0.0);
                    assert!(margin < 1e-12);
                }
                other => panic!(
                    "care {:?}: expected NotStabilizable, got {other:?}",
                    o.method
                ),
            }
        }
    }
    // Discrete: mode at 2 (outside the unit circle), uncontrollable.
    let a = d(&[2.0, 0.5]);
    for o in all_opts() {
        match dare(&a, &b, &Mat::identity(2, 2), &Mat::identity(1, 1), None, &o) {
            Err(LtiError::NotStabilizable { eigenvalue, .. }) => {
                assert!((eigenvalue.re - 2.0).abs() < 1e-12)
            }
            other => panic!(
                "dare {:?}: expected NotStabilizable, got {other:?}",
                o.method
            ),
        }
    }
    // A larger system with one hidden unstable uncontrollable mode: a Kalman controllability
    // form (the third state is not driven and evolves as x₃' = 0.5 x₃) rotated by an
    // orthogonal Q so the structure is not visible in the entries.
    let q = Mat::from_row_slice(3, 3, &[0.36, 0.48, 0.8, 0.48, 0.64, -0.6, -0.8, 0.6, 0.0]);
    let a = &q
        * Mat::from_row_slice(3, 3, &[-1.0, 3.0, 2.0, 0.0, -2.0, 1.0, 0.0, 0.0, 0.5])
        * q.transpose();
    let b = &q * Mat::from_column_slice(3, 1, &[1.0, 1.0, 0.0]);
    for o in all_opts() {
        match care(&a, &b, &Mat::identity(3, 3), &Mat::identity(1, 1), None, &o) {
            Err(LtiError::NotStabilizable { eigenvalue, .. }) => {
                assert!((eigenvalue.re - 0.5).abs() < 1e-10)
            }
            other => panic!(
                "care {:?}: expected NotStabilizable, got {other:?}",
                o.method
            ),
        }
    }
}

/// A = diag(0, −1), B = I, Q = diag(0, 1): the integrator mode is unobservable through Q and
/// on the imaginary axis ⇒ no stabilising solution (the Hamiltonian has a double eigenvalue 0).
#[test]
fn undetectable_boundary_mode() {
    let a = d(&[0.0, -1.0]);
    let b = Mat::identity(2, 2);
    let q = d(&[0.0, 1.0]);
    for o in all_opts() {
        match care(&a, &b, &q, &Mat::identity(2, 2), None, &o) {
            Err(LtiError::NotDetectable { eigenvalue, .. }) => assert!(eigenvalue.norm() < 1e-12),
            other => panic!("care {:?}: expected NotDetectable, got {other:?}", o.method),
        }
    }
    // Discrete: mode at −1 (on the unit circle), unobservable.
    let a = d(&[-1.0, 0.5]);
    for o in all_opts() {
        match dare(&a, &b, &q, &Mat::identity(2, 2), None, &o) {
            Err(LtiError::NotDetectable { eigenvalue, .. }) => {
                assert!((eigenvalue.re + 1.0).abs() < 1e-12)
            }
            other => panic!("dare {:?}: expected NotDetectable, got {other:?}", o.method),
        }
    }
}

/// a = 0, b = 1, q = −1, r = 1: −x² − 1 = 0 has no real solution; the Hamiltonian
/// [[0, −1], [1, 0]] has eigenvalues ±j on the axis.
#[test]
fn hamiltonian_on_imaginary_axis() {
    let m = |v: f64| Mat::from_element(1, 1, v);
    for o in all_opts() {
        let e = care(&m(0.0), &m(1.0), &m(-1.0), &m(1.0), None, &o);
        assert!(
            matches!(
                e,
                Err(LtiError::BoundaryEigenvalue { .. }) | Err(LtiError::NoConvergence { .. })
            ),
            "{:?}: {e:?}",
            o.method
        );
    }
    // With the default method the error names the boundary eigenvalue ±j.
    match care(
        &m(0.0),
        &m(1.0),
        &m(-1.0),
        &m(1.0),
        None,
        &RiccatiOptions::default(),
    ) {
        Err(LtiError::BoundaryEigenvalue { eigenvalue, .. }) => {
            assert!((eigenvalue.im.abs() - 1.0).abs() < 1e-12)
        }
        other => panic!("expected BoundaryEigenvalue, got {other:?}"),
    }
}

#[test]
fn bad_weights_and_shapes() {
    let a = Mat::identity(2, 2);
    let b = Mat::identity(2, 2);
    let q = Mat::identity(2, 2);
    let o = RiccatiOptions::default();
    // R indefinite.
    let r = d(&[1.0, -0.5]);
    match care(&a, &b, &q, &r, None, &o) {
        Err(LtiError::NotPositiveDefinite {
            what,
            min_eigenvalue,
        }) => {
            assert_eq!(what, "R");
            assert!((min_eigenvalue + 0.5).abs() < 1e-12);
        }
        other => panic!("expected NotPositiveDefinite, got {other:?}"),
    }
    assert!(matches!(
        dare(&a, &b, &q, &r, None, &o),
        Err(LtiError::NotPositiveDefinite { .. })
    ));
    // R singular (positive semidefinite) is rejected for the CARE.
    assert!(matches!(
        care(&a, &b, &q, &d(&[1.0, 0.0]), None, &o),
        Err(LtiError::NotPositiveDefinite { .. })
    ));
    // Non-symmetric Q.
    let qn = Mat::from_row_slice(2, 2, &[1.0, 2.0, 0.0, 1.0]);
    assert!(matches!(
        care(&a, &b, &qn, &Mat::identity(2, 2), None, &o),
        Err(LtiError::NotSymmetric { .. })
    ));
    // NaN and Inf.
    let mut an = a.clone();
    an[(0, 1)] = f64::NAN;
    assert!(
        matches!(care(&an, &b, &q, &Mat::identity(2, 2), None, &o), Err(LtiError::NonFinite { what, row: 0, col: 1, .. }) if what == "A")
    );
    let mut bn = b.clone();
    bn[(1, 0)] = f64::INFINITY;
    assert!(matches!(
        dare(&a, &bn, &q, &Mat::identity(2, 2), None, &o),
        Err(LtiError::NonFinite { .. })
    ));
    let mut nn = Mat::zeros(2, 2);
    nn[(0, 0)] = f64::NAN;
    assert!(matches!(
        care(&a, &b, &q, &Mat::identity(2, 2), Some(&nn), &o),
        Err(LtiError::NonFinite { .. })
    ));
    // Shapes.
    assert!(matches!(
        care(&Mat::zeros(2, 3), &b, &q, &Mat::identity(2, 2), None, &o),
        Err(LtiError::NotSquare { .. })
    ));
    assert!(matches!(
        care(&a, &Mat::zeros(3, 1), &q, &Mat::identity(1, 1), None, &o),
        Err(LtiError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        care(&a, &b, &Mat::identity(3, 3), &Mat::identity(2, 2), None, &o),
        Err(LtiError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        dare(&a, &b, &q, &Mat::identity(3, 3), None, &o),
        Err(LtiError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        dare(
            &a,
            &b,
            &q,
            &Mat::identity(2, 2),
            Some(&Mat::zeros(2, 1)),
            &o
        ),
        Err(LtiError::DimensionMismatch { .. })
    ));
    // Empty state: a valid, empty answer.
    let s = care(
        &Mat::zeros(0, 0),
        &Mat::zeros(0, 1),
        &Mat::zeros(0, 0),
        &Mat::identity(1, 1),
        None,
        &o,
    )
    .unwrap();
    assert_eq!(s.gain.shape(), (1, 0));
}

/// No input at all (m = 0): the CARE is the Lyapunov equation AᵀX + XA + Q = 0 when A is
/// Hurwitz, and not stabilisable otherwise.
#[test]
fn no_inputs() {
    let o = RiccatiOptions::default();
    let a = d(&[-1.0, -2.0]);
    let s = care(
        &a,
        &Mat::zeros(2, 0),
        &Mat::identity(2, 2),
        &Mat::zeros(0, 0),
        None,
        &o,
    )
    .unwrap();
    // x_ii = 1/(2|a_i|).
    assert!((s.x[(0, 0)] - 0.5).abs() < 1e-15 && (s.x[(1, 1)] - 0.25).abs() < 1e-15);
    let a = d(&[1.0, -2.0]);
    assert!(matches!(
        care(
            &a,
            &Mat::zeros(2, 0),
            &Mat::identity(2, 2),
            &Mat::zeros(0, 0),
            None,
            &o
        ),
        Err(LtiError::NotStabilizable { .. })
    ));
}
