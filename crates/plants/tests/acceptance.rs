//! Acceptance of the simulator on the two rigs (issue 3) that the unit-level tests do not
//! cover: the book's nonlinear cart P-control run (`p1c34_cdip_plot_pcont`), the IP Toolbox
//! LQR samples on the nonlinear plants through the sampled-data loop, plain and with the
//! quantised-rig preset (`cdip_lqr_sim`, `adip_lqr_sim`), and energy conservation with
//! Dormand–Prince at `rtol = 1e-12` (the RK4 half is in `cart.rs` / `arm.rs`).
//!
//! Items of the acceptance list covered elsewhere: RK4 against the committed Python
//! RK4 and Dopri45 against `expm` (`crates/sim/tests/integrators.rs`), the pulse test of the
//! sampled loop (`crates/sim/tests/sampled.rs`), energy with RK4 at 1e-4 s
//! (`cart.rs`, `arm.rs`, `two_pendulum.rs` here), bad input: non-positive/non-finite masses
//! and lengths (`invalid_parameters_are_typed_errors` in `cart.rs`, `arm.rs`,
//! `two_pendulum.rs`), `ts ≤ 0` and a NaN initial state (`bad_configurations_are_typed_errors`
//! in `crates/sim/tests/sampled.rs`, `bad_inputs_are_typed_errors` in `integrators.rs`).
//! `nan_initial_state_of_a_rig_is_a_typed_error` below repeats the last one on the real plants.

use pendulab_lti::Mat;
use pendulab_lti::design::{StateFeedback, lqr};
use pendulab_plants::{
    ArmEquilibrium, ArmPendulum, ArmPendulumParams, CartEquilibrium, CartPendulum,
    CartPendulumParams, RigSpec,
};
use pendulab_sim::controllers::StaticStateFeedback;
use pendulab_sim::rig::RigChains;
use pendulab_sim::scenario::Imperfections;
use pendulab_sim::{
    Dynamics, Integrator, OdeOptions, RunStatus, SampledLoop, SampledOptions, SampledRun, SimError,
    StateFeedbackLoop, StayWithin, simulate_free,
};
use std::f64::consts::PI;

/// The rig preset "with quantizer" (`docs/model.md` §3): the rig's own chains with
/// encoders, pseudo-differentiated velocities, saturation and D/A.
fn quantized(rig: &RigSpec) -> RigChains {
    rig.chains(&Imperfections::with_quantizer()).unwrap()
}

fn diag(d: &[f64]) -> Mat {
    let mut m = Mat::zeros(d.len(), d.len());
    for (i, v) in d.iter().enumerate() {
        m[(i, i)] = *v;
    }
    m
}

fn column(x: &Mat, j: usize) -> Vec<f64> {
    (0..x.nrows()).map(|i| x[(i, j)]).collect()
}

/// Local extrema `(t, v)` of a sampled signal (strict on the left, so plateaus count once).
fn extrema(t: &[f64], v: &[f64]) -> Vec<(f64, f64)> {
    (1..v.len() - 1)
        .filter(|&k| (v[k] > v[k - 1] && v[k] >= v[k + 1]) || (v[k] < v[k - 1] && v[k] <= v[k + 1]))
        .map(|k| (t[k], v[k]))
        .collect()
}

/// `value` shows as `printed` when rounded to the printed number of decimals
/// (`|value − printed| ≤ ½·10^(−decimals)`, plus 1e-12 for the binary representation).
fn rounds_to(value: f64, printed: f64, decimals: i32) -> bool {
    (value - printed).abs() <= 0.5 * 10f64.powi(-decimals) + 1e-12
}

/// `p1c34_cdip_plot_pcont`: z, φ = θ − π of the cart P control `v = k_P (0.2 − z)`, `k_P = 10`,
/// from the hanging rest, 4 s, with the control law acting continuously and the loop
/// integrated at a fixed step `dt` by `integrator`.
fn pcont_continuous(integrator: Integrator) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let p = StateFeedback::new(Mat::from_row_slice(1, 4, &[10.0, 0.0, 0.0, 0.0])).unwrap();
    let cl = StateFeedbackLoop::new(CartPendulum::book(), &p)
        .unwrap()
        .with_reference(&[0.2, 0.0, 0.0, 0.0])
        .unwrap();
    let o = OdeOptions {
        integrator,
        output: pendulab_sim::Output::Times((0..=4000).map(|k| k as f64 * 1e-3).collect()),
        ..Default::default()
    };
    let sim = simulate_free(&cl, &[0.0, PI, 0.0, 0.0], 4.0, &o).unwrap();
    let x = sim.trajectory.x();
    let phi = column(x, 1).iter().map(|th| th - PI).collect();
    (sim.trajectory.t().to_vec(), column(x, 0), phi)
}

