//! The generic bodies of the SVD drivers (`xGESDD`, `xGESVD`): the job flags, argument
//! validation in the reference order and the shared tail that computes the decomposition
//! (one-sided Jacobi for small matrices) and stores `s`, `U` and `Vᵀ` as the jobs ask.
//!
//! Neighbours: [`super`] exports the `d`/`s` symbols that call these; `args.rs` reads the
//! arguments; `lapack_bodies.rs` and `blas_bodies.rs` hold the other bodies.

use super::args::{dim, flag, leading, read, report_size, run_lapack, slice, slice_mut, store};
use crate::blas::matrix_len;
use crate::{Real, jacobi, lapack};
use core::ffi::{c_char, c_int};

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

/// The arguments xGESDD and xGESVD share, in their common order after the job flags: `M`,
/// `N`, `A`, `LDA`, `S`, `U`, `LDU`, `VT`, `LDVT`, `WORK`, `LWORK` (the raw Fortran pointers;
/// their argument numbers differ between the routines and are checked by each body).
pub(super) struct SvdArgs<T> {
    pub(super) m: *const c_int,
    pub(super) n: *const c_int,
    pub(super) a: *mut T,
    pub(super) lda: *const c_int,
    pub(super) s: *mut T,
    pub(super) u: *mut T,
    pub(super) ldu: *const c_int,
    pub(super) vt: *mut T,
    pub(super) ldvt: *const c_int,
    pub(super) work: *mut T,
    pub(super) lwork: *const c_int,
}

/// Reads `LWORK` (argument `plwork`), checks it against the documented minimum `minwrk`
/// (`Err(plwork)` if smaller and not the query `LWORK = −1`) and reports `minwrk` in
/// `WORK[0]` (argument `pwork`). True for a workspace query, which computes nothing else.
///
/// # Safety
/// `lwork` is valid for reads and `work` for one write (the xGESDD/xGESVD contracts).
unsafe fn workspace_query<T: Real>(
    (work, pwork): (*mut T, c_int),
    (lwork, plwork): (*const c_int, c_int),
    minwrk: usize,
) -> Result<bool, c_int> {
    // SAFETY: forwarded caller contract.
    unsafe {
        let lwork = read(lwork, plwork)?;
        let query = lwork == -1;
        if !query && (lwork as i64) < minwrk as i64 {
            return Err(plwork);
        }
        report_size(slice_mut(work, 1, pwork)?, minwrk);
        Ok(query)
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
/// See [`dgesdd_`](super::dgesdd_).
pub(super) unsafe fn gesdd_impl<T: Real>(jobz: *const c_char, args: SvdArgs<T>, info: *mut c_int) {
    unsafe {
        run_lapack(info, || {
            let job = job_flag(flag(jobz, 1)?, 1)?;
            let (m, n) = (dim(args.m, 2)?, dim(args.n, 3)?);
            let (mn, mx) = (m.min(n), m.max(n));
            let lda = leading(args.lda, m, 5)?;
            let ldu_v = read(args.ldu, 8)?;
            let needs_ldu_m =
                matches!(job, Job::All | Job::Some) || (job == Job::Overwrite && m < n);
            if ldu_v < 1 || (needs_ldu_m && (ldu_v as usize) < m) {
                return Err(8);
            }
            let ldvt_v = read(args.ldvt, 10)?;
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
            if workspace_query((args.work, 11), (args.lwork, 12), minwrk)? || m == 0 || n == 0 {
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
                (args.a, lda),
                args.s,
                (args.u, ldu_v as usize),
                (args.vt, ldvt_v as usize),
                [4, 6, 7, 9],
            )
        })
    }
}

/// # Safety
/// See [`dgesvd_`](super::dgesvd_).
pub(super) unsafe fn gesvd_impl<T: Real>(
    (jobu, jobvt): (*const c_char, *const c_char),
    args: SvdArgs<T>,
    info: *mut c_int,
) {
    unsafe {
        run_lapack(info, || {
            let ju = job_flag(flag(jobu, 1)?, 1)?;
            let jv = job_flag(flag(jobvt, 2)?, 2)?;
            if ju == Job::Overwrite && jv == Job::Overwrite {
                return Err(2);
            }
            let (m, n) = (dim(args.m, 3)?, dim(args.n, 4)?);
            let (mn, mx) = (m.min(n), m.max(n));
            let lda = leading(args.lda, m, 6)?;
            let ldu_v = read(args.ldu, 9)?;
            if ldu_v < 1 || (matches!(ju, Job::All | Job::Some) && (ldu_v as usize) < m) {
                return Err(9);
            }
            let ldvt_v = read(args.ldvt, 11)?;
            let bad_ldvt = ldvt_v < 1
                || (jv == Job::All && (ldvt_v as usize) < n)
                || (jv == Job::Some && (ldvt_v as usize) < mn);
            if bad_ldvt {
                return Err(11);
            }
            // Documented minimum workspace of LAPACK 3.x dgesvd.
            let minwrk = (3 * mn + mx).max(5 * mn).max(1);
            if workspace_query((args.work, 12), (args.lwork, 13), minwrk)? || m == 0 || n == 0 {
                return Ok(0);
            }
            svd_store(
                (ju, jv),
                (m, n),
                (args.a, lda),
                args.s,
                (args.u, ldu_v as usize),
                (args.vt, ldvt_v as usize),
                [5, 7, 8, 10],
            )
        })
    }
}
