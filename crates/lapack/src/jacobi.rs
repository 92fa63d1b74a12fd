//! Allocation-free singular value decomposition of small matrices by one-sided Jacobi
//! rotations, the path the SVD drivers take for Clarabel's PSD-cone scalings.
//!
//! Algorithm: the one-sided (Hestenes) Jacobi method. For `m ≥ n` the columns of a working
//! copy `W` of `A` are made mutually orthogonal by plane rotations applied from the right,
//! `W ← W J`, accumulated in `V ← V J`; at convergence `W = U Σ` with `σ_j = ‖w_j‖`, and
//! `A = U Σ Vᵀ` (M. R. Hestenes, *J. SIAM* 6, 1958). Each rotation annihilates the Gram
//! entry `γ = w_pᵀ w_q` of the pair with the smaller root of `t² + 2ζt − 1 = 0`,
//! `ζ = (β − α)/(2γ)`, `α = ‖w_p‖²`, `β = ‖w_q‖²` (Rutishauser's formula), and a pair is
//! rotated only while `|γ| > tol √(αβ)` with `tol = √m ε`: that stopping rule makes the
//! computed singular values accurate to high *relative* accuracy whenever `A = B D` with
//! `B` well conditioned and `D` diagonal (J. Demmel & K. Veselić, "Jacobi's method is more
//! accurate than QR", *SIAM J. Matrix Anal. Appl.* 13, 1992), which bidiagonal QR does not
//! guarantee. Before pivot `p` is paired with the later columns, the remaining column of
//! largest norm is swapped into place (P. P. M. de Rijk, "A one-sided Jacobi algorithm for
//! computing the singular value decomposition on a vector computer", *SIAM J. Sci. Stat.
//! Comput.* 10, 1989), which speeds convergence and leaves the values nearly sorted. The
//! squared column norms are tracked through `α' = α − tγ`, `β' = β + tγ` and recomputed at
//! every sweep and whenever an update lost more than four bits to cancellation (a safeguard
//! in the spirit of LAPACK's `xGESVJ`, which also recomputes norms after cancellation).
//!
//! For `m < n` the method runs on `Aᵀ = Ū Σ V̄ᵀ`, so that `U = V̄` and `Vᵀ = Ūᵀ`. Columns that
//! end zero (rank-deficient input; a column whose squared norm underflows is flushed to zero
//! first, since its direction is lost) get unit vectors orthogonal to the others
//! (Gram–Schmidt, twice), so `U` always has orthonormal columns as LAPACK promises; the
//! same completion extends the left factor to a square orthogonal matrix for the `'A'` jobs.
//!
//! Cost: with the columns' length a compile-time constant the sweeps run without bounds
//! checks or allocation. Measured with callgrind on random square matrices (`dgesdd_`, job
//! `'S'`, whole call): about 11 k / 17 k / 62 k instructions for sides 5 / 6 / 10, against
//! 26 k / 35 k / 85 k for nalgebra's bidiagonal QR on heap matrices; on the textbook's LMI
//! LQ servo (sides 5, 6, 10) the average call went from 25 k to 16 k. At sides 20 and 30
//! (the SOS gain-scheduling design) Jacobi takes about 7 % more instructions than
//! nalgebra's QR (505 k vs 470 k, 1.43 M vs 1.34 M) but is used there too: nalgebra's SVD
//! can return wrong singular values when vectors are requested (nalgebra issue #1172).

use crate::Real;

/// Largest `max(m, n)` the Jacobi path takes (the working arrays live on the stack).
pub(crate) const MAX_SIDE: usize = 32;

/// Sweep limit: convergence is quadratic and takes 5–8 sweeps in practice; LAPACK's
/// `xGESVJ` also stops at 30. Non-convergence makes [`jacobi_svd`] return false.
const MAX_SWEEPS: usize = 30;

