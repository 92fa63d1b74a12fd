//! LQ regulators of a single-input system with a diagonal state weight by the symmetric root
//! locus (Chang–Letov): [`SymmetricRootLocus`].
//!
//! ## Method
//! For `ẋ = Ax + bu` (one input), `Q = diag(q) ⪰ 0` and `R = r > 0`, write
//! `a(s) = det(sI − A)` and `n(s) = adj(sI − A) b` (so `(sI − A)⁻¹b = n(s)/a(s)`, one
//! numerator polynomial `n_i` per state). The return-difference equality of the optimal gain
//! (Kalman, "When is a linear control system optimal?", J. Basic Eng. 86, 1964; Kwakernaak &
//! Sivan, *Linear Optimal Control Systems*, 1972, §3.8) makes the closed-loop characteristic
//! polynomial `c(s) = det(sI − A + bK) = a(s) + Σ k_i n_i(s)` the stable spectral factor of
//!
//! ```text
//! c(s) c(−s) = a(s) a(−s) + (1/r) Σ q_i n_i(s) n_i(−s),
//! ```
//!
//! so the closed-loop poles are the left-half-plane roots of `r·(right side)`, an even
//! polynomial `P(s²)` with `P` of degree `n`, and the gain solves the `n × n` linear system
//! `N k = c − a` in the numerators' coefficients (`N` is nonsingular exactly when `(A, b)` is
//! controllable). Once per `(A, b)`, [`SymmetricRootLocus::new`] forms `a` (from the
//! eigenvalues of `A`), the numerators (by `n_{j−1} = A n_j + a_j b` from `n_{n−1} = b`, the
//! coefficients of `adj(sI − A) b`), the products `a(s)a(−s)`, `n_i(s)n_i(−s)` and `N⁻¹`.
//! Per weight, [`SymmetricRootLocus::solve`] takes `O(n²)` operations: `P` as a weighted sum,
//! its roots by the Ehrlich–Aberth iteration (Aberth, "Iteration methods for finding all zeros
//! of a polynomial simultaneously", Math. Comp. 27, 1973) from the roots of a nearby problem
//! (the caller's start poles squared, typically the previous slider position's), `c` from the
//! stable square roots and `k = N⁻¹(c − a)`.
//!
//! This serves a caller that solves one small problem at a time from cold caches, the
//! browser lab's slider moves (`docs/web.md`, "Redesign time"): a few hundred flops in a few
//! short loops instead of a Riccati solve's Lyapunov equations and eigenvalue iteration.
//!
//! ## Accuracy and refusal
//! The polynomial representation can be badly conditioned (widely spread or clustered poles,
//! a badly scaled `A`), so a result is returned only with a small first-order forward error
//! bound; otherwise [`SymmetricRootLocus::solve`] returns `None` and the caller uses a Riccati
//! solver ([`care_compact_from`](crate::equations::riccati::care_compact_from),
//! [`lqr`](super::lqr)). The bound combines
//! - the relative error `η` of `a` and `N`, measured once: the larger of `2nε` times the
//!   coefficients of `Π(s + |λ_j|)` over those of `a` (the expansion from the eigenvalues
//!   `λ_j` of `A`) and the relative residual of the recursion's last equation
//!   `A n_0 + a_0 b = 0` (Cayley–Hamilton applied to `b`), at least `8nε`;
//! - each root's condition: coefficient errors `|δP_k| ≤ u |P|_k` (`|P|` the same sums of
//!   absolute values, `u = max(4nε, 2η)`) move a simple root `w` by at most
//!   `u Σ|P|_k|w|^k / |P'(w)|`; the iteration must end with every correction within twice
//!   that bound and the roots apart by more than ten times the sum of their bounds;
//! - `c` from the stable roots `p_j = −√w_j`: relative pole errors `ρ` change its
//!   coefficients by at most `2nρ` times those of `Π(s + |p_j|)`;
//! - `‖δk‖₁ ≤ ‖N⁻¹‖₁ (2nρ ‖Π(s + |p_j|)‖₁ + η (‖a‖₁ + ‖N‖₁ ‖k‖₁) + nε ‖c − a‖₁)`, accepted
//!   when at most [`SRL_TOLERANCE`]` · ‖k‖₁`.
//!
//! A root `w` within its bound of the non-positive real axis (a closed-loop pole on the
//! imaginary axis: `Q` does not see an imaginary-axis mode), a pole right of
//! `−√ε · max|p_j|`, a root without its conjugate, and anything non-finite are refused too.

