//! Validation of a panel before it is drawn: limits, scales and every series' data, with errors
//! that name the panel and the series.
//!
//! Neighbours: [`super`] holds the panel's builder API (`Axes`, `Series`); `limits.rs` the
//! data limits and ticks; `layout.rs` the margins; `draw.rs` draws the panel with the primitives
//! of `marks.rs`.

use super::{Axes, CellKind, Kind, RegionBound, Scale, Series, finite_pairs};
use crate::error::{PlotError, Result};

impl Axes {
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
}
