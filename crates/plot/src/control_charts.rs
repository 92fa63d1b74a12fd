//! Ready-made loop-analysis figures: the Nyquist diagram, the root locus, the Nichols chart
//! with its grid and the singular-value plot. They draw numbers computed elsewhere
//! (`pendulab_lti::nyquist`, `rlocus`, `sigma`); the only arithmetic here is layout: the
//! mirror image and clipping of a Nyquist curve, arrow heads, view boxes, and the Nichols
//! grid's closed-form contours (MATLAB `ngrid`).

use crate::axes::{Axes, LegendPos, Scale};
use crate::color::{Color, palette};
use crate::figure::{DEFAULT_WIDTH, Figure};
use crate::style::{Dash, Marker};
use pendulab_lti::Complex64;

/// Chevron arrow heads along `pts` at the given fractions of its arc length, pointing
/// forward along the polyline (reversed if `backward`), `size` in data units.
fn arrows(ax: &mut Axes, pts: &[(f64, f64)], fractions: &[f64], size: f64, color: Color) {
    let seg: Vec<f64> = pts
        .windows(2)
        .map(|p| ((p[1].0 - p[0].0).powi(2) + (p[1].1 - p[0].1).powi(2)).sqrt())
        .map(|d| if d.is_finite() { d } else { 0.0 })
        .collect();
    let total: f64 = seg.iter().sum();
    if total <= 0.0 || size <= 0.0 {
        return;
    }
    for &f in fractions {
        let target = f * total;
        let mut acc = 0.0;
        for (i, &d) in seg.iter().enumerate() {
            if acc + d >= target && d > 0.0 {
                let t = (target - acc) / d;
                let (a, b) = (pts[i], pts[i + 1]);
                let tip = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
                let (ux, uy) = ((b.0 - a.0) / d, (b.1 - a.1) / d);
                let back = |s: f64| {
                    (
                        tip.0 - size * ux + s * size * 0.6 * (-uy),
                        tip.1 - size * uy + s * size * 0.6 * ux,
                    )
                };
                let (l, r) = (back(1.0), back(-1.0));
                ax.plot(&[l.0, tip.0, r.0], &[l.1, tip.1, r.1])
                    .color(color)
                    .width(1.6);
                break;
            }
            acc += d;
        }
    }
}

#[derive(Debug, Clone)]
struct NyquistData {
    label: String,
    response: Vec<Complex64>,
}

/// A Nyquist diagram (MATLAB `nyquist`, python-control `nyquist_plot`): the curve `L(jω)` for
/// `ω ≥ 0` (solid) and its mirror image for `ω ≤ 0` (dashed), arrows in the direction of
/// increasing `ω`, the unit circle (dotted) and the critical point `−1` (red `+`). Points
/// farther than [`Nyquist::max_magnitude`] from the origin (near an indented pole) are drawn
/// on that circle, dotted, as python-control does with its `max_curve_magnitude`.
///
/// ```
/// use pendulab_lti::Complex64;
/// use pendulab_plot::Nyquist;
/// let h: Vec<Complex64> = (0..200)
///     .map(|k| { let s = Complex64::new(0.0, 0.05 * k as f64); 4.0 / ((s + 1.0) * (s + 1.0) * (s + 1.0)) })
///     .collect();
/// let fig = Nyquist::new().curve("L", &h).figure();
/// assert!(fig.to_svg().unwrap().contains("−1"));
/// ```
#[derive(Debug, Clone)]
pub struct Nyquist {
    curves: Vec<NyquistData>,
    max_magnitude: f64,
    title: Option<String>,
}

impl Default for Nyquist {
    fn default() -> Self {
        Self {
            curves: Vec::new(),
            max_magnitude: 20.0,
            title: None,
        }
    }
}

