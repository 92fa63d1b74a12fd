//! Every routine against SciPy's BLAS/LAPACK (fixture written by
//! `tools/reference/lapack_shim.py`), through the exported Fortran-ABI symbols.
//!
//! Tolerance: 1e-12 in a norm-wise relative sense (‖x − x_ref‖_F ≤ 1e-12 ‖x_ref‖_F, and for
//! eigen/singular values relative to ‖A‖_F; eigen/singular vectors after fixing each vector's
//! sign, which LAPACK leaves free). Observed: ≤ 4e-15. Both sides are backward-stable double-precision
//! algorithms on well-conditioned data of size ≤ 9 (condition numbers below 1e3), so they agree
//! to a few hundred ulps at most; 1e-12 leaves a margin of ~10 over that and would still catch
//! any wrong index, triangle or transposition (errors of order 1).
//!
//! Every matrix is handed over with a leading dimension two larger than needed, the padding
//! filled with a sentinel that must come back unchanged.

use core::ffi::{c_char, c_int};
use pendulab_lapack::ffi::*;
use serde_json::Value;

mod common;

const TOL: f64 = 1e-12;
const PAD: usize = 2;
const SENTINEL: f64 = 7777.0;

fn fixture() -> Value {
    let text = include_str!("fixtures/lapack_reference.json");
    serde_json::from_str(text).expect("fixture parses")
}

