//! 3-D surfaces z = f(x, y) (MATLAB `surf`), drawn in parallel projection with a box, back-wall
//! grids and ticks.

use crate::axes::{LABEL_FONT, TICK_FONT, TITLE_FONT};
use crate::canvas::{Canvas, HAlign, TextStyle, VAlign};
use crate::color::{Color, ColorMap};
use crate::error::{PlotError, Result};
use crate::geometry::Rect;
use crate::style::LineStyle;
use crate::ticks::linear_ticks;

/// A projected face: depth, corners in pixels, colour.
type Face = (f64, [(f64, f64); 4], Color);

/// A surface over a rectangular grid: `z[j * nx + i]` is the height at `(x[i], y[j])`.
///
/// The view follows MATLAB's `view(az, el)`: azimuth measured from the −y axis, positive
/// counter-clockwise seen from above, elevation above the x–y plane, both in degrees (default
/// −37.5°, 30°, MATLAB's 3-D default). Faces are coloured by height with a colour map and
/// outlined like `surf`'s mesh. Non-finite heights leave their faces out.
///
/// ```
/// use pendulab_plot::{Figure, Surface};
/// // The Lyapunov function V = x1² + x2² of the book (p1c43_lyapunov_func).
/// let s = Surface::from_fn((-5.0, 5.0), (-5.0, 5.0), 21, 21, |x1, x2| x1 * x1 + x2 * x2)
///     .labels("x₁", "x₂", "V(x)");
/// let svg = Figure::new(s).to_svg().unwrap();
/// assert!(svg.contains("V(x)"));
/// ```
#[derive(Debug, Clone)]
pub struct Surface {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    labels: [String; 3],
    title: Option<String>,
    azimuth: f64,
    elevation: f64,
    map: ColorMap,
}

impl Surface {
    /// A surface from grid coordinates and heights (`z.len() == x.len() * y.len()`, checked when
    /// rendered).
    pub fn new(x: &[f64], y: &[f64], z: &[f64]) -> Self {
        Self {
            x: x.to_vec(),
            y: y.to_vec(),
            z: z.to_vec(),
            labels: ["x".into(), "y".into(), "z".into()],
            title: None,
            azimuth: -37.5,
            elevation: 30.0,
            map: ColorMap::Parula,
        }
    }
    /// Samples `f(x, y)` on an `nx × ny` grid spanning the ranges (ends included).
    pub fn from_fn(
        x_range: (f64, f64),
        y_range: (f64, f64),
        nx: usize,
        ny: usize,
        f: impl Fn(f64, f64) -> f64,
    ) -> Self {
        let lin = |(a, b): (f64, f64), n: usize| -> Vec<f64> {
            (0..n)
                .map(|k| {
                    if n > 1 {
                        a + (b - a) * k as f64 / (n - 1) as f64
                    } else {
                        a
                    }
                })
                .collect()
        };
        let x = lin(x_range, nx);
        let y = lin(y_range, ny);
        let mut z = Vec::with_capacity(nx * ny);
        for &yv in &y {
            for &xv in &x {
                z.push(f(xv, yv));
            }
        }
        Self::new(&x, &y, &z)
    }
    /// Axis labels (with units).
    pub fn labels(mut self, x: &str, y: &str, z: &str) -> Self {
        self.labels = [x.into(), y.into(), z.into()];
        self
    }
    /// Panel title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// Viewpoint: azimuth and elevation in degrees (MATLAB `view(az, el)`).
    pub fn view(mut self, azimuth: f64, elevation: f64) -> Self {
        self.azimuth = azimuth;
        self.elevation = elevation;
        self
    }
    /// Colour map of the faces (default [`ColorMap::Parula`]).
    pub fn color_map(mut self, map: ColorMap) -> Self {
        self.map = map;
        self
    }

