//! The book's part 2 ch. 1 LMIs, each against an independent reference: a
//! closed form, a defining identity, SciPy's Riccati solution or CVXPY + Clarabel
//! (fixture `lmi_reference.json`, written by `tools/reference/lmi_reference.py`).

mod common;

use pendulab_lmi::synthesis::{
    InputBound, Region, Vertex, alpha_stability, lq_state_feedback, max_decay_rate,
    multiobjective_state_feedback, robust_state_feedback, saturated_state_feedback,
};
use pendulab_lmi::{Expr, Problem, SolveOptions, Status};
use pendulab_lti::{Mat, linalg::eigenvalues};
use serde_json::Value;

const EPS: f64 = 1e-6;

fn fixture() -> Value {
    serde_json::from_str(include_str!("fixtures/lmi_reference.json")).unwrap()
}

fn row(v: &Value) -> Mat {
    let r: Vec<f64> = v[0]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    Mat::from_row_slice(1, r.len(), &r)
}

fn rel(a: &Mat, b: &Mat) -> f64 {
    (a - b).norm() / b.norm()
}

fn a_ex1() -> Mat {
    Mat::from_row_slice(2, 2, &[0.0, 1.0, -2.25, -2.25])
}

/// p2c112_ex1: A = [[0, 1], [−2.25, −2.25]], α = 1, P = [[ξ1, ξ2], [ξ2, 1]]: feasible.
#[test]
fn p2c112_alpha_stability_is_feasible() {
    let a = a_ex1();
    let mut p = Problem::new();
    let xi1 = p.scalar("xi1");
    let xi2 = p.scalar("xi2");
    let e11 = Mat::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 0.0]);
    let e12 = Mat::from_row_slice(2, 2, &[0.0, 1.0, 1.0, 0.0]);
    let e22 = Mat::from_row_slice(2, 2, &[0.0, 0.0, 0.0, 1.0]);
    let pm = &e11 * &xi1 + &e12 * &xi2 + Expr::constant(&e22);
    p.positive_definite("P ≻ 0", &pm, EPS).unwrap();
    p.negative_definite(
        "AᵀP + PA + 2αP ≺ 0",
        &((&a.transpose() * &pm).he() + pm.scale(2.0)),
        EPS,
    )
    .unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    assert_eq!(sol.status, Status::Solved);
    assert!(sol.all_checks_pass());
    // Independent check of the returned P by its eigenvalues.
    let pv = sol.value(&pm).unwrap();
    let lyap = a.transpose() * &pv + &pv * &a + &pv * 2.0;
    assert!(pv.symmetric_eigenvalues().min() > 0.0);
    assert!(lyap.symmetric_eigenvalues().max() < 0.0);
    // The ready synthesis agrees: α = 1 < 1.125 = −max Re λ(A) is feasible, α = 1.2 is not.
    let opts = SolveOptions::default();
    assert!(alpha_stability(&a, 1.0, EPS, &opts).unwrap().feasible);
    let no = alpha_stability(&a, 1.2, EPS, &opts).unwrap();
    assert!(!no.feasible);
    assert!(matches!(no.solution.status, Status::Infeasible { .. }));
}

