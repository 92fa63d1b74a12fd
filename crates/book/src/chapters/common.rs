//! Helpers shared by every chapter: error mapping, the book's gain and pole conventions, the
//! rig presets, small signal summaries, stacked time-response figures, and adding figures and
//! animations to an example's output (as values; the front end renders and writes them).

use crate::error::{BookError, Cause};
use crate::output::{ExampleOutput, Value};
use crate::registry::RunContext;
use pendulab_lti::design::StateFeedback;
use pendulab_lti::{Complex64, Continuous, Mat, StateSpace, Trajectory};
use pendulab_plants::{ArmEquilibrium, ArmPendulum, ArmPendulumParams, RigSpec};
use pendulab_plot::{
    Animation, AnimationOptions, ArmGeometry, Axes, CartGeometry, Figure, LegendPos, PlotError,
    TimeResponse, palette,
};
use pendulab_sim::rig::RigChains;
use pendulab_sim::scenario::Imperfections;

// ------------------------------------------------------------------------------ errors

/// A [`BookError::Computation`] of example `id` caused by `cause` (a toolkit error, or the
/// text of a failed check of the example's own).
pub(crate) fn fail(id: &str, cause: impl Into<Cause>) -> BookError {
    BookError::Computation {
        id: id.to_string(),
        source: Box::new(cause.into()),
    }
}

/// `Result<T, E>` → `Result<T, BookError>` for example `id` ([`BookError::Computation`]).
pub(crate) trait Ctx<T> {
    /// Maps the error with [`fail`].
    fn ctx(self, id: &str) -> Result<T, BookError>;
}

impl<T, E: Into<Cause>> Ctx<T> for Result<T, E> {
    fn ctx(self, id: &str) -> Result<T, BookError> {
        self.map_err(|e| fail(id, e))
    }
}

/// A [`BookError::Figure`] of example `id` about the figure `stem`.
fn figure_error(id: &str, stem: &str, source: PlotError) -> BookError {
    BookError::Figure {
        id: id.to_string(),
        stem: stem.to_string(),
        source,
    }
}

// ------------------------------------------------------------------ matrices and conventions

/// `diag(d)`.
pub(crate) fn diag(d: &[f64]) -> Mat {
    Mat::from_diagonal(&nalgebra::DVector::from_row_slice(d))
}

/// Row `0` of a `1 × n` matrix as a vector.
pub(crate) fn row(m: &Mat) -> Vec<f64> {
    m.row(0).iter().copied().collect()
}

/// Row `0` of a library gain (`u = −K x`) in the book's convention `u = +K_book x`
/// (`K_book = −K`).
pub(crate) fn book_row(k: &Mat) -> Vec<f64> {
    row(k).into_iter().map(|v| -v).collect()
}

/// Column `j` of a sample matrix (rows = samples).
pub(crate) fn column(x: &Mat, j: usize) -> Vec<f64> {
    (0..x.nrows()).map(|i| x[(i, j)]).collect()
}

/// Complex numbers from `(re, im)` pairs (for printed references).
pub(crate) fn complex(p: &[(f64, f64)]) -> Vec<Complex64> {
    p.iter().map(|&(r, i)| Complex64::new(r, i)).collect()
}

/// Poles sorted the workspace's way (real part descending, then imaginary part descending;
/// [`pendulab_lti::linalg::sort_eigenvalues`]).
pub(crate) fn sorted(mut p: Vec<Complex64>) -> Vec<Complex64> {
    pendulab_lti::linalg::sort_eigenvalues(&mut p);
    p
}

