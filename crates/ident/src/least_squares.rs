//! Linear least squares `min_p ‖M p − N‖₂` by Householder QR, never the normal equations.
//!
//! The regressor `M` (n × p, n ≫ p) and the target `N` are streamed through a
//! [`QrAccumulator`] in blocks of rows: the triangular factor of the augmented matrix
//! `[M | N]` is updated by Householder reflections applied to `[R; block]` (the sequential
//! form of TSQR — J. Demmel, L. Grigori, M. Hoemmen, J. Langou, *SIAM J. Sci. Comput.* 34
//! (2012) A206 — with each block kept in cache, so the data is read once). At the end
//! `[M | N] = Q [[R, Qᵀ N], [0, ρ]]` gives the estimate `p = R⁻¹ (Qᵀ N)`, the residual norm
//! `‖M p − N‖ = |ρ|` and, since `MᵀM = RᵀR`, the covariance `σ² R⁻¹ R⁻ᵀ` with
//! `σ² = ρ²/(n − p)` — without ever forming `MᵀM` (whose condition number is the square of
//! `M`'s). The 2-norm condition number of `M` equals that of `R` (an SVD of a p × p matrix).
//!
//! The standard errors assume independent residuals of equal variance. Residuals of filtered
//! and differentiated data are correlated over a few filter time constants, so on such data
//! the standard errors are optimistic (by roughly the square root of the correlation length in
//! samples); they remain useful to compare estimates and to spot poorly excited parameters.

use crate::error::{IdentError, Result};
use nalgebra::DMatrix;

/// Rows per block: 256 rows × (p+1) columns stay in the first-level cache for p ≤ 7.
pub(crate) const BLOCK: usize = 256;

/// Largest column-scaled condition number of a regressor whose estimate is accepted:
/// `ε^(−1/2) = 2²⁶ ≈ 6.7·10⁷` (ε = 2⁻⁵², the f64 machine epsilon).
///
/// Why this bound. The first-order perturbation bound of least squares (Golub & Van Loan,
/// *Matrix Computations*, 4th ed., Thm. 5.3.1) for relative perturbations δ of `M` and `N` is
/// `‖Δp‖/‖p‖ ≤ δ (2κ/cos θ + κ² tan θ)`, where `κ` is the condition number and `θ` the
/// angle between `N` and its fit (`tan θ = ‖residual‖/‖fit‖`). Identification data always
/// leave a residual (quantisation, noise, unmodelled friction), so the `κ² tan θ` term
/// governs: at `κ = ε^(−1/2)` even the rounding of the data alone (δ = ε) moves the estimate
/// by `tan θ` of itself — by 100 % once the residual is as large as the fit — and measured
/// data, whose relative noise δ is orders of magnitude above ε, lose every digit well before
/// that. It is also where the normal equations `MᵀM` (condition `κ²`) stop carrying any
/// digit at all. The rank test of [`QrAccumulator::finish`] (`1/(n ε)`, NumPy's
/// `matrix_rank` tolerance) decides whether a solution exists at all; this bound decides
/// whether it means anything. The book's regressions on the rig data are far inside it
/// (scaled condition numbers of a few: `pendulab identify cart-ls` prints it).
pub const MAX_CONDITION: f64 = 67_108_864.0;

/// The solution of a linear least-squares problem and its diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct LeastSquares {
    /// Regressor column names (the parameter names).
    pub names: Vec<String>,
    /// The estimate `p̂` minimising `‖M p − N‖₂`.
    pub estimate: Vec<f64>,
    /// Standard errors `σ √((MᵀM)⁻¹)_ii`, `σ² = ‖M p̂ − N‖²/(n − p)`.
    pub std_error: Vec<f64>,
    /// Parameter covariance `σ² (MᵀM)⁻¹` (p × p, row-major rows).
    pub covariance: Vec<Vec<f64>>,
    /// Residual norm `‖M p̂ − N‖₂`.
    pub residual_norm: f64,
    /// Root-mean-square residual `‖M p̂ − N‖₂ / √n`.
    pub residual_rms: f64,
    /// 2-norm condition number `σ_max(M)/σ_min(M)`.
    pub condition: f64,
    /// Condition number after scaling every column of `M` to unit norm (the measure the rank
    /// decision uses, independent of the columns' units).
    pub scaled_condition: f64,
    /// Number of rows (samples) n.
    pub samples: usize,
}

