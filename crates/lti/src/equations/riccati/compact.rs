//! A compact CARE solver for small orders ([`care_compact`]): the stabilising solution, the
//! gain and the closed-loop poles of `n ≤ COMPACT_MAX` states on stack arrays, by code that is
//! small rather than fast in a loop.
//!
//! It exists for callers that solve one small CARE at a time from cold caches — the browser
//! lab redesigns on every slider move (`docs/web.md`, "Redesign time"), each move a frame or
//! more after the last, when the time is set by how much code and data the solve touches, not
//! by its flops. The general [`care`](super::care) (validation on heap matrices, the
//! fixed-size doubling path monomorphised per order, the boundary verdict) runs several times
//! as much code. Here every loop runs over run-time `n` on flat row-major arrays, one LU
//! factorisation serves every linear solve, and nothing is allocated.
//!
//! ## Method
//! With `R = LLᵀ` (Cholesky), `G = B R⁻¹ Bᵀ` and the scaling `X = sY`,
//! `s = sqrt(‖Q‖_F / ‖G‖_F)` (SLICOT `SB02MD`'s, as the general path), the Hamiltonian
//! `H = [A, −sG; −Q/s, −Aᵀ]` has `[I; Y]` spanning its stable invariant subspace. Its matrix
//! sign function `W = sign(H)` is computed by Newton's iteration
//! `Z ← (Z/c + c Z⁻¹)/2` with determinant scaling `c = |det Z|^{1/2n}` (Byers, "Solving the
//! algebraic Riccati equation with the matrix sign function", Linear Algebra Appl. 85, 1987;
//! Kenney & Laub, "The matrix sign function", IEEE TAC 40, 1995), stopped when a step changes
//! `Z` by less than `10⁻¹⁰` relative (1-norm). `(W + I)[I; Y] = 0` gives the overdetermined
//! system `[W₁₂; W₂₂ + I] Y = −[W₁₁ + I; W₂₁]`, solved by its normal equations (their squared
//! conditioning only costs accuracy that the refinement restores). Then Newton–Kleinman
//! refinement (Kleinman, "On an iterative technique for Riccati equation computations", IEEE
//! TAC 13, 1968) in residual-correction form: `FᵀΔ + ΔF = −Res(X)`, `F = A − GX`,
//! `Res(X) = AᵀX + XA − XGX + Q`, the Lyapunov equation solved on the `n(n+1)/2` unknowns of
//! the symmetric `Δ` (Kronecker form, LU with partial pivoting; once the relative residual
//! is below `10⁻⁶` a step reuses the last factorisation, the chord method, whose contraction
//! factor is then the size of the previous corrections); a step is kept only if it
//! lowers the relative residual, and the refinement stops when a step gains less than a
//! factor 2 or the residual reaches `10·n·ε` (at most 6 steps). The closed-loop poles
//! `eig(A − BK)` come from a Householder reduction to Hessenberg form and the Francis
//! double-shift QR iteration (EISPACK `hqr`).
//!
//! ## Accuracy and refusal
//! The result is accepted only when the relative residual (the definition of
//! [`care_residual`](super::care_residual): `‖Res(X)‖_F` over the sum of the Frobenius norms
//! of `AᵀX`, `XA`, `XGX`, `Q`) is at most `20·n·ε` (below the general path's `100·n·ε` for its own fast path: the
//! Kronecker-form Lyapunov solves of the refinement lose accuracy on strongly non-normal
//! closed loops, and such a problem is better left to the general solver) and every closed-loop pole lies left of
//! `−sqrt(ε)·‖A − BK‖_F`. A residual at rounding level with a Hurwitz closed loop identifies
//! the unique stabilising solution, so an accepted result is the general solver's to the
//! problem's conditioning. Anything else — `R` not positive definite, `Q` or `R` not exactly
//! symmetric, a singular iterate, slow convergence, a rejected check, a pole near the
//! imaginary axis — sends the problem to the general [`care`](super::care) (default options),
//! whose solution (or error: not stabilisable, boundary eigenvalue, …) is returned instead;
//! [`CompactCare::general`] says which path answered.
//!
//! ## Warm start
//! [`care_compact_from`] replaces the sign function by Kleinman's step from a gain `K₀` the
//! caller has, typically the previous solution's when a slider has changed `Q` or `R` but not
//! `(A, B)`: `X₁` solves `(A − BK₀)ᵀX₁ + X₁(A − BK₀) + Q + K₀ᵀRK₀ = 0` (the cost of
//! `u = −K₀x`), and the refinement above continues from `X₁` (up to 8 steps). For a
//! stabilising `K₀` the iterates converge to the stabilising solution, quadratically once
//! near (Kleinman 1968), so a nearby `K₀` needs a few `n(n+1)/2`-unknown linear solves
//! instead of the sign function's `2n × 2n` inverses. The result is accepted by the same
//! checks; if they fail, the sign function's path (and then the general solver) answers.

