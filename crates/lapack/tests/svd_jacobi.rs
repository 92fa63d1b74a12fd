//! The thin SVD jobs (`'S'`, the call Clarabel's PSD scalings make) on small matrices, where
//! the shim uses one-sided Jacobi: the defining contract on every shape `m, n ∈ 1..=12`
//! (orthonormal `U`, `V`, the residual `A − U Σ Vᵀ`, descending non-negative values), on
//! dense, rank-deficient, graded and zero matrices; the full `'A'` jobs (square orthogonal
//! factors); agreement of the squared singular values with the eigenvalues of the Gram
//! matrix (`dsyevr`, an independent algorithm); and
//! the high relative accuracy on graded matrices `Q D` whose singular values are known in
//! closed form (the `|d_i|`, for orthogonal `Q`).
//!
//! Tolerances, with `ε = 2.2e-16` and sides `n` up to 32:
//! - orthonormality `|UᵀU − I|`, `|VᵀV − I|` ≤ `4 n ε` entrywise: `U`'s columns are
//!   orthogonal to `√m ε` by the stopping rule and normalised in one rounding, `V` is a
//!   product of plane rotations, each orthogonal to a few ε;
//! - residual `‖A − U Σ Vᵀ‖_F ≤ 8 n ε ‖A‖_F`: backward stability of plane rotations;
//! - squared singular values and Gram eigenvalues agree to `8 n ε ‖A‖₂²` (Weyl).

use core::ffi::{c_char, c_int};
use pendulab_lapack::ffi::{dgesdd_, dgesvd_, dsyevr_};

mod common;
use common::lcg_entries;

const EPS: f64 = f64::EPSILON;

/// Output of one SVD call: `info`, `s`, `U` (`m × ucols`, leading dimension `m`), `Vᵀ`
/// (`vtrows × n`, leading dimension `vtrows`).
struct Out {
    info: c_int,
    s: Vec<f64>,
    u: Vec<f64>,
    vt: Vec<f64>,
}

/// `dgesdd_` (`qr = false`) or `dgesvd_` (`qr = true`) with a workspace query first, as
/// Clarabel calls them, with job `'S'` or `'A'` for all factors. `A` is not reused.
fn svd(a: &[f64], (m, n): (usize, usize), job: u8, qr: bool) -> Out {
    let mn = m.min(n);
    let (ucols, vtrows) = if job == b'A' { (m, n) } else { (mn, mn) };
    let mut a = a.to_vec();
    let mut s = vec![-1.0; mn];
    let mut u = vec![0.0; m * ucols];
    let mut vt = vec![0.0; vtrows * n];
    let mut work = vec![0.0; 1];
    let mut iwork = vec![0 as c_int; 8 * mn];
    let (mi, ni, vr) = (m as c_int, n as c_int, vtrows as c_int);
    let mut info: c_int = -77;
    for pass in 0..2 {
        let lwork = if pass == 0 { -1 } else { work.len() as c_int };
        let j = job as core::ffi::c_char;
        unsafe {
            if qr {
                info = common::gesvd(
                    dgesvd_,
                    (j, j),
                    (
                        (mi, ni, &mut a, mi),
                        &mut s,
                        (&mut u, mi, &mut vt, vr),
                        (&mut work, lwork),
                    ),
                )
            } else {
                info = common::gesdd(
                    dgesdd_,
                    j,
                    (
                        (mi, ni, &mut a, mi),
                        &mut s,
                        (&mut u, mi, &mut vt, vr),
                        (&mut work, lwork),
                    ),
                    &mut iwork,
                )
            }
        };
        if pass == 0 {
            assert_eq!(info, 0);
            work.resize(work[0] as usize, 0.0);
        }
    }
    Out { info, s, u, vt }
}