fn ch(s: &Value) -> c_char {
    s.as_str().unwrap().as_bytes()[0] as c_char
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

fn int(v: &Value) -> usize {
    v.as_u64().unwrap() as usize
}

fn vecf(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(num).collect()
}

/// A matrix of the fixture (rows) as (rows, cols, row-major data).
fn rows(v: &Value) -> (usize, usize, Vec<Vec<f64>>) {
    let r: Vec<Vec<f64>> = v.as_array().unwrap().iter().map(vecf).collect();
    let m = r.len();
    let n = r.first().map_or(0, |x| x.len());
    (m, n, r)
}

/// Column-major buffer with leading dimension `m + PAD`, padding = sentinel.
fn padded(v: &Value) -> (Vec<f64>, usize, usize, usize) {
    let (m, n, r) = rows(v);
    let ld = m + PAD;
    let mut buf = vec![SENTINEL; ld * n];
    for j in 0..n {
        for i in 0..m {
            buf[i + j * ld] = r[i][j];
        }
    }
    (buf, ld, m, n)
}

fn unpad(buf: &[f64], ld: usize, m: usize, n: usize) -> Vec<Vec<f64>> {
    (0..m)
        .map(|i| (0..n).map(|j| buf[i + j * ld]).collect())
        .collect()
}

fn assert_padding_intact(buf: &[f64], ld: usize, m: usize, what: &str) {
    for (k, v) in buf.iter().enumerate() {
        if k % ld >= m {
            assert_eq!(*v, SENTINEL, "{what}: padding element {k} overwritten");
        }
    }
}

fn fro(x: &[Vec<f64>]) -> f64 {
    x.iter().flatten().map(|v| v * v).sum::<f64>().sqrt()
}

fn rel_err(x: &[Vec<f64>], r: &[Vec<f64>]) -> f64 {
    assert_eq!(x.len(), r.len());
    let d: f64 = x
        .iter()
        .flatten()
        .zip(r.iter().flatten())
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt();
    d / fro(r).max(f64::MIN_POSITIVE)
}

fn rel_err_vec(x: &[f64], r: &[f64]) -> f64 {
    rel_err(&[x.to_vec()], &[r.to_vec()])
}

/// Flips the sign of each column so that its largest-magnitude entry is positive.
fn sign_normalise_columns(x: &mut [Vec<f64>]) {
    let n = x.first().map_or(0, |r| r.len());
    for j in 0..n {
        let mut best = 0.0_f64;
        for r in x.iter() {
            if r[j].abs() > best.abs() {
                best = r[j];
            }
        }
        if best < 0.0 {
            for r in x.iter_mut() {
                r[j] = -r[j];
            }
        }
    }
}

fn transpose(x: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let n = x.first().map_or(0, |r| r.len());
    (0..n).map(|j| x.iter().map(|r| r[j]).collect()).collect()
}

#[test]
fn gemm_matches_scipy() {
    for c in fixture()["cases"]["gemm"].as_array().unwrap() {
        let (a, lda, ..) = padded(&c["a"]);
        let (b, ldb, ..) = padded(&c["b"]);
        let (mut cc, ldc, m, n) = padded(&c["c"]);
        let beta = num(&c["beta"]);
        if beta == 0.0 {
            // β = 0: C must not be read, so NaN in it must vanish.
            for j in 0..n {
                for i in 0..m {
                    cc[i + j * ldc] = f64::NAN;
                }
            }
        }
        let (mi, ni, ki) = (
            int(&c["m"]) as c_int,
            int(&c["n"]) as c_int,
            int(&c["k"]) as c_int,
        );
        let (lda, ldb, ldc_i) = (lda as c_int, ldb as c_int, ldc as c_int);
        unsafe {
            dgemm_(
                &ch(&c["transa"]),
                &ch(&c["transb"]),
                &mi,
                &ni,
                &ki,
                &num(&c["alpha"]),
                a.as_ptr(),
                &lda,
                b.as_ptr(),
                &ldb,
                &beta,
                cc.as_mut_ptr(),
                &ldc_i,
            )
        };
        let (_, _, reference) = rows(&c["out"]);
        let e = rel_err(&unpad(&cc, ldc, m, n), &reference);
        assert!(
            e <= TOL,
            "dgemm {} {}: rel err {e:e}",
            c["transa"],
            c["transb"]
        );
        assert_padding_intact(&cc, ldc, m, "dgemm C");
    }
}

#[test]
fn gemv_matches_scipy_also_with_negative_increments() {
    for c in fixture()["cases"]["gemv"].as_array().unwrap() {
        let (a, lda, m, n) = padded(&c["a"]);
        let x = vecf(&c["x"]);
        let y0 = vecf(&c["y"]);
        let reference = vecf(&c["out"]);
        let (mi, ni, lda) = (m as c_int, n as c_int, lda as c_int);
        // inc = 1
        let mut y = y0.clone();
        unsafe {
            dgemv_(
                &ch(&c["trans"]),
                &mi,
                &ni,
                &num(&c["alpha"]),
                a.as_ptr(),
                &lda,
                x.as_ptr(),
                &1,
                &num(&c["beta"]),
                y.as_mut_ptr(),
                &1,
            )
        };
        let e = rel_err_vec(&y, &reference);
        assert!(e <= TOL, "dgemv {}: rel err {e:e}", c["trans"]);
        // inc = −2 on x and −3 on y: BLAS traverses a negative-increment vector from its end,
        // so x stored reversed at stride 2 must give the same product.
        let spread = |v: &[f64], s: usize| {
            let mut out = vec![SENTINEL; 1 + (v.len() - 1) * s];
            for (i, val) in v.iter().rev().enumerate() {
                out[i * s] = *val;
            }
            out
        };
        let xs = spread(&x, 2);
        let mut ys = spread(&y0, 3);
        unsafe {
            dgemv_(
                &ch(&c["trans"]),
                &mi,
                &ni,
                &num(&c["alpha"]),
                a.as_ptr(),
                &lda,
                xs.as_ptr(),
                &-2,
                &num(&c["beta"]),
                ys.as_mut_ptr(),
                &-3,
            )
        };
        let got: Vec<f64> = (0..reference.len())
            .map(|i| ys[(reference.len() - 1 - i) * 3])
            .collect();
        let e = rel_err_vec(&got, &reference);
        assert!(e <= TOL, "dgemv {} negative inc: rel err {e:e}", c["trans"]);
        for (k, v) in ys.iter().enumerate() {
            if k % 3 != 0 {
                assert_eq!(*v, SENTINEL, "dgemv wrote between strided elements");
            }
        }
    }
}

#[test]
fn symv_reads_only_its_triangle() {
    for c in fixture()["cases"]["symv"].as_array().unwrap() {
        let (mut a, lda, n, _) = padded(&c["a"]);
        let upper = c["uplo"] == "U";
        // Poison the other triangle: it must not be read.
        for j in 0..n {
            for i in 0..n {
                if (upper && i > j) || (!upper && i < j) {
                    a[i + j * lda] = f64::NAN;
                }
            }
        }
        let x = vecf(&c["x"]);
        let mut y = vecf(&c["y"]);
        let (ni, lda) = (n as c_int, lda as c_int);
        unsafe {
            dsymv_(
                &ch(&c["uplo"]),
                &ni,
                &num(&c["alpha"]),
                a.as_ptr(),
                &lda,
                x.as_ptr(),
                &1,
                &num(&c["beta"]),
                y.as_mut_ptr(),
                &1,
            )
        };
        let e = rel_err_vec(&y, &vecf(&c["out"]));
        assert!(e <= TOL, "dsymv {}: rel err {e:e}", c["uplo"]);
    }
}

/// Checks a syrk/syr2k result: the named triangle against the reference, the other triangle
/// bit-for-bit unchanged.
fn check_triangle(out: &[Vec<f64>], reference: &[Vec<f64>], input: &[Vec<f64>], upper: bool) {
    let n = out.len();
    let mut got_t = Vec::new();
    let mut ref_t = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let in_triangle = if upper { i <= j } else { i >= j };
            if in_triangle {
                got_t.push(out[i][j]);
                ref_t.push(reference[i][j]);
            } else {
                assert_eq!(
                    out[i][j], input[i][j],
                    "other triangle changed at ({i}, {j})"
                );
            }
        }
    }
    let e = rel_err_vec(&got_t, &ref_t);
    assert!(e <= TOL, "rel err {e:e}");
}

