//! Real Schur decomposition `A = Z T Zᵀ` with eigenvalue reordering.
//!
//! `T` is quasi-upper-triangular in LAPACK's **standard form**: 1×1 blocks for real
//! eigenvalues, 2×2 blocks `[[a, b], [c, a]]` with `b·c < 0` for complex-conjugate pairs
//! `a ± sqrt(−b c) j`.
//!
//! Algorithms (all re-implemented here):
//! - Householder reduction to upper Hessenberg form and accumulation of the reflectors
//!   (LAPACK `dgehd2`/`dorghr`; blocked with matrix–matrix trailing updates for larger
//!   matrices, `dgehrd`/`dlahr2` and compact-WY `dlarft`/`dlarfb`);
//! - Francis' implicit double-shift QR iteration with the Ahues–Tisseur deflation criterion and
//!   exceptional shifts (LAPACK `dlahqr`), 2×2 blocks standardised by `dlanv2`;
//! - reordering by **direct swapping** of adjacent 1×1/2×2 blocks (Bai & Demmel, "On swapping
//!   diagonal blocks in real Schur form", Linear Algebra Appl. 186, 1993; LAPACK
//!   `dlaexc`/`dtrexc`/`dtrsen`): the swap solves a small Sylvester equation, builds the
//!   orthogonal transformation from its solution and is **rejected** when it would perturb `T`
//!   by more than a small multiple of `ε‖block‖` (both the weak and the strong stability test
//!   of Bai–Demmel are applied).
//!
//! This file holds the public API ([`RealSchur`], [`real_schur`], [`schur_form`],
//! [`ordered_schur`], the block helpers) and the tests; the algorithms live beside it in
//! `schur/`: `hessenberg.rs` (the Hessenberg reduction), `francis.rs` (the QR iteration),
//! `swap.rs` (the adjacent block swap and the 2×2 standardisation) and `reorder.rs` (moving
//! blocks and selecting eigenvalues).

use crate::error::{LtiError, Result};
use crate::linalg::dense::lanv2;
use crate::linalg::{Complex64, Mat};

mod francis;
mod hessenberg;
mod reorder;
mod swap;

use francis::hqr;
use hessenberg::hessenberg;
use reorder::{reorder_quasi_triangular, trexc};
use swap::SwapRejected;

/// A real Schur decomposition `A = Z T Zᵀ` (Z orthogonal, T quasi-upper-triangular in
/// standard form).
#[derive(Debug, Clone)]
pub struct RealSchur {
    t: Mat,
    z: Mat,
}

/// A diagonal block of a quasi-triangular matrix: its first row/column and its size (1 or 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SchurBlock {
    /// First row (and column) of the block, 0-based.
    pub start: usize,
    /// Order of the block: 1 (real eigenvalue) or 2 (complex-conjugate pair).
    pub size: usize,
}

impl RealSchur {
    /// Computes the real Schur decomposition of `a` (same as [`real_schur`]).
    ///
    /// # Errors
    /// See [`real_schur`].
    pub fn new(a: &Mat) -> Result<Self> {
        real_schur(a)
    }

    /// The quasi-upper-triangular factor `T`.
    pub fn t(&self) -> &Mat {
        &self.t
    }

    /// The orthogonal factor `Z`.
    pub fn z(&self) -> &Mat {
        &self.z
    }

    /// Consumes the decomposition, returning `(T, Z)`.
    pub fn into_parts(self) -> (Mat, Mat) {
        (self.t, self.z)
    }

    /// The diagonal blocks of `T`, top to bottom.
    pub fn blocks(&self) -> Vec<SchurBlock> {
        blocks_of(&self.t)
    }

    /// Eigenvalues in the order they appear on the diagonal of `T`; a conjugate pair appears
    /// as `(a + bj, a − bj)` with `b > 0`.
    pub fn eigenvalues(&self) -> Vec<Complex64> {
        quasi_triangular_eigenvalues(&self.t)
    }

