//! Part 1 chapter 2: PID control of the cart position (book §2.1–2.3).
//!
//! Every simulation runs the nonlinear cart pendulum (table 3.5) with the pendulum hanging,
//! on the rig preset "with quantizer" (encoders, pseudo-differentiated velocities, ±5 V,
//! 16-bit D/A) at 1 kHz, the controllers being the discrete PID family of
//! `pendulab_sim::controllers::Pid` (Tustin, derivative filter `T_f = 0.02 s`, the rig's
//! pseudo-differentiator constant). Linear-loop poles use the drive `P(s) = b_c/(s(s + a_c))`
//! with an ideal derivative.

use super::common::*;
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
    if let Some(dir) = &ctx.out_dir {
        let fig = response_figure(&format!("{id}: r = {R} m step"), runs, R);
        write_figure(id, out, dir, &format!("{id}_response"), &fig)?;
        if let Some(run) = runs.last() {
            write_animation(
                id,
                out,
                dir,
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

// ---------------------------------------------------------------- §2.1 P, PD, PI, PID

const ID211: &str = "p1c211_pcont";

fn p1c211_pcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let (ac, bc) = drive();
    let mut out = ExampleOutput::default();
    let mut runs = Vec::new();
    let mut zmax = Vec::new();
    for kp in [5.0, 10.0, 20.0] {
        // Linear loop: s² + a_c s + b_c k_P = 0.
        let p = roots(ID211, &[1.0, ac, bc * kp])?;
        out.value(&format!("poles_kP{kp}"), Value::Complex(sorted(p)));
        let run = simulate_cart(
            ID211,
            format!("k_P = {kp}"),
            pid(ID211, PidForm::P { kp })?,
            true,
            None,
            10.0,
        )?;
        zmax.push(run.z_max());
        runs.push(run);
    }
    out.value("z_max", Value::Vector(zmax));
    out.reference(
        "poles_kP10",
        Value::Complex(complex(&[(-3.125, 5.817), (-3.125, -5.817)])),
        "book Part 1 §2.1.1",
        0.0005 * std::f64::consts::SQRT_2,
    );
    out.notes.push(NOTE_GAINS.into());
    out.notes.push(
        "z_max: the largest cart position of each run (k_P = 5, 10, 20); the overshoot grows \
         with k_P as the damping ratio a_c/(2√(b_c k_P)) falls."
            .into(),
    );
    write_response(ID211, ctx, &mut out, &runs)?;
    Ok(out)
}

const ID212: &str = "p1c212_pdcont";

fn p1c212_pdcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let (ac, bc) = drive();
    let kp = 10.0;
    let mut out = ExampleOutput::default();
    let mut runs = Vec::new();
    let mut finals = Vec::new();
    for (name, kd) in [("kD01", 0.1), ("kD08", 0.8)] {
        // s² + (a_c + b_c k_D) s + b_c k_P = 0.
        let p = roots(ID212, &[1.0, ac + bc * kd, bc * kp])?;
        out.value(&format!("poles_{name}"), Value::Complex(sorted(p)));
        let run = simulate_cart(
            ID212,
            format!("k_D = {kd}"),
            pid(ID212, PidForm::PD { kp, kd, tf: TF })?,
            true,
            None,
            10.0,
        )?;
        finals.push(run.z_final());
        runs.push(run);
    }
    out.value("z_final", Value::Vector(finals));
    out.notes.push(NOTE_GAINS.into());
    out.notes.push(
        "poles_kD01, poles_kD08: roots of s² + (a_c + b_c k_D) s + b_c k_P; the derivative \
         term adds damping. z_final: z at 10 s for k_D = 0.1, 0.8."
            .into(),
    );
    write_response(ID212, ctx, &mut out, &runs)?;
    Ok(out)
}

const D: f64 = -0.1;

const ID213I: &str = "p1c213_picont";

fn p1c213_picont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let (ac, bc) = drive();
    let kp = 10.0;
    let mut out = ExampleOutput::default();
    let mut runs = Vec::new();
    let p_run = simulate_cart(
        ID213I,
        "P only (k_I = 0)",
        pid(ID213I, PidForm::P { kp })?,
        true,
        Some(D),
        10.0,
    )?;
    out.value("e_final_kI0", Value::Number(R - p_run.z_final()));
    runs.push(p_run);
    for ki in [5.0, 25.0] {
        // s³ + a_c s² + b_c k_P s + b_c k_I = 0.
        let p = roots(ID213I, &[1.0, ac, bc * kp, bc * ki])?;
        out.value(&format!("poles_kI{ki}"), Value::Complex(sorted(p)));
        let run = simulate_cart(
            ID213I,
            format!("k_I = {ki}"),
            pid(ID213I, PidForm::PI { kp, ki })?,
            true,
            Some(D),
            10.0,
        )?;
        out.value(&format!("e_final_kI{ki}"), Value::Number(R - run.z_final()));
        runs.push(run);
    }
    out.notes.push(NOTE_GAINS.into());
    out.notes.push(
        "Input disturbance d = −0.1 V from t = 0. P control leaves e∞ = −d/k_P = 0.01 m \
         (final-value theorem); the integral term removes it (internal model principle). \
         e_final_*: r − z at 10 s."
            .into(),
    );
    write_response(ID213I, ctx, &mut out, &runs)?;
    Ok(out)
}