impl LeastSquares {
    /// Checks that the solution means something: every estimate, standard error and the
    /// condition numbers are finite, and the column-scaled condition number is at most
    /// [`MAX_CONDITION`].
    ///
    /// # Errors
    /// [`IdentError::NonFiniteResult`] naming the first non-finite number;
    /// [`IdentError::IllConditioned`] with the condition numbers and the bound.
    pub fn check(&self) -> Result<()> {
        for (i, name) in self.names.iter().enumerate() {
            for (what, v) in [
                (name.clone(), self.estimate[i]),
                (format!("standard error of {name}"), self.std_error[i]),
            ] {
                if !v.is_finite() {
                    return Err(IdentError::NonFiniteResult {
                        what,
                        value: v,
                        reason: "the least-squares solution overflowed: the data are scaled far \
                                 outside the model's units (SI: m, rad, V, s) or degenerate"
                            .into(),
                    });
                }
            }
        }
        for (what, v) in [
            ("condition number of the regressor", self.condition),
            (
                "scaled condition number of the regressor",
                self.scaled_condition,
            ),
        ] {
            if !v.is_finite() {
                return Err(IdentError::NonFiniteResult {
                    what: what.into(),
                    value: v,
                    reason: "the regressor is numerically singular (too few or degenerate samples)"
                        .into(),
                });
            }
        }
        if self.scaled_condition > MAX_CONDITION {
            return Err(IdentError::IllConditioned {
                columns: self.names.clone(),
                condition: self.condition,
                scaled_condition: self.scaled_condition,
                limit: MAX_CONDITION,
            });
        }
        Ok(())
    }

    /// The estimate of the parameter called `name`, if there is one.
    pub fn get(&self, name: &str) -> Option<(f64, f64)> {
        let i = self.names.iter().position(|n| n == name)?;
        Some((self.estimate[i], self.std_error[i]))
    }
}

/// Streaming Householder QR of `[M | N]` (see the module documentation).
#[derive(Debug, Clone)]
pub struct QrAccumulator {
    names: Vec<String>,
    target: String,
    /// Upper-triangular (p+1) × (p+1) factor, row-major.
    r: Vec<f64>,
    rows: usize,
    /// Column-major block buffer, BLOCK × (p+1).
    buf: Vec<f64>,
}

impl QrAccumulator {
    /// An accumulator for regressor columns called `names` and a target called `target`.
    ///
    /// # Errors
    /// [`IdentError::InvalidParameter`] for no regressor column.
    pub fn new(names: &[&str], target: &str) -> Result<Self> {
        if names.is_empty() {
            return Err(IdentError::InvalidParameter {
                name: "regressor columns".into(),
                value: 0.0,
                reason: "at least one column is needed".into(),
            });
        }
        let w = names.len() + 1;
        Ok(Self {
            names: names.iter().map(|s| s.to_string()).collect(),
            target: target.to_string(),
            r: vec![0.0; w * w],
            rows: 0,
            buf: vec![0.0; BLOCK * w],
        })
    }

    /// Rows accumulated so far.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Adds the rows `columns[j][k]`, `target[k]` (all slices of one length).
    ///
    /// # Errors
    /// [`IdentError::LengthMismatch`] for a column count other than the names' or slices of
    /// different lengths; [`IdentError::NonFinite`] naming the column and the row (counted
    /// over everything pushed so far).
    pub fn push(&mut self, columns: &[&[f64]], target: &[f64]) -> Result<()> {
        let p = self.names.len();
        if columns.len() != p {
            return Err(IdentError::LengthMismatch {
                source_name: "least squares".into(),
                column: "regressor columns".into(),
                expected: p,
                found: columns.len(),
            });
        }
        let n = target.len();
        for (name, c) in self.names.iter().zip(columns) {
            if c.len() != n {
                return Err(IdentError::LengthMismatch {
                    source_name: "least squares".into(),
                    column: name.clone(),
                    expected: n,
                    found: c.len(),
                });
            }
        }
        let mut start = 0;
        while start < n {
            let m = (n - start).min(BLOCK);
            self.load_block(columns, target, start, m)?;
            self.reduce_block(m);
            self.rows += m;
            start += m;
        }
        Ok(())
    }

