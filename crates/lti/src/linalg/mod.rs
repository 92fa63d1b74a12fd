//! The one place that names the matrix library.
//!
//! pendulab works in `f64` throughout. LTI objects are dynamically sized ([`Mat`], [`Vector`]);
//! hot loops elsewhere in the workspace use fixed-size arrays. This module also holds the small
//! helpers every numerical routine needs: shape and finiteness checks (which produce the
//! workspace's typed errors), Frobenius norms, symmetrisation and eigenvalue sorting.
//!
//! The dense eigen-kernel that nalgebra does not provide lives in a submodule: [`schur`] (real
//! Schur form with reordering). [`svd`] is the workspace's SVD with singular vectors: nalgebra's,
//! checked by its defining residual, with a one-sided Jacobi fallback where nalgebra's result
//! is wrong; [`jacobi`] is that fallback's kernel, the workspace's one Jacobi SVD, which the
//! LAPACK shim (`pendulab-lapack`) runs on stack columns too.

pub(crate) mod dense;
pub mod jacobi;
pub mod schur;
pub(crate) mod small_eig;
pub mod svd;

use crate::error::LtiError;

/// Dense, dynamically sized real matrix (column-major).
pub type Mat = nalgebra::DMatrix<f64>;
/// Dense, dynamically sized real column vector.
pub type Vector = nalgebra::DVector<f64>;
/// Double-precision complex number (re, im).
pub type Complex64 = num_complex::Complex64;
/// Dense, dynamically sized complex matrix.
pub type CMat = nalgebra::DMatrix<Complex64>;

/// `n × n` identity matrix.
pub fn eye(n: usize) -> Mat {
    Mat::identity(n, n)
}

/// `rows × cols` zero matrix.
pub fn zeros(rows: usize, cols: usize) -> Mat {
    Mat::zeros(rows, cols)
}

/// Builds a matrix from row slices, e.g. `from_rows(&[&[1.0, 2.0], &[3.0, 4.0]])`.
///
/// # Errors
/// [`LtiError::InvalidArgument`] if the rows do not all have the same length.
pub fn from_rows(rows: &[&[f64]]) -> Result<Mat, LtiError> {
    let nrows = rows.len();
    let ncols = rows.first().map_or(0, |r| r.len());
    if let Some((i, r)) = rows.iter().enumerate().find(|(_, r)| r.len() != ncols) {
        return Err(LtiError::InvalidArgument(format!(
            "row {i} has {} entries, row 0 has {ncols}",
            r.len()
        )));
    }
    Ok(Mat::from_fn(nrows, ncols, |i, j| rows[i][j]))
}

/// Diagonal matrix with the given entries.
pub fn diag(entries: &[f64]) -> Mat {
    Mat::from_diagonal(&Vector::from_column_slice(entries))
}

/// The 1-norm `‖M‖₁ = max_j Σ_i |m_ij|` (the largest column sum of absolute values).
pub(crate) fn norm1(m: &Mat) -> f64 {
    (0..m.ncols())
        .map(|j| m.column(j).iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Frobenius norm `‖M‖_F = sqrt(Σ m_ij²)`.
pub fn fro(m: &Mat) -> f64 {
    m.norm()
}

/// Symmetric part `(M + Mᵀ)/2`.
pub fn symmetrize(m: &Mat) -> Mat {
    (m + m.transpose()) * 0.5
}

/// `M ← (M + Mᵀ)/2` for a square `m`, without allocating (each off-diagonal pair formed once;
/// the diagonal is kept, as `(m_ii + m_ii)/2 = m_ii` exactly).
pub(crate) fn symmetrize_in_place(m: &mut Mat) {
    let n = m.nrows();
    for j in 0..n {
        for i in j + 1..n {
            let v = 0.5 * (m[(i, j)] + m[(j, i)]);
            m[(i, j)] = v;
            m[(j, i)] = v;
        }
    }
}

/// Checks that every entry of `m` is finite.
///
/// # Errors
/// [`LtiError::NonFinite`] naming `what` and the first offending entry.
pub fn check_finite(what: &str, m: &Mat) -> Result<(), LtiError> {
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            let v = m[(i, j)];
            if !v.is_finite() {
                return Err(LtiError::NonFinite {
                    what: what.to_string(),
                    row: i,
                    col: j,
                    value: v,
                });
            }
        }
    }
    Ok(())
}

/// Checks that `m` is square.
///
/// # Errors
/// [`LtiError::NotSquare`] naming `what` and its shape.
pub fn check_square(what: &str, m: &Mat) -> Result<(), LtiError> {
    if m.nrows() != m.ncols() {
        return Err(LtiError::NotSquare {
            what: what.to_string(),
            rows: m.nrows(),
            cols: m.ncols(),
        });
    }
    Ok(())
}

/// Checks that `m` has shape `rows × cols`.
///
/// # Errors
/// [`LtiError::DimensionMismatch`] naming `what`, the expected and the actual shape.
pub fn check_shape(what: &str, m: &Mat, rows: usize, cols: usize) -> Result<(), LtiError> {
    if m.nrows() != rows || m.ncols() != cols {
        return Err(LtiError::DimensionMismatch {
            what: what.to_string(),
            expected: (rows, cols),
            found: (m.nrows(), m.ncols()),
        });
    }
    Ok(())
}

