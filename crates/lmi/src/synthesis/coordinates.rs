//! Coordinates in which the output-feedback LMIs of [`super::hinf_lmi`] and
//! [`super::h2_output_feedback_lmi`] are well conditioned.
//!
//! Both syntheses are invariant under a change of the plant's state coordinates `x = T x̃`
//! and under scalings of the control and measurement signals `u = D_u ũ`, `ỹ = D_y y`: the
//! plant `(T⁻¹AT, T⁻¹B₁, T⁻¹B₂D_u; C₁T, D₁₁, D₁₂D_u; D_yC₂T, D_yD₂₁, D_yD₂₂D_u)` has the same
//! closed loops, a controller `K̃` of it being `K = D_u K̃ D_y` of the original plant. In the
//! H∞ LMIs a common scaling `s` of `w` and `z` (`B̃₁ = sB₁`, `C̃₁ = sC₁`, `D̃₁₁ = s²D₁₁`,
//! `D̃₁₂ = sD₁₂`, `D̃₂₁ = D₂₁s`) multiplies every closed-loop gain and so the level by `s²`
//! and leaves the LMI variables unchanged (a congruence by `diag(I, s⁻¹I, s⁻¹I)`); it is used
//! to bring `γ` near 1. The LMI variables map back as `R = T R̃ Tᵀ`, `S = T⁻ᵀ S̃ T⁻¹` (the H2
//! LMIs' `X` like `R`, `Y` like `S`) and the closed-loop Lyapunov matrix as
//! `X_cl = diag(T⁻ᵀ, I) X̃_cl diag(T⁻¹, I)`.
//!
//! Two transforms are used:
//!
//! - [`Coordinates::equilibrated`], from the plant data alone: the diagonal state scaling
//!   that balances the rows and columns of `[A B; C 0]` (Osborne's iteration, as LAPACK's
//!   `dgebal` and MATLAB's `ssbal`/`prescale` do, with powers of 2 so that the scaling is
//!   exact), then unit-norm columns of `[B₂; D₁₂]` and rows of `[C₂ D₂₁]`;
//! - [`Coordinates::balancing`], from a solution `(R, S)`: the square-root balancing of the
//!   pair (Laub et al., "Computation of system balancing transformations and other
//!   applications of simultaneous diagonalization algorithms", IEEE TAC 32(2), 1987):
//!   with `R = L_R L_Rᵀ`, `S = L_S L_Sᵀ` and `L_SᵀL_R = UΣVᵀ`, `T = L_R V Σ^{-1/2}` gives
//!   `T⁻¹RT⁻ᵀ = TᵀST = Σ`, the square roots of the eigenvalues of `RS` (all ≥ 1 by the coupling
//!   `[R I; I S] ⪰ 0`). Near the optimal level the certificate degenerates: `I − RS`
//!   becomes singular (an eigenvalue of `RS` tends to 1) with `R` tending to a singular and
//!   `S` to an unbounded matrix along one direction (γ_opt set by `X∞` growing without
//!   bound, `R = γX∞⁻¹`) — eigenvalues of `R` and `S` spread over many decades, which an
//!   interior-point method in double precision cannot follow. In the balanced coordinates of
//!   a nearly optimal `(R, S)` that direction has `R̃ = S̃ ≈ 1`, so the next solve starts
//!   from well-scaled variables and can approach the optimum a few decades closer
//!   (Gahinet & Apkarian 1994, §5, note the same degeneration of `R`, `S` near `γ_opt`).

use crate::error::{LmiError, Result};
use pendulab_lti::design::StandardPlant;
use pendulab_lti::{Continuous, Mat, StateSpace};

/// A change of coordinates of a standard plant (module documentation): `x = T x̃`,
/// `w = w̃ / s`, `z̃ = s z` (so `γ̃ = s²γ`), `u = D_u ũ`, `ỹ = D_y y`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Coordinates {
    /// `T`.
    pub t: Mat,
    /// `T⁻¹`.
    pub t_inv: Mat,
    /// `s` (the level scales by `s²`).
    pub s: f64,
    /// Diagonal of `D_u`.
    pub du: Vec<f64>,
    /// Diagonal of `D_y`.
    pub dy: Vec<f64>,
}