/// Frobenius norm, scaled by the largest entry so that the squares neither overflow nor
/// underflow at the extreme scales tested below.
fn fro(x: &[f64]) -> f64 {
    let amax = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if amax == 0.0 {
        return 0.0;
    }
    amax * x.iter().map(|v| (v / amax).powi(2)).sum::<f64>().sqrt()
}

/// Largest entry of `|XᵀX − I|` for the `k` columns of length `len` at stride `ld` and
/// element step `step` (columns of `U`: ld = m, step 1; rows of `Vᵀ`: ld = 1, step = rows).
fn orthonormality(x: &[f64], k: usize, len: usize, (col, step): (usize, usize)) -> f64 {
    let mut worst: f64 = 0.0;
    for p in 0..k {
        for q in 0..k {
            let d: f64 = (0..len)
                .map(|i| x[p * col + i * step] * x[q * col + i * step])
                .sum();
            let target = if p == q { 1.0 } else { 0.0 };
            worst = worst.max((d - target).abs());
        }
    }
    worst
}

/// Checks the thin-job contract on `a` (`m × n`) for both drivers; returns `s`.
fn check_contract(a: &[f64], (m, n): (usize, usize), what: &str) -> Vec<f64> {
    let k = m.min(n);
    let side = m.max(n) as f64;
    let mut values = Vec::new();
    for qr in [false, true] {
        let o = svd(a, (m, n), b'S', qr);
        assert_eq!(o.info, 0, "{what} {m}x{n}");
        assert!(o.s.iter().all(|v| *v >= 0.0), "{what} {m}x{n}: s ≥ 0");
        assert!(
            o.s.windows(2).all(|p| p[0] >= p[1]),
            "{what} {m}x{n}: descending {:?}",
            o.s
        );
        let eu = orthonormality(&o.u, k, m, (m, 1));
        assert!(eu <= 4.0 * side * EPS, "{what} {m}x{n}: UᵀU − I = {eu:e}");
        let ev = orthonormality(&o.vt, k, n, (1, k));
        assert!(ev <= 4.0 * side * EPS, "{what} {m}x{n}: VᵀV − I = {ev:e}");
        let mut r = a.to_vec();
        for j in 0..n {
            for i in 0..m {
                for p in 0..k {
                    r[i + j * m] -= o.u[i + p * m] * o.s[p] * o.vt[p + j * k];
                }
            }
        }
        let res = fro(&r);
        assert!(
            res <= 8.0 * side * EPS * fro(a),
            "{what} {m}x{n}: residual {res:e}"
        );
        if qr {
            assert_eq!(o.s, values, "{what} {m}x{n}: both drivers, same kernel");
        }
        values = o.s;
    }
    values
}

/// Agreement of the squared singular values with the eigenvalues of the smaller Gram matrix
/// (`A Aᵀ` or `Aᵀ A`) from `dsyevr_` (Householder tridiagonalisation and implicit QR, an
/// independent algorithm): both are exact for matrices within `O(n ε) ‖A‖²` of the Gram
/// matrix, so by Weyl `|σ_j² − λ_j| ≤ 8 n ε σ₁²`.
fn check_against_gram(a: &[f64], (m, n): (usize, usize), s: &[f64], what: &str) {
    let k = m.min(n);
    let mut g = vec![0.0; k * k];
    for p in 0..k {
        for q in 0..k {
            g[p + q * k] = if m <= n {
                (0..n).map(|j| a[p + j * m] * a[q + j * m]).sum()
            } else {
                (0..m).map(|i| a[i + p * m] * a[i + q * m]).sum()
            };
        }
    }
    let ki = k as c_int;
    let mut found: c_int = 0;
    let mut lambda = vec![0.0; k];
    let mut z = [0.0];
    let mut isuppz = vec![0 as c_int; 2 * k];
    let mut work = vec![0.0; 26 * k];
    let mut iwork = vec![0 as c_int; 10 * k];
    let info = unsafe {
        common::syevr(
            dsyevr_,
            (b'N' as c_char, b'A' as c_char, b'L' as c_char),
            (ki, &mut g, ki),
            (0.0, 0.0, 0, 0, -1.0),
            (&mut found, &mut lambda, &mut z, 1, &mut isuppz),
            (&mut work, 26 * ki, &mut iwork, 10 * ki),
        )
    };
    assert_eq!((info, found), (0, ki));
    let tol = 8.0 * m.max(n) as f64 * EPS * s[0] * s[0];
    // λ ascending, σ descending.
    for (x, l) in s.iter().zip(lambda.iter().rev()) {
        assert!(
            (x * x - l).abs() <= tol,
            "{what} {m}x{n}: σ² = {} vs λ = {l}",
            x * x
        );
    }
}