/// Calls `dsyrk_` (`routine = "syrk"`) or `dsyr2k_` on one fixture case and checks the
/// `uplo` triangle of `C` against SciPy, the other triangle and the padding unchanged.
fn check_rank_update(c: &Value, routine: &str) {
    let (a, lda, ..) = padded(&c["a"]);
    let (mut cc, ldc, n, _) = padded(&c["c"]);
    let (ul, tr) = (ch(&c["uplo"]), ch(&c["trans"]));
    let (ni, ki) = (int(&c["n"]) as c_int, int(&c["k"]) as c_int);
    let (al, be) = (num(&c["alpha"]), num(&c["beta"]));
    let (lda, ldc_i) = (lda as c_int, ldc as c_int);
    let (pa, pc) = (a.as_ptr(), cc.as_mut_ptr());
    if routine == "syrk" {
        unsafe { dsyrk_(&ul, &tr, &ni, &ki, &al, pa, &lda, &be, pc, &ldc_i) };
    } else {
        let (b, ldb, ..) = padded(&c["b"]);
        let (pb, ldb) = (b.as_ptr(), ldb as c_int);
        unsafe { dsyr2k_(&ul, &tr, &ni, &ki, &al, pa, &lda, pb, &ldb, &be, pc, &ldc_i) };
    }
    let out = unpad(&cc, ldc, n, n);
    check_triangle(&out, &rows(&c["out"]).2, &rows(&c["c"]).2, c["uplo"] == "U");
    assert_padding_intact(&cc, ldc, n, &format!("d{routine} C"));
}

#[test]
fn syrk_and_syr2k_match_scipy_and_keep_the_other_triangle() {
    let f = fixture();
    for routine in ["syrk", "syr2k"] {
        for c in f["cases"][routine].as_array().unwrap() {
            check_rank_update(c, routine);
        }
    }
}

