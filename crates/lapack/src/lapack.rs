//! Safe kernels of the LAPACK drivers: Cholesky (`potrf`, `potrs`), symmetric eigenproblem
//! (`syevr`), singular value decomposition (`gesdd`, `gesvd`) and LU solve (`gesv`).
//!
//! Arguments arrive validated by the symbol layer ([`crate::ffi`]). The results follow the
//! LAPACK 3.x contracts: Cholesky and LU report the failing pivot through `info`, eigenvalues
//! come back in ascending order, singular values in descending order, and the triangle of a
//! symmetric input that the caller did not name is never written.
//!
//! Algorithms: Cholesky is the left-looking column algorithm (Golub & Van Loan, *Matrix
//! Computations*, 4th ed., Alg. 4.2.2); LU is Gaussian elimination with partial pivoting
//! (Alg. 3.4.1, the unblocked LAPACK `xGETF2` organisation, row interchanges recorded as in
//! `IPIV`); the symmetric eigenproblem uses nalgebra's Householder tridiagonalisation with
//! implicit symmetric QR steps and Wilkinson shifts (Alg. 8.3.3); the SVD of matrices with a
//! side above `jacobi::MAX_SIDE` uses nalgebra's Golub–Kahan bidiagonalisation with
//! implicit-shift QR sweeps (Alg. 8.6.2); smaller ones never reach this module (see
//! `crate::jacobi`). Caveat: nalgebra's SVD can return wrong singular values when vectors
//! are requested (nalgebra issue #1172, e.g. the all-ones 3 × 5 matrix), which is one more
//! reason the small sizes take the Jacobi path.

use crate::Real;
use crate::blas::Uplo;
use nalgebra::{DMatrix, linalg::SymmetricEigen};

/// Iteration budget handed to nalgebra's iterative decompositions: QR sweeps need O(n) steps
/// in practice; the cap only guards against an endless loop on pathological input.
fn iteration_cap(n: usize) -> usize {
    1000 + 100 * n
}

/// `d > 0`, false for NaN (a NaN pivot is reported as a failure, like a non-positive one).
fn is_positive<T: Real>(d: T) -> bool {
    d.partial_cmp(&T::zero()) == Some(std::cmp::Ordering::Greater)
}

/// Cholesky factorisation of the `uplo` triangle of the `n × n` matrix in `a` (xPOTRF):
/// `A = L Lᵀ` (lower) or `A = Uᵀ U` (upper), the factor overwriting that triangle.
///
/// Returns `info`: 0 on success, `j ≥ 1` if the leading minor of order `j` is not positive
/// definite (the factorisation stops there, as in LAPACK). The other triangle is not touched.
pub(crate) fn potrf<T: Real>(uplo: Uplo, n: usize, a: &mut [T], lda: usize) -> i32 {
    let mut col = vec![T::zero(); n];
    for j in 0..n {
        match uplo {
            Uplo::Lower => {
                // v = A(j.., j) − L(j.., 0..j) L(j, 0..j)ᵀ, accumulated column by column.
                let v = &mut col[j..n];
                for (t, i) in v.iter_mut().zip(j..n) {
                    *t = a[i + j * lda];
                }
                for p in 0..j {
                    let ljp = a[j + p * lda];
                    if ljp != T::zero() {
                        for (t, i) in v.iter_mut().zip(j..n) {
                            *t -= a[i + p * lda] * ljp;
                        }
                    }
                }
                let d = v[0];
                if !is_positive(d) {
                    a[j + j * lda] = d;
                    return (j + 1) as i32;
                }
                let ljj = d.sqrt();
                a[j + j * lda] = ljj;
                for (t, i) in v.iter().zip(j..n).skip(1) {
                    a[i + j * lda] = *t / ljj;
                }
            }
            Uplo::Upper => {
                // U(j, i) = (A(j, i) − U(0..j, j)ᵀ U(0..j, i)) / U(j, j) for i ≥ j.
                col[..j].copy_from_slice(&a[j * lda..j * lda + j]);
                let uj = &col[..j];
                let dot = |a: &[T], i: usize| -> T {
                    let ui = &a[i * lda..i * lda + j];
                    ui.iter().zip(uj).fold(T::zero(), |s, (p, q)| s + *p * *q)
                };
                let d = a[j + j * lda] - dot(a, j);
                if !is_positive(d) {
                    a[j + j * lda] = d;
                    return (j + 1) as i32;
                }
                let ujj = d.sqrt();
                a[j + j * lda] = ujj;
                for i in j + 1..n {
                    let s = a[j + i * lda] - dot(a, i);
                    a[j + i * lda] = s / ujj;
                }
            }
        }
    }
    0
}

