//! The Nyquist curve of a SISO loop with its encirclement count and the Nyquist criterion
//! (MATLAB `nyquist`, python-control `nyquist_response`), and the Nichols curve (MATLAB
//! `nichols`).
//!
//! # The contour and the count (python-control 0.10's convention)
//!
//! The loop `L` is closed with negative unit feedback. Its **Nyquist contour** runs up the
//! imaginary axis `s = jω`, `ω` from `0` to `∞` (for a discrete loop `z = e^{sT}` runs along
//! the upper half of the unit circle, `ω` from `0` to the Nyquist frequency `π/T`); the lower
//! half is the mirror image (`L(s̄) = conj L(s)`), and the closing arc at infinity maps to the
//! constant `D` of a proper loop, so only the upper half is computed.
//!
//! **Indentation.** A loop pole `p` within `r` (the indentation radius, default `10⁻⁴` rad/s,
//! python-control's `indent_radius`) of the imaginary axis (for a discrete loop: `ln(z)/T`
//! within `r` of it, poles at `z = 0` ignored) is avoided: each contour point `s` with
//! `|s − p| < r` is moved along the real axis onto the circle `|s − p| = r`, to the **right**
//! for `Re p ≤ 0` and to the left for `Re p > 0` (python-control's `indent_direction =
//! 'right'`; MATLAB draws no indentation but treats imaginary-axis poles alike). The contour
//! is densified around such a pole before it is moved. An imaginary-axis pole thus lies
//! outside the contour and counts as stable.
//!
//! **Count.** `N` is the number of **clockwise** encirclements of `−1`: the accumulated
//! change of `−arg(1 + L)` along the upper half divided by `π` (the lower half contributes as
//! much by symmetry), rounded. `P` is the number of open-loop poles with `Re p > 0` (`|z| > 1`)
//! and the Nyquist criterion states that the closed loop has `Z = N + P` poles in the closed
//! right half-plane (on or outside the unit circle); [`NyquistCurve::closed_loop_unstable`]
//! counts them directly from the closed loop's poles (with `Re ≥ 0`, `|z| ≥ 1`, as
//! python-control) so the check [`NyquistCurve::criterion_holds`] is independent of the
//! curve. A pole within a relative `10⁻⁹` (of `max(|p|, 1)`) of the boundary counts as on
//! it, for the indentation and both counts: an integrator computed as `±10⁻¹⁷` is an
//! integrator.
//!
//! # Method
//!
//! A logarithmic grid covers two decades beyond the slowest and fastest pole and zero, starts
//! at `ω = 0` and, for a continuous loop, is extended by decades until `|L(jω) − D| ≤
//! 10⁻³·|1 + D|`; a discrete loop's grid ends exactly at `π/T`. Every interval across which
//! `arg(1 + L)` turns by more than 10° or `|L|` changes by more than a factor `e^{0.25}` is
//! bisected (in the frequency parameter, the indentation re-applied), up to 20 levels, so
//! every angle increment summed is small and the count is exact for curves that keep a
//! distance from `−1`. [`NyquistCurve::winding`] is the unrounded count: far from an integer
//! it says that the curve passes (numerically) through `−1`, i.e. a closed-loop pole on the
//! contour; [`NyquistCurve::min_distance_to_critical`] is `min |1 + L|` on the contour.

use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::frequency_response::{Bode, bode, freqresp};
use crate::interconnect::{FeedbackSign, feedback};
use crate::linalg::{Complex64, Mat};
use crate::state_space::StateSpace;
use crate::transfer_function::TransferFunction;

/// Options of [`nyquist`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NyquistOptions {
    /// Radius `r` (rad/s, in the s-plane also for a discrete loop) of the indentation around
    /// poles on or near the imaginary axis; python-control's default `10⁻⁴`.
    pub indent_radius: f64,
    /// Points placed on `[ω_p − r, ω_p + r]` around each such pole before indenting
    /// (python-control's `indent_points`, 50).
    pub indent_points: usize,
}

impl Default for NyquistOptions {
    fn default() -> Self {
        Self {
            indent_radius: 1e-4,
            indent_points: 50,
        }
    }
}

