//! Helpers shared by the Riccati tests: the `care-n4` data (the book's linearised cart
//! pendulum), the cart's LQ servo augmentation, row-major slices of matrices, and the Riccati
//! condition number that sizes the agreement tolerances.
//!
//! Condition number: a solution with relative backward error `η` has relative forward error
//! at most about `κ·η` (first-order perturbation theory; Byers 1985, Sun 1998), with
//! `κ = ‖Ω⁻¹‖·(‖Q‖ + 2‖A‖‖X‖ + ‖G‖‖X‖²)/‖X‖`, `Ω(Z) = A_cᵀZ + ZA_c`, `G = BR⁻¹Bᵀ`, Frobenius
//! norms, `‖Ω⁻¹‖` estimated by power iteration. An estimate of a sensitivity, used only to
//! size tolerances.
#![allow(dead_code)]

use pendulab_lti::Mat;
use pendulab_lti::equations::{RiccatiSolution, dlyap, lyap};

/// The `care-n4` workload: the linearised cart pendulum (book table 3.5, `docs/model.md` §1) as
/// `(A, B, Q, R)` with `Q = diag(100, 10, 1, 1)`, `R = 1`.
pub fn cart_pendulum() -> (Mat, Mat, Mat, Mat) {
    let (ac, bc, mp, lp, jp, mup, g) = (6.25, 4.36, 0.107, 0.230, 1.59e-3, 2.35e-4, 9.81);
    let j = jp + mp * lp * lp;
    #[rustfmt::skip]
    let a = Mat::from_row_slice(4, 4, &[
        0.0, 0.0, 1.0, 0.0,
        0.0, 0.0, 0.0, 1.0,
        0.0, 0.0, -ac, 0.0,
        0.0, mp * g * lp / j, ac * mp * lp / j, -mup / j,
    ]);
    let b = Mat::from_row_slice(4, 1, &[0.0, 0.0, bc, -bc * mp * lp / j]);
    let q = pendulab_lti::linalg::diag(&[100.0, 10.0, 1.0, 1.0]);
    (a, b, q, Mat::identity(1, 1))
}

/// `‖Ω⁻¹‖_F` on symmetric matrices by power iteration on `Ω⁻*Ω⁻¹`, with `Ω⁻¹` applied through
/// the Lyapunov (`continuous`) or Stein solver.
pub fn inverse_operator_norm(ac: &Mat, continuous: bool) -> f64 {
    let n = ac.nrows();
    let solve = |m: &Mat, z: &Mat| -> Mat {
        let r = if continuous {
            lyap(m, &(-z))
        } else {
            dlyap(m, &(-z))
        };
        r.expect("closed-loop operator is invertible").x
    };
    let mut y = Mat::from_fn(n, n, |i, j| 1.0 + ((i * 7 + j * 3) % 5) as f64 * 0.1);
    y = (&y + y.transpose()) * 0.5;
    y /= y.norm();
    let mut est = 0.0;
    for _ in 0..30 {
        // Ω⁻¹ via the transposed closed loop, its adjoint via the closed loop itself.
        let w = solve(&ac.transpose(), &y);
        let z = solve(ac, &w);
        let nz = z.norm();
        let new = nz.sqrt();
        y = z / nz;
        if (new - est).abs() <= 1e-3 * new {
            return new;
        }
        est = new;
    }
    est
}

/// `κ` of the CARE at the solution `sol` (module documentation); `G = BR⁻¹Bᵀ` without the
/// cross term is enough for sizing a tolerance.
pub fn care_condition(a: &Mat, b: &Mat, q: &Mat, r: &Mat, sol: &RiccatiSolution) -> f64 {
    let ac = a - b * &sol.gain;
    let g = b * r.clone().cholesky().unwrap().solve(&b.transpose());
    let xn = sol.x.norm().max(f64::MIN_POSITIVE);
    inverse_operator_norm(&ac, true) * (q.norm() + 2.0 * a.norm() * xn + g.norm() * xn * xn) / xn
}

/// `m`'s entries row by row (the compact solvers' flat row-major slices).
pub fn rows(m: &Mat) -> Vec<f64> {
    (0..m.nrows())
        .flat_map(|i| (0..m.ncols()).map(move |j| m[(i, j)]))
        .collect()
}

/// The cart's LQ integral servo on `[x; w]`, `w = ∫(r − z)`: `A_aug = [A 0; −C 0]`,
/// `B_aug = [B; 0]` (the book's upright cart, `pendulab_testkit::cart::upright`).
pub fn cart_servo() -> (Mat, Mat) {
    let (a, b) = pendulab_testkit::cart::upright();
    let mut aa = Mat::zeros(5, 5);
    aa.view_mut((0, 0), (4, 4)).copy_from(&a);
    aa[(4, 0)] = -1.0;
    let mut bb = Mat::zeros(5, 1);
    bb.view_mut((0, 0), (4, 1)).copy_from(&b);
    (aa, bb)
}

/// One slider move of the browser lab's weights: `q[slider]` (or `r` when `slider` is past
/// `q`) times `f`, a zero weight becoming `10⁻²` (a log slider's first step off zero).
pub fn move_slider(q: &mut [f64], r: &mut f64, slider: usize, f: f64) {
    match q.get_mut(slider) {
        None => *r *= f,
        Some(v) if *v == 0.0 => *v = 1e-2,
        Some(v) => *v *= f,
    }
}
