//! Small dense kernels shared by the Schur and matrix-equation solvers.
//!
//! Everything here works on column-major storage (`Mat::as_slice`, leading dimension = number
//! of rows) and is written after the corresponding LAPACK auxiliaries (`dlartg`, `dlarfg`,
//! `dlanv2`, `dlasy2`), re-derived and re-implemented for this crate. The LU factorisation
//! with its solves and condition estimate is the submodule `lu`.

mod lu;

pub(crate) use lu::Lu;

/// Safe minimum: the smallest positive normal `f64` such that `1/SAFMIN` does not overflow.
pub(crate) const SAFMIN: f64 = f64::MIN_POSITIVE;
/// Relative machine precision `ε = 2⁻⁵²` (LAPACK's `dlamch('P')`).
pub(crate) const EPS: f64 = f64::EPSILON;

/// Givens rotation `[c s; −s c] [f; g] = [r; 0]` (LAPACK `dlartg` convention, `c ≥ 0`).
#[inline]
pub(crate) fn lartg(f: f64, g: f64) -> (f64, f64, f64) {
    if g == 0.0 {
        (1.0, 0.0, f)
    } else if f == 0.0 {
        (0.0, g.signum(), g.abs())
    } else {
        let d = hypot_fast(f, g);
        let r = d.copysign(f);
        (f.abs() / d, g / r, r)
    }
}

/// Applies the rotation `x ← c x + s y`, `y ← c y − s x` elementwise.
#[inline]
pub(crate) fn rot(x: &mut [f64], y: &mut [f64], c: f64, s: f64) {
    for (xi, yi) in x.iter_mut().zip(y.iter_mut()) {
        let t = c * *xi + s * *yi;
        *yi = c * *yi - s * *xi;
        *xi = t;
    }
}

/// Rotates rows `r1` and `r2` of the column-major `ld × ncols` array `a` over columns
/// `cols`: `row1 ← c row1 + s row2`, `row2 ← c row2 − s row1`.
#[inline]
pub(crate) fn rot_rows(
    a: &mut [f64],
    ld: usize,
    r1: usize,
    r2: usize,
    cols: std::ops::Range<usize>,
    c: f64,
    s: f64,
) {
    for j in cols {
        let x = a[r1 + j * ld];
        let y = a[r2 + j * ld];
        a[r1 + j * ld] = c * x + s * y;
        a[r2 + j * ld] = c * y - s * x;
    }
}

/// Rotates columns `c1 < c2` of the column-major array `a` (leading dimension `ld`) over
/// rows `rows`: `col1 ← c col1 + s col2`, `col2 ← c col2 − s col1`.
#[inline]
pub(crate) fn rot_cols(
    a: &mut [f64],
    ld: usize,
    c1: usize,
    c2: usize,
    rows: std::ops::Range<usize>,
    c: f64,
    s: f64,
) {
    debug_assert!(c1 < c2);
    let (lo, hi) = a.split_at_mut(c2 * ld);
    let x = &mut lo[c1 * ld + rows.start..c1 * ld + rows.end];
    let y = &mut hi[rows.start..rows.end];
    rot(x, y, c, s);
}