#[test]
fn dense_matrices_of_every_small_shape() {
    for m in 1..=12 {
        for n in 1..=12 {
            let a = lcg_entries(m * n, (100 * m + n) as u64);
            let s = check_contract(&a, (m, n), "dense");
            check_against_gram(&a, (m, n), &s, "dense");
        }
    }
}

#[test]
fn rank_deficient_and_zero_matrices_keep_orthonormal_factors() {
    for m in 1..=12 {
        for n in 1..=12 {
            let k = m.min(n);
            for rank in [0, 1, k / 2] {
                // A = B C with B m × rank, C rank × n: rank ≤ `rank`, so k − rank singular
                // values vanish (to rounding) and their U, V columns are arbitrary but must
                // still complete orthonormal sets.
                let b = lcg_entries(m * rank, (7 * m + n) as u64);
                let c = lcg_entries(rank * n, (11 * m + 3 * n) as u64);
                let mut a = vec![0.0; m * n];
                for j in 0..n {
                    for i in 0..m {
                        a[i + j * m] = (0..rank).map(|p| b[i + p * m] * c[p + j * rank]).sum();
                    }
                }
                let s = check_contract(&a, (m, n), "rank-deficient");
                let tiny = 8.0 * m.max(n) as f64 * EPS * s[0];
                assert!(
                    s[rank..].iter().all(|v| *v <= tiny),
                    "rank {rank} {m}x{n}: {s:?}"
                );
                if rank == 0 {
                    assert!(s.iter().all(|v| *v == 0.0), "zero matrix: exact zeros");
                } else {
                    check_against_gram(&a, (m, n), &s, "rank-deficient");
                }
            }
        }
    }
}

/// Graded matrices `A = Q D` (`m ≥ n`) or `D Qᵀ` (`m < n`), `Q` a Householder reflector
/// `I − 2 v vᵀ/(vᵀv)` (orthogonal), `D = diag(d_j)` with `d_j` from 1 down to 1e-15: the
/// singular values are exactly the `d_j`. One-sided Jacobi finds even the smallest to a
/// relative error `O(√n ε κ(Q))` (Demmel & Veselić 1992, their bound for one-sided Jacobi;
/// `κ(Q) = 1` up to the rounding of `Q`), hence the relative tolerance `1e-13` on *each*
/// value, which bidiagonal QR (accurate only to `ε σ_max` in absolute terms) does not
/// promise.
#[test]
fn graded_matrices_have_relatively_accurate_small_singular_values() {
    for m in 1..=12 {
        for n in 1..=12 {
            let (rows, k) = (m.max(n), m.min(n));
            let v = lcg_entries(rows, (13 * m + 17 * n) as u64);
            let vv: f64 = v.iter().map(|x| x * x).sum();
            let q = |i: usize, j: usize| {
                let delta = if i == j { 1.0 } else { 0.0 };
                delta - 2.0 * v[i] * v[j] / vv
            };
            let d: Vec<f64> = (0..k)
                .map(|j| 10f64.powf(-15.0 * j as f64 / (k.max(2) - 1) as f64))
                .collect();
            let mut a = vec![0.0; m * n];
            for j in 0..n {
                for i in 0..m {
                    a[i + j * m] = if m >= n {
                        q(i, j) * d[j]
                    } else {
                        d[i] * q(j, i)
                    };
                }
            }
            let s = check_contract(&a, (m, n), "graded");
            for (j, (x, y)) in s.iter().zip(&d).enumerate() {
                let rel = (x - y).abs() / y;
                assert!(
                    rel <= 1e-13,
                    "graded {m}x{n}: σ_{j} = {x:e}, d = {y:e}, rel {rel:e}"
                );
            }
        }
    }
}

