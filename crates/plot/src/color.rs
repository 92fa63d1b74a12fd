//! Colours, the default series palette and the colour maps of heat maps and surfaces.

/// An sRGB colour with opacity (`a` = 0 transparent … 255 opaque).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Color {
    /// Red, 0–255.
    pub r: u8,
    /// Green, 0–255.
    pub g: u8,
    /// Blue, 0–255.
    pub b: u8,
    /// Opacity, 0–255.
    pub a: u8,
}

impl Color {
    /// An opaque colour.
    pub const fn rgb(r: u8, g: u8, b: u8) -> Self {
        Self { r, g, b, a: 255 }
    }
    /// A colour with opacity `a` (0–255).
    pub const fn rgba(r: u8, g: u8, b: u8, a: u8) -> Self {
        Self { r, g, b, a }
    }
    /// The same colour with opacity `alpha` in [0, 1] (clamped).
    pub fn with_alpha(self, alpha: f64) -> Self {
        Self {
            a: (alpha.clamp(0.0, 1.0) * 255.0).round() as u8,
            ..self
        }
    }
    /// Linear blend `self·(1−s) + other·s` of the colour channels, `s` in [0, 1] (clamped).
    pub fn mix(self, other: Color, s: f64) -> Self {
        let s = s.clamp(0.0, 1.0);
        let m = |a: u8, b: u8| (a as f64 * (1.0 - s) + b as f64 * s).round() as u8;
        Self {
            r: m(self.r, other.r),
            g: m(self.g, other.g),
            b: m(self.b, other.b),
            a: m(self.a, other.a),
        }
    }
    /// `#rrggbb` (opacity is written separately).
    pub fn hex(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.r, self.g, self.b)
    }
    /// Opacity as a fraction in [0, 1].
    pub fn alpha(self) -> f64 {
        self.a as f64 / 255.0
    }

    /// Blue `#0072bd` (first series).
    pub const BLUE: Color = Color::rgb(0, 114, 189);
    /// Red `#d62728` (second series).
    pub const RED: Color = Color::rgb(214, 39, 40);
    /// Green `#2ca02c` (third series).
    pub const GREEN: Color = Color::rgb(44, 160, 44);
    /// Purple `#7e2f8e`.
    pub const PURPLE: Color = Color::rgb(126, 47, 142);
    /// Orange `#e6830f`.
    pub const ORANGE: Color = Color::rgb(230, 131, 15);
    /// Cyan `#17a2c8`.
    pub const CYAN: Color = Color::rgb(23, 162, 200);
    /// Brown `#8c564b`.
    pub const BROWN: Color = Color::rgb(140, 86, 75);
    /// Magenta `#c8379b`.
    pub const MAGENTA: Color = Color::rgb(200, 55, 155);
    /// Black.
    pub const BLACK: Color = Color::rgb(0, 0, 0);
    /// Dark grey `#404040` (reference lines, frames of scenes).
    pub const DARK_GREY: Color = Color::rgb(64, 64, 64);
    /// Grey `#808080` (measured data under a model curve).
    pub const GREY: Color = Color::rgb(128, 128, 128);
    /// Light grey `#d9d9d9` (grids).
    pub const LIGHT_GREY: Color = Color::rgb(217, 217, 217);
    /// White.
    pub const WHITE: Color = Color::rgb(255, 255, 255);
}

/// The colours given in turn to series without an explicit colour: saturated, distinguishable in
/// print and by most colour-blind readers when combined with the line styles.
pub const PALETTE: [Color; 8] = [
    Color::BLUE,
    Color::RED,
    Color::GREEN,
    Color::PURPLE,
    Color::ORANGE,
    Color::CYAN,
    Color::BROWN,
    Color::MAGENTA,
];

/// The `i`-th palette colour (cycling).
pub fn palette(i: usize) -> Color {
    PALETTE[i % PALETTE.len()]
}

/// A continuous colour map from [0, 1] to colours.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ColorMap {
    /// Perceptually uniform dark blue → green → yellow (matplotlib's *viridis*, sampled at nine
    /// points and interpolated linearly).
    #[default]
    Viridis,
    /// MATLAB's *parula*-like blue → cyan → yellow, sampled at seven points.
    Parula,
    /// White → dark blue, for maps of a non-negative quantity.
    Blues,
}

const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (71, 44, 122),
    (59, 81, 139),
    (44, 113, 142),
    (33, 144, 141),
    (39, 173, 129),
    (92, 200, 99),
    (170, 220, 50),
    (253, 231, 37),
];
const PARULA: [(u8, u8, u8); 7] = [
    (53, 42, 135),
    (15, 92, 221),
    (18, 125, 216),
    (7, 156, 207),
    (21, 177, 180),
    (89, 189, 140),
    (249, 251, 14),
];
const BLUES: [(u8, u8, u8); 5] = [
    (247, 251, 255),
    (198, 219, 239),
    (107, 174, 214),
    (33, 113, 181),
    (8, 48, 107),
];

impl ColorMap {
    /// The colour at `s` in [0, 1] (clamped; NaN gives the low end).
    pub fn at(self, s: f64) -> Color {
        let table: &[(u8, u8, u8)] = match self {
            ColorMap::Viridis => &VIRIDIS,
            ColorMap::Parula => &PARULA,
            ColorMap::Blues => &BLUES,
        };
        let s = if s.is_nan() { 0.0 } else { s.clamp(0.0, 1.0) };
        let pos = s * (table.len() - 1) as f64;
        let i = (pos.floor() as usize).min(table.len() - 2);
        let f = pos - i as f64;
        let (a, b) = (table[i], table[i + 1]);
        Color::rgb(a.0, a.1, a.2).mix(Color::rgb(b.0, b.1, b.2), f)
    }
}
