//! Residuals and gains of the two equations at a given `X`: the public relative residuals
//! [`care_residual`] and [`dare_residual`], the residual matrices the Newton refinement corrects,
//! and the gains `K(X)` of either domain.

use super::data::{chol_solve, lower_solve};
use crate::equations::relative_residual;
use crate::linalg::{Mat, symmetrize};

/// CARE residual matrix and relative residual.
pub(crate) fn care_residual_full(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r_chol: &Mat,
    n: Option<&Mat>,
    x: &Mat,
) -> (Mat, f64) {
    let atx = a.transpose() * x;
    let xa = atx.transpose();
    let mut xbn = x * b;
    if let Some(nm) = n {
        xbn += nm;
    }
    let w = lower_solve(r_chol, &xbn.transpose()); // L⁻¹ (XB + N)ᵀ
    let g = w.transpose() * &w;
    let res = symmetrize(&(&atx + &xa - &g + q));
    let rel = relative_residual(&res, &[atx.norm(), xa.norm(), g.norm(), q.norm()]);
    (res, rel)
}

/// Relative residual of the CARE at `x` (see [`equations`](crate::equations)):
/// `‖AᵀX + XA − (XB+N)R⁻¹(BᵀX+Nᵀ) + Q‖_F` divided by the sum of the Frobenius norms of the
/// four terms.
pub fn care_residual(a: &Mat, b: &Mat, q: &Mat, r: &Mat, n: Option<&Mat>, x: &Mat) -> f64 {
    let atx = a.transpose() * x;
    let xa = x * a;
    let mut xbn = x * b;
    if let Some(nm) = n {
        xbn += nm;
    }
    // (XB + N) R⁻¹ (XB + N)ᵀ through a Cholesky factor of R when possible.
    let g = match r.clone().cholesky() {
        Some(ch) => &xbn * ch.solve(&xbn.transpose()),
        None => match r.clone().lu().solve(&xbn.transpose()) {
            Some(sol) => &xbn * sol,
            None => return f64::INFINITY,
        },
    };
    let res = &atx + &xa - &g + q;
    relative_residual(&res, &[atx.norm(), xa.norm(), g.norm(), q.norm()])
}

/// DARE residual matrix and relative residual; `None` if `BᵀXB + R` is singular.
pub(crate) fn dare_residual_full(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    x: &Mat,
) -> Option<(Mat, f64)> {
    let xa = x * a;
    let atxa = symmetrize(&(a.transpose() * &xa));
    let mut atxb = xa.transpose() * b;
    if let Some(nm) = n {
        atxb += nm;
    }
    let s = symmetrize(&(b.transpose() * x * b + r));
    let g = match s.clone().cholesky() {
        Some(ch) => &atxb * ch.solve(&atxb.transpose()),
        None => &atxb * s.lu().solve(&atxb.transpose())?,
    };
    let res = symmetrize(&(&atxa - x - &g + q));
    let rel = relative_residual(&res, &[atxa.norm(), x.norm(), g.norm(), q.norm()]);
    Some((res, rel))
}

/// Relative residual of the DARE at `x` (see [`equations`](crate::equations)):
/// `‖AᵀXA − X − (AᵀXB+N)(BᵀXB+R)⁻¹(BᵀXA+Nᵀ) + Q‖_F` divided by the sum of the Frobenius norms
/// of the four terms; `+∞` if `BᵀXB + R` is singular.
pub fn dare_residual(a: &Mat, b: &Mat, q: &Mat, r: &Mat, n: Option<&Mat>, x: &Mat) -> f64 {
    dare_residual_full(a, b, q, r, n, x).map_or(f64::INFINITY, |(_, rel)| rel)
}

/// CARE gain `K = R⁻¹(BᵀX + Nᵀ)`.
pub(crate) fn care_gain(l: &Mat, b: &Mat, n: Option<&Mat>, x: &Mat) -> Mat {
    let mut rhs = b.transpose() * x;
    if let Some(nm) = n {
        rhs += nm.transpose();
    }
    chol_solve(l, &rhs)
}

/// DARE gain `K = (BᵀXB + R)⁻¹(BᵀXA + Nᵀ)`; `None` if `BᵀXB + R` is singular.
pub(crate) fn dare_gain(a: &Mat, b: &Mat, r: &Mat, n: Option<&Mat>, x: &Mat) -> Option<Mat> {
    let xb = x * b;
    let s = symmetrize(&(b.transpose() * &xb + r));
    let mut rhs = xb.transpose() * a;
    if let Some(nm) = n {
        rhs += nm.transpose();
    }
    match s.clone().cholesky() {
        Some(ch) => Some(ch.solve(&rhs)),
        None => s.lu().solve(&rhs),
    }
}
