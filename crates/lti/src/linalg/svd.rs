//! Singular value decomposition with singular vectors, checked.
//!
//! nalgebra's SVD (Golub–Kahan bidiagonalisation and implicit QR) can return wrong singular
//! values once singular vectors are requested, while the vectors stay orthonormal — so the
//! product `UΣVᴴ` no longer reproduces the matrix (nalgebra issue #1172: e.g. every all-ones
//! matrix of some shapes, such as 5 × 3 or 3 × 5, and a few full-rank integer matrices).
//! [`svd`] therefore checks nalgebra's result by its defining residual and, when that fails,
//! computes the decomposition by the one-sided Jacobi method instead (Hestenes 1958, with
//! the stopping rule of Demmel & Veselić, "Jacobi's method is more accurate than QR", SIAM J.
//! Matrix Anal. Appl. 13, 1992), which is slower but has no such failure mode and computes
//! every singular value to high relative accuracy.

use nalgebra::{ComplexField, DMatrix, DVector};

/// A thin SVD `M = U diag(σ) Vᴴ` of an `m × n` matrix with `k = min(m, n)`: `u` is `m × k` with
/// orthonormal columns, `singular_values` has `k` entries in descending order, `v_t` (`Vᴴ`)
/// is `k × n` with orthonormal rows.
#[derive(Debug, Clone)]
pub struct Svd<T: ComplexField<RealField = f64>> {
    /// `U` (`m × k`).
    pub u: DMatrix<T>,
    /// `σ₁ ≥ … ≥ σ_k ≥ 0`.
    pub singular_values: DVector<f64>,
    /// `Vᴴ` (`k × n`).
    pub v_t: DMatrix<T>,
}

impl<T: ComplexField<RealField = f64>> Svd<T> {
    /// `V Σ⁺ Uᴴ b`: the minimum-norm least-squares solution of `M x = b`, singular values
    /// `≤ eps` (absolute) treated as zero.
    ///
    /// # Panics
    /// Never for matching shapes; `b` must have `m` rows (a programming error otherwise).
    pub fn solve(&self, b: &DMatrix<T>, eps: f64) -> DMatrix<T> {
        let mut w = self.u.adjoint() * b;
        for (i, mut row) in w.row_iter_mut().enumerate() {
            let s = self.singular_values[i];
            if s > eps {
                row.unscale_mut(s);
            } else {
                row.fill(T::zero());
            }
        }
        self.v_t.adjoint() * w
    }

    /// The pseudo-inverse `V Σ⁺ Uᴴ`, singular values `≤ eps` (absolute) treated as zero.
    pub fn pseudo_inverse(&self, eps: f64) -> DMatrix<T> {
        self.solve(&DMatrix::identity(self.u.nrows(), self.u.nrows()), eps)
    }
}

/// Relative residual bound `‖UΣVᴴ − M‖_F ≤ 100·max(m, n)·ε·‖M‖_F` an accepted nalgebra result
/// must meet (a backward-stable SVD achieves `O(max(m, n)·ε)`; Golub & Van Loan §8.6.3).
const ACCEPT: f64 = 100.0;

/// Thin SVD of `m` with singular vectors: nalgebra's when it reproduces `m` (residual within
/// `100·max(m, n)·ε·‖M‖_F`, singular values in descending order), otherwise one-sided Jacobi
/// (module documentation). Non-finite input gives non-finite output after a bounded number
/// of Jacobi sweeps (callers check their data first).
pub fn svd<T: ComplexField<RealField = f64>>(m: &DMatrix<T>) -> Svd<T> {
    let (rows, cols) = m.shape();
    if rows == 0 || cols == 0 {
        let k = rows.min(cols);
        return Svd {
            u: DMatrix::zeros(rows, k),
            singular_values: DVector::zeros(k),
            v_t: DMatrix::zeros(k, cols),
        };
    }
    if !m.iter().all(|v| v.clone().is_finite()) {
        // nalgebra's iteration has no iteration limit by default; Jacobi's sweeps are
        // bounded and carry the NaN through.
        return jacobi(m);
    }
    let norm = m.norm();
    let d = m.clone().svd(true, true);
    if let (Some(u), Some(v_t)) = (d.u, d.v_t) {
        let s = d.singular_values;
        let ordered = s.as_slice().windows(2).all(|w| w[0] >= w[1]);
        let mut us = u.clone();
        for (j, mut c) in us.column_iter_mut().enumerate() {
            c.scale_mut(s[j]);
        }
        let res = (&us * &v_t - m).norm();
        if ordered && res <= ACCEPT * rows.max(cols) as f64 * f64::EPSILON * norm {
            return Svd {
                u,
                singular_values: s,
                v_t,
            };
        }
    }
    jacobi(m)
}

