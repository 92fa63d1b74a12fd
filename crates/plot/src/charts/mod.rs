//! Ready-made figures of the book: time responses of trajectories, Bode diagrams, pole–zero
//! maps with design regions, gain-scheduling curves, identification fits and region-of-attraction
//! maps. Each builder returns a [`Figure`] (or its [`Axes`]) that can still be changed before it
//! is saved.

use pendulab_lti::Trajectory;

use crate::axes::Axes;
use crate::color::{Color, palette};
use crate::error::{PlotError, Result};
use crate::figure::{Figure, Panel};
use crate::style::Dash;

mod frequency;

pub use frequency::{Bode, FrequencyUnit, PoleZeroMap};

/// A signal of a [`Trajectory`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    /// State `x[i]`.
    State(usize),
    /// Input `u[i]`.
    Input(usize),
    /// Output `y[i]`.
    Output(usize),
}

impl Channel {
    fn get<'a>(&self, tr: &'a Trajectory) -> Option<&'a [f64]> {
        match *self {
            Channel::State(i) if i < tr.x().ncols() => Some(tr.x_signal(i)),
            Channel::Input(i) if i < tr.u().ncols() => Some(tr.u_signal(i)),
            Channel::Output(i) if i < tr.y().ncols() => Some(tr.y_signal(i)),
            _ => None,
        }
    }
    fn describe(&self) -> String {
        match self {
            Channel::State(i) => format!("state x[{i}]"),
            Channel::Input(i) => format!("input u[{i}]"),
            Channel::Output(i) => format!("output y[{i}]"),
        }
    }
}

/// One panel of a [`TimeResponse`]: the channels it shows, its axis label and how values are
/// drawn.
#[derive(Debug, Clone)]
pub struct SignalPanel {
    channels: Vec<(Channel, Option<String>)>,
    ylabel: String,
    scale: f64,
    stairs: bool,
    references: Vec<(f64, Option<String>)>,
}

impl SignalPanel {
    /// A panel showing one channel, labelled `ylabel` (with its unit).
    pub fn new(channel: Channel, ylabel: impl Into<String>) -> Self {
        Self {
            channels: vec![(channel, None)],
            ylabel: ylabel.into(),
            scale: 1.0,
            stairs: false,
            references: Vec::new(),
        }
    }
    /// Adds another channel to the same panel; `name` appears in the legend.
    pub fn with(mut self, channel: Channel, name: impl Into<String>) -> Self {
        self.channels.push((channel, Some(name.into())));
        self
    }
    /// Names the first channel in the legend.
    pub fn named(mut self, name: impl Into<String>) -> Self {
        if let Some(c) = self.channels.first_mut() {
            c.1 = Some(name.into());
        }
        self
    }
    /// Multiplies every value by `factor` before drawing (e.g. `180/π` for degrees).
    pub fn scaled(mut self, factor: f64) -> Self {
        self.scale = factor;
        self
    }
    /// Draws the channels as staircases (sampled or zero-order-hold signals).
    pub fn stairs(mut self) -> Self {
        self.stairs = true;
        self
    }
    /// Adds a horizontal reference line (e.g. the target r = 0.5 m), in drawn units.
    pub fn reference(mut self, value: f64, label: Option<&str>) -> Self {
        self.references.push((value, label.map(str::to_string)));
        self
    }
}

/// Time responses of one or several runs, one panel per [`SignalPanel`], stacked over a common
/// time axis. Runs get the palette colours in turn (the first panel carries the legend); with a
/// single run, channels sharing a panel get the colours instead.
///
/// ```
/// use pendulab_lti::{Mat, Trajectory};
/// use pendulab_plot::{Channel, SignalPanel, TimeResponse};
/// let t: Vec<f64> = (0..100).map(|k| k as f64 * 0.01).collect();
/// let x = Mat::from_fn(100, 2, |k, i| if i == 0 { t[k] } else { t[k].sin() });
/// let tr = Trajectory::new(t.clone(), x, Mat::zeros(100, 0), Mat::zeros(100, 0)).unwrap();
/// let fig = TimeResponse::new()
///     .run("LQR", &tr)
///     .panel(SignalPanel::new(Channel::State(0), "z [m]"))
///     .panel(SignalPanel::new(Channel::State(1), "θ [deg]").scaled(180.0 / std::f64::consts::PI))
///     .figure()
///     .unwrap();
/// assert!(fig.to_svg().unwrap().contains("θ [deg]"));
/// ```
#[derive(Debug, Clone, Default)]
pub struct TimeResponse<'a> {
    runs: Vec<(String, &'a Trajectory)>,
    panels: Vec<SignalPanel>,
    title: Option<String>,
    xlabel: Option<String>,
}

