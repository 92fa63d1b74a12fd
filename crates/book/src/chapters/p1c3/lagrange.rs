//! Part 1 §3.1: the cart pendulum's equations of motion by Lagrange's method, checked by its
//! energy balance.

use super::*;

pub(super) const ID311: &str = "p1c311_cdip_lagrange";

/// Runs the cart pendulum with input `v(t)` (sampled and held at 1 ms, plain rig) from `x0`.
pub(super) fn open_loop_cart(
    id: &'static str,
    params: CartPendulumParams,
    v: Signal,
    x0: [f64; 4],
    t_final: f64,
) -> Result<pendulab_lti::Trajectory, BookError> {
    let plant = CartPendulum::new(params).ctx(id)?;
    let opts = SampledOptions {
        t_final,
        ..Default::default()
    };
    let mut lp = SampledLoop::new(plant, OpenLoop::new(vec![v], 4), opts)
        .ctx(id)?
        .with_rig(RigChains::plain(4))
        .ctx(id)?;
    Ok(lp.run(&x0).ctx(id)?.trajectory)
}

pub(super) fn p1c311_cdip_lagrange(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let params = CartPendulumParams {
        mu_p: 0.0,
        ..CartPendulumParams::book()
    };
    let plant = CartPendulum::new(params).ctx(ID311)?;
    let energy = |tr: &pendulab_lti::Trajectory| -> Vec<f64> {
        (0..tr.len())
            .map(|k| {
                let x = CartPendulumState {
                    z: tr.x()[(k, 0)],
                    theta: tr.x()[(k, 1)],
                    dz: tr.x()[(k, 2)],
                    dtheta: tr.x()[(k, 3)],
                };
                plant.energy(&x)
            })
            .collect()
    };
    // 1) Cart at rest, no input, no friction: E must stay constant.
    let free = open_loop_cart(
        ID311,
        params,
        Signal::zero(),
        [0.0, PI - 1.0, 0.0, 0.0],
        10.0,
    )?;
    let e_free = energy(&free);
    let e0 = e_free[0];
    let drift = e_free
        .iter()
        .map(|e| (e - e0).abs() / e0)
        .fold(0.0, f64::max);
    // 2) Driven cart: dE/dt = −m_p l_p cos θ θ̇ z̈ (power of the cart's acceleration).
    let v = Signal::sine(0.6, 2.0 * PI * 0.8, 0.0).ctx(ID311)?;
    let driven = open_loop_cart(ID311, params, v, [0.0, PI - 0.5, 0.0, 0.0], 10.0)?;
    let e_dr = energy(&driven);
    let (ml, ac, bc) = (params.m_p * params.l_p, params.a_c, params.b_c);
    let power = |k: usize, vk: f64| {
        let (th, dz, dth) = (driven.x()[(k, 1)], driven.x()[(k, 2)], driven.x()[(k, 3)]);
        -ml * th.cos() * dth * (-ac * dz + bc * vk)
    };
    // The input is held on [t_k, t_{k+1}): the trapezoid on each interval with v_k at both
    // ends integrates the (smooth inside the interval) power to O(ts²).
    let t = driven.t();
    let mut work = vec![0.0; t.len()];
    for k in 0..t.len() - 1 {
        let vk = driven.u()[(k, 0)];
        work[k + 1] = work[k] + 0.5 * (t[k + 1] - t[k]) * (power(k, vk) + power(k + 1, vk));
    }
    let swing = e_dr.iter().map(|e| (e - e_dr[0]).abs()).fold(0.0, f64::max);
    let balance = e_dr
        .iter()
        .zip(&work)
        .map(|(e, w)| (e - e_dr[0] - w).abs())
        .fold(0.0, f64::max)
        / swing;
    let mut out = ExampleOutput::default();
    out.value("energy_drift", Value::Number(drift));
    out.value("power_balance_error", Value::Number(balance));
    out.notes.push(
        "Equations of motion (Euler–Lagrange with the drive as an acceleration source): \
         z̈ = −a_c ż + b_c v;  (J_p + m_p l_p²) θ̈ + m_p l_p cos θ · z̈ = m_p g l_p sin θ − μ_p θ̇ \
         (eqs 3.7, 3.21, 3.22), θ from upright. Check with μ_p = 0: E = ½ J θ̇² + m_p g l_p \
         (1 + cos θ) stays constant with the cart at rest (energy_drift: largest relative \
         change over 10 s from θ = π − 1), and with the cart driven by v = 0.6 sin(1.6π t) V its \
         change equals the work −∫ m_p l_p cos θ θ̇ z̈ dt (power_balance_error, relative to the \
         largest change of E)."
            .into(),
    );
    super::super::mfile_refs::symbolic_note(
        &mut out,
        ID311,
        "the cart pendulum's equations of motion eq (line 48) by the Euler–Lagrange equations \
         of W − U with the dissipation D and a force f_c on the cart, in symbolic m_c, μ_c, \
         J_p, m_p, μ_p, g, l_p",
        "three ways: pendulab-plants' model (the same pendulum equation, with the cart driven \
         as the acceleration source z̈ = −a_c ż + b_c v that the book identifies) against a \
         SymPy Euler–Lagrange derivation at 40 digits (tools/reference/plants_lagrange.py, \
         plants' cart.rs), its linearisation against the closed form of docs/model.md §1 \
         (cart.rs), and here by the energy and power balance of the simulated motion",
    );
    if ctx.figures {
        let phi_free: Vec<f64> = free.x_signal(1).iter().map(|th| th - PI).collect();
        let phi_dr: Vec<f64> = driven.x_signal(1).iter().map(|th| th - PI).collect();
        let e_pred: Vec<f64> = work.iter().map(|w| e_dr[0] + w).collect();
        let fig = stacked(
            "p1c311_cdip_lagrange: energy with μ_p = 0",
            "time [s]",
            vec![
                PanelSpec::new(
                    "φ = θ − π [rad]",
                    vec![
                        ("cart at rest".into(), free.t(), phi_free),
                        ("cart driven".into(), driven.t(), phi_dr),
                    ],
                ),
                PanelSpec::new(
                    "energy E [J]",
                    vec![
                        ("cart at rest".into(), free.t(), e_free.clone()),
                        ("cart driven".into(), driven.t(), e_dr.clone()),
                        ("E(0) + work of z̈".into(), driven.t(), e_pred),
                    ],
                ),
            ],
        );
        write_figure(&mut out, "p1c311_cdip_lagrange_energy", fig);
        write_animation(
            ID311,
            &mut out,
            "p1c311_cdip_lagrange_anim",
            animation(
                Rig::Cart,
                driven.t(),
                driven.x_signal(0),
                driven.x_signal(1),
                "cart driven, μ_p = 0",
            ),
        )?;
    }
    Ok(out)
}
