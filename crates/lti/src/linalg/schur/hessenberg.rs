//! Householder reduction to upper Hessenberg form `H = Qᵀ A Q` and the accumulation of `Q`
//! (LAPACK `dgehd2`/`dorghr`, blocked `dgehrd`/`dlahr2` with compact-WY `dlarft`/`dlarfb`): the
//! first stage of the real Schur form.
//!
//! Neighbours: [`super`] holds the public API (`RealSchur`, `real_schur`, `ordered_schur`);
//! `francis.rs` iterates the Hessenberg matrix to Schur form; `swap.rs` and `reorder.rs` reorder
//! the Schur form.

use crate::linalg::Mat;
use crate::linalg::dense::{axpy, dot, larfg};

/// Panel width of the blocked Hessenberg reduction and of the blocked accumulation of `Q`.
const HESS_NB: usize = 32;

/// Smallest order for which [`hessenberg`] uses the blocked algorithms; smaller matrices (and
/// the last `2·HESS_NB` reflectors of larger ones) use the unblocked ones.
const HESS_BLOCKED_MIN: usize = 96;

/// Reduces the column-major `n × n` matrix `a` to upper Hessenberg form `H = Qᵀ A Q` by
/// Householder reflectors; if `q` is given it is overwritten with `Q`. Entries below the
/// subdiagonal are set to zero.
///
/// For `n ≥ HESS_BLOCKED_MIN` the reflectors are generated in panels of `HESS_NB` and the
/// trailing matrix is updated with matrix–matrix products (LAPACK `dgehrd`/`dlahr2`;
/// G. Quintana-Ortí & R. van de Geijn, "Improving the performance of reduction to Hessenberg
/// form", ACM TOMS 32, 2006), and `Q` is accumulated backwards in blocks `I − V T Vᵀ`
/// (compact WY form, Schreiber & Van Loan 1989; LAPACK `dlarft`/`dlarfb`/`dorghr`). The last
/// reflectors (and small matrices) use the unblocked algorithms (LAPACK `dgehd2`/`dorg2r`).
pub(crate) fn hessenberg(a: &mut [f64], n: usize, q: Option<&mut [f64]>) {
    hessenberg_impl(a, n, q, n >= HESS_BLOCKED_MIN);
}

/// [`hessenberg`] with the choice between the blocked and the unblocked algorithms explicit.
pub(super) fn hessenberg_impl(a: &mut [f64], n: usize, q: Option<&mut [f64]>, blocked: bool) {
    let nr = n.saturating_sub(2);
    let mut taus = vec![0.0; nr];
    let mut start = 0;
    if blocked {
        let mut ws = PanelWork::new(n, HESS_NB);
        while nr - start > 2 * HESS_NB {
            hessenberg_panel(
                a,
                n,
                start,
                HESS_NB,
                &mut taus[start..start + HESS_NB],
                &mut ws,
            );
            start += HESS_NB;
        }
    }
    hessenberg_unblocked(a, n, start, &mut taus);
    if let Some(q) = q {
        accumulate_q(a, n, &taus, q, blocked);
    }
    for j in 0..n {
        for i in j + 2..n {
            a[i + j * n] = 0.0;
        }
    }
}

/// Unblocked Householder reduction (LAPACK `dgehd2`) of columns `start..n−2` of `a`; the
/// reflector tails are left below the subdiagonal and their factors in `taus`.
fn hessenberg_unblocked(a: &mut [f64], n: usize, start: usize, taus: &mut [f64]) {
    let nr = n.saturating_sub(2);
    let mut w = vec![0.0; n];
    let mut v = vec![0.0; n];
    for k in start..nr {
        let col = k * n;
        let len = n - k - 1; // reflector length (rows k+1..n)
        let alpha = a[col + k + 1];
        let (beta, tau) = larfg(alpha, &mut a[col + k + 2..col + n]);
        taus[k] = tau;
        a[col + k + 1] = beta;
        if tau == 0.0 {
            continue;
        }
        v[0] = 1.0;
        v[1..len].copy_from_slice(&a[col + k + 2..col + n]);
        let v = &v[..len];
        // Right: A[:, k+1..n] ← A[:, k+1..n] (I − τ v vᵀ).  w = A[:, k+1..n] v.
        w.iter_mut().for_each(|x| *x = 0.0);
        for (i, &vi) in v.iter().enumerate() {
            let c = (k + 1 + i) * n;
            axpy(vi, &a[c..c + n], &mut w);
        }
        for (i, &vi) in v.iter().enumerate() {
            let c = (k + 1 + i) * n;
            axpy(-tau * vi, &w, &mut a[c..c + n]);
        }
        // Left: A[k+1..n, k+1..n] ← (I − τ v vᵀ) A[k+1..n, k+1..n].
        for j in k + 1..n {
            let c = j * n + k + 1;
            let s = tau * dot(v, &a[c..c + len]);
            axpy(-s, v, &mut a[c..c + len]);
        }
    }
}

