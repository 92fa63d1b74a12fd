//! Helpers shared by the examples of part 1, chapters 2–4: error mapping, the cart rig presets,
//! stacked time-response figures and figure/animation writing.

use crate::error::BookError;
use crate::output::{ExampleOutput, Value};
use pendulab_lti::{Complex64, linalg::sort_eigenvalues};
use pendulab_plants::RigSpec;
use pendulab_plot::{Animation, AnimationOptions, Axes, CartGeometry, Figure, LegendPos, palette};
use pendulab_sim::rig::RigChains;
use std::path::Path;

/// Maps any displayable error to [`BookError::Computation`] for example `id`.
pub(crate) fn comp<E: std::fmt::Display>(id: &'static str) -> impl Fn(E) -> BookError {
    move |e| BookError::Computation {
        id: id.to_string(),
        message: e.to_string(),
    }
}

/// A computation error with a message.
pub(crate) fn fail(id: &'static str, message: impl Into<String>) -> BookError {
    BookError::Computation {
        id: id.to_string(),
        message: message.into(),
    }
}

/// The cart rig of SPEC §1.3 as the book's Simulink plant: "plain" (exact full state, ideal
/// amplifier) or "with quantizer" (encoders 4.8414e-5 m and 2π/14400 rad, velocities by the
/// pseudo-differentiator 1/(0.02 s + 1), ±5 V, 16-bit D/A).
pub(crate) fn cart_rig(quantised: bool) -> Result<RigChains, pendulab_sim::SimError> {
    rig_chains(&RigSpec::cart(), quantised)
}

fn rig_chains(rig: &RigSpec, quantised: bool) -> Result<RigChains, pendulab_sim::SimError> {
    if !quantised {
        return Ok(RigChains::plain(rig.nx));
    }
    let enc: Vec<(usize, f64)> = rig.encoders.iter().map(|e| (e.state, e.step)).collect();
    let vel: Vec<(usize, usize, f64)> = rig
        .velocity_estimators
        .iter()
        .map(|v| (v.position_state, v.velocity_state, v.time_constant))
        .collect();
    RigChains::with_quantizer(rig.nx, &enc, &vel, rig.input_limit, rig.dac.bits)
}

/// Eigenvalues / poles as a value, in the workspace order (real part descending, then
/// imaginary part descending).
pub(crate) fn complex_value(mut v: Vec<Complex64>) -> Value {
    sort_eigenvalues(&mut v);
    Value::Complex(v)
}

/// Complex numbers from `(re, im)` pairs (for printed references).
pub(crate) fn cpx(pairs: &[(f64, f64)]) -> Value {
    Value::Complex(pairs.iter().map(|&(r, i)| Complex64::new(r, i)).collect())
}

/// One line of a panel: legend label, abscissa, ordinate.
pub(crate) type Line<'a> = (String, &'a [f64], Vec<f64>);

/// One panel of a stacked figure.
pub(crate) struct PanelSpec<'a> {
    /// Vertical axis label with unit.
    pub ylabel: String,
    /// The lines, overlaid in palette colours.
    pub lines: Vec<Line<'a>>,
    /// Horizontal reference lines (value, legend label).
    pub refs: Vec<(f64, String)>,
}

impl<'a> PanelSpec<'a> {
    pub(crate) fn new(ylabel: &str, lines: Vec<Line<'a>>) -> Self {
        Self {
            ylabel: ylabel.to_string(),
            lines,
            refs: Vec::new(),
        }
    }
    pub(crate) fn reference(mut self, value: f64, label: &str) -> Self {
        self.refs.push((value, label.to_string()));
        self
    }
}

/// Panels stacked over a common horizontal axis labelled `xlabel`.
pub(crate) fn stacked(title: &str, xlabel: &str, panels: Vec<PanelSpec<'_>>) -> Figure {
    let n = panels.len();
    let axes: Vec<Axes> = panels
        .into_iter()
        .enumerate()
        .map(|(p, spec)| {
            let mut ax = Axes::new();
            ax.ylabel(spec.ylabel).legend(LegendPos::Best);
            if p + 1 == n {
                ax.xlabel(xlabel);
            }
            for (i, (label, x, y)) in spec.lines.iter().enumerate() {
                ax.plot(x, y).label(label.clone()).color(palette(i));
            }
            for (v, label) in spec.refs {
                ax.hline(v).label(label).dashed();
            }
            ax
        })
        .collect();
    let h = 240.0 * n as f64 + 60.0;
    Figure::column(axes).title(title).size(640.0, h)
}