const ID213D: &str = "p1c213_pidcont";

fn p1c213_pidcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let (ac, bc) = drive();
    let (kp, kd, ki) = (10.0, 0.8, 5.0);
    let mut out = ExampleOutput::default();
    // s³ + (a_c + b_c k_D) s² + b_c k_P s + b_c k_I = 0.
    let p = roots(ID213D, &[1.0, ac + bc * kd, bc * kp, bc * ki])?;
    out.value("poles", Value::Complex(sorted(p)));
    let pi_run = simulate_cart(
        ID213D,
        "PI (k_P = 10, k_I = 5)",
        pid(ID213D, PidForm::PI { kp, ki })?,
        true,
        Some(D),
        10.0,
    )?;
    let run = simulate_cart(
        ID213D,
        "PID (k_P = 10, k_D = 0.8, k_I = 5)",
        pid(ID213D, PidForm::PID { kp, ki, kd, tf: TF })?,
        true,
        Some(D),
        10.0,
    )?;
    out.value("e_final", Value::Number(R - run.z_final()));
    out.value("z_max", Value::Number(run.z_max()));
    out.notes.push(NOTE_GAINS.into());
    out.notes.push(
        "poles: roots of s³ + (a_c + b_c k_D) s² + b_c k_P s + b_c k_I; the PI run with the \
         same k_P, k_I is drawn for comparison. d = −0.1 V from t = 0."
            .into(),
    );
    write_response(ID213D, ctx, &mut out, &[pi_run, run])?;
    Ok(out)
}

const ID213B: &str = "p1c213_pidbode";

fn p1c213_pidbode(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let (ac, bc) = drive();
    let (kp, kd, ki) = (10.0, 0.8, 5.0);
    let (ti, td) = (kp / ki, kd / kp);
    let p = |s: Complex64| Complex64::new(bc, 0.0) / (s * (s + ac));
    let c = |s: Complex64| kp * (1.0 + 1.0 / (ti * s) + td * s);
    let l = |w: f64| {
        let s = Complex64::new(0.0, w);
        p(s) * c(s)
    };
    // Gain crossover |L(jω)| = 1: bracket on a log grid, then bisection in log ω.
    let w = logspace(-2.0, 3.0, 501);
    let k = w
        .windows(2)
        .position(|p| (l(p[0]).norm() - 1.0) * (l(p[1]).norm() - 1.0) <= 0.0)
        .ok_or_else(|| fail(ID213B, "|P(jω)C(jω)| does not cross 1 on 0.01–1000 rad/s"))?;
    let (mut lo, mut hi) = (w[k].ln(), w[k + 1].ln());
    let f = |x: f64| l(x.exp()).norm() - 1.0;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(lo) * f(mid) <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let wc = (0.5 * (lo + hi)).exp();
    let pm = 180.0 + l(wc).arg().to_degrees();
    let mut out = ExampleOutput::default();
    out.value("TI", Value::Number(ti));
    out.value("TD", Value::Number(td));
    out.value("wc", Value::Number(wc));
    out.value("phase_margin", Value::Number(pm));
    out.notes.push(
        "C(s) = k_P (1 + 1/(T_I s) + T_D s) with k_P = 10, T_I = k_P/k_I = 2 s, \
         T_D = k_D/k_P = 0.08 s; wc is the gain crossover of P(s)C(s) (rad/s), phase_margin \
         in degrees."
            .into(),
    );
    if let Some(dir) = &ctx.out_dir {
        let hp: Vec<Complex64> = w.iter().map(|&w| p(Complex64::new(0.0, w))).collect();
        let hc: Vec<Complex64> = w.iter().map(|&w| c(Complex64::new(0.0, w))).collect();
        let hl: Vec<Complex64> = w.iter().map(|&w| l(w)).collect();
        let fig = Bode::new()
            .response("C(s)", &w, &hc)
            .response("P(s)C(s)", &w, &hl)
            .response("P(s)", &w, &hp)
            .title("p1c213_pidbode: PID (k_P = 10, T_I = 2 s, T_D = 0.08 s)")
            .figure();
        write_figure(ID213B, &mut out, dir, "p1c213_pidbode_bode", &fig)?;
    }
    Ok(out)
}

