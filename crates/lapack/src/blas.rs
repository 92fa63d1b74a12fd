//! Safe kernels of the five BLAS routines (level 2: `gemv`, `symv`; level 3: `gemm`, `syrk`,
//! `syr2k`).
//!
//! Every function here takes column-major matrices as slices with a leading dimension, exactly
//! like the Fortran routines, but with arguments already validated by the symbol layer
//! ([`crate::ffi`]): flags decoded, dimensions non-negative, leading dimensions large enough,
//! slices long enough. They follow the reference BLAS semantics (netlib BLAS 3.x):
//!
//! - `beta = 0` means the output is *not read* (NaN or garbage in it is overwritten);
//! - `alpha = 0` means the inputs are *not read*;
//! - `syrk`/`syr2k`/`symv` read and write only the triangle named by `uplo`.
//!
//! All five are the textbook loop orderings of the reference BLAS (column-oriented `axpy`
//! updates for untransposed operands, dot products down columns for transposed ones), which
//! keep the innermost loop on contiguous memory. `gemm` with `op(A)` of at most 16 rows (the
//! PSD-cone products of Clarabel) instead accumulates each column of `C` in a fixed-size
//! array, a transposed `A` first copied to columns. (nalgebra's own `gemm` is not used: for
//! small sizes it walks strided views by their underlying slice length, which is wrong for
//! the transposed operands BLAS callers pass.)

use crate::Real;

/// Whether an operand is used as stored or transposed (`'N'` or `'T'`/`'C'` in BLAS).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Trans {
    /// `op(A) = A`.
    No,
    /// `op(A) = Aᵀ` (`'T'`, and `'C'` which is the same for real data).
    Yes,
}

/// Which triangle of a symmetric matrix is referenced (`'U'` or `'L'`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Uplo {
    /// Upper triangle (including the diagonal).
    Upper,
    /// Lower triangle (including the diagonal).
    Lower,
}

/// A strided vector as BLAS sees it: `n` elements `x[k0 + i·inc]`, where a negative increment
/// starts from the end (`k0 = (n − 1)·|inc|`), as in the reference BLAS.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Stride {
    start: usize,
    inc: isize,
}

impl Stride {
    /// Describes `n` elements with increment `inc ≠ 0`.
    pub(crate) fn new(n: usize, inc: isize) -> Self {
        let start = if inc < 0 {
            (n.saturating_sub(1)) * inc.unsigned_abs()
        } else {
            0
        };
        Self { start, inc }
    }

    /// Position of element `i` in the underlying slice.
    #[inline]
    pub(crate) fn at(&self, i: usize) -> usize {
        (self.start as isize + i as isize * self.inc) as usize
    }
}

/// Length a slice must have to hold `n` elements at increment `inc`.
pub(crate) fn strided_len(n: usize, inc: isize) -> usize {
    if n == 0 {
        0
    } else {
        1 + (n - 1) * inc.unsigned_abs()
    }
}

/// Length a column-major array must have to hold `rows × cols` with leading dimension `ld`.
pub(crate) fn matrix_len(rows: usize, cols: usize, ld: usize) -> usize {
    if rows == 0 || cols == 0 {
        0
    } else {
        (cols - 1) * ld + rows
    }
}

/// `y ← β y` over a strided vector, without reading `y` when `β = 0`.
fn scale_vector<T: Real>(beta: T, y: &mut [T], ys: Stride, n: usize) {
    if beta == T::one() {
        return;
    }
    for i in 0..n {
        let k = ys.at(i);
        y[k] = if beta == T::zero() {
            T::zero()
        } else {
            beta * y[k]
        };
    }
}

