//! The loop-analysis verbs: `nyquist`, `nichols`, `rlocus` (with `--at`: `rlocfind`),
//! `diskmargin` (SISO, or a square MIMO loop's loop-at-a-time and multi-loop margins) and
//! `sigma`, over `pendulab_lti::{nyquist, rlocus, disk_margin, mu, sigma}` and the charts of
//! `pendulab_plot`.

use super::input::{Sys, vector_arg, with_sys};
use super::verbs::{finite_or_null, frequencies, pairs, parse_complex, save_figure};
use super::{FigureArgs, SysCommand};
use anyhow::{Result, anyhow, bail};
use pendulab_lti::disk_margin::{DiskMargin, disk_margin};
use pendulab_lti::mu::{MimoDiskMargin, disk_margin_mimo};
use pendulab_lti::nyquist::{NyquistOptions, nichols, nyquist};
use pendulab_lti::rlocus::{rlocfind, rlocus};
use pendulab_lti::sigma::sigma;
use pendulab_plot::{Nichols, Nyquist, RootLocusPlot, SigmaPlot};
use serde_json::{Value, json};

/// Runs one loop-analysis verb.
///
/// # Errors
/// The system's errors; the library's (a MIMO loop, an ill-posed loop, a bad option); a
/// figure that cannot be written.
pub fn run(cmd: &SysCommand) -> Result<()> {
    match cmd {
        SysCommand::Nyquist {
            sys,
            indent_radius,
            max_magnitude,
            fig,
        } => nyquist_verb(&sys.load()?, *indent_radius, *max_magnitude, fig),
        SysCommand::Nichols { sys, freq, fig } => {
            let s = sys.load()?;
            let w = frequencies(&s, freq)?;
            let n = with_sys!(&s, |v| nichols(v, &w))?;
            let chart = || {
                Nichols::new()
                    .curve("L", &n.phase_deg, &n.magnitude_db)
                    .title("Nichols chart")
                    .figure()
            };
            let data = || json!({ "w": n.w, "phase_deg": n.phase_deg, "gain_db": n.magnitude_db });
            emit(fig, chart, data, || {
                println!(
                    "Nichols: {} frequencies from {:.4e} to {:.4e} rad/s; phase {:.2}° … {:.2}°",
                    w.len(),
                    w.first().copied().unwrap_or(0.0),
                    w.last().copied().unwrap_or(0.0),
                    n.phase_deg.first().copied().unwrap_or(f64::NAN),
                    n.phase_deg.last().copied().unwrap_or(f64::NAN),
                );
            })
        }
        SysCommand::Rlocus {
            sys,
            gains,
            at,
            fig,
        } => rlocus_verb(&sys.load()?, gains.as_deref(), at.as_deref(), fig),
        SysCommand::Diskmargin { sys, skew, json } => diskmargin_verb(&sys.load()?, *skew, *json),
        SysCommand::Sigma { sys, freq, fig } => {
            let s = sys.load()?;
            let w = frequencies(&s, freq)?;
            let sv = with_sys!(&s, |v| sigma(v, &w))?;
            let chart = || {
                SigmaPlot::new()
                    .response("G", &sv.w, &sv.values)
                    .title("singular values")
                    .figure()
            };
            emit(
                fig,
                chart,
                || json!({ "w": sv.w, "sv": sv.values }),
                || {
                    let peak = sv
                        .values
                        .iter()
                        .zip(&sv.w)
                        .map(|(v, w)| (v.first().copied().unwrap_or(0.0), *w))
                        .fold((0.0, f64::NAN), |a, b| if b.0 > a.0 { b } else { a });
                    println!(
                        "sigma: {} frequencies, {} singular value(s); largest σ₁ {:.6} at ω = {:.6} rad/s on the grid",
                        w.len(),
                        sv.values.first().map_or(0, Vec::len),
                        peak.0,
                        peak.1
                    );
                },
            )
        }
        _ => Err(anyhow!("not a loop-analysis verb")),
    }
}

/// A chart verb's output: its `chart` written to `--out` when given, then one JSON object
/// (`data`, with `--json`) or the verb's `text` followed by the figure's path.
///
/// # Errors
/// A figure that cannot be written (nothing is printed then).
fn emit(
    fig: &FigureArgs,
    chart: impl FnOnce() -> pendulab_plot::Figure,
    data: impl FnOnce() -> serde_json::Value,
    text: impl FnOnce(),
) -> Result<()> {
    if let Some(path) = &fig.out {
        save_figure(&chart(), path)?;
    }
    if fig.json {
        println!("{}", data());
    } else {
        text();
        if let Some(path) = &fig.out {
            println!("figure: {}", path.display());
        }
    }
    Ok(())
}

