//! `pendulab plot RUN.csv [--vs SIM.csv] [--out F.svg|F.png] [--json]`: the figures of a rig
//! log or a simulation, and the overlay of two with the fit per signal (`docs/lab.md`).
//!
//! Both files are CSV with a header naming the columns (`pendulab_ident::Dataset`): `t` in
//! seconds and the plant's signals named as the rig log and `pendulab simulate` name them —
//! `z, theta, dz, dtheta` (cart) or `theta1, theta2, dtheta1, dtheta2` (arm), SI units and
//! radians, and `v` \[V\]. The figure has three panels: the drive position (`z` in m, `θ₁` in
//! degrees), the pendulum angle in degrees and the voltage `v`, one curve per file.
//!
//! **Time origin.** A rig log (`pendulab rig run --log`, a `status` column) starts with the
//! connect phase, while the emulator holds the pendulum: its time is taken from its first row
//! with the amplifier enabled (status bit `ENABLED`, `docs/rig/protocol.md`), the moment the
//! run begins and the pendulum is let go, as a simulation's `t = 0` is. A file without a
//! `status` column keeps its times.
//!
//! **Fit.** With `--vs`, every signal the two files share (besides `t`) is compared over
//! their common time span: the second file is interpolated linearly at the first's times, and
//! the fit is MATLAB `compare`'s normalised root-mean-square measure,
//! `fit = 100 (1 − ‖y − ŷ‖ / ‖y − mean(y)‖)` percent (`pendulab_ident::fit_percent`), with `y`
//! the first file's samples (the measurement) and `ŷ` the second's (the model): 100 % is a
//! perfect match, 0 % no better than the measurement's mean, and it is negative when worse.

use anyhow::{Context, Result, bail};
use pendulab_ident::{Dataset, fit_percent};
use pendulab_lti::{Mat, Trajectory};
use pendulab_plot::{Channel, SignalPanel, TimeResponse};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Arguments of `pendulab plot`.
#[derive(Debug, clap::Args)]
pub struct PlotArgs {
    /// The run: a rig log (`rig run --log`) or a simulation's run.csv.
    pub run: PathBuf,
    /// A second file to overlay and compare with (e.g. the simulation of the same controller).
    #[arg(long)]
    pub vs: Option<PathBuf>,
    /// The figure's file, .svg or .png (default: RUN's name with .svg).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object instead of lines.
    #[arg(long)]
    pub json: bool,
}

/// The status bit of an enabled amplifier (`pendulab_rig::protocol::status::ENABLED`).
const ENABLED: u16 = pendulab_rig::protocol::status::ENABLED;

/// One file's columns, its time origin applied.
struct Record {
    path: PathBuf,
    names: Vec<String>,
    t: Vec<f64>,
    cols: Vec<Vec<f64>>,
    /// The time removed from the file's `t` (the first enabled row of a rig log).
    shift: f64,
}

impl Record {
    fn column(&self, name: &str) -> Option<&[f64]> {
        let i = self.names.iter().position(|n| n == name)?;
        Some(&self.cols[i])
    }
}

fn read(path: &Path) -> Result<Record> {
    let source = path.display().to_string();
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {source}"))?;
    let data = Dataset::from_csv_str(&source, &text)?;
    let t = data.time()?.to_vec();
    let names: Vec<String> = data
        .names()
        .iter()
        .filter(|n| n.as_str() != "t")
        .cloned()
        .collect();
    let mut cols = Vec::with_capacity(names.len());
    for n in &names {
        let c = data.column(n)?;
        if let Some(k) = c.iter().position(|v| !v.is_finite()) {
            bail!(
                "{source}: column '{n}', row {}: {} is not a finite number",
                k + 2,
                c[k]
            );
        }
        cols.push(c.to_vec());
    }
    let shift = match names.iter().position(|n| n == "status") {
        Some(i) => {
            let first = cols[i]
                .iter()
                .position(|&s| (s as u16) & ENABLED != 0)
                .with_context(|| {
                    format!("{source}: no row has the amplifier enabled (status bit {ENABLED}): the run never started")
                })?;
            t[first]
        }
        None => 0.0,
    };
    // Rows before the origin (the held connect phase) are left out.
    let keep: Vec<usize> = (0..t.len()).filter(|&k| t[k] >= shift).collect();
    Ok(Record {
        path: path.to_path_buf(),
        t: keep.iter().map(|&k| t[k] - shift).collect(),
        cols: cols
            .iter()
            .map(|c| keep.iter().map(|&k| c[k]).collect())
            .collect(),
        names,
        shift,
    })
}

