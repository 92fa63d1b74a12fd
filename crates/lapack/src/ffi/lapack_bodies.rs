//! The generic bodies of the LAPACK factorisations, solves and eigenvalue driver (`xPOTRF`,
//! `xPOTRS`, `xSYEVR`, `xGESV`): argument validation in the reference order (`INFO = −i`),
//! then the safe kernels of the crate's `lapack` module. Argument positions follow the
//! Fortran argument lists.
//!
//! Neighbours: [`super`] exports the `d`/`s` symbols that call these; `args.rs` reads the
//! arguments; `svd_bodies.rs` holds the SVD drivers; `blas_bodies.rs` the BLAS bodies.

use super::args::{
    dim, flag, leading, read, report_size, run_lapack, slice, slice_mut, store, uplo_flag,
};
use crate::blas::matrix_len;
use crate::lapack::EigRange;
use crate::{Real, lapack};
use core::ffi::{c_char, c_int};

/// # Safety
/// See [`dpotrf_`](super::dpotrf_).
pub(super) unsafe fn potrf_impl<T: Real>(
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
/// See [`dpotrs_`](super::dpotrs_).
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn potrs_impl<T: Real>(
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
/// See [`dsyevr_`](super::dsyevr_).
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn syevr_impl<T: Real>(
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

/// # Safety
/// See [`dgesv_`](super::dgesv_).
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn gesv_impl<T: Real>(
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
