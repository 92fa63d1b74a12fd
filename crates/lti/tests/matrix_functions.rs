//! Matrix exponential, logarithm and square root against closed forms, high-precision
//! references (tools/reference/expm.py) and defining identities.

mod sys_support;

use pendulab_lti::LtiError;
use pendulab_lti::matrix_functions::{
    expm, expm_with_info, foh_integrals, logm, sqrtm, van_loan_integral, zoh_integrals,
};
use pendulab_lti::{Complex64, Mat};
use sys_support::{fixture, json_mat, mat, rel};

const U: f64 = f64::EPSILON / 2.0;

#[test]
fn expm_rotation_closed_form() {
    // exp([[0, ω], [−ω, 0]] t) = [[cos ωt, sin ωt], [−sin ωt, cos ωt]], for a small and a large
    // angle (the large one needs many squarings). Error bound: backward error u‖A‖ times the
    // (unit) condition of a normal matrix, so ~‖A‖·u in absolute terms: 1e-13·max(1, ωt).
    for &th in &[0.3, 1.0, 7.5, 100.0] {
        let a = mat(2, 2, &[0.0, th, -th, 0.0]);
        let e = expm(&a).unwrap();
        let exact = mat(2, 2, &[th.cos(), th.sin(), -th.sin(), th.cos()]);
        assert!((e - exact).norm() < 1e-13 * th.max(1.0), "θ = {th}");
    }
}

#[test]
fn expm_nilpotent_is_a_finite_series() {
    // N strictly upper triangular (N⁴ = 0): e^N = I + N + N²/2 + N³/6 exactly.
    let n = mat(
        4,
        4,
        &[
            0.0, 2.0, -1.0, 3.0, 0.0, 0.0, 4.0, 0.5, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 0.0,
        ],
    );
    let n2 = &n * &n;
    let n3 = &n2 * &n;
    let exact = Mat::identity(4, 4) + &n + &n2 / 2.0 + &n3 / 6.0;
    // The Padé approximant is exact on nilpotent matrices up to rounding in the solve:
    // relative error a few u times the entries' growth (≤ 1e-14).
    assert!(rel(&expm(&n).unwrap(), &exact) < 1e-14);
}

#[test]
fn expm_diagonalisable_closed_form() {
    // A = V diag(−1, −3, 0.5) V⁻¹ with a well-conditioned V: e^A = V diag(e^λ) V⁻¹.
    let v = mat(3, 3, &[1.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 1.0]);
    let vinv = v.clone().try_inverse().unwrap();
    let lam = [-1.0, -3.0, 0.5];
    let a = &v * Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&lam)) * &vinv;
    let e_exact =
        &v * Mat::from_diagonal(&nalgebra::DVector::from_iterator(
            3,
            lam.iter().map(|l| l.exp()),
        )) * &vinv;
    // cond(V) ≈ 2 and ‖A‖ ≈ 3: relative error ≤ 1e-14 is ~50u.
    assert!(rel(&expm(&a).unwrap(), &e_exact) < 1e-14);
    // Scalar and zero cases.
    assert!((expm(&mat(1, 1, &[2.0])).unwrap()[(0, 0)] - 2f64.exp()).abs() < 4.0 * U * 2f64.exp());
    assert_eq!(expm(&Mat::zeros(3, 3)).unwrap(), Mat::identity(3, 3));
}

#[test]
fn expm_against_high_precision_reference() {
    let fx = fixture("expm.json");
    for case in fx["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let a = json_mat(&case["a"]);
        let want = json_mat(&case["expm_mp60"]);
        let kappa = case["kappa_exp"].as_f64().unwrap();
        let (got, info) = expm_with_info(&a).unwrap();
        let err = rel(&got, &want);
        // A backward-stable evaluation has relative forward error ≲ κ_exp(A)·u; allow a
        // factor 100 for the dimension and the squaring phase, and a floor of 100u.
        let tol = 100.0 * U * kappa.max(1.0);
        if name.starts_with("overscaling") {
            // κ_exp is huge (1e7–1e15), so check the stronger componentwise accuracy the
            // dₖ-based scaling delivers on [[1, b], [0, −1]] (Al-Mohy & Higham 2009, §1): every
            // entry of the closed form [[e, b sinh 1], [0, 1/e]] to 1e-13 relative (500u,
            // allowing rounding over the few squarings).
            let b = a[(0, 1)];
            let exact = [1f64.exp(), b * 1f64.sinh(), 0.0, (-1f64).exp()];
            for (k, &(i, j)) in [(0, 0), (0, 1), (1, 0), (1, 1)].iter().enumerate() {
                let e = exact[k];
                let d = (got[(i, j)] - e).abs();
                assert!(
                    d <= 1e-13 * e.abs().max(f64::MIN_POSITIVE) || (e == 0.0 && d == 0.0),
                    "{name}: entry ({i},{j}) {} vs {e} (squarings {})",
                    got[(i, j)],
                    info.squarings
                );
            }
        } else {
            assert!(
                err <= tol,
                "{name}: relative error {err:e} > {tol:e} (κ = {kappa:e}, m = {}, s = {})",
                info.pade_degree,
                info.squarings
            );
        }
    }
}

#[test]
fn expm_rejects_bad_input() {
    assert!(matches!(
        expm(&Mat::zeros(2, 3)),
        Err(LtiError::NotSquare { .. })
    ));
    assert!(matches!(
        expm(&mat(1, 1, &[f64::NAN])),
        Err(LtiError::NonFinite { .. })
    ));
    // Overflow is reported, not returned as infinities.
    assert!(expm(&mat(1, 1, &[1000.0])).is_err());
}

