//! The Fortran-ABI symbols. This is the only module with `unsafe` code.
//!
//! Each symbol has the signature `lapack-sys`/`blas-sys` declare for it: every argument is a
//! pointer (Fortran passes by reference), flags are single `c_char`s, integers are `c_int`,
//! and there are no hidden string-length arguments. The body of each symbol
//!
//! 1. reads the scalar arguments and validates them in the order the reference
//!    implementation does (BLAS: an invalid argument makes the call a no-op, where reference
//!    BLAS would call `XERBLA`; LAPACK: `INFO = −i` for the first invalid argument `i`),
//! 2. builds slices of exactly the length the Fortran contract implies for each array,
//! 3. calls the safe kernel in the crate's private `blas` / `lapack` modules,
//!
//! all inside `catch_unwind`, because a panic unwinding out of an `extern "C"` function aborts
//! the process. A caught panic (which would be a bug in this crate) is reported as
//! `INFO =` [`INTERNAL_ERROR`] by the LAPACK routines; the BLAS routines have no way to report
//! it and leave their output unspecified.

use crate::Real;
use crate::blas::{self, Trans, Uplo, matrix_len, strided_len};
use crate::jacobi;
use crate::lapack::{self, EigRange};
use core::ffi::{c_char, c_int};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// `INFO` value reported when the shim itself failed internally (a caught panic). Positive,
/// so callers treat it as a computational failure, and far outside LAPACK's own range.
pub const INTERNAL_ERROR: c_int = c_int::MAX;

/// A reason to stop: `Err(i)` means "argument `i` (1-based) is invalid".
type Check = Result<(), c_int>;

/// Reads a by-reference scalar argument.
///
/// # Safety
/// `p` must be null or point to a readable `T`.
unsafe fn read<T: Copy>(p: *const T, position: c_int) -> Result<T, c_int> {
    if p.is_null() {
        Err(position)
    } else {
        // SAFETY: non-null, and the caller guarantees it points to a readable `T`.
        Ok(unsafe { p.read() })
    }
}

/// Reads a by-reference integer argument as a dimension (`≥ 0`).
///
/// # Safety
/// As [`read`].
unsafe fn dim(p: *const c_int, position: c_int) -> Result<usize, c_int> {
    let v = unsafe { read(p, position)? };
    usize::try_from(v).map_err(|_| position)
}

/// Reads a flag argument (`'N'`, `'T'`, ...) as an upper-case ASCII letter.
///
/// # Safety
/// As [`read`].
unsafe fn flag(p: *const c_char, position: c_int) -> Result<u8, c_int> {
    Ok((unsafe { read(p, position)? } as u8).to_ascii_uppercase())
}

/// Reads a leading dimension and checks `ld ≥ max(1, rows)`.
///
/// # Safety
/// As [`read`].
unsafe fn leading(p: *const c_int, rows: usize, position: c_int) -> Result<usize, c_int> {
    let ld = unsafe { read(p, position)? };
    match usize::try_from(ld) {
        Ok(ld) if ld >= rows.max(1) => Ok(ld),
        _ => Err(position),
    }
}

fn trans_flag(f: u8, position: c_int) -> Result<Trans, c_int> {
    match f {
        b'N' => Ok(Trans::No),
        b'T' | b'C' => Ok(Trans::Yes),
        _ => Err(position),
    }
}

fn uplo_flag(f: u8, position: c_int) -> Result<Uplo, c_int> {
    match f {
        b'U' => Ok(Uplo::Upper),
        b'L' => Ok(Uplo::Lower),
        _ => Err(position),
    }
}

/// Reads a vector increment and checks `inc ≠ 0`.
///
/// # Safety
/// As [`read`].
unsafe fn increment(p: *const c_int, position: c_int) -> Result<isize, c_int> {
    match unsafe { read(p, position)? } {
        0 => Err(position),
        v => Ok(v as isize),
    }
}

/// Borrows `len` elements behind `p` (nothing is dereferenced when `len = 0`).
///
/// # Safety
/// When `len > 0`, `p` must be null or point to `len` initialised `T`s that nothing writes
/// during the borrow.
unsafe fn slice<'a, T>(p: *const T, len: usize, position: c_int) -> Result<&'a [T], c_int> {
    if len == 0 {
        Ok(&[])
    } else if p.is_null() {
        Err(position)
    } else {
        // SAFETY: non-null and, by the caller's contract, valid for `len` reads.
        Ok(unsafe { std::slice::from_raw_parts(p, len) })
    }
}

/// Mutably borrows `len` elements behind `p` (nothing is dereferenced when `len = 0`).
///
/// # Safety
/// When `len > 0`, `p` must be null or point to `len` `T`s that nothing else accesses during
/// the borrow (the Fortran rule that output arrays do not alias inputs).
unsafe fn slice_mut<'a, T>(p: *mut T, len: usize, position: c_int) -> Result<&'a mut [T], c_int> {
    if len == 0 {
        Ok(&mut [])
    } else if p.is_null() {
        Err(position)
    } else {
        // SAFETY: non-null and, by the caller's contract, valid and unaliased for `len` elements.
        Ok(unsafe { std::slice::from_raw_parts_mut(p, len) })
    }
}

