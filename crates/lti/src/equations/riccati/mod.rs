//! Algebraic Riccati equations, continuous ([`care`]) and discrete ([`dare`]), with cross term.
//!
//! Continuous (CARE):
//! `AᵀX + XA − (XB + N) R⁻¹ (BᵀX + Nᵀ) + Q = 0`, stabilising gain `K = R⁻¹(BᵀX + Nᵀ)`,
//! closed loop `A − BK` Hurwitz.
//!
//! Discrete (DARE):
//! `AᵀXA − X − (AᵀXB + N)(BᵀXB + R)⁻¹(BᵀXA + Nᵀ) + Q = 0`, stabilising gain
//! `K = (BᵀXB + R)⁻¹(BᵀXA + Nᵀ)`, closed loop `A − BK` Schur-stable.
//!
//! Both return a [`RiccatiSolution`] carrying the solution, the gain, the closed-loop poles and
//! the relative residual (module [`equations`](crate::equations) defines it).

mod care;
mod dare;
pub(crate) mod pencil;

pub use care::care;
pub use dare::dare;

use crate::error::{LtiError, Result};
use crate::linalg::{Complex64, Mat, check_finite, check_shape, check_square, check_symmetric};

/// The algorithm used to compute the stabilising solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RiccatiMethod {
    /// Choose automatically (the Schur method, falling back to the extended pencil when `R` is
    /// ill conditioned or the Schur method fails its accuracy check).
    #[default]
    Auto,
    /// Ordered real Schur form of the Hamiltonian matrix (CARE) or of the symplectic matrix
    /// (DARE, requires `A` invertible), Laub's method.
    Schur,
    /// Ordered generalised Schur (QZ) form of the extended `(2n + m)` pencil, which never
    /// inverts `R` (Van Dooren; SLICOT `SB02OD`).
    ExtendedPencil,
}

/// Options for [`care`] and [`dare`], with documented defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RiccatiOptions {
    /// Algorithm (default [`RiccatiMethod::Auto`]).
    pub method: RiccatiMethod,
    /// Scale the data before solving (default `true`); the solution is returned unscaled.
    pub scaling: bool,
    /// Maximum number of Newton (Kleinman / Hewer) refinement steps applied to the computed
    /// solution (default 1). A step is kept only if it lowers the relative residual.
    pub max_refinement_steps: usize,
}

impl Default for RiccatiOptions {
    fn default() -> Self {
        Self {
            method: RiccatiMethod::Auto,
            scaling: true,
            max_refinement_steps: 1,
        }
    }
}

/// Stabilising solution of an algebraic Riccati equation, with diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct RiccatiSolution {
    /// The stabilising solution `X` (symmetric).
    pub x: Mat,
    /// The optimal gain `K` (the control law is `u = −K x`).
    pub gain: Mat,
    /// Eigenvalues of `A − B K`, sorted as [`sort_eigenvalues`](crate::linalg::sort_eigenvalues).
    pub closed_loop_poles: Vec<Complex64>,
    /// Relative residual of the equation at `X`.
    pub residual: f64,
    /// The algorithm that produced `X`.
    pub method: RiccatiMethod,
    /// Newton refinement steps applied.
    pub refinement_steps: usize,
}

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
        let min = crate::linalg::symmetric_eigenvalues(r)
            .into_iter()
            .fold(f64::INFINITY, f64::min);
        if min.is_nan() || min <= r.norm() * f64::EPSILON * (m as f64) {
            return Err(LtiError::NotPositiveDefinite {
                what: "R".into(),
                min_eigenvalue: min,
            });
        }
    }
    Ok(RiccatiDims { n: nx, m })
}

/// Relative residual of the CARE at `x` (see [`equations`](crate::equations)).
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
        None => {
            &xbn * r.clone().pseudo_inverse(0.0).unwrap_or_else(|_| r.clone()) * xbn.transpose()
        }
    };
    let res = &atx + &xa - &g + q;
    super::relative_residual(&res, &[atx.norm(), xa.norm(), g.norm(), q.norm()])
}

/// Relative residual of the DARE at `x` (see [`equations`](crate::equations)).
pub fn dare_residual(a: &Mat, b: &Mat, q: &Mat, r: &Mat, n: Option<&Mat>, x: &Mat) -> f64 {
    let atxa = a.transpose() * x * a;
    let mut atxb = a.transpose() * x * b;
    if let Some(nm) = n {
        atxb += nm;
    }
    let s = b.transpose() * x * b + r;
    let g = match s.clone().cholesky() {
        Some(ch) => &atxb * ch.solve(&atxb.transpose()),
        None => match s.clone().lu().solve(&atxb.transpose()) {
            Some(sol) => &atxb * sol,
            None => return f64::INFINITY,
        },
    };
    let res = &atxa - x - &g + q;
    super::relative_residual(&res, &[atxa.norm(), x.norm(), g.norm(), q.norm()])
}
