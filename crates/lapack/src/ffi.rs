//! The Fortran-ABI symbols. This is the only module (with its submodules in `ffi/`) with
//! `unsafe` code.
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
//!
//! This file holds the exported `d` (f64) and `s` (f32) symbols; beside it in `ffi/`:
//! `args.rs` (reading and validating the arguments, running a body), `blas_bodies.rs`,
//! `lapack_bodies.rs` and `svd_bodies.rs` (the generic bodies the symbols call).

use core::ffi::{c_char, c_int};

mod args;
mod blas_bodies;
mod lapack_bodies;
mod svd_bodies;

use blas_bodies::{ScaledArgs, gemm_impl, gemv_impl, symv_impl, syr2k_impl, syrk_impl};
use lapack_bodies::{gesv_impl, potrf_impl, potrs_impl, syevr_impl};
use svd_bodies::{SvdArgs, gesdd_impl, gesvd_impl};

/// `INFO` value reported when the shim itself failed internally (a caught panic). Positive,
/// so callers treat it as a computational failure, and far outside LAPACK's own range.
pub const INTERNAL_ERROR: c_int = c_int::MAX;

// The exported symbols: one `d` (f64) and one `s` (f32) version of each routine.

/// One SVD driver's `extern "C"` entry point (xGESDD, xGESVD): the job flags, the argument
/// list the drivers share (`M` … `LWORK`, see `svd_bodies::SvdArgs`), the driver's own
/// trailing arguments, then `INFO`; it forwards to the driver's generic body.
macro_rules! svd_entry {
    (@jobs $job:ident) => { $job };
    (@jobs $($job:ident),+) => { ($($job),+) };
    ($(#[$doc:meta])* $t:ty, $name:ident, $body:ident, ($($job:ident),+ $(,)?), ($($extra:ident: $et:ty),*)) => {
        $(#[$doc])*
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            $($job: *const c_char,)+
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
            $($extra: $et,)*
            info: *mut c_int,
        ) {
            let args = SvdArgs { m, n, a, lda, s, u, ldu, vt, ldvt, work, lwork };
            // SAFETY: forwarded caller contract.
            unsafe { $body::<$t>(svd_entry!(@jobs $($job),+), args, info) }
        }
    };
}

/// One `extern "C"` entry point of xGEMM, xSYR2K, xGEMV or xSYMV: the routine's leading
/// arguments, then the trailing ones of the form `ALPHA, A, LDA, B, LDB, BETA, C, LDC` (see
/// `blas_bodies::ScaledArgs`; `X, INCX, Y, INCY` in place of `B, LDB, C, LDC` for the
/// matrix–vector routines); it forwards to the routine's generic body.
macro_rules! scaled_entry {
    ($(#[$doc:meta])* $t:ty, $name:ident, $body:ident, ($($lead:ident: $lt:ty),+ $(,)?),
     ($b:ident, $ldb:ident, $c:ident, $ldc:ident)) => {
        $(#[$doc])*
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            $($lead: $lt,)+
            alpha: *const $t,
            a: *const $t,
            lda: *const c_int,
            $b: *const $t,
            $ldb: *const c_int,
            beta: *const $t,
            $c: *mut $t,
            $ldc: *const c_int,
        ) {
            let args = ScaledArgs { alpha, a, lda, b: $b, ldb: $ldb, beta, c: $c, ldc: $ldc };
            // SAFETY: forwarded caller contract.
            unsafe { $body::<$t>(($($lead),+), args) }
        }
    };
}

macro_rules! symbols {
    ($t:ty, $p:literal,
     $gemm:ident, $gemv:ident, $symv:ident, $syrk:ident, $syr2k:ident,
     $potrf:ident, $potrs:ident, $syevr:ident, $gesdd:ident, $gesvd:ident, $gesv:ident) => {
        scaled_entry!(
            #[doc = concat!("BLAS `", $p, "GEMM`: `C ← α op(A) op(B) + β C` (`C` is `m × n`).")]
            ///
            /// `op(X)` is `X` for `'N'`, `Xᵀ` for `'T'`/`'C'`. `β = 0` does not read `C`;
            /// `α = 0` does not read `A`, `B`. An invalid argument makes the call a no-op.
            ///
            /// # Safety
            /// Fortran contract: every pointer refers to a valid object of the documented size
            /// (`A`: `lda × ka`, `B`: `ldb × kb`, `C`: `ldc × n`); `C` does not alias `A` or `B`.
            $t, $gemm, gemm_impl,
            (transa: *const c_char, transb: *const c_char, m: *const c_int, n: *const c_int,
             k: *const c_int),
            (b, ldb, c, ldc)
        );

        scaled_entry!(
            #[doc = concat!("BLAS `", $p, "GEMV`: `y ← α op(A) x + β y` (`A` is `m × n`).")]
            ///
            /// Increments may be negative (the vector is then traversed from its end) but not
            /// zero. `β = 0` does not read `y`. An invalid argument makes the call a no-op.
            ///
            /// # Safety
            /// Fortran contract: `A` is `lda × n`, `x`/`y` hold `1 + (len − 1)|inc|` elements;
            /// `y` does not alias `A` or `x`.
            $t, $gemv, gemv_impl,
            (trans: *const c_char, m: *const c_int, n: *const c_int),
            (x, incx, y, incy)
        );

        scaled_entry!(
            #[doc = concat!("BLAS `", $p, "SYMV`: `y ← α A x + β y`, `A` symmetric given by its `uplo` triangle.")]
            ///
            /// Only the named triangle of `A` is read. An invalid argument makes the call a no-op.
            ///
            /// # Safety
            /// Fortran contract as for the `GEMV` routine with `A` `lda × n`.
            $t, $symv, symv_impl,
            (uplo: *const c_char, n: *const c_int),
            (x, incx, y, incy)
        );

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

        scaled_entry!(
            #[doc = concat!("BLAS `", $p, "SYR2K`: `C ← α (A Bᵀ + B Aᵀ) + β C` (`'N'`) or `C ← α (Aᵀ B + Bᵀ A) + β C`.")]
            ///
            /// Only the `uplo` triangle of `C` is read and written. An invalid argument makes the
            /// call a no-op.
            ///
            /// # Safety
            /// Fortran contract: `A`, `B` are `ld × k` (`'N'`) or `ld × n`, `C` is `ldc × n`, no aliasing.
            $t, $syr2k, syr2k_impl,
            (uplo: *const c_char, trans: *const c_char, n: *const c_int, k: *const c_int),
            (b, ldb, c, ldc)
        );

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

        svd_entry!(
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
            $t, $gesdd, gesdd_impl, (jobz), (_iwork: *mut c_int)
        );

        svd_entry!(
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
            $t, $gesvd, gesvd_impl, (jobu, jobvt), ()
        );

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