#[test]
fn logm_inverts_expm() {
    // log(e^X) = X when the eigenvalues of X have |Im| < π (principal branch): a random-like
    // fixed matrix with a complex pair and a real spread. Error bound: the condition of log at
    // e^X times u; with ‖X‖ ≈ 3 and well-separated eigenvalues, 1e-12 relative.
    let x = mat(
        4,
        4,
        &[
            -0.5, 1.2, 0.3, 0.0, -1.1, -0.4, 0.2, 0.7, 0.0, 0.5, -2.0, 0.1, 0.3, 0.0, 0.4, 0.8,
        ],
    );
    let l = logm(&expm(&x).unwrap()).unwrap();
    assert!(rel(&l, &x) < 1e-12, "error {:e}", rel(&l, &x));
    // Closed form: log of a rotation by θ < π is the generator.
    let th: f64 = 2.5;
    let r = mat(2, 2, &[th.cos(), -th.sin(), th.sin(), th.cos()]);
    let l = logm(&r).unwrap();
    assert!((l - mat(2, 2, &[0.0, -th, th, 0.0])).norm() < 1e-14);
    // Identity ↦ 0; a triangular matrix with a Jordan-like coupling: log([[a, 1], [0, a]]) =
    // [[ln a, 1/a], [0, ln a]].
    assert!(logm(&Mat::identity(3, 3)).unwrap().norm() < 1e-15);
    let a = 3.0f64;
    let l = logm(&mat(2, 2, &[a, 1.0, 0.0, a])).unwrap();
    assert!((l - mat(2, 2, &[a.ln(), 1.0 / a, 0.0, a.ln()])).norm() < 1e-14);
}

#[test]
fn logm_of_near_identity_keeps_relative_accuracy() {
    // X small (as in d2c at a fast sample rate): log(e^X) must recover X to relative 1e-10
    // even though e^X − I is only 1e-4 in size (cancellation costs ~u/‖X‖ ≈ 1e-12).
    let x = mat(2, 2, &[-1e-4, 3e-4, -2e-4, -5e-5]);
    let l = logm(&expm(&x).unwrap()).unwrap();
    assert!(rel(&l, &x) < 1e-10, "{:e}", rel(&l, &x));
}

#[test]
fn logm_refuses_negative_real_eigenvalues() {
    let e = logm(&mat(2, 2, &[-1.0, 0.0, 0.0, 2.0])).unwrap_err();
    assert!(
        matches!(e, LtiError::NoRealLogarithm { eigenvalue, .. } if eigenvalue == Complex64::new(-1.0, 0.0))
    );
    assert!(matches!(
        logm(&mat(2, 2, &[0.0, 1.0, 0.0, 1.0])),
        Err(LtiError::NoRealLogarithm { .. })
    ));
}

#[test]
fn sqrtm_squares_back() {
    // Defining identity X² = A, with a complex pair and real eigenvalues in the Schur form.
    let a = mat(3, 3, &[4.0, 1.0, 0.5, -2.0, 3.0, 0.2, 0.1, 0.3, 9.0]);
    let x = sqrtm(&a).unwrap();
    assert!(rel(&(&x * &x), &a) < 1e-14);
    // Principal root: eigenvalues in the right half-plane.
    let ev = pendulab_lti::linalg::eigenvalues(&x).unwrap();
    assert!(ev.iter().all(|l| l.re > 0.0));
}

#[test]
fn block_exponential_integrals_match_quadrature_free_closed_forms() {
    // Scalar a: Φ = e^{at}, Γ = (e^{at} − 1)/a · b, Γ₁ = ∫₀ᵗ e^{as}(t − s)/t ds b
    //   = b (e^{at} − 1 − a t)/(a² t).
    let (a, b, t) = (-1.7f64, 0.6, 0.35);
    let (phi, g) = zoh_integrals(&mat(1, 1, &[a]), &mat(1, 1, &[b]), t).unwrap();
    let (phi2, g0, g1) = foh_integrals(&mat(1, 1, &[a]), &mat(1, 1, &[b]), t).unwrap();
    let e = (a * t).exp();
    // Relative 1e-14: a handful of roundings in a well-conditioned 2×2/3×3 exponential.
    assert!((phi[(0, 0)] - e).abs() < 1e-14);
    assert!((phi2[(0, 0)] - e).abs() < 1e-14);
    assert!((g[(0, 0)] - (e - 1.0) / a * b).abs() < 1e-14);
    assert!((g0[(0, 0)] - (e - 1.0) / a * b).abs() < 1e-14);
    assert!((g1[(0, 0)] - b * (e - 1.0 - a * t) / (a * a * t)).abs() < 1e-14);
    // Van Loan: ∫₀ᵗ e^{2fs} w ds = w (e^{2ft} − 1)/(2f) for scalars.
    let (f, w) = (-0.8f64, 2.5);
    let (ef, int) = van_loan_integral(&mat(1, 1, &[f]), &mat(1, 1, &[w]), t).unwrap();
    assert!((ef[(0, 0)] - (f * t).exp()).abs() < 1e-15);
    assert!((int[(0, 0)] - w * ((2.0 * f * t).exp() - 1.0) / (2.0 * f)).abs() < 1e-14);
}