mod kernels;

use super::{RiccatiOptions, care};
use crate::error::{LtiError, Result};
use crate::linalg::{Complex64, Mat};
use kernels::{cholesky, eigenvalues, inverse, lu, lu_solve};

/// The largest state dimension [`care_compact`] accepts.
pub const COMPACT_MAX: usize = 6;

/// The compact path's acceptance bound on the relative residual, in units of `n·ε`.
const ACCEPT: f64 = 20.0;

/// The relative residual below which the refinement reuses the last factorised Lyapunov
/// operator (the chord step) instead of factorising the current closed loop's.
const CHORD: f64 = 1e-6;

const SQ: usize = COMPACT_MAX * COMPACT_MAX;
const H2: usize = 4 * SQ;
const SYM: usize = COMPACT_MAX * (COMPACT_MAX + 1) / 2;

/// The result of [`care_compact`], in fixed arrays (row-major, the first entries used).
#[derive(Debug, Clone, PartialEq)]
pub struct CompactCare {
    n: usize,
    m: usize,
    x: [f64; SQ],
    k: [f64; SQ],
    poles: [Complex64; COMPACT_MAX],
    /// The relative residual of the CARE at `X` (the definition of
    /// [`care_residual`](super::care_residual)).
    pub residual: f64,
    /// Whether the general [`care`](super::care) produced the result (the compact path
    /// refused the problem; module documentation).
    pub general: bool,
    /// Whether the Newton–Kleinman iteration from the caller's gain produced the result
    /// ([`care_compact_from`]; `false` when the sign function or the general solver did).
    pub warm: bool,
}

impl CompactCare {
    /// The stabilising solution `X`, `n × n` row-major (symmetric).
    pub fn x(&self) -> &[f64] {
        &self.x[..self.n * self.n]
    }

    /// The gain `K = R⁻¹BᵀX`, `m × n` row-major (the control law `u = −K x`).
    pub fn gain(&self) -> &[f64] {
        &self.k[..self.m * self.n]
    }

    /// The closed-loop poles `eig(A − BK)`, in the order of
    /// [`sort_eigenvalues`](crate::linalg::sort_eigenvalues) (real part descending, then
    /// imaginary part descending).
    pub fn poles(&self) -> &[Complex64] {
        &self.poles[..self.n]
    }
}

/// The stabilising solution of `AᵀX + XA − XBR⁻¹BᵀX + Q = 0` for `n ≤` [`COMPACT_MAX`]
/// states and `1 ≤ m ≤ n` inputs, its gain `K = R⁻¹BᵀX` and the closed-loop poles
/// `eig(A − BK)` (module documentation: method, accuracy, when the general solver answers
/// instead).
///
/// `a` is `n × n`, `b` `n × m`, `q` `n × n`, `r` `m × m`, each row-major, with
/// `m = b.len() / n`.
///
/// # Errors
/// [`LtiError::InvalidArgument`] when the slices' lengths do not fit `n` (or `n` is 0 or
/// above [`COMPACT_MAX`], or `m` is 0 or above `n`); otherwise the errors of the general
/// [`care`](super::care) when it answers: non-finite or non-symmetric data, `R` not positive
/// definite, no stabilising solution ([`LtiError::NotStabilizable`],
/// [`LtiError::NotDetectable`], [`LtiError::BoundaryEigenvalue`]).
pub fn care_compact(a: &[f64], b: &[f64], q: &[f64], r: &[f64], n: usize) -> Result<CompactCare> {
    let m = shape(a, b, q, r, n)?;
    if let Some(sol) = compact(a, b, q, r, n, m) {
        return Ok(sol);
    }
    general(a, b, q, r, n, m)
}