impl Nyquist {
    /// An empty diagram (clipping radius 20, python-control's default).
    pub fn new() -> Self {
        Self::default()
    }
    /// Adds the upper half `response[k] = L(jω_k)`, `ω` ascending from 0 (e.g.
    /// `NyquistCurve::response` of pendulab-lti).
    pub fn curve(mut self, label: impl Into<String>, response: &[Complex64]) -> Self {
        self.curves.push(NyquistData {
            label: label.into(),
            response: response.to_vec(),
        });
        self
    }
    /// Radius beyond which the curve is drawn on the circle of that radius (dotted).
    pub fn max_magnitude(mut self, r: f64) -> Self {
        self.max_magnitude = r;
        self
    }
    /// Figure title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// The figure (checked when rendered).
    pub fn figure(&self) -> Figure {
        let mut ax = Axes::new();
        ax.xlabel("real axis")
            .ylabel("imaginary axis")
            .equal_aspect()
            .legend(LegendPos::Best);
        let r = if self.max_magnitude.is_finite() && self.max_magnitude > 0.0 {
            self.max_magnitude
        } else {
            f64::INFINITY
        };
        let circle: Vec<(f64, f64)> = (0..=180)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 180.0;
                (t.cos(), t.sin())
            })
            .collect();
        let (cx, cy): (Vec<f64>, Vec<f64>) = circle.into_iter().unzip();
        ax.plot(&cx, &cy).color(Color::GREY).dotted().width(1.0);
        ax.hline(0.0).color(Color::LIGHT_GREY).width(0.8);
        ax.vline(0.0).color(Color::LIGHT_GREY).width(0.8);
        // Extent for the arrow size.
        let mut extent: f64 = 1.0;
        for c in &self.curves {
            for z in &c.response {
                let m = z.norm().min(r);
                if m.is_finite() {
                    extent = extent.max(m);
                }
            }
        }
        let size = 0.04 * extent;
        for (k, c) in self.curves.iter().enumerate() {
            let col = palette(k);
            // Split into the unclipped (solid) and clipped (dotted) runs, NaN-separated.
            let clip = |z: &Complex64| -> (Complex64, bool) {
                let m = z.norm();
                if m > r {
                    (z * (r / m), true)
                } else {
                    (*z, false)
                }
            };
            let mut inner = (Vec::new(), Vec::new());
            let mut outer = (Vec::new(), Vec::new());
            let mut prev: Option<bool> = None;
            for z in &c.response {
                let (p, clipped) = clip(z);
                if let Some(pc) = prev
                    && pc != clipped
                {
                    // Join the runs at the boundary point.
                    let (a, b) = if clipped {
                        (&mut inner, &mut outer)
                    } else {
                        (&mut outer, &mut inner)
                    };
                    a.0.push(p.re);
                    a.1.push(p.im);
                    a.0.push(f64::NAN);
                    a.1.push(f64::NAN);
                    b.0.push(p.re);
                    b.1.push(p.im);
                    prev = Some(clipped);
                    continue;
                }
                let t = if clipped { &mut outer } else { &mut inner };
                t.0.push(p.re);
                t.1.push(p.im);
                prev = Some(clipped);
            }
            let mirror =
                |v: &(Vec<f64>, Vec<f64>)| -> Vec<f64> { v.1.iter().map(|y| -y).collect() };
            ax.plot(&inner.0, &inner.1)
                .label(c.label.clone())
                .color(col)
                .width(1.8);
            ax.plot(&inner.0, &mirror(&inner))
                .color(col)
                .dashed()
                .width(1.4);
            if !outer.0.is_empty() {
                ax.plot(&outer.0, &outer.1).color(col).dotted().width(1.4);
                ax.plot(&outer.0, &mirror(&outer))
                    .color(col)
                    .dotted()
                    .width(1.4);
            }
            let pts: Vec<(f64, f64)> = c
                .response
                .iter()
                .filter(|z| z.norm() <= r)
                .map(|z| (z.re, z.im))
                .collect();
            arrows(&mut ax, &pts, &[0.3, 0.7], size, col);
            // The mirror is traversed from ω = −∞ to 0: the conjugate points in reverse.
            let back: Vec<(f64, f64)> = pts.iter().rev().map(|p| (p.0, -p.1)).collect();
            arrows(&mut ax, &back, &[0.3, 0.7], size, col);
        }
        ax.scatter(&[-1.0], &[0.0])
            .marker(Marker::Plus)
            .marker_size(10.0)
            .width(2.0)
            .color(Color::RED);
        ax.text(-1.0 + 0.03 * extent, 0.04 * extent, "−1")
            .color(Color::RED);
        let mut fig = Figure::new(ax).size(DEFAULT_WIDTH, 560.0);
        if let Some(t) = &self.title {
            fig = fig.title(t.clone());
        }
        fig
    }
}