    fn load_block(
        &mut self,
        columns: &[&[f64]],
        target: &[f64],
        start: usize,
        m: usize,
    ) -> Result<()> {
        let p = self.names.len();
        let mut finite = true;
        for j in 0..=p {
            let src = if j < p {
                &columns[j][start..start + m]
            } else {
                &target[start..start + m]
            };
            let dst = &mut self.buf[j * BLOCK..j * BLOCK + m];
            dst.copy_from_slice(src);
            finite &= dst.iter().all(|v| v.is_finite());
        }
        if finite {
            return Ok(());
        }
        for j in 0..=p {
            let col = &self.buf[j * BLOCK..j * BLOCK + m];
            if let Some(k) = col.iter().position(|v| !v.is_finite()) {
                return Err(IdentError::NonFinite {
                    source_name: "least squares".into(),
                    column: if j < p {
                        self.names[j].clone()
                    } else {
                        self.target.clone()
                    },
                    at: crate::error::SamplePos::index(self.rows + k),
                    value: col[k],
                });
            }
        }
        Ok(())
    }

    /// Householder reduction of `[R; B]` (R upper triangular (p+1)², B the m loaded rows).
    fn reduce_block(&mut self, m: usize) {
        let w = self.names.len() + 1;
        reduce(&mut self.r, w, &mut self.buf, BLOCK, m);
    }

    /// Folds in `m ≤ BLOCK` rows held column by column in `block` (regressors then target),
    /// using `block` as scratch (it is overwritten). The caller guarantees finite values.
    pub(crate) fn push_scratch<const W: usize>(&mut self, block: &mut [[f64; BLOCK]; W], m: usize) {
        debug_assert_eq!(W, self.names.len() + 1);
        let m = m.min(BLOCK);
        reduce_fused::<W>(&mut self.r, block, m);
        self.rows += m;
    }

    /// Solves the accumulated problem.
    ///
    /// # Errors
    /// [`IdentError::TooFewSamples`] with `n ≤ p` rows (no residual degree of freedom);
    /// [`IdentError::RankDeficient`] if a column is zero or the column-scaled condition
    /// number exceeds `1/(max(n, p) ε)` (NumPy's `matrix_rank` tolerance), naming the
    /// (nearly) dependent combination of columns.
    pub fn finish(self) -> Result<LeastSquares> {
        let p = self.names.len();
        let w = p + 1;
        let n = self.rows;
        if n <= p {
            return Err(IdentError::TooFewSamples {
                source_name: "least squares".into(),
                what: format!("a least-squares fit of {p} parameters"),
                needed: p + 1,
                found: n,
            });
        }
        if let Some(k) = self.r.iter().position(|v| !v.is_finite()) {
            return Err(IdentError::NonFinite {
                source_name: "least squares".into(),
                column: if k % w < p {
                    self.names[k % w].clone()
                } else {
                    self.target.clone()
                },
                at: crate::error::SamplePos::index(n),
                value: self.r[k],
            });
        }
        let r = DMatrix::from_fn(p, p, |i, j| if j >= i { self.r[i * w + j] } else { 0.0 });
        let qtb: Vec<f64> = (0..p).map(|i| self.r[i * w + p]).collect();
        let rho = self.r[p * w + p].abs();
        // Column norms of M are those of R.
        let col_norms: Vec<f64> = (0..p).map(|j| r.column(j).norm()).collect();
        let zero: Vec<String> = (0..p)
            .filter(|&j| col_norms[j] == 0.0)
            .map(|j| format!("'{}'", self.names[j]))
            .collect();
        if !zero.is_empty() {
            return Err(IdentError::RankDeficient {
                columns: self.names.clone(),
                condition: f64::INFINITY,
                scaled_condition: f64::INFINITY,
                limit: rank_limit(n, p),
                detail: if zero.len() == 1 {
                    format!("the column of {} is identically zero", zero[0])
                } else {
                    format!("the columns of {} are identically zero", zero.join(" and "))
                },
            });
        }
        let sv = r.clone().svd(false, false).singular_values;
        let condition = sv.max() / sv.min();
        let scaled = DMatrix::from_fn(p, p, |i, j| r[(i, j)] / col_norms[j]);
        let ssvd = pendulab_lti::linalg::svd::svd(&scaled);
        let (smax, smin) = (ssvd.singular_values.max(), ssvd.singular_values.min());
        let scaled_condition = smax / smin;
        let limit = rank_limit(n, p);
        if scaled_condition.is_nan() || scaled_condition > limit {
            let vt = &ssvd.v_t;
            let k = ssvd.singular_values.imin();
            let involved: Vec<String> = (0..p)
                .filter(|&j| vt[(k, j)].abs() > 0.05)
                .map(|j| format!("'{}'", self.names[j]))
                .collect();
            let weights: Vec<String> = (0..p).map(|j| format!("{:.3}", vt[(k, j)])).collect();
            return Err(IdentError::RankDeficient {
                columns: self.names.clone(),
                condition,
                scaled_condition,
                limit,
                detail: format!(
                    "the columns of {} are (nearly) linearly dependent (null direction of the \
                     scaled regressor: [{}])",
                    involved.join(", "),
                    weights.join(", ")
                ),
            });
        }
        // Back substitution R p = Qᵀb, and R⁻¹ for the covariance.
        let mut est = vec![0.0; p];
        for i in (0..p).rev() {
            let mut acc = qtb[i];
            for k in i + 1..p {
                acc -= r[(i, k)] * est[k];
            }
            est[i] = acc / r[(i, i)];
        }
        let mut rinv = DMatrix::<f64>::zeros(p, p);
        for c in 0..p {
            for i in (0..=c).rev() {
                let mut acc = if i == c { 1.0 } else { 0.0 };
                for k in i + 1..=c {
                    acc -= r[(i, k)] * rinv[(k, c)];
                }
                rinv[(i, c)] = acc / r[(i, i)];
            }
        }
        let sigma2 = rho * rho / (n - p) as f64;
        let cov = &rinv * rinv.transpose() * sigma2;
        Ok(LeastSquares {
            names: self.names,
            std_error: (0..p).map(|i| cov[(i, i)].sqrt()).collect(),
            covariance: (0..p)
                .map(|i| (0..p).map(|j| cov[(i, j)]).collect())
                .collect(),
            estimate: est,
            residual_norm: rho,
            residual_rms: rho / (n as f64).sqrt(),
            condition,
            scaled_condition,
            samples: n,
        })
    }
}

