//! One panel of a figure: a Cartesian plot with any number of series.
//!
//! ```
//! use pendulab_plot::{Axes, Color, Figure};
//! let t: Vec<f64> = (0..=1000).map(|k| k as f64 * 0.01).collect();
//! let y: Vec<f64> = t.iter().map(|t| (-0.5 * t).exp() * t.cos()).collect();
//! let mut ax = Axes::new();
//! ax.xlabel("time [s]").ylabel("position [m]");
//! ax.plot(&t, &y).label("y(t)");
//! ax.hline(0.0).color(Color::GREY).dashed();
//! let svg = Figure::new(ax).to_svg().unwrap();
//! assert!(svg.contains("time [s]"));
//! ```

use crate::canvas::{Canvas, HAlign, TextStyle, VAlign};
use crate::color::{Color, ColorMap, palette};
use crate::error::{PlotError, Result};
use crate::font;
use crate::geometry::{Rect, clip_polygon, clip_polyline, decimate};
use crate::style::{Dash, LineStyle, Marker};
use crate::ticks::{Ticks, linear_ticks, log_ticks, nice_limits};
use pendulab_lti::Complex64;

pub(crate) const TICK_FONT: f64 = 11.5;
pub(crate) const LABEL_FONT: f64 = 12.5;
pub(crate) const TITLE_FONT: f64 = 13.0;
pub(crate) const LEGEND_FONT: f64 = 11.0;
const TICK_LEN: f64 = 5.0;
const PAD: f64 = 6.0;
const FRAME: Color = Color::rgb(38, 38, 38);
const GRID: Color = Color::rgb(222, 222, 222);
const GRID_MINOR: Color = Color::rgb(240, 240, 240);

/// Linear or logarithmic (base 10) axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// Linear axis.
    #[default]
    Linear,
    /// Base-10 logarithmic axis; samples ≤ 0 are not drawn.
    Log,
}

/// Where the legend goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LegendPos {
    /// The inside corner that covers the fewest drawn points.
    #[default]
    Best,
    /// Inside, upper right.
    UpperRight,
    /// Inside, upper left.
    UpperLeft,
    /// Inside, lower left.
    LowerLeft,
    /// Inside, lower right.
    LowerRight,
    /// No legend, even if series have labels.
    Hidden,
}

/// One convex constraint of a pole-placement region in the complex plane (the D-stability
/// regions of the LMI examples). A region is the intersection of its bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RegionBound {
    /// Decay rate at least α: Re s ≤ −α (α may be 0 for the open left half-plane).
    DecayRate(f64),
    /// Speed limit β: Re s ≥ −β (β > 0).
    SpeedLimit(f64),
    /// Conic sector of half-angle θ ∈ (0, π/2] about the negative real axis:
    /// |Im s| ≤ tan θ · (−Re s) (damping ratio at least cos θ).
    Sector(f64),
    /// Disk |s − c| ≤ r with a real centre c and radius r > 0; `Disk { center: 0, radius: 1 }` is the
    /// stability region of discrete-time systems.
    Disk {
        /// Centre on the real axis.
        center: f64,
        /// Radius (> 0).
        radius: f64,
    },
}

impl RegionBound {
    /// The unit disk |z| ≤ 1.
    pub const UNIT_DISK: RegionBound = RegionBound::Disk {
        center: 0.0,
        radius: 1.0,
    };
}

#[derive(Debug, Clone)]
pub(crate) enum CellKind {
    Boolean {
        labels: [String; 2],
        colors: [Color; 2],
    },
    Scalar {
        map: ColorMap,
        range: Option<(f64, f64)>,
        label: String,
    },
}

#[derive(Debug, Clone)]
pub(crate) struct Cells {
    x_range: (f64, f64),
    y_range: (f64, f64),
    nx: usize,
    ny: usize,
    values: Vec<f64>,
    kind: CellKind,
}

#[derive(Debug, Clone)]
pub(crate) enum Kind {
    Line {
        x: Vec<f64>,
        y: Vec<f64>,
    },
    Steps {
        x: Vec<f64>,
        y: Vec<f64>,
    },
    Scatter {
        x: Vec<f64>,
        y: Vec<f64>,
    },
    Bars {
        x: Vec<f64>,
        h: Vec<f64>,
    },
    HLine(f64),
    VLine(f64),
    Fill {
        x: Vec<f64>,
        y: Vec<f64>,
    },
    Band {
        x: Vec<f64>,
        lo: Vec<f64>,
        hi: Vec<f64>,
    },
    Region(Vec<RegionBound>),
    Cells(Cells),
    Text {
        x: f64,
        y: f64,
        text: String,
    },
}

/// A series of an [`Axes`], returned by the adding methods so that its look can be set in a chain:
/// `ax.plot(&t, &y).label("θ").color(Color::RED).dashed()`.
#[derive(Debug, Clone)]
pub struct Series {
    pub(crate) kind: Kind,
    label: Option<String>,
    color: Option<Color>,
    width: f64,
    dash: Dash,
    marker: Option<Marker>,
    marker_size: f64,
    fill: Option<Color>,
}

impl Series {
    fn new(kind: Kind) -> Self {
        Self {
            kind,
            label: None,
            color: None,
            width: 1.6,
            dash: Dash::Solid,
            marker: None,
            marker_size: 6.0,
            fill: None,
        }
    }
    /// Legend text (series without a label are not listed).
    pub fn label(&mut self, label: impl Into<String>) -> &mut Self {
        self.label = Some(label.into());
        self
    }
    /// Line and marker colour (default: the next palette colour of the axes).
    pub fn color(&mut self, color: Color) -> &mut Self {
        self.color = Some(color);
        self
    }
    /// Line width in SVG pixels (default 1.6).
    pub fn width(&mut self, width: f64) -> &mut Self {
        self.width = width;
        self
    }
    /// Dash pattern.
    pub fn dash(&mut self, dash: Dash) -> &mut Self {
        self.dash = dash;
        self
    }
    /// Dashed line (MATLAB `'--'`).
    pub fn dashed(&mut self) -> &mut Self {
        self.dash(Dash::Dashed)
    }
    /// Dotted line (MATLAB `':'`).
    pub fn dotted(&mut self) -> &mut Self {
        self.dash(Dash::Dotted)
    }
    /// Dash-dot line (MATLAB `'-.'`).
    pub fn dash_dot(&mut self) -> &mut Self {
        self.dash(Dash::DashDot)
    }
    /// Draws `marker` at the samples (on lines with more than 60 samples, at about 30 evenly
    /// spaced samples).
    pub fn marker(&mut self, marker: Marker) -> &mut Self {
        self.marker = Some(marker);
        self
    }
    /// Marker size in SVG pixels (default 6).
    pub fn marker_size(&mut self, size: f64) -> &mut Self {
        self.marker_size = size;
        self
    }
    /// Fill colour of areas, bars and regions (default: the line colour, translucent).
    pub fn fill(&mut self, color: Color) -> &mut Self {
        self.fill = Some(color);
        self
    }
}

/// A Cartesian plot panel: series, labels, scales, limits, grid and legend.
///
/// Adding methods copy the data and return the new [`Series`] for styling. Nothing is checked
/// until the figure is rendered; then every problem is reported as a [`PlotError`] naming the
/// panel and series.
///
/// **Missing data.** NaN and infinite samples are gaps: a line is broken there (the MATLAB
/// convention, so NaN can be inserted on purpose to separate pieces) and markers are left out. On
/// a logarithmic axis samples ≤ 0 are gaps too. A series with no drawable sample at all is an
/// error ([`PlotError::NothingToDraw`]).
#[derive(Debug, Clone, Default)]
pub struct Axes {
    title: Option<String>,
    xlabel: Option<String>,
    ylabel: Option<String>,
    xscale: Scale,
    yscale: Scale,
    xlim: Option<(f64, f64)>,
    ylim: Option<(f64, f64)>,
    equal_aspect: bool,
    no_grid: bool,
    legend: LegendPos,
    x_step: Option<f64>,
    y_step: Option<f64>,
    pub(crate) series: Vec<Series>,
}

