//! Singular value decomposition with singular vectors, checked.
//!
//! nalgebra's SVD (Golub–Kahan bidiagonalisation and implicit QR) can return wrong singular
//! values once singular vectors are requested, while the vectors stay orthonormal — so the
//! product `UΣVᴴ` no longer reproduces the matrix (nalgebra issue #1172: e.g. every all-ones
//! matrix of some shapes, such as 5 × 3 or 3 × 5, and a few full-rank integer matrices).
//! [`svd`] therefore checks nalgebra's result by its defining residual and, when that fails,
//! computes the decomposition by the one-sided Jacobi method instead (the workspace's one
//! kernel, [`crate::linalg::jacobi`]: Hestenes 1958, with the stopping rule of Demmel &
//! Veselić, "Jacobi's method is more accurate than QR", SIAM J. Matrix Anal. Appl. 13, 1992),
//! which is slower but has no such failure mode and computes every singular value to high
//! relative accuracy.

use nalgebra::{ComplexField, DMatrix, DVector};

use crate::linalg::jacobi::one_sided_jacobi;

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
/// (module documentation). Non-finite input gives NaN factors (callers check their data
/// first).
pub fn svd<T: ComplexField<RealField = f64> + Copy>(m: &DMatrix<T>) -> Svd<T> {
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
        // nalgebra's iteration has no iteration limit by default; the Jacobi kernel rejects
        // the input at once.
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

/// One-sided Jacobi SVD by the workspace's kernel ([`one_sided_jacobi`]) on heap columns:
/// the kernel runs on `M` (`m ≥ n`) or `Mᴴ` (`m < n`, then `M = V̄ Σ Ūᴴ`). NaN factors if an
/// entry is not finite or the sweeps did not converge.
fn jacobi<T: ComplexField<RealField = f64> + Copy>(m: &DMatrix<T>) -> Svd<T> {
    let (rows, cols) = m.shape();
    let transposed = rows < cols;
    let w_mat = if transposed { m.adjoint() } else { m.clone() };
    let (r, k) = w_mat.shape();
    let mut w: Vec<Vec<T>> = w_mat
        .column_iter()
        .map(|c| c.iter().copied().collect())
        .collect();
    let mut v = vec![vec![T::zero(); k]; k];
    let mut s = vec![0.0; k];
    if !one_sided_jacobi(&mut w, Some(&mut v), &mut s, k) {
        let nan = T::from_real(f64::NAN);
        return Svd {
            u: DMatrix::from_element(rows, k, nan),
            singular_values: DVector::from_element(k, f64::NAN),
            v_t: DMatrix::from_element(k, cols, nan),
        };
    }
    // W = Ū Σ V̄ᴴ with Ū = [w_j] (r × k), V̄ = [v_j] (k × k).
    let u_bar = DMatrix::from_fn(r, k, |i, j| w[j][i]);
    let v_bar = DMatrix::from_fn(k, k, |i, j| v[j][i]);
    let (u, v_t) = if transposed {
        (v_bar, u_bar.adjoint())
    } else {
        (u_bar, v_bar.adjoint())
    };
    Svd {
        u,
        singular_values: DVector::from_vec(s),
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