#[test]
fn potrf_and_potrs_match_scipy() {
    let f = fixture();
    for c in f["cases"]["potrf"].as_array().unwrap() {
        let (mut a, lda, n, _) = padded(&c["a"]);
        let mut info: c_int = -77;
        let (ni, lda_i) = (n as c_int, lda as c_int);
        unsafe { dpotrf_(&ch(&c["uplo"]), &ni, a.as_mut_ptr(), &lda_i, &mut info) };
        assert_eq!(info as usize, int(&c["info"]), "dpotrf info");
        if c["out"].is_null() {
            continue;
        }
        // The factor's triangle matches; the other triangle (garbage in the fixture) is kept.
        check_triangle(
            &unpad(&a, lda, n, n),
            &rows(&c["out"]).2,
            &rows(&c["a"]).2,
            c["uplo"] == "U",
        );
        assert_padding_intact(&a, lda, n, "dpotrf A");
    }
    for c in f["cases"]["potrs"].as_array().unwrap() {
        let (fac, lda, n, _) = padded(&c["factor"]);
        let (mut b, ldb, _, nrhs) = padded(&c["b"]);
        let (ni, nr, lda, ldb_i) = (n as c_int, nrhs as c_int, lda as c_int, ldb as c_int);
        let (uplo, factor, rhs) = (ch(&c["uplo"]), (ni, &fac[..], lda), (nr, &mut b[..], ldb_i));
        let info = unsafe { common::potrs(dpotrs_, uplo, factor, rhs) };
        assert_eq!(info, 0);
        let e = rel_err(&unpad(&b, ldb, n, nrhs), &rows(&c["out"]).2);
        assert!(e <= TOL, "dpotrs {}: rel err {e:e}", c["uplo"]);
        assert_padding_intact(&b, ldb, n, "dpotrs B");
    }
}

/// Calls dsyevr the way Clarabel does: a workspace query first, then the computation.
#[allow(clippy::type_complexity)]
fn call_dsyevr(
    c: &Value,
    a: &mut [f64],
    lda: usize,
    n: usize,
) -> (c_int, Vec<f64>, Vec<f64>, usize, Vec<c_int>) {
    let (ni, lda_i, ldz) = (n as c_int, lda as c_int, (n + PAD) as c_int);
    let mut m: c_int = -1;
    let mut w = vec![0.0; n];
    let mut z = vec![SENTINEL; (n + PAD) * n];
    let mut isuppz = vec![0 as c_int; 2 * n];
    let mut work = vec![0.0; 1];
    let mut iwork = vec![0 as c_int; 1];
    let mut info: c_int = -77;
    let (il, iu) = (int(&c["il"]) as c_int, int(&c["iu"]) as c_int);
    let (vl, vu) = (num(&c["vl"]), num(&c["vu"]));
    for pass in 0..2 {
        let (lwork, liwork) = if pass == 0 {
            (-1, -1)
        } else {
            (work.len() as c_int, iwork.len() as c_int)
        };
        info = unsafe {
            common::syevr(
                dsyevr_,
                (b'V' as c_char, ch(&c["range"]), ch(&c["uplo"])),
                (ni, a, lda_i),
                (vl, vu, il, iu, -1.0),
                (&mut m, &mut w, &mut z, ldz, &mut isuppz),
                (&mut work, lwork, &mut iwork, liwork),
            )
        };
        assert_eq!(info, 0, "dsyevr pass {pass}");
        if pass == 0 {
            // The query reports LAPACK's documented minimum sizes and computes nothing.
            assert_eq!(work[0] as usize, (26 * n).max(1));
            assert_eq!(iwork[0] as usize, (10 * n).max(1));
            assert_eq!(m, -1, "query must not compute");
            work.resize(work[0] as usize, 0.0);
            iwork.resize(iwork[0] as usize, 0);
        }
    }
    (info, w, z, m as usize, isuppz)
}

