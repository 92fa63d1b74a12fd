//! Direct swapping of two adjacent 1×1/2×2 diagonal blocks of a real Schur form (Bai & Demmel,
//! Linear Algebra Appl. 186, 1993; LAPACK `dlaexc`) with the weak and strong stability tests,
//! and the standardisation of a 2×2 block (`dlanv2`) after the swap.
//!
//! Neighbours: [`super`] holds the public API; `reorder.rs` moves blocks along the diagonal with
//! these swaps; `hessenberg.rs` and `francis.rs` compute the Schur form.

use super::block_eigenvalues;
use crate::error::LtiError;
use crate::linalg::dense::{EPS, SAFMIN, lanv2, larfg, lartg, rot_cols, rot_rows, sylv_small};
use crate::linalg::{Complex64, Mat};

/// A swap refused by the stability test.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SwapRejected {
    /// Eigenvalue of the upper block.
    pub upper: Complex64,
    /// Eigenvalue of the lower block.
    pub lower: Complex64,
    /// Size of the perturbation the swap would have introduced.
    pub error: f64,
    /// Accepted perturbation.
    pub threshold: f64,
}

impl SwapRejected {
    pub(crate) fn into_error(self) -> LtiError {
        LtiError::Inaccurate {
            what: format!(
                "Schur reordering: exchanging the eigenvalues {:.6e}{:+.6e}j and {:.6e}{:+.6e}j \
                 (too close to be separated reliably)",
                self.upper.re, self.upper.im, self.lower.re, self.lower.im
            ),
            residual: self.error,
            tolerance: self.threshold,
        }
    }
}

/// Local 4×4 work block (row, col) for the swap kernels.
type Blk = [[f64; 4]; 4];

/// Applies `H = I − τ v vᵀ` (`v` of length 3) from the left to rows `r0..r0+3`, columns
/// `0..nc` of a 4×4 block.
fn blk_left(d: &mut Blk, v: &[f64; 3], tau: f64, r0: usize, nc: usize) {
    for j in 0..nc {
        let s = v[0] * d[r0][j] + v[1] * d[r0 + 1][j] + v[2] * d[r0 + 2][j];
        for (p, vp) in v.iter().enumerate() {
            d[r0 + p][j] -= tau * s * vp;
        }
    }
}

/// Applies `H` from the right to columns `c0..c0+3`, rows `0..nr` of a 4×4 block.
fn blk_right(d: &mut Blk, v: &[f64; 3], tau: f64, c0: usize, nr: usize) {
    for row in d.iter_mut().take(nr) {
        let s = v[0] * row[c0] + v[1] * row[c0 + 1] + v[2] * row[c0 + 2];
        for (p, vp) in v.iter().enumerate() {
            row[c0 + p] -= tau * s * vp;
        }
    }
}

/// Applies `H = I − τ v vᵀ` from the left to rows `r0..r0+3`, columns `cols` of `t`.
fn mat_left(t: &mut Mat, v: &[f64; 3], tau: f64, r0: usize, cols: std::ops::Range<usize>) {
    let n = t.nrows();
    let d = t.as_mut_slice();
    let (t0, t1, t2) = (tau * v[0], tau * v[1], tau * v[2]);
    for j in cols {
        let c = &mut d[j * n + r0..j * n + r0 + 3];
        let s = v[0] * c[0] + v[1] * c[1] + v[2] * c[2];
        c[0] -= s * t0;
        c[1] -= s * t1;
        c[2] -= s * t2;
    }
}

/// Applies `H = I − τ v vᵀ` from the right to columns `c0..c0+3`, rows `rows` of `t`.
fn mat_right(t: &mut Mat, v: &[f64; 3], tau: f64, c0: usize, rows: std::ops::Range<usize>) {
    let n = t.nrows();
    let s = t.as_mut_slice();
    let (a, rest) = s[c0 * n..].split_at_mut(n);
    let (b, c) = rest.split_at_mut(n);
    for r in rows {
        let sum = v[0] * a[r] + v[1] * b[r] + v[2] * c[r];
        a[r] -= tau * sum * v[0];
        b[r] -= tau * sum * v[1];
        c[r] -= tau * sum * v[2];
    }
}

/// Householder reflector for a 3-vector with the pivot (the entry kept) at position `p`
/// (0 or 2): returns `(v, tau)` with `v[p] = 1`.
fn reflector3(u: [f64; 3], p: usize) -> ([f64; 3], f64) {
    if p == 0 {
        let mut x = [u[1], u[2]];
        let (_, tau) = larfg(u[0], &mut x);
        ([1.0, x[0], x[1]], tau)
    } else {
        let mut x = [u[0], u[1]];
        let (_, tau) = larfg(u[2], &mut x);
        ([x[0], x[1], 1.0], tau)
    }
}

