//! Small dense kernels of the interior-point method on column-major arrays with tight leading
//! dimension: dot products and norms, svec/smat, `d × d` products (fixed-size up to side 16),
//! congruences, Cholesky factorisation (plain and regularised) and triangular solves.
//!
//! Neighbours: [`super`] describes the method; `scaling.rs` (the cones' Nesterov–Todd scaling),
//! `kkt.rs` (the Newton systems), `embedding.rs` (iterate, residuals, stopping measures) and
//! `driver.rs` (the iteration) use these kernels.

use pendulab_lapack::kernels::cholesky_lower;
use std::f64::consts::SQRT_2;

/// `aᵀb` over the common length, in four interleaved partial sums (independent chains the
/// processor overlaps and the compiler vectorises).
#[inline]
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        let x: &[f64; 4] = x.try_into().unwrap_or(&[0.0; 4]);
        let y: &[f64; 4] = y.try_into().unwrap_or(&[0.0; 4]);
        acc[0] += x[0] * y[0];
        acc[1] += x[1] * y[1];
        acc[2] += x[2] * y[2];
        acc[3] += x[3] * y[3];
    }
    let mut tail = 0.0;
    for (x, y) in ra.iter().zip(rb) {
        tail += x * y;
    }
    (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail
}

pub(super) fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