/// Solves `A X = B` with the Cholesky factor from [`potrf`] (xPOTRS); `B` (`n × nrhs`) is
/// overwritten by `X`. Only the `uplo` triangle of `a` is read.
pub(crate) fn potrs<T: Real>(
    uplo: Uplo,
    (n, nrhs): (usize, usize),
    (a, lda): (&[T], usize),
    (b, ldb): (&mut [T], usize),
) {
    for r in 0..nrhs {
        let x = &mut b[r * ldb..r * ldb + n];
        match uplo {
            Uplo::Lower => {
                // L y = b (forward, column-oriented), then Lᵀ x = y (backward, dot products).
                for j in 0..n {
                    x[j] /= a[j + j * lda];
                    let xj = x[j];
                    for i in j + 1..n {
                        x[i] -= a[i + j * lda] * xj;
                    }
                }
                for j in (0..n).rev() {
                    let mut s = x[j];
                    for i in j + 1..n {
                        s -= a[i + j * lda] * x[i];
                    }
                    x[j] = s / a[j + j * lda];
                }
            }
            Uplo::Upper => {
                // Uᵀ y = b (forward, dot products with columns of U), then U x = y (backward).
                for j in 0..n {
                    let mut s = x[j];
                    for i in 0..j {
                        s -= a[i + j * lda] * x[i];
                    }
                    x[j] = s / a[j + j * lda];
                }
                for j in (0..n).rev() {
                    x[j] /= a[j + j * lda];
                    let xj = x[j];
                    for i in 0..j {
                        x[i] -= a[i + j * lda] * xj;
                    }
                }
            }
        }
    }
}

/// Copies the `uplo` triangle of a column-major `n × n` array into a full symmetric matrix.
fn symmetric_from_triangle<T: Real>(uplo: Uplo, n: usize, a: &[T], lda: usize) -> DMatrix<T> {
    let mut m = DMatrix::zeros(n, n);
    for j in 0..n {
        let rows = match uplo {
            Uplo::Upper => 0..j + 1,
            Uplo::Lower => j..n,
        };
        for i in rows {
            let v = a[i + j * lda];
            m[(i, j)] = v;
            m[(j, i)] = v;
        }
    }
    m
}

/// Which eigenvalues `syevr` returns (LAPACK's `RANGE`).
#[derive(Debug, Clone, Copy)]
pub(crate) enum EigRange<T> {
    /// `'A'`: all of them.
    All,
    /// `'V'`: those in the half-open interval `(vl, vu]`.
    Values(T, T),
    /// `'I'`: the `il`-th through `iu`-th smallest (1-based, inclusive).
    Indices(usize, usize),
}

/// Output of [`syevr`]: the selected eigenvalues (ascending) and, when requested, their
/// orthonormal eigenvectors as the columns of `vectors` (`n × m`).
pub(crate) struct SymEig<T: Real> {
    pub(crate) values: Vec<T>,
    pub(crate) vectors: Option<DMatrix<T>>,
}

