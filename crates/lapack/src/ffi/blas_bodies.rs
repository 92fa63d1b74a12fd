//! The generic bodies of the BLAS symbols (`xGEMM`, `xGEMV`, `xSYMV`, `xSYRK`, `xSYR2K`):
//! argument validation in the reference order, then the safe kernels of the crate's `blas`
//! module. Argument positions follow the Fortran argument lists.
//!
//! Neighbours: [`super`] exports the `d`/`s` symbols that call these; `args.rs` reads the
//! arguments; `lapack_bodies.rs` and `svd_bodies.rs` hold the LAPACK bodies.

use super::args::{
    dim, flag, increment, leading, read, run_blas, slice, slice_mut, trans_flag, uplo_flag,
};
use crate::blas::{Trans, Uplo, matrix_len, strided_len};
use crate::{Real, blas};
use core::ffi::{c_char, c_int};

/// How one array argument of a BLAS routine is laid out: a column-major `rows × columns`
/// matrix with a leading dimension ([`Matrix`]) or a vector of `len` elements with an
/// increment ([`Vector`]).
trait Layout: Copy {
    /// The leading dimension (`usize`) or the increment (`isize`).
    type Stride: Copy;
    /// Reads and validates the stride argument at `position`: `LD ≥ max(1, rows)` for a
    /// matrix, `INC ≠ 0` for a vector.
    ///
    /// # Safety
    /// As [`read`].
    unsafe fn stride(self, p: *const c_int, position: c_int) -> Result<Self::Stride, c_int>;
    /// How many elements the array spans with that stride.
    fn len(self, stride: Self::Stride) -> usize;
}

/// A column-major `rows × columns` matrix argument.
#[derive(Clone, Copy)]
struct Matrix(usize, usize);

/// A strided vector argument of `len` elements.
#[derive(Clone, Copy)]
struct Vector(usize);

impl Layout for Matrix {
    type Stride = usize;
    unsafe fn stride(self, p: *const c_int, position: c_int) -> Result<usize, c_int> {
        // SAFETY: forwarded caller contract.
        unsafe { leading(p, self.0, position) }
    }
    fn len(self, ld: usize) -> usize {
        matrix_len(self.0, self.1, ld)
    }
}

impl Layout for Vector {
    type Stride = isize;
    unsafe fn stride(self, p: *const c_int, position: c_int) -> Result<isize, c_int> {
        // SAFETY: forwarded caller contract.
        unsafe { increment(p, position) }
    }
    fn len(self, inc: isize) -> usize {
        strided_len(self.0, inc)
    }
}

/// The trailing arguments of the BLAS routines of the form `C ← α·(products of A and B) + β·C`,
/// in their common order: `ALPHA`, `A`, `LDA`, `B`, `LDB`, `BETA`, `C`, `LDC` for xGEMM and
/// xSYR2K, and `ALPHA`, `A`, `LDA`, `X`, `INCX`, `BETA`, `Y`, `INCY` for xGEMV and xSYMV
/// (`B`, `C` hold `X`, `Y`). The raw Fortran pointers, numbered consecutively from `ALPHA`
/// (6 in xGEMM, 5 in xSYR2K, 4 in xGEMV, 3 in xSYMV); [`ScaledArgs::borrow`] reads them.
pub(super) struct ScaledArgs<T> {
    pub(super) alpha: *const T,
    pub(super) a: *const T,
    pub(super) lda: *const c_int,
    pub(super) b: *const T,
    pub(super) ldb: *const c_int,
    pub(super) beta: *const T,
    pub(super) c: *mut T,
    pub(super) ldc: *const c_int,
}