/// The input count `m = b.len() / n`, or the error of slices that do not fit `n`.
fn shape(a: &[f64], b: &[f64], q: &[f64], r: &[f64], n: usize) -> Result<usize> {
    let m = b.len().checked_div(n).unwrap_or(0);
    let fits = (1..=COMPACT_MAX).contains(&n)
        && (1..=n).contains(&m)
        && a.len() == n * n
        && b.len() == n * m
        && q.len() == n * n
        && r.len() == m * m;
    if !fits {
        return Err(LtiError::InvalidArgument(format!(
            "care_compact needs A n×n, B n×m, Q n×n, R m×m with 1 ≤ m ≤ n ≤ {COMPACT_MAX}; \
             got n = {n} and {}, {}, {}, {} entries",
            a.len(),
            b.len(),
            q.len(),
            r.len()
        )));
    }
    Ok(m)
}

/// [`care_compact`] started from the gain `k0` (`m × n`, row-major; `u = −K₀x`), typically
/// the previous solution's when only `Q` and `R` have changed: Newton–Kleinman's iteration
/// from `K₀`'s cost matrix replaces the sign function (module documentation, "Warm start").
/// With a stabilising `K₀` near the answer this takes a few small Lyapunov solves; the
/// result passes the same checks as [`care_compact`]'s, and when it does not (a `K₀` that
/// does not stabilise `(A, B)`, or one too far for the iteration's step limit) the answer
/// is [`care_compact`]'s, so the result never depends on `K₀` beyond rounding.
///
/// # Errors
/// As [`care_compact`]; [`LtiError::InvalidArgument`] also when `k0` has not `m·n` entries
/// or has a non-finite one.
pub fn care_compact_from(
    a: &[f64],
    b: &[f64],
    q: &[f64],
    r: &[f64],
    n: usize,
    k0: &[f64],
) -> Result<CompactCare> {
    let m = shape(a, b, q, r, n)?;
    let finite = k0.iter().all(|v| v.is_finite());
    if k0.len() != m * n || !finite {
        return Err(LtiError::InvalidArgument(format!(
            "care_compact_from needs a finite starting gain K0 of m×n = {m}×{n} entries; got {} entries{}",
            k0.len(),
            if finite { "" } else { ", not all finite" }
        )));
    }
    if let Some(sol) = compact_from(a, b, q, r, k0, n, m) {
        return Ok(sol);
    }
    if let Some(sol) = compact(a, b, q, r, n, m) {
        return Ok(sol);
    }
    general(a, b, q, r, n, m)
}

/// The general solver's answer in a [`CompactCare`].
fn general(a: &[f64], b: &[f64], q: &[f64], r: &[f64], n: usize, m: usize) -> Result<CompactCare> {
    let mat = |rows, cols, v: &[f64]| Mat::from_row_slice(rows, cols, v);
    let sol = care(
        &mat(n, n, a),
        &mat(n, m, b),
        &mat(n, n, q),
        &mat(m, m, r),
        None,
        &RiccatiOptions::default(),
    )?;
    let mut out = CompactCare {
        n,
        m,
        x: [0.0; SQ],
        k: [0.0; SQ],
        poles: [Complex64::new(0.0, 0.0); COMPACT_MAX],
        residual: sol.residual,
        general: true,
        warm: false,
    };
    for i in 0..n {
        for j in 0..n {
            out.x[i * n + j] = sol.x[(i, j)];
        }
    }
    for i in 0..m {
        for j in 0..n {
            out.k[i * n + j] = sol.gain[(i, j)];
        }
    }
    out.poles[..n].copy_from_slice(&sol.closed_loop_poles);
    Ok(out)
}