/// Nearest power of 2 (an exact scaling factor).
fn pow2(v: f64) -> f64 {
    if v.is_finite() && v > 0.0 {
        2f64.powi(v.log2().round() as i32)
    } else {
        1.0
    }
}

impl Coordinates {
    /// The identity transform of a plant with `n` states, `ncon` controls and `nmeas`
    /// measurements.
    pub fn identity(n: usize, ncon: usize, nmeas: usize) -> Self {
        Self {
            t: Mat::identity(n, n),
            t_inv: Mat::identity(n, n),
            s: 1.0,
            du: vec![1.0; ncon],
            dy: vec![1.0; nmeas],
        }
    }

    /// The equilibrating transform of `plant` from its data (module documentation).
    pub fn equilibrated(plant: &StandardPlant) -> Self {
        let n = plant.nx();
        let sys = plant.system();
        let (a, b, c) = (sys.a(), sys.b(), sys.c());
        // Osborne's iteration on the state rows and columns of [A B; C 0] (2-norms without
        // the diagonal), factors of 2.
        let mut d = vec![1.0; n];
        for _ in 0..100 {
            let mut changed = false;
            for i in 0..n {
                let mut row = 0.0;
                let mut col = 0.0;
                for j in 0..n {
                    if j != i {
                        row += (a[(i, j)] * d[j] / d[i]).powi(2);
                        col += (a[(j, i)] * d[i] / d[j]).powi(2);
                    }
                }
                row += b.row(i).norm_squared() / (d[i] * d[i]);
                col += c.column(i).norm_squared() * d[i] * d[i];
                if row == 0.0 || col == 0.0 {
                    continue;
                }
                // New d_i·f balances: row/f² = col·f².
                let f = pow2((row / col).powf(0.25));
                if f != 1.0 && ((row / (f * f) + col * f * f) < 0.95 * (row + col)) {
                    d[i] *= f;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        let mut out = Self::identity(n, plant.ncon(), plant.nmeas());
        for i in 0..n {
            out.t[(i, i)] = d[i];
            out.t_inv[(i, i)] = 1.0 / d[i];
        }
        // Unit columns of [B₂; D₁₂] and rows of [C₂ D₂₁] in the scaled state.
        let (b2, d12, c2, d21) = (plant.b2(), plant.d12(), plant.c2(), plant.d21());
        for k in 0..plant.ncon() {
            let v = (0..n).map(|i| (b2[(i, k)] / d[i]).powi(2)).sum::<f64>()
                + d12.column(k).norm_squared();
            out.du[k] = pow2(1.0 / v.sqrt());
        }
        for k in 0..plant.nmeas() {
            let v = (0..n).map(|i| (c2[(k, i)] * d[i]).powi(2)).sum::<f64>()
                + d21.row(k).norm_squared();
            out.dy[k] = pow2(1.0 / v.sqrt());
        }
        out
    }

    /// These coordinates followed by the balancing transform of `(R̃, S̃)`, a solution in
    /// them (module documentation), and the level scaling `s² = 1/γ` for the level `γ` (of
    /// the original plant) the solution belongs to. None when `R̃` or `S̃` is not positive
    /// definite to working precision or the transform is not finite.
    pub fn balancing(&self, r: &Mat, s: &Mat, gamma: f64) -> Option<Self> {
        let lr = crate::linalg::sym(r).cholesky()?.l();
        let ls = crate::linalg::sym(s).cholesky()?.l();
        let svd = pendulab_lti::linalg::svd::svd(&(ls.transpose() * &lr));
        let n = r.nrows();
        let sigma = &svd.singular_values;
        if !sigma.iter().all(|v| v.is_finite() && *v > 0.0) {
            return None;
        }
        let mut t = lr * svd.v_t.transpose();
        let mut ti = svd.u.transpose() * ls.transpose();
        for i in 0..n {
            let q = sigma[i].sqrt();
            t.column_mut(i).unscale_mut(q);
            ti.row_mut(i).unscale_mut(q);
        }
        let t = &self.t * t;
        let t_inv = ti * &self.t_inv;
        if !(t.iter().chain(t_inv.iter()).all(|v| v.is_finite())
            && gamma.is_finite()
            && gamma > 0.0)
        {
            return None;
        }
        Some(Self {
            t,
            t_inv,
            s: 1.0 / gamma.sqrt(),
            du: self.du.clone(),
            dy: self.dy.clone(),
        })
    }

    /// The plant in these coordinates.
    ///
    /// # Errors
    /// [`LmiError::Lti`] if the transformed data are not a valid plant (not finite).
    pub fn plant(&self, plant: &StandardPlant) -> Result<StandardPlant> {
        let du = Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(&self.du));
        let dy = Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(&self.dy));
        let s = self.s;
        Ok(StandardPlant::from_blocks(
            &(&self.t_inv * plant.a() * &self.t),
            &(&self.t_inv * plant.b1() * s),
            &(&self.t_inv * plant.b2() * &du),
            &(plant.c1() * &self.t * s),
            &(&dy * plant.c2() * &self.t),
            &(plant.d11() * (s * s)),
            &(plant.d12() * &du * s),
            &(&dy * plant.d21() * s),
            &(&dy * plant.d22() * &du),
        )?)
    }

    /// The level of the original plant for a level `γ̃` in these coordinates: `γ̃ / s²`.
    pub fn gamma(&self, gamma: f64) -> f64 {
        gamma / (self.s * self.s)
    }

    /// The level in these coordinates for a level `γ` of the original plant: `s²γ`.
    pub fn scaled_gamma(&self, gamma: f64) -> f64 {
        gamma * self.s * self.s
    }

    /// A controller of the transformed plant as one of the original plant:
    /// `K = (A_k, B_kD_y, D_uC_k, D_uD_kD_y)`.
    ///
    /// # Errors
    /// [`LmiError::Lti`] for a controller of the wrong size.
    pub fn controller(&self, k: &StateSpace<Continuous>) -> Result<StateSpace<Continuous>> {
        let du = Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(&self.du));
        let dy = Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(&self.dy));
        if k.nu() != self.dy.len() || k.ny() != self.du.len() {
            return Err(LmiError::ShapeMismatch {
                op: "controller in scaled coordinates".into(),
                left: (k.ny(), k.nu()),
                right: (self.du.len(), self.dy.len()),
            });
        }
        Ok(StateSpace::continuous(
            k.a().clone(),
            k.b() * &dy,
            &du * k.c(),
            &du * k.d() * &dy,
        )?)
    }

    /// `R = T R̃ Tᵀ` (also the H2 LMIs' `X`).
    pub fn r(&self, r: &Mat) -> Mat {
        crate::linalg::sym(&(&self.t * r * self.t.transpose()))
    }

    /// `S = T⁻ᵀ S̃ T⁻¹` (also the H2 LMIs' `Y`).
    pub fn s(&self, s: &Mat) -> Mat {
        crate::linalg::sym(&(self.t_inv.transpose() * s * &self.t_inv))
    }

    /// `X_cl = diag(T⁻ᵀ, I) X̃_cl diag(T⁻¹, I)`.
    pub fn lyapunov(&self, x: &Mat) -> Mat {
        let n = self.t.nrows();
        let m = x.nrows();
        let mut w = Mat::identity(m, m);
        w.view_mut((0, 0), (n, n)).copy_from(&self.t_inv);
        crate::linalg::sym(&(w.transpose() * x * w))
    }
}

