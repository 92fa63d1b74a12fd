//! Figures and animations for pendulab, as SVG, PNG and GIF files.
//!
//! Rendering only: this crate computes nothing about systems. It takes plain numbers (or a
//! [`pendulab_lti::Trajectory`]) and draws textbook figures with titles, axis labels with units,
//! legends and grids.
//!
//! # Tour
//! - [`Figure`] — one or more panels in rows and columns ([`Figure::new`], [`Figure::column`]
//!   for panels stacked over a common time axis, [`Figure::row`], [`Figure::grid`]); writes
//!   [`Figure::save`] `dir/stem.svg` + `dir/stem.png`, or returns [`Figure::to_svg`],
//!   [`Figure::to_png`], [`Figure::to_raster`].
//! - [`Axes`] — a Cartesian panel: [`Axes::plot`] (lines), [`Axes::step`] (stairs of sampled
//!   signals), [`Axes::scatter`], [`Axes::bar`], [`Axes::hline`]/[`Axes::vline`] (reference
//!   lines), [`Axes::fill`]/[`Axes::fill_between`], [`Axes::text`], [`Axes::poles`]/
//!   [`Axes::zeros`], [`Axes::region`] (D-stability regions built from [`RegionBound`]s),
//!   [`Axes::bool_map`]/[`Axes::heat_map`] (cell maps with legend or colour bar); log axes,
//!   fixed limits, equal aspect. Each adding method returns a [`Series`] to style: label,
//!   [`Color`], width, [`Dash`], [`Marker`].
//! - [`Surface`] — a 3-D surface z = f(x, y) (the book's Lyapunov function plot).
//! - Ready-made book figures: [`TimeResponse`] (runs × [`SignalPanel`]s of a trajectory),
//!   [`Bode`], [`PoleZeroMap`], [`GainCurves`] (K(θ₁) against constant LQ gains),
//!   [`IdentFit`] (measured against model, with fit %), [`region_of_attraction`]; loop
//!   analysis: [`Nyquist`] (unit circle, −1, direction arrows), [`RootLocusPlot`] (poles ×,
//!   zeros ○, asymptotes, gain annotations), [`Nichols`] (with the closed-loop M/N grid),
//!   [`SigmaPlot`].
//! - [`Animation`] — the cart-type ([`CartGeometry`]) and arm-type ([`ArmGeometry`]) pendulums
//!   as looping GIF ([`Animation::save_gif`]) and SMIL-animated SVG ([`Animation::save_svg`]),
//!   frames resampled from any sample rate at [`AnimationOptions::fps`].
//! - [`PlotError`] — every failure, naming the panel, series, sample or path.
//!
//! # Conventions
//! - Sizes are CSS pixels (SVG user units); the PNG is the same picture at
//!   [`Figure::png_scale`] (default 2) device pixels per unit.
//! - NaN and infinite samples are gaps in lines (MATLAB's convention), never errors, unless a
//!   series has nothing drawable at all. Animations reject NaN.
//! - Long traces are reduced to what the pixel grid can show before drawing (per pixel column
//!   the first, lowest, highest and last sample, then Douglas–Peucker at 0.1 px), so peaks
//!   survive and a 10⁴-sample trace costs about as much as a 10³-sample one.
//! - Text uses the embedded DejaVu Sans (Bitstream Vera licence, `assets/LICENSE_DEJAVU`):
//!   no system fonts or libraries are read. Rendering is thread-safe.
//!
//! # Example
//! ```
//! use pendulab_plot::{Axes, Color, Figure};
//! let t: Vec<f64> = (0..=1000).map(|k| k as f64 * 0.01).collect();
//! let y1: Vec<f64> = t.iter().map(|t| (-t).exp()).collect();
//! let y2: Vec<f64> = t.iter().map(|t| 2.0 * t.sin()).collect();
//! let mut ax = Axes::new();
//! ax.xlabel("time [s]").ylabel("position [m]");
//! ax.plot(&t, &y1).label("y1(t)").color(Color::RED).dashed();
//! ax.plot(&t, &y2).label("y2(t)").color(Color::GREEN).dotted();
//! let fig = Figure::new(ax).title("p1c41_cdip_response");
//! let dir = std::env::temp_dir().join("pendulab-plot-doc");
//! let saved = fig.save(&dir, "p1c41_cdip_response").unwrap();
//! assert!(saved.png.exists() && saved.svg.exists());
//! ```
#![warn(missing_docs)]

mod anim;
mod axes;
mod canvas;
mod charts;
mod color;
mod control_charts;
mod error;
mod figure;
mod font;
mod geometry;
mod style;
mod surface;
mod ticks;

pub use anim::{Animation, AnimationInfo, AnimationOptions, ArmGeometry, CartGeometry};
pub use axes::{Axes, LegendPos, MIN_FONT, PanelLayout, RegionBound, Scale, Series};
pub use charts::{
    Bode, CHATTER_RATIO, Channel, FrequencyUnit, GainCurves, IdentFit, PoleZeroMap, SignalPanel,
    TimeResponse, chatters, fit_percent, region_of_attraction,
};
pub use color::{Color, ColorMap, PALETTE, palette};
pub use control_charts::{Nichols, Nyquist, RootLocusPlot, SigmaPlot};
pub use error::{PlotError, Result};
pub use figure::{DEFAULT_WIDTH, Figure, MAX_OUTSIDE_LEGEND, Panel, Raster, SavedFigure};
pub use font::ensure_font;
pub use style::{Dash, LineStyle, Marker};
pub use surface::Surface;