/// A root locus (MATLAB `rlocus`): each branch a line, open-loop poles `×`, zeros `○`,
/// optional asymptotes (dashed rays from the centroid), break points (dots) and points
/// annotated with their gain (square marker and `K = …`); the view covers the poles, zeros,
/// break points and annotations with a margin, and branches leaving it are cut there.
///
/// ```
/// use pendulab_lti::Complex64;
/// use pendulab_plot::RootLocusPlot;
/// // s(s + 2) + K = 0: two branches meeting at −1 and leaving vertically.
/// let rows: Vec<Vec<Complex64>> = (0..50)
///     .map(|k| { let kk = 0.1 * k as f64; let d = Complex64::new(1.0 - kk, 0.0).sqrt();
///                vec![-1.0 + d, -1.0 - d] })
///     .collect();
/// let p = [Complex64::new(0.0, 0.0), Complex64::new(-2.0, 0.0)];
/// let fig = RootLocusPlot::new(&rows).poles(&p).annotate(Complex64::new(-1.0, 1.0), 2.0).figure();
/// assert!(fig.to_svg().unwrap().contains("K = 2"));
/// ```
#[derive(Debug, Clone, Default)]
pub struct RootLocusPlot {
    branches: Vec<Vec<Complex64>>,
    poles: Vec<Complex64>,
    zeros: Vec<Complex64>,
    asymptotes: Option<(f64, Vec<f64>)>,
    break_points: Vec<Complex64>,
    notes: Vec<(Complex64, f64)>,
    discrete: bool,
    title: Option<String>,
}

