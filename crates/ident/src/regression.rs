//! The book's least-squares identifications (book part 1 §3.2–3.3, eqs 3.43–3.47).
//!
//! Each model is written as `M(t) p = N(t)` with measured regressors `M` and target `N`:
//!
//! | function | `M` | `N` | `p` |
//! |---|---|---|---|
//! | [`cart_drive_ls`] | `[−ż, v]` | `z̈` | `[a_c, b_c]` |
//! | [`cart_pendulum_ls`] | `[φ̈, φ̇]` | `m_p l_p cos φ z̈ − m_p l_p² φ̈ − m_p g l_p sin φ` | `[J_p, μ_p]` |
//! | [`arm_drive_ls`] | `[−φ̇₁, v]` | `φ̈₁` | `[a₁, b₁]` |
//! | [`arm_pendulum_ls`] | `[φ̈₂, φ̇₂ − φ̇₁]` | `α₃ cos(φ₁−φ₂) φ̈₁ − α₃ φ̇₁² sin(φ₁−φ₂) − α₅ sin φ₂` | `[α₂, μ₂]`, `J₂ = α₂ − m₂ l₂²` |
//!
//! with `α₃ = m₂ L₁ l₂`, `α₅ = m₂ l₂ g`. Angles: the cart pendulum's `φ = θ − π` is measured
//! from the hanging rest (eq. 3.44); for the arm rig, as in the book's arm data and Simulink
//! model, `φ₁` is the arm angle θ₁ and `φ₂ = θ₂ − π` the pendulum's absolute angle from hanging.
//! Substituting θ₂ = φ₂ + π into the arm pendulum's equation (`docs/model.md` §2) gives exactly the
//! arm row of the table.
//!
//! The recipe: derivatives by a [`Differentiator`] (the book's three-point formulas applied
//! twice by default), the nonlinear target assembled sample by sample, then **every** column
//! of `M` and `N` passed through the same [`Prefilter`] (the book's causal
//! `1/(0.075 s + 1)³` by default), then [`least_squares`] by Householder QR.
//!
//! **Streaming.** With three-point derivatives and a causal (or no) filter — the book's recipe
//! — the `*_ls` functions never build the columns: each block of 256 rows is differentiated,
//! assembled, filtered (the filter states carried from block to block) and folded into the QR
//! factor while it is in cache. The arithmetic is the same, operation for operation, as that of
//! the explicit [`Regression`] (which the `*_regression` functions return for plotting), so
//! both routes give the same estimates up to the order of the least-squares sums.

use crate::differentiate::{Derivatives, Differentiator, savgol_coefficients, three_point_at};
use crate::error::{IdentError, Result, SamplePos, UNNAMED, short};
use crate::filter::{BANK_BLOCK, BOOK_TF, FilterBank, LowPass3, Prefilter};
use crate::least_squares::{LeastSquares, QrAccumulator, least_squares};

/// Options shared by the least-squares identifications.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LsOptions {
    /// How velocities and accelerations are obtained (default: three-point, twice).
    pub differentiator: Differentiator,
    /// The filter applied to every regressor column and the target (default: the book's
    /// causal `1/(0.075 s + 1)³`, ZOH-exact).
    pub prefilter: Prefilter,
}

/// The fewest differentiator stencils a record must hold: 4. A stencil is the span of samples
/// one derivative value is computed from (5 for the book's three-point formulas applied
/// twice, `window` for Savitzky–Golay). With fewer, most samples sit within half a stencil of
/// an end, where the one-sided end formulas (less accurate, and for Savitzky–Golay one
/// polynomial for half a window) make up the regression.
pub const MIN_STENCILS: usize = 4;

/// The longest prefilter time constant, as a fraction of the record span: 1/10. The impulse
/// response of `1/(T_f s + 1)³`, `t² e^{−t/T_f}/(2 T_f³)`, leaves `e^{−10}(1 + 10 + 50) ≈ 0.3 %`
/// of its weight beyond `10 T_f`; with a longer `T_f` no filtered sample has settled, and the
/// regression is fitted to the filter's start-up transient (with `T_f = 10⁹ s` the columns are
/// triple integrals scaled by `10⁻²⁷`, and the residual 10⁻³⁰ means nothing).
pub const MAX_TF_FRACTION: f64 = 0.1;

/// The largest relative error of the derivatives over the band the regression uses: 1 %.
/// The band ends at the prefilter's corner `1/T_f` (without a prefilter, at the book's
/// `1/`[`BOOK_TF`] `= 13.3 rad/s`, above the rigs' dynamics: table 3.5's drive pole
/// `a_c = 6.25 /s`, the pendulums' `ω ≈ 6–7 rad/s`). The error at `ω` is that of the
/// differentiator's frequency response against `iω` and `−ω²`: for the three-point formula
/// `1 − sin(ω t_s)/(ω t_s)` and, applied twice, `1 − (sin(ω t_s)/(ω t_s))²`; for
/// Savitzky–Golay that of its centre kernel. A larger error biases the estimates, since the
/// undifferentiated columns (the voltage, `sin φ`) are not distorted alike: a 4001-sample
/// window on the 4001-sample book record gives `J_p` 113× too large.
pub const MAX_DERIVATIVE_ERROR: f64 = 0.01;

/// Plausible masses of the pendulum rigs' bodies, kg: from a 1 g bob to a 10 kg load (the
/// book's pendulums: 0.107 kg and 0.096 kg).
pub const MASS_RANGE: (f64, f64) = (1e-3, 10.0);

/// Plausible lengths of the pendulum rigs (pivot to centre of mass, arm length), m: 1 mm to
/// 2 m (the book's: 0.195–0.230 m).
pub const LENGTH_RANGE: (f64, f64) = (1e-3, 2.0);

/// Plausible gravitational acceleration, m/s²: Earth's surface gravity lies between 9.78
/// (equator) and 9.83 (poles), a little less at altitude.
pub const GRAVITY_RANGE: (f64, f64) = (9.7, 9.9);

/// Largest pole (or natural frequency) times the sample time an estimate may have: 0.25. At
/// `ω t_s = 0.25` the book's twice-applied three-point derivative already errs by 2 %
/// (`1 − (sin x/x)²`), so a faster mode is not resolved by the sampling: such an estimate
/// is an artefact (a 3-sample window returns `a_c = 1/t_s` exactly).
pub const MAX_POLE_TIMES_TS: f64 = 0.25;

fn in_range(name: &str, value: f64, unit: &str, range: (f64, f64), reason: &str) -> Result<()> {
    if value >= range.0 && value <= range.1 {
        Ok(())
    } else {
        Err(IdentError::ConstantOutOfRange {
            name: name.into(),
            value,
            unit: unit.into(),
            min: range.0,
            max: range.1,
            reason: reason.into(),
        })
    }
}