/// Householder reflector (LAPACK `dlarfg`): given `alpha` and `x`, finds `beta`, `tau` and
/// overwrites `x` with `v` such that `(I − τ [1; v][1; v]ᵀ) [alpha; x] = [beta; 0]`.
/// Returns `(beta, tau)`; `tau = 0` (identity) when `x = 0`.
pub(crate) fn larfg(alpha: f64, x: &mut [f64]) -> (f64, f64) {
    // Fast path: with the largest magnitude of (alpha, x) in [1e-150, 1e150] no square
    // overflows, nor their sum for fewer than 2²⁰ entries (≤ 2²⁰·1e300 < 1e307); squares that
    // underflow are negligible against the largest one; and |beta| ≥ 1e-150 needs no
    // rescaling — so beta = ∓‖(alpha, x)‖ with a single square root.
    let xmax = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if xmax == 0.0 {
        return (alpha, 0.0);
    }
    let big = xmax.max(alpha.abs());
    if xmax.is_finite() && (1e-150..=1e150).contains(&big) && x.len() < 1 << 20 {
        let ss = alpha * alpha + x.iter().map(|v| v * v).sum::<f64>();
        let beta = -ss.sqrt().copysign(alpha);
        let tau = (beta - alpha) / beta;
        let scal = 1.0 / (alpha - beta);
        x.iter_mut().for_each(|v| *v *= scal);
        return (beta, tau);
    }
    let mut xnorm = norm2(x);
    if xnorm == 0.0 {
        return (alpha, 0.0);
    }
    let mut alpha = alpha;
    let mut beta = -hypot_fast(alpha, xnorm).copysign(alpha);
    let rsafmn = 1.0 / (SAFMIN / EPS);
    let mut knt = 0;
    if beta.abs() < SAFMIN / EPS {
        // Rescale so that beta is representable with full accuracy.
        while beta.abs() < SAFMIN / EPS && knt < 20 {
            knt += 1;
            x.iter_mut().for_each(|v| *v *= rsafmn);
            beta *= rsafmn;
            alpha *= rsafmn;
        }
        xnorm = norm2(x);
        beta = -hypot_fast(alpha, xnorm).copysign(alpha);
    }
    let tau = (beta - alpha) / beta;
    let scal = 1.0 / (alpha - beta);
    x.iter_mut().for_each(|v| *v *= scal);
    for _ in 0..knt {
        beta *= SAFMIN / EPS;
    }
    (beta, tau)
}

/// `sqrt(a² + b²)` without spurious overflow or underflow: the plain formula when the larger
/// magnitude lies in `[1e-150, 1e150]` (where neither square can overflow and an underflowing
/// smaller square is negligible), `f64::hypot` otherwise; within two ulps of the exact value.
#[inline]
pub(crate) fn hypot_fast(a: f64, b: f64) -> f64 {
    let m = a.abs().max(b.abs());
    if (1e-150..=1e150).contains(&m) {
        (a * a + b * b).sqrt()
    } else {
        a.hypot(b)
    }
}

/// Euclidean norm with scaling against overflow/underflow.
pub(crate) fn norm2(x: &[f64]) -> f64 {
    let amax = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if amax == 0.0 || !amax.is_finite() {
        return amax;
    }
    if !(1e-150..=1e150).contains(&amax) {
        let s: f64 = x.iter().map(|v| (v / amax) * (v / amax)).sum();
        amax * s.sqrt()
    } else {
        x.iter().map(|v| v * v).sum::<f64>().sqrt()
    }
}

/// Result of [`lanv2`]: the standardised block `[[a, b], [c, d]]`, its eigenvalues
/// `(re, im)` and the rotation `(cs, sn)`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Lanv2 {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub d: f64,
    pub rt1: (f64, f64),
    pub rt2: (f64, f64),
    pub cs: f64,
    pub sn: f64,
}