    pub(crate) fn check(&self, panel: usize) -> Result<()> {
        let what = format!("panel {panel}, surface");
        let (nx, ny) = (self.x.len(), self.y.len());
        if nx < 2 || ny < 2 {
            return Err(PlotError::InvalidArgument(format!(
                "{what}: needs at least 2 x 2 grid points, got {nx} x {ny}"
            )));
        }
        if self.z.len() != nx * ny {
            return Err(PlotError::LengthMismatch {
                what: format!("{what} (heights vs x·y = {nx}·{ny})"),
                left: self.z.len(),
                right: nx * ny,
            });
        }
        for (name, v) in [("x", &self.x), ("y", &self.y)] {
            if let Some(i) = v.iter().position(|a| !a.is_finite()) {
                return Err(PlotError::NonFinite {
                    what: format!("{what} ({name} grid)"),
                    index: i,
                    value: v[i],
                });
            }
            if v.windows(2).any(|w| w[1] <= w[0]) {
                return Err(PlotError::InvalidArgument(format!(
                    "{what}: {name} grid must be strictly increasing"
                )));
            }
        }
        if !self.z.iter().any(|v| v.is_finite()) {
            return Err(PlotError::NothingToDraw {
                what,
                reason: "every height is NaN or infinite".into(),
            });
        }
        if !(self.azimuth.is_finite() && self.elevation.is_finite()) {
            return Err(PlotError::InvalidArgument(format!(
                "{what}: view angles must be finite"
            )));
        }
        Ok(())
    }