#[test]
fn syevr_matches_scipy_ascending_and_orthonormal() {
    for c in fixture()["cases"]["syevr"].as_array().unwrap() {
        let (mut a, lda, n, _) = padded(&c["a"]);
        let a_full = rows(&c["a"]).2;
        let upper = c["uplo"] == "U";
        // Poison the unused triangle: must not be read.
        for j in 0..n {
            for i in 0..n {
                if (upper && i > j) || (!upper && i < j) {
                    a[i + j * lda] = f64::NAN;
                }
            }
        }
        let (_, w, z, m, isuppz) = call_dsyevr(c, &mut a, lda, n);
        assert_eq!(m, int(&c["m"]), "number of eigenvalues found");
        let w_ref = vecf(&c["w"]);
        let scale = fro(&a_full);
        let dw: f64 = w[..m]
            .iter()
            .zip(&w_ref)
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(dw <= TOL * scale, "dsyevr values: {dw:e} vs ‖A‖ {scale}");
        assert!(w[..m].windows(2).all(|p| p[0] <= p[1]), "ascending");
        let mut zz = unpad(&z, n + PAD, n, m);
        let mut zr = rows(&c["z"]).2;
        sign_normalise_columns(&mut zz);
        sign_normalise_columns(&mut zr);
        let e = rel_err(&zz, &zr);
        assert!(e <= TOL, "dsyevr vectors: rel err {e:e}");
        assert_padding_intact(&z, n + PAD, n, "dsyevr Z");
        if c["range"] == "A" {
            // ISUPPZ: a dense random matrix has eigenvectors with full support.
            for k in 0..m {
                assert_eq!((isuppz[2 * k], isuppz[2 * k + 1]), (1, n as c_int));
            }
        }
    }
}

/// SVD through dgesdd or dgesvd with a workspace query first, as Clarabel calls them.
fn call_svd(c: &Value, divide_and_conquer: bool) -> (Vec<f64>, Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let (mut a, lda, m, n) = padded(&c["a"]);
    let full = c["job"] == "A";
    let mn = m.min(n);
    let (ucols, vtrows) = if full { (m, n) } else { (mn, mn) };
    let (ldu, ldvt) = (m + PAD, vtrows + PAD);
    let mut s = vec![0.0; mn];
    let mut u = vec![SENTINEL; ldu * ucols];
    let mut vt = vec![SENTINEL; ldvt * n];
    let mut work = vec![0.0; 1];
    let mut iwork = vec![0 as c_int; 8 * mn];
    let job = ch(&c["job"]);
    let (mi, ni, lda_i, ldu_i, ldvt_i) = (
        m as c_int,
        n as c_int,
        lda as c_int,
        ldu as c_int,
        ldvt as c_int,
    );
    for pass in 0..2 {
        let lwork = if pass == 0 { -1 } else { work.len() as c_int };
        let info: c_int;
        unsafe {
            if divide_and_conquer {
                info = common::gesdd(
                    dgesdd_,
                    job,
                    (
                        (mi, ni, &mut a, lda_i),
                        &mut s,
                        (&mut u, ldu_i, &mut vt, ldvt_i),
                        (&mut work, lwork),
                    ),
                    &mut iwork,
                )
            } else {
                info = common::gesvd(
                    dgesvd_,
                    (job, job),
                    (
                        (mi, ni, &mut a, lda_i),
                        &mut s,
                        (&mut u, ldu_i, &mut vt, ldvt_i),
                        (&mut work, lwork),
                    ),
                )
            }
        };
        assert_eq!(info, 0);
        if pass == 0 {
            assert!(s.iter().all(|v| *v == 0.0), "query must not compute");
            work.resize(work[0] as usize, 0.0);
        }
    }
    assert_padding_intact(&u, ldu, m, "U");
    assert_padding_intact(&vt, ldvt, vtrows, "VT");
    (s, unpad(&u, ldu, m, ucols), unpad(&vt, ldvt, vtrows, n))
}