/// The compact path from the sign function; `None` refuses (module documentation).
fn compact(a: &[f64], b: &[f64], q: &[f64], r: &[f64], n: usize, m: usize) -> Option<CompactCare> {
    let f = Factors::new(a, b, q, r, n, m)?;
    let x = sign_start(a, q, &f, n)?;
    finish(a, b, q, &f, x, n, m, false)
}

/// The compact path from the gain `k0`; `None` refuses (module documentation).
fn compact_from(
    a: &[f64],
    b: &[f64],
    q: &[f64],
    r: &[f64],
    k0: &[f64],
    n: usize,
    m: usize,
) -> Option<CompactCare> {
    let f = Factors::new(a, b, q, r, n, m)?;
    let x = kleinman_start(a, b, q, r, k0, n, m)?;
    finish(a, b, q, &f, x, n, m, true)
}

/// The weights' factors every path shares: `R = LLᵀ`, `W = L⁻¹Bᵀ` (`m × n`), `G = WᵀW`.
struct Factors {
    l: [f64; SQ],
    w: [f64; SQ],
    g: [f64; SQ],
}

impl Factors {
    /// `None` for non-finite data, a `Q` or `R` not exactly symmetric, or `R` not positive
    /// definite.
    fn new(a: &[f64], b: &[f64], q: &[f64], r: &[f64], n: usize, m: usize) -> Option<Self> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let symmetric =
            |v: &[f64], k: usize| (0..k).all(|i| (0..i).all(|j| v[i * k + j] == v[j * k + i]));
        if !(finite(a) && finite(b) && finite(q) && finite(r) && symmetric(q, n) && symmetric(r, m))
        {
            return None;
        }
        let mut l = [0.0; SQ];
        l[..m * m].copy_from_slice(r);
        if !cholesky(&mut l, m) {
            return None;
        }
        let mut w = [0.0; SQ];
        for j in 0..n {
            for i in 0..m {
                let s: f64 = (0..i).map(|p| l[i * m + p] * w[p * n + j]).sum();
                w[i * n + j] = (b[j * m + i] - s) / l[i * m + i];
            }
        }
        let mut g = [0.0; SQ];
        for i in 0..n {
            for j in 0..n {
                g[i * n + j] = (0..m).map(|p| w[p * n + i] * w[p * n + j]).sum();
            }
        }
        Some(Self { l, w, g })
    }
}