/// Eigenvalues (ascending) and optionally eigenvectors of the symmetric matrix given by its
/// `uplo` triangle (xSYEVR). `None` if the input is not finite or the QR iteration did not
/// converge (LAPACK's `INFO > 0`).
pub(crate) fn syevr<T: Real>(
    want_vectors: bool,
    range: EigRange<T>,
    uplo: Uplo,
    n: usize,
    (a, lda): (&[T], usize),
) -> Option<SymEig<T>> {
    let m = symmetric_from_triangle(uplo, n, a, lda);
    if m.iter().any(|v| !v.is_finite()) {
        return None;
    }
    // Eigenvalues only: nalgebra's value-only path skips accumulating the rotations (the
    // input is finite, on which the implicit symmetric QR iteration always converges).
    let (vals, vecs) = if want_vectors {
        let eig = SymmetricEigen::try_new(m, T::default_epsilon(), iteration_cap(n))?;
        (eig.eigenvalues, Some(eig.eigenvectors))
    } else {
        (m.symmetric_eigenvalues(), None)
    };
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| {
        vals[i]
            .partial_cmp(&vals[j])
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let selected: Vec<usize> = match range {
        EigRange::All => order,
        EigRange::Values(vl, vu) => order
            .into_iter()
            .filter(|&i| vals[i] > vl && vals[i] <= vu)
            .collect(),
        EigRange::Indices(il, iu) => order[il - 1..iu].to_vec(),
    };
    let values = selected.iter().map(|&i| vals[i]).collect();
    let vectors = vecs.map(|v| DMatrix::from_fn(n, selected.len(), |r, c| v[(r, selected[c])]));
    Some(SymEig { values, vectors })
}

/// Thin singular value decomposition `A = U diag(s) Vᵀ` of an `m × n` matrix (`m, n ≥ 1`):
/// `s` descending (length `min(m, n)`), `U` is `m × min(m, n)`, `Vᵀ` is `min(m, n) × n`.
/// `None` if the input is not finite or the iteration did not converge.
pub(crate) struct Svd<T: Real> {
    pub(crate) s: Vec<T>,
    pub(crate) u: Option<DMatrix<T>>,
    pub(crate) vt: Option<DMatrix<T>>,
}

/// See [`Svd`]. `full_u`/`full_vt` extend `U` to `m × m` / `Vᵀ` to `n × n` with an
/// orthonormal basis of the complement (LAPACK's `'A'` jobs).
pub(crate) fn svd<T: Real>(
    (m, n): (usize, usize),
    (a, lda): (&[T], usize),
    (want_u, full_u): (bool, bool),
    (want_vt, full_vt): (bool, bool),
) -> Option<Svd<T>> {
    let mat = DMatrix::from_fn(m, n, |i, j| a[i + j * lda]);
    if mat.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let eps = T::default_epsilon() * nalgebra::convert(5.0);
    let dec = nalgebra::linalg::SVD::try_new(mat, want_u, want_vt, eps, iteration_cap(m.max(n)))?;
    // `try_new` sorts in descending order; a NaN-free input keeps that order exact.
    let s: Vec<T> = dec.singular_values.iter().copied().collect();
    let u = dec
        .u
        .map(|u| if full_u { complete_orthonormal(u) } else { u });
    let vt = dec.v_t.map(|vt| {
        if full_vt {
            complete_orthonormal(vt.transpose()).transpose()
        } else {
            vt
        }
    });
    Some(Svd { s, u, vt })
}

/// Extends the orthonormal columns of `q` (`m × k`, `k ≤ m`) to an `m × m` orthogonal matrix:
/// the Householder QR of `q` gives `q = H diag(±1) [I; 0]`, so the last `m − k` columns of the
/// full `H` span the orthogonal complement.
fn complete_orthonormal<T: Real>(q: DMatrix<T>) -> DMatrix<T> {
    let (m, k) = q.shape();
    if k >= m {
        return q;
    }
    let qr = q.clone().qr();
    let mut h = DMatrix::<T>::identity(m, m);
    qr.q_tr_mul(&mut h); // h = Hᵀ
    let h = h.transpose();
    let mut full = DMatrix::zeros(m, m);
    full.columns_mut(0, k).copy_from(&q);
    full.columns_mut(k, m - k).copy_from(&h.columns(k, m - k));
    full
}

/// LU factorisation with partial pivoting of the `n × n` matrix in `a` followed by the solve
/// of `A X = B` for the `nrhs` columns of `b` (xGESV).
///
/// On return `a` holds `L` (unit lower, below the diagonal) and `U`, `ipiv` the 1-based row
/// interchanges (row `j` was swapped with row `ipiv[j]`). Returns `info`: 0 on success,
/// `j ≥ 1` if `U(j, j)` is exactly zero, in which case the factorisation is complete but no
/// solution is computed.
pub(crate) fn gesv<T: Real>(
    (n, nrhs): (usize, usize),
    (a, lda): (&mut [T], usize),
    ipiv: &mut [i32],
    (b, ldb): (&mut [T], usize),
) -> i32 {
    let mut info = 0;
    for j in 0..n {
        // Pivot: the first entry of largest magnitude on or below the diagonal.
        let mut p = j;
        let mut best = a[j + j * lda].abs();
        for i in j + 1..n {
            let v = a[i + j * lda].abs();
            if v > best {
                best = v;
                p = i;
            }
        }
        ipiv[j] = (p + 1) as i32;
        if a[p + j * lda] != T::zero() {
            if p != j {
                for c in 0..n {
                    a.swap(j + c * lda, p + c * lda);
                }
            }
            let piv = a[j + j * lda];
            for i in j + 1..n {
                a[i + j * lda] /= piv;
            }
        } else if info == 0 {
            info = (j + 1) as i32;
        }
        // Rank-one update of the trailing block.
        for c in j + 1..n {
            let t = a[j + c * lda];
            if t != T::zero() {
                for i in j + 1..n {
                    let l = a[i + j * lda];
                    a[i + c * lda] -= l * t;
                }
            }
        }
    }
    if info != 0 {
        return info;
    }
    for r in 0..nrhs {
        let x = &mut b[r * ldb..r * ldb + n];
        for j in 0..n {
            let p = (ipiv[j] - 1) as usize;
            x.swap(j, p);
        }
        for j in 0..n {
            let xj = x[j];
            for i in j + 1..n {
                x[i] -= a[i + j * lda] * xj;
            }
        }
        for j in (0..n).rev() {
            x[j] /= a[j + j * lda];
            let xj = x[j];
            for i in 0..j {
                x[i] -= a[i + j * lda] * xj;
            }
        }
    }
    0
}

/// Eigenvalues only of the symmetric matrix given by its `uplo` triangle (xSYEVR with
/// `JOBZ = 'N'`), without allocating: the selected eigenvalues go ascending into `w` and
/// their number is returned; `None` if the input is not finite or the iteration did not
/// converge (LAPACK's `INFO > 0`). For `n ≤ 16` the `uplo` triangle of `a` is only read
/// (the reduction runs on a copy); for larger `n` it is destroyed, as in LAPACK (it holds the
/// Householder reduction). The other triangle is neither read nor written. `work` needs
/// `3n` entries.
///
/// Algorithm: Householder reduction to tridiagonal form (Golub & Van Loan, *Matrix
/// Computations*, 4th ed., Alg. 8.3.1, the rank-2 update `A ← A − v wᵀ − w vᵀ` of LAPACK's
/// `xSYTD2`; on a full symmetric copy on the stack for `n ≤ 16`, on the stored triangle
/// otherwise), then implicit symmetric QR steps with the Wilkinson shift on the
/// tridiagonal matrix (Alg. 8.3.2) in the root-free Pal–Walker–Kahan form of LAPACK's
/// `xSTERF`, deflating where `|e_i| ≤ ε (|d_i| + |d_{i+1}|)`. Both stages are backward
/// stable: the eigenvalues are exact for a matrix within `O(ε)‖A‖`.
pub(crate) fn syevr_values<T: Real>(
    range: EigRange<T>,
    uplo: Uplo,
    n: usize,
    (a, lda): (&mut [T], usize),
    w: &mut [T],
    work: &mut [T],
) -> Option<usize> {
    let (d, rest) = work[..3 * n].split_at_mut(n);
    let (e, v) = rest.split_at_mut(n);
    // Small matrices (Clarabel's PSD step lengths): a full symmetric copy on the stack with
    // a compile-time side, where the Householder steps run on contiguous columns.
    macro_rules! dispatch {
        ($($size:literal)*) => {
            match n {
                $($size => tridiagonalise_small::<T, $size>(uplo, (&*a, lda), d, e),)*
                _ => tridiagonalise_packed(uplo, n, (a, lda), (d, e, v)),
            }
        };
    }
    if !dispatch!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16) {
        return None;
    }
    if !tridiagonal_eigenvalues(&mut d[..n], &mut e[..n], iteration_cap(n)) {
        return None;
    }
    // Insertion sort (n is small; no allocation).
    for i in 1..n {
        let x = d[i];
        let mut j = i;
        while j > 0 && d[j - 1] > x {
            d[j] = d[j - 1];
            j -= 1;
        }
        d[j] = x;
    }
    let mut found = 0;
    for (i, &x) in d[..n].iter().enumerate() {
        let keep = match range {
            EigRange::All => true,
            EigRange::Values(vl, vu) => x > vl && x <= vu,
            EigRange::Indices(il, iu) => i + 1 >= il && i < iu,
        };
        if keep {
            w[found] = x;
            found += 1;
        }
    }
    Some(found)
}