/// Most solves [`refine`] makes.
pub(crate) const MAX_PASSES: usize = 3;

/// A relative improvement of the objective below this ends [`refine`].
const STALL: f64 = 1e-7;

/// One solve of [`refine`] in given coordinates.
pub(crate) struct Pass<T> {
    /// The objective in the original plant's units (the level `γ`, or `tr W`), if the solver
    /// returned one.
    pub objective: Option<f64>,
    /// Whether the solve counts (solved, every recheck passing).
    pub accepted: bool,
    /// `(R̃, S̃)` (or the H2 LMIs' `(X̃, Ỹ)`) of the solve, to balance the next coordinates.
    pub pair: Option<(Mat, Mat)>,
    /// The rest of the solve.
    pub data: T,
}

/// What [`refine`] found: the accepted solve with the smallest objective as
/// `(objective, coordinates, data)`, or the last solve when none was accepted.
pub(crate) type Refined<T> = std::result::Result<(f64, Coordinates, T), T>;

/// Solves in `start`, then again in the coordinates that balance each solve's pair
/// ([`Coordinates::balancing`], with the level scaling when `scale_level`; in the plant's
/// own coordinates when a solve before any accepted one has no pair), keeping the
/// accepted solve with the smallest objective; stops after [`MAX_PASSES`] solves, when a
/// solve after an accepted one does not lower the objective by more than a relative 1e-7,
/// or when no balancing transform exists.
///
/// # Errors
/// Those of `solve`.
pub(crate) fn refine<T>(
    start: Coordinates,
    scale_level: bool,
    mut solve: impl FnMut(&Coordinates) -> Result<Pass<T>>,
) -> Result<Refined<T>> {
    let mut best: Option<(f64, Coordinates, T)> = None;
    let mut last = None;
    let identity = Coordinates::identity(start.t.nrows(), start.du.len(), start.dy.len());
    let mut coords = start;
    for _ in 0..MAX_PASSES {
        let pass = solve(&coords)?;
        let previous = best.as_ref().map(|b| b.0);
        let next = match (&pass.pair, pass.objective) {
            (Some((r, s)), Some(g)) if g > 0.0 => {
                let mut c = coords.balancing(r, s, g);
                if let (Some(c), false) = (c.as_mut(), scale_level) {
                    c.s = coords.s;
                }
                c
            }
            _ => None,
        };
        let improved = pass.accepted
            && pass
                .objective
                .is_some_and(|g| previous.is_none_or(|b| g < b));
        let stalled = match (previous, pass.objective) {
            (Some(b), Some(g)) => !improved || b - g <= STALL * b.abs(),
            _ => false,
        };
        // Nothing to balance from the first coordinates: try the plant's own.
        let fallback = next.is_none() && !improved && previous.is_none() && coords != identity;
        match pass.objective {
            Some(g) if improved => best = Some((g, coords, pass.data)),
            _ => last = Some(pass.data),
        }
        match next {
            Some(c) if !stalled => coords = c,
            None if fallback => coords = identity.clone(),
            _ => break,
        }
    }
    match (best, last) {
        (Some(b), _) => Ok(Ok(b)),
        (None, Some(l)) => Ok(Err(l)),
        (None, None) => Err(LmiError::Solver("no solve was made".into())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pendulab_lti::design::hinf_syn;
    use pendulab_lti::norms::{h2_norm, hinf_norm};

    fn m(r: usize, c: usize, v: &[f64]) -> Mat {
        Mat::from_row_slice(r, c, v)
    }

    /// A 3-state plant with entries over four decades (w, z, u, y of sizes 2, 2, 1, 1).
    fn plant() -> StandardPlant {
        StandardPlant::from_blocks(
            &m(3, 3, &[-0.01, 0.0, 40.0, 0.0, -20.0, 15.0, 0.0, -8.0, -1.0]),
            &m(3, 2, &[1.0, 0.0, 1.0, 0.0, 1.0, 0.0]),
            &m(3, 1, &[0.0, 0.0, 30.0]),
            &m(2, 3, &[5.0, 1.0, 0.0, 0.0, 0.0, 0.0]),
            &m(1, 3, &[1.0, 0.0, 70.0]),
            &Mat::zeros(2, 2),
            &m(2, 1, &[0.0, 0.1]),
            &m(1, 2, &[0.0, 1.0]),
            &Mat::zeros(1, 1),
        )
        .unwrap()
    }

    /// The defining property of the balancing transform: `T⁻¹RT⁻ᵀ = TᵀST = Σ` diagonal with
    /// `Σ² = eig(RS)`, `T T⁻¹ = I`.
    #[test]
    fn balancing_diagonalises_both() {
        let r = m(3, 3, &[4.0, 1.0, 0.0, 1.0, 2.0, 0.5, 0.0, 0.5, 0.2]);
        let s = m(3, 3, &[3.0, -1.0, 0.2, -1.0, 5.0, 0.0, 0.2, 0.0, 2e3]);
        let c = Coordinates::identity(3, 1, 1)
            .balancing(&r, &s, 4.0)
            .unwrap();
        let rt = &c.t_inv * &r * c.t_inv.transpose();
        let st = c.t.transpose() * &s * &c.t;
        assert!((&c.t * &c.t_inv - Mat::identity(3, 3)).norm() < 1e-12);
        let mut eig: Vec<f64> = (&r * &s)
            .complex_eigenvalues()
            .iter()
            .map(|z| z.re)
            .collect();
        eig.sort_by(|a, b| b.total_cmp(a));
        for i in 0..3 {
            for j in 0..3 {
                let tol = 1e-10 * rt.norm();
                if i == j {
                    assert!((rt[(i, i)] - st[(i, i)]).abs() < tol, "{rt} {st}");
                    assert!((rt[(i, i)].powi(2) - eig[i]).abs() < 1e-9 * eig[i], "{i}");
                } else {
                    assert!(
                        rt[(i, j)].abs() < tol && st[(i, j)].abs() < tol,
                        "{rt} {st}"
                    );
                }
            }
        }
        assert_eq!(c.s, 0.5);
        assert!(
            Coordinates::identity(3, 1, 1)
                .balancing(&-r, &s, 1.0)
                .is_none()
        );
    }

    /// Invariance: a controller of the plant in equilibrated coordinates, mapped back, gives
    /// the original plant a closed loop with the same H∞ and H2 norms (divided by `s²`), and
    /// `R`, `S` map back as congruences.
    #[test]
    fn controllers_and_certificates_map_back() {
        let p = plant();
        let eq = Coordinates::equilibrated(&p);
        let r = m(3, 3, &[4.0, 1.0, 0.0, 1.0, 2.0, 0.5, 0.0, 0.5, 0.2]);
        let s = m(3, 3, &[3.0, -1.0, 0.2, -1.0, 5.0, 0.0, 0.2, 0.0, 2e3]);
        let c = eq.balancing(&r, &s, 3.0).unwrap();
        for c in [eq, c] {
            let scaled = c.plant(&p).unwrap();
            let g = c.scaled_gamma(50.0);
            assert!((c.gamma(g) - 50.0).abs() < 1e-12);
            let k = hinf_syn(&scaled, g).unwrap();
            let cl_scaled = scaled.close_loop(&k.controller).unwrap();
            let cl = p.close_loop(&c.controller(&k.controller).unwrap()).unwrap();
            let s2 = c.s * c.s;
            let (a, b) = (
                hinf_norm(&cl, 1e-10).unwrap().value,
                hinf_norm(&cl_scaled, 1e-10).unwrap().value / s2,
            );
            assert!((a - b).abs() < 1e-8 * a, "{a} vs {b}");
            let (a, b) = (h2_norm(&cl).unwrap(), h2_norm(&cl_scaled).unwrap() / s2);
            assert!((a - b).abs() < 1e-8 * a, "{a} vs {b}");
            let back = c.r(&(&c.t_inv * &r * c.t_inv.transpose()));
            assert!((back - &r).norm() < 1e-10 * r.norm());
            let back = c.s(&(c.t.transpose() * &s * &c.t));
            assert!((back - &s).norm() < 1e-10 * s.norm());
        }
    }
}