/// Schur factorisation of a real 2×2 block in standard form (LAPACK `dlanv2`):
/// `[a b; c d] = [cs −sn; sn cs] [aa bb; cc dd] [cs sn; −sn cs]` where either `cc = 0`
/// (real eigenvalues `aa`, `dd`) or `aa = dd` and `bb·cc < 0` (complex pair
/// `aa ± sqrt(bb·cc)`).
///
/// Applying it to a larger matrix: rows `(k, k+1)` right of the block are rotated with
/// `rot(row_k, row_k1, cs, sn)`, columns `(k, k+1)` above it with the same call, and the
/// Schur vectors' columns likewise.
pub(crate) fn lanv2(a: f64, b: f64, c: f64, d: f64) -> Lanv2 {
    let multpl = 4.0;
    let (mut a, mut b, mut c, mut d) = (a, b, c, d);
    let (mut cs, mut sn);
    if c == 0.0 {
        cs = 1.0;
        sn = 0.0;
    } else if b == 0.0 {
        // Swap rows and columns.
        cs = 0.0;
        sn = 1.0;
        std::mem::swap(&mut a, &mut d);
        b = -c;
        c = 0.0;
    } else if a - d == 0.0 && b.signum() != c.signum() {
        cs = 1.0;
        sn = 0.0;
    } else {
        let temp = a - d;
        let mut p = 0.5 * temp;
        let bcmax = b.abs().max(c.abs());
        let bcmis = b.abs().min(c.abs()) * b.signum() * c.signum();
        let scale = p.abs().max(bcmax);
        let mut z = (p / scale) * p + (bcmax / scale) * bcmis;
        if z >= multpl * EPS {
            // Real eigenvalues.
            z = p + (scale.sqrt() * z.sqrt()).copysign(p);
            a = d + z;
            d -= (bcmax / z) * bcmis;
            let tau = hypot_fast(c, z);
            cs = z / tau;
            sn = c / tau;
            b -= c;
            c = 0.0;
        } else {
            // Complex eigenvalues, or real (almost) equal ones: make the diagonal equal.
            let sigma = b + c;
            let tau = hypot_fast(sigma, temp);
            cs = (0.5 * (1.0 + sigma.abs() / tau)).sqrt();
            sn = -(p / (tau * cs)) * if sigma >= 0.0 { 1.0 } else { -1.0 };
            let aa = a * cs + b * sn;
            let bb = -a * sn + b * cs;
            let cc = c * cs + d * sn;
            let dd = -c * sn + d * cs;
            a = aa * cs + cc * sn;
            b = bb * cs + dd * sn;
            c = -aa * sn + cc * cs;
            d = -bb * sn + dd * cs;
            let temp = 0.5 * (a + d);
            a = temp;
            d = temp;
            if c != 0.0 {
                if b != 0.0 {
                    if b.signum() == c.signum() {
                        // Real eigenvalues: reduce to upper triangular form.
                        let sab = b.abs().sqrt();
                        let sac = c.abs().sqrt();
                        p = (sab * sac).copysign(c);
                        let tau = 1.0 / (b + c).abs().sqrt();
                        a = temp + p;
                        d = temp - p;
                        b -= c;
                        c = 0.0;
                        let cs1 = sab * tau;
                        let sn1 = sac * tau;
                        let t = cs * cs1 - sn * sn1;
                        sn = cs * sn1 + sn * cs1;
                        cs = t;
                    }
                } else {
                    b = -c;
                    c = 0.0;
                    let t = cs;
                    cs = -sn;
                    sn = t;
                }
            }
        }
    }
    let (rt1, rt2) = if c == 0.0 {
        ((a, 0.0), (d, 0.0))
    } else {
        let im = b.abs().sqrt() * c.abs().sqrt();
        ((a, im), (d, -im))
    };
    Lanv2 {
        a,
        b,
        c,
        d,
        rt1,
        rt2,
        cs,
        sn,
    }
}

/// Solves the small dense system `M x = rhs` (`k ≤ 8`, `M` stored column-major in `m`) by
/// Gaussian elimination with complete pivoting; pivots smaller than `smin` are replaced by
/// `smin` (a perturbation of relative size ε, as LAPACK `dlasy2`/`dgesc2` do), so the solve
/// never fails. Returns `true` if a pivot had to be perturbed.
pub(crate) fn solve_small_complete_pivoting(
    k: usize,
    m: &mut [f64],
    rhs: &mut [f64],
    smin: f64,
) -> bool {
    debug_assert!(k <= 8);
    let mut colperm = [0usize; 8];
    for (i, p) in colperm.iter_mut().enumerate().take(k) {
        *p = i;
    }
    let mut perturbed = false;
    for s in 0..k {
        // Complete pivoting: largest entry of the trailing block.
        let (mut pi, mut pj, mut best) = (s, s, -1.0);
        for j in s..k {
            for i in s..k {
                let v = m[i + j * k].abs();
                if v > best {
                    best = v;
                    pi = i;
                    pj = j;
                }
            }
        }
        if pi != s {
            for j in 0..k {
                m.swap(s + j * k, pi + j * k);
            }
            rhs.swap(s, pi);
        }
        if pj != s {
            for i in 0..k {
                m.swap(i + s * k, i + pj * k);
            }
            colperm.swap(s, pj);
        }
        if m[s + s * k].abs() < smin {
            m[s + s * k] = smin;
            perturbed = true;
        }
        let piv = m[s + s * k];
        for i in s + 1..k {
            let l = m[i + s * k] / piv;
            m[i + s * k] = l;
            for j in s + 1..k {
                m[i + j * k] -= l * m[s + j * k];
            }
            rhs[i] -= l * rhs[s];
        }
    }
    // Back substitution.
    for i in (0..k).rev() {
        let mut v = rhs[i];
        for j in i + 1..k {
            v -= m[i + j * k] * rhs[j];
        }
        rhs[i] = v / m[i + i * k];
    }
    // Undo the column permutation: x[colperm[i]] = y[i].
    let mut x = [0.0; 8];
    for i in 0..k {
        x[colperm[i]] = rhs[i];
    }
    rhs[..k].copy_from_slice(&x[..k]);
    perturbed
}