// ---------------------------------------------------------------- §2.2 identification, design

const ID221: &str = "p1c221_id_cart";

/// What `cartident.m` returns for one voltage step: the gain `K` and the time constant `T`.
#[derive(Debug, Clone, Copy)]
struct CartIdent {
    /// `K = mean(dy(1400:1500))/ref` (m/s per V).
    k: f64,
    /// `T = t(k)`, the last sample before the velocity first crosses `0.632 K ref` (s).
    t: f64,
}

/// `cartident.m` (called by `p1c221_id_cart.m`, line 36) line by line on the sampled position
/// `y` at times `t` (`t[0] = 0`, step `ts`):
///
/// - lines 5–10: `dy` by three-point differentiation, the one-sided formulas at both ends;
/// - lines 3, 14–15: `datasize = int32(tend/ts)`, `init_data = int32(1.4/ts)` (1500 and 1400 for
///   the M-file's `ts = 0.001`, `tend = 1.5`) and `K = mean(dy(init_data:datasize))`, i.e. the
///   101 samples `t = 1.399 … 1.499 s` of MATLAB's 1-based array;
/// - lines 17–24: the first `i ≤ datasize` with `dy(i) < 0.632 K` and `dy(i+1) > 0.632 K` (both
///   strict), and `T = t(i)`, the sample *before* the crossing;
/// - line 26: `K = K/ref`.
///
/// # Errors
/// [`BookError::Computation`] if the record is shorter than `datasize + 1` samples or the
/// velocity never crosses `0.632 K` (where MATLAB would stop with "undefined k").
fn cartident(
    id: &'static str,
    t: &[f64],
    y: &[f64],
    reference: f64,
    ts: f64,
    tend: f64,
) -> Result<CartIdent, BookError> {
    // MATLAB's int32() rounds to the nearest integer.
    let datasize = (tend / ts).round() as usize;
    let init_data = (1.4 / ts).round() as usize;
    if y.len() != t.len() || y.len() < datasize + 1 || init_data < 1 || init_data > datasize {
        return Err(fail(
            id,
            format!(
                "cartident needs {} samples of t and y (tend/ts + 1), got {} and {}",
                datasize + 1,
                t.len(),
                y.len()
            ),
        ));
    }
    let dy = pendulab_ident::three_point(y, ts).ctx(id)?;
    // dy(init_data:datasize), 1-based and inclusive.
    let window = &dy[init_data - 1..datasize];
    let k = window.iter().sum::<f64>() / window.len() as f64;
    let level = 0.632 * k;
    // for i = 1:datasize: dy(i) < 0.632K & dy(i+1) > 0.632K → T = t(i).
    let i = (0..datasize)
        .find(|&i| dy[i] < level && dy[i + 1] > level)
        .ok_or_else(|| {
            fail(
                id,
                format!(
                    "the velocity never crosses 0.632 K = {level} m/s before sample {datasize} \
                     (cartident.m, lines 17-22)"
                ),
            )
        })?;
    Ok(CartIdent {
        k: k / reference,
        t: t[i],
    })
}

/// MATLAB's `round(x*10^3)/10^3` (half away from zero, as `f64::round`).
fn round3(x: f64) -> f64 {
    (x * 1e3).round() / 1e3
}

