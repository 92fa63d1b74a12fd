//! Fixed-size fast path of [`care`](super::care) for small problems.
//!
//! For `n ≤ SMALL_MAX` states and `m ≤ n` inputs, [`RiccatiMethod::Auto`] first runs the same
//! algorithms as the general solver on stack-allocated `n × n` matrices (nalgebra `SMatrix`,
//! one monomorphised copy per order), so a solve performs almost no heap allocation:
//!
//! 1. the cross term is removed and `R` factored as in the general path, with `R`, `Bᵀ` and
//!    `Nᵀ` padded to `n × n` (`R` by an identity block, `Bᵀ`, `Nᵀ` by zero rows — the padding
//!    contributes exact zeros to every product, so no result depends on it);
//! 2. structure-preserving doubling after a Cayley transform (Chu, Fan & Lin, "A
//!    structure-preserving doubling algorithm for continuous-time algebraic Riccati
//!    equations", Linear Algebra Appl. 396, 2005), with the general path's scaling, shift and
//!    stopping rules;
//! 3. Kleinman–Newton refinement in residual-correction form, under the general path's rules
//!    (a step is kept only if it lowers the residual; stop when it gains less than a factor
//!    2), its Lyapunov equation `FᵀΔ + ΔF = −Res(X)` solved directly on the `n(n+1)/2`
//!    unknowns of the symmetric `Δ` (Kronecker form, LU with partial pivoting);
//! 4. **strict acceptance**: the relative residual (the same definition as
//!    [`care_residual`](super::care_residual)) must be at most `100·n·ε` — below the general
//!    path's own acceptance bound [`GOOD_RESIDUAL`](super::GOOD_RESIDUAL) —, every closed-loop
//!    pole (computed on the stack by the fixed-size Hessenberg + Francis QR of
//!    `linalg::small_eig`) must lie in the open left half-plane and, for LQR data
//!    (`Q̃ ⪰ 0`), `X` must be positive semidefinite (as the stabilising solution is then,
//!    `X = ∫ e^{Fᵀt}(Q̃ + KᵀRK)e^{Ft} dt`).
//!
//! A residual at rounding level together with a Hurwitz closed loop identifies the unique
//! stabilising solution, so an accepted result is the one the general path would return, to
//! the problem's conditioning. Anything else (breakdown, slow convergence, a rejected check)
//! returns `None` and the general ordered-Schur path runs as if the fast path did not exist;
//! it also produces every diagnostic error.

use super::{REFINEMENT_FLOOR, RiccatiMethod, RiccatiOptions, RiccatiSolution};
use crate::linalg::small_eig::eigenvalues_small;
use crate::linalg::{Complex64, Mat};
use nalgebra::SMatrix;

/// Largest state dimension handled by the fixed-size path.
pub(crate) const SMALL_MAX: usize = 8;

/// Number of unknowns of a symmetric `SMALL_MAX × SMALL_MAX` matrix.
const SYM_MAX: usize = SMALL_MAX * (SMALL_MAX + 1) / 2;

/// Acceptance bound on the relative residual, in units of `n·ε`.
const ACCEPT_FACTOR: f64 = 100.0;

type Sq<const N: usize> = SMatrix<f64, N, N>;

/// Tries the fixed-size path; `None` means "use the general solver" (the data were already
/// validated by the caller).
pub(crate) fn care_small(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    options: &RiccatiOptions,
) -> Option<RiccatiSolution> {
    let m = b.ncols();
    if m == 0 || m > a.nrows() {
        return None;
    }
    match a.nrows() {
        1 => solve::<1>(a, b, q, r, n, options),
        2 => solve::<2>(a, b, q, r, n, options),
        3 => solve::<3>(a, b, q, r, n, options),
        4 => solve::<4>(a, b, q, r, n, options),
        5 => solve::<5>(a, b, q, r, n, options),
        6 => solve::<6>(a, b, q, r, n, options),
        7 => solve::<7>(a, b, q, r, n, options),
        8 => solve::<8>(a, b, q, r, n, options),
        _ => None,
    }
}

