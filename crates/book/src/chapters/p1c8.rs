//! Part 1 chapter 8 — discretisation (zero-order hold and bilinear transform).

use super::common::*;
use super::p1c7::{ob_design, ob_figure, ob_summary, run_ob_controller};
use crate::error::BookError;
use crate::output::{ExampleOutput, Value};
use crate::registry::{Example, RunContext};
use pendulab_lti::design::observer_controller;
use pendulab_lti::linalg::eigenvalues;
use pendulab_lti::{Complex64, Discretization, LtiError, TransferFunction};
use pendulab_plot::{Bode, PoleZeroMap};

/// The chapter's examples, in book order.
pub(crate) fn examples() -> Vec<Example> {
    vec![
        Example {
            id: "p1c83_ex1_zero_order_hold",
            title: "Zero-order-hold discretisation of C(s) = 1/(s² + s + 1)",
            section: "Part 1 §8.3, example 8.1",
            parameters: "C(s) = 1/(s² + s + 1), ts = 1 s",
            needs_data: None,
            run: ex1_zoh,
        },
        Example {
            id: "p1c83_ex2_cdip_ob_design_zoh",
            title: "The observer-based controller of ch. 7 discretised by ZOH",
            section: "Part 1 §8.3, example 8.2",
            parameters: "cart pendulum, table 3.5; controller of p1c74_ex1, ZOH, ts = 0.01 s; quantised plant, θ0 = 10°, 3 s",
            needs_data: None,
            run: ex2_zoh,
        },
        Example {
            id: "p1c84_ex3_bilinear",
            title: "Bilinear (Tustin) discretisation of C(s) = 1/(s² + s + 1)",
            section: "Part 1 §8.4, example 8.3",
            parameters: "C(s) = 1/(s² + s + 1), ts = 1 s",
            needs_data: None,
            run: ex3_tustin,
        },
        Example {
            id: "p1c84_ex4_cdip_ob_design_bilinear",
            title: "The observer-based controller of ch. 7 discretised by Tustin",
            section: "Part 1 §8.4, example 8.4",
            parameters: "cart pendulum, table 3.5; controller of p1c74_ex1, Tustin, ts = 0.01 s; quantised plant, θ0 = 10°, 3 s",
            needs_data: None,
            run: ex4_tustin,
        },
    ]
}

/// `1/(s² + s + 1)` discretised at 1 s: `(num, den)` with `den` monic, descending powers of z.
pub(crate) fn discretize_c(method: Discretization) -> Result<(Vec<f64>, Vec<f64>), LtiError> {
    let c = TransferFunction::continuous(&[1.0], &[1.0, 1.0, 1.0])?;
    let d = c.c2d(1.0, method)?;
    let lead = d.den().leading();
    let num: Vec<f64> = d.num().coefficients().iter().map(|v| v / lead).collect();
    let den: Vec<f64> = d.den().coefficients().iter().map(|v| v / lead).collect();
    Ok((num, den))
}

fn tf_example(
    ctx: &RunContext,
    id: &str,
    method: Discretization,
    book: (&[f64], &[f64]),
    tol: f64,
    what: &str,
) -> Result<ExampleOutput, BookError> {
    let (num, den) = discretize_c(method).ctx(id)?;
    let mut out = ExampleOutput::default();
    out.value("num", Value::vector(&num))
        .value("den", Value::vector(&den));
    let source = format!("book Part 1 ch. 8, {id}.m");
    out.reference("num", Value::vector(book.0), &source, tol)
        .reference("den", Value::vector(book.1), &source, tol);
    out.notes.push(format!(
        "{what}: C[z] = num/den in descending powers of z, den monic."
    ));
    if ctx.figures {
        let c = TransferFunction::continuous(&[1.0], &[1.0, 1.0, 1.0]).ctx(id)?;
        let d = TransferFunction::discrete(&num, &den, 1.0).ctx(id)?;
        // Up to the Nyquist frequency π rad/s of ts = 1 s.
        let top = std::f64::consts::PI.log10();
        let w: Vec<f64> = (0..=200)
            .map(|k| 10f64.powf(-2.0 + k as f64 * (2.0 + top) / 200.0))
            .collect();
        let hc: Vec<Complex64> = w.iter().map(|&w| c.eval(Complex64::new(0.0, w))).collect();
        let hd: Vec<Complex64> = w
            .iter()
            .map(|&w| d.eval(Complex64::from_polar(1.0, w)))
            .collect();
        let fig = Bode::new()
            .response("C(s)", &w, &hc)
            .response(format!("C[z], {what}, ts = 1 s"), &w, &hd)
            .title(format!("{id}: continuous and discretised"))
            .figure();
        save_figure(ctx, &mut out, id, "bode", Ok(fig))?;
    }
    Ok(out)
}