/// Limits and their mapping to a plot rectangle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Map {
    pub rect: Rect,
    pub x: (f64, f64),
    pub y: (f64, f64),
    pub xlog: bool,
    pub ylog: bool,
}

impl Map {
    fn tx(v: f64, log: bool) -> f64 {
        if log {
            if v > 0.0 { v.log10() } else { f64::NAN }
        } else {
            v
        }
    }
    /// Pixel x of data x.
    pub fn px(&self, x: f64) -> f64 {
        let (a, b) = (Self::tx(self.x.0, self.xlog), Self::tx(self.x.1, self.xlog));
        self.rect.x0 + (Self::tx(x, self.xlog) - a) / (b - a) * self.rect.w()
    }
    /// Pixel y of data y.
    pub fn py(&self, y: f64) -> f64 {
        let (a, b) = (Self::tx(self.y.0, self.ylog), Self::tx(self.y.1, self.ylog));
        self.rect.y1 - (Self::tx(y, self.ylog) - a) / (b - a) * self.rect.h()
    }
    /// Pixel of a data point (NaN components where it cannot be drawn).
    pub fn p(&self, x: f64, y: f64) -> (f64, f64) {
        (self.px(x), self.py(y))
    }
}

/// Space around the plot rectangle of a panel.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Margins {
    pub left: f64,
    pub right: f64,
    pub top: f64,
    pub bottom: f64,
}

fn finite_pairs<'a>(
    x: &'a [f64],
    y: &'a [f64],
    xlog: bool,
    ylog: bool,
) -> impl Iterator<Item = (f64, f64)> + 'a {
    x.iter()
        .zip(y)
        .map(|(a, b)| (*a, *b))
        .filter(move |(a, b)| {
            a.is_finite() && b.is_finite() && (!xlog || *a > 0.0) && (!ylog || *b > 0.0)
        })
}

fn widen(b: &mut Option<(f64, f64)>, v: f64) {
    if v.is_finite() {
        *b = Some(match *b {
            None => (v, v),
            Some((lo, hi)) => (lo.min(v), hi.max(v)),
        });
    }
}

impl Axes {
    /// An empty panel with a grid and an automatic legend.
    pub fn new() -> Self {
        Self::default()
    }

    // ----- decoration -------------------------------------------------------------------------

    /// Panel title.
    pub fn title(&mut self, title: impl Into<String>) -> &mut Self {
        self.title = Some(title.into());
        self
    }
    /// Horizontal axis label, with its unit, e.g. `"time [s]"`.
    pub fn xlabel(&mut self, label: impl Into<String>) -> &mut Self {
        self.xlabel = Some(label.into());
        self
    }
    /// Vertical axis label, with its unit, e.g. `"θ [deg]"`.
    pub fn ylabel(&mut self, label: impl Into<String>) -> &mut Self {
        self.ylabel = Some(label.into());
        self
    }
    /// Horizontal scale.
    pub fn xscale(&mut self, scale: Scale) -> &mut Self {
        self.xscale = scale;
        self
    }
    /// Vertical scale.
    pub fn yscale(&mut self, scale: Scale) -> &mut Self {
        self.yscale = scale;
        self
    }
    /// Fixed horizontal limits (default: tight around lines, padded around points).
    pub fn xlim(&mut self, lo: f64, hi: f64) -> &mut Self {
        self.xlim = Some((lo, hi));
        self
    }
    /// Fixed vertical limits (default: the data padded and widened to tick multiples).
    pub fn ylim(&mut self, lo: f64, hi: f64) -> &mut Self {
        self.ylim = Some((lo, hi));
        self
    }
    /// Same data units per pixel on both axes (pole maps, phase portraits); the limits are
    /// widened as needed.
    pub fn equal_aspect(&mut self) -> &mut Self {
        self.equal_aspect = true;
        self
    }
    /// Grid lines at the major ticks (on by default).
    pub fn grid(&mut self, on: bool) -> &mut Self {
        self.no_grid = !on;
        self
    }
    /// Fixed spacing of the horizontal major ticks (linear axis), e.g. 0.5 s.
    pub fn x_tick_step(&mut self, step: f64) -> &mut Self {
        self.x_step = Some(step);
        self
    }
    /// Fixed spacing of the vertical major ticks (linear axis), e.g. 90° for phase plots;
    /// automatic limits are widened to multiples of it.
    pub fn y_tick_step(&mut self, step: f64) -> &mut Self {
        self.y_step = Some(step);
        self
    }
    /// Legend placement.
    pub fn legend(&mut self, pos: LegendPos) -> &mut Self {
        self.legend = pos;
        self
    }

    // ----- series -----------------------------------------------------------------------------

    fn push(&mut self, kind: Kind) -> &mut Series {
        self.series.push(Series::new(kind));
        let n = self.series.len();
        &mut self.series[n - 1]
    }