/// p2c121_ex3: minimise ξ1 + ξ2. Closed form (ε → 0): with c = 2ξ2 − 2.5, the LMI holds
/// iff ξ2 ∈ [1, 1.25] and ξ1 ≥ 2.25ξ2 − 0.25 − √((2.5 − 2ξ2)(2ξ2 − 2)); minimising the sum
/// gives 233ξ2² − 524.25ξ2 + 292.25 = 0 (smaller root).
#[test]
fn p2c121_optimum_matches_its_closed_form_and_the_book() {
    let a = a_ex1();
    let mut p = Problem::new();
    let xi1 = p.scalar("xi1");
    let xi2 = p.scalar("xi2");
    let pm = Expr::block(&[&[&xi1, &xi2], &[&xi2, &Expr::scalar(1.0)]]);
    p.positive_definite("P ≻ 0", &pm, EPS).unwrap();
    p.negative_definite(
        "AᵀP + PA + 2P ≺ 0",
        &((&a.transpose() * &pm).he() + pm.scale(2.0)),
        EPS,
    )
    .unwrap();
    p.minimize(&(&xi1 + &xi2)).unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    assert!(sol.all_checks_pass());
    let x2: f64 = (524.25 - (524.25f64.powi(2) - 4.0 * 233.0 * 292.25).sqrt()) / 466.0;
    let x1 = 2.25 * x2 - 0.25 - ((2.5 - 2.0 * x2) * (2.0 * x2 - 2.0)).sqrt();
    // The margins ε = 1e-6 move the optimum by O(ε · ‖dual‖) ≈ 1e-5; solver accuracy 1e-8.
    let tol = 1e-4;
    assert!((sol.objective.unwrap() - (x1 + x2)).abs() < tol);
    assert!((sol.value(&xi1).unwrap()[(0, 0)] - x1).abs() < tol);
    assert!((sol.value(&xi2).unwrap()[(0, 0)] - x2).abs() < tol);
    // The book's rounded values (part 2 §1.2.1, example 1.3): 2.929, 1.911, 1.019 (±0.5 in the last
    // digit).
    assert!((sol.objective.unwrap() - 2.929).abs() < 5e-4);
    assert!((sol.value(&xi1).unwrap()[(0, 0)] - 1.911).abs() < 5e-4);
    assert!((sol.value(&xi2).unwrap()[(0, 0)] - 1.019).abs() < 5e-4);
    // CVXPY + Clarabel on the same problem.
    let f = fixture();
    assert!((sol.objective.unwrap() - f["p2c121"]["optimum"].as_f64().unwrap()).abs() < 1e-6);
}

/// An unstable A admits no Lyapunov matrix: the answer is the status Infeasible with a
/// certificate, whose defining identities are checked here from A alone.
#[test]
fn lyapunov_lmi_for_an_unstable_matrix_is_infeasible_with_a_certificate() {
    let (a, _) = common::arm(common::A1, common::B1, 0.0); // open loop: pendulum upright
    let mut p = Problem::new();
    let pv = p.symmetric("P", 4);
    p.positive_definite("P ≻ 0", &pv, EPS).unwrap();
    p.negative_definite("AᵀP + PA ≺ 0", &(&a.transpose() * &pv).he(), EPS)
        .unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    let Status::Infeasible { certificate, .. } = &sol.status else {
        panic!("expected Infeasible, got {:?}", sol.status);
    };
    assert!(sol.value(&pv).is_err(), "no P is returned");
    assert!(certificate.is_valid(1e-6), "{certificate:?}");
    // Farkas: with G1 = P − εI ⪰ 0 and G2 = −(AᵀP + PA) − εI ⪰ 0, multipliers Z1, Z2 ⪰ 0
    // with ⟨G1, Z1⟩ + ⟨G2, Z2⟩ ≡ −1 means Z1 = A Z2 + Z2 Aᵀ and ε (tr Z1 + tr Z2) = 1.
    let z1 = &certificate.multipliers[0].1;
    let z2 = &certificate.multipliers[1].1;
    let scale = z1.norm() + z2.norm();
    let station = z1 - (&a * z2 + z2 * a.transpose());
    assert!(station.norm() <= 1e-6 * scale, "{}", station.norm() / scale);
    assert!((EPS * (z1.trace() + z2.trace()) - 1.0).abs() < 1e-6);
    assert!(z1.symmetric_eigenvalues().min() > -1e-8 * scale);
    assert!(z2.symmetric_eigenvalues().min() > -1e-8 * scale);
}

