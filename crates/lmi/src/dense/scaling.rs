//! The cones of `K` and their Nesterov–Todd scaling: applying `W`, `Wᵀ`, `W⁻¹`, `W⁻ᵀ`, the scaled
//! point `λ`, the Jordan product and its inverse, the step to the boundary, and the factored
//! update of the scaling after a step (module docs of [`super`], **Scaling**).
//!
//! Neighbours: `kernels.rs` (dense kernels), `kkt.rs` (the Newton systems in the scaled space),
//! `embedding.rs` (iterate, residuals, stopping measures), `driver.rs` (the iteration).

use super::kernels::{cholesky, congruence, mul, smat_into, svec_sym, transpose};
use crate::conic::svec_index;
use pendulab_lapack::kernels::{svd_square, symmetric_eigenvalues};

/// A nonnegative orthant of `len` rows from `start`: `W = diag(w)`, `w = √(s/z)`,
/// `λ = √(sz)`.
#[derive(Debug, Clone)]
pub(super) struct Lp {
    pub(super) start: usize,
    pub(super) len: usize,
    pub(super) w: Vec<f64>,
    pub(super) lambda: Vec<f64>,
}

/// A `side × side` PSD cone on the svec rows from `start`: `W(U) = RᵀUR`, `W⁻ᵀ(U) =
/// R⁻¹UR⁻ᵀ`, `Wᵀ(U) = RURᵀ`, `W⁻¹(U) = R⁻ᵀUR⁻¹` (column-major `R`, `R⁻¹`, `R⁻ᵀ`).
#[derive(Debug, Clone)]
pub(super) struct Psd {
    pub(super) start: usize,
    pub(super) side: usize,
    pub(super) r: Vec<f64>,
    pub(super) rinv: Vec<f64>,
    pub(super) rinv_t: Vec<f64>,
    pub(super) lambda: Vec<f64>,
}

/// One cone of `K` (the zero-cone rows aside) with its Nesterov–Todd scaling.
#[derive(Debug, Clone)]
pub(super) enum Cone {
    Lp(Lp),
    Psd(Psd),
}

impl Cone {
    pub(super) fn rows(&self) -> std::ops::Range<usize> {
        match self {
            Cone::Lp(c) => c.start..c.start + c.len,
            Cone::Psd(c) => c.start..c.start + c.side * (c.side + 1) / 2,
        }
    }

    /// `W⁻ᵀ v` (row space → scaled space).
    pub(super) fn w_inv_t(&self, v: &[f64], out: &mut [f64]) {
        match self {
            Cone::Lp(c) => {
                for ((o, x), wi) in out.iter_mut().zip(v).zip(&c.w) {
                    *o = x / wi;
                }
            }
            Cone::Psd(c) => congruence(c.side, &c.rinv, v, out),
        }
    }

    /// `Wᵀ v` (scaled space → row space).
    pub(super) fn w_t(&self, v: &[f64], out: &mut [f64]) {
        match self {
            Cone::Lp(c) => {
                for ((o, x), wi) in out.iter_mut().zip(v).zip(&c.w) {
                    *o = x * wi;
                }
            }
            Cone::Psd(c) => congruence(c.side, &c.r, v, out),
        }
    }

    /// `W⁻¹ v` (scaled space → row space).
    pub(super) fn w_inv(&self, v: &[f64], out: &mut [f64]) {
        match self {
            Cone::Lp(c) => {
                for ((o, x), wi) in out.iter_mut().zip(v).zip(&c.w) {
                    *o = x / wi;
                }
            }
            Cone::Psd(c) => congruence(c.side, &c.rinv_t, v, out),
        }
    }

    /// `λ` as a vector of the scaled space.
    pub(super) fn lambda_vec(&self) -> Vec<f64> {
        match self {
            Cone::Lp(c) => c.lambda.clone(),
            Cone::Psd(c) => {
                let mut v = vec![0.0; c.side * (c.side + 1) / 2];
                for (i, l) in c.lambda.iter().enumerate() {
                    v[svec_index(i, i)] = *l;
                }
                v
            }
        }
    }

    /// `λ ∘ λ` into `out` (scaled space).
    pub(super) fn lambda_sq(&self, out: &mut [f64]) {
        match self {
            Cone::Lp(c) => {
                for (o, l) in out.iter_mut().zip(&c.lambda) {
                    *o = l * l;
                }
            }
            Cone::Psd(c) => {
                out.iter_mut().for_each(|v| *v = 0.0);
                for (i, l) in c.lambda.iter().enumerate() {
                    out[svec_index(i, i)] = l * l;
                }
            }
        }
    }

    /// Adds `a · e` (the cone's identity) to `out`.
    pub(super) fn add_identity(&self, a: f64, out: &mut [f64]) {
        match self {
            Cone::Lp(_) => out.iter_mut().for_each(|v| *v += a),
            Cone::Psd(c) => {
                for i in 0..c.side {
                    out[svec_index(i, i)] += a;
                }
            }
        }
    }

    /// `λ ◇⁻¹ d`: the `u` with `λ ∘ u = d` (in place).
    pub(super) fn lambda_inv_prod(&self, d: &mut [f64]) {
        match self {
            Cone::Lp(c) => {
                for (x, l) in d.iter_mut().zip(&c.lambda) {
                    *x /= l;
                }
            }
            Cone::Psd(c) => {
                let mut k = 0;
                for j in 0..c.side {
                    for i in 0..=j {
                        d[k] *= 2.0 / (c.lambda[i] + c.lambda[j]);
                        k += 1;
                    }
                }
            }
        }
    }