impl<'a> TimeResponse<'a> {
    /// An empty builder.
    pub fn new() -> Self {
        Self::default()
    }
    /// Adds a run (a simulated or measured trajectory) with its legend label.
    pub fn run(mut self, label: impl Into<String>, traj: &'a Trajectory) -> Self {
        self.runs.push((label.into(), traj));
        self
    }
    /// Adds a panel (top to bottom in call order).
    pub fn panel(mut self, panel: SignalPanel) -> Self {
        self.panels.push(panel);
        self
    }
    /// Figure title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// Time axis label (default `time [s]`).
    pub fn xlabel(mut self, label: impl Into<String>) -> Self {
        self.xlabel = Some(label.into());
        self
    }

    /// Builds the figure.
    ///
    /// # Errors
    /// [`PlotError::Empty`] without runs or panels or for an empty trajectory;
    /// [`PlotError::InvalidArgument`] if a panel asks for a channel a run does not have.
    pub fn figure(&self) -> Result<Figure> {
        if self.runs.is_empty() || self.panels.is_empty() {
            return Err(PlotError::Empty {
                what: "time response (needs at least one run and one panel)".into(),
            });
        }
        let multi = self.runs.len() > 1;
        let mut axes = Vec::new();
        for (p, panel) in self.panels.iter().enumerate() {
            let mut ax = Axes::new();
            ax.ylabel(panel.ylabel.clone());
            if p + 1 == self.panels.len() {
                ax.xlabel(self.xlabel.clone().unwrap_or_else(|| "time [s]".into()));
            }
            // Chattering signals (switching, quantised, noisy) first, lighter and thinner, so
            // that the smooth ones stay visible on top; otherwise in call order.
            let mut lines = Vec::new();
            for (r, (label, tr)) in self.runs.iter().enumerate() {
                if tr.is_empty() {
                    return Err(PlotError::Empty {
                        what: format!("run \"{label}\""),
                    });
                }
                for (c, (ch, name)) in panel.channels.iter().enumerate() {
                    let data = ch.get(tr).ok_or_else(|| {
                        PlotError::InvalidArgument(format!(
                            "panel {p} asks for {} but run \"{label}\" has {} states, {} inputs, {} outputs",
                            ch.describe(),
                            tr.x().ncols(),
                            tr.u().ncols(),
                            tr.y().ncols()
                        ))
                    })?;
                    let v: Vec<f64> = data.iter().map(|v| v * panel.scale).collect();
                    lines.push((chatters(&v), r, label, *tr, c, name, v));
                }
            }
            lines.sort_by_key(|l| !l.0);
            for (chatter, r, label, tr, c, name, v) in lines {
                let s = if panel.stairs {
                    ax.step(tr.t(), &v)
                } else {
                    ax.plot(tr.t(), &v)
                };
                if multi {
                    s.color(palette(r)).dash(dash_cycle(c));
                    let legend = match name {
                        Some(n) if panel.channels.len() > 1 => Some(format!("{label}: {n}")),
                        _ if p == 0 && c == 0 => Some(label.clone()),
                        _ => None,
                    };
                    if let Some(l) = legend {
                        s.label(l);
                    }
                } else {
                    s.color(palette(c));
                    if let Some(n) = name {
                        s.label(n.clone());
                    }
                }
                if chatter {
                    let col = if multi { palette(r) } else { palette(c) };
                    s.color(col.with_alpha(0.45)).width(0.9);
                }
            }
            for (v, l) in &panel.references {
                let s = ax.hline(*v);
                s.dashed().color(Color::DARK_GREY);
                if let Some(l) = l {
                    s.label(l.clone());
                }
            }
            axes.push(ax);
        }
        let mut fig = Figure::column(axes);
        if let Some(t) = &self.title {
            fig = fig.title(t.clone());
        }
        Ok(fig)
    }
}

/// Total variation over range above which a signal counts as chattering.
pub const CHATTER_RATIO: f64 = 40.0;

