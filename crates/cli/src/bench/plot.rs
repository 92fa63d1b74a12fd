//! Figure workloads: a book-sized batch of figures rendered to SVG + PNG (`plot-figures`) and
//! the cart animation of a 16 s, 1 kHz run encoded as GIF + SVG (`plot-animation`).

use super::{BenchReport, Budget, Workload, time};
use anyhow::Result;
use pendulab_lti::{Complex64, Mat, Trajectory};
use pendulab_plot::{
    Animation, Bode, CartGeometry, Channel, Figure, PoleZeroMap, RegionBound, SignalPanel, Surface,
    TimeResponse,
};
use serde_json::json;

/// The workloads of this file.
pub fn workloads() -> Vec<Workload> {
    vec![
        Workload {
            name: "plot-figures",
            description: "4 book figures (3 runs x 10^4 samples stacked, Bode, pole map, surface) to SVG + PNG",
            run: plot_figures,
        },
        Workload {
            name: "plot-animation",
            description: "cart pendulum animation of a 16 s run at 1 kHz to GIF + animated SVG",
            run: plot_animation,
        },
    ]
}

/// A damped swing of the cart pendulum sampled at 1 kHz (shape only; no simulation needed).
fn run(n: usize, phase: f64) -> Trajectory {
    let t: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3).collect();
    let x = Mat::from_fn(n, 4, |k, i| {
        let t = t[k];
        match i {
            0 => 0.2 * (1.0 - (-0.8 * t).exp()) + 0.05 * (-0.5 * t).exp() * (4.0 * t).sin(),
            1 => 0.26 * (-0.4 * t).exp() * (6.0 * t + phase).cos(),
            2 => 0.16 * (-0.8 * t).exp(),
            _ => -1.5 * (-0.4 * t).exp() * (6.0 * t + phase).sin(),
        }
    });
    let u = Mat::from_fn(n, 1, |k, _| {
        (4.0 * (-0.6 * t[k]).exp() * (9.0 * t[k]).cos() * 100.0).round() / 100.0
    });
    Trajectory::new(t, x, u, Mat::zeros(n, 0)).expect("consistent shapes")
}

fn figures(runs: &[Trajectory]) -> Result<Vec<Figure>> {
    let mut tr = TimeResponse::new();
    for (k, r) in runs.iter().enumerate() {
        tr = tr.run(format!("run {k}"), r);
    }
    let stacked = tr
        .panel(SignalPanel::new(Channel::State(0), "z [m]"))
        .panel(SignalPanel::new(Channel::State(1), "θ [deg]").scaled(180.0 / std::f64::consts::PI))
        .panel(SignalPanel::new(Channel::Input(0), "v [V]").stairs())
        .figure()?;
    let w: Vec<f64> = (0..=500)
        .map(|k| 10f64.powf(-2.0 + 5.0 * k as f64 / 500.0))
        .collect();
    let h: Vec<Complex64> = w
        .iter()
        .map(|&w| {
            let s = Complex64::new(0.0, w);
            4.36 / (s * (s + 6.25))
        })
        .collect();
    let bode = Bode::new().response("P(s)", &w, &h).figure();
    let poles = [
        Complex64::new(-3.0, 2.0),
        Complex64::new(-3.0, -2.0),
        Complex64::new(-8.0, 0.0),
    ];
    let pz = PoleZeroMap::new()
        .region(
            "region",
            &[
                RegionBound::DecayRate(2.0),
                RegionBound::SpeedLimit(16.0),
                RegionBound::Sector(std::f64::consts::FRAC_PI_4),
            ],
        )
        .poles("poles", &poles)
        .figure();
    let surf = Figure::new(Surface::from_fn(
        (-5.0, 5.0),
        (-5.0, 5.0),
        21,
        21,
        |a, b| a * a + b * b,
    ));
    Ok(vec![stacked, bode, pz, surf])
}

fn plot_figures(budget: &Budget) -> Result<BenchReport> {
    let runs: Vec<Trajectory> = (0..3).map(|k| run(10_001, 0.3 * k as f64)).collect();
    let figs = figures(&runs)?;
    let mut svg_bytes = 0;
    let mut png_bytes = 0;
    let mut failure = None;
    let timing = time(budget, || {
        svg_bytes = 0;
        png_bytes = 0;
        for f in &figs {
            match (f.to_svg(), f.to_png()) {
                (Ok(s), Ok(p)) => {
                    svg_bytes += s.len();
                    png_bytes += p.len();
                }
                (Err(e), _) | (_, Err(e)) => failure = Some(e.to_string()),
            }
        }
    });
    if let Some(e) = failure {
        anyhow::bail!("rendering failed: {e}");
    }
    let per_figure_ms = timing.median_s / figs.len() as f64 * 1e3;
    Ok(BenchReport {
        workload: "plot-figures".into(),
        figure: per_figure_ms,
        unit: "ms/figure (SVG + PNG)".into(),
        check: json!({
            "figures": figs.len(),
            "samples_per_trace": 10_001,
            "svg_bytes_total": svg_bytes,
            "png_bytes_total": png_bytes,
            "projected_60_figures_s": per_figure_ms * 60.0 / 1e3,
            "timing": timing,
        }),
    })
}

fn plot_animation(budget: &Budget) -> Result<BenchReport> {
    let r = run(16_001, 0.0);
    let anim = Animation::cart(r.t(), r.x_signal(0), r.x_signal(1), CartGeometry::default())?;
    let mut gif_bytes = 0;
    let mut svg_bytes = 0;
    let mut failure = None;
    let timing = time(budget, || match (anim.to_gif(), anim.to_svg()) {
        (Ok(g), Ok(s)) => {
            gif_bytes = g.len();
            svg_bytes = s.len();
        }
        (Err(e), _) | (_, Err(e)) => failure = Some(e.to_string()),
    });
    if let Some(e) = failure {
        anyhow::bail!("animation failed: {e}");
    }
    Ok(BenchReport {
        workload: "plot-animation".into(),
        figure: timing.median_s * 1e3,
        unit: "ms/animation (GIF + SVG)".into(),
        check: json!({
            "frames": anim.frame_times().len(),
            "gif_bytes": gif_bytes,
            "svg_bytes": svg_bytes,
            "timing": timing,
        }),
    })
}
