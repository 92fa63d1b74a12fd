//! Part 1 §3.2: the cart rig's measured P-control responses and its identification.

use super::*;

pub(super) fn dataset(id: &'static str, name: &str, text: &str) -> Result<Dataset, BookError> {
    Dataset::from_csv_str(name, text).ctx(id)
}

pub(super) const ID321P: &str = "p1c321_cdip_plot_pcont";

/// A measured record: legend label, t, z, θ.
pub(super) type Record = (String, Vec<f64>, Vec<f64>, Vec<f64>);

pub(super) fn p1c321_cdip_plot_pcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let mut sets = Vec::new();
    for (kp, name, text) in PCONT {
        sets.push((kp, dataset(ID321P, name, text)?));
    }
    let mut zmax = Vec::new();
    let mut tmax = Vec::new();
    let mut thmax = Vec::new();
    for (_, d) in &sets {
        let (t, z, th) = (
            d.time().ctx(ID321P)?,
            d.column("z").ctx(ID321P)?,
            d.column("theta").ctx(ID321P)?,
        );
        let (k, m) = z
            .iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |(bk, bm), (k, &v)| {
                if v > bm { (k, v) } else { (bk, bm) }
            });
        zmax.push(m);
        tmax.push(t[k] - STEP_TIME);
        thmax.push(th.iter().fold(0.0f64, |a, v| a.max(v.abs())));
    }
    let mut out = ExampleOutput::default();
    out.value("z_max", Value::Vector(zmax));
    out.value("t_z_max", Value::Vector(tmax));
    out.value("phi_max", Value::Vector(thmax));
    out.unit(&["z_max"], "m")
        .unit(&["t_z_max"], "s")
        .unit(&["phi_max"], "rad");
    out.notes.push(
        "Measured on the rig: u = k_P (0.2 − z), k_P = 2.5, 5, 10, 20 (values in that order), \
         the reference stepping at t = 1 s, the pendulum hanging. z_max: largest cart position \
         [m]; t_z_max: its time after the step (first sample of the plateau) [s]; phi_max: \
         largest |φ| [rad]. The peaks are flattened by belt stretch and friction."
            .into(),
    );
    if ctx.figures {
        let cols: Vec<Record> = sets
            .iter()
            .map(|(kp, d)| {
                Ok((
                    format!("k_P = {kp}"),
                    d.time().ctx(ID321P)?.to_vec(),
                    d.column("z").ctx(ID321P)?.to_vec(),
                    d.column("theta").ctx(ID321P)?.to_vec(),
                ))
            })
            .collect::<Result<_, BookError>>()?;
        let fig = stacked(
            "p1c321_cdip_plot_pcont: measured P control, target 0.2 m",
            "time [s]",
            vec![
                PanelSpec::new(
                    "cart position z [m]",
                    cols.iter()
                        .map(|(l, t, z, _)| (l.clone(), t.as_slice(), z.clone()))
                        .collect(),
                )
                .reference(TARGET, "target"),
                PanelSpec::new(
                    "pendulum angle φ [rad]",
                    cols.iter()
                        .map(|(l, t, _, th)| (l.clone(), t.as_slice(), th.clone()))
                        .collect(),
                ),
            ],
        );
        write_figure(&mut out, "p1c321_cdip_plot_pcont_measured", fig);
    }
    Ok(out)
}

/// Windowed data from `t0` on.
pub(super) fn from(
    id: &'static str,
    d: &Dataset,
    t0: Option<f64>,
    t1: Option<f64>,
) -> Result<Dataset, BookError> {
    d.window(t0, t1).ctx(id)
}

pub(super) fn fit_figure(
    id: &'static str,
    out: &mut ExampleOutput,
    stem: &str,
    title: &str,
    t: &[f64],
    panels: &[(&str, &[f64], &[f64])],
) -> Result<(), BookError> {
    let mut f = IdentFit::new(t).title(title);
    for (label, y, yh) in panels {
        f = f.signal(*label, y, &[("identified model", yh)]);
    }
    let fig = f.figure().ctx(id)?;
    write_figure(out, stem, fig);
    Ok(())
}

/// Adds the one-panel fit figure `stem` of the measured `y` over `t` (legend `label`) with the
/// identified model's simulation from `val`, when the context asks for figures.
///
/// # Errors
/// The figure's errors ([`BookError::Computation`]).
pub(super) fn save_fit(
    ctx: &RunContext,
    id: &'static str,
    out: &mut ExampleOutput,
    stem: &str,
    title: &str,
    (t, label, y): (&[f64], &str, &[f64]),
    val: &pendulab_ident::Validation,
) -> Result<(), BookError> {
    if !ctx.figures {
        return Ok(());
    }
    let sim = padded(&val.simulated, val.start);
    fit_figure(id, out, stem, title, t, &[(label, y, &sim)])
}

/// Pads a validation output (which starts at sample `start`) with NaN to the data length.
pub(super) fn padded(sim: &[f64], start: usize) -> Vec<f64> {
    let mut v = vec![f64::NAN; start];
    v.extend_from_slice(sim);
    v
}
