//! The M-files' identification recipes (data windows, sample indices and formulas, cited by
//! line), shared by the cart (§3.2) and arm (§3.3) rig examples.

use super::*;

/// The rows of `(t, columns…)` whose time satisfies `keep`, with `shift` subtracted from `t`:
/// the M-files' `for i = 1:length(t_data), if t_data(i) >= tmin … t(k) = t_data(i) − tmin`
/// loops, with their exact floating-point comparisons on the recorded times.
pub(super) fn mfile_rows(
    id: &'static str,
    t: &[f64],
    columns: &[&[f64]],
    keep: impl Fn(f64) -> bool,
    shift: f64,
) -> Result<(Vec<f64>, Vec<Vec<f64>>), BookError> {
    let rows: Vec<usize> = (0..t.len()).filter(|&i| keep(t[i])).collect();
    if rows.len() < 3 {
        return Err(fail(
            id,
            format!(
                "only {} samples of the data (t = {} … {} s) lie in the M-file's window",
                rows.len(),
                t.first().copied().unwrap_or(f64::NAN),
                t.last().copied().unwrap_or(f64::NAN)
            ),
        ));
    }
    let tw = rows.iter().map(|&i| t[i] - shift).collect();
    let cols = columns
        .iter()
        .map(|c| rows.iter().map(|&i| c[i]).collect())
        .collect();
    Ok((tw, cols))
}

/// The peak-time identification of `p1c321_cdip_id_cart.m` (lines 18–56) and
/// `p1c332_adip_id_arm.m` (lines 21–60), under the M-files' variable names.
#[derive(Debug, Clone, Copy)]
pub(super) struct PeakFeature {
    /// `Tp = (t(imax) + t(imax_last))/2`: the middle of the first peak plateau, time after the
    /// step (s).
    pub(super) tp: f64,
    /// `Amax = ymax − yc`: the overshoot above the reference (m or rad).
    pub(super) amax: f64,
    /// `gamma = −(1/Tp) log(Amax/yc)` (1/s).
    pub(super) gamma: f64,
    /// `delta = π/Tp` (rad/s).
    pub(super) delta: f64,
    /// `omega_n = √(gamma² + delta²)` (rad/s).
    pub(super) omega_n: f64,
    /// `zeta = gamma/omega_n`.
    pub(super) zeta: f64,
    /// `2 zeta omega_n` (`ac`, `a1`), 1/s.
    pub(super) a: f64,
    /// `omega_n²/kP` (`bc`, `b1`).
    pub(super) b: f64,
}

/// The M-files' peak-time recipe on the record `(t, y)`: the samples from `t ≥ 1 s` with
/// `t − 1`, `[ymax imax] = max(y)` (the first largest sample), `imax_last` the end of the plateau
/// of equal samples that follows, `Tp` its middle, then the overshoot `Amax` over the reference
/// `yc` (not over the step actually travelled) and `a = 2ζω_n`, `b = ω_n²/kP`.
///
/// # Errors
/// [`BookError::Computation`] when no sample lies at or after 1 s, or the record does not
/// overshoot `yc` (MATLAB's `log` of a non-positive ratio would turn the result complex).
pub(super) fn peak_feature(
    id: &'static str,
    t_data: &[f64],
    y_data: &[f64],
    yc: f64,
    kp: f64,
) -> Result<PeakFeature, BookError> {
    let (t, cols) = mfile_rows(id, t_data, &[y_data], |t| t >= 1.0, 1.0)?;
    let y = &cols[0];
    // [ymax imax] = max(y): the first index of the largest value.
    let (imax, ymax) = y
        .iter()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |(bi, bm), (i, &v)| {
            if v > bm { (i, v) } else { (bi, bm) }
        });
    let mut imax_last = imax;
    for (i, &v) in y.iter().enumerate().skip(imax) {
        if v == ymax {
            imax_last = i;
        }
        if v < ymax {
            break;
        }
    }
    let tp = (t[imax] + t[imax_last]) / 2.0;
    let amax = ymax - yc;
    // Data are finite (the CSV reader refuses NaN), so these comparisons decide.
    if amax <= 0.0 || tp <= 0.0 {
        return Err(fail(
            id,
            format!(
                "the record does not overshoot the reference {yc} after t = 1 s (largest value \
                 {ymax} at {} s after the step): no peak time or overshoot to read",
                t[imax]
            ),
        ));
    }
    let gamma = -(1.0 / tp) * (amax / yc).ln();
    let delta = PI / tp;
    let omega_n = (gamma * gamma + delta * delta).sqrt();
    let zeta = gamma / omega_n;
    Ok(PeakFeature {
        tp,
        amax,
        gamma,
        delta,
        omega_n,
        zeta,
        a: 2.0 * zeta * omega_n,
        b: omega_n * omega_n / kp,
    })
}

