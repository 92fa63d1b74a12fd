//! The rigs' drawing: the view from model coordinates (m) to the picture (px), the colours, the
//! cart body and the rods.

use super::CartGeometry;
use crate::canvas::Canvas;
use crate::color::Color;
use crate::style::LineStyle;

pub(super) struct View {
    pub(super) scale: f64,
    pub(super) cx: f64,
    pub(super) cy: f64,
}

impl View {
    pub(super) fn p(&self, x: f64, y: f64) -> (f64, f64) {
        (self.cx + self.scale * x, self.cy - self.scale * y)
    }
}

pub(super) const RAIL: Color = Color::rgb(120, 120, 120);
pub(super) const DARK: Color = Color::rgb(45, 45, 45);
pub(super) const CART: Color = Color::rgb(70, 130, 190);
pub(super) const ARM: Color = Color::rgb(70, 130, 190);
pub(super) const POST: Color = Color::rgb(170, 170, 170);
pub(super) const ROD: Color = Color::rgb(200, 60, 40);
pub(super) const BOB: Color = Color::rgb(170, 40, 30);

/// Cart body and wheels with the pivot at `p` (pixels).
pub(super) fn draw_cart_body(c: &mut dyn Canvas, p: (f64, f64), g: &CartGeometry, s: f64) {
    let (hw, hh) = (g.cart_width * s / 2.0, g.cart_height * s / 2.0);
    c.rect(
        p.0 - hw,
        p.1 - hh,
        2.0 * hw,
        2.0 * hh,
        Some(CART),
        Some(&LineStyle::new(DARK, 1.2)),
    );
    let r = g.wheel_radius * s;
    for dx in [-0.6 * hw, 0.6 * hw] {
        c.circle((p.0 + dx, p.1 + hh + r), r, Some(DARK), None);
        c.circle((p.0 + dx, p.1 + hh + r), r * 0.35, Some(POST), None);
    }
}

/// Pendulum rod from `a` to `b` with a bob of radius `r` at `b` and a pivot pin at `a`.
pub(super) fn draw_rod(c: &mut dyn Canvas, a: (f64, f64), b: (f64, f64), r: f64) {
    c.polyline(&[a, b], &LineStyle::new(ROD, (0.45 * r).max(2.5)));
    c.circle(b, r.max(3.0), Some(BOB), Some(&LineStyle::new(DARK, 1.0)));
    c.circle(
        a,
        (0.45 * r).max(2.0),
        Some(Color::WHITE),
        Some(&LineStyle::new(DARK, 1.2)),
    );
}
