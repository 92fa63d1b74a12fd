//! Allocation-free singular value decomposition of small matrices by one-sided Jacobi
//! rotations, the path the SVD drivers take for Clarabel's PSD-cone scalings.
//!
//! The algorithm is the workspace's one Jacobi kernel,
//! [`pendulab_lti::linalg::jacobi::one_sided_jacobi`] (its documentation gives the method,
//! the stopping rule and the completion of rank-deficient factors); this module loads the
//! LAPACK-style column-major input into `R` stack columns of compile-time length
//! `R = max(m, n)` (so the sweeps run without bounds checks or allocation) and presents the
//! result as LAPACK's `U`, `s`, `Vᵀ`. For `m < n` the kernel runs on `Aᵀ = Ū Σ V̄ᵀ`, so that
//! `U = V̄` and `Vᵀ = Ūᵀ`.
//!
//! The drivers take this path for every matrix with both sides ≤ [`MAX_SIDE`], also where
//! nalgebra's bidiagonal QR would be a little cheaper: nalgebra's SVD can return wrong
//! singular values when vectors are requested (nalgebra issue #1172), while Jacobi computes
//! every singular value to high relative accuracy.

use crate::Real;
use pendulab_lti::linalg::jacobi::one_sided_jacobi;

/// Largest `max(m, n)` the Jacobi path takes (the working arrays live on the stack).
pub(crate) const MAX_SIDE: usize = 32;

/// The SVD `A = U diag(s) Vᵀ` (`k = min(m, n)` values, descending) computed by
/// [`jacobi_svd`], as views of its working arrays (handed to the caller's sink).
pub(crate) struct Factors<'a, T> {
    /// Rows of the working matrix (`max(m, n)`), the stride of `w` and `v`.
    rows: usize,
    /// Whether the method ran on `Aᵀ` (`m < n`).
    transposed: bool,
    /// `Ū` (`rows × k`, or `rows × rows` when completed; column-major, stride `rows`).
    w: &'a [T],
    /// `V̄` (`k × k`, stride `rows`); zeros unless accumulated.
    v: &'a [T],
    /// The singular values, descending.
    pub(crate) s: &'a [T],
}

impl<T: Real> Factors<'_, T> {
    /// `U(i, j)`, `0 ≤ i < m`, `0 ≤ j < k` (`< m` when `U` was completed).
    #[inline]
    pub(crate) fn u(&self, i: usize, j: usize) -> T {
        if self.transposed {
            self.v[i + j * self.rows]
        } else {
            self.w[i + j * self.rows]
        }
    }

    /// `Vᵀ(i, j)`, `0 ≤ i < k` (`< n` when `V` was completed), `0 ≤ j < n`.
    #[inline]
    pub(crate) fn vt(&self, i: usize, j: usize) -> T {
        if self.transposed {
            self.w[j + i * self.rows]
        } else {
            self.v[j + i * self.rows]
        }
    }
}

/// SVD of the `m × n` column-major array `a` (leading dimension `lda`), `1 ≤ m, n ≤`
/// [`MAX_SIDE`], by one-sided Jacobi (module documentation), handed to `sink`. `want_v` asks
/// for the accumulation of the right factor of the working matrix (needed for `Vᵀ` when
/// `m ≥ n`, for `U` when `m < n`). `full` extends the working matrix's left factor to a
/// square orthogonal one (LAPACK's `'A'` jobs: `U` is then `m × m` when `m > n`, `Vᵀ` is
/// `n × n` when `m < n`). False (and `sink` not called) if the input is not finite or the
/// sweeps did not converge.
pub(crate) fn jacobi_svd<T: Real>(
    (m, n): (usize, usize),
    (a, lda): (&[T], usize),
    (want_v, full): (bool, bool),
    sink: impl FnOnce(Factors<'_, T>),
) -> bool {
    // The working columns have exactly `max(m, n)` entries: a compile-time length lets the
    // compiler unroll and vectorise the dot products and rotations.
    macro_rules! dispatch {
        ($($size:literal)*) => {
            match m.max(n) {
                $($size => sweep::<T, $size>((m, n), (a, lda), (want_v, full), sink),)*
                _ => false,
            }
        };
    }
    dispatch!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32)
}

/// [`jacobi_svd`] for `max(m, n) = R`: loads `A` (or `Aᵀ`) into `R` columns of length `R`
/// on the stack and runs the shared kernel on them. The right factor is kept with `R` rows
/// too (the rows beyond `k` stay zero), so both rotations run on columns of the same fixed
/// length.
fn sweep<T: Real, const R: usize>(
    (m, n): (usize, usize),
    (a, lda): (&[T], usize),
    (want_v, full): (bool, bool),
    sink: impl FnOnce(Factors<'_, T>),
) -> bool {
    let transposed = m < n;
    let k = m.min(n);
    let mut w = [[T::zero(); R]; R];
    let mut v = [[T::zero(); R]; R];
    let mut s = [T::zero(); R];
    for j in 0..n {
        for i in 0..m {
            let x = a[i + j * lda];
            if transposed {
                w[i][j] = x;
            } else {
                w[j][i] = x;
            }
        }
    }
    let complete = if full { R } else { k };
    let v_cols = want_v.then_some(&mut v[..k]);
    if !one_sided_jacobi(&mut w[..], v_cols, &mut s[..k], complete) {
        return false;
    }
    sink(Factors {
        rows: R,
        transposed,
        w: w.as_flattened(),
        v: v.as_flattened(),
        s: &s[..k],
    });
    true
}