    /// Moves the diagonal block starting at row `from` to row `to` by a sequence of adjacent
    /// swaps (LAPACK `dtrexc`), updating `T` and `Z`. Returns the row where the block
    /// finally starts (it differs from `to` by one when a 2×2 block is moved past a 1×1 one).
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] for an index out of range; [`LtiError::Inaccurate`] when
    /// a swap is rejected by the stability test (the eigenvalues are too close to be
    /// separated reliably). Swaps completed before the rejection are kept, so `T`, `Z` remain
    /// a valid Schur decomposition.
    pub fn move_block(&mut self, from: usize, to: usize) -> Result<usize> {
        let n = self.t.nrows();
        if from >= n || to >= n {
            return Err(LtiError::InvalidArgument(format!(
                "Schur block index out of range: from {from}, to {to}, order {n}"
            )));
        }
        trexc(&mut self.t, Some(&mut self.z), from, to).map_err(SwapRejected::into_error)
    }

    /// Reorders the decomposition so that the eigenvalues for which `select` returns `true`
    /// appear in the leading block `T[0..k, 0..k]` (LAPACK `dtrsen` without condition
    /// estimates), keeping their relative order; returns `k`. Then the first `k` columns of
    /// `Z` span the invariant subspace of `A` belonging to the selected eigenvalues.
    ///
    /// `select` is called once per diagonal block, before any swap, with the block's
    /// eigenvalue (for a complex pair, the one with positive imaginary part); conjugate pairs
    /// are always kept together.
    ///
    /// # Errors
    /// [`LtiError::Inaccurate`] when a swap is rejected by the stability test.
    #[doc(alias = "ordschur")]
    pub fn reorder<F: FnMut(Complex64) -> bool>(&mut self, select: F) -> Result<usize> {
        reorder_quasi_triangular(&mut self.t, Some(&mut self.z), select)
            .map_err(SwapRejected::into_error)
    }
}

/// Computes the real Schur decomposition `A = Z T Zᵀ` of a square matrix (MATLAB `schur(A,
/// 'real')`), `T` in standard form.
///
/// # Errors
/// [`LtiError::NotSquare`], [`LtiError::NonFinite`], [`LtiError::NoConvergence`] if the QR
/// iteration needs more than `30·max(10, n)` iterations.
#[doc(alias = "schur")]
pub fn real_schur(a: &Mat) -> Result<RealSchur> {
    crate::linalg::check_square("A", a)?;
    crate::linalg::check_finite("A", a)?;
    let n = a.nrows();
    let mut t = a.clone();
    let mut z = Mat::zeros(n, n);
    hessenberg(t.as_mut_slice(), n, Some(z.as_mut_slice()));
    hqr(t.as_mut_slice(), n, Some(z.as_mut_slice()), true)?;
    Ok(RealSchur { t, z })
}

/// Computes `T` (not `Z`) of the real Schur decomposition, the cheapest route to the
/// eigenvalues (with [`quasi_triangular_eigenvalues`]).
///
/// # Errors
/// As [`real_schur`].
pub fn schur_form(a: &Mat) -> Result<Mat> {
    crate::linalg::check_square("A", a)?;
    crate::linalg::check_finite("A", a)?;
    let n = a.nrows();
    let mut t = a.clone();
    hessenberg(t.as_mut_slice(), n, None);
    hqr(t.as_mut_slice(), n, None, false)?;
    Ok(t)
}

/// Computes the ordered real Schur decomposition in one call: [`real_schur`] followed by
/// [`RealSchur::reorder`]. Returns the decomposition and the number `k` of selected
/// eigenvalues (the order of the leading block).
///
/// # Errors
/// As [`real_schur`] and [`RealSchur::reorder`].
#[doc(alias = "ordschur")]
pub fn ordered_schur<F: FnMut(Complex64) -> bool>(
    a: &Mat,
    select: F,
) -> Result<(RealSchur, usize)> {
    let mut s = real_schur(a)?;
    let k = s.reorder(select)?;
    Ok((s, k))
}

/// Diagonal blocks of a quasi-triangular matrix (a nonzero subdiagonal entry marks a 2×2
/// block).
pub fn blocks_of(t: &Mat) -> Vec<SchurBlock> {
    let n = t.nrows();
    let mut out = Vec::with_capacity(n);
    let mut k = 0;
    while k < n {
        let size = if k + 1 < n && t[(k + 1, k)] != 0.0 {
            2
        } else {
            1
        };
        out.push(SchurBlock { start: k, size });
        k += size;
    }
    out
}

/// Eigenvalue(s) of the diagonal block of `t` starting at `k` with order `size`.
fn block_eigenvalues(t: &Mat, k: usize, size: usize) -> [Complex64; 2] {
    if size == 1 {
        let v = Complex64::new(t[(k, k)], 0.0);
        return [v, v];
    }
    let (a, b, c, d) = (t[(k, k)], t[(k, k + 1)], t[(k + 1, k)], t[(k + 1, k + 1)]);
    if a == d && b * c < 0.0 {
        // Standard form: exact formula without cancellation.
        let im = b.abs().sqrt() * c.abs().sqrt();
        return [Complex64::new(a, im), Complex64::new(a, -im)];
    }
    let r = lanv2(a, b, c, d);
    [
        Complex64::new(r.rt1.0, r.rt1.1.abs()),
        Complex64::new(r.rt2.0, -r.rt1.1.abs()),
    ]
}

/// Eigenvalues of a quasi-upper-triangular matrix in diagonal order (pairs as `a ± bj`,
/// `b > 0`).
pub fn quasi_triangular_eigenvalues(t: &Mat) -> Vec<Complex64> {
    let mut ev = Vec::with_capacity(t.nrows());
    for blk in blocks_of(t) {
        let e = block_eigenvalues(t, blk.start, blk.size);
        ev.push(e[0]);
        if blk.size == 2 {
            ev.push(e[1]);
        }
    }
    ev
}

