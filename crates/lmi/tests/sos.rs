//! Sum-of-squares constraints: known (non)negative polynomials, the S-procedure on an
//! interval against the exact minimum, matrix SOS, odd terms forced to vanish, and the
//! book's gain-scheduled servo (p2c15_ex7) against its known optimum.

mod common;

use pendulab_lmi::synthesis::{GainScheduleSpec, LpvPlant, gain_scheduled_lq};
use pendulab_lmi::{Expr, Problem, SolveOptions, Status};
use pendulab_lti::Mat;

/// Minimum of a univariate polynomial on [lo, hi] by a dense grid refined with a few
/// golden-section steps around the best grid point (an independent 1-D computation).
fn min_on(p: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let n = 20_000;
    let h = (hi - lo) / n as f64;
    let (mut best, mut xb) = (f64::INFINITY, lo);
    for k in 0..=n {
        let x = lo + h * k as f64;
        if p(x) < best {
            best = p(x);
            xb = x;
        }
    }
    let (mut a, mut b) = ((xb - h).max(lo), (xb + h).min(hi));
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..100 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if p(c) < p(d) {
            b = d;
        } else {
            a = c;
        }
    }
    p(0.5 * (a + b)).min(best)
}

#[test]
fn a_square_is_sos_and_a_negative_dip_is_not() {
    // (ρ² − 1)² = ρ⁴ − 2ρ² + 1 is a square: SOS, with a certified decomposition.
    let mut p = Problem::new();
    let rho = p.parameter("ρ");
    let r2 = &rho * &rho;
    let poly = &r2 * &r2 - r2.scale(2.0) + Expr::scalar(1.0);
    let id = p.sos("(ρ²−1)²", &poly).unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    assert!(sol.all_checks_pass(), "{:?}", sol.status);
    let chk = sol.sos_check(id).unwrap();
    assert_eq!(
        chk.gram_size, 3,
        "basis [1, ρ, ρ²] from the Newton polytope"
    );
    assert!(chk.relative_residual <= 1e-6 && chk.gram_min_eigenvalue >= -1e-8);
    // ρ⁴ − 2ρ² + 0.9 dips to −0.1 at ρ = ±1: not SOS, reported as infeasible.
    let mut q = Problem::new();
    let rho = q.parameter("ρ");
    let r2 = &rho * &rho;
    q.sos("dip", &(&r2 * &r2 - r2.scale(2.0) + Expr::scalar(0.9)))
        .unwrap();
    let sol = q.solve(&SolveOptions::default()).unwrap();
    assert!(sol.status.is_infeasible(), "{:?}", sol.status);
}

/// For univariate polynomials, nonnegative = SOS, so max t s.t. p − t SOS is min p.
#[test]
fn the_largest_sos_lower_bound_of_a_univariate_polynomial_is_its_minimum() {
    let pf = |x: f64| x.powi(4) - 3.0 * x * x + x + 2.0;
    let mut p = Problem::new();
    let rho = p.parameter("ρ");
    let t = p.scalar("t");
    let r2 = &rho * &rho;
    let poly = &r2 * &r2 - r2.scale(3.0) + &rho + Expr::scalar(2.0);
    let id = p.sos("p − t", &(&poly - &t)).unwrap();
    p.maximize(&t).unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    assert!(sol.all_checks_pass());
    let exact = min_on(pf, -3.0, 3.0);
    // Solver accuracy 1e-8 relative on O(1) data; the SOS certificate is exact here.
    assert!(
        (sol.objective.unwrap() - exact).abs() < 1e-6,
        "{:?} vs {exact}",
        sol.objective
    );
    assert!(sol.sos_check(id).unwrap().relative_residual <= 1e-6);
}

