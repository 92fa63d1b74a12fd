#![cfg(feature = "lmi")]
//! The constrained linear MPC (`pendulab_control::mpc`): its QP method against Clarabel and
//! the KKT conditions, its unconstrained law against the discrete LQR, infeasibility, and the
//! closed loop on the nonlinear cart pendulum with voltage and track limits.

mod common;

use common::{column, diag};
use pendulab_control::ControlError;
use pendulab_control::inspect::{Inspected, Update};
use pendulab_control::mpc::{
    DualActiveSetQp, LinearMpc, MpcController, MpcSettings, QpOptions, QpStatus, StateBound,
    Terminal, WarmStart, kkt_residuals,
};
use pendulab_lti::design::lqr;
use pendulab_lti::{Discretization, Mat};
use pendulab_plants::{CartEquilibrium, CartPendulum};
use pendulab_sim::{Controller, SampledLoop, SampledOptions};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The closed-loop case: prediction step 10 ms, horizon 20 (0.2 s), `Q = diag(100, 100, 0, 0)`,
/// `R = 0.01` (aggressive: the unconstrained law asks for ±20 V from 10°), `|u| ≤ 5 V`, track
/// `|z| ≤ 0.08 m` (from 10° with 5 V the cart needs about that much: at 0.07 m the MPC keeps
/// the track and loses the pendulum).
const DT: f64 = 0.01;
const HORIZON: usize = 20;
const U_MAX: f64 = 5.0;
const TRACK: f64 = 0.08;

fn settings(track: Option<f64>) -> MpcSettings {
    MpcSettings {
        horizon: HORIZON,
        q: diag(&[100.0, 100.0, 0.0, 0.0]),
        r: diag(&[0.01]),
        terminal: Terminal::Dare,
        u_min: vec![-U_MAX],
        u_max: vec![U_MAX],
        du_max: None,
        state_bounds: track
            .map(|t| {
                vec![StateBound {
                    index: 0,
                    min: -t,
                    max: t,
                }]
            })
            .unwrap_or_default(),
        qp: QpOptions::default(),
    }
}

fn cart_mpc(s: &MpcSettings) -> LinearMpc {
    let lin = CartPendulum::book()
        .linearize(CartEquilibrium::upright())
        .unwrap();
    LinearMpc::sampled(&lin, DT, s).unwrap()
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Clarabel's minimiser of `½uᵀHu + gᵀu s.t. Gu ≤ w` at `tol`: 1e-10 on the random QPs, 1e-12
/// on the cart's (they are
/// degenerate, many rows active at once; at 1e-10 Clarabel's plan is still 2e-5 from the exact
/// one, at 1e-12 within 5e-7, while its objective approaches ours from above).
fn clarabel(h: &Mat, g: &[f64], a: &Mat, w: &[f64], tol: f64) -> Vec<f64> {
    let ans = pendulab_lmi::solve_qp(h, g, a, w, tol).unwrap();
    assert!(ans.solved, "Clarabel: {}", ans.status);
    ans.x
}

#[test]
fn the_qp_method_equals_clarabel_on_random_feasible_instances() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut active_seen = 0;
    for case in 0..40 {
        let n = rng.random_range(2..25);
        let m = rng.random_range(1..3 * n);
        let l = Mat::from_fn(n, n, |_, _| rng.random_range(-1.0..1.0));
        let h = &l * l.transpose() + Mat::identity(n, n) * 0.1;
        let a = Mat::from_fn(m, n, |_, _| rng.random_range(-1.0..1.0));
        // Feasible by construction: w = G z₀ + slack, a third of the slacks zero.
        let z0: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
        let az0 = &a * nalgebra::DVector::from_column_slice(&z0);
        let w: Vec<f64> = (0..m)
            .map(|i| {
                az0[i]
                    + if rng.random_bool(1.0 / 3.0) {
                        0.0
                    } else {
                        rng.random_range(0.0..1.0)
                    }
            })
            .collect();
        let g: Vec<f64> = (0..n).map(|_| rng.random_range(-5.0..5.0)).collect();
        let mut qp = DualActiveSetQp::new(&h, &a, QpOptions::default()).unwrap();
        assert_eq!(
            qp.solve(&g, &w, &[]).unwrap(),
            QpStatus::Solved,
            "case {case}"
        );
        let mine = qp.solution().to_vec();
        active_seen += qp.active_set().len();
        let theirs = clarabel(&h, &g, &a, &w, 1e-10);
        let scale = 1.0 + theirs.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(
            max_abs_diff(&mine, &theirs) < 1e-6 * scale,
            "case {case}: n {n}, m {m}: {:e}",
            max_abs_diff(&mine, &theirs)
        );
        let r = kkt_residuals(&h, &g, &a, &w, &mine, qp.multipliers()).unwrap();
        assert!(
            r.stationarity < 1e-9 && r.primal < 1e-9 && r.dual == 0.0 && r.complementarity < 1e-9,
            "case {case}: {r:?}"
        );
        // A warm start from any working set (here: the first half of the rows) ends at the same
        // point.
        let warm: Vec<usize> = (0..m / 2).collect();
        assert_eq!(qp.solve(&g, &w, &warm).unwrap(), QpStatus::Solved);
        assert!(max_abs_diff(qp.solution(), &mine) < 1e-9, "case {case}");
    }
    // The instances exercise the active set (not only unconstrained minima).
    assert!(active_seen > 100, "{active_seen}");
}