/// The upper half of the Nyquist curve with the encirclement count (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct NyquistCurve {
    /// The frequency parameter `ω` (rad/s) of each contour point, ascending from 0.
    pub w: Vec<f64>,
    /// The contour points: `s` (continuous, `jω` or an indentation point) or `z = e^{sT}`.
    pub contour: Vec<Complex64>,
    /// `L` at each contour point.
    pub response: Vec<Complex64>,
    /// `N`: clockwise encirclements of `−1` by the whole (mirrored) curve.
    pub encirclements: i64,
    /// The unrounded count (close to an integer unless the curve passes through `−1`).
    pub winding: f64,
    /// `P`: open-loop poles with `Re p > 0` (continuous) or `|z| > 1` (discrete).
    pub open_loop_unstable: usize,
    /// Closed-loop poles (of `L/(1 + L)`) with `Re ≥ 0` (`|z| ≥ 1`), from the closed loop's
    /// eigenvalues.
    pub closed_loop_unstable: usize,
    /// Poles of `L` around which the contour was indented (s-plane, `Im ≥ 0`).
    pub indented_poles: Vec<Complex64>,
    /// `min |1 + L|` over the contour points.
    pub min_distance_to_critical: f64,
    /// Sample time of a discrete loop, `None` in continuous time.
    pub sample_time: Option<f64>,
}

impl NyquistCurve {
    /// The Nyquist criterion `Z = N + P` with `Z` counted from the closed loop's poles.
    pub fn criterion_holds(&self) -> bool {
        self.closed_loop_unstable as i64 == self.encirclements + self.open_loop_unstable as i64
    }
}

/// Turn of `arg(1 + L)` (radians) above which an interval is bisected.
const MAX_TURN: f64 = 10.0 * std::f64::consts::PI / 180.0;
/// Change of `ln |L|` above which an interval is bisected.
const MAX_LOG_MAG: f64 = 0.25;
/// Bisection levels at most.
const MAX_LEVELS: usize = 20;
/// Relative distance from the stability boundary within which a pole counts as on it.
const BOUNDARY_TOL: f64 = 1e-9;

