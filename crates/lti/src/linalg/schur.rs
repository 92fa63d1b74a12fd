//! Real Schur decomposition `A = Z T Zᵀ` with eigenvalue reordering.
//!
//! `T` is quasi-upper-triangular in LAPACK's standard form: 1×1 blocks for real eigenvalues,
//! 2×2 blocks `[[a, b], [c, a]]` with `b·c < 0` for complex-conjugate pairs.
//!
//! (Interim implementation on nalgebra's Schur; reordering follows.)

use crate::error::{LtiError, Result};
use crate::linalg::{Complex64, Mat};

/// A real Schur decomposition `A = Z T Zᵀ` (Z orthogonal, T quasi-upper-triangular).
#[derive(Debug, Clone)]
pub struct RealSchur {
    t: Mat,
    z: Mat,
}

impl RealSchur {
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

    /// Eigenvalues in the order they appear on the diagonal of `T`; a conjugate pair appears
    /// as `(a + bj, a − bj)` with `b > 0`.
    pub fn eigenvalues(&self) -> Vec<Complex64> {
        let t = &self.t;
        let n = t.nrows();
        let mut ev = Vec::with_capacity(n);
        let mut k = 0;
        while k < n {
            if k + 1 < n && t[(k + 1, k)] != 0.0 {
                let (a, b, c, d) = (t[(k, k)], t[(k, k + 1)], t[(k + 1, k)], t[(k + 1, k + 1)]);
                let tr = 0.5 * (a + d);
                let det = a * d - b * c;
                let disc = tr * tr - det;
                if disc < 0.0 {
                    let im = (-disc).sqrt();
                    ev.push(Complex64::new(tr, im));
                    ev.push(Complex64::new(tr, -im));
                } else {
                    let s = disc.sqrt();
                    ev.push(Complex64::new(tr + s, 0.0));
                    ev.push(Complex64::new(tr - s, 0.0));
                }
                k += 2;
            } else {
                ev.push(Complex64::new(t[(k, k)], 0.0));
                k += 1;
            }
        }
        ev
    }
}

/// Computes the real Schur decomposition of a square matrix.
///
/// # Errors
/// [`LtiError::NotSquare`], [`LtiError::NonFinite`], [`LtiError::NoConvergence`].
pub fn real_schur(a: &Mat) -> Result<RealSchur> {
    crate::linalg::check_square("A", a)?;
    crate::linalg::check_finite("A", a)?;
    let n = a.nrows();
    if n == 0 {
        return Ok(RealSchur {
            t: a.clone(),
            z: a.clone(),
        });
    }
    let s = nalgebra::linalg::Schur::try_new(a.clone(), f64::EPSILON, 100 * n.max(10)).ok_or(
        LtiError::NoConvergence {
            algorithm: "real Schur QR iteration".into(),
            iterations: 100 * n.max(10),
        },
    )?;
    let (z, t) = s.unpack();
    Ok(RealSchur { t, z })
}