/// Runs a BLAS body; argument errors and panics both leave the outputs as they are.
fn run_blas(body: impl FnOnce() -> Check) {
    let _ = catch_unwind(AssertUnwindSafe(body));
}

/// Runs a LAPACK body and stores its `INFO` (`−i` for an invalid argument `i`).
///
/// # Safety
/// `info` must be null or point to a writable `c_int`.
unsafe fn run_lapack(info: *mut c_int, body: impl FnOnce() -> Result<c_int, c_int>) {
    let code = match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(code)) => code,
        Ok(Err(position)) => -position,
        Err(_) => INTERNAL_ERROR,
    };
    if !info.is_null() {
        // SAFETY: non-null and writable by the caller's contract.
        unsafe { info.write(code) };
    }
}

/// Stores a workspace size in `work[0]` the way LAPACK does (as a floating-point number).
fn report_size<T: Real>(work: &mut [T], size: usize) {
    if let Some(w) = work.first_mut() {
        *w = nalgebra::convert(size as f64);
    }
}

/// Writes column-major `m` into the `rows × cols` leading block of an array with leading
/// dimension `ld`.
fn store<T: Real>(m: &nalgebra::DMatrix<T>, out: &mut [T], ld: usize) {
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            out[i + j * ld] = m[(i, j)];
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Generic bodies. Argument positions follow the Fortran argument lists.

/// # Safety
/// See [`dgemm_`].
#[allow(clippy::too_many_arguments)]
unsafe fn gemm_impl<T: Real>(
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
/// See [`dgemv_`].
#[allow(clippy::too_many_arguments)]
unsafe fn gemv_impl<T: Real>(
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
/// See [`dsymv_`].
#[allow(clippy::too_many_arguments)]
unsafe fn symv_impl<T: Real>(
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

/// # Safety
/// See [`dsyrk_`].
#[allow(clippy::too_many_arguments)]
unsafe fn syrk_impl<T: Real>(
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
        let ul = uplo_flag(flag(uplo, 1)?, 1)?;
        let t = trans_flag(flag(trans, 2)?, 2)?;
        let (n, k) = (dim(n, 3)?, dim(k, 4)?);
        let (nrowa, ncola) = if t == Trans::No { (n, k) } else { (k, n) };
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
/// See [`dsyr2k_`].
#[allow(clippy::too_many_arguments)]
unsafe fn syr2k_impl<T: Real>(
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
        let ul = uplo_flag(flag(uplo, 1)?, 1)?;
        let t = trans_flag(flag(trans, 2)?, 2)?;
        let (n, k) = (dim(n, 3)?, dim(k, 4)?);
        let (nrow, ncol) = if t == Trans::No { (n, k) } else { (k, n) };
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

/// # Safety
/// See [`dpotrf_`].
unsafe fn potrf_impl<T: Real>(
    uplo: *const c_char,
    n: *const c_int,
    a: *mut T,
    lda: *const c_int,
    info: *mut c_int,
) {
    unsafe {
        run_lapack(info, || {
            let ul = uplo_flag(flag(uplo, 1)?, 1)?;
            let n = dim(n, 2)?;
            let lda = leading(lda, n, 4)?;
            if n == 0 {
                return Ok(0);
            }
            let a = slice_mut(a, matrix_len(n, n, lda), 3)?;
            Ok(lapack::potrf(ul, n, a, lda))
        })
    }
}

/// # Safety
/// See [`dpotrs_`].
#[allow(clippy::too_many_arguments)]
unsafe fn potrs_impl<T: Real>(
    uplo: *const c_char,
    n: *const c_int,
    nrhs: *const c_int,
    a: *const T,
    lda: *const c_int,
    b: *mut T,
    ldb: *const c_int,
    info: *mut c_int,
) {
    unsafe {
        run_lapack(info, || {
            let ul = uplo_flag(flag(uplo, 1)?, 1)?;
            let (n, nrhs) = (dim(n, 2)?, dim(nrhs, 3)?);
            let lda = leading(lda, n, 5)?;
            let ldb = leading(ldb, n, 7)?;
            if n == 0 || nrhs == 0 {
                return Ok(0);
            }
            let a = slice(a, matrix_len(n, n, lda), 4)?;
            let b = slice_mut(b, matrix_len(n, nrhs, ldb), 6)?;
            lapack::potrs(ul, (n, nrhs), (a, lda), (b, ldb));
            Ok(0)
        })
    }
}

/// # Safety
/// See [`dsyevr_`].
#[allow(clippy::too_many_arguments)]
unsafe fn syevr_impl<T: Real>(
    jobz: *const c_char,
    range: *const c_char,
    uplo: *const c_char,
    n: *const c_int,
    a: *mut T,
    lda: *const c_int,
    vl: *const T,
    vu: *const T,
    il: *const c_int,
    iu: *const c_int,
    _abstol: *const T,
    m: *mut c_int,
    w: *mut T,
    z: *mut T,
    ldz: *const c_int,
    isuppz: *mut c_int,
    work: *mut T,
    lwork: *const c_int,
    iwork: *mut c_int,
    liwork: *const c_int,
    info: *mut c_int,
) {
    unsafe {
        run_lapack(info, || {
            let wantz = match flag(jobz, 1)? {
                b'V' => true,
                b'N' => false,
                _ => return Err(1),
            };
            let range_flag = flag(range, 2)?;
            if !matches!(range_flag, b'A' | b'V' | b'I') {
                return Err(2);
            }
            let ul = uplo_flag(flag(uplo, 3)?, 3)?;
            let n = dim(n, 4)?;
            let lda = leading(lda, n, 6)?;
            let sel = match range_flag {
                b'V' => {
                    let (lo, hi) = (read(vl, 7)?, read(vu, 8)?);
                    if n > 0 && hi <= lo {
                        return Err(8);
                    }
                    EigRange::Values(lo, hi)
                }
                b'I' => {
                    let (lo, hi) = (read(il, 9)?, read(iu, 10)?);
                    if lo < 1 || lo as usize > n.max(1) {
                        return Err(9);
                    }
                    if (hi as i64) < (n as i64).min(lo as i64) || hi as usize > n {
                        return Err(10);
                    }
                    EigRange::Indices(lo as usize, hi as usize)
                }
                _ => EigRange::All,
            };
            let ldz_v = read(ldz, 15)?;
            if ldz_v < 1 || (wantz && (ldz_v as usize) < n) {
                return Err(15);
            }
            let ldz = ldz_v as usize;
            let (lwork, liwork) = (read(lwork, 18)?, read(liwork, 20)?);
            let query = lwork == -1 || liwork == -1;
            // The documented minimum workspace (LAPACK dsyevr: LWORK ≥ max(1, 26N),
            // LIWORK ≥ max(1, 10N)); the shim itself needs none of it.
            let (lwmin, liwmin) = ((26 * n).max(1), (10 * n).max(1));
            if !query && (lwork as i64) < lwmin as i64 {
                return Err(18);
            }
            if !query && (liwork as i64) < liwmin as i64 {
                return Err(20);
            }
            let work_ptr = work;
            let work = slice_mut(work, 1, 17)?;
            let iwork = slice_mut(iwork, 1, 19)?;
            report_size(work, lwmin);
            iwork[0] = liwmin as c_int;
            if query {
                return Ok(0);
            }
            let m = slice_mut(m, 1, 12)?;
            m[0] = 0;
            if n == 0 {
                return Ok(0);
            }
            if !wantz {
                // Eigenvalues only (Clarabel's step length): the allocation-free path, on the
                // caller's A (whose triangle LAPACK also destroys) and WORK (≥ 26N ≥ 3N).
                let a = slice_mut(a, matrix_len(n, n, lda), 5)?;
                let work = slice_mut(work_ptr, lwork as usize, 17)?;
                let w = slice_mut(w, n, 13)?;
                let Some(found) = lapack::syevr_values(sel, ul, n, (a, lda), w, work) else {
                    return Ok(1);
                };
                m[0] = found as c_int;
                return Ok(0);
            }
            let a = slice(a, matrix_len(n, n, lda), 5)?;
            let Some(eig) = lapack::syevr(wantz, sel, ul, n, (a, lda)) else {
                return Ok(1);
            };
            let found = eig.values.len();
            m[0] = found as c_int;
            let w = slice_mut(w, n, 13)?;
            w[..found].copy_from_slice(&eig.values);
            if let Some(v) = &eig.vectors {
                let z = slice_mut(z, matrix_len(n, found, ldz), 14)?;
                store(v, z, ldz);
                // ISUPPZ is defined for the full-spectrum cases only (as in LAPACK).
                let full = matches!(sel, EigRange::All)
                    || matches!(sel, EigRange::Indices(lo, hi) if hi + 1 - lo == n);
                if full {
                    let isuppz = slice_mut(isuppz, 2 * found.max(1), 16)?;
                    for c in 0..found {
                        let col = v.column(c);
                        let first = col.iter().position(|x| *x != T::zero()).unwrap_or(0);
                        let last = col.iter().rposition(|x| *x != T::zero()).unwrap_or(0);
                        isuppz[2 * c] = first as c_int + 1;
                        isuppz[2 * c + 1] = last as c_int + 1;
                    }
                }
            }
            Ok(0)
        })
    }
}

/// What an SVD driver does with one factor.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Job {
    /// `'A'`: the full square factor into its own array.
    All,
    /// `'S'`: the `min(m, n)` leading vectors into its own array.
    Some,
    /// `'O'`: the `min(m, n)` leading vectors over `A`.
    Overwrite,
    /// `'N'`: not computed.
    None,
}

fn job_flag(f: u8, position: c_int) -> Result<Job, c_int> {
    match f {
        b'A' => Ok(Job::All),
        b'S' => Ok(Job::Some),
        b'O' => Ok(Job::Overwrite),
        b'N' => Ok(Job::None),
        _ => Err(position),
    }
}

/// Shared tail of the SVD drivers: computes the decomposition of the `m × n` array `a` and
/// stores `s`, `U` and `Vᵀ` according to the jobs. Returns `INFO`.
///
/// # Safety
/// The pointers must satisfy the xGESDD/xGESVD contracts for the given jobs and dimensions.
#[allow(clippy::too_many_arguments)]
unsafe fn svd_store<T: Real>(
    (jobu, jobvt): (Job, Job),
    (m, n): (usize, usize),
    (a, lda): (*mut T, usize),
    s: *mut T,
    (u, ldu): (*mut T, usize),
    (vt, ldvt): (*mut T, usize),
    positions: [c_int; 4],
) -> Result<c_int, c_int> {
    let [pa, ps, pu, pvt] = positions;
    let mn = m.min(n);
    // Thin jobs on small matrices (Clarabel's PSD-cone scalings): allocation-free one-sided
    // Jacobi. Its only failure, no convergence within the sweep limit, falls through to the
    // bidiagonal QR below (as does non-finite input, which that path reports).
    // Small matrices (Clarabel's PSD-cone scalings): allocation-free one-sided Jacobi. Its
    // only failure, no convergence within the sweep limit, falls through to the bidiagonal
    // QR below (as does non-finite input, which that path reports).
    if m.max(n) <= jacobi::MAX_SIDE {
        // The working matrix is A (m ≥ n) or Aᵀ: its right factor is V or U, its left
        // factor U or V, completed to a square matrix for an 'A' job on that side.
        let (want_v, full) = if m >= n {
            (jobvt != Job::None, jobu == Job::All)
        } else {
            (jobu != Job::None, jobvt == Job::All)
        };
        let (ucols, vtrows) = (
            if jobu == Job::All { m } else { mn },
            if jobvt == Job::All { n } else { mn },
        );
        // The outputs (A itself for the 'O' jobs) are borrowed only after the input was
        // read into the working array, inside the sink.
        let mut result = Ok(0);
        let sink = |f: jacobi::Factors<'_, T>| {
            result = (|| {
                unsafe { slice_mut(s, mn, ps)? }.copy_from_slice(f.s);
                if jobu != Job::None {
                    let (target, ld) = if jobu == Job::Overwrite {
                        (unsafe { slice_mut(a, matrix_len(m, n, lda), pa)? }, lda)
                    } else {
                        (unsafe { slice_mut(u, matrix_len(m, ucols, ldu), pu)? }, ldu)
                    };
                    for j in 0..ucols {
                        for (i, x) in target[j * ld..j * ld + m].iter_mut().enumerate() {
                            *x = f.u(i, j);
                        }
                    }
                }
                if jobvt != Job::None {
                    let (target, ld) = if jobvt == Job::Overwrite {
                        (unsafe { slice_mut(a, matrix_len(m, n, lda), pa)? }, lda)
                    } else {
                        (
                            unsafe { slice_mut(vt, matrix_len(vtrows, n, ldvt), pvt)? },
                            ldvt,
                        )
                    };
                    for j in 0..n {
                        for (i, x) in target[j * ld..j * ld + vtrows].iter_mut().enumerate() {
                            *x = f.vt(i, j);
                        }
                    }
                }
                Ok(0)
            })();
        };
        let a_in = unsafe { slice(a as *const T, matrix_len(m, n, lda), pa)? };
        let done = if jobu == Job::Overwrite || jobvt == Job::Overwrite {
            // The sink writes over A: hand the kernel a copy, so that no borrow of A is
            // alive while it is written.
            let mut copy = [T::zero(); jacobi::MAX_SIDE * jacobi::MAX_SIDE];
            for j in 0..n {
                copy[j * m..(j + 1) * m].copy_from_slice(&a_in[j * lda..j * lda + m]);
            }
            jacobi::jacobi_svd((m, n), (&copy[..m * n], m), (want_v, full), sink)
        } else {
            jacobi::jacobi_svd((m, n), (a_in, lda), (want_v, full), sink)
        };
        if done {
            return result;
        }
    }
    let dec = {
        let a = unsafe { slice(a as *const T, matrix_len(m, n, lda), pa)? };
        lapack::svd(
            (m, n),
            (a, lda),
            (jobu != Job::None, jobu == Job::All),
            (jobvt != Job::None, jobvt == Job::All),
        )
    };
    let Some(dec) = dec else {
        return Ok(1);
    };
    let s = unsafe { slice_mut(s, mn, ps)? };
    s.copy_from_slice(&dec.s);
    if let Some(uf) = &dec.u {
        let target = if jobu == Job::Overwrite {
            unsafe { slice_mut(a, matrix_len(m, n, lda), pa)? }
        } else {
            unsafe { slice_mut(u, matrix_len(m, uf.ncols(), ldu), pu)? }
        };
        store(uf, target, if jobu == Job::Overwrite { lda } else { ldu });
    }
    if let Some(vf) = &dec.vt {
        let target = if jobvt == Job::Overwrite {
            unsafe { slice_mut(a, matrix_len(m, n, lda), pa)? }
        } else {
            unsafe { slice_mut(vt, matrix_len(vf.nrows(), n, ldvt), pvt)? }
        };
        store(vf, target, if jobvt == Job::Overwrite { lda } else { ldvt });
    }
    Ok(0)
}

/// # Safety
/// See [`dgesdd_`].
#[allow(clippy::too_many_arguments)]
unsafe fn gesdd_impl<T: Real>(
    jobz: *const c_char,
    m: *const c_int,
    n: *const c_int,
    a: *mut T,
    lda: *const c_int,
    s: *mut T,
    u: *mut T,
    ldu: *const c_int,
    vt: *mut T,
    ldvt: *const c_int,
    work: *mut T,
    lwork: *const c_int,
    _iwork: *mut c_int,
    info: *mut c_int,
) {
    unsafe {
        run_lapack(info, || {
            let job = job_flag(flag(jobz, 1)?, 1)?;
            let (m, n) = (dim(m, 2)?, dim(n, 3)?);
            let (mn, mx) = (m.min(n), m.max(n));
            let lda = leading(lda, m, 5)?;
            let ldu_v = read(ldu, 8)?;
            let needs_ldu_m =
                matches!(job, Job::All | Job::Some) || (job == Job::Overwrite && m < n);
            if ldu_v < 1 || (needs_ldu_m && (ldu_v as usize) < m) {
                return Err(8);
            }
            let ldvt_v = read(ldvt, 10)?;
            let bad_ldvt = ldvt_v < 1
                || (job == Job::All && (ldvt_v as usize) < n)
                || (job == Job::Some && (ldvt_v as usize) < mn)
                || (job == Job::Overwrite && m >= n && (ldvt_v as usize) < n);
            if bad_ldvt {
                return Err(10);
            }
            // Documented minimum workspace of LAPACK 3.x dgesdd.
            let minwrk = match job {
                Job::None => 3 * mn + mx.max(7 * mn),
                Job::Overwrite => 3 * mn + mx.max(5 * mn * mn + 4 * mn),
                Job::Some => 4 * mn * mn + 7 * mn,
                Job::All => 4 * mn * mn + 6 * mn + mx,
            }
            .max(1);
            let lwork = read(lwork, 12)?;
            let query = lwork == -1;
            if !query && (lwork as i64) < minwrk as i64 {
                return Err(12);
            }
            report_size(slice_mut(work, 1, 11)?, minwrk);
            if query || m == 0 || n == 0 {
                return Ok(0);
            }
            // 'O' overwrites A with U when m ≥ n and with Vᵀ otherwise; the other factor is
            // returned in full (it is square), as LAPACK documents.
            let (jobu, jobvt) = match job {
                Job::Overwrite if m >= n => (Job::Overwrite, Job::Some),
                Job::Overwrite => (Job::Some, Job::Overwrite),
                j => (j, j),
            };
            svd_store(
                (jobu, jobvt),
                (m, n),
                (a, lda),
                s,
                (u, ldu_v as usize),
                (vt, ldvt_v as usize),
                [4, 6, 7, 9],
            )
        })
    }
}

/// # Safety
/// See [`dgesvd_`].
#[allow(clippy::too_many_arguments)]
unsafe fn gesvd_impl<T: Real>(
    jobu: *const c_char,
    jobvt: *const c_char,
    m: *const c_int,
    n: *const c_int,
    a: *mut T,
    lda: *const c_int,
    s: *mut T,
    u: *mut T,
    ldu: *const c_int,
    vt: *mut T,
    ldvt: *const c_int,
    work: *mut T,
    lwork: *const c_int,
    info: *mut c_int,
) {
    unsafe {
        run_lapack(info, || {
            let ju = job_flag(flag(jobu, 1)?, 1)?;
            let jv = job_flag(flag(jobvt, 2)?, 2)?;
            if ju == Job::Overwrite && jv == Job::Overwrite {
                return Err(2);
            }
            let (m, n) = (dim(m, 3)?, dim(n, 4)?);
            let (mn, mx) = (m.min(n), m.max(n));
            let lda = leading(lda, m, 6)?;
            let ldu_v = read(ldu, 9)?;
            if ldu_v < 1 || (matches!(ju, Job::All | Job::Some) && (ldu_v as usize) < m) {
                return Err(9);
            }
            let ldvt_v = read(ldvt, 11)?;
            let bad_ldvt = ldvt_v < 1
                || (jv == Job::All && (ldvt_v as usize) < n)
                || (jv == Job::Some && (ldvt_v as usize) < mn);
            if bad_ldvt {
                return Err(11);
            }
            // Documented minimum workspace of LAPACK 3.x dgesvd.
            let minwrk = (3 * mn + mx).max(5 * mn).max(1);
            let lwork = read(lwork, 13)?;
            let query = lwork == -1;
            if !query && (lwork as i64) < minwrk as i64 {
                return Err(13);
            }
            report_size(slice_mut(work, 1, 12)?, minwrk);
            if query || m == 0 || n == 0 {
                return Ok(0);
            }
            svd_store(
                (ju, jv),
                (m, n),
                (a, lda),
                s,
                (u, ldu_v as usize),
                (vt, ldvt_v as usize),
                [5, 7, 8, 10],
            )
        })
    }
}

/// # Safety
/// See [`dgesv_`].
#[allow(clippy::too_many_arguments)]
unsafe fn gesv_impl<T: Real>(
    n: *const c_int,
    nrhs: *const c_int,
    a: *mut T,
    lda: *const c_int,
    ipiv: *mut c_int,
    b: *mut T,
    ldb: *const c_int,
    info: *mut c_int,
) {
    unsafe {
        run_lapack(info, || {
            let (n, nrhs) = (dim(n, 1)?, dim(nrhs, 2)?);
            let lda = leading(lda, n, 4)?;
            let ldb = leading(ldb, n, 7)?;
            if n == 0 {
                return Ok(0);
            }
            let a = slice_mut(a, matrix_len(n, n, lda), 3)?;
            let ipiv = slice_mut(ipiv, n, 5)?;
            let b = slice_mut(b, matrix_len(n, nrhs, ldb), 6)?;
            Ok(lapack::gesv((n, nrhs), (a, lda), ipiv, (b, ldb)))
        })
    }
}

// ---------------------------------------------------------------------------------------------
// The exported symbols: one `d` (f64) and one `s` (f32) version of each routine.

macro_rules! symbols {
    ($t:ty, $p:literal,
     $gemm:ident, $gemv:ident, $symv:ident, $syrk:ident, $syr2k:ident,
     $potrf:ident, $potrs:ident, $syevr:ident, $gesdd:ident, $gesvd:ident, $gesv:ident) => {
        #[doc = concat!("BLAS `", $p, "GEMM`: `C ← α op(A) op(B) + β C` (`C` is `m × n`).")]
        ///
        /// `op(X)` is `X` for `'N'`, `Xᵀ` for `'T'`/`'C'`. `β = 0` does not read `C`;
        /// `α = 0` does not read `A`, `B`. An invalid argument makes the call a no-op.
        ///
        /// # Safety
        /// Fortran contract: every pointer refers to a valid object of the documented size
        /// (`A`: `lda × ka`, `B`: `ldb × kb`, `C`: `ldc × n`); `C` does not alias `A` or `B`.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $gemm(
            transa: *const c_char,
            transb: *const c_char,
            m: *const c_int,
            n: *const c_int,
            k: *const c_int,
            alpha: *const $t,
            a: *const $t,
            lda: *const c_int,
            b: *const $t,
            ldb: *const c_int,
            beta: *const $t,
            c: *mut $t,
            ldc: *const c_int,
        ) {
            // SAFETY: forwarded caller contract.
            unsafe { gemm_impl::<$t>(transa, transb, m, n, k, alpha, a, lda, b, ldb, beta, c, ldc) }
        }

        #[doc = concat!("BLAS `", $p, "GEMV`: `y ← α op(A) x + β y` (`A` is `m × n`).")]
        ///
        /// Increments may be negative (the vector is then traversed from its end) but not
        /// zero. `β = 0` does not read `y`. An invalid argument makes the call a no-op.
        ///
        /// # Safety
        /// Fortran contract: `A` is `lda × n`, `x`/`y` hold `1 + (len − 1)|inc|` elements;
        /// `y` does not alias `A` or `x`.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $gemv(
            trans: *const c_char,
            m: *const c_int,
            n: *const c_int,
            alpha: *const $t,
            a: *const $t,
            lda: *const c_int,
            x: *const $t,
            incx: *const c_int,
            beta: *const $t,
            y: *mut $t,
            incy: *const c_int,
        ) {
            // SAFETY: forwarded caller contract.
            unsafe { gemv_impl::<$t>(trans, m, n, alpha, a, lda, x, incx, beta, y, incy) }
        }

        #[doc = concat!("BLAS `", $p, "SYMV`: `y ← α A x + β y`, `A` symmetric given by its `uplo` triangle.")]
        ///
        /// Only the named triangle of `A` is read. An invalid argument makes the call a no-op.
        ///
        /// # Safety
        /// Fortran contract as for the `GEMV` routine with `A` `lda × n`.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $symv(
            uplo: *const c_char,
            n: *const c_int,
            alpha: *const $t,
            a: *const $t,
            lda: *const c_int,
            x: *const $t,
            incx: *const c_int,
            beta: *const $t,
            y: *mut $t,
            incy: *const c_int,
        ) {
            // SAFETY: forwarded caller contract.
            unsafe { symv_impl::<$t>(uplo, n, alpha, a, lda, x, incx, beta, y, incy) }
        }

        #[doc = concat!("BLAS `", $p, "SYRK`: `C ← α A Aᵀ + β C` (`'N'`) or `C ← α Aᵀ A + β C` (`'T'`/`'C'`).")]
        ///
        /// Only the `uplo` triangle of `C` (`n × n`) is read and written; the other triangle
        /// is left untouched. An invalid argument makes the call a no-op.
        ///
        /// # Safety
        /// Fortran contract: `A` is `lda × k` (`'N'`) or `lda × n`, `C` is `ldc × n`, no aliasing.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $syrk(
            uplo: *const c_char,
            trans: *const c_char,
            n: *const c_int,
            k: *const c_int,
            alpha: *const $t,
            a: *const $t,
            lda: *const c_int,
            beta: *const $t,
            c: *mut $t,
            ldc: *const c_int,
        ) {
            // SAFETY: forwarded caller contract.
            unsafe { syrk_impl::<$t>(uplo, trans, n, k, alpha, a, lda, beta, c, ldc) }
        }

        #[doc = concat!("BLAS `", $p, "SYR2K`: `C ← α (A Bᵀ + B Aᵀ) + β C` (`'N'`) or `C ← α (Aᵀ B + Bᵀ A) + β C`.")]
        ///
        /// Only the `uplo` triangle of `C` is read and written. An invalid argument makes the
        /// call a no-op.
        ///
        /// # Safety
        /// Fortran contract: `A`, `B` are `ld × k` (`'N'`) or `ld × n`, `C` is `ldc × n`, no aliasing.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $syr2k(
            uplo: *const c_char,
            trans: *const c_char,
            n: *const c_int,
            k: *const c_int,
            alpha: *const $t,
            a: *const $t,
            lda: *const c_int,
            b: *const $t,
            ldb: *const c_int,
            beta: *const $t,
            c: *mut $t,
            ldc: *const c_int,
        ) {
            // SAFETY: forwarded caller contract.
            unsafe { syr2k_impl::<$t>(uplo, trans, n, k, alpha, a, lda, b, ldb, beta, c, ldc) }
        }

        #[doc = concat!("LAPACK `", $p, "POTRF`: Cholesky factorisation `A = L Lᵀ` (`'L'`) or `A = Uᵀ U` (`'U'`).")]
        ///
        /// The factor overwrites the named triangle; the other triangle is untouched.
        /// `INFO = j > 0`: the leading minor of order `j` is not positive definite.
        /// `INFO = −i`: argument `i` is invalid.
        ///
        /// # Safety
        /// Fortran contract: `A` is `lda × n`, `info` writable.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $potrf(
            uplo: *const c_char,
            n: *const c_int,
            a: *mut $t,
            lda: *const c_int,
            info: *mut c_int,
        ) {
            // SAFETY: forwarded caller contract.
            unsafe { potrf_impl::<$t>(uplo, n, a, lda, info) }
        }

        #[doc = concat!("LAPACK `", $p, "POTRS`: solves `A X = B` with the factor from `", $p, "POTRF`.")]
        ///
        /// `B` (`n × nrhs`) is overwritten by `X`. `INFO = −i`: argument `i` is invalid.
        ///
        /// # Safety
        /// Fortran contract: `A` is `lda × n`, `B` is `ldb × nrhs`, `info` writable.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $potrs(
            uplo: *const c_char,
            n: *const c_int,
            nrhs: *const c_int,
            a: *const $t,
            lda: *const c_int,
            b: *mut $t,
            ldb: *const c_int,
            info: *mut c_int,
        ) {
            // SAFETY: forwarded caller contract.
            unsafe { potrs_impl::<$t>(uplo, n, nrhs, a, lda, b, ldb, info) }
        }

        #[doc = concat!("LAPACK `", $p, "SYEVR`: eigenvalues (ascending) and optionally eigenvectors of a symmetric matrix.")]
        ///
        /// `RANGE` `'A'` (all), `'V'` (those in `(vl, vu]`) or `'I'` (the `il`-th to
        /// `iu`-th); `M` returns how many were found, `W[0..M]` the values in ascending order,
        /// `Z` their orthonormal eigenvectors (`JOBZ = 'V'`). `ABSTOL` is ignored: values are
        /// always computed to full working accuracy. `ISUPPZ` is filled for the full-spectrum
        /// cases, as in LAPACK. `A` is not modified (LAPACK leaves its triangle unspecified).
        /// A workspace query (`LWORK = −1` or `LIWORK = −1`) only reports the documented
        /// minimum sizes `max(1, 26n)` and `max(1, 10n)` in `WORK[0]`/`IWORK[0]`.
        /// `INFO = 1`: non-finite input or no convergence; `INFO = −i`: argument `i` invalid.
        ///
        /// # Safety
        /// Fortran contract for xSYEVR: array sizes as documented there (`W`: `n`,
        /// `Z`: `ldz × M`, `ISUPPZ`: `2 max(1, M)`, `WORK`: `max(1, LWORK)`,
        /// `IWORK`: `max(1, LIWORK)`).
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $syevr(
            jobz: *const c_char,
            range: *const c_char,
            uplo: *const c_char,
            n: *const c_int,
            a: *mut $t,
            lda: *const c_int,
            vl: *const $t,
            vu: *const $t,
            il: *const c_int,
            iu: *const c_int,
            abstol: *const $t,
            m: *mut c_int,
            w: *mut $t,
            z: *mut $t,
            ldz: *const c_int,
            isuppz: *mut c_int,
            work: *mut $t,
            lwork: *const c_int,
            iwork: *mut c_int,
            liwork: *const c_int,
            info: *mut c_int,
        ) {
            // SAFETY: forwarded caller contract.
            unsafe {
                syevr_impl::<$t>(
                    jobz, range, uplo, n, a, lda, vl, vu, il, iu, abstol, m, w, z, ldz, isuppz,
                    work, lwork, iwork, liwork, info,
                )
            }
        }

        #[doc = concat!("LAPACK `", $p, "GESDD`: singular value decomposition `A = U Σ Vᵀ`, singular values descending.")]
        ///
        /// `JOBZ` `'A'` (full `U`, `Vᵀ`), `'S'` (the `min(m, n)` leading vectors), `'O'`
        /// (leading vectors overwrite `A`: `U` if `m ≥ n`, else `Vᵀ`) or `'N'` (values only).
        /// A workspace query (`LWORK = −1`) reports LAPACK's documented minimum in `WORK[0]`.
        /// Matrices with both sides ≤ 32 are decomposed by one-sided Jacobi (no allocation;
        /// small singular values of graded matrices to high relative accuracy), larger ones
        /// by bidiagonal QR; `WORK` is not used beyond `WORK[0]`. `IWORK` is not used. `INFO = 1`: non-finite input or no convergence;
        /// `INFO = −i`: argument `i` invalid.
        ///
        /// # Safety
        /// Fortran contract for xGESDD (array sizes as documented there).
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $gesdd(
            jobz: *const c_char,
            m: *const c_int,
            n: *const c_int,
            a: *mut $t,
            lda: *const c_int,
            s: *mut $t,
            u: *mut $t,
            ldu: *const c_int,
            vt: *mut $t,
            ldvt: *const c_int,
            work: *mut $t,
            lwork: *const c_int,
            iwork: *mut c_int,
            info: *mut c_int,
        ) {
            // SAFETY: forwarded caller contract.
            unsafe {
                gesdd_impl::<$t>(
                    jobz, m, n, a, lda, s, u, ldu, vt, ldvt, work, lwork, iwork, info,
                )
            }
        }

        #[doc = concat!("LAPACK `", $p, "GESVD`: singular value decomposition `A = U Σ Vᵀ`, singular values descending.")]
        ///
        /// `JOBU`/`JOBVT` `'A'`, `'S'`, `'O'` (overwrite `A`; not both) or `'N'`, as in
        /// LAPACK. A workspace query (`LWORK = −1`) reports the documented minimum
        /// `max(1, 3 min(m,n) + max(m,n), 5 min(m,n))`. The algorithm is chosen as for the
        /// `GESDD` routine (one-sided Jacobi up to side 32). `INFO = 1`: non-finite input or no
        /// convergence; `INFO = −i`: argument `i` invalid.
        ///
        /// # Safety
        /// Fortran contract for xGESVD (array sizes as documented there).
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $gesvd(
            jobu: *const c_char,
            jobvt: *const c_char,
            m: *const c_int,
            n: *const c_int,
            a: *mut $t,
            lda: *const c_int,
            s: *mut $t,
            u: *mut $t,
            ldu: *const c_int,
            vt: *mut $t,
            ldvt: *const c_int,
            work: *mut $t,
            lwork: *const c_int,
            info: *mut c_int,
        ) {
            // SAFETY: forwarded caller contract.
            unsafe {
                gesvd_impl::<$t>(
                    jobu, jobvt, m, n, a, lda, s, u, ldu, vt, ldvt, work, lwork, info,
                )
            }
        }

        #[doc = concat!("LAPACK `", $p, "GESV`: solves `A X = B` by LU factorisation with partial pivoting.")]
        ///
        /// On exit `A` holds `L` (unit lower) and `U`, `IPIV` the 1-based row interchanges,
        /// `B` the solution. `INFO = j > 0`: `U(j, j)` is exactly zero (no solution computed);
        /// `INFO = −i`: argument `i` invalid.
        ///
        /// # Safety
        /// Fortran contract: `A` is `lda × n`, `IPIV` holds `n` integers, `B` is `ldb × nrhs`.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $gesv(
            n: *const c_int,
            nrhs: *const c_int,
            a: *mut $t,
            lda: *const c_int,
            ipiv: *mut c_int,
            b: *mut $t,
            ldb: *const c_int,
            info: *mut c_int,
        ) {
            // SAFETY: forwarded caller contract.
            unsafe { gesv_impl::<$t>(n, nrhs, a, lda, ipiv, b, ldb, info) }
        }
    };
}

symbols!(
    f64, "D", dgemm_, dgemv_, dsymv_, dsyrk_, dsyr2k_, dpotrf_, dpotrs_, dsyevr_, dgesdd_, dgesvd_,
    dgesv_
);
symbols!(
    f32, "S", sgemm_, sgemv_, ssymv_, ssyrk_, ssyr2k_, spotrf_, spotrs_, ssyevr_, sgesdd_, sgesvd_,
    sgesv_
);
