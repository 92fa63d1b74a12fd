//! Small dense helpers on [`Mat`].

use crate::error::{LmiError, Result};
use pendulab_lti::Mat;

/// Symmetric part `(M + Mᵀ)/2`.
pub(crate) fn sym(m: &Mat) -> Mat {
    (m + m.transpose()) * 0.5
}

/// Checks that every entry is finite.
pub(crate) fn check_finite(what: &str, m: &Mat) -> Result<()> {
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            if !m[(i, j)].is_finite() {
                return Err(LmiError::NonFinite {
                    what: what.to_string(),
                    row: i,
                    col: j,
                    value: m[(i, j)],
                });
            }
        }
    }
    Ok(())
}

/// Checks the shape `rows × cols`.
pub(crate) fn check_shape(what: &str, m: &Mat, rows: usize, cols: usize) -> Result<()> {
    if m.shape() != (rows, cols) {
        return Err(LmiError::ShapeMismatch {
            op: what.to_string(),
            left: (rows, cols),
            right: m.shape(),
        });
    }
    Ok(())
}

/// The symmetric positive semidefinite square root `S = V √Λ Vᵀ` of a symmetric `M ⪰ 0`,
/// so that `S S = M` (used for `Q^½`, `R^½` in the LQ LMIs).
///
/// # Errors
/// [`LmiError::NotSquare`], [`LmiError::NonFinite`], [`LmiError::NotSymmetric`] (relative
/// asymmetry above 1e-10), [`LmiError::InvalidArgument`] if an eigenvalue is below
/// `−1e-12 · ‖M‖`.
pub(crate) fn psd_sqrt(what: &str, m: &Mat) -> Result<Mat> {
    if m.nrows() != m.ncols() {
        return Err(LmiError::NotSquare {
            what: what.to_string(),
            rows: m.nrows(),
            cols: m.ncols(),
        });
    }
    check_finite(what, m)?;
    let scale = m.norm().max(f64::MIN_POSITIVE);
    for j in 0..m.ncols() {
        for i in 0..j {
            let d = (m[(i, j)] - m[(j, i)]).abs();
            if d > 1e-10 * scale {
                return Err(LmiError::NotSymmetric {
                    what: what.to_string(),
                    row: i,
                    col: j,
                    difference: d,
                });
            }
        }
    }
    if m.nrows() == 0 {
        return Ok(m.clone());
    }
    let e = sym(m).symmetric_eigen();
    let min = e.eigenvalues.iter().copied().fold(f64::INFINITY, f64::min);
    if min < -1e-12 * scale {
        return Err(LmiError::InvalidArgument {
            what: what.to_string(),
            reason: format!("must be positive semidefinite (smallest eigenvalue {min:e})"),
        });
    }
    let d = Mat::from_diagonal(&e.eigenvalues.map(|v| v.max(0.0).sqrt()));
    Ok(sym(&(&e.eigenvectors * d * e.eigenvectors.transpose())))
}