fn p1c221_id_cart(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let e = ID221;
    // p1c221_id_cart.m, lines 33–63: cart_model.slx for ref = 0.8, 0.9, 1.0, 1.1 V, each record
    // through cartident(t, y_raw, ref, 0.001, 1.5). The model is the cart with the encoder and
    // D/A quantizers and ±5 V, the step applied at t = 0, 1 ms fixed step: pendulab's quantised
    // rig with a constant input. y_raw is the encoder position.
    let refs = [0.8, 0.9, 1.0, 1.1];
    let mut runs = Vec::new();
    let mut ids = Vec::new();
    let mut exact = Vec::new();
    for u in refs {
        let ctrl = OpenLoop::new(vec![Signal::step(0.0, u).ctx(e)?], 4);
        let run = simulate_cart(ID221, format!("u(t) = {u}"), ctrl, true, None, 2.0)?;
        ids.push(cartident(e, &run.t, &run.z_measured, u, TS, 1.5)?);
        exact.push(cartident(e, &run.t, &run.z, u, TS, 1.5)?);
        runs.push(run);
    }
    // Lines 69–70: the means rounded to 1e-3; lines 72–77 print K, T, a = 1/T, b = K/T.
    let mean = |f: &dyn Fn(&CartIdent) -> f64, v: &[CartIdent]| {
        v.iter().map(f).sum::<f64>() / v.len() as f64
    };
    let tave = round3(mean(&|c| c.t, &ids));
    let kave = round3(mean(&|c| c.k, &ids));
    let (a, b) = (1.0 / tave, kave / tave);
    let mut out = ExampleOutput::default();
    out.value("ac", Value::Number(a));
    out.value("bc", Value::Number(b));
    out.value("Kave", Value::Number(kave));
    out.value("Tave", Value::Number(tave));
    out.value("a", Value::Number(a));
    out.value("b", Value::Number(b));
    for (j, c) in ids.iter().enumerate() {
        out.value(&format!("K{}", j + 1), Value::Number(c.k));
        out.value(&format!("T{}", j + 1), Value::Number(c.t));
    }
    // pendulab's addition: the same recipe on the exact (unquantised) cart position.
    let tx = round3(mean(&|c| c.t, &exact));
    let kx = round3(mean(&|c| c.k, &exact));
    out.value("ac_unquantised", Value::Number(1.0 / tx));
    out.value("bc_unquantised", Value::Number(kx / tx));
    // The book prints a = 6.250e+00, b = 4.362e+00 (Kave = 0.698, Tave = 0.160 → b = 4.3625):
    // both are exact results of the rounded means, so the tolerance is the rounding of b's
    // last printed digit.
    let src = "book §2.2.1 (p1c221_id_cart.m, lines 72-77)";
    out.reference("Kave", Value::Number(0.698), src, 1e-9);
    out.reference("Tave", Value::Number(0.160), src, 1e-9);
    out.reference("a", Value::Number(6.250), src, 0.0005);
    out.reference("b", Value::Number(4.3625), src, 0.0005);
    out.reference(
        "ac",
        Value::Number(6.250),
        "book Part 1 §2.2.1 (cdip_para2.m)",
        0.0005,
    );
    out.reference(
        "bc",
        Value::Number(4.362),
        "book Part 1 §2.2.1 (cdip_para2.m)",
        0.001,
    );
    out.notes.push(
        "As p1c221_id_cart.m with cartident.m: open-loop voltage steps u = 0.8, 0.9, 1.0, 1.1 V \
         on the simulated rig (nonlinear cart pendulum, table 3.5, encoder and 16-bit D/A \
         quantizers, 1 ms); dy by three-point differentiation of the encoder position; K_i = \
         mean of dy over samples 1400-1500 of the M-file's 1-based array (t = 1.399-1.499 s) \
         divided by u; T_i = the last sample below 0.632 K u before the first crossing. Kave, \
         Tave: the means rounded to 1e-3 (lines 69-70); a = 1/Tave, b = Kave/Tave (ac, bc). \
         The quantised velocity moves in steps of 0.024 m/s, so the T_i scatter by several ms \
         (K1..K4, T1..T4); ac_unquantised, bc_unquantised: the same recipe on the exact \
         position."
            .into(),
    );
    if let Some(dir) = &ctx.out_dir {
        let vel: Vec<Vec<f64>> = runs
            .iter()
            .map(|r| pendulab_ident::three_point(&r.z_measured, TS).ctx(e))
            .collect::<Result<_, _>>()?;
        let lines: Vec<Line<'_>> = runs
            .iter()
            .zip(&vel)
            .map(|(r, v)| (r.label.clone(), r.t.as_slice(), v.clone()))
            .collect();
        let mut panel = PanelSpec::new("dy(t)/dt [m/s]", lines);
        for (u, c) in refs.iter().zip(&ids) {
            panel = panel.reference(c.k * u, &format!("K u = {:.3}", c.k * u));
        }
        let fig = stacked(
            "p1c221_id_cart: open-loop velocity steps",
            "t [s]",
            vec![panel],
        );
        write_figure(ID221, &mut out, dir, "p1c221_id_cart_velocity", &fig)?;
    }
    Ok(out)
}