/// The first `X` from the sign function of the scaled Hamiltonian (module documentation).
fn sign_start(a: &[f64], q: &[f64], f: &Factors, n: usize) -> Option<[f64; SQ]> {
    let g = &f.g;
    let (qn, gn) = (fro(&q[..n * n]), fro(&g[..n * n]));
    let s = if qn > 0.0 && gn > 0.0 {
        (qn / gn).sqrt()
    } else {
        1.0
    };

    // The sign function of H = [A, −sG; −Q/s, −Aᵀ].
    let n2 = 2 * n;
    let mut z = [0.0; H2];
    for i in 0..n {
        for j in 0..n {
            z[i * n2 + j] = a[i * n + j];
            z[i * n2 + n + j] = -s * g[i * n + j];
            z[(n + i) * n2 + j] = -q[i * n + j] / s;
            z[(n + i) * n2 + n + j] = -a[j * n + i];
        }
    }
    let mut converged = false;
    for _ in 0..60 {
        let mut lu_z = z;
        let mut piv = [0usize; 2 * COMPACT_MAX];
        if !lu(&mut lu_z, &mut piv, n2) {
            return None;
        }
        let log_det: f64 = (0..n2).map(|i| lu_z[i * n2 + i].abs().ln()).sum();
        let c = (log_det / n2 as f64).exp();
        let mut zi = [0.0; H2];
        inverse(&lu_z, &piv, n2, &mut zi);
        let (mut change, mut size) = (0.0f64, 0.0f64);
        for j in 0..n2 {
            let (mut dc, mut sc) = (0.0, 0.0);
            for i in 0..n2 {
                let new = 0.5 * (z[i * n2 + j] / c + c * zi[i * n2 + j]);
                dc += (new - z[i * n2 + j]).abs();
                sc += new.abs();
                z[i * n2 + j] = new;
            }
            change = change.max(dc);
            size = size.max(sc);
        }
        if !(change.is_finite() && size.is_finite()) {
            return None;
        }
        if change <= 1e-10 * size {
            converged = true;
            break;
        }
    }
    if !converged {
        return None;
    }
    // [W₁₂; W₂₂ + I] Y = −[W₁₁ + I; W₂₁] by its normal equations; X = sY.
    let col = |i: usize, j: usize| z[i * n2 + n + j] + if i == n + j { 1.0 } else { 0.0 };
    let rhs = |i: usize, j: usize| -(z[i * n2 + j] + if i == j { 1.0 } else { 0.0 });
    let mut nm = [0.0; SQ];
    let mut x = [0.0; SQ];
    for i in 0..n {
        for j in 0..n {
            nm[i * n + j] = (0..n2).map(|p| col(p, i) * col(p, j)).sum();
            x[i * n + j] = (0..n2).map(|p| col(p, i) * rhs(p, j)).sum();
        }
    }
    let mut piv = [0usize; 2 * COMPACT_MAX];
    if !lu(&mut nm, &mut piv, n) {
        return None;
    }
    let mut colv = [0.0; 2 * COMPACT_MAX];
    for j in 0..n {
        for i in 0..n {
            colv[i] = x[i * n + j];
        }
        lu_solve(&nm, &piv, n, &mut colv);
        for i in 0..n {
            x[i * n + j] = s * colv[i];
        }
    }
    symmetrize(&mut x, n);
    Some(x)
}

/// The first `X` from the gain `k0` (`m × n`): Kleinman's step, the cost matrix of
/// `u = −K₀x` under the weights, `(A − BK₀)ᵀX + X(A − BK₀) + Q + K₀ᵀRK₀ = 0`. When `K₀`
/// stabilises `(A, B)` this `X` bounds the stabilising solution from above and Newton's
/// iteration from it converges to that solution (Kleinman 1968); for any other `K₀`,
/// [`finish`]'s checks refuse what comes out. `k0` is finite ([`care_compact_from`] checks).
fn kleinman_start(
    a: &[f64],
    b: &[f64],
    q: &[f64],
    r: &[f64],
    k0: &[f64],
    n: usize,
    m: usize,
) -> Option<[f64; SQ]> {
    let f = minus_bk(a, b, k0, n, m);
    let mut c = [0.0; SQ];
    let mut rk = [0.0; SQ];
    for i in 0..m {
        for j in 0..n {
            rk[i * n + j] = (0..m).map(|p| r[i * m + p] * k0[p * n + j]).sum();
        }
    }
    for i in 0..n {
        for j in 0..n {
            c[i * n + j] =
                q[i * n + j] + (0..m).map(|p| k0[p * n + i] * rk[p * n + j]).sum::<f64>();
        }
    }
    let mut op = Lyapunov::new();
    if !op.factor(&f, n) {
        return None;
    }
    let mut x = [0.0; SQ];
    op.solve(&c, &mut x);
    symmetrize(&mut x, n);
    Some(x)
}

