//! Part 1 chapter 2: PID control of the cart position (book §2.1–2.3).
//!
//! Every simulation runs the nonlinear cart pendulum (table 3.5) with the pendulum hanging,
//! on the rig preset "with quantizer" (encoders, pseudo-differentiated velocities, ±5 V,
//! 16-bit D/A) at 1 kHz, the controllers being the discrete PID family of
//! `pendulab_sim::controllers::Pid` (Tustin, derivative filter `T_f = 0.02 s`, the rig's
//! pseudo-differentiator constant). Linear-loop poles use the drive `P(s) = b_c/(s(s + a_c))`
//! with an ideal derivative.

use super::common::*;
use super::mfile_refs::no_display_note;
use crate::error::BookError;
use crate::output::{ExampleOutput, Value};
use crate::registry::{Example, RunContext};
use pendulab_lti::frequency_response::logspace;
use pendulab_lti::{Complex64, Mat, Polynomial};
use pendulab_plants::{CartEquilibrium, CartPendulum, CartPendulumParams, RigSpec};
use pendulab_plot::Bode;
use pendulab_sim::controllers::{OpenLoop, Pid, PidDiscretization, PidForm};
use pendulab_sim::rig::RigChains;
use pendulab_sim::{Controller, DisturbancePoint, SampledLoop, SampledOptions, Signal};
use std::f64::consts::PI;

mod design;
mod pid;
use design::*;
use pid::*;

/// Derivative filter time constant of the simulated PD/PID laws (s): the rig's
/// pseudo-differentiator 1/(0.02 s + 1).
const TF: f64 = 0.02;
/// Sample time (s).
const TS: f64 = 1e-3;
/// The reference step of the chapter (m).
const R: f64 = 0.1;

fn ex(
    id: &'static str,
    title: &'static str,
    section: &'static str,
    run: fn(&RunContext) -> Result<ExampleOutput, BookError>,
) -> Example {
    Example {
        id,
        title,
        section,
        parameters: "cart pendulum, table 3.5 (hanging), quantised rig, 1 ms",
        needs_data: None,
        run,
    }
}

/// The chapter's examples, in book order.
pub(crate) fn examples() -> Vec<Example> {
    vec![
        ex(
            "p1c211_pcont",
            "P control of the cart position (k_P = 5, 10, 20)",
            "Part 1 §2.1.1",
            p1c211_pcont,
        ),
        ex(
            "p1c212_pdcont",
            "PD control of the cart position (k_P = 10, k_D = 0.1, 0.8)",
            "Part 1 §2.1.2",
            p1c212_pdcont,
        ),
        ex(
            "p1c213_picont",
            "PI control against an input disturbance (k_I = 5, 25; d = −0.1 V)",
            "Part 1 §2.1.3",
            p1c213_picont,
        ),
        ex(
            "p1c213_pidcont",
            "PID control against an input disturbance (k_P = 10, k_D = 0.8, k_I = 5)",
            "Part 1 §2.1.3",
            p1c213_pidcont,
        ),
        ex(
            "p1c213_pidbode",
            "Bode diagrams of the PID controller, the loop and the drive",
            "Part 1 §2.1.3",
            p1c213_pidbode,
        ),
        ex(
            "p1c221_id_cart",
            "Drive identification from open-loop voltage steps",
            "Part 1 §2.2.1",
            p1c221_id_cart,
        ),
        ex(
            "p1c223_pcont",
            "P gain from a second-order reference model",
            "Part 1 §2.2.3",
            p1c223_pcont,
        ),
        ex(
            "p1c224_p_dcont",
            "P–D control from a second-order reference model (ω_n = 5, 10)",
            "Part 1 §2.2.4",
            p1c224_p_dcont,
        ),
        ex(
            "p1c224_i_pdcont",
            "I–PD control from third-order reference models (binomial, Butterworth, ITAE)",
            "Part 1 §2.2.4",
            p1c224_i_pdcont,
        ),
        ex(
            "p1c23_crane",
            "Crane: I–PD cart control with and without pendulum damping",
            "Part 1 §2.3",
            p1c23_crane,
        ),
    ]
}

/// `(a_c, b_c)` of table 3.5.
fn drive() -> (f64, f64) {
    let p = CartPendulumParams::book();
    (p.a_c, p.b_c)
}

/// Roots of a polynomial in descending powers, in the workspace order.
pub(crate) fn roots(id: &'static str, coeffs: &[f64]) -> Result<Vec<Complex64>, BookError> {
    Polynomial::new(coeffs).and_then(|p| p.roots()).ctx(id)
}