/// Reports a [`PeakFeature`] under the M-file's names (`a`, `b` as `a_name`, `b_name`) with the
/// transfer function `sysGyr = tf(omega_n^2, [1 2*zeta*omega_n omega_n^2])` the M-file
/// displays, and `overshoot` (= `Amax`).
pub(super) fn report_peak_feature(
    out: &mut ExampleOutput,
    f: &PeakFeature,
    a_name: &str,
    b_name: &str,
) {
    out.value("Tp", Value::Number(f.tp));
    out.value("Amax", Value::Number(f.amax));
    out.value("gamma", Value::Number(f.gamma));
    out.value("delta", Value::Number(f.delta));
    out.value("omega_n", Value::Number(f.omega_n));
    out.value("zeta", Value::Number(f.zeta));
    out.value(a_name, Value::Number(f.a));
    out.value(b_name, Value::Number(f.b));
    out.value("overshoot", Value::Number(f.amax));
    let w2 = f.omega_n * f.omega_n;
    out.value("sysGyr_num", Value::Vector(vec![w2]));
    out.value(
        "sysGyr_den",
        Value::Vector(vec![1.0, 2.0 * f.zeta * f.omega_n, w2]),
    );
    // γ = ζω_n (decay rate), δ = ω_n√(1−ζ²) (damped frequency) of the fitted second order.
    out.unit(&["Tp"], "s")
        .unit(&["gamma"], "1/s")
        .unit(&["delta", "omega_n"], "rad/s");
}

pub(super) const ID321C: &str = "p1c321_cdip_id_cart";

pub(super) fn p1c321_cdip_id_cart(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    // p1c321_cdip_id_cart.m: line 8 loads the k_P = 10 record, kP = 10 (line 9), zc = 0.2
    // (line 11).
    let (kp, name, text) = PCONT[2];
    let raw = dataset(ID321C, name, text)?;
    let (t_all, z_all) = (raw.time().ctx(ID321C)?, raw.column("z").ctx(ID321C)?);
    let f = peak_feature(ID321C, t_all, z_all, TARGET, kp)?;
    let d = from(ID321C, &raw, Some(STEP_TIME), None)?;
    let (t, z) = (d.time().ctx(ID321C)?, d.column("z").ctx(ID321C)?);
    let val = validate_p_step(t, z, STEP_TIME, TARGET, kp, f.a, f.b).ctx(ID321C)?;
    let mut out = ExampleOutput::default();
    report_peak_feature(&mut out, &f, "ac", "bc");
    out.value("fit_percent", Value::Number(val.fit_percent));
    out.unit(&["ac"], "1/s").unit(&["bc"], "m/(s²·V)");
    // What the M-file displays (lines 59-71: fprintf %5.2e, and the tf of line 71 with four
    // significant digits), as GNU Octave 7.3.0 printed it running the M-file unchanged.
    let text = include_str!("../../../tests/data/octave/p1c321_cdip_id_cart.txt");
    let disp = OctaveDisplay::parse(ID321C, text);
    for (ours, theirs) in [
        ("Tp", "Tp"),
        ("Amax", "Amax"),
        ("gamma", "gamma_c"),
        ("delta", "delta_c"),
        ("omega_n", "omega_nc"),
        ("zeta", "zeta_c"),
        ("ac", "ac"),
        ("bc", "bc"),
    ] {
        disp.compare(
            ID321C,
            &mut out,
            ours,
            theirs,
            "lines 59-68 (fprintf %5.2e)",
        )?;
    }
    let (num, a, b) =
        displayed_tf2(text).ok_or_else(|| fail(ID321C, "the committed display has no sysGyr"))?;
    let src = disp.source("line 71 (sysGyr, four significant digits)");
    out.reference("sysGyr_num", Value::Vector(vec![num]), &src, 0.005);
    out.reference("sysGyr_den", Value::Vector(vec![1.0, a, b]), &src, 0.005);
    display_note(
        &mut out,
        ID321C,
        &[
            "Tp", "Amax", "gamma_c", "delta_c", "omega_nc", "zeta_c", "ac", "bc", "sysGyr",
        ],
        &[],
        &[],
    );
    out.notes.push(
        "sysGyr_den is compared to ±0.005, the last printed digit of its largest coefficient \
         (43.23); its middle coefficient (6.227) is printed to 0.001 and is ac, compared above."
            .into(),
    );
    finish_fit(
        ctx,
        ID321C,
        out,
        "As p1c321_cdip_id_cart.m on the measured k_P = 10 step: the samples from t = 1 s \
         (line 20), Tp = the middle of the first peak plateau after the step [s] (lines 28-39), \
         Amax = zmax − zc with the reference zc = 0.2 m (line 47) and gamma = −ln(Amax/zc)/Tp \
         (line 49), delta = π/Tp, omega_n = √(gamma² + delta²), zeta = gamma/omega_n, ac = \
         2 zeta omega_n, bc = omega_n²/kP (lines 50-56); overshoot = Amax; sysGyr_num, \
         sysGyr_den: the displayed tf (line 71). fit_percent (pendulab): MATLAB compare fit of \
         the identified loop.",
        "k_P = 10 step, measured and identified",
        (t, "cart position z [m]", z),
        &val,
    )
}