/// Householder reduction of `[R; B]`: `r` the (w × w, row-major) upper-triangular factor, `buf`
/// the `m` new rows as `w` columns of stride `stride` (overwritten).
fn reduce(r: &mut [f64], w: usize, buf: &mut [f64], stride: usize, m: usize) {
    for j in 0..w {
        let (head, tail) = buf.split_at_mut((j + 1) * stride);
        let bj = &head[j * stride..j * stride + m];
        let sq = dot(bj, bj);
        let Some((alpha, v0, tau)) = reflector(r[j * w + j], bj, sq) else {
            continue;
        };
        for c in j + 1..w {
            let bc = &mut tail[(c - j - 1) * stride..(c - j - 1) * stride + m];
            let s = tau * (v0 * r[j * w + c] + dot(bj, bc));
            r[j * w + c] -= s * v0;
            for (b, a) in bc.iter_mut().zip(bj) {
                *b -= s * a;
            }
        }
        r[j * w + j] = alpha;
    }
}

/// [`reduce`] for a block of `W` columns known at compile time, with the passes over the block
/// fused: for each pivot column `j` one pass forms all the dot products `b_jᵀ b_c` (`c ≥ j`)
/// and one pass applies the reflector to all the later columns, so each pivot column is read
/// twice instead of `2(W − j) − 1` times. Every sum is accumulated in the same order as
/// [`dot`] (four partial sums over the rows `4i + l`, then the tail), and every update is the
/// same operation, so the result equals [`reduce`]'s bit for bit.
fn reduce_fused<const W: usize>(r: &mut [f64], buf: &mut [[f64; BLOCK]; W], m: usize) {
    let m = m.min(BLOCK);
    if W > 4 {
        reduce(r, W, buf.as_flattened_mut(), BLOCK, m);
        return;
    }
    pivot::<W, 0>(r, buf, m);
    pivot::<W, 1>(r, buf, m);
    pivot::<W, 2>(r, buf, m);
    pivot::<W, 3>(r, buf, m);
}