/// Sorted poles of the state-feedback loop of the pair `(A, B)` (`n × n`, `n × m`) under the
/// library gain `K` (`m × n`, `u = −K x`): the eigenvalues of the toolkit's
/// [`StateFeedback::closed_loop`] `A − BK`.
///
/// # Errors
/// The toolkit's errors for shapes that do not fit or non-finite entries.
pub(crate) fn feedback_poles(
    id: &str,
    a: &Mat,
    b: &Mat,
    k: &Mat,
) -> Result<Vec<Complex64>, BookError> {
    let n = a.nrows();
    let pair = StateSpace::<Continuous>::continuous(
        a.clone(),
        b.clone(),
        Mat::identity(n, n),
        Mat::zeros(n, b.ncols()),
    )
    .ctx(id)?;
    let closed = StateFeedback::new(k.clone())
        .ctx(id)?
        .closed_loop(&pair)
        .ctx(id)?;
    closed.poles().map(sorted).ctx(id)
}

/// Largest real part of a set of poles (−∞ for none).
pub(crate) fn max_re(p: &[Complex64]) -> f64 {
    p.iter().map(|z| z.re).fold(f64::NEG_INFINITY, f64::max)
}

/// Adds the book's exactly printed values `refs` (`(name, value)` pairs: entries of integer
/// matrices, ranks, yes/no answers), each cited as `source` and reproduced only when equal
/// (tolerance 0).
pub(crate) fn exact_references<const N: usize>(
    out: &mut ExampleOutput,
    source: &str,
    refs: [(&str, Value); N],
) {
    for (name, value) in refs {
        out.reference(name, value, source, 0.0);
    }
}

// ------------------------------------------------------------------------- signal summaries

/// Largest `|v_k|` over the samples with `t_k ≥ from` (0 for none).
pub(crate) fn max_abs_after(t: &[f64], v: &[f64], from: f64) -> f64 {
    t.iter()
        .zip(v)
        .filter(|(ti, _)| **ti >= from - 1e-12)
        .map(|(_, v)| v.abs())
        .fold(0.0, f64::max)
}