fn ex1_zoh(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    // Printed to 4 decimals: half a unit of the last digit.
    tf_example(
        ctx,
        "p1c83_ex1_zero_order_hold",
        Discretization::Zoh,
        (&[0.3403, 0.2417], &[1.0, -0.7859, 0.3679]),
        5e-5,
        "zero-order hold",
    )
}

fn ex3_tustin(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    // Printed to 5 decimals: half a unit of the last digit.
    tf_example(
        ctx,
        "p1c84_ex3_bilinear",
        Discretization::Tustin { prewarp: None },
        (&[0.14286, 0.28571, 0.14286], &[1.0, -0.85714, 0.42857]),
        5e-6,
        "bilinear transform",
    )
}

/// The ch. 7 observer-based controller discretised at 10 ms by `method`, run on the
/// quantised rig against the continuous controller (its Tustin form at 1 ms).
fn ob_discrete(
    ctx: &RunContext,
    id: &str,
    method: Discretization,
    label: &str,
) -> Result<ExampleOutput, BookError> {
    let ts = 0.01;
    let (lin, fb, l) = ob_design(id)?;
    let ctrl = observer_controller(&lin, fb.gain(), &l).ctx(id)?;
    let cont_poles = sorted(eigenvalues(ctrl.a()).ctx(id)?);
    let disc = ctrl.c2d(ts, method).ctx(id)?;
    let disc_poles = sorted(eigenvalues(disc.a()).ctx(id)?);
    let mut out = ExampleOutput::default();
    out.value("Ad", Value::matrix(disc.a()))
        .value("Bd", Value::matrix(disc.b()))
        .value("Cd", Value::matrix(disc.c()))
        .value("Dd", Value::matrix(disc.d()))
        .value(
            "controller_poles_continuous",
            Value::Complex(cont_poles.clone()),
        )
        .value("controller_poles", Value::Complex(disc_poles.clone()));
    let traj = run_ob_controller(id, &lin, &fb, &l, ts, method)?;
    ob_summary(&traj, &mut out);
    out.notes.push(format!(
        "Controller (A + BK + LC, −L, K) of p1c74_ex1 (book signs) discretised by {label} at \
         ts = 10 ms and run on the quantised rig (encoders z, θ; ±5 V, 16-bit D/A) from θ0 = 10°."
    ));
    if ctx.figures {
        let cont = run_ob_controller(
            id,
            &lin,
            &fb,
            &l,
            1e-3,
            Discretization::Tustin { prewarp: None },
        )?;
        let lab = format!("{label}, ts = 10 ms");
        ob_figure(
            ctx,
            id,
            &format!("{id}: discretised observer-based controller"),
            &[("continuous (1 ms)", &cont), (lab.as_str(), &traj)],
            &mut out,
        )?;
        let fig = PoleZeroMap::discrete()
            .poles(format!("controller poles, {label}"), &disc_poles)
            .title(format!("{id}: discrete controller poles (ts = 10 ms)"))
            .figure();
        save_figure(ctx, &mut out, id, "poles", Ok(fig))?;
    }
    Ok(out)
}

fn ex2_zoh(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    ob_discrete(
        ctx,
        "p1c83_ex2_cdip_ob_design_zoh",
        Discretization::Zoh,
        "ZOH",
    )
}

fn ex4_tustin(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    ob_discrete(
        ctx,
        "p1c84_ex4_cdip_ob_design_bilinear",
        Discretization::Tustin { prewarp: None },
        "Tustin",
    )
}
