//! The dense kernels of [`care_compact`](super::care_compact) on flat row-major stack arrays
//! with run-time loops (small code rather than fast loops; the module documentation of
//! `compact`): Cholesky, LU with partial pivoting, its solves and inverse, and the
//! eigenvalues of a small real matrix by Hessenberg reduction and the Francis double-shift
//! QR iteration (EISPACK `hqr`).

use super::{COMPACT_MAX, SQ};
use crate::linalg::Complex64;

/// `R = LLᵀ` in place (lower triangle); `false` unless `R ≻ 0`.
pub(super) fn cholesky(l: &mut [f64; SQ], m: usize) -> bool {
    for j in 0..m {
        let d = l[j * m + j] - (0..j).map(|p| l[j * m + p] * l[j * m + p]).sum::<f64>();
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let d = d.sqrt();
        l[j * m + j] = d;
        for i in j + 1..m {
            let s: f64 = (0..j).map(|p| l[i * m + p] * l[j * m + p]).sum();
            l[i * m + j] = (l[i * m + j] - s) / d;
        }
    }
    true
}

/// `PA = LU` in place (row-major, stride `n`), partial pivoting; `false` on a zero pivot.
pub(super) fn lu(a: &mut [f64], piv: &mut [usize], n: usize) -> bool {
    for k in 0..n {
        let p = (k..n)
            .max_by(|&i, &j| a[i * n + k].abs().total_cmp(&a[j * n + k].abs()))
            .unwrap_or(k);
        piv[k] = p;
        if a[p * n + k] == 0.0 {
            return false;
        }
        if p != k {
            for j in 0..n {
                a.swap(k * n + j, p * n + j);
            }
        }
        let inv = 1.0 / a[k * n + k];
        // Rows k + 1.. less multiples of the pivot row (its entries right of the pivot).
        let (upper, lower) = a[..n * n].split_at_mut((k + 1) * n);
        let pivot = &upper[k * n + k + 1..(k + 1) * n];
        for row in lower.chunks_exact_mut(n) {
            let f = row[k] * inv;
            row[k] = f;
            if f != 0.0 {
                for (x, p) in row[k + 1..].iter_mut().zip(pivot) {
                    *x -= f * p;
                }
            }
        }
    }
    true
}

/// Solves `A y = b` in place from [`lu`]'s factors.
pub(super) fn lu_solve(lu: &[f64], piv: &[usize], n: usize, b: &mut [f64]) {
    for k in 0..n {
        b.swap(k, piv[k]);
    }
    let (lu, b) = (&lu[..n * n], &mut b[..n]);
    for (i, row) in lu.chunks_exact(n).enumerate() {
        let s: f64 = row[..i].iter().zip(&b[..i]).map(|(l, y)| l * y).sum();
        b[i] -= s;
    }
    for (i, row) in lu.chunks_exact(n).enumerate().rev() {
        let s: f64 = row[i + 1..]
            .iter()
            .zip(&b[i + 1..])
            .map(|(u, y)| u * y)
            .sum();
        b[i] = (b[i] - s) / row[i];
    }
}

/// `A⁻¹` (stride `n`) from [`lu`]'s factors.
pub(super) fn inverse(lu: &[f64], piv: &[usize], n: usize, out: &mut [f64]) {
    let mut e = [0.0; 2 * COMPACT_MAX];
    for j in 0..n {
        e[..n].fill(0.0);
        e[j] = 1.0;
        lu_solve(lu, piv, n, &mut e);
        for i in 0..n {
            out[i * n + j] = e[i];
        }
    }
}