pub(super) const ID321D: &str = "p1c321_cdip_id_pend";

pub(super) fn p1c321_cdip_id_pend(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let d = from(
        ID321D,
        &dataset(ID321D, "cdip_pend_data.csv", PEND)?,
        Some(35.0),
        Some(51.0),
    )?;
    let c = CartPendulumConstants::default();
    let (t, th) = (d.time().ctx(ID321D)?, d.column("theta").ctx(ID321D)?);
    let ts = d.sample_time().ctx(ID321D)?;
    let osc = free_oscillation(t, th, &OscillationOptions::default()).ctx(ID321D)?;
    let p = pendulum_from_oscillation(&osc, c.mp, c.lp, c.g, PeriodCorrection::None).ctx(ID321D)?;
    let start = osc.peaks[0].first;
    let val = validate_oscillation(ts, th, start, p.omega_n, p.zeta).ctx(ID321D)?;
    let mut out = ExampleOutput::default();
    out.value("Jp", Value::Number(p.j));
    out.value("mup", Value::Number(p.mu));
    out.value("period", Value::Number(osc.period));
    out.value("decay_ratio", Value::Number(osc.decay_ratio));
    out.value("peaks", Value::Number(osc.peaks.len() as f64));
    // Under the M-file's names (lines 94-100, 132-145).
    let (gamma, delta, omega_n, zeta) = osc.second_order();
    out.value("T", Value::Vector(osc.periods.clone()));
    out.value("lambda", Value::Vector(osc.decay_ratios.clone()));
    out.value("T_average", Value::Number(osc.period));
    out.value("lambda_average", Value::Number(osc.decay_ratio));
    out.value("gamma", Value::Number(gamma));
    out.value("delta", Value::Number(delta));
    out.value("omega_n", Value::Number(omega_n));
    out.value("zeta", Value::Number(zeta));
    out.value("mp", Value::Number(c.mp));
    out.value("lp", Value::Number(c.lp));
    out.value("g", Value::Number(c.g));
    // γ = ln(1/λ̄)/T̄, δ = 2π/T̄ (ident's Oscillation::second_order).
    out.unit(&["Jp"], "kg·m²")
        .unit(&["mup"], "kg·m²/s")
        .unit(&["period", "T", "T_average"], "s")
        .unit(&["gamma"], "1/s")
        .unit(&["delta", "omega_n"], "rad/s")
        .unit(&["mp"], "kg")
        .unit(&["lp"], "m")
        .unit(&["g"], "m/s²");
    // What the M-file displays, as GNU Octave 7.3.0 printed it running the M-file unchanged:
    // T_average, lambda_average (lines 99-100), T(i), lambda(i) (%5.3e, lines 149-152), the
    // rest %5.2e (lines 154-165).
    let disp = OctaveDisplay::parse(
        ID321D,
        include_str!("../../../tests/data/octave/p1c321_cdip_id_pend.txt"),
    );
    disp.compare(ID321D, &mut out, "T_average", "T_average", "line 99")?;
    disp.compare(
        ID321D,
        &mut out,
        "lambda_average",
        "lambda_average",
        "line 100",
    )?;
    for name in ["T", "lambda"] {
        let d = disp.indexed(ID321D, name)?;
        out.reference(
            name,
            d.value.clone(),
            &disp.source(&format!("lines 149-152 ({name}(i), %5.3e)")),
            d.tolerance(),
        );
    }
    for (ours, theirs) in [
        ("gamma", "gamma_p"),
        ("delta", "delta_p"),
        ("omega_n", "omega_np"),
        ("zeta", "zeta_p"),
        ("mp", "mp"),
        ("lp", "lp"),
        ("g", "g"),
        ("Jp", "Jp"),
        ("mup", "mup"),
    ] {
        disp.compare(
            ID321D,
            &mut out,
            ours,
            theirs,
            "lines 157-165 (fprintf %5.2e)",
        )?;
    }
    display_note(
        &mut out,
        ID321D,
        &[
            "T_average",
            "lambda_average",
            "T(i)",
            "lambda(i)",
            "gamma_p",
            "delta_p",
            "omega_np",
            "zeta_p",
            "mp",
            "lp",
            "g",
            "Jp",
            "mup",
        ],
        &[],
        &[(
            "T, lambda of lines 154-155",
            "T_average and lambda_average again, to three digits",
        )],
    );
    finish_fit(
        ctx,
        ID321D,
        out,
        "Free oscillation, window 35–51 s: mean period T̄ (peak to peak) [s] and mean decay \
         ratio λ̄ = A_{i+1}/A_i; γ = ln(1/λ̄)/T̄, δ = 2π/T̄, ω_n = √(γ² + δ²), ζ = γ/ω_n, \
         J_p = m_p g l_p/ω_n² − m_p l_p², μ_p = 2ζω_n (J_p + m_p l_p²). The book's method \
         ignores the swing's large-amplitude period lengthening (≈ 1.7 % here), which makes \
         J_p come out high (table 3.5: 1.59e-3); `pendulab identify pend-free \
         --amplitude-correction` removes it.",
        "free oscillation, measured and identified",
        (t, "pendulum angle φ [rad]", th),
        &val,
    )
}

