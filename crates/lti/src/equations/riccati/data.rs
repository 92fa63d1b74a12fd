//! Steps 1–3 of the solve (see the [module documentation](super)): validation of the data,
//! removal of the cross term with a Cholesky factor of `R`, and the scale factor of the
//! balancing `X = s Y`.

use crate::error::{LtiError, Result};
use crate::linalg::{Mat, check_finite, check_shape, check_square, check_symmetric, symmetrize};

/// Shapes `(n, m)` of validated Riccati data.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RiccatiDims {
    pub n: usize,
    pub m: usize,
}

/// Validates Riccati data: `A` `n×n`, `B` `n×m`, `Q` `n×n` symmetric, `R` `m×m` symmetric
/// (positive definite if `require_r_pd`), `N` `n×m`; all finite.
pub(crate) fn validate(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    require_r_pd: bool,
) -> Result<RiccatiDims> {
    check_square("A", a)?;
    let nx = a.nrows();
    check_shape("B", b, nx, b.ncols())?;
    let m = b.ncols();
    check_shape("Q", q, nx, nx)?;
    check_shape("R", r, m, m)?;
    for (name, mat) in [("A", a), ("B", b), ("Q", q), ("R", r)] {
        check_finite(name, mat)?;
    }
    if let Some(nm) = n {
        check_shape("N", nm, nx, m)?;
        check_finite("N", nm)?;
    }
    // Symmetry to a few hundred ulps of the matrix's own size: data typed in by hand or
    // computed as MᵀM passes, a genuinely non-symmetric weight does not.
    check_symmetric("Q", q, 1e-12)?;
    check_symmetric("R", r, 1e-12)?;
    if require_r_pd && m > 0 {
        // A 1×1 R is its own eigenvalue (no eigensolver call on the single-input fast path).
        let min = if m == 1 {
            r[(0, 0)]
        } else {
            crate::linalg::symmetric_eigenvalues(r)
                .into_iter()
                .fold(f64::INFINITY, f64::min)
        };
        if min.is_nan() || min <= r.norm() * f64::EPSILON * (m as f64) {
            return Err(LtiError::NotPositiveDefinite {
                what: "R".into(),
                min_eigenvalue: min,
            });
        }
    }
    Ok(RiccatiDims { n: nx, m })
}

/// Riccati data with the cross term removed and `R` factored (step 2 of the module docs).
pub(crate) struct Reduced {
    /// Cholesky factor `L` of `R = L Lᵀ`.
    pub l: Mat,
    /// `Ã = A − B R⁻¹ Nᵀ`.
    pub a: Mat,
    /// `G = B R⁻¹ Bᵀ` (symmetric positive semidefinite).
    pub g: Mat,
    /// `Q̃ = Q − N R⁻¹ Nᵀ` (symmetric).
    pub q: Mat,
}

/// Lower Cholesky factor of a symmetric positive definite matrix, or
/// [`LtiError::NotPositiveDefinite`] with its smallest eigenvalue.
pub(crate) fn cholesky_lower(what: &str, r: &Mat) -> Result<Mat> {
    match r.clone().cholesky() {
        Some(c) => Ok(c.l()),
        None => Err(LtiError::NotPositiveDefinite {
            what: what.into(),
            min_eigenvalue: crate::linalg::symmetric_eigenvalues(r)
                .first()
                .copied()
                .unwrap_or(f64::NAN),
        }),
    }
}

/// Solves `L Y = M` for lower-triangular `L`.
pub(super) fn lower_solve(l: &Mat, m: &Mat) -> Mat {
    let mut y = m.clone();
    let k = l.nrows();
    for j in 0..y.ncols() {
        for i in 0..k {
            let mut v = y[(i, j)];
            for p in 0..i {
                v -= l[(i, p)] * y[(p, j)];
            }
            y[(i, j)] = v / l[(i, i)];
        }
    }
    y
}

/// Solves `R Y = M` with `R = L Lᵀ`.
pub(crate) fn chol_solve(l: &Mat, m: &Mat) -> Mat {
    let y = lower_solve(l, m);
    // Lᵀ Z = Y.
    let k = l.nrows();
    let mut z = y;
    for j in 0..z.ncols() {
        for i in (0..k).rev() {
            let mut v = z[(i, j)];
            for p in i + 1..k {
                v -= l[(p, i)] * z[(p, j)];
            }
            z[(i, j)] = v / l[(i, i)];
        }
    }
    z
}

/// Step 2: removes the cross term and forms `G`.
pub(crate) fn reduce(a: &Mat, b: &Mat, q: &Mat, r: &Mat, n: Option<&Mat>) -> Result<Reduced> {
    let l = cholesky_lower("R", r)?;
    let w = lower_solve(&l, &b.transpose()); // L⁻¹ Bᵀ
    let g = symmetrize(&(w.transpose() * &w));
    let (ar, qr) = match n {
        Some(nm) => {
            let v = lower_solve(&l, &nm.transpose()); // L⁻¹ Nᵀ
            (
                a - w.transpose() * &v,
                symmetrize(&(q - v.transpose() * &v)),
            )
        }
        None => (a.clone(), symmetrize(q)),
    };
    Ok(Reduced { l, a: ar, g, q: qr })
}

/// Scale factor of step 3.
pub(crate) fn scale_factor(red: &Reduced, scaling: bool) -> f64 {
    let qn = red.q.norm();
    let gn = red.g.norm();
    if scaling && qn > 0.0 && gn > 0.0 && (qn / gn).is_finite() {
        (qn / gn).sqrt()
    } else {
        1.0
    }
}
