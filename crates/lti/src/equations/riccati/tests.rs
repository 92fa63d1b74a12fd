use super::*;

use crate::linalg::symmetrize;
use crate::linalg::testing::splitmix_matrix as test_matrix;

#[test]
fn newton_step_from_schur_data_solves_the_kleinman_equation() {
    for (n, seed) in [(1, 1), (7, 2), (40, 3), (90, 4)] {
        // A stable closed loop A_K = U₁ T₁₁ U₁⁻¹ with T₁₁ quasi-triangular in standard
        // form (real Schur form of a shifted random matrix, so complex pairs occur) and a
        // well-conditioned non-orthogonal U₁.
        let m = test_matrix(n, n, seed);
        let shift = 1.0
            + crate::linalg::eigenvalues(&m)
                .unwrap()
                .iter()
                .map(|l| l.re)
                .fold(f64::NEG_INFINITY, f64::max);
        let stable = &m - Mat::identity(n, n) * shift;
        let t11 = crate::linalg::schur::real_schur(&stable)
            .unwrap()
            .t()
            .clone();
        let u1 = Mat::identity(n, n) + test_matrix(n, n, seed + 100) * (0.5 / n as f64);
        let lu = crate::linalg::dense::Lu::new(&u1);
        let ak = &u1 * &t11 * lu.inverse();
        let res = symmetrize(&test_matrix(n, n, seed + 200));
        let hint = ClosedLoopSchur { u1, lu, t11 };
        let d = hint.newton_step(&res).unwrap();
        // Defining residual of A_Kᵀ Δ + Δ A_K + Res = 0, relative to its terms. A
        // backward-stable Bartels–Stewart solve gives O(n ε); the transformation with U₁
        // (cond ≤ 3 here) and the flip add small factors: 100·n·ε is generous.
        let atd = ak.transpose() * &d;
        let dak = &d * &ak;
        let r = (&atd + &dak + &res).norm() / (atd.norm() + dak.norm() + res.norm());
        assert!(
            r <= 100.0 * n as f64 * f64::EPSILON,
            "n = {n}: residual {r:e}"
        );
        // The exact step through a new Schur decomposition of A_Kᵀ (an independent
        // algorithm) agrees to the conditioning of the Lyapunov operator times ε (observed
        // ≤ 1e-14 relative; 1e-12 leaves a factor 100).
        let exact = crate::equations::lyap(&ak.transpose(), &res).unwrap().x;
        let diff = (&d - &exact).norm() / exact.norm();
        assert!(
            diff <= 1e-12,
            "n = {n}: differs from the exact step by {diff:e}"
        );
    }
}