/// Swaps the adjacent diagonal blocks `T11` (order `n1`, starting at row `j1`) and `T22`
/// (order `n2`) of the standard-form quasi-triangular `t` by an orthogonal similarity,
/// accumulated into `z` (LAPACK `dlaexc`, Bai–Demmel direct swapping). Rejected — leaving
/// `t`, `z` untouched — when the swapped block would deviate from block-triangular form or
/// fail to reproduce the original block by more than a small multiple of `ε‖block‖`.
pub(crate) fn exchange(
    t: &mut Mat,
    mut z: Option<&mut Mat>,
    j1: usize,
    n1: usize,
    n2: usize,
) -> std::result::Result<(), SwapRejected> {
    let n = t.nrows();
    if n1 == 0 || n2 == 0 || j1 + n1 + n2 > n {
        return Ok(());
    }
    let j2 = j1 + 1;
    if n1 == 1 && n2 == 1 {
        // Two 1×1 blocks: a single rotation, always accurate.
        let t11 = t[(j1, j1)];
        let t22 = t[(j2, j2)];
        let (cs, sn, _) = lartg(t[(j1, j2)], t22 - t11);
        let ld = n;
        if j1 + 2 < n {
            rot_rows(t.as_mut_slice(), ld, j1, j2, j1 + 2..n, cs, sn);
        }
        rot_cols(t.as_mut_slice(), ld, j1, j2, 0..j1, cs, sn);
        t[(j1, j1)] = t22;
        t[(j2, j2)] = t11;
        if let Some(z) = z.as_deref_mut() {
            let nz = z.nrows();
            rot_cols(z.as_mut_slice(), nz, j1, j2, 0..nz, cs, sn);
        }
        return Ok(());
    }

    let nd = n1 + n2;
    let mut d: Blk = [[0.0; 4]; 4];
    for (i, row) in d.iter_mut().enumerate().take(nd) {
        for (j, e) in row.iter_mut().enumerate().take(nd) {
            *e = t[(j1 + i, j1 + j)];
        }
    }
    let orig = d;
    let dnorm = d.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
    let dfro = d.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
    let smlnum = SAFMIN / EPS;
    // Weak test threshold (LAPACK dlaexc) and strong test threshold (LAPACK dtgex2).
    let thresh = (10.0 * EPS * dnorm).max(smlnum);
    let thresh_strong = (20.0 * EPS * dfro).max(smlnum);

    // Solve T11 X − X T22 = T12.
    let mut t11 = [[0.0; 2]; 2];
    let mut t22 = [[0.0; 2]; 2];
    let mut t12 = [[0.0; 2]; 2];
    for i in 0..n1 {
        for j in 0..n1 {
            t11[i][j] = d[i][j];
        }
        for j in 0..n2 {
            t12[i][j] = d[i][n1 + j];
        }
    }
    for i in 0..n2 {
        for j in 0..n2 {
            t22[i][j] = d[n1 + i][n1 + j];
        }
    }
    let x = sylv_small(n1, n2, -1.0, &t11, &t22, &t12);
    let scale = 1.0;

    let reject = |err: f64, thr: f64| SwapRejected {
        upper: block_eigenvalues(t, j1, n1)[0],
        lower: block_eigenvalues(t, j1 + n1, n2)[0],
        error: err,
        threshold: thr,
    };

    // The reflectors, as (v, tau, offset) applied in order: D ← H_k ⋯ H_1 D H_1 ⋯ H_k.
    let mut refl: Vec<([f64; 3], f64, usize)> = Vec::with_capacity(2);
    let weak_err;
    match (n1, n2) {
        (1, 2) => {
            let (v, tau) = reflector3([scale, x[0][0], x[0][1]], 2);
            blk_left(&mut d, &v, tau, 0, 3);
            blk_right(&mut d, &v, tau, 0, 3);
            weak_err = d[2][0]
                .abs()
                .max(d[2][1].abs())
                .max((d[2][2] - orig[0][0]).abs());
            refl.push((v, tau, 0));
        }
        (2, 1) => {
            let (v, tau) = reflector3([-x[0][0], -x[1][0], scale], 0);
            blk_left(&mut d, &v, tau, 0, 3);
            blk_right(&mut d, &v, tau, 0, 3);
            weak_err = d[1][0]
                .abs()
                .max(d[2][0].abs())
                .max((d[0][0] - orig[2][2]).abs());
            refl.push((v, tau, 0));
        }
        _ => {
            let (v1, tau1) = reflector3([-x[0][0], -x[1][0], scale], 0);
            let temp = -tau1 * (x[0][1] + v1[1] * x[1][1]);
            let (v2, tau2) = reflector3([-temp * v1[1] - x[1][1], -temp * v1[2], scale], 0);
            blk_left(&mut d, &v1, tau1, 0, 4);
            blk_right(&mut d, &v1, tau1, 0, 4);
            blk_left(&mut d, &v2, tau2, 1, 4);
            blk_right(&mut d, &v2, tau2, 1, 4);
            weak_err = d[2][0]
                .abs()
                .max(d[2][1].abs())
                .max(d[3][0].abs())
                .max(d[3][1].abs());
            refl.push((v1, tau1, 0));
            refl.push((v2, tau2, 1));
        }
    }
    if weak_err > thresh {
        return Err(reject(weak_err, thresh));
    }
    // Strong test: zero the entries that the swap should annihilate, transform back and
    // compare with the original block.
    let mut back = d;
    match (n1, n2) {
        (1, 2) => {
            back[2][0] = 0.0;
            back[2][1] = 0.0;
            back[2][2] = orig[0][0];
        }
        (2, 1) => {
            back[1][0] = 0.0;
            back[2][0] = 0.0;
            back[0][0] = orig[2][2];
        }
        _ => {
            back[2][0] = 0.0;
            back[2][1] = 0.0;
            back[3][0] = 0.0;
            back[3][1] = 0.0;
        }
    }
    for (v, tau, off) in refl.iter().rev() {
        blk_left(&mut back, v, *tau, *off, nd);
        blk_right(&mut back, v, *tau, *off, nd);
    }
    let mut strong_err = 0.0_f64;
    for i in 0..nd {
        for j in 0..nd {
            let e = back[i][j] - orig[i][j];
            strong_err += e * e;
        }
    }
    let strong_err = strong_err.sqrt();
    if strong_err > thresh_strong {
        return Err(reject(strong_err, thresh_strong));
    }

    // Accepted: apply to the whole of T and Z.
    for (v, tau, off) in &refl {
        let r0 = j1 + off;
        mat_left(t, v, *tau, r0, j1..n);
        mat_right(t, v, *tau, r0, 0..(j1 + nd).min(n));
        if let Some(z) = z.as_deref_mut() {
            let nz = z.nrows();
            mat_right(z, v, *tau, r0, 0..nz);
        }
    }
    // Put the exact zeros and values in.
    match (n1, n2) {
        (1, 2) => {
            t[(j1 + 2, j1)] = 0.0;
            t[(j1 + 2, j1 + 1)] = 0.0;
            t[(j1 + 2, j1 + 2)] = orig[0][0];
        }
        (2, 1) => {
            t[(j1, j1)] = orig[2][2];
            t[(j1 + 1, j1)] = 0.0;
            t[(j1 + 2, j1)] = 0.0;
        }
        _ => {
            t[(j1 + 2, j1)] = 0.0;
            t[(j1 + 2, j1 + 1)] = 0.0;
            t[(j1 + 3, j1)] = 0.0;
            t[(j1 + 3, j1 + 1)] = 0.0;
        }
    }
    // Standardise the 2×2 blocks in their new positions.
    if n2 == 2 {
        standardize_block(t, z.as_deref_mut(), j1);
    }
    if n1 == 2 {
        standardize_block(t, z, j1 + n2);
    }
    Ok(())
}

/// Puts the 2×2 diagonal block of `t` at `(k, k)` into standard form with [`lanv2`],
/// rotating the rest of `t` and `z`.
pub(crate) fn standardize_block(t: &mut Mat, z: Option<&mut Mat>, k: usize) {
    let n = t.nrows();
    let r = lanv2(t[(k, k)], t[(k, k + 1)], t[(k + 1, k)], t[(k + 1, k + 1)]);
    t[(k, k)] = r.a;
    t[(k, k + 1)] = r.b;
    t[(k + 1, k)] = r.c;
    t[(k + 1, k + 1)] = r.d;
    if k + 2 < n {
        rot_rows(t.as_mut_slice(), n, k, k + 1, k + 2..n, r.cs, r.sn);
    }
    rot_cols(t.as_mut_slice(), n, k, k + 1, 0..k, r.cs, r.sn);
    if let Some(z) = z {
        let nz = z.nrows();
        rot_cols(z.as_mut_slice(), nz, k, k + 1, 0..nz, r.cs, r.sn);
    }
}
