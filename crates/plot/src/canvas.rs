//! Two drawing surfaces with one interface: SVG text and an anti-aliased RGBA raster.
//!
//! Figures are laid out once in SVG user units (CSS pixels) and drawn through [`Canvas`]; the
//! raster canvas multiplies every coordinate, width and font size by its scale, so PNG and SVG
//! show the same picture.

use std::fmt::Write as _;

use ab_glyph::FontRef;
use tiny_skia::{
    FillRule, LineCap, LineJoin, Paint, Path, PathBuilder, Pixmap, Stroke, StrokeDash,
};

use crate::color::Color;
use crate::error::{PlotError, Result};
use crate::font::{self, SVG_FONT_FAMILY};
use crate::style::LineStyle;

/// Horizontal text anchor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum HAlign {
    Left,
    Center,
    Right,
}

/// Vertical text anchor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum VAlign {
    /// Anchor at the top of capital letters.
    Top,
    /// Anchor halfway up capital letters.
    Center,
    /// Anchor on the baseline.
    Baseline,
    /// Anchor at the bottom of descenders.
    Bottom,
}

/// How a piece of text is set.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TextStyle {
    pub size: f64,
    pub color: Color,
    pub h: HAlign,
    pub v: VAlign,
    /// Rotated by −90° (reads bottom to top), for vertical axis labels.
    pub vertical: bool,
    pub bold: bool,
}

impl TextStyle {
    pub fn new(size: f64, h: HAlign, v: VAlign) -> Self {
        Self {
            size,
            color: Color::BLACK,
            h,
            v,
            vertical: false,
            bold: false,
        }
    }
    /// Offset from the anchor to the baseline start, along and across the text direction.
    fn baseline_offset(&self, width: f64) -> (f64, f64) {
        let dx = match self.h {
            HAlign::Left => 0.0,
            HAlign::Center => -width / 2.0,
            HAlign::Right => -width,
        };
        let dy = match self.v {
            VAlign::Top => font::cap_height(self.size),
            VAlign::Center => font::cap_height(self.size) / 2.0,
            VAlign::Baseline => 0.0,
            VAlign::Bottom => -font::descent(self.size),
        };
        (dx, dy)
    }
}

/// A drawing surface in SVG user units, y downwards.
pub(crate) trait Canvas {
    /// Strokes an open polyline.
    fn polyline(&mut self, pts: &[(f64, f64)], style: &LineStyle);
    /// Fills and/or strokes a closed polygon.
    fn polygon(&mut self, pts: &[(f64, f64)], fill: Option<Color>, stroke: Option<&LineStyle>);
    /// Fills and/or strokes a circle.
    fn circle(&mut self, c: (f64, f64), r: f64, fill: Option<Color>, stroke: Option<&LineStyle>);
    /// Sets a line of text.
    fn text(&mut self, text: &str, at: (f64, f64), style: &TextStyle);
    /// Paints an `nx × ny` image of cells (row 0 at the top) into the rectangle `(x, y, w, h)`.
    fn cells(&mut self, rect: (f64, f64, f64, f64), nx: usize, ny: usize, colors: &[Color]);
    /// Width of `text` at `size` px per em.
    fn text_width(&self, text: &str, size: f64) -> f64;
    /// Fills an axis-aligned rectangle.
    fn rect(
        &mut self,
        x: f64,
        y: f64,
        w: f64,
        h: f64,
        fill: Option<Color>,
        stroke: Option<&LineStyle>,
    ) {
        self.polygon(
            &[(x, y), (x + w, y), (x + w, y + h), (x, y + h)],
            fill,
            stroke,
        );
    }
}

// ---------------------------------------------------------------------------------------------
// SVG

/// Writes SVG elements into a string.
pub(crate) struct SvgCanvas {
    pub out: String,
    font: &'static FontRef<'static>,
}

/// A number with at most two decimals, trailing zeros removed.
pub(crate) fn num(v: f64) -> String {
    let v = if v.abs() < 5e-3 { 0.0 } else { v };
    let mut s = format!("{v:.2}");
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    s
}

/// Escapes text for XML content and attribute values.
pub(crate) fn xml_escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&#39;"),
            c if (c as u32) < 0x20 && c != '\n' && c != '\t' => {}
            c => o.push(c),
        }
    }
    o
}