#[test]
fn p1c34_cart_p_control_reproduces_the_book_digits() {
    // Book part 1 §3.4 (p1c34_cdip_plot_pcont): z peaks 0.237 m at 0.54 s and settles at 0.200 m; φ
    // extrema +0.394 rad at 0.30 s, −0.701 at 0.79 s, +0.755 at 1.35 s. The book's digits come from
    // the P law acting continuously (a Simulink gain block in the continuous loop) integrated at
    // 1 ms. The same law sampled at 1 kHz with zero-order hold (an effective delay of ts/2) gives
    // +0.3950, −0.7026, +0.7567 — off in the third decimal; tools/reference/sim_p1c34.py shows both
    // with an independent plain-Python RK4. A P law reads only z, so the velocity estimate
    // (derivative + 1/(0.02 s + 1)) plays no part here.
    let rk4 = pcont_continuous(Integrator::Rk4 { dt: 1e-3 });
    // The same run by Dormand–Prince at 1e-11 (an independent algorithm; its dense output at
    // the same instants): the 1 ms RK4 is converged far below the printed digits (5e-4).
    let dp = pcont_continuous(Integrator::dopri45(1e-11, 1e-13));
    let dev = (0..rk4.0.len())
        .map(|k| (rk4.1[k] - dp.1[k]).abs().max((rk4.2[k] - dp.2[k]).abs()))
        .fold(0.0, f64::max);
    assert!(dev < 1e-8, "RK4 1 ms vs Dopri45: {dev:e}");
    for (name, (t, z, phi)) in [("RK4 1 ms", rk4), ("Dopri45", dp)] {
        let z_ext = extrema(&t, &z);
        let (tz, zp) = z_ext[0];
        assert!(
            rounds_to(zp, 0.237, 3) && rounds_to(tz, 0.54, 2),
            "{name}: z peak {zp} at {tz}"
        );
        // The first extremum is the maximum of the whole run (the overshoot).
        assert!(z.iter().all(|v| *v <= zp));
        let zf = *z.last().unwrap();
        assert!(rounds_to(zf, 0.200, 3), "{name}: z(4 s) = {zf}");
        let phi_ext = extrema(&t, &phi);
        for ((te, ve), (tb, vb)) in
            phi_ext
                .iter()
                .zip([(0.30, 0.394), (0.79, -0.701), (1.35, 0.755)])
        {
            assert!(
                rounds_to(*ve, vb, 3) && rounds_to(*te, tb, 2),
                "{name}: φ extremum {ve} at {te}, book {vb} at {tb}"
            );
        }
    }
}

/// The book's LQR design for the cart (`cdip_lqr_sim`, `Q = diag(10, 10, 0, 0)`, `R = 1`) in
/// the library's sign `u = −K x`.
fn cart_lqr() -> Mat {
    let plant = CartPendulum::book();
    let sys = plant.linearize(CartEquilibrium::upright()).unwrap();
    lqr(
        &sys,
        &diag(&[10.0, 10.0, 0.0, 0.0]),
        &Mat::identity(1, 1),
        None,
    )
    .unwrap()
    .gain
}