    pub(crate) fn draw(&self, c: &mut dyn Canvas, outer: Rect) -> Result<()> {
        let (nx, ny) = (self.x.len(), self.y.len());
        let xr = (self.x[0], self.x[nx - 1]);
        let yr = (self.y[0], self.y[ny - 1]);
        let (mut zlo, mut zhi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in self.z.iter().filter(|v| v.is_finite()) {
            zlo = zlo.min(*v);
            zhi = zhi.max(*v);
        }
        if zhi <= zlo {
            zlo -= 0.5;
            zhi += 0.5;
        }
        let zt = linear_ticks(zlo, zhi, 5);
        // The z box spans whole ticks.
        let step = if zt.major.len() >= 2 {
            zt.major[1].0 - zt.major[0].0
        } else {
            zhi - zlo
        };
        let zr = ((zlo / step).floor() * step, (zhi / step).ceil() * step);
        let zt = linear_ticks(zr.0, zr.1, 5);
        let xt = linear_ticks(xr.0, xr.1, 5);
        let yt = linear_ticks(yr.0, yr.1, 5);

        let (az, el) = (self.azimuth.to_radians(), self.elevation.to_radians());
        let right = (az.cos(), az.sin(), 0.0);
        let up = (-el.sin() * az.sin(), el.sin() * az.cos(), el.cos());
        let toward = (el.cos() * az.sin(), -el.cos() * az.cos(), el.sin());
        let hz = 0.8; // box half-height relative to the half-widths
        let norm = |x: f64, y: f64, z: f64| -> (f64, f64, f64) {
            (
                2.0 * (x - xr.0) / (xr.1 - xr.0) - 1.0,
                2.0 * (y - yr.0) / (yr.1 - yr.0) - 1.0,
                hz * (2.0 * (z - zr.0) / (zr.1 - zr.0) - 1.0),
            )
        };
        let dot = |a: (f64, f64, f64), b: (f64, f64, f64)| a.0 * b.0 + a.1 * b.1 + a.2 * b.2;
        // Fit the projected box into the panel.
        let mut title_h = 0.0;
        if self.title.is_some() {
            title_h = TITLE_FONT * 1.8;
        }
        let inner = Rect {
            x0: outer.x0 + 55.0,
            y0: outer.y0 + 12.0 + title_h,
            x1: outer.x1 - 40.0,
            y1: outer.y1 - 45.0,
        };
        let mut corners: Vec<(f64, f64, f64)> = Vec::with_capacity(8);
        for a in [-1.0, 1.0] {
            for b in [-1.0, 1.0] {
                for z in [-hz, hz] {
                    corners.push((a, b, z));
                }
            }
        }
        let (mut sx0, mut sx1, mut sy0, mut sy1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for &p in &corners {
            let (u, v) = (dot(p, right), dot(p, up));
            sx0 = sx0.min(u);
            sx1 = sx1.max(u);
            sy0 = sy0.min(v);
            sy1 = sy1.max(v);
        }
        let scale = (inner.w() / (sx1 - sx0)).min(inner.h() / (sy1 - sy0));
        let cx = 0.5 * (inner.x0 + inner.x1) - scale * 0.5 * (sx0 + sx1);
        let cy = 0.5 * (inner.y0 + inner.y1) + scale * 0.5 * (sy0 + sy1);
        let proj = |p: (f64, f64, f64)| -> (f64, f64) {
            (cx + scale * dot(p, right), cy - scale * dot(p, up))
        };
        let centre = proj((0.0, 0.0, 0.0));

        // Back walls: the side of each axis farther from the viewer.
        let xb = if toward.0 > 0.0 { -1.0 } else { 1.0 };
        let yb = if toward.1 > 0.0 { -1.0 } else { 1.0 };
        let zb = if toward.2 > 0.0 { -hz } else { hz };
        let grid = LineStyle::new(Color::rgb(215, 215, 215), 0.7);
        let edge = LineStyle::new(Color::rgb(60, 60, 60), 0.9);
        let wall = Color::rgb(250, 250, 250);
        let quad =
            |a: (f64, f64, f64), b: (f64, f64, f64), cc: (f64, f64, f64), d: (f64, f64, f64)| {
                vec![proj(a), proj(b), proj(cc), proj(d)]
            };
        c.polygon(
            &quad(
                (xb, -1.0, -hz),
                (xb, 1.0, -hz),
                (xb, 1.0, hz),
                (xb, -1.0, hz),
            ),
            Some(wall),
            Some(&edge),
        );
        c.polygon(
            &quad(
                (-1.0, yb, -hz),
                (1.0, yb, -hz),
                (1.0, yb, hz),
                (-1.0, yb, hz),
            ),
            Some(wall),
            Some(&edge),
        );
        c.polygon(
            &quad(
                (-1.0, -1.0, zb),
                (1.0, -1.0, zb),
                (1.0, 1.0, zb),
                (-1.0, 1.0, zb),
            ),
            Some(wall),
            Some(&edge),
        );
        for (v, _) in &xt.major {
            let u = norm(*v, yr.0, zr.0).0;
            c.polyline(&[proj((u, yb, -hz)), proj((u, yb, hz))], &grid);
            c.polyline(&[proj((u, -1.0, zb)), proj((u, 1.0, zb))], &grid);
        }
        for (v, _) in &yt.major {
            let u = norm(xr.0, *v, zr.0).1;
            c.polyline(&[proj((xb, u, -hz)), proj((xb, u, hz))], &grid);
            c.polyline(&[proj((-1.0, u, zb)), proj((1.0, u, zb))], &grid);
        }
        for (v, _) in &zt.major {
            let u = norm(xr.0, yr.0, *v).2;
            c.polyline(&[proj((xb, -1.0, u)), proj((xb, 1.0, u))], &grid);
            c.polyline(&[proj((-1.0, yb, u)), proj((1.0, yb, u))], &grid);
        }

        // Faces, far to near (painter's algorithm).
        let mut faces: Vec<Face> = Vec::with_capacity((nx - 1) * (ny - 1));
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let idx = [
                    j * nx + i,
                    j * nx + i + 1,
                    (j + 1) * nx + i + 1,
                    (j + 1) * nx + i,
                ];
                let zs: Vec<f64> = idx.iter().map(|&k| self.z[k]).collect();
                if zs.iter().any(|v| !v.is_finite()) {
                    continue;
                }
                let pts = [
                    norm(self.x[i], self.y[j], zs[0]),
                    norm(self.x[i + 1], self.y[j], zs[1]),
                    norm(self.x[i + 1], self.y[j + 1], zs[2]),
                    norm(self.x[i], self.y[j + 1], zs[3]),
                ];
                let depth = pts.iter().map(|p| dot(*p, toward)).sum::<f64>() / 4.0;
                let zm = zs.iter().sum::<f64>() / 4.0;
                let col = self.map.at((zm - zr.0) / (zr.1 - zr.0));
                faces.push((
                    depth,
                    [proj(pts[0]), proj(pts[1]), proj(pts[2]), proj(pts[3])],
                    col,
                ));
            }
        }
        faces.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mesh = LineStyle::new(Color::rgba(30, 30, 30, 150), 0.5);
        for (_, q, col) in &faces {
            c.polygon(q, Some(*col), Some(&mesh));
        }

        // Axes on the front edges, tick labels pushed away from the box centre.
        let xf = -xb;
        let yf = -yb;
        let tick_text = |c: &mut dyn Canvas, p: (f64, f64), s: &str| {
            let (dx, dy) = (p.0 - centre.0, p.1 - centre.1);
            let n = (dx * dx + dy * dy).sqrt().max(1e-9);
            let q = (p.0 + 12.0 * dx / n, p.1 + 12.0 * dy / n);
            let h = if dx / n > 0.35 {
                HAlign::Left
            } else if dx / n < -0.35 {
                HAlign::Right
            } else {
                HAlign::Center
            };
            c.text(s, q, &TextStyle::new(TICK_FONT, h, VAlign::Center));
        };
        let label_at = |c: &mut dyn Canvas, p: (f64, f64), s: &str| {
            let (dx, dy) = (p.0 - centre.0, p.1 - centre.1);
            let n = (dx * dx + dy * dy).sqrt().max(1e-9);
            let q = (p.0 + 34.0 * dx / n, p.1 + 34.0 * dy / n);
            c.text(
                s,
                q,
                &TextStyle::new(LABEL_FONT, HAlign::Center, VAlign::Center),
            );
        };
        let zfloor = -hz;
        c.polyline(&[proj((-1.0, yf, zfloor)), proj((1.0, yf, zfloor))], &edge);
        c.polyline(&[proj((xf, -1.0, zfloor)), proj((xf, 1.0, zfloor))], &edge);
        for (v, s) in &xt.major {
            let u = norm(*v, yr.0, zr.0).0;
            tick_text(c, proj((u, yf, zfloor)), s);
        }
        for (v, s) in &yt.major {
            let u = norm(xr.0, *v, zr.0).1;
            tick_text(c, proj((xf, u, zfloor)), s);
        }
        label_at(c, proj((0.0, yf, zfloor)), &self.labels[0]);
        label_at(c, proj((xf, 0.0, zfloor)), &self.labels[1]);
        // z axis on the vertical edge that is leftmost on screen.
        let mut zx = (-1.0, -1.0);
        let mut best = f64::INFINITY;
        for (a, b) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
            let sx = proj((a, b, 0.0)).0;
            if sx < best {
                best = sx;
                zx = (a, b);
            }
        }
        c.polyline(&[proj((zx.0, zx.1, -hz)), proj((zx.0, zx.1, hz))], &edge);
        let mut zw: f64 = 0.0;
        for (v, s) in &zt.major {
            let u = norm(xr.0, yr.0, *v).2;
            let p = proj((zx.0, zx.1, u));
            c.text(
                s,
                (p.0 - 8.0, p.1),
                &TextStyle::new(TICK_FONT, HAlign::Right, VAlign::Center),
            );
            zw = zw.max(c.text_width(s, TICK_FONT));
        }
        let pm = proj((zx.0, zx.1, 0.0));
        let mut ts = TextStyle::new(LABEL_FONT, HAlign::Center, VAlign::Bottom);
        ts.vertical = true;
        c.text(&self.labels[2], (pm.0 - 8.0 - zw - 8.0, pm.1), &ts);
        if let Some(t) = &self.title {
            c.text(
                t,
                ((outer.x0 + outer.x1) / 2.0, outer.y0 + 8.0 + TITLE_FONT),
                &TextStyle::new(TITLE_FONT, HAlign::Center, VAlign::Baseline),
            );
        }
        Ok(())
    }
}
