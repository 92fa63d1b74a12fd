//! Matrix functions: exponential, principal logarithm and square root, and the block
//! exponentials that discretisation and sampled-data design are built on.
//!
//! | function | MATLAB | method |
//! |---|---|---|
//! | [`expm`] | `expm` | scaling and squaring with Padé degree 3–13 (Higham 2005; Al-Mohy & Higham 2009 scaling) |
//! | [`logm`] | `logm` | inverse scaling and squaring on the real Schur form (Higham 2001, 2008 Alg. 11.10) |
//! | [`sqrtm`] | `sqrtm` | real Schur square root (Higham 1987) |
//! | [`zoh_integrals`], [`foh_integrals`] | (`c2d` internals) | one block exponential each (Van Loan 1978) |
//! | [`van_loan_integral`] | (`lqrd` internals) | `∫₀ᵗ e^{Fᵀs} W e^{Fs} ds` from one block exponential (Van Loan 1978) |

use crate::error::{LtiError, Result};
use crate::linalg::{Complex64, Mat, check_finite, check_square, norm1};

/// Diagnostics of one [`expm`] evaluation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExpmInfo {
    /// Degree `m` of the diagonal Padé approximant used (3, 5, 7, 9 or 13).
    pub pade_degree: usize,
    /// Number of squarings `s` (the approximant was evaluated at `A / 2ˢ`).
    pub squarings: u32,
}

/// Matrix exponential `e^A` (MATLAB `expm`).
///
/// Scaling and squaring with a diagonal Padé approximant `r_m`, `m ∈ {3, 5, 7, 9, 13}`:
/// Higham, "The scaling and squaring method for the matrix exponential revisited", SIAM J.
/// Matrix Anal. Appl. 26(4), 2005 (the degrees, θₘ thresholds and the evaluation scheme of
/// `r₁₃` with 6 matrix products), with the refinement of Al-Mohy & Higham, "A new scaling and
/// squaring algorithm for the matrix exponential", SIAM J. Matrix Anal. Appl. 31(3), 2009:
/// the degree and scaling are chosen from `dₖ = ‖Aᵏ‖₁^{1/k}` instead of `‖A‖₁` (which avoids
/// over-scaling non-normal matrices, e.g. `[[1, 1e6], [0, −1]]`), and the backward-error
/// correction `ℓ(A, m)` adds squarings only where the bound on `|A|` demands it. Powers
/// `‖Aᵏ‖₁` and `‖|A|ᵏ‖₁` are computed exactly (not estimated), which suits the small and
/// moderate dimensions of control problems.
///
/// Backward error: `e^A` is computed as `e^{A + ΔA}` with `‖ΔA‖ ≤ u ‖A‖` in exact arithmetic
/// (`u = 2⁻⁵³`); for normal matrices the forward error is a modest multiple of `u ‖A‖`.
///
/// # Errors
/// [`LtiError::NotSquare`], [`LtiError::NonFinite`] for invalid input or if the result
/// overflows, [`LtiError::Singular`] if the Padé denominator cannot be factorised (it cannot
/// for finite input within the thresholds; reported rather than assumed).
pub fn expm(a: &Mat) -> Result<Mat> {
    expm_with_info(a).map(|(e, _)| e)
}

/// [`expm`] returning also the Padé degree and number of squarings used.
///
/// # Errors
/// As [`expm`].
pub fn expm_with_info(a: &Mat) -> Result<(Mat, ExpmInfo)> {
    check_square("A", a)?;
    check_finite("A", a)?;
    let n = a.nrows();
    if n == 0 {
        return Ok((
            a.clone(),
            ExpmInfo {
                pade_degree: 0,
                squarings: 0,
            },
        ));
    }
    let (e, info) = expm_kernel(a)?;
    check_finite("expm result (overflow)", &e)?;
    Ok((e, info))
}