/// Step response of the reference model ω_n²/(s² + 2ζω_n s + ω_n²) at times `t`.
fn second_order_step(t: &[f64], wn: f64, zeta: f64) -> Vec<f64> {
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let phi = zeta.acos();
    t.iter()
        .map(|&t| {
            R * (1.0 - (-zeta * wn * t).exp() / (1.0 - zeta * zeta).sqrt() * (wd * t + phi).sin())
        })
        .collect()
}

const ZETA: f64 = std::f64::consts::FRAC_1_SQRT_2;

const ID223: &str = "p1c223_pcont";

fn p1c223_pcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let (ac, bc) = drive();
    let speed = |wn: f64| wn * wn / bc;
    let partial = |wn: f64| ac * wn / (2.0 * bc * ZETA);
    let gains = [
        ("kP_speed_wn5", "speed matching, ω_n = 5", speed(5.0)),
        ("kP_speed_wn10", "speed matching, ω_n = 10", speed(10.0)),
        (
            "kP_partial_wn10",
            "partial model matching, ω_n = 10",
            partial(10.0),
        ),
    ];
    let mut out = ExampleOutput::default();
    let mut runs = Vec::new();
    for (name, label, kp) in gains {
        out.value(name, Value::Number(kp));
        runs.push(simulate_cart(
            ID223,
            format!("{label} (k_P = {kp:.3})"),
            pid(ID223, PidForm::P { kp })?,
            true,
            None,
            3.0,
        )?);
    }
    out.notes.push(NOTE_GAINS.into());
    out.notes.push(
        "Reference model ω_n²/(s² + 2ζω_n s + ω_n²), ζ = 1/√2. Speed matching equates the \
         constant terms: k_P = ω_n²/b_c; partial model matching the ratio of the first two \
         coefficients: k_P = a_c ω_n/(2 b_c ζ). a_c, b_c from table 3.5."
            .into(),
    );
    if let Some(dir) = &ctx.out_dir {
        let fig = model_match_figure(
            "p1c223_pcont: P control against the reference models",
            &runs,
        );
        write_figure(ID223, &mut out, dir, "p1c223_pcont_response", &fig)?;
    }
    Ok(out)
}

/// Cart position and input of `runs` (3 s steps of r), the position overlaid with the reference
/// models' steps for ω_n = 5 and 10 rad/s.
fn model_match_figure(title: &str, runs: &[CartRun]) -> pendulab_plot::Figure {
    let t = runs[0].t.clone();
    let mut lines: Vec<Line<'_>> = runs
        .iter()
        .map(|r| (r.label.clone(), r.t.as_slice(), r.z.clone()))
        .collect();
    lines.push(("model ω_n = 5".into(), &t, second_order_step(&t, 5.0, ZETA)));
    lines.push((
        "model ω_n = 10".into(),
        &t,
        second_order_step(&t, 10.0, ZETA),
    ));
    stacked(
        title,
        "time [s]",
        vec![
            PanelSpec::new("cart position z [m]", lines),
            PanelSpec::new(
                "input voltage v [V]",
                runs.iter()
                    .map(|r| (r.label.clone(), r.t.as_slice(), r.v.clone()))
                    .collect(),
            ),
        ],
    )
}

const ID224PD: &str = "p1c224_p_dcont";

