//! Safe Rust entry points to this crate's dense kernels, for pendulab's own small dense
//! linear algebra (the dense interior-point method of `pendulab-lmi`): the same code the
//! exported symbols run, on column-major `f64` arrays with a tight leading dimension (the
//! number of rows), without the Fortran calling convention.

use crate::blas::Uplo;
use crate::{jacobi, lapack};

/// Cholesky factorisation `A = L Lᵀ` (xPOTRF, lower) of the `n × n` symmetric matrix whose
/// lower triangle `a` holds; `L` overwrites that triangle, the strict upper triangle is not
/// touched. `Err(j)` (1-based) if the leading minor of order `j` is not positive definite
/// (or holds NaN).
///
/// # Panics
/// If `a` has fewer than `n²` entries.
pub fn cholesky_lower(n: usize, a: &mut [f64]) -> Result<(), usize> {
    assert!(a.len() >= n * n);
    match lapack::potrf(Uplo::Lower, n, a, n.max(1)) {
        0 => Ok(()),
        j => Err(j as usize),
    }
}

/// Eigenvalues, ascending, of the `n × n` symmetric matrix whose lower triangle `a` holds
/// (xSYEVR with `JOBZ = 'N'`: Householder tridiagonalisation and the root-free implicit QR,
/// backward stable), into `w[..n]`. `a` is overwritten for `n > 16`; `work` needs `3n`
/// entries. False if an entry is not finite or the iteration did not converge.
///
/// # Panics
/// If a slice is too short.
pub fn symmetric_eigenvalues(n: usize, a: &mut [f64], w: &mut [f64], work: &mut [f64]) -> bool {
    assert!(a.len() >= n * n && w.len() >= n && work.len() >= 3 * n);
    if n == 0 {
        return true;
    }
    lapack::syevr_values(lapack::EigRange::All, Uplo::Lower, n, (a, n), w, work) == Some(n)
}

/// The SVD `A = U diag(s) Vᵀ` of the square `n × n` matrix `a`: `u` and `vt` (`n × n`,
/// orthogonal), `s` descending. One-sided Jacobi for `n ≤ 32` (as `dgesvd_`), nalgebra's
/// bidiagonal QR beyond. False if an entry is not finite or the iteration did not converge.
///
/// # Panics
/// If a slice is too short.
pub fn svd_square(n: usize, a: &[f64], u: &mut [f64], s: &mut [f64], vt: &mut [f64]) -> bool {
    assert!(a.len() >= n * n && u.len() >= n * n && vt.len() >= n * n && s.len() >= n);
    if n == 0 {
        return true;
    }
    if n <= jacobi::MAX_SIDE {
        let done = jacobi::jacobi_svd((n, n), (a, n), (true, false), |f| {
            s[..n].copy_from_slice(f.s);
            for j in 0..n {
                for i in 0..n {
                    u[i + j * n] = f.u(i, j);
                    vt[i + j * n] = f.vt(i, j);
                }
            }
        });
        if done {
            return true;
        }
    }
    let Some(dec) = lapack::svd((n, n), (a, n), (true, false), (true, false)) else {
        return false;
    };
    let (Some(uf), Some(vf)) = (&dec.u, &dec.vt) else {
        return false;
    };
    s[..n].copy_from_slice(&dec.s);
    u[..n * n].copy_from_slice(uf.as_slice());
    vt[..n * n].copy_from_slice(vf.as_slice());
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `op(A) op(B)` of `n × n` column-major matrices by the defining sum.
    fn product(n: usize, (ta, tb): (bool, bool), a: &[f64], b: &[f64]) -> Vec<f64> {
        let at = |i: usize, k: usize| if ta { a[k + i * n] } else { a[i + k * n] };
        let bt = |k: usize, j: usize| if tb { b[j + k * n] } else { b[k + j * n] };
        let mut c = vec![0.0; n * n];
        for j in 0..n {
            for i in 0..n {
                c[i + j * n] = (0..n).map(|k| at(i, k) * bt(k, j)).sum();
            }
        }
        c
    }

    /// The kernels against their defining equations on a small SPD matrix.
    #[test]
    fn kernels_satisfy_their_defining_equations() {
        let n = 4;
        // A = BᵀB + I with a fixed B: symmetric positive definite.
        let b: Vec<f64> = (0..n * n)
            .map(|k| ((k * 7 + 3) % 11) as f64 - 5.0)
            .collect();
        let mut a = product(n, (true, false), &b, &b);
        for i in 0..n {
            a[i + i * n] += 1.0;
        }
        // Cholesky: L Lᵀ = A to rounding.
        let mut l = a.clone();
        cholesky_lower(n, &mut l).unwrap();
        for j in 0..n {
            for i in 0..j {
                l[i + j * n] = 0.0;
            }
        }
        let llt = product(n, (false, true), &l, &l);
        let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for k in 0..n * n {
            assert!((llt[k] - a[k]).abs() <= 1e-13 * scale);
        }
        // Eigenvalues: their sum is the trace and each makes A − λI singular (det via
        // the Cholesky of A − (λ − δ)I succeeding just below and failing just above).
        let mut copy = a.clone();
        let (mut w, mut work) = (vec![0.0; n], vec![0.0; 3 * n]);
        assert!(symmetric_eigenvalues(n, &mut copy, &mut w, &mut work));
        let trace: f64 = (0..n).map(|i| a[i + i * n]).sum();
        assert!((w.iter().sum::<f64>() - trace).abs() <= 1e-12 * trace);
        assert!(w.windows(2).all(|p| p[0] <= p[1]));
        let shifted = |mu: f64| {
            let mut m = a.clone();
            for i in 0..n {
                m[i + i * n] -= mu;
            }
            cholesky_lower(n, &mut m).is_ok()
        };
        assert!(shifted(w[0] * (1.0 - 1e-9)) && !shifted(w[0] * (1.0 + 1e-9)));
        // SVD: U diag(s) Vᵀ = B, U and V orthogonal.
        let (mut u, mut s, mut vt) = (vec![0.0; n * n], vec![0.0; n], vec![0.0; n * n]);
        assert!(svd_square(n, &b, &mut u, &mut s, &mut vt));
        let mut us = u.clone();
        for j in 0..n {
            for i in 0..n {
                us[i + j * n] *= s[j];
            }
        }
        let usv = product(n, (false, false), &us, &vt);
        let bscale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for k in 0..n * n {
            assert!((usv[k] - b[k]).abs() <= 1e-13 * bscale * n as f64);
        }
        let utu = product(n, (true, false), &u, &u);
        for j in 0..n {
            for i in 0..n {
                let id = if i == j { 1.0 } else { 0.0 };
                assert!((utu[i + j * n] - id).abs() <= 1e-14 * n as f64);
            }
        }
    }
}
