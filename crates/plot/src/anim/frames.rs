//! The GIF encoding's helpers: the fixed palette of the drawing's colours and the box of
//! pixels that changed between frames (the rest transparent).

use super::draw::{BOB, CART, DARK, POST, RAIL, ROD};
use crate::color::Color;

pub(super) const TRANSPARENT: u8 = 255;

/// Fixed GIF palette: the scene colours blended with white in 16 steps, a grey ramp, and a
/// 5-bit-per-channel nearest-colour lookup table.
pub(super) struct Palette {
    pub(super) bytes: Vec<u8>,
    lut: Vec<u8>,
}

impl Palette {
    pub(super) fn new() -> Self {
        let mut cols: Vec<Color> = Vec::new();
        for base in [RAIL, CART, ROD, BOB, POST, Color::rgb(30, 60, 110)] {
            for k in 0..16 {
                cols.push(base.mix(Color::WHITE, k as f64 / 16.0));
            }
        }
        for k in 0..64 {
            let g = (k * 255 / 63) as u8;
            cols.push(Color::rgb(g, g, g));
        }
        // Blends of the rod and bob over the cart and the arm.
        for base in [ROD, BOB, DARK] {
            for k in 1..8 {
                cols.push(base.mix(CART, k as f64 / 8.0));
            }
        }
        cols.truncate(255);
        let mut bytes = Vec::with_capacity(768);
        for c in &cols {
            bytes.extend_from_slice(&[c.r, c.g, c.b]);
        }
        while bytes.len() < 768 {
            bytes.extend_from_slice(&[255, 255, 255]);
        }
        let mut lut = vec![0u8; 32 * 32 * 32];
        for (i, e) in lut.iter_mut().enumerate() {
            // Bin centres spread over the full range, so that 31 maps to 255 (pure white).
            let level = |v: usize| v * 255 / 31;
            let (r, g, b) = (level((i >> 10) & 31), level((i >> 5) & 31), level(i & 31));
            let mut best = (u32::MAX, 0u8);
            for (k, c) in cols.iter().enumerate() {
                let d = (c.r as i32 - r as i32).pow(2) as u32
                    + (c.g as i32 - g as i32).pow(2) as u32
                    + (c.b as i32 - b as i32).pow(2) as u32;
                if d < best.0 {
                    best = (d, k as u8);
                }
            }
            *e = best.1;
        }
        Self { bytes, lut }
    }
    /// Palette indices of an opaque premultiplied RGBA image.
    pub(super) fn index_image(&self, rgba: &[u8]) -> Vec<u8> {
        rgba.chunks_exact(4)
            .map(|p| {
                self.lut[((p[0] as usize >> 3) << 10)
                    | ((p[1] as usize >> 3) << 5)
                    | (p[2] as usize >> 3)]
            })
            .collect()
    }
}

/// Bounding box (x0, y0, x1, y1, inclusive) of the pixels that differ, or `None`.
pub(super) fn changed_box(
    a: &[u8],
    b: &[u8],
    w: usize,
    h: usize,
) -> Option<(usize, usize, usize, usize)> {
    let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
    for y in 0..h {
        let ra = &a[y * w..(y + 1) * w];
        let rb = &b[y * w..(y + 1) * w];
        if ra == rb {
            continue;
        }
        let first = ra.iter().zip(rb).position(|(p, q)| p != q).unwrap_or(0);
        let last = w
            - 1
            - ra.iter()
                .rev()
                .zip(rb.iter().rev())
                .position(|(p, q)| p != q)
                .unwrap_or(0);
        x0 = x0.min(first);
        x1 = x1.max(last);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if x0 == usize::MAX {
        None
    } else {
        Some((x0, y0, x1, y1))
    }
}
