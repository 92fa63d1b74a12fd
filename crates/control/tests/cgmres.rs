//! C/GMRES and GMRES against independent answers: direct linear solves, the Krylov-space
//! least-squares minimum, a dynamic-programming (Riccati recursion) solution of the same
//! discretised LQ problem, finite differences of the cost, and a closed-form constrained
//! optimum.

use nalgebra::{DMatrix, DVector};
use pendulab_control::ControlError;
use pendulab_control::cgmres::{
    Cgmres, CgmresOptions, Horizon, InitOptions, InputBound, InputBounds, OptimalControlProblem,
};
use pendulab_control::gmres::{self, GmresWorkspace};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

// ---------------------------------------------------------------------------------------------
// GMRES

fn random_system(n: usize, seed: u64) -> (DMatrix<f64>, DVector<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // Nonsymmetric, eigenvalues spread around 3 ± 1: well conditioned but not trivial.
    let mut a = DMatrix::from_fn(n, n, |_, _| rng.random_range(-1.0..1.0) / (n as f64).sqrt());
    for i in 0..n {
        a[(i, i)] += 3.0;
    }
    let b = DVector::from_fn(n, |_, _| rng.random_range(-1.0..1.0));
    (a, b)
}

#[test]
fn gmres_with_full_budget_equals_direct_solve() {
    for (n, seed) in [(1, 1), (7, 2), (30, 3)] {
        let (a, b) = random_system(n, seed);
        let direct = a.clone().lu().solve(&b).unwrap();
        let mut ws = GmresWorkspace::new(n, n);
        let mut x = vec![0.0; n];
        let rep = gmres::solve(
            &mut ws,
            |v, y| {
                let r = &a * DVector::from_column_slice(v);
                y.copy_from_slice(r.as_slice());
            },
            b.as_slice(),
            &mut x,
            0.0,
        );
        let err = (DVector::from_column_slice(&x) - &direct).norm() / direct.norm();
        // n Arnoldi steps span the whole space; what remains is rounding in MGS and the
        // triangular solve, a few ε·cond(A) (cond ≈ 2 here).
        assert!(err < 1e-12, "n = {n}: relative error {err:e}");
        let true_res = (&b - &a * DVector::from_column_slice(&x)).norm();
        assert!(rep.residual < 1e-12 * b.norm() + 1e-300);
        assert!(true_res < 1e-12 * b.norm(), "true residual {true_res:e}");
    }
}

#[test]
fn gmres_residual_is_the_krylov_space_minimum() {
    // After k < n steps GMRES returns argmin over x0 + K_k of ‖b − Ax‖. Independent
    // answer: form the Krylov matrix K = [r0, A r0, …, A^{k−1} r0] explicitly and solve the
    // least-squares problem min_y ‖r0 − A K y‖ by SVD.
    let n = 25;
    let (a, b) = random_system(n, 11);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let x0 = DVector::from_fn(n, |_, _| rng.random_range(-1.0..1.0));
    for k in 1..=5 {
        let mut ws = GmresWorkspace::new(n, k);
        let mut x = x0.as_slice().to_vec();
        let rep = gmres::solve(
            &mut ws,
            |v, y| y.copy_from_slice((&a * DVector::from_column_slice(v)).as_slice()),
            b.as_slice(),
            &mut x,
            0.0,
        );
        assert_eq!(rep.iterations, k);
        let r0 = &b - &a * &x0;
        assert!((rep.initial_residual - r0.norm()).abs() < 1e-12 * r0.norm());
        let mut kry = DMatrix::zeros(n, k);
        let mut col = r0.clone();
        for j in 0..k {
            kry.set_column(j, &col);
            col = &a * &col;
        }
        let ak = &a * &kry;
        let y = ak.clone().svd(true, true).solve(&r0, 1e-14).unwrap();
        let best = (&r0 - &ak * &y).norm();
        let true_res = (&b - &a * DVector::from_column_slice(&x)).norm();
        // Both are the same minimum; the explicit Krylov basis is ill conditioned only
        // mildly for k ≤ 5 (cond(K) ≲ 3^5), so agreement to 1e-9 relative is expected.
        assert!(
            (true_res - best).abs() <= 1e-9 * r0.norm(),
            "k = {k}: GMRES {true_res:e}, least squares {best:e}"
        );
        // The Givens estimate is the true residual of a linear operator.
        assert!((rep.residual - true_res).abs() <= 1e-10 * r0.norm());
    }
}