/// Repeated singular values: a multiple of an orthogonal matrix has all `σ = 3` and any
/// orthonormal `U`, `V` pair with `U Vᵀ = Q`; the contract still holds.
#[test]
fn repeated_singular_values() {
    for m in 1..=12 {
        let v = lcg_entries(m, m as u64);
        let vv: f64 = v.iter().map(|x| x * x).sum();
        let mut a = vec![0.0; m * m];
        for j in 0..m {
            for i in 0..m {
                let delta = if i == j { 1.0 } else { 0.0 };
                a[i + j * m] = 3.0 * (delta - 2.0 * v[i] * v[j] / vv);
            }
        }
        let s = check_contract(&a, (m, m), "3·Q");
        for x in &s {
            assert!(
                (x - 3.0).abs() <= 8.0 * m as f64 * EPS * 3.0,
                "3·Q {m}: {x}"
            );
        }
    }
}

/// Entries near the ends of the exponent range are scaled before the squared column norms
/// are formed: the residual and orthonormality hold and the values scale exactly with `A`
/// (`2^1020` would overflow the squares, `2^-1000` underflow them, without that scaling).
#[test]
fn extreme_scales_neither_overflow_nor_underflow() {
    for (m, n) in [(5, 5), (6, 4), (4, 6), (10, 10)] {
        let a = lcg_entries(m * n, 99);
        let s1 = check_contract(&a, (m, n), "unit");
        for factor in [
            2f64.powi(600),
            2f64.powi(-600),
            2f64.powi(1020),
            2f64.powi(-1000),
        ] {
            let b: Vec<f64> = a.iter().map(|x| x * factor).collect();
            let s = check_contract(&b, (m, n), "scaled");
            // The kernel scales W by the power of two nearest max |a_ij|: scaled by a power
            // of two, the matrix runs through bit-identical arithmetic.
            for (x, y) in s.iter().zip(&s1) {
                assert_eq!(*x, y * factor, "values scale exactly");
            }
        }
    }
}

/// The `'A'` jobs: `U` is `m × m` and `Vᵀ` is `n × n`, both orthogonal (the columns beyond
/// `min(m, n)` complete the bases), the leading ones agree with the `'S'` job's (same kernel,
/// so exactly), and `A = U Σ Vᵀ` with the rectangular `Σ`. Includes the rank-one all-ones
/// matrices, `σ₁ = √(mn)`, on which nalgebra 0.3x's SVD returns wrong values once vectors
/// are requested (nalgebra issue #1172).
#[test]
fn full_jobs_give_square_orthogonal_factors() {
    for m in 1..=12 {
        for n in 1..=12 {
            for ones in [false, true] {
                let a = if ones {
                    vec![1.0; m * n]
                } else {
                    lcg_entries(m * n, (31 * m + n) as u64)
                };
                let side = m.max(n) as f64;
                let thin = svd(&a, (m, n), b'S', false);
                for qr in [false, true] {
                    let o = svd(&a, (m, n), b'A', qr);
                    assert_eq!(o.info, 0);
                    assert_eq!(o.s, thin.s, "{m}x{n}: values as in the thin job");
                    let eu = orthonormality(&o.u, m, m, (m, 1));
                    assert!(eu <= 4.0 * side * EPS, "{m}x{n}: full UᵀU − I = {eu:e}");
                    let ev = orthonormality(&o.vt, n, n, (1, n));
                    assert!(ev <= 4.0 * side * EPS, "{m}x{n}: full VVᵀ − I = {ev:e}");
                    let mut r = a.clone();
                    for j in 0..n {
                        for i in 0..m {
                            for p in 0..m.min(n) {
                                r[i + j * m] -= o.u[i + p * m] * o.s[p] * o.vt[p + j * n];
                            }
                        }
                    }
                    let res = fro(&r);
                    assert!(
                        res <= 8.0 * side * EPS * fro(&a),
                        "{m}x{n}: residual {res:e}"
                    );
                    if ones {
                        let exact = ((m * n) as f64).sqrt();
                        assert!((o.s[0] - exact).abs() <= 8.0 * side * EPS * exact);
                    }
                }
            }
        }
    }
}