/// Newton–Kleinman refinement of `x`, then the gain, the closed-loop poles and the
/// acceptance checks (module documentation); `warm` records which start gave `x`.
#[allow(clippy::too_many_arguments)]
fn finish(
    a: &[f64],
    b: &[f64],
    q: &[f64],
    fa: &Factors,
    mut x: [f64; SQ],
    n: usize,
    m: usize,
    warm: bool,
) -> Option<CompactCare> {
    let (l, w) = (&fa.l, &fa.w);
    // Newton–Kleinman refinement.
    let mut res = [0.0; SQ];
    let mut rel = residual(a, w, q, &x, n, m, &mut res);
    let floor = 10.0 * n as f64 * f64::EPSILON;
    let mut op = Lyapunov::new();
    let mut factored = false;
    for _ in 0..if warm { 8 } else { 6 } {
        if rel <= floor {
            break;
        }
        // Newton's step on the closed loop of `X`, or, once the residual is small, the chord
        // step on the last factorised closed loop (it differs from this one by the last
        // steps' corrections, which the contraction factor then is of the order of).
        let chord = factored && rel <= CHORD;
        if !chord {
            let mut f = [0.0; SQ];
            closed_loop(a, w, &x, n, m, &mut f);
            if !op.factor(&f, n) {
                break;
            }
            factored = true;
        }
        let mut d = [0.0; SQ];
        op.solve(&res, &mut d);
        let mut trial = x;
        for (t, dv) in trial[..n * n].iter_mut().zip(&d[..n * n]) {
            *t += dv;
        }
        symmetrize(&mut trial, n);
        let mut trial_res = [0.0; SQ];
        let trial_rel = residual(a, w, q, &trial, n, m, &mut trial_res);
        // A NaN residual is no improvement either; a chord step that is none is retried
        // as Newton's.
        if trial_rel.partial_cmp(&rel) != Some(std::cmp::Ordering::Less) {
            if chord {
                factored = false;
                continue;
            }
            break;
        }
        let gain = rel / trial_rel;
        (x, res, rel) = (trial, trial_res, trial_rel);
        if gain < 2.0 {
            break;
        }
    }
    if rel.is_nan() || rel > ACCEPT * n as f64 * f64::EPSILON {
        return None;
    }
    // K = R⁻¹BᵀX = L⁻ᵀ (W X), the closed loop A − BK = A − GX and its poles.
    let mut k = [0.0; SQ];
    for j in 0..n {
        for i in 0..m {
            k[i * n + j] = (0..n).map(|p| w[i * n + p] * x[p * n + j]).sum();
        }
        for i in (0..m).rev() {
            let s: f64 = (i + 1..m).map(|p| l[p * m + i] * k[p * n + j]).sum();
            k[i * n + j] = (k[i * n + j] - s) / l[i * m + i];
        }
    }
    let mut f = minus_bk(a, b, &k, n, m);
    let margin = f64::EPSILON.sqrt() * fro(&f[..n * n]);
    let poles = eigenvalues(&mut f, n)?;
    if poles[..n].iter().any(|p| p.re.is_nan() || p.re >= -margin) {
        return None;
    }
    Some(CompactCare {
        n,
        m,
        x,
        k,
        poles,
        residual: rel,
        general: false,
        warm,
    })
}