/// Pivot column `J` of [`reduce_fused`] (nothing if `J ≥ W`); `J` and `W` are constants so the
/// loops over the columns unroll and the passes over the rows vectorise.
#[inline(always)]
fn pivot<const W: usize, const J: usize>(r: &mut [f64], buf: &mut [[f64; BLOCK]; W], m: usize) {
    if J >= W {
        return;
    }
    let chunks = m / 4;
    // dots[c] = b_Jᵀ b_c for c ≥ J, four partial sums each.
    let mut acc = [[0.0f64; 4]; W];
    {
        let quads: [&[[f64; 4]]; W] = std::array::from_fn(|c| buf[c][..4 * chunks].as_chunks().0);
        for i in 0..chunks {
            let a = quads[J][i];
            for c in J..W {
                let b = quads[c][i];
                for l in 0..4 {
                    acc[c][l] += a[l] * b[l];
                }
            }
        }
    }
    let mut dots = [0.0f64; W];
    for c in J..W {
        let mut tail = 0.0;
        for i in 4 * chunks..m {
            tail += buf[J][i] * buf[c][i];
        }
        let a = acc[c];
        dots[c] = (a[0] + a[1]) + (a[2] + a[3]) + tail;
    }
    let Some((alpha, v0, tau)) = reflector(r[J * W + J], &buf[J][..m], dots[J]) else {
        return;
    };
    let mut s = [0.0f64; W];
    for c in J + 1..W {
        s[c] = tau * (v0 * r[J * W + c] + dots[c]);
        r[J * W + c] -= s[c] * v0;
    }
    let (head, tail) = buf.split_at_mut(J + 1);
    let bj = &head[J];
    for (k, bc) in tail.iter_mut().enumerate() {
        let sc = s[J + 1 + k];
        for (b, a) in bc[..m].iter_mut().zip(&bj[..m]) {
            *b -= sc * a;
        }
    }
    r[J * W + J] = alpha;
}

/// The Householder reflector `H = I − τ v vᵀ` that maps `[R_jj; b_j]` onto `α e₁`:
/// `(α, v₀, τ)` with `α = −sign(R_jj)‖·‖` (no cancellation in `v₀ = R_jj − α`),
/// `τ = 1/(α(α − R_jj))` (from `vᵀv = 2α(α − R_jj)`); `None` if `b_j = 0` (nothing to do).
#[inline]
fn reflector(rjj: f64, bj: &[f64], sq: f64) -> Option<(f64, f64, f64)> {
    if sq == 0.0 {
        return None;
    }
    let norm = stable_norm(rjj, bj, sq);
    let alpha = if rjj >= 0.0 { -norm } else { norm };
    Some((alpha, rjj - alpha, 1.0 / (alpha * (alpha - rjj))))
}