/// The QP of the cart's MPC at a state.
fn cart_qp_at(mpc: &LinearMpc, x0: &[f64], u_prev: f64) -> (Vec<f64>, Vec<f64>) {
    let mut g = vec![0.0; mpc.hessian().nrows()];
    let mut w = vec![0.0; mpc.constraint_matrix().nrows()];
    mpc.qp_vectors(x0, &[u_prev], &mut g, &mut w).unwrap();
    (g, w)
}

#[test]
fn the_carts_mpc_qp_equals_clarabel_with_voltage_track_and_rate_limits_active() {
    let mut s = settings(Some(TRACK));
    s.du_max = Some(vec![2.0]);
    let mut mpc = cart_mpc(&s);
    // 20 inputs; per stage 2 voltage rows, 2 rate rows, 2 track rows.
    assert_eq!(mpc.hessian().nrows(), 20);
    assert_eq!(mpc.rows_per_stage(), 6);
    let (h, a) = (mpc.hessian().clone(), mpc.constraint_matrix().clone());
    let mut kinds = [0usize; 3];
    for (x0, u_prev) in [
        ([0.0, 10f64.to_radians(), 0.0, 0.0], 0.0),
        ([0.03, 8f64.to_radians(), 0.2, 0.3], 1.0),
        ([-0.05, -5f64.to_radians(), -0.3, 0.5], -4.0),
        ([0.0, 2f64.to_radians(), 0.0, 0.0], 0.0),
    ] {
        let status = mpc.solve(&x0, &[u_prev], WarmStart::Cold).unwrap();
        assert_eq!(status, QpStatus::Solved, "{x0:?}");
        let (g, w) = cart_qp_at(&mpc, &x0, u_prev);
        let theirs = clarabel(&h, &g, &a, &w, 1e-12);
        assert!(
            max_abs_diff(mpc.plan(), &theirs) < 1e-6,
            "{x0:?}: {:e}",
            max_abs_diff(mpc.plan(), &theirs)
        );
        let r = kkt_residuals(&h, &g, &a, &w, mpc.plan(), mpc.qp().multipliers()).unwrap();
        assert!(
            r.stationarity < 1e-8 && r.primal < 1e-9 && r.complementarity < 1e-9,
            "{r:?}"
        );
        for &row in mpc.qp().active_set() {
            kinds[(row % 6) / 2] += 1;
        }
    }
    // Each kind of limit is active somewhere: voltage, rate and track.
    assert!(kinds.iter().all(|&k| k > 0), "{kinds:?}");
}

#[test]
fn without_active_constraints_the_first_move_is_the_discrete_lqr_law() {
    // With P the DARE solution the tail of the horizon is the infinite-horizon cost to go, so
    // the unconstrained plan starts with u₀ = −K x₀ for the discrete LQR gain K (Bellman):
    // K from lti's lqr on the same sampled model, computed independently of the condensing.
    let lin = CartPendulum::book()
        .linearize(CartEquilibrium::upright())
        .unwrap();
    let d = lin.c2d(DT, Discretization::Zoh).unwrap();
    let s = settings(None);
    let k = lqr(&d, &s.q, &s.r, None).unwrap().gain;
    for horizon in [1, 5, 20] {
        let mut mpc = LinearMpc::new(
            d.a(),
            d.b(),
            &MpcSettings {
                horizon,
                u_min: vec![-1e3],
                u_max: vec![1e3],
                ..s.clone()
            },
        )
        .unwrap();
        for x0 in [[0.0, 0.1, 0.0, 0.0], [0.05, -0.02, 0.3, -0.4]] {
            assert_eq!(
                mpc.solve(&x0, &[0.0], WarmStart::Cold).unwrap(),
                QpStatus::Solved
            );
            assert!(mpc.qp().active_set().is_empty());
            let u_lqr: f64 = -(0..4).map(|j| k[(0, j)] * x0[j]).sum::<f64>();
            let u0 = mpc.plan()[0];
            assert!(
                (u0 - u_lqr).abs() < 1e-9 * (1.0 + u_lqr.abs()),
                "N = {horizon}: {u0} vs {u_lqr}"
            );
        }
        assert!(
            (mpc.lq_gain() - &k).amax() < 1e-9 * k.amax(),
            "{}",
            mpc.lq_gain()
        );
    }
}

