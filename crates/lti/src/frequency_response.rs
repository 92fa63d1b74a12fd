//! Frequency response and Bode data, continuous and discrete.
//!
//! - [`freqresp`] (MATLAB `freqresp`): `G(jω)` (continuous) or `G(e^{jωts})` (discrete) for
//!   every frequency, as complex `ny × nu` matrices.
//! - [`bode`] / [`bode_channel`] / [`bode_tf`] (MATLAB `bode`): magnitude in dB and phase in
//!   degrees, **unwrapped** along the frequency grid, for one input/output channel.
//! - [`logspace`] and [`frequency_grid`]: logarithmic grids, the latter chosen from the
//!   system's poles and zeros.
//!
//! Evaluation: `A` is reduced once to upper Hessenberg form `H = QᵀAQ` (orthogonal, so
//! backward stable), and for each frequency `(sI − H) X = QᵀB` is solved by Gaussian
//! elimination with partial pivoting specialised to Hessenberg structure (`O(n²)` per
//! frequency and input instead of `O(n³)`; Laub, "Efficient multivariable frequency response
//! computations", IEEE TAC 26(2), 1981). Transfer functions are evaluated by Horner's rule.

use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::linalg::{CMat, Complex64, Mat};
use crate::state_space::StateSpace;
use crate::transfer_function::TransferFunction;

/// Complex frequency response samples.
#[derive(Debug, Clone, PartialEq)]
pub struct FrequencyResponse {
    /// Frequencies in rad/s.
    pub w: Vec<f64>,
    /// `response[k]` is the `ny × nu` matrix `G` at `w[k]`.
    pub response: Vec<CMat>,
}

/// Bode data of one channel.
#[derive(Debug, Clone, PartialEq)]
pub struct Bode {
    /// Frequencies in rad/s.
    pub w: Vec<f64>,
    /// `20 log₁₀ |G|` in dB.
    pub magnitude_db: Vec<f64>,
    /// `∠G` in degrees, unwrapped: consecutive values differ by less than 180°; the first
    /// value is the principal argument in `(−180°, 180°]`.
    pub phase_deg: Vec<f64>,
}

/// `n` logarithmically spaced points from `10^start` to `10^stop` (MATLAB `logspace`).
pub fn logspace(start: f64, stop: f64, n: usize) -> Vec<f64> {
    match n {
        0 => Vec::new(),
        1 => vec![10f64.powf(stop)],
        _ => (0..n)
            .map(|k| 10f64.powf(start + (stop - start) * k as f64 / (n - 1) as f64))
            .collect(),
    }
}

/// A logarithmic grid (`points_per_decade` points per decade) covering one decade below the
/// slowest and one above the fastest pole or zero magnitude (MATLAB's automatic Bode range);
/// discrete systems are mapped through `s = ln(z)/ts` and the grid stops at the Nyquist
/// frequency `π/ts`. Systems without dynamics get `[0.1, 10]` rad/s.
///
/// # Errors
/// [`LtiError::NoConvergence`] from the eigenvalue computations.
pub fn frequency_grid<D: TimeDomain>(
    sys: &StateSpace<D>,
    points_per_decade: usize,
) -> Result<Vec<f64>> {
    let ts = sys.domain().sample_time();
    let mut feats: Vec<Complex64> = sys.poles()?;
    if sys.nu() == 1 && sys.ny() == 1 {
        feats.extend(sys.zeros()?);
    }
    let mags: Vec<f64> = feats
        .into_iter()
        .filter_map(|p| match ts {
            None => Some(p.norm()),
            Some(ts) => (p.norm() > 0.0).then(|| (p.ln() / ts).norm()),
        })
        .filter(|&m| m > 0.0 && m.is_finite())
        .collect();
    let (lo, mut hi) = if mags.is_empty() {
        (-1.0, 1.0)
    } else {
        let mn = mags.iter().copied().fold(f64::INFINITY, f64::min);
        let mx = mags.iter().copied().fold(0.0, f64::max);
        (mn.log10().floor() - 1.0, mx.log10().ceil() + 1.0)
    };
    if let Some(ts) = ts {
        hi = hi.min((std::f64::consts::PI / ts).log10());
    }
    let lo = lo.min(hi - 1.0);
    let n = (((hi - lo) * points_per_decade.max(1) as f64).ceil() as usize).max(2) + 1;
    Ok(logspace(lo, hi, n))
}

