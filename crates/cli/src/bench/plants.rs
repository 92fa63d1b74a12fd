//! `plants-rhs`: the nonlinear right-hand sides of the pendulum plants inside a fixed-step RK4
//! loop, the innermost cost of every nonlinear simulation.
//!
//! Figure: evaluations per second of `CartPendulum::derivative_array` (through its `Dynamics`
//! implementation in the simulator's `rk4_step`; book parameters with
//! `μ_p = 0`), four per RK4 step, 10 s at 1 ms per call (40 000 evaluations). The check holds
//! the same figure for `ArmPendulum::derivative_array` and the physics evidence of the timed
//! runs: with friction removed and the drive at rest (cart/arm held) the pendulum's energy
//! must stay constant; its relative drift after 10 s of RK4 at 1 ms is `O((ω h)⁴ ω t)` ≈ 1e-7.

use super::{BenchReport, Budget, time};
use anyhow::Result;
use pendulab_plants::{ArmPendulum, ArmPendulumParams, CartPendulum, CartPendulumParams};
use pendulab_sim::{Dynamics, rk4_step};
use serde_json::json;
use std::hint::black_box;

const STEPS: usize = 10_000;
const H: f64 = 1e-3;

/// `STEPS` classic RK4 steps of `H` from `x` with the input at zero: the simulator's one
/// RK4 stepper ([`rk4_step`]) on `[f64; 4]`, four right-hand sides per step.
fn rk4<P: Dynamics>(plant: &P, mut x: [f64; 4]) -> [f64; 4] {
    for k in 0..STEPS {
        rk4_step(plant, k as f64 * H, &mut x, &[0.0], H);
    }
    x
}

/// Runs the workload.
pub fn run(budget: &Budget) -> Result<BenchReport> {
    let cart = CartPendulum::new(CartPendulumParams {
        mu_p: 0.0,
        ..CartPendulumParams::book()
    })?;
    let arm = ArmPendulum::new(ArmPendulumParams {
        mu2: 0.0,
        ..ArmPendulumParams::book()
    })?;
    let x_cart = [0.0, 2.0, 0.0, 1.5];
    let x_arm = [0.3, 2.0, 0.0, 1.5];

    let mut cart_end = x_cart;
    let t_cart = time(budget, || {
        cart_end = rk4(&cart, black_box(x_cart));
    });
    let mut arm_end = x_arm;
    let t_arm = time(budget, || {
        arm_end = rk4(&arm, black_box(x_arm));
    });

    let e0 = cart.energy(&x_cart.into());
    let cart_drift = (cart.energy(&cart_end.into()) - e0).abs() / e0;
    let e0 = arm.pendulum_energy(&x_arm.into());
    let arm_drift = (arm.pendulum_energy(&arm_end.into()) - e0).abs() / e0;
    let evals = (4 * STEPS) as f64;
    Ok(BenchReport {
        workload: "plants-rhs".into(),
        figure: evals / t_cart.median_s,
        unit: "evals/s".into(),
        check: json!({
            "figure_measures": "CartPendulum::derivative_array, 4 per RK4 step, 10 s at 1 ms",
            "cart_median_s_per_run": t_cart.median_s,
            "cart_rk4_steps_per_s": STEPS as f64 / t_cart.median_s,
            "arm_evals_per_s": evals / t_arm.median_s,
            "arm_median_s_per_run": t_arm.median_s,
            "cart_energy_relative_drift": cart_drift,
            "arm_energy_relative_drift": arm_drift,
            "cart_held": cart_end[0] == x_cart[0] && cart_end[2] == 0.0,
            "arm_held": arm_end[0] == x_arm[0] && arm_end[2] == 0.0,
        }),
    })
}