/// The SVD `A = U diag(s) Vᵀ` (`k = min(m, n)` values, descending) computed by
/// [`jacobi_svd`], as views of its working arrays (handed to the caller's sink).
pub(crate) struct Factors<'a, T> {
    /// Rows of the working matrix (`max(m, n)`), the stride of `w` and `v`.
    rows: usize,
    /// Whether the method ran on `Aᵀ` (`m < n`).
    transposed: bool,
    /// `Ū` (`rows × k`, or `rows × rows` when completed; column-major, stride `rows`).
    w: &'a [T],
    /// `V̄` (`k × k`, stride `rows`); zeros unless accumulated.
    v: &'a [T],
    /// The singular values, descending.
    pub(crate) s: &'a [T],
}

impl<T: Real> Factors<'_, T> {
    /// `U(i, j)`, `0 ≤ i < m`, `0 ≤ j < k` (`< m` when `U` was completed).
    #[inline]
    pub(crate) fn u(&self, i: usize, j: usize) -> T {
        if self.transposed {
            self.v[i + j * self.rows]
        } else {
            self.w[i + j * self.rows]
        }
    }

    /// `Vᵀ(i, j)`, `0 ≤ i < k` (`< n` when `V` was completed), `0 ≤ j < n`.
    #[inline]
    pub(crate) fn vt(&self, i: usize, j: usize) -> T {
        if self.transposed {
            self.w[j + i * self.rows]
        } else {
            self.v[j + i * self.rows]
        }
    }
}

/// `Σ x_i y_i` over equal-length slices.
#[inline]
fn dot<T: Real>(x: &[T], y: &[T]) -> T {
    x.iter().zip(y).fold(T::zero(), |s, (p, q)| s + *p * *q)
}

/// `‖x‖₂` without harmful underflow: the plain sum of squares where it is safely normal,
/// otherwise the sum of squares of `x / max|x_i|` (the scaling idea of LAPACK's `xNRM2`).
fn norm<T: Real>(x: &[T]) -> T {
    let ss = dot(x, x);
    if ss.is_finite() && ss >= T::MIN_POSITIVE / T::default_epsilon() {
        return ss.sqrt();
    }
    let amax = x.iter().fold(T::zero(), |m, v| m.max(v.abs()));
    if amax == T::zero() || !amax.is_finite() {
        return amax;
    }
    let ss = x.iter().fold(T::zero(), |s, v| {
        let t = *v / amax;
        s + t * t
    });
    amax * ss.sqrt()
}

/// SVD of the `m × n` column-major array `a` (leading dimension `lda`), `1 ≤ m, n ≤`
/// [`MAX_SIDE`], by one-sided Jacobi (module documentation), handed to `sink`. `want_v` asks
/// for the accumulation of the right factor of the working matrix (needed for `Vᵀ` when
/// `m ≥ n`, for `U` when `m < n`). `full` extends the working matrix's left factor to a
/// square orthogonal one (LAPACK's `'A'` jobs: `U` is then `m × m` when `m > n`, `Vᵀ` is
/// `n × n` when `m < n`). False (and `sink` not called) if the input is not finite or the
/// sweeps did not converge.
pub(crate) fn jacobi_svd<T: Real>(
    (m, n): (usize, usize),
    (a, lda): (&[T], usize),
    (want_v, full): (bool, bool),
    sink: impl FnOnce(Factors<'_, T>),
) -> bool {
    // The working columns have exactly `max(m, n)` entries: a compile-time length lets the
    // compiler unroll and vectorise the dot products and rotations.
    macro_rules! dispatch {
        ($($size:literal)*) => {
            match m.max(n) {
                $($size => sweep::<T, $size>((m, n), (a, lda), (want_v, full), sink),)*
                _ => false,
            }
        };
    }
    dispatch!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32)
}

/// `Σ x_i y_i` over two columns of length `R`.
#[inline(always)]
fn dot_r<T: Real, const R: usize>(x: &[T; R], y: &[T; R]) -> T {
    let mut s = T::zero();
    for i in 0..R {
        s += x[i] * y[i];
    }
    s
}

