//! The one-sided Jacobi SVD kernel of the workspace, real or complex, on columns of any
//! storage: fixed-size arrays on the stack (the LAPACK shim `pendulab-lapack`, for
//! Clarabel's PSD-cone scalings) or heap vectors ([`crate::linalg::svd::svd`]'s fallback).
//!
//! Algorithm: the one-sided (Hestenes) Jacobi method. The `k` columns of a working matrix
//! `W` (`rows ≥ k` entries each: `A` when `m ≥ n`, `Aᴴ` otherwise) are made mutually
//! orthogonal by plane rotations applied from the right, `W ← W J`, accumulated in
//! `V ← V J`; at convergence `W = U Σ` with `σ_j = ‖w_j‖`, and `A = U Σ Vᴴ` (M. R. Hestenes,
//! *J. SIAM* 6, 1958). Each rotation annihilates the Gram entry `γ = w_pᴴ w_q = e |γ|`
//! (`e = γ/|γ|`, the sign of `γ` for real data) of the pair with the smaller root of
//! `t² + 2ζt − 1 = 0`, `ζ = (β − α)/(2|γ|)`, `α = ‖w_p‖²`, `β = ‖w_q‖²` (Rutishauser's
//! formula): `w_p ← c w_p − s ē w_q`, `w_q ← s e w_p + c w_q` with `c = 1/√(1 + t²)`,
//! `s = c t` (for real data the classical rotation with `t·e`). A pair is rotated only while
//! `|γ| > tol √(αβ)` with `tol = √rows · ε`: that stopping rule makes the computed singular
//! values accurate to high *relative* accuracy whenever `A = B D` with `B` well conditioned
//! and `D` diagonal (J. Demmel & K. Veselić, "Jacobi's method is more accurate than QR",
//! *SIAM J. Matrix Anal. Appl.* 13, 1992), which bidiagonal QR does not guarantee. Before
//! pivot `p` is paired with the later columns, the remaining column of largest norm is
//! swapped into place (P. P. M. de Rijk, "A one-sided Jacobi algorithm for computing the
//! singular value decomposition on a vector computer", *SIAM J. Sci. Stat. Comput.* 10,
//! 1989), which speeds convergence and leaves the values nearly sorted. The squared column
//! norms are tracked through `α' = α − t|γ|`, `β' = β + t|γ|` and recomputed at every sweep
//! and whenever an update lost more than four bits to cancellation (a safeguard in the
//! spirit of LAPACK's `xGESVJ`, which also recomputes norms after cancellation).
//!
//! `W` is first scaled exactly, by a power of two, so that its largest entry is near 1.
//! Columns that end zero (rank-deficient input; a column whose squared norm underflows is
//! flushed to zero first, since its direction is lost) get unit vectors orthogonal to the
//! others (Gram–Schmidt, twice), so `U` always has orthonormal columns; the same completion
//! extends the left factor to a square unitary matrix on request (LAPACK's `'A'` jobs).
//!
//! With columns of compile-time length (`[T; R]`) the sweeps run without bounds checks or
//! allocation; the kernel itself never allocates.

use nalgebra::{ComplexField, RealField};

/// Sweep limit: convergence is quadratic and takes 5–8 sweeps in practice; LAPACK's
/// `xGESVJ` also stops at 30. Non-convergence makes [`one_sided_jacobi`] return false.
pub const MAX_SWEEPS: usize = 30;

/// The real types the kernel works in (`f64`, `f32`): what it needs beyond
/// [`RealField`] to scale its working matrix exactly.
pub trait JacobiReal: RealField + Copy {
    /// The smallest positive normal number.
    const MIN_POSITIVE: Self;
    /// The machine epsilon (the gap between 1 and the next larger number).
    const EPSILON: Self;

    /// `2^round(log₂ x)` for finite `x > 0`, the exponent clamped to the normal range: a
    /// scale factor that divides exactly.
    fn power_of_two_near(x: Self) -> Self;
}