fn check_frequencies(w: &[f64]) -> Result<()> {
    if let Some((i, &v)) = w.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(LtiError::NonFinite {
            what: "frequency vector".into(),
            row: 0,
            col: i,
            value: v,
        });
    }
    Ok(())
}

fn point<D: TimeDomain>(domain: D, w: f64) -> Complex64 {
    match domain.sample_time() {
        None => Complex64::new(0.0, w),
        Some(ts) => Complex64::from_polar(1.0, w * ts),
    }
}

/// Frequency response `G(jω)` / `G(e^{jωts})` at every `w` (rad/s), by the Hessenberg method.
///
/// # Errors
/// [`LtiError::NonFinite`] for a non-finite frequency; [`LtiError::PoleAtEvaluationPoint`]
/// if a frequency hits a pole exactly (a zero pivot in the Hessenberg elimination).
pub fn freqresp<D: TimeDomain>(sys: &StateSpace<D>, w: &[f64]) -> Result<FrequencyResponse> {
    check_frequencies(w)?;
    let n = sys.nx();
    let (ny, nu) = (sys.ny(), sys.nu());
    let dc: CMat = sys.d().map(|v| Complex64::new(v, 0.0));
    if n == 0 {
        return Ok(FrequencyResponse {
            w: w.to_vec(),
            response: vec![dc; w.len()],
        });
    }
    let (q, h) = sys.a().clone().hessenberg().unpack();
    let qb: Mat = q.transpose() * sys.b();
    let cq: CMat = (sys.c() * &q).map(|v| Complex64::new(v, 0.0));
    let mut out = Vec::with_capacity(w.len());
    let mut m = CMat::zeros(n, n);
    let mut x = CMat::zeros(n, nu);
    for &wk in w {
        let s = point(sys.domain(), wk);
        for j in 0..n {
            for i in 0..n {
                m[(i, j)] = Complex64::new(-h[(i, j)], 0.0);
            }
            m[(j, j)] += s;
        }
        for j in 0..nu {
            for i in 0..n {
                x[(i, j)] = Complex64::new(qb[(i, j)], 0.0);
            }
        }
        hessenberg_solve(&mut m, &mut x).map_err(|()| LtiError::PoleAtEvaluationPoint {
            what: format!("frequency response at {wk} rad/s"),
            pole: s,
        })?;
        let g = &cq * &x + &dc;
        debug_assert_eq!(g.shape(), (ny, nu));
        out.push(g);
    }
    Ok(FrequencyResponse {
        w: w.to_vec(),
        response: out,
    })
}

/// Solves `M X = R` in place for upper-Hessenberg `M` (Gaussian elimination with partial
/// pivoting between adjacent rows, then back substitution). `Err` on an exactly zero pivot.
fn hessenberg_solve(m: &mut CMat, r: &mut CMat) -> std::result::Result<(), ()> {
    let n = m.nrows();
    let nr = r.ncols();
    for k in 0..n.saturating_sub(1) {
        if m[(k + 1, k)].norm() > m[(k, k)].norm() {
            for j in k..n {
                let t = m[(k, j)];
                m[(k, j)] = m[(k + 1, j)];
                m[(k + 1, j)] = t;
            }
            for j in 0..nr {
                let t = r[(k, j)];
                r[(k, j)] = r[(k + 1, j)];
                r[(k + 1, j)] = t;
            }
        }
        let piv = m[(k, k)];
        if piv.norm() == 0.0 {
            return Err(());
        }
        let l = m[(k + 1, k)] / piv;
        if l.norm() != 0.0 {
            for j in k + 1..n {
                let v = m[(k, j)];
                m[(k + 1, j)] -= l * v;
            }
            for j in 0..nr {
                let v = r[(k, j)];
                r[(k + 1, j)] -= l * v;
            }
        }
        m[(k + 1, k)] = Complex64::new(0.0, 0.0);
    }
    for j in 0..nr {
        for i in (0..n).rev() {
            let mut acc = r[(i, j)];
            for k in i + 1..n {
                acc -= m[(i, k)] * r[(k, j)];
            }
            let piv = m[(i, i)];
            if piv.norm() == 0.0 {
                return Err(());
            }
            r[(i, j)] = acc / piv;
        }
    }
    Ok(())
}

