//! The problem's structure and the Newton (KKT) systems: the reduction to the normal equations
//! `H = VᵀV` with `V = W⁻ᵀG`, their Cholesky factorisation (with the equalities), and the solve
//! with iterative refinement on the unreduced system (module docs of [`super`], **Linear
//! algebra**).
//!
//! Neighbours: `kernels.rs` (dense kernels), `scaling.rs` (the cones' scaling), `embedding.rs`
//! (iterate, residuals, stopping measures), `driver.rs` (the iteration).

use super::kernels::{
    chol_solve, cholesky_regularised, dot, forward, mul_nt_cols, norm_inf, svec_upper,
};
use super::scaling::{Cone, Lp, Psd};
use super::{MAX_REFINEMENT, REFINE_BELOW};
use crate::conic::{ConeKind, ConicData};
use std::f64::consts::SQRT_2;

/// `(a, b, g)`: entry `g` of the symmetric coefficient matrix at `(a, b)`, `a ≤ b` (and
/// `(b, a)`), of one variable in one PSD cone; for an orthant, `(row, 0, g)`.
type Entries = Vec<(usize, usize, f64)>;

/// The structure of the data: which rows are equalities, each variable's coefficients per
/// cone.
pub(super) struct Structure {
    pub(super) n: usize,
    pub(super) m: usize,
    /// Rows of the zero cones with a coefficient, in order (`y` index ↔ row).
    pub(super) eq_rows: Vec<usize>,
    /// Rows of the zero cones without one (`0 = f_k`).
    pub(super) dropped_eq: Vec<usize>,
    /// `E` (`p × n`), column-major.
    e: Vec<f64>,
    /// Per cone: `(variable, entries)` of every variable with a coefficient in the cone.
    columns: Vec<Vec<(usize, Entries)>>,
    /// Per row: whether it is a zero-cone row.
    is_eq: Vec<bool>,
    /// Cone degree `ν` (orthant rows plus PSD sides).
    pub(super) degree: usize,
}

impl Structure {
    pub(super) fn new(data: &ConicData) -> (Self, Vec<Cone>) {
        let (n, m) = (data.n, data.m);
        let mut is_eq = vec![false; m];
        let mut eq_rows = Vec::new();
        let mut cones = Vec::new();
        // Row → (cone index, (i, j) within the cone).
        let mut row_pos = vec![(usize::MAX, 0usize, 0usize); m];
        let mut start = 0;
        let mut degree = 0;
        for kind in &data.cones {
            let rows = kind.rows();
            match *kind {
                ConeKind::Zero(len) => {
                    for r in start..start + len {
                        is_eq[r] = true;
                        eq_rows.push(r);
                    }
                }
                ConeKind::NonNegative(len) => {
                    for (k, rp) in row_pos[start..start + len].iter_mut().enumerate() {
                        *rp = (cones.len(), k, 0);
                    }
                    cones.push(Cone::Lp(Lp {
                        start,
                        len,
                        w: vec![1.0; len],
                        lambda: vec![1.0; len],
                    }));
                    degree += len;
                }
                ConeKind::Psd(side) => {
                    let mut k = start;
                    for j in 0..side {
                        for i in 0..=j {
                            row_pos[k] = (cones.len(), i, j);
                            k += 1;
                        }
                    }
                    let mut id = vec![0.0; side * side];
                    for i in 0..side {
                        id[i + i * side] = 1.0;
                    }
                    cones.push(Cone::Psd(Psd {
                        start,
                        side,
                        r: id.clone(),
                        rinv: id.clone(),
                        rinv_t: id,
                        lambda: vec![1.0; side],
                    }));
                    degree += side;
                }
            }
            start += rows;
        }
        // Zero-cone rows without a coefficient are `0 = f_k`: dropped from E (trivially
        // satisfied when f_k = 0; see `inconsistent_row` otherwise).
        let mut has_coef = vec![false; m];
        for &r in &data.rowval {
            has_coef[r] = true;
        }
        let dropped_eq: Vec<usize> = eq_rows.iter().copied().filter(|&r| !has_coef[r]).collect();
        eq_rows.retain(|&r| has_coef[r]);
        let p = eq_rows.len();
        let mut eq_index = vec![usize::MAX; m];
        for (k, &r) in eq_rows.iter().enumerate() {
            eq_index[r] = k;
        }
        let mut e = vec![0.0; p * n];
        let mut columns: Vec<Vec<(usize, Entries)>> = vec![Vec::new(); cones.len()];
        for j in 0..n {
            for k in data.colptr[j]..data.colptr[j + 1] {
                let (row, v) = (data.rowval[k], data.nzval[k]);
                if is_eq[row] {
                    e[eq_index[row] + j * p] = v;
                    continue;
                }
                let (c, a, b) = row_pos[row];
                // svec off-diagonals carry √2: the matrix entry is v/√2.
                let g = match cones[c] {
                    Cone::Psd(_) if a != b => v / SQRT_2,
                    _ => v,
                };
                let list = &mut columns[c];
                if list.last().map(|l| l.0) != Some(j) {
                    list.push((j, Vec::new()));
                }
                if let Some(last) = list.last_mut() {
                    last.1.push((a, b, g));
                }
            }
        }
        (
            Self {
                n,
                m,
                eq_rows,
                dropped_eq,
                e,
                columns,
                is_eq,
                degree,
            },
            cones,
        )
    }