/// Eigenvalues of `a` (`n × n`, destroyed): Householder reduction to Hessenberg form, then
/// the Francis double-shift QR iteration (EISPACK `hqr`); sorted as
/// [`sort_eigenvalues`](crate::linalg::sort_eigenvalues). `None` when the iteration does not
/// converge in `30·n` steps.
pub(super) fn eigenvalues(a: &mut [f64; SQ], n: usize) -> Option<[Complex64; COMPACT_MAX]> {
    hessenberg(a, n);
    let mut wr = [0.0; COMPACT_MAX];
    let mut wi = [0.0; COMPACT_MAX];
    if !hqr(a, n, &mut wr, &mut wi) {
        return None;
    }
    let mut ev = [Complex64::new(0.0, 0.0); COMPACT_MAX];
    for i in 0..n {
        ev[i] = Complex64::new(wr[i], wi[i]);
    }
    // Insertion sort in the order of `sort_eigenvalues` (no allocation, little code).
    let before = |x: &Complex64, y: &Complex64| x.re > y.re || (x.re == y.re && x.im > y.im);
    for i in 1..n {
        let mut j = i;
        while j > 0 && before(&ev[j], &ev[j - 1]) {
            ev.swap(j, j - 1);
            j -= 1;
        }
    }
    Some(ev)
}

/// Householder reduction of `a` (`n × n`) to upper Hessenberg form by similarity.
fn hessenberg(a: &mut [f64; SQ], n: usize) {
    for k in 0..n.saturating_sub(2) {
        let mut v = [0.0; COMPACT_MAX];
        let norm = (k + 1..n)
            .map(|i| a[i * n + k] * a[i * n + k])
            .sum::<f64>()
            .sqrt();
        if norm == 0.0 {
            continue;
        }
        let alpha = if a[(k + 1) * n + k] > 0.0 {
            -norm
        } else {
            norm
        };
        for i in k + 1..n {
            v[i] = a[i * n + k];
        }
        v[k + 1] -= alpha;
        let vv: f64 = (k + 1..n).map(|i| v[i] * v[i]).sum();
        if vv == 0.0 {
            continue;
        }
        // (I − 2vvᵀ/vᵀv) A (I − 2vvᵀ/vᵀv).
        for j in 0..n {
            let s = 2.0 * (k + 1..n).map(|i| v[i] * a[i * n + j]).sum::<f64>() / vv;
            for i in k + 1..n {
                a[i * n + j] -= s * v[i];
            }
        }
        for i in 0..n {
            let s = 2.0 * (k + 1..n).map(|j| a[i * n + j] * v[j]).sum::<f64>() / vv;
            for j in k + 1..n {
                a[i * n + j] -= s * v[j];
            }
        }
        for i in k + 2..n {
            a[i * n + k] = 0.0;
        }
    }
}

/// |a| with the sign of b.
fn sign(a: f64, b: f64) -> f64 {
    if b >= 0.0 { a.abs() } else { -a.abs() }
}