/// `C ← α op(A) op(B) + β C`, `C` is `m × n`, `op(A)` is `m × k`, `op(B)` is `k × n` (xGEMM).
pub(crate) fn gemm<T: Real>(
    ta: Trans,
    tb: Trans,
    (m, n, k): (usize, usize, usize),
    alpha: T,
    (a, lda): (&[T], usize),
    (b, ldb): (&[T], usize),
    beta: T,
    (c, ldc): (&mut [T], usize),
) {
    if m == 0 || n == 0 || ((alpha == T::zero() || k == 0) && beta == T::one()) {
        return;
    }
    if alpha == T::zero() || k == 0 {
        for j in 0..n {
            for i in 0..m {
                let v = &mut c[i + j * ldc];
                *v = if beta == T::zero() {
                    T::zero()
                } else {
                    beta * *v
                };
            }
        }
        return;
    }
    if m <= SMALL_M && (ta == Trans::No || k <= SMALL_K) {
        // Clarabel's PSD cones multiply n × n matrices with n of a few units (5, 6, 10 on
        // the textbook's LMIs): every column of C is accumulated in a fixed-size array the
        // compiler keeps in registers (see `small_gemm`).
        let args = SmallGemm {
            ta,
            tb,
            n,
            k,
            alpha,
            a: (a, lda),
            b: (b, ldb),
            beta,
        };
        macro_rules! dispatch {
            ($($size:literal)*) => {
                match m {
                    $($size => small_gemm::<T, $size>(&args, (c, ldc)),)*
                    _ => {}
                }
            };
        }
        dispatch!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16);
        return;
    }
    for j in 0..n {
        let cj = &mut c[j * ldc..j * ldc + m];
        if beta == T::zero() {
            cj.fill(T::zero());
        } else if beta != T::one() {
            cj.iter_mut().for_each(|v| *v = beta * *v);
        }
        match (ta, tb) {
            (Trans::No, _) => {
                // C(:, j) += Σ_l α op(B)(l, j) A(:, l): contiguous column updates, four
                // columns of A per pass over C(:, j) (a quarter of the loads and stores of C
                // for the small matrices of Clarabel's PSD cones).
                let bl = |l: usize| match tb {
                    Trans::No => b[l + j * ldb],
                    Trans::Yes => b[j + l * ldb],
                };
                let mut l = 0;
                while l + 4 <= k {
                    let (t0, t1, t2, t3) = (
                        alpha * bl(l),
                        alpha * bl(l + 1),
                        alpha * bl(l + 2),
                        alpha * bl(l + 3),
                    );
                    let a0 = &a[l * lda..l * lda + m];
                    let a1 = &a[(l + 1) * lda..(l + 1) * lda + m];
                    let a2 = &a[(l + 2) * lda..(l + 2) * lda + m];
                    let a3 = &a[(l + 3) * lda..(l + 3) * lda + m];
                    for ((((cij, &x0), &x1), &x2), &x3) in
                        cj.iter_mut().zip(a0).zip(a1).zip(a2).zip(a3)
                    {
                        *cij += t0 * x0 + t1 * x1 + t2 * x2 + t3 * x3;
                    }
                    l += 4;
                }
                for l in l..k {
                    let t = alpha * bl(l);
                    if t != T::zero() {
                        let al = &a[l * lda..l * lda + m];
                        cj.iter_mut()
                            .zip(al)
                            .for_each(|(cij, ail)| *cij += t * *ail);
                    }
                }
            }
            (Trans::Yes, _) => {
                // C(i, j) += α A(:, i)ᵀ op(B)(:, j): dot products down the columns of A.
                for (i, cij) in cj.iter_mut().enumerate() {
                    let ai = &a[i * lda..i * lda + k];
                    let s = match tb {
                        Trans::No => dot(ai, &b[j * ldb..j * ldb + k]),
                        Trans::Yes => ai
                            .iter()
                            .enumerate()
                            .fold(T::zero(), |s, (l, p)| s + *p * b[j + l * ldb]),
                    };
                    *cij += alpha * s;
                }
            }
        }
    }
}

/// Largest row count of `op(A)` [`gemm`] hands to [`small_gemm`].
const SMALL_M: usize = 16;
/// Largest inner dimension `k` [`small_gemm`] takes with a transposed `A`.
const SMALL_K: usize = 16;

