//! Pole placement: the book's observer-based design (p1c74_ex1), Ackermann vs KNV, multi-input
//! placement with complex and repeated poles, observers by duality, errors.

mod sys_support;

use pendulab_lti::design::{PlacementMethod, StateFeedback, acker, place, place_observer};
use pendulab_lti::polynomial::Polynomial;
use pendulab_lti::{Complex64, LtiError, Mat};
use rand::{Rng, SeedableRng};
use sys_support::{assert_same_poles, c, cdip, mat};

fn book_poles() -> Vec<Complex64> {
    vec![c(-6.5, 1.5), c(-6.5, -1.5), c(-4.0, 0.0), c(-2.5, 0.0)]
}

#[test]
fn p1c74_ex1_state_feedback_gain() {
    // Book: poles {−6.5 ± 1.5j, −4, −2.5} → K = [3.06513, 12.57293, 4.32424, 2.16707] in the
    // book's convention u = +K x; printed to 5 decimals (tolerance half a unit, 5e-6).
    let (a, b) = cdip();
    let book = mat(1, 4, &[3.06513, 12.57293, 4.32424, 2.16707]);
    for p in [
        place(&a, &b, &book_poles()).unwrap(),
        acker(&a, &b, &book_poles()).unwrap(),
    ] {
        let fb = StateFeedback::new(p.gain.clone()).unwrap();
        let kb = fb.book_gain();
        for j in 0..4 {
            assert!(
                (kb[(0, j)] - book[(0, j)]).abs() < 5e-6,
                "{:?}: {kb}",
                p.method
            );
        }
        // The reported accuracy is honest: recompute eig(A − BK) independently.
        let ev = pendulab_lti::linalg::eigenvalues(&(&a - &b * &p.gain)).unwrap();
        assert_same_poles(&ev, &book_poles(), 1e-10 * 6.7);
        assert!(p.max_relative_error < 1e-12);
    }
    // Round trip of the convention type.
    let fb = StateFeedback::from_book(&book).unwrap();
    assert_eq!(fb.gain(), &(-&book));
    let u = fb.control(&[1.0, 0.0, 0.0, 0.0]).unwrap();
    assert_eq!(u, vec![book[(0, 0)]]);
}

#[test]
fn ackermann_matches_knv_on_single_input() {
    // Single input: the gain is unique, so Ackermann's formula and KNV must agree.
    let (a, b) = cdip();
    let sets = [
        book_poles(),
        vec![c(-1.0, 0.0), c(-2.0, 0.0), c(-3.0, 0.0), c(-4.0, 0.0)],
        vec![c(-2.0, 3.0), c(-2.0, -3.0), c(-5.0, 1.0), c(-5.0, -1.0)],
    ];
    for poles in sets {
        let k1 = acker(&a, &b, &poles).unwrap();
        let k2 = place(&a, &b, &poles).unwrap();
        assert_eq!(k2.method, PlacementMethod::KautskyNicholsVanDooren);
        // cond(M_c) of the cart pendulum is ~1e3, so Ackermann carries ~1e-13 relative error;
        // 1e-9 leaves room for the eigenvector route's own conditioning.
        let d = (&k1.gain - &k2.gain).norm() / k2.gain.norm();
        assert!(d < 1e-9, "{poles:?}: {d:e}");
    }
}

fn random_pair(n: usize, m: usize, seed: u64) -> (Mat, Mat) {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let a = Mat::from_fn(n, n, |_, _| rng.random_range(-1.0..1.0));
    let b = Mat::from_fn(n, m, |_, _| rng.random_range(-1.0..1.0));
    (a, b)
}

/// Characteristic polynomial of `A − BK` evaluated at `s`, against the desired one: the
/// coefficients of a polynomial are well conditioned even where repeated roots are not.
fn charpoly_mismatch(a: &Mat, b: &Mat, k: &Mat, poles: &[Complex64]) -> f64 {
    let acl = a - b * k;
    let n = a.nrows();
    let want = Polynomial::from_roots(poles).unwrap();
    let mut worst: f64 = 0.0;
    for s in [c(0.3, 0.2), c(-1.0, 2.0), c(2.0, 0.0), c(-4.0, -1.0)] {
        let mut m = pendulab_lti::CMat::zeros(n, n);
        for i in 0..n {
            for j in 0..n {
                m[(i, j)] = Complex64::new(-acl[(i, j)], 0.0);
            }
            m[(i, i)] += s;
        }
        let det = m.determinant();
        let w = want.eval_complex(s);
        worst = worst.max((det - w).norm() / w.norm());
    }
    worst
}

