//! Part 2 ch. 2 — digital control: the optimal dynamic quantizer, the I–PD controller at a
//! slow sample rate, and the sampled-data LQR.

use super::common::*;
use super::mfile_refs::{OctaveDisplay, display_note, short_half_unit};
use crate::error::BookError;
use crate::output::{ExampleOutput, Value};
use crate::registry::{Example, RunContext};
use pendulab_control::quantizer::{
    InputQuantizer, OdqLpOptions, QuantizedController, Realization, feedback_error_system, odq_lp,
};
use pendulab_lti::design::{StateFeedback, integral_augmentation, lqr, lqr_sampled_data};
use pendulab_lti::interconnect::{feedback, parallel_tf};
use pendulab_lti::{Discretization, FeedbackSign, Mat, StateSpace, TransferFunction};
use pendulab_plants::{CartEquilibrium, CartPendulum, Drive};
use pendulab_plot::{Axes, Channel, Color, Figure, SignalPanel, TimeResponse, palette};
use pendulab_sim::controllers::{Pid, PidDiscretization, PidForm, StaticStateFeedback};
use pendulab_sim::{Integrator, SampledLoop, SampledOptions, SampledRun, Signal};
use std::f64::consts::PI;

const DEG: f64 = 180.0 / PI;
const CART: &str = "cart pendulum, book table 3.5";

/// The chapter's examples, in book order.
pub(crate) fn examples() -> Vec<Example> {
    vec![
        Example {
            id: "p2c234_ex1_cdip_odq",
            title: "Quantised input (d = 2 V): optimal dynamic quantizer vs static vs none",
            section: "Part 2 §2.3.4",
            parameters: CART,
            needs_data: None,
            run: p2c234_ex1,
        },
        Example {
            id: "p2c242_ex2_cart_ipd",
            title: "I–PD cart position control: continuous vs discrete at 25 ms",
            section: "Part 2 §2.4.2",
            parameters: "cart drive P(s) = b_c/(s² + a_c s), a_c = 6.25, b_c = 4.36",
            needs_data: None,
            run: p2c242_ex2,
        },
        Example {
            id: "p2c244_ex3_cdip_sampled_data_lqr_sim",
            title: "Sampled-data LQR at 0.1 s vs the continuous LQR gain held at 0.1 s",
            section: "Part 2 §2.4.4",
            parameters: CART,
            needs_data: None,
            run: p2c244_ex3,
        },
    ]
}

fn options(ts: f64, t_final: f64) -> SampledOptions {
    SampledOptions {
        ts,
        t_final,
        integrator: Integrator::Rk4 { dt: 1e-3 },
        ..Default::default()
    }
}

fn cart_lin(id: &str) -> Result<StateSpace<pendulab_lti::Continuous>, BookError> {
    CartPendulum::book()
        .linearize(CartEquilibrium::upright())
        .ctx(id)
}

/// LQR Q = diag(10, 10, 0, 0), R = 1 on the upright cart model (library sign).
fn cart_lqr(id: &str) -> Result<Mat, BookError> {
    let lin = cart_lin(id)?;
    Ok(
        lqr(&lin, &diag(&[10.0, 10.0, 0.0, 0.0]), &diag(&[1.0]), None)
            .ctx(id)?
            .gain,
    )
}