#[cfg(test)]
mod tests {
    use super::hessenberg::hessenberg_impl;
    use super::*;
    use crate::linalg::dense::EPS;

    /// [`crate::linalg::testing::splitmix_matrix`] (`n × n`) with column `j` scaled by
    /// `grade^j` (a graded matrix for `grade < 1`).
    fn test_matrix(n: usize, seed: u64, grade: f64) -> Mat {
        let mut a = crate::linalg::testing::splitmix_matrix(n, n, seed);
        for (j, mut col) in a.column_iter_mut().enumerate() {
            col *= grade.powi(j as i32);
        }
        a
    }

    /// Runs the reduction, blocked or not, and checks the defining properties: `H` upper
    /// Hessenberg, `Q` orthogonal, `QᵀAQ = H`. Householder reductions are backward stable with
    /// errors of order `c·n·ε‖A‖` (Higham, *Accuracy and Stability*, §19.3) with a modest
    /// constant; `10·n·ε` allows for it.
    fn reduce_and_check(a: &Mat, blocked: bool) -> (Mat, Mat) {
        let n = a.nrows();
        let mut h = a.clone();
        let mut q = Mat::zeros(n, n);
        hessenberg_impl(h.as_mut_slice(), n, Some(q.as_mut_slice()), blocked);
        for j in 0..n {
            for i in j + 2..n {
                assert_eq!(h[(i, j)], 0.0, "H not Hessenberg at ({i}, {j})");
            }
        }
        let tol = 10.0 * n as f64 * EPS;
        let orth = (q.transpose() * &q - Mat::identity(n, n)).norm();
        assert!(
            orth <= tol,
            "orthogonality error {orth:e} (blocked: {blocked})"
        );
        let rec = (q.transpose() * a * &q - &h).norm() / a.norm();
        assert!(rec <= tol, "similarity error {rec:e} (blocked: {blocked})");
        (h, q)
    }

    #[test]
    fn blocked_hessenberg_matches_unblocked() {
        // Orders around the switch points: one panel, several panels, a partial last block.
        for (n, seed, grade) in [(97, 1, 1.0), (130, 2, 1.0), (200, 3, 1.0), (160, 4, 0.9)] {
            let a = test_matrix(n, seed, grade);
            let (hb, qb) = reduce_and_check(&a, true);
            let (hu, qu) = reduce_and_check(&a, false);
            if grade != 1.0 {
                // Graded: tiny trailing columns make the reduction ill-determined (the
                // implicit-Q perturbation bound grows with 1/min subdiagonal), so only the
                // defining identities above are checked.
                continue;
            }
            // Both are Householder reductions with the same reflector sign convention, so by
            // the implicit-Q theorem they compute the same H and Q up to rounding; for these
            // unreduced random matrices the differences stay within a small multiple of the
            // backward error above (observed ≈ 1e-13 relative; 1e-10 leaves room for the
            // amplification by small subdiagonal entries).
            let dh = (&hb - &hu).norm() / a.norm();
            let dq = (&qb - &qu).norm() / (n as f64).sqrt();
            assert!(
                dh <= 1e-10,
                "n = {n}: blocked and unblocked H differ by {dh:e}"
            );
            assert!(
                dq <= 1e-10,
                "n = {n}: blocked and unblocked Q differ by {dq:e}"
            );
        }
    }

    #[test]
    fn schur_residual_on_random_and_graded_matrices() {
        // Defining identities of the whole decomposition through the blocked reduction:
        // A = Z T Zᵀ, Z orthogonal, T quasi-triangular; bound as above (backward stability of
        // the Householder reduction and the QR iteration, c·n·ε with c ≤ 10).
        for (n, seed, grade) in [(150, 5, 1.0), (200, 6, 0.97), (120, 7, 0.8)] {
            let a = test_matrix(n, seed, grade);
            let s = real_schur(&a).unwrap();
            let (t, z) = (s.t(), s.z());
            let tol = 10.0 * n as f64 * EPS;
            let rec = (z * t * z.transpose() - &a).norm() / a.norm();
            assert!(rec <= tol, "n = {n}: reconstruction error {rec:e}");
            let orth = (z.transpose() * z - Mat::identity(n, n)).norm();
            assert!(orth <= tol, "n = {n}: orthogonality error {orth:e}");
            for j in 0..n {
                for i in j + 2..n {
                    assert_eq!(t[(i, j)], 0.0, "T not quasi-triangular at ({i}, {j})");
                }
                if j + 2 < n {
                    assert!(
                        t[(j + 1, j)] == 0.0 || t[(j + 2, j + 1)] == 0.0,
                        "adjacent 2×2 blocks overlap at {j}"
                    );
                }
            }
        }
    }
}