fn nyquist_verb(s: &Sys, indent_radius: f64, max_magnitude: f64, fig: &FigureArgs) -> Result<()> {
    let opts = NyquistOptions {
        indent_radius,
        ..NyquistOptions::default()
    };
    let c = with_sys!(s, |v| nyquist(v, &opts))?;
    let chart = || {
        Nyquist::new()
            .curve("L", &c.response)
            .max_magnitude(max_magnitude)
            .title(format!(
                "Nyquist diagram: N = {}, P = {}, Z = {}",
                c.encirclements, c.open_loop_unstable, c.closed_loop_unstable
            ))
            .figure()
    };
    let data = || {
        json!({
            "w": c.w,
            "re": c.response.iter().map(|z| z.re).collect::<Vec<_>>(),
            "im": c.response.iter().map(|z| z.im).collect::<Vec<_>>(),
            "contour": pairs(&c.contour),
            "encirclements": c.encirclements,
            "winding": c.winding,
            "open_loop_unstable": c.open_loop_unstable,
            "closed_loop_unstable": c.closed_loop_unstable,
            "criterion_holds": c.criterion_holds(),
            "indented_poles": pairs(&c.indented_poles),
            "min_distance_to_critical": c.min_distance_to_critical,
            "dt": c.sample_time,
            "convention": "N = clockwise encirclements of −1 by L over the whole contour (ω from −∞ to ∞, the upper half listed); P = open-loop poles with Re > 0 (|z| > 1); Z = closed-loop poles with Re ≥ 0 (|z| ≥ 1); the contour passes imaginary-axis poles on the right (python-control)",
        })
    };
    emit(fig, chart, data, || {
        println!(
            "N = {} clockwise encirclement(s) of −1, P = {} open-loop unstable pole(s): Z = N + P = {}",
            c.encirclements,
            c.open_loop_unstable,
            c.encirclements + c.open_loop_unstable as i64
        );
        println!(
            "closed-loop poles with Re ≥ 0 (|z| ≥ 1): {} — the Nyquist criterion {}",
            c.closed_loop_unstable,
            if c.criterion_holds() {
                "holds"
            } else {
                "does NOT hold (the curve passes through −1 or the grid missed a turn)"
            }
        );
        println!(
            "min |1 + L| on the contour {:.6}; {} contour points; {} indented pole(s)",
            c.min_distance_to_critical,
            c.w.len(),
            c.indented_poles.len()
        );
    })
}

fn rlocus_verb(s: &Sys, gains: Option<&str>, at: Option<&str>, fig: &FigureArgs) -> Result<()> {
    let g = gains.map(|t| vector_arg(t, "gains")).transpose()?;
    let rl = with_sys!(s, |v| rlocus(v, g.as_deref()))?;
    let found = match at {
        None => None,
        Some(t) => {
            let Some(s0) = parse_complex(t.trim()) else {
                bail!("--at {t}: not a complex number (write -1+2i)");
            };
            Some((s0, with_sys!(s, |v| rlocfind(v, s0))?))
        }
    };
    let chart = || {
        let mut p = RootLocusPlot::new(&rl.roots)
            .poles(&rl.poles)
            .zeros(&rl.zeros)
            .asymptotes(rl.asymptotes.centroid, &rl.asymptotes.angles)
            .break_points(&rl.break_points.iter().map(|b| b.point).collect::<Vec<_>>())
            .title("root locus");
        if s.dt().is_some() {
            p = p.discrete();
        }
        if let Some((s0, f)) = &found {
            p = p.annotate(*s0, f.gain);
        }
        p.figure()
    };
    let find_json = found.as_ref().map(|(s0, f)| {
        json!({
            "point": [s0.re, s0.im],
            "gain": f.gain,
            "gain_complex": [f.gain_complex.re, f.gain_complex.im],
            "poles": pairs(&f.poles),
            "distance": f.distance,
        })
    });
    let data = || {
        json!({
            "gains": rl.gains,
            "roots": rl.roots.iter().map(|r| pairs(r)).collect::<Vec<_>>(),
            "poles": pairs(&rl.poles),
            "zeros": pairs(&rl.zeros),
            "asymptotes": {
                "centroid": finite_or_null(rl.asymptotes.centroid),
                "angles_deg": rl.asymptotes.angles.iter().map(|a| a.to_degrees()).collect::<Vec<_>>(),
            },
            "break_points": rl.break_points.iter().map(|b| json!({"point": [b.point.re, b.point.im], "gain": b.gain})).collect::<Vec<_>>(),
            "rlocfind": find_json,
            "dt": s.dt(),
        })
    };
    emit(fig, chart, data, || {
        println!(
            "root locus: {} branch(es) over {} gains from {} to {:.4e}",
            rl.poles.len(),
            rl.gains.len(),
            rl.gains.first().copied().unwrap_or(0.0),
            rl.gains.last().copied().unwrap_or(0.0)
        );
        if !rl.asymptotes.angles.is_empty() {
            println!(
                "asymptotes from σ = {:.6} at {:?}°",
                rl.asymptotes.centroid,
                rl.asymptotes
                    .angles
                    .iter()
                    .map(|a| (a.to_degrees() * 1e6).round() / 1e6)
                    .collect::<Vec<_>>()
            );
        }
        for b in &rl.break_points {
            println!(
                "break point s = {:.6}{:+.6}j at K = {:.6}",
                b.point.re, b.point.im, b.gain
            );
        }
        if let Some((s0, f)) = &found {
            println!(
                "at s = {}{:+}j: K = {:.6} (−D/N = {:.6}{:+.6}j), nearest closed-loop pole at distance {:.3e}",
                s0.re, s0.im, f.gain, f.gain_complex.re, f.gain_complex.im, f.distance
            );
        }
    })
}