/// Eigenvalues of the upper Hessenberg `a` (`n × n`, destroyed) by the Francis double-shift
/// QR iteration with EISPACK `hqr`'s deflation test and exceptional shifts; `false` when an
/// eigenvalue takes more than 30 iterations.
fn hqr(a: &mut [f64; SQ], n: usize, wr: &mut [f64], wi: &mut [f64]) -> bool {
    let at = |i: usize, j: usize| i * n + j;
    let mut anorm = 0.0;
    for i in 0..n {
        for j in i.saturating_sub(1)..n {
            anorm += a[at(i, j)].abs();
        }
    }
    let mut nn = n as isize - 1;
    let mut t = 0.0;
    while nn >= 0 {
        let mut its = 0;
        loop {
            let nu = nn as usize;
            // A negligible subdiagonal entry splits the matrix at l.
            let mut l = nu;
            while l >= 1 {
                let mut s = a[at(l - 1, l - 1)].abs() + a[at(l, l)].abs();
                if s == 0.0 {
                    s = anorm;
                }
                if a[at(l, l - 1)].abs() + s == s {
                    a[at(l, l - 1)] = 0.0;
                    break;
                }
                l -= 1;
            }
            let mut x = a[at(nu, nu)];
            if l == nu {
                wr[nu] = x + t;
                wi[nu] = 0.0;
                nn -= 1;
                break;
            }
            let mut y = a[at(nu - 1, nu - 1)];
            let mut w = a[at(nu, nu - 1)] * a[at(nu - 1, nu)];
            if l + 1 == nu {
                let p = 0.5 * (y - x);
                let q = p * p + w;
                let z = q.abs().sqrt();
                x += t;
                if q >= 0.0 {
                    let z = p + sign(z, p);
                    wr[nu - 1] = x + z;
                    wr[nu] = if z != 0.0 { x - w / z } else { x + z };
                    wi[nu - 1] = 0.0;
                    wi[nu] = 0.0;
                } else {
                    wr[nu - 1] = x + p;
                    wr[nu] = x + p;
                    wi[nu - 1] = z;
                    wi[nu] = -z;
                }
                nn -= 2;
                break;
            }
            if its == 30 {
                return false;
            }
            if its == 10 || its == 20 {
                t += x;
                for i in 0..=nu {
                    a[at(i, i)] -= x;
                }
                let s = a[at(nu, nu - 1)].abs() + a[at(nu - 1, nu - 2)].abs();
                x = 0.75 * s;
                y = x;
                w = -0.4375 * s * s;
            }
            its += 1;
            // Two consecutive small subdiagonal entries start the bulge at m.
            let mut m = nu - 2;
            let (mut p, mut q, mut r);
            loop {
                let z = a[at(m, m)];
                let rr = x - z;
                let ss = y - z;
                p = (rr * ss - w) / a[at(m + 1, m)] + a[at(m, m + 1)];
                q = a[at(m + 1, m + 1)] - z - rr - ss;
                r = a[at(m + 2, m + 1)];
                let s = p.abs() + q.abs() + r.abs();
                p /= s;
                q /= s;
                r /= s;
                if m == l {
                    break;
                }
                let u = a[at(m, m - 1)].abs() * (q.abs() + r.abs());
                let v = p.abs() * (a[at(m - 1, m - 1)].abs() + z.abs() + a[at(m + 1, m + 1)].abs());
                if u + v == v {
                    break;
                }
                m -= 1;
            }
            for i in m + 2..=nu {
                a[at(i, i - 2)] = 0.0;
                if i != m + 2 {
                    a[at(i, i - 3)] = 0.0;
                }
            }
            // The double-shift QR step on rows l..=nu, columns m..=nu.
            for k in m..nu {
                if k != m {
                    p = a[at(k, k - 1)];
                    q = a[at(k + 1, k - 1)];
                    r = if k + 1 != nu {
                        a[at(k + 2, k - 1)]
                    } else {
                        0.0
                    };
                    x = p.abs() + q.abs() + r.abs();
                    if x != 0.0 {
                        p /= x;
                        q /= x;
                        r /= x;
                    }
                }
                let s = sign((p * p + q * q + r * r).sqrt(), p);
                if s != 0.0 {
                    if k == m {
                        if l != m {
                            a[at(k, k - 1)] = -a[at(k, k - 1)];
                        }
                    } else {
                        a[at(k, k - 1)] = -s * x;
                    }
                    p += s;
                    x = p / s;
                    y = q / s;
                    let z = r / s;
                    q /= p;
                    r /= p;
                    for j in k..=nu {
                        let mut pp = a[at(k, j)] + q * a[at(k + 1, j)];
                        if k + 1 != nu {
                            pp += r * a[at(k + 2, j)];
                            a[at(k + 2, j)] -= pp * z;
                        }
                        a[at(k + 1, j)] -= pp * y;
                        a[at(k, j)] -= pp * x;
                    }
                    let mmin = if nu < k + 3 { nu } else { k + 3 };
                    for i in l..=mmin {
                        let mut pp = x * a[at(i, k)] + y * a[at(i, k + 1)];
                        if k + 1 != nu {
                            pp += z * a[at(i, k + 2)];
                            a[at(i, k + 2)] -= pp * r;
                        }
                        a[at(i, k + 1)] -= pp * q;
                        a[at(i, k)] -= pp;
                    }
                }
            }
        }
    }
    true
}