impl JacobiReal for f64 {
    const MIN_POSITIVE: Self = f64::MIN_POSITIVE;
    const EPSILON: Self = f64::EPSILON;
    fn power_of_two_near(x: Self) -> Self {
        2f64.powi((x.log2().round() as i32).clamp(-1022, 1023))
    }
}

impl JacobiReal for f32 {
    const MIN_POSITIVE: Self = f32::MIN_POSITIVE;
    const EPSILON: Self = f32::EPSILON;
    fn power_of_two_near(x: Self) -> Self {
        2f32.powi((x.log2().round() as i32).clamp(-126, 127))
    }
}

/// The entry types the kernel works on: `f64`, `f32` and their complex counterparts
/// (any [`ComplexField`] that is `Copy` and whose real type is a [`JacobiReal`]).
pub trait JacobiScalar: ComplexField<RealField: JacobiReal> + Copy {}

impl<T: ComplexField<RealField: JacobiReal> + Copy> JacobiScalar for T {}

/// `Σ conj(x_i) y_i` over equal-length slices.
#[inline(always)]
fn dotc<T: JacobiScalar>(x: &[T], y: &[T]) -> T {
    x.iter()
        .zip(y)
        .fold(T::zero(), |s, (p, q)| s + p.conjugate() * *q)
}

/// `Σ |x_i|²`.
#[inline(always)]
fn squared_norm<T: JacobiScalar>(x: &[T]) -> T::RealField {
    x.iter().fold(nalgebra::zero::<T::RealField>(), |s, p| {
        s + p.modulus_squared()
    })
}

/// `‖x‖₂` without harmful underflow: the plain sum of squares where it is safely normal,
/// otherwise the sum of squares of `x / max|x_i|` (the scaling idea of LAPACK's `xNRM2`).
fn norm<T>(x: &[T]) -> T::RealField
where
    T: JacobiScalar,
{
    let ss = squared_norm(x);
    if ss.is_finite() && ss >= T::RealField::MIN_POSITIVE / T::RealField::EPSILON {
        return ss.sqrt();
    }
    let amax = x
        .iter()
        .fold(nalgebra::zero::<T::RealField>(), |m, v| m.max(v.modulus()));
    if amax == nalgebra::zero::<T::RealField>() || !amax.is_finite() {
        return amax;
    }
    let ss = x.iter().fold(nalgebra::zero::<T::RealField>(), |s, v| {
        s + v.unscale(amax).modulus_squared()
    });
    amax * ss.sqrt()
}

/// `‖x‖²`, or 0 after zeroing `x` when that is below `negligible`.
#[inline(always)]
fn squared_norm_or_flush<T: JacobiScalar>(x: &mut [T], negligible: T::RealField) -> T::RealField {
    let d = squared_norm(x);
    if d < negligible {
        x.iter_mut().for_each(|v| *v = T::zero());
        nalgebra::zero::<T::RealField>()
    } else {
        d
    }
}

/// Two distinct columns `p < q`, both mutable.
#[inline(always)]
fn pair<C>(cols: &mut [C], p: usize, q: usize) -> (&mut C, &mut C) {
    let (head, tail) = cols.split_at_mut(q);
    (&mut head[p], &mut tail[0])
}

/// `x ← c x − sē y`, `y ← se x + c y` on two columns of equal length.
#[inline(always)]
fn rotate<T: JacobiScalar>(x: &mut [T], y: &mut [T], c: T::RealField, se: T) {
    let sec = se.conjugate();
    for (xi, yi) in x.iter_mut().zip(y.iter_mut()) {
        let (xp, xq) = (*xi, *yi);
        *xi = xp.scale(c) - sec * xq;
        *yi = se * xp + xq.scale(c);
    }
}

