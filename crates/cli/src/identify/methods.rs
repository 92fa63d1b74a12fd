//! The identification itself: the record read and windowed, the columns and data checked,
//! then each method's estimate recorded through the [`Gate`] — the least-squares drive and
//! pendulum regressions, the P-control step response, the free oscillation — with its
//! validation against the measured record.

use super::report::{FitMeaning, Gate, Report, fit_json, g4};
use super::{IdentifyArgs, Method, known_constants, ls_options, options_json, parse_window};
use anyhow::{Context, Result, bail};
use pendulab_ident::{
    ArmPendulumConstants, CartPendulumConstants, Dataset, IdentError, LeastSquares, LsOptions,
    OscillationOptions, PStepOptions, PeriodCorrection, Validation, arm_drive_ls, arm_pendulum_ls,
    cart_drive_ls, cart_pendulum_ls, free_oscillation, p_step, pendulum_from_oscillation,
    validate_arm_pendulum, validate_cart_pendulum, validate_drive, validate_free_pendulum,
    validate_oscillation, validate_p_step,
};
use serde_json::{Map, Value, json};

/// What every method reads: the arguments, the windowed record and its sampling, the
/// least-squares options and the known constants.
struct Input<'a> {
    args: &'a IdentifyArgs,
    source: &'a str,
    data: &'a Dataset,
    ts: f64,
    t: &'a [f64],
    /// The window's start (the P step's default step time).
    w0: Option<f64>,
    opts: LsOptions,
    cart: CartPendulumConstants,
    arm: ArmPendulumConstants,
}

/// What every method writes: the gate (its warnings), the estimates, their standard errors
/// and the report.
struct Output {
    gate: Gate,
    est: Map<String, Value>,
    se: Map<String, Value>,
    report: Report,
}