/// [`ScaledArgs`] read: `α`, `(A, LDA)`, `(B, stride)`, `β`, `(C, stride)`.
struct Scaled<'a, T, B: Layout, C: Layout> {
    alpha: T,
    a: (&'a [T], usize),
    b: (&'a [T], B::Stride),
    beta: T,
    c: (&'a mut [T], C::Stride),
}

impl<T: Real> ScaledArgs<T> {
    /// Validates the arguments in the reference order — the strides of `A`, `B`, `C` against
    /// their layouts `a`, `b`, `c`, then `ALPHA` and `BETA` — and borrows the three arrays.
    /// `Ok(None)` if `quick_return` (the routine's empty case, decided from its dimensions
    /// by the caller; no array is read); `Err(i)`: argument `i` invalid, numbered from
    /// `ALPHA = alpha_at`.
    ///
    /// # Safety
    /// The pointers satisfy the Fortran contract of the routine for these layouts.
    unsafe fn borrow<'a, B: Layout, C: Layout>(
        self,
        alpha_at: c_int,
        (a, b, c): (Matrix, B, C),
        quick_return: bool,
    ) -> Result<Option<Scaled<'a, T, B, C>>, c_int> {
        // SAFETY: forwarded caller contract.
        unsafe {
            let lda = a.stride(self.lda, alpha_at + 2)?;
            let sb = b.stride(self.ldb, alpha_at + 4)?;
            let sc = c.stride(self.ldc, alpha_at + 7)?;
            let (alpha, beta) = (read(self.alpha, alpha_at)?, read(self.beta, alpha_at + 5)?);
            if quick_return {
                return Ok(None);
            }
            Ok(Some(Scaled {
                alpha,
                a: (slice(self.a, a.len(lda), alpha_at + 1)?, lda),
                b: (slice(self.b, b.len(sb), alpha_at + 3)?, sb),
                beta,
                c: (slice_mut(self.c, c.len(sc), alpha_at + 6)?, sc),
            }))
        }
    }
}

/// xGEMM's leading arguments: `TRANSA`, `TRANSB`, `M`, `N`, `K`.
pub(super) type GemmHead = (
    *const c_char,
    *const c_char,
    *const c_int,
    *const c_int,
    *const c_int,
);

/// # Safety
/// See [`dgemm_`](super::dgemm_).
pub(super) unsafe fn gemm_impl<T: Real>((transa, transb, m, n, k): GemmHead, args: ScaledArgs<T>) {
    run_blas(|| unsafe {
        let ta = trans_flag(flag(transa, 1)?, 1)?;
        let tb = trans_flag(flag(transb, 2)?, 2)?;
        let (m, n, k) = (dim(m, 3)?, dim(n, 4)?, dim(k, 5)?);
        let (ra, ca) = if ta == Trans::No { (m, k) } else { (k, m) };
        let (rb, cb) = if tb == Trans::No { (k, n) } else { (n, k) };
        let layouts = (Matrix(ra, ca), Matrix(rb, cb), Matrix(m, n));
        if let Some(x) = args.borrow(6, layouts, m == 0 || n == 0)? {
            blas::gemm(ta, tb, (m, n, k), x.alpha, x.a, x.b, x.beta, x.c);
        }
        Ok(())
    })
}

/// xGEMV's leading arguments: `TRANS`, `M`, `N`.
pub(super) type GemvHead = (*const c_char, *const c_int, *const c_int);

/// # Safety
/// See [`dgemv_`](super::dgemv_).
pub(super) unsafe fn gemv_impl<T: Real>((trans, m, n): GemvHead, args: ScaledArgs<T>) {
    run_blas(|| unsafe {
        let t = trans_flag(flag(trans, 1)?, 1)?;
        let (m, n) = (dim(m, 2)?, dim(n, 3)?);
        let (lenx, leny) = if t == Trans::No { (n, m) } else { (m, n) };
        let layouts = (Matrix(m, n), Vector(lenx), Vector(leny));
        if let Some(v) = args.borrow(4, layouts, m == 0 || n == 0)? {
            blas::gemv(t, (m, n), v.alpha, v.a, v.b, v.beta, v.c);
        }
        Ok(())
    })
}

