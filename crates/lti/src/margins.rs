//! Classical loop analysis of a SISO loop transfer function `L`: every gain and phase
//! crossing with its gain, phase and delay margin (MATLAB `allmargin` / `margin`,
//! python-control `stability_margins(…, returnall=True)`), and the gang of four.
//!
//! # Definitions and conventions
//!
//! The loop `L(s)` (continuous, `s = jω`) or `L(z)` (discrete, `z = e^{jωts}`) is closed with
//! negative unit feedback, `u = −L y`; frequencies are in rad/s.
//!
//! - A **gain crossing** is a frequency `ω > 0` with `|L(jω)| = 1`. Its **phase margin** is
//!   `PM = mod(∠L(jω), 360°) − 180°` in `[−180°, 180°)` (python-control's convention; MATLAB
//!   reports the same number) and its **delay margin** is the smallest delay `τ ≥ 0` that
//!   moves the crossing onto `−1`: `L(jω)e^{−jωτ} = −1`, i.e. `τ = mod(PM, 360°)·(π/180°)/ω`
//!   in seconds (for discrete loops divide by `ts` for MATLAB's "sample periods"; it is not
//!   rounded to an integer).
//! - A **phase crossing** is a frequency `ω ≥ 0` where `L(jω)` is real and `≤ 0` (the Nyquist
//!   curve crosses the negative real axis, the phase passes −180° modulo 360°). Its **gain
//!   margin** is `GM = 1/|L(jω)|` (a factor; `20 log₁₀ GM` in dB). `ω = 0` counts when the DC
//!   gain is finite and negative. For discrete loops the search covers `0 ≤ ω < π/ts`: the
//!   Nyquist frequency itself, where `L` is always real, is excluded, as in python-control.
//! - The **reported margins** are python-control's choice among all crossings: the gain
//!   margin closest to 1 in the log sense (`min |ln GM|`), the phase margin smallest in
//!   absolute value, and (our addition, MATLAB `allmargin`'s `DelayMargin` minimum) the
//!   smallest delay margin.
//!
//! # Method
//!
//! `(A, b)` is reduced once, orthogonally, to controller-Hessenberg form (`QᵀAQ` upper
//! Hessenberg, `Qᵀb = βe₁`) and `L` evaluated from it by Hyman's method (a real-times-complex
//! recurrence of `O(n²)` per point without pivoting or allocation, componentwise backward
//! stable; the DC gain comes from the same form, refused when a pole lies within
//! `n ε (‖A‖_F + 1)` of `s = 0` (`z = 1`), as [`StateSpace::dc_gain`] refuses it) on a
//! logarithmic grid of 20 points per decade that covers two decades beyond the slowest and
//! fastest pole and zero and is extended further where the asymptotic slope of `|L|`
//! predicts a gain crossing beyond it; an interval is bisected (in `ln ω`) while the phase
//! turns by more than 15° across it, or the magnitude changes by more than a factor
//! `e^{0.35}` across it with `|ln |L||` at an end within twice that change of 0 (near
//! `|L| = 1`, where a pair of gain crossings could hide), up to 16 levels, so a lightly
//! damped resonance is resolved. A crossing is bracketed where `ln |L|` (gain) or
//! `sin ∠L` (phase) changes sign between neighbouring grid points and refined by the
//! Illinois variant of regula falsi on `ln ω` to a bracket width of a few ulp, all brackets
//! in lock-step (one frequency-response call per step).
//!
//! # Poles on the stability boundary (documented status)
//!
//! Loop poles on the imaginary axis (unit circle), e.g. integrators, are allowed: their
//! frequencies are reported in [`StabilityMargins::boundary_pole_frequencies`], the grid
//! steps around them (no evaluation within a relative `10⁻⁸` of one), and a sign change of
//! `sin ∠L` caused by the phase jump of ±180° across such a pole is recognised (the refined
//! point is not real) and not reported as a crossing. A pole at `ω = 0` removes the `ω = 0`
//! phase crossing (the DC gain is infinite).