// θₘ of Higham (2005), Table 2.3: the largest ‖2⁻ˢA‖₁ for which the degree-m Padé
// approximant has backward error ≤ u; θ₁₃ = 4.25 per Al-Mohy & Higham (2009), Table 3.1,
// for the dₖ-based choice.
const THETA3: f64 = 1.495_585_217_958_292e-2;
const THETA5: f64 = 2.539_398_330_063_23e-1;
const THETA7: f64 = 9.504_178_996_162_932e-1;
const THETA9: f64 = 2.097_847_961_257_068;
const THETA13: f64 = 4.25;

// Coefficients bⱼ of the numerator pₘ(x) = Σ bⱼ xʲ of the [m/m] Padé approximant of eˣ
// (qₘ(x) = pₘ(−x)): bⱼ = (2m − j)! m! / ((2m)! j! (m − j)!), scaled to integers.
const B3: [f64; 4] = [120.0, 60.0, 12.0, 1.0];
const B5: [f64; 6] = [30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0];
const B7: [f64; 8] = [
    17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0,
];
const B9: [f64; 10] = [
    17643225600.0,
    8821612800.0,
    2075673600.0,
    302702400.0,
    30270240.0,
    2162160.0,
    110880.0,
    3960.0,
    90.0,
    1.0,
];
const B13: [f64; 14] = [
    64764752532480000.0,
    32382376266240000.0,
    7771770303897600.0,
    1187353796428800.0,
    129060195264000.0,
    10559470521600.0,
    670442572800.0,
    33522128640.0,
    1323241920.0,
    40840800.0,
    960960.0,
    16380.0,
    182.0,
    1.0,
];

/// Exact `‖|A|ᵖ‖₁` as the largest entry of `1ᵀ|A|ᵖ` (p vector–matrix products).
fn norm1_abs_power(a: &Mat, p: usize) -> f64 {
    let n = a.nrows();
    let mut v = vec![1.0; n];
    let mut w = vec![0.0; n];
    for _ in 0..p {
        for j in 0..n {
            w[j] = (0..n).map(|i| v[i] * a[(i, j)].abs()).sum();
        }
        std::mem::swap(&mut v, &mut w);
    }
    v.into_iter().fold(0.0, f64::max)
}

/// Al-Mohy & Higham (2009) eq. (5.1): extra squarings `ℓ(A, m)` needed so that the
/// truncated backward-error bound `|c₂ₘ₊₁| ‖|A|²ᵐ⁺¹‖₁ / ‖A‖₁ ≤ u`, with
/// `1/|c₂ₘ₊₁| = (2m)!(2m+1)!/(m!)²`.
fn ell(a: &Mat, m: usize) -> u32 {
    let na = norm1(a);
    if na == 0.0 {
        return 0;
    }
    let p = norm1_abs_power(a, 2 * m + 1);
    if p == 0.0 {
        return 0;
    }
    let mut recip = 1.0f64; // (2m)!(2m+1)!/(m!)²
    for k in 1..=2 * m {
        recip *= k as f64;
    }
    let mut f2 = recip;
    f2 *= (2 * m + 1) as f64;
    let mut mf = 1.0;
    for k in 1..=m {
        mf *= k as f64;
    }
    let c_recip = recip * f2 / (mf * mf);
    let alpha = p / (na * c_recip);
    let u = f64::EPSILON / 2.0;
    let v = ((alpha / u).log2() / (2 * m) as f64).ceil();
    if v.is_finite() && v > 0.0 {
        v as u32
    } else {
        0
    }
}

fn pade_odd_even(a: &Mat, powers: &[&Mat], b: &[f64]) -> (Mat, Mat) {
    // powers = [A², A⁴, A⁶, …] as needed; U = A Σ b_{2k+1} A^{2k}, V = Σ b_{2k} A^{2k}.
    let n = a.nrows();
    let eye = Mat::identity(n, n);
    let mut u = &eye * b[1];
    let mut v = &eye * b[0];
    for (k, p) in powers.iter().enumerate() {
        let j = 2 * (k + 1);
        if j + 1 < b.len() {
            u += *p * b[j + 1];
        }
        if j < b.len() {
            v += *p * b[j];
        }
    }
    (a * u, v)
}

