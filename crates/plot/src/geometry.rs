//! Clipping and decimation in pixel space.

/// An axis-aligned rectangle `x0 ≤ x ≤ x1`, `y0 ≤ y ≤ y1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rect {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

impl Rect {
    pub fn new(x: f64, y: f64, w: f64, h: f64) -> Self {
        Self {
            x0: x,
            y0: y,
            x1: x + w,
            y1: y + h,
        }
    }
    pub fn w(&self) -> f64 {
        self.x1 - self.x0
    }
    pub fn h(&self) -> f64 {
        self.y1 - self.y0
    }
    pub fn contains(&self, p: (f64, f64)) -> bool {
        p.0 >= self.x0 - 1e-9
            && p.0 <= self.x1 + 1e-9
            && p.1 >= self.y0 - 1e-9
            && p.1 <= self.y1 + 1e-9
    }
    pub fn corners(&self) -> Vec<(f64, f64)> {
        vec![
            (self.x0, self.y0),
            (self.x1, self.y0),
            (self.x1, self.y1),
            (self.x0, self.y1),
        ]
    }
}

/// Liang–Barsky clipping of the segment `a`–`b` to `r`; `None` if it lies outside.
pub(crate) fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    r: &Rect,
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let mut t0: f64 = 0.0;
    let mut t1: f64 = 1.0;
    for (p, q) in [
        (-dx, a.0 - r.x0),
        (dx, r.x1 - a.0),
        (-dy, a.1 - r.y0),
        (dy, r.y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
            if t0 > t1 {
                return None;
            }
        }
    }
    Some((
        (a.0 + t0 * dx, a.1 + t0 * dy),
        (a.0 + t1 * dx, a.1 + t1 * dy),
    ))
}

/// Clips a polyline to `r`, returning the visible pieces.
pub(crate) fn clip_polyline(pts: &[(f64, f64)], r: &Rect) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    if pts.len() == 1 && r.contains(pts[0]) {
        return vec![pts.to_vec()];
    }
    for w in pts.windows(2) {
        match clip_segment(w[0], w[1], r) {
            Some((p, q)) => {
                if cur.is_empty() {
                    cur.push(p);
                } else if let Some(last) = cur.last()
                    && ((last.0 - p.0).abs() > 1e-9 || (last.1 - p.1).abs() > 1e-9)
                {
                    out.push(std::mem::take(&mut cur));
                    cur.push(p);
                }
                cur.push(q);
                if q != w[1] {
                    out.push(std::mem::take(&mut cur));
                }
            }
            None => {
                if cur.len() > 1 {
                    out.push(std::mem::take(&mut cur));
                }
                cur.clear();
            }
        }
    }
    if cur.len() > 1 {
        out.push(cur);
    }
    out
}

