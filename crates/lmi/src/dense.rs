//! A dense primal–dual interior-point method for small semidefinite programs: the LMIs of
//! control design, whose few dozen variables meet a few PSD cones of side ≤ ~30.
//!
//! # Problem
//! The conic form of [`crate::conic`], written with the zero-cone rows apart:
//!
//! ```text
//! minimise cᵀx   s.t.   G x + s = h,  s ∈ K,        E x = f
//! maximise −hᵀz − fᵀy   s.t.   Gᵀz + Eᵀy + c = 0,  z ∈ K
//! ```
//!
//! with `K` a product of nonnegative orthants and PSD cones (svec layout, self-dual).
//!
//! # Method
//! The homogeneous self-dual embedding (Ye, Todd & Mizuno 1994; in the form of
//! L. Vandenberghe, "The CVXOPT linear and quadratic cone program solvers", 2010, §7): find
//! `(x, y, z, s, τ, κ)` with `s, z ∈ K`, `τ, κ ≥ 0` and
//!
//! ```text
//! Eᵀy + Gᵀz + cτ = 0,   Ex − fτ = 0,   Gx + s − hτ = 0,   cᵀx + fᵀy + hᵀz + κ = 0.
//! ```
//!
//! Its solutions have `sᵀz + τκ = 0`: with `τ > 0`, `(x, y, z, s)/τ` is a primal–dual optimal
//! pair; with `κ > 0`, `hᵀz + fᵀy < 0` certifies primal infeasibility (Farkas) or `cᵀx < 0`
//! dual infeasibility. Each iteration takes one infeasible-start Newton step towards the
//! central path `s ∘ z = μe`, `τκ = μ`, `μ = (sᵀz + τκ)/(ν + 1)` (ν the cone degree), with
//! Mehrotra's predictor–corrector: an affine step `σ = 0`, then `σ = (1 − α_aff)³` and the
//! second-order term `Δs_aff ∘ Δz_aff`, the residuals scaled by `1 − σ` and the step
//! [`STEP`] of the way to the boundary.
//!
//! **Scaling.** Nesterov–Todd: `W` with `W⁻ᵀ s = W z = λ`; on a PSD cone `W(U) = RᵀUR`,
//! `S = RΛRᵀ`, `Z = R⁻ᵀΛR⁻¹` with `Λ = diag(λ)`, so the scaled point is diagonal and the
//! Jordan product `u ∘ v = (UV + VU)/2` is inverted entrywise:
//! `(λ ◇⁻¹ d)_ij = 2 d_ij/(λ_i + λ_j)`. The scaling is kept in factored form and updated after
//! each step from the scaled iterates `s̃ = λ + αΔŝ`, `z̃ = λ + αΔẑ` (Cholesky factors
//! `L₁L₁ᵀ = s̃`, `L₂L₂ᵀ = z̃`, SVD `L₂ᵀL₁ = UΛ₊Vᵀ`, `R ← R L₁ V Λ₊^{-½}`,
//! `R⁻¹ ← Λ₊^{-½} Uᵀ L₂ᵀ R⁻¹`; Todd, Toh & Tütüncü 1998, §4; Vandenberghe 2010, §4.3), which
//! stays accurate as `s` and `z` approach the boundary: `s̃` and `z̃` are near `λ`, which is
//! near `√μ I` on the central path. The cone iterates are then taken from the scaling,
//! `s = Wᵀλ`, `z = W⁻¹λ` (as CVXOPT's `conelp` does), so they lie in the cone and agree with
//! the scaling to rounding; `x` and `y` are updated additively.
//!
//! **Linear algebra.** The Newton systems reduce to
//!
//! ```text
//! [ 0   Eᵀ   Gᵀ   ] [x]   [b_x]
//! [ E   0    0    ] [y] = [b_y]
//! [ G   0   −WᵀW  ] [z]   [b_z]
//! ```
//!
//! solved by eliminating `z = W⁻¹W⁻ᵀ(Gx − b_z)`: with `V = W⁻ᵀG` (column `j` on a PSD cone is
//! `svec(R⁻¹ G_j R⁻ᵀ)`), `H = VᵀV` is the Schur complement (the "normal equations" of SDPT3
//! and SeDuMi), factored by Cholesky as `H + EᵀE` and, with equalities, `E(H + EᵀE)⁻¹Eᵀ`
//! (equivalent to `[H Eᵀ; E 0]` when `[G; E]` has full column rank), with a small diagonal
//! shift if a factorisation fails. Everything is solved in the scaled space: the
//! right-hand side enters as `W⁻ᵀb_z`, the answer leaves as `Wz = Vx − W⁻ᵀb_z`, and `z`
//! itself is never formed (`Gᵀz = VᵀWz`, `hᵀz = (W⁻ᵀh)ᵀWz`). `H` squares the conditioning
//! of `V`, which grows as the iterates approach an optimum on the cones' boundary, so each
//! solve is followed by iterative refinement on the unreduced system (Higham, *Accuracy and
//! Stability of Numerical Algorithms*, 2nd ed., §12.1) when its residual exceeds
//! [`REFINE_BELOW`] of the terms it sums: up to [`MAX_REFINEMENT`] steps, as long as each at
//! least halves the residual. The dense `H` costs `O(n² · rows)` per iteration: this method
//! is for small problems, where it avoids the sparse factorisation of the full KKT matrix
//! with its dense `d(d+1)/2` blocks per cone. An equality no variable enters, `0 = f_k`, is
//! dropped, or certifies infeasibility at once when `|f_k|` exceeds the feasibility
//! tolerance.
//!
//! # Stopping (in the solver's data scale)
//! With `x̄ = x/τ` etc.: solved when the relative primal residual
//! `‖(Ex̄ − f, Gx̄ + s̄ − h)‖ / max(1, ‖(f, h)‖)` and dual residual
//! `‖Eᵀȳ + Gᵀz̄ + c‖ / max(1, ‖c‖)` are at most the feasibility tolerance, and the duality
//! gap `s̄ᵀz̄` and the objective difference `|cᵀx̄ + hᵀz̄ + fᵀȳ|` are within the absolute or the
//! relative (to `max(1, min(|cᵀx̄|, |hᵀz̄ + fᵀȳ|))`) gap tolerance. Primal infeasible when
//! `hᵀz + fᵀy < 0` and `‖Eᵀy + Gᵀz‖ / max(1, ‖c‖) ≤ tol · (−hᵀz − fᵀy)`; dual infeasible
//! when `cᵀx < 0` and `‖(Ex, Gx + s)‖ / max(1, ‖(f, h)‖) ≤ tol · (−cᵀx)`.
//!
//! The method also stops when it makes no progress ([`NO_PROGRESS`]) or `μ` reaches zero in
//! rounding. When it stops short (that, the iteration or time limit, a step too short to
//! progress, a failed factorisation), the best iterate seen is returned as *almost solved*
//! if it meets the reduced tolerances ([`REDUCED_FEASIBILITY`] and [`REDUCED_GAP`] times the
//! requested ones: Clarabel's default reduced tolerances 10⁻⁴ and 5·10⁻⁵ relative to its
//! default 10⁻⁸).