/// The SVD of the working matrix `W` held in the first `k = s.len()` columns of `w` (each
/// of the same length `rows ≥ k`), in place, by one-sided Jacobi (module documentation).
///
/// On success `w[..k]` holds `U` (orthonormal columns), `s` the singular values
/// `σ₁ ≥ … ≥ σ_k ≥ 0`, and, when given, `v` (`k` columns of length `≥ k`, overwritten with
/// the identity first) the unitary `V` of `W = U diag(s) Vᴴ`; the columns `k..complete` of
/// `w` (`k ≤ complete ≤ min(rows, w.len())`) are overwritten with unit vectors completing
/// `U` to orthonormal columns (`complete = rows` gives a square unitary `U`). False, with
/// `w`, `v` and `s` in an unspecified state, if an entry of `W` is not finite or the sweeps
/// did not converge within [`MAX_SWEEPS`].
pub fn one_sided_jacobi<T, C>(
    w: &mut [C],
    mut v: Option<&mut [C]>,
    s: &mut [T::RealField],
    complete: usize,
) -> bool
where
    T: JacobiScalar,
    C: AsRef<[T]> + AsMut<[T]>,
{
    let k = s.len();
    let rows = w.first().map_or(0, |c| c.as_ref().len());
    // The scale of the largest entry.
    let mut amax = nalgebra::zero::<T::RealField>();
    for x in w[..k].iter().flat_map(|c| c.as_ref()) {
        if !x.is_finite() {
            return false;
        }
        amax = amax.max(x.modulus());
    }
    // Scale W exactly (by a power of two) so that its largest entry is near 1: the squared
    // norms then neither overflow nor underflow except for columns negligible next to ‖A‖
    // (see `negligible` below); Σ is scaled back at the end.
    let one = nalgebra::one::<T::RealField>();
    let zero = nalgebra::zero::<T::RealField>();
    let scale = if amax > zero {
        T::RealField::power_of_two_near(amax)
    } else {
        one
    };
    if scale != one {
        for x in w[..k].iter_mut().flat_map(|c| c.as_mut()) {
            *x = x.unscale(scale);
        }
    }
    if let Some(v) = v.as_deref_mut() {
        for (j, vj) in v[..k].iter_mut().enumerate() {
            let vj = vj.as_mut();
            vj.iter_mut().for_each(|x| *x = T::zero());
            vj[j] = T::one();
        }
    }
    let eps = T::RealField::EPSILON;
    let tol = eps * nalgebra::convert::<f64, T::RealField>(rows as f64).sqrt();
    let cancelled: T::RealField = nalgebra::convert(1.0 / 16.0);
    // A column whose squared norm is below this has lost its direction to underflow and
    // cannot be orthogonalised: it is set to zero (a perturbation below √(MIN_POSITIVE/ε)
    // ≈ 1e-146 ‖A‖ in f64, 3e-16 ‖A‖ in f32, W being scaled to max |w_ij| ≈ 1) and
    // completed at the end like an exactly zero column.
    let negligible = T::RealField::MIN_POSITIVE / eps;
    let big_zeta = one / eps;
    let half: T::RealField = nalgebra::convert(0.5);
    // The squared column norms live in `s` during the sweeps.
    let d = &mut *s;
    let mut converged = k < 2;
    for _ in 0..MAX_SWEEPS {
        if converged {
            break;
        }
        for (dj, wj) in d.iter_mut().zip(w.iter_mut()) {
            *dj = squared_norm_or_flush(wj.as_mut(), negligible);
        }
        let mut rotated = false;
        for p in 0..k - 1 {
            // de Rijk: bring the remaining column of largest norm to position p.
            let best = largest_from(d, p);
            if best != p {
                d.swap(p, best);
                w.swap(p, best);
                if let Some(v) = v.as_deref_mut() {
                    v.swap(p, best);
                }
            }
            for q in p + 1..k {
                let (alpha, beta) = (d[p], d[q]);
                if alpha == zero || beta == zero {
                    continue;
                }
                let (wp, wq) = pair(w, p, q);
                let (wp, wq) = (wp.as_mut(), wq.as_mut());
                let gamma = dotc(wp, wq);
                let g = gamma.modulus();
                if g <= tol * (alpha * beta).sqrt() {
                    continue;
                }
                rotated = true;
                let e = gamma.unscale(g);
                let zeta = (beta - alpha) / (g + g);
                let t = if zeta.abs() > big_zeta {
                    // 1/(|ζ| + √(1 + ζ²)) → 1/(2|ζ|) without squaring a huge ζ.
                    half / zeta
                } else {
                    let r = one / (zeta.abs() + (one + zeta * zeta).sqrt());
                    if zeta < zero { -r } else { r }
                };
                let c = one / (one + t * t).sqrt();
                let se = e.scale(c * t);
                rotate(wp, wq, c, se);
                if let Some(v) = v.as_deref_mut() {
                    let (vp, vq) = pair(v, p, q);
                    rotate(vp.as_mut(), vq.as_mut(), c, se);
                }
                let tg = t * g;
                d[p] = alpha - tg;
                d[q] = beta + tg;
                if d[p] < cancelled * alpha {
                    d[p] = squared_norm_or_flush(wp, negligible);
                }
                if d[q] < cancelled * beta {
                    d[q] = squared_norm_or_flush(wq, negligible);
                }
            }
        }
        converged = !rotated;
    }
    if !converged {
        return false;
    }
    // σ_j = ‖w_j‖, u_j = w_j / σ_j.
    for (sj, wj) in s.iter_mut().zip(w.iter_mut()) {
        let wj = wj.as_mut();
        let sigma = norm(wj);
        if sigma > zero {
            wj.iter_mut().for_each(|x| *x = x.unscale(sigma));
        }
        *sj = sigma;
    }
    // Descending order (selection sort with the matching column swaps).
    for p in 0..k {
        let best = largest_from(s, p);
        if best != p {
            s.swap(p, best);
            w.swap(p, best);
            if let Some(v) = v.as_deref_mut() {
                v.swap(p, best);
            }
        }
    }
    // Zero columns (they sort last), and the columns k..complete: unit vectors orthogonal to
    // the columns before them.
    for j in 0..complete.max(k) {
        if j >= k || s[j] == zero {
            complete_column(w, j);
        }
    }
    if scale != one {
        s.iter_mut().for_each(|x| *x *= scale);
    }
    true
}