fn fro(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn symmetrize(x: &mut [f64; SQ], n: usize) {
    for i in 0..n {
        for j in 0..i {
            let v = 0.5 * (x[i * n + j] + x[j * n + i]);
            x[i * n + j] = v;
            x[j * n + i] = v;
        }
    }
}

/// `A − BK` (`b` `n × m`, `k` `m × n`, row-major).
fn minus_bk(a: &[f64], b: &[f64], k: &[f64], n: usize, m: usize) -> [f64; SQ] {
    let mut f = [0.0; SQ];
    for i in 0..n {
        for j in 0..n {
            f[i * n + j] = a[i * n + j] - (0..m).map(|p| b[i * m + p] * k[p * n + j]).sum::<f64>();
        }
    }
    f
}

/// `WX` (`m × n`) of `W = L⁻¹Bᵀ` (`m × n`) and the symmetric `X`: with `G = WᵀW`,
/// `GX = Wᵀ(WX)` and `XGX = (WX)ᵀ(WX)` cost `m·n²` each instead of `n³` (the rank of `G`
/// is `m`).
fn w_times(w: &[f64; SQ], x: &[f64; SQ], n: usize, m: usize) -> [f64; SQ] {
    let mut wx = [0.0; SQ];
    for k in 0..m {
        for j in 0..n {
            wx[k * n + j] = (0..n).map(|p| w[k * n + p] * x[p * n + j]).sum();
        }
    }
    wx
}

/// `F = A − GX = A − Wᵀ(WX)`.
fn closed_loop(a: &[f64], w: &[f64; SQ], x: &[f64; SQ], n: usize, m: usize, f: &mut [f64; SQ]) {
    let wx = w_times(w, x, n, m);
    for i in 0..n {
        for j in 0..n {
            f[i * n + j] = a[i * n + j] - (0..m).map(|k| w[k * n + i] * wx[k * n + j]).sum::<f64>();
        }
    }
}

/// `Res = AᵀX + XA − XGX + Q` into `res` (`XGX = (WX)ᵀ(WX)`, [`w_times`]); returns the
/// relative residual.
fn residual(
    a: &[f64],
    w: &[f64; SQ],
    q: &[f64],
    x: &[f64; SQ],
    n: usize,
    m: usize,
    res: &mut [f64; SQ],
) -> f64 {
    let mut xa = [0.0; SQ];
    for i in 0..n {
        for j in 0..n {
            xa[i * n + j] = (0..n).map(|p| x[i * n + p] * a[p * n + j]).sum();
        }
    }
    let wx = w_times(w, x, n, m);
    let (mut rn, mut xan, mut xgxn, mut qn) = (0.0, 0.0, 0.0, 0.0);
    for i in 0..n {
        for j in 0..n {
            let xgx: f64 = (0..m).map(|k| wx[k * n + i] * wx[k * n + j]).sum();
            let v = xa[j * n + i] + xa[i * n + j] - xgx + q[i * n + j];
            res[i * n + j] = v;
            rn += v * v;
            xan += xa[i * n + j] * xa[i * n + j];
            xgxn += xgx * xgx;
            qn += q[i * n + j] * q[i * n + j];
        }
    }
    let sum = 2.0 * xan.sqrt() + xgxn.sqrt() + qn.sqrt();
    if sum > 0.0 {
        rn.sqrt() / sum
    } else {
        rn.sqrt()
    }
}

/// The Lyapunov operator `D ↦ FᵀD + DF` on symmetric `D` (the unknowns `D_ij`, `i ≤ j`:
/// `n(n+1)/2` of them), LU-factorised once for any number of right-hand sides.
struct Lyapunov {
    kron: [f64; SYM * SYM],
    piv: [usize; SYM],
    n: usize,
}

impl Lyapunov {
    fn new() -> Self {
        Self {
            kron: [0.0; SYM * SYM],
            piv: [0; SYM],
            n: 0,
        }
    }

    /// The unknown of `D_ij` (either order).
    fn idx(n: usize, i: usize, j: usize) -> usize {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        i * n - i * (i + 1) / 2 + j
    }

    /// Factorises the operator of `F` (`n × n`); `false` when it is singular.
    fn factor(&mut self, f: &[f64; SQ], n: usize) -> bool {
        let p = n * (n + 1) / 2;
        self.n = n;
        let kron = &mut self.kron[..p * p];
        kron.fill(0.0);
        for i in 0..n {
            for j in i..n {
                let row = Self::idx(n, i, j);
                // Σ_k F_ki D_kj + Σ_k D_ik F_kj.
                for k in 0..n {
                    kron[row * p + Self::idx(n, k, j)] += f[k * n + i];
                    kron[row * p + Self::idx(n, i, k)] += f[k * n + j];
                }
            }
        }
        lu(kron, &mut self.piv, p)
    }

    /// `FᵀD + DF = −Res` by the last [`Lyapunov::factor`].
    fn solve(&self, res: &[f64; SQ], d: &mut [f64; SQ]) {
        let n = self.n;
        let p = n * (n + 1) / 2;
        let mut rhs = [0.0; SYM];
        for i in 0..n {
            for j in i..n {
                rhs[Self::idx(n, i, j)] = -res[i * n + j];
            }
        }
        lu_solve(&self.kron[..p * p], &self.piv, p, &mut rhs);
        for i in 0..n {
            for j in 0..n {
                d[i * n + j] = rhs[Self::idx(n, i, j)];
            }
        }
    }
}