/// Whether a sampled signal chatters: its total variation `Σ|v[k+1] − v[k]|` (over consecutive
/// finite samples) exceeds [`CHATTER_RATIO`] times its range `max − min`, i.e. it sweeps its
/// whole range more than 20 times back and forth (a switching or quantised input; a lightly
/// damped oscillation of a few dozen cycles stays below). [`TimeResponse`] draws such signals
/// first (beneath the others), lighter and thinner; hand-built panels can do the same.
pub fn chatters(v: &[f64]) -> bool {
    let (mut lo, mut hi, mut tv) = (f64::INFINITY, f64::NEG_INFINITY, 0.0);
    for w in v.windows(2) {
        if w[0].is_finite() && w[1].is_finite() {
            tv += (w[1] - w[0]).abs();
        }
    }
    for x in v.iter().filter(|x| x.is_finite()) {
        lo = lo.min(*x);
        hi = hi.max(*x);
    }
    hi > lo && tv > CHATTER_RATIO * (hi - lo)
}

fn dash_cycle(k: usize) -> Dash {
    [Dash::Solid, Dash::Dashed, Dash::Dotted, Dash::DashDot][k % 4]
}

/// Gain-scheduling curves K(θ) beside constant reference gains (book part 2 fig. 1.16): one
/// panel per gain entry, the scheduled gain as a solid line and the constant gain as a dashed
/// horizontal line, in a grid of two columns.
///
/// ```
/// use pendulab_plot::GainCurves;
/// let th: Vec<f64> = (0..=65).map(|k| k as f64).collect();
/// let k11: Vec<f64> = th.iter().map(|t| 1.0 + 0.01 * t).collect();
/// let fig = GainCurves::new("θ₁ [deg]", &th).gain("K₁₁", &k11, Some(1.2)).figure().unwrap();
/// assert!(fig.to_svg().unwrap().contains("K₁₁"));
/// ```
#[derive(Debug, Clone)]
pub struct GainCurves {
    xlabel: String,
    x: Vec<f64>,
    gains: Vec<(String, Vec<f64>, Option<f64>)>,
    names: (String, String),
    title: Option<String>,
}

impl GainCurves {
    /// Curves over the scheduling variable `x` (e.g. θ₁ in degrees).
    pub fn new(xlabel: impl Into<String>, x: &[f64]) -> Self {
        Self {
            xlabel: xlabel.into(),
            x: x.to_vec(),
            gains: Vec::new(),
            names: ("gain scheduling".into(), "LQ (constant)".into()),
            title: None,
        }
    }
    /// Adds a gain entry: its name, its scheduled values over `x`, and the constant gain to
    /// compare with.
    pub fn gain(mut self, name: impl Into<String>, values: &[f64], constant: Option<f64>) -> Self {
        self.gains.push((name.into(), values.to_vec(), constant));
        self
    }
    /// Legend names of the scheduled and of the constant gains.
    pub fn legend_names(
        mut self,
        scheduled: impl Into<String>,
        constant: impl Into<String>,
    ) -> Self {
        self.names = (scheduled.into(), constant.into());
        self
    }
    /// Figure title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// Builds the figure.
    ///
    /// # Errors
    /// [`PlotError::Empty`] without gains; data errors are reported when rendering.
    pub fn figure(&self) -> Result<Figure> {
        if self.gains.is_empty() {
            return Err(PlotError::Empty {
                what: "gain curves (no gain)".into(),
            });
        }
        let n = self.gains.len();
        let cols = if n > 2 { 2 } else { 1 };
        let mut rows: Vec<Vec<Panel>> = Vec::new();
        for (k, (name, v, c)) in self.gains.iter().enumerate() {
            let mut ax = Axes::new();
            ax.ylabel(name.clone());
            if k + cols >= n {
                ax.xlabel(self.xlabel.clone());
            }
            let s = ax.plot(&self.x, v).color(Color::BLUE);
            if k == 0 {
                s.label(self.names.0.clone());
            }
            if let Some(c) = c {
                let s = ax.hline(*c).color(Color::RED).dashed().width(1.5);
                if k == 0 {
                    s.label(self.names.1.clone());
                }
            }
            if k % cols == 0 {
                rows.push(Vec::new());
            }
            if let Some(r) = rows.last_mut() {
                r.push(ax.into());
            }
        }
        if let Some(r) = rows.last_mut() {
            while r.len() < cols {
                r.push(Panel::Empty);
            }
        }
        let h = 210.0 * rows.len() as f64 + 20.0;
        let w = if cols == 2 {
            900.0
        } else {
            crate::figure::DEFAULT_WIDTH
        };
        let mut fig = Figure::grid(rows).size(w, h + if self.title.is_some() { 26.0 } else { 0.0 });
        if let Some(t) = &self.title {
            fig = fig.title(t.clone());
        }
        Ok(fig)
    }
}