use crate::conic::{ConeKind, ConicData, RawStatus, Settings, svec_index};
use pendulab_lapack::kernels::{cholesky_lower, svd_square, symmetric_eigenvalues};
use std::f64::consts::SQRT_2;
use std::time::Instant;

/// What the dense method returns, in the solver's scale (see [`ConicData`]).
#[derive(Debug, Clone)]
pub(crate) struct Outcome {
    pub(crate) status: RawStatus,
    /// Primal `x` (solved), the ray `x` (unbounded), or the last iterate.
    pub(crate) x: Vec<f64>,
    /// One dual per row: `y` on the zero-cone rows, `z` on the others (solved), the
    /// certificate `(y, z)` (infeasible), or the last iterate.
    pub(crate) z: Vec<f64>,
    /// `cᵀx` at the solution.
    pub(crate) objective: f64,
    pub(crate) iterations: u32,
    pub(crate) primal_residual: f64,
    pub(crate) dual_residual: f64,
}

/// Fraction of the way to the cone's boundary of each combined step. Over the book's four
/// state-feedback designs and 80 planted SDPs (sides 5–25), 0.97 took 10 % fewer iterations
/// in all than CVXOPT's 0.99 (936 against 1038), 0.95 and 0.98 about as few as 0.97.
const STEP: f64 = 0.97;
/// Exponent of Mehrotra's centring heuristic `σ = (1 − α_aff)^EXPON`.
const EXPON: i32 = 3;
/// Most refinement steps on the unreduced KKT system after each reduced solve.
const MAX_REFINEMENT: usize = 4;
/// A solve is refined only when its residual exceeds this fraction of the magnitude of the
/// terms it sums (about 4500 ε: a direction accurate to twelve digits needs no refinement).
const REFINE_BELOW: f64 = 1e-12;
/// Consecutive steps shorter than [`MIN_STEP`] after which the method gives up.
const STALL: usize = 3;
/// A step length below which no progress is being made.
const MIN_STEP: f64 = 1e-9;
/// Iterations without progress (the iterate's largest ratio to the optimality tolerances, a
/// certificate's ratio to the infeasibility tolerance, or `μ` falling by the factor
/// [`PROGRESS`]) after which the method stops: near an optimum on the cones' boundary
/// rounding eventually dominates the steps, and the best iterate is then as good as it gets.
/// It also stops once `μ ≤ 0` (complementarity exhausted to rounding).
const NO_PROGRESS: usize = 8;
/// The factor by which a ratio must fall below its best value to count as progress.
const PROGRESS: f64 = 0.8;
/// Reduced feasibility tolerance as a multiple of the requested one.
const REDUCED_FEASIBILITY: f64 = 1e4;
/// Reduced gap tolerances as a multiple of the requested ones.
const REDUCED_GAP: f64 = 5e3;

// ---------------------------------------------------------------------------------------
// Small dense helpers on column-major arrays with tight leading dimension.