/// Dot product with four partial sums (independent chains that pipeline and vectorise).
#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 4];
    let chunks = n / 4;
    for i in 0..chunks {
        for l in 0..4 {
            acc[l] += a[4 * i + l] * b[4 * i + l];
        }
    }
    let mut tail = 0.0;
    for i in 4 * chunks..n {
        tail += a[i] * b[i];
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Largest column-scaled condition number accepted for `n` rows and `p` columns.
fn rank_limit(n: usize, p: usize) -> f64 {
    1.0 / (n.max(p) as f64 * f64::EPSILON)
}

/// ‖[a; b]‖ given `sq = ‖b‖²`, rescaling when the plain sum over- or underflowed.
fn stable_norm(a: f64, b: &[f64], sq: f64) -> f64 {
    let plain = (a * a + sq).sqrt();
    if plain.is_finite() && plain > 1e-150 {
        return plain;
    }
    let scale = b.iter().fold(a.abs(), |m, v| m.max(v.abs()));
    let s: f64 = b.iter().map(|v| (v / scale).powi(2)).sum::<f64>() + (a / scale).powi(2);
    scale * s.sqrt()
}

/// Solves `min_p ‖Σ_j p_j columns[j] − target‖₂` by Householder QR (see the module docs).
///
/// `columns` pairs each regressor column with its name (the parameter's name); `target` pairs
/// the target with its name (used in error messages).
///
/// # Errors
/// As [`QrAccumulator::push`] and [`QrAccumulator::finish`].
#[doc(alias = "lstsq")]
#[doc(alias = "mldivide")]
pub fn least_squares(columns: &[(&str, &[f64])], target: (&str, &[f64])) -> Result<LeastSquares> {
    let names: Vec<&str> = columns.iter().map(|c| c.0).collect();
    let cols: Vec<&[f64]> = columns.iter().map(|c| c.1).collect();
    let mut acc = QrAccumulator::new(&names, target.0)?;
    acc.push(&cols, target.1)?;
    acc.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_fit_and_streaming_equals_one_shot() {
        // y = 2 x1 − 3 x2 exactly: estimate exact, residual ~0.
        let x1: Vec<f64> = (0..1000).map(|k| (k as f64 * 0.01).sin()).collect();
        let x2: Vec<f64> = (0..1000).map(|k| 1.0 + (k as f64 * 0.013).cos()).collect();
        let y: Vec<f64> = x1.iter().zip(&x2).map(|(a, b)| 2.0 * a - 3.0 * b).collect();
        let ls = least_squares(&[("a", &x1), ("b", &x2)], ("y", &y)).unwrap();
        assert!((ls.estimate[0] - 2.0).abs() < 1e-12 && (ls.estimate[1] + 3.0).abs() < 1e-12);
        assert!(ls.residual_rms < 1e-12);
        // Pushing in uneven pieces gives the same factorisation up to rounding.
        let mut acc = QrAccumulator::new(&["a", "b"], "y").unwrap();
        for (s, e) in [(0, 7), (7, 300), (300, 1000)] {
            acc.push(&[&x1[s..e], &x2[s..e]], &y[s..e]).unwrap();
        }
        let ls2 = acc.finish().unwrap();
        assert!((ls2.estimate[0] - 2.0).abs() < 1e-12);
        assert!((ls2.condition - ls.condition).abs() < 1e-10 * ls.condition);
    }

    #[test]
    fn fused_reduction_equals_plain_bit_for_bit() {
        // The fused passes promise the plain reduction's arithmetic exactly: same triangular
        // factor bit for bit, for a full block and a short one with a tail (m mod 4 ≠ 0).
        let block = |seed: f64| -> [[f64; BLOCK]; 3] {
            std::array::from_fn(|c| {
                std::array::from_fn(|k| ((k as f64 + 1.0) * (0.37 + c as f64) + seed).sin())
            })
        };
        let mut r_plain = vec![0.0; 9];
        let mut r_fused = vec![0.0; 9];
        for (seed, m) in [(0.1, BLOCK), (2.3, 203), (4.1, 1)] {
            let mut a = block(seed);
            let mut b = a;
            reduce(&mut r_plain, 3, a.as_flattened_mut(), BLOCK, m);
            reduce_fused::<3>(&mut r_fused, &mut b, m);
            assert_eq!(r_plain, r_fused, "block of {m} rows");
        }
        assert!(r_plain[0] != 0.0);
    }

    #[test]
    fn max_condition_is_the_inverse_square_root_of_epsilon() {
        assert_eq!(MAX_CONDITION, 1.0 / f64::EPSILON.sqrt());
    }

    /// `M = [u, u + δ w]` with orthonormal `u`, `w`: with its columns scaled to unit norm the
    /// Gram matrix is `[[1, c], [c, 1]]`, `c = 1/√(1 + δ²)`, so the scaled condition number is
    /// `√((1 + c)/(1 − c))` in closed form (≈ 2/δ for small δ).
    fn near_dependent(delta: f64, n: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>, f64) {
        let u: Vec<f64> = (0..n)
            .map(|k| (if k % 2 == 0 { 1.0 } else { -1.0 }) / (n as f64).sqrt())
            .collect();
        let w: Vec<f64> = (0..n)
            .map(|k| (if (k / 2) % 2 == 0 { 1.0 } else { -1.0 }) / (n as f64).sqrt())
            .collect();
        assert!(dot(&u, &w).abs() < 1e-15 && (dot(&w, &w) - 1.0).abs() < 1e-15);
        let x2: Vec<f64> = u.iter().zip(&w).map(|(a, b)| a + delta * b).collect();
        // A target with a residual (θ ≠ 0): y = u + x2 + 0.1 r, r ⟂ u, w.
        let y: Vec<f64> = (0..n)
            .map(|k| u[k] + x2[k] + 0.1 * (if k % 4 == 1 || k % 4 == 2 { 1.0 } else { -1.0 }))
            .collect();
        let c = 1.0 / (1.0 + delta * delta).sqrt();
        // 1 − c = δ²/(√(1+δ²)(1 + √(1+δ²))), written without cancellation.
        let s = (1.0 + delta * delta).sqrt();
        let one_minus_c = delta * delta / (s * (1.0 + s));
        (u, x2, y, ((1.0 + c) / one_minus_c).sqrt())
    }

    #[test]
    fn condition_bound_separates_determined_from_undetermined() {
        let n = 400;
        // δ = 1e-5: κ ≈ 2e5, inside the bound; the reported κ is the closed form's to the
        // accuracy of the smallest singular value (relative error ~ κ ε ≈ 5e-11; 1e-8).
        let (u, x2, y, kappa) = near_dependent(1e-5, n);
        let ls = least_squares(&[("a", &u), ("b", &x2)], ("y", &y)).unwrap();
        assert!(
            (ls.scaled_condition / kappa - 1.0).abs() < 1e-8,
            "{} vs {kappa}",
            ls.scaled_condition
        );
        ls.check().unwrap();
        // δ = 2e-9: κ ≈ 1e9, over MAX_CONDITION but under the rank limit 1/(n ε) ≈ 1.1e13:
        // solved, then refused. κ is computed to ~κ ε ≈ 2e-7 relative; 1e-4.
        let (u, x2, y, kappa) = near_dependent(2e-9, n);
        assert!(kappa > MAX_CONDITION && kappa < 1.0 / (n as f64 * f64::EPSILON));
        let ls = least_squares(&[("a", &u), ("b", &x2)], ("y", &y)).unwrap();
        assert!(
            (ls.scaled_condition / kappa - 1.0).abs() < 1e-4,
            "{} vs {kappa}",
            ls.scaled_condition
        );
        let e = ls.check().unwrap_err();
        assert!(
            matches!(&e, IdentError::IllConditioned { limit, .. } if *limit == MAX_CONDITION),
            "{e}"
        );
        assert!(e.to_string().contains("badly conditioned"), "{e}");
        // An exact dependence (x2 = −2 x1) is not solved at all.
        let x1: Vec<f64> = (0..n).map(|k| (k as f64 * 0.1).sin()).collect();
        let dep: Vec<f64> = x1.iter().map(|v| -2.0 * v).collect();
        assert!(matches!(
            least_squares(&[("a", &x1), ("b", &dep)], ("y", &y)),
            Err(IdentError::RankDeficient { .. })
        ));
        // A non-finite standard error (overflowed covariance) is refused by name.
        let mut bad = ls.clone();
        bad.std_error[1] = f64::NAN;
        bad.scaled_condition = 1.0;
        let e = bad.check().unwrap_err();
        assert!(
            matches!(&e, IdentError::NonFiniteResult { what, .. } if what == "standard error of b"),
            "{e}"
        );
    }

    #[test]
    fn rank_deficiency_is_an_error() {
        let x1: Vec<f64> = (0..100).map(|k| k as f64).collect();
        let x2: Vec<f64> = x1.iter().map(|v| -2.0 * v).collect();
        let zero = vec![0.0; 100];
        let y = vec![1.0; 100];
        let e = least_squares(&[("a", &x1), ("b", &x2)], ("y", &y)).unwrap_err();
        assert!(matches!(e, IdentError::RankDeficient { .. }), "{e}");
        let e = least_squares(&[("a", &x1), ("v", &zero)], ("y", &y)).unwrap_err();
        assert!(e.to_string().contains("'v' is identically zero"), "{e}");
        let e = least_squares(&[("a", &x1[..1])], ("y", &y[..1])).unwrap_err();
        assert!(matches!(e, IdentError::TooFewSamples { .. }));
        let mut bad = x1.clone();
        bad[37] = f64::NAN;
        let e = least_squares(&[("a", &bad)], ("y", &y)).unwrap_err();
        assert!(
            matches!(&e, IdentError::NonFinite { column, at, .. } if column == "a" && at.index == 37)
        );
    }
}
