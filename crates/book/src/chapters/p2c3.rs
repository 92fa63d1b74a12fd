//! Part 2 ch. 3 — nonlinear control: swing-up of the cart pendulum by energy pumping with a
//! switch to sliding-mode balancing, and the C/GMRES NMPC swing-up of the arm pendulum.

use super::common::*;
use crate::error::BookError;
use crate::output::{ExampleOutput, Value};
use crate::registry::{Example, RunContext};
use pendulab_control::cgmres::TimedController;
use pendulab_control::nmpc::{ArmSwingUpSettings, arm_swing_up_controller};
use pendulab_control::sliding_mode::{
    ReducedWeight, RegularForm, SlidingModeController, SlidingSurface, lq_sliding_surface,
};
use pendulab_control::swing_up::{EnergyPumping, swing_up_then_balance, wrap_angle};
use pendulab_plants::{ArmPendulum, CartEquilibrium, CartPendulum, CartPendulumState, RigSpec};
use pendulab_plot::{Axes, Channel, Color, Figure, SignalPanel, TimeResponse};
use pendulab_sim::controllers::Saturated;
use pendulab_sim::rig::RigChains;
use pendulab_sim::{SampledLoop, SampledOptions, SampledRun};
use std::f64::consts::PI;

const DEG: f64 = 180.0 / PI;

/// The chapter's examples, in book order.
pub(crate) fn examples() -> Vec<Example> {
    vec![
        Example {
            id: "p2c323_ex1_cdip_swing_up",
            title: "Cart pendulum swing-up: energy pumping, then sliding mode on the LQ hyperplane",
            section: "Part 2 §3.2.3",
            parameters: "cart pendulum, book table 3.5; K1 = 0.8, K2 = 30, δ = 0 and 5",
            needs_data: None,
            run: p2c323_ex1,
        },
        Example {
            id: "p2c33_adip_nmpc_swing_up",
            title: "Arm pendulum swing-up by NMPC (C/GMRES), |u| ≤ 2.5 V",
            section: "Part 2 §3.3",
            parameters: "arm pendulum, book table 3.7; quantised rig preset",
            needs_data: None,
            run: p2c33_nmpc,
        },
    ]
}

fn surface(
    id: &str,
    plant: &CartPendulum,
) -> Result<
    (
        SlidingSurface,
        pendulab_lti::StateSpace<pendulab_lti::Continuous>,
    ),
    BookError,
> {
    let lin = plant.linearize(CartEquilibrium::upright()).ctx(id)?;
    let s = lq_sliding_surface(
        lin.a(),
        lin.b(),
        &diag(&[10.0, 100.0, 1.0, 1.0]),
        RegularForm::BookShear,
        ReducedWeight::BookScript,
    )
    .ctx(id)?;
    Ok((s, lin))
}

fn swing_up_run(id: &str, delta: f64, quantised: bool) -> Result<SampledRun, BookError> {
    let plant = CartPendulum::book();
    let (s, lin) = surface(id, &plant)?;
    let smc = SlidingModeController::from_surface(&s, lin.a(), lin.b(), 30.0, delta).ctx(id)?;
    let c = swing_up_then_balance(
        EnergyPumping::new(&plant, 0.8).ctx(id)?,
        smc,
        vec![(1, PI / 4.0)],
    )
    .ctx(id)?;
    let mut l = SampledLoop::new(
        plant,
        c,
        SampledOptions {
            t_final: 16.0,
            ..Default::default()
        },
    )
    .ctx(id)?
    .with_rig(if quantised {
        quantized_rig(id, &RigSpec::cart())?
    } else {
        RigChains::plain(4)
    })
    .ctx(id)?;
    l.run(&[0.1, PI + 0.001, 0.0, 0.0]).ctx(id)
}