/// Householder tridiagonalisation of the symmetric matrix given by its `uplo` triangle, in
/// place on that triangle (Golub & Van Loan, Alg. 8.3.1, the rank-2 update
/// `A ← A − v wᵀ − w vᵀ` of LAPACK's `xSYTD2`): the diagonal into `d`, the off-diagonal into
/// `e[..n−1]` (`e[n−1] = 0`); `v` is scratch of length `n`. False if an entry of the
/// triangle is not finite.
fn tridiagonalise_packed<T: Real>(
    uplo: Uplo,
    n: usize,
    (a, lda): (&mut [T], usize),
    (d, e, v): (&mut [T], &mut [T], &mut [T]),
) -> bool {
    // Element (i, j), i ≥ j, of the symmetric matrix in the stored triangle.
    let at = |i: usize, j: usize| match uplo {
        Uplo::Lower => i + j * lda,
        Uplo::Upper => j + i * lda,
    };
    for j in 0..n {
        for i in j..n {
            if !a[at(i, j)].is_finite() {
                return false;
            }
        }
    }
    let half: T = nalgebra::convert(0.5);
    // Householder tridiagonalisation: step k annihilates A(k+2.., k).
    for k in 0..n.saturating_sub(2) {
        let m = n - k - 1;
        let x0 = a[at(k + 1, k)];
        let scale = (k + 1..n).fold(T::zero(), |s, i| s.max(a[at(i, k)].abs()));
        let tail = (k + 2..n).fold(T::zero(), |s, i| {
            let t = a[at(i, k)] / scale;
            s + t * t
        });
        if scale == T::zero() || tail == T::zero() {
            e[k] = x0;
            continue;
        }
        let xs = x0 / scale;
        let norm = (xs * xs + tail).sqrt() * scale;
        // H x = σ e₁ with H = I − β v vᵀ, v = x − σ e₁, vᵀv = 2σ(σ − x₀).
        let sigma = if x0 > T::zero() { -norm } else { norm };
        v[0] = x0 - sigma;
        for i in 1..m {
            v[i] = a[at(k + 1 + i, k)];
        }
        let beta = T::one() / (sigma * (sigma - x0));
        // p = β B v for the trailing block B = A(k+1.., k+1..) (stored triangle only).
        let p = &mut d[..m];
        p.iter_mut().for_each(|x| *x = T::zero());
        for j in 0..m {
            let bjj = a[at(k + 1 + j, k + 1 + j)];
            let mut s = bjj * v[j];
            for i in j + 1..m {
                let bij = a[at(k + 1 + i, k + 1 + j)];
                s += bij * v[i];
                p[i] += bij * v[j];
            }
            p[j] += s;
        }
        let mut pv = T::zero();
        for i in 0..m {
            p[i] *= beta;
            pv += p[i] * v[i];
        }
        // w = p − (β pᵀv / 2) v, B ← B − v wᵀ − w vᵀ.
        let kk = half * beta * pv;
        for i in 0..m {
            p[i] -= kk * v[i];
        }
        for j in 0..m {
            for i in j..m {
                let idx = at(k + 1 + i, k + 1 + j);
                a[idx] -= v[i] * p[j] + p[i] * v[j];
            }
        }
        e[k] = sigma;
    }
    for k in 0..n {
        d[k] = a[at(k, k)];
    }
    if n >= 2 {
        e[n - 2] = a[at(n - 1, n - 2)];
    }
    if n > 0 {
        e[n - 1] = T::zero();
    }
    true
}