    /// The Jordan product `u ∘ v` into `out` (PSD: `(UV + VU)/2`).
    pub(super) fn jordan(&self, u: &[f64], v: &[f64], out: &mut [f64]) {
        match self {
            Cone::Lp(_) => {
                for ((o, a), b) in out.iter_mut().zip(u).zip(v) {
                    *o = a * b;
                }
            }
            Cone::Psd(c) => {
                let d = c.side;
                let (mut um, mut vm, mut p) =
                    (vec![0.0; d * d], vec![0.0; d * d], vec![0.0; d * d]);
                smat_into(u, d, &mut um);
                smat_into(v, d, &mut vm);
                mul(d, (false, false), &um, &vm, &mut p);
                svec_sym(&p, d, out);
            }
        }
    }

    /// Largest `α` with `λ + α u` in the cone (`∞` if every `α ≥ 0` is; 0 for NaN).
    pub(super) fn max_step(&self, u: &[f64]) -> f64 {
        match self {
            Cone::Lp(c) => {
                let mut a = f64::INFINITY;
                for (l, x) in c.lambda.iter().zip(u) {
                    if x.is_nan() {
                        return 0.0;
                    }
                    if *x < 0.0 {
                        a = a.min(-l / x);
                    }
                }
                a
            }
            Cone::Psd(c) => {
                // λ + αU ⪰ 0 ⇔ I + α Λ^{-½} U Λ^{-½} ⪰ 0.
                let d = c.side;
                let mut m = vec![0.0; d * d];
                smat_into(u, d, &mut m);
                let isq: Vec<f64> = c.lambda.iter().map(|l| 1.0 / l.sqrt()).collect();
                for j in 0..d {
                    for i in j..d {
                        m[i + j * d] *= isq[i] * isq[j];
                    }
                }
                let (mut w, mut work) = (vec![0.0; d], vec![0.0; 3 * d]);
                if !symmetric_eigenvalues(d, &mut m, &mut w, &mut work) {
                    return 0.0;
                }
                if w[0] < 0.0 {
                    -1.0 / w[0]
                } else {
                    f64::INFINITY
                }
            }
        }
    }

    /// `−λ_min` of `v` (row space): how far `v` is outside the cone (≤ 0 inside; +∞ for
    /// non-finite entries).
    pub(super) fn violation(&self, v: &[f64]) -> f64 {
        match self {
            Cone::Lp(_) => v.iter().map(|x| -x).fold(f64::NEG_INFINITY, f64::max),
            Cone::Psd(c) => {
                let d = c.side;
                let mut m = vec![0.0; d * d];
                smat_into(v, d, &mut m);
                let (mut w, mut work) = (vec![0.0; d], vec![0.0; 3 * d]);
                if symmetric_eigenvalues(d, &mut m, &mut w, &mut work) {
                    -w[0]
                } else {
                    f64::INFINITY
                }
            }
        }
    }

    /// Updates the scaling to the scaled iterates `s̃`, `z̃` (scaled space, interior points):
    /// afterwards `W⁻ᵀ s = W z = λ` for the `s`, `z` whose old-scaled images are `s̃`, `z̃`.
    /// `false` if a factorisation fails (a point not strictly inside the cone).
    pub(super) fn update(&mut self, st: &[f64], zt: &[f64]) -> bool {
        match self {
            Cone::Lp(c) => {
                for k in 0..c.len {
                    if !(st[k] > 0.0 && zt[k] > 0.0) {
                        return false;
                    }
                    c.w[k] *= (st[k] / zt[k]).sqrt();
                    c.lambda[k] = (st[k] * zt[k]).sqrt();
                }
                true
            }
            Cone::Psd(c) => {
                let d = c.side;
                let mut m = vec![0.0; d * d];
                smat_into(st, d, &mut m);
                let Some(l1) = cholesky(d, &m) else {
                    return false;
                };
                smat_into(zt, d, &mut m);
                let Some(l2) = cholesky(d, &m) else {
                    return false;
                };
                // L₂ᵀ L₁ = U Λ₊ Vᵀ.
                let mut p = vec![0.0; d * d];
                mul(d, (true, false), &l2, &l1, &mut p);
                let (mut u, mut sv, mut vt) = (vec![0.0; d * d], vec![0.0; d], vec![0.0; d * d]);
                if !svd_square(d, &p, &mut u, &mut sv, &mut vt)
                    || !sv.iter().all(|v| *v > 0.0 && v.is_finite())
                {
                    return false;
                }
                let isq: Vec<f64> = sv.iter().map(|v| 1.0 / v.sqrt()).collect();
                // R ← R L₁ V Λ₊^{-½};  R⁻¹ ← Λ₊^{-½} Uᵀ L₂ᵀ R⁻¹.
                let mut right = vec![0.0; d * d];
                mul(d, (false, true), &l1, &vt, &mut right);
                for j in 0..d {
                    right[j * d..(j + 1) * d]
                        .iter_mut()
                        .for_each(|x| *x *= isq[j]);
                }
                let mut left = vec![0.0; d * d];
                mul(d, (true, true), &u, &l2, &mut left);
                for j in 0..d {
                    for i in 0..d {
                        left[i + j * d] *= isq[i];
                    }
                }
                let mut r = vec![0.0; d * d];
                mul(d, (false, false), &c.r, &right, &mut r);
                let mut rinv = vec![0.0; d * d];
                mul(d, (false, false), &left, &c.rinv, &mut rinv);
                c.rinv_t = transpose(d, &rinv);
                c.r = r;
                c.rinv = rinv;
                c.lambda = sv;
                true
            }
        }
    }
}
