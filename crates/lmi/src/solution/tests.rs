use super::{Backend, FULL_REFINEMENT_STEPS, KktSolver, SolveOptions, Status, solve_with};
use crate::clarabel_backend;
use crate::conic::RawStatus;
use crate::{Expr, Problem};
use pendulab_lti::Mat;
use std::cell::RefCell;

/// `min tr X` subject to `X ⪰ C`: the optimum is `tr C` (= 4) at `X = C`.
fn trace_problem() -> (Problem, Expr) {
    let mut p = Problem::new();
    let x = p.symmetric("X", 2);
    let c = Mat::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
    p.positive_semidefinite("X ⪰ C", &(&x - Expr::constant(&c)))
        .unwrap();
    p.minimize(&x.trace()).unwrap();
    (p, x)
}

/// A backend that reports numerical trouble whenever it is called with fewer than
/// `fail_below` refinement steps (and the real solve otherwise): the repeated solve
/// happens exactly when the first one is in trouble with shortened refinement, uses
/// Clarabel's default refinement, and its (correct) result is what the user gets.
#[test]
fn numerical_trouble_with_short_refinement_is_solved_again_with_full_refinement() {
    let (p, x) = trace_problem();
    for (fail_below, steps, expect_calls, expect_retry) in [
        (2, 1, vec![1, FULL_REFINEMENT_STEPS], true),
        (0, 1, vec![1], false),
        // Trouble with Clarabel's default refinement already: no second solve.
        (
            u32::MAX,
            FULL_REFINEMENT_STEPS,
            vec![FULL_REFINEMENT_STEPS],
            false,
        ),
    ] {
        let calls = RefCell::new(Vec::new());
        let options = SolveOptions {
            refinement_steps: steps,
            backend: Backend::Clarabel,
            ..SolveOptions::default()
        };
        let sol = solve_with(&p, &options, |prob, data, settings| {
            calls.borrow_mut().push(settings.refinement_steps);
            let mut raw = clarabel_backend::solve(prob, data, settings)?;
            if settings.refinement_steps < fail_below {
                raw.status = RawStatus::NumericalError;
            }
            Ok(raw)
        })
        .unwrap();
        assert_eq!(*calls.borrow(), expect_calls);
        assert_eq!(sol.refinement_retry, expect_retry);
        if fail_below == u32::MAX {
            assert!(matches!(sol.status, Status::NumericalTrouble { .. }));
            continue;
        }
        assert!(sol.all_checks_pass(), "{:?}", sol.status);
        // The solver's 1e-8 tolerances on an O(1) problem.
        assert!((sol.objective.unwrap() - 4.0).abs() < 1e-6);
        let xv = sol.value(&x).unwrap();
        assert!((xv[(0, 1)] - 1.0).abs() < 1e-6);
    }
}

#[test]
fn auto_picks_faer_from_the_stated_dimension() {
    let d = KktSolver::AUTO_FAER_DIMENSION;
    assert_eq!(KktSolver::Auto.method(d - 1), "qdldl");
    assert_eq!(KktSolver::Auto.method(d), "faer");
    assert_eq!(KktSolver::Qdldl.method(10 * d), "qdldl");
    assert_eq!(KktSolver::Faer.method(1), "faer");
}