/// `A·B` by the plain triple loop over the column arrays of nalgebra's storage (`j, k, i`
/// order, each result column accumulated in a local array). For the fixed orders used here
/// the compiler unrolls and vectorises it completely, which nalgebra's generic product (a
/// `gemm` call with run-time strides) does not.
#[inline(always)]
fn mm<const N: usize>(a: &Sq<N>, b: &Sq<N>) -> Sq<N> {
    let (ac, bc) = (&a.data.0, &b.data.0);
    let mut c = Sq::<N>::zeros();
    for (cj, bj) in c.data.0.iter_mut().zip(bc) {
        let mut col = [0.0f64; N];
        for (ak, &bkj) in ac.iter().zip(bj) {
            for (ci, &aik) in col.iter_mut().zip(ak) {
                *ci += aik * bkj;
            }
        }
        *cj = col;
    }
    c
}

/// `Aᵀ·B`.
#[inline(always)]
fn mtm<const N: usize>(a: &Sq<N>, b: &Sq<N>) -> Sq<N> {
    let mut c = Sq::<N>::zeros();
    let (av, bv) = (a.as_slice(), b.as_slice());
    let cv = c.as_mut_slice();
    for j in 0..N {
        for i in 0..N {
            let mut acc = 0.0;
            for k in 0..N {
                acc += av[k + i * N] * bv[k + j * N];
            }
            cv[i + j * N] = acc;
        }
    }
    c
}

/// `tr(A·B) = Σ_ij a_ij b_ji` without forming the product.
fn trace_of_product<const N: usize>(a: &Sq<N>, b: &Sq<N>) -> f64 {
    let mut t = 0.0;
    for i in 0..N {
        for j in 0..N {
            t += a[(i, j)] * b[(j, i)];
        }
    }
    t
}

/// Symmetric part `(M + Mᵀ)/2`, each off-diagonal pair formed once (the diagonal is kept:
/// `(m_ii + m_ii)/2 = m_ii` exactly).
#[inline(always)]
fn sym<const N: usize>(m: &Sq<N>) -> Sq<N> {
    let mut s = *m;
    for j in 0..N {
        for i in 0..j {
            let v = (m[(i, j)] + m[(j, i)]) * 0.5;
            s[(i, j)] = v;
            s[(j, i)] = v;
        }
    }
    s
}

/// Frobenius norm `sqrt(Σ m_ij²)` (the plain sum of squares, as nalgebra's `norm`), summed
/// column-wise (one partial sum per row index) so that the compiler vectorises it.
#[inline(always)]
fn fro<const N: usize>(m: &Sq<N>) -> f64 {
    let mut acc = [0.0f64; N];
    for col in &m.data.0 {
        for (a, &v) in acc.iter_mut().zip(col) {
            *a += v * v;
        }
    }
    acc.iter().sum::<f64>().sqrt()
}

