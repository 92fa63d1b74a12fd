//! Line styles and markers.

use crate::color::Color;

/// Dash pattern of a line. Patterns scale with the line width, as in print.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Dash {
    /// Continuous line (MATLAB `'-'`).
    #[default]
    Solid,
    /// Dashes (MATLAB `'--'`).
    Dashed,
    /// Round dots (MATLAB `':'`).
    Dotted,
    /// Dash-dot (MATLAB `'-.'`).
    DashDot,
}

impl Dash {
    /// The on/off lengths in pixels for a line of width `width`, and whether caps are round.
    pub(crate) fn pattern(self, width: f64) -> Option<(Vec<f64>, bool)> {
        let k = width.max(0.8);
        match self {
            Dash::Solid => None,
            Dash::Dashed => Some((vec![4.0 * k, 2.6 * k], false)),
            // Zero-length dashes with round caps draw dots of the line's width.
            Dash::Dotted => Some((vec![0.01, 2.2 * k], true)),
            Dash::DashDot => Some((vec![4.5 * k, 2.0 * k, 0.01, 2.0 * k], true)),
        }
    }
}

/// Marker drawn at each sample of a series.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// Filled circle.
    Dot,
    /// Hollow circle (zeros of a pole–zero map).
    Circle,
    /// Diagonal cross `×` (poles of a pole–zero map).
    Cross,
    /// Plus sign `+`.
    Plus,
    /// Hollow square.
    Square,
    /// Hollow upward triangle.
    Triangle,
}

/// Everything needed to stroke a line: colour, width in pixels (SVG user units) and dash pattern.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineStyle {
    /// Colour.
    pub color: Color,
    /// Width in pixels of the SVG (PNG pixels are this times the PNG scale).
    pub width: f64,
    /// Dash pattern.
    pub dash: Dash,
}

impl LineStyle {
    /// A solid line.
    pub fn new(color: Color, width: f64) -> Self {
        Self {
            color,
            width,
            dash: Dash::Solid,
        }
    }
    /// The same line with another dash pattern.
    pub fn dash(self, dash: Dash) -> Self {
        Self { dash, ..self }
    }
}
