//! Part 2 ch. 3 — nonlinear control: swing-up of the cart pendulum by energy pumping with a
//! switch to sliding-mode balancing, and the C/GMRES NMPC swing-up of the arm pendulum.

use super::common::*;
use super::mfile_refs::{OctaveDisplay, display_note};
use crate::error::BookError;
use crate::output::{ExampleOutput, Value};
use crate::registry::{Example, RunContext};
use pendulab_control::cgmres::{CgmresOptions, TimedController};
use pendulab_control::nmpc::{ArmSwingUpSettings, arm_swing_up_controller};
use pendulab_control::sliding_mode::{
    ReducedWeight, RegularForm, SlidingModeController, SlidingSurface, lq_sliding_surface,
};
use pendulab_control::swing_up::{EnergyPumping, swing_up_then_balance, wrap_angle};
use pendulab_ident::Dataset;
use pendulab_plants::{
    ArmPendulum, ArmPendulumParams, CartEquilibrium, CartPendulum, CartPendulumState, RigSpec,
};
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
            parameters: "arm pendulum of the book's NMPC program (inputInvPendC.m); plain model and quantised rig preset",
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
    // p2c323_ex1_cdip_swing_up.m line 14 runs p2c323_Sliding_Mode_Control.m, whose line 35
    // displays S; GNU Octave's run of the M-file (its Simulink run shimmed).
    OctaveDisplay::parse(
        id,
        include_str!("../../tests/data/octave/p2c323_ex1_cdip_swing_up.txt"),
    )
    .compare(
        id,
        &mut out,
        "S",
        "S",
        "line 14 (p2c323_Sliding_Mode_Control.m line 35)",
    )?;
    display_note(
        &mut out,
        id,
        &["S"],
        &[(
            "t_sw (line 34)",
            "the switching time of the Simulink run cdip_swing_up_sim; pendulab's own run's is \
             switch_time",
        )],
        &[],
    );
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

/// The book program's record of its run: `aginvpendC.c` (the C/GMRES code of Part 2 §3.3,
/// generated by AutoGenU from `inputInvPendC.m`) compiled and run unchanged by
/// `tools/reference/p2c33_book_cgmres.sh`; columns `t, θ₁, θ₂, θ̇₁, θ̇₂, u₁, u₂, u₃` every 5 ms
/// (the program's `dstep = 5`), six significant digits.
const BOOK_PROGRAM_RUN: &str = include_str!("../../tests/data/p2c33_aginvpendC04.csv");

/// The arm pendulum the book's NMPC program models (`inputInvPendC.m`, line 31):
/// `As = 6.25`, `Bs = 15.6`, `α₂ = 0.004565`, `α₃ = 0.0041314`, `α₅ = 0.178542`,
/// `C₂ = 0.000186` — an older parameter set than table 3.7. Only `a₁`, `b₁`, `α₂`, `α₃`, `α₅` and
/// `μ₂` enter the model (`inputInvPendC.m`, line 15); `g`, `l₂` and `L₂` are kept from
/// table 3.7 and `m₂ = α₅/(g l₂)`, `L₁ = α₃/(m₂ l₂)`, `J₂ = α₂ − m₂ l₂²` follow.
fn book_program_plant(id: &str) -> Result<ArmPendulum, BookError> {
    const ALPHA2: f64 = 0.004565;
    const ALPHA3: f64 = 0.0041314;
    const ALPHA5: f64 = 0.178542;
    let table = ArmPendulumParams::book();
    let m2 = ALPHA5 / (table.g * table.l2);
    ArmPendulum::new(ArmPendulumParams {
        a1: 6.25,
        b1: 15.6,
        L1: ALPHA3 / (m2 * table.l2),
        m2,
        J2: ALPHA2 - m2 * table.l2 * table.l2,
        mu2: 0.000186,
        ..table
    })
    .ctx(id)
}

/// The book program's problem and solver settings (`inputInvPendC.m`, lines 15-45):
/// `Q = diag(1, 1, 0, 0)`, `S_f = diag(3, 1, 0, 0)`, `L = ½xᵀQx + ½ r₁ u₁² − r₂ u₂` with
/// `r = (1, 0.1)`, the bound `u₁² + u₂² = 2.5²` (the dummy input `u₂`), `T(t) = 0.5(1 − e^{−0.5t})`,
/// `dv = 25` grid points, `ζ = 1000`, the difference step `hdir = 0.002`, `kmax = 5`, `ht = 1 ms`:
/// [`ArmSwingUpSettings::book`] with the program's input weight `r₁ = 1` and difference step.
fn book_program_settings() -> ArmSwingUpSettings {
    let base = ArmSwingUpSettings::book();
    ArmSwingUpSettings {
        r: 1.0,
        solver: CgmresOptions {
            difference_step: 0.002,
            ..base.solver
        },
        ..base
    }
}

