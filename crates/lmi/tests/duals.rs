//! `Solution::dual`: the dual variable of each constraint, checked against a problem whose
//! dual is known in closed form, on both methods and with the row/objective scaling.

use pendulab_lmi::{Backend, Expr, Problem, SolveOptions};
use pendulab_lti::Mat;

/// `min tr X` subject to `X ⪰ C`, `C = [[2, 1], [1, 2]]`: the optimum is `X = C`, and the
/// dual of `G = X − C ⪰ 0` is `Z = I` (stationarity `I − Z = 0`), dual bound `⟨Z, C⟩ = tr C`.
#[test]
fn dual_of_the_trace_problem_is_the_identity_on_both_methods() {
    let c = Mat::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
    for backend in [Backend::Dense, Backend::Clarabel] {
        for scale_rows in [false, true] {
            let mut p = Problem::new();
            let x = p.symmetric("X", 2);
            // Scaled by 3 so that the row scaling has something to undo: G = 3(X − C).
            let id = p
                .positive_semidefinite("3(X − C) ⪰ 0", &(&x - Expr::constant(&c)).scale(3.0))
                .unwrap();
            // Objective scaled by 5: the dual scales with it, Z = (5/3) I.
            p.minimize(&x.trace().scale(5.0)).unwrap();
            let sol = p
                .solve(&SolveOptions {
                    backend,
                    scale_rows,
                    ..SolveOptions::default()
                })
                .unwrap();
            assert!(sol.all_checks_pass(), "{backend:?}: {:?}", sol.status);
            let z = sol.dual(id).unwrap();
            let want = Mat::identity(2, 2) * (5.0 / 3.0);
            assert!(
                (z - &want).norm() < 1e-6,
                "{backend:?}, scale_rows {scale_rows}: Z = {z}"
            );
            // Dual bound −⟨Z, G(0)⟩ = ⟨Z, 3C⟩ = 5 tr C = the optimum.
            let bound: f64 = z.iter().zip((&c * 3.0).iter()).map(|(a, b)| a * b).sum();
            assert!((bound - sol.objective.unwrap()).abs() < 1e-6);
        }
    }
}