/// One number of a least-squares result, in the order the gate sees them.
enum Put {
    /// An estimate.
    Est(&'static str, f64),
    /// A standard error.
    Se(&'static str, f64),
}

/// Identifies by `args.method`: the report with every estimate, or the first refusal.
pub(super) fn identify(args: &IdentifyArgs) -> Result<Report> {
    let source = args.data.display().to_string();
    let text =
        std::fs::read_to_string(&args.data).with_context(|| format!("cannot read {source}"))?;
    let mut gate = Gate {
        force: args.force,
        warnings: Vec::new(),
    };
    let mut full = Dataset::from_csv_str(&source, &text)?;
    if let Some(u) = args.time_unit {
        full = full.with_time_unit(u.into())?;
    }
    // The unit is judged on the whole record, before a window (in seconds) is cut from it.
    gate.check(full.check_time_unit())?;
    let (w0, w1) = match &args.window {
        Some(s) => parse_window(s)?,
        None => (None, None),
    };
    let data = full.window(w0, w1)?;
    let ts = data.uniform_step()?;
    let t = data.time()?;
    let span = [t[0], t[t.len() - 1]];
    let opts = ls_options(args);
    let (cart, arm) = known_constants(args)?;
    let report = Report {
        method: args.method.name(),
        data: source.clone(),
        window: span,
        samples: data.len(),
        ts,
        options: Value::Null,
        constants: Value::Null,
        estimates: Map::new(),
        std_errors: Map::new(),
        condition: None,
        residual_rms: None,
        fit: json!({"skipped": "no validation was run"}),
        fit_linear: None,
        warnings: Vec::new(),
        units: Vec::new(),
    };
    let input = Input {
        args,
        source: &source,
        data: &data,
        ts,
        t,
        w0,
        opts,
        cart,
        arm,
    };
    let mut out = Output {
        gate,
        est: Map::new(),
        se: Map::new(),
        report,
    };
    check_input(&input, &mut out.gate, span)?;
    match args.method {
        Method::CartLs | Method::ArmLs => drive_ls(&input, &mut out)?,
        Method::PendLs => cart_pendulum(&input, &mut out)?,
        Method::ArmPendLs => arm_pendulum(&input, &mut out)?,
        Method::CartStep | Method::ArmStep => p_step_response(&input, &mut out)?,
        Method::PendFree | Method::ArmPendFree => free_swing(&input, &mut out)?,
        // Refused by `check_input` (the columns' match).
        Method::Arx | Method::Moesp => {}
    }
    let Output {
        gate,
        est,
        se,
        mut report,
    } = out;
    report.estimates = est;
    report.std_errors = se;
    report.warnings = gate.warnings;
    Ok(report)
}

/// Structural errors first: every column the method reads must be present; then the
/// least-squares methods' sample count and the pendulum methods' constants.
fn check_input(i: &Input<'_>, gate: &mut Gate, span: [f64; 2]) -> Result<()> {
    let args = i.args;
    let signal = |cart: &str, arm: &str| -> String {
        args.column.clone().unwrap_or_else(|| {
            if matches!(args.method, Method::CartStep | Method::PendFree) {
                cart.to_string()
            } else {
                arm.to_string()
            }
        })
    };
    let needed: Vec<String> = match args.method {
        Method::CartLs => vec!["z".into(), "v".into()],
        Method::ArmLs => vec!["phi1".into(), "v".into()],
        Method::PendLs => vec!["z".into(), "phi".into()],
        Method::ArmPendLs => vec!["phi1".into(), "phi2".into()],
        Method::CartStep | Method::ArmStep => vec![signal("z", "theta1")],
        Method::PendFree | Method::ArmPendFree => vec![signal("theta", "theta2")],
        Method::Arx | Method::Moesp => {
            bail!("identify: arx and moesp are run by identify_blackbox")
        }
    };
    for c in &needed {
        i.data.column(c)?;
    }
    let ls_method = matches!(
        args.method,
        Method::CartLs | Method::ArmLs | Method::PendLs | Method::ArmPendLs
    );
    if ls_method {
        let source = i.source;
        let named = i.opts.check_data(i.ts, i.data.len()).map_err(|e| match e {
            IdentError::TooFewSamples {
                what,
                needed,
                found,
                ..
            } => IdentError::TooFewSamples {
                source_name: format!("{source} (t = {} … {} s)", span[0], span[1]),
                what,
                needed,
                found,
            },
            other => other,
        });
        gate.check(named)?;
    }
    match args.method {
        Method::PendLs | Method::PendFree => gate.check(i.cart.check_range())?,
        Method::ArmPendLs | Method::ArmPendFree => gate.check(i.arm.check_range())?,
        _ => {}
    }
    Ok(())
}

/// Records a least-squares result: its failed checks through the gate, the numbers `puts` in
/// order, the solution's condition number and residual RMS, the validation `validate` with
/// its `meaning`, the options, the `constants` and the `units`.
fn record_ls(
    i: &Input<'_>,
    o: &mut Output,
    failed: Vec<IdentError>,
    puts: &[Put],
    lsq: &LeastSquares,
    meaning: &FitMeaning<'_>,
    validate: impl FnOnce() -> pendulab_ident::Result<Validation>,
    constants: Value,
) -> Result<()> {
    let gate = &mut o.gate;
    gate.check_all(failed)?;
    for p in puts {
        match *p {
            Put::Est(n, v) => gate.put(&mut o.est, n, v)?,
            Put::Se(n, v) => gate.put_se(&mut o.se, n, v)?,
        }
    }
    o.report.condition = Some(gate.num("condition number", lsq.condition)?);
    o.report.residual_rms = Some(gate.num("residual RMS", lsq.residual_rms)?);
    if let Some(val) = gate.soft("validation", validate())? {
        o.report.fit = fit_json(gate, &val, meaning)?;
    }
    o.report.options = options_json(&i.opts);
    o.report.constants = constants;
    Ok(())
}

/// `cart-ls`, `arm-ls`: the drive `ÿ = −a ẏ + b v` by least squares.
fn drive_ls(i: &Input<'_>, o: &mut Output) -> Result<()> {
    let (ts, opts) = (i.ts, &i.opts);
    let cart = i.args.method == Method::CartLs;
    let (ycol, names) = if cart {
        ("z", ["ac", "bc"])
    } else {
        ("phi1", ["a1", "b1"])
    };
    let (y, v) = (i.data.column(ycol)?, i.data.column("v")?);
    let d = if cart {
        cart_drive_ls(ts, y, v, opts)?
    } else {
        arm_drive_ls(ts, y, v, opts)?
    };
    let meaning = FitMeaning {
        model: format!(
            "the identified drive {ycol}'' = −{} {ycol}' + ({}) v (exact ZOH simulation, open loop from the measured initial state)",
            g4(d.a),
            g4(d.b)
        ),
        input: "the measured voltage v",
        t: i.t,
    };
    let puts: Vec<Put> = names
        .iter()
        .enumerate()
        .flat_map(|(k, n)| {
            [
                Put::Est(n, d.lsq.estimate[k]),
                Put::Se(n, d.lsq.std_error[k]),
            ]
        })
        .collect();
    record_ls(
        i,
        o,
        d.failed_checks(ts),
        &puts,
        &d.lsq,
        &meaning,
        || validate_drive(ts, y, v, d.a, d.b, ycol),
        json!({}),
    )?;
    o.report.units = if cart {
        vec![("ac", "1/s"), ("bc", "m/(s^2 V)")]
    } else {
        vec![("a1", "1/s"), ("b1", "rad/(s^2 V)")]
    };
    Ok(())
}

/// `pend-ls`: the cart pendulum `[J_p, μ_p]` by least squares.
fn cart_pendulum(i: &Input<'_>, o: &mut Output) -> Result<()> {
    let (ts, cart) = (i.ts, &i.cart);
    let (z, phi) = (i.data.column("z")?, i.data.column("phi")?);
    let p = cart_pendulum_ls(ts, z, phi, cart, &i.opts)?;
    let meaning = FitMeaning {
        model: "the identified nonlinear cart pendulum (J_p, μ_p with the known m_p, l_p, g; RK4 from the measured initial angle and rate)".into(),
        input: "the measured cart acceleration (three-point z'' of z)",
        t: i.t,
    };
    record_ls(
        i,
        o,
        p.failed_checks(ts, cart),
        &[
            Put::Est("Jp", p.jp),
            Put::Est("mup", p.mup),
            Put::Se("Jp", p.lsq.std_error[0]),
            Put::Se("mup", p.lsq.std_error[1]),
        ],
        &p.lsq,
        &meaning,
        || validate_cart_pendulum(ts, z, phi, p.jp, p.mup, cart),
        json!({"mp": cart.mp, "lp": cart.lp, "g": cart.g}),
    )?;
    o.report.units = vec![("Jp", "kg m^2"), ("mup", "N m s/rad")];
    Ok(())
}

/// `arm-pend-ls`: the arm pendulum `[α₂, μ₂] → J₂` by least squares.
fn arm_pendulum(i: &Input<'_>, o: &mut Output) -> Result<()> {
    let (ts, arm) = (i.ts, &i.arm);
    let (p1, p2) = (i.data.column("phi1")?, i.data.column("phi2")?);
    let p = arm_pendulum_ls(ts, p1, p2, arm, &i.opts)?;
    let meaning = FitMeaning {
        model: "the identified nonlinear arm pendulum (α₂, μ₂ with the known L1, m2, l2, g; RK4 from the measured initial angle and rate)".into(),
        input: "the measured arm motion phi1 (with its three-point derivatives)",
        t: i.t,
    };
    record_ls(
        i,
        o,
        p.failed_checks(ts, arm),
        &[
            Put::Est("J2", p.j2),
            Put::Est("mu2", p.mu2),
            Put::Est("alpha2", p.alpha2),
            Put::Se("J2", p.lsq.std_error[0]),
            Put::Se("mu2", p.lsq.std_error[1]),
            Put::Se("alpha2", p.lsq.std_error[0]),
        ],
        &p.lsq,
        &meaning,
        || validate_arm_pendulum(ts, p1, p2, p.alpha2, p.mu2, arm),
        json!({"L1": arm.l1, "m2": arm.m2, "l2": arm.l2, "g": arm.g}),
    )?;
    o.report.units = vec![("J2", "kg m^2"), ("mu2", "N m s/rad"), ("alpha2", "kg m^2")];
    Ok(())
}

/// `cart-step`, `arm-step`: the drive from the P-control step response (book part 1 §3.2).
fn p_step_response(i: &Input<'_>, out: &mut Output) -> Result<()> {
    let (t, w0, source) = (i.t, i.w0, i.source);
    let cart_step = i.args.method == Method::CartStep;
    let col = i
        .args
        .column
        .clone()
        .unwrap_or_else(|| if cart_step { "z" } else { "theta1" }.to_string());
    let y = i.data.column(&col)?;
    let o = PStepOptions {
        step_time: i.args.step_time.or(w0).unwrap_or(1.0),
        target: i.args.target.unwrap_or(if cart_step { 0.2 } else { 1.0 }),
        k_p: i.args.kp.unwrap_or(if cart_step { 10.0 } else { 3.0 }),
    };
    let e = p_step(t, y, &o).with_context(|| format!("{source}: column '{col}'"))?;
    let (a, b) = if cart_step {
        ("ac", "bc")
    } else {
        ("a1", "b1")
    };
    out.gate.put(&mut out.est, a, e.a)?;
    out.gate.put(&mut out.est, b, e.b)?;
    out.gate.put(&mut out.est, "Tp", e.tp)?;
    out.gate.put(&mut out.est, "overshoot", e.overshoot)?;
    out.gate.put(&mut out.est, "omega_n", e.omega_n)?;
    out.gate.put(&mut out.est, "zeta", e.zeta)?;
    let meaning = FitMeaning {
        model: format!(
            "the P-control loop of the identified drive ({a} = {}, {b} = {}, k_P = {}), at rest at the step time {} s",
            g4(e.a),
            g4(e.b),
            o.k_p,
            o.step_time
        ),
        input: &format!("the reference step to {}", o.target),
        t,
    };
    if let Some(mut val) = out.gate.soft(
        "validation",
        validate_p_step(t, y, o.step_time, o.target, o.k_p, e.a, e.b),
    )? {
        val.output = col.clone();
        out.report.fit = fit_json(&mut out.gate, &val, &meaning)?;
    }
    out.report.options = json!({"column": col, "step_time": o.step_time});
    out.report.constants = json!({"kP": o.k_p, "target": o.target});
    out.report.units = vec![
        (a, "1/s"),
        (
            b,
            if cart_step {
                "m/(s^2 V)"
            } else {
                "rad/(s^2 V)"
            },
        ),
        ("Tp", "s"),
        ("overshoot", if cart_step { "m" } else { "rad" }),
        ("omega_n", "rad/s"),
        ("zeta", "-"),
    ];
    Ok(())
}

/// `pend-free`, `arm-pend-free`: the pendulum from its free oscillation, validated by the
/// nonlinear pendulum and the book's linear oscillation.
fn free_swing(i: &Input<'_>, out: &mut Output) -> Result<()> {
    let (ts, t, source) = (i.ts, i.t, i.source);
    let (cart, arm) = (&i.cart, &i.arm);
    let cart_pend = i.args.method == Method::PendFree;
    let col = i
        .args
        .column
        .clone()
        .unwrap_or_else(|| if cart_pend { "theta" } else { "theta2" }.to_string());
    let y = i.data.column(&col)?;
    let osc = free_oscillation(
        t,
        y,
        &OscillationOptions {
            hysteresis: i.args.hysteresis,
        },
    )
    .with_context(|| format!("{source}: column '{col}'"))?;
    let (m, l, g) = if cart_pend {
        (cart.mp, cart.lp, cart.g)
    } else {
        (arm.m2, arm.l2, arm.g)
    };
    let correction = if i.args.amplitude_correction {
        PeriodCorrection::LargeAmplitude
    } else {
        PeriodCorrection::None
    };
    let p = pendulum_from_oscillation(&osc, m, l, g, correction)?;
    let (jn, mun) = if cart_pend {
        ("Jp", "mup")
    } else {
        ("J2", "mu2")
    };
    out.gate.put(&mut out.est, jn, p.j)?;
    out.gate.put(&mut out.est, mun, p.mu)?;
    out.gate.put(&mut out.est, "period", osc.period)?;
    out.gate.put(&mut out.est, "decay_ratio", osc.decay_ratio)?;
    out.gate.put(&mut out.est, "omega_n", p.omega_n)?;
    out.gate.put(&mut out.est, "zeta", p.zeta)?;
    if let Some((sj, sm)) = p.std_errors {
        out.gate.put_se(&mut out.se, jn, sj)?;
        out.gate.put_se(&mut out.se, mun, sm)?;
    }
    if let Some(s) = osc.period_std_error {
        out.gate.put_se(&mut out.se, "period", s)?;
    }
    if let Some(s) = osc.decay_ratio_std_error {
        out.gate.put_se(&mut out.se, "decay_ratio", s)?;
    }
    // Two checks from the first peak: the nonlinear pendulum the parameters belong
    // to (`fit`), and the book's linear oscillation (`fit_linear`).
    let start = osc.peaks[0].first;
    let nonlinear_meaning = FitMeaning {
        model: format!(
            "the identified nonlinear pendulum on a held support ({jn}, {mun} with the known m, l, g), released at rest from the first peak"
        ),
        input: "no input (free swing)",
        t,
    };
    let linear_meaning = FitMeaning {
        model: format!(
            "the book's linear oscillation (ω_n = {}, ζ = {}), released at rest from the first peak",
            g4(p.omega_n),
            g4(p.zeta)
        ),
        input: "no input (free swing)",
        t,
    };
    if let Some(mut nonlinear) = out.gate.soft(
        "validation",
        validate_free_pendulum(ts, y, start, p.j, p.mu, (m, l, g)),
    )? {
        nonlinear.output = col.clone();
        out.report.fit = fit_json(&mut out.gate, &nonlinear, &nonlinear_meaning)?;
    }
    if let Some(mut linear) = out.gate.soft(
        "linear validation",
        validate_oscillation(ts, y, start, p.omega_n, p.zeta),
    )? {
        linear.output = col.clone();
        out.report.fit_linear = Some(fit_json(&mut out.gate, &linear, &linear_meaning)?);
    }
    out.report.options = json!({
        "column": col,
        "peaks": osc.peaks.len(),
        "hysteresis": osc.hysteresis,
        "amplitude_correction": i.args.amplitude_correction,
        "corrected_period": p.period,
    });
    out.report.constants = if cart_pend {
        json!({"mp": m, "lp": l, "g": g})
    } else {
        json!({"m2": m, "l2": l, "g": g})
    };
    out.report.units = vec![
        (jn, "kg m^2"),
        (mun, "N m s/rad"),
        ("period", "s"),
        ("decay_ratio", "-"),
        ("omega_n", "rad/s"),
        ("zeta", "-"),
    ];
    Ok(())
}
