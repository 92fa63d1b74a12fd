//! Reading the Fortran arguments: by-reference scalars, dimensions, flags, leading dimensions
//! and increments validated in the reference implementation's order, arrays borrowed as slices
//! of the length the contract implies, and the wrappers that run a body inside `catch_unwind`
//! and report `INFO`.
//!
//! Neighbours: [`super`] exports the symbols; `blas_bodies.rs`, `lapack_bodies.rs` and
//! `svd_bodies.rs` hold the generic bodies that read their arguments with these helpers.

use super::INTERNAL_ERROR;
use crate::Real;
use crate::blas::{Trans, Uplo};
use core::ffi::{c_char, c_int};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// A reason to stop: `Err(i)` means "argument `i` (1-based) is invalid".
type Check = Result<(), c_int>;

/// Reads a by-reference scalar argument.
///
/// # Safety
/// `p` must be null or point to a readable `T`.
pub(super) unsafe fn read<T: Copy>(p: *const T, position: c_int) -> Result<T, c_int> {
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
pub(super) unsafe fn dim(p: *const c_int, position: c_int) -> Result<usize, c_int> {
    let v = unsafe { read(p, position)? };
    usize::try_from(v).map_err(|_| position)
}

/// Reads a flag argument (`'N'`, `'T'`, ...) as an upper-case ASCII letter.
///
/// # Safety
/// As [`read`].
pub(super) unsafe fn flag(p: *const c_char, position: c_int) -> Result<u8, c_int> {
    Ok((unsafe { read(p, position)? } as u8).to_ascii_uppercase())
}

/// Reads a leading dimension and checks `ld ≥ max(1, rows)`.
///
/// # Safety
/// As [`read`].
pub(super) unsafe fn leading(
    p: *const c_int,
    rows: usize,
    position: c_int,
) -> Result<usize, c_int> {
    let ld = unsafe { read(p, position)? };
    match usize::try_from(ld) {
        Ok(ld) if ld >= rows.max(1) => Ok(ld),
        _ => Err(position),
    }
}

pub(super) fn trans_flag(f: u8, position: c_int) -> Result<Trans, c_int> {
    match f {
        b'N' => Ok(Trans::No),
        b'T' | b'C' => Ok(Trans::Yes),
        _ => Err(position),
    }
}

pub(super) fn uplo_flag(f: u8, position: c_int) -> Result<Uplo, c_int> {
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
pub(super) unsafe fn increment(p: *const c_int, position: c_int) -> Result<isize, c_int> {
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
pub(super) unsafe fn slice<'a, T>(
    p: *const T,
    len: usize,
    position: c_int,
) -> Result<&'a [T], c_int> {
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
pub(super) unsafe fn slice_mut<'a, T>(
    p: *mut T,
    len: usize,
    position: c_int,
) -> Result<&'a mut [T], c_int> {
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
pub(super) fn run_blas(body: impl FnOnce() -> Check) {
    let _ = catch_unwind(AssertUnwindSafe(body));
}

/// Runs a LAPACK body and stores its `INFO` (`−i` for an invalid argument `i`).
///
/// # Safety
/// `info` must be null or point to a writable `c_int`.
pub(super) unsafe fn run_lapack(info: *mut c_int, body: impl FnOnce() -> Result<c_int, c_int>) {
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
pub(super) fn report_size<T: Real>(work: &mut [T], size: usize) {
    if let Some(w) = work.first_mut() {
        *w = nalgebra::convert(size as f64);
    }
}

/// Writes column-major `m` into the `rows × cols` leading block of an array with leading
/// dimension `ld`.
pub(super) fn store<T: Real>(m: &nalgebra::DMatrix<T>, out: &mut [T], ld: usize) {
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            out[i + j * ld] = m[(i, j)];
        }
    }
}
