//! Sylvester and Lyapunov equations: residuals on random systems of order 10, 50, 100;
//! agreement with an independent Kronecker-product solve (LU of the vectorised operator) on
//! small systems; closed forms; the book's p1c43_stability2; error cases.

mod equations_support;

use equations_support::*;
use pendulab_lti::equations::{dlyap, lyap, sylvester};
use pendulab_lti::{LtiError, Mat};

/// Kronecker product.
fn kron(a: &Mat, b: &Mat) -> Mat {
    let (ar, ac) = a.shape();
    let (br, bc) = b.shape();
    Mat::from_fn(ar * br, ac * bc, |i, j| {
        a[(i / br, j / bc)] * b[(i % br, j % bc)]
    })
}

fn vec_of(m: &Mat) -> pendulab_lti::Vector {
    pendulab_lti::Vector::from_column_slice(m.as_slice())
}

fn unvec(v: &pendulab_lti::Vector, r: usize, c: usize) -> Mat {
    Mat::from_column_slice(r, c, v.as_slice())
}

/// Issue acceptance: residual ≤ 1e-12 relative on orders 10, 50, 100 with well-conditioned
/// stable coefficients (Bartels–Stewart is backward stable: residual ≈ c·n·ε ≈ 1e-14).
#[test]
fn random_residuals_orders_10_50_100() {
    let mut r = rng(10);
    for &n in &[10usize, 50, 100] {
        let a = rand_stable(&mut r, n);
        let b = rand_stable(&mut r, n / 2 + 3);
        let c = rand_mat(&mut r, n, n / 2 + 3);
        let s = sylvester(&a, &b, &c).unwrap();
        assert!(s.residual <= 1e-12, "sylvester n={n}: {:e}", s.residual);
        // Recompute the residual independently of the solver's own figure.
        let res = (&a * &s.x + &s.x * &b - &c).norm() / c.norm();
        assert!(res <= 1e-12, "sylvester n={n} recomputed: {res:e}");

        let q = rand_mat(&mut r, n, n);
        let q = &q * q.transpose();
        let l = lyap(&a, &q).unwrap();
        assert!(l.residual <= 1e-12, "lyap n={n}: {:e}", l.residual);
        let res = (&a * &l.x + &l.x * a.transpose() + &q).norm() / q.norm();
        assert!(res <= 1e-12, "lyap n={n} recomputed: {res:e}");
        assert_eq!(l.x, l.x.transpose());
        // A Hurwitz, Q ⪰ 0 ⇒ X ⪰ 0 (smallest eigenvalue ≥ −rounding).
        let min = pendulab_lti::linalg::symmetric_eigenvalues(&l.x)[0];
        assert!(min >= -1e-12 * l.x.norm(), "lyap X not PSD: {min:e}");

        // Discrete: ‖A_d‖₂ ≤ 0.9 keeps λ_iλ_j far from 1.
        let ad = rand_mat(&mut r, n, n);
        let ad = &ad * (0.9 / ad.clone().svd(false, false).singular_values.max());
        let d = dlyap(&ad, &q).unwrap();
        assert!(d.residual <= 1e-12, "dlyap n={n}: {:e}", d.residual);
        let res = (&ad * &d.x * ad.transpose() - &d.x + &q).norm() / q.norm();
        assert!(res <= 1e-12, "dlyap n={n} recomputed: {res:e}");
    }
}

/// Two independent algorithms: Bartels–Stewart versus Gaussian elimination on the Kronecker
/// form. Both are backward stable; with operator condition numbers ≲ 10³ here, 1e-11 relative
/// agreement is guaranteed with margin.
#[test]
fn agree_with_kronecker_solves() {
    let mut r = rng(11);
    for trial in 0..10 {
        let m = 2 + trial % 5;
        let n = 1 + (trial * 3) % 6;
        // General (not stable) coefficients with complex eigenvalues; shift B so that no sum
        // λ + μ is near zero.
        let a = rand_mat(&mut r, m, m) * 2.0;
        let b = rand_mat(&mut r, n, n) * 2.0 + Mat::identity(n, n) * 5.0;
        let c = rand_mat(&mut r, m, n);
        let op = kron(&Mat::identity(n, n), &a) + kron(&b.transpose(), &Mat::identity(m, m));
        let xref = unvec(&op.lu().solve(&vec_of(&c)).unwrap(), m, n);
        let x = sylvester(&a, &b, &c).unwrap().x;
        assert!(
            (&x - &xref).norm() <= 1e-11 * xref.norm(),
            "sylvester trial {trial}"
        );

        let a = rand_mat(&mut r, m, m) - Mat::identity(m, m) * 2.5;
        let q = rand_mat(&mut r, m, m);
        let op = kron(&Mat::identity(m, m), &a) + kron(&a, &Mat::identity(m, m));
        let xref = unvec(&op.lu().solve(&(-vec_of(&q))).unwrap(), m, m);
        let x = lyap(&a, &q).unwrap().x;
        assert!(
            (&x - &xref).norm() <= 1e-11 * xref.norm(),
            "lyap trial {trial}"
        );

        let ad = rand_mat(&mut r, m, m) * 0.4;
        let op = kron(&ad, &ad) - Mat::identity(m * m, m * m);
        let xref = unvec(&op.lu().solve(&(-vec_of(&q))).unwrap(), m, m);
        let x = dlyap(&ad, &q).unwrap().x;
        assert!(
            (&x - &xref).norm() <= 1e-11 * xref.norm(),
            "dlyap trial {trial}"
        );
    }
}

