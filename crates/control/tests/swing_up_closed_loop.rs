//! Swing-up on the nonlinear plants through the sampled-data loop (1 ms, zero-order hold),
//! on the plain model and on the rig preset "with quantizer" (encoders, pseudo-differentiated
//! velocities, ±5 V, 16-bit D/A) — book example `p2c323_ex1_cdip_swing_up` and the
//! energy-shaping laws for both rigs.
//!
//! "Upright and holding" is checked as `|wrap(θ)| ≤ 1°` from 4 s after the switch to the end:
//! the balancing phase on the quantised rig keeps a limit cycle of a few encoder counts
//! (2π/14400 rad = 0.025° each), far inside that. The cart track is taken as `|z| ≤ 0.5 m`
//! (neither the book nor its records give the rail length; its swing-up figure spans ±0.4 m).

mod common;

use common::{column, diag, max_abs_after, quantized};
use pendulab_control::sliding_mode::{
    ReducedWeight, RegularForm, SlidingModeController, lq_sliding_surface,
};
use pendulab_control::swing_up::{
    ArmEnergyShaping, CartEnergyShaping, EnergyPumping, EnergyShapingGains, swing_up_then_balance,
    wrap_angle,
};
use pendulab_lti::design::lqr;
use pendulab_plants::{
    ArmEquilibrium, ArmPendulum, CartEquilibrium, CartPendulum, CartPendulumState, RigSpec,
};
use pendulab_sim::controllers::StaticStateFeedback;
use pendulab_sim::rig::RigChains;
use pendulab_sim::{SampledLoop, SampledOptions, SampledRun};
use std::f64::consts::PI;

const RAIL: f64 = 0.5;
const UPRIGHT: f64 = PI / 180.0;

fn preset(quantised: bool, rig: &RigSpec) -> RigChains {
    if quantised {
        quantized(rig)
    } else {
        RigChains::plain(4)
    }
}

/// The book's swing-up: energy pumping K₁ = 0.8, switch at |θ| ≤ π/4 to sliding mode on the
/// LQ-optimal surface (Q = diag(10, 100, 1, 1), the book script's weighting), K₂ = 30.
fn book_swing_up(delta: f64, quantised: bool) -> SampledRun {
    let plant = CartPendulum::book();
    let lin = plant.linearize(CartEquilibrium::upright()).unwrap();
    let surface = lq_sliding_surface(
        lin.a(),
        lin.b(),
        &diag(&[10.0, 100.0, 1.0, 1.0]),
        RegularForm::BookShear,
        ReducedWeight::BookScript,
    )
    .unwrap();
    let smc = SlidingModeController::from_surface(&surface, lin.a(), lin.b(), 30.0, delta).unwrap();
    let c = swing_up_then_balance(
        EnergyPumping::new(&plant, 0.8).unwrap(),
        smc,
        vec![(1, PI / 4.0)],
    )
    .unwrap();
    let mut l = SampledLoop::new(
        plant,
        c,
        SampledOptions {
            t_final: 16.0,
            ..Default::default()
        },
    )
    .unwrap()
    .with_rig(preset(quantised, &RigSpec::cart()))
    .unwrap();
    l.run(&[0.1, PI + 0.001, 0.0, 0.0]).unwrap()
}

fn check_upright(run: &SampledRun, angle: usize, what: &str) -> f64 {
    assert_eq!(
        run.diagnostics.switch_times.len(),
        1,
        "{what}: exactly one switch expected, got {:?}",
        run.diagnostics.switch_times
    );
    let ts = run.diagnostics.switch_times[0];
    let t = run.trajectory.t();
    let th: Vec<f64> = column(run.trajectory.x(), angle)
        .iter()
        .map(|v| wrap_angle(*v))
        .collect();
    let hold = max_abs_after(t, &th, ts + 4.0);
    assert!(
        ts + 4.0 < *t.last().unwrap() && hold <= UPRIGHT,
        "{what}: switch at {ts} s, then max |θ| = {hold} rad"
    );
    ts
}

#[test]
fn book_swing_up_reaches_and_holds_the_upright_within_the_rail() {
    for quantised in [false, true] {
        let mut switch = Vec::new();
        for delta in [0.0, 5.0] {
            let what = format!("δ = {delta}, quantised rig {quantised}");
            let run = book_swing_up(delta, quantised);
            switch.push(check_upright(&run, 1, &what));
            let z = column(run.trajectory.x(), 0);
            let zmax = max_abs_after(run.trajectory.t(), &z, 0.0);
            assert!(zmax <= RAIL, "{what}: |z| reached {zmax} m");
        }
        // The swing-up phase does not depend on δ (only the balancing law does), so both runs
        // switch at the same sample.
        assert_eq!(switch[0], switch[1]);
    }
}

