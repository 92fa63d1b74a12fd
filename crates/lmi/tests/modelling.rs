//! The modelling layer: expressions evaluate like the matrices they denote, invalid input is a
//! typed error (never a panic), and the solver sees the problem the user wrote.

use pendulab_lmi::{Expr, LmiError, Problem, Relation, SolveOptions, Status};
use pendulab_lti::Mat;

/// Deterministic test matrix with entries in [−1, 1].
fn mat(r: usize, c: usize, seed: u64) -> Mat {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15).wrapping_add(1);
    Mat::from_fn(r, c, |_, _| {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    })
}

/// A problem whose variables are pinned by equalities to known values, so that `value()`
/// returns exactly the evaluation of an expression at those values.
#[test]
fn expressions_evaluate_like_the_matrices_they_denote() {
    let mut p = Problem::new();
    let x = p.symmetric("X", 3);
    let l = p.matrix("L", 2, 3);
    let g = p.scalar("g");
    let xv = {
        let m = mat(3, 3, 1);
        &m + m.transpose()
    };
    let lv = mat(2, 3, 2);
    let gv = 0.7;
    p.equal("X fixed", &x, &Expr::constant(&xv)).unwrap();
    p.equal("L fixed", &l, &Expr::constant(&lv)).unwrap();
    p.equal("g fixed", &g, &Expr::scalar(gv)).unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    assert!(sol.all_checks_pass(), "{:?}", sol.status);

    let a = mat(3, 3, 3);
    let b = mat(3, 2, 4);
    let c = mat(2, 2, 5);
    // Each pair: an expression and the same matrix computed directly.
    let cases: Vec<(Expr, Mat)> = vec![
        (&a * &x + &b * &l, &a * &xv + &b * &lv),
        ((&a * &x + &b * &l).he(), {
            let y = &a * &xv + &b * &lv;
            &y + y.transpose()
        }),
        (l.t() * &c, lv.transpose() * &c),
        (&x * &a - x.scale(2.0), &xv * &a - &xv * 2.0),
        (&g + Expr::scalar(1.0), Mat::from_element(1, 1, gv + 1.0)),
        (x.trace(), Mat::from_element(1, 1, xv.trace())),
        (Expr::kron(&Expr::constant(&c), &x), c.kronecker(&xv)),
        (Expr::kron(&l, &Expr::constant(&c)), lv.kronecker(&c)),
        (Expr::block(&[&[&x, &l.t()], &[&l, &Expr::identity(2)]]), {
            let mut m = Mat::zeros(5, 5);
            m.view_mut((0, 0), (3, 3)).copy_from(&xv);
            m.view_mut((0, 3), (3, 2)).copy_from(&lv.transpose());
            m.view_mut((3, 0), (2, 3)).copy_from(&lv);
            m.view_mut((3, 3), (2, 2)).copy_from(&Mat::identity(2, 2));
            m
        }),
        (
            x.sub_block(1, 0, 2, 3),
            xv.view((1, 0), (2, 3)).into_owned(),
        ),
        (-(&x * 3.0) + 1.5 * &x, &xv * -1.5),
    ];
    for (k, (e, expect)) in cases.iter().enumerate() {
        let got = sol.value(e).unwrap();
        // The equalities are met to the solver's tolerance (1e-8 relative), entries are O(1).
        assert!((&got - expect).amax() < 1e-7, "case {k}: {got} vs {expect}");
    }
}

#[test]
fn parameters_make_polynomials_that_substitute_and_evaluate() {
    let mut p = Problem::new();
    let rho = p.parameter("rho");
    let x0 = p.symmetric("X0", 2);
    let x1 = p.symmetric("X1", 2);
    let xr = &x0 + &rho * &x1 + (&rho * &rho) * &x0;
    assert!(xr.is_parametric() && xr.has_variables());
    let a = mat(2, 2, 7);
    p.equal("X0", &x0, &Expr::constant(&(&a + a.transpose())))
        .unwrap();
    p.equal("X1", &x1, &Expr::identity(2)).unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    let at = sol.value_at(&xr, &[(&rho, 0.5)]).unwrap();
    let expect = (&a + a.transpose()) * 1.25 + Mat::identity(2, 2) * 0.5;
    assert!((at - &expect).amax() < 1e-7);
    let sub = sol.value(&xr.at(&rho, 0.5)).unwrap();
    assert!((sub - &expect).amax() < 1e-7);
    // Forgetting the parameter is an error, not a silent zero.
    assert!(matches!(
        sol.value(&xr),
        Err(LmiError::ParameterDependent { .. })
    ));
    // A monomial column.
    let z = Expr::monomials(&rho, 3);
    assert_eq!(z.shape(), (4, 1));
    let zv = z.at(&rho, 2.0).to_constant().unwrap();
    assert_eq!(zv.as_slice(), &[1.0, 2.0, 4.0, 8.0]);
}