/// xSYMV's leading arguments: `UPLO`, `N`.
pub(super) type SymvHead = (*const c_char, *const c_int);

/// # Safety
/// See [`dsymv_`](super::dsymv_).
pub(super) unsafe fn symv_impl<T: Real>((uplo, n): SymvHead, args: ScaledArgs<T>) {
    run_blas(|| unsafe {
        let ul = uplo_flag(flag(uplo, 1)?, 1)?;
        let n = dim(n, 2)?;
        let layouts = (Matrix(n, n), Vector(n), Vector(n));
        if let Some(v) = args.borrow(3, layouts, n == 0)? {
            blas::symv(ul, n, v.alpha, v.a, v.b, v.beta, v.c);
        }
        Ok(())
    })
}

/// `UPLO`, `TRANS`, `(N, K)` and the shape `(rows, columns)` of `A` of a rank-k update.
type RankUpdateHead = (Uplo, Trans, (usize, usize), (usize, usize));

/// The leading arguments of xSYRK and xSYR2K, in their common order: `UPLO` (1), `TRANS` (2),
/// `N` (3), `K` (4). Returns them decoded with the shape `(rows, columns)` of `A` (and `B`):
/// `n × k` for `TRANS = 'N'`, `k × n` otherwise. `Err(i)`: argument `i` invalid.
///
/// # Safety
/// The four pointers are valid for reads (the BLAS caller contract).
unsafe fn rank_update_head(
    uplo: *const c_char,
    trans: *const c_char,
    n: *const c_int,
    k: *const c_int,
) -> Result<RankUpdateHead, c_int> {
    // SAFETY: forwarded caller contract.
    unsafe {
        let ul = uplo_flag(flag(uplo, 1)?, 1)?;
        let t = trans_flag(flag(trans, 2)?, 2)?;
        let (n, k) = (dim(n, 3)?, dim(k, 4)?);
        let shape = if t == Trans::No { (n, k) } else { (k, n) };
        Ok((ul, t, (n, k), shape))
    }
}

/// # Safety
/// See [`dsyrk_`](super::dsyrk_).
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn syrk_impl<T: Real>(
    uplo: *const c_char,
    trans: *const c_char,
    n: *const c_int,
    k: *const c_int,
    alpha: *const T,
    a: *const T,
    lda: *const c_int,
    beta: *const T,
    c: *mut T,
    ldc: *const c_int,
) {
    run_blas(|| unsafe {
        let (ul, t, (n, k), (nrowa, ncola)) = rank_update_head(uplo, trans, n, k)?;
        let lda = leading(lda, nrowa, 7)?;
        let ldc = leading(ldc, n, 10)?;
        let (alpha, beta) = (read(alpha, 5)?, read(beta, 8)?);
        if n == 0 {
            return Ok(());
        }
        let a = slice(a, matrix_len(nrowa, ncola, lda), 6)?;
        let c = slice_mut(c, matrix_len(n, n, ldc), 9)?;
        blas::syrk(ul, t, (n, k), alpha, (a, lda), beta, (c, ldc));
        Ok(())
    })
}

/// xSYR2K's leading arguments: `UPLO`, `TRANS`, `N`, `K`.
pub(super) type Syr2kHead = (*const c_char, *const c_char, *const c_int, *const c_int);

/// # Safety
/// See [`dsyr2k_`](super::dsyr2k_).
pub(super) unsafe fn syr2k_impl<T: Real>((uplo, trans, n, k): Syr2kHead, args: ScaledArgs<T>) {
    run_blas(|| unsafe {
        let (ul, t, (n, k), (rows, cols)) = rank_update_head(uplo, trans, n, k)?;
        let layouts = (Matrix(rows, cols), Matrix(rows, cols), Matrix(n, n));
        if let Some(x) = args.borrow(5, layouts, n == 0)? {
            blas::syr2k(ul, t, (n, k), x.alpha, x.a, x.b, x.beta, x.c);
        }
        Ok(())
    })
}