/// The frequency response error of a derivative stencil: `coefs[j]` at sample offsets
/// `j − centre`, the `deriv`-th derivative, at `ω` rad/s with sample time `ts`; relative to
/// `(iω)^deriv`.
fn stencil_error(coefs: &[f64], centre: usize, deriv: usize, omega: f64, ts: f64) -> f64 {
    let (mut re, mut im) = (0.0, 0.0);
    for (j, c) in coefs.iter().enumerate() {
        let x = omega * (j as f64 - centre as f64) * ts;
        re += c * x.cos();
        im += c * x.sin();
    }
    // (iω)¹ = iω, (iω)² = −ω².
    let (tr, ti) = if deriv == 1 {
        (0.0, omega)
    } else {
        (-omega * omega, 0.0)
    };
    ((re - tr).hypot(im - ti)) / (tr.hypot(ti))
}

/// The `x = ω t_s` at which the twice-applied three-point derivative's error
/// `1 − (sin x/x)²` reaches [`MAX_DERIVATIVE_ERROR`] (≈ 0.1735), by bisection on (0, 1].
fn three_point_limit() -> f64 {
    let err = |x: f64| 1.0 - (x.sin() / x).powi(2);
    let (mut lo, mut hi) = (1e-6, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if err(mid) > MAX_DERIVATIVE_ERROR {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    lo
}

impl LsOptions {
    /// Checks that the options suit `n` samples every `ts` seconds, so that the regression
    /// means what it models:
    /// * the record holds at least [`MIN_STENCILS`] differentiator stencils (5 samples for the
    ///   three-point formulas applied twice, `window` for Savitzky–Golay);
    /// * a prefilter time constant is at most [`MAX_TF_FRACTION`] of the record span;
    /// * the derivatives err by at most [`MAX_DERIVATIVE_ERROR`] at the band edge (`1/T_f`,
    ///   or `1/`[`BOOK_TF`] unfiltered) — this bounds `T_f` from below relative to `t_s`
    ///   (`T_f ≥ 5.8 t_s` for three-point derivatives) and a Savitzky–Golay window from above
    ///   relative to the dynamics.
    ///
    /// The `*_ls` functions do not call it (they compute whatever the data give, for studies
    /// such as the book's unfiltered failure); the command-line tool does.
    ///
    /// # Errors
    /// [`IdentError::InvalidParameter`] for a bad `ts` or method parameters;
    /// [`IdentError::TooFewSamples`] for a record shorter than [`MIN_STENCILS`] stencils;
    /// [`IdentError::UnsuitedOption`] naming the time constant or window and the bound.
    pub fn check_data(&self, ts: f64, n: usize) -> Result<()> {
        positive("sample time ts", ts)?;
        self.differentiator.validate()?;
        self.prefilter.design(ts)?;
        let (stencil, what) = match self.differentiator {
            Differentiator::ThreePoint => (
                5,
                "the three-point derivatives applied twice (a 5-sample stencil)".to_string(),
            ),
            Differentiator::SavitzkyGolay { window, .. } => (
                window,
                format!("the Savitzky–Golay derivatives (a {window}-sample window)"),
            ),
        };
        let needed = MIN_STENCILS * stencil;
        if n < needed {
            return Err(IdentError::TooFewSamples {
                source_name: UNNAMED.into(),
                what: format!("{what}, which must fit {MIN_STENCILS} times into the record,"),
                needed,
                found: n,
            });
        }
        let span = (n - 1) as f64 * ts;
        let tf = match self.prefilter {
            Prefilter::None => None,
            Prefilter::Causal { tf, .. } | Prefilter::ZeroPhase { tf, .. } => Some(tf),
        };
        if let Some(tf) = tf
            && tf > MAX_TF_FRACTION * span
        {
            return Err(IdentError::UnsuitedOption {
                option: "prefilter time constant T_f".into(),
                value: tf,
                unit: "s".into(),
                reason: format!(
                    "longer than {MAX_TF_FRACTION} of the record span {} s (the filter \
                     needs about 10 T_f to settle); use T_f ≤ {} s or a longer record",
                    short(span),
                    short(MAX_TF_FRACTION * span)
                ),
            });
        }
        let omega = 1.0 / tf.unwrap_or(BOOK_TF);
        let band = match tf {
            Some(tf) => format!("the prefilter's corner 1/T_f = {omega:.4} rad/s (T_f = {tf} s)"),
            None => format!("the rigs' band up to 1/{BOOK_TF} s = {omega:.4} rad/s (no prefilter)"),
        };
        let (e1, e2) = match self.differentiator {
            Differentiator::ThreePoint => {
                let x = omega * ts;
                let r = if x == 0.0 { 1.0 } else { x.sin() / x };
                ((1.0 - r).abs(), (1.0 - r * r).abs())
            }
            Differentiator::SavitzkyGolay { window, order } => {
                let c = window / 2;
                let k1 = savgol_coefficients(window, order, 1, ts, c)?;
                let k2 = savgol_coefficients(window, order, 2, ts, c)?;
                (
                    stencil_error(&k1, c, 1, omega, ts),
                    stencil_error(&k2, c, 2, omega, ts),
                )
            }
        };
        let err = e1.max(e2);
        if err > MAX_DERIVATIVE_ERROR || err.is_nan() {
            let pct = 100.0 * err;
            let limit = 100.0 * MAX_DERIVATIVE_ERROR;
            return Err(match (self.differentiator, tf) {
                (Differentiator::ThreePoint, Some(tf)) => IdentError::UnsuitedOption {
                    option: "prefilter time constant T_f".into(),
                    value: tf,
                    unit: "s".into(),
                    reason: format!(
                        "too short for the sample time {} s: the three-point derivatives err \
                         by {pct:.3} % at {band} (limit {limit} %); use T_f ≥ {} s",
                        short(ts),
                        short(ts / three_point_limit())
                    ),
                },
                (Differentiator::ThreePoint, None) => IdentError::UnsuitedOption {
                    option: "sample time ts".into(),
                    value: ts,
                    unit: "s".into(),
                    reason: format!(
                        "too long: the three-point derivatives err by {pct:.3} % at {band} \
                         (limit {limit} %)"
                    ),
                },
                (Differentiator::SavitzkyGolay { window, .. }, _) => IdentError::UnsuitedOption {
                    option: "Savitzky–Golay window".into(),
                    value: window as f64,
                    unit: "samples".into(),
                    reason: format!(
                        "too long for the dynamics: spanning {} s, its derivatives err by \
                         {pct:.3} % at {band} (limit {limit} %); use a shorter window",
                        short((window - 1) as f64 * ts)
                    ),
                },
            });
        }
        Ok(())
    }
}

/// Known constants of the cart-type pendulum (book table 3.5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartPendulumConstants {
    /// Pendulum mass `m_p`, kg (book: 0.107).
    pub mp: f64,
    /// Pivot to centre of mass `l_p`, m (book: 0.230).
    pub lp: f64,
    /// Gravitational acceleration `g`, m/s² (book: 9.81).
    pub g: f64,
}

impl Default for CartPendulumConstants {
    fn default() -> Self {
        Self {
            mp: 0.107,
            lp: 0.230,
            g: 9.81,
        }
    }
}

/// Known constants of the arm-type pendulum (book table 3.7).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmPendulumConstants {
    /// Arm length `L₁` (pivot to pendulum joint), m (book: 0.227).
    pub l1: f64,
    /// Pendulum mass `m₂`, kg (book: 0.096).
    pub m2: f64,
    /// Joint to pendulum centre of mass `l₂`, m (book: 0.195).
    pub l2: f64,
    /// Gravitational acceleration `g`, m/s² (book: 9.81).
    pub g: f64,
}

