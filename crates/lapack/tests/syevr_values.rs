//! `dsyevr` with `JOBZ = 'N'` (eigenvalues only, the call Clarabel's PSD step length makes):
//! against SciPy's LAPACK (fixture of `tools/reference/lapack_shim.py`), against the
//! eigenvector path `JOBZ = 'V'` of the same symbol (a different algorithm: nalgebra's
//! symmetric QR with accumulated rotations) on larger random matrices, and against closed
//! forms.
//!
//! Tolerance 1e-12 relative to ‖A‖_F, as in `reference.rs`: both sides are backward-stable
//! double-precision eigensolvers, so their eigenvalues agree to O(n ε ‖A‖) (≈ 1e-14 here);
//! a wrong triangle, sign or ordering gives errors of order 1.

use core::ffi::{c_char, c_int};
use pendulab_lapack::ffi::dsyevr_;
use serde_json::Value;

mod common;
use common::lcg_entries as lcg;

const TOL: f64 = 1e-12;

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

/// Calls `dsyevr_` as Clarabel does (workspace query, then the computation) and returns
/// (info, eigenvalues found, and the vectors for JOBZ = 'V').
#[allow(clippy::too_many_arguments)]
fn call(
    jobz: u8,
    range: u8,
    uplo: u8,
    n: usize,
    a: &mut [f64],
    lda: usize,
    (vl, vu): (f64, f64),
    (il, iu): (c_int, c_int),
) -> (c_int, Vec<f64>, Vec<f64>) {
    let mut m: c_int = -1;
    let mut w = vec![0.0; n];
    let mut z = vec![0.0; if jobz == b'V' { n * n } else { 1 }];
    let mut isuppz = vec![0 as c_int; 2 * n.max(1)];
    let mut work = vec![0.0; 1];
    let mut iwork = vec![0 as c_int; 1];
    let mut info: c_int = -77;
    let ldz = if jobz == b'V' { n.max(1) } else { 1 } as c_int;
    for pass in 0..2 {
        let (lwork, liwork) = if pass == 0 {
            (-1, -1)
        } else {
            (work.len() as c_int, iwork.len() as c_int)
        };
        info = unsafe {
            common::syevr(
                dsyevr_,
                (jobz as c_char, range as c_char, uplo as c_char),
                (n as c_int, a, lda as c_int),
                (vl, vu, il, iu, -1.0),
                (&mut m, &mut w, &mut z, ldz, &mut isuppz),
                (&mut work, lwork, &mut iwork, liwork),
            )
        };
        if info != 0 {
            return (info, Vec::new(), Vec::new());
        }
        if pass == 0 {
            work.resize(work[0] as usize, 0.0);
            iwork.resize(iwork[0] as usize, 0);
        }
    }
    w.truncate(m as usize);
    (info, w, z)
}