/// [`tridiagonalise_packed`] for `n = R` on a full symmetric copy `F` on the stack (the
/// caller's triangle is only read): step `k` forms `v`, `β` with `(I − β v vᵀ) x = σ e₁` for
/// `x = F(k+1.., k)`, then `p = β F₂₂ v`, `w = p − (β pᵀv / 2) v` and
/// `F₂₂ ← F₂₂ − v wᵀ − w vᵀ`, column by column on contiguous memory.
fn tridiagonalise_small<T: Real, const R: usize>(
    uplo: Uplo,
    (a, lda): (&[T], usize),
    d: &mut [T],
    e: &mut [T],
) -> bool {
    let mut f = [[T::zero(); R]; R];
    for j in 0..R {
        let rows = match uplo {
            Uplo::Upper => 0..j + 1,
            Uplo::Lower => j..R,
        };
        for i in rows {
            let x = a[i + j * lda];
            if !x.is_finite() {
                return false;
            }
            f[j][i] = x;
            f[i][j] = x;
        }
    }
    let half: T = nalgebra::convert(0.5);
    for k in 0..R.saturating_sub(2) {
        let (head, tail) = f.split_at_mut(k + 1);
        let x = &head[k][k + 1..];
        let x0 = x[0];
        let scale = x.iter().fold(T::zero(), |s, xi| s.max(xi.abs()));
        if scale == T::zero() {
            e[k] = x0;
            continue;
        }
        let inv = T::one() / scale;
        let tail_sq = x[1..].iter().fold(T::zero(), |s, xi| {
            let t = *xi * inv;
            s + t * t
        });
        if tail_sq == T::zero() {
            e[k] = x0;
            continue;
        }
        let xs = x0 * inv;
        let norm = (xs * xs + tail_sq).sqrt() * scale;
        // H x = σ e₁ with H = I − β v vᵀ, v = x − σ e₁, vᵀv = 2σ(σ − x₀). `v` and `p` keep
        // all R entries, zero above row k + 1, so that every loop below has the fixed length
        // R (unrolled and vectorised); the zeros leave rows ≤ k of F untouched.
        let sigma = if x0 > T::zero() { -norm } else { norm };
        let mut v = [T::zero(); R];
        v[k + 1..].copy_from_slice(x);
        v[k + 1] = x0 - sigma;
        let beta = T::one() / (sigma * (sigma - x0));
        // p = β B v, B = F(k+1.., k+1..), as Σ_j v_j F(:, j).
        let mut p = [T::zero(); R];
        for (col, &vj) in tail.iter().zip(&v[k + 1..]) {
            for i in 0..R {
                p[i] += col[i] * vj;
            }
        }
        // Rows ≤ k of p come from the rows of F above the trailing block: not part of B v.
        p[..=k].iter_mut().for_each(|x| *x = T::zero());
        let mut pv = T::zero();
        for i in 0..R {
            p[i] *= beta;
            pv += p[i] * v[i];
        }
        let kk = half * beta * pv;
        for i in 0..R {
            p[i] -= kk * v[i];
        }
        for (col, (&vj, &wj)) in tail.iter_mut().zip(v[k + 1..].iter().zip(&p[k + 1..])) {
            for i in 0..R {
                col[i] -= v[i] * wj + p[i] * vj;
            }
        }
        e[k] = sigma;
    }
    for k in 0..R {
        d[k] = f[k][k];
    }
    if R >= 2 {
        e[R - 2] = f[R - 2][R - 1];
    }
    if R > 0 {
        e[R - 1] = T::zero();
    }
    true
}