impl Default for ArmPendulumConstants {
    fn default() -> Self {
        Self {
            l1: 0.227,
            m2: 0.096,
            l2: 0.195,
            g: 9.81,
        }
    }
}

impl ArmPendulumConstants {
    /// `α₃ = m₂ L₁ l₂`, kg m².
    pub fn alpha3(&self) -> f64 {
        self.m2 * self.l1 * self.l2
    }
    /// `α₅ = m₂ l₂ g`, N m.
    pub fn alpha5(&self) -> f64 {
        self.m2 * self.l2 * self.g
    }
}

fn positive(name: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(IdentError::InvalidParameter {
            name: name.into(),
            value: v,
            reason: "must be finite and > 0".into(),
        })
    }
}

impl CartPendulumConstants {
    /// Checks that every constant lies in its documented plausible range ([`MASS_RANGE`],
    /// [`LENGTH_RANGE`], [`GRAVITY_RANGE`]). The `*_ls` functions only require positive
    /// finite values; the command-line tool calls this too.
    ///
    /// # Errors
    /// [`IdentError::ConstantOutOfRange`] naming the constant, its value and the range.
    pub fn check_range(&self) -> Result<()> {
        self.validate()?;
        in_range(
            "m_p",
            self.mp,
            "kg",
            MASS_RANGE,
            "pendulum mass of a tabletop rig",
        )?;
        in_range("l_p", self.lp, "m", LENGTH_RANGE, "pivot to centre of mass")?;
        in_range(
            "g",
            self.g,
            "m/s²",
            GRAVITY_RANGE,
            "Earth's surface gravity",
        )
    }

    fn validate(&self) -> Result<()> {
        positive("m_p", self.mp)?;
        positive("l_p", self.lp)?;
        positive("g", self.g)
    }
}

impl ArmPendulumConstants {
    /// Checks that every constant lies in its documented plausible range ([`MASS_RANGE`],
    /// [`LENGTH_RANGE`], [`GRAVITY_RANGE`]).
    ///
    /// # Errors
    /// [`IdentError::ConstantOutOfRange`] naming the constant, its value and the range.
    pub fn check_range(&self) -> Result<()> {
        self.validate()?;
        in_range(
            "L1",
            self.l1,
            "m",
            LENGTH_RANGE,
            "arm length of a tabletop rig",
        )?;
        in_range(
            "m2",
            self.m2,
            "kg",
            MASS_RANGE,
            "pendulum mass of a tabletop rig",
        )?;
        in_range("l2", self.l2, "m", LENGTH_RANGE, "joint to centre of mass")?;
        in_range(
            "g",
            self.g,
            "m/s²",
            GRAVITY_RANGE,
            "Earth's surface gravity",
        )
    }

    fn validate(&self) -> Result<()> {
        positive("L1", self.l1)?;
        positive("m2", self.m2)?;
        positive("l2", self.l2)?;
        positive("g", self.g)
    }
}

/// The (filtered) regression `M p = N` of one identification, ready to solve or to plot (the
/// book's `p1c322_cdip_plot_MN`).
#[derive(Debug, Clone, PartialEq)]
pub struct Regression {
    /// Parameter names, one per column of `M`.
    pub names: Vec<String>,
    /// What each column of `M` is, in terms of the measured signals (e.g. `−ż`, `v`).
    pub signals: Vec<String>,
    /// Columns of `M`, each as long as the data.
    pub columns: Vec<Vec<f64>>,
    /// Name of the target.
    pub target_name: String,
    /// The target `N`.
    pub target: Vec<f64>,
}

impl Regression {
    /// Solves it by Householder QR ([`least_squares`]).
    ///
    /// # Errors
    /// As [`least_squares`].
    pub fn solve(&self) -> Result<LeastSquares> {
        let cols: Vec<(&str, &[f64])> = self
            .names
            .iter()
            .zip(&self.columns)
            .map(|(n, c)| (n.as_str(), c.as_slice()))
            .collect();
        let names: Vec<&str> = self.names.iter().map(String::as_str).collect();
        let signals: Vec<&str> = self.signals.iter().map(String::as_str).collect();
        least_squares(&cols, (&self.target_name, &self.target))
            .map_err(|e| describe_rank(e, &names, &signals))
    }

    fn filtered(mut self, prefilter: &Prefilter, ts: f64) -> Result<Self> {
        match prefilter.design(ts)? {
            None => {}
            Some((f, zero_phase)) => {
                let mut all: Vec<Vec<f64>> = std::mem::take(&mut self.columns);
                all.push(std::mem::take(&mut self.target));
                let out = filter_all(&f, zero_phase, &all);
                let mut out = out;
                self.target = out.pop().expect("target column");
                self.columns = out;
            }
        }
        Ok(self)
    }
}

fn filter_all(f: &LowPass3, zero_phase: bool, cols: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let n = cols.first().map_or(0, Vec::len);
    let inputs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    let mut out: Vec<Vec<f64>> = vec![vec![0.0; n]; cols.len()];
    {
        let mut refs: Vec<&mut [f64]> = out.iter_mut().map(Vec::as_mut_slice).collect();
        f.filter_many(&inputs, &mut refs);
    }
    if zero_phase {
        for c in &mut out {
            c.reverse();
        }
        let rev: Vec<Vec<f64>> = out.clone();
        let inputs: Vec<&[f64]> = rev.iter().map(Vec::as_slice).collect();
        {
            let mut refs: Vec<&mut [f64]> = out.iter_mut().map(Vec::as_mut_slice).collect();
            f.filter_many(&inputs, &mut refs);
        }
        for c in &mut out {
            c.reverse();
        }
    }
    out
}

/// Three-point first and second derivatives of a signal on one block `[k0, k1)`, computed
/// from the neighbouring samples with exactly the formulas (and the operation order) of
/// [`crate::differentiate::three_point`] applied once and twice to the whole signal.
struct BlockDerivatives {
    /// `ẋ` on `[lo, hi)` ⊇ the indices the block's second derivatives need.
    d1: Vec<f64>,
    n: usize,
    h: f64,
}

