//! A diagonal state scaling for LQ-type LMIs, from an estimate of the optimal `X = P⁻¹`.
//!
//! The LMI LQ problem's optimum is `X* = P⁻¹`, `P` the stabilising solution of the CARE
//! `AᵀP + PA − P B R⁻¹ Bᵀ P + Q = 0`. Solving the LMIs in coordinates where `X*` has unit
//! diagonal halves the interior-point iterations on the book's servo (26 → 13). Only a rough
//! estimate is needed, so it is computed here with the matrix sign function of the
//! Hamiltonian (Roberts 1971; determinant scaling after Byers, "Solving the algebraic
//! Riccati equation with the matrix sign function", Linear Algebra Appl. 85, 1987):
//! `sign(H)` annihilates the stable invariant subspace `span[I; P]`, so
//! `[W₁₂; W₂₂ + I] P = −[W₁₁ + I; W₂₁]`. Any failure (no convergence, a singular iterate,
//! `P` not positive definite) simply means "no scaling".

use pendulab_lti::Mat;

/// `t_i = √X_ii` with `X = P⁻¹` estimated as above, or None.
pub(crate) fn lq_scaling(a: &Mat, b: &Mat, q: &Mat, r: &Mat) -> Option<Vec<f64>> {
    let n = a.nrows();
    let rinv = r.clone().try_inverse()?;
    let g = b * rinv * b.transpose();
    let mut z = Mat::zeros(2 * n, 2 * n);
    z.view_mut((0, 0), (n, n)).copy_from(a);
    z.view_mut((0, n), (n, n)).copy_from(&(-&g));
    z.view_mut((n, 0), (n, n)).copy_from(&(-q));
    z.view_mut((n, n), (n, n)).copy_from(&(-a.transpose()));
    let mut converged = false;
    for _ in 0..100 {
        let lu = z.clone().lu();
        let det = lu.determinant();
        if !(det.is_finite() && det != 0.0) {
            return None;
        }
        let c = det.abs().powf(-1.0 / (2 * n) as f64);
        let zinv = lu.try_inverse()?;
        let next = (&z * c + zinv / c) * 0.5;
        let diff = (&next - &z).norm();
        z = next;
        if !z.iter().all(|v| v.is_finite()) {
            return None;
        }
        if diff <= 1e-10 * z.norm() {
            converged = true;
            break;
        }
    }
    if !converged {
        return None;
    }
    let id = Mat::identity(n, n);
    let mut lhs = Mat::zeros(2 * n, n);
    lhs.view_mut((0, 0), (n, n))
        .copy_from(&z.view((0, n), (n, n)));
    lhs.view_mut((n, 0), (n, n))
        .copy_from(&(z.view((n, n), (n, n)) + &id));
    let mut rhs = Mat::zeros(2 * n, n);
    rhs.view_mut((0, 0), (n, n))
        .copy_from(&(-(z.view((0, 0), (n, n)) + &id)));
    rhs.view_mut((n, 0), (n, n))
        .copy_from(&(-z.view((n, 0), (n, n))));
    let p = pendulab_lti::linalg::svd::svd(&lhs).solve(&rhs, 1e-12);
    let p = (&p + p.transpose()) * 0.5;
    let x = p.cholesky()?.inverse();
    let t: Vec<f64> = (0..n).map(|i| x[(i, i)].sqrt()).collect();
    t.iter().all(|v| v.is_finite() && *v > 0.0).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The estimate reproduces SciPy's Riccati solution of the book's arm servo
    /// (fixture written by tools/reference/lmi_reference.py) to 1e-8 relative: the sign
    /// iteration converges quadratically to 1e-10 and the least-squares solve is well
    /// conditioned here.
    #[test]
    fn estimate_matches_scipy_riccati_solution() {
        let f: serde_json::Value =
            serde_json::from_str(include_str!("../../tests/fixtures/lmi_reference.json")).unwrap();
        let p: Vec<Vec<f64>> = serde_json::from_value(f["p2c122_lq"]["P_riccati"].clone()).unwrap();
        let p = Mat::from_fn(5, 5, |i, j| p[i][j]);
        let x = p.try_inverse().unwrap();
        // The plant: the book's arm pendulum at θ1e = 0 (pendulab-testkit), servo-augmented
        // with ∫(r − θ1) (book eq. 6.40).
        let (a4, b4) = pendulab_testkit::arm::ArmParams::book().linearization(0.0);
        let c = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
        let plant = pendulab_lti::StateSpace::continuous(a4, b4, c, Mat::zeros(1, 1)).unwrap();
        let (a, b) = pendulab_lti::design::integral_augmentation(&plant).unwrap();
        let q = Mat::from_diagonal(&pendulab_lti::Vector::from_vec(vec![
            0.1, 1.0, 0.001, 0.001, 4.0,
        ]));
        let r = Mat::from_element(1, 1, 1.0);
        let t = lq_scaling(&a, &b, &q, &r).expect("converges");
        for i in 0..5 {
            let e = (t[i] * t[i] - x[(i, i)]).abs() / x[(i, i)];
            assert!(e < 1e-8, "state {i}: {} vs {}", t[i] * t[i], x[(i, i)]);
        }
        // An unstabilisable pair (B = 0, A unstable) gives no estimate, not a panic.
        assert!(lq_scaling(&a, &Mat::zeros(5, 1), &q, &r).is_none());
    }
}
