//! Real Schur decomposition and reordering: defining identities (reconstruction,
//! orthogonality, standard form, invariant subspaces) and eigenvalues of matrices built with a
//! known spectrum.

mod equations_support;

use equations_support::*;
use pendulab_lti::linalg::schur::{ordered_schur, real_schur};
use pendulab_lti::{Complex64, Mat};

const EPS: f64 = f64::EPSILON;

/// Reconstruction and orthogonality of `A = Z T Zᵀ`. A backward-stable Schur algorithm
/// (Householder/Givens only) gives errors of order `c·n·ε‖A‖` with a small constant; the bound
/// `10·n·ε` leaves room for that constant and is still ~10⁻¹² at n = 200.
fn check_decomposition(a: &Mat, t: &Mat, z: &Mat) {
    let n = a.nrows() as f64;
    let rec = (z * t * z.transpose() - a).norm() / a.norm().max(f64::MIN_POSITIVE);
    assert!(rec <= 10.0 * n * EPS, "reconstruction error {rec:e}");
    let orth = orthogonality_error(z);
    assert!(orth <= 10.0 * n * EPS, "orthogonality error {orth:e}");
    check_standard_form(t).unwrap();
}

#[test]
fn random_matrices_decompose() {
    let mut r = rng(1);
    for &n in &[1usize, 2, 3, 4, 5, 8, 13, 30, 64, 120, 200] {
        let a = rand_mat(&mut r, n, n);
        let s = real_schur(&a).unwrap();
        check_decomposition(&a, s.t(), s.z());
    }
}

#[test]
fn known_spectrum_is_recovered() {
    // A = Q D Qᵀ with D block diagonal holding chosen eigenvalues (real and complex pairs):
    // the eigenvalues are known exactly; the computed ones must agree to a perturbation bound
    // ε‖A‖·κ with κ = 1 here (A is normal), so 100 ε‖A‖ is generous.
    let mut r = rng(2);
    let n = 9;
    let wanted = [
        Complex64::new(-3.0, 0.0),
        Complex64::new(2.0, 0.0),
        Complex64::new(0.5, 4.0),
        Complex64::new(0.5, -4.0),
        Complex64::new(-1.0, 0.25),
        Complex64::new(-1.0, -0.25),
        Complex64::new(0.0, 0.0),
        Complex64::new(7.0, 1.0),
        Complex64::new(7.0, -1.0),
    ];
    let mut d = Mat::zeros(n, n);
    let mut k = 0;
    while k < n {
        let w = wanted[k];
        if w.im == 0.0 {
            d[(k, k)] = w.re;
            k += 1;
        } else {
            d[(k, k)] = w.re;
            d[(k + 1, k + 1)] = w.re;
            d[(k, k + 1)] = w.im;
            d[(k + 1, k)] = -w.im;
            k += 2;
        }
    }
    let q = rand_orthogonal(&mut r, n);
    let a = &q * d * q.transpose();
    let ev = pendulab_lti::linalg::eigenvalues(&a).unwrap();
    let d = eig_distance(&ev, &wanted);
    assert!(d <= 100.0 * EPS * a.norm(), "eigenvalue error {d:e}");
}

#[test]
fn companion_matrix_roots() {
    // Companion matrix of (s+1)(s+2)(s+3)(s²+2s+5): roots −1, −2, −3, −1 ± 2j, a closed form.
    // Polynomial s⁵ + 8s⁴ + 28s³ + 58s² + 67s + 30 (expanded by hand: (s³+6s²+11s+6)(s²+2s+5)).
    let c = [8.0, 28.0, 58.0, 67.0, 30.0];
    let n = 5;
    let mut a = Mat::zeros(n, n);
    for j in 0..n {
        a[(0, j)] = -c[j];
    }
    for i in 1..n {
        a[(i, i - 1)] = 1.0;
    }
    let ev = pendulab_lti::linalg::eigenvalues(&a).unwrap();
    let ex = [
        Complex64::new(-1.0, 2.0),
        Complex64::new(-1.0, -2.0),
        Complex64::new(-1.0, 0.0),
        Complex64::new(-2.0, 0.0),
        Complex64::new(-3.0, 0.0),
    ];
    // Simple roots of a modest polynomial: condition numbers ≲ 10², so 1e-12 absolute.
    let d = eig_distance(&ev, &ex);
    assert!(d < 1e-12, "eigenvalue error {d:e}");
}

