//! LU factorisation with partial pivoting of a square matrix, its solves and its condition
//! estimate (LAPACK `dgetf2`, `dgetrs`, `dlacon`), column-major.

use super::{axpy, dot};

/// Block size of the blocked triangular solves of [`Lu`].
const TRSM_NB: usize = 16;
/// Smallest order for which [`Lu::solve_transpose_in_place`] uses the blocked substitutions.
const TRSM_MIN_ORDER: usize = 64;
/// Smallest number of right-hand sides for the blocked substitutions.
const TRSM_MIN_RHS: usize = 16;

/// LU factorisation with partial pivoting `P A = L U` of a square matrix (LAPACK `dgetf2`,
/// right-looking, column-major), with solves for `A X = B` and `Aᵀ X = B` and a reciprocal
/// condition estimate in the 1-norm (Hager–Higham, LAPACK `dlacon`).
#[derive(Debug, Clone)]
pub(crate) struct Lu {
    lu: crate::linalg::Mat,
    piv: Vec<usize>,
    anorm1: f64,
    singular: bool,
}

impl Lu {
    /// Factorises `a` (square).
    pub(crate) fn new(a: &crate::linalg::Mat) -> Self {
        let n = a.nrows();
        let anorm1 = (0..n)
            .map(|j| a.column(j).iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        let mut lu = a.clone();
        let mut piv = vec![0; n];
        let mut singular = false;
        let d = lu.as_mut_slice();
        for k in 0..n {
            let col = &d[k * n..(k + 1) * n];
            let (mut p, mut best) = (k, -1.0);
            for (i, v) in col.iter().enumerate().skip(k) {
                if v.abs() > best {
                    best = v.abs();
                    p = i;
                }
            }
            piv[k] = p;
            if p != k {
                for j in 0..n {
                    d.swap(k + j * n, p + j * n);
                }
            }
            let pv = d[k + k * n];
            if pv == 0.0 {
                singular = true;
                continue;
            }
            let inv = 1.0 / pv;
            for i in k + 1..n {
                d[i + k * n] *= inv;
            }
            let (left, right) = d.split_at_mut((k + 1) * n);
            let lcol = &left[k * n + k + 1..k * n + n];
            for j in 0..n - k - 1 {
                let c = &mut right[j * n..(j + 1) * n];
                let ukj = c[k];
                if ukj != 0.0 {
                    axpy(-ukj, lcol, &mut c[k + 1..n]);
                }
            }
        }
        Lu {
            lu,
            piv,
            anorm1,
            singular,
        }
    }

    /// Solves `A X = B` in place.
    ///
    /// Row interchanges, forward substitution with `L`, backward substitution with `U`; for
    /// many right-hand sides and large `n` blocked as [`Lu::solve_transpose_in_place`].
    pub(crate) fn solve_in_place(&self, b: &mut crate::linalg::Mat) {
        let n = self.lu.nrows();
        if n >= TRSM_MIN_ORDER && b.ncols() >= TRSM_MIN_RHS {
            self.solve_blocked(b);
            return;
        }
        let l = self.lu.as_slice();
        for j in 0..b.ncols() {
            let x = &mut b.as_mut_slice()[j * n..(j + 1) * n];
            for (k, &p) in self.piv.iter().enumerate() {
                if p != k {
                    x.swap(k, p);
                }
            }
            // Forward: unit lower triangular, column-oriented.
            for k in 0..n {
                let xk = x[k];
                if xk != 0.0 {
                    axpy(-xk, &l[k * n + k + 1..(k + 1) * n], &mut x[k + 1..n]);
                }
            }
            // Backward: upper triangular.
            for k in (0..n).rev() {
                x[k] /= l[k + k * n];
                let xk = x[k];
                if xk != 0.0 {
                    axpy(-xk, &l[k * n..k * n + k], &mut x[..k]);
                }
            }
        }
    }

    /// Solves `Aᵀ X = B` in place.
    ///
    /// With `PA = LU`, `Aᵀ = Uᵀ Lᵀ P`: forward substitution with `Uᵀ`, backward substitution
    /// with `Lᵀ`, then the row interchanges in reverse. For many right-hand sides and large
    /// `n` the substitutions are blocked (LAPACK `dtrsm`'s blocked variant): each block of
    /// `TRSM_NB` rows first subtracts the contribution of the rows already solved as one
    /// matrix–matrix product.
    pub(crate) fn solve_transpose_in_place(&self, b: &mut crate::linalg::Mat) {
        let n = self.lu.nrows();
        if n >= TRSM_MIN_ORDER && b.ncols() >= TRSM_MIN_RHS {
            self.solve_transpose_blocked(b);
            return;
        }
        let l = self.lu.as_slice();
        for j in 0..b.ncols() {
            let x = &mut b.as_mut_slice()[j * n..(j + 1) * n];
            // Uᵀ y = x (forward, row-oriented on columns of U).
            for k in 0..n {
                let s = dot(&l[k * n..k * n + k], &x[..k]);
                x[k] = (x[k] - s) / l[k + k * n];
            }
            // Lᵀ z = y (backward).
            for k in (0..n).rev() {
                let s = dot(&l[k * n + k + 1..(k + 1) * n], &x[k + 1..n]);
                x[k] -= s;
            }
            for (k, &p) in self.piv.iter().enumerate().rev() {
                if p != k {
                    x.swap(k, p);
                }
            }
        }
    }

    /// Blocked [`Lu::solve_in_place`]: each block of `TRSM_NB` rows first subtracts the
    /// contribution of the rows already solved as one matrix–matrix product, then is solved
    /// row by row on a transposed copy (axpy over all right-hand sides).
    fn solve_blocked(&self, b: &mut crate::linalg::Mat) {
        let n = self.lu.nrows();
        let l = self.lu.as_slice();
        let nrhs = b.ncols();
        {
            let bs = b.as_mut_slice();
            for j in 0..nrhs {
                let x = &mut bs[j * n..(j + 1) * n];
                for (k, &p) in self.piv.iter().enumerate() {
                    if p != k {
                        x.swap(k, p);
                    }
                }
            }
        }
        let mut panel = vec![0.0; TRSM_NB * nrhs];
        // L Y = P B (unit lower), block rows top to bottom.
        let mut r = 0;
        while r < n {
            let nb = TRSM_NB.min(n - r);
            if r > 0 {
                // Y[r..r+nb] −= L[r..r+nb, 0..r] Y[0..r].
                let lb = self.lu.view((r, 0), (nb, r));
                let (done, mut blk) = b.rows_range_pair_mut(0..r, r..r + nb);
                blk.gemm(-1.0, &lb, &done, 1.0);
            }
            gather_rows(b, r, nb, &mut panel);
            for i in 0..nb {
                let k = r + i;
                let (done, cur) = panel.split_at_mut(i * nrhs);
                let cur = &mut cur[..nrhs];
                for p in 0..i {
                    let lv = l[(r + p) * n + k];
                    if lv != 0.0 {
                        axpy(-lv, &done[p * nrhs..(p + 1) * nrhs], cur);
                    }
                }
            }
            scatter_rows(&panel, r, nb, b);
            r += nb;
        }
        // U X = Y, block rows bottom to top.
        let mut end = n;
        while end > 0 {
            let nb = TRSM_NB.min(end);
            let r = end - nb;
            if end < n {
                // X[r..end] −= U[r..end, end..n] X[end..n].
                let ub = self.lu.view((r, end), (nb, n - end));
                let (mut blk, done) = b.rows_range_pair_mut(r..end, end..n);
                blk.gemm(-1.0, &ub, &done, 1.0);
            }
            gather_rows(b, r, nb, &mut panel);
            for i in (0..nb).rev() {
                let k = r + i;
                let (cur, done) = panel.split_at_mut((i + 1) * nrhs);
                let cur = &mut cur[i * nrhs..];
                for p in i + 1..nb {
                    let uv = l[(r + p) * n + k];
                    if uv != 0.0 {
                        axpy(-uv, &done[(p - i - 1) * nrhs..(p - i) * nrhs], cur);
                    }
                }
                let d = l[k + k * n];
                for v in cur.iter_mut() {
                    *v /= d;
                }
            }
            scatter_rows(&panel, r, nb, b);
            end = r;
        }
    }

    /// Blocked [`Lu::solve_transpose_in_place`].
    fn solve_transpose_blocked(&self, b: &mut crate::linalg::Mat) {
        let n = self.lu.nrows();
        let l = self.lu.as_slice();
        let nrhs = b.ncols();
        let mut panel = vec![0.0; TRSM_NB * nrhs];
        // Uᵀ Y = B, block rows top to bottom.
        let mut r = 0;
        while r < n {
            let nb = TRSM_NB.min(n - r);
            if r > 0 {
                // Y[r..r+nb] −= U[0..r, r..r+nb]ᵀ Y[0..r].
                let ut = self.lu.view((0, r), (r, nb)).transpose();
                let (done, mut blk) = b.rows_range_pair_mut(0..r, r..r + nb);
                blk.gemm(-1.0, &ut, &done, 1.0);
            }
            // The diagonal block row by row on a transposed copy, so that each update is an
            // axpy over all right-hand sides (contiguous, vectorisable).
            gather_rows(b, r, nb, &mut panel);
            for i in 0..nb {
                let k = r + i;
                let (done, cur) = panel.split_at_mut(i * nrhs);
                let cur = &mut cur[..nrhs];
                for p in 0..i {
                    let u = l[k * n + r + p];
                    if u != 0.0 {
                        axpy(-u, &done[p * nrhs..(p + 1) * nrhs], cur);
                    }
                }
                let d = l[k + k * n];
                for v in cur.iter_mut() {
                    *v /= d;
                }
            }
            scatter_rows(&panel, r, nb, b);
            r += nb;
        }
        // Lᵀ W = Y, block rows bottom to top.
        let mut end = n;
        while end > 0 {
            let nb = TRSM_NB.min(end);
            let r = end - nb;
            if end < n {
                // W[r..end] −= L[end..n, r..end]ᵀ W[end..n].
                let lt = self.lu.view((end, r), (n - end, nb)).transpose();
                let (mut blk, done) = b.rows_range_pair_mut(r..end, end..n);
                blk.gemm(-1.0, &lt, &done, 1.0);
            }
            gather_rows(b, r, nb, &mut panel);
            for i in (0..nb).rev() {
                let k = r + i;
                let (cur, done) = panel.split_at_mut((i + 1) * nrhs);
                let cur = &mut cur[i * nrhs..];
                for p in i + 1..nb {
                    let lv = l[k * n + r + p];
                    if lv != 0.0 {
                        axpy(-lv, &done[(p - i - 1) * nrhs..(p - i) * nrhs], cur);
                    }
                }
            }
            scatter_rows(&panel, r, nb, b);
            end = r;
        }
        let bs = b.as_mut_slice();
        for j in 0..nrhs {
            let x = &mut bs[j * n..(j + 1) * n];
            for (k, &p) in self.piv.iter().enumerate().rev() {
                if p != k {
                    x.swap(k, p);
                }
            }
        }
    }

    /// Estimate of the reciprocal 1-norm condition number `1 / (‖A‖₁ ‖A⁻¹‖₁)` (Hager's method
    /// with Higham's extra test vector); `0` for an exactly singular matrix.
    pub(crate) fn rcond(&self) -> f64 {
        let n = self.lu.nrows();
        if n == 0 {
            return 1.0;
        }
        if self.singular || self.anorm1 == 0.0 {
            return 0.0;
        }
        let mut x = crate::linalg::Mat::from_element(n, 1, 1.0 / n as f64);
        let mut est = 0.0_f64;
        for iter in 0..5 {
            let mut y = x.clone();
            self.solve_in_place(&mut y);
            let e: f64 = y.iter().map(|v| v.abs()).sum();
            if !e.is_finite() {
                return 0.0;
            }
            if iter > 0 && e <= est {
                break;
            }
            est = e;
            let mut z = y.map(|v| if v >= 0.0 { 1.0 } else { -1.0 });
            self.solve_transpose_in_place(&mut z);
            let (j, zmax) = z.iter().enumerate().fold((0, -1.0), |(bj, bv), (i, v)| {
                if v.abs() > bv { (i, v.abs()) } else { (bj, bv) }
            });
            if iter > 0 && zmax <= z.dot(&x) {
                break;
            }
            x = crate::linalg::Mat::zeros(n, 1);
            x[(j, 0)] = 1.0;
        }
        // Higham's alternating test vector.
        let mut alt = crate::linalg::Mat::from_fn(n, 1, |i, _| {
            let s = if i % 2 == 0 { 1.0 } else { -1.0 };
            s * (1.0 + i as f64 / (n.max(2) - 1) as f64)
        });
        self.solve_in_place(&mut alt);
        let e2 = 2.0 * alt.iter().map(|v| v.abs()).sum::<f64>() / (3.0 * n as f64);
        est = est.max(e2);
        if !est.is_finite() || est == 0.0 {
            return 0.0;
        }
        1.0 / (self.anorm1 * est)
    }
}

/// Copies rows `r..r+nb` of `b` into `panel` transposed: row `r+i` becomes the contiguous
/// slice `panel[i·ncols..(i+1)·ncols]`.
fn gather_rows(b: &crate::linalg::Mat, r: usize, nb: usize, panel: &mut [f64]) {
    let (n, nrhs) = b.shape();
    let bs = b.as_slice();
    for j in 0..nrhs {
        let col = &bs[j * n + r..j * n + r + nb];
        for (i, v) in col.iter().enumerate() {
            panel[i * nrhs + j] = *v;
        }
    }
}

/// Inverse of [`gather_rows`].
fn scatter_rows(panel: &[f64], r: usize, nb: usize, b: &mut crate::linalg::Mat) {
    let (n, nrhs) = b.shape();
    let bs = b.as_mut_slice();
    for j in 0..nrhs {
        let col = &mut bs[j * n + r..j * n + r + nb];
        for (i, v) in col.iter_mut().enumerate() {
            *v = panel[i * nrhs + j];
        }
    }
}

impl Lu {
    /// `A⁻¹` (solve with the identity).
    pub(crate) fn inverse(&self) -> crate::linalg::Mat {
        let n = self.lu.nrows();
        let mut x = crate::linalg::Mat::identity(n, n);
        self.solve_in_place(&mut x);
        x
    }
}