/// `√(x² + y²)`: the plain formula where it neither overflows nor underflows (the common
/// case, several times cheaper than the C library's `hypot`), `hypot` otherwise.
#[inline]
fn fast_hypot<T: Real>(x: T, y: T) -> T {
    let s = x * x + y * y;
    // Below MIN_POSITIVE/ε (≈ 1e-292 in f64) the squares lose precision to gradual
    // underflow; an overflow shows as a non-finite sum.
    if s.is_finite() && s >= T::MIN_POSITIVE / T::default_epsilon() {
        s.sqrt()
    } else {
        x.hypot(y)
    }
}

/// Eigenvalues of the symmetric tridiagonal matrix with diagonal `d` and off-diagonal
/// `e[..n−1]` (`e[n−1]` is scratch), overwriting `d` (unordered; `e` is destroyed): implicit
/// QR steps with the Wilkinson shift on the trailing unreduced block, in the root-free form
/// of Pal, Walker and Kahan (B. N. Parlett, *The Symmetric Eigenvalue Problem*, SIAM 1998,
/// ch. 8; the QR branch of LAPACK's `xSTERF`), which carries the squares `e_i²` and needs no
/// square root inside the bulge chase (unlike the Givens form of Golub & Van Loan
/// Alg. 8.3.2). Off-diagonals with
/// `e_i² ≤ ε² (|d_i| + |d_{i+1}|)²` are deflated. A matrix whose largest entry lies outside
/// `Real::square_safe_range` is first scaled by it, so that the squares neither overflow nor
/// underflow harmfully. False if `cap` sweeps did not suffice.
fn tridiagonal_eigenvalues<T: Real>(d: &mut [T], e: &mut [T], cap: usize) -> bool {
    let n = d.len();
    if n < 2 {
        return true;
    }
    let e = &mut e[..n - 1];
    let amax = d
        .iter()
        .chain(e.iter())
        .fold(T::zero(), |m, x| m.max(x.abs()));
    if amax == T::zero() {
        return true;
    }
    let (small, big) = T::square_safe_range();
    let scale = if amax > big || amax < small {
        amax
    } else {
        T::one()
    };
    if scale != T::one() {
        d.iter_mut().for_each(|x| *x /= scale);
        e.iter_mut().for_each(|x| *x /= scale);
    }
    e.iter_mut().for_each(|x| *x = *x * *x);
    let eps = T::default_epsilon();
    let eps2 = eps * eps;
    let two: T = nalgebra::convert(2.0);
    let negligible = |e2: T, a: T, b: T| {
        let s = a.abs() + b.abs();
        e2 <= eps2 * s * s
    };
    let mut hi = n - 1;
    let mut sweeps = 0;
    loop {
        // Deflate at the bottom, then find the top `lo` of the unreduced block lo..=hi.
        while hi > 0 && negligible(e[hi - 1], d[hi - 1], d[hi]) {
            hi -= 1;
        }
        if hi == 0 {
            break;
        }
        let mut lo = hi - 1;
        while lo > 0 && !negligible(e[lo - 1], d[lo - 1], d[lo]) {
            lo -= 1;
        }
        sweeps += 1;
        if sweeps > cap {
            return false;
        }
        // Wilkinson shift: the eigenvalue of the trailing 2 × 2 closer to d[hi].
        let rte = e[hi - 1].sqrt();
        let delta = (d[hi - 1] - d[hi]) / (two * rte);
        let r = fast_hypot(delta, T::one());
        let sigma = d[hi]
            - rte
                / if delta >= T::zero() {
                    delta + r
                } else {
                    delta - r
                };
        // Root-free chase: c = cos², s = sin² of the implicit rotations.
        let (mut c, mut s) = (T::one(), T::zero());
        let mut gamma = d[lo] - sigma;
        let mut p = gamma * gamma;
        for i in lo..hi {
            let bb = e[i];
            let r = p + bb;
            if i > lo {
                e[i - 1] = s * r;
            }
            let old_c = c;
            c = p / r;
            s = bb / r;
            let old_gamma = gamma;
            let alpha = d[i + 1];
            gamma = c * (alpha - sigma) - s * old_gamma;
            d[i] = old_gamma + (alpha - gamma);
            p = if c != T::zero() {
                gamma * gamma / c
            } else {
                old_c * bb
            };
        }
        e[hi - 1] = s * p;
        d[hi] = sigma + gamma;
    }
    if scale != T::one() {
        d.iter_mut().for_each(|x| *x *= scale);
    }
    true
}