pub(crate) fn svg_stroke_attrs(s: &LineStyle) -> String {
    let mut a = format!(
        r#" stroke="{}" stroke-width="{}""#,
        s.color.hex(),
        num(s.width)
    );
    if s.color.a < 255 {
        let _ = write!(a, r#" stroke-opacity="{:.3}""#, s.color.alpha());
    }
    if let Some((pat, round)) = s.dash.pattern(s.width) {
        let p: Vec<String> = pat.iter().map(|v| num(*v)).collect();
        let _ = write!(a, r#" stroke-dasharray="{}""#, p.join(" "));
        if round {
            a.push_str(r#" stroke-linecap="round""#);
        }
    }
    a.push_str(r#" stroke-linejoin="round""#);
    a
}

fn svg_fill_attrs(fill: Option<Color>) -> String {
    match fill {
        None => r#" fill="none""#.to_string(),
        Some(c) if c.a < 255 => format!(r#" fill="{}" fill-opacity="{:.3}""#, c.hex(), c.alpha()),
        Some(c) => format!(r#" fill="{}""#, c.hex()),
    }
}

fn points_attr(pts: &[(f64, f64)]) -> String {
    let mut s = String::with_capacity(pts.len() * 12);
    for (i, (x, y)) in pts
        .iter()
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .enumerate()
    {
        if i > 0 {
            s.push(' ');
        }
        s.push_str(&num(*x));
        s.push(',');
        s.push_str(&num(*y));
    }
    s
}

impl SvgCanvas {
    pub fn new(width: f64, height: f64) -> Result<Self> {
        let mut out = String::with_capacity(64 * 1024);
        let _ = write!(
            out,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="{ff}">"#,
            w = num(width),
            h = num(height),
            ff = SVG_FONT_FAMILY.replace('\'', "&#39;"),
        );
        out.push('\n');
        let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
        Ok(Self {
            out,
            font: font::font()?,
        })
    }
    pub fn finish(mut self) -> String {
        self.out.push_str("</svg>\n");
        self.out
    }
}

impl Canvas for SvgCanvas {
    fn polyline(&mut self, pts: &[(f64, f64)], style: &LineStyle) {
        if pts.len() < 2 {
            return;
        }
        let _ = writeln!(
            self.out,
            r#"<polyline points="{}" fill="none"{}/>"#,
            points_attr(pts),
            svg_stroke_attrs(style)
        );
    }
    fn polygon(&mut self, pts: &[(f64, f64)], fill: Option<Color>, stroke: Option<&LineStyle>) {
        if pts.len() < 3 {
            return;
        }
        let _ = writeln!(
            self.out,
            r#"<polygon points="{}"{}{}/>"#,
            points_attr(pts),
            svg_fill_attrs(fill),
            stroke.map(svg_stroke_attrs).unwrap_or_default()
        );
    }
    fn circle(&mut self, c: (f64, f64), r: f64, fill: Option<Color>, stroke: Option<&LineStyle>) {
        if !(c.0.is_finite() && c.1.is_finite() && r.is_finite()) {
            return;
        }
        let _ = writeln!(
            self.out,
            r#"<circle cx="{}" cy="{}" r="{}"{}{}/>"#,
            num(c.0),
            num(c.1),
            num(r),
            svg_fill_attrs(fill),
            stroke.map(svg_stroke_attrs).unwrap_or_default()
        );
    }
    fn text(&mut self, text: &str, at: (f64, f64), style: &TextStyle) {
        if text.is_empty() || !(at.0.is_finite() && at.1.is_finite()) {
            return;
        }
        let (_, dy) = style.baseline_offset(0.0);
        let anchor = match style.h {
            HAlign::Left => "start",
            HAlign::Center => "middle",
            HAlign::Right => "end",
        };
        let mut attrs = format!(
            r#" font-size="{}" text-anchor="{anchor}" fill="{}""#,
            num(style.size),
            style.color.hex()
        );
        if style.bold {
            attrs.push_str(r#" font-weight="bold""#);
        }
        if style.vertical {
            let _ = writeln!(
                self.out,
                r#"<text x="0" y="{}" transform="translate({} {}) rotate(-90)"{attrs}>{}</text>"#,
                num(dy),
                num(at.0),
                num(at.1),
                xml_escape(text)
            );
        } else {
            let _ = writeln!(
                self.out,
                r#"<text x="{}" y="{}"{attrs}>{}</text>"#,
                num(at.0),
                num(at.1 + dy),
                xml_escape(text)
            );
        }
    }
    fn cells(&mut self, rect: (f64, f64, f64, f64), nx: usize, ny: usize, colors: &[Color]) {
        if nx == 0 || ny == 0 || colors.len() != nx * ny {
            return;
        }
        let (x, y, w, h) = rect;
        let (cw, ch) = (w / nx as f64, h / ny as f64);
        // Few distinct colours (boolean maps): rectangles merged along rows stay small and crisp.
        // Many (scalar maps): one embedded PNG of nx × ny pixels, scaled without smoothing.
        let mut distinct: Vec<Color> = Vec::new();
        for c in colors {
            if !distinct.contains(c) {
                distinct.push(*c);
                if distinct.len() > 8 {
                    break;
                }
            }
        }
        if distinct.len() <= 8 {
            for j in 0..ny {
                let row = &colors[j * nx..(j + 1) * nx];
                let mut i = 0;
                while i < nx {
                    let c = row[i];
                    let mut k = i + 1;
                    while k < nx && row[k] == c {
                        k += 1;
                    }
                    // Overlap by a hair so that anti-aliased edges of neighbours leave no seams.
                    let _ = writeln!(
                        self.out,
                        r#"<rect x="{}" y="{}" width="{}" height="{}"{} shape-rendering="crispEdges"/>"#,
                        num(x + i as f64 * cw),
                        num(y + j as f64 * ch),
                        num((k - i) as f64 * cw + 0.02),
                        num(ch + 0.02),
                        svg_fill_attrs(Some(c))
                    );
                    i = k;
                }
            }
        } else {
            let mut rgba = Vec::with_capacity(nx * ny * 4);
            for c in colors {
                rgba.extend_from_slice(&[c.r, c.g, c.b, c.a]);
            }
            if let Ok(png) = encode_png_rgba(nx as u32, ny as u32, &rgba, None) {
                let _ = writeln!(
                    self.out,
                    r#"<image x="{}" y="{}" width="{}" height="{}" preserveAspectRatio="none" style="image-rendering:pixelated" href="data:image/png;base64,{}"/>"#,
                    num(x),
                    num(y),
                    num(w),
                    num(h),
                    base64(&png)
                );
            }
        }
    }
    fn text_width(&self, text: &str, size: f64) -> f64 {
        font::text_width(self.font, text, size)
    }
}

/// Standard base64 (RFC 4648) with padding.
pub(crate) fn base64(data: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(data.len().div_ceil(3) * 4);
    for chunk in data.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        s.push(T[(n >> 18) as usize & 63] as char);
        s.push(T[(n >> 12) as usize & 63] as char);
        s.push(if chunk.len() > 1 {
            T[(n >> 6) as usize & 63] as char
        } else {
            '='
        });
        s.push(if chunk.len() > 2 {
            T[n as usize & 63] as char
        } else {
            '='
        });
    }
    s
}

// ---------------------------------------------------------------------------------------------
// Raster

/// Draws anti-aliased into an RGBA pixmap at `scale` pixels per SVG unit.
pub(crate) struct RasterCanvas {
    pub pixmap: Pixmap,
    scale: f64,
    font: &'static FontRef<'static>,
}

fn paint(c: Color) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(c.r, c.g, c.b, c.a);
    p.anti_alias = true;
    p
}

impl RasterCanvas {
    /// A white canvas of `width × height` SVG units at `scale` pixels per unit.
    pub fn new(width: f64, height: f64, scale: f64) -> Result<Self> {
        let (w, h) = (
            (width * scale).round().max(1.0),
            (height * scale).round().max(1.0),
        );
        if w * h > 64.0e6 {
            return Err(PlotError::InvalidArgument(format!(
                "raster of {w} x {h} pixels is too large"
            )));
        }
        let mut pixmap = Pixmap::new(w as u32, h as u32).ok_or_else(|| {
            PlotError::InvalidArgument(format!("cannot allocate a {w} x {h} raster"))
        })?;
        pixmap.fill(tiny_skia::Color::WHITE);
        Ok(Self {
            pixmap,
            scale,
            font: font::font()?,
        })
    }
    /// Pixel width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.pixmap.width(), self.pixmap.height())
    }
    /// Fills the whole canvas with one colour.
    pub fn clear(&mut self, c: Color) {
        self.pixmap
            .fill(tiny_skia::Color::from_rgba8(c.r, c.g, c.b, c.a));
    }
    /// Premultiplied RGBA pixels.
    pub fn data(&self) -> &[u8] {
        self.pixmap.data()
    }
    fn path(&self, pts: &[(f64, f64)], close: bool) -> Option<tiny_skia::Path> {
        let mut pb = PathBuilder::with_capacity(pts.len() + 1, pts.len() * 2);
        let s = self.scale;
        let mut first = true;
        for &(x, y) in pts {
            if !(x.is_finite() && y.is_finite()) {
                continue;
            }
            let (x, y) = ((x * s) as f32, (y * s) as f32);
            if first {
                pb.move_to(x, y);
                first = false;
            } else {
                pb.line_to(x, y);
            }
        }
        if close {
            pb.close();
        }
        pb.finish()
    }
    fn stroke_style(&self, st: &LineStyle) -> Stroke {
        let s = self.scale;
        let mut stroke = Stroke {
            width: (st.width * s) as f32,
            line_join: LineJoin::Round,
            ..Stroke::default()
        };
        if let Some((pat, round)) = st.dash.pattern(st.width) {
            let v: Vec<f32> = pat.iter().map(|p| (p * s).max(0.01) as f32).collect();
            stroke.dash = StrokeDash::new(v, 0.0);
            if round {
                stroke.line_cap = LineCap::Round;
            }
        }
        stroke
    }
    /// Fills `path` (non-zero winding) with `fill`, then strokes it with `stroke`, each if
    /// given (SVG's painting order for a shape with both).
    fn fill_then_stroke(&mut self, path: &Path, fill: Option<Color>, stroke: Option<&LineStyle>) {
        let identity = tiny_skia::Transform::identity();
        if let Some(c) = fill {
            self.pixmap
                .fill_path(path, &paint(c), FillRule::Winding, identity, None);
        }
        if let Some(st) = stroke {
            let stroke = self.stroke_style(st);
            self.pixmap
                .stroke_path(path, &paint(st.color), &stroke, identity, None);
        }
    }
    /// Straight (un-premultiplied) RGBA bytes.
    pub fn rgba(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.pixmap.data().len());
        for p in self.pixmap.pixels() {
            let c = p.demultiply();
            out.extend_from_slice(&[c.red(), c.green(), c.blue(), c.alpha()]);
        }
        out
    }
}

impl Canvas for RasterCanvas {
    fn polyline(&mut self, pts: &[(f64, f64)], style: &LineStyle) {
        if pts.len() < 2 {
            return;
        }
        if let Some(path) = self.path(pts, false) {
            let stroke = self.stroke_style(style);
            self.pixmap.stroke_path(
                &path,
                &paint(style.color),
                &stroke,
                tiny_skia::Transform::identity(),
                None,
            );
        }
    }
    fn polygon(&mut self, pts: &[(f64, f64)], fill: Option<Color>, stroke: Option<&LineStyle>) {
        if pts.len() < 3 {
            return;
        }
        let Some(path) = self.path(pts, true) else {
            return;
        };
        self.fill_then_stroke(&path, fill, stroke);
    }
    fn circle(&mut self, c: (f64, f64), r: f64, fill: Option<Color>, stroke: Option<&LineStyle>) {
        let s = self.scale;
        let Some(path) =
            PathBuilder::from_circle((c.0 * s) as f32, (c.1 * s) as f32, (r * s).max(0.1) as f32)
        else {
            return;
        };
        self.fill_then_stroke(&path, fill, stroke);
    }
    fn text(&mut self, text: &str, at: (f64, f64), style: &TextStyle) {
        if text.is_empty() {
            return;
        }
        let s = self.scale;
        let width = font::text_width(self.font, text, style.size);
        let (dx, dy) = style.baseline_offset(width);
        let contours = font::text_contours(self.font, text, style.size);
        let mut pb = PathBuilder::new();
        for contour in &contours {
            for (k, &(u, v)) in contour.iter().enumerate() {
                let (lx, ly) = (u + dx, v + dy);
                // Rotation by −90° on screen (y down): (x, y) → (y, −x).
                let (rx, ry) = if style.vertical { (ly, -lx) } else { (lx, ly) };
                let (px, py) = (((at.0 + rx) * s) as f32, ((at.1 + ry) * s) as f32);
                if k == 0 {
                    pb.move_to(px, py);
                } else {
                    pb.line_to(px, py);
                }
            }
            pb.close();
        }
        if let Some(path) = pb.finish() {
            let p = paint(style.color);
            self.pixmap.fill_path(
                &path,
                &p,
                FillRule::Winding,
                tiny_skia::Transform::identity(),
                None,
            );
            if style.bold {
                let stroke = Stroke {
                    width: (style.size * s * 0.045) as f32,
                    ..Stroke::default()
                };
                self.pixmap
                    .stroke_path(&path, &p, &stroke, tiny_skia::Transform::identity(), None);
            }
        }
    }
    fn cells(&mut self, rect: (f64, f64, f64, f64), nx: usize, ny: usize, colors: &[Color]) {
        if nx == 0 || ny == 0 || colors.len() != nx * ny {
            return;
        }
        let s = self.scale;
        let (x, y, w, h) = rect;
        // Cell edges snapped to whole pixels so neighbours tile without seams.
        let xe: Vec<f32> = (0..=nx)
            .map(|i| ((x + w * i as f64 / nx as f64) * s).round() as f32)
            .collect();
        let ye: Vec<f32> = (0..=ny)
            .map(|j| ((y + h * j as f64 / ny as f64) * s).round() as f32)
            .collect();
        let mut p = Paint {
            anti_alias: false,
            ..Paint::default()
        };
        for j in 0..ny {
            for i in 0..nx {
                let c = colors[j * nx + i];
                p.set_color_rgba8(c.r, c.g, c.b, c.a);
                if let Some(r) = tiny_skia::Rect::from_ltrb(xe[i], ye[j], xe[i + 1], ye[j + 1]) {
                    self.pixmap
                        .fill_rect(r, &p, tiny_skia::Transform::identity(), None);
                }
            }
        }
    }
    fn text_width(&self, text: &str, size: f64) -> f64 {
        font::text_width(self.font, text, size)
    }
}

/// Encodes straight RGBA bytes as PNG, optionally recording the resolution in dots per inch.
pub(crate) fn encode_png_rgba(w: u32, h: u32, rgba: &[u8], dpi: Option<f64>) -> Result<Vec<u8>> {
    encode_png(w, h, png::ColorType::Rgba, rgba, dpi)
}

/// Encodes the canvas as an opaque RGB PNG.
pub(crate) fn encode_png_rgb(canvas: &RasterCanvas, dpi: Option<f64>) -> Result<Vec<u8>> {
    let (w, h) = canvas.size();
    let mut rgb = Vec::with_capacity((w * h * 3) as usize);
    for p in canvas.pixmap.pixels() {
        // The canvas starts opaque white and every paint composites over it: alpha is 255.
        rgb.extend_from_slice(&[p.red(), p.green(), p.blue()]);
    }
    encode_png(w, h, png::ColorType::Rgb, &rgb, dpi)
}

/// Encodes `w × h` pixels of 8-bit channels laid out as `color` (row-major, no padding) as PNG
/// with fast compression, recording the resolution when `dpi` (dots per inch) is given (PNG's
/// `pHYs` chunk, in pixels per metre).
fn encode_png(
    w: u32,
    h: u32,
    color: png::ColorType,
    data: &[u8],
    dpi: Option<f64>,
) -> Result<Vec<u8>> {
    let encode_error = |e: png::EncodingError| PlotError::Encode {
        format: "PNG",
        message: e.to_string(),
    };
    let mut buf = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut buf, w, h);
        enc.set_color(color);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Fast);
        if let Some(dpi) = dpi {
            let ppm = (dpi / 0.0254).round() as u32;
            enc.set_pixel_dims(Some(png::PixelDimensions {
                xppu: ppm,
                yppu: ppm,
                unit: png::Unit::Meter,
            }));
        }
        let mut wr = enc.write_header().map_err(encode_error)?;
        wr.write_image_data(data).map_err(encode_error)?;
    }
    Ok(buf)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648_vectors() {
        // RFC 4648 §10 test vectors.
        for (i, o) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(i.as_bytes()), o);
        }
    }

    #[test]
    fn numbers_are_short() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(1.2345), "1.23");
        assert_eq!(num(-0.001), "0");
        assert_eq!(num(10.5), "10.5");
    }
}