/// A figure comparing three runs of the cart: its title, the runs' legend labels and the
/// label of the held command panel.
struct Comparison {
    title: &'static str,
    labels: [&'static str; 3],
    input: &'static str,
}

/// p2c234_ex1's runs: the same LQR without, with static and with dynamic input quantisation.
const ODQ_FIGURE: Comparison = Comparison {
    title: "p2c234_ex1: input quantisation d = 2 V, θ(0) = 10°",
    labels: [
        "no quantizer",
        "static quantizer",
        "optimal dynamic quantizer",
    ],
    input: "v [V]",
};

/// p2c244_ex3's runs: the sampled-data gain and the continuous gain held at 0.1 s and at 1 ms.
const SAMPLED_DATA_FIGURE: Comparison = Comparison {
    title: "p2c244_ex3: θ(0) = 15°, sampled-data LQR vs held continuous gain",
    labels: ["K_d at 0.1 s", "K held at 0.1 s", "K at 1 ms"],
    input: "u [V]",
};

/// The comparison figure `fig` of the three cart runs `runs` (`z`, `θ` and the held command)
/// as `<id>_response`, and the animation of `animated` as `<id>_animation`.
///
/// # Errors
/// [`BookError::Figure`] naming the figure or the animation.
fn cart_comparison(
    ctx: &RunContext,
    out: &mut ExampleOutput,
    id: &str,
    fig: &Comparison,
    runs: [&SampledRun; 3],
    animated: &SampledRun,
) -> Result<(), BookError> {
    let response = fig
        .labels
        .iter()
        .zip(runs)
        .fold(TimeResponse::new().title(fig.title), |tr, (label, run)| {
            tr.run(*label, &run.trajectory)
        })
        .panel(SignalPanel::new(Channel::State(0), "z [m]"))
        .panel(SignalPanel::new(Channel::State(1), "θ [deg]").scaled(DEG))
        .panel(SignalPanel::new(Channel::Input(0), fig.input).stairs());
    let animated = &animated.trajectory;
    save_response_and_animation(ctx, out, id, &response, Rig::Cart, animated)
}

fn p2c234_ex1(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c234_ex1_cdip_odq";
    let lin = cart_lin(id)?;
    let k = cart_lqr(id)?;
    let ts = 0.01;
    let d = 2.0;
    let dsys = lin.c2d(ts, Discretization::Zoh).ctx(id)?;
    let cy = Mat::from_row_slice(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let fb = StateFeedback::new(k.clone()).ctx(id)?;
    let errsys = feedback_error_system(&dsys, &fb, &cy).ctx(id)?;
    // The book's design: horizon T = 300, filter gain bound γ_wv = 3.35, order-2 realisation.
    let design = odq_lp(
        &errsys,
        d,
        &OdqLpOptions {
            horizon: 300,
            max_filter_gain: Some(3.35),
            realization: Realization::Reduced { order: 2 },
            ..Default::default()
        },
    )
    .ctx(id)?;
    let run = |q: InputQuantizer| -> Result<SampledRun, BookError> {
        let c =
            QuantizedController::new(StaticStateFeedback::new(k.clone()).ctx(id)?, q).ctx(id)?;
        let mut l = SampledLoop::new(CartPendulum::book(), c, options(ts, 5.0)).ctx(id)?;
        l.run(&[0.0, 10f64.to_radians(), 0.0, 0.0]).ctx(id)
    };
    let ideal = run(InputQuantizer::Ideal)?;
    let stat = run(InputQuantizer::Static { step: d })?;
    let odq = run(InputQuantizer::from(design.quantizer.clone()))?;
    // max over samples of |y − y*| for y = [z, θ] against the unquantised run.
    let deviation = |r: &SampledRun| -> Vec<f64> {
        (0..2)
            .map(|j| {
                r.trajectory
                    .x_signal(j)
                    .iter()
                    .zip(ideal.trajectory.x_signal(j))
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max)
            })
            .collect()
    };
    let (dev_s, dev_q) = (deviation(&stat), deviation(&odq));
    let mut out = ExampleOutput::default();
    out.value("K", Value::Vector(book_row(&k)))
        .value(
            "quantizer_order",
            Value::Number(design.quantizer.order() as f64),
        )
        .value("worst_case_bound_odq", Value::Number(design.cost.bound))
        .value(
            "worst_case_bound_static",
            Value::Number(design.static_cost.bound),
        )
        .value("deviation_static", Value::Vector(dev_s.clone()))
        .value("deviation_odq", Value::Vector(dev_q.clone()));
    // The gain is known to 6 significant digits (5 decimals): half a unit of the last.
    out.reference(
        "K",
        Value::Vector(vec![3.16228, 13.47175, 4.48137, 2.26289]),
        "IP Toolbox cdip_lqr_sim.m, q2 = 10 (the same LQR)",
        5e-6,
    );
    out.notes
        .push("Gains in the book's convention u = +K x.".into());
    out.notes.push(format!(
        "deviation_* = max |y − y*| over the run for y = [z, θ] (m, rad) against the unquantised loop: \
         the ODQ's is {:.0}× (z) and {:.0}× (θ) smaller than static rounding's.",
        dev_s[0] / dev_q[0],
        dev_s[1] / dev_q[1]
    ));
    cart_comparison(ctx, &mut out, id, &ODQ_FIGURE, [&ideal, &stat, &odq], &odq)?;
    Ok(out)
}

/// Percent overshoot of `y` over the final value `r`.
fn overshoot(y: &[f64], r: f64) -> f64 {
    let m = y.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    ((m - r) / r * 100.0).max(0.0)
}

fn p2c242_ex2(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c242_ex2_cart_ipd";
    let p = pendulab_plants::CartPendulumParams::book();
    let (a, b) = (p.a_c, p.b_c);
    // I–PD u = (k_I/s)(r − z) − k_P z − k_D ż on b/(s(s + a)): the closed loop is
    // s³ + (a + b k_D)s² + b k_P s + b k_I; binomial (s + ω_n)³ gives the gains.
    let wn: f64 = 25.0;
    let (ki, kp, kd) = (wn.powi(3) / b, 3.0 * wn * wn / b, (3.0 * wn - a) / b);
    let r = 0.1;
    // Continuous loop: the drive augmented with w = ∫(r − z) by the toolkit's
    // integral_augmentation (states [z, ż, w]), the I–PD as the state feedback
    // u = −[k_P, k_D, −k_I] [z, ż, w] closed by StateFeedback::closed_loop (outputs [z, u]), the
    // reference entering the integrator; exact (ZOH-sampled constant reference) at 1 ms.
    let drive = Drive::new(a, b).ctx(id)?;
    let (a_aug, b_aug) = integral_augmentation(&drive.state_space().ctx(id)?).ctx(id)?;
    let z_and_u = StateSpace::continuous(
        a_aug,
        b_aug,
        Mat::from_row_slice(2, 3, &[1.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
        Mat::from_column_slice(2, 1, &[0.0, 1.0]),
    )
    .ctx(id)?;
    let ipd = StateFeedback::new(Mat::from_row_slice(1, 3, &[kp, kd, -ki])).ctx(id)?;
    let closed = ipd.closed_loop(&z_and_u).ctx(id)?;
    let reference_input = Mat::from_column_slice(3, 1, &[0.0, 0.0, 1.0]);
    let (acl, _, ccl, _) = closed.into_parts();
    let cl = StateSpace::continuous(acl, reference_input, ccl, Mat::zeros(2, 1)).ctx(id)?;
    let t: Vec<f64> = (0..=1000).map(|k| k as f64 * 1e-3).collect();
    let step = pendulab_lti::response::step(&cl, &t).ctx(id)?;
    let cont = step
        .first()
        .ok_or_else(|| fail(id, "empty step response"))?;
    let zc: Vec<f64> = cont.y_signal(0).iter().map(|v| v * r).collect();
    let uc: Vec<f64> = cont.y_signal(1).iter().map(|v| v * r).collect();
    // Discrete: the PID family's I–PD at 25 ms by Tustin, integral and derivative. The book's
    // derivative is unfiltered; the PID type needs T_f > 0, and T_f = 1 ps is that limit to
    // ~1e-10 relative (the Tustin derivative's pole (2T_f − ts)/(2T_f + ts) → −1).
    let tsd = 0.025;
    let pid = Pid::new(
        PidForm::IPD {
            kp,
            ki,
            kd,
            tf: 1e-12,
        },
        tsd,
        PidDiscretization::Tustin,
    )
    .ctx(id)?
    .reference(Signal::step(0.0, r).ctx(id)?)
    .measurement(0, 2)
    .ctx(id)?;
    let mut l = SampledLoop::new(drive, pid, options(tsd, 1.0)).ctx(id)?;
    let dr = l.run(&[0.0, 0.0]).ctx(id)?;
    // The discrete loop's poles (r = 0): the ZOH-sampled drive under u = −C(z) z with the
    // I–PD's terms by Tustin, C(z) = k_P + (k_I ts/2)(z + 1)/(z − 1) + (2k_D/ts)(z − 1)/(z + 1),
    // closed by the toolkit's parallel and feedback connections.
    let dd = drive
        .state_space()
        .ctx(id)?
        .c2d(tsd, Discretization::Zoh)
        .ctx(id)?;
    let tustin = |num: &[f64], den: &[f64]| TransferFunction::discrete(num, den, tsd);
    let (gi, gd) = (ki * tsd / 2.0, 2.0 * kd / tsd);
    let pi = parallel_tf(
        &tustin(&[kp], &[1.0]).ctx(id)?,
        &tustin(&[gi, gi], &[1.0, -1.0]).ctx(id)?,
    )
    .ctx(id)?;
    let pid_z = parallel_tf(&pi, &tustin(&[gd, -gd], &[1.0, 1.0]).ctx(id)?).ctx(id)?;
    let sampled = feedback(
        &dd,
        &pid_z.to_state_space().ctx(id)?,
        FeedbackSign::Negative,
    )
    .ctx(id)?;
    let radius = sampled
        .poles()
        .ctx(id)?
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max);
    let os_c = overshoot(&zc, r);
    let os_d = overshoot(dr.trajectory.x_signal(0), r);
    let mut out = ExampleOutput::default();
    out.value("gains", Value::Vector(vec![ki, kp, kd]))
        .value("overshoot_continuous", Value::Number(os_c))
        .value("overshoot_discrete", Value::Number(os_d))
        .value("discrete_spectral_radius", Value::Number(radius));
    // Printed to 5 significant digits: half a unit of the last digit each.
    out.reference(
        "gains",
        Value::Vector(vec![3583.7, 430.05, 15.768]),
        "book Part 2 §2.4.2, example 2.2",
        0.05,
    );
    out.notes.push(
        "gains = [k_I, k_P, k_D] (the order p2c242_ex2_cart_ipd.m defines them). Overshoot in % of r = 0.1 m; the discrete one at the 25 ms samples."
            .into(),
    );
    out.notes.push(format!(
        "Discrete I–PD: integral and (unfiltered) derivative by Tustin at 25 ms. The continuous loop (binomial poles, no zeros) \
         does not overshoot; sampled at 25 ms (ω_n ts = 0.625) the loop is unstable (spectral radius {radius:.3}): the Tustin \
         derivative's pole at z = −1 feeds an oscillation at the Nyquist frequency that grows, so overshoot_discrete depends on \
         the 1 s window."
    ));
    if ctx.figures {
        let mut az = Axes::new();
        az.ylabel("z [m]");
        az.plot(&t, &zc).label("continuous").color(palette(0));
        az.plot(dr.trajectory.t(), dr.trajectory.x_signal(0))
            .label("discrete, ts = 25 ms")
            .color(palette(1))
            .dashed();
        az.hline(r)
            .color(Color::DARK_GREY)
            .dashed()
            .label("r = 0.1 m");
        let mut au = Axes::new();
        au.ylabel("u [V]").xlabel("time [s]");
        au.plot(&t, &uc).color(palette(0));
        au.step(dr.trajectory.t(), dr.trajectory.u_signal(0))
            .color(palette(1));
        save_figure(
            ctx,
            &mut out,
            id,
            "response",
            Ok(Figure::column([az, au])
                .title("p2c242_ex2: I–PD, continuous vs discrete (Tustin, 25 ms)")),
        )?;
    }
    Ok(out)
}

fn p2c244_ex3(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c244_ex3_cdip_sampled_data_lqr_sim";
    let lin = cart_lin(id)?;
    let (q, r) = (diag(&[10.0, 10.0, 0.0, 0.0]), diag(&[1.0]));
    let ts = 0.1;
    let sd = lqr_sampled_data(&lin, &q, &r, None, ts).ctx(id)?;
    let k = cart_lqr(id)?;
    let x0 = [0.0, 15f64.to_radians(), 0.0, 0.0];
    let sim = |gain: &Mat, ts: f64| -> Result<SampledRun, BookError> {
        let c = StaticStateFeedback::new(gain.clone()).ctx(id)?;
        let mut l = SampledLoop::new(CartPendulum::book(), c, options(ts, 4.0)).ctx(id)?;
        l.run(&x0).ctx(id)
    };
    let run_kd = sim(&sd.lqr.gain, ts)?;
    let run_held = sim(&k, ts)?;
    let run_cont = sim(&k, 1e-3)?;
    // The continuous cost of a held input, Σ [x_k; u_k]ᵀ W_d [x_k; u_k] (exact on the linear
    // model), measured along the nonlinear runs at 0.1 s.
    let mut wd = Mat::zeros(5, 5);
    wd.view_mut((0, 0), (4, 4)).copy_from(&sd.cost.q);
    wd.view_mut((0, 4), (4, 1)).copy_from(&sd.cost.n);
    wd.view_mut((4, 0), (1, 4))
        .copy_from(&sd.cost.n.transpose());
    wd.view_mut((4, 4), (1, 1)).copy_from(&sd.cost.r);
    let cost = |run: &SampledRun| -> f64 {
        let tr = &run.trajectory;
        (0..tr.len())
            .map(|i| {
                let w = nalgebra::DVector::from_fn(5, |a, _| {
                    if a < 4 {
                        tr.x_signal(a)[i]
                    } else {
                        tr.u_signal(0)[i]
                    }
                });
                (w.transpose() * &wd * &w)[(0, 0)]
            })
            .sum()
    };
    let (cost_kd, cost_held) = (cost(&run_kd), cost(&run_held));
    let mut out = ExampleOutput::default();
    out.value("Kd", Value::Vector(book_row(&sd.lqr.gain)))
        .value("Rd", Value::Number(sd.cost.r[(0, 0)]))
        .value("Qd", Value::matrix(&sd.cost.q))
        .value(
            "Sd",
            Value::Vector(sd.cost.n.column(0).iter().copied().collect()),
        )
        .value("K", Value::Vector(book_row(&k)))
        .value("cost_Kd", Value::Number(cost_kd))
        .value("cost_K_held", Value::Number(cost_held));
    // Line 26 displays K = −lqr(A, B, Q, R), as GNU Octave printed it running the M-file.
    OctaveDisplay::parse(
        id,
        include_str!("../../tests/data/octave/p2c244_ex3_cdip_sampled_data_lqr_sim.txt"),
    )
    .compare(id, &mut out, "K", "K", "line 26")?;
    // Line 44, Kd = −dlqr(Ad, Bd, Qd, Rd, Sd) after the Van Loan weights of lines 28-43: the
    // Octave run stops at line 29 (the control package's c2d takes a system, not MATLAB's
    // (A, B, ts)), so the reference is SciPy's run of those lines (tools/reference/book_p2c2.py).
    let kd_scipy = [
        1.5778974127092174,
        9.363318455665842,
        3.049762687384925,
        1.5949349557822252,
    ];
    out.reference(
        "Kd",
        Value::vector(&kd_scipy),
        "p2c244_ex3_cdip_sampled_data_lqr_sim.m lines 28-44, the same steps in SciPy \
         (tools/reference/book_p2c2.py)",
        short_half_unit(9.363318455665842),
    );
    display_note(&mut out, id, &["K", "Kd"], &[], &[]);
    out.notes
        .push("Gains in the book's convention u = +K x.".into());
    out.notes.push(
        "cost_* = ∫(xᵀQx + uᵀRu)dt over the 4 s nonlinear runs at 0.1 s, as Σ [x_k; u_k]ᵀ W_d [x_k; u_k]: K_d does better than the held continuous gain."
            .into(),
    );
    out.notes.push(
        "Van Loan: Q_d, S_d, R_d make Σ [x_k; u_k]ᵀ[[Q_d, S_d], [S_dᵀ, R_d]][x_k; u_k] equal ∫(xᵀQx + uᵀRu)dt for held inputs; K_d = dlqr(A_d, B_d, Q_d, R_d, S_d)."
            .into(),
    );
    let runs = [&run_kd, &run_held, &run_cont];
    cart_comparison(ctx, &mut out, id, &SAMPLED_DATA_FIGURE, runs, &run_kd)?;
    Ok(out)
}