use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::frequency_response::SisoHessenbergEvaluator;
use crate::interconnect::{FeedbackSign, feedback, series};
use crate::linalg::{Complex64, Mat};
use crate::state_space::StateSpace;
use crate::transfer_function::TransferFunction;
use std::cell::RefCell;

/// A gain crossing `|L(jω)| = 1` with its phase and delay margins.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GainCrossing {
    /// Crossing frequency `ω` in rad/s (`> 0`).
    pub frequency: f64,
    /// Phase margin `mod(∠L, 360°) − 180°` in degrees, in `[−180°, 180°)`.
    pub phase_margin_deg: f64,
    /// Delay margin `mod(PM, 360°)·(π/180°)/ω` in seconds.
    pub delay_margin: f64,
}

/// A phase crossing (`L(jω)` real and `≤ 0`) with its gain margin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhaseCrossing {
    /// Crossing frequency `ω` in rad/s (`≥ 0`).
    pub frequency: f64,
    /// Gain margin `1/|L(jω)|` as a factor (infinite where `L(jω) = 0`).
    pub gain_margin: f64,
}

impl PhaseCrossing {
    /// The gain margin in dB, `20 log₁₀ GM`.
    pub fn gain_margin_db(&self) -> f64 {
        20.0 * self.gain_margin.log10()
    }
}

/// All gain and phase crossings of a SISO loop (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct StabilityMargins {
    /// Every gain crossing, by increasing frequency.
    pub gain_crossings: Vec<GainCrossing>,
    /// Every phase crossing of the negative real axis, by increasing frequency.
    pub phase_crossings: Vec<PhaseCrossing>,
    /// Frequencies (rad/s, `≥ 0`, ascending, each once) of loop poles on the imaginary axis
    /// (unit circle) within a relative `10⁻⁹`: integrators, undamped modes.
    pub boundary_pole_frequencies: Vec<f64>,
    /// Sample time of a discrete loop (seconds), `None` in continuous time.
    pub sample_time: Option<f64>,
}

impl StabilityMargins {
    /// The reported gain margin: the phase crossing whose gain margin is closest to 1 in the
    /// log sense (`min |ln GM|`, python-control's and MATLAB `margin`'s choice); `None`
    /// without a phase crossing (an infinite gain margin).
    #[doc(alias = "margin")]
    pub fn gain_margin(&self) -> Option<PhaseCrossing> {
        self.phase_crossings.iter().copied().min_by(|a, b| {
            a.gain_margin
                .ln()
                .abs()
                .total_cmp(&b.gain_margin.ln().abs())
        })
    }

    /// The reported phase margin: the gain crossing with the smallest `|PM|`; `None` without
    /// a gain crossing (an infinite phase margin).
    pub fn phase_margin(&self) -> Option<GainCrossing> {
        self.gain_crossings.iter().copied().min_by(|a, b| {
            a.phase_margin_deg
                .abs()
                .total_cmp(&b.phase_margin_deg.abs())
        })
    }

    /// The gain crossing with the smallest delay margin; `None` without a gain crossing.
    pub fn delay_margin(&self) -> Option<GainCrossing> {
        self.gain_crossings
            .iter()
            .copied()
            .min_by(|a, b| a.delay_margin.total_cmp(&b.delay_margin))
    }
}

/// Grid density before refinement (points per decade).
const POINTS_PER_DECADE: f64 = 20.0;
/// Refinement: split an interval while the phase turns by more than this (radians) …
const MAX_PHASE_STEP: f64 = 15.0 * std::f64::consts::PI / 180.0;
/// … or `ln |L|` changes by more than this.
const MAX_LOG_MAG_STEP: f64 = 0.35;
/// At most this many bisection levels.
const MAX_LEVELS: usize = 16;
/// Relative distance kept from a boundary pole's frequency.
const POLE_GAP: f64 = 1e-8;