/// The tail of the §3.2.1 identification examples: the example's `note` (how it follows its
/// M-file), then the fit figure `{id}_fit`, titled `{id}: {what}`, of the measured `series`
/// against the identified model's output (`save_fit`).
fn finish_fit(
    ctx: &RunContext,
    id: &'static str,
    mut out: ExampleOutput,
    note: &str,
    what: &str,
    series: (&[f64], &str, &[f64]),
    val: &pendulab_ident::Validation,
) -> Result<ExampleOutput, BookError> {
    out.notes.push(note.into());
    save_fit(
        ctx,
        id,
        &mut out,
        &format!("{id}_fit"),
        &format!("{id}: {what}"),
        series,
        val,
    )?;
    Ok(out)
}

pub(super) const ID322: &str = "p1c322_cdip_id_least_square";

pub(super) fn p1c322_cdip_id_least_square(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let d = from(
        ID322,
        &dataset(ID322, "cdip_least_square_data.csv", LS)?,
        Some(1.0),
        Some(5.0),
    )?;
    let ts = d.sample_time().ctx(ID322)?;
    let (t, z, phi, v) = (
        d.time().ctx(ID322)?,
        d.column("z").ctx(ID322)?,
        d.column("phi").ctx(ID322)?,
        d.column("v").ctx(ID322)?,
    );
    let opts = LsOptions::default();
    let c = CartPendulumConstants::default();
    let drive = cart_drive_ls(ts, z, v, &opts).ctx(ID322)?;
    let pend = cart_pendulum_ls(ts, z, phi, &c, &opts).ctx(ID322)?;
    let mut out = ExampleOutput::default();
    out.value("ac", Value::Number(drive.a));
    out.value("bc", Value::Number(drive.b));
    out.value("Jp", Value::Number(pend.jp));
    out.value("mup", Value::Number(pend.mup));
    out.unit(&["ac"], "1/s")
        .unit(&["bc"], "m/(s²·V)")
        .unit(&["Jp"], "kg·m²")
        .unit(&["mup"], "kg·m²/s");
    // Table 3.5 prints the estimates of this recipe to three significant digits: half a unit
    // of the last digit.
    let src = "book table 3.5";
    out.reference("ac", Value::Number(6.25), src, 0.005);
    out.reference("bc", Value::Number(4.36), src, 0.005);
    out.reference("Jp", Value::Number(1.59e-3), src, 0.005e-3);
    out.reference("mup", Value::Number(2.35e-4), src, 0.005e-4);
    out.notes.push(
        "Least squares (eqs 3.43–3.47): three-point derivatives, every column filtered by \
         1/(0.075 s + 1)³ (exact ZOH discretisation, causal), Householder QR, data 1–5 s. \
         Table 3.5: a_c = 6.25, b_c = 4.36, J_p = 1.59e-3, μ_p = 2.35e-4."
            .into(),
    );
    if ctx.figures {
        let vz = validate_drive(ts, z, v, drive.a, drive.b, "z").ctx(ID322)?;
        let vp = validate_cart_pendulum(ts, z, phi, pend.jp, pend.mup, &c).ctx(ID322)?;
        let sz = padded(&vz.simulated, vz.start);
        let sp = padded(&vp.simulated, vp.start);
        fit_figure(
            ID322,
            &mut out,
            "p1c322_cdip_id_least_square_fit",
            "p1c322_cdip_id_least_square: measured and simulated with the estimates",
            t,
            &[
                ("cart position z [m]", z, &sz),
                ("pendulum angle φ [rad]", phi, &sp),
            ],
        )?;
    }
    Ok(out)
}