fn pade_solve(u: &Mat, v: &Mat) -> Result<Mat> {
    let den = v - u;
    let num = v + u;
    let lu = den.lu();
    lu.solve(&num).ok_or_else(|| LtiError::Singular {
        what: "Padé denominator q(A) in expm".into(),
        rcond: 0.0,
    })
}

fn expm_kernel(a: &Mat) -> Result<(Mat, ExpmInfo)> {
    let a2 = a * a;
    let a4 = &a2 * &a2;
    let a6 = &a2 * &a4;
    let d4 = norm1(&a4).powf(0.25);
    let d6 = norm1(&a6).powf(1.0 / 6.0);
    let eta1 = d4.max(d6);
    let info = |m, s| ExpmInfo {
        pade_degree: m,
        squarings: s,
    };
    if eta1 <= THETA3 && ell(a, 3) == 0 {
        let (u, v) = pade_odd_even(a, &[&a2], &B3);
        return Ok((pade_solve(&u, &v)?, info(3, 0)));
    }
    if eta1 <= THETA5 && ell(a, 5) == 0 {
        let (u, v) = pade_odd_even(a, &[&a2, &a4], &B5);
        return Ok((pade_solve(&u, &v)?, info(5, 0)));
    }
    let a8 = &a4 * &a4;
    let d8 = norm1(&a8).powf(1.0 / 8.0);
    let eta3 = d6.max(d8);
    if eta3 <= THETA7 && ell(a, 7) == 0 {
        let (u, v) = pade_odd_even(a, &[&a2, &a4, &a6], &B7);
        return Ok((pade_solve(&u, &v)?, info(7, 0)));
    }
    if eta3 <= THETA9 && ell(a, 9) == 0 {
        let (u, v) = pade_odd_even(a, &[&a2, &a4, &a6, &a8], &B9);
        return Ok((pade_solve(&u, &v)?, info(9, 0)));
    }
    let a10 = &a4 * &a6;
    let d10 = norm1(&a10).powf(0.1);
    let eta4 = d8.max(d10);
    let eta5 = eta3.min(eta4);
    let mut s = if eta5 > 0.0 {
        (eta5 / THETA13).log2().ceil().max(0.0) as u32
    } else {
        0
    };
    let scale = |p: u32| 2f64.powi(-(p as i32));
    s += ell(&(a * scale(s)), 13);
    let f = scale(s);
    let (as1, as2, as4, as6) = (a * f, &a2 * f.powi(2), &a4 * f.powi(4), &a6 * f.powi(6));
    let n = a.nrows();
    let eye = Mat::identity(n, n);
    let b = &B13;
    // U = A [A⁶(b₁₃A⁶ + b₁₁A⁴ + b₉A²) + b₇A⁶ + b₅A⁴ + b₃A² + b₁I]
    let inner_u = &as6 * b[13] + &as4 * b[11] + &as2 * b[9];
    let u_poly = &as6 * inner_u + &as6 * b[7] + &as4 * b[5] + &as2 * b[3] + &eye * b[1];
    let u = &as1 * u_poly;
    // V = A⁶(b₁₂A⁶ + b₁₀A⁴ + b₈A²) + b₆A⁶ + b₄A⁴ + b₂A² + b₀I
    let inner_v = &as6 * b[12] + &as4 * b[10] + &as2 * b[8];
    let v = &as6 * inner_v + &as6 * b[6] + &as4 * b[4] + &as2 * b[2] + &eye * b[0];
    let mut r = pade_solve(&u, &v)?;
    for _ in 0..s {
        r = &r * &r;
    }
    Ok((r, info(13, s)))
}

