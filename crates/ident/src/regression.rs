//! The book's least-squares identifications (eqs 3.43–3.47, SPEC.md §2).
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
//! Substituting θ₂ = φ₂ + π into SPEC.md §1.2's pendulum equation gives exactly the arm row
//! of the table.
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

use crate::differentiate::{Derivatives, Differentiator, three_point_at};
use crate::error::{IdentError, Result, SamplePos, UNNAMED};
use crate::filter::{BANK_BLOCK, FilterBank, LowPass3, Prefilter};
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

/// Known constants of the cart-type pendulum (SPEC.md §1.1, table 3.5).
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

/// Known constants of the arm-type pendulum (SPEC.md §1.2, table 3.7).
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
    fn validate(&self) -> Result<()> {
        positive("m_p", self.mp)?;
        positive("l_p", self.lp)?;
        positive("g", self.g)
    }
}

impl ArmPendulumConstants {
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

/// The arm-pendulum regression (SPEC.md §2), filtered. `phi1` = θ₁ (arm), `phi2` = θ₂ − π
/// (pendulum from hanging), radians.
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