/// `y` sampled at `t` by linear interpolation, at the times of `at` inside `t`'s span; the
/// indices of `at` used.
fn resample(t: &[f64], y: &[f64], at: &[f64]) -> (Vec<usize>, Vec<f64>) {
    let (lo, hi) = (t[0], t[t.len() - 1]);
    let mut out = (Vec::new(), Vec::new());
    let mut j = 0;
    for (k, &s) in at.iter().enumerate() {
        if s < lo || s > hi {
            continue;
        }
        while j + 1 < t.len() - 1 && t[j + 1] < s {
            j += 1;
        }
        let (t0, t1) = (t[j], t[(j + 1).min(t.len() - 1)]);
        let v = if t1 > t0 {
            let w = (s - t0) / (t1 - t0);
            y[j] + w.clamp(0.0, 1.0) * (y[(j + 1).min(y.len() - 1)] - y[j])
        } else {
            y[j]
        };
        out.0.push(k);
        out.1.push(v);
    }
    out
}

#[derive(Serialize)]
struct Fit {
    signal: String,
    percent: f64,
    samples: usize,
}

#[derive(Serialize)]
struct PlotJson {
    run: PathBuf,
    vs: Option<PathBuf>,
    figure: PathBuf,
    run_time_shift: f64,
    vs_time_shift: Option<f64>,
    fits: Vec<Fit>,
    definition: &'static str,
}

/// The signals of a figure: drive, pendulum angle, voltage (the cart's or the arm's names).
fn panels(rec: &Record) -> Result<[&'static str; 3]> {
    if rec.column("z").is_some() && rec.column("theta").is_some() {
        Ok(["z", "theta", "v"])
    } else if rec.column("theta1").is_some() && rec.column("theta2").is_some() {
        Ok(["theta1", "theta2", "v"])
    } else {
        bail!(
            "{}: neither the cart's columns (z, theta) nor the arm's (theta1, theta2) are there (columns: t, {})",
            rec.path.display(),
            rec.names.join(", ")
        )
    }
}

fn trajectory(rec: &Record, signals: &[&str; 3]) -> Result<Trajectory> {
    let n = rec.t.len();
    let zeros = vec![0.0; n];
    let cols: Vec<&[f64]> = signals
        .iter()
        .map(|s| rec.column(s).unwrap_or(&zeros))
        .collect();
    let x = Mat::from_fn(n, 2, |k, i| cols[i][k]);
    let u = Mat::from_fn(n, 1, |k, _| cols[2][k]);
    Trajectory::new(rec.t.clone(), x, u, Mat::zeros(n, 0))
        .with_context(|| format!("{}: the record as a trajectory", rec.path.display()))
}