    /// A line through `(x[k], y[k])` (MATLAB `plot`).
    pub fn plot(&mut self, x: &[f64], y: &[f64]) -> &mut Series {
        self.push(Kind::Line {
            x: x.to_vec(),
            y: y.to_vec(),
        })
    }
    /// A staircase holding `y[k]` from `x[k]` to `x[k+1]` (MATLAB `stairs`): discrete-time and
    /// zero-order-hold signals.
    pub fn step(&mut self, x: &[f64], y: &[f64]) -> &mut Series {
        self.push(Kind::Steps {
            x: x.to_vec(),
            y: y.to_vec(),
        })
    }
    /// Markers only (default marker: filled dot).
    pub fn scatter(&mut self, x: &[f64], y: &[f64]) -> &mut Series {
        let s = self.push(Kind::Scatter {
            x: x.to_vec(),
            y: y.to_vec(),
        });
        s.marker = Some(Marker::Dot);
        s.marker_size = 5.0;
        s
    }
    /// Vertical bars of height `h[k]` centred at `x[k]`, 0.8 of the smallest spacing wide.
    pub fn bar(&mut self, x: &[f64], h: &[f64]) -> &mut Series {
        self.push(Kind::Bars {
            x: x.to_vec(),
            h: h.to_vec(),
        })
    }
    /// A horizontal reference line across the panel at `y` (thin, dark grey by default).
    pub fn hline(&mut self, y: f64) -> &mut Series {
        let s = self.push(Kind::HLine(y));
        s.width = 1.2;
        s
    }
    /// A vertical reference line across the panel at `x`.
    pub fn vline(&mut self, x: f64) -> &mut Series {
        let s = self.push(Kind::VLine(x));
        s.width = 1.2;
        s
    }
    /// A filled polygon with vertices `(x[k], y[k])` (translucent by default, no outline).
    pub fn fill(&mut self, x: &[f64], y: &[f64]) -> &mut Series {
        self.push(Kind::Fill {
            x: x.to_vec(),
            y: y.to_vec(),
        })
    }
    /// The area between `lo[k]` and `hi[k]` over `x[k]` (envelopes, bounds).
    pub fn fill_between(&mut self, x: &[f64], lo: &[f64], hi: &[f64]) -> &mut Series {
        self.push(Kind::Band {
            x: x.to_vec(),
            lo: lo.to_vec(),
            hi: hi.to_vec(),
        })
    }
    /// Text at a data point, its left end at `(x, y)`.
    pub fn text(&mut self, x: f64, y: f64, text: impl Into<String>) -> &mut Series {
        self.push(Kind::Text {
            x,
            y,
            text: text.into(),
        })
    }
    /// Poles as `×` markers at (Re, Im) (MATLAB `pzmap`).
    pub fn poles(&mut self, poles: &[Complex64]) -> &mut Series {
        let (x, y): (Vec<f64>, Vec<f64>) = poles.iter().map(|p| (p.re, p.im)).unzip();
        let s = self.scatter(&x, &y);
        s.marker = Some(Marker::Cross);
        s.marker_size = 8.0;
        s.width = 1.8;
        s
    }
    /// Zeros as `○` markers at (Re, Im).
    pub fn zeros(&mut self, zeros: &[Complex64]) -> &mut Series {
        let (x, y): (Vec<f64>, Vec<f64>) = zeros.iter().map(|p| (p.re, p.im)).unzip();
        let s = self.scatter(&x, &y);
        s.marker = Some(Marker::Circle);
        s.marker_size = 8.0;
        s.width = 1.5;
        s
    }
    /// A design region of the complex plane: the intersection of `bounds`, shaded, with each
    /// boundary drawn dashed. Give it a label to list it in the legend.
    pub fn region(&mut self, bounds: &[RegionBound]) -> &mut Series {
        let s = self.push(Kind::Region(bounds.to_vec()));
        s.color = Some(Color::DARK_GREY);
        s.fill = Some(Color::rgba(120, 170, 230, 56));
        s.width = 1.1;
        s.dash = Dash::Dashed;
        s
    }
    /// A map of yes/no cells over a rectangle, e.g. a region of attraction: `cells[j * nx + i]`
    /// is the cell of column `i` (from `x_range.0`) and row `j` (from `y_range.0`, bottom).
    /// `labels` name the `true` and the `false` cells in the legend.
    pub fn bool_map(
        &mut self,
        x_range: (f64, f64),
        y_range: (f64, f64),
        nx: usize,
        ny: usize,
        cells: &[bool],
        labels: [&str; 2],
    ) -> &mut Series {
        self.push(Kind::Cells(Cells {
            x_range,
            y_range,
            nx,
            ny,
            values: cells.iter().map(|&b| if b { 1.0 } else { 0.0 }).collect(),
            kind: CellKind::Boolean {
                labels: [labels[0].to_string(), labels[1].to_string()],
                colors: [Color::rgb(120, 180, 235), Color::rgb(252, 232, 226)],
            },
        }))
    }
    /// A heat map of values over a rectangle (layout as [`Axes::bool_map`]) with a colour bar
    /// labelled `label`; NaN cells are left light grey. The colour range is the finite data
    /// range unless set with [`Axes::color_range`].
    pub fn heat_map(
        &mut self,
        x_range: (f64, f64),
        y_range: (f64, f64),
        nx: usize,
        ny: usize,
        values: &[f64],
        label: &str,
    ) -> &mut Series {
        self.push(Kind::Cells(Cells {
            x_range,
            y_range,
            nx,
            ny,
            values: values.to_vec(),
            kind: CellKind::Scalar {
                map: ColorMap::Viridis,
                range: None,
                label: label.to_string(),
            },
        }))
    }
    /// Sets the colour map and the value range of every heat map of this panel.
    pub fn color_range(&mut self, map: ColorMap, range: Option<(f64, f64)>) -> &mut Self {
        for s in &mut self.series {
            if let Kind::Cells(c) = &mut s.kind
                && let CellKind::Scalar {
                    map: m, range: r, ..
                } = &mut c.kind
            {
                *m = map;
                *r = range;
            }
        }
        self
    }

    // ----- checking ---------------------------------------------------------------------------

    fn series_name(panel: usize, k: usize, s: &Series) -> String {
        match &s.label {
            Some(l) => format!("panel {panel}, series \"{l}\""),
            None => format!("panel {panel}, series #{k}"),
        }
    }

    pub(crate) fn check(&self, panel: usize) -> Result<()> {
        let (xlog, ylog) = (self.xscale == Scale::Log, self.yscale == Scale::Log);
        for (name, lim, log) in [("x", self.xlim, xlog), ("y", self.ylim, ylog)] {
            if let Some((a, b)) = lim
                && (!(a.is_finite() && b.is_finite()) || a >= b || (log && a <= 0.0))
            {
                return Err(PlotError::InvalidArgument(format!(
                    "panel {panel}: {name} limits [{a}, {b}] must be finite, increasing{}",
                    if log { " and positive (log scale)" } else { "" }
                )));
            }
        }
        for (name, st) in [("x", self.x_step), ("y", self.y_step)] {
            if let Some(v) = st
                && !(v.is_finite() && v > 0.0)
            {
                return Err(PlotError::InvalidArgument(format!(
                    "panel {panel}: {name} tick step {v} must be finite and positive"
                )));
            }
        }
        for (k, s) in self.series.iter().enumerate() {
            let what = || Self::series_name(panel, k, s);
            if !(s.width.is_finite()
                && s.width >= 0.0
                && s.marker_size.is_finite()
                && s.marker_size >= 0.0)
            {
                return Err(PlotError::InvalidArgument(format!(
                    "{}: line width {} and marker size {} must be finite and ≥ 0",
                    what(),
                    s.width,
                    s.marker_size
                )));
            }
            let pair = |x: &[f64], y: &[f64], xn: &str, yn: &str| -> Result<()> {
                if x.len() != y.len() {
                    return Err(PlotError::LengthMismatch {
                        what: format!("{} ({xn} vs {yn})", what()),
                        left: x.len(),
                        right: y.len(),
                    });
                }
                if x.is_empty() {
                    return Err(PlotError::Empty { what: what() });
                }
                if finite_pairs(x, y, xlog, ylog).next().is_none() {
                    return Err(PlotError::NothingToDraw {
                        what: what(),
                        reason: if xlog || ylog {
                            "every sample is NaN, infinite or not positive on a log axis".into()
                        } else {
                            "every sample is NaN or infinite".into()
                        },
                    });
                }
                Ok(())
            };
            match &s.kind {
                Kind::Line { x, y }
                | Kind::Steps { x, y }
                | Kind::Scatter { x, y }
                | Kind::Fill { x, y } => pair(x, y, "x", "y")?,
                Kind::Bars { x, h } => pair(x, h, "x", "heights")?,
                Kind::Band { x, lo, hi } => {
                    pair(x, lo, "x", "lower")?;
                    pair(x, hi, "x", "upper")?;
                }
                Kind::HLine(v) | Kind::VLine(v) => {
                    if !v.is_finite()
                        || (*v <= 0.0 && matches!(s.kind, Kind::HLine(_)) && ylog)
                        || (*v <= 0.0 && matches!(s.kind, Kind::VLine(_)) && xlog)
                    {
                        return Err(PlotError::NonFinite {
                            what: format!("{} (reference line position)", what()),
                            index: 0,
                            value: *v,
                        });
                    }
                }
                Kind::Text { x, y, .. } => {
                    for (i, v) in [*x, *y].into_iter().enumerate() {
                        if !v.is_finite() {
                            return Err(PlotError::NonFinite {
                                what: format!("{} (text position)", what()),
                                index: i,
                                value: v,
                            });
                        }
                    }
                }
                Kind::Region(bounds) => {
                    if bounds.is_empty() {
                        return Err(PlotError::Empty { what: what() });
                    }
                    if xlog || ylog {
                        return Err(PlotError::InvalidArgument(format!(
                            "{}: regions of the complex plane need linear axes",
                            what()
                        )));
                    }
                    for b in bounds {
                        let ok = match *b {
                            RegionBound::DecayRate(a) => a.is_finite(),
                            RegionBound::SpeedLimit(b) => b.is_finite() && b > 0.0,
                            RegionBound::Sector(t) => {
                                t.is_finite() && t > 0.0 && t <= std::f64::consts::FRAC_PI_2
                            }
                            RegionBound::Disk { center, radius } => {
                                center.is_finite() && radius.is_finite() && radius > 0.0
                            }
                        };
                        if !ok {
                            return Err(PlotError::InvalidArgument(format!(
                                "{}: bad region bound {b:?} (α finite, β > 0, 0 < θ ≤ π/2, r > 0)",
                                what()
                            )));
                        }
                    }
                }
                Kind::Cells(c) => {
                    if c.nx == 0 || c.ny == 0 {
                        return Err(PlotError::Empty { what: what() });
                    }
                    if c.values.len() != c.nx * c.ny {
                        return Err(PlotError::LengthMismatch {
                            what: format!("{} (cells vs nx·ny = {}·{})", what(), c.nx, c.ny),
                            left: c.values.len(),
                            right: c.nx * c.ny,
                        });
                    }
                    for (a, b) in [c.x_range, c.y_range] {
                        if !(a.is_finite() && b.is_finite() && a < b) {
                            return Err(PlotError::InvalidArgument(format!(
                                "{}: cell range [{a}, {b}] must be finite and increasing",
                                what()
                            )));
                        }
                    }
                    if xlog || ylog {
                        return Err(PlotError::InvalidArgument(format!(
                            "{}: cell maps need linear axes",
                            what()
                        )));
                    }
                    if let CellKind::Scalar {
                        range: Some((a, b)),
                        ..
                    } = c.kind
                        && !(a.is_finite() && b.is_finite() && a < b)
                    {
                        return Err(PlotError::InvalidArgument(format!(
                            "{}: colour range [{a}, {b}] must be finite and increasing",
                            what()
                        )));
                    }
                }
            }
        }
        Ok(())
    }