/// Unwraps a phase sequence in degrees so that consecutive values differ by at most 180°.
pub fn unwrap_degrees(phase: &mut [f64]) {
    for k in 1..phase.len() {
        let d = phase[k] - phase[k - 1];
        let turns = (d / 360.0).round();
        phase[k] -= 360.0 * turns;
    }
}

fn bode_from(w: &[f64], values: impl Iterator<Item = Complex64>) -> Bode {
    let mut mag = Vec::with_capacity(w.len());
    let mut ph = Vec::with_capacity(w.len());
    for g in values {
        mag.push(20.0 * g.norm().log10());
        ph.push(g.arg().to_degrees());
    }
    unwrap_degrees(&mut ph);
    Bode {
        w: w.to_vec(),
        magnitude_db: mag,
        phase_deg: ph,
    }
}

/// Bode data of a SISO system (MATLAB `bode(sys, w)`).
///
/// # Errors
/// [`LtiError::NotSiso`], and as [`freqresp`].
pub fn bode<D: TimeDomain>(sys: &StateSpace<D>, w: &[f64]) -> Result<Bode> {
    if sys.nu() != 1 || sys.ny() != 1 {
        return Err(LtiError::NotSiso {
            what: "bode".into(),
            ny: sys.ny(),
            nu: sys.nu(),
        });
    }
    bode_channel(sys, w, 0, 0)
}

/// Bode data of the channel from input `input` to output `output` (0-based).
///
/// # Errors
/// [`LtiError::InvalidArgument`] for an index out of range, and as [`freqresp`].
pub fn bode_channel<D: TimeDomain>(
    sys: &StateSpace<D>,
    w: &[f64],
    output: usize,
    input: usize,
) -> Result<Bode> {
    if output >= sys.ny() || input >= sys.nu() {
        return Err(LtiError::InvalidArgument(format!(
            "bode channel ({output}, {input}) out of range for {} outputs x {} inputs",
            sys.ny(),
            sys.nu()
        )));
    }
    let f = freqresp(sys, w)?;
    Ok(bode_from(w, f.response.iter().map(|g| g[(output, input)])))
}

/// Bode data of a transfer function (proper or not, e.g. an ideal PID).
///
/// # Errors
/// [`LtiError::NonFinite`] for a non-finite frequency; [`LtiError::PoleAtEvaluationPoint`]
/// where the denominator vanishes exactly.
pub fn bode_tf<D: TimeDomain>(g: &TransferFunction<D>, w: &[f64]) -> Result<Bode> {
    check_frequencies(w)?;
    let mut vals = Vec::with_capacity(w.len());
    for &wk in w {
        let s = point(g.domain(), wk);
        let den = g.den().eval_complex(s);
        if den.norm() == 0.0 {
            return Err(LtiError::PoleAtEvaluationPoint {
                what: format!("frequency response at {wk} rad/s"),
                pole: s,
            });
        }
        vals.push(g.num().eval_complex(s) / den);
    }
    Ok(bode_from(w, vals.into_iter()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Continuous;

    #[test]
    fn first_order_lag_closed_form() {
        // 1/(s + 1): |G| = 1/√(1 + ω²), ∠G = −atan ω.
        let g = TransferFunction::<Continuous>::continuous(&[1.0], &[1.0, 1.0]).unwrap();
        let sys = g.to_state_space().unwrap();
        let w = logspace(-2.0, 2.0, 9);
        let b = bode(&sys, &w).unwrap();
        let bt = bode_tf(&g, &w).unwrap();
        for (k, &wk) in w.iter().enumerate() {
            let mag = -10.0 * (1.0 + wk * wk).log10();
            let ph = -wk.atan().to_degrees();
            assert!((b.magnitude_db[k] - mag).abs() < 1e-12);
            assert!((b.phase_deg[k] - ph).abs() < 1e-12);
            assert!((bt.magnitude_db[k] - mag).abs() < 1e-12);
        }
    }

    #[test]
    fn phase_is_unwrapped_past_minus_180() {
        // 1/(s + 1)³ ends near −270°.
        let g = TransferFunction::<Continuous>::continuous(&[1.0], &[1.0, 3.0, 3.0, 1.0]).unwrap();
        let w = logspace(-2.0, 3.0, 200);
        let b = bode(&g.to_state_space().unwrap(), &w).unwrap();
        let last = *b.phase_deg.last().unwrap();
        assert!((last - (-3.0 * 1000f64.atan().to_degrees())).abs() < 1e-9);
    }
}