#[test]
fn infeasible_limits_give_the_status_with_a_farkas_certificate() {
    // The cart 0.3 m beyond a ±0.08 m track, at rest: with |u| ≤ 5 V it cannot be back within
    // one 10 ms step, so the stage-1 track row already has no solution.
    let mut mpc = cart_mpc(&settings(Some(TRACK)));
    let x0 = [0.38, 0.0, 0.0, 0.0];
    assert_eq!(
        mpc.solve(&x0, &[0.0], WarmStart::Cold).unwrap(),
        QpStatus::Infeasible
    );
    let y = mpc.qp().certificate().unwrap().to_vec();
    let (_, w) = cart_qp_at(&mpc, &x0, 0.0);
    let a = mpc.constraint_matrix();
    assert!(y.iter().all(|&v| v >= 0.0));
    let yt_a = a.transpose() * nalgebra::DVector::from_column_slice(&y);
    let yt_w: f64 = y.iter().zip(&w).map(|(p, q)| p * q).sum();
    let size: f64 = y.iter().sum();
    assert!(yt_a.amax() < 1e-9 * size, "{:e}", yt_a.amax());
    assert!(yt_w < -1e-3 * size, "{yt_w}");
    // Clarabel agrees that it is infeasible.
    let ans = pendulab_lmi::solve_qp(mpc.hessian(), &[0.0; 20], a, &w, 1e-10).unwrap();
    assert_eq!(ans.status, "PrimalInfeasible");
    // Settings that admit no point are refused when the MPC is built, naming the key.
    let mut bad = settings(Some(TRACK));
    bad.u_min = vec![1.0];
    bad.u_max = vec![-1.0];
    let lin = CartPendulum::book()
        .linearize(CartEquilibrium::upright())
        .unwrap();
    let e = LinearMpc::sampled(&lin, DT, &bad).unwrap_err();
    assert!(
        matches!(&e, ControlError::InvalidParameter { name, .. } if name == "u_min[0]"),
        "{e}"
    );
    bad = settings(Some(TRACK));
    bad.state_bounds[0].index = 4;
    let e = LinearMpc::sampled(&lin, DT, &bad).unwrap_err();
    assert!(e.to_string().contains("state_bounds[0].index"), "{e}");
    bad = settings(Some(TRACK));
    bad.du_max = Some(vec![0.0]);
    assert!(
        LinearMpc::sampled(&lin, DT, &bad)
            .unwrap_err()
            .to_string()
            .contains("du_max")
    );
}

/// The worst KKT residual and Clarabel distance over the solves of an inspected MPC.
struct Checks {
    worst_kkt: f64,
    worst_clarabel: f64,
    clarabel_every: usize,
    count: usize,
}

/// The inspector (`pendulab_control::inspect`): every solve's KKT residuals, and every
/// `clarabel_every`-th against Clarabel.
fn check_solve(s: &mut Checks, c: &MpcController, _: &Update<'_>) {
    let mpc = c.mpc();
    let (g, w) = mpc.last_qp_vectors();
    let (h, a) = (mpc.hessian(), mpc.constraint_matrix());
    let r = kkt_residuals(h, g, a, w, mpc.plan(), mpc.qp().multipliers()).unwrap();
    s.worst_kkt = s
        .worst_kkt
        .max(r.stationarity)
        .max(r.primal)
        .max(r.dual)
        .max(r.complementarity);
    if s.count.is_multiple_of(s.clarabel_every) {
        let theirs = clarabel(h, g, a, w, 1e-12);
        s.worst_clarabel = s.worst_clarabel.max(max_abs_diff(mpc.plan(), &theirs));
    }
    s.count += 1;
}

/// Clipped discrete LQR `u = clamp(−K x, ±5 V)` with the MPC's `K`.
struct ClippedLqr(Mat);

impl Controller for ClippedLqr {
    fn ny(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {}
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        let v: f64 = -(0..4).map(|j| self.0[(0, j)] * y[j]).sum::<f64>();
        u[0] = v.clamp(-U_MAX, U_MAX);
    }
}

struct Outcome {
    max_abs_z: f64,
    max_abs_u: f64,
    final_state: Vec<f64>,
}

fn run<C: Controller, T>(
    c: C,
    x0: &[f64],
    t_final: f64,
    inspect: impl FnOnce(&C) -> T,
) -> (Outcome, T) {
    let mut l = SampledLoop::new(
        CartPendulum::book(),
        c,
        SampledOptions {
            t_final,
            ..Default::default()
        },
    )
    .unwrap();
    let r = l.run(x0).unwrap();
    let x = r.trajectory.x();
    let z = column(x, 0);
    let out = Outcome {
        max_abs_z: z.iter().fold(0.0, |m, v| m.max(v.abs())),
        max_abs_u: r.commands.iter().fold(0.0, |m: f64, v| m.max(v.abs())),
        final_state: r.diagnostics.final_state.clone(),
    };
    (out, inspect(l.controller()))
}