fn p1c224_p_dcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let (ac, bc) = drive();
    let mut out = ExampleOutput::default();
    let mut runs = Vec::new();
    for wn in [5.0, 10.0] {
        let kp = wn * wn / bc;
        let kd = (2.0 * ZETA * wn - ac) / bc;
        out.value(&format!("kP_wn{wn}"), Value::Number(kp));
        out.value(&format!("kD_wn{wn}"), Value::Number(kd));
        runs.push(simulate_cart(
            ID224PD,
            format!("ω_n = {wn} (k_P = {kp:.3}, k_D = {kd:.3})"),
            pid(ID224PD, PidForm::PMinusD { kp, kd, tf: TF })?,
            true,
            None,
            3.0,
        )?);
    }
    out.notes.push(NOTE_GAINS.into());
    out.notes.push(
        "P–D (derivative on the output z): the loop is exactly the reference model \
         ω_n²/(s² + 2ζω_n s + ω_n²) with k_P = ω_n²/b_c, k_D = (2ζω_n − a_c)/b_c, ζ = 1/√2."
            .into(),
    );
    if let Some(dir) = &ctx.out_dir {
        let fig = model_match_figure(
            "p1c224_p_dcont: P–D control and its reference models",
            &runs,
        );
        write_figure(ID224PD, &mut out, dir, "p1c224_p_dcont_response", &fig)?;
    }
    Ok(out)
}

/// I–PD gains `[k_I, k_P, k_D]` from `s³ + α₂ω_n s² + α₁ω_n² s + ω_n³`, in the order of
/// `p1c224_i_pdcont.m` (lines 42–44): `k_I = ω_n³/b_c`, `k_P = α₁ω_n²/b_c`,
/// `k_D = (α₂ω_n − a_c)/b_c`.
pub(crate) fn ipd_gains(alpha1: f64, alpha2: f64, wn: f64) -> [f64; 3] {
    let (ac, bc) = drive();
    [
        wn.powi(3) / bc,
        alpha1 * wn * wn / bc,
        (alpha2 * wn - ac) / bc,
    ]
}

const ID224IPD: &str = "p1c224_i_pdcont";

fn p1c224_i_pdcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let wn = 10.0;
    let mut out = ExampleOutput::default();
    let mut runs = Vec::new();
    // p1c224_i_pdcont.m: omegaM = 10 (line 36); (alpha1, alpha2) = (3, 3) binomial (lines
    // 39–40), (2, 2) Butterworth (lines 54–55), (2.15, 1.75) ITAE (lines 68–69).
    for (name, label, alpha1, alpha2) in [
        ("gains_binomial", "binomial", 3.0, 3.0),
        ("gains_butterworth", "Butterworth", 2.0, 2.0),
        ("gains_itae", "ITAE", 2.15, 1.75),
    ] {
        let [ki, kp, kd] = ipd_gains(alpha1, alpha2, wn);
        out.value(name, Value::Vector(vec![ki, kp, kd]));
        runs.push(simulate_cart(
            ID224IPD,
            label,
            pid(ID224IPD, PidForm::IPD { kp, ki, kd, tf: TF })?,
            true,
            None,
            3.0,
        )?);
    }
    out.value("alpha1", Value::Vector(vec![3.0, 2.0, 2.15]));
    out.value("alpha2", Value::Vector(vec![3.0, 2.0, 1.75]));
    // The M-file's ITAE gains with table 3.5 (a_c = 6.25, b_c = 4.36), rounded to 1e-3:
    // [1000/4.36, 215/4.36, (17.5 − 6.25)/4.36].
    out.reference(
        "gains_itae",
        Value::Vector(vec![229.358, 49.312, 2.580]),
        "p1c224_i_pdcont.m, lines 68-73",
        0.0005,
    );
    out.notes.push(NOTE_GAINS.into());
    out.notes.push(
        "I–PD u = (k_I/s) e − k_P z − k_D ż: closed loop b_c k_I/(s³ + (a_c + b_c k_D) s² + \
         b_c k_P s + b_c k_I) matched to ω_n³/(s³ + α₂ω_n s² + α₁ω_n² s + ω_n³), ω_n = 10, as \
         p1c224_i_pdcont.m: kI = ω_n³/b, kP = α₁ω_n²/b, kD = (α₂ω_n − a)/b; gains reported as \
         [kI, kP, kD] for (α₁, α₂) = (3, 3) binomial, (2, 2) Butterworth, (2.15, 1.75) ITAE \
         (alpha1, alpha2 in that order)."
            .into(),
    );
    if let Some(dir) = &ctx.out_dir {
        let fig = response_figure("p1c224_i_pdcont: I–PD, ω_n = 10", &runs, R);
        write_figure(ID224IPD, &mut out, dir, "p1c224_i_pdcont_response", &fig)?;
    }
    Ok(out)
}