fn check_svd(c: &Value, divide_and_conquer: bool) {
    let (s, u, vt) = call_svd(c, divide_and_conquer);
    let (_, _, a) = rows(&c["a"]);
    let scale = fro(&a);
    let s_ref = vecf(&c["s"]);
    let ds = rel_err_vec(&s, &s_ref) * fro(std::slice::from_ref(&s_ref)) / scale;
    assert!(ds <= TOL, "singular values: {ds:e}");
    assert!(s.windows(2).all(|p| p[0] >= p[1]), "descending");
    let mn = s.len();
    // The singular vectors of distinct singular values are unique up to sign: compare the
    // first min(m, n) of them. Columns beyond (full 'A' jobs) span the orthogonal complement,
    // which is not unique: check orthonormality of the whole factor instead.
    let lead = |x: &[Vec<f64>], cols: usize| -> Vec<Vec<f64>> {
        x.iter().map(|r| r[..cols].to_vec()).collect()
    };
    let mut uu = lead(&u, mn);
    let mut ur = lead(&rows(&c["u"]).2, mn);
    sign_normalise_columns(&mut uu);
    sign_normalise_columns(&mut ur);
    let e = rel_err(&uu, &ur);
    assert!(e <= TOL, "U: rel err {e:e}");
    let mut vv = lead(&transpose(&vt), mn);
    let mut vr = lead(&transpose(&rows(&c["vt"]).2), mn);
    sign_normalise_columns(&mut vv);
    sign_normalise_columns(&mut vr);
    let e = rel_err(&vv, &vr);
    assert!(e <= TOL, "V: rel err {e:e}");
    for q in [u.clone(), transpose(&vt)] {
        let k = q[0].len();
        for i in 0..k {
            for j in 0..k {
                let d: f64 = q.iter().map(|r| r[i] * r[j]).sum();
                let expect = if i == j { 1.0 } else { 0.0 };
                assert!((d - expect).abs() <= 1e-13, "orthonormality ({i},{j}): {d}");
            }
        }
    }
}

#[test]
fn gesdd_and_gesvd_match_scipy() {
    let f = fixture();
    for c in f["cases"]["gesdd"].as_array().unwrap() {
        check_svd(c, true);
    }
    for c in f["cases"]["gesvd"].as_array().unwrap() {
        check_svd(c, false);
    }
}

#[test]
fn gesv_matches_scipy_and_reports_singularity() {
    for c in fixture()["cases"]["gesv"].as_array().unwrap() {
        let (mut a, lda, n, _) = padded(&c["a"]);
        let (mut b, ldb, _, nrhs) = padded(&c["b"]);
        let mut ipiv = vec![0 as c_int; n];
        let mut info: c_int = -77;
        let (ni, nr, lda_i, ldb_i) = (n as c_int, nrhs as c_int, lda as c_int, ldb as c_int);
        unsafe {
            dgesv_(
                &ni,
                &nr,
                a.as_mut_ptr(),
                &lda_i,
                ipiv.as_mut_ptr(),
                b.as_mut_ptr(),
                &ldb_i,
                &mut info,
            )
        };
        assert_eq!(info as usize, int(&c["info"]), "dgesv info");
        if c["x"].is_null() {
            continue;
        }
        let piv: Vec<c_int> = c["ipiv"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_i64().unwrap() as c_int)
            .collect();
        assert_eq!(ipiv, piv, "pivot sequence");
        let e = rel_err(&unpad(&a, lda, n, n), &rows(&c["lu"]).2);
        assert!(e <= TOL, "dgesv LU: rel err {e:e}");
        let e = rel_err(&unpad(&b, ldb, n, nrhs), &rows(&c["x"]).2);
        assert!(e <= TOL, "dgesv X: rel err {e:e}");
        assert_padding_intact(&a, lda, n, "dgesv A");
        assert_padding_intact(&b, ldb, n, "dgesv B");
    }
}

