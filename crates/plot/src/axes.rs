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
//!
//! This file holds the panel's builder API ([`Axes`], [`Series`], [`Scale`], [`LegendPos`],
//! [`RegionBound`]); beside it in `axes/`: `check.rs` (validation), `limits.rs` (data limits,
//! scales and ticks), `layout.rs` (margins), `draw.rs` (drawing a panel) and `marks.rs` (the
//! drawing primitives: lines, markers, regions, cells, colour bar, legend).

use crate::color::{Color, ColorMap};
use crate::geometry::Rect;
use crate::style::{Dash, Marker};
use pendulab_lti::Complex64;

mod check;
mod draw;
mod layout;
mod limits;
mod marks;

/// Smallest font size of a figure, in CSS pixels: 12 px = 9 pt, legible when the figure is shown
/// at its own width (the lab report does so wherever the page is wide enough).
pub const MIN_FONT: f64 = 12.0;
pub(crate) const TICK_FONT: f64 = MIN_FONT;
pub(crate) const LABEL_FONT: f64 = 13.0;
pub(crate) const TITLE_FONT: f64 = 13.5;
pub(crate) const LEGEND_FONT: f64 = MIN_FONT;
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
    /// Inside, at the place that covers the fewest drawn points (as matplotlib's
    /// `loc="best"`): tried in the order upper right, upper left, lower left, lower right,
    /// centre right, centre left, upper centre, lower centre, centre; the first with the
    /// fewest points wins. When every place covers data, the legend goes outside, as
    /// [`LegendPos::Outside`], unless it is wider than
    /// [`MAX_OUTSIDE_LEGEND`](crate::MAX_OUTSIDE_LEGEND) of the plot.
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
    /// Outside the plot area, to the right of its upper corner; the panel's right margin
    /// grows by the legend's width, so the legend covers no data whatever the data.
    Outside,
    /// No legend, even if series have labels.
    Hidden,
}

/// Where the parts of one panel landed when its figure was drawn, in SVG pixels (x to the
/// right, y down, origin at the figure's upper left corner); from [`Figure::layout`](crate::Figure::layout).
#[derive(Debug, Clone, PartialEq)]
pub struct PanelLayout {
    /// The plot rectangle `[x0, y0, x1, y1]` (inside the frame).
    pub plot: [f64; 4],
    /// The legend box `[x0, y0, x1, y1]`, if a legend was drawn.
    pub legend: Option<[f64; 4]>,
    /// Points of everything drawn in the plot area, in pixels: the lines sampled at least
    /// every 6 px along their length, every marker centre, reference lines. A legend is placed
    /// to avoid these.
    pub points: Vec<(f64, f64)>,
}

impl PanelLayout {
    /// The drawn points that lie inside the legend box (none when there is no legend).
    pub fn points_under_legend(&self) -> usize {
        self.legend.map_or(0, |[x0, y0, x1, y1]| {
            self.points
                .iter()
                .filter(|(x, y)| *x >= x0 && *x <= x1 && *y >= y0 && *y <= y1)
                .count()
        })
    }
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
    pub(crate) fn label_text(&self) -> Option<&str> {
        self.label.as_deref()
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
/// until the figure is rendered; then every problem is reported as a
/// [`PlotError`](crate::error::PlotError) naming the panel and series.
///
/// **Missing data.** NaN and infinite samples are gaps: a line is broken there (the MATLAB
/// convention, so NaN can be inserted on purpose to separate pieces) and markers are left out. On
/// a logarithmic axis samples ≤ 0 are gaps too. A series with no drawable sample at all is an
/// error ([`PlotError::NothingToDraw`](crate::error::PlotError::NothingToDraw)).
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
    pub(crate) fn legend_pos(&self) -> LegendPos {
        self.legend
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
}