/// S-procedure on [0, 1]: max t s.t. ρ³ − ρ − t ⪰ 0 for ρ ∈ [0, 1] (min −2/(3√3) at 1/√3),
/// certified as ρ³ − ρ − t − ρ(1 − ρ) S(ρ) SOS with S = [1, ρ] R [1, ρ]ᵀ.
#[test]
fn the_s_procedure_certifies_positivity_on_an_interval() {
    let mut p = Problem::new();
    let rho = p.parameter("ρ");
    let t = p.scalar("t");
    let q = &rho * &rho * &rho - &rho - &t;
    let g = &rho * (Expr::scalar(1.0) - &rho);
    let z = Expr::monomials(&rho, 1);
    let id = p.psd_on_set("cubic on [0, 1]", &q, &[(&g, &z)]).unwrap();
    p.maximize(&t).unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    assert!(sol.all_checks_pass(), "{:?}", sol.status);
    let exact = -2.0 / (3.0 * 3f64.sqrt());
    assert!((exact - min_on(|x| x.powi(3) - x, 0.0, 1.0)).abs() < 1e-12);
    assert!(
        (sol.objective.unwrap() - exact).abs() < 1e-6,
        "{:?}",
        sol.objective
    );
    assert!(sol.sos_check(id).unwrap().satisfied);
    // Without the interval the cubic is unbounded below: no SOS certificate at all.
    let mut u = Problem::new();
    let rho = u.parameter("ρ");
    let t = u.scalar("t");
    u.sos("cubic", &(&rho * &rho * &rho - &rho - &t)).unwrap();
    u.maximize(&t).unwrap();
    let sol = u.solve(&SolveOptions::default()).unwrap();
    assert!(sol.status.is_infeasible(), "{:?}", sol.status);
}

/// A matrix polynomial [[1 + ρ², ρ], [ρ, 1]] (determinant 1) is a matrix SOS; shrinking
/// its (2, 2) entry to 1 − c makes it indefinite at large ρ, so max c is 0.
#[test]
fn matrix_sos_and_its_boundary() {
    let mut p = Problem::new();
    let rho = p.parameter("ρ");
    let c = p.scalar("c");
    let one = Expr::scalar(1.0);
    let m = Expr::block(&[&[&(&one + &rho * &rho), &rho], &[&rho, &(&one - &c)]]);
    let id = p.sos("M(ρ)", &m).unwrap();
    p.maximize(&c).unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    assert!(sol.all_checks_pass());
    // det = (1 + ρ²)(1 − c) − ρ² = 1 − c − cρ² ≥ 0 for all ρ iff c ≤ 0.
    assert!(sol.objective.unwrap().abs() < 1e-6, "{:?}", sol.objective);
    let chk = sol.sos_check(id).unwrap();
    assert!(chk.relative_residual <= 1e-6);
}

/// A polynomial affine in a second parameter w cannot be SOS unless its w-terms vanish:
/// they become equality constraints (max c s.t. 1 + ρ² + c w SOS gives c = 0).
#[test]
fn odd_terms_in_a_parameter_are_forced_to_vanish() {
    let mut p = Problem::new();
    let rho = p.parameter("ρ");
    let w = p.parameter("w");
    let c = p.scalar("c");
    let poly = Expr::scalar(1.0) + &rho * &rho + &c * &w;
    let id = p.sos("1 + ρ² + c w", &poly).unwrap();
    p.maximize(&c).unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    assert!(sol.all_checks_pass());
    assert!(sol.objective.unwrap().abs() < 1e-8);
    assert!(sol.sos_check(id).unwrap().matching_constraint.is_some());
}

fn servo_design() -> (
    pendulab_lmi::synthesis::GainSchedule,
    GainScheduleSpec,
    LpvPlant,
) {
    let (spec, plant) = common::book_gain_schedule();
    let gs = gain_scheduled_lq(&plant, &spec, &SolveOptions::default()).unwrap();
    (gs, spec, plant)
}

