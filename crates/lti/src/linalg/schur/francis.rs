//! Francis' implicit double-shift QR iteration on an upper Hessenberg matrix (LAPACK `dlahqr`,
//! Ahues–Tisseur deflation, exceptional shifts, 2×2 blocks standardised by `dlanv2`): the second
//! stage of the real Schur form.
//!
//! Neighbours: [`super`] holds the public API; `hessenberg.rs` produces the Hessenberg input;
//! `swap.rs` and `reorder.rs` reorder the resulting Schur form.

use crate::error::{LtiError, Result};
use crate::linalg::dense::{EPS, SAFMIN, lanv2, larfg, rot_cols, rot_rows};

/// Francis' implicit double-shift QR iteration on the upper Hessenberg `n × n` matrix `h`
/// (column-major), after LAPACK `dlahqr`. With `want_t` the full Schur form `T` in standard
/// form is computed; otherwise only the eigenvalues are meaningful (diagonal blocks). If `z`
/// is given the transformations are accumulated into it (`Z ← Z Q`).
pub(crate) fn hqr(h: &mut [f64], n: usize, mut z: Option<&mut [f64]>, want_t: bool) -> Result<()> {
    if n == 0 {
        return Ok(());
    }
    for j in 0..n.saturating_sub(3) {
        h[j + 2 + j * n] = 0.0;
        h[j + 3 + j * n] = 0.0;
    }
    if n >= 3 {
        h[n - 1 + (n - 3) * n] = 0.0;
    }
    let ix = |i: usize, j: usize| i + j * n;
    let ulp = EPS;
    let smlnum = SAFMIN * (n as f64 / ulp);
    let itmax = 30 * n.max(10);
    let (mut i1, mut i2) = (0usize, n - 1);
    // i: last row of the active block; eigenvalues i+1..n have converged.
    let mut i_opt: Option<usize> = Some(n - 1);
    while let Some(i) = i_opt {
        let mut l = 0usize;
        let mut converged = false;
        for its in 0..=itmax {
            // Look for a single small subdiagonal element.
            let mut k = i;
            while k > l {
                let hkk1 = h[ix(k, k - 1)].abs();
                if hkk1 <= smlnum {
                    break;
                }
                let mut tst = h[ix(k - 1, k - 1)].abs() + h[ix(k, k)].abs();
                if tst == 0.0 {
                    if k >= 2 {
                        tst += h[ix(k - 1, k - 2)].abs();
                    }
                    if k + 1 < n {
                        tst += h[ix(k + 1, k)].abs();
                    }
                }
                // Ahues & Tisseur (LAPACK Working Note 122) conservative deflation test.
                if hkk1 <= ulp * tst {
                    let hk1k = h[ix(k - 1, k)].abs();
                    let ab = hkk1.max(hk1k);
                    let ba = hkk1.min(hk1k);
                    let d = (h[ix(k - 1, k - 1)] - h[ix(k, k)]).abs();
                    let hk = h[ix(k, k)].abs();
                    let aa = hk.max(d);
                    let bb = hk.min(d);
                    let s = aa + ab;
                    if ba * (ab / s) <= smlnum.max(ulp * (bb * (aa / s))) {
                        break;
                    }
                }
                k -= 1;
            }
            l = k;
            if l > 0 {
                h[ix(l, l - 1)] = 0.0;
            }
            if l + 1 >= i {
                converged = true;
                break;
            }
            if !want_t {
                i1 = l;
                i2 = i;
            }
            // Shifts.
            let (h11, h12, h21, h22) = if its == 10 {
                let s = h[ix(l + 1, l)].abs() + h[ix(l + 2, l + 1)].abs();
                let h11 = 0.75 * s + h[ix(l, l)];
                (h11, -0.4375 * s, s, h11)
            } else if its == 20 {
                let s = h[ix(i, i - 1)].abs() + h[ix(i - 1, i - 2)].abs();
                let h11 = 0.75 * s + h[ix(i, i)];
                (h11, -0.4375 * s, s, h11)
            } else {
                (
                    h[ix(i - 1, i - 1)],
                    h[ix(i - 1, i)],
                    h[ix(i, i - 1)],
                    h[ix(i, i)],
                )
            };
            let s = h11.abs() + h12.abs() + h21.abs() + h22.abs();
            let (rt1r, rt1i, rt2r, rt2i);
            if s == 0.0 {
                rt1r = 0.0;
                rt1i = 0.0;
                rt2r = 0.0;
                rt2i = 0.0;
            } else {
                let (h11, h12, h21, h22) = (h11 / s, h12 / s, h21 / s, h22 / s);
                let tr = (h11 + h22) / 2.0;
                let det = (h11 - tr) * (h22 - tr) - h12 * h21;
                let rtdisc = det.abs().sqrt();
                if det >= 0.0 {
                    rt1r = tr * s;
                    rt2r = rt1r;
                    rt1i = rtdisc * s;
                    rt2i = -rt1i;
                } else {
                    // Real shifts: use the one closer to h22, twice.
                    let a = tr + rtdisc;
                    let b = tr - rtdisc;
                    let r = if (a - h22).abs() <= (b - h22).abs() {
                        a * s
                    } else {
                        b * s
                    };
                    rt1r = r;
                    rt2r = r;
                    rt1i = 0.0;
                    rt2i = 0.0;
                }
            }
            // Look for two consecutive small subdiagonal elements.
            let mut m = i - 2;
            let mut v = [0.0; 3];
            loop {
                let mut h21s = h[ix(m + 1, m)];
                let s = (h[ix(m, m)] - rt2r).abs() + rt2i.abs() + h21s.abs();
                h21s /= s;
                v[0] = h21s * h[ix(m, m + 1)] + (h[ix(m, m)] - rt1r) * ((h[ix(m, m)] - rt2r) / s)
                    - rt1i * (rt2i / s);
                v[1] = h21s * (h[ix(m, m)] + h[ix(m + 1, m + 1)] - rt1r - rt2r);
                v[2] = h21s * h[ix(m + 2, m + 1)];
                let s = v[0].abs() + v[1].abs() + v[2].abs();
                v.iter_mut().for_each(|x| *x /= s);
                if m == l {
                    break;
                }
                let h00 = h[ix(m, m - 1)].abs() * (v[1].abs() + v[2].abs());
                let h01 = ulp
                    * v[0].abs()
                    * (h[ix(m - 1, m - 1)].abs() + h[ix(m, m)].abs() + h[ix(m + 1, m + 1)].abs());
                if h00 <= h01 {
                    break;
                }
                m -= 1;
            }
            // Double-shift QR sweep: chase the bulge from row m to row i.
            for k in m..i {
                let nr = 3.min(i - k + 1);
                if k > m {
                    v[..nr].copy_from_slice(&h[ix(k, k - 1)..ix(k, k - 1) + nr]);
                }
                let (beta, t1) = {
                    let (a, rest) = v.split_at_mut(1);
                    larfg(a[0], &mut rest[..nr - 1])
                };
                v[0] = beta;
                if k > m {
                    h[ix(k, k - 1)] = beta;
                    h[ix(k + 1, k - 1)] = 0.0;
                    if k + 1 < i {
                        h[ix(k + 2, k - 1)] = 0.0;
                    }
                } else if m > l {
                    // Equivalent to negating it, robust when v(2), v(3) underflow.
                    h[ix(k, k - 1)] *= 1.0 - t1;
                }
                let v2 = v[1];
                let t2 = t1 * v2;
                if nr == 3 {
                    let v3 = v[2];
                    let t3 = t1 * v3;
                    // Rows k..k+2, columns k..=i2.
                    for j in k..=i2 {
                        let c = &mut h[ix(k, j)..ix(k, j) + 3];
                        let sum = c[0] + v2 * c[1] + v3 * c[2];
                        c[0] -= sum * t1;
                        c[1] -= sum * t2;
                        c[2] -= sum * t3;
                    }
                    // Columns k..k+2, rows i1..=min(k+3, i).
                    let rmax = (k + 3).min(i) + 1;
                    apply_reflector3_cols(h, n, k, i1..rmax, v2, v3, t1, t2, t3);
                    if let Some(z) = z.as_deref_mut() {
                        apply_reflector3_cols(z, n, k, 0..n, v2, v3, t1, t2, t3);
                    }
                } else {
                    for j in k..=i2 {
                        let c = &mut h[ix(k, j)..ix(k, j) + 2];
                        let sum = c[0] + v2 * c[1];
                        c[0] -= sum * t1;
                        c[1] -= sum * t2;
                    }
                    apply_reflector2_cols(h, n, k, i1..i + 1, v2, t1, t2);
                    if let Some(z) = z.as_deref_mut() {
                        apply_reflector2_cols(z, n, k, 0..n, v2, t1, t2);
                    }
                }
            }
        }
        if !converged {
            return Err(LtiError::NoConvergence {
                algorithm: "real Schur QR iteration".into(),
                iterations: itmax,
            });
        }
        if l + 1 == i {
            // A 2×2 block has converged: standardise it.
            let r = lanv2(
                h[ix(i - 1, i - 1)],
                h[ix(i - 1, i)],
                h[ix(i, i - 1)],
                h[ix(i, i)],
            );
            h[ix(i - 1, i - 1)] = r.a;
            h[ix(i - 1, i)] = r.b;
            h[ix(i, i - 1)] = r.c;
            h[ix(i, i)] = r.d;
            if want_t {
                if i2 > i {
                    rot_rows(h, n, i - 1, i, i + 1..i2 + 1, r.cs, r.sn);
                }
                rot_cols(h, n, i - 1, i, i1..i - 1, r.cs, r.sn);
            }
            if let Some(z) = z.as_deref_mut() {
                rot_cols(z, n, i - 1, i, 0..n, r.cs, r.sn);
            }
        }
        i_opt = l.checked_sub(1);
    }
    Ok(())
}