/// I–PD on the cart position plus pendulum damping `u ← u − (k_P2 φ + k_D2 φ̇)` (book §2.3).
#[derive(Debug, Clone)]
struct Crane {
    ipd: Pid,
    kp2: f64,
    kd2: f64,
}

impl Controller for Crane {
    fn ny(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {
        self.ipd.reset();
    }
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        self.ipd.update(t, y, u);
        // y = [z, θ, ż, θ̇] (quantised, pseudo-differentiated); φ = θ − π.
        u[0] -= self.kp2 * (y[1] - PI) + self.kd2 * y[3];
    }
    fn sample_time(&self) -> Option<f64> {
        self.ipd.sample_time()
    }
}

const ID23: &str = "p1c23_crane";

fn p1c23_crane(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let e = ID23;
    let [ki, kp, kd] = ipd_gains(2.0, 2.0, 10.0);
    let plant = CartPendulum::book();
    let lin = plant.linearize(CartEquilibrium::hanging()).ctx(e)?;
    let mut out = ExampleOutput::default();
    let mut runs = Vec::new();
    for (name, kp2, kd2) in [("without", 0.0, 0.0), ("with", -1.0, -0.1)] {
        // Linear closed loop on x̃ = [z, φ, ż, φ̇, w], ẇ = r − z, u = k_I w − k_P z − k_D ż −
        // k_P2 φ − k_D2 φ̇ (ideal derivative).
        let mut acl = Mat::zeros(5, 5);
        acl.view_mut((0, 0), (4, 4)).copy_from(lin.a());
        acl[(4, 0)] = -1.0;
        let k = [-kp, -kp2, -kd, -kd2, ki];
        for i in 0..4 {
            for (j, kj) in k.iter().enumerate() {
                acl[(i, j)] += lin.b()[(i, 0)] * kj;
            }
        }
        let poles = pendulab_lti::linalg::eigenvalues(&acl).ctx(e)?;
        out.value(&format!("poles_{name}"), Value::Complex(sorted(poles)));
        let ctrl = Crane {
            ipd: pid(ID23, PidForm::IPD { kp, ki, kd, tf: TF })?,
            kp2,
            kd2,
        };
        let label = if name == "without" {
            "without damping".to_string()
        } else {
            "with damping (k_P2 = −1, k_D2 = −0.1)".to_string()
        };
        let run = simulate_cart(ID23, label, ctrl, true, None, 5.0)?;
        let k1 = run.t.partition_point(|&t| t < 1.0);
        let m = run.phi[k1..].iter().fold(0.0f64, |m, p| m.max(p.abs()));
        out.value(&format!("phi_max_after_1s_{name}"), Value::Number(m));
        runs.push(run);
    }
    out.notes.push(NOTE_GAINS.into());
    out.notes.push(
        "I–PD (Butterworth, ω_n = 10) on the cart; the damping term u ← u − (k_P2 φ + k_D2 φ̇) \
         with k_P2 = −1, k_D2 = −0.1 feeds the swing back into the drive. poles_*: the \
         linearised (hanging) closed loop on [z, φ, ż, φ̇, w]; without damping they are the \
         I–PD poles ω_n·{−1, −½ ± j√3/2} and the free pendulum's. phi_max_after_1s_*: the \
         largest |φ| after the cart has arrived."
            .into(),
    );
    if let Some(dir) = &ctx.out_dir {
        let fig = response_figure("p1c23_crane: I–PD with and without damping", &runs, R);
        write_figure(ID23, &mut out, dir, "p1c23_crane_response", &fig)?;
        for (run, stem) in runs.iter().zip(["without", "with"]) {
            write_animation(
                ID23,
                &mut out,
                dir,
                &format!("p1c23_crane_anim_{stem}"),
                animation(
                    Rig::Cart,
                    &run.t,
                    &run.z,
                    &run.theta,
                    &format!("crane, {}", run.label),
                ),
            )?;
        }
    }
    Ok(out)
}
