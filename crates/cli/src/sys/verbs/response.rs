//! The response verbs of `pendulab sys`: the time grid and default final time, step,
//! impulse, initial and lsim trajectories as tables or figures, and the Bode diagram with its
//! frequency grid.

use super::super::input::{Sys, with_sys};
use super::super::{FigureArgs, FreqArgs, TimeArgs};
use crate::lqr::rows_of;
use anyhow::{Context, Result, bail};
use pendulab_lti::frequency_response::{freqresp, frequency_grid, logspace};
use pendulab_lti::response::{impulse, response_times, step};
use pendulab_lti::{Complex64, Trajectory};
use pendulab_plot::{Bode, Channel, Figure, SignalPanel, TimeResponse};
use serde_json::json;
use std::path::Path;

/// The response's time grid: `0 … t_final` by the step size (a discrete system's dt),
/// pendulab-lti's `response_times`, with the flags named in its errors.
pub(super) fn time_grid(s: &Sys, time: &TimeArgs) -> Result<Vec<f64>> {
    if let Some(t) = time.t_final.filter(|t| !(t.is_finite() && *t > 0.0)) {
        bail!("--t-final {t}: must be finite and > 0 seconds");
    }
    if let Some(h) = time.step_size.filter(|h| !(h.is_finite() && *h > 0.0)) {
        bail!("--step-size {h}: must be finite and > 0 seconds");
    }
    if s.dt().is_some() && time.step_size.is_some() {
        bail!("--step-size applies to continuous systems; a discrete system steps at its dt");
    }
    Ok(with_sys!(s, |v| response_times(
        v,
        time.t_final,
        time.step_size
    ))?)
}

/// `step` and `impulse`: one trajectory per input.
pub(super) fn channels(
    s: &Sys,
    time: &TimeArgs,
    fig: &FigureArgs,
    impulse_resp: bool,
) -> Result<()> {
    let t = time_grid(s, time)?;
    let trajs = if impulse_resp {
        with_sys!(s, |v| impulse(v, &t))?
    } else {
        with_sys!(s, |v| step(v, &t))?
    };
    let what = if impulse_resp { "impulse" } else { "step" };
    let labelled: Vec<(String, Trajectory)> = trajs
        .into_iter()
        .enumerate()
        .map(|(j, tr)| (format!("{what} on u{}", j + 1), tr))
        .collect();
    let refs: Vec<(&str, Trajectory)> = labelled
        .iter()
        .map(|(l, t)| (l.as_str(), t.clone()))
        .collect();
    trajectory_out(&refs, fig, what)
}

/// Prints responses (`t`, `y[output][run][sample]`, and `x` for one run) and draws them.
pub(super) fn trajectory_out(
    runs: &[(&str, Trajectory)],
    fig: &FigureArgs,
    what: &str,
) -> Result<()> {
    let Some((_, first)) = runs.first() else {
        bail!("the system has no inputs: no {what} response");
    };
    let t = first.t().to_vec();
    let ny = first.y().ncols();
    let y: Vec<Vec<Vec<f64>>> = (0..ny)
        .map(|i| {
            runs.iter()
                .map(|(_, tr)| tr.y().column(i).iter().copied().collect())
                .collect()
        })
        .collect();
    if let Some(path) = &fig.out {
        let mut tr = TimeResponse::new().title(format!("{what} response"));
        for (label, traj) in runs {
            tr = tr.run(*label, traj);
        }
        for i in 0..ny {
            tr = tr.panel(SignalPanel::new(Channel::Output(i), format!("y{}", i + 1)));
        }
        save_figure(&tr.figure()?, path)?;
    }
    if fig.json {
        let mut out =
            json!({ "t": t, "y": y, "runs": runs.iter().map(|(l, _)| *l).collect::<Vec<_>>() });
        if runs.len() == 1 {
            out["x"] = json!(rows_of(first.x()));
        }
        println!("{out}");
        return Ok(());
    }
    println!(
        "{what} response: {} samples, t = 0 … {:.6} s, {} output(s), {} run(s)",
        t.len(),
        t.last().copied().unwrap_or(0.0),
        ny,
        runs.len()
    );
    for (i, per_run) in y.iter().enumerate() {
        for ((label, _), series) in runs.iter().zip(per_run) {
            let last = series.last().copied().unwrap_or(f64::NAN);
            let (lo, hi) = series
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            println!(
                "  y{} ({label}): final {last:.6}, min {lo:.6}, max {hi:.6}",
                i + 1
            );
        }
    }
    if let Some(path) = &fig.out {
        println!("figure: {}", path.display());
    }
    Ok(())
}