#[test]
fn on_the_nonlinear_cart_from_10_degrees_the_mpc_keeps_5_v_and_the_track_and_balances() {
    let mpc = cart_mpc(&settings(Some(TRACK)));
    let k = mpc.lq_gain().clone();
    let periods = (DT / 1e-3).round() as usize;
    let ctrl = MpcController::new(mpc, 1e-3, periods, &[0.0; 4], &[-U_MAX], &[U_MAX]).unwrap();
    let x0 = [0.0, 10f64.to_radians(), 0.0, 0.0];
    let (mpc_run, checked) = run(
        Inspected::new(
            ctrl,
            Checks {
                worst_kkt: 0.0,
                worst_clarabel: 0.0,
                clarabel_every: 25,
                count: 0,
            },
            check_solve,
        ),
        &x0,
        5.0,
        |c| {
            (
                *c.inner.statistics(),
                c.state.worst_kkt,
                c.state.worst_clarabel,
            )
        },
    );
    let (stats, worst_kkt, worst_clarabel) = checked;
    assert_eq!(stats.solves, 5001);
    assert_eq!(stats.infeasible + stats.max_iterations_hit, 0, "{stats:?}");
    // Limits at every sample: the voltage by construction of the QP, the track on the
    // nonlinear plant (the prediction is linear; a hair of model error is allowed).
    assert!(mpc_run.max_abs_u <= U_MAX + 1e-12, "{}", mpc_run.max_abs_u);
    assert!(mpc_run.max_abs_z <= TRACK * 1.02, "{}", mpc_run.max_abs_z);
    // The voltage limit is reached (the constraints are active) and it balances.
    assert!(mpc_run.max_abs_u > U_MAX - 1e-9, "{}", mpc_run.max_abs_u);
    assert!(
        mpc_run.final_state.iter().all(|v| v.abs() < 1e-3),
        "{:?}",
        mpc_run.final_state
    );
    assert!(worst_kkt < 1e-8, "{worst_kkt:e}");
    assert!(worst_clarabel < 1e-6, "{worst_clarabel:e}");
    // The same gain clipped to ±5 V leaves the track (measured on the same scenario).
    let (lqr_run, _) = run(ClippedLqr(k), &x0, 5.0, |_| ());
    assert!(lqr_run.max_abs_z > TRACK * 1.05, "{}", lqr_run.max_abs_z);
    eprintln!(
        "mpc: max |z| {:.4} m, max |u| {:.3} V, final {:?}, mean iterations {:.2}, max {}; \
         clipped LQR: max |z| {:.4} m, final {:?}",
        mpc_run.max_abs_z,
        mpc_run.max_abs_u,
        mpc_run.final_state,
        stats.total_iterations as f64 / stats.solves as f64,
        stats.max_iterations,
        lqr_run.max_abs_z,
        lqr_run.final_state
    );
}

#[test]
fn a_warm_start_reaches_the_cold_answer_in_fewer_iterations_along_the_closed_loop() {
    // The closed loop's QPs solved twice: shifted warm start (as the controller does) and cold.
    let mpc = cart_mpc(&settings(Some(TRACK)));
    let periods = (DT / 1e-3).round() as usize;
    let ctrl = MpcController::new(mpc, 1e-3, periods, &[0.0; 4], &[-U_MAX], &[U_MAX]).unwrap();
    let x0 = [0.0, 10f64.to_radians(), 0.0, 0.0];
    let mut l = SampledLoop::new(
        CartPendulum::book(),
        ctrl,
        SampledOptions {
            t_final: 1.0,
            ..Default::default()
        },
    )
    .unwrap();
    let r = l.run(&x0).unwrap();
    let warm_total = l.controller().statistics().total_iterations;
    let mut cold = cart_mpc(&settings(Some(TRACK)));
    let (x, cmd) = (r.trajectory.x(), &r.commands);
    let mut cold_total = 0;
    let mut u_prev = 0.0;
    for k in 0..x.nrows() {
        let xk: Vec<f64> = (0..4).map(|j| x[(k, j)]).collect();
        assert_eq!(
            cold.solve(&xk, &[u_prev], WarmStart::Cold).unwrap(),
            QpStatus::Solved
        );
        cold_total += cold.qp().iterations() as u64;
        assert!((cold.plan()[0] - cmd[(k, 0)]).abs() < 1e-9, "sample {k}");
        u_prev = cmd[(k, 0)];
    }
    assert!(
        warm_total < cold_total,
        "warm {warm_total}, cold {cold_total}"
    );
    eprintln!("iterations over 1 s: warm {warm_total}, cold {cold_total}");
}
