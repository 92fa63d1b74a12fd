//! `dgemm_` on all of its code paths: the fixed-size kernel for `op(A)` of at most 16 rows
//! (with `A` read in place when untransposed and tightly stored, copied otherwise, and, with
//! a transposed `A`, an inner dimension of at most 16) and the general loops beyond, for
//! every transposition pair, `β ∈ {0, 1, −0.7}` and tight or padded leading dimensions.
//!
//! Reference: the defining sum `C(i, j) = α Σ_l op(A)(i, l) op(B)(l, j) + β C(i, j)`
//! evaluated term by term in the test. Both sides are sums of at most 20 products of numbers
//! of order 1, so they differ by at most a few `k · ε` relative to `Σ_l |op(A)(i, l)|
//! |op(B)(l, j)| + |β C(i, j)|` (Higham, *Accuracy and Stability of Numerical Algorithms*,
//! 2nd ed., §3.1); the tolerance 1e-13 of that magnitude is ~20× that bound and still far
//! below the order-1 errors of a wrong index or transposition. The padding of `C` holds a
//! sentinel that must come back unchanged, and `β = 0` must not read the NaN-filled `C`.

use core::ffi::c_char;
use pendulab_lapack::ffi::dgemm_;

mod common;
use common::lcg_entries as fill;

const PAD: usize = 2;
const SENTINEL: f64 = 7777.0;

#[test]
fn small_and_general_paths_match_the_defining_sum() {
    let shapes = [
        (5, 4, 3),
        (6, 6, 6),
        (10, 10, 10),
        (16, 3, 16),
        (1, 7, 2),
        (17, 5, 4),
        (6, 6, 17),
        (20, 19, 18),
    ];
    let mut seed = 1;
    for (&(m, n, k), pad) in shapes.iter().flat_map(|s| [(s, 0), (s, PAD)]) {
        for ta in [b'N', b'T'] {
            for tb in [b'N', b'T'] {
                for beta in [0.0, 1.0, -0.7] {
                    seed += 1;
                    let (ar, ac) = if ta == b'N' { (m, k) } else { (k, m) };
                    let (br, bc) = if tb == b'N' { (k, n) } else { (n, k) };
                    let (lda, ldb, ldc) = (ar + pad, br + pad, m + pad);
                    let a = fill(lda * ac, seed);
                    let b = fill(ldb * bc, seed + 1000);
                    let opa = |i: usize, l: usize| {
                        if ta == b'N' {
                            a[i + l * lda]
                        } else {
                            a[l + i * lda]
                        }
                    };
                    let opb = |l: usize, j: usize| {
                        if tb == b'N' {
                            b[l + j * ldb]
                        } else {
                            b[j + l * ldb]
                        }
                    };
                    let c0 = fill(ldc * n, seed + 2000);
                    let mut c = c0.clone();
                    for j in 0..n {
                        for i in 0..ldc {
                            if i >= m {
                                c[i + j * ldc] = SENTINEL;
                            } else if beta == 0.0 {
                                c[i + j * ldc] = f64::NAN;
                            }
                        }
                    }
                    let alpha = -1.3;
                    let (mi, ni, ki) = (m as i32, n as i32, k as i32);
                    let (ldai, ldbi, ldci) = (lda as i32, ldb as i32, ldc as i32);
                    unsafe {
                        dgemm_(
                            &(ta as c_char),
                            &(tb as c_char),
                            &mi,
                            &ni,
                            &ki,
                            &alpha,
                            a.as_ptr(),
                            &ldai,
                            b.as_ptr(),
                            &ldbi,
                            &beta,
                            c.as_mut_ptr(),
                            &ldci,
                        )
                    };
                    for j in 0..n {
                        for i in 0..ldc {
                            let got = c[i + j * ldc];
                            if i >= m {
                                assert_eq!(got, SENTINEL, "padding of C overwritten");
                                continue;
                            }
                            let cij = if beta == 0.0 { 0.0 } else { c0[i + j * ldc] };
                            let want = alpha * (0..k).map(|l| opa(i, l) * opb(l, j)).sum::<f64>()
                                + beta * cij;
                            let scale = alpha.abs()
                                * (0..k).map(|l| (opa(i, l) * opb(l, j)).abs()).sum::<f64>()
                                + (beta * cij).abs();
                            assert!(
                                (got - want).abs() <= 1e-13 * scale.max(1.0),
                                "dgemm {}{} ({m}, {n}, {k}) β = {beta}: C({i}, {j}) = {got}, want {want}",
                                ta as char,
                                tb as char
                            );
                        }
                    }
                }
            }
        }
    }
}
