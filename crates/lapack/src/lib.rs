//! # pendulab-lapack — the BLAS/LAPACK symbols Clarabel's SDP path needs, in pure Rust
//!
//! Clarabel (the conic interior-point solver pendulab uses for LMIs) handles positive
//! semidefinite cones with dense linear algebra reached through the `blas`/`lapack` crates,
//! i.e. through the Fortran symbols `dgemm_`, `dsyevr_`, ... of whatever BLAS/LAPACK is
//! linked. pendulab may not require a system BLAS/LAPACK, so this crate *is* that library for
//! exactly the eleven routines Clarabel 0.11 calls, in double (`d`) and single (`s`) precision:
//!
//! | routine | operation | Clarabel's use (0.11, `src/algebra/dense/blas`) |
//! |---|---|---|
//! | `gemm`  | `C ← α op(A) op(B) + β C` | PSD-cone scaling products, `op` ∈ {N, T} |
//! | `gemv`  | `y ← α op(A) x + β y` | dense matrix–vector products, N and T |
//! | `symv`  | `y ← α A x + β y`, `A` symmetric | `U` and `L` triangles |
//! | `syrk`  | `C ← α A Aᵀ + β C` | `R Rᵀ` of the scaling, `U`, trans N/T |
//! | `syr2k` | `C ← α (A Bᵀ + B Aᵀ) + β C` | symmetric products, `U`, N |
//! | `potrf` | Cholesky `A = L Lᵀ` | factors of the primal/dual PSD blocks, `L` |
//! | `potrs` | solve with the Cholesky factor | PSD completion (chordal decomposition), `L` |
//! | `syevr` | symmetric eigenvalues / vectors | step length, `JOBZ` N/V, `RANGE` A, `U`, `ABSTOL = −1` |
//! | `gesdd` | SVD (divide and conquer driver) | Nesterov–Todd scaling, `JOBZ = S` |
//! | `gesvd` | SVD (QR driver) | alternative SVD engine, `JOBU = JOBVT = S` |
//! | `gesv`  | LU solve | dense LU solve |
//!
//! Clarabel first calls `syevr`, `gesdd` and `gesvd` with `LWORK = −1` (a workspace query)
//! and reads the size back from `WORK[0]`; every call uses tight leading dimensions. The shim
//! nevertheless implements each routine's full documented contract (all flag values, general
//! leading dimensions and increments), so any other caller gets LAPACK semantics too.
//!
//! ## Contracts honoured
//! - Signatures as `blas-sys`/`lapack-sys` declare them: every argument by pointer, flags as
//!   `c_char`, integers as `c_int`, no hidden string-length arguments.
//! - Workspace queries only report sizes; the triangle a symmetric routine was not told to use
//!   is never written; eigenvalues come out ascending, singular values descending.
//! - Failures are reported through `INFO` (`−i` for an invalid argument `i`, `> 0` for a
//!   computational failure such as a non-positive-definite minor); nothing panics across the
//!   `extern "C"` boundary (each body runs under `catch_unwind`).
//!
//! ## Use
//! The crate exists for its symbols; [`kernels`] also offers safe Rust entry points to the
//! same dense kernels (Cholesky, symmetric eigenvalues, SVD) for pendulab's own small dense
//! linear algebra. A crate that links
//! Clarabel with its `sdp`, `blas-src` and `lapack-src` features (no backend selected) must
//! mention this crate so that it is linked:
//!
//! ```
//! use pendulab_lapack as _;
//! ```
//!
//! Nothing else in the dependency tree may bring a real BLAS/LAPACK (the symbols would clash).
//!
//! ## Layout
//! - [`ffi`]: the exported symbols (the only `unsafe` code), argument validation;
//! - [`kernels`]: the safe Rust entry points;
//! - `blas`, `lapack` (private): the safe kernels, on nalgebra where nalgebra has the
//!   algorithm (symmetric eigenvectors, SVD of matrices with a side above 32);
//! - `jacobi` (private): the SVD of matrices with both sides ≤ 32 (all of Clarabel's PSD
//!   cones on pendulab's problems) by the workspace's one-sided Jacobi kernel
//!   (`pendulab_lti::linalg::jacobi`) on stack columns, allocation-free and more accurate
//!   than bidiagonal QR on graded matrices.

#![warn(missing_docs)]

mod blas;
pub mod ffi;
mod jacobi;
pub mod kernels;
mod lapack;

/// The two floating-point types the routines exist for (`f64` → `d…`, `f32` → `s…`); the
/// smallest normal number and the exact power-of-two scaling come from the Jacobi kernel's
/// [`JacobiReal`](pendulab_lti::linalg::jacobi::JacobiReal).
pub(crate) trait Real: pendulab_lti::linalg::jacobi::JacobiReal {
    /// `(small, big)`: for magnitudes in `[small, big]` the squares, and sums of up to 256
    /// of them, are normal numbers that keep full relative precision even after a further
    /// factor `ε²` (`small = √MIN_POSITIVE / ε`, `big = 1 / (16 √MIN_POSITIVE)`; about
    /// `[7e-139, 4e152]` in `f64`, `[9e-13, 5e17]` in `f32`). Kernels that work with squared
    /// magnitudes scale their input into this range first.
    fn square_safe_range() -> (Self, Self) {
        let r = Self::MIN_POSITIVE.sqrt();
        let sixteen: Self = nalgebra::convert(16.0);
        (r / Self::default_epsilon(), Self::one() / (sixteen * r))
    }
}
impl Real for f64 {}
impl Real for f32 {}