/// Infeasibility that does not hinge on the margins: X ⪰ I and X ⪯ 0.
#[test]
fn contradictory_lmis_are_infeasible() {
    let mut p = Problem::new();
    let x = p.symmetric("X", 3);
    p.positive_semidefinite("X ⪰ I", &(&x - &Expr::identity(3)))
        .unwrap();
    p.negative_semidefinite("X ⪯ 0", &x).unwrap();
    let sol = p.solve(&SolveOptions::default()).unwrap();
    let Status::Infeasible { certificate, .. } = &sol.status else {
        panic!("{:?}", sol.status);
    };
    assert!(certificate.is_valid(1e-6));
    // Z1 (for X − I) and Z2 (for −X) must be equal (stationarity) with tr Z1 = 1.
    let z1 = &certificate.multipliers[0].1;
    let z2 = &certificate.multipliers[1].1;
    assert!((z1 - z2).norm() < 1e-6 * z1.norm());
    assert!((z1.trace() - 1.0).abs() < 1e-6);
}

/// p2c122_ex4: LMI LQ servo gain vs the Riccati LQ gain (SciPy solve_continuous_are).
#[test]
fn p2c122_lmi_lq_gain_agrees_with_the_riccati_gain() {
    let (a, b) = common::arm(common::A1, common::B1, 0.0);
    let (at, bt) = common::augment(&a, &b);
    let (q, r) = common::servo_weights();
    let d = lq_state_feedback(&at, &bt, &q, &r, &SolveOptions::default()).unwrap();
    assert!(d.solution.all_checks_pass());
    let fb = d.feedback.expect("solved");
    let f = fixture();
    let k_lq = row(&f["p2c122_lq"]["K_riccati"]);
    // The book: "agrees to ~3 digits". The LMI optimum differs from the Riccati solution by
    // the margin ε = 1e-6 and the solver tolerance 1e-8 amplified by κ(X) ≈ 1e4.
    let e = rel(&fb.gain, &k_lq);
    assert!(
        e < 1e-3,
        "relative gain difference {e:e}: {} vs {}",
        fb.gain,
        k_lq
    );
    // X⁻¹ is the Riccati solution P (the LMI's optimum), to the same accuracy.
    let p_ref: Vec<Vec<f64>> = serde_json::from_value(f["p2c122_lq"]["P_riccati"].clone()).unwrap();
    let p_ref = Mat::from_fn(5, 5, |i, j| p_ref[i][j]);
    let p_lmi = fb.x.clone().try_inverse().unwrap();
    assert!(rel(&p_lmi, &p_ref) < 1e-3);
    // Stable closed loop.
    assert!(fb.closed_loop_poles[0].iter().all(|z| z.re < 0.0));
    // CVXPY + Clarabel reaches the same trace X (relative 1e-4: both stop at tolerance 1e-8
    // on an objective of order 4e3 with κ ≈ 1e4).
    let tr = f["p2c122_lq"]["trace_X"].as_f64().unwrap();
    assert!((fb.x.trace() - tr).abs() < 1e-4 * tr);
}

/// p2c122_ex4 multi-objective: Re λ < −2, Re λ > −16, damping sector π/4, and LQ.
#[test]
fn p2c122_multiobjective_poles_lie_in_the_region() {
    let (a, b) = common::arm(common::A1, common::B1, 0.0);
    let (at, bt) = common::augment(&a, &b);
    let (q, r) = common::servo_weights();
    let regions = [
        Region::DecayRate { alpha: 2.0 },
        Region::SpeedLimit { beta: 16.0 },
        Region::Sector {
            theta: std::f64::consts::FRAC_PI_4,
        },
    ];
    let d = multiobjective_state_feedback(&at, &bt, &q, &r, &regions, &SolveOptions::default())
        .unwrap();
    // Maximising tr X under the regions drives X to its margin X ⪰ εI (CVXPY's solution has
    // eigenvalues down to 2e-6 as well), an optimum the solver reaches only to reduced
    // accuracy; the design then re-solves for an interior point at 0.99 tr X*, which passes
    // every recheck.
    let final_sol = d.refined.as_ref().unwrap_or(&d.solution);
    assert!(final_sol.all_checks_pass());
    let fb = d.feedback.unwrap();
    // Independent check of the poles of Ã − B̃K (real Schur eigenvalues).
    let poles = eigenvalues(&(&at - &bt * &fb.gain)).unwrap();
    for z in &poles {
        assert!(z.re < -2.0 && z.re > -16.0, "{z}");
        assert!(z.im.abs() < -z.re, "outside the π/4 sector: {z}");
    }
    assert!(fb.poles_in_regions);
    // The optimal value max tr X is well determined (X and K at the optimum are not: X is
    // singular there); same as CVXPY + Clarabel to 1e-4 relative (both at reduced accuracy).
    let f = fixture();
    let tr = f["p2c122_multiobjective"]["trace_X"].as_f64().unwrap();
    assert!((d.solution.objective.unwrap() - tr).abs() < 1e-4 * tr);
}