    // ----- limits -----------------------------------------------------------------------------

    /// Data limits before layout: (x, y), each tight or padded.
    fn auto_limits(&self) -> ((f64, f64), (f64, f64), bool, bool, bool) {
        let (xlog, ylog) = (self.xscale == Scale::Log, self.yscale == Scale::Log);
        let mut bx: Option<(f64, f64)> = None;
        let mut by: Option<(f64, f64)> = None;
        let mut x_tight = false;
        let mut y_tight = false;
        let mut has_region = false;
        for s in &self.series {
            match &s.kind {
                Kind::Line { x, y } | Kind::Steps { x, y } => {
                    x_tight = true;
                    for (a, b) in finite_pairs(x, y, xlog, ylog) {
                        widen(&mut bx, a);
                        widen(&mut by, b);
                    }
                }
                Kind::Scatter { x, y } | Kind::Fill { x, y } => {
                    for (a, b) in finite_pairs(x, y, xlog, ylog) {
                        widen(&mut bx, a);
                        widen(&mut by, b);
                    }
                }
                Kind::Bars { x, h } => {
                    let dx = min_spacing(x) * 0.5;
                    for (a, b) in finite_pairs(x, h, xlog, ylog) {
                        widen(&mut bx, a - dx);
                        widen(&mut bx, a + dx);
                        widen(&mut by, b);
                    }
                    if !ylog {
                        widen(&mut by, 0.0);
                    }
                }
                Kind::Band { x, lo, hi } => {
                    x_tight = true;
                    for (a, b) in
                        finite_pairs(x, lo, xlog, ylog).chain(finite_pairs(x, hi, xlog, ylog))
                    {
                        widen(&mut bx, a);
                        widen(&mut by, b);
                    }
                }
                Kind::HLine(v) => widen(&mut by, *v),
                Kind::VLine(v) => widen(&mut bx, *v),
                Kind::Text { x, y, .. } => {
                    widen(&mut bx, *x);
                    widen(&mut by, *y);
                }
                Kind::Region(bounds) => {
                    has_region = true;
                    for b in bounds {
                        match *b {
                            RegionBound::DecayRate(a) => {
                                widen(&mut bx, -a);
                                widen(&mut bx, 0.0);
                            }
                            RegionBound::SpeedLimit(b) => {
                                widen(&mut bx, -b);
                                widen(&mut by, -0.25 * b);
                                widen(&mut by, 0.25 * b);
                            }
                            RegionBound::Sector(_) => widen(&mut bx, 0.0),
                            RegionBound::Disk { center, radius } => {
                                widen(&mut bx, center - radius);
                                widen(&mut bx, center + radius);
                                widen(&mut by, -radius);
                                widen(&mut by, radius);
                            }
                        }
                    }
                }
                Kind::Cells(c) => {
                    x_tight = true;
                    y_tight = true;
                    widen(&mut bx, c.x_range.0);
                    widen(&mut bx, c.x_range.1);
                    widen(&mut by, c.y_range.0);
                    widen(&mut by, c.y_range.1);
                }
            }
        }
        if has_region {
            x_tight = false;
        }
        // Bars standing on zero keep zero as the frame's edge.
        let bars_floor = self.series.iter().any(|s| matches!(&s.kind, Kind::Bars { h, .. } if h.iter().all(|v| !v.is_finite() || *v >= 0.0)));
        if bars_floor && let Some((lo, _)) = by.as_mut() {
            *lo = lo.max(0.0);
        }
        let bx = bx.unwrap_or((0.0, 1.0));
        let by = by.unwrap_or((0.0, 1.0));
        (bx, by, x_tight, y_tight, bars_floor)
    }

    fn finish_limits(
        raw: (f64, f64),
        tight: bool,
        log: bool,
        pad: f64,
        target: usize,
    ) -> (f64, f64) {
        let (mut lo, mut hi) = raw;
        if log {
            if hi <= lo * 1.0001 {
                lo /= 10.0;
                hi *= 10.0;
            }
            if tight {
                return (lo, hi);
            }
            return (
                10f64.powf((lo.log10() + 1e-9).floor()),
                10f64.powf((hi.log10() - 1e-9).ceil()),
            );
        }
        if hi - lo <= 1e-12 * lo.abs().max(hi.abs()).max(1e-300) {
            let d = if lo == 0.0 { 1.0 } else { 0.5 * lo.abs() };
            lo -= d;
            hi += d;
            return nice_limits(lo, hi, target);
        }
        if tight {
            return (lo, hi);
        }
        // Pad a little, then widen to half-tick multiples: the data never touches the frame
        // and little space is wasted.
        let d = (hi - lo) * pad;
        let step = crate::ticks::nice_step((hi - lo + 2.0 * d) / target.max(1) as f64);
        crate::ticks::snap_limits(lo - d, hi + d, step / 2.0)
    }

    fn limits(&self, rect: &Rect) -> ((f64, f64), (f64, f64)) {
        let (xlog, ylog) = (self.xscale == Scale::Log, self.yscale == Scale::Log);
        let (bx, by, xt, yt, floor) = self.auto_limits();
        let tx = x_target(rect.w());
        let ty = y_target(rect.h());
        let pad = if self.equal_aspect { 0.08 } else { 0.025 };
        let mut x = self
            .xlim
            .unwrap_or_else(|| Self::finish_limits(bx, xt, xlog, pad, tx));
        let mut y = self
            .ylim
            .unwrap_or_else(|| Self::finish_limits(by, yt, ylog, pad, ty));
        if floor && self.ylim.is_none() && !ylog && by.0 >= 0.0 {
            y.0 = y.0.max(0.0);
        }
        if let (Some(st), None, Scale::Linear) = (self.y_step, self.ylim, self.yscale) {
            y = crate::ticks::snap_limits(by.0, by.1, st);
            if y.1 - y.0 < st {
                y = (y.0 - st / 2.0, y.1 + st / 2.0);
            }
        }
        if self.equal_aspect && !xlog && !ylog && rect.w() > 0.0 && rect.h() > 0.0 {
            let ux = (x.1 - x.0) / rect.w();
            let uy = (y.1 - y.0) / rect.h();
            if ux > uy && self.ylim.is_none() {
                let c = 0.5 * (y.0 + y.1);
                let h = 0.5 * ux * rect.h();
                y = (c - h, c + h);
            } else if uy > ux && self.xlim.is_none() {
                let c = 0.5 * (x.0 + x.1);
                let h = 0.5 * uy * rect.w();
                x = (c - h, c + h);
            }
        }
        (x, y)
    }

