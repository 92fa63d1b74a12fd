//! The embedded font (DejaVu Sans, Bitstream Vera licence, `assets/LICENSE_DEJAVU`) and text
//! metrics.
//!
//! The font is parsed once, on first use, into a process-wide [`OnceLock`]: any number of threads
//! may render at the same time, and no system font, fontconfig or other system library is read.
//! SVG output names the font family (`DejaVu Sans`, falling back to Verdana and the browser's
//! sans-serif, which share its metrics closely); PNG and GIF output draws the embedded glyph
//! outlines themselves.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, GlyphId, OutlineCurve};

use crate::error::{PlotError, Result};

static FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static FONT: OnceLock<Option<FontRef<'static>>> = OnceLock::new();

/// The CSS font stack written into SVG files.
pub(crate) const SVG_FONT_FAMILY: &str =
    "'DejaVu Sans', Verdana, 'Bitstream Vera Sans', sans-serif";

/// The parsed embedded font.
///
/// # Errors
/// [`PlotError::Font`] if the embedded bytes do not parse (a defect of the build, caught by the
/// crate's tests).
pub(crate) fn font() -> Result<&'static FontRef<'static>> {
    FONT.get_or_init(|| FontRef::try_from_slice(FONT_BYTES).ok())
        .as_ref()
        .ok_or(PlotError::Font)
}

/// Checks that the embedded font is usable. Calling it is optional (every renderer does it);
/// it is cheap after the first call and safe from any thread.
///
/// # Errors
/// [`PlotError::Font`] as for rendering.
pub fn ensure_font() -> Result<()> {
    font().map(|_| ())
}

/// Font units → pixels factor for an em of `size` pixels.
fn units(f: &FontRef<'static>, size: f64) -> f64 {
    size / f.units_per_em().unwrap_or(2048.0) as f64
}

/// Width in pixels of `text` set at `size` px per em (advances plus kerning).
pub(crate) fn text_width(f: &FontRef<'static>, text: &str, size: f64) -> f64 {
    let s = units(f, size);
    let mut w = 0.0;
    let mut prev: Option<GlyphId> = None;
    for c in text.chars() {
        let g = f.glyph_id(c);
        if let Some(p) = prev {
            w += f.kern_unscaled(p, g) as f64 * s;
        }
        w += f.h_advance_unscaled(g) as f64 * s;
        prev = Some(g);
    }
    w
}

/// Height of capital letters above the baseline, in pixels, at `size` px per em.
pub(crate) fn cap_height(size: f64) -> f64 {
    // DejaVu Sans: cap height 1493 / 2048 em.
    size * 0.729
}

/// Depth of descenders below the baseline, in pixels, at `size` px per em.
pub(crate) fn descent(size: f64) -> f64 {
    // DejaVu Sans: descender 483 / 2048 em.
    size * 0.236
}

/// Glyph outlines of `text` laid out from the origin along +x, baseline at y = 0, y downwards, at
/// `size` px per em: one closed contour list of points per glyph contour, with curves flattened.
pub(crate) fn text_contours(f: &FontRef<'static>, text: &str, size: f64) -> Vec<Vec<(f64, f64)>> {
    let s = units(f, size);
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut pen = 0.0;
    let mut prev: Option<GlyphId> = None;
    // Flattening tolerance: 16 segments per curve is below 0.1 px error at label sizes.
    let steps = if size > 40.0 { 16 } else { 8 };
    for c in text.chars() {
        let g = f.glyph_id(c);
        if let Some(p) = prev {
            pen += f.kern_unscaled(p, g) as f64 * s;
        }
        if let Some(outline) = f.outline(g) {
            let map = |p: ab_glyph::Point| (pen + p.x as f64 * s, -(p.y as f64) * s);
            let mut contour: Vec<(f64, f64)> = Vec::new();
            let mut last: Option<ab_glyph::Point> = None;
            for curve in &outline.curves {
                let (start, end) = match curve {
                    OutlineCurve::Line(a, b) => (*a, *b),
                    OutlineCurve::Quad(a, _, b) => (*a, *b),
                    OutlineCurve::Cubic(a, _, _, b) => (*a, *b),
                };
                if last.is_none_or(|l| l != start) {
                    if contour.len() > 2 {
                        out.push(std::mem::take(&mut contour));
                    }
                    contour.clear();
                    contour.push(map(start));
                }
                match curve {
                    OutlineCurve::Line(_, b) => contour.push(map(*b)),
                    OutlineCurve::Quad(a, c, b) => {
                        for k in 1..=steps {
                            let t = k as f32 / steps as f32;
                            let u = 1.0 - t;
                            let p = ab_glyph::point(
                                u * u * a.x + 2.0 * u * t * c.x + t * t * b.x,
                                u * u * a.y + 2.0 * u * t * c.y + t * t * b.y,
                            );
                            contour.push(map(p));
                        }
                    }
                    OutlineCurve::Cubic(a, c1, c2, b) => {
                        for k in 1..=steps {
                            let t = k as f32 / steps as f32;
                            let u = 1.0 - t;
                            let p = ab_glyph::point(
                                u * u * u * a.x
                                    + 3.0 * u * u * t * c1.x
                                    + 3.0 * u * t * t * c2.x
                                    + t * t * t * b.x,
                                u * u * u * a.y
                                    + 3.0 * u * u * t * c1.y
                                    + 3.0 * u * t * t * c2.y
                                    + t * t * t * b.y,
                            );
                            contour.push(map(p));
                        }
                    }
                }
                last = Some(end);
            }
            if contour.len() > 2 {
                out.push(contour);
            }
        }
        pen += f.h_advance_unscaled(g) as f64 * s;
        prev = Some(g);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn font_parses_from_many_threads() {
        let handles: Vec<_> = (0..4)
            .map(|_| std::thread::spawn(|| ensure_font().is_ok()))
            .collect();
        for h in handles {
            assert!(h.join().unwrap());
        }
        assert!(ensure_font().is_ok());
    }

    #[test]
    fn width_scales_with_size_and_length() {
        let f = font().unwrap();
        let w1 = text_width(f, "time [s]", 10.0);
        let w2 = text_width(f, "time [s]", 20.0);
        // Metrics are linear in the em size (exact up to f32 rounding of the advances).
        assert!((w2 - 2.0 * w1).abs() < 1e-6);
        assert!(text_width(f, "θ₁ [rad]", 12.0) > text_width(f, "θ", 12.0));
        // Greek, subscripts, superscripts and the minus sign all have glyphs in DejaVu Sans.
        for c in ['θ', '₁', '⁻', '²', '−', '°', 'ω', 'φ', '×'] {
            assert_ne!(f.glyph_id(c).0, 0, "missing glyph {c}");
        }
    }
}
