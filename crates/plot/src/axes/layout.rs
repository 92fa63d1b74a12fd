//! Layout of a panel: the space its tick labels, axis labels, title and colour bar need around
//! the plot rectangle.
//!
//! Neighbours: [`super`] holds the panel's builder API; `check.rs` validates the panel;
//! `limits.rs` the data limits and ticks; `draw.rs` draws the panel with the primitives of
//! `marks.rs`.

use super::marks::{LEGEND_GAP, cell_range, legend_size};
use super::{
    Axes, CellKind, Cells, Kind, LABEL_FONT, LEGEND_FONT, LegendPos, Margins, PAD, TICK_FONT,
    TITLE_FONT,
};
use crate::error::{PlotError, Result};
use crate::font;
use crate::geometry::Rect;
use crate::ticks::linear_ticks;

impl Axes {
    pub(super) fn colorbar(&self) -> Option<&Cells> {
        self.series.iter().find_map(|s| match &s.kind {
            Kind::Cells(c) if matches!(c.kind, CellKind::Scalar { .. }) => Some(c),
            _ => None,
        })
    }

    /// The texts the legend may list: labelled series and the two labels of yes/no maps.
    fn legend_labels(&self) -> Vec<String> {
        let mut v = Vec::new();
        for s in &self.series {
            if let Kind::Cells(Cells {
                kind: CellKind::Boolean { labels, .. },
                ..
            }) = &s.kind
            {
                v.extend(labels.iter().cloned());
            } else if let Some(l) = s.label_text() {
                v.push(l.to_string());
            }
        }
        v
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
            if self.legend == LegendPos::Outside {
                let labels = self.legend_labels();
                if !labels.is_empty() {
                    let (w, _) = legend_size(labels.iter().map(String::as_str), |s| {
                        font::text_width(f, s, LEGEND_FONT)
                    });
                    m.right += LEGEND_GAP + w;
                }
            }
        }
        Ok(m)
    }
}