fn vertices() -> Vec<Vertex> {
    let mut v = Vec::new();
    for a1 in [3.41, 8.99] {
        for b1 in [8.69, 22.91] {
            let (a, b) = common::arm(a1, b1, 0.0);
            let (at, bt) = common::augment(&a, &b);
            v.push(Vertex { a: at, b: bt });
        }
    }
    v
}

/// p2c13_ex5: the nominal LQ servo is unstable at the vertex (a1, b1) = (8.99, 8.69); the
/// robust design (α = 2, β = 40, common X, L at all four vertices) is stable at all four.
#[test]
fn p2c13_robust_design_stabilises_every_vertex_where_nominal_lq_does_not() {
    let verts = vertices();
    let (q, r) = common::servo_weights();
    let f = fixture();
    let k_lq = row(&f["p2c122_lq"]["K_riccati"]);
    let max_re = |v: &Vertex, k: &Mat| {
        eigenvalues(&(&v.a - &v.b * k))
            .unwrap()
            .iter()
            .map(|z| z.re)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    // Nominal LQ at the four vertices, in the order (3.41, 8.69), (3.41, 22.91),
    // (8.99, 8.69), (8.99, 22.91): unstable at the third.
    let nominal: Vec<f64> = verts.iter().map(|v| max_re(v, &k_lq)).collect();
    assert!(nominal[2] > 0.0, "{nominal:?}");
    let regions = [
        Region::DecayRate { alpha: 2.0 },
        Region::SpeedLimit { beta: 40.0 },
    ];
    let d = robust_state_feedback(&verts, &q, &r, &regions, &SolveOptions::default()).unwrap();
    assert!(d.refined.as_ref().unwrap_or(&d.solution).all_checks_pass());
    let fb = d.feedback.unwrap();
    for v in &verts {
        let poles = eigenvalues(&(&v.a - &v.b * &fb.gain)).unwrap();
        assert!(
            poles.iter().all(|z| z.re < -2.0 && z.re > -40.0),
            "{poles:?}"
        );
    }
    assert!(fb.poles_in_regions);
    // Same optimum tr X* as CVXPY + Clarabel (relative 1e-5: both solved to 1e-8 on an
    // objective of 540 with κ(X) large at the optimum).
    let tr = f["p2c13_robust"]["trace_X"].as_f64().unwrap();
    assert!((d.solution.objective.unwrap() - tr).abs() < 1e-5 * tr);
}

/// p2c14_ex6: |u| ≤ 0.1 V from x0 = [10°, 0, 0, 0]. The invariant-ellipsoid argument is
/// checked on the linear closed loop by exact (matrix-exponential) sampling.
#[test]
fn p2c14_saturation_design_keeps_the_input_within_its_bound() {
    let (a, b) = common::arm(common::A1, common::B1, 0.0);
    let q = Mat::from_diagonal(&pendulab_lti::Vector::from_vec(vec![20.0, 10.0, 0.1, 0.1]));
    let r = Mat::from_element(1, 1, 1.0);
    let x0 = vec![10f64.to_radians(), 0.0, 0.0, 0.0];
    let bound = InputBound {
        u_max: vec![0.1],
        initial_states: vec![x0.clone()],
    };
    let d = saturated_state_feedback(&a, &b, &q, &r, &bound, &SolveOptions::default()).unwrap();
    let refined = d.refined.as_ref().expect("re-solved as feasibility");
    assert!(refined.all_checks_pass());
    // The optimisation reaches CVXPY's max tr X (relative 1e-4).
    let f = fixture();
    let tr = f["p2c14_saturation"]["trace_X_max"].as_f64().unwrap();
    assert!((d.solution.objective.unwrap() - tr).abs() < 1e-4 * tr);
    let fb = d.feedback.unwrap();
    // x0 in the ellipsoid and |K_i| bounded on it: x0ᵀX⁻¹x0 ≤ 1, K X Kᵀ ≤ u_max².
    assert!(fb.cost_bound(&x0).unwrap() <= 1.0 + 1e-9);
    assert!((&fb.gain * &fb.x * fb.gain.transpose())[(0, 0)] <= 0.01 * (1.0 + 1e-9));
    // Linear closed loop from x0, sampled every 1 ms for 10 s: |u| ≤ 0.1, and the Lyapunov
    // function V = xᵀX⁻¹x never increases (the ellipsoid is invariant).
    let acl = &a - &b * &fb.gain;
    let step = (&acl * 1e-3).exp();
    let xinv = fb.x.clone().try_inverse().unwrap();
    let v = |x: &Mat| (x.transpose() * &xinv * x)[(0, 0)];
    let mut x = Mat::from_column_slice(4, 1, &x0);
    let mut umax: f64 = 0.0;
    let v0 = v(&x);
    let mut vprev = v0;
    for _ in 0..10_000 {
        umax = umax.max((&fb.gain * &x)[(0, 0)].abs());
        x = &step * &x;
        let vk = v(&x);
        assert!(vk <= vprev * (1.0 + 1e-12), "V increased: {vprev} -> {vk}");
        vprev = vk;
    }
    assert!(umax <= 0.1, "max |u| = {umax}");
    assert!(vprev < 0.5 * v0, "V decreased over 10 s: {v0} -> {vprev}");
}

/// Decay rate by bisection on α equals the spectral abscissa −max Re λ(A) (1.125 for the
/// p2c112 matrix, whose eigenvalues are −1.125 ± 0.992j).
#[test]
fn max_decay_rate_equals_the_spectral_abscissa() {
    let a = a_ex1();
    let d = max_decay_rate(&a, EPS, 1e-5, &SolveOptions::default()).unwrap();
    // Bisection tolerance 1e-5; the margin ε makes the LMI value slightly smaller.
    assert!((d.alpha - 1.125).abs() < 1e-3, "{}", d.alpha);
    assert!(d.alpha < 1.125);
}

/// The two KKT factorisations Clarabel offers (QDLDL's simplicial and faer's supernodal
/// LDLᵀ) are independent implementations of the same step: forced one way and the other on
/// the p2c122 servo LMI, both reach the Riccati gain and the same optimum.
#[test]
fn kkt_factorisations_agree_on_the_servo_lmi() {
    use pendulab_lmi::KktSolver;
    let (a, b) = common::arm(common::A1, common::B1, 0.0);
    let (at, bt) = common::augment(&a, &b);
    let (q, r) = common::servo_weights();
    let k_lq = row(&fixture()["p2c122_lq"]["K_riccati"]);
    let mut traces = Vec::new();
    for kkt_solver in [KktSolver::Qdldl, KktSolver::Faer] {
        let opts = SolveOptions {
            kkt_solver,
            ..SolveOptions::default()
        };
        let d = lq_state_feedback(&at, &bt, &q, &r, &opts).unwrap();
        assert!(d.solution.all_checks_pass(), "{kkt_solver:?}");
        let fb = d.feedback.expect("solved");
        // As in p2c122_lmi_lq_gain_agrees_with_the_riccati_gain.
        assert!(rel(&fb.gain, &k_lq) < 1e-3, "{kkt_solver:?}");
        traces.push(fb.x.trace());
    }
    // Both stop at relative gap 1e-8 on the same objective (tr X ≈ 3.9e3).
    assert!(
        (traces[0] - traces[1]).abs() < 1e-6 * traces[0],
        "{traces:?}"
    );
}
