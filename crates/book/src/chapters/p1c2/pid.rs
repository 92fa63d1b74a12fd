//! Part 1 §2.1: P, PD, PI and PID control of the cart position, and the PID's Bode plot.

use super::*;

pub(super) const ID211: &str = "p1c211_pcont";

pub(super) fn p1c211_pcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
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
    finish_response(
        ID211,
        ctx,
        out,
        "z_max: the largest cart position of each run (k_P = 5, 10, 20); the overshoot grows \
         with k_P as the damping ratio a_c/(2√(b_c k_P)) falls.",
        &runs,
    )
}

pub(super) const ID212: &str = "p1c212_pdcont";

pub(super) fn p1c212_pdcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
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
    finish_response(
        ID212,
        ctx,
        out,
        "poles_kD01, poles_kD08: roots of s² + (a_c + b_c k_D) s + b_c k_P; the derivative \
         term adds damping. z_final: z at 10 s for k_D = 0.1, 0.8.",
        &runs,
    )
}

pub(super) const D: f64 = -0.1;

pub(super) const ID213I: &str = "p1c213_picont";

pub(super) fn p1c213_picont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
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
    finish_response(
        ID213I,
        ctx,
        out,
        "Input disturbance d = −0.1 V from t = 0. P control leaves e∞ = −d/k_P = 0.01 m \
         (final-value theorem); the integral term removes it (internal model principle). \
         e_final_*: r − z at 10 s.",
        &runs,
    )
}

pub(super) const ID213D: &str = "p1c213_pidcont";

pub(super) fn p1c213_pidcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
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
    finish_response(
        ID213D,
        ctx,
        out,
        "poles: roots of s³ + (a_c + b_c k_D) s² + b_c k_P s + b_c k_I; the PI run with the \
         same k_P, k_I is drawn for comparison. d = −0.1 V from t = 0.",
        &[pi_run, run],
    )
}

/// The tail of the PID family's response examples: the gains' note and the example's own
/// `note`, the response figure and animation of `runs` (when `ctx` asks for figures), and the
/// note that the example's M-file only sets the gains and draws its Simulink model's responses.
fn finish_response(
    id: &'static str,
    ctx: &RunContext,
    mut out: ExampleOutput,
    note: &str,
    runs: &[CartRun],
) -> Result<ExampleOutput, BookError> {
    out.notes.push(NOTE_GAINS.into());
    out.notes.push(note.into());
    write_response(id, ctx, &mut out, runs)?;
    no_display_note(
        &mut out,
        id,
        "it sets the gains and draws the responses of its Simulink model",
    );
    Ok(out)
}

pub(super) const ID213B: &str = "p1c213_pidbode";

pub(super) fn p1c213_pidbode(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
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
    if ctx.figures {
        let hp: Vec<Complex64> = w.iter().map(|&w| p(Complex64::new(0.0, w))).collect();
        let hc: Vec<Complex64> = w.iter().map(|&w| c(Complex64::new(0.0, w))).collect();
        let hl: Vec<Complex64> = w.iter().map(|&w| l(w)).collect();
        let fig = Bode::new()
            .response("C(s)", &w, &hc)
            .response("P(s)C(s)", &w, &hl)
            .response("P(s)", &w, &hp)
            .title("p1c213_pidbode: PID (k_P = 10, T_I = 2 s, T_D = 0.08 s)")
            .figure();
        write_figure(&mut out, "p1c213_pidbode_bode", fig);
    }
    no_display_note(&mut out, "p1c213_pidbode", "it draws Bode plots");
    Ok(out)
}