/// All gain and phase crossings of the SISO loop `L` with their margins (MATLAB `allmargin`,
/// python-control `stability_margins(L, returnall=True)`); the definitions, the method and
/// the status of poles on the stability boundary are in the module documentation.
///
/// # Errors
/// [`LtiError::NotSiso`] unless `L` has one input and one output; [`LtiError::NoConvergence`]
/// from the pole and zero computations.
#[doc(alias = "allmargin")]
#[doc(alias = "margin")]
pub fn stability_margins<D: TimeDomain>(l: &StateSpace<D>) -> Result<StabilityMargins> {
    if l.nu() != 1 || l.ny() != 1 {
        return Err(LtiError::NotSiso {
            what: "stability_margins".into(),
            ny: l.ny(),
            nu: l.nu(),
        });
    }
    let ts = l.domain().sample_time();
    let poles = l.poles()?;
    let zeros = l.zeros()?;
    let scale = l.a().norm().max(1.0);
    let to_freq = |p: Complex64| -> Option<f64> {
        match ts {
            None => Some(p.norm()),
            Some(ts) => (p.norm() > 0.0).then(|| (p.ln() / ts).norm()),
        }
    };
    let mut boundary: Vec<f64> = poles
        .iter()
        .filter(|p| {
            let d = l.domain().stability_distance(**p).abs();
            d <= 1e-9
                * if ts.is_some() {
                    1.0
                } else {
                    p.norm().max(1e-9 * scale)
                }
        })
        .map(|p| match ts {
            None => p.im.abs(),
            Some(ts) => p.arg().abs() / ts,
        })
        .collect();
    boundary.sort_by(f64::total_cmp);
    boundary.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs().max(1e-300));
    let mags: Vec<f64> = poles
        .iter()
        .chain(zeros.iter())
        .filter_map(|&p| to_freq(p))
        .filter(|&m| m > 0.0 && m.is_finite())
        .collect();
    let nyquist = ts.map(|ts| std::f64::consts::PI / ts);
    let (mut lo, mut hi) = if mags.is_empty() {
        (1e-2, 1e2)
    } else {
        let mn = mags.iter().copied().fold(f64::INFINITY, f64::min);
        let mx = mags.iter().copied().fold(0.0, f64::max);
        (mn / 100.0, mx * 100.0)
    };
    if let Some(wn) = nyquist {
        hi = wn;
        lo = lo.min(wn / 1e3);
    }
    let avoid = |w: f64| -> f64 {
        // Step off a boundary pole's frequency (the response is infinite there).
        match boundary
            .iter()
            .find(|&&p| (w - p).abs() <= POLE_GAP * p.max(f64::MIN_POSITIVE))
        {
            Some(&p) => p * (1.0 + 2.0 * POLE_GAP),
            None => w,
        }
    };
    // One controller-Hessenberg reduction for every evaluation of the search.
    let evaluator = RefCell::new(SisoHessenbergEvaluator::new(l.a(), l.b(), l.c(), l.d()));
    let eval = |w: &[f64]| -> Result<Vec<Complex64>> {
        let mut ev = evaluator.borrow_mut();
        w.iter()
            .map(|&x| {
                let wk = avoid(x);
                let s = match ts {
                    None => Complex64::new(0.0, wk),
                    Some(ts) => Complex64::from_polar(1.0, wk * ts),
                };
                ev.eval(s).map_err(|()| LtiError::PoleAtEvaluationPoint {
                    what: format!("stability_margins at {wk} rad/s"),
                    pole: s,
                })
            })
            .collect()
    };
    let grid_between = |lo: f64, hi: f64| -> Vec<f64> {
        let decades = (hi / lo).log10();
        let n = ((decades * POINTS_PER_DECADE).ceil() as usize).max(2);
        (0..=n)
            .map(|k| avoid(lo * (hi / lo).powf(k as f64 / n as f64)))
            .collect()
    };
    let mut w = grid_between(lo, hi);
    if let Some(wn) = nyquist {
        // Stay strictly below the Nyquist frequency (L is real there by symmetry).
        let last = w.len() - 1;
        w[last] = wn * (1.0 - 1e-12);
    }
    let mut g = eval(&w)?;
    // Extend the ends where the asymptotic slope of |L| predicts a gain crossing beyond them.
    for _ in 0..8 {
        let mut grew = false;
        let k = w.len();
        if nyquist.is_none() {
            let slope = (g[k - 1].norm().ln() - g[k - 2].norm().ln()) / (w[k - 1] / w[k - 2]).ln();
            let lm = g[k - 1].norm().ln();
            if slope.is_finite() && slope.abs() > 1e-3 && lm.is_finite() && lm / slope < 0.0 {
                let target = (w[k - 1] * (-lm / slope).exp() * 100.0).min(w[k - 1] * 1e12);
                let ext = grid_between(w[k - 1], target);
                let ge = eval(&ext[1..])?;
                w.extend_from_slice(&ext[1..]);
                g.extend(ge);
                grew = true;
            }
        }
        let slope = (g[1].norm().ln() - g[0].norm().ln()) / (w[1] / w[0]).ln();
        let lm = g[0].norm().ln();
        if slope.is_finite() && slope.abs() > 1e-3 && lm.is_finite() && lm / slope > 0.0 {
            let target = (w[0] * (-lm / slope).exp() / 100.0).max(w[0] * 1e-12);
            let ext = grid_between(target, w[0]);
            let n = ext.len() - 1;
            let ge = eval(&ext[..n])?;
            let mut nw = ext[..n].to_vec();
            nw.extend_from_slice(&w);
            let mut ng = ge;
            ng.extend_from_slice(&g);
            w = nw;
            g = ng;
            grew = true;
        }
        if !grew {
            break;
        }
    }
    // Adaptive refinement, level by level (one response call per level).
    for _ in 0..MAX_LEVELS {
        let mids: Vec<(usize, f64)> = (0..w.len() - 1)
            .filter(|&i| {
                let (a, b) = (g[i], g[i + 1]);
                let turn = (b / a).arg().abs();
                let (la, lb) = (log_modulus(a), log_modulus(b));
                let dm = (lb - la).abs();
                // A large magnitude step matters only near |L| = 1 (a gain crossing could
                // hide in it); far from it, a crossing needs the phase to turn.
                let near_one = la.abs().min(lb.abs()) <= 2.0 * dm || la * lb <= 0.0;
                !(turn <= MAX_PHASE_STEP && (dm <= MAX_LOG_MAG_STEP || !near_one))
            })
            .map(|i| (i, avoid((w[i] * w[i + 1]).sqrt())))
            .filter(|&(i, m)| m > w[i] && m < w[i + 1])
            .collect();
        if mids.is_empty() {
            break;
        }
        let gm = eval(&mids.iter().map(|m| m.1).collect::<Vec<_>>())?;
        (w, g) = insert_midpoints(&w, &g, &mids, &gm);
    }
    let logmag = log_modulus;
    let sinarg = |v: Complex64| v.im / v.norm();
    // Brackets (grid indices) of sign changes.
    let gain_brackets: Vec<usize> = (0..w.len() - 1)
        .filter(|&i| changes_sign(logmag(g[i]), logmag(g[i + 1])))
        .collect();
    let phase_brackets: Vec<usize> = (0..w.len() - 1)
        .filter(|&i| changes_sign(sinarg(g[i]), sinarg(g[i + 1])))
        .collect();
    let wg = refine(&w, &g, &gain_brackets, logmag, &eval)?;
    let wp = refine(&w, &g, &phase_brackets, sinarg, &eval)?;
    let mut gain_crossings: Vec<GainCrossing> = wg
        .into_iter()
        .filter(|&(_, v)| (v.norm() - 1.0).abs() <= 1e-6)
        .map(|(wc, v)| {
            let pm = v.arg().to_degrees().rem_euclid(360.0) - 180.0;
            GainCrossing {
                frequency: wc,
                phase_margin_deg: pm,
                delay_margin: pm.rem_euclid(360.0).to_radians() / wc,
            }
        })
        .collect();
    let mut phase_crossings: Vec<PhaseCrossing> = wp
        .into_iter()
        .filter(|&(_, v)| v.re <= 0.0 && v.im.abs() <= 1e-6 * v.norm())
        .map(|(wc, v)| PhaseCrossing {
            frequency: wc,
            gain_margin: 1.0 / v.norm(),
        })
        .collect();
    // ω = 0: a finite negative DC gain is a phase crossing.
    // The DC gain from the same reduction, refused (as `dc_gain` does) when `s₀I − A` is
    // singular to working precision: a pole within `n ε (‖A‖_F + 1)` of `s₀`.
    let s0 = Complex64::new(if ts.is_some() { 1.0 } else { 0.0 }, 0.0);
    let near_s0 = (l.nx().max(1) as f64) * f64::EPSILON * (l.a().norm() + 1.0);
    if boundary.first().is_none_or(|&p| p > 0.0)
        && poles.iter().all(|&p| (p - s0).norm() > near_s0)
        && let Ok(dc) = evaluator.borrow_mut().eval(s0)
        && dc.re < 0.0
    {
        phase_crossings.insert(
            0,
            PhaseCrossing {
                frequency: 0.0,
                gain_margin: 1.0 / dc.re.abs(),
            },
        );
    }
    gain_crossings.sort_by(|a, b| a.frequency.total_cmp(&b.frequency));
    phase_crossings.sort_by(|a, b| a.frequency.total_cmp(&b.frequency));
    Ok(StabilityMargins {
        gain_crossings,
        phase_crossings,
        boundary_pole_frequencies: boundary,
        sample_time: ts,
    })
}