// θₘ for the [m/m] Padé approximant of log(1 + x) (Higham, "Evaluating Padé approximants of
// the matrix logarithm", SIAM J. Matrix Anal. Appl. 22(4), 2001, Table 2.1): the largest
// ‖X‖ with |rₘ(−‖X‖) − log(1 − ‖X‖)| ≤ u, which bounds ‖rₘ(X) − log(I + X)‖ (Kenney & Laub
// 1989). Values reproduced independently in 60-digit arithmetic.
const LOG_THETA: [f64; 16] = [
    1.10e-5, 1.82e-3, 1.62e-2, 5.39e-2, 1.14e-1, 1.87e-1, 2.64e-1, 3.40e-1, 4.11e-1, 4.75e-1,
    5.31e-1, 5.81e-1, 6.24e-1, 6.62e-1, 6.95e-1, 7.24e-1,
];

/// Principal matrix logarithm `log A` (MATLAB `logm`): the unique real `X` with `e^X = A`
/// and every eigenvalue's imaginary part in `(−π, π)`.
///
/// Inverse scaling and squaring on the real Schur form `A = Z T Zᵀ` (Higham, *Functions of
/// Matrices*, SIAM 2008, Algorithm 11.10, in real arithmetic): take square roots
/// `T ← T^{1/2}` ([`sqrtm`]'s Schur recurrence, Higham 1987) until `X = T − I` is small enough
/// for the degree-m Padé approximant (θₘ of Higham 2001, choosing `m` and the number of roots
/// `k` by that algorithm's cost rule), evaluate `rₘ(X)` by its partial-fraction form
/// `Σ wⱼ X (I + xⱼX)⁻¹` (Gauss–Legendre nodes on `[0, 1]`), scale by `2ᵏ`, and recompute the
/// diagonal blocks of the result from the scalar logarithms of the eigenvalues.
///
/// # Errors
/// [`LtiError::NotSquare`], [`LtiError::NonFinite`]; [`LtiError::NoRealLogarithm`] if an
/// eigenvalue lies on the closed negative real axis (including 0), where no real principal
/// logarithm exists; [`LtiError::NoConvergence`] if the Schur form or the square roots fail.
pub fn logm(a: &Mat) -> Result<Mat> {
    check_square("A", a)?;
    check_finite("A", a)?;
    let n = a.nrows();
    if n == 0 {
        return Ok(a.clone());
    }
    let (t0, z) = crate::linalg::schur::real_schur(a)?.into_parts();
    let blocks = schur_blocks(&t0);
    for &(i, sz) in &blocks {
        for ev in block_eigenvalues(&t0, i, sz) {
            if ev.im == 0.0 && ev.re <= 0.0 {
                return Err(LtiError::NoRealLogarithm {
                    what: "matrix".into(),
                    eigenvalue: ev,
                });
            }
        }
    }
    let mut t = t0.clone();
    let eye = Mat::identity(n, n);
    let mut k: u32 = 0;
    let mut extra = 0;
    let m = loop {
        let nx = norm1(&(&t - &eye));
        if nx <= LOG_THETA[15] {
            let j1 = LOG_THETA.iter().position(|&th| th >= nx).unwrap_or(15) + 1;
            let j2 = LOG_THETA
                .iter()
                .position(|&th| th >= nx / 2.0)
                .unwrap_or(15)
                + 1;
            // Higham (2008) Alg. 11.10: one more square root pays when it lowers the degree by
            // more than one; at most two such extra roots.
            if j1 - j2 <= 1 || extra == 2 {
                break j1;
            }
            extra += 1;
        }
        if k >= 64 {
            return Err(LtiError::NoConvergence {
                algorithm: "logm inverse scaling (repeated square roots)".into(),
                iterations: k as usize,
            });
        }
        t = sqrt_quasi_triangular(&t, &blocks)?;
        k += 1;
    };
    let x = &t - &eye;
    let (nodes, weights) = gauss_legendre_01(m);
    let mut l = Mat::zeros(n, n);
    for (xj, wj) in nodes.iter().zip(&weights) {
        let den = &eye + &x * *xj;
        let y = den.lu().solve(&x).ok_or_else(|| LtiError::Singular {
            what: "I + x_j X in the logm Padé approximant".into(),
            rcond: 0.0,
        })?;
        l += y * *wj;
    }
    l *= 2f64.powi(k as i32);
    // Diagonal blocks from the scalar logarithms (exact up to rounding).
    for &(i, sz) in &blocks {
        if sz == 1 {
            l[(i, i)] = t0[(i, i)].ln();
        } else {
            let ev = block_eigenvalues(&t0, i, sz);
            if ev[0].im != 0.0 {
                // f(M) = Re f(λ) I + (Im f(λ)/ν)(M − μI) for a 2×2 block with eigenvalues μ ± iν.
                let lam = ev[0];
                let f = lam.ln();
                let (mu, nu) = (lam.re, lam.im);
                for r in 0..2 {
                    for c in 0..2 {
                        let mrc = t0[(i + r, i + c)] - if r == c { mu } else { 0.0 };
                        l[(i + r, i + c)] = if r == c { f.re } else { 0.0 } + f.im / nu * mrc;
                    }
                }
            }
        }
    }
    let out = &z * l * z.transpose();
    check_finite("logm result", &out)?;
    Ok(out)
}