/// `[x y] ← [x y] [c s; −s c]` on two columns of length `R`.
#[inline(always)]
fn rotate_r<T: Real, const R: usize>(x: &mut [T; R], y: &mut [T; R], c: T, s: T) {
    for i in 0..R {
        let (xp, xq) = (x[i], y[i]);
        x[i] = c * xp - s * xq;
        y[i] = s * xp + c * xq;
    }
}

/// `‖x‖²`, or 0 after zeroing `x` when that is below `negligible`.
#[inline(always)]
fn squared_norm_or_flush<T: Real, const R: usize>(x: &mut [T; R], negligible: T) -> T {
    let d = dot_r(x, x);
    if d < negligible {
        *x = [T::zero(); R];
        T::zero()
    } else {
        d
    }
}

/// Two distinct columns `p < q` of a column array, both mutable.
#[inline(always)]
fn pair<T, const R: usize>(cols: &mut [[T; R]], p: usize, q: usize) -> (&mut [T; R], &mut [T; R]) {
    let (head, tail) = cols.split_at_mut(q);
    (&mut head[p], &mut tail[0])
}

/// [`jacobi_svd`] for `max(m, n) = R`. The right factor is kept with `R` rows too (the rows
/// beyond `k` stay zero), so both rotations run on columns of the same fixed length.
fn sweep<T: Real, const R: usize>(
    (m, n): (usize, usize),
    (a, lda): (&[T], usize),
    (want_v, full): (bool, bool),
    sink: impl FnOnce(Factors<'_, T>),
) -> bool {
    let transposed = m < n;
    let k = m.min(n);
    let mut w_all = [[T::zero(); R]; R];
    let mut v = [[T::zero(); R]; R];
    let w = &mut w_all;
    // W = A or Aᵀ (R × k); the scale of its largest entry.
    let mut amax = T::zero();
    for j in 0..n {
        for i in 0..m {
            let x = a[i + j * lda];
            if !x.is_finite() {
                return false;
            }
            amax = amax.max(x.abs());
            if transposed {
                w[i][j] = x;
            } else {
                w[j][i] = x;
            }
        }
    }
    // Scale W exactly (by a power of two) so that its largest entry is near 1: the squared
    // norms then neither overflow nor underflow except for columns negligible next to ‖A‖
    // (see `negligible` below); Σ is scaled back at the end.
    let scale = if amax > T::zero() {
        T::power_of_two_near(amax)
    } else {
        T::one()
    };
    if scale != T::one() {
        w.iter_mut().flatten().for_each(|x| *x /= scale);
    }
    if want_v {
        for (j, vj) in v[..k].iter_mut().enumerate() {
            vj[j] = T::one();
        }
    }
    let w = &mut w[..k];
    let v = &mut v[..k];
    let eps = T::default_epsilon();
    let tol = eps * nalgebra::convert::<f64, T>(R as f64).sqrt();
    let cancelled: T = nalgebra::convert(1.0 / 16.0);
    // A column whose squared norm is below this has lost its direction to underflow and
    // cannot be orthogonalised: it is set to zero (a perturbation below √(MIN_POSITIVE/ε)
    // ≈ 1e-146 ‖A‖ in f64, 3e-16 ‖A‖ in f32, W being scaled to max |w_ij| ≈ 1) and
    // completed at the end like an exactly zero column.
    let negligible = T::MIN_POSITIVE / eps;
    let big_zeta = T::one() / eps;
    let half: T = nalgebra::convert(0.5);
    let mut d = [T::zero(); R];
    let d = &mut d[..k];
    let mut converged = k < 2;
    for _ in 0..MAX_SWEEPS {
        if converged {
            break;
        }
        for (dj, wj) in d.iter_mut().zip(w.iter_mut()) {
            *dj = squared_norm_or_flush(wj, negligible);
        }
        let mut rotated = false;
        for p in 0..k - 1 {
            // de Rijk: bring the remaining column of largest norm to position p.
            let mut best = p;
            for j in p + 1..k {
                if d[j] > d[best] {
                    best = j;
                }
            }
            if best != p {
                d.swap(p, best);
                w.swap(p, best);
                v.swap(p, best);
            }
            for q in p + 1..k {
                let (alpha, beta) = (d[p], d[q]);
                if alpha == T::zero() || beta == T::zero() {
                    continue;
                }
                let (wp, wq) = pair(w, p, q);
                let gamma = dot_r(wp, wq);
                if gamma.abs() <= tol * (alpha * beta).sqrt() {
                    continue;
                }
                rotated = true;
                let zeta = (beta - alpha) / (gamma + gamma);
                let t = if zeta.abs() > big_zeta {
                    // 1/(|ζ| + √(1 + ζ²)) → 1/(2|ζ|) without squaring a huge ζ.
                    half / zeta
                } else {
                    let r = T::one() / (zeta.abs() + (T::one() + zeta * zeta).sqrt());
                    if zeta < T::zero() { -r } else { r }
                };
                let c = T::one() / (T::one() + t * t).sqrt();
                let s = c * t;
                rotate_r(wp, wq, c, s);
                if want_v {
                    let (vp, vq) = pair(v, p, q);
                    rotate_r(vp, vq, c, s);
                }
                let tg = t * gamma;
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
    let mut s = [T::zero(); R];
    let s = &mut s[..k];
    for (sj, wj) in s.iter_mut().zip(w.iter_mut()) {
        let sigma = norm(wj);
        if sigma > T::zero() {
            wj.iter_mut().for_each(|x| *x /= sigma);
        }
        *sj = sigma;
    }
    // Descending order (selection sort with the matching column swaps).
    for p in 0..k {
        let mut best = p;
        for j in p + 1..k {
            if s[j] > s[best] {
                best = j;
            }
        }
        if best != p {
            s.swap(p, best);
            w.swap(p, best);
            v.swap(p, best);
        }
    }
    // Zero columns (they sort last), and for `full` the columns beyond k: unit vectors
    // orthogonal to the columns before them.
    let last = if full { R } else { k };
    for j in 0..last {
        if j >= k || s[j] == T::zero() {
            complete_column(w_all.as_flattened_mut(), R, j);
        }
    }
    if scale != T::one() {
        s.iter_mut().for_each(|x| *x *= scale);
    }
    sink(Factors {
        rows: R,
        transposed,
        w: w_all.as_flattened(),
        v: v.as_flattened(),
        s,
    });
    true
}

/// Replaces column `j` of the `rows`-row array `w` by a unit vector orthogonal to columns
/// `0..j` (assumed orthonormal, `j < rows`): of the standard basis vectors, the one whose
/// component orthogonal to them is largest (at least `√((rows − j)/rows)`), orthogonalised
/// by classical Gram–Schmidt applied twice ("twice is enough", Giraud et al. 2005).
fn complete_column<T: Real>(w: &mut [T], rows: usize, j: usize) {
    let (done, rest) = w.split_at_mut(j * rows);
    let col = &mut rest[..rows];
    // ‖(I − Q Qᵀ) e_i‖² = 1 − Σ_c Q(i, c)²: pick the largest.
    let mut best = 0;
    let mut best_res = T::zero() - T::one();
    for i in 0..rows {
        let res = T::one()
            - (0..j).fold(T::zero(), |s, c| {
                let q = done[i + c * rows];
                s + q * q
            });
        if res > best_res {
            best_res = res;
            best = i;
        }
    }
    col.iter_mut().for_each(|x| *x = T::zero());
    col[best] = T::one();
    for _ in 0..2 {
        for c in 0..j {
            let q = &done[c * rows..(c + 1) * rows];
            let h = dot(q, col);
            for (x, y) in col.iter_mut().zip(q) {
                *x -= h * *y;
            }
        }
    }
    let nrm = norm(col);
    col.iter_mut().for_each(|x| *x /= nrm);
}