/// [`stability_margins`] of a SISO transfer function (through its state-space realisation).
///
/// # Errors
/// [`LtiError::Improper`] for an improper transfer function; otherwise as
/// [`stability_margins`].
pub fn stability_margins_tf<D: TimeDomain>(l: &TransferFunction<D>) -> Result<StabilityMargins> {
    stability_margins(&l.to_state_space()?)
}

/// One step of adaptive frequency refinement: the grid `w` with its values `v`, and the new
/// points `mids` (`(i, ω)`: ω lies between `w[i]` and `w[i + 1]`, `i` increasing) with their
/// values `vm`, merged into one increasing grid and its values.
pub(crate) fn insert_midpoints<T: Copy>(
    w: &[f64],
    v: &[T],
    mids: &[(usize, f64)],
    vm: &[T],
) -> (Vec<f64>, Vec<T>) {
    let mut nw = Vec::with_capacity(w.len() + mids.len());
    let mut nv = Vec::with_capacity(w.len() + mids.len());
    let mut next = mids.iter().zip(vm).peekable();
    for i in 0..w.len() {
        nw.push(w[i]);
        nv.push(v[i]);
        if let Some(((j, m), x)) = next.peek()
            && *j == i
        {
            nw.push(*m);
            nv.push(**x);
            next.next();
        }
    }
    (nw, nv)
}