/// One panel of an [`IdentFit`]: axis label, measured values, named model outputs.
type FitSignal = (String, Vec<f64>, Vec<(String, Vec<f64>)>);

/// Identification fits: measured signals (grey) against model outputs (coloured), one panel per
/// signal, with the fit percentage 100 (1 − ‖y − ŷ‖ / ‖y − mean y‖) of each model in its legend
/// entry (MATLAB `compare`; computed over the samples where both are finite).
///
/// ```
/// use pendulab_plot::IdentFit;
/// let t: Vec<f64> = (0..50).map(|k| k as f64 * 0.1).collect();
/// let y: Vec<f64> = t.iter().map(|t| 1.0 - (-t).exp()).collect();
/// let fig = IdentFit::new(&t).signal("z [m]", &y, &[("model", &y)]).figure().unwrap();
/// assert!(fig.to_svg().unwrap().contains("fit 100.0 %"));
/// ```
#[derive(Debug, Clone)]
pub struct IdentFit {
    t: Vec<f64>,
    signals: Vec<FitSignal>,
    measured_name: String,
    title: Option<String>,
    xlabel: String,
}

impl IdentFit {
    /// Fits over the common sample times `t`.
    pub fn new(t: &[f64]) -> Self {
        Self {
            t: t.to_vec(),
            signals: Vec::new(),
            measured_name: "measured".into(),
            title: None,
            xlabel: "time [s]".into(),
        }
    }
    /// Adds a panel: the measured signal and one or more model outputs `(name, values)`.
    pub fn signal(
        mut self,
        ylabel: impl Into<String>,
        measured: &[f64],
        models: &[(&str, &[f64])],
    ) -> Self {
        self.signals.push((
            ylabel.into(),
            measured.to_vec(),
            models
                .iter()
                .map(|(n, v)| (n.to_string(), v.to_vec()))
                .collect(),
        ));
        self
    }
    /// Legend name of the measured data (default "measured").
    pub fn measured_name(mut self, name: impl Into<String>) -> Self {
        self.measured_name = name.into();
        self
    }
    /// Horizontal axis label (default "time \[s\]").
    pub fn xlabel(mut self, label: impl Into<String>) -> Self {
        self.xlabel = label.into();
        self
    }
    /// Figure title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// Builds the figure.
    ///
    /// # Errors
    /// [`PlotError::Empty`] without signals; [`PlotError::LengthMismatch`] if a model output and
    /// its measured signal differ in length (other data errors are reported when rendering).
    pub fn figure(&self) -> Result<Figure> {
        if self.signals.is_empty() {
            return Err(PlotError::Empty {
                what: "identification fit (no signal)".into(),
            });
        }
        let mut axes = Vec::new();
        let n = self.signals.len();
        for (p, (ylabel, y, models)) in self.signals.iter().enumerate() {
            let mut ax = Axes::new();
            ax.ylabel(ylabel.clone());
            if p + 1 == n {
                ax.xlabel(self.xlabel.clone());
            }
            // The models first, wide and coloured; the measured record on top of them, thin
            // and dark, so that it stays visible where a good model lies right on it.
            for (k, (name, yh)) in models.iter().enumerate() {
                if yh.len() != y.len() {
                    return Err(PlotError::LengthMismatch {
                        what: format!(
                            "identification fit, panel {p}: model \"{name}\" vs measured"
                        ),
                        left: yh.len(),
                        right: y.len(),
                    });
                }
                let label = match fit_percent(y, yh) {
                    Some(f) => format!("{name} (fit {f:.1} %)"),
                    None => name.clone(),
                };
                ax.plot(&self.t, yh)
                    .label(label)
                    .color(palette(k).with_alpha(0.7))
                    .dash(dash_cycle(k))
                    .width(3.2);
            }
            ax.plot(&self.t, y)
                .label(self.measured_name.clone())
                .color(Color::rgb(20, 20, 20))
                .width(1.0);
            axes.push(ax);
        }
        let mut fig = Figure::column(axes);
        if let Some(t) = &self.title {
            fig = fig.title(t.clone());
        }
        Ok(fig)
    }
}

/// NRMSE fit in percent, `None` if undefined (fewer than two finite pairs or constant data).
pub fn fit_percent(y: &[f64], yh: &[f64]) -> Option<f64> {
    let pairs: Vec<(f64, f64)> = y
        .iter()
        .zip(yh)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (*a, *b))
        .collect();
    if pairs.len() < 2 {
        return None;
    }
    let mean = pairs.iter().map(|p| p.0).sum::<f64>() / pairs.len() as f64;
    let num = pairs
        .iter()
        .map(|p| (p.0 - p.1).powi(2))
        .sum::<f64>()
        .sqrt();
    let den = pairs
        .iter()
        .map(|p| (p.0 - mean).powi(2))
        .sum::<f64>()
        .sqrt();
    if den == 0.0 {
        return None;
    }
    Some(100.0 * (1.0 - num / den))
}