#[test]
fn cdip_lqr_balances_the_nonlinear_cart_plain_and_quantised() {
    let k = cart_lqr();
    // The gain is the book's K_q10 = [3.16228, 13.47175, 4.48137, 2.26289] (u = +K x, printed
    // to 5 decimals) with the sign flipped.
    for (j, b) in [3.16228, 13.47175, 4.48137, 2.26289].iter().enumerate() {
        assert!((k[(0, j)] + b).abs() <= 5e-6, "K[{j}] = {}", k[(0, j)]);
    }
    let theta0 = 15f64.to_radians();
    // One encoder count of the pendulum angle (`docs/model.md` §3).
    let count = 2.0 * PI / 14400.0;
    for quantised in [false, true] {
        let what = if quantised { "quantised rig" } else { "plain" };
        let mut l = SampledLoop::new(
            CartPendulum::book(),
            StaticStateFeedback::new(k.clone()).unwrap(),
            SampledOptions {
                t_final: 4.0,
                ..Default::default()
            },
        )
        .unwrap();
        if quantised {
            l = l.with_rig(quantized(&RigSpec::cart())).unwrap();
        }
        // Balancing means: the pendulum never tilts further than it started (a stop if it
        // does), the ±5 V amplifier never saturates (the linear design holds), and in the last
        // second θ stays within 5 encoder counts (0.11°) and z within 1 cm of the origin. The
        // design's slowest closed-loop pole (checked below) shrinks a 15° tilt by e^{σ·3 s}
        // < 1e-3 in the first 3 s; the quantised rig keeps a limit cycle of a couple of counts.
        let mut stay = StayWithin::new(1, theta0 + 1e-12);
        let run = l.run_with(&[0.0, theta0, 0.0, 0.0], &mut stay).unwrap();
        assert_eq!(run.status, RunStatus::Completed, "{what}");
        assert!(stay.held(), "{what}: tilted past θ0");
        assert_eq!(run.diagnostics.saturated_samples, 0, "{what}");
        let t = run.trajectory.t();
        let x = run.trajectory.x();
        let late: Vec<usize> = (0..t.len()).filter(|&i| t[i] >= 3.0 - 1e-9).collect();
        let th = late.iter().map(|&i| x[(i, 1)].abs()).fold(0.0, f64::max);
        let z = late.iter().map(|&i| x[(i, 0)].abs()).fold(0.0, f64::max);
        assert!(
            th <= 5.0 * count,
            "{what}: |θ| up to {th} rad in the last second"
        );
        assert!(z <= 0.01, "{what}: |z| up to {z} m in the last second");
    }
    // The decay rate used in the justification: the slowest pole of A − B K.
    let sys = CartPendulum::book()
        .linearize(CartEquilibrium::upright())
        .unwrap();
    let acl = sys.a() - sys.b() * &k;
    let slowest = pendulab_lti::linalg::eigenvalues(&acl)
        .unwrap()
        .iter()
        .map(|p| p.re)
        .fold(f64::MIN, f64::max);
    assert!((slowest * 3.0).exp() < 1e-3, "slowest pole {slowest}");
}

#[test]
fn adip_lqr_dips_match_the_toolbox_sample() {
    // adip_lqr_sim: Q = diag(q1, 10, 0.1, 0.1), R = 1, from θ1(0) = 30° with the pendulum
    // upright, 2 s, on the quantised plant with filtered derivatives at 1 ms (the IP Toolbox
    // samples' setting, here the "with quantizer" preset). The book quotes the pendulum's dip
    // as ≈ −2°, −4°, −6.7°: values read off its plot, so the tolerance is 0.1° (4 encoder
    // counts of 0.025°). Observed: −2.07°, −3.94°, −6.64°. (Not asserted: the plain plant
    // with exact velocities dips only −1.99°, −3.74°, −6.14° — the filtered velocity's lag
    // deepens the dip; a one-sample computation delay on top gives −2.09°, −3.98°, −6.72°.)
    let arm = ArmPendulum::book();
    let sys = arm.linearize(ArmEquilibrium::upright(0.0)).unwrap();
    let mut dips = Vec::new();
    for (q1, book) in [(1.0, -2.0), (5.0, -4.0), (20.0, -6.7)] {
        let k = lqr(
            &sys,
            &diag(&[q1, 10.0, 0.1, 0.1]),
            &Mat::identity(1, 1),
            None,
        )
        .unwrap()
        .gain;
        let mut l = SampledLoop::new(
            arm,
            StaticStateFeedback::new(k).unwrap(),
            SampledOptions {
                t_final: 2.0,
                ..Default::default()
            },
        )
        .unwrap()
        .with_rig(quantized(&RigSpec::arm()))
        .unwrap();
        let run: SampledRun = l.run(&[30f64.to_radians(), 0.0, 0.0, 0.0]).unwrap();
        let th2 = column(run.trajectory.x(), 1);
        let dip = th2.iter().copied().fold(f64::MAX, f64::min).to_degrees();
        assert!(
            (dip - book).abs() <= 0.1,
            "q1 = {q1}: dip {dip}° vs ≈ {book}°"
        );
        // The arm returns: |θ1| below 2° at 2 s (30° → 0 with the slowest q1 = 1 design).
        let th1 = run.diagnostics.final_state[0].to_degrees();
        assert!(th1.abs() < 2.0, "q1 = {q1}: θ1(2 s) = {th1}°");
        dips.push(dip);
    }
    // A heavier weight on the arm angle returns it faster at the price of a deeper dip.
    assert!(dips[0] > dips[1] && dips[1] > dips[2]);
}