/// Runs `pendulab plot`.
///
/// # Errors
/// An unreadable or malformed CSV (naming the file, column and row); files of different
/// plants; no common time span; a figure that cannot be drawn or written.
pub fn run(args: &PlotArgs) -> Result<()> {
    let run = read(&args.run)?;
    let signals = panels(&run)?;
    let vs = args.vs.as_deref().map(read).transpose()?;
    if let Some(v) = &vs
        && panels(v)? != signals
    {
        bail!(
            "{} and {} are records of different plants",
            run.path.display(),
            v.path.display()
        );
    }
    let mut fits = Vec::new();
    if let Some(v) = &vs {
        for (i, name) in run.names.iter().enumerate() {
            if ["k", "t_nominal", "t_wall", "seq", "status"].contains(&name.as_str()) {
                continue;
            }
            let Some(model) = v.column(name) else {
                continue;
            };
            let (idx, yhat) = resample(&v.t, model, &run.t);
            if idx.len() < 2 {
                bail!(
                    "{} and {} share no time span (after the time origin)",
                    run.path.display(),
                    v.path.display()
                );
            }
            let y: Vec<f64> = idx.iter().map(|&k| run.cols[i][k]).collect();
            // A constant measurement has no fit (fit_percent says why); it is left out.
            if let Ok(p) = fit_percent(&y, &yhat) {
                fits.push(Fit {
                    signal: name.clone(),
                    percent: p,
                    samples: y.len(),
                });
            }
        }
    }
    let deg = 180.0 / std::f64::consts::PI;
    let arm = signals[0] == "theta1";
    let drive = if arm {
        SignalPanel::new(Channel::State(0), "θ₁ [deg]").scaled(deg)
    } else {
        SignalPanel::new(Channel::State(0), "z [m]")
    };
    let angle = if arm { "θ₂ [deg]" } else { "θ [deg]" };
    let label = |r: &Record| {
        r.path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let t_run = trajectory(&run, &signals)?;
    let t_vs = vs.as_ref().map(|v| trajectory(v, &signals)).transpose()?;
    let mut fig = TimeResponse::new().run(label(&run), &t_run);
    if let (Some(v), Some(tv)) = (&vs, &t_vs) {
        let mut l = label(v);
        if l == label(&run) {
            l = v.path.display().to_string();
        }
        fig = fig.run(l, tv);
    }
    let figure = fig
        .panel(drive)
        .panel(SignalPanel::new(Channel::State(1), angle).scaled(deg))
        .panel(SignalPanel::new(Channel::Input(0), "v [V]"))
        .figure()
        .context("drawing the figure")?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| args.run.with_extension("svg"));
    let bytes = match out.extension().and_then(|e| e.to_str()) {
        Some("svg") => figure.to_svg()?.into_bytes(),
        Some("png") => figure.to_png()?,
        _ => bail!("--out {}: must end in .svg or .png", out.display()),
    };
    crate::lab::write_whole(&out, &bytes)?;
    let json = PlotJson {
        run: args.run.clone(),
        vs: args.vs.clone(),
        figure: out,
        run_time_shift: run.shift,
        vs_time_shift: vs.as_ref().map(|v| v.shift),
        fits,
        definition: "fit = 100 (1 − ‖y − ŷ‖/‖y − mean y‖) %, y = RUN, ŷ = VS interpolated at RUN's times",
    };
    if args.json {
        println!("{}", serde_json::to_string(&json)?);
        return Ok(());
    }
    println!("wrote {}", json.figure.display());
    if run.shift > 0.0 {
        println!(
            "{}: time from its first enabled row (t = {} s in the file)",
            run.path.display(),
            run.shift
        );
    }
    if let Some(v) = &vs {
        if v.shift > 0.0 {
            println!(
                "{}: time from its first enabled row (t = {} s in the file)",
                v.path.display(),
                v.shift
            );
        }
        println!(
            "fit of {} (ŷ) to {} (y), {}:",
            v.path.display(),
            run.path.display(),
            "100 (1 − ‖y − ŷ‖/‖y − mean y‖)"
        );
        for f in &json.fits {
            println!(
                "  {:<8} {:>8.2} %  ({} samples)",
                f.signal, f.percent, f.samples
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::resample;

    /// Linear interpolation reproduces a straight line exactly and leaves out times outside
    /// the span.
    #[test]
    fn resampling_a_line_is_exact_inside_the_span() {
        let t = [0.0, 0.1, 0.2, 0.3];
        let y: Vec<f64> = t.iter().map(|s| 2.0 * s + 1.0).collect();
        let at = [-0.05, 0.0, 0.05, 0.25, 0.3, 0.4];
        let (idx, v) = resample(&t, &y, &at);
        assert_eq!(idx, vec![1, 2, 3, 4]);
        for (k, &i) in idx.iter().enumerate() {
            assert!((v[k] - (2.0 * at[i] + 1.0)).abs() < 1e-12);
        }
    }
}
