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

/// # Safety
/// See [`dgemm_`](super::dgemm_).
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn gemm_impl<T: Real>(
    transa: *const c_char,
    transb: *const c_char,
    m: *const c_int,
    n: *const c_int,
    k: *const c_int,
    alpha: *const T,
    a: *const T,
    lda: *const c_int,
    b: *const T,
    ldb: *const c_int,
    beta: *const T,
    c: *mut T,
    ldc: *const c_int,
) {
    run_blas(|| unsafe {
        let ta = trans_flag(flag(transa, 1)?, 1)?;
        let tb = trans_flag(flag(transb, 2)?, 2)?;
        let (m, n, k) = (dim(m, 3)?, dim(n, 4)?, dim(k, 5)?);
        let (nrowa, ncola) = if ta == Trans::No { (m, k) } else { (k, m) };
        let (nrowb, ncolb) = if tb == Trans::No { (k, n) } else { (n, k) };
        let lda = leading(lda, nrowa, 8)?;
        let ldb = leading(ldb, nrowb, 10)?;
        let ldc = leading(ldc, m, 13)?;
        let (alpha, beta) = (read(alpha, 6)?, read(beta, 11)?);
        if m == 0 || n == 0 {
            return Ok(());
        }
        let a = slice(a, matrix_len(nrowa, ncola, lda), 7)?;
        let b = slice(b, matrix_len(nrowb, ncolb, ldb), 9)?;
        let c = slice_mut(c, matrix_len(m, n, ldc), 12)?;
        blas::gemm(ta, tb, (m, n, k), alpha, (a, lda), (b, ldb), beta, (c, ldc));
        Ok(())
    })
}

/// # Safety
/// See [`dgemv_`](super::dgemv_).
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn gemv_impl<T: Real>(
    trans: *const c_char,
    m: *const c_int,
    n: *const c_int,
    alpha: *const T,
    a: *const T,
    lda: *const c_int,
    x: *const T,
    incx: *const c_int,
    beta: *const T,
    y: *mut T,
    incy: *const c_int,
) {
    run_blas(|| unsafe {
        let t = trans_flag(flag(trans, 1)?, 1)?;
        let (m, n) = (dim(m, 2)?, dim(n, 3)?);
        let lda = leading(lda, m, 6)?;
        let incx = increment(incx, 8)?;
        let incy = increment(incy, 11)?;
        let (alpha, beta) = (read(alpha, 4)?, read(beta, 9)?);
        if m == 0 || n == 0 {
            return Ok(());
        }
        let (lenx, leny) = if t == Trans::No { (n, m) } else { (m, n) };
        let a = slice(a, matrix_len(m, n, lda), 5)?;
        let x = slice(x, strided_len(lenx, incx), 7)?;
        let y = slice_mut(y, strided_len(leny, incy), 10)?;
        blas::gemv(t, (m, n), alpha, (a, lda), (x, incx), beta, (y, incy));
        Ok(())
    })
}

/// # Safety
/// See [`dsymv_`](super::dsymv_).
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn symv_impl<T: Real>(
    uplo: *const c_char,
    n: *const c_int,
    alpha: *const T,
    a: *const T,
    lda: *const c_int,
    x: *const T,
    incx: *const c_int,
    beta: *const T,
    y: *mut T,
    incy: *const c_int,
) {
    run_blas(|| unsafe {
        let ul = uplo_flag(flag(uplo, 1)?, 1)?;
        let n = dim(n, 2)?;
        let lda = leading(lda, n, 5)?;
        let incx = increment(incx, 7)?;
        let incy = increment(incy, 10)?;
        let (alpha, beta) = (read(alpha, 3)?, read(beta, 8)?);
        if n == 0 {
            return Ok(());
        }
        let a = slice(a, matrix_len(n, n, lda), 4)?;
        let x = slice(x, strided_len(n, incx), 6)?;
        let y = slice_mut(y, strided_len(n, incy), 9)?;
        blas::symv(ul, n, alpha, (a, lda), (x, incx), beta, (y, incy));
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

/// # Safety
/// See [`dsyr2k_`](super::dsyr2k_).
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn syr2k_impl<T: Real>(
    uplo: *const c_char,
    trans: *const c_char,
    n: *const c_int,
    k: *const c_int,
    alpha: *const T,
    a: *const T,
    lda: *const c_int,
    b: *const T,
    ldb: *const c_int,
    beta: *const T,
    c: *mut T,
    ldc: *const c_int,
) {
    run_blas(|| unsafe {
        let (ul, t, (n, k), (nrow, ncol)) = rank_update_head(uplo, trans, n, k)?;
        let lda = leading(lda, nrow, 7)?;
        let ldb = leading(ldb, nrow, 9)?;
        let ldc = leading(ldc, n, 12)?;
        let (alpha, beta) = (read(alpha, 5)?, read(beta, 10)?);
        if n == 0 {
            return Ok(());
        }
        let a = slice(a, matrix_len(nrow, ncol, lda), 6)?;
        let b = slice(b, matrix_len(nrow, ncol, ldb), 8)?;
        let c = slice_mut(c, matrix_len(n, n, ldc), 11)?;
        blas::syr2k(ul, t, (n, k), alpha, (a, lda), (b, ldb), beta, (c, ldc));
        Ok(())
    })
}