#[test]
fn invalid_models_are_typed_errors() {
    let mut p = Problem::new();
    let x = p.symmetric("X", 2);
    let l = p.matrix("L", 1, 2);
    // Shape mismatch, deferred to the constraint.
    let bad = &x + &l;
    assert!(matches!(
        p.positive_semidefinite("bad", &bad),
        Err(LmiError::ShapeMismatch { .. })
    ));
    // Product of two decision-dependent expressions.
    assert!(matches!(
        p.positive_semidefinite("quad", &(&x * &x)),
        Err(LmiError::NotAffine { .. })
    ));
    // A non-symmetric matrix inequality.
    let a = Mat::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
    assert!(matches!(
        p.negative_definite("asym", &(&a * &x), 1e-6),
        Err(LmiError::NotSymmetric { .. })
    ));
    // A non-square matrix inequality.
    assert!(matches!(
        p.positive_semidefinite("rect", &l),
        Err(LmiError::NotSquare { .. })
    ));
    // Non-finite constants.
    let nan = Mat::from_element(2, 2, f64::NAN);
    assert!(matches!(
        p.positive_semidefinite("nan", &(&x + &nan)),
        Err(LmiError::NonFinite { .. })
    ));
    // Invalid margin.
    assert!(matches!(
        p.positive_definite("m", &x, 0.0),
        Err(LmiError::InvalidArgument { .. })
    ));
    assert!(matches!(
        p.positive_definite("m", &x, f64::NAN),
        Err(LmiError::InvalidArgument { .. })
    ));
    // Objective must be 1x1 and parameter-free.
    assert!(matches!(
        p.minimize(&x),
        Err(LmiError::ShapeMismatch { .. })
    ));
    let rho = p.parameter("rho");
    assert!(matches!(
        p.minimize(&(&rho * &x.trace())),
        Err(LmiError::ParameterDependent { .. })
    ));
    assert!(matches!(
        p.positive_semidefinite("param", &(&rho * &x)),
        Err(LmiError::ParameterDependent { .. })
    ));
    // Expressions of another problem.
    let mut q = Problem::new();
    let y = q.symmetric("Y", 2);
    assert!(matches!(
        p.positive_semidefinite("foreign", &y),
        Err(LmiError::ForeignExpression { .. })
    ));
    assert!(matches!(
        (&x + &y).check(),
        Err(LmiError::ForeignExpression { .. })
    ));
    // Not a parameter.
    assert!(matches!(
        x.at(&x, 1.0).check(),
        Err(LmiError::NotAParameter { .. })
    ));
    // The failed constraints were not added.
    assert!(p.constraint_names().is_empty());
    // Bad options.
    let opts = SolveOptions {
        check_tolerance: -1.0,
        ..SolveOptions::default()
    };
    assert!(matches!(
        p.solve(&opts),
        Err(LmiError::InvalidArgument { .. })
    ));
}

/// The solver's data are the model's: an LMI whose solution is known in closed form.
/// minimise tr(C X) s.t. X ⪰ I has the solution X = I when C ≻ 0 (tr(C X) ≥ tr C for X ⪰ I).
#[test]
fn a_closed_form_sdp_is_solved_exactly() {
    let g = mat(4, 4, 9);
    let c = &g * g.transpose() + Mat::identity(4, 4);
    let mut p = Problem::new();
    let x = p.symmetric("X", 4);
    let id = p
        .positive_semidefinite("X ⪰ I", &(&x - &Expr::identity(4)))
        .unwrap();
    p.minimize(&(&c * &x).trace()).unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    assert_eq!(sol.status, Status::Solved);
    // Solver accuracy 1e-8 relative on O(1) data.
    assert!((sol.value(&x).unwrap() - Mat::identity(4, 4)).amax() < 1e-6);
    assert!((sol.objective.unwrap() - c.trace()).abs() < 1e-6 * c.trace());
    let chk = sol.check(id).unwrap();
    assert_eq!(chk.relation, Relation::PositiveSemidefinite);
    assert!(chk.satisfied && chk.value.abs() < 1e-6);
    // Dimensions: a symmetric 4×4 variable is 10 scalars, the LMI one 4×4 cone.
    assert_eq!(sol.dims.variables, 10);
    assert_eq!(sol.dims.psd_sizes, vec![4]);
}

#[test]
fn maximisation_and_unboundedness() {
    // maximise t s.t. t ≤ 3: optimum 3.
    let mut p = Problem::new();
    let t = p.scalar("t");
    p.less_equal("t ≤ 3", &t, &Expr::scalar(3.0)).unwrap();
    p.maximize(&t).unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    assert!((sol.objective.unwrap() - 3.0).abs() < 1e-7);
    // Without the bound the problem is unbounded: a status, not an error.
    let mut q = Problem::new();
    let t = q.scalar("t");
    q.nonnegative("t ≥ 0", &t).unwrap();
    q.maximize(&t).unwrap();
    let sol = q.solve(&SolveOptions::default()).unwrap();
    assert!(
        matches!(sol.status, Status::Unbounded { .. }),
        "{:?}",
        sol.status
    );
    assert!(sol.value(&t).is_err(), "no values without a solution");
}