/// Index of the largest of `d[p..]` (the first one on ties).
#[inline(always)]
fn largest_from<R: RealField + Copy>(d: &[R], p: usize) -> usize {
    let mut best = p;
    for j in p + 1..d.len() {
        if d[j] > d[best] {
            best = j;
        }
    }
    best
}

/// Replaces column `j` of `w` by a unit vector orthogonal to columns `0..j` (assumed
/// orthonormal, `j < rows`): of the standard basis vectors, the one whose component
/// orthogonal to them is largest (at least `√((rows − j)/rows)`), orthogonalised by classical
/// Gram–Schmidt applied twice ("twice is enough", Giraud et al. 2005).
fn complete_column<T, C>(w: &mut [C], j: usize)
where
    T: JacobiScalar,
    C: AsRef<[T]> + AsMut<[T]>,
{
    let (done, rest) = w.split_at_mut(j);
    let col = rest[0].as_mut();
    let rows = col.len();
    let one = nalgebra::one::<T::RealField>();
    // ‖(I − Q Qᴴ) e_i‖² = 1 − Σ_c |Q(i, c)|²: pick the largest.
    let mut best = 0;
    let mut best_res = nalgebra::zero::<T::RealField>() - one;
    for i in 0..rows {
        let res = one
            - done.iter().fold(nalgebra::zero::<T::RealField>(), |s, q| {
                s + q.as_ref()[i].modulus_squared()
            });
        if res > best_res {
            best_res = res;
            best = i;
        }
    }
    col.iter_mut().for_each(|x| *x = T::zero());
    col[best] = T::one();
    for _ in 0..2 {
        for q in done.iter() {
            let q = q.as_ref();
            let h = dotc(q, col);
            for (x, y) in col.iter_mut().zip(q) {
                *x -= *y * h;
            }
        }
    }
    let nrm = norm(col);
    col.iter_mut().for_each(|x| *x = x.unscale(nrm));
}