/// Solves the small Sylvester equation `T11 X + isgn · X T22 = T12` for `X` (`n1 × n2`,
/// `n1, n2 ∈ {1, 2}`), the kernel of LAPACK `dlasy2` (without its overflow scaling; near
/// singular systems are perturbed by `ε‖·‖`). Matrices are given as 2×2 arrays (row, col).
/// Returns `X` as a 2×2 array (unused entries zero).
pub(crate) fn sylv_small(
    n1: usize,
    n2: usize,
    isgn: f64,
    t11: &[[f64; 2]; 2],
    t22: &[[f64; 2]; 2],
    t12: &[[f64; 2]; 2],
) -> [[f64; 2]; 2] {
    // Kronecker form: (I ⊗ T11 + isgn · T22ᵀ ⊗ I) vec(X) = vec(T12), vec column-major.
    let k = n1 * n2;
    let mut m = [0.0; 16];
    let mut rhs = [0.0; 4];
    let mut amax = 0.0_f64;
    for q in 0..n2 {
        for p in 0..n1 {
            let row = p + q * n1;
            rhs[row] = t12[p][q];
            for s in 0..n2 {
                for r in 0..n1 {
                    let col = r + s * n1;
                    let mut v = 0.0;
                    if s == q {
                        v += t11[p][r];
                    }
                    if r == p {
                        v += isgn * t22[s][q];
                    }
                    m[row + col * k] = v;
                    amax = amax.max(v.abs());
                }
            }
        }
    }
    let smin = (EPS * amax).max(SAFMIN / EPS);
    solve_small_complete_pivoting(k, &mut m[..k * k], &mut rhs[..k], smin);
    let mut x = [[0.0; 2]; 2];
    for q in 0..n2 {
        for p in 0..n1 {
            x[p][q] = rhs[p + q * n1];
        }
    }
    x
}

/// `y ← y − alpha · x` (axpy with negative sign), vectorisable.
#[inline]
pub(crate) fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}

/// Dot product.
#[inline]
pub(crate) fn dot(x: &[f64], y: &[f64]) -> f64 {
    // Four partial sums let the compiler vectorise without reassociation licence.
    let mut s = [0.0; 4];
    let chunks = x.len() / 4;
    for c in 0..chunks {
        for l in 0..4 {
            s[l] += x[4 * c + l] * y[4 * c + l];
        }
    }
    let mut t = (s[0] + s[1]) + (s[2] + s[3]);
    for i in 4 * chunks..x.len() {
        t += x[i] * y[i];
    }
    t
}

#[cfg(test)]
mod tests {
    use crate::linalg::testing::splitmix_matrix as test_matrix;

    /// The blocked multi-right-hand-side solve (`transpose`: `AᵀX = B`, else `AX = B`) on
    /// orders that are and are not multiples of the block size.
    ///
    /// Defining residual: LU with partial pivoting and triangular substitution are backward
    /// stable, ‖op(A)X − B‖ ≤ c·n·ε‖A‖‖X‖ with a small c (Higham, Accuracy and Stability,
    /// Thm 9.4); 10·n·ε allows for it. The unblocked substitution, one column at a time
    /// (below the blocking threshold), performs the same operations in another order:
    /// agreement to rounding times cond(A) (random A: cond ~ 1e2–1e3; 1e-10 relative is
    /// generous).
    fn check_blocked_solve(transpose: bool, cases: [(usize, usize, u64); 3]) {
        for (n, m, seed) in cases {
            let a = test_matrix(n, n, seed);
            let b = test_matrix(n, m, seed + 10);
            let lu = Lu::new(&a);
            let solve = |x: &mut crate::linalg::Mat| {
                if transpose {
                    lu.solve_transpose_in_place(x);
                } else {
                    lu.solve_in_place(x);
                }
            };
            let mut x = b.clone();
            solve(&mut x); // blocked (n ≥ 64, m ≥ 16)
            let op_a = if transpose { a.transpose() } else { a.clone() };
            let rel = (op_a * &x - &b).norm() / (a.norm() * x.norm());
            assert!(rel <= 10.0 * n as f64 * EPS, "n = {n}: residual {rel:e}");
            for j in 0..m {
                let mut col = b.columns(j, 1).into_owned();
                solve(&mut col);
                let d = (&col - x.column(j)).norm() / x.column(j).norm();
                assert!(d <= 1e-10, "n = {n}, column {j}: differs by {d:e}");
            }
        }
    }