/// Single precision (`sgesdd_`), where squares overflow already beyond `2^64`: a matrix
/// scaled by `2^100` gives exactly `2^100` times the singular values of the unscaled one,
/// and those agree with the double-precision values to single-precision accuracy
/// (`8 n ε_f32 σ₁`, as for the double tolerance above).
#[test]
fn single_precision_path_scales_too() {
    use pendulab_lapack::ffi::sgesdd_;
    let (m, n) = (6usize, 5usize);
    let a = lcg_entries(m * n, 5);
    let s64 = check_contract(&a, (m, n), "f64");
    let run = |factor: f32| -> Vec<f32> {
        let mut a32: Vec<f32> = a.iter().map(|x| *x as f32 * factor).collect();
        let mut s = vec![0f32; n];
        let mut u = vec![0f32; m * n];
        let mut vt = vec![0f32; n * n];
        let mut work = vec![0f32; 1000];
        let mut iwork = vec![0 as c_int; 8 * n];
        let info: c_int;
        unsafe {
            info = common::gesdd(
                sgesdd_,
                b'S' as c_char,
                (
                    (m as c_int, n as c_int, &mut a32, m as c_int),
                    &mut s,
                    (&mut u, m as c_int, &mut vt, n as c_int),
                    (&mut work, 1000),
                ),
                &mut iwork,
            )
        };
        assert_eq!(info, 0);
        s
    };
    let s1 = run(1.0);
    let big = 2f32.powi(100);
    let sb = run(big);
    for ((x, y), z) in sb.iter().zip(&s1).zip(&s64) {
        assert!(x.is_finite());
        assert_eq!(*x, y * big, "values scale exactly");
        let tol = 8.0 * 6.0 * f32::EPSILON as f64 * s64[0];
        assert!((*y as f64 - z).abs() <= tol, "f32 {y} vs f64 {z}");
    }
}

/// The Jacobi path up to side 32 (Clarabel's PSD cones on the textbook's SOS design have
/// sides up to 30): dense matrices against the Gram eigenvalues, and the all-ones matrices
/// `1_m 1_nᵀ` (rank one, `σ₁ = √(mn)`, the family on which nalgebra's SVD returns wrong
/// values once vectors are requested, nalgebra issue #1172), with the contract checks above.
#[test]
fn larger_sides_up_to_32() {
    for (m, n) in [(20, 20), (30, 30), (32, 17), (17, 32), (32, 32), (25, 3)] {
        let a = lcg_entries(m * n, (m * 37 + n) as u64);
        let s = check_contract(&a, (m, n), "dense");
        check_against_gram(&a, (m, n), &s, "dense");
        let ones = vec![1.0; m * n];
        let s = check_contract(&ones, (m, n), "ones");
        let exact = ((m * n) as f64).sqrt();
        assert!(
            (s[0] - exact).abs() <= 8.0 * 32.0 * EPS * exact,
            "{m}x{n}: {}",
            s[0]
        );
        assert!(s[1..].iter().all(|v| *v <= 8.0 * 32.0 * EPS * exact));
    }
}