// ---------------------------------------------------------------------------------------------
// A linear-quadratic problem: f = Ax + Bu, L = ½(xᵀQx + uᵀRu), φ = ½xᵀSx.

#[derive(Clone)]
struct Lq {
    a: DMatrix<f64>,
    b: DMatrix<f64>,
    q: DMatrix<f64>,
    r: DMatrix<f64>,
    s: DMatrix<f64>,
}

impl Lq {
    fn double_integrator() -> Self {
        Self {
            a: DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]),
            b: DMatrix::from_row_slice(2, 1, &[0.0, 1.0]),
            q: DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 0.5]),
            r: DMatrix::from_row_slice(1, 1, &[0.1]),
            s: DMatrix::from_row_slice(2, 2, &[2.0, 0.3, 0.3, 1.0]),
        }
    }

    /// The Euler-discretised finite-horizon problem solved by dynamic programming:
    /// A_d = I + AΔτ, B_d = BΔτ, stage cost Δτ·½(xᵀQx + uᵀRu), terminal ½xᵀSx. Returns the
    /// optimal input sequence (stage-major) from x0.
    fn riccati_sequence(&self, x0: &[f64], horizon: f64, n: usize) -> Vec<f64> {
        let nx = self.a.nrows();
        let dt = horizon / n as f64;
        let ad = DMatrix::identity(nx, nx) + &self.a * dt;
        let bd = &self.b * dt;
        let mut p = self.s.clone();
        let mut gains = Vec::with_capacity(n);
        for _ in 0..n {
            // K = (RΔτ + B_dᵀPB_d)⁻¹B_dᵀPA_d with the common factor Δτ cancelled, which
            // keeps the zero-length horizon (Δτ = 0) well defined.
            let k = (&self.r + self.b.transpose() * &p * &self.b * dt)
                .lu()
                .solve(&(self.b.transpose() * &p * &ad))
                .unwrap();
            p = &self.q * dt + ad.transpose() * &p * &ad - ad.transpose() * &p * &bd * &k;
            p = (&p + p.transpose()) * 0.5;
            gains.push(k);
        }
        gains.reverse();
        let mut x = DVector::from_column_slice(x0);
        let mut u = Vec::new();
        for k in &gains {
            let ui = -(k * &x);
            u.extend_from_slice(ui.as_slice());
            x = &ad * &x + &bd * &ui;
        }
        u
    }
}