    fn ticks(&self, x: (f64, f64), y: (f64, f64), rect: &Rect) -> (Ticks, Ticks) {
        let xt = match (self.xscale, self.x_step) {
            (Scale::Linear, Some(st)) => crate::ticks::stepped_ticks(x.0, x.1, st),
            (Scale::Linear, None) => linear_ticks(x.0, x.1, x_target(rect.w())),
            (Scale::Log, _) => log_ticks(x.0, x.1, (rect.w() / 45.0) as usize),
        };
        let yt = match (self.yscale, self.y_step) {
            (Scale::Linear, Some(st)) => crate::ticks::stepped_ticks(y.0, y.1, st),
            (Scale::Linear, None) => linear_ticks(y.0, y.1, y_target(rect.h())),
            (Scale::Log, _) => log_ticks(y.0, y.1, (rect.h() / 30.0) as usize),
        };
        (xt, yt)
    }

    fn colorbar(&self) -> Option<&Cells> {
        self.series.iter().find_map(|s| match &s.kind {
            Kind::Cells(c) if matches!(c.kind, CellKind::Scalar { .. }) => Some(c),
            _ => None,
        })
    }

    /// Space needed around a plot rectangle when the panel occupies `outer`.
    pub(crate) fn margins(&self, outer: &Rect) -> Result<Margins> {
        let f = font::font()?;
        let mut m = Margins {
            left: 60.0,
            right: 12.0,
            top: 12.0,
            bottom: 40.0,
        };
        for _ in 0..2 {
            let rect = Rect {
                x0: outer.x0 + m.left,
                y0: outer.y0 + m.top,
                x1: outer.x1 - m.right,
                y1: outer.y1 - m.bottom,
            };
            if rect.w() <= 10.0 || rect.h() <= 10.0 {
                return Err(PlotError::InvalidArgument(format!(
                    "figure too small: a panel of {:.0} x {:.0} px leaves no room for the plot",
                    outer.w(),
                    outer.h()
                )));
            }
            let (x, y) = self.limits(&rect);
            let (xt, yt) = self.ticks(x, y, &rect);
            let ylab_w = yt
                .major
                .iter()
                .map(|(_, s)| font::text_width(f, s, TICK_FONT))
                .fold(0.0, f64::max);
            m.left = PAD + ylab_w + 5.0;
            if self.ylabel.is_some() {
                m.left += LABEL_FONT * 1.35;
            }
            m.left = m.left.max(30.0);
            m.bottom = PAD + 4.0 + font::cap_height(TICK_FONT) + 4.0;
            if self.xlabel.is_some() {
                m.bottom += LABEL_FONT * 1.45;
            }
            m.top = 10.0;
            if self.title.is_some() {
                m.top += TITLE_FONT * 1.5;
            }
            if yt.multiplier.is_some() && self.title.is_none() {
                m.top += TICK_FONT;
            }
            // Room for the last x tick label to hang over the frame.
            let last_x = xt
                .major
                .last()
                .map(|(_, s)| font::text_width(f, s, TICK_FONT))
                .unwrap_or(0.0);
            m.right = (last_x / 2.0 + 4.0).max(12.0);
            if xt.multiplier.is_some() {
                m.right = m.right.max(font::text_width(f, "×10⁻⁰⁰", TICK_FONT) + 4.0);
            }
            if let Some(c) = self.colorbar() {
                let (lo, hi) = cell_range(c);
                let ct = linear_ticks(lo, hi, 5);
                let w = ct
                    .major
                    .iter()
                    .map(|(_, s)| font::text_width(f, s, TICK_FONT))
                    .fold(0.0, f64::max);
                m.right = 14.0 + 14.0 + 5.0 + w + 6.0 + LABEL_FONT * 1.4;
            }
        }
        Ok(m)
    }

    // ----- drawing ----------------------------------------------------------------------------