/// Work space of [`hessenberg_panel`]: `V` and `Y` (`n × nb`), `T` (`nb × nb`), all
/// column-major.
struct PanelWork {
    v: Mat,
    y: Mat,
    t: Mat,
    tmp: Vec<f64>,
}

impl PanelWork {
    fn new(n: usize, nb: usize) -> Self {
        Self {
            v: Mat::zeros(n, nb),
            y: Mat::zeros(n, nb),
            t: Mat::zeros(nb, nb),
            tmp: vec![0.0; nb],
        }
    }
}

/// Reduces the `nb` columns `p0..p0+nb` of `a` and applies the panel's transformation
/// `Q_p = H_{p0}⋯H_{p0+nb−1} = I − V T Vᵀ` to the rest: `A ← Q_pᵀ A Q_p`.
///
/// With `Y = A V T` (`A` before the panel), `A Q_p = A − Y Vᵀ`. Column `c = p0 + j` is brought
/// up to date just before its reflector is generated (`−Y₍<j₎ V₍<j₎[c, :]ᵀ`, then the left
/// factor `I − V₍<j₎ T₍<j₎ᵀ V₍<j₎ᵀ`); the new column of `Y` is
/// `τ_j (A v_j − Y₍<j₎ V₍<j₎ᵀ v_j)` and of `T` is `−τ_j T₍<j₎ V₍<j₎ᵀ v_j` (LAPACK `dlahr2`). Rows
/// `0..=p0` of `Y` are formed afterwards by one product, then the trailing columns get
/// `A ← A − Y Vᵀ` and `A ← (I − V Tᵀ Vᵀ) A` as matrix–matrix products.
fn hessenberg_panel(
    a: &mut [f64],
    n: usize,
    p0: usize,
    nb: usize,
    taus: &mut [f64],
    ws: &mut PanelWork,
) {
    let r0 = p0 + 1; // first row touched by the panel's reflectors
    let m = n - r0; // their length
    ws.v.fill(0.0);
    ws.y.fill(0.0);
    ws.t.fill(0.0);
    for j in 0..nb {
        let c = p0 + j;
        if j > 0 {
            // Right factor of the previous reflectors on rows r0..n of column c.
            {
                let col = &mut a[c * n + r0..c * n + n];
                for i in 0..j {
                    let vci = ws.v[(c, i)];
                    if vci != 0.0 {
                        axpy(-vci, &ws.y.as_slice()[i * n + r0..i * n + n], col);
                    }
                }
            }
            // Left factor I − V T₍<j₎ᵀ Vᵀ on rows r0..n of column c.
            let col = &mut a[c * n + r0..c * n + n];
            let vs = ws.v.as_slice();
            for i in 0..j {
                ws.tmp[i] = dot(&vs[i * n + r0..i * n + n], col);
            }
            // tmp ← Tᵀ tmp (T upper triangular): from the bottom up.
            for i in (0..j).rev() {
                let mut s = 0.0;
                for l in 0..=i {
                    s += ws.t[(l, i)] * ws.tmp[l];
                }
                ws.tmp[i] = s;
            }
            for i in 0..j {
                axpy(-ws.tmp[i], &vs[i * n + r0..i * n + n], col);
            }
        }
        // Reflector annihilating rows c+2..n of column c.
        let (beta, tau) = {
            let col = &mut a[c * n..c * n + n];
            let (head, tail) = col.split_at_mut(c + 2);
            larfg(head[c + 1], tail)
        };
        a[c * n + c + 1] = beta;
        taus[j] = tau;
        {
            let vcol = &mut ws.v.as_mut_slice()[j * n..j * n + n];
            vcol[c + 1] = 1.0;
            vcol[c + 2..].copy_from_slice(&a[c * n + c + 2..c * n + n]);
        }
        // Y[r0.., j] = τ (A[r0.., c+1..n] v − Y[r0.., <j] (V<jᵀ v)).
        let vs = ws.v.as_slice();
        let vj = &vs[j * n..j * n + n];
        {
            let ycol = &mut ws.y.as_mut_slice()[j * n + r0..j * n + n];
            for l in c + 1..n {
                let vl = vj[l];
                if vl != 0.0 {
                    axpy(vl, &a[l * n + r0..l * n + n], ycol);
                }
            }
        }
        for i in 0..j {
            ws.tmp[i] = dot(&vs[i * n + c + 1..i * n + n], &vj[c + 1..]);
        }
        {
            let (yprev, ynext) = ws.y.as_mut_slice().split_at_mut(j * n);
            let ycol = &mut ynext[r0..n];
            for i in 0..j {
                axpy(-ws.tmp[i], &yprev[i * n + r0..i * n + n], ycol);
            }
            ycol.iter_mut().for_each(|x| *x *= tau);
        }
        // T[<j, j] = −τ T<j tmp, T[j, j] = τ.
        for i in 0..j {
            let mut s = 0.0;
            for l in i..j {
                s += ws.t[(i, l)] * ws.tmp[l];
            }
            ws.t[(i, j)] = -tau * s;
        }
        ws.t[(j, j)] = tau;
    }
    let mut am = nalgebra::DMatrixViewMut::from_slice(a, n, n);
    let v = &ws.v;
    let vsub = v.rows(r0, m);
    // Rows 0..r0 of Y = A[0..r0, r0..n] V[r0..n, :] T (those rows of A are still untouched).
    {
        let mut ytop = ws.y.rows_mut(0, r0);
        ytop.gemm(1.0, &am.view((0, r0), (r0, m)), &vsub, 0.0);
        let yt = ytop.clone_owned() * ws.t.upper_triangle();
        ytop.copy_from(&yt);
    }
    let y = &ws.y;
    // Right update of the trailing columns: A[:, p0+nb..n] −= Y V[p0+nb..n, :]ᵀ.
    let c1 = p0 + nb;
    let vt_trail = v.rows(c1, n - c1).transpose();
    am.view_mut((0, c1), (n, n - c1))
        .gemm(-1.0, y, &vt_trail, 1.0);
    // Rows 0..r0 of the panel columns p0+1..p0+nb: −Y[0..r0, :] V[p0+1..p0+nb, :]ᵀ.
    let vt_panel = v.rows(r0, nb - 1).transpose();
    am.view_mut((0, r0), (r0, nb - 1))
        .gemm(-1.0, &y.rows(0, r0), &vt_panel, 1.0);
    // Left update of the trailing columns: A[r0.., c1..] ← (I − V Tᵀ Vᵀ) A[r0.., c1..].
    let mut w = vsub.transpose() * am.view((r0, c1), (m, n - c1));
    w = ws.t.upper_triangle().transpose() * w;
    am.view_mut((r0, c1), (m, n - c1))
        .gemm(-1.0, &vsub, &w, 1.0);
}