/// Applies `I − t1 v vᵀ` with `v = [1, v2, v3]` from the right to columns `k..k+3` of the
/// column-major array `a`, rows `rows`.
#[inline]
fn apply_reflector3_cols(
    a: &mut [f64],
    ld: usize,
    k: usize,
    rows: std::ops::Range<usize>,
    v2: f64,
    v3: f64,
    t1: f64,
    t2: f64,
    t3: f64,
) {
    let (c0, rest) = a[k * ld..].split_at_mut(ld);
    let (c1, c2) = rest.split_at_mut(ld);
    let c0 = &mut c0[rows.clone()];
    let c1 = &mut c1[rows.clone()];
    let c2 = &mut c2[rows];
    for ((x, y), w) in c0.iter_mut().zip(c1.iter_mut()).zip(c2.iter_mut()) {
        let sum = *x + v2 * *y + v3 * *w;
        *x -= sum * t1;
        *y -= sum * t2;
        *w -= sum * t3;
    }
}

/// Applies `I − t1 v vᵀ` with `v = [1, v2]` from the right to columns `k, k+1`, rows `rows`.
#[inline]
fn apply_reflector2_cols(
    a: &mut [f64],
    ld: usize,
    k: usize,
    rows: std::ops::Range<usize>,
    v2: f64,
    t1: f64,
    t2: f64,
) {
    let (c0, rest) = a[k * ld..].split_at_mut(ld);
    let c0 = &mut c0[rows.clone()];
    let c1 = &mut rest[rows];
    for (x, y) in c0.iter_mut().zip(c1.iter_mut()) {
        let sum = *x + v2 * *y;
        *x -= sum * t1;
        *y -= sum * t2;
    }
}