fn dist(x: &[f64], y: &[f64]) -> f64 {
    assert_eq!(x.len(), y.len(), "number of eigenvalues");
    x.iter()
        .zip(y)
        .map(|(p, q)| (p - q).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Column-major symmetric `n × n` with leading dimension `lda`, the triangle not named by
/// `uplo` poisoned with NaN (it must not be read).
fn stored(full: &[f64], n: usize, lda: usize, uplo: u8) -> Vec<f64> {
    let mut a = vec![f64::NAN; lda * n];
    for j in 0..n {
        for i in 0..n {
            if (uplo == b'U' && i <= j) || (uplo == b'L' && i >= j) {
                a[i + j * lda] = full[i + j * n];
            }
        }
    }
    a
}

#[test]
fn values_only_match_scipy_for_every_range_and_triangle() {
    let f: Value =
        serde_json::from_str(include_str!("fixtures/lapack_reference.json")).expect("fixture");
    for c in f["cases"]["syevr"].as_array().unwrap() {
        let rows: Vec<Vec<f64>> = c["a"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r.as_array().unwrap().iter().map(num).collect())
            .collect();
        let n = rows.len();
        let full: Vec<f64> = (0..n * n).map(|k| rows[k % n][k / n]).collect();
        let uplo = c["uplo"].as_str().unwrap().as_bytes()[0];
        let range = c["range"].as_str().unwrap().as_bytes()[0];
        let lda = n + 2;
        let mut a = stored(&full, n, lda, uplo);
        let il = c["il"].as_u64().unwrap() as c_int;
        let iu = c["iu"].as_u64().unwrap() as c_int;
        let (info, w, _) = call(
            b'N',
            range,
            uplo,
            n,
            &mut a,
            lda,
            (num(&c["vl"]), num(&c["vu"])),
            (il, iu),
        );
        assert_eq!(info, 0);
        let w_ref: Vec<f64> = c["w"].as_array().unwrap().iter().map(num).collect();
        let scale = full.iter().map(|v| v * v).sum::<f64>().sqrt();
        let d = dist(&w, &w_ref);
        assert!(d <= TOL * scale, "{d:e} vs ‖A‖ {scale}");
        // The unnamed triangle and the padding rows were not written.
        for j in 0..n {
            for i in 0..lda {
                let named = i < n && ((uplo == b'U' && i <= j) || (uplo == b'L' && i >= j));
                if !named {
                    assert!(a[i + j * lda].is_nan(), "({i}, {j}) written");
                }
            }
        }
    }
}

#[test]
fn values_only_agree_with_the_eigenvector_path_on_larger_matrices() {
    for (n, seed) in [(4, 1), (11, 2), (20, 3), (31, 4), (64, 5)] {
        let r = lcg(n * n, seed);
        // Symmetric, with a spread of magnitudes (diagonal grows with the index).
        let full: Vec<f64> = (0..n * n)
            .map(|k| {
                let (i, j) = (k % n, k / n);
                let s = r[i.min(j) + i.max(j) * n];
                if i == j { s + i as f64 } else { s }
            })
            .collect();
        let scale = full.iter().map(|v| v * v).sum::<f64>().sqrt();
        for uplo in [b'U', b'L'] {
            let mut a = stored(&full, n, n, uplo);
            let (info, w, _) = call(b'N', b'A', uplo, n, &mut a, n, (0.0, 0.0), (0, 0));
            assert_eq!(info, 0);
            let mut b = stored(&full, n, n, uplo);
            let (info_v, w_v, _) = call(b'V', b'A', uplo, n, &mut b, n, (0.0, 0.0), (0, 0));
            assert_eq!(info_v, 0);
            assert!(w.windows(2).all(|p| p[0] <= p[1]), "ascending");
            let d = dist(&w, &w_v);
            assert!(d <= TOL * scale, "n = {n}: {d:e} vs ‖A‖ {scale}");
            // Trace and Frobenius norm are invariants: Σλ = tr A, Σλ² = ‖A‖_F².
            let tr: f64 = (0..n).map(|i| full[i + i * n]).sum();
            let sum: f64 = w.iter().sum();
            assert!((sum - tr).abs() <= TOL * scale * n as f64);
            let sq: f64 = w.iter().map(|x| x * x).sum();
            assert!((sq - scale * scale).abs() <= TOL * scale * scale * n as f64);
        }
    }
}

#[test]
fn closed_forms_diagonal_repeated_and_two_by_two() {
    // Diagonal (no reflection needed): the sorted diagonal.
    let n = 6;
    let diag = [3.0, -1.0, 0.5, 2.0, -7.0, 0.0];
    let mut a = vec![0.0; n * n];
    for i in 0..n {
        a[i + i * n] = diag[i];
    }
    let (_, w, _) = call(b'N', b'A', b'L', n, &mut a, n, (0.0, 0.0), (0, 0));
    assert_eq!(w, vec![-7.0, -1.0, 0.0, 0.5, 2.0, 3.0]);
    // 2 I + 1 1ᵀ (n = 5): eigenvalue 2 four times and 2 + n once.
    let n = 5;
    let mut a: Vec<f64> = (0..n * n)
        .map(|k| if k % n == k / n { 3.0 } else { 1.0 })
        .collect();
    let (_, w, _) = call(b'N', b'A', b'U', n, &mut a, n, (0.0, 0.0), (0, 0));
    let expect = [2.0, 2.0, 2.0, 2.0, 7.0];
    assert!(dist(&w, &expect) <= 1e-14 * 7.0, "{w:?}");
    // [[a, b], [b, c]]: (a + c)/2 ∓ √(((a − c)/2)² + b²); with RANGE = 'I' the larger only.
    let (p, q, r) = (1.5, -2.0, 0.25);
    let mut a = vec![p, q, q, r];
    let h = ((p - r) / 2.0f64).hypot(q);
    let (_, w, _) = call(b'N', b'I', b'U', 2, &mut a, 2, (0.0, 0.0), (2, 2));
    assert!((w[0] - ((p + r) / 2.0 + h)).abs() <= 1e-15 * 4.0);
    assert_eq!(w.len(), 1);
    // A non-finite entry of the named triangle is a computational failure (INFO > 0).
    let mut a = vec![1.0, f64::INFINITY, 0.0, 1.0];
    let (info, _, _) = call(b'N', b'A', b'L', 2, &mut a, 2, (0.0, 0.0), (0, 0));
    assert!(info > 0, "info = {info}");
}

/// Every side 1..=17 — the sides ≤ 16 reduce a full copy on the stack, 17 the stored
/// triangle — with a padded leading dimension, both triangles, on a dense matrix and on an
/// arrow matrix whose columns below the subdiagonal are partly zero (the Householder steps
/// that find nothing to annihilate): against the eigenvector path (nalgebra's QR with
/// accumulated rotations) and the invariants `Σλ = tr A`, `Σλ² = ‖A‖_F²`. Same tolerances
/// as above (both sides backward stable, O(n ε ‖A‖) ≈ 1e-14 here).
#[test]
fn values_only_on_every_small_side_and_the_packed_path() {
    for n in 1..=17 {
        let r = lcg(n * n, 40 + n as u64);
        for arrow in [false, true] {
            let full: Vec<f64> = (0..n * n)
                .map(|k| {
                    let (i, j) = (k % n, k / n);
                    let s = r[i.min(j) + i.max(j) * n];
                    // Arrow: diagonal, first row and column only.
                    if arrow && i != j && i.min(j) != 0 {
                        0.0
                    } else {
                        s
                    }
                })
                .collect();
            let scale = full.iter().map(|v| v * v).sum::<f64>().sqrt();
            let lda = n + 3;
            for uplo in [b'U', b'L'] {
                let mut a = stored(&full, n, lda, uplo);
                let (info, w, _) = call(b'N', b'A', uplo, n, &mut a, lda, (0.0, 0.0), (0, 0));
                assert_eq!(info, 0);
                let mut b = stored(&full, n, lda, uplo);
                let (info_v, w_v, _) = call(b'V', b'A', uplo, n, &mut b, lda, (0.0, 0.0), (0, 0));
                assert_eq!(info_v, 0);
                assert!(w.windows(2).all(|p| p[0] <= p[1]), "ascending");
                let d = dist(&w, &w_v);
                assert!(
                    d <= TOL * scale,
                    "n = {n} arrow {arrow}: {d:e} vs ‖A‖ {scale}"
                );
                let tr: f64 = (0..n).map(|i| full[i + i * n]).sum();
                let sum: f64 = w.iter().sum();
                assert!((sum - tr).abs() <= TOL * scale * n as f64);
                let sq: f64 = w.iter().map(|x| x * x).sum();
                assert!((sq - scale * scale).abs() <= TOL * scale * scale * n as f64);
            }
        }
    }
}

/// The Clement (Kac) matrix: zero diagonal, off-diagonal `√(i (n − i))`, `i = 1..n−1`, has
/// the eigenvalues `−(n−1), −(n−3), …, n−1` exactly (M. Kac, *Amer. Math. Monthly* 54, 1947;
/// P. A. Clement, *SIAM Rev.* 1, 1959). It is already tridiagonal and its zero diagonal
/// makes every relative deflation test hinge on the off-diagonals. Scaled by `2^±600`, the
/// squares the root-free QR carries would over- or underflow without the scaling step; the
/// eigenvalues must scale exactly with the matrix. Tolerance 1e-12 ‖A‖_F as above.
#[test]
fn clement_matrix_closed_form_also_at_extreme_scales() {
    for n in 1..=17usize {
        for factor in [1.0, 2f64.powi(600), 2f64.powi(-600)] {
            let mut full = vec![0.0; n * n];
            for i in 1..n {
                let v = factor * ((i * (n - i)) as f64).sqrt();
                full[(i - 1) + i * n] = v;
                full[i + (i - 1) * n] = v;
            }
            let scale = full
                .iter()
                .map(|v| (v / factor).powi(2))
                .sum::<f64>()
                .sqrt()
                .max(1.0);
            for uplo in [b'U', b'L'] {
                let mut a = stored(&full, n, n, uplo);
                let (info, w, _) = call(b'N', b'A', uplo, n, &mut a, n, (0.0, 0.0), (0, 0));
                assert_eq!(info, 0);
                for (k, x) in w.iter().enumerate() {
                    let exact = -((n - 1) as f64) + 2.0 * k as f64;
                    let err = (x / factor - exact).abs();
                    assert!(err <= TOL * scale, "n = {n}, ×{factor:e}: λ_{k} = {x:e}");
                }
            }
        }
    }
}