/// `ln |z|`, from `|z|²` where that neither over- nor underflows.
fn log_modulus(z: Complex64) -> f64 {
    let q = z.norm_sqr();
    if q.is_finite() && q > f64::MIN_POSITIVE {
        0.5 * q.ln()
    } else {
        z.norm().ln()
    }
}

fn changes_sign(a: f64, b: f64) -> bool {
    a.is_finite() && b.is_finite() && ((a <= 0.0 && b > 0.0) || (a > 0.0 && b <= 0.0))
}

/// Refines every bracket `[w[i], w[i+1]]` of a sign change of `f(L(jω))` by the Illinois
/// method on `ln ω`, all brackets in lock-step; returns `(ω, L(jω))` per bracket.
fn refine<F, E>(
    w: &[f64],
    g: &[Complex64],
    brackets: &[usize],
    f: F,
    eval: &E,
) -> Result<Vec<(f64, Complex64)>>
where
    F: Fn(Complex64) -> f64,
    E: Fn(&[f64]) -> Result<Vec<Complex64>>,
{
    struct Br {
        a: f64,
        fa: f64,
        b: f64,
        fb: f64,
        best: (f64, Complex64, f64),
        done: bool,
    }
    let mut br: Vec<Br> = brackets
        .iter()
        .map(|&i| {
            let (fa, fb) = (f(g[i]), f(g[i + 1]));
            let best = if fa.abs() <= fb.abs() {
                (w[i], g[i], fa.abs())
            } else {
                (w[i + 1], g[i + 1], fb.abs())
            };
            Br {
                a: w[i].ln(),
                fa,
                b: w[i + 1].ln(),
                fb,
                best,
                done: false,
            }
        })
        .collect();
    for _ in 0..200 {
        let active: Vec<usize> = (0..br.len()).filter(|&k| !br[k].done).collect();
        if active.is_empty() {
            break;
        }
        let xs: Vec<f64> = active
            .iter()
            .map(|&k| {
                let r = &br[k];
                let x = (r.a * r.fb - r.b * r.fa) / (r.fb - r.fa);
                if x.is_finite() && x > r.a.min(r.b) && x < r.a.max(r.b) {
                    x
                } else {
                    0.5 * (r.a + r.b)
                }
            })
            .collect();
        let ws: Vec<f64> = xs.iter().map(|x| x.exp()).collect();
        let vs = eval(&ws)?;
        for ((&k, &x), v) in active.iter().zip(&xs).zip(vs) {
            let r = &mut br[k];
            let fx = f(v);
            if fx.abs() < r.best.2 || !r.best.2.is_finite() {
                r.best = (x.exp(), v, fx.abs());
            }
            if fx == 0.0 || !fx.is_finite() {
                r.done = true;
                continue;
            }
            if changes_sign(fx, r.fb) {
                r.a = r.b;
                r.fa = r.fb;
                r.b = x;
                r.fb = fx;
            } else {
                r.b = x;
                r.fb = fx;
                r.fa *= 0.5;
            }
            if (r.a - r.b).abs() <= 4.0 * f64::EPSILON * r.a.abs().max(r.b.abs()).max(1.0) {
                r.done = true;
            }
        }
    }
    Ok(br.into_iter().map(|r| (r.best.0, r.best.1)).collect())
}