use crate::error::{LtiError, Result};
use crate::linalg::{Complex64, Mat, check_finite, eigenvalues, norm1, sort_eigenvalues};
use crate::polynomial::Polynomial;

/// The largest state dimension [`SymmetricRootLocus`] accepts.
pub const SRL_MAX: usize = 6;

/// [`SymmetricRootLocus::solve`]'s acceptance bound on the gain's relative forward error
/// (1-norm; module documentation).
pub const SRL_TOLERANCE: f64 = 1e-9;

/// The Ehrlich–Aberth iteration's sweep limit.
const MAX_SWEEPS: usize = 12;

const W: usize = SRL_MAX + 1;

/// `e^{iφ}` for the golden angle `φ = π(3 − √5)` (`cos φ`, `sin φ` to double precision).
const GOLDEN: Complex64 = Complex64::new(-0.737_368_878_078_319_7, 0.675_490_294_261_523_8);

/// `|z|` without `hypot` (whose code a cold call would fetch; the moduli here are far from
/// overflow).
fn modulus(z: Complex64) -> f64 {
    z.norm_sqr().sqrt()
}

/// The principal square root (`Re ≥ 0`) in real arithmetic, without the polar form's
/// trigonometric functions: `t = √((|x| + |z|)/2)`, then `(t, y/2t)` for `x ≥ 0` and
/// `(|y|/2t, ±t)` otherwise (no cancellation either way).
fn principal_sqrt(z: Complex64) -> Complex64 {
    let (x, y) = (z.re, z.im);
    let t = ((x.abs() + modulus(z)) / 2.0).sqrt();
    if t == 0.0 {
        Complex64::new(0.0, 0.0)
    } else if x >= 0.0 {
        Complex64::new(t, y / (2.0 * t))
    } else {
        Complex64::new(y.abs() / (2.0 * t), t.copysign(y))
    }
}

/// The weight-independent part of single-input LQ designs on one `(A, b)` (module
/// documentation): build once with [`SymmetricRootLocus::new`], solve per weight with
/// [`SymmetricRootLocus::solve`].
#[derive(Debug, Clone, PartialEq)]
pub struct SymmetricRootLocus {
    n: usize,
    /// `a(s)`, ascending powers (`a[n] = 1`).
    a: [f64; W],
    /// `a(s)a(−s)` as a polynomial in `w = s²` (ascending), and its absolute-value sums.
    e0: [f64; W],
    e0_abs: [f64; W],
    /// `n_i(s)n_i(−s)` in `w` per state `i` (row `i`, ascending), and absolute-value sums.
    e: [[f64; W]; SRL_MAX],
    e_abs: [[f64; W]; SRL_MAX],
    /// `N⁻¹` (`n × n`, row-major): `k = N⁻¹(c − a)` over the coefficients of `s⁰ … sⁿ⁻¹`.
    n_inv: [f64; SRL_MAX * SRL_MAX],
    n_inv_norm: f64,
    a_norm: f64,
    n_norm: f64,
    eta: f64,
}

/// An accepted [`SymmetricRootLocus::solve`]: the gain and the closed-loop poles.
#[derive(Debug, Clone, PartialEq)]
pub struct SrlSolution {
    n: usize,
    gain: [f64; SRL_MAX],
    poles: [Complex64; SRL_MAX],
    /// The first-order bound on `‖δk‖₁ / ‖k‖₁` the result was accepted with (module
    /// documentation), at most [`SRL_TOLERANCE`].
    pub error_bound: f64,
    /// Ehrlich–Aberth sweeps taken.
    pub sweeps: usize,
}

impl SrlSolution {
    /// The gain `K` (`1 × n`; the control law `u = −K x`).
    pub fn gain(&self) -> &[f64] {
        &self.gain[..self.n]
    }

    /// The closed-loop poles `eig(A − bK)`, in the order of [`sort_eigenvalues`]; conjugate
    /// pairs are exact conjugates.
    pub fn poles(&self) -> &[Complex64] {
        &self.poles[..self.n]
    }
}