/// A disk margin as JSON (`null` for an infinite or undefined number).
fn margin_json(m: &DiskMargin) -> Value {
    json!({
        "alpha": finite_or_null(m.alpha),
        "skew": m.skew,
        "gain_interval": [m.gain_interval.0, finite_or_null(m.gain_interval.1)],
        "gain_margin_db": finite_or_null(m.gain_margin_db()),
        "phase_margin_deg": m.phase_margin_deg,
        "frequency": finite_or_null(m.frequency),
        "frequency_infinite": m.frequency == f64::INFINITY,
        "closed_loop_stable": m.closed_loop_stable,
    })
}

/// `pendulab diskmargin`: the SISO disk margin, or for a square MIMO loop (more than one
/// channel) the loop-at-a-time margins of each channel and the multi-loop margin with its
/// bounds (`pendulab_lti::mu::disk_margin_mimo`).
///
/// # Errors
/// A non-square loop, a non-finite skew, an ill-posed loop (the library's messages).
fn diskmargin_verb(s: &Sys, skew: f64, as_json: bool) -> Result<()> {
    let (ny, nu) = with_sys!(s, |v| (v.ny(), v.nu()));
    if ny == 1 && nu == 1 {
        let m = with_sys!(s, |v| disk_margin(v, skew))?;
        let mut out = margin_json(&m);
        out["convention"] = json!(
            "alpha = 1/‖S + (skew − 1)/2‖∞ (0 for an unstable closed loop); null = ∞; the loop L is closed as u = −L y"
        );
        if as_json {
            println!("{out}");
        } else {
            print_margin("disk margin", &m);
        }
        return Ok(());
    }
    let m = with_sys!(s, |v| disk_margin_mimo(v, skew))?;
    if as_json {
        println!("{}", mimo_json(&m));
        return Ok(());
    }
    if !m.multi_loop.closed_loop_stable {
        println!("the closed loop is unstable: every disk margin is 0");
        return Ok(());
    }
    for (i, c) in m.loop_at_a_time.iter().enumerate() {
        print_margin(&format!("channel {i} (others closed)"), c);
    }
    print_margin("multi-loop (all channels at once)", &m.multi_loop);
    println!(
        "multi-loop α in [{:.6}, {:.6}] (1/μ upper, 1/μ lower at the peak); μ ∈ [{:.6}, {:.6}]",
        m.multi_loop_alpha_bounds.0, m.multi_loop_alpha_bounds.1, m.mu_peak.lower, m.mu_peak.upper
    );
    Ok(())
}

/// The MIMO disk margins as one JSON object.
fn mimo_json(m: &MimoDiskMargin) -> Value {
    json!({
        "loop_at_a_time": m.loop_at_a_time.iter().map(margin_json).collect::<Vec<_>>(),
        "multi_loop": margin_json(&m.multi_loop),
        "multi_loop_alpha_bounds": [finite_or_null(m.multi_loop_alpha_bounds.0), finite_or_null(m.multi_loop_alpha_bounds.1)],
        "mu_peak": {
            "lower": finite_or_null(m.mu_peak.lower),
            "upper": finite_or_null(m.mu_peak.upper),
            "d_scaling": m.mu_peak.d_scaling,
        },
        "peak_frequency": finite_or_null(m.peak_frequency),
        "peak_frequency_infinite": m.peak_frequency == f64::INFINITY,
        "closed_loop_stable": m.multi_loop.closed_loop_stable,
        "convention": "S = (I + L)⁻¹, S_σ = S + (skew − 1)/2 I; loop at a time: alpha_i = 1/‖(S_σ)_ii‖∞ (channel i broken, the others closed); multi-loop: alpha = 1/sup_ω μ_upper(S_σ(jω)) for simultaneous independent perturbations of every channel (conservative; the true value lies in multi_loop_alpha_bounds at the located peak); null = ∞; u = −L y",
    })
}

/// Prints one margin: α, its frequency, the gain interval and the phase margin.
fn print_margin(what: &str, m: &DiskMargin) {
    if !m.closed_loop_stable {
        println!("the closed loop is unstable: {what} 0");
        return;
    }
    println!(
        "{what}: α = {:.6} (skew {}) at ω = {:.6} rad/s",
        m.alpha, m.skew, m.frequency
    );
    println!(
        "  gain may vary in ({:.6}, {:.6}) = {:.4} dB; phase by ±{:.4}°",
        m.gain_interval.0,
        m.gain_interval.1,
        m.gain_margin_db(),
        m.phase_margin_deg
    );
}