impl BlockDerivatives {
    fn new(n: usize, ts: f64) -> Self {
        Self {
            d1: Vec::with_capacity(BANK_BLOCK + 4),
            n,
            h: 0.5 / ts,
        }
    }

    /// Writes `ẋ` and `ẍ` on `[k0, k1)` into `first[..k1−k0]` and `second[..k1−k0]`.
    fn load(&mut self, x: &[f64], k0: usize, k1: usize, first: &mut [f64], second: &mut [f64]) {
        let (n, h) = (self.n, self.h);
        let m = k1 - k0;
        let mut lo = k0.saturating_sub(1);
        let mut hi = (k1 + 1).min(n);
        if k0 == 0 {
            hi = hi.max(3);
        }
        if k1 == n {
            lo = lo.min(n - 3);
        }
        // ẋ on [lo, hi): interior by the central difference, ends by the one-sided formulas.
        self.d1.clear();
        let a = lo.max(1);
        let b = hi.min(n - 1);
        if lo == 0 {
            self.d1.push(three_point_at(x, h, 0));
        }
        self.d1
            .extend(x[a - 1..b + 1].windows(3).map(|w| (w[2] - w[0]) * h));
        if hi == n {
            self.d1.push(three_point_at(x, h, n - 1));
        }
        debug_assert_eq!(self.d1.len(), hi - lo);
        first[..m].copy_from_slice(&self.d1[k0 - lo..k1 - lo]);
        // ẍ on [k0, k1): the same formulas on ẋ.
        let d = &self.d1;
        let mut i = 0;
        if k0 == 0 {
            second[0] = (-3.0 * d[0] + 4.0 * d[1] - d[2]) * h;
            i = 1;
        }
        let (ia, ib) = (k0.max(1), k1.min(n - 1));
        if ib > ia {
            for (o, w) in second[i..i + (ib - ia)]
                .iter_mut()
                .zip(d[ia - 1 - lo..ib + 1 - lo].windows(3))
            {
                *o = (w[2] - w[0]) * h;
            }
            i += ib - ia;
        }
        if k1 == n {
            let e = n - lo;
            second[i] = (d[e - 3] - 4.0 * d[e - 2] + 3.0 * d[e - 1]) * h;
            i += 1;
        }
        debug_assert_eq!(i, m);
    }
}

/// `true` if every value is finite: `0·x` is (±)0 for finite `x` and NaN otherwise, and NaN
/// survives a sum (four partial sums, so the loop vectorises).
fn all_finite(x: &[f64]) -> bool {
    let mut acc = [0.0f64; 4];
    let chunks = x.chunks_exact(4);
    let rest = chunks.remainder();
    for c in chunks {
        for l in 0..4 {
            acc[l] += 0.0 * c[l];
        }
    }
    let tail: f64 = rest.iter().map(|v| 0.0 * v).sum();
    (acc[0] + acc[1] + acc[2] + acc[3] + tail) == 0.0
}

/// `true` if the options allow the streamed route (three-point derivatives, causal or no
/// filter).
fn streamable(opts: &LsOptions) -> bool {
    opts.differentiator == Differentiator::ThreePoint
        && !matches!(opts.prefilter, Prefilter::ZeroPhase { .. })
}

/// Solves `M p = N` streamed block by block: `fill(k0, m, raw)` writes rows `k0 … k0+m−1` of
/// the `W − 1` regressor columns and the target (last) into `raw[c][..m]`.
fn stream_solve<const W: usize>(
    signals: &[(&str, &[f64])],
    ts: f64,
    needed: usize,
    prefilter: &Prefilter,
    names: &[&str],
    target: &str,
    mut fill: impl FnMut(usize, usize, &mut [[f64; BANK_BLOCK]; W]),
) -> Result<LeastSquares> {
    debug_assert_eq!(names.len() + 1, W);
    let n = check_signals_with(signals, ts, needed, false)?;
    let mut bank = prefilter.design(ts)?.map(|(f, _)| FilterBank::<W>::new(&f));
    let mut acc = QrAccumulator::new(names, target)?;
    let mut raw = [[0.0; BANK_BLOCK]; W];
    let mut out = [[0.0; BANK_BLOCK]; W];
    let mut k0 = 0;
    while k0 < n {
        let m = (n - k0).min(BANK_BLOCK);
        fill(k0, m, &mut raw);
        if !raw.iter().all(|c| all_finite(&c[..m])) {
            // Name the offending input sample (a NaN/∞ in the data); a non-finite value
            // computed from finite data (overflow) is named by its regressor column.
            check_signals(signals, ts, needed)?;
            let (c, i) = (0..W)
                .find_map(|c| {
                    raw[c][..m]
                        .iter()
                        .position(|v| !v.is_finite())
                        .map(|i| (c, i))
                })
                .expect("a non-finite value was seen");
            return Err(IdentError::NonFinite {
                source_name: UNNAMED.into(),
                column: if c + 1 < W { names[c] } else { target }.to_string(),
                at: SamplePos::index(k0 + i),
                value: raw[c][i],
            });
        }
        match bank.as_mut() {
            Some(b) => {
                b.process(&raw, &mut out, m);
                acc.push_scratch(&mut out, m);
            }
            None => acc.push_scratch(&mut raw, m),
        }
        k0 += m;
    }
    acc.finish()
}

/// Checks lengths, finiteness and the sample count of named input signals.
fn check_signals(signals: &[(&str, &[f64])], ts: f64, needed: usize) -> Result<usize> {
    check_signals_with(signals, ts, needed, true)
}

/// As [`check_signals`]; with `finite = false` the values are not scanned (the streamed route
/// checks each block in cache and calls the full check only to name a bad sample).
fn check_signals_with(
    signals: &[(&str, &[f64])],
    ts: f64,
    needed: usize,
    finite: bool,
) -> Result<usize> {
    positive("sample time ts", ts)?;
    let n = signals[0].1.len();
    for (name, s) in signals {
        if s.len() != n {
            return Err(IdentError::LengthMismatch {
                source_name: UNNAMED.into(),
                column: name.to_string(),
                expected: n,
                found: s.len(),
            });
        }
        if !finite {
            continue;
        }
        if let Some(k) = s.iter().position(|v| !v.is_finite()) {
            return Err(IdentError::NonFinite {
                source_name: UNNAMED.into(),
                column: name.to_string(),
                at: SamplePos::index(k),
                value: s[k],
            });
        }
    }
    if n < needed {
        return Err(IdentError::TooFewSamples {
            source_name: UNNAMED.into(),
            what: "the least-squares identification".into(),
            needed,
            found: n,
        });
    }
    Ok(n)
}

fn needed(opts: &LsOptions) -> usize {
    opts.differentiator.min_samples().max(3)
}

fn derivs(opts: &LsOptions, x: &[f64], ts: f64) -> Result<Derivatives> {
    opts.differentiator.derivatives(x, ts)
}