/// Coefficients of `p(s)p(−s)` in `w = s²` (ascending; the odd powers of the even product
/// vanish; `p` ascending), or with `abs` the same sums of absolute values (the error bounds'
/// `|P|`).
fn mirror_product(p: &[f64], abs: bool) -> [f64; W] {
    let mut out = [0.0; W];
    for (i, &x) in p.iter().enumerate() {
        for (j, &y) in p.iter().enumerate() {
            if (i + j) % 2 == 0 {
                let v = x * y * if j % 2 == 1 { -1.0 } else { 1.0 };
                out[(i + j) / 2] += if abs { v.abs() } else { v };
            }
        }
    }
    out
}

/// `Σ |vᵢ|`: a vector's (or a coefficient list's) 1-norm.
fn sum_abs(v: &[f64]) -> f64 {
    v.iter().map(|x| x.abs()).sum()
}

/// Ascending coefficients of a polynomial with the given roots (conjugate-closed).
fn ascending_from_roots(roots: &[Complex64]) -> Result<Vec<f64>> {
    let mut c = Polynomial::from_roots(roots)?.coefficients().to_vec();
    c.reverse();
    Ok(c)
}

impl SymmetricRootLocus {
    /// The weight-independent part for `A` (`n × n`, row-major) and `b` (`n` entries),
    /// `1 ≤ n ≤` [`SRL_MAX`] (module documentation).
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] for slices that do not fit `n`; [`LtiError::NonFinite`]
    /// for a non-finite entry; [`LtiError::NoConvergence`] when `A`'s eigenvalues cannot be
    /// computed; [`LtiError::Singular`] when the numerator matrix `N` is singular to working
    /// precision (`(A, b)` not controllable, or nearly so).
    pub fn new(a: &[f64], b: &[f64], n: usize) -> Result<Self> {
        if !(1..=SRL_MAX).contains(&n) || a.len() != n * n || b.len() != n {
            return Err(LtiError::InvalidArgument(format!(
                "SymmetricRootLocus needs A n×n and b with n entries, 1 ≤ n ≤ {SRL_MAX}; got n = {n}, {} and {} entries",
                a.len(),
                b.len()
            )));
        }
        let am = Mat::from_row_slice(n, n, a);
        check_finite("A", &am)?;
        check_finite("b", &Mat::from_row_slice(n, 1, b))?;
        let lambda = eigenvalues(&am)?;
        let mut ac = [0.0; W];
        ac[..=n].copy_from_slice(&ascending_from_roots(&lambda)?);
        let abs_roots: Vec<Complex64> = lambda
            .iter()
            .map(|l| Complex64::new(-l.norm(), 0.0))
            .collect();
        let eps = f64::EPSILON;
        let a_norm = sum_abs(&ac[..=n]);
        let eta_a = 2.0 * n as f64 * eps * sum_abs(&ascending_from_roots(&abs_roots)?) / a_norm;

        // n_{n−1} = b, n_{j−1} = A n_j + a_j b; numerators[j][i] is the coefficient of sʲ in n_i.
        let mut numerators = [[0.0; SRL_MAX]; SRL_MAX];
        numerators[n - 1][..n].copy_from_slice(b);
        let times_a_plus = |v: &[f64; SRL_MAX], c: f64| {
            let mut out = [0.0; SRL_MAX];
            for (i, o) in out[..n].iter_mut().enumerate() {
                *o = (0..n).map(|p| a[i * n + p] * v[p]).sum::<f64>() + c * b[i];
            }
            out
        };
        for j in (1..n).rev() {
            numerators[j - 1] = times_a_plus(&numerators[j], ac[j]);
        }
        let last = times_a_plus(&numerators[0], ac[0]);
        let scale = norm1(&am) * sum_abs(&numerators[0][..n]) + ac[0].abs() * sum_abs(b);
        let residual = sum_abs(&last[..n]);
        let eta_n = if residual == 0.0 {
            0.0
        } else {
            residual / scale
        };
        let eta = (8.0 * n as f64 * eps).max(eta_a).max(eta_n);

        let mut nm = Mat::zeros(n, n);
        let (mut e, mut e_abs) = ([[0.0; W]; SRL_MAX], [[0.0; W]; SRL_MAX]);
        for i in 0..n {
            let ni: Vec<f64> = (0..n).map(|j| numerators[j][i]).collect();
            for (j, v) in ni.iter().enumerate() {
                nm[(j, i)] = *v;
            }
            e[i] = mirror_product(&ni, false);
            e_abs[i] = mirror_product(&ni, true);
        }
        let n_norm = norm1(&nm);
        let singular = |rcond: f64| LtiError::Singular {
            what: "the numerator matrix N of (sI − A)⁻¹b ((A, b) not controllable)".into(),
            rcond,
        };
        let inv = nm.try_inverse().ok_or_else(|| singular(0.0))?;
        let n_inv_norm = norm1(&inv);
        let rcond = 1.0 / (n_norm * n_inv_norm);
        if rcond.is_nan() || rcond <= n as f64 * eps {
            return Err(singular(if rcond.is_nan() { 0.0 } else { rcond }));
        }
        let mut n_inv = [0.0; SRL_MAX * SRL_MAX];
        for i in 0..n {
            for j in 0..n {
                n_inv[i * n + j] = inv[(i, j)];
            }
        }
        Ok(Self {
            n,
            a: ac,
            e0: mirror_product(&ac[..=n], false),
            e0_abs: mirror_product(&ac[..=n], true),
            e,
            e_abs,
            n_inv,
            n_inv_norm,
            a_norm,
            n_norm,
            eta,
        })
    }

    /// The LQ gain for `Q = diag(q)`, `R = r` and its closed-loop poles, by the iteration
    /// from `start` (`n` poles of a nearby problem, e.g. the previous weights' closed loop;
    /// module documentation). `Ok(None)` when the result cannot be certified to
    /// [`SRL_TOLERANCE`] (a start too far for the sweep limit, a badly conditioned problem, a
    /// closed-loop pole on or near the imaginary axis): the caller then solves the Riccati
    /// equation.
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] when `q` or `start` has not `n` entries, an entry of `q`
    /// is negative or not finite, `r` is not finite and positive, or a start pole is not
    /// finite.
    pub fn solve(&self, q: &[f64], r: f64, start: &[Complex64]) -> Result<Option<SrlSolution>> {
        let n = self.n;
        let finite_start = start.iter().all(|p| p.re.is_finite() && p.im.is_finite());
        let weights = q.iter().all(|v| v.is_finite() && *v >= 0.0) && r.is_finite() && r > 0.0;
        if q.len() != n || start.len() != n || !finite_start || !weights {
            return Err(LtiError::InvalidArgument(format!(
                "SymmetricRootLocus::solve needs {n} finite weights q ≥ 0, a finite r > 0 and {n} finite start poles; got q = {q:?}, r = {r}, start = {start:?}"
            )));
        }
        let eps = f64::EPSILON;
        // r·(a(s)a(−s)) + Σ q_i n_i(s)n_i(−s) = P(s²).
        let (mut p, mut pa) = ([0.0; W], [0.0; W]);
        for k in 0..=n {
            p[k] = r * self.e0[k];
            pa[k] = r * self.e0_abs[k];
            for i in 0..n {
                p[k] += q[i] * self.e[i][k];
                pa[k] += q[i] * self.e_abs[i][k];
            }
        }
        let u = (4.0 * n as f64 * eps).max(2.0 * self.eta);

        // Ehrlich–Aberth on P from the start poles squared, each moved by a relative 10⁻³ in
        // its own direction (steps of the golden angle): conjugate starts kept exactly
        // symmetric could never split into two real roots.
        let mut w = [Complex64::new(0.0, 0.0); SRL_MAX];
        let mut turn = Complex64::new(1e-3, 0.0);
        for (wj, s) in w.iter_mut().zip(start) {
            turn *= GOLDEN;
            *wj = s * s * (1.0 + turn);
        }
        let mut err = [0.0; SRL_MAX];
        let mut sweeps = 0;
        loop {
            if sweeps == MAX_SWEEPS {
                return Ok(None);
            }
            sweeps += 1;
            let (mut done, mut close) = (true, false);
            for j in 0..n {
                let z = w[j];
                let (mut v, mut d) = (Complex64::new(p[n], 0.0), Complex64::new(0.0, 0.0));
                let (az, mut va) = (modulus(z), pa[n]);
                for k in (0..n).rev() {
                    d = d * z + v;
                    v = v * z + p[k];
                    va = va * az + pa[k];
                }
                err[j] = u * va / modulus(d);
                let mut sum = Complex64::new(0.0, 0.0);
                for (i, wi) in w[..n].iter().enumerate() {
                    if i != j {
                        let dz = z - wi;
                        // Apart by less than ten times their bounds (the later of the pair
                        // sees both of this sweep): not certified as distinct roots.
                        let apart = 10.0 * (err[i] + err[j]);
                        let d2 = dz.norm_sqr();
                        close |= d2.is_nan() || d2 <= apart * apart;
                        sum += dz.inv();
                    }
                }
                let ratio = v / d;
                let step = ratio / (1.0 - ratio * sum);
                w[j] = z - step;
                done &= modulus(step) <= 2.0 * err[j];
            }
            if done && close {
                return Ok(None);
            }
            if done {
                break;
            }
        }

        // The stable square roots (a non-real root's pole with its exact conjugate; the lower
        // roots are those conjugates), c(s) = Π(s − p_j) and Π(s + |p_j|) multiplied out in
        // place, ascending (loops of run-time length: small code).
        let mut poles = [Complex64::new(0.0, 0.0); SRL_MAX];
        let (mut c, mut c_abs) = ([0.0; W + 1], [0.0; W + 1]);
        c[0] = 1.0;
        c_abs[0] = 1.0;
        let (mut deg, mut rho, mut big) = (0, eps, 0.0f64);
        for j in 0..n {
            let wj = w[j];
            rho = rho.max(err[j] / (2.0 * modulus(wj)));
            let real = wj.im.abs() <= err[j];
            if !real && wj.im < 0.0 {
                continue;
            }
            // A root w ≤ 0: closed-loop poles on the imaginary axis.
            if real && (wj.re.is_nan() || wj.re <= err[j]) {
                return Ok(None);
            }
            let (pole, factors) = if real {
                (Complex64::new(-wj.re.sqrt(), 0.0), 1)
            } else {
                (-principal_sqrt(wj), 2)
            };
            // More upper than lower roots: not conjugate-closed.
            if deg + factors > n {
                return Ok(None);
            }
            let m = modulus(pole);
            big = big.max(m);
            // c·(s − p) or c·(s² − 2 Re p s + |p|²); c_abs·(s + |p|) or c_abs·(s + |p|)².
            let (quadratic, c1, c0, a1, a0) = if real {
                (0.0, 1.0, -pole.re, 1.0, m)
            } else {
                (1.0, -2.0 * pole.re, m * m, 2.0 * m, m * m)
            };
            for k in (0..=deg).rev() {
                let (v, va) = (c[k], c_abs[k]);
                c[k + 2] += quadratic * v;
                c[k + 1] += c1 * v;
                c[k] = c0 * v;
                c_abs[k + 2] += quadratic * va;
                c_abs[k + 1] += a1 * va;
                c_abs[k] = a0 * va;
            }
            poles[deg] = pole;
            if !real {
                poles[deg + 1] = pole.conj();
            }
            deg += factors;
        }
        let margin = eps.sqrt() * big;
        if deg != n || poles[..n].iter().any(|p| p.re.is_nan() || p.re >= -margin) {
            return Ok(None);
        }
        let mut gain = [0.0; SRL_MAX];
        let mut diff = 0.0;
        for j in 0..n {
            diff += (c[j] - self.a[j]).abs();
        }
        for (i, g) in gain[..n].iter_mut().enumerate() {
            *g = (0..n)
                .map(|j| self.n_inv[i * n + j] * (c[j] - self.a[j]))
                .sum();
        }
        let k_norm = sum_abs(&gain[..n]);
        let bound = self.n_inv_norm
            * (2.0 * n as f64 * rho * sum_abs(&c_abs[..=n])
                + self.eta * (self.a_norm + self.n_norm * k_norm)
                + n as f64 * eps * diff);
        if bound.is_nan() || bound > SRL_TOLERANCE * k_norm {
            return Ok(None);
        }
        sort_eigenvalues(&mut poles[..n]);
        Ok(Some(SrlSolution {
            n,
            gain,
            poles,
            error_bound: bound / k_norm,
            sweeps,
        }))
    }
}
