//! Data limits and scales of a panel: automatic limits from the series, padding and rounding
//! to nice values, and the tick positions on linear and logarithmic axes.
//!
//! Neighbours: [`super`] holds the panel's builder API; `check.rs` validates the panel;
//! `layout.rs` computes the margins; `draw.rs` draws the panel with the primitives of
//! `marks.rs`.

use super::{Axes, Kind, RegionBound, Scale, finite_pairs, widen};
use crate::geometry::Rect;
use crate::ticks::{Ticks, linear_ticks, log_ticks, nice_limits};

impl Axes {
    /// Data limits before layout: (x, y), each tight or padded.
    fn auto_limits(&self) -> ((f64, f64), (f64, f64), bool, bool, bool) {
        let (xlog, ylog) = (self.xscale == Scale::Log, self.yscale == Scale::Log);
        let mut bx: Option<(f64, f64)> = None;
        let mut by: Option<(f64, f64)> = None;
        let mut x_tight = false;
        let mut y_tight = false;
        let mut has_region = false;
        for s in &self.series {
            match &s.kind {
                Kind::Line { x, y } | Kind::Steps { x, y } => {
                    x_tight = true;
                    for (a, b) in finite_pairs(x, y, xlog, ylog) {
                        widen(&mut bx, a);
                        widen(&mut by, b);
                    }
                }
                Kind::Scatter { x, y } | Kind::Fill { x, y } => {
                    for (a, b) in finite_pairs(x, y, xlog, ylog) {
                        widen(&mut bx, a);
                        widen(&mut by, b);
                    }
                }
                Kind::Bars { x, h } => {
                    let dx = min_spacing(x) * 0.5;
                    for (a, b) in finite_pairs(x, h, xlog, ylog) {
                        widen(&mut bx, a - dx);
                        widen(&mut bx, a + dx);
                        widen(&mut by, b);
                    }
                    if !ylog {
                        widen(&mut by, 0.0);
                    }
                }
                Kind::Band { x, lo, hi } => {
                    x_tight = true;
                    for (a, b) in
                        finite_pairs(x, lo, xlog, ylog).chain(finite_pairs(x, hi, xlog, ylog))
                    {
                        widen(&mut bx, a);
                        widen(&mut by, b);
                    }
                }
                Kind::HLine(v) => widen(&mut by, *v),
                Kind::VLine(v) => widen(&mut bx, *v),
                Kind::Text { x, y, .. } => {
                    widen(&mut bx, *x);
                    widen(&mut by, *y);
                }
                Kind::Region(bounds) => {
                    has_region = true;
                    for b in bounds {
                        match *b {
                            RegionBound::DecayRate(a) => {
                                widen(&mut bx, -a);
                                widen(&mut bx, 0.0);
                            }
                            RegionBound::SpeedLimit(b) => {
                                widen(&mut bx, -b);
                                widen(&mut by, -0.25 * b);
                                widen(&mut by, 0.25 * b);
                            }
                            RegionBound::Sector(_) => widen(&mut bx, 0.0),
                            RegionBound::Disk { center, radius } => {
                                widen(&mut bx, center - radius);
                                widen(&mut bx, center + radius);
                                widen(&mut by, -radius);
                                widen(&mut by, radius);
                            }
                        }
                    }
                }
                Kind::Cells(c) => {
                    x_tight = true;
                    y_tight = true;
                    widen(&mut bx, c.x_range.0);
                    widen(&mut bx, c.x_range.1);
                    widen(&mut by, c.y_range.0);
                    widen(&mut by, c.y_range.1);
                }
            }
        }
        if has_region {
            x_tight = false;
        }
        // Bars standing on zero keep zero as the frame's edge.
        let bars_floor = self.series.iter().any(|s| matches!(&s.kind, Kind::Bars { h, .. } if h.iter().all(|v| !v.is_finite() || *v >= 0.0)));
        if bars_floor && let Some((lo, _)) = by.as_mut() {
            *lo = lo.max(0.0);
        }
        let bx = bx.unwrap_or((0.0, 1.0));
        let by = by.unwrap_or((0.0, 1.0));
        (bx, by, x_tight, y_tight, bars_floor)
    }