/// Smallest value of `v` (+∞ for none).
pub(crate) fn min_of(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

/// Largest value of `v` (−∞ for none).
pub(crate) fn max_of(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
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

// ------------------------------------------------------------------------------- rig presets

/// The book's rig preset "with quantizer" (`docs/model.md` §3): the rig's
/// [`RigSpec::chains`] with [`Imperfections::with_quantizer`] — encoders on the positions,
/// velocities by the pseudo-differentiator `s/(0.02 s + 1)`, ±5 V and a 16-bit D/A.
///
/// # Errors
/// The chains' construction errors (none for the built-in rigs).
pub(crate) fn quantized_rig(id: &str, rig: &RigSpec) -> Result<RigChains, BookError> {
    rig.chains(&Imperfections::with_quantizer()).ctx(id)
}

/// The nonlinear plant "plain" with the book's default measurement (`docs/model.md` §3): the
/// rig's [`RigSpec::chains`] with only the pseudo-differentiator switched on — exact
/// positions, velocities by derivative + `1/(0.02 s + 1)`, ideal actuator.
///
/// # Errors
/// The sensor's construction errors (none for the built-in rigs).
pub(crate) fn filtered_rig(id: &str, rig: &RigSpec) -> Result<RigChains, BookError> {
    let effects = Imperfections {
        pseudo_differentiator: true,
        ..Imperfections::ideal()
    };
    rig.chains(&effects).ctx(id)
}

/// The arm pendulum linearised upright at `θ₁ = 0` with drive parameters `a1`, `b1`,
/// augmented with the servo integrator `w = ∫(r − θ₁)`: `Ã = [[A, 0], [−C, 0]]`, `B̃ = [B; 0]`.
///
/// # Errors
/// The model's construction errors (none for positive `a1`, `b1`).
pub(crate) fn arm_servo_model(id: &str, a1: f64, b1: f64) -> Result<(Mat, Mat), BookError> {
    let plant = ArmPendulum::new(ArmPendulumParams {
        a1,
        b1,
        ..ArmPendulumParams::book()
    })
    .ctx(id)?;
    let lin = plant.linearize(ArmEquilibrium::upright(0.0)).ctx(id)?;
    arm_servo_augmentation(id, lin.a(), lin.b())
}

/// An arm pendulum model `(A, B)` (`4 × 4`, `4 × 1`; e.g. a frozen LPV model) augmented with
/// the servo integrator `w = ∫(r − θ₁)` by the toolkit's
/// [`integral_augmentation`](pendulab_lti::design::integral_augmentation):
/// `Ã = [[A, 0], [−C, 0]]`, `B̃ = [B; 0]`, `C = [1, 0, 0, 0]`.
///
/// # Errors
/// The model's construction errors (wrong shapes, non-finite entries).
pub(crate) fn arm_servo_augmentation(id: &str, a: &Mat, b: &Mat) -> Result<(Mat, Mat), BookError> {
    let c = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
    let sys =
        StateSpace::<Continuous>::continuous(a.clone(), b.clone(), c, Mat::zeros(1, 1)).ctx(id)?;
    pendulab_lti::design::integral_augmentation(&sys).ctx(id)
}

// ---------------------------------------------------------------------------------- figures

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
    /// A panel of `lines` under the axis label `ylabel`.
    pub(crate) fn new(ylabel: &str, lines: Vec<Line<'a>>) -> Self {
        Self {
            ylabel: ylabel.to_string(),
            lines,
            refs: Vec::new(),
        }
    }
    /// Adds a dashed horizontal reference line at `value`.
    pub(crate) fn reference(mut self, value: f64, label: &str) -> Self {
        self.refs.push((value, label.to_string()));
        self
    }
}

/// Panels stacked over a common horizontal axis labelled `xlabel`.
pub(crate) fn stacked(title: &str, xlabel: &str, panels: Vec<PanelSpec<'_>>) -> Figure {
    let n = panels.len();
    // A panel repeating the first panel's lines (same labels, no references of its own) needs
    // no legend of its own: the first panel's names them.
    let first: Vec<String> = panels
        .first()
        .map(|s| s.lines.iter().map(|l| l.0.clone()).collect())
        .unwrap_or_default();
    let axes: Vec<Axes> = panels
        .into_iter()
        .enumerate()
        .map(|(p, spec)| {
            let mut ax = Axes::new();
            let repeats =
                p > 0 && spec.refs.is_empty() && spec.lines.iter().map(|l| &l.0).eq(first.iter());
            ax.ylabel(spec.ylabel).legend(if repeats {
                LegendPos::Hidden
            } else {
                LegendPos::Best
            });
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

/// Adds `fig` to `out` under the file stem `stem` (`stem.svg`, `stem.png`).
pub(crate) fn write_figure(out: &mut ExampleOutput, stem: &str, fig: Figure) {
    out.figure(stem, fig);
}

/// Adds `fig` to `out` as `<id>_<what>` when the context asks for figures (nothing otherwise).
///
/// # Errors
/// [`BookError::Figure`] naming the figure when `fig` could not be drawn.
pub(crate) fn save_figure(
    ctx: &RunContext,
    out: &mut ExampleOutput,
    id: &str,
    what: &str,
    fig: Result<Figure, PlotError>,
) -> Result<(), BookError> {
    if !ctx.figures {
        return Ok(());
    }
    let stem = format!("{id}_{what}");
    let fig = fig.map_err(|e| figure_error(id, &stem, e))?;
    write_figure(out, &stem, fig);
    Ok(())
}

// ------------------------------------------------------------------------------- animations

/// Which rig an animation draws.
pub(crate) enum Rig {
    /// The cart-type pendulum: `a` = cart position `z` [m], `b` = `θ` [rad] from upright.
    Cart,
    /// The arm-type pendulum: `a` = arm angle `θ₁`, `b` = pendulum angle `θ₂` [rad].
    Arm,
}

/// An animation of `rig` over the samples `t` [s] of its two position coordinates `a`, `b`,
/// at 20 frames/s and at most 160 frames. The cart's rail is widened to keep the cart 0.3 m
/// inside its ends.
///
/// # Errors
/// The plot crate's errors for mismatched or non-finite samples.
pub(crate) fn animation(
    rig: Rig,
    t: &[f64],
    a: &[f64],
    b: &[f64],
    title: &str,
) -> Result<Animation, PlotError> {
    let anim = match rig {
        Rig::Cart => {
            let zmax = a.iter().fold(0.5f64, |m, v| m.max(v.abs() + 0.3));
            let geometry = CartGeometry {
                rail: (-zmax, zmax),
                ..CartGeometry::default()
            };
            Animation::cart(t, a, b, geometry)?
        }
        Rig::Arm => Animation::arm(t, a, b, ArmGeometry::default())?,
    };
    Ok(anim
        .options(AnimationOptions {
            fps: 20.0,
            max_frames: 160,
            ..AnimationOptions::default()
        })
        .title(title))
}

/// [`animation`] of a recorded run whose state starts with the two position coordinates
/// (`x = [z, θ, ż, θ̇]` or `[θ₁, θ₂, θ̇₁, θ̇₂]`).
///
/// # Errors
/// As [`animation`].
pub(crate) fn run_animation(
    rig: Rig,
    tr: &Trajectory,
    title: &str,
) -> Result<Animation, PlotError> {
    animation(rig, tr.t(), tr.x_signal(0), tr.x_signal(1), title)
}

/// Adds `anim` to `out` under the file stem `stem` (`stem.gif`, the animated `stem.svg`).
///
/// # Errors
/// [`BookError::Figure`] naming the animation when it could not be built.
pub(crate) fn write_animation(
    id: &str,
    out: &mut ExampleOutput,
    stem: &str,
    anim: Result<Animation, PlotError>,
) -> Result<(), BookError> {
    let anim = anim.map_err(|e| figure_error(id, stem, e))?;
    out.animation(stem, anim);
    Ok(())
}

/// Adds the animation `build` makes as `<id>_<what>` when the context asks for figures
/// (`build` is not called otherwise).
///
/// # Errors
/// [`BookError::Figure`] naming the animation.
pub(crate) fn save_animation(
    ctx: &RunContext,
    out: &mut ExampleOutput,
    id: &str,
    what: &str,
    build: impl FnOnce() -> Result<Animation, PlotError>,
) -> Result<(), BookError> {
    if !ctx.figures {
        return Ok(());
    }
    write_animation(id, out, &format!("{id}_{what}"), build())
}

/// Adds the time-response figure `response` as `<id>_response` and the [`run_animation`] of
/// the recorded run `tr` on `rig`, titled `id`, as `<id>_animation` when the context asks for
/// figures (nothing is built otherwise).
///
/// # Errors
/// [`BookError::Figure`] naming the figure or the animation.
pub(crate) fn save_response_and_animation(
    ctx: &RunContext,
    out: &mut ExampleOutput,
    id: &str,
    response: &TimeResponse<'_>,
    rig: Rig,
    tr: &Trajectory,
) -> Result<(), BookError> {
    if !ctx.figures {
        return Ok(());
    }
    save_figure(ctx, out, id, "response", response.figure())?;
    save_run_animation(ctx, out, id, rig, tr, id)
}

/// Adds the [`run_animation`] of the recorded run `tr` on `rig`, titled `title`, as
/// `<id>_animation` when the context asks for figures (nothing is built otherwise).
///
/// # Errors
/// [`BookError::Figure`] naming the animation.
pub(crate) fn save_run_animation(
    ctx: &RunContext,
    out: &mut ExampleOutput,
    id: &str,
    rig: Rig,
    tr: &Trajectory,
    title: &str,
) -> Result<(), BookError> {
    save_animation(ctx, out, id, "animation", || run_animation(rig, tr, title))
}