    /// Draws the panel with its plot area at `rect`; returns nothing but errors of fonts.
    pub(crate) fn draw(&self, c: &mut dyn Canvas, rect: Rect) -> Result<()> {
        let (xlog, ylog) = (self.xscale == Scale::Log, self.yscale == Scale::Log);
        let (x, y) = self.limits(&rect);
        let (xt, yt) = self.ticks(x, y, &rect);
        let map = Map {
            rect,
            x,
            y,
            xlog,
            ylog,
        };
        let mut occupied: Vec<(f64, f64)> = Vec::new();
        let mut legend: Vec<(String, LegendGlyph)> = Vec::new();

        // Colours of unstyled series, in order.
        let mut next = 0;
        let colors: Vec<Color> = self
            .series
            .iter()
            .map(|s| match (s.color, &s.kind) {
                (Some(c), _) => c,
                (None, Kind::HLine(_) | Kind::VLine(_)) => Color::DARK_GREY,
                (None, Kind::Text { .. }) => Color::BLACK,
                (None, _) => {
                    let c = palette(next);
                    next += 1;
                    c
                }
            })
            .collect();

        // 1. cell maps, under everything.
        for (s, _) in self.series.iter().zip(&colors) {
            if let Kind::Cells(cells) = &s.kind {
                draw_cells(c, &map, cells, &mut legend);
            }
        }
        // 2. grid.
        if !self.no_grid {
            let minor_grid = LineStyle::new(GRID_MINOR, 0.6);
            let grid = LineStyle::new(GRID, 0.7);
            if xlog {
                for &v in &xt.minor {
                    let p = map.px(v);
                    c.polyline(&[(p, rect.y0), (p, rect.y1)], &minor_grid);
                }
            }
            if ylog {
                for &v in &yt.minor {
                    let p = map.py(v);
                    c.polyline(&[(rect.x0, p), (rect.x1, p)], &minor_grid);
                }
            }
            for (v, _) in &xt.major {
                let p = map.px(*v);
                c.polyline(&[(p, rect.y0), (p, rect.y1)], &grid);
            }
            for (v, _) in &yt.major {
                let p = map.py(*v);
                c.polyline(&[(rect.x0, p), (rect.x1, p)], &grid);
            }
        }
        // 3. areas.
        for (s, col) in self.series.iter().zip(&colors) {
            let fill = s.fill.unwrap_or(col.with_alpha(0.25));
            match &s.kind {
                Kind::Fill { x, y } => {
                    let pts: Vec<(f64, f64)> = finite_pairs(x, y, xlog, ylog)
                        .map(|(a, b)| map.p(a, b))
                        .collect();
                    let poly = clip_polygon(&pts, &rect);
                    c.polygon(&poly, Some(fill), None);
                    if let Some(l) = &s.label {
                        legend.push((l.clone(), LegendGlyph::Patch(fill)));
                    }
                }
                Kind::Band { x, lo, hi } => {
                    let mut pts: Vec<(f64, f64)> = finite_pairs(x, lo, xlog, ylog)
                        .map(|(a, b)| map.p(a, b))
                        .collect();
                    let upper: Vec<(f64, f64)> = finite_pairs(x, hi, xlog, ylog)
                        .map(|(a, b)| map.p(a, b))
                        .collect();
                    pts.extend(upper.into_iter().rev());
                    let poly = clip_polygon(&pts, &rect);
                    c.polygon(&poly, Some(fill), None);
                    if let Some(l) = &s.label {
                        legend.push((l.clone(), LegendGlyph::Patch(fill)));
                    }
                }
                Kind::Bars { x, h } => {
                    let w = min_spacing(x) * 0.8;
                    let base = if ylog { y.0 } else { 0.0 };
                    let bar_fill = s.fill.unwrap_or(*col);
                    for (a, b) in finite_pairs(x, h, xlog, ylog) {
                        let p0 = map.p(a - w / 2.0, base);
                        let p1 = map.p(a + w / 2.0, b);
                        let poly = vec![(p0.0, p0.1), (p1.0, p0.1), (p1.0, p1.1), (p0.0, p1.1)];
                        let poly = clip_polygon(&poly, &rect);
                        c.polygon(&poly, Some(bar_fill), None);
                        occupied.extend(poly);
                    }
                    if let Some(l) = &s.label {
                        legend.push((l.clone(), LegendGlyph::Patch(bar_fill)));
                    }
                }
                Kind::Region(bounds) => {
                    let poly = region_polygon(bounds, &map);
                    c.polygon(&poly, Some(fill), None);
                    if let Some(l) = &s.label {
                        legend.push((l.clone(), LegendGlyph::Patch(fill)));
                    }
                }
                _ => {}
            }
        }
        // 4. region boundaries.
        for (s, col) in self.series.iter().zip(&colors) {
            if let Kind::Region(bounds) = &s.kind {
                let st = LineStyle {
                    color: *col,
                    width: s.width,
                    dash: s.dash,
                };
                for piece in region_boundaries(bounds, &map) {
                    for p in clip_polyline(&piece, &rect) {
                        c.polyline(&p, &st);
                    }
                }
            }
        }
        // 5. lines.
        for (s, col) in self.series.iter().zip(&colors) {
            let st = LineStyle {
                color: *col,
                width: s.width,
                dash: s.dash,
            };
            let mut drawn = true;
            match &s.kind {
                Kind::Line { x, y } => {
                    for piece in pieces(x, y, xlog, ylog, false) {
                        draw_piece(c, &map, &piece, &st, &mut occupied);
                    }
                }
                Kind::Steps { x, y } => {
                    for piece in pieces(x, y, xlog, ylog, true) {
                        draw_piece(c, &map, &piece, &st, &mut occupied);
                    }
                }
                Kind::HLine(v) => {
                    let p = map.py(*v);
                    if p >= rect.y0 - 0.5 && p <= rect.y1 + 0.5 {
                        let seg = [(rect.x0, p), (rect.x1, p)];
                        c.polyline(&seg, &st);
                        sample_segments(&seg, &mut occupied);
                    }
                }
                Kind::VLine(v) => {
                    let p = map.px(*v);
                    if p >= rect.x0 - 0.5 && p <= rect.x1 + 0.5 {
                        let seg = [(p, rect.y0), (p, rect.y1)];
                        c.polyline(&seg, &st);
                        sample_segments(&seg, &mut occupied);
                    }
                }
                _ => drawn = false,
            }
            if drawn && let Some(l) = &s.label {
                legend.push((l.clone(), LegendGlyph::Line(st, s.marker, s.marker_size)));
            }
        }
        // 6. markers.
        for (s, col) in self.series.iter().zip(&colors) {
            let Some(m) = s.marker else { continue };
            let (x, y, thin) = match &s.kind {
                Kind::Scatter { x, y } => (x, y, false),
                Kind::Line { x, y } | Kind::Steps { x, y } => (x, y, true),
                _ => continue,
            };
            let every = if thin && x.len() > 60 {
                x.len().div_ceil(30)
            } else {
                1
            };
            for (k, (a, b)) in x.iter().zip(y).enumerate() {
                if k % every != 0 || !(a.is_finite() && b.is_finite()) {
                    continue;
                }
                let p = map.p(*a, *b);
                if p.0.is_finite() && p.1.is_finite() && rect.contains(p) {
                    draw_marker(c, m, p, s.marker_size, *col, s.width.clamp(1.0, 2.0));
                    occupied.push(p);
                }
            }
            if matches!(s.kind, Kind::Scatter { .. })
                && let Some(l) = &s.label
            {
                legend.push((
                    l.clone(),
                    LegendGlyph::Marker(m, s.marker_size, *col, s.width.clamp(1.0, 2.0)),
                ));
            }
        }
        // 7. annotations.
        for (s, col) in self.series.iter().zip(&colors) {
            if let Kind::Text { x, y, text } = &s.kind {
                let p = map.p(*x, *y);
                if rect.contains(p) {
                    let mut ts = TextStyle::new(LEGEND_FONT, HAlign::Left, VAlign::Center);
                    ts.color = *col;
                    c.text(text, p, &ts);
                }
            }
        }
        // 8. frame and ticks.
        let frame = LineStyle::new(FRAME, 0.9);
        let tick = LineStyle::new(FRAME, 0.8);
        for (v, _) in &xt.major {
            let p = map.px(*v);
            c.polyline(&[(p, rect.y1), (p, rect.y1 - TICK_LEN)], &tick);
            c.polyline(&[(p, rect.y0), (p, rect.y0 + TICK_LEN)], &tick);
        }
        for (v, _) in &yt.major {
            let p = map.py(*v);
            c.polyline(&[(rect.x0, p), (rect.x0 + TICK_LEN, p)], &tick);
            c.polyline(&[(rect.x1, p), (rect.x1 - TICK_LEN, p)], &tick);
        }
        for &v in &xt.minor {
            let p = map.px(v);
            c.polyline(&[(p, rect.y1), (p, rect.y1 - TICK_LEN / 2.0)], &tick);
            c.polyline(&[(p, rect.y0), (p, rect.y0 + TICK_LEN / 2.0)], &tick);
        }
        for &v in &yt.minor {
            let p = map.py(v);
            c.polyline(&[(rect.x0, p), (rect.x0 + TICK_LEN / 2.0, p)], &tick);
            c.polyline(&[(rect.x1, p), (rect.x1 - TICK_LEN / 2.0, p)], &tick);
        }
        c.polygon(&rect.corners(), None, Some(&frame));
        // 9. tick labels.
        let tick_style_x = TextStyle::new(TICK_FONT, HAlign::Center, VAlign::Top);
        for (v, s) in &xt.major {
            c.text(s, (map.px(*v), rect.y1 + 6.0), &tick_style_x);
        }
        let tick_style_y = TextStyle::new(TICK_FONT, HAlign::Right, VAlign::Center);
        let mut ylab_w: f64 = 0.0;
        for (v, s) in &yt.major {
            c.text(s, (rect.x0 - 5.0, map.py(*v)), &tick_style_y);
            ylab_w = ylab_w.max(c.text_width(s, TICK_FONT));
        }
        if let Some(mul) = &xt.multiplier {
            c.text(
                mul,
                (rect.x1, rect.y1 + 6.0 + TICK_FONT * 1.3),
                &TextStyle::new(TICK_FONT, HAlign::Right, VAlign::Top),
            );
        }
        if let Some(mul) = &yt.multiplier {
            c.text(
                mul,
                (rect.x0, rect.y0 - 4.0),
                &TextStyle::new(TICK_FONT, HAlign::Left, VAlign::Bottom),
            );
        }
        // 10. labels and title.
        if let Some(l) = &self.xlabel {
            let yb = rect.y1 + 6.0 + font::cap_height(TICK_FONT) + 8.0;
            c.text(
                l,
                ((rect.x0 + rect.x1) / 2.0, yb),
                &TextStyle::new(LABEL_FONT, HAlign::Center, VAlign::Top),
            );
        }
        if let Some(l) = &self.ylabel {
            let mut ts = TextStyle::new(LABEL_FONT, HAlign::Center, VAlign::Bottom);
            ts.vertical = true;
            c.text(
                l,
                (rect.x0 - 5.0 - ylab_w - 7.0, (rect.y0 + rect.y1) / 2.0),
                &ts,
            );
        }
        if let Some(t) = &self.title {
            c.text(
                t,
                ((rect.x0 + rect.x1) / 2.0, rect.y0 - 8.0),
                &TextStyle::new(TITLE_FONT, HAlign::Center, VAlign::Baseline),
            );
        }
        // 11. colour bar.
        if let Some(cells) = self.colorbar() {
            draw_colorbar(c, &rect, cells);
        }
        // 12. legend.
        if self.legend != LegendPos::Hidden && !legend.is_empty() {
            draw_legend(c, &rect, &legend, self.legend, &occupied);
        }
        Ok(())
    }
}