#[test]
fn multi_input_placement_with_complex_and_repeated_poles() {
    for (n, m, seed) in [(6, 2, 1u64), (8, 3, 2), (10, 4, 3)] {
        let (a, b) = random_pair(n, m, seed);
        // Complex pairs, reals, and a pole repeated m times (allowed: multiplicity ≤ rank B).
        let mut poles = vec![c(-1.0, 1.0), c(-1.0, -1.0), c(-2.0, 0.5), c(-2.0, -0.5)];
        while poles.len() < n - m {
            poles.push(c(-3.0 - poles.len() as f64 * 0.5, 0.0));
        }
        while poles.len() < n {
            poles.push(c(-1.5, 0.0));
        }
        let p = place(&a, &b, &poles).unwrap();
        assert_eq!(p.method, PlacementMethod::KautskyNicholsVanDooren);
        // KNV gives a diagonalisable closed loop with a moderate eigenvector condition, so the
        // (even repeated) poles are placed to ~cond(X)·u relative; 1e-8 is far below any
        // practical need and far above rounding.
        assert!(p.eigenvector_condition.is_finite());
        assert!(
            p.max_relative_error < 1e-8,
            "n={n} m={m}: error {:e}, cond {:e}",
            p.max_relative_error,
            p.eigenvector_condition
        );
        assert!(charpoly_mismatch(&a, &b, &p.gain, &poles) < 1e-8);
    }
}

/// With as many inputs as states every basis of KNV's eigenvector spaces is the identity,
/// a real one: a complex pole's starting vector must still be independent of its conjugate.
/// B = I, A = 0 (the closed loop is −K: any K = −M with eig(M) the poles) and random square
/// pairs, only complex poles (a repeated pair too) and complex with real ones; the closed
/// loop's characteristic polynomial against the requested one (away from its evaluation
/// points).
#[test]
fn square_b_with_complex_poles() {
    let two = [c(-1.0, 1.0), c(-1.0, -1.0)];
    let p = place(&Mat::zeros(2, 2), &Mat::identity(2, 2), &two).unwrap();
    assert_eq!(p.method, PlacementMethod::KautskyNicholsVanDooren);
    assert!(p.max_relative_error < 1e-12, "{:e}", p.max_relative_error);
    assert!(charpoly_mismatch(&Mat::zeros(2, 2), &Mat::identity(2, 2), &p.gain, &two) < 1e-12);
    let sets: [&[Complex64]; 3] = [
        &[c(-1.0, 1.5), c(-1.0, -1.5), c(-3.0, 0.5), c(-3.0, -0.5)],
        &[c(-1.0, 1.0), c(-1.0, -1.0), c(-1.0, 1.0), c(-1.0, -1.0)],
        &[c(-2.0, 1.0), c(-2.0, -1.0), c(-0.5, 0.0), c(-4.0, 0.0)],
    ];
    for (seed, poles) in sets.iter().enumerate() {
        for (a, b) in [
            (Mat::zeros(4, 4), Mat::identity(4, 4)),
            random_pair(4, 4, 40 + seed as u64),
        ] {
            let p = place(&a, &b, poles).unwrap();
            assert!(p.eigenvector_condition.is_finite());
            assert!(
                p.max_relative_error < 1e-9,
                "{poles:?}: error {:e}, cond {:e}",
                p.max_relative_error,
                p.eigenvector_condition
            );
            assert!(
                charpoly_mismatch(&a, &b, &p.gain, poles) < 1e-9,
                "{poles:?}"
            );
        }
    }
    // Three states, two inputs: the null spaces are 2-dimensional and complex.
    let (a, b) = random_pair(3, 2, 50);
    let poles = [c(-1.0, 3.0), c(-1.0, -3.0), c(-2.0, 0.0)];
    let p = place(&a, &b, &poles).unwrap();
    assert!(charpoly_mismatch(&a, &b, &p.gain, &poles) < 1e-9);
}

#[test]
fn repeated_poles_beyond_rank_b() {
    // Single input, all four poles at −3 (Jordan block): the gain is unique; compare the
    // characteristic polynomial (well conditioned) rather than the roots (ill conditioned,
    // perturbed by ~u^{1/4}).
    let (a, b) = cdip();
    let poles = vec![c(-3.0, 0.0); 4];
    let p = place(&a, &b, &poles).unwrap();
    assert_eq!(p.method, PlacementMethod::HessenbergAckermann);
    assert!(charpoly_mismatch(&a, &b, &p.gain, &poles) < 1e-10);
    let k = acker(&a, &b, &poles).unwrap();
    assert!((&k.gain - &p.gain).norm() < 1e-9 * p.gain.norm());
    // Two inputs, a pole of multiplicity 3 > 2.
    let (a, b) = random_pair(5, 2, 11);
    let poles = vec![
        c(-2.0, 0.0),
        c(-2.0, 0.0),
        c(-2.0, 0.0),
        c(-1.0, 1.0),
        c(-1.0, -1.0),
    ];
    let p = place(&a, &b, &poles).unwrap();
    assert_eq!(p.method, PlacementMethod::SingleInputReduction);
    assert!(charpoly_mismatch(&a, &b, &p.gain, &poles) < 1e-8);
}