    fn finish_limits(
        raw: (f64, f64),
        tight: bool,
        log: bool,
        pad: f64,
        target: usize,
    ) -> (f64, f64) {
        let (mut lo, mut hi) = raw;
        if log {
            if hi <= lo * 1.0001 {
                lo /= 10.0;
                hi *= 10.0;
            }
            if tight {
                return (lo, hi);
            }
            return (
                10f64.powf((lo.log10() + 1e-9).floor()),
                10f64.powf((hi.log10() - 1e-9).ceil()),
            );
        }
        if hi - lo <= 1e-12 * lo.abs().max(hi.abs()).max(1e-300) {
            let d = if lo == 0.0 { 1.0 } else { 0.5 * lo.abs() };
            lo -= d;
            hi += d;
            return nice_limits(lo, hi, target);
        }
        if tight {
            return (lo, hi);
        }
        // Pad a little, then widen to half-tick multiples: the data never touches the frame
        // and little space is wasted.
        let d = (hi - lo) * pad;
        let step = crate::ticks::nice_step((hi - lo + 2.0 * d) / target.max(1) as f64);
        crate::ticks::snap_limits(lo - d, hi + d, step / 2.0)
    }

    pub(super) fn limits(&self, rect: &Rect) -> ((f64, f64), (f64, f64)) {
        let (xlog, ylog) = (self.xscale == Scale::Log, self.yscale == Scale::Log);
        let (bx, by, xt, yt, floor) = self.auto_limits();
        let tx = x_target(rect.w());
        let ty = y_target(rect.h());
        let pad = if self.equal_aspect { 0.08 } else { 0.025 };
        let mut x = self
            .xlim
            .unwrap_or_else(|| Self::finish_limits(bx, xt, xlog, pad, tx));
        let mut y = self
            .ylim
            .unwrap_or_else(|| Self::finish_limits(by, yt, ylog, pad, ty));
        if floor && self.ylim.is_none() && !ylog && by.0 >= 0.0 {
            y.0 = y.0.max(0.0);
        }
        if let (Some(st), None, Scale::Linear) = (self.y_step, self.ylim, self.yscale) {
            y = crate::ticks::snap_limits(by.0, by.1, st);
            if y.1 - y.0 < st {
                y = (y.0 - st / 2.0, y.1 + st / 2.0);
            }
        }
        if self.equal_aspect && !xlog && !ylog && rect.w() > 0.0 && rect.h() > 0.0 {
            let ux = (x.1 - x.0) / rect.w();
            let uy = (y.1 - y.0) / rect.h();
            if ux > uy && self.ylim.is_none() {
                let c = 0.5 * (y.0 + y.1);
                let h = 0.5 * ux * rect.h();
                y = (c - h, c + h);
            } else if uy > ux && self.xlim.is_none() {
                let c = 0.5 * (x.0 + x.1);
                let h = 0.5 * uy * rect.w();
                x = (c - h, c + h);
            }
        }
        (x, y)
    }

    pub(super) fn ticks(&self, x: (f64, f64), y: (f64, f64), rect: &Rect) -> (Ticks, Ticks) {
        let xt = match (self.xscale, self.x_step) {
            (Scale::Linear, Some(st)) => crate::ticks::stepped_ticks(x.0, x.1, st),
            (Scale::Linear, None) => linear_ticks(x.0, x.1, x_target(rect.w())),
            (Scale::Log, _) => log_ticks(x.0, x.1, (rect.w() / 45.0) as usize),
        };
        let yt = match (self.yscale, self.y_step) {
            (Scale::Linear, Some(st)) => crate::ticks::stepped_ticks(y.0, y.1, st),
            (Scale::Linear, None) => linear_ticks(y.0, y.1, y_target(rect.h())),
            (Scale::Log, _) => log_ticks(y.0, y.1, (rect.h() / 30.0) as usize),
        };
        (xt, yt)
    }
}

fn x_target(w: f64) -> usize {
    ((w / 80.0) as usize).clamp(3, 10)
}
fn y_target(h: f64) -> usize {
    ((h / 48.0) as usize).clamp(2, 8)
}

pub(super) fn min_spacing(x: &[f64]) -> f64 {
    let mut v: Vec<f64> = x.iter().copied().filter(|a| a.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    let d = v
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .fold(f64::INFINITY, f64::min);
    if d.is_finite() { d } else { 1.0 }
}