#[test]
fn book_pumping_never_loses_more_energy_than_friction_and_the_hold_take() {
    // On the plain model the book's law, applied continuously, gives
    // Ė = m l K₁(θ̇ cos θ)² − μθ̇² ≥ −μθ̇². Sampled and held, the acceleration uses
    // θ̇ₖ cos θₖ of the last sample, and Ė = m l K₁ (θ̇ cos θ)(θ̇ₖ cos θₖ) − μθ̇² can dip below
    // zero inside a sample by at most m l K₁ |θ̇|·|θ̇ cos θ − θ̇ₖ cos θₖ| with the mismatch
    // bounded by (|θ̈| + θ̇²) dt. So over one sample
    // ΔE ≥ −dt [μ w² + m l K₁ w (a + w²) dt], w = max|θ̇|, a = max|θ̈| — taken at the two
    // endpoints with a 10 % allowance for their variation inside 1 ms.
    let plant = CartPendulum::book();
    let p = *plant.params();
    let run = book_swing_up(0.0, false);
    let ts = run.diagnostics.switch_times[0];
    let (x, u, t) = (run.trajectory.x(), run.trajectory.u(), run.trajectory.t());
    let state = |i: usize| [x[(i, 0)], x[(i, 1)], x[(i, 2)], x[(i, 3)]];
    let energy = |i: usize| plant.energy(&CartPendulumState::from_array(state(i)));
    let k1 = 0.8;
    let mut k = 0;
    while t[k + 1] < ts {
        let dt = t[k + 1] - t[k];
        let w = x[(k, 3)].abs().max(x[(k + 1, 3)].abs());
        let a = plant.derivative_array(&state(k), u[(k, 0)])[3]
            .abs()
            .max(plant.derivative_array(&state(k + 1), u[(k, 0)])[3].abs());
        let bound = 1.1 * dt * (p.mu_p * w * w + p.m_p * p.l_p * k1 * w * (a + w * w) * dt);
        assert!(
            energy(k + 1) >= energy(k) - bound,
            "energy fell from {} to {} at t = {} (bound {bound:e})",
            energy(k),
            energy(k + 1),
            t[k]
        );
        k += 1;
    }
    assert!(k > 1000, "the pumping phase lasted {k} samples only");
}

#[test]
fn energy_shaping_swings_the_cart_pendulum_up() {
    let plant = CartPendulum::book();
    let lin = plant.linearize(CartEquilibrium::upright()).unwrap();
    let k = lqr(&lin, &diag(&[10.0, 10.0, 0.0, 0.0]), &diag(&[1.0]), None)
        .unwrap()
        .gain;
    for quantised in [false, true] {
        let c = swing_up_then_balance(
            CartEnergyShaping::new(&plant, EnergyShapingGains::cart_rig()).unwrap(),
            StaticStateFeedback::new(k.clone()).unwrap(),
            vec![(1, 0.3)],
        )
        .unwrap();
        let mut l = SampledLoop::new(
            plant,
            c,
            SampledOptions {
                t_final: 20.0,
                ..Default::default()
            },
        )
        .unwrap()
        .with_rig(preset(quantised, &RigSpec::cart()))
        .unwrap();
        let run = l.run(&[0.0, PI + 0.001, 0.0, 0.0]).unwrap();
        let what = format!("cart energy shaping, quantised rig {quantised}");
        check_upright(&run, 1, &what);
        let z = column(run.trajectory.x(), 0);
        let zmax = max_abs_after(run.trajectory.t(), &z, 0.0);
        assert!(zmax <= RAIL, "{what}: |z| reached {zmax} m");
    }
}

#[test]
fn energy_shaping_swings_the_arm_pendulum_up_from_arm_up_and_arm_down() {
    let plant = ArmPendulum::book();
    let lin = plant.linearize(ArmEquilibrium::upright(0.0)).unwrap();
    let k = lqr(&lin, &diag(&[5.0, 10.0, 0.1, 0.1]), &diag(&[1.0]), None)
        .unwrap()
        .gain;
    for x0 in [[0.0, PI + 0.001, 0.0, 0.0], [PI, PI + 0.001, 0.0, 0.0]] {
        for quantised in [false, true] {
            // The balancing LQR sees both angles wrapped (θ₁ may have wound up by 2π).
            let c = swing_up_then_balance(
                ArmEnergyShaping::new(&plant, EnergyShapingGains::arm_rig()).unwrap(),
                StaticStateFeedback::new(k.clone()).unwrap(),
                vec![(0, PI), (1, 0.3)],
            )
            .unwrap();
            let mut l = SampledLoop::new(
                plant,
                c,
                SampledOptions {
                    t_final: 20.0,
                    ..Default::default()
                },
            )
            .unwrap()
            .with_rig(preset(quantised, &RigSpec::arm()))
            .unwrap();
            let run = l.run(&x0).unwrap();
            let what = format!("arm energy shaping from {x0:?}, quantised rig {quantised}");
            let ts = check_upright(&run, 1, &what);
            // The arm ends near its upright too (the LQR's equilibrium θ₁ = 0 mod 2π).
            let th1: Vec<f64> = column(run.trajectory.x(), 0)
                .iter()
                .map(|v| wrap_angle(*v))
                .collect();
            let arm = max_abs_after(run.trajectory.t(), &th1, ts + 4.0);
            assert!(arm <= 2.0 * UPRIGHT, "{what}: arm at {arm} rad");
        }
    }
}