#[test]
fn energy_is_conserved_by_dopri45_at_1e_minus_12() {
    // μ = 0, v = 0 and the drive at rest: the cart (arm) is held and the pendulum's energy is
    // a first integral. Dormand–Prince at rtol 1e-12 (atol 1e-14) over 10 s: the global error
    // stays near 1e-11 of the state, so the energy drifts ≤ 1e-9 relative (the requirement).
    let o = OdeOptions {
        integrator: Integrator::dopri45(1e-12, 1e-14),
        ..Default::default()
    };
    let cart = CartPendulum::new(CartPendulumParams {
        mu_p: 0.0,
        ..CartPendulumParams::book()
    })
    .unwrap();
    for theta0 in [0.3, 2.0, PI - 0.01] {
        let x0 = [0.1, theta0, 0.0, 1.5];
        let sim = simulate_free(&cart, &x0, 10.0, &o).unwrap();
        let e0 = cart.energy(&x0.into());
        let drift = drift(sim.trajectory.x(), |x| cart.energy(&x.into()), e0);
        assert!(drift <= 1e-9 * e0, "cart θ0 = {theta0}: {drift:e} of {e0}");
        assert_eq!(sim.trajectory.t().last().copied(), Some(10.0));
    }
    let arm = ArmPendulum::new(ArmPendulumParams {
        mu2: 0.0,
        ..ArmPendulumParams::book()
    })
    .unwrap();
    for (theta1, theta2) in [(0.0, 0.4), (0.8, 2.5), (-1.0, PI - 0.05)] {
        let x0 = [theta1, theta2, 0.0, 2.0];
        let sim = simulate_free(&arm, &x0, 10.0, &o).unwrap();
        let e0 = arm.pendulum_energy(&x0.into());
        let drift = drift(sim.trajectory.x(), |x| arm.pendulum_energy(&x.into()), e0);
        assert!(drift <= 1e-9 * e0, "arm: {drift:e} of {e0}");
    }
}

/// Largest `|E(x_k) − e0|` over the recorded states.
fn drift(x: &Mat, energy: impl Fn([f64; 4]) -> f64, e0: f64) -> f64 {
    (0..x.nrows())
        .map(|i| (energy([x[(i, 0)], x[(i, 1)], x[(i, 2)], x[(i, 3)]]) - e0).abs())
        .fold(0.0, f64::max)
}

#[test]
fn nan_initial_state_of_a_rig_is_a_typed_error() {
    let mut l = SampledLoop::new(
        CartPendulum::book(),
        StaticStateFeedback::new(cart_lqr()).unwrap(),
        SampledOptions::default(),
    )
    .unwrap()
    .with_rig(quantized(&RigSpec::cart()))
    .unwrap();
    match l.run(&[0.0, f64::NAN, 0.0, 0.0]) {
        Err(SimError::NonFiniteInitialState { index: 1, .. }) => {}
        other => panic!("expected NonFiniteInitialState at 1, got {other:?}"),
    }
    let arm = ArmPendulum::book();
    assert_eq!(arm.nx(), 4);
    match simulate_free(
        &arm,
        &[0.0, 0.0, f64::INFINITY, 0.0],
        1.0,
        &OdeOptions::default(),
    ) {
        Err(SimError::NonFiniteInitialState { index: 2, .. }) => {}
        other => panic!("expected NonFiniteInitialState at 2, got {other:?}"),
    }
}