/// The drive regression `[−ẏ, v] [a, b]ᵀ = ÿ` (filtered), shared by cart and arm.
fn drive_regression(
    ts: f64,
    y: (&str, &[f64]),
    v: &[f64],
    names: [&str; 2],
    opts: &LsOptions,
) -> Result<Regression> {
    check_signals(&[y, ("v", v)], ts, needed(opts))?;
    let d = derivs(opts, y.1, ts)?;
    let minus_dy: Vec<f64> = d.first.iter().map(|v| -v).collect();
    Regression {
        names: names.iter().map(|s| s.to_string()).collect(),
        signals: vec![format!("−d{}/dt", y.0), "v".into()],
        columns: vec![minus_dy, v.to_vec()],
        target_name: format!("{}_ddot", y.0),
        target: d.second,
    }
    .filtered(&opts.prefilter, ts)
}

/// The cart-drive regression of eq. 3.43 (`M₁ = [−ż, v]`, `N₁ = z̈`), filtered.
///
/// `z` is the cart position in metres and `v` the motor voltage in volts, sampled every `ts`
/// seconds.
///
/// # Errors
/// [`IdentError::InvalidParameter`] for a bad `ts` or options; [`IdentError::LengthMismatch`],
/// [`IdentError::NonFinite`] naming the signal and sample; [`IdentError::TooFewSamples`].
pub fn cart_drive_regression(
    ts: f64,
    z: &[f64],
    v: &[f64],
    opts: &LsOptions,
) -> Result<Regression> {
    drive_regression(ts, ("z", z), v, ["ac", "bc"], opts)
}

/// A drive `ÿ = −a ẏ + b v` identified by least squares.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveLs {
    /// `a` (1/s): `a_c` for the cart, `a₁` for the arm.
    pub a: f64,
    /// `b` (m/(s² V) for the cart, rad/(s² V) for the arm).
    pub b: f64,
    /// The least-squares solution with its diagnostics (names `ac, bc` or `a1, b1`).
    pub lsq: LeastSquares,
}

impl DriveLs {
    /// Checks that the estimate describes a damped drive (`a > 0`, `b ≠ 0`).
    ///
    /// # Errors
    /// [`IdentError::Implausible`] otherwise.
    pub fn check_plausible(&self) -> Result<()> {
        if self.a.is_nan() || self.a <= 0.0 {
            return Err(IdentError::Implausible {
                what: self.lsq.names[0].clone(),
                value: self.a,
                reason: "a drive with back-EMF and friction has a > 0".into(),
            });
        }
        if self.b == 0.0 {
            return Err(IdentError::Implausible {
                what: self.lsq.names[1].clone(),
                value: self.b,
                reason: "the input has no effect".into(),
            });
        }
        Ok(())
    }
}

impl DriveLs {
    /// Every check of an estimate from data sampled every `ts` seconds: as
    /// [`DriveLs::check_plausible`] and [`LeastSquares::check`] (finite, well conditioned),
    /// and the pole `a` must be resolved by the record: `1/span ≤ a ≤`
    /// [`MAX_POLE_TIMES_TS`]`/t_s` (a time constant longer than the record is not seen in
    /// it; a shorter one than four samples is not resolved).
    ///
    /// # Errors
    /// [`IdentError::Implausible`], [`IdentError::NonFiniteResult`],
    /// [`IdentError::IllConditioned`].
    pub fn check(&self, ts: f64) -> Result<()> {
        first_failure(self.failed_checks(ts))
    }

    /// Every failed check of [`DriveLs::check`], not only the first (for reports that print
    /// the estimate anyway).
    pub fn failed_checks(&self, ts: f64) -> Vec<IdentError> {
        let mut out = plausible_and_solved(self.check_plausible(), &self.lsq);
        out.extend(self.pole_in_record(ts).err());
        out
    }

    fn pole_in_record(&self, ts: f64) -> Result<()> {
        let span = (self.lsq.samples.max(2) - 1) as f64 * ts;
        let name = &self.lsq.names[0];
        if !self.a.is_finite() || self.a <= 0.0 {
            return Ok(()); // check_plausible / lsq.check name it
        }
        if self.a * ts > MAX_POLE_TIMES_TS {
            return Err(IdentError::Implausible {
                what: name.clone(),
                value: self.a,
                reason: format!(
                    "its time constant 1/{name} = {:.3e} s is shorter than the {} s the \
                     sampling at {} s resolves",
                    1.0 / self.a,
                    short(ts / MAX_POLE_TIMES_TS),
                    short(ts)
                ),
            });
        }
        if self.a * span < 1.0 {
            return Err(IdentError::Implausible {
                what: name.clone(),
                value: self.a,
                reason: format!(
                    "its time constant 1/{name} = {:.3e} s is longer than the record ({} s)",
                    1.0 / self.a,
                    short(span)
                ),
            });
        }
        Ok(())
    }
}

/// The natural frequency `ω_n = √(m g l / α)` of a pendulum of inertia `α` about its pivot must
/// be resolved by the sampling and show in the record: `ω_n span ≥ 1` (a sixth of a period),
/// `ω_n t_s ≤` [`MAX_POLE_TIMES_TS`].
/// The first of the failed checks `failed`, or `Ok` if there is none: what each result's
/// `check` returns from its `failed_checks`.
fn first_failure(failed: Vec<IdentError>) -> Result<()> {
    failed.into_iter().next().map_or(Ok(()), Err)
}

/// The checks every least-squares result starts with: its own physical plausibility, then its
/// solution's ([`LeastSquares::check`]: finite, well conditioned); the failures, in that order.
fn plausible_and_solved(plausible: Result<()>, lsq: &LeastSquares) -> Vec<IdentError> {
    [plausible, lsq.check()]
        .into_iter()
        .filter_map(Result::err)
        .collect()
}

fn pendulum_in_record(j: (&str, f64), alpha: f64, mgl: f64, ts: f64, n: usize) -> Result<()> {
    let wn = (mgl / alpha).sqrt();
    let span = (n.max(2) - 1) as f64 * ts;
    let reason = if !wn.is_finite() {
        format!("the natural frequency √(m g l/(J + m l²)) = {wn} is not finite")
    } else if wn * span < 1.0 {
        format!(
            "the natural frequency it implies, ω_n = √(m g l/(J + m l²)) = {wn:.3e} rad/s, \
             would not show in the record ({} s: ω_n·span < 1 rad)",
            short(span)
        )
    } else if wn * ts > MAX_POLE_TIMES_TS {
        format!(
            "the natural frequency it implies, ω_n = {wn:.3e} rad/s, is faster than the \
             sampling at {} s resolves (ω_n t_s > {MAX_POLE_TIMES_TS})",
            short(ts)
        )
    } else {
        return Ok(());
    };
    Err(IdentError::Implausible {
        what: j.0.into(),
        value: j.1,
        reason,
    })
}

fn drive_from(lsq: LeastSquares) -> DriveLs {
    DriveLs {
        a: lsq.estimate[0],
        b: lsq.estimate[1],
        lsq,
    }
}