#[test]
fn special_structures() {
    // Zero, identity, already triangular, a nilpotent Jordan block, a rotation generator,
    // and a graded matrix: all must decompose without failure.
    let mut cases = vec![
        Mat::zeros(4, 4),
        Mat::identity(5, 5),
        Mat::from_fn(6, 6, |i, j| if j >= i { (i + 2 * j) as f64 } else { 0.0 }),
        Mat::from_fn(6, 6, |i, j| if j == i + 1 { 1.0 } else { 0.0 }),
        Mat::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]),
        Mat::from_fn(8, 8, |i, j| {
            10f64.powi(i as i32 - j as i32) * ((i * 7 + j * 3) % 5) as f64
        }),
    ];
    // Hamiltonian-like matrix with eigenvalues ±λ.
    let mut r = rng(3);
    let a = rand_mat(&mut r, 5, 5);
    let g = rand_mat(&mut r, 5, 5);
    let g = &g * g.transpose();
    let q = rand_mat(&mut r, 5, 5);
    let q = &q * q.transpose();
    let mut h = Mat::zeros(10, 10);
    h.view_mut((0, 0), (5, 5)).copy_from(&a);
    h.view_mut((0, 5), (5, 5)).copy_from(&(-&g));
    h.view_mut((5, 0), (5, 5)).copy_from(&(-&q));
    h.view_mut((5, 5), (5, 5)).copy_from(&(-a.transpose()));
    cases.push(h);
    for a in &cases {
        let s = real_schur(a).unwrap();
        let n = a.nrows() as f64;
        let rec = (s.z() * s.t() * s.z().transpose() - a).norm();
        assert!(rec <= 10.0 * n * EPS * a.norm().max(1.0), "rec {rec:e}");
        check_standard_form(s.t()).unwrap();
    }
}

/// After reordering, the selected eigenvalues lead, `A Z₁ = Z₁ T₁₁` (invariant subspace), and
/// the decomposition is still exact to rounding.
#[test]
fn reorder_moves_stable_eigenvalues_first() {
    let mut r = rng(4);
    for &n in &[2usize, 3, 6, 11, 40, 100] {
        let a = rand_mat(&mut r, n, n);
        let (s, k) = ordered_schur(&a, |l| l.re < 0.0).unwrap();
        check_decomposition(&a, s.t(), s.z());
        let ev = s.eigenvalues();
        let nstable = ev.iter().filter(|l| l.re < 0.0).count();
        assert_eq!(k, nstable);
        assert!(ev[..k].iter().all(|l| l.re < 0.0));
        assert!(ev[k..].iter().all(|l| l.re >= 0.0));
        // Eigenvalues unchanged as a set (swaps are backward stable; these random matrices
        // have eigenvalue condition numbers ≲ 10³, so 1e-10 absolute).
        let before = pendulab_lti::linalg::eigenvalues(&a).unwrap();
        let d = eig_distance(&ev, &before);
        assert!(d < 1e-10, "eigenvalues moved by {d:e}");
        let z1 = s.z().columns(0, k).into_owned();
        let t11 = s.t().view((0, 0), (k, k)).into_owned();
        let inv = (&a * &z1 - &z1 * t11).norm() / a.norm();
        assert!(inv <= 10.0 * n as f64 * EPS, "invariance {inv:e}");
    }
}

#[test]
fn move_block_both_directions() {
    let mut r = rng(5);
    let n = 12;
    let a = rand_mat(&mut r, n, n);
    let mut s = real_schur(&a).unwrap();
    let blocks = s.blocks();
    let last = blocks.last().unwrap().start;
    let ev_last = s.eigenvalues()[last];
    let pos = s.move_block(last, 0).unwrap();
    assert_eq!(pos, 0);
    // The moved eigenvalue (a sum of exact swaps, backward stable) is now first.
    assert!((s.eigenvalues()[0] - ev_last).norm() < 1e-12);
    check_decomposition(&a, s.t(), s.z());
    let first_ev = s.eigenvalues()[0];
    let end = s.move_block(0, n - 1).unwrap();
    let ev = s.eigenvalues();
    assert!((ev[end] - first_ev).norm() < 1e-12);
    check_decomposition(&a, s.t(), s.z());
    assert!(s.move_block(n, 0).is_err());
}

#[test]
fn reorder_with_complex_pairs_and_splits() {
    // Matrices whose 2×2 blocks are nearly real (eigenvalues a ± tiny j) exercise the
    // split-pair branches of the block mover.
    let mut r = rng(6);
    for trial in 0..20 {
        let n = 10;
        let mut d = Mat::zeros(n, n);
        for k in (0..n).step_by(2) {
            let re = r.random_range(-2.0..2.0);
            let im = if trial % 2 == 0 {
                1e-9
            } else {
                r.random_range(0.1..2.0)
            };
            d[(k, k)] = re;
            d[(k + 1, k + 1)] = re;
            d[(k, k + 1)] = im;
            d[(k + 1, k)] = -im;
        }
        let q = rand_orthogonal(&mut r, n);
        let a = &q * (d + rand_mat(&mut r, n, n).upper_triangle() * 0.3) * q.transpose();
        let (s, k) = ordered_schur(&a, |l| l.re > 0.0).unwrap();
        check_decomposition(&a, s.t(), s.z());
        let ev = s.eigenvalues();
        assert!(ev[..k].iter().all(|l| l.re > 0.0));
        assert!(ev[k..].iter().all(|l| l.re <= 0.0));
    }
}

use rand::Rng;