/// A region-of-attraction map: which initial conditions on an `nx × ny` grid were stabilised
/// (`cells[j * nx + i]`, column `i` from `x_range.0`, row `j` from `y_range.0` at the bottom).
/// Returns the panel so that boundaries or trajectories can be drawn over it.
///
/// ```
/// use pendulab_plot::{region_of_attraction, Figure};
/// let n = 20;
/// let cells: Vec<bool> = (0..n * n)
///     .map(|k| { let (i, j) = (k % n, k / n); (i as f64 - 9.5).hypot(j as f64 - 9.5) < 7.0 })
///     .collect();
/// let ax = region_of_attraction((-1.0, 1.0), (-4.0, 4.0), n, n, &cells, "θ(0) [rad]", "θ'(0) [rad/s]");
/// assert!(Figure::new(ax).to_svg().unwrap().contains("stabilised"));
/// ```
pub fn region_of_attraction(
    x_range: (f64, f64),
    y_range: (f64, f64),
    nx: usize,
    ny: usize,
    cells: &[bool],
    xlabel: &str,
    ylabel: &str,
) -> Axes {
    let mut ax = Axes::new();
    ax.xlabel(xlabel).ylabel(ylabel).grid(false);
    ax.bool_map(
        x_range,
        y_range,
        nx,
        ny,
        cells,
        ["stabilised", "not stabilised"],
    );
    ax
}

#[cfg(test)]
mod tests {
    use super::frequency::unwrap_degrees;
    use super::*;
    use pendulab_lti::Complex64;

    #[test]
    fn chattering_is_told_from_smooth_signals() {
        // A ±0.1 switching every sample: total variation 0.2·999 over a range of 0.2.
        let sw: Vec<f64> = (0..1000)
            .map(|k| if k % 2 == 0 { 0.1 } else { -0.1 })
            .collect();
        assert!(chatters(&sw));
        // Five cycles of a sine: total variation 4·5 = 20 over a range of 2 (ratio 10).
        let sine: Vec<f64> = (0..1000)
            .map(|k| (2.0 * std::f64::consts::PI * 5.0 * k as f64 / 1000.0).sin())
            .collect();
        assert!(!chatters(&sine));
        // 25 cycles: ratio 50, above the threshold of 40; 15 cycles: 30, below.
        let osc = |n: f64| -> Vec<f64> {
            (0..=4000)
                .map(|k| (2.0 * std::f64::consts::PI * n * k as f64 / 4000.0).sin())
                .collect()
        };
        assert!(chatters(&osc(25.0)));
        assert!(!chatters(&osc(15.0)));
        // Constant and empty signals have no range: never chattering; NaN gaps are skipped.
        assert!(!chatters(&[1.0; 10]));
        assert!(!chatters(&[]));
        let mut gappy = sw.clone();
        gappy[500] = f64::NAN;
        assert!(chatters(&gappy));
    }

    #[test]
    fn unwrapping_removes_branch_jumps() {
        // arg of 1/(s+1)^3 passes −180° at ω = √3: atan2 jumps from −180 to +180 there.
        let w: Vec<f64> = (0..200)
            .map(|k| 10f64.powf(-1.0 + 3.0 * k as f64 / 199.0))
            .collect();
        let mut p: Vec<f64> = w
            .iter()
            .map(|&w| {
                let s = Complex64::new(1.0, w);
                (1.0 / (s * s * s)).arg().to_degrees()
            })
            .collect();
        unwrap_degrees(&mut p);
        for (k, &w) in w.iter().enumerate() {
            // Closed form: phase = −3 atan(ω).
            assert!((p[k] - (-3.0 * w.atan().to_degrees())).abs() < 1e-9);
        }
    }

    #[test]
    fn fit_of_perfect_and_mean_models() {
        let y = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(fit_percent(&y, &y), Some(100.0));
        // Predicting the mean leaves ‖y − ŷ‖ = ‖y − ȳ‖: fit 0 %.
        assert_eq!(fit_percent(&y, &[2.5; 4]), Some(0.0));
        assert_eq!(fit_percent(&[1.0; 3], &[1.0; 3]), None);
    }
}