/// Cart drive `z̈ = −a_c ż + b_c v` by least squares (eq. 3.43; book `p1c322`).
///
/// # Errors
/// As [`cart_drive_regression`] and [`least_squares`] (rank deficiency, e.g. `v ≡ 0`).
#[doc(alias = "p1c322_cdip_id_least_square")]
pub fn cart_drive_ls(ts: f64, z: &[f64], v: &[f64], opts: &LsOptions) -> Result<DriveLs> {
    drive_ls(ts, ("z", z), v, ["ac", "bc"], opts)
}

fn drive_ls(
    ts: f64,
    y: (&str, &[f64]),
    v: &[f64],
    names: [&str; 2],
    opts: &LsOptions,
) -> Result<DriveLs> {
    if !streamable(opts) {
        return Ok(drive_from(
            drive_regression(ts, y, v, names, opts)?.solve()?,
        ));
    }
    opts.differentiator.validate()?;
    let n = y.1.len();
    let x = y.1;
    let mut d = BlockDerivatives::new(n, ts);
    let target = format!("{}_ddot", y.0);
    let signals = [y, ("v", v)];
    let lsq = stream_solve::<3>(
        &signals,
        ts,
        needed(opts),
        &opts.prefilter,
        &names,
        &target,
        |k0, m, raw| {
            let [dy, vv, ddy] = raw;
            d.load(x, k0, k0 + m, dy, ddy);
            for a in &mut dy[..m] {
                *a = -*a;
            }
            vv[..m].copy_from_slice(&v[k0..k0 + m]);
        },
    )
    .map_err(|e| describe_rank(e, &names, &[&format!("−d{}/dt", y.0), "v"]))?;
    Ok(drive_from(lsq))
}