/// One-sided Jacobi SVD (module documentation).
fn jacobi<T: ComplexField<RealField = f64>>(m: &DMatrix<T>) -> Svd<T> {
    let (rows, cols) = m.shape();
    if rows < cols {
        // M = (Mᴴ)ᴴ = (U' Σ V'ᴴ)ᴴ = V' Σ U'ᴴ.
        let t = jacobi(&m.adjoint());
        return Svd {
            u: t.v_t.adjoint(),
            singular_values: t.singular_values,
            v_t: t.u.adjoint(),
        };
    }
    let n = cols;
    let mut a = m.clone();
    let mut v = DMatrix::<T>::identity(n, n);
    let tol = rows as f64 * f64::EPSILON;
    for _sweep in 0..60 {
        let mut rotated = false;
        for p in 0..n {
            for q in p + 1..n {
                let alpha = a.column(p).norm_squared();
                let beta = a.column(q).norm_squared();
                let gamma = a.column(p).dotc(&a.column(q));
                let g = gamma.clone().modulus();
                if g == 0.0 || g <= tol * (alpha * beta).sqrt() {
                    continue;
                }
                rotated = true;
                // Make aₚᴴa_q real and positive by a unit scaling of column q, then rotate
                // in the real plane: ζ = (β − α)/(2|γ|), t = sign(ζ)/(|ζ| + √(1 + ζ²)).
                let phase = gamma.unscale(g).conjugate();
                let zeta = (beta - alpha) / (2.0 * g);
                let t = zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt());
                let c = 1.0 / (1.0 + t * t).sqrt();
                let s = c * t;
                for mat in [&mut a, &mut v] {
                    for i in 0..mat.nrows() {
                        let xp = mat[(i, p)].clone();
                        let xq = mat[(i, q)].clone() * phase.clone();
                        mat[(i, p)] = xp.clone().scale(c) - xq.clone().scale(s);
                        mat[(i, q)] = xp.scale(s) + xq.scale(c);
                    }
                }
            }
        }
        if !rotated {
            break;
        }
    }
    // σⱼ = ‖aⱼ‖, uⱼ = aⱼ/σⱼ; descending order.
    let sig: Vec<f64> = (0..n).map(|j| a.column(j).norm()).collect();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| sig[j].total_cmp(&sig[i]));
    let smax = sig.iter().copied().fold(0.0, f64::max);
    let mut u = DMatrix::<T>::zeros(rows, n);
    let mut v_t = DMatrix::<T>::zeros(n, n);
    let mut s = DVector::<f64>::zeros(n);
    let mut missing = Vec::new();
    for (k, &j) in order.iter().enumerate() {
        s[k] = sig[j];
        v_t.row_mut(k).copy_from(&v.column(j).adjoint());
        if sig[j] > smax * f64::EPSILON * rows as f64 && sig[j] > 0.0 {
            u.set_column(k, &a.column(j).unscale(sig[j]));
        } else {
            missing.push(k);
        }
    }
    // Columns of U for (numerically) zero singular values: complete the orthonormal set from
    // the coordinate vectors by two passes of Gram–Schmidt.
    let mut e = 0;
    for k in missing {
        while e < rows {
            let mut x = DVector::<T>::zeros(rows);
            x[e] = T::one();
            e += 1;
            for _ in 0..2 {
                for j in 0..n {
                    if j == k || u.column(j).norm_squared() == 0.0 {
                        continue;
                    }
                    let proj = u.column(j).dotc(&x);
                    x -= u.column(j) * proj;
                }
            }
            let nx = x.norm();
            if nx > 0.5 {
                u.set_column(k, &x.unscale(nx));
                break;
            }
        }
    }
    Svd {
        u,
        singular_values: s,
        v_t,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::{CMat, Complex64, Mat};

    /// Checks the defining properties: `UΣVᴴ = M`, orthonormal `U` columns and `Vᴴ` rows,
    /// descending non-negative values, and the values against nalgebra's values-only SVD
    /// (which issue #1172 does not affect) by `Σσ² = ‖M‖_F²` and entrywise.
    fn check<T: ComplexField<RealField = f64>>(m: &DMatrix<T>, d: &Svd<T>) {
        let (rows, cols) = m.shape();
        let k = rows.min(cols);
        let tol = 100.0 * rows.max(cols) as f64 * f64::EPSILON;
        assert_eq!(d.u.shape(), (rows, k));
        assert_eq!(d.v_t.shape(), (k, cols));
        let mut us = d.u.clone();
        for (j, mut c) in us.column_iter_mut().enumerate() {
            c.scale_mut(d.singular_values[j]);
        }
        let res = (&us * &d.v_t - m).norm();
        assert!(res <= tol * m.norm(), "{rows}x{cols}: residual {res:e}");
        let ou = (d.u.adjoint() * &d.u - DMatrix::<T>::identity(k, k)).norm();
        let ov = (&d.v_t * d.v_t.adjoint() - DMatrix::<T>::identity(k, k)).norm();
        assert!(
            ou <= tol && ov <= tol,
            "{rows}x{cols}: orthogonality {ou:e} {ov:e}"
        );
        let s = &d.singular_values;
        assert!(s.as_slice().windows(2).all(|w| w[0] >= w[1]) && s.min() >= 0.0);
        let values = m.clone().svd(false, false).singular_values;
        let mut values: Vec<f64> = values.iter().copied().collect();
        values.sort_by(|a, b| b.total_cmp(a));
        for (x, y) in s.iter().zip(&values) {
            // Weyl: both are exact for matrices within O(n ε ‖M‖) of M.
            assert!(
                (x - y).abs() <= tol * m.norm(),
                "{rows}x{cols}: σ {x} vs {y}"
            );
        }
    }

    #[test]
    fn all_ones_matrices_have_their_closed_form() {
        // ‖1 1ᵀ‖: one singular value √(rows·cols), the others zero (closed form); these are
        // the shapes on which nalgebra's SVD with vectors fails (issue #1172).
        for (r, c) in [
            (5, 3),
            (3, 5),
            (16, 2),
            (5, 5),
            (6, 21),
            (2, 2),
            (1, 4),
            (4, 1),
        ] {
            let m = Mat::from_element(r, c, 1.0);
            let d = svd(&m);
            check(&m, &d);
            let s1 = ((r * c) as f64).sqrt();
            assert!((d.singular_values[0] - s1).abs() <= 1e-14 * s1);
            assert!(d.singular_values.iter().skip(1).all(|&x| x <= 1e-14 * s1));
        }
    }

    #[test]
    fn jacobi_matches_the_defining_properties_real_and_complex() {
        let mut st: u64 = 7;
        let mut rnd = move || {
            st = st
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((st >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for (r, c) in [(1, 1), (3, 3), (6, 4), (4, 6), (10, 10), (12, 5)] {
            let m = Mat::from_fn(r, c, |_, _| rnd());
            check(&m, &jacobi(&m));
            check(&m, &svd(&m));
            let z = CMat::from_fn(r, c, |_, _| Complex64::new(rnd(), rnd()));
            check(&z, &jacobi(&z));
            check(&z, &svd(&z));
            // Rank-deficient: the product of thin factors, and a zero matrix.
            let lo = Mat::from_fn(r, 1, |_, _| rnd()) * Mat::from_fn(1, c, |_, _| rnd());
            check(&lo, &jacobi(&lo));
            let zero = Mat::zeros(r, c);
            check(&zero, &jacobi(&zero));
        }
    }

    #[test]
    fn non_finite_input_returns_promptly() {
        let mut m = Mat::from_element(4, 3, 1.0);
        m[(2, 1)] = f64::NAN;
        let d = svd(&m);
        assert!(d.singular_values.iter().any(|v| v.is_nan()));
    }

    #[test]
    fn pseudo_inverse_satisfies_the_penrose_conditions() {
        // Rank 2 in a 5 × 3 matrix (all-ones plus a rank-one term): the four Moore–Penrose
        // conditions define the pseudo-inverse uniquely.
        let m = Mat::from_element(5, 3, 1.0)
            + Mat::from_fn(5, 1, |i, _| i as f64) * Mat::from_row_slice(1, 3, &[1.0, -2.0, 0.5]);
        let d = svd(&m);
        check(&m, &d);
        let p = d.pseudo_inverse(1e-12 * d.singular_values[0]);
        let tol = 1e-12 * m.norm() * p.norm();
        assert!((&m * &p * &m - &m).norm() <= tol * m.norm());
        assert!((&p * &m * &p - &p).norm() <= tol * p.norm());
        let mp = &m * &p;
        let pm = &p * &m;
        assert!((&mp - mp.transpose()).norm() <= tol);
        assert!((&pm - pm.transpose()).norm() <= tol);
    }

    #[test]
    fn graded_matrix_keeps_small_singular_values_accurate() {
        // Q·diag(1, 1e-5, 1e-10, 1e-15) with Q orthogonal (a rotation product): the singular
        // values are exactly the diagonal (closed form); one-sided Jacobi keeps each to a
        // modest relative error (Demmel & Veselić).
        let n = 4;
        let mut q = Mat::identity(n, n);
        for (i, j, th) in [(0, 1, 0.3), (1, 2, -1.1), (2, 3, 0.7), (0, 3, 2.0)] {
            let mut g = Mat::identity(n, n);
            let (s, c) = f64::sin_cos(th);
            g[(i, i)] = c;
            g[(j, j)] = c;
            g[(i, j)] = -s;
            g[(j, i)] = s;
            q = g * q;
        }
        let dvals = [1.0, 1e-5, 1e-10, 1e-15];
        let m = &q * Mat::from_diagonal(&DVector::from_row_slice(&dvals));
        let d = jacobi(&m);
        for (x, y) in d.singular_values.iter().zip(dvals) {
            assert!((x - y).abs() <= 1e-12 * y, "{x} vs {y}");
        }
    }
}