/// The single-precision symbols run the same kernels; compare with the double-precision
/// reference at single-precision accuracy (1e-5 relative: ~100 ulps of f32 at these sizes).
#[test]
fn single_precision_symbols_agree_with_the_double_reference() {
    let f = fixture();
    let to32 = |v: &[f64]| -> Vec<f32> { v.iter().map(|x| *x as f32).collect() };
    // sgemm
    let c = &f["cases"]["gemm"][0];
    let (a, lda, ..) = padded(&c["a"]);
    let (b, ldb, ..) = padded(&c["b"]);
    let (cc, ldc, m, n) = padded(&c["c"]);
    let (a, b, mut cc) = (to32(&a), to32(&b), to32(&cc));
    let (mi, ni, ki) = (m as c_int, n as c_int, int(&c["k"]) as c_int);
    let (lda, ldb, ldc_i) = (lda as c_int, ldb as c_int, ldc as c_int);
    unsafe {
        sgemm_(
            &ch(&c["transa"]),
            &ch(&c["transb"]),
            &mi,
            &ni,
            &ki,
            &(num(&c["alpha"]) as f32),
            a.as_ptr(),
            &lda,
            b.as_ptr(),
            &ldb,
            &(num(&c["beta"]) as f32),
            cc.as_mut_ptr(),
            &ldc_i,
        )
    };
    let got: Vec<f64> = cc.iter().map(|x| *x as f64).collect();
    let e = rel_err(&unpad(&got, ldc, m, n), &rows(&c["out"]).2);
    assert!(e <= 1e-5, "sgemm: {e:e}");
    // ssyevr, eigenvalues only
    let c = &f["cases"]["syevr"][0];
    let (a, lda, n, _) = padded(&c["a"]);
    let mut a = to32(&a);
    let (ni, lda_i) = (n as c_int, lda as c_int);
    let mut m: c_int = 0;
    let mut w = vec![0f32; n];
    let mut z = vec![0f32; 1];
    let mut isuppz = vec![0 as c_int; 2 * n];
    let mut work = vec![0f32; 26 * n];
    let mut iwork = vec![0 as c_int; 10 * n];
    let (lw, liw) = (work.len() as c_int, iwork.len() as c_int);
    let info = unsafe {
        common::syevr(
            ssyevr_,
            (b'N' as c_char, b'A' as c_char, ch(&c["uplo"])),
            (ni, &mut a, lda_i),
            (0.0, 0.0, 0, 0, -1.0),
            (&mut m, &mut w, &mut z, 1, &mut isuppz),
            (&mut work, lw, &mut iwork, liw),
        )
    };
    assert_eq!(info, 0);
    let got: Vec<f64> = w.iter().map(|x| *x as f64).collect();
    let e = rel_err_vec(&got, &vecf(&c["w"]));
    assert!(e <= 1e-5, "ssyevr: {e:e}");
    // spotrf + spotrs
    let c = &f["cases"]["potrs"][1];
    let (fac, lda, n, _) = padded(&c["factor"]);
    let (b, ldb, _, nrhs) = padded(&c["b"]);
    let (fac, mut b) = (to32(&fac), to32(&b));
    let (ni, nr, lda, ldb_i) = (n as c_int, nrhs as c_int, lda as c_int, ldb as c_int);
    let (uplo, factor, rhs) = (ch(&c["uplo"]), (ni, &fac[..], lda), (nr, &mut b[..], ldb_i));
    let info = unsafe { common::potrs(spotrs_, uplo, factor, rhs) };
    assert_eq!(info, 0);
    let got: Vec<f64> = b.iter().map(|x| *x as f64).collect();
    let e = rel_err(&unpad(&got, ldb, n, nrhs), &rows(&c["out"]).2);
    assert!(e <= 1e-4, "spotrs: {e:e}"); // solve: κ(A) ≈ 10 amplifies f32 rounding
}