/// Adds the meaning of each column to a rank-deficiency error.
fn describe_rank(e: IdentError, names: &[&str], signals: &[&str]) -> IdentError {
    match e {
        IdentError::RankDeficient {
            columns,
            condition,
            scaled_condition,
            limit,
            detail,
        } => IdentError::RankDeficient {
            detail: format!(
                "{detail} (columns: {})",
                names
                    .iter()
                    .zip(signals)
                    .map(|(n, s)| format!("{n} multiplies {s}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            columns,
            condition,
            scaled_condition,
            limit,
        },
        other => other,
    }
}

/// Arm drive `φ̈₁ = −a₁ φ̇₁ + b₁ v` by least squares (`M₁ = [−φ̇₁, v]`, `N₁ = φ̈₁`).
///
/// # Errors
/// As [`cart_drive_ls`].
#[doc(alias = "p1c332_adip_id_least_square")]
pub fn arm_drive_ls(ts: f64, phi1: &[f64], v: &[f64], opts: &LsOptions) -> Result<DriveLs> {
    drive_ls(ts, ("phi1", phi1), v, ["a1", "b1"], opts)
}

/// The cart-pendulum regression of eq. 3.45, filtered.
///
/// `z` in metres, `phi` = θ − π in radians (from the hanging rest).
///
/// # Errors
/// As [`cart_drive_regression`], and [`IdentError::InvalidParameter`] for non-positive
/// constants.
pub fn cart_pendulum_regression(
    ts: f64,
    z: &[f64],
    phi: &[f64],
    c: &CartPendulumConstants,
    opts: &LsOptions,
) -> Result<Regression> {
    c.validate()?;
    check_signals(&[("z", z), ("phi", phi)], ts, needed(opts))?;
    let dz = derivs(opts, z, ts)?;
    let dp = derivs(opts, phi, ts)?;
    let (ml, ml2, mgl) = (c.mp * c.lp, c.mp * c.lp * c.lp, c.mp * c.g * c.lp);
    let target: Vec<f64> = (0..z.len())
        .map(|k| {
            let (s, co) = phi[k].sin_cos();
            ml * co * dz.second[k] - ml2 * dp.second[k] - mgl * s
        })
        .collect();
    Regression {
        names: vec!["Jp".into(), "mup".into()],
        signals: vec!["d²phi/dt²".into(), "dphi/dt".into()],
        columns: vec![dp.second, dp.first],
        target_name: "N2".into(),
        target,
    }
    .filtered(&opts.prefilter, ts)
}

/// The cart pendulum `[J_p, μ_p]` identified by least squares.
#[derive(Debug, Clone, PartialEq)]
pub struct CartPendulumLs {
    /// Moment of inertia about the centre of mass `J_p`, kg m².
    pub jp: f64,
    /// Viscous friction `μ_p`, N m s/rad.
    pub mup: f64,
    /// The least-squares solution (names `Jp, mup`).
    pub lsq: LeastSquares,
}

impl CartPendulumLs {
    /// Checks `J_p > 0` and `μ_p ≥ 0`.
    ///
    /// # Errors
    /// [`IdentError::Implausible`] otherwise.
    pub fn check_plausible(&self) -> Result<()> {
        pendulum_plausible(("Jp", self.jp), ("mup", self.mup))
    }

    /// Every check of an estimate from data sampled every `ts` seconds with the constants
    /// `c`: [`CartPendulumLs::check_plausible`], [`LeastSquares::check`] (finite, well
    /// conditioned), and the natural frequency `ω_n = √(m_p g l_p/(J_p + m_p l_p²))` must
    /// show in the record (`ω_n span ≥ 1`) and be resolved by the sampling
    /// (`ω_n t_s ≤` [`MAX_POLE_TIMES_TS`]).
    ///
    /// # Errors
    /// [`IdentError::Implausible`], [`IdentError::NonFiniteResult`],
    /// [`IdentError::IllConditioned`].
    pub fn check(&self, ts: f64, c: &CartPendulumConstants) -> Result<()> {
        first_failure(self.failed_checks(ts, c))
    }

    /// Every failed check of [`CartPendulumLs::check`], not only the first.
    pub fn failed_checks(&self, ts: f64, c: &CartPendulumConstants) -> Vec<IdentError> {
        let mut out = plausible_and_solved(self.check_plausible(), &self.lsq);
        if self.jp > 0.0 {
            out.extend(
                pendulum_in_record(
                    ("Jp", self.jp),
                    self.jp + c.mp * c.lp * c.lp,
                    c.mp * c.g * c.lp,
                    ts,
                    self.lsq.samples,
                )
                .err(),
            );
        }
        out
    }
}

fn pendulum_plausible(j: (&str, f64), mu: (&str, f64)) -> Result<()> {
    if j.1.is_nan() || j.1 <= 0.0 {
        return Err(IdentError::Implausible {
            what: j.0.into(),
            value: j.1,
            reason: "a moment of inertia is positive".into(),
        });
    }
    if mu.1.is_nan() || mu.1 < 0.0 {
        return Err(IdentError::Implausible {
            what: mu.0.into(),
            value: mu.1,
            reason: "viscous friction dissipates energy (μ ≥ 0)".into(),
        });
    }
    Ok(())
}

/// Cart pendulum `[J_p, μ_p]` by least squares (eq. 3.45; book `p1c322`), with `m_p`,
/// `l_p`, `g` known.
///
/// # Errors
/// As [`cart_pendulum_regression`] and [`least_squares`].
#[doc(alias = "p1c322_cdip_id_least_square")]
pub fn cart_pendulum_ls(
    ts: f64,
    z: &[f64],
    phi: &[f64],
    c: &CartPendulumConstants,
    opts: &LsOptions,
) -> Result<CartPendulumLs> {
    let lsq = if streamable(opts) {
        c.validate()?;
        let n = z.len();
        let (ml, ml2, mgl) = (c.mp * c.lp, c.mp * c.lp * c.lp, c.mp * c.g * c.lp);
        let mut dz = BlockDerivatives::new(n, ts);
        let mut dp = BlockDerivatives::new(n, ts);
        let mut scratch = [0.0; BANK_BLOCK];
        let signals = [("z", z), ("phi", phi)];
        stream_solve::<3>(
            &signals,
            ts,
            needed(opts),
            &opts.prefilter,
            &["Jp", "mup"],
            "N2",
            |k0, m, raw| {
                let [ddp, dp1, target] = raw;
                // ż is not needed: `scratch` takes it; the target slot first holds z̈.
                dz.load(z, k0, k0 + m, &mut scratch, target);
                dp.load(phi, k0, k0 + m, dp1, ddp);
                for i in 0..m {
                    let (s, co) = phi[k0 + i].sin_cos();
                    target[i] = ml * co * target[i] - ml2 * ddp[i] - mgl * s;
                }
            },
        )
        .map_err(|e| describe_rank(e, &["Jp", "mup"], &["d²phi/dt²", "dphi/dt"]))?
    } else {
        cart_pendulum_regression(ts, z, phi, c, opts)?.solve()?
    };
    Ok(CartPendulumLs {
        jp: lsq.estimate[0],
        mup: lsq.estimate[1],
        lsq,
    })
}

/// The arm-pendulum regression (book part 1 §3.3, the arm form of eqs 3.43–3.45), filtered.
/// `phi1` = θ₁ (arm), `phi2` = θ₂ − π (pendulum from hanging), radians.
///
/// # Errors
/// As [`cart_pendulum_regression`].
pub fn arm_pendulum_regression(
    ts: f64,
    phi1: &[f64],
    phi2: &[f64],
    c: &ArmPendulumConstants,
    opts: &LsOptions,
) -> Result<Regression> {
    c.validate()?;
    check_signals(&[("phi1", phi1), ("phi2", phi2)], ts, needed(opts))?;
    let d1 = derivs(opts, phi1, ts)?;
    let d2 = derivs(opts, phi2, ts)?;
    let (a3, a5) = (c.alpha3(), c.alpha5());
    let target: Vec<f64> = (0..phi1.len())
        .map(|k| {
            let (s12, c12) = (phi1[k] - phi2[k]).sin_cos();
            a3 * c12 * d1.second[k] - a3 * d1.first[k] * d1.first[k] * s12 - a5 * phi2[k].sin()
        })
        .collect();
    let rel: Vec<f64> = d2.first.iter().zip(&d1.first).map(|(a, b)| a - b).collect();
    Regression {
        names: vec!["alpha2".into(), "mu2".into()],
        signals: vec!["d²phi2/dt²".into(), "dphi2/dt − dphi1/dt".into()],
        columns: vec![d2.second, rel],
        target_name: "N2".into(),
        target,
    }
    .filtered(&opts.prefilter, ts)
}

/// The arm pendulum identified by least squares.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmPendulumLs {
    /// `α₂ = J₂ + m₂ l₂²`, kg m².
    pub alpha2: f64,
    /// Viscous friction `μ₂`, N m s/rad.
    pub mu2: f64,
    /// `J₂ = α₂ − m₂ l₂²`, kg m² (its standard error is that of `α₂`).
    pub j2: f64,
    /// The least-squares solution (names `alpha2, mu2`).
    pub lsq: LeastSquares,
}

impl ArmPendulumLs {
    /// Checks `J₂ > 0` and `μ₂ ≥ 0`.
    ///
    /// # Errors
    /// [`IdentError::Implausible`] otherwise.
    pub fn check_plausible(&self) -> Result<()> {
        pendulum_plausible(("J2", self.j2), ("mu2", self.mu2))
    }

    /// Every check of an estimate from data sampled every `ts` seconds with the constants
    /// `c`, as [`CartPendulumLs::check`] with `ω_n = √(α₅/α₂)`.
    ///
    /// # Errors
    /// [`IdentError::Implausible`], [`IdentError::NonFiniteResult`],
    /// [`IdentError::IllConditioned`].
    pub fn check(&self, ts: f64, c: &ArmPendulumConstants) -> Result<()> {
        first_failure(self.failed_checks(ts, c))
    }

    /// Every failed check of [`ArmPendulumLs::check`], not only the first.
    pub fn failed_checks(&self, ts: f64, c: &ArmPendulumConstants) -> Vec<IdentError> {
        let mut out = plausible_and_solved(self.check_plausible(), &self.lsq);
        if self.j2 > 0.0 {
            out.extend(
                pendulum_in_record(
                    ("J2", self.j2),
                    self.alpha2,
                    c.alpha5(),
                    ts,
                    self.lsq.samples,
                )
                .err(),
            );
        }
        out
    }
}

/// Arm pendulum `[α₂, μ₂] → J₂` by least squares (book `p1c332`), with `L₁`, `m₂`, `l₂`,
/// `g` known.
///
/// # Errors
/// As [`arm_pendulum_regression`] and [`least_squares`].
#[doc(alias = "p1c332_adip_id_least_square")]
pub fn arm_pendulum_ls(
    ts: f64,
    phi1: &[f64],
    phi2: &[f64],
    c: &ArmPendulumConstants,
    opts: &LsOptions,
) -> Result<ArmPendulumLs> {
    let lsq = if streamable(opts) {
        c.validate()?;
        let n = phi1.len();
        let (a3, a5) = (c.alpha3(), c.alpha5());
        let mut d1 = BlockDerivatives::new(n, ts);
        let mut d2 = BlockDerivatives::new(n, ts);
        let mut w1 = [0.0; BANK_BLOCK];
        let signals = [("phi1", phi1), ("phi2", phi2)];
        stream_solve::<3>(
            &signals,
            ts,
            needed(opts),
            &opts.prefilter,
            &["alpha2", "mu2"],
            "N2",
            |k0, m, raw| {
                let [dd2, rel, target] = raw;
                // The target slot first holds φ̈₁; `w1` takes φ̇₁.
                d1.load(phi1, k0, k0 + m, &mut w1, target);
                d2.load(phi2, k0, k0 + m, rel, dd2);
                for i in 0..m {
                    let k = k0 + i;
                    let (s12, c12) = (phi1[k] - phi2[k]).sin_cos();
                    let w = w1[i];
                    rel[i] -= w;
                    target[i] = a3 * c12 * target[i] - a3 * w * w * s12 - a5 * phi2[k].sin();
                }
            },
        )
        .map_err(|e| {
            describe_rank(
                e,
                &["alpha2", "mu2"],
                &["d²phi2/dt²", "dphi2/dt − dphi1/dt"],
            )
        })?
    } else {
        arm_pendulum_regression(ts, phi1, phi2, c, opts)?.solve()?
    };
    Ok(ArmPendulumLs {
        alpha2: lsq.estimate[0],
        mu2: lsq.estimate[1],
        j2: lsq.estimate[0] - c.m2 * c.l2 * c.l2,
        lsq,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::differentiate::savitzky_golay;
    use crate::filter::FilterHold;

    const TS: f64 = 1e-3;

    fn causal(tf: f64) -> LsOptions {
        LsOptions {
            prefilter: Prefilter::Causal {
                tf,
                hold: FilterHold::Zoh,
            },
            ..LsOptions::default()
        }
    }

    #[test]
    fn sample_count_for_the_differentiator() {
        // Three-point twice: a 5-sample stencil, four of them → 20 samples; unfiltered so the
        // filter bound does not interfere.
        let raw = LsOptions {
            prefilter: Prefilter::None,
            ..LsOptions::default()
        };
        assert!(raw.check_data(TS, 20).is_ok());
        let e = raw.check_data(TS, 19).unwrap_err();
        assert!(
            matches!(
                e,
                IdentError::TooFewSamples {
                    needed: 20,
                    found: 19,
                    ..
                }
            ),
            "{e}"
        );
        // Savitzky–Golay: the window, four times.
        let sg = LsOptions {
            differentiator: Differentiator::SavitzkyGolay {
                window: 41,
                order: 3,
            },
            prefilter: Prefilter::None,
        };
        assert!(sg.check_data(TS, 164).is_ok());
        assert!(matches!(
            sg.check_data(TS, 163),
            Err(IdentError::TooFewSamples { needed: 164, .. })
        ));
    }

    #[test]
    fn prefilter_time_constant_against_record_and_sample_time() {
        // Record of 4001 samples = 4 s: T_f up to 0.4 s.
        assert!(causal(0.4).check_data(TS, 4001).is_ok());
        let e = causal(0.41).check_data(TS, 4001).unwrap_err();
        assert!(
            matches!(&e, IdentError::UnsuitedOption { option, .. } if option.contains("T_f")),
            "{e}"
        );
        assert!(matches!(
            causal(1e9).check_data(TS, 4001),
            Err(IdentError::UnsuitedOption { .. })
        ));
        // Short T_f: the twice-applied three-point derivative errs by 1 − (sin x/x)², x = t_s/T_f.
        // Found independently by differentiating a sampled sinusoid at ω = 1/T_f.
        let err_at = |tf: f64| {
            let w = 1.0 / tf;
            let x: Vec<f64> = (0..200).map(|k| (w * k as f64 * TS).sin()).collect();
            let d2 = crate::differentiate::three_point_twice(&x, TS).unwrap();
            // Interior sample 100, away from the ends: exact second derivative −ω² sin.
            let exact = -w * w * (w * 100.0 * TS).sin();
            (d2[100] / exact - 1.0).abs()
        };
        let (short, long) = (4.0 * TS, 8.0 * TS);
        assert!(err_at(short) > MAX_DERIVATIVE_ERROR && err_at(long) < MAX_DERIVATIVE_ERROR);
        assert!(matches!(
            causal(short).check_data(TS, 4001),
            Err(IdentError::UnsuitedOption { .. })
        ));
        assert!(causal(long).check_data(TS, 4001).is_ok());
        // The book's recipe on the book's record passes.
        assert!(LsOptions::default().check_data(TS, 4001).is_ok());
    }

    #[test]
    fn savitzky_golay_window_against_the_dynamics() {
        // The error at the band edge 1/T_f, measured independently by differentiating a
        // sampled sinusoid with the Savitzky–Golay routine (not the kernel's response).
        let measured = |window: usize, tf: f64| {
            let w = 1.0 / tf;
            let n = 3 * window;
            let x: Vec<f64> = (0..n).map(|k| (w * k as f64 * TS).sin()).collect();
            let d1 = savitzky_golay(&x, TS, window, 3, 1).unwrap();
            let d2 = savitzky_golay(&x, TS, window, 3, 2).unwrap();
            let k = n / 2;
            let t = k as f64 * TS;
            let e1 = (d1[k] - w * (w * t).cos()).abs() / w;
            let e2 = (d2[k] + w * w * (w * t).sin()).abs() / (w * w);
            e1.max(e2)
        };
        let sg = |window: usize, tf: f64| LsOptions {
            differentiator: Differentiator::SavitzkyGolay { window, order: 3 },
            ..causal(tf)
        };
        // 41 samples (40 ms) against T_f = 0.075 s: accurate, accepted.
        assert!(measured(41, 0.075) < MAX_DERIVATIVE_ERROR);
        assert!(sg(41, 0.075).check_data(TS, 4001).is_ok());
        // 301 samples (0.3 s) against T_f = 0.075 s: inaccurate, refused (the record is long
        // enough for the stencil count and the filter, so the window is what is named).
        assert!(measured(301, 0.075) > MAX_DERIVATIVE_ERROR);
        let e = sg(301, 0.075).check_data(TS, 20_001).unwrap_err();
        assert!(
            matches!(&e, IdentError::UnsuitedOption { option, .. } if option.contains("Savitzky")),
            "{e}"
        );
        // The 4001-sample window on the 4001-sample record: too few stencils.
        assert!(matches!(
            sg(4001, 0.075).check_data(TS, 4001),
            Err(IdentError::TooFewSamples { .. })
        ));
    }

    #[test]
    fn constants_out_of_range_are_named() {
        assert!(CartPendulumConstants::default().check_range().is_ok());
        assert!(ArmPendulumConstants::default().check_range().is_ok());
        let e = CartPendulumConstants {
            mp: 1e-300,
            ..Default::default()
        }
        .check_range()
        .unwrap_err();
        assert!(
            matches!(&e, IdentError::ConstantOutOfRange { name, min, .. } if name == "m_p" && *min == MASS_RANGE.0),
            "{e}"
        );
        let e = ArmPendulumConstants {
            l2: 3.0,
            ..Default::default()
        }
        .check_range()
        .unwrap_err();
        assert!(e.to_string().contains("l2 = 3"), "{e}");
        assert!(matches!(
            CartPendulumConstants {
                g: 1.62,
                ..Default::default()
            }
            .check_range(),
            Err(IdentError::ConstantOutOfRange { .. })
        ));
    }
}
