//! Helpers shared by the shim's integration tests.
#![allow(dead_code)]

/// `len` deterministic entries in (−1, 1) from a linear congruential sequence (Knuth's MMIX
/// multiplier and increment), the column-major data of the tests' random matrices.
pub fn lcg_entries(len: usize, seed: u64) -> Vec<f64> {
    let mut s = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (0..len)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}

use core::ffi::{c_char, c_int};

/// The Fortran signature of xSYEVR (`dsyevr_`, `ssyevr_`), in LAPACK's argument order.
pub type SyevrFn<T> = unsafe extern "C" fn(
    *const c_char,
    *const c_char,
    *const c_char,
    *const c_int,
    *mut T,
    *const c_int,
    *const T,
    *const T,
    *const c_int,
    *const c_int,
    *const T,
    *mut c_int,
    *mut T,
    *mut T,
    *const c_int,
    *mut c_int,
    *mut T,
    *const c_int,
    *mut c_int,
    *const c_int,
    *mut c_int,
);

/// Calls xSYEVR `f` with its arguments grouped as LAPACK documents them and returns `INFO`:
/// the flags (`JOBZ`, `RANGE`, `UPLO`), the matrix (`N`, `A`, `LDA`), the selection and
/// tolerance (`VL`, `VU`, `IL`, `IU`, `ABSTOL`), the outputs (`M`, `W`, `Z`, `LDZ`,
/// `ISUPPZ`) and the workspaces (`WORK`, `LWORK`, `IWORK`, `LIWORK`). The integers are passed
/// as given, so a test can pass invalid ones and see the routine's `INFO = −i`.
///
/// # Safety
/// The dimensions and workspace lengths passed fit the slices, unless the routine rejects
/// them (an argument error or a workspace query) before touching the arrays.
#[allow(clippy::type_complexity)]
pub unsafe fn syevr<T: Copy>(
    f: SyevrFn<T>,
    (jobz, range, uplo): (c_char, c_char, c_char),
    (n, a, lda): (c_int, &mut [T], c_int),
    (vl, vu, il, iu, abstol): (T, T, c_int, c_int, T),
    (m, w, z, ldz, isuppz): (&mut c_int, &mut [T], &mut [T], c_int, &mut [c_int]),
    (work, lwork, iwork, liwork): (&mut [T], c_int, &mut [c_int], c_int),
) -> c_int {
    let mut info: c_int = -77;
    let (a, w, z, isuppz) = (
        a.as_mut_ptr(),
        w.as_mut_ptr(),
        z.as_mut_ptr(),
        isuppz.as_mut_ptr(),
    );
    let (work, iwork) = (work.as_mut_ptr(), iwork.as_mut_ptr());
    // SAFETY: forwarded caller contract.
    unsafe {
        f(
            &jobz, &range, &uplo, &n, a, &lda, &vl, &vu, &il, &iu, &abstol, m, w, z, &ldz, isuppz,
            work, &lwork, iwork, &liwork, &mut info,
        )
    };
    info
}

/// The Fortran signature of xGESDD (`dgesdd_`, `sgesdd_`), in LAPACK's argument order.
pub type GesddFn<T> = unsafe extern "C" fn(
    *const c_char,
    *const c_int,
    *const c_int,
    *mut T,
    *const c_int,
    *mut T,
    *mut T,
    *const c_int,
    *mut T,
    *const c_int,
    *mut T,
    *const c_int,
    *mut c_int,
    *mut c_int,
);

/// The Fortran signature of xGESVD (`dgesvd_`, `sgesvd_`), in LAPACK's argument order.
pub type GesvdFn<T> = unsafe extern "C" fn(
    *const c_char,
    *const c_char,
    *const c_int,
    *const c_int,
    *mut T,
    *const c_int,
    *mut T,
    *mut T,
    *const c_int,
    *mut T,
    *const c_int,
    *mut T,
    *const c_int,
    *mut c_int,
);