fn x_target(w: f64) -> usize {
    ((w / 80.0) as usize).clamp(3, 10)
}
fn y_target(h: f64) -> usize {
    ((h / 48.0) as usize).clamp(2, 8)
}

fn min_spacing(x: &[f64]) -> f64 {
    let mut v: Vec<f64> = x.iter().copied().filter(|a| a.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    let d = v
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .fold(f64::INFINITY, f64::min);
    if d.is_finite() { d } else { 1.0 }
}

/// Splits data at gaps (non-finite, or ≤ 0 on log axes); for staircases inserts the hold points.
fn pieces(x: &[f64], y: &[f64], xlog: bool, ylog: bool, stairs: bool) -> Vec<Vec<(f64, f64)>> {
    let ok =
        |a: f64, b: f64| a.is_finite() && b.is_finite() && (!xlog || a > 0.0) && (!ylog || b > 0.0);
    let mut out = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    for k in 0..x.len() {
        if ok(x[k], y[k]) {
            if stairs && let Some(&(_, py)) = cur.last() {
                cur.push((x[k], py));
            }
            cur.push((x[k], y[k]));
        } else if !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

fn sample_segments(pts: &[(f64, f64)], out: &mut Vec<(f64, f64)>) {
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let n = (len / 6.0).ceil().max(1.0) as usize;
        for k in 0..n {
            let t = k as f64 / n as f64;
            out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
        }
    }
    if let Some(p) = pts.last() {
        out.push(*p);
    }
}

fn draw_piece(
    c: &mut dyn Canvas,
    map: &Map,
    data: &[(f64, f64)],
    st: &LineStyle,
    occupied: &mut Vec<(f64, f64)>,
) {
    // Map, keep the envelope of each pixel column, drop points within 0.1 px of the line,
    // clip, draw.
    // Values so far outside the limits that their pixel coordinate overflows are gaps too.
    let px: Vec<(f64, f64)> = data.iter().map(|&(a, b)| map.p(a, b)).collect();
    // Clip against a slightly larger rectangle so line caps at the frame are not cut short.
    let r = map.rect;
    let clip = Rect {
        x0: r.x0 - 0.5,
        y0: r.y0 - 0.5,
        x1: r.x1 + 0.5,
        y1: r.y1 + 0.5,
    };
    for run in px.split(|p| !(p.0.is_finite() && p.1.is_finite())) {
        let dec = crate::geometry::simplify(&decimate(run), 0.1);
        if dec.len() == 1 {
            if clip.contains(dec[0]) {
                c.circle(dec[0], st.width * 0.6, Some(st.color), None);
            }
            continue;
        }
        for p in clip_polyline(&dec, &clip) {
            c.polyline(&p, st);
            sample_segments(&p, occupied);
        }
    }
}

pub(crate) fn draw_marker(
    c: &mut dyn Canvas,
    m: Marker,
    p: (f64, f64),
    size: f64,
    color: Color,
    width: f64,
) {
    let r = size / 2.0;
    let st = LineStyle::new(color, width);
    match m {
        Marker::Dot => c.circle(p, r * 0.85, Some(color), None),
        Marker::Circle => c.circle(p, r, Some(Color::WHITE), Some(&st)),
        Marker::Cross => {
            let d = r * 0.8;
            c.polyline(&[(p.0 - d, p.1 - d), (p.0 + d, p.1 + d)], &st);
            c.polyline(&[(p.0 - d, p.1 + d), (p.0 + d, p.1 - d)], &st);
        }
        Marker::Plus => {
            c.polyline(&[(p.0 - r, p.1), (p.0 + r, p.1)], &st);
            c.polyline(&[(p.0, p.1 - r), (p.0, p.1 + r)], &st);
        }
        Marker::Square => {
            let d = r * 0.85;
            c.polygon(
                &[
                    (p.0 - d, p.1 - d),
                    (p.0 + d, p.1 - d),
                    (p.0 + d, p.1 + d),
                    (p.0 - d, p.1 + d),
                ],
                Some(Color::WHITE),
                Some(&st),
            );
        }
        Marker::Triangle => {
            c.polygon(
                &[
                    (p.0, p.1 - r),
                    (p.0 + r * 0.9, p.1 + r * 0.6),
                    (p.0 - r * 0.9, p.1 + r * 0.6),
                ],
                Some(Color::WHITE),
                Some(&st),
            );
        }
    }
}

fn circle_points(center: f64, radius: f64, n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|k| {
            let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            (center + radius * a.cos(), radius * a.sin())
        })
        .collect()
}

/// The allowed region (data coordinates clipped to the view), as a pixel polygon.
fn region_polygon(bounds: &[RegionBound], map: &Map) -> Vec<(f64, f64)> {
    let view = [
        (map.x.0, map.y.0),
        (map.x.1, map.y.0),
        (map.x.1, map.y.1),
        (map.x.0, map.y.1),
    ];
    let mut poly = view.to_vec();
    for b in bounds {
        poly = match *b {
            RegionBound::DecayRate(a) => crate::geometry::clip_halfplane(&poly, 1.0, 0.0, -a),
            RegionBound::SpeedLimit(b) => crate::geometry::clip_halfplane(&poly, -1.0, 0.0, b),
            RegionBound::Sector(t) => {
                // |y| ≤ −x tan θ  ⇔  y + x tan θ ≤ 0 and −y + x tan θ ≤ 0.
                let tn = t.tan().min(1e12);
                let p = crate::geometry::clip_halfplane(&poly, tn, 1.0, 0.0);
                crate::geometry::clip_halfplane(&p, tn, -1.0, 0.0)
            }
            RegionBound::Disk { center, radius } => {
                // Intersect with the circumscribed 256-gon's edges (inside the disk to 0.01 %).
                let n = 256;
                let mut p = poly;
                for k in 0..n {
                    let a = 2.0 * std::f64::consts::PI * (k as f64 + 0.5) / n as f64;
                    let (nx, ny) = (a.cos(), a.sin());
                    p = crate::geometry::clip_halfplane(&p, nx, ny, nx * center + radius);
                }
                p
            }
        };
    }
    poly.into_iter().map(|(x, y)| map.p(x, y)).collect()
}

/// Boundary curves of each bound, in pixels (unclipped).
fn region_boundaries(bounds: &[RegionBound], map: &Map) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let big = 4.0 * ((map.x.1 - map.x.0).abs() + (map.y.1 - map.y.0).abs());
    for b in bounds {
        match *b {
            RegionBound::DecayRate(a) => out.push(vec![map.p(-a, map.y.0), map.p(-a, map.y.1)]),
            RegionBound::SpeedLimit(b) => out.push(vec![map.p(-b, map.y.0), map.p(-b, map.y.1)]),
            RegionBound::Sector(t) => {
                let (dx, dy) = (-t.cos() * big, t.sin() * big);
                out.push(vec![map.p(0.0, 0.0), map.p(dx, dy)]);
                out.push(vec![map.p(0.0, 0.0), map.p(dx, -dy)]);
            }
            RegionBound::Disk { center, radius } => {
                let mut pts: Vec<(f64, f64)> = circle_points(center, radius, 361)
                    .into_iter()
                    .map(|(x, y)| map.p(x, y))
                    .collect();
                pts.push(pts[0]);
                out.push(pts);
            }
        }
    }
    out
}