/// Overwrites `q` with `Q = H_0 H_1 ⋯ H_{n−3}` from the reflectors left in `a` by the
/// reduction (LAPACK `dorghr`): backward accumulation, in blocks `I − V T Vᵀ` for large `n`.
fn accumulate_q(a: &[f64], n: usize, taus: &[f64], q: &mut [f64], blocked: bool) {
    let nr = taus.len();
    q.iter_mut().for_each(|x| *x = 0.0);
    for i in 0..n {
        q[i + i * n] = 1.0;
    }
    // Reflectors kb..nr unblocked (the last ones), the rest in blocks of HESS_NB.
    let nblocks = if blocked {
        nr.saturating_sub(2 * HESS_NB) / HESS_NB
    } else {
        0
    };
    let kb = nblocks * HESS_NB;
    let mut v = vec![0.0; n];
    for k in (kb..nr).rev() {
        let tau = taus[k];
        if tau == 0.0 {
            continue;
        }
        let len = n - k - 1;
        let col = k * n;
        v[0] = 1.0;
        v[1..len].copy_from_slice(&a[col + k + 2..col + n]);
        let v = &v[..len];
        for j in k + 1..n {
            let c = j * n + k + 1;
            let s = tau * dot(v, &q[c..c + len]);
            if s != 0.0 {
                axpy(-s, v, &mut q[c..c + len]);
            }
        }
    }
    if nblocks == 0 {
        return;
    }
    let nb = HESS_NB;
    let mut vm = Mat::zeros(n, nb);
    let mut t = Mat::zeros(nb, nb);
    let mut qm = nalgebra::DMatrixViewMut::from_slice(q, n, n);
    for blk in (0..nblocks).rev() {
        let p0 = blk * nb;
        let r0 = p0 + 1;
        let m = n - r0;
        vm.fill(0.0);
        for j in 0..nb {
            let c = p0 + j;
            vm[(c + 1, j)] = 1.0;
            for r in c + 2..n {
                vm[(r, j)] = a[r + c * n];
            }
        }
        // T (LAPACK dlarft, forward, columnwise): T[<j, j] = −τ_j T<j V<jᵀ v_j.
        t.fill(0.0);
        for j in 0..nb {
            let tau = taus[p0 + j];
            let mut tmp = [0.0; HESS_NB];
            let vs = vm.as_slice();
            for (i, ti) in tmp.iter_mut().enumerate().take(j) {
                *ti = dot(&vs[i * n + r0..i * n + n], &vs[j * n + r0..j * n + n]);
            }
            for i in 0..j {
                let mut s = 0.0;
                for l in i..j {
                    s += t[(i, l)] * tmp[l];
                }
                t[(i, j)] = -tau * s;
            }
            t[(j, j)] = tau;
        }
        // Q[r0.., r0..] ← (I − V T Vᵀ) Q[r0.., r0..].
        let vsub = vm.rows(r0, m);
        let mut w = vsub.transpose() * qm.view((r0, r0), (m, m));
        w = &t * w;
        qm.view_mut((r0, r0), (m, m)).gemm(-1.0, &vsub, &w, 1.0);
    }
}
