//! Part 1 chapter 4 examples against closed forms, defining residuals and the book's printed
//! values.

mod common;
use common::*;

use pendulab_book::Value;
use pendulab_lti::{Complex64, Mat};

#[test]
fn p1c41_cdip_response() {
    let out = run("p1c41_cdip_response");
    // Closed form: s² + a_c s + b_c k_P = 0 with a_c = 6.25, b_c = 4.36, k_P = 1.
    let (a, b) = (6.25f64, 4.36f64);
    let d = (a * a - 4.0 * b).sqrt();
    let ev = cplx(&out, "eig");
    assert_eq!(ev.len(), 2);
    // Eigenvalues of a 2×2 by QR: a few ulps of the norm.
    assert!((ev[0] - Complex64::new((-a + d) / 2.0, 0.0)).norm() < 1e-12);
    assert!((ev[1] - Complex64::new((-a - d) / 2.0, 0.0)).norm() < 1e-12);
    // Superposition y3 = y1 + y2 (eq. 4.24) holds for the exact discretisation up to rounding
    // of responses of size ~10: 1e-12 is a thousand ulps.
    assert!(num(&out, "max_superposition_error") < 1e-12);
}

fn a1() -> Mat {
    Mat::from_row_slice(
        5,
        5,
        &[
            0., -1., 0., 0., -1., 1., 0., 0., 1., 0., 1., 1., 1., 0., 1., 0., 1., -1., 1., 0., 1.,
            1., 1., 1., -1.,
        ],
    )
}

fn a2() -> Mat {
    Mat::from_row_slice(
        5,
        5,
        &[
            -1., -1., -1., -1., 0., 1., -1., -1., 0., -1., 1., 0., 0., -1., 0., 1., -1., 1., 0.,
            -1., -1., 1., -1., 1., 0.,
        ],
    )
}

#[test]
fn p1c43_stability1() {
    let out = run("p1c43_stability1");
    references_reproduced(&out);
    assert_eq!(out.get("stable"), Some(&Value::Bool(false)));
    // Independent invariants: Σλ = trace A, Πλ = det A (LU, not Schur), to 1e-10.
    let a = a1();
    let ev = cplx(&out, "eig");
    let sum: Complex64 = ev.iter().sum();
    let prod: Complex64 = ev.iter().product();
    assert!((sum - Complex64::new(a.trace(), 0.0)).norm() < 1e-10);
    assert!((prod - Complex64::new(a.determinant(), 0.0)).norm() < 1e-10);
}

#[test]
fn p1c43_stability2() {
    let out = run("p1c43_stability2");
    references_reproduced(&out);
    let a = a2();
    let p = match out.get("P") {
        Some(Value::Matrix(m)) => Mat::from_fn(5, 5, |i, j| m[i][j]),
        v => panic!("P: {v:?}"),
    };
    // The defining residual PA + AᵀP + I = 0; entries of P are ≤ 30, so 1e-11 is ~100 ulps
    // of the products.
    let r = &p * &a + a.transpose() * &p + Mat::identity(5, 5);
    assert!(r.amax() < 1e-11, "residual {}", r.amax());
    // P ≻ 0: Cholesky succeeds (independent of the reported eigenvalues).
    assert!(p.clone().cholesky().is_some());
    let pe = match out.get("P_eig") {
        Some(Value::Vector(v)) => v.clone(),
        v => panic!("{v:?}"),
    };
    // Σ eig(P) = trace P.
    assert!((pe.iter().sum::<f64>() - p.trace()).abs() < 1e-10);
    assert_eq!(out.get("P_positive_definite"), Some(&Value::Bool(true)));
    let ev = cplx(&out, "eig");
    assert!(ev.iter().all(|z| z.re < 0.0));
    let sum: Complex64 = ev.iter().sum();
    assert!((sum.re - a.trace()).abs() < 1e-10 && sum.im.abs() < 1e-12);
}

#[test]
fn p1c43_lyapunov_func() {
    let out = run("p1c43_lyapunov_func");
    // The grid spans [−5, 5]² with an odd number of points: V = 0 at the centre, 50 at the
    // corners, exactly.
    assert_eq!(num(&out, "V_min"), 0.0);
    assert_eq!(num(&out, "V_max"), 50.0);
}

#[test]
fn chapter_4_figures_are_written() {
    let dir = TempDir::new("p1c4");
    let ids = [
        "p1c41_cdip_response",
        "p1c43_stability1",
        "p1c43_stability2",
        "p1c43_lyapunov_func",
    ];
    for (id, files) in ids.iter().zip(assert_figures_written(&dir, &ids)) {
        for f in &files {
            assert!(f.file_name().unwrap().to_str().unwrap().starts_with(id));
        }
    }
}