/// The operands of one [`small_gemm`] call.
struct SmallGemm<'a, T> {
    ta: Trans,
    tb: Trans,
    n: usize,
    k: usize,
    alpha: T,
    a: (&'a [T], usize),
    b: (&'a [T], usize),
    beta: T,
}

/// [`gemm`] for `op(A)` of exactly `M` rows: the columns of `op(A)` are handed to
/// [`small_gemm_columns`] as `[T; M]` arrays — in place when `A` is untransposed and tightly
/// stored (`lda = M`, Clarabel's case), otherwise copied into a `[[T; M]; SMALL_K]` (a
/// transposed `A` column by column, so `k ≤ SMALL_K`), or, for an untransposed `A` with
/// `k > SMALL_K`, borrowed column by column.
fn small_gemm<T: Real, const M: usize>(g: &SmallGemm<'_, T>, c: (&mut [T], usize)) {
    let (a, lda) = g.a;
    match g.ta {
        Trans::No if lda == M => {
            let (cols, _) = a[..g.k * M].as_chunks::<M>();
            small_gemm_columns::<T, M>(g, cols, c);
        }
        Trans::No if g.k <= SMALL_K => {
            let mut at = [[T::zero(); M]; SMALL_K];
            for (col, l) in at.iter_mut().zip(0..g.k) {
                col.copy_from_slice(&a[l * lda..l * lda + M]);
            }
            small_gemm_columns::<T, M>(g, &at[..g.k], c);
        }
        Trans::No => {
            for j in 0..g.n {
                let bj = |l: usize| match g.tb {
                    Trans::No => g.b.0[l + j * g.b.1],
                    Trans::Yes => g.b.0[j + l * g.b.1],
                };
                let mut acc = [T::zero(); M];
                for l in 0..g.k {
                    let blj = bj(l);
                    let al = a[l * lda..]
                        .first_chunk::<M>()
                        .expect("validated: A holds m rows per column");
                    for (s, &x) in acc.iter_mut().zip(al) {
                        *s += blj * x;
                    }
                }
                store_column(g, acc, &mut c.0[j * c.1..j * c.1 + M]);
            }
        }
        Trans::Yes => {
            let mut at = [[T::zero(); M]; SMALL_K];
            for (i, ai) in a.chunks(lda).take(M).enumerate() {
                for (col, &v) in at.iter_mut().zip(&ai[..g.k]) {
                    col[i] = v;
                }
            }
            small_gemm_columns::<T, M>(g, &at[..g.k], c);
        }
    }
}

/// `C(:, j) ← α acc + β C(:, j)` (`C` not read when `β = 0`).
#[inline(always)]
fn store_column<T: Real, const M: usize>(g: &SmallGemm<'_, T>, acc: [T; M], cj: &mut [T]) {
    if g.beta == T::zero() {
        for (cij, s) in cj.iter_mut().zip(acc) {
            *cij = g.alpha * s;
        }
    } else {
        for (cij, s) in cj.iter_mut().zip(acc) {
            *cij = g.alpha * s + g.beta * *cij;
        }
    }
}

/// `C ← α op(A) op(B) + β C` with `op(A)(:, l) = cols[l]` (`k` columns): each column `C(:, j)`
/// is accumulated as `Σ_l op(B)(l, j) op(A)(:, l)` in a `[T; M]` (fully unrolled), then
/// scaled by `α` and added to `β C(:, j)` (`C` not read when `β = 0`). Same operation as the
/// general loops of [`gemm`]; only the association of the sums differs (`α Σ` instead of
/// `Σ α`).
fn small_gemm_columns<T: Real, const M: usize>(
    g: &SmallGemm<'_, T>,
    cols: &[[T; M]],
    (c, ldc): (&mut [T], usize),
) {
    let (b, ldb) = g.b;
    for j in 0..g.n {
        let mut acc = [T::zero(); M];
        match g.tb {
            Trans::No => {
                for (&blj, col) in b[j * ldb..j * ldb + g.k].iter().zip(cols) {
                    for (s, &x) in acc.iter_mut().zip(col) {
                        *s += blj * x;
                    }
                }
            }
            Trans::Yes => {
                for (l, col) in cols.iter().enumerate() {
                    let blj = b[j + l * ldb];
                    for (s, &x) in acc.iter_mut().zip(col) {
                        *s += blj * x;
                    }
                }
            }
        }
        store_column(g, acc, &mut c[j * ldc..j * ldc + M]);
    }
}

/// `xᵀy` for equal-length slices, with four independent partial sums.
fn dot<T: Real>(x: &[T], y: &[T]) -> T {
    let (xc, yc) = (x.chunks_exact(4), y.chunks_exact(4));
    let (xr, yr) = (xc.remainder(), yc.remainder());
    let mut acc = [T::zero(); 4];
    for (p, q) in xc.zip(yc) {
        acc[0] += p[0] * q[0];
        acc[1] += p[1] * q[1];
        acc[2] += p[2] * q[2];
        acc[3] += p[3] * q[3];
    }
    let tail = xr.iter().zip(yr).fold(T::zero(), |s, (p, q)| s + *p * *q);
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// `y ← α op(A) x + β y`, `A` is `m × n` (xGEMV).
pub(crate) fn gemv<T: Real>(
    trans: Trans,
    (m, n): (usize, usize),
    alpha: T,
    (a, lda): (&[T], usize),
    (x, incx): (&[T], isize),
    beta: T,
    (y, incy): (&mut [T], isize),
) {
    if m == 0 || n == 0 || (alpha == T::zero() && beta == T::one()) {
        return;
    }
    let (lenx, leny) = match trans {
        Trans::No => (n, m),
        Trans::Yes => (m, n),
    };
    let xs = Stride::new(lenx, incx);
    let ys = Stride::new(leny, incy);
    scale_vector(beta, y, ys, leny);
    if alpha == T::zero() {
        return;
    }
    match trans {
        Trans::No => {
            // y += α Σ_j A(:, j) x_j, one column at a time.
            for j in 0..n {
                let t = alpha * x[xs.at(j)];
                if t != T::zero() {
                    let col = &a[j * lda..j * lda + m];
                    for (i, aij) in col.iter().enumerate() {
                        y[ys.at(i)] += t * *aij;
                    }
                }
            }
        }
        Trans::Yes => {
            // y_j += α A(:, j)ᵀ x.
            for j in 0..n {
                let col = &a[j * lda..j * lda + m];
                let mut s = T::zero();
                for (i, aij) in col.iter().enumerate() {
                    s += *aij * x[xs.at(i)];
                }
                y[ys.at(j)] += alpha * s;
            }
        }
    }
}

/// `y ← α A x + β y`, `A` symmetric `n × n` given by its `uplo` triangle (xSYMV).
pub(crate) fn symv<T: Real>(
    uplo: Uplo,
    n: usize,
    alpha: T,
    (a, lda): (&[T], usize),
    (x, incx): (&[T], isize),
    beta: T,
    (y, incy): (&mut [T], isize),
) {
    if n == 0 || (alpha == T::zero() && beta == T::one()) {
        return;
    }
    let xs = Stride::new(n, incx);
    let ys = Stride::new(n, incy);
    scale_vector(beta, y, ys, n);
    if alpha == T::zero() {
        return;
    }
    // Each stored off-diagonal a_ij contributes to y_i (with x_j) and to y_j (with x_i).
    for j in 0..n {
        let t1 = alpha * x[xs.at(j)];
        let mut t2 = T::zero();
        let rows = match uplo {
            Uplo::Upper => 0..j,
            Uplo::Lower => j + 1..n,
        };
        for i in rows {
            let aij = a[i + j * lda];
            y[ys.at(i)] += t1 * aij;
            t2 += aij * x[xs.at(i)];
        }
        y[ys.at(j)] += t1 * a[j + j * lda] + alpha * t2;
    }
}

/// Rows `i` of column `j` that belong to the `uplo` triangle.
fn triangle_rows(uplo: Uplo, j: usize, n: usize) -> std::ops::Range<usize> {
    match uplo {
        Uplo::Upper => 0..j + 1,
        Uplo::Lower => j..n,
    }
}

/// `C ← β C` on the `uplo` triangle, without reading `C` when `β = 0`.
fn scale_triangle<T: Real>(uplo: Uplo, n: usize, beta: T, c: &mut [T], ldc: usize) {
    if beta == T::one() {
        return;
    }
    for j in 0..n {
        for i in triangle_rows(uplo, j, n) {
            let v = &mut c[i + j * ldc];
            *v = if beta == T::zero() {
                T::zero()
            } else {
                beta * *v
            };
        }
    }
}

/// A symmetric rank-k update `C ← α (…) + β C` on the `uplo` triangle of `C`, the loop that
/// xSYRK and xSYR2K share. Nothing is done when `n = 0` or when the `α` term vanishes
/// (`α = 0` or `k = 0`) and `β = 1`; otherwise `C ← β C` on the triangle, then, if `α ≠ 0` and
/// `k > 0`, the `α` term through the routine's kernels: for `trans = No`,
/// `column(j, rows, C(rows, j))` adds column `j`'s share on the triangle's rows `rows`; for
/// `trans = Yes`, `C(i, j) += α · dot(i, j)`.
fn rank_update<T: Real>(
    (uplo, trans): (Uplo, Trans),
    (n, k): (usize, usize),
    (alpha, beta): (T, T),
    (c, ldc): (&mut [T], usize),
    column: impl Fn(usize, std::ops::Range<usize>, &mut [T]),
    dot: impl Fn(usize, usize) -> T,
) {
    let no_product = alpha == T::zero() || k == 0;
    if n == 0 || (no_product && beta == T::one()) {
        return;
    }
    scale_triangle(uplo, n, beta, c, ldc);
    if no_product {
        return;
    }
    for j in 0..n {
        let rows = triangle_rows(uplo, j, n);
        match trans {
            Trans::No => column(
                j,
                rows.clone(),
                &mut c[j * ldc + rows.start..j * ldc + rows.end],
            ),
            Trans::Yes => {
                for i in rows {
                    c[i + j * ldc] += alpha * dot(i, j);
                }
            }
        }
    }
}

/// `C ← α A Aᵀ + β C` (`trans = No`, `A` is `n × k`) or `C ← α Aᵀ A + β C` (`trans = Yes`,
/// `A` is `k × n`), updating only the `uplo` triangle of `C` (xSYRK).
pub(crate) fn syrk<T: Real>(
    uplo: Uplo,
    trans: Trans,
    (n, k): (usize, usize),
    alpha: T,
    (a, lda): (&[T], usize),
    beta: T,
    (c, ldc): (&mut [T], usize),
) {
    // C(:, j) += α Σ_l A(:, l) A(j, l).
    let column = |j: usize, rows: std::ops::Range<usize>, cj: &mut [T]| {
        for l in 0..k {
            let t = alpha * a[j + l * lda];
            if t != T::zero() {
                let al = &a[l * lda + rows.start..l * lda + rows.end];
                for (cij, &x) in cj.iter_mut().zip(al) {
                    *cij += t * x;
                }
            }
        }
    };
    // C(i, j) += α A(:, i)ᵀ A(:, j).
    let dot = |i: usize, j: usize| {
        let (ai, aj) = (&a[i * lda..i * lda + k], &a[j * lda..j * lda + k]);
        ai.iter().zip(aj).fold(T::zero(), |s, (p, q)| s + *p * *q)
    };
    rank_update((uplo, trans), (n, k), (alpha, beta), (c, ldc), column, dot);
}

/// `C ← α (A Bᵀ + B Aᵀ) + β C` (`trans = No`, `A`, `B` are `n × k`) or
/// `C ← α (Aᵀ B + Bᵀ A) + β C` (`trans = Yes`, `A`, `B` are `k × n`), updating only the
/// `uplo` triangle of `C` (xSYR2K).
pub(crate) fn syr2k<T: Real>(
    uplo: Uplo,
    trans: Trans,
    (n, k): (usize, usize),
    alpha: T,
    (a, lda): (&[T], usize),
    (b, ldb): (&[T], usize),
    beta: T,
    (c, ldc): (&mut [T], usize),
) {
    // C(:, j) += α Σ_l (A(:, l) B(j, l) + B(:, l) A(j, l)).
    let column = |j: usize, rows: std::ops::Range<usize>, cj: &mut [T]| {
        for l in 0..k {
            let tb = alpha * b[j + l * ldb];
            let ta = alpha * a[j + l * lda];
            if tb != T::zero() || ta != T::zero() {
                let al = &a[l * lda + rows.start..l * lda + rows.end];
                let bl = &b[l * ldb + rows.start..l * ldb + rows.end];
                for ((cij, &x), &y) in cj.iter_mut().zip(al).zip(bl) {
                    *cij += x * tb + y * ta;
                }
            }
        }
    };
    // C(i, j) += α (A(:, i)ᵀ B(:, j) + B(:, i)ᵀ A(:, j)).
    let dot = |i: usize, j: usize| {
        let (ai, aj) = (&a[i * lda..i * lda + k], &a[j * lda..j * lda + k]);
        let (bi, bj) = (&b[i * ldb..i * ldb + k], &b[j * ldb..j * ldb + k]);
        let mut s = T::zero();
        for l in 0..k {
            s += ai[l] * bj[l] + bi[l] * aj[l];
        }
        s
    };
    rank_update((uplo, trans), (n, k), (alpha, beta), (c, ldc), column, dot);
}