/// Checks that a square matrix is symmetric to a relative tolerance:
/// `‖M − Mᵀ‖_F ≤ tol · max(1, ‖M‖_F)`.
///
/// # Errors
/// [`LtiError::NotSymmetric`] naming `what` and the asymmetry found.
pub fn check_symmetric(what: &str, m: &Mat, tol: f64) -> Result<(), LtiError> {
    check_square(what, m)?;
    // ‖M − Mᵀ‖_F² = 2·Σ_{i<j} (m_ij − m_ji)², without forming Mᵀ or M − Mᵀ.
    let n = m.nrows();
    let mut sum = 0.0;
    for j in 0..n {
        for i in 0..j {
            let d = m[(i, j)] - m[(j, i)];
            sum += d * d;
        }
    }
    let asym = (2.0 * sum).sqrt();
    if asym > tol * fro(m).max(1.0) {
        return Err(LtiError::NotSymmetric {
            what: what.to_string(),
            asymmetry: asym,
        });
    }
    Ok(())
}

/// Sorts eigenvalues into the workspace's canonical order: by real part descending, then by
/// imaginary part descending (so a conjugate pair appears as `a + bj, a − bj`).
pub fn sort_eigenvalues(ev: &mut [Complex64]) {
    ev.sort_by(|x, y| {
        y.re.partial_cmp(&x.re)
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(y.im.partial_cmp(&x.im).unwrap_or(std::cmp::Ordering::Equal))
    });
}

/// Eigenvalues of a square real matrix, in the order of [`sort_eigenvalues`].
///
/// Computed from the real Schur form ([`schur::real_schur`]); conjugate pairs are exact
/// conjugates.
///
/// # Errors
/// [`LtiError::NotSquare`], [`LtiError::NonFinite`], or [`LtiError::NoConvergence`] if the QR
/// iteration fails.
pub fn eigenvalues(a: &Mat) -> Result<Vec<Complex64>, LtiError> {
    check_square("matrix", a)?;
    check_finite("matrix", a)?;
    if a.nrows() == 0 {
        return Ok(Vec::new());
    }
    let t = schur::schur_form(a)?;
    let mut ev = schur::quasi_triangular_eigenvalues(&t);
    sort_eigenvalues(&mut ev);
    Ok(ev)
}

/// Eigenvalues of a symmetric matrix (its symmetric part is used), ascending.
pub fn symmetric_eigenvalues(m: &Mat) -> Vec<f64> {
    if m.nrows() == 0 {
        return Vec::new();
    }
    let mut ev: Vec<f64> = symmetrize(m)
        .symmetric_eigenvalues()
        .iter()
        .copied()
        .collect();
    ev.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    ev
}

/// Popov–Belevitch–Hautus controllability margin of the mode `λ`:
/// `σ_min([A − λI, B]) / max(1, ‖[A, B]‖₂)`.
///
/// The mode `λ` (an eigenvalue of `A`) is uncontrollable exactly when `[A − λI, B]` loses
/// rank, so a margin near machine precision means "numerically uncontrollable"; the margin is
/// the relative distance (in the 2-norm) to the nearest pair in which `λ` is uncontrollable.
/// For observability of `(C, A)` call it with `(Aᵀ, Cᵀ)`.
pub fn pbh_margin(a: &Mat, b: &Mat, lambda: Complex64) -> f64 {
    let n = a.nrows();
    let m = b.ncols();
    if n == 0 {
        return f64::INFINITY;
    }
    let mut ab = Mat::zeros(n, n + m);
    ab.view_mut((0, 0), (n, n)).copy_from(a);
    ab.view_mut((0, n), (n, m)).copy_from(b);
    let scale = ab.clone().svd(false, false).singular_values.max().max(1.0);
    let mut mc = CMat::zeros(n, n + m);
    for i in 0..n {
        for j in 0..n + m {
            mc[(i, j)] = Complex64::new(ab[(i, j)], 0.0);
        }
        mc[(i, i)] -= lambda;
    }
    let sv = mc.svd(false, false).singular_values;
    sv.min() / scale
}

/// Deterministic pseudo-random test matrices for the crate's unit tests.
#[cfg(test)]
pub(crate) mod testing {
    use super::Mat;

    /// `r × c` matrix with entries uniform in `[−1, 1)` from the SplitMix64 sequence started
    /// at `seed` (filled column by column).
    pub(crate) fn splitmix_matrix(r: usize, c: usize, seed: u64) -> Mat {
        crate::random::SplitMix64::new(seed).matrix(r, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The asymmetry `check_symmetric` reports is ‖M − Mᵀ‖_F, formed here explicitly (the
    /// two sums differ only in rounding order: 1e-14 relative is a few hundred ulp of slack
    /// for 36 terms); a symmetric matrix passes with a zero tolerance.
    #[test]
    fn check_symmetric_reports_the_frobenius_asymmetry() {
        let m = Mat::from_fn(6, 6, |i, j| {
            ((i * 7 + j * 3) % 5) as f64 - 1.5 + 0.1 * i as f64
        });
        let want = fro(&(&m - m.transpose()));
        match check_symmetric("M", &m, 1e-12) {
            Err(LtiError::NotSymmetric { what, asymmetry }) => {
                assert_eq!(what, "M");
                assert!(
                    (asymmetry - want).abs() <= 1e-14 * want,
                    "{asymmetry} vs {want}"
                );
            }
            other => panic!("expected NotSymmetric, got {other:?}"),
        }
        let s = &m + m.transpose();
        assert!(check_symmetric("S", &s, 0.0).is_ok());
        // Just inside and just outside the tolerance.
        let mut t = s.clone();
        t[(0, 3)] += 1e-9;
        let rel = 1e-9 * std::f64::consts::SQRT_2 / fro(&t);
        assert!(check_symmetric("T", &t, 1.01 * rel).is_ok());
        assert!(check_symmetric("T", &t, 0.99 * rel).is_err());
    }
}