    #[test]
    fn blocked_transpose_solve_matches_column_by_column() {
        check_blocked_solve(true, [(64, 16, 1), (100, 40, 2), (150, 17, 3)]);
    }

    #[test]
    fn blocked_solve_matches_column_by_column() {
        check_blocked_solve(false, [(64, 16, 4), (100, 40, 5), (150, 17, 6)]);
    }
    use super::*;

    #[test]
    fn lanv2_standardises() {
        // Complex pair: result must have equal diagonal and b·c < 0, and be similar.
        for &(a, b, c, d) in &[
            (1.0, 2.0, -3.0, 4.0),
            (4.0, -5.0, 1.0, 0.5),
            (0.0, 1.0, -1.0, 1e-17),
            (1.0, 2.0, 3.0, 4.0),
            (2.0, 0.0, 1.0, 3.0),
            (1.0, 1e-20, -1e-20, 1.0),
        ] {
            let r = lanv2(a, b, c, d);
            // Reconstruct: [a b; c d] = G [aa bb; cc dd] Gᵀ with G = [cs −sn; sn cs].
            let (cs, sn) = (r.cs, r.sn);
            let g = [[cs, -sn], [sn, cs]];
            let s = [[r.a, r.b], [r.c, r.d]];
            let mut gs = [[0.0; 2]; 2];
            for i in 0..2 {
                for j in 0..2 {
                    gs[i][j] = g[i][0] * s[0][j] + g[i][1] * s[1][j];
                }
            }
            let mut m = [[0.0; 2]; 2];
            for i in 0..2 {
                for j in 0..2 {
                    m[i][j] = gs[i][0] * g[j][0] + gs[i][1] * g[j][1];
                }
            }
            let orig = [[a, b], [c, d]];
            let scale = a.abs() + b.abs() + c.abs() + d.abs();
            for i in 0..2 {
                for j in 0..2 {
                    // Backward stable: 10 ε relative to the block's size.
                    assert!((m[i][j] - orig[i][j]).abs() <= 10.0 * EPS * scale);
                }
            }
            assert!(r.c == 0.0 || (r.a == r.d && r.b * r.c < 0.0));
        }
    }

    #[test]
    fn larfg_annihilates() {
        let alpha = 3.0;
        let mut x = [4.0, 12.0];
        let (beta, tau) = larfg(alpha, &mut x);
        let v = [1.0, x[0], x[1]];
        let orig = [3.0, 4.0, 12.0];
        let s: f64 = v.iter().zip(&orig).map(|(a, b)| a * b).sum();
        let h: Vec<f64> = (0..3).map(|i| orig[i] - tau * s * v[i]).collect();
        // |beta| = ‖[3, 4, 12]‖ = 13 exactly; rounding only.
        assert!((beta.abs() - 13.0).abs() < 1e-14);
        assert!((h[0] - beta).abs() < 1e-14 && h[1].abs() < 1e-14 && h[2].abs() < 1e-14);
        // The same vector scaled to 1e-200 and 1e200 (outside the single-square-root range):
        // the rescaled path must give the scaled beta and the same reflector.
        for scale in [1e-200, 1e200] {
            let mut y = [4.0 * scale, 12.0 * scale];
            let (b2, t2) = larfg(3.0 * scale, &mut y);
            assert!((b2 / scale - beta).abs() < 1e-14, "beta at scale {scale:e}");
            assert!((t2 - tau).abs() < 1e-14, "tau at scale {scale:e}");
            assert!((y[0] - x[0]).abs() < 1e-14 && (y[1] - x[1]).abs() < 1e-14);
        }
    }
}
