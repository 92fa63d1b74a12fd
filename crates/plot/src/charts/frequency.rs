//! The frequency-domain charts: Bode diagrams (magnitude and phase of several systems, the
//! phase unwrapped) and pole–zero maps with design regions.

use super::dash_cycle;
use pendulab_lti::Complex64;

use crate::axes::{Axes, LegendPos, RegionBound, Scale};
use crate::color::{Color, palette};
use crate::figure::Figure;
use crate::style::Dash;

/// Frequency unit of a Bode diagram's horizontal axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrequencyUnit {
    /// ω in rad/s (MATLAB's default).
    #[default]
    RadPerSec,
    /// f in Hz; frequencies given in rad/s are divided by 2π.
    Hertz,
}

#[derive(Debug, Clone)]
struct BodeCurve {
    label: String,
    w: Vec<f64>,
    mag_db: Vec<f64>,
    phase_deg: Vec<f64>,
    dash: Dash,
}

/// A Bode diagram: gain in dB over phase in degrees against a logarithmic frequency axis
/// (MATLAB `bode`), several systems overlaid.
///
/// ```
/// use pendulab_lti::Complex64;
/// use pendulab_plot::Bode;
/// // P(s) = 4.36 / (s (s + 6.25)) on 10⁻¹ … 10³ rad/s.
/// let w: Vec<f64> = (0..=200).map(|k| 10f64.powf(-1.0 + 4.0 * k as f64 / 200.0)).collect();
/// let h: Vec<Complex64> = w
///     .iter()
///     .map(|&w| { let s = Complex64::new(0.0, w); 4.36 / (s * (s + 6.25)) })
///     .collect();
/// let fig = Bode::new().response("P(s)", &w, &h).figure();
/// assert!(fig.to_svg().unwrap().contains("phase [deg]"));
/// ```
#[derive(Debug, Clone, Default)]
pub struct Bode {
    curves: Vec<BodeCurve>,
    unit: FrequencyUnit,
    title: Option<String>,
}