#[test]
fn rank_deficient_b_is_compressed() {
    // B with two identical columns behaves as one input; poles must still be placed.
    let (a, b1) = cdip();
    let b = Mat::from_fn(4, 2, |i, _| b1[(i, 0)]);
    let p = place(&a, &b, &book_poles()).unwrap();
    assert!(p.max_relative_error < 1e-10);
    assert_same_poles(
        &pendulab_lti::linalg::eigenvalues(&(&a - &b * &p.gain)).unwrap(),
        &book_poles(),
        1e-9,
    );
}

#[test]
fn observer_by_duality() {
    // p1c74_ex1: y = [z, θ]; observer poles four times the state-feedback poles.
    let (a, _) = cdip();
    let cm = mat(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let obs: Vec<Complex64> = book_poles().iter().map(|p| p * 4.0).collect();
    let l = place_observer(&a, &cm, &obs).unwrap();
    assert_eq!(l.gain.shape(), (4, 2));
    let ev = pendulab_lti::linalg::eigenvalues(&(&a - &l.gain * &cm)).unwrap();
    assert_same_poles(&ev, &obs, 1e-9 * 26.0);
    // Unobservable output (y = z alone): refused.
    let cz = mat(1, 4, &[1.0, 0.0, 0.0, 0.0]);
    assert!(matches!(
        place_observer(&a, &cz, &obs),
        Err(LtiError::NotControllable { .. })
    ));
}

#[test]
fn placement_errors() {
    // p1c511_ex2 is uncontrollable: arbitrary placement is impossible.
    let a = mat(3, 3, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
    let b = mat(3, 1, &[0.0, 0.0, 1.0]);
    let poles = [c(-1.0, 0.0), c(-2.0, 0.0), c(-3.0, 0.0)];
    let e = place(&a, &b, &poles).unwrap_err();
    assert!(
        matches!(e, LtiError::NotControllable { controllable_dimension: 2, nx: 3, mode } if (mode - c(1.0, 0.0)).norm() < 1e-12),
        "{e}"
    );
    assert!(acker(&a, &b, &poles).is_err());
    let (a, b) = cdip();
    // Wrong count, unpaired complex pole, NaN.
    assert!(matches!(
        place(&a, &b, &poles),
        Err(LtiError::InvalidArgument(_))
    ));
    assert!(matches!(
        place(
            &a,
            &b,
            &[c(-1.0, 1.0), c(-2.0, 0.0), c(-3.0, 0.0), c(-4.0, 0.0)]
        ),
        Err(LtiError::InvalidArgument(_))
    ));
    assert!(matches!(
        place(
            &a,
            &b,
            &[c(f64::NAN, 0.0), c(-2.0, 0.0), c(-3.0, 0.0), c(-4.0, 0.0)]
        ),
        Err(LtiError::NonFinite { .. })
    ));
    assert!(acker(&a, &Mat::zeros(4, 2), &book_poles()).is_err());
}

#[test]
fn rank_deficient_input_matrix_of_identical_columns() {
    // B = ones(5, 3): three identical inputs, rank 1, so `place` compresses B to its range by
    // an SVD with singular vectors — a shape on which nalgebra's SVD with vectors returns a
    // wrong σ₁ (nalgebra issue #1172; σ₁ = √15 in closed form). With a controllable (A, b)
    // (A a chain of integrators, b the all-ones column: controllability matrix triangular
    // after elimination) the requested poles must come out as the eigenvalues of A − BK,
    // recomputed independently.
    let n = 5;
    let a = Mat::from_fn(n, n, |i, j| if j == i + 1 { 1.0 } else { 0.0 });
    let b = Mat::from_element(n, 3, 1.0);
    let poles: Vec<Complex64> = [-1.0, -2.0, -3.0, -4.0, -5.0]
        .iter()
        .map(|&p| c(p, 0.0))
        .collect();
    let p = place(&a, &b, &poles).unwrap();
    let ev = pendulab_lti::linalg::eigenvalues(&(&a - &b * &p.gain)).unwrap();
    // Distinct real poles of a 5 × 5 companion-like closed loop: the eigenvalue condition
    // numbers are O(10²–10³), so 1e-8 relative leaves a wide margin over ε·κ.
    assert_same_poles(&ev, &poles, 1e-8 * 5.0);
    assert!(p.max_relative_error < 1e-8, "{}", p.max_relative_error);
}