    fn p(&self) -> usize {
        self.eq_rows.len()
    }

    /// `out = A x` over all rows.
    pub(super) fn a_mul(&self, data: &ConicData, x: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
        for (j, xj) in x.iter().enumerate().take(self.n) {
            if *xj != 0.0 {
                for k in data.colptr[j]..data.colptr[j + 1] {
                    out[data.rowval[k]] += data.nzval[k] * xj;
                }
            }
        }
    }

    /// `out = Aᵀ z` over all rows.
    pub(super) fn at_mul(&self, data: &ConicData, z: &[f64], out: &mut [f64]) {
        for (j, o) in out.iter_mut().enumerate().take(self.n) {
            let mut acc = 0.0;
            for k in data.colptr[j]..data.colptr[j + 1] {
                acc += data.nzval[k] * z[data.rowval[k]];
            }
            *o = acc;
        }
    }
}

/// A solution of the unreduced KKT system: `x`, `y` on the zero-cone rows of `yz`, and
/// `W z` on its cone rows (scaled space). `z` itself is never needed: `Gᵀz = VᵀWz` and
/// `hᵀz = (W⁻ᵀh)ᵀWz`.
#[derive(Clone)]
pub(super) struct KktSolution {
    pub(super) x: Vec<f64>,
    pub(super) yz: Vec<f64>,
}

/// The factored reduced KKT system for one scaling.
pub(super) struct Kkt {
    /// `V = W⁻ᵀG` over all rows (zero-cone rows: zero), `m × n` column-major.
    v: Vec<f64>,
    /// Cholesky factor of `H + EᵀE` (+ regularisation), `n × n`.
    l: Vec<f64>,
    /// With equalities: the Cholesky factor of `E(H + EᵀE)⁻¹Eᵀ`, `p × p`.
    schur: Option<Vec<f64>>,
}