fn cell_range(c: &Cells) -> (f64, f64) {
    if let CellKind::Scalar { range: Some(r), .. } = c.kind {
        return r;
    }
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for v in c.values.iter().filter(|v| v.is_finite()) {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi <= lo {
        return (lo - 0.5, lo + 0.5);
    }
    (lo, hi)
}

fn draw_cells(
    c: &mut dyn Canvas,
    map: &Map,
    cells: &Cells,
    legend: &mut Vec<(String, LegendGlyph)>,
) {
    let p0 = map.p(cells.x_range.0, cells.y_range.1);
    let p1 = map.p(cells.x_range.1, cells.y_range.0);
    let (nx, ny) = (cells.nx, cells.ny);
    let mut colors = Vec::with_capacity(nx * ny);
    let nan = Color::rgb(225, 225, 225);
    match &cells.kind {
        CellKind::Boolean { labels, colors: cs } => {
            for j in (0..ny).rev() {
                for i in 0..nx {
                    colors.push(if cells.values[j * nx + i] != 0.0 {
                        cs[0]
                    } else {
                        cs[1]
                    });
                }
            }
            legend.push((labels[0].clone(), LegendGlyph::Patch(cs[0])));
            legend.push((labels[1].clone(), LegendGlyph::Patch(cs[1])));
        }
        CellKind::Scalar { map: cm, .. } => {
            let (lo, hi) = cell_range(cells);
            for j in (0..ny).rev() {
                for i in 0..nx {
                    let v = cells.values[j * nx + i];
                    colors.push(if v.is_finite() {
                        cm.at((v - lo) / (hi - lo))
                    } else {
                        nan
                    });
                }
            }
        }
    }
    c.cells((p0.0, p0.1, p1.0 - p0.0, p1.1 - p0.1), nx, ny, &colors);
}

fn draw_colorbar(c: &mut dyn Canvas, rect: &Rect, cells: &Cells) {
    let CellKind::Scalar { map: cm, label, .. } = &cells.kind else {
        return;
    };
    let (lo, hi) = cell_range(cells);
    let x = rect.x1 + 14.0;
    let w = 14.0;
    let n = 128;
    let colors: Vec<Color> = (0..n)
        .map(|k| cm.at(1.0 - (k as f64 + 0.5) / n as f64))
        .collect();
    c.cells((x, rect.y0, w, rect.h()), 1, n, &colors);
    c.polygon(
        &[
            (x, rect.y0),
            (x + w, rect.y0),
            (x + w, rect.y1),
            (x, rect.y1),
        ],
        None,
        Some(&LineStyle::new(FRAME, 0.8)),
    );
    let t = linear_ticks(lo, hi, 5);
    let mut wmax: f64 = 0.0;
    for (v, s) in &t.major {
        let py = rect.y1 - (v - lo) / (hi - lo) * rect.h();
        c.polyline(
            &[(x + w - 3.0, py), (x + w, py)],
            &LineStyle::new(FRAME, 0.8),
        );
        c.text(
            s,
            (x + w + 4.0, py),
            &TextStyle::new(TICK_FONT, HAlign::Left, VAlign::Center),
        );
        wmax = wmax.max(c.text_width(s, TICK_FONT));
    }
    let mut ts = TextStyle::new(LABEL_FONT, HAlign::Center, VAlign::Top);
    ts.vertical = true;
    // Rotated −90°: "top" of the text faces left, so the anchor sits at its left edge.
    ts.v = VAlign::Bottom;
    c.text(
        label,
        (
            x + w + 4.0 + wmax + 6.0 + LABEL_FONT,
            (rect.y0 + rect.y1) / 2.0,
        ),
        &ts,
    );
}

#[derive(Debug, Clone, Copy)]
enum LegendGlyph {
    Line(LineStyle, Option<Marker>, f64),
    Marker(Marker, f64, Color, f64),
    Patch(Color),
}

fn draw_legend(
    c: &mut dyn Canvas,
    rect: &Rect,
    entries: &[(String, LegendGlyph)],
    pos: LegendPos,
    occupied: &[(f64, f64)],
) {
    let row = LEGEND_FONT * 1.45;
    let sample = 24.0;
    let text_w = entries
        .iter()
        .map(|(s, _)| c.text_width(s, LEGEND_FONT))
        .fold(0.0, f64::max);
    let w = 8.0 + sample + 6.0 + text_w + 8.0;
    let h = 6.0 + row * entries.len() as f64 + 2.0;
    let inset = 8.0;
    let corners = [
        (LegendPos::UpperRight, rect.x1 - inset - w, rect.y0 + inset),
        (LegendPos::UpperLeft, rect.x0 + inset, rect.y0 + inset),
        (
            LegendPos::LowerRight,
            rect.x1 - inset - w,
            rect.y1 - inset - h,
        ),
        (LegendPos::LowerLeft, rect.x0 + inset, rect.y1 - inset - h),
    ];
    let (bx, by) = match pos {
        LegendPos::Best => {
            let mut best = (usize::MAX, corners[0].1, corners[0].2);
            for &(_, x, y) in &corners {
                let r = Rect::new(x - 2.0, y - 2.0, w + 4.0, h + 4.0);
                let n = occupied.iter().filter(|p| r.contains(**p)).count();
                if n < best.0 {
                    best = (n, x, y);
                }
            }
            (best.1, best.2)
        }
        p => corners
            .iter()
            .find(|c| c.0 == p)
            .map(|c| (c.1, c.2))
            .unwrap_or((corners[0].1, corners[0].2)),
    };
    c.polygon(
        &[(bx, by), (bx + w, by), (bx + w, by + h), (bx, by + h)],
        Some(Color::rgba(255, 255, 255, 235)),
        Some(&LineStyle::new(Color::rgb(190, 190, 190), 0.8)),
    );
    for (k, (label, g)) in entries.iter().enumerate() {
        let cy = by + 4.0 + row * (k as f64 + 0.5);
        let x0 = bx + 8.0;
        match *g {
            LegendGlyph::Line(st, m, ms) => {
                c.polyline(&[(x0, cy), (x0 + sample, cy)], &st);
                if let Some(m) = m {
                    draw_marker(
                        c,
                        m,
                        (x0 + sample / 2.0, cy),
                        ms,
                        st.color,
                        st.width.clamp(1.0, 2.0),
                    );
                }
            }
            LegendGlyph::Marker(m, ms, col, wd) => {
                draw_marker(c, m, (x0 + sample / 2.0, cy), ms, col, wd)
            }
            LegendGlyph::Patch(col) => {
                let hh = LEGEND_FONT * 0.8;
                c.polygon(
                    &[
                        (x0 + 3.0, cy - hh / 2.0),
                        (x0 + sample - 3.0, cy - hh / 2.0),
                        (x0 + sample - 3.0, cy + hh / 2.0),
                        (x0 + 3.0, cy + hh / 2.0),
                    ],
                    Some(col),
                    Some(&LineStyle::new(Color::rgb(150, 150, 150), 0.6)),
                );
            }
        }
        c.text(
            label,
            (x0 + sample + 6.0, cy),
            &TextStyle::new(LEGEND_FONT, HAlign::Left, VAlign::Center),
        );
    }
}