/// The closed loop of the book program's problem from `x₀ = [π, π, 0, 0]` for 10 s, on the plain
/// model (as the book's program runs it) or on the quantised rig preset. The command is limited
/// to ±u_max: the dummy input's bound holds only up to the continuation's residual (the
/// unlimited command reaches 2.5002 V on the plain model).
fn nmpc_run(id: &str, quantised: bool) -> Result<(SampledRun, f64, f64), BookError> {
    let plant = book_program_plant(id)?;
    let settings = book_program_settings();
    let inner = TimedController::new(arm_swing_up_controller(plant, &settings).ctx(id)?);
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

/// Largest difference of `ours` (sampled every `ts` from 0) from the book program's column
/// `name` at the book program's sample times (multiples of `ts`).
fn max_deviation(
    id: &str,
    book: &Dataset,
    name: &str,
    ours: &[f64],
    ts: f64,
) -> Result<f64, BookError> {
    let tb = book.time().ctx(id)?;
    let yb = book.column(name).ctx(id)?;
    let mut worst = 0.0f64;
    for (t, y) in tb.iter().zip(yb) {
        let k = (t / ts).round() as usize;
        let v = ours.get(k).ok_or_else(|| {
            fail(
                id,
                format!("the run ends before the book program's sample t = {t} s"),
            )
        })?;
        worst = worst.max((v - y).abs());
    }
    Ok(worst)
}

fn p2c33_nmpc(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c33_adip_nmpc_swing_up";
    let book_text: String = BOOK_PROGRAM_RUN
        .lines()
        .filter(|l| !l.starts_with('#'))
        .collect::<Vec<_>>()
        .join("\n");
    let book = Dataset::from_csv_str("p2c33_aginvpendC04.csv", &book_text).ctx(id)?;
    let (run, mean_us, max_us) = nmpc_run(id, false)?;
    let (runq, _, _) = nmpc_run(id, true)?;
    let tol = 5f64.to_radians();
    let t_up = settle_time(&run, tol).ok_or_else(|| {
        fail(
            id,
            "the arm pendulum was not upright (both angles within 5°) at the end of the run",
        )
    })?;
    let t_upq = settle_time(&runq, tol);
    // The book program's run, by the same measure on its 5 ms record.
    let tb = book.time().ctx(id)?;
    let (b1, b2) = (
        book.column("theta1").ctx(id)?,
        book.column("theta2").ctx(id)?,
    );
    let mut k = tb.len();
    while k > 0 && wrap_angle(b1[k - 1]).abs() <= tol && wrap_angle(b2[k - 1]).abs() <= tol {
        k -= 1;
    }
    let t_up_book = tb.get(k).copied().unwrap_or(f64::NAN);
    let tr = &run.trajectory;
    let ts = book_program_settings().ts;
    let umax = max_abs_after(tr.t(), tr.u_signal(0), 0.0);
    let umax_book = max_abs_after(tb, book.column("u1").ctx(id)?, 0.0);
    let mut out = ExampleOutput::default();
    out.value("swing_up_time", Value::Number(t_up))
        .value("max_abs_u", Value::Number(umax))
        .value(
            "final_state",
            Value::Vector(run.diagnostics.final_state.clone()),
        )
        .unit(&["swing_up_time"], "s")
        .value("swing_up_time_book_program", Value::Number(t_up_book))
        .unit(&["swing_up_time_book_program"], "s")
        .value("max_abs_u_book_program", Value::Number(umax_book))
        .value(
            "max_dev_theta1",
            Value::Number(max_deviation(id, &book, "theta1", tr.x_signal(0), ts)?),
        )
        .value(
            "max_dev_theta2",
            Value::Number(max_deviation(id, &book, "theta2", tr.x_signal(1), ts)?),
        )
        .value(
            "max_dev_u",
            Value::Number(max_deviation(id, &book, "u1", tr.u_signal(0), ts)?),
        )
        .value("upright_at_end_quantised", Value::Bool(t_upq.is_some()));
    if let Some(t) = t_upq {
        out.value("swing_up_time_quantised", Value::Number(t));
    }
    out.value(
        "final_state_quantised",
        Value::Vector(runq.diagnostics.final_state.clone()),
    )
    .value("mean_update_us", Value::Number(mean_us))
    .value("max_update_us", Value::Number(max_us));
    let last = tb.len().saturating_sub(1);
    let book_final = ["theta1", "theta2", "dtheta1", "dtheta2"]
        .iter()
        .map(|c| Ok(book.column(c).ctx(id)?[last]))
        .collect::<Result<Vec<f64>, BookError>>()?;
    let src = "the book's program aginvpendC.c (Part 2 §3.3), its run record \
               (tools/reference/p2c33_book_cgmres.sh)";
    out.reference("swing_up_time", Value::Number(t_up_book), src, 0.005);
    out.reference("final_state", Value::Vector(book_final), src, 1e-5);
    out.notes.push(
        "Compared with the book program's run: swing_up_time to the 5 ms sampling of its record; final_state (at 10 s) to 1e-5 rad, rad/s, a tolerance of the two algorithms, not of printed digits: the program integrates the plant by Runge–Kutta–Gill and Adams–Bashforth–Moulton and preconditions its optimality residual by the Hessian of the Hamiltonian, pendulab integrates by RK4 and continues the plain residual, so the runs differ by up to max_dev_theta1, max_dev_theta2 (rad) and max_dev_u (V) over the swing, at the record's samples."
            .into(),
    );
    out.notes.push(
        "The book program's problem (inputInvPendC.m, from which AutoGenU generated aginvpendC.c): its own arm parameters (As = 6.25, Bs = 15.6, α2 = 0.004565, α3 = 0.0041314, α5 = 0.178542, C2 = 0.000186), Q = diag(1, 1, 0, 0), Sf = diag(3, 1, 0, 0), input weight r1 = 1, dummy weight r2 = 0.1, |u| ≤ 2.5 V by the dummy input, T(t) = 0.5(1 − e^(−0.5t)), 25 grid points, ζ = 1000, difference step 0.002, kmax = 5, 1 ms; run on the plain model from [π, π, 0, 0] as the program runs it. The program is given the input weight and the parameter set of its own; the book's text gives neither."
            .into(),
    );
    out.notes.push(
        "*_book_program: the book's program compiled and run unchanged (tools/reference/p2c33_book_cgmres.sh, gcc 12.2; its record every 5 ms, six significant digits); it applies its command unclipped (up to 2.49948 V), pendulab limits the command to ±2.5 V."
            .into(),
    );
    out.notes.push(
        "swing_up_time: first time from which both angles stay within 5° of upright to the end (10 s). *_quantised: the same controller on the quantised rig preset (encoders, pseudo-differentiated velocities, 16-bit D/A); with the lag of the pseudo-differentiated velocities it need not hold the pendulum up (upright_at_end_quantised), and it is not drawn. Update times are wall-clock on the machine that ran the example (the book: < 0.2 ms on a laptop); see `pendulab bench nmpc-update`."
            .into(),
    );
    if ctx.figures {
        // θ₁, θ₂ in degrees and u of the book program's record and of pendulab's run.
        let deg = |v: &[f64]| v.iter().map(|x| x * DEG).collect::<Vec<f64>>();
        let panel =
            |ylabel: &str, name: &str, j: usize, scale: bool| -> Result<PanelSpec<'_>, BookError> {
                let v = if j < 4 {
                    tr.x_signal(j)
                } else {
                    tr.u_signal(0)
                };
                let b = book.column(name).ctx(id)?;
                Ok(PanelSpec::new(
                    ylabel,
                    vec![
                        (
                            "book program (aginvpendC.c)".to_string(),
                            tb,
                            if scale { deg(b) } else { b.to_vec() },
                        ),
                        (
                            "pendulab".to_string(),
                            tr.t(),
                            if scale { deg(v) } else { v.to_vec() },
                        ),
                    ],
                ))
            };
        let mut fig = stacked(
            "p2c33: NMPC (C/GMRES) swing-up of the arm pendulum",
            "time [s]",
            vec![
                panel("θ1 [deg]", "theta1", 0, true)?,
                panel("θ2 [deg]", "theta2", 1, true)?,
                panel("u [V] (dashed: ±2.5 V)", "u1", 4, false)?
                    .reference(2.5, "±2.5 V")
                    .reference(-2.5, "−2.5 V"),
            ],
        );
        // u spends most of the swing at ±2.5 V: no legend fits beside it; the lines are the
        // first panel's and the axis label names the limits.
        if let Some(ax) = fig.axes_mut(2, 0) {
            ax.legend(pendulab_plot::LegendPos::Hidden);
        }
        write_figure(&mut out, &format!("{id}_response"), fig);
        save_run_animation(ctx, &mut out, id, Rig::Arm, &run.trajectory, id)?;
    }
    Ok(out)
}