/// The gang of four of the loop `P`, `C` under negative feedback `u = −C y` (output
/// sensitivity convention, MIMO allowed): `S = (I + PC)⁻¹`, `T = PC(I + PC)⁻¹ = I − S`,
/// `PS = P(I + CP)⁻¹` (load disturbance to output) and `CS = C(I + PC)⁻¹` (noise to control).
#[derive(Debug, Clone, PartialEq)]
pub struct GangOfFour<D: TimeDomain> {
    /// Sensitivity `S = (I + PC)⁻¹`.
    pub s: StateSpace<D>,
    /// Complementary sensitivity `T = PC(I + PC)⁻¹`.
    pub t: StateSpace<D>,
    /// Load sensitivity `PS = P(I + CP)⁻¹`.
    pub ps: StateSpace<D>,
    /// Noise sensitivity `CS = C(I + PC)⁻¹`.
    pub cs: StateSpace<D>,
}

/// The gang of four (see [`GangOfFour`]), each a state-space system built with
/// [`series`] and [`feedback`] (MATLAB `loopsens`, python-control `gangof4`). `S` and `T`
/// act on the outputs of `P`, `PS` from `P`'s input to its output, `CS` from `P`'s output
/// (the measurement noise) to `C`'s output.
///
/// # Errors
/// [`LtiError::DimensionMismatch`] unless `C` maps `P`'s outputs to its inputs;
/// [`LtiError::Singular`] for an ill-posed loop (`I + D_P D_C` singular);
/// [`LtiError::SampleTimeMismatch`].
#[doc(alias = "gangof4")]
#[doc(alias = "loopsens")]
pub fn gang_of_four<D: TimeDomain>(p: &StateSpace<D>, c: &StateSpace<D>) -> Result<GangOfFour<D>> {
    if c.nu() != p.ny() || c.ny() != p.nu() {
        return Err(LtiError::DimensionMismatch {
            what: "gang_of_four: C (outputs x inputs, must be P's inputs x outputs)".into(),
            expected: (p.nu(), p.ny()),
            found: (c.ny(), c.nu()),
        });
    }
    let l = series(c, p)?; // L = P C
    let eye = StateSpace::static_gain(Mat::identity(p.ny(), p.ny()), p.domain())?;
    Ok(GangOfFour {
        s: feedback(&eye, &l, FeedbackSign::Negative)?,
        t: feedback(&l, &eye, FeedbackSign::Negative)?,
        ps: feedback(p, c, FeedbackSign::Negative)?,
        cs: feedback(c, p, FeedbackSign::Negative)?,
    })
}