/// Principal matrix square root `A^{1/2}` (MATLAB `sqrtm`): the unique real `X` with
/// `X² = A` whose eigenvalues have positive real part.
///
/// Real Schur method (Higham, "Computing real square roots of a real matrix", Linear Algebra
/// Appl. 88/89, 1987): square roots of the 1×1 and 2×2 diagonal blocks of `T` in closed form
/// (`√M = (M + δI)/√(tr M + 2δ)`, `δ = √det M` for a 2×2 block), then the off-diagonal blocks
/// from the small Sylvester equations `Rᵢᵢ Rᵢⱼ + Rᵢⱼ Rⱼⱼ = Tᵢⱼ − Σₖ Rᵢₖ Rₖⱼ`.
///
/// # Errors
/// [`LtiError::NotSquare`], [`LtiError::NonFinite`]; [`LtiError::NoRealLogarithm`] (the
/// principal root needs the same spectrum condition) for an eigenvalue on the closed negative
/// real axis.
pub fn sqrtm(a: &Mat) -> Result<Mat> {
    check_square("A", a)?;
    check_finite("A", a)?;
    if a.nrows() == 0 {
        return Ok(a.clone());
    }
    let (t, z) = crate::linalg::schur::real_schur(a)?.into_parts();
    let blocks = schur_blocks(&t);
    for &(i, sz) in &blocks {
        for ev in block_eigenvalues(&t, i, sz) {
            if ev.im == 0.0 && ev.re < 0.0 {
                return Err(LtiError::NoRealLogarithm {
                    what: "matrix (principal square root)".into(),
                    eigenvalue: ev,
                });
            }
        }
    }
    let r = sqrt_quasi_triangular(&t, &blocks)?;
    Ok(&z * r * z.transpose())
}

/// Diagonal blocks `(start, size)` of a quasi-upper-triangular matrix.
fn schur_blocks(t: &Mat) -> Vec<(usize, usize)> {
    let n = t.nrows();
    let mut out = Vec::new();
    let mut i = 0;
    while i < n {
        if i + 1 < n && t[(i + 1, i)] != 0.0 {
            out.push((i, 2));
            i += 2;
        } else {
            out.push((i, 1));
            i += 1;
        }
    }
    out
}