impl Bode {
    /// An empty diagram.
    pub fn new() -> Self {
        Self::default()
    }
    /// Adds a frequency response `h[k] = G(jω_k)` at frequencies `w` in rad/s. The gain is
    /// 20 log₁₀|h| dB; the phase arg h is unwrapped along the frequency axis (jumps larger
    /// than 180° between neighbours are removed by adding multiples of 360°, MATLAB's
    /// convention) and starts in (−180°, 180°]. Lengths are checked when the figure is
    /// rendered; zero gains are gaps.
    pub fn response(mut self, label: impl Into<String>, w: &[f64], h: &[Complex64]) -> Self {
        let mag_db = h.iter().map(|c| 20.0 * c.norm().log10()).collect();
        let mut phase: Vec<f64> = h.iter().map(|c| c.arg().to_degrees()).collect();
        unwrap_degrees(&mut phase);
        let dash = dash_cycle(self.curves.len() / crate::color::PALETTE.len());
        self.curves.push(BodeCurve {
            label: label.into(),
            w: w.to_vec(),
            mag_db,
            phase_deg: phase,
            dash,
        });
        self
    }
    /// Adds precomputed gain (dB) and phase (degrees) at frequencies `w` in rad/s, drawn as given.
    pub fn magnitude_phase(
        mut self,
        label: impl Into<String>,
        w: &[f64],
        mag_db: &[f64],
        phase_deg: &[f64],
    ) -> Self {
        let dash = dash_cycle(self.curves.len() / crate::color::PALETTE.len());
        self.curves.push(BodeCurve {
            label: label.into(),
            w: w.to_vec(),
            mag_db: mag_db.to_vec(),
            phase_deg: phase_deg.to_vec(),
            dash,
        });
        self
    }
    /// Frequency unit of the axis.
    pub fn unit(mut self, unit: FrequencyUnit) -> Self {
        self.unit = unit;
        self
    }
    /// Figure title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// The two-panel figure (checked when rendered).
    pub fn figure(&self) -> Figure {
        let (f, xl) = match self.unit {
            FrequencyUnit::RadPerSec => (1.0, "frequency ω [rad/s]"),
            FrequencyUnit::Hertz => (1.0 / (2.0 * std::f64::consts::PI), "frequency f [Hz]"),
        };
        let mut mag = Axes::new();
        mag.ylabel("gain [dB]")
            .xscale(Scale::Log)
            .legend(LegendPos::Best);
        let mut ph = Axes::new();
        ph.ylabel("phase [deg]")
            .xlabel(xl)
            .xscale(Scale::Log)
            .y_tick_step(90.0);
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for (k, c) in self.curves.iter().enumerate() {
            let w: Vec<f64> = c.w.iter().map(|w| w * f).collect();
            for v in w.iter().filter(|v| v.is_finite() && **v > 0.0) {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
            mag.plot(&w, &c.mag_db)
                .label(c.label.clone())
                .color(palette(k))
                .dash(c.dash);
            ph.plot(&w, &c.phase_deg).color(palette(k)).dash(c.dash);
        }
        let mut span = 0.0;
        for c in &self.curves {
            let (a, b) = finite_span(&c.phase_deg);
            span = f64::max(span, b - a);
        }
        if span > 720.0 {
            ph.y_tick_step(180.0);
        } else if span < 100.0 {
            ph.y_tick_step(45.0);
        }
        if lo.is_finite() && hi > lo {
            mag.xlim(lo, hi);
            ph.xlim(lo, hi);
        }
        let mut fig = Figure::column([mag, ph]).size(crate::figure::DEFAULT_WIDTH, 520.0);
        if let Some(t) = &self.title {
            fig = fig.title(t.clone());
        }
        fig
    }
}

fn finite_span(v: &[f64]) -> (f64, f64) {
    let mut a = f64::INFINITY;
    let mut b = f64::NEG_INFINITY;
    for x in v.iter().filter(|x| x.is_finite()) {
        a = a.min(*x);
        b = b.max(*x);
    }
    if a <= b { (a, b) } else { (0.0, 0.0) }
}

/// Removes jumps of more than 180° between neighbouring finite phases (degrees).
pub(crate) fn unwrap_degrees(p: &mut [f64]) {
    let mut prev: Option<f64> = None;
    let mut offset = 0.0;
    for v in p.iter_mut() {
        if !v.is_finite() {
            continue;
        }
        let mut x = *v + offset;
        if let Some(q) = prev {
            while x - q > 180.0 {
                x -= 360.0;
                offset -= 360.0;
            }
            while x - q < -180.0 {
                x += 360.0;
                offset += 360.0;
            }
        }
        *v = x;
        prev = Some(x);
    }
}

/// A pole–zero map (MATLAB `pzmap`) with optional design regions, in equal scales.
///
/// ```
/// use pendulab_lti::Complex64;
/// use pendulab_plot::{PoleZeroMap, RegionBound};
/// let p = [Complex64::new(-3.0, 2.0), Complex64::new(-3.0, -2.0), Complex64::new(-8.0, 0.0)];
/// let fig = PoleZeroMap::new()
///     .region("design region", &[RegionBound::DecayRate(2.0), RegionBound::SpeedLimit(16.0),
///                                RegionBound::Sector(std::f64::consts::FRAC_PI_4)])
///     .poles("closed loop", &p)
///     .figure();
/// assert!(fig.to_svg().unwrap().contains("closed loop"));
/// ```
#[derive(Debug, Clone, Default)]
pub struct PoleZeroMap {
    axes: Axes,
    sets: usize,
    title: Option<String>,
}

impl PoleZeroMap {
    /// An empty map of the s-plane (axes "real axis", "imaginary axis").
    pub fn new() -> Self {
        let mut axes = Axes::new();
        axes.xlabel("real axis [1/s]")
            .ylabel("imaginary axis [1/s]")
            .equal_aspect();
        Self {
            axes,
            sets: 0,
            title: None,
        }
    }
    /// A map of the z-plane: the unit disk (stability region) is shaded and outlined, and the
    /// axes have no unit.
    pub fn discrete() -> Self {
        let mut m = Self::new();
        m.axes.xlabel("real axis").ylabel("imaginary axis");
        m.axes
            .region(&[RegionBound::UNIT_DISK])
            .label("|z| < 1")
            .dash(Dash::Dashed);
        m
    }
    /// Adds poles (× markers) in the next palette colour.
    pub fn poles(mut self, label: impl Into<String>, poles: &[Complex64]) -> Self {
        let c = palette(self.sets);
        self.sets += 1;
        self.axes.poles(poles).label(label).color(c);
        self
    }
    /// Adds zeros (○ markers) in the next palette colour.
    pub fn zeros(mut self, label: impl Into<String>, zeros: &[Complex64]) -> Self {
        let c = palette(self.sets);
        self.sets += 1;
        self.axes.zeros(zeros).label(label).color(c);
        self
    }
    /// Adds a shaded design region (intersection of the bounds) with dashed boundaries.
    pub fn region(mut self, label: impl Into<String>, bounds: &[RegionBound]) -> Self {
        self.axes.region(bounds).label(label);
        self
    }
    /// Figure title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// The panel, for further additions.
    pub fn axes(&mut self) -> &mut Axes {
        &mut self.axes
    }
    /// The figure (checked when rendered).
    pub fn figure(&self) -> Figure {
        let mut ax = self.axes.clone();
        ax.hline(0.0).color(Color::GREY).width(0.8);
        ax.vline(0.0).color(Color::GREY).width(0.8);
        let mut fig = Figure::new(ax).size(crate::figure::DEFAULT_WIDTH, 480.0);
        if let Some(t) = &self.title {
            fig = fig.title(t.clone());
        }
        fig
    }
}