fn p2c323_ex1(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c323_ex1_cdip_swing_up";
    let plant = CartPendulum::book();
    let (s, _) = surface(id, &plant)?;
    let run0 = swing_up_run(id, 0.0, false)?;
    let run5 = swing_up_run(id, 5.0, false)?;
    let runq = swing_up_run(id, 5.0, true)?;
    let switch = |r: &SampledRun| -> Result<f64, BookError> {
        r.diagnostics.switch_times.first().copied().ok_or_else(|| {
            fail(
                id,
                "the pendulum never entered the switching window |θ| ≤ π/4",
            )
        })
    };
    let (ts0, ts5, tsq) = (switch(&run0)?, switch(&run5)?, switch(&runq)?);
    let mut finq = runq.diagnostics.final_state.clone();
    finq[1] = wrap_angle(finq[1]);
    let mut fin = run0.diagnostics.final_state.clone();
    fin[1] = wrap_angle(fin[1]);
    let mut fin5 = run5.diagnostics.final_state.clone();
    fin5[1] = wrap_angle(fin5[1]);
    let zmax = [&run0, &run5, &runq]
        .iter()
        .map(|r| max_abs_after(r.trajectory.t(), r.trajectory.x_signal(0), 0.0))
        .fold(0.0, f64::max);
    let mut out = ExampleOutput::default();
    out.value("S", Value::Vector(s.s.clone()))
        .value("sliding_poles", Value::Complex(s.sliding_poles.clone()))
        .value("switch_time", Value::Number(ts0))
        .value("final_state", Value::Vector(fin))
        .value("switch_time_delta5", Value::Number(ts5))
        .value("final_state_delta5", Value::Vector(fin5))
        .value("switch_time_quantised", Value::Number(tsq))
        .value("final_state_quantised", Value::Vector(finq))
        .value("max_abs_z", Value::Number(zmax));
    out.notes.push(
        "final_state is [z, θ wrapped to (−π, π], ż, θ̇] at 16 s for δ = 0 (sign switching); the *_delta5 values for the boundary layer δ = 5 (plain plant, full state, 1 ms); *_quantised: δ = 5 on the rig preset with quantizer (encoders, pseudo-differentiated velocities, ±5 V, 16-bit D/A)."
            .into(),
    );
    out.notes.push(
        "S from the regular form with the book's shear T and care on the reduced system (Q = diag(10, 100, 1, 1), the book script's weighting)."
            .into(),
    );
    if ctx.figures {
        let fig = TimeResponse::new()
            .title("p2c323_ex1: swing-up and sliding-mode balancing")
            .run("δ = 0", &run0.trajectory)
            .run("δ = 5", &run5.trajectory)
            .run("δ = 5, quantised rig", &runq.trajectory)
            .panel(SignalPanel::new(Channel::State(0), "z [m]"))
            .panel(SignalPanel::new(Channel::State(1), "θ [deg]").scaled(DEG))
            .panel(SignalPanel::new(Channel::Input(0), "u [V]"))
            .figure();
        save_figure(ctx, &mut out, id, "response", fig)?;
        // E(t) and σ(t) of both runs.
        let e_up = plant.upright_energy();
        let mut ax_e = Axes::new();
        ax_e.ylabel("E [J]");
        let mut ax_s = Axes::new();
        ax_s.ylabel("σ = Sᵀx").xlabel("time [s]");
        for (k, (name, run, tsw)) in [("δ = 0", &run0, ts0), ("δ = 5", &run5, ts5)]
            .into_iter()
            .enumerate()
        {
            let tr = &run.trajectory;
            let n = tr.len();
            let (mut e, mut sig) = (Vec::with_capacity(n), Vec::with_capacity(n));
            for i in 0..n {
                let x = [
                    tr.x_signal(0)[i],
                    tr.x_signal(1)[i],
                    tr.x_signal(2)[i],
                    tr.x_signal(3)[i],
                ];
                e.push(plant.energy(&CartPendulumState::from_array(x)));
                let xw = [x[0], wrap_angle(x[1]), x[2], x[3]];
                let sv: f64 = s.s.iter().zip(xw).map(|(a, b)| a * b).sum();
                sig.push(if tr.t()[i] >= tsw { sv } else { f64::NAN });
            }
            let c = pendulab_plot::palette(k);
            ax_e.plot(tr.t(), &e).label(name).color(c);
            // The sign-switching run chatters along σ = 0: drawn first, lighter and thinner.
            let chatter = pendulab_plot::chatters(&sig);
            ax_s.plot(tr.t(), &sig)
                .label(format!("{name} (after the switch)"))
                .color(if chatter { c.with_alpha(0.45) } else { c })
                .width(if chatter { 0.9 } else { 1.6 });
            ax_s.vline(tsw).color(c).dotted();
        }
        ax_e.hline(e_up)
            .label("upright energy 2 m g l")
            .color(Color::DARK_GREY)
            .dashed();
        save_figure(
            ctx,
            &mut out,
            id,
            "energy_sigma",
            Ok(Figure::column([ax_e, ax_s])
                .title("p2c323_ex1: pendulum energy E(t) and switching function σ(t)")),
        )?;
        save_run_animation(ctx, &mut out, id, Rig::Cart, &run5.trajectory, id)?;
    }
    Ok(out)
}