/// `aᵀb` over the common length, in four interleaved partial sums (independent chains the
/// processor overlaps and the compiler vectorises).
#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        let x: &[f64; 4] = x.try_into().unwrap_or(&[0.0; 4]);
        let y: &[f64; 4] = y.try_into().unwrap_or(&[0.0; 4]);
        acc[0] += x[0] * y[0];
        acc[1] += x[1] * y[1];
        acc[2] += x[2] * y[2];
        acc[3] += x[3] * y[3];
    }
    let mut tail = 0.0;
    for (x, y) in ra.iter().zip(rb) {
        tail += x * y;
    }
    (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

fn norm_inf(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// The symmetric `d × d` matrix of an svec, into `m`.
fn smat_into(v: &[f64], d: usize, m: &mut [f64]) {
    let mut k = 0;
    for j in 0..d {
        for i in 0..=j {
            if i == j {
                m[i + j * d] = v[k];
            } else {
                let x = v[k] / SQRT_2;
                m[i + j * d] = x;
                m[j + i * d] = x;
            }
            k += 1;
        }
    }
}

/// svec of the symmetric part of the `d × d` matrix `m`, into `out`.
fn svec_sym(m: &[f64], d: usize, out: &mut [f64]) {
    let mut k = 0;
    for j in 0..d {
        for i in 0..=j {
            out[k] = if i == j {
                m[i + j * d]
            } else {
                (m[i + j * d] + m[j + i * d]) * (0.5 * SQRT_2)
            };
            k += 1;
        }
    }
}

/// `out = op(A) op(B)` for `d × d` matrices, `op(X) = Xᵀ` when its flag is set. Sides up to
/// 16 run on a kernel with the side as a compile-time constant (the columns
/// then live in registers); larger ones on the same loops with a run-time side.
fn mul(d: usize, (ta, tb): (bool, bool), a: &[f64], b: &[f64], out: &mut [f64]) {
    macro_rules! dispatch {
        ($($side:literal)*) => {
            match d {
                $($side => mul_fixed::<$side>((ta, tb), a, b, out),)*
                _ => mul_dynamic(d, (ta, tb), a, b, out),
            }
        };
    }
    dispatch!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
}

/// [`mul`] for side `D`: each column of the result accumulated in a `[f64; D]`.
#[inline(always)]
fn mul_fixed<const D: usize>((ta, tb): (bool, bool), a: &[f64], b: &[f64], out: &mut [f64]) {
    let (ac, _) = a[..D * D].as_chunks::<D>();
    let (bc, _) = b[..D * D].as_chunks::<D>();
    let (oc, _) = out[..D * D].as_chunks_mut::<D>();
    if ta {
        // out(i, j) = A(:, i) · op(B)(:, j); with op(B) = Bᵀ, that column is row j of B.
        for j in 0..D {
            let bj: [f64; D] = if tb {
                std::array::from_fn(|k| bc[k][j])
            } else {
                bc[j]
            };
            for i in 0..D {
                let mut acc = 0.0;
                for k in 0..D {
                    acc += ac[i][k] * bj[k];
                }
                oc[j][i] = acc;
            }
        }
    } else {
        // out(:, j) = Σ_k A(:, k) op(B)(k, j).
        for j in 0..D {
            let mut col = [0.0; D];
            for k in 0..D {
                let bkj = if tb { bc[k][j] } else { bc[j][k] };
                let ak = &ac[k];
                for i in 0..D {
                    col[i] += ak[i] * bkj;
                }
            }
            oc[j] = col;
        }
    }
}

/// [`mul`] for any side.
fn mul_dynamic(d: usize, (ta, tb): (bool, bool), a: &[f64], b: &[f64], out: &mut [f64]) {
    let bkj = |k: usize, j: usize| if tb { b[j + k * d] } else { b[k + j * d] };
    if ta {
        for j in 0..d {
            for i in 0..d {
                out[i + j * d] = (0..d).map(|k| a[k + i * d] * bkj(k, j)).sum();
            }
        }
    } else {
        for j in 0..d {
            let col = &mut out[j * d..(j + 1) * d];
            col.iter_mut().for_each(|x| *x = 0.0);
            for k in 0..d {
                let s = bkj(k, j);
                for (o, aik) in col.iter_mut().zip(&a[k * d..(k + 1) * d]) {
                    *o += aik * s;
                }
            }
        }
    }
}

/// svec of the `d × d` matrix `m` that is symmetric by construction (up to rounding), from
/// its upper triangle, into `out`.
fn svec_upper(m: &[f64], d: usize, out: &mut [f64]) {
    let mut k = 0;
    for j in 0..d {
        let col = &m[j * d..j * d + j + 1];
        let dst = &mut out[k..k + j + 1];
        for (o, x) in dst.iter_mut().zip(col) {
            *o = x * SQRT_2;
        }
        dst[j] = col[j];
        k += j + 1;
    }
}

/// `out = T · Pᵀ` for `d × d` matrices where only the columns `cols` of `T` are nonzero:
/// `out(:, q) = Σ_{c ∈ cols} T(:, c) P(q, c)` (fixed-size kernel up to side 16).
fn mul_nt_cols(d: usize, t: &[f64], p: &[f64], cols: &[usize], out: &mut [f64]) {
    macro_rules! dispatch {
        ($($side:literal)*) => {
            match d {
                $($side => mul_nt_cols_fixed::<$side>(t, p, cols, out),)*
                _ => {
                    for q in 0..d {
                        let o = &mut out[q * d..(q + 1) * d];
                        o.iter_mut().for_each(|x| *x = 0.0);
                        for &c in cols {
                            let w = p[q + c * d];
                            for (ov, tv) in o.iter_mut().zip(&t[c * d..(c + 1) * d]) {
                                *ov += tv * w;
                            }
                        }
                    }
                }
            }
        };
    }
    dispatch!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
}

#[inline(always)]
fn mul_nt_cols_fixed<const D: usize>(t: &[f64], p: &[f64], cols: &[usize], out: &mut [f64]) {
    let (tc, _) = t[..D * D].as_chunks::<D>();
    let (pc, _) = p[..D * D].as_chunks::<D>();
    let (oc, _) = out[..D * D].as_chunks_mut::<D>();
    for q in 0..D {
        let mut col = [0.0; D];
        for &c in cols {
            let w = pc[c][q];
            let tcol = &tc[c];
            for i in 0..D {
                col[i] += tcol[i] * w;
            }
        }
        oc[q] = col;
    }
}

/// `svec(P · smat(v) · Pᵀ)` into `out` (`P` is `d × d`).
fn congruence(d: usize, p: &[f64], v: &[f64], out: &mut [f64]) {
    let mut m = vec![0.0; d * d];
    let mut t = vec![0.0; d * d];
    smat_into(v, d, &mut m);
    mul(d, (false, false), p, &m, &mut t);
    mul(d, (false, true), &t, p, &mut m);
    svec_upper(&m, d, out);
}

fn transpose(d: usize, a: &[f64]) -> Vec<f64> {
    let mut t = vec![0.0; d * d];
    for j in 0..d {
        for i in 0..d {
            t[j + i * d] = a[i + j * d];
        }
    }
    t
}

/// Lower Cholesky factor of a copy of the symmetric `m` (strict upper triangle zeroed), or
/// None when it is not positive definite.
fn cholesky(d: usize, m: &[f64]) -> Option<Vec<f64>> {
    let mut l = m.to_vec();
    cholesky_lower(d, &mut l).ok()?;
    for j in 0..d {
        for i in 0..j {
            l[i + j * d] = 0.0;
        }
    }
    Some(l)
}

/// Cholesky factor of the symmetric positive (semi)definite `n × n` matrix `m`, with a
/// diagonal shift of growing size (from `10⁻¹⁴·max diag`) when the plain factorisation
/// fails.
fn cholesky_regularised(n: usize, m: &[f64]) -> Option<Vec<f64>> {
    let scale = (0..n).fold(0.0f64, |a, i| a.max(m[i + i * n].abs()));
    if !scale.is_finite() {
        return None;
    }
    if let Some(l) = cholesky(n, m) {
        return Some(l);
    }
    let mut delta = 1e-14 * scale.max(f64::MIN_POSITIVE);
    for _ in 0..6 {
        let mut shifted = m.to_vec();
        for i in 0..n {
            shifted[i + i * n] += delta;
        }
        if let Some(l) = cholesky(n, &shifted) {
            return Some(l);
        }
        delta *= 100.0;
    }
    None
}

/// `b ← L⁻¹ b` for the lower triangular `n × n` `l`.
fn forward(n: usize, l: &[f64], b: &mut [f64]) {
    for j in 0..n {
        let v = b[j] / l[j + j * n];
        b[j] = v;
        if v != 0.0 {
            for i in j + 1..n {
                b[i] -= l[i + j * n] * v;
            }
        }
    }
}

/// `b ← L⁻ᵀ b` for the lower triangular `n × n` `l`.
fn backward(n: usize, l: &[f64], b: &mut [f64]) {
    for j in (0..n).rev() {
        let col = &l[j * n..(j + 1) * n];
        let s: f64 = (j + 1..n).map(|i| col[i] * b[i]).sum();
        b[j] = (b[j] - s) / col[j];
    }
}

/// `b ← (L Lᵀ)⁻¹ b`.
fn chol_solve(n: usize, l: &[f64], b: &mut [f64]) {
    forward(n, l, b);
    backward(n, l, b);
}

// ---------------------------------------------------------------------------------------
// Cones and their scaling.

/// A nonnegative orthant of `len` rows from `start`: `W = diag(w)`, `w = √(s/z)`,
/// `λ = √(sz)`.
#[derive(Debug, Clone)]
struct Lp {
    start: usize,
    len: usize,
    w: Vec<f64>,
    lambda: Vec<f64>,
}

/// A `side × side` PSD cone on the svec rows from `start`: `W(U) = RᵀUR`, `W⁻ᵀ(U) =
/// R⁻¹UR⁻ᵀ`, `Wᵀ(U) = RURᵀ`, `W⁻¹(U) = R⁻ᵀUR⁻¹` (column-major `R`, `R⁻¹`, `R⁻ᵀ`).
#[derive(Debug, Clone)]
struct Psd {
    start: usize,
    side: usize,
    r: Vec<f64>,
    rinv: Vec<f64>,
    rinv_t: Vec<f64>,
    lambda: Vec<f64>,
}

/// One cone of `K` (the zero-cone rows aside) with its Nesterov–Todd scaling.
#[derive(Debug, Clone)]
enum Cone {
    Lp(Lp),
    Psd(Psd),
}

impl Cone {
    fn rows(&self) -> std::ops::Range<usize> {
        match self {
            Cone::Lp(c) => c.start..c.start + c.len,
            Cone::Psd(c) => c.start..c.start + c.side * (c.side + 1) / 2,
        }
    }

    /// `W⁻ᵀ v` (row space → scaled space).
    fn w_inv_t(&self, v: &[f64], out: &mut [f64]) {
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
    fn w_t(&self, v: &[f64], out: &mut [f64]) {
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
    fn w_inv(&self, v: &[f64], out: &mut [f64]) {
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
    fn lambda_vec(&self) -> Vec<f64> {
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
    fn lambda_sq(&self, out: &mut [f64]) {
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
    fn add_identity(&self, a: f64, out: &mut [f64]) {
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
    fn lambda_inv_prod(&self, d: &mut [f64]) {
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
    fn jordan(&self, u: &[f64], v: &[f64], out: &mut [f64]) {
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
    fn max_step(&self, u: &[f64]) -> f64 {
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
    fn violation(&self, v: &[f64]) -> f64 {
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
    fn update(&mut self, st: &[f64], zt: &[f64]) -> bool {
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

// ---------------------------------------------------------------------------------------
// Problem structure and the KKT systems.

/// `(a, b, g)`: entry `g` of the symmetric coefficient matrix at `(a, b)`, `a ≤ b` (and
/// `(b, a)`), of one variable in one PSD cone; for an orthant, `(row, 0, g)`.
type Entries = Vec<(usize, usize, f64)>;

/// The structure of the data: which rows are equalities, each variable's coefficients per
/// cone.
struct Structure {
    n: usize,
    m: usize,
    /// Rows of the zero cones with a coefficient, in order (`y` index ↔ row).
    eq_rows: Vec<usize>,
    /// Rows of the zero cones without one (`0 = f_k`).
    dropped_eq: Vec<usize>,
    /// `E` (`p × n`), column-major.
    e: Vec<f64>,
    /// Per cone: `(variable, entries)` of every variable with a coefficient in the cone.
    columns: Vec<Vec<(usize, Entries)>>,
    /// Per row: whether it is a zero-cone row.
    is_eq: Vec<bool>,
    /// Cone degree `ν` (orthant rows plus PSD sides).
    degree: usize,
}

impl Structure {
    fn new(data: &ConicData) -> (Self, Vec<Cone>) {
        let (n, m) = (data.n, data.m);
        let mut is_eq = vec![false; m];
        let mut eq_rows = Vec::new();
        let mut cones = Vec::new();
        // Row → (cone index, (i, j) within the cone).
        let mut row_pos = vec![(usize::MAX, 0usize, 0usize); m];
        let mut start = 0;
        let mut degree = 0;
        for kind in &data.cones {
            let rows = kind.rows();
            match *kind {
                ConeKind::Zero(len) => {
                    for r in start..start + len {
                        is_eq[r] = true;
                        eq_rows.push(r);
                    }
                }
                ConeKind::NonNegative(len) => {
                    for (k, rp) in row_pos[start..start + len].iter_mut().enumerate() {
                        *rp = (cones.len(), k, 0);
                    }
                    cones.push(Cone::Lp(Lp {
                        start,
                        len,
                        w: vec![1.0; len],
                        lambda: vec![1.0; len],
                    }));
                    degree += len;
                }
                ConeKind::Psd(side) => {
                    let mut k = start;
                    for j in 0..side {
                        for i in 0..=j {
                            row_pos[k] = (cones.len(), i, j);
                            k += 1;
                        }
                    }
                    let mut id = vec![0.0; side * side];
                    for i in 0..side {
                        id[i + i * side] = 1.0;
                    }
                    cones.push(Cone::Psd(Psd {
                        start,
                        side,
                        r: id.clone(),
                        rinv: id.clone(),
                        rinv_t: id,
                        lambda: vec![1.0; side],
                    }));
                    degree += side;
                }
            }
            start += rows;
        }
        // Zero-cone rows without a coefficient are `0 = f_k`: dropped from E (trivially
        // satisfied when f_k = 0; see `inconsistent_row` otherwise).
        let mut has_coef = vec![false; m];
        for &r in &data.rowval {
            has_coef[r] = true;
        }
        let dropped_eq: Vec<usize> = eq_rows.iter().copied().filter(|&r| !has_coef[r]).collect();
        eq_rows.retain(|&r| has_coef[r]);
        let p = eq_rows.len();
        let mut eq_index = vec![usize::MAX; m];
        for (k, &r) in eq_rows.iter().enumerate() {
            eq_index[r] = k;
        }
        let mut e = vec![0.0; p * n];
        let mut columns: Vec<Vec<(usize, Entries)>> = vec![Vec::new(); cones.len()];
        for j in 0..n {
            for k in data.colptr[j]..data.colptr[j + 1] {
                let (row, v) = (data.rowval[k], data.nzval[k]);
                if is_eq[row] {
                    e[eq_index[row] + j * p] = v;
                    continue;
                }
                let (c, a, b) = row_pos[row];
                // svec off-diagonals carry √2: the matrix entry is v/√2.
                let g = match cones[c] {
                    Cone::Psd(_) if a != b => v / SQRT_2,
                    _ => v,
                };
                let list = &mut columns[c];
                if list.last().map(|l| l.0) != Some(j) {
                    list.push((j, Vec::new()));
                }
                if let Some(last) = list.last_mut() {
                    last.1.push((a, b, g));
                }
            }
        }
        (
            Self {
                n,
                m,
                eq_rows,
                dropped_eq,
                e,
                columns,
                is_eq,
                degree,
            },
            cones,
        )
    }

    fn p(&self) -> usize {
        self.eq_rows.len()
    }

    /// `out = A x` over all rows.
    fn a_mul(&self, data: &ConicData, x: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
        for (j, xj) in x.iter().enumerate().take(self.n) {
            if *xj != 0.0 {
                for k in data.colptr[j]..data.colptr[j + 1] {
                    out[data.rowval[k]] += data.nzval[k] * xj;
                }
            }
        }
    }

    /// `out = Aᵀ z` over all rows.
    fn at_mul(&self, data: &ConicData, z: &[f64], out: &mut [f64]) {
        for (j, o) in out.iter_mut().enumerate().take(self.n) {
            let mut acc = 0.0;
            for k in data.colptr[j]..data.colptr[j + 1] {
                acc += data.nzval[k] * z[data.rowval[k]];
            }
            *o = acc;
        }
    }
}

/// A solution of the unreduced KKT system: `x`, `y` on the zero-cone rows of `yz`, and
/// `W z` on its cone rows (scaled space). `z` itself is never needed: `Gᵀz = VᵀWz` and
/// `hᵀz = (W⁻ᵀh)ᵀWz`.
#[derive(Clone)]
struct KktSolution {
    x: Vec<f64>,
    yz: Vec<f64>,
}

/// The factored reduced KKT system for one scaling.
struct Kkt {
    /// `V = W⁻ᵀG` over all rows (zero-cone rows: zero), `m × n` column-major.
    v: Vec<f64>,
    /// Cholesky factor of `H + EᵀE` (+ regularisation), `n × n`.
    l: Vec<f64>,
    /// With equalities: the Cholesky factor of `E(H + EᵀE)⁻¹Eᵀ`, `p × p`.
    schur: Option<Vec<f64>>,
}

impl Kkt {
    fn factor(st: &Structure, cones: &[Cone]) -> Option<Self> {
        let (m, n, p) = (st.m, st.n, st.p());
        let mut v = vec![0.0; m * n];
        for (cone, cols) in cones.iter().zip(&st.columns) {
            match cone {
                Cone::Lp(c) => {
                    for (j, entries) in cols {
                        for &(k, _, g) in entries {
                            v[c.start + k + j * m] = g / c.w[k];
                        }
                    }
                }
                Cone::Psd(c) => {
                    let d = c.side;
                    let rinv = &c.rinv;
                    let mut t = vec![0.0; d * d];
                    let mut o = vec![0.0; d * d];
                    let mut touched = vec![false; d];
                    let mut cols_t = Vec::with_capacity(d);
                    for (j, entries) in cols {
                        // T = R⁻¹ G_j (G_j symmetric, from its upper entries; only the
                        // touched columns are nonzero), then svec(T R⁻ᵀ).
                        for &c0 in &cols_t {
                            t[c0 * d..(c0 + 1) * d].iter_mut().for_each(|x| *x = 0.0);
                            touched[c0] = false;
                        }
                        cols_t.clear();
                        // T(:, col) += g R⁻¹(:, from), marking the column touched.
                        let mut add = |col: usize, from: usize, g: f64| {
                            let src = &rinv[from * d..(from + 1) * d];
                            for (tv, rv) in t[col * d..(col + 1) * d].iter_mut().zip(src) {
                                *tv += g * rv;
                            }
                            if !touched[col] {
                                touched[col] = true;
                                cols_t.push(col);
                            }
                        };
                        for &(a, b, g) in entries {
                            add(b, a, g);
                            if a != b {
                                add(a, b, g);
                            }
                        }
                        mul_nt_cols(d, &t, rinv, &cols_t, &mut o);
                        svec_upper(
                            &o,
                            d,
                            &mut v[c.start + j * m..c.start + j * m + d * (d + 1) / 2],
                        );
                    }
                }
            }
        }
        // H = VᵀV + EᵀE (symmetric: the lower triangle, mirrored).
        let mut h = vec![0.0; n * n];
        for j in 0..n {
            let vj = &v[j * m..(j + 1) * m];
            for i in j..n {
                let mut hij = dot(&v[i * m..(i + 1) * m], vj);
                if p > 0 {
                    hij += dot(&st.e[i * p..(i + 1) * p], &st.e[j * p..(j + 1) * p]);
                }
                h[i + j * n] = hij;
                h[j + i * n] = hij;
            }
        }
        let l = cholesky_regularised(n, &h)?;
        let schur = if p > 0 {
            // Y = L⁻¹ Eᵀ (n × p), S = YᵀY.
            let mut y = vec![0.0; n * p];
            for k in 0..p {
                let col = &mut y[k * n..(k + 1) * n];
                for j in 0..n {
                    col[j] = st.e[k + j * p];
                }
                forward(n, &l, col);
            }
            let mut s = vec![0.0; p * p];
            for j in 0..p {
                for i in j..p {
                    let sij = dot(&y[i * n..(i + 1) * n], &y[j * n..(j + 1) * n]);
                    s[i + j * p] = sij;
                    s[j + i * p] = sij;
                }
            }
            Some(cholesky_regularised(p, &s)?)
        } else {
            None
        };
        Some(Self { v, l, schur })
    }

    /// Solves the reduced system once for `(b_x, t)` with `t = (b_y, W⁻ᵀb_z)` (rows).
    fn solve_once(&self, st: &Structure, bx: &[f64], t: &[f64]) -> KktSolution {
        let (m, n, p) = (st.m, st.n, st.p());
        // r = b_x + Vᵀ t (V is zero on the zero-cone rows).
        let mut rhs: Vec<f64> = (0..n)
            .map(|j| bx[j] + dot(&self.v[j * m..(j + 1) * m], t))
            .collect();
        let mut yz = vec![0.0; m];
        let x = if let Some(s) = &self.schur {
            let by: Vec<f64> = st.eq_rows.iter().map(|&r| t[r]).collect();
            // r ← r + Eᵀ b_y; y = S⁻¹(E H̃⁻¹ r − b_y); x = H̃⁻¹(r − Eᵀ y).
            for j in 0..n {
                rhs[j] += dot(&st.e[j * p..(j + 1) * p], &by);
            }
            let mut hr = rhs.clone();
            chol_solve(n, &self.l, &mut hr);
            let mut y: Vec<f64> = (0..p)
                .map(|k| (0..n).map(|j| st.e[k + j * p] * hr[j]).sum::<f64>() - by[k])
                .collect();
            chol_solve(p, s, &mut y);
            for j in 0..n {
                rhs[j] -= dot(&st.e[j * p..(j + 1) * p], &y);
            }
            for (k, &r) in st.eq_rows.iter().enumerate() {
                yz[r] = y[k];
            }
            chol_solve(n, &self.l, &mut rhs);
            rhs
        } else {
            chol_solve(n, &self.l, &mut rhs);
            rhs
        };
        // W z = V x − t on the cone rows.
        for (j, xj) in x.iter().enumerate() {
            if *xj != 0.0 {
                for (w, vv) in yz.iter_mut().zip(&self.v[j * m..(j + 1) * m]) {
                    *w += vv * xj;
                }
            }
        }
        for (i, w) in yz.iter_mut().enumerate() {
            if !st.is_eq[i] {
                *w -= t[i];
            }
        }
        KktSolution { x, yz }
    }

    /// The residual of `u` in the scaled unreduced system, `(b_x − (Eᵀy + VᵀWz), (b_y − Ex,
    /// 0))`, its largest magnitude, and the largest magnitude of the terms it sums.
    fn residual(
        &self,
        st: &Structure,
        (bx, t): (&[f64], &[f64]),
        u: &KktSolution,
    ) -> (Vec<f64>, Vec<f64>, f64, f64) {
        let (m, n, p) = (st.m, st.n, st.p());
        let ex: Vec<f64> = (0..n)
            .map(|j| {
                let mut acc = dot(&self.v[j * m..(j + 1) * m], &u.yz);
                for (k, &r) in st.eq_rows.iter().enumerate() {
                    acc += st.e[k + j * p] * u.yz[r];
                }
                bx[j] - acc
            })
            .collect();
        // The cone rows hold by construction (W z = V x − t, and a correction keeps it to
        // rounding), so only the zero-cone rows' b_y − E x remain.
        let mut et = vec![0.0; m];
        for (k, &r) in st.eq_rows.iter().enumerate() {
            let ex_k: f64 = (0..n).map(|j| st.e[k + j * p] * u.x[j]).sum();
            et[r] = t[r] - ex_k;
        }
        let size = norm_inf(&ex).max(norm_inf(&et));
        // The magnitude of the terms summed: rounding alone leaves residuals of ε times it.
        let terms = norm_inf(bx).max(norm_inf(t)).max(
            ex.iter()
                .zip(bx)
                .map(|(e, b)| (b - e).abs())
                .fold(0.0, f64::max),
        );
        (ex, et, size, terms)
    }

    /// Solves `[0 Eᵀ Gᵀ; E 0 0; G 0 −WᵀW] (x, y, z) = (b_x, b_y, b_z)` given `t = (b_y,
    /// W⁻ᵀb_z)`, refining on the unreduced system in the scaled space (module docs).
    fn solve(&self, st: &Structure, bx: &[f64], t: &[f64]) -> KktSolution {
        let mut u = self.solve_once(st, bx, t);
        let (mut ex, mut et, mut size, terms) = self.residual(st, (bx, t), &u);
        let floor = REFINE_BELOW * terms;
        for _ in 0..MAX_REFINEMENT {
            // Also stops on NaN (no comparison holds).
            if size.partial_cmp(&floor) != Some(std::cmp::Ordering::Greater) {
                break;
            }
            let du = self.solve_once(st, &ex, &et);
            let mut next = u.clone();
            next.x.iter_mut().zip(&du.x).for_each(|(a, b)| *a += b);
            next.yz.iter_mut().zip(&du.yz).for_each(|(a, b)| *a += b);
            let (nex, net, nsize, _) = self.residual(st, (bx, t), &next);
            if nsize.partial_cmp(&size) != Some(std::cmp::Ordering::Less) {
                break;
            }
            let halved = nsize <= 0.5 * size;
            (u, ex, et, size) = (next, nex, net, nsize);
            if !halved {
                break;
            }
        }
        u
    }
}

// ---------------------------------------------------------------------------------------
// The iteration.

/// A search direction: `Δx`; `Δy` on the zero-cone rows and the scaled `Δẑ = WΔz` on the
/// cone rows of `yz`; the scaled `Δŝ = W⁻ᵀΔs`; `Δτ`, `Δκ`.
struct Direction {
    x: Vec<f64>,
    yz: Vec<f64>,
    s_hat: Vec<f64>,
    tau: f64,
    kappa: f64,
}

/// The iterate of the homogeneous embedding.
#[derive(Clone)]
struct Iterate {
    x: Vec<f64>,
    /// `y` on the zero-cone rows, `z` on the cone rows.
    zf: Vec<f64>,
    /// `s` on the cone rows (zero on the zero-cone rows).
    s: Vec<f64>,
    tau: f64,
    kappa: f64,
}

/// Residuals of the embedding at an iterate.
struct Residuals {
    /// `Eᵀy + Gᵀz + cτ`.
    x: Vec<f64>,
    /// `Ex − fτ` and `Gx + s − hτ`.
    row: Vec<f64>,
    /// `κ + cᵀx + fᵀy + hᵀz`.
    tau: f64,
}

/// The embedding's residuals at `it`.
fn residuals(st: &Structure, data: &ConicData, it: &Iterate) -> Residuals {
    let (m, n) = (st.m, st.n);
    let mut rx = vec![0.0; n];
    st.at_mul(data, &it.zf, &mut rx);
    for (r, ci) in rx.iter_mut().zip(&data.q) {
        *r += ci * it.tau;
    }
    let mut row = vec![0.0; m];
    st.a_mul(data, &it.x, &mut row);
    for i in 0..m {
        row[i] += it.s[i] - data.b[i] * it.tau;
    }
    let tau = it.kappa + dot(&data.q, &it.x) + dot(&data.b, &it.zf);
    Residuals { x: rx, row, tau }
}

/// The stopping measures of an iterate (module docs), relative to the tolerances.
#[derive(Debug, Clone, Copy)]
struct Measures {
    pres: f64,
    dres: f64,
    pcost: f64,
    /// Largest of the gap measures relative to their tolerances (≤ 1: within tolerance).
    gap_ratio: f64,
}

impl Measures {
    /// Largest ratio to the requested tolerances (≤ 1: solved).
    fn ratio(&self, s: &Settings) -> f64 {
        (self.pres / s.feasibility)
            .max(self.dres / s.feasibility)
            .max(self.gap_ratio)
    }

    /// Within the reduced tolerances.
    fn almost(&self, s: &Settings) -> bool {
        self.pres <= REDUCED_FEASIBILITY * s.feasibility
            && self.dres <= REDUCED_FEASIBILITY * s.feasibility
            && self.gap_ratio <= REDUCED_GAP
    }
}

fn outcome(status: RawStatus, it: &Iterate, m: &Measures, iterations: u32) -> Outcome {
    let inv = 1.0 / it.tau;
    Outcome {
        status,
        x: it.x.iter().map(|v| v * inv).collect(),
        z: it.zf.iter().map(|v| v * inv).collect(),
        objective: m.pcost,
        iterations,
        primal_residual: m.pres,
        dual_residual: m.dres,
    }
}

/// Ends a run that stopped short: the best iterate as almost solved if it meets the reduced
/// tolerances, else `status` with the last iterate.
fn stop_short(
    status: RawStatus,
    it: &Iterate,
    best: &Option<(Iterate, Measures)>,
    settings: &Settings,
    iterations: u32,
) -> Outcome {
    if let Some((b, m)) = best
        && m.almost(settings)
    {
        return outcome(RawStatus::AlmostSolved, b, m, iterations);
    }
    Outcome {
        status,
        x: it.x.clone(),
        z: it.zf.clone(),
        objective: f64::NAN,
        iterations,
        primal_residual: f64::NAN,
        dual_residual: f64::NAN,
    }
}

/// Solves `data` by the dense method (module docs).
pub(crate) fn solve(data: &ConicData, settings: &Settings) -> Outcome {
    let start = Instant::now();
    let (st, mut cones) = Structure::new(data);
    let (m, n) = (st.m, st.n);
    let c = &data.q;
    let b = &data.b;
    let mut it = Iterate {
        x: vec![0.0; n],
        zf: vec![0.0; m],
        s: vec![0.0; m],
        tau: 1.0,
        kappa: 1.0,
    };
    let mut best: Option<(Iterate, Measures)> = None;
    if st.degree == 0 {
        return stop_short(RawStatus::NumericalError, &it, &best, settings, 0);
    }
    let resx0 = norm(c).max(1.0);
    let resrow0 = norm(b).max(1.0);
    // An equality `0 = f_k` with |f_k| beyond the feasibility tolerance: y = −sign(f_k) e_k
    // (z = 0) is a Farkas certificate, Eᵀy + Gᵀz = 0 and fᵀy = −|f_k| < 0.
    for &r in &st.dropped_eq {
        if b[r].abs() > settings.feasibility * resrow0 {
            let mut z = vec![0.0; m];
            z[r] = -b[r].signum() / b[r].abs();
            return Outcome {
                status: RawStatus::Infeasible,
                x: vec![0.0; n],
                z,
                objective: f64::NAN,
                iterations: 0,
                primal_residual: f64::NAN,
                dual_residual: f64::NAN,
            };
        }
    }

    // Starting point (Vandenberghe 2010, §7.4): with W = I, the primal least-squares point
    // and the dual least-norm point, each shifted into the cones' interior.
    let Some(kkt) = Kkt::factor(&st, &cones) else {
        return stop_short(RawStatus::NumericalError, &it, &best, settings, 0);
    };
    let neg_c: Vec<f64> = c.iter().map(|v| -v).collect();
    // With W = I the scaled right-hand side is the plain one and W z = z.
    let primal = kkt.solve(&st, &vec![0.0; n], b);
    let dual = kkt.solve(&st, &neg_c, &vec![0.0; m]);
    it.x = primal.x;
    it.zf = dual.yz;
    for cone in &cones {
        for r in cone.rows() {
            it.s[r] = -primal.yz[r];
        }
    }
    // Only the cone rows of s and z are shifted; y stays.
    let mut finite = true;
    for v in [&mut it.s, &mut it.zf] {
        let t = cones
            .iter()
            .map(|cone| cone.violation(&v[cone.rows()]))
            .fold(f64::NEG_INFINITY, f64::max);
        let size = cones
            .iter()
            .map(|cone| norm(&v[cone.rows()]))
            .fold(0.0, f64::max)
            .max(1.0);
        finite &= t.is_finite();
        if t >= -1e-8 * size {
            for cone in &cones {
                let r = cone.rows();
                cone.add_identity(1.0 + t, &mut v[r]);
            }
        }
    }
    if !finite {
        return stop_short(RawStatus::NumericalError, &it, &best, settings, 0);
    }
    // The Nesterov–Todd scaling of the starting point (from W = I).
    for cone in cones.iter_mut() {
        let r = cone.rows();
        if !cone.update(&it.s[r.clone()], &it.zf[r]) {
            return stop_short(RawStatus::NumericalError, &it, &best, settings, 0);
        }
    }

    let mut stalls = 0;
    let mut since_best = 0;
    let mut best_progress = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let mut iteration = 0u32;
    let mut scratch = vec![0.0; m];
    loop {
        // Residuals and stopping tests.
        let res = residuals(&st, data, &it);
        let cx = dot(c, &it.x);
        let bz = dot(b, &it.zf);
        let sz: f64 = cones
            .iter()
            .map(|cone| {
                let r = cone.rows();
                dot(&it.s[r.clone()], &it.zf[r])
            })
            .sum();
        let mu = (sz + it.tau * it.kappa) / (st.degree as f64 + 1.0);
        let pcost = cx / it.tau;
        let dcost = -bz / it.tau;
        let rel_base = pcost.abs().min(dcost.abs()).max(1.0);
        let gap_measure = |g: f64| (g / settings.gap_abs).min(g / rel_base / settings.gap_rel);
        let meas = Measures {
            pres: norm(&res.row) / it.tau / resrow0,
            dres: norm(&res.x) / it.tau / resx0,
            pcost,
            gap_ratio: gap_measure((sz / (it.tau * it.tau)).abs())
                .max(gap_measure((pcost - dcost).abs())),
        };
        if !(meas.pres.is_finite() && meas.dres.is_finite() && mu.is_finite()) {
            return stop_short(RawStatus::NumericalError, &it, &best, settings, iteration);
        }
        if meas.ratio(settings) <= 1.0 {
            return outcome(RawStatus::Solved, &it, &meas, iteration);
        }
        if best
            .as_ref()
            .is_none_or(|(_, bm)| meas.ratio(settings) < bm.ratio(settings))
        {
            best = Some((it.clone(), meas));
        }
        // Infeasibility certificates: the ray's residual relative to its separation, as a
        // ratio to the tolerance (≤ 1: certified).
        let mut infeasibility_ratio = f64::INFINITY;
        if bz < 0.0 {
            // ‖Eᵀy + Gᵀz‖ = ‖r_x − cτ‖.
            let hx: Vec<f64> = res.x.iter().zip(c).map(|(r, ci)| r - ci * it.tau).collect();
            let ratio = norm(&hx) / resx0 / (-bz) / settings.infeasibility;
            if ratio <= 1.0 {
                let inv = -1.0 / bz;
                return Outcome {
                    status: RawStatus::Infeasible,
                    x: it.x.clone(),
                    z: it.zf.iter().map(|v| v * inv).collect(),
                    objective: f64::NAN,
                    iterations: iteration,
                    primal_residual: meas.pres,
                    dual_residual: meas.dres,
                };
            }
            infeasibility_ratio = ratio;
        }
        if cx < 0.0 {
            // ‖(Ex, Gx + s)‖ = ‖r_row + bτ‖.
            let hr: Vec<f64> = res
                .row
                .iter()
                .zip(b)
                .map(|(r, bi)| r + bi * it.tau)
                .collect();
            let ratio = norm(&hr) / resrow0 / (-cx) / settings.infeasibility;
            if ratio <= 1.0 {
                let inv = -1.0 / cx;
                return Outcome {
                    status: RawStatus::Unbounded,
                    x: it.x.iter().map(|v| v * inv).collect(),
                    z: it.zf.clone(),
                    objective: f64::NAN,
                    iterations: iteration,
                    primal_residual: meas.pres,
                    dual_residual: meas.dres,
                };
            }
            infeasibility_ratio = infeasibility_ratio.min(ratio);
        }
        // Progress towards either kind of answer, or along the central path; the method
        // stops without it, or once complementarity is exhausted to rounding (`μ ≤ 0`: no
        // step can improve on the best iterate).
        let (optimality, infeasibility) = (meas.ratio(settings), infeasibility_ratio);
        if optimality < PROGRESS * best_progress.0
            || infeasibility < PROGRESS * best_progress.1
            || mu < PROGRESS * best_progress.2
        {
            best_progress = (
                best_progress.0.min(optimality),
                best_progress.1.min(infeasibility),
                best_progress.2.min(mu),
            );
            since_best = 0;
        } else {
            since_best += 1;
        }
        if mu <= 0.0 || since_best >= NO_PROGRESS {
            return stop_short(
                RawStatus::InsufficientProgress,
                &it,
                &best,
                settings,
                iteration,
            );
        }
        if iteration >= settings.max_iterations {
            return stop_short(RawStatus::MaxIterations, &it, &best, settings, iteration);
        }
        if start.elapsed().as_secs_f64() > settings.time_limit {
            return stop_short(RawStatus::MaxTime, &it, &best, settings, iteration);
        }
        iteration += 1;

        // The Newton systems of this scaling.
        let Some(kkt) = Kkt::factor(&st, &cones) else {
            return stop_short(RawStatus::NumericalError, &it, &best, settings, iteration);
        };
        // The scaled right-hand sides b̂ = (f, W⁻ᵀh) and r̂ = (r_y, W⁻ᵀr_z).
        let (mut bhat, mut rhat) = (b.clone(), res.row.clone());
        for cone in &cones {
            let r = cone.rows();
            cone.w_inv_t(&b[r.clone()], &mut bhat[r.clone()]);
            cone.w_inv_t(&res.row[r.clone()], &mut rhat[r]);
        }
        // fᵀy + hᵀz = b̂ᵀ(y, Wz).
        let bz_of = |u: &KktSolution| dot(&bhat, &u.yz);
        // K (x₁, y₁, z₁) = (−c, f, h).
        let u1 = kkt.solve(&st, &neg_c, &bhat);
        let denom = dot(c, &u1.x) + bz_of(&u1) - it.kappa / it.tau;
        let newton = |beta: f64, ds: &[f64], dk: f64| -> Direction {
            // ξ = λ ◇⁻¹ d_s; right-hand side (−β r_x, −β r_y, −β W⁻ᵀr_z − ξ) (scaled rows).
            let mut xi = ds.to_vec();
            for cone in &cones {
                cone.lambda_inv_prod(&mut xi[cone.rows()]);
            }
            let bx: Vec<f64> = res.x.iter().map(|v| -beta * v).collect();
            let t: Vec<f64> = rhat.iter().zip(&xi).map(|(r, x)| -beta * r - x).collect();
            let u2 = kkt.solve(&st, &bx, &t);
            let dtau = (-beta * res.tau - dk / it.tau - (dot(c, &u2.x) + bz_of(&u2))) / denom;
            let comb = |a: &[f64], b: &[f64]| -> Vec<f64> {
                a.iter().zip(b).map(|(p, q)| p + dtau * q).collect()
            };
            let (x, yz) = (comb(&u2.x, &u1.x), comb(&u2.yz, &u1.yz));
            let mut s_hat = vec![0.0; m];
            for cone in &cones {
                for k in cone.rows() {
                    s_hat[k] = xi[k] - yz[k];
                }
            }
            Direction {
                x,
                yz,
                s_hat,
                tau: dtau,
                kappa: (dk - it.kappa * dtau) / it.tau,
            }
        };
        let max_step = |d: &Direction| -> f64 {
            let mut a = f64::INFINITY;
            for cone in &cones {
                let r = cone.rows();
                a = a
                    .min(cone.max_step(&d.s_hat[r.clone()]))
                    .min(cone.max_step(&d.yz[r]));
            }
            if d.tau < 0.0 {
                a = a.min(-it.tau / d.tau);
            }
            if d.kappa < 0.0 {
                a = a.min(-it.kappa / d.kappa);
            }
            a
        };

        // Affine (predictor) direction: d_s = −λ∘λ, d_κ = −τκ.
        let mut ds = vec![0.0; m];
        for cone in &cones {
            let r = cone.rows();
            cone.lambda_sq(&mut ds[r.clone()]);
            ds[r].iter_mut().for_each(|v| *v = -*v);
        }
        let aff = newton(1.0, &ds, -it.tau * it.kappa);
        let alpha_aff = max_step(&aff).min(1.0);
        if !alpha_aff.is_finite() {
            return stop_short(RawStatus::NumericalError, &it, &best, settings, iteration);
        }
        let sigma = (1.0 - alpha_aff).max(0.0).powi(EXPON);

        // Combined direction: d_s = −λ∘λ + σμe − Δŝ_aff ∘ Δẑ_aff, d_κ = −τκ + σμ − Δτ Δκ.
        for cone in &cones {
            let r = cone.rows();
            cone.jordan(
                &aff.s_hat[r.clone()],
                &aff.yz[r.clone()],
                &mut scratch[r.clone()],
            );
            for k in r.clone() {
                ds[k] -= scratch[k];
            }
            cone.add_identity(sigma * mu, &mut ds[r]);
        }
        let dk = -it.tau * it.kappa + sigma * mu - aff.tau * aff.kappa;
        let dir = newton(1.0 - sigma, &ds, dk);
        let alpha = (STEP * max_step(&dir)).min(1.0);
        if !alpha.is_finite() || alpha <= 0.0 {
            return stop_short(RawStatus::NumericalError, &it, &best, settings, iteration);
        }
        stalls = if alpha < MIN_STEP { stalls + 1 } else { 0 };
        if stalls >= STALL {
            return stop_short(
                RawStatus::InsufficientProgress,
                &it,
                &best,
                settings,
                iteration,
            );
        }

        // Step: x and y additively, the cones' s and z from the updated scaling.
        for (v, d) in it.x.iter_mut().zip(&dir.x) {
            *v += alpha * d;
        }
        for &r in &st.eq_rows {
            it.zf[r] += alpha * dir.yz[r];
        }
        it.tau += alpha * dir.tau;
        it.kappa += alpha * dir.kappa;
        for cone in cones.iter_mut() {
            let r = cone.rows();
            let lambda = cone.lambda_vec();
            let step = |d: &[f64]| -> Vec<f64> {
                lambda.iter().zip(d).map(|(l, x)| l + alpha * x).collect()
            };
            let (st_, zt) = (step(&dir.s_hat[r.clone()]), step(&dir.yz[r.clone()]));
            if !cone.update(&st_, &zt) {
                return stop_short(RawStatus::NumericalError, &it, &best, settings, iteration);
            }
            // s = Wᵀλ, z = W⁻¹λ: the cone iterates from the updated scaling itself, so that
            // they lie in the cone and agree with the scaling to rounding (as CVXOPT's
            // conelp does); Δs of the direction is not needed beyond the scaled step.
            let lam = cone.lambda_vec();
            cone.w_t(&lam, &mut it.s[r.clone()]);
            cone.w_inv(&lam, &mut it.zf[r]);
        }
    }
}