/// Writes `fig` as `dir/stem.svg` + `dir/stem.png` and records both paths.
pub(crate) fn save_figure(
    id: &'static str,
    out: &mut ExampleOutput,
    dir: &Path,
    stem: &str,
    fig: &Figure,
) -> Result<(), BookError> {
    let saved = fig.save(dir, stem).map_err(|e| BookError::Figure {
        id: id.to_string(),
        path: dir.join(stem).display().to_string(),
        message: e.to_string(),
    })?;
    out.figures.push(saved.svg);
    out.figures.push(saved.png);
    Ok(())
}

/// Writes a cart-pendulum animation (`stem.gif` + animated `stem.svg`) of `z`, `θ` (from
/// upright) and records the paths.
#[allow(clippy::too_many_arguments)]
pub(crate) fn save_cart_animation(
    id: &'static str,
    out: &mut ExampleOutput,
    dir: &Path,
    stem: &str,
    title: &str,
    t: &[f64],
    z: &[f64],
    theta: &[f64],
) -> Result<(), BookError> {
    let zmax = z.iter().fold(0.5f64, |m, v| m.max(v.abs() + 0.3));
    let geometry = CartGeometry {
        rail: (-zmax, zmax),
        ..CartGeometry::default()
    };
    let anim = Animation::cart(t, z, theta, geometry)
        .map_err(comp(id))?
        .options(AnimationOptions {
            max_frames: 120,
            ..AnimationOptions::default()
        })
        .title(title);
    save_animation(id, out, dir, stem, &anim)
}

/// Writes `anim` as `stem.gif` and `stem.svg` and records both paths.
pub(crate) fn save_animation(
    id: &'static str,
    out: &mut ExampleOutput,
    dir: &Path,
    stem: &str,
    anim: &Animation,
) -> Result<(), BookError> {
    std::fs::create_dir_all(dir).map_err(|e| BookError::Figure {
        id: id.to_string(),
        path: dir.display().to_string(),
        message: e.to_string(),
    })?;
    for ext in ["gif", "svg"] {
        let path = dir.join(format!("{stem}.{ext}"));
        let r = if ext == "gif" {
            anim.save_gif(&path)
        } else {
            anim.save_svg(&path)
        };
        r.map_err(|e| BookError::Figure {
            id: id.to_string(),
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        out.figures.push(path);
    }
    Ok(())
}

/// Local extrema of `y` (strict sign changes of the first difference, plateaus timed at their
/// midpoint) after index `start`: `(time, value)` pairs.
pub(crate) fn extrema(t: &[f64], y: &[f64], start: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut k = start.max(1);
    let mut dir = 0.0f64; // sign of the last non-zero difference
    let mut plateau_start = k - 1;
    while k < y.len() {
        let d = y[k] - y[k - 1];
        if d != 0.0 {
            let s = d.signum();
            if dir != 0.0 && s != dir {
                // Extremum on the plateau [plateau_start, k − 1].
                let mid = 0.5 * (t[plateau_start] + t[k - 1]);
                out.push((mid, y[k - 1]));
            }
            dir = s;
            plateau_start = k;
        }
        k += 1;
    }
    out
}

/// `Result<T, E>` → `Result<T, BookError>` for example `id` ([`BookError::Computation`]).
pub(crate) trait Ctx<T> {
    /// Maps the error with [`comp`].
    fn ctx(self, id: &'static str) -> Result<T, BookError>;
}

impl<T, E: std::fmt::Display> Ctx<T> for Result<T, E> {
    fn ctx(self, id: &'static str) -> Result<T, BookError> {
        self.map_err(comp(id))
    }
}