/// Closed forms for diagonal coefficients: X_ij = −Q_ij / (a_i + a_j) (continuous) and
/// X_ij = Q_ij / (1 − a_i a_j) (discrete), exact up to one rounding per entry.
#[test]
fn diagonal_closed_forms() {
    let av = [-1.0, -2.5, -0.3, -7.0];
    let a = Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(&av));
    let q = Mat::from_fn(4, 4, |i, j| 1.0 + (i * 4 + j) as f64);
    let x = lyap(&a, &q).unwrap().x;
    let dv = [0.5, -0.2, 0.9, 0.1];
    let ad = Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(&dv));
    let xd = dlyap(&ad, &q).unwrap().x;
    for i in 0..4 {
        for j in 0..4 {
            let e = -q[(i, j)] / (av[i] + av[j]);
            assert!((x[(i, j)] - e).abs() <= 1e-14 * e.abs().max(1.0));
            let e = q[(i, j)] / (1.0 - dv[i] * dv[j]);
            assert!((xd[(i, j)] - e).abs() <= 1e-14 * e.abs().max(1.0));
        }
    }
    // Scalar Sylvester: (a + b) x = c.
    let s = sylvester(
        &Mat::from_element(1, 1, 3.0),
        &Mat::from_element(1, 1, 4.0),
        &Mat::from_element(1, 1, 14.0),
    )
    .unwrap();
    assert!((s.x[(0, 0)] - 2.0).abs() < 1e-15);
}

/// Book example p1c43_stability2: P A + Aᵀ P = −I, i.e. lyap(Aᵀ, I); the book prints
/// eig(P) = 0.505, 0.650, 2.247, 45.22, 61.13, compared to half a unit of the last printed
/// digit.
#[test]
fn book_p1c43_stability2() {
    let a = Mat::from_row_slice(
        5,
        5,
        &[
            -1.0, -1.0, -1.0, -1.0, 0.0, //
            1.0, -1.0, -1.0, 0.0, -1.0, //
            1.0, 0.0, 0.0, -1.0, 0.0, //
            1.0, -1.0, 1.0, 0.0, -1.0, //
            -1.0, 1.0, -1.0, 1.0, 0.0,
        ],
    );
    let sol = lyap(&a.transpose(), &Mat::identity(5, 5)).unwrap();
    assert!(sol.residual <= 1e-12);
    let ev = pendulab_lti::linalg::symmetric_eigenvalues(&sol.x);
    let book = [
        (0.505, 5e-4),
        (0.650, 5e-4),
        (2.247, 5e-4),
        (45.22, 5e-3),
        (61.13, 5e-3),
    ];
    for (e, (b, tol)) in ev.iter().zip(book) {
        assert!((e - b).abs() <= tol, "P eigenvalue {e} vs book {b}");
    }
}

#[test]
fn errors_are_typed() {
    // Eigenvalues ±j: λ + λ̄ = 0 ⇒ singular Lyapunov operator.
    let osc = Mat::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]);
    assert!(matches!(
        lyap(&osc, &Mat::identity(2, 2)),
        Err(LtiError::NoUniqueSolution { .. })
    ));
    // λ(A) + μ(B) = 1 + (−1) = 0.
    let e = sylvester(
        &Mat::from_element(1, 1, 1.0),
        &Mat::from_element(1, 1, -1.0),
        &Mat::from_element(1, 1, 1.0),
    );
    match e {
        Err(LtiError::NoUniqueSolution { detail, .. }) => assert!(detail.contains("1.0")),
        other => panic!("expected NoUniqueSolution, got {other:?}"),
    }
    // Discrete: eigenvalue 1 ⇒ λλ = 1.
    let rot = Mat::from_row_slice(2, 2, &[0.6, -0.8, 0.8, 0.6]);
    assert!(matches!(
        dlyap(&rot, &Mat::identity(2, 2)),
        Err(LtiError::NoUniqueSolution { .. })
    ));
    let mut bad = Mat::identity(3, 3);
    bad[(1, 2)] = f64::NAN;
    assert!(matches!(
        lyap(&bad, &Mat::identity(3, 3)),
        Err(LtiError::NonFinite { row: 1, col: 2, .. })
    ));
    assert!(matches!(
        dlyap(&Mat::identity(3, 3), &Mat::identity(2, 2)),
        Err(LtiError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        sylvester(&Mat::zeros(2, 3), &Mat::identity(2, 2), &Mat::zeros(2, 2)),
        Err(LtiError::NotSquare { .. })
    ));
    assert!(matches!(
        sylvester(
            &Mat::identity(2, 2),
            &Mat::identity(3, 3),
            &Mat::zeros(3, 2)
        ),
        Err(LtiError::DimensionMismatch { .. })
    ));
    let mut inf = Mat::identity(2, 2);
    inf[(0, 0)] = f64::INFINITY;
    assert!(matches!(
        sylvester(&Mat::identity(2, 2), &Mat::identity(2, 2), &inf),
        Err(LtiError::NonFinite { .. })
    ));
    // Empty problems are fine.
    assert_eq!(
        lyap(&Mat::zeros(0, 0), &Mat::zeros(0, 0))
            .unwrap()
            .x
            .shape(),
        (0, 0)
    );
}