/// First time after which both angles (wrapped) stay within `tol` rad up to the end.
fn settle_time(run: &SampledRun, tol: f64) -> Option<f64> {
    let tr = &run.trajectory;
    let t = tr.t();
    let ok = |i: usize| {
        wrap_angle(tr.x_signal(0)[i]).abs() <= tol && wrap_angle(tr.x_signal(1)[i]).abs() <= tol
    };
    let mut k = t.len();
    while k > 0 && ok(k - 1) {
        k -= 1;
    }
    (k < t.len()).then(|| t[k])
}

fn nmpc_run(id: &str, quantised: bool) -> Result<(SampledRun, f64, f64), BookError> {
    let plant = ArmPendulum::book();
    let settings = ArmSwingUpSettings::book();
    let inner = TimedController::new(arm_swing_up_controller(plant, &settings).ctx(id)?);
    // The controller's own limiter at ±u_max: the dummy-input bound holds only up to the
    // optimality residual of the continuation; the limiter makes |u| ≤ 2.5 V exact.
    let c = Saturated::new(inner, -settings.u_max, settings.u_max).ctx(id)?;
    let rig = if quantised {
        quantized_rig(id, &RigSpec::arm())?
    } else {
        RigChains::plain(4)
    };
    let mut l = SampledLoop::new(
        plant,
        c,
        SampledOptions {
            t_final: 10.0,
            ..Default::default()
        },
    )
    .ctx(id)?
    .with_rig(rig)
    .ctx(id)?;
    let run = l.run(&[PI, PI, 0.0, 0.0]).ctx(id)?;
    let timing = *l.controller().inner().timing();
    Ok((run, timing.mean_seconds() * 1e6, timing.max_seconds * 1e6))
}

fn p2c33_nmpc(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c33_adip_nmpc_swing_up";
    let (run, mean_us, max_us) = nmpc_run(id, true)?;
    let tol = 5f64.to_radians();
    let t_up = settle_time(&run, tol).ok_or_else(|| {
        fail(
            id,
            "the arm pendulum was not upright (both angles within 5°) at the end of the run",
        )
    })?;
    let umax = max_abs_after(run.trajectory.t(), run.trajectory.u_signal(0), 0.0);
    let mut out = ExampleOutput::default();
    out.value("swing_up_time", Value::Number(t_up))
        .value("max_abs_u", Value::Number(umax))
        .value("mean_update_us", Value::Number(mean_us))
        .value("max_update_us", Value::Number(max_us))
        .value(
            "final_state",
            Value::Vector(run.diagnostics.final_state.clone()),
        );
    out.notes.push(
        "swing_up_time: first time from which both angles stay within 5° of upright to the end (10 s). \
         Quantised rig preset (encoders, pseudo-differentiated velocities, 16-bit D/A); the NMPC command is limited to ±2.5 V by the controller."
            .into(),
    );
    out.notes.push(
        "Update times are wall-clock on the machine that ran the example (the book: < 0.2 ms on a laptop); see `pendulab bench nmpc-update`."
            .into(),
    );
    if ctx.figures {
        let (plain, _, _) = nmpc_run(id, false)?;
        let fig = TimeResponse::new()
            .title("p2c33: NMPC (C/GMRES) swing-up of the arm pendulum")
            .run("quantised rig", &run.trajectory)
            .run("plain model", &plain.trajectory)
            .panel(SignalPanel::new(Channel::State(0), "θ1 [deg]").scaled(DEG))
            .panel(SignalPanel::new(Channel::State(1), "θ2 [deg]").scaled(DEG))
            .panel(
                SignalPanel::new(Channel::Input(0), "u [V]")
                    .reference(2.5, Some("±2.5 V"))
                    .reference(-2.5, None),
            )
            .figure();
        save_figure(ctx, &mut out, id, "response", fig)?;
        save_run_animation(ctx, &mut out, id, Rig::Arm, &run.trajectory, id)?;
    }
    Ok(out)
}