/// Induced 1-norm (largest column sum).
fn norm1<const N: usize>(m: &Sq<N>) -> f64 {
    m.column_iter()
        .map(|c| c.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Inverse by Gauss–Jordan elimination with partial pivoting (`PA = LU` followed by the
/// solve for the columns of the identity, done in place) and its exact reciprocal 1-norm
/// condition number; `None` if singular or not finite.
fn inverse_rcond<const N: usize>(m: &Sq<N>) -> Option<(Sq<N>, f64)> {
    // Row-major working copies: row operations then touch contiguous memory.
    let mut w = [[0.0f64; N]; N];
    let mut inv = [[0.0f64; N]; N];
    for i in 0..N {
        for j in 0..N {
            w[i][j] = m[(i, j)];
        }
        inv[i][i] = 1.0;
    }
    for col in 0..N {
        let mut piv = col;
        for row in col + 1..N {
            if w[row][col].abs() > w[piv][col].abs() {
                piv = row;
            }
        }
        let d = w[piv][col];
        if d == 0.0 || !d.is_finite() {
            return None;
        }
        if piv != col {
            w.swap(piv, col);
            inv.swap(piv, col);
        }
        let (wc, ic) = (w[col], inv[col]);
        // One division per pivot; the multipliers are formed with its reciprocal.
        let dinv = 1.0 / d;
        for row in 0..N {
            if row != col {
                let f = w[row][col] * dinv;
                if f != 0.0 {
                    for k in 0..N {
                        w[row][k] -= f * wc[k];
                        inv[row][k] -= f * ic[k];
                    }
                }
            }
        }
    }
    let rdiag: [f64; N] = std::array::from_fn(|i| 1.0 / w[i][i]);
    let inv = Sq::<N>::from_fn(|i, j| inv[i][j] * rdiag[i]);
    let rc = 1.0 / (norm1(m) * norm1(&inv));
    rc.is_finite().then_some((inv, rc))
}

/// `true` if `M + δI` admits a Cholesky factorisation, `δ = tol·‖M‖_F`: `M` is positive
/// semidefinite up to `tol` relative.
fn is_psd<const N: usize>(m: &Sq<N>, tol: f64) -> bool {
    let shifted = m + Sq::<N>::identity() * (tol * fro(m));
    cholesky(&shifted).is_some()
}

/// Lower Cholesky factor `L` of `M = LLᵀ` from the lower triangle of `M` (the
/// column-by-column Cholesky–Banachiewicz recurrence, Golub & Van Loan, "Matrix
/// Computations", 4th ed., Algorithm 4.2.2); `None` unless every pivot is positive and
/// finite (`M` not numerically positive definite).
fn cholesky<const N: usize>(m: &Sq<N>) -> Option<Sq<N>> {
    let mut l = Sq::<N>::zeros();
    for j in 0..N {
        let mut d = m[(j, j)];
        for k in 0..j {
            d -= l[(j, k)] * l[(j, k)];
        }
        if !(d > 0.0 && d.is_finite()) {
            return None;
        }
        let ljj = d.sqrt();
        l[(j, j)] = ljj;
        for i in j + 1..N {
            let mut s = m[(i, j)];
            for k in 0..j {
                s -= l[(i, k)] * l[(j, k)];
            }
            l[(i, j)] = s / ljj;
        }
    }
    Some(l)
}

/// `L⁻¹B` by forward substitution (`L` lower triangular with a nonzero diagonal, as
/// [`cholesky`] returns it).
fn solve_lower<const N: usize>(l: &Sq<N>, b: &Sq<N>) -> Sq<N> {
    let mut x = *b;
    for c in 0..N {
        for i in 0..N {
            let mut s = x[(i, c)];
            for k in 0..i {
                s -= l[(i, k)] * x[(k, c)];
            }
            x[(i, c)] = s / l[(i, i)];
        }
    }
    x
}

/// `L⁻ᵀB` by back substitution (`L` as in [`solve_lower`]).
fn solve_lower_tr<const N: usize>(l: &Sq<N>, b: &Sq<N>) -> Sq<N> {
    let mut x = *b;
    for c in 0..N {
        for i in (0..N).rev() {
            let mut s = x[(i, c)];
            for k in i + 1..N {
                s -= l[(k, i)] * x[(k, c)];
            }
            x[(i, c)] = s / l[(i, i)];
        }
    }
    x
}

/// Data of the problem with the cross term removed (module docs, step 1).
struct Data<const N: usize> {
    /// `A` as given.
    a: Sq<N>,
    /// `Aᵀ`.
    a_tr: Sq<N>,
    /// `B` padded with zero columns to `n × n`.
    b: Sq<N>,
    /// `Q` (symmetric part).
    q: Sq<N>,
    /// `‖Q‖_F` of the data as given (a residual term).
    q_norm: f64,
    /// Lower Cholesky factor of `R` padded by an identity block.
    l: Sq<N>,
    /// `L⁻¹Bᵀ` (rows `≥ m` zero).
    w0: Sq<N>,
    /// `L⁻¹Nᵀ` (rows `≥ m` zero).
    v: Sq<N>,
    /// `Ã = A − BR⁻¹Nᵀ`.
    at: Sq<N>,
    /// `G = BR⁻¹Bᵀ`.
    g: Sq<N>,
    /// `Q̃ = Q − NR⁻¹Nᵀ`.
    qt: Sq<N>,
}

impl<const N: usize> Data<N> {
    fn new(a: &Mat, b: &Mat, q: &Mat, r: &Mat, nc: Option<&Mat>) -> Option<Self> {
        let m = b.ncols();
        let a_f = Sq::<N>::from_fn(|i, j| a[(i, j)]);
        let b_f = Sq::<N>::from_fn(|i, j| if j < m { b[(i, j)] } else { 0.0 });
        let q_f = Sq::<N>::from_fn(|i, j| 0.5 * (q[(i, j)] + q[(j, i)]));
        let r_f = Sq::<N>::from_fn(|i, j| {
            if i < m && j < m {
                r[(i, j)]
            } else if i == j {
                1.0
            } else {
                0.0
            }
        });
        let l = cholesky(&r_f)?;
        let w0 = solve_lower(&l, &b_f.transpose());
        let v = match nc {
            Some(nm) => {
                let nt = Sq::<N>::from_fn(|i, j| if i < m { nm[(j, i)] } else { 0.0 });
                solve_lower(&l, &nt)
            }
            None => Sq::<N>::zeros(),
        };
        let at = a_f - mtm(&w0, &v);
        let g = sym(&mtm(&w0, &w0));
        let qt = sym(&(q_f - mtm(&v, &v)));
        Some(Self {
            a: a_f,
            a_tr: a_f.transpose(),
            b: b_f,
            q: q_f,
            q_norm: q.norm(),
            l,
            w0,
            v,
            at,
            g,
            qt,
        })
    }

    /// Gain `K = R⁻¹(BᵀX + Nᵀ) = L⁻ᵀ(W₀X + V)` (rows `≥ m` zero) and `Z = W₀X + V`.
    fn gain(&self, x: &Sq<N>) -> Option<(Sq<N>, Sq<N>)> {
        let z = mm(&self.w0, x) + self.v;
        let k = solve_lower_tr(&self.l, &z);
        Some((k, z))
    }

    /// Residual matrix `AᵀX + XA − (XB+N)R⁻¹(BᵀX+Nᵀ) + Q` (with `(XB+N)R⁻¹(BᵀX+Nᵀ) = ZᵀZ`)
    /// and the relative residual (sum of the four terms' Frobenius norms in the denominator;
    /// `‖XA‖_F = ‖(AᵀX)ᵀ‖_F = ‖AᵀX‖_F` for symmetric `X`).
    fn residual(&self, x: &Sq<N>, z: &Sq<N>) -> (Sq<N>, f64) {
        let atx = mm(&self.a_tr, x);
        let xa = atx.transpose();
        let g = mm(&z.transpose(), z);
        let res = sym(&(atx + xa - g + self.q));
        let s = 2.0 * fro(&atx) + fro(&g) + self.q_norm;
        let rn = fro(&res);
        (res, if s > 0.0 { rn / s } else { rn })
    }
}

/// Scale factor `sqrt(‖Q̃‖_F / ‖G‖_F)` (the general path's step 3).
fn scale_factor<const N: usize>(d: &Data<N>, scaling: bool) -> f64 {
    let (qn, gn) = (fro(&d.qt), fro(&d.g));
    if scaling && qn > 0.0 && gn > 0.0 && (qn / gn).is_finite() {
        (qn / gn).sqrt()
    } else {
        1.0
    }
}

/// Doubling after a Cayley transform (same shift choice as the general path), unrefined.
fn doubling<const N: usize>(d: &Data<N>, s: f64) -> Option<Sq<N>> {
    let (e0, g0, h0) = cayley_start(d, s)?;
    sda_iterate(e0, g0, h0).map(|(_, _, h)| h * s)
}

/// The starting pencil `(E₀, G₀, H₀)` of the doubling iteration for the data scaled by `s`
/// (`G·s`, `Q̃/s`): the Cayley transform with shift `γ` (Chu, Fan & Lin 2005).
fn cayley_start<const N: usize>(d: &Data<N>, s: f64) -> Option<(Sq<N>, Sq<N>, Sq<N>)> {
    let g = d.g * s;
    let q = d.qt * (1.0 / s);
    let eye = Sq::<N>::identity();
    // Shift: the root mean square of the Hamiltonian's eigenvalues, from
    // `Σλ(H)² = tr(H²) = 2 tr(Ã²) + 2 tr(GQ̃)` (scale-invariant; the ±λ pairs share λ²), where
    // the convergence factor `max |(λ+γ)/(λ−γ)|` over the stable eigenvalues is typically
    // smallest; the general path's norm-based shift when that vanishes. The shift only
    // affects the speed of convergence.
    let tr = trace_of_product(&d.at, &d.at) + trace_of_product(&d.g, &d.qt);
    let rms = (tr.abs() / N as f64).sqrt();
    let mut gamma = if rms.is_finite() && rms > 1e-3 {
        rms
    } else {
        (fro(&d.at).max((fro(&g) * fro(&q)).sqrt()) / (N as f64).sqrt()).max(1e-3)
    };
    for _ in 0..4 {
        let ag = d.at - eye * gamma;
        let Some((agi, _)) = inverse_rcond(&ag).filter(|(_, rc)| *rc >= 1e3 * f64::EPSILON) else {
            gamma *= 2.0;
            continue;
        };
        let agi_g = mm(&agi, &g);
        let w = ag.transpose() + mm(&q, &agi_g);
        let Some((wi, _)) = inverse_rcond(&w).filter(|(_, rc)| *rc >= 1e3 * f64::EPSILON) else {
            gamma *= 2.0;
            continue;
        };
        let wi_q_agi = mm(&mm(&wi, &q), &agi);
        let e0 = eye + (agi - mm(&agi_g, &wi_q_agi)) * (2.0 * gamma);
        let g0 = sym(&(mm(&agi_g, &wi) * (2.0 * gamma)));
        let h0 = sym(&(wi_q_agi * (2.0 * gamma)));
        return Some((e0, g0, h0));
    }
    None
}

/// One doubling step on the symplectic pencil `(E, G, H)` in first standard form (Chu, Fan,
/// Lin, Wang 2004), in place; returns `‖ΔH‖_F`, or `None` if `I + GH` is numerically singular
/// (reciprocal condition number below `ε`).
///
/// With `W = I + GH` and `[Y₁ Y₂] = W⁻¹[E G]` (the arrangement of the general path's
/// `sda_iterate`, eight `n × n` products): `E₊ = E Y₁`, `G₊ = G + (E Y₂) Eᵀ`,
/// `H₊ = H + Eᵀ(H Y₁)` (`H W⁻¹ = W⁻ᵀH`, so this is the textbook `H + Eᵀ(I + HG)⁻¹HE`); `G₊`
/// and `H₊` are symmetrised.
#[inline(always)]
fn sda_step<const N: usize>(e: &mut Sq<N>, g: &mut Sq<N>, h: &mut Sq<N>) -> Option<f64> {
    let w = Sq::<N>::identity() + mm(g, h);
    let (wi, rc) = inverse_rcond(&w)?;
    if rc < f64::EPSILON {
        return None;
    }
    let y1 = mm(&wi, e);
    let y2 = mm(&wi, g);
    let et = e.transpose();
    let delta_h = mm(&et, &mm(h, &y1));
    *h = sym(&(*h + delta_h));
    *g = sym(&(*g + mm(&mm(e, &y2), &et)));
    *e = mm(e, &y1);
    Some(fro(&delta_h))
}

/// The doubling iteration ([`sda_step`]) with the general path's stopping rules; returns the
/// final pencil `(E, G, H)`, `H` the approximation of the solution.
///
/// Stopping: `‖ΔH‖ ≤ 4√n·ε‖H‖`, `‖E‖ ≤ ε`, the general path's prediction of the next
/// increment `‖ΔH‖·(‖E₊‖/‖E‖)² ≤ ε‖H‖` (in the quadratic phase `ΔH_{k+1} = O(‖E_{k+1}‖²)`,
/// so the confirming step that would change `H` below rounding level is not taken), or
/// rounding-level stagnation.
fn sda_iterate<const N: usize>(
    mut e: Sq<N>,
    mut g: Sq<N>,
    mut h: Sq<N>,
) -> Option<(Sq<N>, Sq<N>, Sq<N>)> {
    let tol = 4.0 * f64::EPSILON * (N as f64).sqrt();
    let mut last_dh = f64::INFINITY;
    let mut e_norm = fro(&e);
    for _ in 0..60 {
        let dh = sda_step(&mut e, &mut g, &mut h)?;
        let hn = fro(&h);
        let e_new = fro(&e);
        if !hn.is_finite() || !e_new.is_finite() {
            return None;
        }
        let predicted = if e_norm > 0.0 {
            dh * (e_new / e_norm).powi(2)
        } else {
            0.0
        };
        if dh <= tol * hn || predicted <= f64::EPSILON * hn || e_new <= f64::EPSILON {
            return Some((e, g, h));
        }
        if dh <= 1e-10 * hn && dh >= 0.5 * last_dh {
            return Some((e, g, h));
        }
        last_dh = dh;
        e_norm = e_new;
    }
    None
}

/// Eigenvalues of `f` in the order of [`sort_eigenvalues`](crate::linalg::sort_eigenvalues)
/// by the fixed-size Hessenberg–Francis QR of [`eigenvalues_small`] (no allocation); `None`
/// (non-finite entries, or no convergence) sends the problem to the general path.
///
/// `eigenvalues_small` reads a row-major array; the column arrays of `f`'s (column-major)
/// storage are passed as its rows, so it works on `fᵀ`, which has the same eigenvalues, and
/// its backward error `fᵀ + E` is the backward error `f + Eᵀ` of the same size.
fn eigenvalues<const N: usize>(f: &Sq<N>) -> Option<[Complex64; N]> {
    eigenvalues_small(&f.data.0).ok()
}

/// Index of the unknown `Δ_ij = Δ_ji` in the packed upper triangle (column by column).
fn packed(i: usize, j: usize) -> usize {
    let (i, j) = if i <= j { (i, j) } else { (j, i) };
    j * (j + 1) / 2 + i
}

/// Solves `FᵀΔ + ΔF = C` for symmetric `Δ` (`C` symmetric) through its `n(n+1)/2` packed
/// unknowns: equation `(i, j)`, `i ≤ j`, reads `Σ_k F_ki Δ_kj + Σ_k Δ_ik F_kj = C_ij`. Gaussian
/// elimination with partial pivoting; `None` if a pivot vanishes.
fn lyap_packed<const N: usize>(f: &Sq<N>, c: &Sq<N>) -> Option<Sq<N>> {
    let p = N * (N + 1) / 2;
    let mut m = [[0.0f64; SYM_MAX]; SYM_MAX];
    let mut rhs = [0.0f64; SYM_MAX];
    for j in 0..N {
        for i in 0..=j {
            let row = packed(i, j);
            rhs[row] = c[(i, j)];
            for k in 0..N {
                m[row][packed(k, j)] += f[(k, i)];
                m[row][packed(i, k)] += f[(k, j)];
            }
        }
    }
    for col in 0..p {
        let piv = (col..p)
            .max_by(|&x, &y| m[x][col].abs().total_cmp(&m[y][col].abs()))
            .unwrap_or(col);
        if m[piv][col] == 0.0 || !m[piv][col].is_finite() {
            return None;
        }
        m.swap(piv, col);
        rhs.swap(piv, col);
        let d = m[col][col];
        for row in col + 1..p {
            let factor = m[row][col] / d;
            if factor != 0.0 {
                for k in col..p {
                    m[row][k] -= factor * m[col][k];
                }
                rhs[row] -= factor * rhs[col];
            }
        }
    }
    for row in (0..p).rev() {
        let mut v = rhs[row];
        for k in row + 1..p {
            v -= m[row][k] * rhs[k];
        }
        rhs[row] = v / m[row][row];
    }
    Some(Sq::<N>::from_fn(|i, j| rhs[packed(i, j)]))
}

fn solve<const N: usize>(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    nc: Option<&Mat>,
    options: &RiccatiOptions,
) -> Option<RiccatiSolution> {
    let m = b.ncols();
    let d = Data::<N>::new(a, b, q, r, nc)?;
    let s = scale_factor(&d, options.scaling);
    let mut x = sym(&doubling(&d, s)?);
    let (mut k, z) = d.gain(&x)?;
    let (mut res, mut residual) = d.residual(&x, &z);
    let floor = REFINEMENT_FLOOR * N as f64 * f64::EPSILON;
    let mut steps = 0;
    while steps < options.max_refinement_steps && residual > floor && residual.is_finite() {
        let f = d.a - mm(&d.b, &k);
        let Some(delta) = lyap_packed(&f, &(-res)) else {
            break;
        };
        let x_new = sym(&(x + delta));
        let Some((k_new, z_new)) = d.gain(&x_new) else {
            break;
        };
        let (res_new, rel) = d.residual(&x_new, &z_new);
        if rel < residual {
            let gain = residual / rel;
            x = x_new;
            k = k_new;
            res = res_new;
            residual = rel;
            steps += 1;
            if gain < 2.0 {
                break;
            }
        } else {
            break;
        }
    }
    if residual.is_nan() || residual > ACCEPT_FACTOR * N as f64 * f64::EPSILON {
        return None;
    }
    let tol = ACCEPT_FACTOR * N as f64 * f64::EPSILON;
    if is_psd(&d.qt, tol) && !is_psd(&x, tol) {
        return None;
    }
    let f = d.a - mm(&d.b, &k);
    let poles = eigenvalues(&f)?;
    if poles.iter().any(|p| p.re.is_nan() || p.re >= 0.0) {
        return None;
    }
    Some(RiccatiSolution {
        x: Mat::from_fn(N, N, |i, j| x[(i, j)]),
        gain: Mat::from_fn(m, N, |i, j| k[(i, j)]),
        closed_loop_poles: poles.to_vec(),
        residual,
        method: RiccatiMethod::Doubling,
        refinement_steps: steps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::testing::splitmix_matrix;

    const EPS: f64 = f64::EPSILON;

    fn sq<const N: usize>(m: &Mat) -> Sq<N> {
        Sq::<N>::from_fn(|i, j| m[(i, j)])
    }

    /// `γ_n = nε/(1 − nε)`, the rounding-error constant of an `n`-term sum (Higham,
    /// "Accuracy and Stability of Numerical Algorithms", 2nd ed., §3.1).
    fn gamma(n: usize) -> f64 {
        n as f64 * EPS / (1.0 - n as f64 * EPS)
    }

    /// The helpers against their definitions and nalgebra's own routines, for one order.
    fn helpers_for<const N: usize>(seed: u64) {
        let a = sq::<N>(&splitmix_matrix(N, N, seed));
        let b = sq::<N>(&splitmix_matrix(N, N, seed + 1000));
        // `mm`: each entry is an inner product of length N, within γ_N (|A||B|)_ij of the
        // exact one (Higham §3.5), so it differs from nalgebra's product (another summation
        // order) by at most 2γ_N (|A||B|)_ij.
        let got = mm(&a, &b);
        let want = a * b;
        let bound = a.abs() * b.abs() * (2.0 * gamma(N));
        for (i, j) in (0..N).flat_map(|i| (0..N).map(move |j| (i, j))) {
            assert!(
                (got[(i, j)] - want[(i, j)]).abs() <= bound[(i, j)],
                "mm ({i},{j})"
            );
        }
        // `sym` is (M + Mᵀ)/2 entry by entry: the same two roundings in either order.
        assert_eq!(sym(&a), (a + a.transpose()) * 0.5);
        // `fro`: a sum of N² squares in another order, then a square root: relative
        // difference at most N²ε (γ_{N²}) plus the root's half ulp.
        let (f, n) = (fro(&a), a.norm());
        assert!(
            (f - n).abs() <= (N * N) as f64 * EPS * n + EPS * n,
            "fro {f} vs {n}"
        );

        // Cholesky of an SPD matrix M = CᵀC + I/10: backward stable, |LLᵀ − M| ≤
        // γ_{N+1}|L||Lᵀ| (Higham Thm 10.3), and ‖|L||Lᵀ|‖_F ≤ ‖L‖_F²; a factor 2 spare.
        let m = a.transpose() * a + Sq::<N>::identity() * 0.1;
        let l = cholesky(&m).expect("SPD");
        for i in 0..N {
            for j in i + 1..N {
                assert_eq!(l[(i, j)], 0.0, "L not lower triangular");
            }
        }
        let tol = 2.0 * gamma(N + 1) * l.norm_squared();
        assert!((l * l.transpose() - m).norm() <= tol, "LLᵀ ≠ M");
        // Indefinite: a negative pivot appears, no factor.
        let mut ind = m;
        ind[(N - 1, N - 1)] = -1.0 - m.norm();
        assert!(cholesky(&ind).is_none());
        // Triangular solves: backward stable (Higham Thm 8.5, |ΔL| ≤ γ_N|L|), so the
        // residual is at most γ_N‖|L||X|‖_F ≤ γ_N‖L‖_F‖X‖_F; a factor 2 spare.
        let x = solve_lower(&l, &b);
        let tol = 2.0 * gamma(N) * l.norm() * x.norm();
        assert!((l * x - b).norm() <= tol, "L X ≠ B");
        let x = solve_lower_tr(&l, &b);
        let tol = 2.0 * gamma(N) * l.norm() * x.norm();
        assert!((l.transpose() * x - b).norm() <= tol, "Lᵀ X ≠ B");

        // Inverse: residual of Gauss–Jordan with partial pivoting, ‖MX − I‖ ≤ c_N ε‖M‖‖X‖
        // with a modest c_N for these random matrices (Higham §14.4; growth factor small);
        // c_N = 20N allows for it. The rcond is the definition 1/(‖M‖₁‖M⁻¹‖₁), compared with
        // the one from nalgebra's LU inverse: the two inverses differ by O(κ₁ Nε) relatively
        // (first-order perturbation of the inverse), so the rconds by O(κ₁ Nε)·rcond; the
        // constant 100 covers c_N for both routines.
        let (inv, rc) = inverse_rcond(&a).expect("nonsingular");
        let tol = 20.0 * N as f64 * EPS * a.norm() * inv.norm();
        assert!((a * inv - Sq::<N>::identity()).norm() <= tol, "M M⁻¹ ≠ I");
        let reference = a.try_inverse().expect("nonsingular");
        let rc_ref = 1.0 / (norm1(&a) * norm1(&reference));
        let kappa = 1.0 / rc_ref;
        assert!(
            (rc - rc_ref).abs() <= 100.0 * N as f64 * EPS * kappa * rc_ref,
            "rcond {rc} vs {rc_ref}"
        );
        assert!(inverse_rcond(&Sq::<N>::zeros()).is_none());
    }

    #[test]
    fn helpers_satisfy_their_defining_equations() {
        for seed in 0..20 {
            helpers_for::<1>(seed);
            helpers_for::<2>(seed);
            helpers_for::<3>(seed);
            helpers_for::<4>(seed);
            helpers_for::<5>(seed);
            helpers_for::<8>(seed);
        }
    }

    /// Runs the doubling to its stop on the given data, then takes the step the predictive
    /// test skipped: it must change `H` by no more than the rounding-level convergence bound
    /// `4√n·ε‖H‖` (the rule that would have stopped the iteration after it).
    fn skipped_step_is_negligible<const N: usize>(a: &Mat, b: &Mat, q: &Mat, r: &Mat) {
        let d = Data::<N>::new(a, b, q, r, None).expect("data");
        let s = scale_factor(&d, true);
        let (e0, g0, h0) = cayley_start(&d, s).expect("Cayley transform");
        let (mut e, mut g, mut h) = sda_iterate(e0, g0, h0).expect("converges");
        let h_stop = h;
        let dh = sda_step(&mut e, &mut g, &mut h).expect("step");
        let bound = 4.0 * (N as f64).sqrt() * EPS * fro(&h_stop);
        assert!(
            dh <= bound,
            "n = {N}: skipped step changes H by {dh:e} > {bound:e}"
        );
    }

    #[test]
    fn predicted_stop_only_skips_a_rounding_level_step() {
        // The cart pendulum of `care-n4` (book table 3.5 parameters, `docs/model.md` §1).
        let (ac, bc, mp, lp, jp, mup, g) = (6.25, 4.36, 0.107, 0.230, 1.59e-3, 2.35e-4, 9.81);
        let j = jp + mp * lp * lp;
        #[rustfmt::skip]
        let a = Mat::from_row_slice(4, 4, &[
            0.0, 0.0, 1.0, 0.0,
            0.0, 0.0, 0.0, 1.0,
            0.0, 0.0, -ac, 0.0,
            0.0, mp * g * lp / j, ac * mp * lp / j, -mup / j,
        ]);
        let b = Mat::from_row_slice(4, 1, &[0.0, 0.0, bc, -bc * mp * lp / j]);
        let q = Mat::from_diagonal(&crate::linalg::Vector::from_column_slice(&[
            100.0, 10.0, 1.0, 1.0,
        ]));
        skipped_step_is_negligible::<4>(&a, &b, &q, &Mat::identity(1, 1));
        // Random LQ problems (Q = CᵀC/n + I/10, R = I).
        fn random<const N: usize>(seed: u64, m: usize) {
            let a = splitmix_matrix(N, N, seed);
            let b = splitmix_matrix(N, m, seed + 1);
            let c = splitmix_matrix(N, N, seed + 2);
            let q = c.transpose() * &c * (1.0 / N as f64) + Mat::identity(N, N) * 0.1;
            skipped_step_is_negligible::<N>(&a, &b, &q, &Mat::identity(m, m));
        }
        for seed in 0..10 {
            random::<2>(seed * 7, 1);
            random::<3>(seed * 7, 2);
            random::<4>(seed * 7, 1);
            random::<6>(seed * 7, 2);
            random::<8>(seed * 7, 3);
        }
    }
}
