//! Drawing a panel: frame, grid, ticks and labels, every series in order, the colour bar and
//! the legend.
//!
//! Neighbours: [`super`] holds the panel's builder API; `check.rs` validates the panel;
//! `limits.rs` the data limits and ticks; `layout.rs` the margins; `marks.rs` the drawing
//! primitives used here.

use super::limits::min_spacing;
use super::marks::{
    LegendGlyph, draw_cells, draw_colorbar, draw_legend, draw_marker, draw_piece, pieces,
    region_boundaries, region_polygon, sample_segments,
};
use super::{
    Axes, FRAME, GRID, GRID_MINOR, Kind, LABEL_FONT, LEGEND_FONT, LegendPos, Map, PanelLayout,
    Scale, TICK_FONT, TICK_LEN, TITLE_FONT, finite_pairs,
};
use crate::canvas::{Canvas, HAlign, TextStyle, VAlign};
use crate::color::{Color, palette};
use crate::error::Result;
use crate::font;
use crate::geometry::{Rect, clip_polygon, clip_polyline};
use crate::style::LineStyle;

impl Axes {
    /// Draws the panel with its plot area at `rect`; returns where its parts landed.
    pub(crate) fn draw(&self, c: &mut dyn Canvas, rect: Rect) -> Result<PanelLayout> {
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
        let legend_box = (self.legend != LegendPos::Hidden && !legend.is_empty())
            .then(|| draw_legend(c, &rect, &legend, self.legend, &occupied))
            .map(|b| [b.x0, b.y0, b.x1, b.y1]);
        Ok(PanelLayout {
            plot: [rect.x0, rect.y0, rect.x1, rect.y1],
            legend: legend_box,
            points: occupied,
        })
    }
}