impl Kkt {
    pub(super) fn factor(st: &Structure, cones: &[Cone]) -> Option<Self> {
        let (m, n, p) = (st.m, st.n, st.p());
        let mut v = vec![0.0; m * n];
        for (cone, cols) in cones.iter().zip(&st.columns) {
            match cone {
                Cone::Lp(c) => {
                    for (j, entries) in cols {
                        for &(k, _, g) in entries {
                            v[c.start + k + j * m] = g / c.w[k];
                        }
                    }
                }
                Cone::Psd(c) => {
                    let d = c.side;
                    let rinv = &c.rinv;
                    let mut t = vec![0.0; d * d];
                    let mut o = vec![0.0; d * d];
                    let mut touched = vec![false; d];
                    let mut cols_t = Vec::with_capacity(d);
                    for (j, entries) in cols {
                        // T = R⁻¹ G_j (G_j symmetric, from its upper entries; only the
                        // touched columns are nonzero), then svec(T R⁻ᵀ).
                        for &c0 in &cols_t {
                            t[c0 * d..(c0 + 1) * d].iter_mut().for_each(|x| *x = 0.0);
                            touched[c0] = false;
                        }
                        cols_t.clear();
                        // T(:, col) += g R⁻¹(:, from), marking the column touched.
                        let mut add = |col: usize, from: usize, g: f64| {
                            let src = &rinv[from * d..(from + 1) * d];
                            for (tv, rv) in t[col * d..(col + 1) * d].iter_mut().zip(src) {
                                *tv += g * rv;
                            }
                            if !touched[col] {
                                touched[col] = true;
                                cols_t.push(col);
                            }
                        };
                        for &(a, b, g) in entries {
                            add(b, a, g);
                            if a != b {
                                add(a, b, g);
                            }
                        }
                        mul_nt_cols(d, &t, rinv, &cols_t, &mut o);
                        svec_upper(
                            &o,
                            d,
                            &mut v[c.start + j * m..c.start + j * m + d * (d + 1) / 2],
                        );
                    }
                }
            }
        }
        // H = VᵀV + EᵀE (symmetric: the lower triangle, mirrored).
        let mut h = vec![0.0; n * n];
        for j in 0..n {
            let vj = &v[j * m..(j + 1) * m];
            for i in j..n {
                let mut hij = dot(&v[i * m..(i + 1) * m], vj);
                if p > 0 {
                    hij += dot(&st.e[i * p..(i + 1) * p], &st.e[j * p..(j + 1) * p]);
                }
                h[i + j * n] = hij;
                h[j + i * n] = hij;
            }
        }
        let l = cholesky_regularised(n, &h)?;
        let schur = if p > 0 {
            // Y = L⁻¹ Eᵀ (n × p), S = YᵀY.
            let mut y = vec![0.0; n * p];
            for k in 0..p {
                let col = &mut y[k * n..(k + 1) * n];
                for j in 0..n {
                    col[j] = st.e[k + j * p];
                }
                forward(n, &l, col);
            }
            let mut s = vec![0.0; p * p];
            for j in 0..p {
                for i in j..p {
                    let sij = dot(&y[i * n..(i + 1) * n], &y[j * n..(j + 1) * n]);
                    s[i + j * p] = sij;
                    s[j + i * p] = sij;
                }
            }
            Some(cholesky_regularised(p, &s)?)
        } else {
            None
        };
        Some(Self { v, l, schur })
    }

    /// Solves the reduced system once for `(b_x, t)` with `t = (b_y, W⁻ᵀb_z)` (rows).
    fn solve_once(&self, st: &Structure, bx: &[f64], t: &[f64]) -> KktSolution {
        let (m, n, p) = (st.m, st.n, st.p());
        // r = b_x + Vᵀ t (V is zero on the zero-cone rows).
        let mut rhs: Vec<f64> = (0..n)
            .map(|j| bx[j] + dot(&self.v[j * m..(j + 1) * m], t))
            .collect();
        let mut yz = vec![0.0; m];
        let x = if let Some(s) = &self.schur {
            let by: Vec<f64> = st.eq_rows.iter().map(|&r| t[r]).collect();
            // r ← r + Eᵀ b_y; y = S⁻¹(E H̃⁻¹ r − b_y); x = H̃⁻¹(r − Eᵀ y).
            for j in 0..n {
                rhs[j] += dot(&st.e[j * p..(j + 1) * p], &by);
            }
            let mut hr = rhs.clone();
            chol_solve(n, &self.l, &mut hr);
            let mut y: Vec<f64> = (0..p)
                .map(|k| (0..n).map(|j| st.e[k + j * p] * hr[j]).sum::<f64>() - by[k])
                .collect();
            chol_solve(p, s, &mut y);
            for j in 0..n {
                rhs[j] -= dot(&st.e[j * p..(j + 1) * p], &y);
            }
            for (k, &r) in st.eq_rows.iter().enumerate() {
                yz[r] = y[k];
            }
            chol_solve(n, &self.l, &mut rhs);
            rhs
        } else {
            chol_solve(n, &self.l, &mut rhs);
            rhs
        };
        // W z = V x − t on the cone rows.
        for (j, xj) in x.iter().enumerate() {
            if *xj != 0.0 {
                for (w, vv) in yz.iter_mut().zip(&self.v[j * m..(j + 1) * m]) {
                    *w += vv * xj;
                }
            }
        }
        for (i, w) in yz.iter_mut().enumerate() {
            if !st.is_eq[i] {
                *w -= t[i];
            }
        }
        KktSolution { x, yz }
    }