/// One simulated run: time, cart position, pendulum angle from hanging, input voltage.
pub(crate) struct CartRun {
    pub label: String,
    pub t: Vec<f64>,
    pub z: Vec<f64>,
    /// The cart position as the rig measures it (encoder-quantised with the quantised rig).
    pub z_measured: Vec<f64>,
    pub theta: Vec<f64>,
    pub phi: Vec<f64>,
    pub v: Vec<f64>,
}

impl CartRun {
    /// Value of `z` at the last sample.
    pub fn z_final(&self) -> f64 {
        *self.z.last().unwrap_or(&f64::NAN)
    }
    /// Largest `z`.
    pub fn z_max(&self) -> f64 {
        self.z.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }
}

/// Simulates the nonlinear cart pendulum from the hanging rest under `controller` on the
/// quantised rig (or the plain one), with an optional constant input disturbance (V).
pub(crate) fn simulate_cart<C: Controller>(
    id: &'static str,
    label: impl Into<String>,
    controller: C,
    quantised: bool,
    disturbance: Option<f64>,
    t_final: f64,
) -> Result<CartRun, BookError> {
    let e = id;
    let spec = RigSpec::cart();
    let mut rig = if quantised {
        quantized_rig(e, &spec)?
    } else {
        RigChains::plain(spec.nx)
    };
    if let Some(d) = disturbance {
        rig.actuator = rig.actuator.disturbance(
            vec![Signal::constant(d).ctx(e)?],
            DisturbancePoint::BeforeSaturation,
        );
    }
    let opts = SampledOptions {
        ts: TS,
        t_final,
        ..Default::default()
    };
    let mut lp = SampledLoop::new(CartPendulum::book(), controller, opts)
        .ctx(e)?
        .with_rig(rig)
        .ctx(e)?;
    let run = lp.run(&[0.0, PI, 0.0, 0.0]).ctx(e)?;
    let tr = run.trajectory;
    let theta = tr.x_signal(1).to_vec();
    Ok(CartRun {
        label: label.into(),
        t: tr.t().to_vec(),
        z: tr.x_signal(0).to_vec(),
        z_measured: tr.y_signal(0).to_vec(),
        phi: theta.iter().map(|th| th - PI).collect(),
        theta,
        v: tr.u_signal(0).to_vec(),
    })
}

/// A PID-family law on the cart position `y[0]` of the rig's 4-entry measurement, following
/// the step `r = 0.1 m` at `t = 0`.
fn pid(id: &'static str, form: PidForm) -> Result<Pid, BookError> {
    let e = id;
    Pid::new(form, TS, PidDiscretization::Tustin)
        .ctx(e)?
        .reference(Signal::step(0.0, R).ctx(e)?)
        .measurement(0, 4)
        .ctx(e)
}

/// The usual figure of the chapter: z, φ and v of several runs overlaid.
fn response_figure(title: &str, runs: &[CartRun], reference: f64) -> pendulab_plot::Figure {
    let lines = |f: &dyn Fn(&CartRun) -> Vec<f64>| -> Vec<Line<'_>> {
        runs.iter()
            .map(|r| (r.label.clone(), r.t.as_slice(), f(r)))
            .collect()
    };
    stacked(
        title,
        "time [s]",
        vec![
            PanelSpec::new("cart position z [m]", lines(&|r| r.z.clone()))
                .reference(reference, "reference r"),
            PanelSpec::new("pendulum angle φ = θ − π [rad]", lines(&|r| r.phi.clone())),
            PanelSpec::new("input voltage v [V]", lines(&|r| r.v.clone())),
        ],
    )
}

fn write_response(
    id: &'static str,
    ctx: &RunContext,
    out: &mut ExampleOutput,
    runs: &[CartRun],
) -> Result<(), BookError> {
    if ctx.figures {
        let fig = response_figure(&format!("{id}: r = {R} m step"), runs, R);
        write_figure(out, &format!("{id}_response"), fig);
        if let Some(run) = runs.last() {
            write_animation(
                id,
                out,
                &format!("{id}_anim"),
                animation(
                    Rig::Cart,
                    &run.t,
                    &run.z,
                    &run.theta,
                    &format!("{id}: {}", run.label),
                ),
            )?;
        }
    }
    Ok(())
}

const NOTE_GAINS: &str = "Gains of the book's laws on the error e = r − z (classical control, \
     not state feedback; u = +k_P e + …). Simulated: nonlinear cart pendulum, pendulum hanging, \
     quantised rig at 1 ms, Tustin PID with derivative filter 1/(0.02 s + 1).";