/// The Nyquist curve of the SISO loop `L` with its encirclement count (module documentation).
///
/// # Errors
/// [`LtiError::NotSiso`]; [`LtiError::InvalidArgument`] for a radius that is not finite and
/// positive or fewer than 3 indentation points; [`LtiError::Singular`] for an ill-posed loop
/// (`1 + D = 0`); [`LtiError::PoleAtEvaluationPoint`] if a contour point still hits a pole
/// (a radius too small for the pole's magnitude); eigenvalue errors.
pub fn nyquist<D: TimeDomain>(l: &StateSpace<D>, opts: &NyquistOptions) -> Result<NyquistCurve> {
    if l.nu() != 1 || l.ny() != 1 {
        return Err(LtiError::NotSiso {
            what: "nyquist".into(),
            ny: l.ny(),
            nu: l.nu(),
        });
    }
    let r = opts.indent_radius;
    if !(r.is_finite() && r > 0.0) || opts.indent_points < 3 {
        return Err(LtiError::InvalidArgument(format!(
            "nyquist: the indentation radius must be finite and > 0 (got {r}) with at least 3 points (got {})",
            opts.indent_points
        )));
    }
    let ts = l.domain().sample_time();
    let dl = l.d()[(0, 0)];
    let closed = feedback(
        l,
        &StateSpace::static_gain(Mat::identity(1, 1), l.domain())?,
        FeedbackSign::Negative,
    )?;
    let poles = l.poles()?;
    let zeros = l.zeros()?;
    let splane = |p: Complex64| -> Option<Complex64> {
        match ts {
            None => Some(p),
            Some(t) => (p.norm() > 1e-12).then(|| p.ln() / t),
        }
    };
    // A pole within a relative 10⁻⁹ of the stability boundary is on it (eigenvalues of a
    // realisation carry rounding: an integrator may come out at ±10⁻¹⁷).
    let tol = |p: Complex64| BOUNDARY_TOL * p.norm().max(1.0);
    let sp: Vec<Complex64> = poles
        .iter()
        .filter_map(|&p| splane(p))
        .map(|p| {
            if p.re.abs() <= tol(p) {
                Complex64::new(0.0, p.im)
            } else {
                p
            }
        })
        .collect();
    let open_loop_unstable = poles
        .iter()
        .filter(|&&p| l.domain().stability_distance(p) > tol(p))
        .count();
    let closed_loop_unstable = closed
        .poles()?
        .iter()
        .filter(|&&p| closed.domain().stability_distance(p) >= -tol(p))
        .count();
    let indented: Vec<Complex64> = sp
        .iter()
        .copied()
        .filter(|p| p.re.abs() <= r && p.im >= 0.0)
        .collect();
    // Base grid.
    let mags: Vec<f64> = poles
        .iter()
        .chain(zeros.iter())
        .filter_map(|&p| splane(p))
        .map(|p| p.norm())
        .filter(|&m| m > 0.0 && m.is_finite())
        .collect();
    let (lo, hi) = if mags.is_empty() {
        (1e-2, 1e2)
    } else {
        let mn = mags.iter().copied().fold(f64::INFINITY, f64::min);
        let mx = mags.iter().copied().fold(0.0, f64::max);
        (mn / 100.0, mx * 100.0)
    };
    let nyq = ts.map(|t| std::f64::consts::PI / t);
    let hi = nyq.map_or(hi, |wn| wn);
    let lo = lo.min(hi / 1e3);
    let mut w: Vec<f64> = vec![0.0];
    w.extend(crate::frequency_response::logspace(
        lo.log10(),
        hi.log10(),
        200,
    ));
    if let Some(wn) = nyq {
        let k = w.len() - 1;
        w[k] = wn;
    }
    for p in &indented {
        let (a, b) = ((p.im - r).max(0.0), p.im + r);
        w.retain(|&x| !(x > a && x < b));
        let n = opts.indent_points;
        w.extend((0..n).map(|k| a + (b - a) * k as f64 / (n - 1) as f64));
    }
    w.retain(|&x| nyq.is_none_or(|wn| x <= wn));
    w.sort_by(f64::total_cmp);
    w.dedup();
    let point = |x: f64| -> Complex64 {
        let mut s = Complex64::new(0.0, x);
        if let Some(p) = sp
            .iter()
            .min_by(|a, b| (*a - s).norm().total_cmp(&(*b - s).norm()))
        {
            let d = s - p;
            if d.norm() < r {
                let off = (r * r - d.im * d.im).max(0.0).sqrt() - d.re;
                if p.re <= 0.0 {
                    s += off;
                } else {
                    s -= off;
                }
            }
        }
        s
    };
    let to_plane = |s: Complex64| -> Complex64 {
        match ts {
            None => s,
            Some(t) => (s * t).exp(),
        }
    };
    let eval = |ws: &[f64]| -> Result<Vec<(Complex64, Complex64)>> {
        let pts: Vec<Complex64> = ws.iter().map(|&x| point(x)).collect();
        let axis: Vec<usize> = (0..ws.len()).filter(|&k| pts[k].re == 0.0).collect();
        let mut out = vec![(Complex64::new(0.0, 0.0), Complex64::new(0.0, 0.0)); ws.len()];
        let fr = freqresp(l, &axis.iter().map(|&k| ws[k]).collect::<Vec<_>>())?;
        for (&k, g) in axis.iter().zip(&fr.response) {
            out[k] = (to_plane(pts[k]), g[(0, 0)]);
        }
        for k in (0..ws.len()).filter(|&k| pts[k].re != 0.0) {
            let z = to_plane(pts[k]);
            let g = crate::analysis::evaluate_at(l.a(), l.b(), l.c(), l.d(), z, "nyquist")?;
            out[k] = (z, g[(0, 0)]);
        }
        Ok(out)
    };
    let mut v = eval(&w)?;
    let one_plus_d = (1.0 + dl).abs();
    if nyq.is_none() {
        for _ in 0..12 {
            let last = v[v.len() - 1].1;
            if (last - dl).norm() <= 1e-3 * one_plus_d {
                break;
            }
            let w0 = w[w.len() - 1];
            let ext = crate::frequency_response::logspace(w0.log10(), w0.log10() + 1.0, 41);
            let ve = eval(&ext[1..])?;
            w.extend_from_slice(&ext[1..]);
            v.extend(ve);
        }
    }
    for _ in 0..MAX_LEVELS {
        let mids: Vec<(usize, f64)> = (0..w.len() - 1)
            .filter(|&i| {
                let (a, b) = (v[i].1, v[i + 1].1);
                let turn = ((1.0 + b) / (1.0 + a)).arg().abs();
                let dm = (b.norm().ln() - a.norm().ln()).abs();
                !(turn <= MAX_TURN && (dm <= MAX_LOG_MAG || !dm.is_finite()))
            })
            .map(|i| (i, 0.5 * (w[i] + w[i + 1])))
            .filter(|&(i, m)| m > w[i] && m < w[i + 1])
            .collect();
        if mids.is_empty() {
            break;
        }
        let vm = eval(&mids.iter().map(|m| m.1).collect::<Vec<_>>())?;
        (w, v) = crate::margins::insert_midpoints(&w, &v, &mids, &vm);
    }
    let winding: f64 = -v
        .windows(2)
        .map(|p| ((1.0 + p[1].1) / (1.0 + p[0].1)).arg())
        .sum::<f64>()
        / std::f64::consts::PI;
    let min_distance_to_critical = v
        .iter()
        .map(|x| (1.0 + x.1).norm())
        .fold(f64::INFINITY, f64::min);
    Ok(NyquistCurve {
        w,
        contour: v.iter().map(|x| x.0).collect(),
        response: v.iter().map(|x| x.1).collect(),
        encirclements: winding.round() as i64,
        winding,
        open_loop_unstable,
        closed_loop_unstable,
        indented_poles: indented,
        min_distance_to_critical,
        sample_time: ts,
    })
}