fn block_eigenvalues(t: &Mat, i: usize, sz: usize) -> Vec<Complex64> {
    if sz == 1 {
        return vec![Complex64::new(t[(i, i)], 0.0)];
    }
    let (a, b, c, d) = (t[(i, i)], t[(i, i + 1)], t[(i + 1, i)], t[(i + 1, i + 1)]);
    let tr = 0.5 * (a + d);
    let disc = 0.25 * (a - d) * (a - d) + b * c;
    if disc < 0.0 {
        let im = (-disc).sqrt();
        vec![Complex64::new(tr, im), Complex64::new(tr, -im)]
    } else {
        let s = disc.sqrt();
        vec![Complex64::new(tr + s, 0.0), Complex64::new(tr - s, 0.0)]
    }
}

fn sqrt_quasi_triangular(t: &Mat, blocks: &[(usize, usize)]) -> Result<Mat> {
    let n = t.nrows();
    let mut r = Mat::zeros(n, n);
    for &(i, sz) in blocks {
        if sz == 1 {
            let v = t[(i, i)];
            if v < 0.0 {
                return Err(LtiError::NoRealLogarithm {
                    what: "matrix (square root)".into(),
                    eigenvalue: Complex64::new(v, 0.0),
                });
            }
            r[(i, i)] = v.sqrt();
        } else {
            let (a, b, c, d) = (t[(i, i)], t[(i, i + 1)], t[(i + 1, i)], t[(i + 1, i + 1)]);
            let det = a * d - b * c;
            let delta = det.max(0.0).sqrt();
            let tau2 = a + d + 2.0 * delta;
            if det <= 0.0 || tau2 <= 0.0 {
                let ev = block_eigenvalues(t, i, 2);
                return Err(LtiError::NoRealLogarithm {
                    what: "matrix (square root)".into(),
                    eigenvalue: ev[1],
                });
            }
            let tau = tau2.sqrt();
            r[(i, i)] = (a + delta) / tau;
            r[(i, i + 1)] = b / tau;
            r[(i + 1, i)] = c / tau;
            r[(i + 1, i + 1)] = (d + delta) / tau;
        }
    }
    for jb in 0..blocks.len() {
        let (j, q) = blocks[jb];
        for ib in (0..jb).rev() {
            let (i, p) = blocks[ib];
            // rhs = T_ij − Σ_{k strictly between} R_ik R_kj
            let mut rhs = t.view((i, j), (p, q)).clone_owned();
            for &(k, s) in &blocks[ib + 1..jb] {
                rhs -= r.view((i, k), (p, s)) * r.view((k, j), (s, q));
            }
            let rii = r.view((i, i), (p, p)).clone_owned();
            let rjj = r.view((j, j), (q, q)).clone_owned();
            let x = small_sylvester(&rii, &rjj, &rhs)?;
            r.view_mut((i, j), (p, q)).copy_from(&x);
        }
    }
    Ok(r)
}

/// Solves `P X + X Q = C` for blocks of size ≤ 2 through the Kronecker form
/// `(I ⊗ P + Qᵀ ⊗ I) vec X = vec C`.
fn small_sylvester(p: &Mat, q: &Mat, c: &Mat) -> Result<Mat> {
    let (np, nq) = (p.nrows(), q.nrows());
    let dim = np * nq;
    let mut k = Mat::zeros(dim, dim);
    for a in 0..nq {
        for b in 0..nq {
            for i in 0..np {
                for j in 0..np {
                    let mut v = 0.0;
                    if a == b {
                        v += p[(i, j)];
                    }
                    if i == j {
                        v += q[(b, a)];
                    }
                    k[(a * np + i, b * np + j)] = v;
                }
            }
        }
    }
    let rhs = crate::linalg::Vector::from_column_slice(c.as_slice());
    let sol = k.lu().solve(&rhs).ok_or_else(|| LtiError::Singular {
        what: "square-root block Sylvester equation".into(),
        rcond: 0.0,
    })?;
    Ok(Mat::from_column_slice(np, nq, sol.as_slice()))
}

