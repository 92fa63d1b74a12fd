//! Figures and animations for pendulab, as SVG, PNG and GIF files.
#![warn(missing_docs)]

mod axes;
mod canvas;
mod charts;
mod color;
mod error;
mod figure;
mod font;
mod geometry;
mod style;
mod surface;
mod ticks;

pub use axes::{Axes, LegendPos, RegionBound, Scale, Series};
pub use charts::{
    Bode, Channel, FrequencyUnit, GainCurves, IdentFit, PoleZeroMap, SignalPanel, TimeResponse,
    fit_percent, region_of_attraction,
};
pub use color::{Color, ColorMap, PALETTE, palette};
pub use error::{PlotError, Result};
pub use figure::{DEFAULT_WIDTH, Figure, Panel, Raster, SavedFigure};
pub use font::ensure_font;
pub use style::{Dash, LineStyle, Marker};
pub use surface::Surface;