impl RootLocusPlot {
    /// A locus from `rows[k][b]`, branch `b` at the `k`-th gain (branches matched across rows,
    /// as `RootLocus::roots` of pendulab-lti).
    pub fn new(rows: &[Vec<Complex64>]) -> Self {
        let nb = rows.iter().map(Vec::len).max().unwrap_or(0);
        let branches = (0..nb)
            .map(|b| {
                rows.iter()
                    .map(|r| {
                        r.get(b)
                            .copied()
                            .unwrap_or(Complex64::new(f64::NAN, f64::NAN))
                    })
                    .collect()
            })
            .collect();
        Self {
            branches,
            ..Self::default()
        }
    }
    /// Open-loop poles (`×`).
    pub fn poles(mut self, p: &[Complex64]) -> Self {
        self.poles = p.to_vec();
        self
    }
    /// Open-loop zeros (`○`).
    pub fn zeros(mut self, z: &[Complex64]) -> Self {
        self.zeros = z.to_vec();
        self
    }
    /// Asymptotes: rays from `(centroid, 0)` at `angles` (radians).
    pub fn asymptotes(mut self, centroid: f64, angles: &[f64]) -> Self {
        if centroid.is_finite() && !angles.is_empty() {
            self.asymptotes = Some((centroid, angles.to_vec()));
        }
        self
    }
    /// Break-away / break-in points (dots).
    pub fn break_points(mut self, points: &[Complex64]) -> Self {
        self.break_points = points.to_vec();
        self
    }
    /// Marks `point` with its gain `K` (e.g. from `rlocfind`).
    pub fn annotate(mut self, point: Complex64, gain: f64) -> Self {
        self.notes.push((point, gain));
        self
    }
    /// z-plane: draws the unit circle and labels the axes without units.
    pub fn discrete(mut self) -> Self {
        self.discrete = true;
        self
    }
    /// Figure title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// The figure (checked when rendered).
    pub fn figure(&self) -> Figure {
        let mut ax = Axes::new();
        let (xl, yl) = if self.discrete {
            ("real axis", "imaginary axis")
        } else {
            ("real axis [1/s]", "imaginary axis [1/s]")
        };
        ax.xlabel(xl)
            .ylabel(yl)
            .equal_aspect()
            .legend(LegendPos::Best);
        // View box.
        let mut pts: Vec<Complex64> = self
            .poles
            .iter()
            .chain(&self.zeros)
            .chain(&self.break_points)
            .copied()
            .chain(self.notes.iter().map(|n| n.0))
            .filter(|p| p.re.is_finite() && p.im.is_finite())
            .collect();
        if let Some((c, _)) = &self.asymptotes {
            pts.push(Complex64::new(*c, 0.0));
        }
        if self.discrete {
            pts.push(Complex64::new(1.0, 1.0));
            pts.push(Complex64::new(-1.0, -1.0));
        }
        let (mut x0, mut x1, mut y0, mut y1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for p in &pts {
            x0 = x0.min(p.re);
            x1 = x1.max(p.re);
            y0 = y0.min(p.im);
            y1 = y1.max(p.im);
        }
        if !x0.is_finite() {
            (x0, x1, y0, y1) = (-1.0, 1.0, -1.0, 1.0);
        }
        let span = (x1 - x0).max(y1 - y0).max(1e-3);
        let (mx, my) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let half = 0.5 * span * 1.6 + 0.1 * span;
        let (vx0, vx1, vy0, vy1) = (mx - half, mx + half, my - half, my + half);
        let inside = |p: &Complex64| p.re >= vx0 && p.re <= vx1 && p.im >= vy0 && p.im <= vy1;
        ax.hline(0.0).color(Color::LIGHT_GREY).width(0.8);
        ax.vline(0.0).color(Color::LIGHT_GREY).width(0.8);
        if self.discrete {
            let (cx, cy): (Vec<f64>, Vec<f64>) = (0..=180)
                .map(|k| {
                    let t = k as f64 * std::f64::consts::TAU / 180.0;
                    (t.cos(), t.sin())
                })
                .unzip();
            ax.plot(&cx, &cy).color(Color::GREY).dotted().width(1.0);
        }
        if let Some((c, angles)) = &self.asymptotes {
            for (k, a) in angles.iter().enumerate() {
                let far = 4.0 * half;
                let s = ax.plot(&[*c, c + far * a.cos()], &[0.0, far * a.sin()]);
                s.color(Color::GREY).dashed().width(1.0);
                if k == 0 {
                    s.label("asymptotes");
                }
            }
        }
        for (b, br) in self.branches.iter().enumerate() {
            let (x, y): (Vec<f64>, Vec<f64>) = br
                .iter()
                .map(|p| {
                    if inside(p) {
                        (p.re, p.im)
                    } else {
                        (f64::NAN, f64::NAN)
                    }
                })
                .unzip();
            let s = ax.plot(&x, &y).color(palette(b)).width(1.8);
            if b == 0 {
                s.label("branches");
            }
        }
        if !self.poles.is_empty() {
            ax.poles(&self.poles)
                .label("open-loop poles")
                .color(Color::BLACK);
        }
        if !self.zeros.is_empty() {
            ax.zeros(&self.zeros).label("zeros").color(Color::BLACK);
        }
        if !self.break_points.is_empty() {
            let (x, y): (Vec<f64>, Vec<f64>) =
                self.break_points.iter().map(|p| (p.re, p.im)).unzip();
            ax.scatter(&x, &y)
                .label("break points")
                .color(Color::DARK_GREY);
        }
        for (p, k) in &self.notes {
            ax.scatter(&[p.re], &[p.im])
                .marker(Marker::Square)
                .marker_size(9.0)
                .width(2.0)
                .color(Color::RED);
            ax.text(
                p.re + 0.03 * span,
                p.im + 0.03 * span,
                format!("K = {}", fmt_gain(*k)),
            )
            .color(Color::RED);
        }
        ax.xlim(vx0, vx1).ylim(vy0, vy1);
        let mut fig = Figure::new(ax).size(DEFAULT_WIDTH, 560.0);
        if let Some(t) = &self.title {
            fig = fig.title(t.clone());
        }
        fig
    }
}

/// A gain with four significant digits, without trailing zeros.
fn fmt_gain(k: f64) -> String {
    if k != 0.0 && (k.abs() >= 1e5 || k.abs() < 1e-3) {
        return format!("{k:.3e}");
    }
    let digits = (3 - k.abs().log10().floor() as i32).clamp(0, 6) as usize;
    let s = format!("{k:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[derive(Debug, Clone)]
struct NicholsData {
    label: String,
    phase_deg: Vec<f64>,
    gain_db: Vec<f64>,
}

/// A Nichols chart (MATLAB `nichols` + `ngrid`): open-loop gain (dB) against phase (deg),
/// over the grid of constant closed-loop gain `|T|` (solid grey, labelled in dB) and phase
/// `∠T` (dotted) for `T = L/(1 + L)`, repeated every 360° across the curves' phase range;
/// the critical point `(−180°, 0 dB)` is a red `+`.
///
/// ```
/// use pendulab_plot::Nichols;
/// let ph: Vec<f64> = (0..100).map(|k| -90.0 - 1.5 * k as f64).collect();
/// let g: Vec<f64> = (0..100).map(|k| 20.0 - 0.5 * k as f64).collect();
/// let fig = Nichols::new().curve("L", &ph, &g).figure();
/// assert!(fig.to_svg().unwrap().contains("open-loop phase"));
/// ```
#[derive(Debug, Clone)]
pub struct Nichols {
    curves: Vec<NicholsData>,
    grid: bool,
    title: Option<String>,
}

impl Default for Nichols {
    fn default() -> Self {
        Self {
            curves: Vec::new(),
            grid: true,
            title: None,
        }
    }
}

/// Closed-loop gains (dB) of the grid's M contours (python-control's `nichols_grid` set).
const M_DB: [f64; 13] = [
    -40.0, -20.0, -12.0, -6.0, -3.0, -1.0, -0.5, 0.0, 0.25, 0.5, 1.0, 3.0, 6.0,
];
/// Closed-loop phases (deg) of the grid's N contours.
const N_DEG: [f64; 11] = [
    -1.0, -5.0, -10.0, -20.0, -30.0, -45.0, -60.0, -90.0, -120.0, -150.0, -179.0,
];

impl Nichols {
    /// An empty chart with the grid on.
    pub fn new() -> Self {
        Self::default()
    }
    /// Adds a curve (phase in degrees, gain in dB, e.g. pendulab-lti's `nichols`).
    pub fn curve(mut self, label: impl Into<String>, phase_deg: &[f64], gain_db: &[f64]) -> Self {
        self.curves.push(NicholsData {
            label: label.into(),
            phase_deg: phase_deg.to_vec(),
            gain_db: gain_db.to_vec(),
        });
        self
    }
    /// Draw the closed-loop grid (default on).
    pub fn grid(mut self, on: bool) -> Self {
        self.grid = on;
        self
    }
    /// Figure title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// The figure (checked when rendered).
    pub fn figure(&self) -> Figure {
        let mut ax = Axes::new();
        ax.xlabel("open-loop phase [deg]")
            .ylabel("open-loop gain [dB]")
            .legend(LegendPos::Best)
            .grid(false)
            .x_tick_step(45.0);
        let (mut p0, mut p1, mut g0, mut g1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for c in &self.curves {
            for (p, g) in c.phase_deg.iter().zip(&c.gain_db) {
                if p.is_finite() && g.is_finite() {
                    p0 = p0.min(*p);
                    p1 = p1.max(*p);
                    g0 = g0.min(*g);
                    g1 = g1.max(*g);
                }
            }
        }
        if !p0.is_finite() {
            (p0, p1, g0, g1) = (-360.0, 0.0, -40.0, 20.0);
        }
        // The view: the curves' range with the critical point, gains clipped to −60 … 60 dB
        // around it unless the curves need more.
        let (vp0, vp1) = (
            (p0.min(-180.0) / 45.0).floor() * 45.0,
            (p1.max(-180.0) / 45.0).ceil() * 45.0,
        );
        let (vg0, vg1) = (
            (g0.clamp(-80.0, -20.0) / 10.0).floor() * 10.0,
            (g1.clamp(10.0, 80.0) / 10.0).ceil() * 10.0,
        );
        if self.grid {
            let k0 = ((vp0 + 360.0) / 360.0).floor() as i64 - 1;
            let k1 = (vp1 / 360.0).ceil() as i64 + 1;
            for (i, &m) in M_DB.iter().enumerate() {
                let mag = 10f64.powf(m / 20.0);
                let pts: Vec<Complex64> = (0..=1440)
                    .map(|j| {
                        let psi = (-360.0 + 0.25 * j as f64).to_radians();
                        Complex64::from_polar(mag, psi)
                    })
                    .collect();
                let label = format!("{m} dB");
                self.contour(
                    &mut ax,
                    &pts,
                    k0,
                    k1,
                    Dash::Solid,
                    (vp0, vp1, vg0, vg1),
                    (i == 0).then_some("|T| [dB]"),
                    Some(&label),
                );
            }
            for (i, &n) in N_DEG.iter().enumerate() {
                let pts: Vec<Complex64> = (0..=1200)
                    .map(|j| {
                        Complex64::from_polar(
                            10f64.powf(-4.0 + 8.0 * j as f64 / 1200.0),
                            n.to_radians(),
                        )
                    })
                    .collect();
                self.contour(
                    &mut ax,
                    &pts,
                    k0,
                    k1,
                    Dash::Dotted,
                    (vp0, vp1, vg0, vg1),
                    (i == 0).then_some("∠T"),
                    None,
                );
            }
        }
        for (k, c) in self.curves.iter().enumerate() {
            ax.plot(&c.phase_deg, &c.gain_db)
                .label(c.label.clone())
                .color(palette(k))
                .width(2.0);
        }
        let crit: Vec<f64> = (((vp0 + 180.0) / 360.0).ceil() as i64
            ..=((vp1 + 180.0) / 360.0).floor() as i64)
            .map(|k| -180.0 + 360.0 * k as f64)
            .collect();
        ax.scatter(&crit, &vec![0.0; crit.len()])
            .marker(Marker::Plus)
            .marker_size(10.0)
            .width(2.0)
            .color(Color::RED);
        ax.xlim(vp0, vp1).ylim(vg0, vg1);
        let mut fig = Figure::new(ax).size(DEFAULT_WIDTH, 520.0);
        if let Some(t) = &self.title {
            fig = fig.title(t.clone());
        }
        fig
    }

    /// Draws `L = T/(1 − T)` for the closed-loop values `t`, its phase in `(−360°, 0°]`
    /// shifted by `360° k` for `k0 ≤ k ≤ k1`, cut where the phase wraps; labels at the point
    /// of largest phase inside the view.
    #[allow(clippy::too_many_arguments)]
    fn contour(
        &self,
        ax: &mut Axes,
        t: &[Complex64],
        k0: i64,
        k1: i64,
        dash: Dash,
        view: (f64, f64, f64, f64),
        legend: Option<&str>,
        text: Option<&str>,
    ) {
        let base: Vec<(f64, f64)> = t
            .iter()
            .map(|t| {
                let l = t / (Complex64::new(1.0, 0.0) - t);
                let mut ph = l.arg().to_degrees();
                if ph > 0.0 {
                    ph -= 360.0;
                }
                (ph, 20.0 * l.norm().log10())
            })
            .collect();
        let mut first = true;
        for k in k0..=k1 {
            let (mut x, mut y) = (Vec::new(), Vec::new());
            let mut best: Option<(f64, f64)> = None;
            for (i, &(p, g)) in base.iter().enumerate() {
                if i > 0 && (p - base[i - 1].0).abs() > 180.0 {
                    x.push(f64::NAN);
                    y.push(f64::NAN);
                }
                let (px, gy) = (p + 360.0 * k as f64, g);
                let ok = gy.is_finite() && gy > view.2 - 20.0 && gy < view.3 + 20.0;
                x.push(if ok { px } else { f64::NAN });
                y.push(if ok { gy } else { f64::NAN });
                if px >= view.0
                    && px <= view.1
                    && gy >= view.2
                    && gy <= view.3
                    && best.is_none_or(|b| px > b.0)
                {
                    best = Some((px, gy));
                }
            }
            if x.iter().all(|v| v.is_nan()) {
                continue;
            }
            let s = ax
                .plot(&x, &y)
                .color(Color::LIGHT_GREY)
                .dash(dash)
                .width(1.0);
            if first && let Some(l) = legend {
                s.label(l);
                first = false;
            }
            if let (Some(txt), Some(b)) = (text, best) {
                ax.text(b.0 - 18.0, b.1 + 0.8, txt).color(Color::GREY);
            }
        }
    }
}

#[derive(Debug, Clone)]
struct SigmaData {
    label: String,
    w: Vec<f64>,
    values: Vec<Vec<f64>>,
}

/// A singular-value plot (MATLAB `sigma`): every `σᵢ(G(jω))` in dB against a logarithmic
/// frequency axis, the largest solid, the others dashed, one colour per system.
///
/// ```
/// use pendulab_plot::SigmaPlot;
/// let w: Vec<f64> = (0..100).map(|k| 10f64.powf(-2.0 + 0.04 * k as f64)).collect();
/// let sv: Vec<Vec<f64>> = w.iter().map(|w| vec![1.0 / (1.0 + w), 0.1 / (1.0 + w * w)]).collect();
/// let fig = SigmaPlot::new().response("G", &w, &sv).figure();
/// assert!(fig.to_svg().unwrap().contains("singular values [dB]"));
/// ```
#[derive(Debug, Clone, Default)]
pub struct SigmaPlot {
    curves: Vec<SigmaData>,
    title: Option<String>,
}

impl SigmaPlot {
    /// An empty plot.
    pub fn new() -> Self {
        Self::default()
    }
    /// Adds `values[k]` (descending singular values, absolute) at `w[k]` rad/s.
    pub fn response(mut self, label: impl Into<String>, w: &[f64], values: &[Vec<f64>]) -> Self {
        self.curves.push(SigmaData {
            label: label.into(),
            w: w.to_vec(),
            values: values.to_vec(),
        });
        self
    }
    /// Figure title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// The figure (checked when rendered).
    pub fn figure(&self) -> Figure {
        let mut ax = Axes::new();
        ax.xlabel("frequency ω [rad/s]")
            .ylabel("singular values [dB]")
            .xscale(Scale::Log)
            .legend(LegendPos::Best);
        for (k, c) in self.curves.iter().enumerate() {
            let n = c.values.iter().map(Vec::len).max().unwrap_or(0);
            for i in 0..n {
                let y: Vec<f64> = c
                    .values
                    .iter()
                    .map(|v| v.get(i).map_or(f64::NAN, |s| 20.0 * s.log10()))
                    .collect();
                let s = ax
                    .plot(&c.w, &y)
                    .color(palette(k))
                    .width(if i == 0 { 2.0 } else { 1.4 });
                if i == 0 {
                    s.label(format!("{} σ₁", c.label));
                } else {
                    s.dashed();
                    if i == 1 {
                        s.label(format!("{} σ₂…", c.label));
                    }
                }
            }
        }
        let mut fig = Figure::new(ax).size(DEFAULT_WIDTH, 440.0);
        if let Some(t) = &self.title {
            fig = fig.title(t.clone());
        }
        fig
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gains_print_short() {
        assert_eq!(fmt_gain(2.0), "2");
        assert_eq!(fmt_gain(0.3849), "0.3849");
        assert_eq!(fmt_gain(12.3456), "12.35");
        assert_eq!(fmt_gain(2.5e6), "2.500e6");
    }
}