/// Gauss–Legendre nodes and weights on `[0, 1]` with `m` points (Newton's method on the
/// Legendre polynomial from the Tricomi initial guesses; accurate to a few ulps for m ≤ 16).
fn gauss_legendre_01(m: usize) -> (Vec<f64>, Vec<f64>) {
    // (P_m(x), P_m'(x)) by the three-term recurrence.
    let legendre = |x: f64| {
        let (mut p0, mut p1) = (1.0, x);
        for j in 2..=m {
            let p2 = ((2 * j - 1) as f64 * x * p1 - (j - 1) as f64 * p0) / j as f64;
            p0 = p1;
            p1 = p2;
        }
        (p1, m as f64 * (x * p1 - p0) / (x * x - 1.0))
    };
    let mut nodes = Vec::with_capacity(m);
    let mut weights = Vec::with_capacity(m);
    for k in 1..=m {
        let mut x = (std::f64::consts::PI * (k as f64 - 0.25) / (m as f64 + 0.5)).cos();
        for _ in 0..100 {
            let (p, dp) = legendre(x);
            let dx = p / dp;
            x -= dx;
            if dx.abs() <= 1e-16 {
                break;
            }
        }
        let (_, dp) = legendre(x);
        nodes.push(0.5 * (1.0 + x));
        weights.push(1.0 / ((1.0 - x * x) * dp * dp));
    }
    (nodes, weights)
}

/// Zero-order-hold integrals from one block exponential (Van Loan 1978):
/// `exp([[A, B], [0, 0]] t) = [[Φ, Γ], [0, I]]` with `Φ = e^{At}` and `Γ = ∫₀ᵗ e^{As} ds B`.
///
/// Returns `(Φ, Γ)`. `t` may be any finite number (negative `t` integrates backwards).
///
/// # Errors
/// [`LtiError::DimensionMismatch`] if `B` has another row count than `A`; as [`expm`].
pub fn zoh_integrals(a: &Mat, b: &Mat, t: f64) -> Result<(Mat, Mat)> {
    check_square("A", a)?;
    crate::linalg::check_shape("B", b, a.nrows(), b.ncols())?;
    if !t.is_finite() {
        return Err(LtiError::InvalidArgument(format!(
            "integration time must be finite, got {t}"
        )));
    }
    let (n, m) = (a.nrows(), b.ncols());
    let mut big = Mat::zeros(n + m, n + m);
    big.view_mut((0, 0), (n, n)).copy_from(&(a * t));
    big.view_mut((0, n), (n, m)).copy_from(&(b * t));
    let e = expm(&big)?;
    Ok((
        e.view((0, 0), (n, n)).clone_owned(),
        e.view((0, n), (n, m)).clone_owned(),
    ))
}

/// First-order-hold (triangle-hold) integrals from one block exponential (Van Loan 1978):
/// `exp([[A t, B t, 0], [0, 0, I], [0, 0, 0]]) = [[Φ, Γ₀, Γ₁], [0, I, I], [0, 0, I]]` with
/// `Φ = e^{At}`, `Γ₀ = ∫₀ᵗ e^{As} ds B` and `Γ₁ = ∫₀ᵗ e^{As} (t − s)/t ds B`.
///
/// With the input linear between samples, `u(kt + τ) = u_k + (u_{k+1} − u_k) τ/t`, the state
/// obeys exactly `x_{k+1} = Φ x_k + (Γ₀ − Γ₁) u_k + Γ₁ u_{k+1}`.
///
/// Returns `(Φ, Γ₀, Γ₁)`.
///
/// # Errors
/// As [`zoh_integrals`]; [`LtiError::InvalidArgument`] if `t = 0`.
pub fn foh_integrals(a: &Mat, b: &Mat, t: f64) -> Result<(Mat, Mat, Mat)> {
    check_square("A", a)?;
    crate::linalg::check_shape("B", b, a.nrows(), b.ncols())?;
    if !t.is_finite() || t == 0.0 {
        return Err(LtiError::InvalidArgument(format!(
            "first-order-hold interval must be finite and non-zero, got {t}"
        )));
    }
    let (n, m) = (a.nrows(), b.ncols());
    let mut big = Mat::zeros(n + 2 * m, n + 2 * m);
    big.view_mut((0, 0), (n, n)).copy_from(&(a * t));
    big.view_mut((0, n), (n, m)).copy_from(&(b * t));
    for i in 0..m {
        big[(n + i, n + m + i)] = 1.0;
    }
    let e = expm(&big)?;
    Ok((
        e.view((0, 0), (n, n)).clone_owned(),
        e.view((0, n), (n, m)).clone_owned(),
        e.view((0, n + m), (n, m)).clone_owned(),
    ))
}