    /// The residual of `u` in the scaled unreduced system, `(b_x − (Eᵀy + VᵀWz), (b_y − Ex,
    /// 0))`, its largest magnitude, and the largest magnitude of the terms it sums.
    fn residual(
        &self,
        st: &Structure,
        (bx, t): (&[f64], &[f64]),
        u: &KktSolution,
    ) -> (Vec<f64>, Vec<f64>, f64, f64) {
        let (m, n, p) = (st.m, st.n, st.p());
        let ex: Vec<f64> = (0..n)
            .map(|j| {
                let mut acc = dot(&self.v[j * m..(j + 1) * m], &u.yz);
                for (k, &r) in st.eq_rows.iter().enumerate() {
                    acc += st.e[k + j * p] * u.yz[r];
                }
                bx[j] - acc
            })
            .collect();
        // The cone rows hold by construction (W z = V x − t, and a correction keeps it to
        // rounding), so only the zero-cone rows' b_y − E x remain.
        let mut et = vec![0.0; m];
        for (k, &r) in st.eq_rows.iter().enumerate() {
            let ex_k: f64 = (0..n).map(|j| st.e[k + j * p] * u.x[j]).sum();
            et[r] = t[r] - ex_k;
        }
        let size = norm_inf(&ex).max(norm_inf(&et));
        // The magnitude of the terms summed: rounding alone leaves residuals of ε times it.
        let terms = norm_inf(bx).max(norm_inf(t)).max(
            ex.iter()
                .zip(bx)
                .map(|(e, b)| (b - e).abs())
                .fold(0.0, f64::max),
        );
        (ex, et, size, terms)
    }

    /// Solves `[0 Eᵀ Gᵀ; E 0 0; G 0 −WᵀW] (x, y, z) = (b_x, b_y, b_z)` given `t = (b_y,
    /// W⁻ᵀb_z)`, refining on the unreduced system in the scaled space (module docs).
    pub(super) fn solve(&self, st: &Structure, bx: &[f64], t: &[f64]) -> KktSolution {
        let mut u = self.solve_once(st, bx, t);
        let (mut ex, mut et, mut size, terms) = self.residual(st, (bx, t), &u);
        let floor = REFINE_BELOW * terms;
        for _ in 0..MAX_REFINEMENT {
            // Also stops on NaN (no comparison holds).
            if size.partial_cmp(&floor) != Some(std::cmp::Ordering::Greater) {
                break;
            }
            let du = self.solve_once(st, &ex, &et);
            let mut next = u.clone();
            next.x.iter_mut().zip(&du.x).for_each(|(a, b)| *a += b);
            next.yz.iter_mut().zip(&du.yz).for_each(|(a, b)| *a += b);
            let (nex, net, nsize, _) = self.residual(st, (bx, t), &next);
            if nsize.partial_cmp(&size) != Some(std::cmp::Ordering::Less) {
                break;
            }
            let halved = nsize <= 0.5 * size;
            (u, ex, et, size) = (next, nex, net, nsize);
            if !halved {
                break;
            }
        }
        u
    }
}