/// [`nyquist`] of a SISO transfer function (through its realisation).
///
/// # Errors
/// [`LtiError::Improper`] for an improper transfer function (its curve goes to infinity and
/// the contour's arc at infinity does not map to a point); otherwise as [`nyquist`].
pub fn nyquist_tf<D: TimeDomain>(
    l: &TransferFunction<D>,
    opts: &NyquistOptions,
) -> Result<NyquistCurve> {
    nyquist(&l.to_state_space()?, opts)
}

/// The Nichols curve of a SISO system: gain `20 log₁₀|L|` (dB) against phase (degrees) at the
/// frequencies `w` (rad/s), the phase unwrapped along `w` as [`bode`] and then shifted by a
/// multiple of 360° so that its first value lies in `(−360°, 0°]` (the Nichols chart's
/// critical point is `(−180°, 0 dB)`). The [`Bode`] fields hold the curve.
///
/// # Errors
/// As [`bode`] ([`LtiError::NotSiso`], non-finite frequencies, a frequency on a pole).
pub fn nichols<D: TimeDomain>(l: &StateSpace<D>, w: &[f64]) -> Result<Bode> {
    let mut b = bode(l, w)?;
    if let Some(&first) = b.phase_deg.iter().find(|p| p.is_finite()) {
        let shift = 360.0 * (first / 360.0).ceil();
        for p in &mut b.phase_deg {
            *p -= shift;
        }
    }
    Ok(b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_order_lag_does_not_encircle() {
        let l = TransferFunction::continuous(&[2.0], &[1.0, 1.0]).unwrap();
        let c = nyquist_tf(&l, &NyquistOptions::default()).unwrap();
        assert_eq!(c.encirclements, 0);
        assert!(c.criterion_holds());
        // The contour starts at ω = 0 with L(0) = 2; min |1 + L| → 1 as ω → ∞.
        assert!((c.response[0] - Complex64::new(2.0, 0.0)).norm() < 1e-14);
        assert!(c.min_distance_to_critical < 1.0 + 1e-3 && c.min_distance_to_critical >= 1.0);
    }

    #[test]
    fn nichols_phase_starts_in_the_chart_window() {
        let l = TransferFunction::continuous(&[-1.0], &[1.0, 1.0])
            .unwrap()
            .to_state_space()
            .unwrap();
        let b = nichols(&l, &[0.1, 1.0, 10.0]).unwrap();
        // −1/(s + 1) at ω = 0.1: phase 180° − atan(0.1) → shifted to −180° − 5.71°.
        assert!((b.phase_deg[0] - (-180.0 - 0.1f64.atan().to_degrees())).abs() < 1e-12);
    }
}