/// p2c15_ex7: γ* against the book's optimum (γ* ≈ 222: the printed γ = 236, book part 2 §1.5,
/// p. 164, is the 1.06 γ* cap of its feasibility re-solve, 236/1.06 = 222.6) and against CVXPY +
/// Clarabel on a hand-written kernel-form copy of the same SOS program; the returned schedule
/// satisfies the design conditions pointwise.
#[test]
fn p2c15_gain_scheduled_servo_reaches_the_known_optimum() {
    let (gs, spec, plant) = servo_design();
    let gamma_star = gs.gamma_star.expect("γ minimisation solved");
    // Tolerance 0.5 %: the reference is quoted as ≈ 222 (three digits, ±0.23 %) and the
    // double-precision optimum of this degenerate SDP moves by ±0.1 % with solver settings;
    // the failure mode of double-precision solvers on the book's raw coordinates (~1 % high) lies
    // outside.
    assert!(
        (gamma_star - 222.0).abs() < 0.005 * 222.0,
        "γ* = {gamma_star}"
    );
    let f: serde_json::Value =
        serde_json::from_str(include_str!("fixtures/lmi_reference.json")).unwrap();
    let g_ref = f["p2c15_gain_schedule"]["gamma_star"].as_f64().unwrap();
    assert!(
        (gamma_star - g_ref).abs() < 0.002 * g_ref,
        "{gamma_star} vs CVXPY {g_ref}"
    );

    // The design returned is the interior solution with γ ≤ 1.06 γ* (the book's 236).
    let s = gs
        .schedule
        .as_ref()
        .expect("feasibility re-solve passed its rechecks");
    assert!(s.gamma <= 1.06 * gamma_star * (1.0 + 1e-9));
    let refined = gs.refined.as_ref().unwrap();
    assert_eq!(refined.status, Status::Solved);
    assert!(refined.all_checks_pass());
    for chk in &refined.sos_checks {
        assert!(chk.relative_residual <= 1e-6, "{chk:?}");
        assert!(chk.residual <= 1e-6 * 1e3, "{chk:?}");
        assert!(chk.satisfied, "{chk:?}");
    }

    // Pointwise on a grid: X(ρ) ≻ 0, X(ρ0)⁻¹ ⪯ γI, and the decrease condition
    // ρ̇(X1 + 2ρX2) − He(A(ρ)X + B(ρ)L) − XQX − LᵀRL ⪰ 0 at ρ̇ = ±0.75 (the vertices of the
    // ρ̇ interval: the condition is affine in ρ̇). Tolerance 1e-7 relative to the norm of
    // the matrix checked (solver accuracy; the certificate itself leaves margin ε = 1e-6).
    let (q, r) = (&spec.lq.q, &spec.lq.r);
    let [_, x1, x2] = &s.x_coefficients;
    for k in 0..=50 {
        let rho = spec.rho_range.1 * k as f64 / 50.0;
        let x = s.x(rho);
        let l = s.l(rho);
        let ev = x.clone().symmetric_eigenvalues();
        assert!(ev.min() > 0.0);
        assert!(
            1.0 / ev.min() <= s.gamma * (1.0 + 1e-7),
            "X(ρ0)⁻¹ ⪯ γI at {rho}"
        );
        let a = &plant.a0 + &plant.a1 * rho;
        let b = &plant.b0 + &plant.b1 * rho;
        let y = &a * &x + &b * &l;
        for rho_dot in [-0.75, 0.75] {
            let n = (x1 + x2 * (2.0 * rho)) * rho_dot
                - (&y + y.transpose())
                - &x * q * &x
                - l.transpose() * r * &l;
            let n = (&n + n.transpose()) * 0.5;
            let lmin = n.clone().symmetric_eigenvalues().min();
            assert!(
                lmin >= -1e-7 * n.norm(),
                "decrease fails at ρ = {rho}, ρ̇ = {rho_dot}: {lmin}"
            );
        }
        // The gain is finite and the closed loop at frozen ρ is stable.
        let kg = s.gain(rho).unwrap();
        let poles = pendulab_lti::linalg::eigenvalues(&(&a - &b * &kg)).unwrap();
        assert!(poles.iter().all(|z| z.re < 0.0));
    }

    // At the optimum the gain at ρ = ρ̄ is well determined: CVXPY's agrees to 2 % (both
    // solvers stop at reduced accuracy on this boundary point).
    let opt = gs.optimum.as_ref().unwrap();
    let k_bar = opt.gain(spec.rho_range.1).unwrap();
    let r: Vec<f64> = f["p2c15_gain_schedule"]["K_at_rho_max_at_optimum"][0]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let k_ref = Mat::from_row_slice(1, 5, &r);
    let e = (&k_bar - &k_ref).norm() / k_ref.norm();
    assert!(
        e < 0.02,
        "K(ρ̄) at the optimum: {k_bar} vs CVXPY {k_ref} (rel {e:e})"
    );
}