/// Van Loan's integral (Van Loan, "Computing integrals involving the matrix exponential",
/// IEEE Trans. Automat. Control 23(3), 1978, Theorem 1):
/// `exp([[−Fᵀ, W], [0, F]] t) = [[·, G₁₂], [0, G₂₂]]`, `G₂₂ = e^{Ft}`, and
/// `∫₀ᵗ e^{Fᵀs} W e^{Fs} ds = G₂₂ᵀ G₁₂`.
///
/// Returns `(e^{Ft}, ∫₀ᵗ e^{Fᵀs} W e^{Fs} ds)`; the integral is symmetrised when `W` is
/// symmetric.
///
/// # Errors
/// [`LtiError::NotSquare`] / [`LtiError::DimensionMismatch`] for inconsistent shapes, as
/// [`expm`].
pub fn van_loan_integral(f: &Mat, w: &Mat, t: f64) -> Result<(Mat, Mat)> {
    check_square("F", f)?;
    crate::linalg::check_shape("W", w, f.nrows(), f.nrows())?;
    check_finite("W", w)?;
    if !t.is_finite() {
        return Err(LtiError::InvalidArgument(format!(
            "integration time must be finite, got {t}"
        )));
    }
    let n = f.nrows();
    let mut big = Mat::zeros(2 * n, 2 * n);
    big.view_mut((0, 0), (n, n))
        .copy_from(&(f.transpose() * (-t)));
    big.view_mut((0, n), (n, n)).copy_from(&(w * t));
    big.view_mut((n, n), (n, n)).copy_from(&(f * t));
    let e = expm(&big)?;
    let g22 = e.view((n, n), (n, n)).clone_owned();
    let g12 = e.view((0, n), (n, n)).clone_owned();
    let mut integral = g22.transpose() * g12;
    if (w - w.transpose()).norm() == 0.0 {
        integral = crate::linalg::symmetrize(&integral);
    }
    Ok((g22, integral))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        // An m-point rule is exact for degree ≤ 2m − 1: ∫₀¹ x^k dx = 1/(k + 1).
        for m in 1..=16 {
            let (x, w) = gauss_legendre_01(m);
            for k in 0..2 * m {
                let q: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(k as i32)).sum();
                assert!((q - 1.0 / (k as f64 + 1.0)).abs() < 1e-14, "m={m} k={k}");
            }
        }
    }

    #[test]
    fn ell_is_zero_for_normal_and_positive_for_nonnormal() {
        // A scalar has |A|^{2m+1}/‖A‖ = a^{2m}; below θ₁₃ the bound is far under u.
        assert_eq!(ell(&Mat::from_element(1, 1, 1.0), 13), 0);
        // Non-normal [[a, b], [0, a]]: ‖|A|⁷‖₁/‖A‖₁ ≈ 7a⁶ = 0.11 for a = 0.5, so
        // α/u = 0.11/(100800 u) ≈ 1e10 and ℓ = ⌈log₂(1e10)/6⌉ = 6 > 0.
        let a = Mat::from_row_slice(2, 2, &[0.5, 1e8, 0.0, 0.5]);
        assert!(ell(&a, 3) > 0);
    }
}
