//! Drawing primitives of a panel: data split at gaps, line pieces, markers, stability regions
//! and their boundaries, cell maps, the colour bar and the legend.
//!
//! Neighbours: `draw.rs` draws a panel with these; [`super`] holds the panel's builder API;
//! `check.rs`, `limits.rs` and `layout.rs` validate, scale and lay it out.

use super::{
    CellKind, Cells, FRAME, LABEL_FONT, LEGEND_FONT, LegendPos, Map, RegionBound, TICK_FONT,
};
use crate::canvas::{Canvas, HAlign, TextStyle, VAlign};
use crate::color::Color;
use crate::geometry::{Rect, clip_polyline, decimate};
use crate::style::{LineStyle, Marker};
use crate::ticks::linear_ticks;

/// Splits data at gaps (non-finite, or ≤ 0 on log axes); for staircases inserts the hold points.
pub(super) fn pieces(
    x: &[f64],
    y: &[f64],
    xlog: bool,
    ylog: bool,
    stairs: bool,
) -> Vec<Vec<(f64, f64)>> {
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

pub(super) fn sample_segments(pts: &[(f64, f64)], out: &mut Vec<(f64, f64)>) {
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

pub(super) fn draw_piece(
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
pub(super) fn region_polygon(bounds: &[RegionBound], map: &Map) -> Vec<(f64, f64)> {
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
pub(super) fn region_boundaries(bounds: &[RegionBound], map: &Map) -> Vec<Vec<(f64, f64)>> {
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

pub(super) fn cell_range(c: &Cells) -> (f64, f64) {
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

pub(super) fn draw_cells(
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

pub(super) fn draw_colorbar(c: &mut dyn Canvas, rect: &Rect, cells: &Cells) {
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
pub(super) enum LegendGlyph {
    Line(LineStyle, Option<Marker>, f64),
    Marker(Marker, f64, Color, f64),
    Patch(Color),
}

/// Width and height of the legend box of `labels` in pixels.
pub(super) fn legend_size<'a>(
    labels: impl IntoIterator<Item = &'a str>,
    width: impl Fn(&str) -> f64,
) -> (f64, f64) {
    let (mut text_w, mut n) = (0.0_f64, 0usize);
    for l in labels {
        text_w = text_w.max(width(l));
        n += 1;
    }
    (
        8.0 + LEGEND_SAMPLE + 6.0 + text_w + 8.0,
        6.0 + LEGEND_FONT * 1.45 * n as f64 + 2.0,
    )
}

const LEGEND_SAMPLE: f64 = 24.0;
/// Gap between the plot frame and a legend outside it.
pub(super) const LEGEND_GAP: f64 = 8.0;

/// Draws the legend; returns its box.
pub(super) fn draw_legend(
    c: &mut dyn Canvas,
    rect: &Rect,
    entries: &[(String, LegendGlyph)],
    pos: LegendPos,
    occupied: &[(f64, f64)],
) -> Rect {
    let row = LEGEND_FONT * 1.45;
    let sample = LEGEND_SAMPLE;
    let (w, h) = legend_size(entries.iter().map(|(s, _)| s.as_str()), |s| {
        c.text_width(s, LEGEND_FONT)
    });
    let inset = 8.0;
    let (xl, xc, xr) = (
        rect.x0 + inset,
        (rect.x0 + rect.x1 - w) / 2.0,
        rect.x1 - inset - w,
    );
    let (yt, yc, yb) = (
        rect.y0 + inset,
        (rect.y0 + rect.y1 - h) / 2.0,
        rect.y1 - inset - h,
    );
    // matplotlib's order of `loc="best"`.
    let places = [
        (LegendPos::UpperRight, xr, yt),
        (LegendPos::UpperLeft, xl, yt),
        (LegendPos::LowerLeft, xl, yb),
        (LegendPos::LowerRight, xr, yb),
        (LegendPos::Best, xr, yc),
        (LegendPos::Best, xl, yc),
        (LegendPos::Best, xc, yt),
        (LegendPos::Best, xc, yb),
        (LegendPos::Best, xc, yc),
    ];
    let (bx, by) = match pos {
        LegendPos::Best => {
            let mut best = (usize::MAX, places[0].1, places[0].2);
            for &(_, x, y) in &places {
                let r = Rect::new(x - 2.0, y - 2.0, w + 4.0, h + 4.0);
                let n = occupied.iter().filter(|p| r.contains(**p)).count();
                if n < best.0 {
                    best = (n, x, y);
                }
            }
            (best.1, best.2)
        }
        LegendPos::Outside => (rect.x1 + LEGEND_GAP, rect.y0),
        p => places
            .iter()
            .find(|c| c.0 == p)
            .map(|c| (c.1, c.2))
            .unwrap_or((places[0].1, places[0].2)),
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
    Rect::new(bx, by, w, h)
}