/// The arguments xGESDD and xGESVD share, grouped as LAPACK documents them: the matrix
/// (`M`, `N`, `A`, `LDA`), `S`, the factors (`U`, `LDU`, `VT`, `LDVT`) and the workspace
/// (`WORK`, `LWORK`). The integers are passed as given.
pub type SvdArgs<'a, T> = (
    (c_int, c_int, &'a mut [T], c_int),
    &'a mut [T],
    (&'a mut [T], c_int, &'a mut [T], c_int),
    (&'a mut [T], c_int),
);

/// Calls xGESDD `f` with job `jobz`, the shared SVD arguments and `IWORK`; returns `INFO`.
///
/// # Safety
/// As for [`syevr`]: the dimensions and lengths passed fit the slices, unless the routine
/// rejects them before touching the arrays.
pub unsafe fn gesdd<T: Copy>(
    f: GesddFn<T>,
    jobz: c_char,
    ((m, n, a, lda), s, (u, ldu, vt, ldvt), (work, lwork)): SvdArgs<'_, T>,
    iwork: &mut [c_int],
) -> c_int {
    let mut info: c_int = -77;
    let (a, s, u, vt, work) = (
        a.as_mut_ptr(),
        s.as_mut_ptr(),
        u.as_mut_ptr(),
        vt.as_mut_ptr(),
        work.as_mut_ptr(),
    );
    // SAFETY: forwarded caller contract.
    unsafe {
        f(
            &jobz,
            &m,
            &n,
            a,
            &lda,
            s,
            u,
            &ldu,
            vt,
            &ldvt,
            work,
            &lwork,
            iwork.as_mut_ptr(),
            &mut info,
        )
    };
    info
}

/// Calls xGESVD `f` with jobs `(jobu, jobvt)` and the shared SVD arguments; returns `INFO`.
///
/// # Safety
/// As for [`gesdd`].
pub unsafe fn gesvd<T: Copy>(
    f: GesvdFn<T>,
    (jobu, jobvt): (c_char, c_char),
    ((m, n, a, lda), s, (u, ldu, vt, ldvt), (work, lwork)): SvdArgs<'_, T>,
) -> c_int {
    let mut info: c_int = -77;
    let (a, s, u, vt, work) = (
        a.as_mut_ptr(),
        s.as_mut_ptr(),
        u.as_mut_ptr(),
        vt.as_mut_ptr(),
        work.as_mut_ptr(),
    );
    // SAFETY: forwarded caller contract.
    unsafe {
        f(
            &jobu, &jobvt, &m, &n, a, &lda, s, u, &ldu, vt, &ldvt, work, &lwork, &mut info,
        )
    };
    info
}

/// The Fortran signature of xPOTRS (`dpotrs_`, `spotrs_`), in LAPACK's argument order.
pub type PotrsFn<T> = unsafe extern "C" fn(
    *const c_char,
    *const c_int,
    *const c_int,
    *const T,
    *const c_int,
    *mut T,
    *const c_int,
    *mut c_int,
);

/// Calls xPOTRS `f` with `UPLO`, the factor (`N`, `A`, `LDA`) and the right-hand sides
/// (`NRHS`, `B`, `LDB`), grouped as LAPACK documents them; returns `INFO`.
///
/// # Safety
/// As for [`syevr`]: the dimensions passed fit the slices, unless the routine rejects them
/// before touching the arrays.
pub unsafe fn potrs<T: Copy>(
    f: PotrsFn<T>,
    uplo: c_char,
    (n, a, lda): (c_int, &[T], c_int),
    (nrhs, b, ldb): (c_int, &mut [T], c_int),
) -> c_int {
    let mut info: c_int = -77;
    // SAFETY: forwarded caller contract.
    unsafe {
        f(
            &uplo,
            &n,
            &nrhs,
            a.as_ptr(),
            &lda,
            b.as_mut_ptr(),
            &ldb,
            &mut info,
        )
    };
    info
}