impl OptimalControlProblem for Lq {
    fn nx(&self) -> usize {
        self.a.nrows()
    }
    fn nu(&self) -> usize {
        self.b.ncols()
    }
    fn state_equation(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        let r = &self.a * DVector::from_column_slice(x) + &self.b * DVector::from_column_slice(u);
        dx.copy_from_slice(r.as_slice());
    }
    fn hamiltonian_x(&self, _t: f64, x: &[f64], _u: &[f64], l: &[f64], hx: &mut [f64]) {
        let r = &self.q * DVector::from_column_slice(x)
            + self.a.transpose() * DVector::from_column_slice(l);
        hx.copy_from_slice(r.as_slice());
    }
    fn hamiltonian_u(&self, _t: f64, _x: &[f64], u: &[f64], l: &[f64], hu: &mut [f64]) {
        let r = &self.r * DVector::from_column_slice(u)
            + self.b.transpose() * DVector::from_column_slice(l);
        hu.copy_from_slice(r.as_slice());
    }
    fn terminal_gradient(&self, _t: f64, x: &[f64], phix: &mut [f64]) {
        phix.copy_from_slice((&self.s * DVector::from_column_slice(x)).as_slice());
    }
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn initial_solution_of_a_fixed_horizon_lq_problem_matches_dynamic_programming() {
    let p = Lq::double_integrator();
    let n = 20;
    let horizon = 1.0;
    let opts = CgmresOptions {
        horizon: Horizon::Fixed { length: horizon },
        grid_points: n,
        ..Default::default()
    };
    let mut s = Cgmres::new(p.clone(), opts).unwrap();
    let x0 = [1.0, -0.5];
    let rep = s
        .initialize(0.0, &x0, &[0.0], &InitOptions::default())
        .unwrap();
    assert!(rep.residual <= 1e-8);
    let reference = p.riccati_sequence(&x0, horizon, n);
    // F is affine in U with F_U ⪰ R = 0.1 I (F is the cost gradient divided by Δτ), so
    // ‖U − U*‖ ≤ ‖F‖/0.1 ≤ 1e-7; the comparison allows that plus rounding of both methods.
    let d = dist(s.sequence(), &reference);
    assert!(d <= rep.residual / 0.1 + 1e-10, "distance {d:e}");
}

/// Runs the LQ closed loop for 3 s and returns, per sample, (‖F‖ on entry, ‖U − U*‖,
/// GMRES residual of the update).
fn lq_closed_loop(kmax: usize, dt: f64) -> (Vec<(f64, f64, f64)>, Vec<f64>) {
    let p = Lq::double_integrator();
    let n = 20;
    let opts = CgmresOptions {
        horizon: Horizon::Growing {
            final_length: 1.0,
            rate: 2.0,
        },
        grid_points: n,
        zeta: 1.0 / dt,
        gmres_iterations: kmax,
        ..Default::default()
    };
    let mut s = Cgmres::new(p.clone(), opts).unwrap();
    let mut x = vec![1.0, 0.0];
    s.initialize(0.0, &x, &[0.0], &InitOptions::default())
        .unwrap();
    let mut f = vec![0.0; n];
    let mut out = Vec::new();
    let steps = (3.0 / dt).round() as usize;
    for k in 0..steps {
        let t = k as f64 * dt;
        let res = s.residual(t, &x, &mut f).unwrap();
        let reference = p.riccati_sequence(&x, s.horizon_at(t), n);
        let d = dist(s.sequence(), &reference);
        let u0 = s.input()[0];
        let rep = s.update(t, &x, dt).unwrap();
        assert!((rep.optimality_residual - res).abs() <= 1e-12 * (1.0 + res));
        out.push((res, d, rep.gmres.residual));
        x = vec![x[0] + dt * x[1], x[1] + dt * u0];
    }
    (out, x)
}

#[test]
fn continuation_tracks_the_dynamic_programming_solution_along_a_closed_loop() {
    // Closed loop: the plant is the model stepped by explicit Euler with the sample period
    // dt and ζ dt = 1. Reference at every sample: the DP solution for the current state and
    // horizon length. Because F is affine in U with F_U ⪰ r I (r = 0.1; F is the cost gradient
    // divided by Δτ), ‖U − U*‖ ≤ ‖F(U)‖/r holds for any U — checked at every sample, it ties
    // the solver's own residual to the independent solution.
    let check_bound = |trace: &[(f64, f64, f64)], what: &str| {
        for (k, &(res, d, _)) in trace.iter().enumerate() {
            assert!(
                d <= res / 0.1 + 1e-9,
                "{what}, sample {k}: ‖U − U*‖ = {d:e} exceeds ‖F‖/r = {:e}",
                res / 0.1
            );
        }
    };
    // Exact linear solves (kmax = N·m = 20). With ζ dt = 1 the explicit continuation step
    // cancels F to first order, so what remains is its second-order term: halving dt must
    // divide ‖F‖ at a fixed time by 4 (the measured ratio may deviate by the third-order
    // term, a few per cent at these step sizes — allow ±10 %).
    let (coarse, x) = lq_closed_loop(20, 1e-3);
    let (fine, _) = lq_closed_loop(20, 5e-4);
    check_bound(&coarse, "kmax 20, dt 1 ms");
    check_bound(&fine, "kmax 20, dt 0.5 ms");
    for t in [0.01, 0.1, 0.5, 1.0] {
        let ratio =
            coarse[(t / 1e-3_f64).round() as usize].0 / fine[(t / 5e-4_f64).round() as usize].0;
        assert!(
            (3.6..=4.4).contains(&ratio),
            "t = {t}: ‖F‖(dt)/‖F‖(dt/2) = {ratio}, expected 4 (second order)"
        );
    }
    assert!(x[0].abs() < 0.05 && x[1].abs() < 0.1, "final state {x:?}");
    // The book's budget kmax = 5: the bound holds at every sample, the regulator works, and
    // once the horizon has stopped growing (Ṫ(2 s) = 2e^{−4} ≈ 0.04 1/s) the sequence has
    // converged onto the DP solution: the residual sources (Ṫ, the state's motion) have died
    // out, so ‖U − U*‖ on [2, 3] s is below 1e-3 of its worst early value — a continuation with
    // a wrong term would leave an error of the order of its early value.
    let (book, x) = lq_closed_loop(5, 1e-3);
    check_bound(&book, "kmax 5");
    let worst = book.iter().map(|t| t.1).fold(0.0, f64::max);
    let late = book[2000..].iter().map(|t| t.1).fold(0.0, f64::max);
    assert!(
        late <= 1e-3 * worst,
        "late ‖U − U*‖ {late:e}, worst {worst:e}"
    );
    assert!(x[0].abs() < 0.05 && x[1].abs() < 0.1, "final state {x:?}");
}

// ---------------------------------------------------------------------------------------------
// Nonlinear problem: the costate recursion gives the gradient of the discretised cost.

#[derive(Clone)]
struct Pendulum;

impl Pendulum {
    fn f(x: &[f64], u: f64) -> [f64; 2] {
        [x[1], x[0].sin() - 0.1 * x[1] + u * x[0].cos()]
    }
    fn l(x: &[f64], u: f64) -> f64 {
        0.5 * (x[0] * x[0] + 0.1 * x[1] * x[1] + 0.01 * u * u)
    }
    fn phi(x: &[f64]) -> f64 {
        0.5 * (x[0] * x[0] + x[1] * x[1])
    }
    /// Discretised cost Σ L Δτ + φ(x_N) by a forward rollout only.
    fn cost(x0: &[f64], u: &[f64], horizon: f64) -> f64 {
        let n = u.len();
        let dt = horizon / n as f64;
        let mut x = [x0[0], x0[1]];
        let mut j = 0.0;
        for &ui in u {
            j += Self::l(&x, ui) * dt;
            let d = Self::f(&x, ui);
            x = [x[0] + dt * d[0], x[1] + dt * d[1]];
        }
        j + Self::phi(&x)
    }
}

impl OptimalControlProblem for Pendulum {
    fn nx(&self) -> usize {
        2
    }
    fn nu(&self) -> usize {
        1
    }
    fn state_equation(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        dx.copy_from_slice(&Self::f(x, u[0]));
    }
    fn hamiltonian_x(&self, _t: f64, x: &[f64], u: &[f64], l: &[f64], hx: &mut [f64]) {
        hx[0] = x[0] + l[1] * (x[0].cos() - u[0] * x[0].sin());
        hx[1] = 0.1 * x[1] + l[0] - 0.1 * l[1];
    }
    fn hamiltonian_u(&self, _t: f64, x: &[f64], u: &[f64], l: &[f64], hu: &mut [f64]) {
        hu[0] = 0.01 * u[0] + l[1] * x[0].cos();
    }
    fn terminal_gradient(&self, _t: f64, x: &[f64], phix: &mut [f64]) {
        phix.copy_from_slice(&x[..2]);
    }
}

#[test]
fn optimality_residual_is_the_scaled_gradient_of_the_discretised_cost() {
    let n = 15;
    let horizon = 1.2;
    let opts = CgmresOptions {
        horizon: Horizon::Fixed { length: horizon },
        grid_points: n,
        ..Default::default()
    };
    let mut s = Cgmres::new(Pendulum, opts).unwrap();
    let x0 = [0.7, -0.3];
    // Any sequence will do for the gradient identity: take a non-constant one.
    let u: Vec<f64> = (0..n).map(|i| 0.2 + 0.05 * (i as f64).sin()).collect();
    s.set_sequence(0.0, &u).unwrap();
    let mut f = vec![0.0; n];
    s.residual(0.0, &x0, &mut f).unwrap();
    let dtau = horizon / n as f64;
    for (i, fi) in f.iter().enumerate() {
        let e = 1e-6;
        let mut up = u.clone();
        let mut um = u.clone();
        up[i] += e;
        um[i] -= e;
        let g = (Pendulum::cost(&x0, &up, horizon) - Pendulum::cost(&x0, &um, horizon)) / (2.0 * e);
        // Central difference: truncation O(e²·J''') ≈ 1e-12, rounding O(ε J / e) ≈ 1e-10.
        assert!(
            (fi * dtau - g).abs() <= 1e-8 * (1.0 + g.abs()),
            "stage {i}: F·Δτ = {:e}, dJ/du = {g:e}",
            fi * dtau
        );
    }
    // Newton on the full horizon converges for this problem, and the solution is a
    // stationary point of the cost computed by rollouts alone.
    let rep = s
        .initialize(0.0, &x0, &[0.0], &InitOptions::default())
        .unwrap();
    assert!(rep.residual <= 1e-8);
    let sol = s.sequence().to_vec();
    for i in 0..n {
        let e = 1e-6;
        let mut up = sol.clone();
        let mut um = sol.clone();
        up[i] += e;
        um[i] -= e;
        let g = (Pendulum::cost(&x0, &up, horizon) - Pendulum::cost(&x0, &um, horizon)) / (2.0 * e);
        assert!(g.abs() <= 1e-8, "stage {i}: dJ/du = {g:e} at the solution");
    }
}

// ---------------------------------------------------------------------------------------------
// Input bounds by dummy inputs: a case whose constrained optimum is known in closed form.

#[derive(Clone)]
struct Integrator;

impl OptimalControlProblem for Integrator {
    fn nx(&self) -> usize {
        1
    }
    fn nu(&self) -> usize {
        1
    }
    fn state_equation(&self, _t: f64, _x: &[f64], u: &[f64], dx: &mut [f64]) {
        dx[0] = u[0];
    }
    fn hamiltonian_x(&self, _t: f64, x: &[f64], _u: &[f64], _l: &[f64], hx: &mut [f64]) {
        hx[0] = x[0];
    }
    fn hamiltonian_u(&self, _t: f64, _x: &[f64], u: &[f64], l: &[f64], hu: &mut [f64]) {
        hu[0] = u[0] + l[0];
    }
    fn terminal_gradient(&self, _t: f64, x: &[f64], phix: &mut [f64]) {
        phix[0] = x[0];
    }
}

#[test]
fn bounded_input_reaches_the_closed_form_constrained_optimum() {
    // ẋ = u, L = ½x² + ½u², φ = ½x², x0 = 5, |u| ≤ 1, T = 1. Over the horizon x ≥ 4 > 0, so
    // every discrete costate λ_{i+1} ≥ x_N ≥ 4 and ∂J/∂u_i = Δτ(u_i + λ_{i+1}) > 0 for all
    // feasible u: the constrained optimum is u_i = −1 at every stage (KKT of the box).
    let w = 0.01;
    let p = InputBounds::new(Integrator, vec![InputBound::symmetric(0, 1.0, w)]).unwrap();
    let guess = p.stage_guess(&[-0.5]).unwrap();
    assert_eq!(guess.len(), 3);
    let n = 10;
    let opts = CgmresOptions {
        horizon: Horizon::Fixed { length: 1.0 },
        grid_points: n,
        ..Default::default()
    };
    let mut s = Cgmres::new(p, opts).unwrap();
    let rep = s
        .initialize(0.0, &[5.0], &guess, &InitOptions::default())
        .unwrap();
    assert!(rep.residual <= 1e-8);
    for stage in s.sequence().chunks(3) {
        let (u, v, rho) = (stage[0], stage[1], stage[2]);
        // At the solution ρ = w/(2v) and u(1 + 2ρ) = −λ with λ ≥ 4, so v ≈ w/λ ≤ 2.5e-3 and
        // u = −√(1 − v²) ≥ −1 + 3.2e-6: within 1e-5 of the bound.
        assert!((u + 1.0).abs() < 1e-5, "u = {u}");
        assert!(v > 0.0 && rho > 0.0);
        assert!((u * u + v * v - 1.0).abs() < 1e-8);
    }
}

// ---------------------------------------------------------------------------------------------
// Errors.

#[test]
fn bad_options_and_inputs_are_typed_errors() {
    let bad = [
        CgmresOptions {
            grid_points: 0,
            ..Default::default()
        },
        CgmresOptions {
            zeta: -1.0,
            ..Default::default()
        },
        CgmresOptions {
            difference_step: f64::NAN,
            ..Default::default()
        },
        CgmresOptions {
            gmres_iterations: 0,
            ..Default::default()
        },
        CgmresOptions {
            horizon: Horizon::Growing {
                final_length: 0.5,
                rate: 0.0,
            },
            ..Default::default()
        },
        CgmresOptions {
            horizon: Horizon::Fixed { length: -1.0 },
            ..Default::default()
        },
    ];
    for o in bad {
        assert!(matches!(
            Cgmres::new(Integrator, o),
            Err(ControlError::InvalidParameter { .. })
        ));
    }
    let mut s = Cgmres::new(Integrator, CgmresOptions::default()).unwrap();
    assert!(matches!(
        s.update(0.0, &[1.0], 1e-3),
        Err(ControlError::NotApplicable { .. })
    ));
    assert!(matches!(
        s.initialize(0.0, &[1.0, 2.0], &[0.0], &InitOptions::default()),
        Err(ControlError::DimensionMismatch { .. })
    ));
    s.initialize(0.0, &[1.0], &[0.0], &InitOptions::default())
        .unwrap();
    assert!(matches!(
        s.update(0.001, &[f64::NAN], 1e-3),
        Err(ControlError::NonFinite { .. })
    ));
    assert!(matches!(
        s.update(0.001, &[1.0], 0.0),
        Err(ControlError::InvalidParameter { .. })
    ));
    assert!(matches!(
        InputBounds::new(Integrator, vec![InputBound::symmetric(1, 1.0, 0.01)]),
        Err(ControlError::InvalidParameter { .. })
    ));
    assert!(matches!(
        InputBounds::new(Integrator, vec![InputBound::symmetric(0, 1.0, 0.0)]),
        Err(ControlError::InvalidParameter { .. })
    ));
    let p = InputBounds::new(Integrator, vec![InputBound::symmetric(0, 1.0, 0.01)]).unwrap();
    assert!(matches!(
        p.stage_guess(&[1.5]),
        Err(ControlError::InvalidParameter { .. })
    ));
}