pub(in crate::sys) fn save_figure(f: &Figure, path: &Path) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("svg") => f.save_svg(path),
        Some("png") => f.save_png(path),
        _ => bail!(
            "--out {}: the figure file must end in .svg or .png",
            path.display()
        ),
    }
    .with_context(|| format!("writing {}", path.display()))
}

/// The frequencies of a frequency-domain verb: MATLAB's automatic range, or `points`
/// log-spaced values on `[w_min, w_max]` (below the Nyquist frequency of a discrete system).
pub(in crate::sys) fn frequencies(s: &Sys, freq: &FreqArgs) -> Result<Vec<f64>> {
    let points = freq.points;
    Ok(match (freq.w_min, freq.w_max) {
        (None, None) => with_sys!(s, |v| frequency_grid(v, 100))?,
        (Some(lo), Some(hi)) => {
            if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo) {
                bail!("--w-min {lo} --w-max {hi}: need 0 < w-min < w-max, finite (rad/s)");
            }
            if !(2..=1_000_000).contains(&points) {
                bail!("--points {points}: must be in [2, 10⁶]");
            }
            if let Some(dt) = s.dt()
                && hi > std::f64::consts::PI / dt
            {
                bail!(
                    "--w-max {hi}: above the Nyquist frequency π/dt = {} rad/s",
                    std::f64::consts::PI / dt
                );
            }
            logspace(lo.log10(), hi.log10(), points)
        }
        _ => bail!("give both --w-min and --w-max, or neither (MATLAB's automatic range)"),
    })
}

pub(super) fn bode(s: &Sys, freq: &FreqArgs, fig: &FigureArgs) -> Result<()> {
    let w = frequencies(s, freq)?;
    let fr = with_sys!(s, |v| freqresp(v, &w))?;
    let (_, b, c, _) = s.matrices();
    let (ny, nu) = (c.nrows(), b.ncols());
    let mut plot = Bode::new().title("Bode diagram");
    let mut chans = Vec::new();
    for i in 0..ny {
        for j in 0..nu {
            let h: Vec<Complex64> = fr.response.iter().map(|g| g[(i, j)]).collect();
            let label = format!("u{} → y{}", j + 1, i + 1);
            let mag: Vec<f64> = h.iter().map(|z| 20.0 * z.norm().log10()).collect();
            let mut phase: Vec<f64> = h.iter().map(|z| z.arg().to_degrees()).collect();
            pendulab_lti::frequency_response::unwrap_degrees(&mut phase);
            plot = plot.response(label.clone(), &w, &h);
            chans.push(
                json!({ "input": j + 1, "output": i + 1, "magnitude_db": mag, "phase_deg": phase }),
            );
        }
    }
    if let Some(path) = &fig.out {
        save_figure(&plot.figure(), path)?;
    }
    if fig.json {
        println!("{}", json!({ "w": w, "channels": chans }));
        return Ok(());
    }
    println!(
        "Bode: {} frequencies from {:.4e} to {:.4e} rad/s, {} channel(s)",
        w.len(),
        w.first().copied().unwrap_or(0.0),
        w.last().copied().unwrap_or(0.0),
        chans.len()
    );
    if let Some(path) = &fig.out {
        println!("figure: {}", path.display());
    }
    Ok(())
}