/// Sutherland–Hodgman clipping of a polygon to the half-plane `a·x + b·y ≤ c`.
pub(crate) fn clip_halfplane(poly: &[(f64, f64)], a: f64, b: f64, c: f64) -> Vec<(f64, f64)> {
    let n = poly.len();
    let mut out = Vec::with_capacity(n + 2);
    if n == 0 {
        return out;
    }
    let f = |p: (f64, f64)| a * p.0 + b * p.1 - c;
    for i in 0..n {
        let p = poly[i];
        let q = poly[(i + 1) % n];
        let (fp, fq) = (f(p), f(q));
        if fp <= 0.0 {
            out.push(p);
        }
        if (fp <= 0.0) != (fq <= 0.0) {
            let t = fp / (fp - fq);
            out.push((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
        }
    }
    out
}

/// Clips a polygon to a rectangle.
pub(crate) fn clip_polygon(poly: &[(f64, f64)], r: &Rect) -> Vec<(f64, f64)> {
    let p = clip_halfplane(poly, -1.0, 0.0, -r.x0);
    let p = clip_halfplane(&p, 1.0, 0.0, r.x1);
    let p = clip_halfplane(&p, 0.0, -1.0, -r.y0);
    clip_halfplane(&p, 0.0, 1.0, r.y1)
}

/// Reduces a polyline to what a screen can show, keeping its envelope.
///
/// Where x never decreases (time series) the points falling in one pixel column are replaced by
/// the first, the lowest, the highest and the last of them in their original order (the "M4"
/// scheme): every peak survives and the drawn pixels are those of the full line. Otherwise points
/// closer than a quarter pixel to the last kept one are dropped.
pub(crate) fn decimate(pts: &[(f64, f64)]) -> Vec<(f64, f64)> {
    if pts.len() < 8 {
        return pts.to_vec();
    }
    let monotone = pts.windows(2).all(|w| w[1].0 >= w[0].0);
    let mut out = Vec::with_capacity(pts.len().min(4096));
    if monotone {
        let mut i = 0;
        while i < pts.len() {
            let col = pts[i].0.floor();
            let mut j = i;
            let (mut imin, mut imax) = (i, i);
            while j < pts.len() && pts[j].0.floor() == col {
                if pts[j].1 < pts[imin].1 {
                    imin = j;
                }
                if pts[j].1 > pts[imax].1 {
                    imax = j;
                }
                j += 1;
            }
            let last = j - 1;
            let mut idx = [i, imin, imax, last];
            idx.sort_unstable();
            let mut prev = usize::MAX;
            for k in idx {
                if k != prev {
                    out.push(pts[k]);
                    prev = k;
                }
            }
            i = j;
        }
    } else {
        out.push(pts[0]);
        for &p in &pts[1..pts.len() - 1] {
            let l = out[out.len() - 1];
            if (p.0 - l.0).powi(2) + (p.1 - l.1).powi(2) >= 0.0625 {
                out.push(p);
            }
        }
        out.push(pts[pts.len() - 1]);
    }
    out
}

/// Douglas–Peucker simplification (Douglas & Peucker 1973): drops points closer than `eps` to
/// the chord of the points kept around them, so the result stays within `eps` of the input.
pub(crate) fn simplify(pts: &[(f64, f64)], eps: f64) -> Vec<(f64, f64)> {
    let n = pts.len();
    if n < 3 {
        return pts.to_vec();
    }
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[n - 1] = true;
    let mut stack = vec![(0usize, n - 1)];
    let eps2 = eps * eps;
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (p, q) = (pts[a], pts[b]);
        let (dx, dy) = (q.0 - p.0, q.1 - p.1);
        let len2 = dx * dx + dy * dy;
        let mut best = (0.0, a);
        for (i, r) in pts.iter().enumerate().take(b).skip(a + 1) {
            let d2 = if len2 > 0.0 {
                let t = ((r.0 - p.0) * dx + (r.1 - p.1) * dy) / len2;
                let t = t.clamp(0.0, 1.0);
                let (ex, ey) = (p.0 + t * dx - r.0, p.1 + t * dy - r.1);
                ex * ex + ey * ey
            } else {
                (r.0 - p.0).powi(2) + (r.1 - p.1).powi(2)
            };
            if d2 > best.0 {
                best = (d2, i);
            }
        }
        if best.0 > eps2 {
            keep[best.1] = true;
            stack.push((a, best.1));
            stack.push((best.1, b));
        }
    }
    pts.iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(p, _)| *p)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_clipping() {
        let r = Rect::new(0.0, 0.0, 10.0, 10.0);
        let (a, b) = clip_segment((-5.0, 5.0), (15.0, 5.0), &r).unwrap();
        assert_eq!((a, b), ((0.0, 5.0), (10.0, 5.0)));
        assert!(clip_segment((-5.0, -1.0), (15.0, -1.0), &r).is_none());
        let pieces = clip_polyline(&[(-1.0, 5.0), (5.0, 5.0), (5.0, 20.0), (6.0, 5.0)], &r);
        assert_eq!(pieces.len(), 2);
    }

    #[test]
    fn decimation_keeps_extremes_of_each_column() {
        // 10 000 samples of a fast oscillation over 100 pixel columns.
        let pts: Vec<(f64, f64)> = (0..10_000)
            .map(|k| {
                let x = k as f64 / 100.0;
                (x, (k as f64 * 0.37).sin() * 50.0)
            })
            .collect();
        let d = decimate(&pts);
        assert!(d.len() <= 400);
        for col in 0..100 {
            let c = col as f64;
            let full: Vec<f64> = pts
                .iter()
                .filter(|p| p.0.floor() == c)
                .map(|p| p.1)
                .collect();
            let kept: Vec<f64> = d.iter().filter(|p| p.0.floor() == c).map(|p| p.1).collect();
            let mx = |v: &[f64]| v.iter().cloned().fold(f64::MIN, f64::max);
            let mn = |v: &[f64]| v.iter().cloned().fold(f64::MAX, f64::min);
            assert_eq!(mx(&full), mx(&kept));
            assert_eq!(mn(&full), mn(&kept));
        }
    }

    #[test]
    fn simplification_stays_within_tolerance() {
        let pts: Vec<(f64, f64)> = (0..5000)
            .map(|k| (k as f64 * 0.1, 100.0 * (k as f64 * 0.002).sin()))
            .collect();
        let s = simplify(&pts, 0.1);
        assert!(s.len() < 500, "{} points kept", s.len());
        // Every input point lies within 0.1 of the kept polyline (checked against its segments).
        for p in pts.iter().step_by(7) {
            let d = s
                .windows(2)
                .map(|w| {
                    let (a, b) = (w[0], w[1]);
                    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                    let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (dx * dx + dy * dy))
                        .clamp(0.0, 1.0);
                    ((a.0 + t * dx - p.0).powi(2) + (a.1 + t * dy - p.1).powi(2)).sqrt()
                })
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 0.1 + 1e-9, "point {p:?} is {d} away");
        }
    }

    #[test]
    fn halfplane_clip_of_square() {
        let sq = vec![(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)];
        let p = clip_halfplane(&sq, 1.0, 0.0, 1.0);
        let area: f64 = (0..p.len())
            .map(|i| {
                let (a, b) = (p[i], p[(i + 1) % p.len()]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum::<f64>()
            / 2.0;
        assert!((area.abs() - 2.0).abs() < 1e-12);
    }
}