pub(super) fn norm_inf(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// The symmetric `d × d` matrix of an svec, into `m`.
pub(super) fn smat_into(v: &[f64], d: usize, m: &mut [f64]) {
    let mut k = 0;
    for j in 0..d {
        for i in 0..=j {
            if i == j {
                m[i + j * d] = v[k];
            } else {
                let x = v[k] / SQRT_2;
                m[i + j * d] = x;
                m[j + i * d] = x;
            }
            k += 1;
        }
    }
}

/// svec of the symmetric part of the `d × d` matrix `m`, into `out`.
pub(super) fn svec_sym(m: &[f64], d: usize, out: &mut [f64]) {
    let mut k = 0;
    for j in 0..d {
        for i in 0..=j {
            out[k] = if i == j {
                m[i + j * d]
            } else {
                (m[i + j * d] + m[j + i * d]) * (0.5 * SQRT_2)
            };
            k += 1;
        }
    }
}

/// `out = op(A) op(B)` for `d × d` matrices, `op(X) = Xᵀ` when its flag is set. Sides up to
/// 16 run on a kernel with the side as a compile-time constant (the columns
/// then live in registers); larger ones on the same loops with a run-time side.
pub(super) fn mul(d: usize, (ta, tb): (bool, bool), a: &[f64], b: &[f64], out: &mut [f64]) {
    macro_rules! dispatch {
        ($($side:literal)*) => {
            match d {
                $($side => mul_fixed::<$side>((ta, tb), a, b, out),)*
                _ => mul_dynamic(d, (ta, tb), a, b, out),
            }
        };
    }
    dispatch!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
}

/// [`mul`] for side `D`: each column of the result accumulated in a `[f64; D]`.
#[inline(always)]
fn mul_fixed<const D: usize>((ta, tb): (bool, bool), a: &[f64], b: &[f64], out: &mut [f64]) {
    let (ac, _) = a[..D * D].as_chunks::<D>();
    let (bc, _) = b[..D * D].as_chunks::<D>();
    let (oc, _) = out[..D * D].as_chunks_mut::<D>();
    if ta {
        // out(i, j) = A(:, i) · op(B)(:, j); with op(B) = Bᵀ, that column is row j of B.
        for j in 0..D {
            let bj: [f64; D] = if tb {
                std::array::from_fn(|k| bc[k][j])
            } else {
                bc[j]
            };
            for i in 0..D {
                let mut acc = 0.0;
                for k in 0..D {
                    acc += ac[i][k] * bj[k];
                }
                oc[j][i] = acc;
            }
        }
    } else {
        // out(:, j) = Σ_k A(:, k) op(B)(k, j).
        for j in 0..D {
            let mut col = [0.0; D];
            for k in 0..D {
                let bkj = if tb { bc[k][j] } else { bc[j][k] };
                let ak = &ac[k];
                for i in 0..D {
                    col[i] += ak[i] * bkj;
                }
            }
            oc[j] = col;
        }
    }
}

/// [`mul`] for any side.
fn mul_dynamic(d: usize, (ta, tb): (bool, bool), a: &[f64], b: &[f64], out: &mut [f64]) {
    let bkj = |k: usize, j: usize| if tb { b[j + k * d] } else { b[k + j * d] };
    if ta {
        for j in 0..d {
            for i in 0..d {
                out[i + j * d] = (0..d).map(|k| a[k + i * d] * bkj(k, j)).sum();
            }
        }
    } else {
        for j in 0..d {
            let col = &mut out[j * d..(j + 1) * d];
            col.iter_mut().for_each(|x| *x = 0.0);
            for k in 0..d {
                let s = bkj(k, j);
                for (o, aik) in col.iter_mut().zip(&a[k * d..(k + 1) * d]) {
                    *o += aik * s;
                }
            }
        }
    }
}

/// svec of the `d × d` matrix `m` that is symmetric by construction (up to rounding), from
/// its upper triangle, into `out`.
pub(super) fn svec_upper(m: &[f64], d: usize, out: &mut [f64]) {
    let mut k = 0;
    for j in 0..d {
        let col = &m[j * d..j * d + j + 1];
        let dst = &mut out[k..k + j + 1];
        for (o, x) in dst.iter_mut().zip(col) {
            *o = x * SQRT_2;
        }
        dst[j] = col[j];
        k += j + 1;
    }
}

/// `out = T · Pᵀ` for `d × d` matrices where only the columns `cols` of `T` are nonzero:
/// `out(:, q) = Σ_{c ∈ cols} T(:, c) P(q, c)` (fixed-size kernel up to side 16).
pub(super) fn mul_nt_cols(d: usize, t: &[f64], p: &[f64], cols: &[usize], out: &mut [f64]) {
    macro_rules! dispatch {
        ($($side:literal)*) => {
            match d {
                $($side => mul_nt_cols_fixed::<$side>(t, p, cols, out),)*
                _ => {
                    for q in 0..d {
                        let o = &mut out[q * d..(q + 1) * d];
                        o.iter_mut().for_each(|x| *x = 0.0);
                        for &c in cols {
                            let w = p[q + c * d];
                            for (ov, tv) in o.iter_mut().zip(&t[c * d..(c + 1) * d]) {
                                *ov += tv * w;
                            }
                        }
                    }
                }
            }
        };
    }
    dispatch!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
}

#[inline(always)]
fn mul_nt_cols_fixed<const D: usize>(t: &[f64], p: &[f64], cols: &[usize], out: &mut [f64]) {
    let (tc, _) = t[..D * D].as_chunks::<D>();
    let (pc, _) = p[..D * D].as_chunks::<D>();
    let (oc, _) = out[..D * D].as_chunks_mut::<D>();
    for q in 0..D {
        let mut col = [0.0; D];
        for &c in cols {
            let w = pc[c][q];
            let tcol = &tc[c];
            for i in 0..D {
                col[i] += tcol[i] * w;
            }
        }
        oc[q] = col;
    }
}

/// `svec(P · smat(v) · Pᵀ)` into `out` (`P` is `d × d`).
pub(super) fn congruence(d: usize, p: &[f64], v: &[f64], out: &mut [f64]) {
    let mut m = vec![0.0; d * d];
    let mut t = vec![0.0; d * d];
    smat_into(v, d, &mut m);
    mul(d, (false, false), p, &m, &mut t);
    mul(d, (false, true), &t, p, &mut m);
    svec_upper(&m, d, out);
}

pub(super) fn transpose(d: usize, a: &[f64]) -> Vec<f64> {
    let mut t = vec![0.0; d * d];
    for j in 0..d {
        for i in 0..d {
            t[j + i * d] = a[i + j * d];
        }
    }
    t
}

/// Lower Cholesky factor of a copy of the symmetric `m` (strict upper triangle zeroed), or
/// None when it is not positive definite.
pub(super) fn cholesky(d: usize, m: &[f64]) -> Option<Vec<f64>> {
    let mut l = m.to_vec();
    cholesky_lower(d, &mut l).ok()?;
    for j in 0..d {
        for i in 0..j {
            l[i + j * d] = 0.0;
        }
    }
    Some(l)
}

/// Cholesky factor of the symmetric positive (semi)definite `n × n` matrix `m`, with a
/// diagonal shift of growing size (from `10⁻¹⁴·max diag`) when the plain factorisation
/// fails.
pub(super) fn cholesky_regularised(n: usize, m: &[f64]) -> Option<Vec<f64>> {
    let scale = (0..n).fold(0.0f64, |a, i| a.max(m[i + i * n].abs()));
    if !scale.is_finite() {
        return None;
    }
    if let Some(l) = cholesky(n, m) {
        return Some(l);
    }
    let mut delta = 1e-14 * scale.max(f64::MIN_POSITIVE);
    for _ in 0..6 {
        let mut shifted = m.to_vec();
        for i in 0..n {
            shifted[i + i * n] += delta;
        }
        if let Some(l) = cholesky(n, &shifted) {
            return Some(l);
        }
        delta *= 100.0;
    }
    None
}

/// `b ← L⁻¹ b` for the lower triangular `n × n` `l`.
pub(super) fn forward(n: usize, l: &[f64], b: &mut [f64]) {
    for j in 0..n {
        let v = b[j] / l[j + j * n];
        b[j] = v;
        if v != 0.0 {
            for i in j + 1..n {
                b[i] -= l[i + j * n] * v;
            }
        }
    }
}

/// `b ← L⁻ᵀ b` for the lower triangular `n × n` `l`.
fn backward(n: usize, l: &[f64], b: &mut [f64]) {
    for j in (0..n).rev() {
        let col = &l[j * n..(j + 1) * n];
        let s: f64 = (j + 1..n).map(|i| col[i] * b[i]).sum();
        b[j] = (b[j] - s) / col[j];
    }
}

/// `b ← (L Lᵀ)⁻¹ b`.
pub(super) fn chol_solve(n: usize, l: &[f64], b: &mut [f64]) {
    forward(n, l, b);
    backward(n, l, b);
}
