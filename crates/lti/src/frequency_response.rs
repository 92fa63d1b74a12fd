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
    let mut ev = HessenbergEvaluator::new(sys.a(), sys.b(), sys.c(), sys.d());
    let mut out = Vec::with_capacity(w.len());
    for &wk in w {
        let s = point(sys.domain(), wk);
        let mut g = CMat::zeros(sys.ny(), sys.nu());
        ev.eval(s, &mut g)
            .map_err(|()| LtiError::PoleAtEvaluationPoint {
                what: format!("frequency response at {wk} rad/s"),
                pole: s,
            })?;
        out.push(g);
    }
    Ok(FrequencyResponse {
        w: w.to_vec(),
        response: out,
    })
}

/// `G(s) = C(sI − A)⁻¹B + D` at many points `s` from one reduction of `A` to upper Hessenberg
/// form `H = QᵀAQ` (see the module documentation): each evaluation solves
/// `(sI − H) X = QᵀB` by [`hessenberg_solve`] in work buffers kept between calls (no heap
/// allocation) and forms `(CQ) X + D`. The engine of [`freqresp`], the loop margins and the
/// H∞ norm.
pub(crate) struct HessenbergEvaluator {
    n: usize,
    h: Mat,
    qb: Mat,
    cq: Mat,
    d: Mat,
    m: CMat,
    x: CMat,
}

impl HessenbergEvaluator {
    /// Reduces `A` once; `B`, `C`, `D` must have the shapes of a state-space system.
    pub(crate) fn new(a: &Mat, b: &Mat, c: &Mat, d: &Mat) -> Self {
        let n = a.nrows();
        let (h, qb, cq) = if n == 0 {
            (
                Mat::zeros(0, 0),
                Mat::zeros(0, b.ncols()),
                Mat::zeros(c.nrows(), 0),
            )
        } else {
            let (q, h) = a.clone().hessenberg().unpack();
            (h, q.transpose() * b, c * &q)
        };
        Self {
            n,
            h,
            qb,
            cq,
            d: d.clone(),
            m: CMat::zeros(n, n),
            x: CMat::zeros(n, b.ncols()),
        }
    }

    /// `G(s)` into `out` (`ny × nu`); `Err` when `s` is a pole (an exactly zero pivot).
    pub(crate) fn eval(&mut self, s: Complex64, out: &mut CMat) -> std::result::Result<(), ()> {
        let n = self.n;
        let (ny, nu) = self.d.shape();
        for j in 0..nu {
            for i in 0..ny {
                out[(i, j)] = Complex64::new(self.d[(i, j)], 0.0);
            }
        }
        if n == 0 {
            return Ok(());
        }
        {
            let (m, h) = (self.m.as_mut_slice(), self.h.as_slice());
            for j in 0..n {
                // Below the subdiagonal H (and so sI − H) is zero; those entries are never read.
                let rows = n.min(j + 2);
                for (mi, &hi) in m[j * n..j * n + rows]
                    .iter_mut()
                    .zip(&h[j * n..j * n + rows])
                {
                    *mi = Complex64::new(-hi, 0.0);
                }
                m[j + j * n] += s;
            }
        }
        for (xi, &bi) in self.x.as_mut_slice().iter_mut().zip(self.qb.as_slice()) {
            *xi = Complex64::new(bi, 0.0);
        }
        hessenberg_solve(&mut self.m, &mut self.x)?;
        let (x, cq) = (self.x.as_slice(), self.cq.as_slice());
        for j in 0..nu {
            for k in 0..n {
                let xk = x[k + j * n];
                for i in 0..ny {
                    out[(i, j)] += xk * cq[i + k * ny];
                }
            }
        }
        Ok(())
    }
}

/// `G(s) = c(sI − A)⁻¹b + d` of a SISO system at many points `s`, from one orthogonal
/// reduction to **controller-Hessenberg form**: `QᵀAQ = H` upper Hessenberg and `Qᵀb = βe₁`
/// (the Hessenberg reduction of `[[0, 0], [b, A]]`; its reflectors leave `e₁` fixed). Only
/// the leading `k × k` block of `H` is kept, `k` the first index with an exactly zero
/// subdiagonal `h_{k+1,k}` (the rest is uncontrollable from `b` and does not enter `G`).
///
/// Each evaluation is Hyman's method: with `M = sI − H`, set `x_k = 1` and solve rows
/// `k, …, 2` of `M x = α e₁` upwards, `x_{i−1} = (s x_i − Σ_{j≥i} h_{ij} x_j)/h_{i,i−1}`
/// (real divisors, their reciprocals precomputed), then `α = (M x)₁`, so that
/// `G = d + β (c̃ x)/α` with `c̃ = cQ`. Every row equation is satisfied with a componentwise
/// relative perturbation of its coefficients (Wilkinson's analysis of Hyman's method, see
/// Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., §14.6.1), so the
/// result is the exact response of a componentwise nearby `sI − H`. `x` is rescaled by
/// exact powers of two when it grows beyond `2⁴⁰⁰`. `O(k²)` real-times-complex operations
/// per point, no pivoting and no heap allocation.
pub(crate) struct SisoHessenbergEvaluator {
    k: usize,
    /// Leading `k × k` block of `H`, row-major.
    h: Vec<f64>,
    /// `1/h_{i+1,i}`, `i = 0 … k − 2`.
    rsub: Vec<f64>,
    /// `β c̃` (first `k` entries).
    c: Vec<f64>,
    d: f64,
    x: Vec<Complex64>,
}

/// Rescaling threshold of Hyman's recurrence and its (exact) reciprocal.
const HYMAN_BIG: f64 = f64::from_bits((1023 + 400) << 52); // 2^400
const HYMAN_SMALL: f64 = f64::from_bits((1023 - 400) << 52); // 2^-400

impl SisoHessenbergEvaluator {
    /// Reduces `(A, b, c)` once; `b` is `n × 1`, `c` is `1 × n`, `d` is `1 × 1`.
    pub(crate) fn new(a: &Mat, b: &Mat, c: &Mat, d: &Mat) -> Self {
        let n = a.nrows();
        let d = d[(0, 0)];
        let empty = Self {
            k: 0,
            h: Vec::new(),
            rsub: Vec::new(),
            c: Vec::new(),
            d,
            x: Vec::new(),
        };
        if n == 0 {
            return empty;
        }
        let mut t = Mat::zeros(n + 1, n + 1);
        t.view_mut((1, 0), (n, 1)).copy_from(&b.column(0));
        t.view_mut((1, 1), (n, n)).copy_from(a);
        let (qt, ht) = t.hessenberg().unpack();
        let beta = ht[(1, 0)];
        if beta == 0.0 {
            return empty;
        }
        let k = (1..n).find(|&i| ht[(i + 1, i)] == 0.0).unwrap_or(n);
        let q = qt.view((1, 1), (n, k));
        let ct = c * q;
        Self {
            k,
            h: (0..k * k).map(|p| ht[(1 + p / k, 1 + p % k)]).collect(),
            rsub: (0..k - 1).map(|i| 1.0 / ht[(i + 2, i + 1)]).collect(),
            c: ct.iter().map(|&v| beta * v).collect(),
            d,
            x: vec![Complex64::new(0.0, 0.0); k],
        }
    }

    /// `G(s)`; `Err` when `s` is a pole (`α = 0` exactly).
    pub(crate) fn eval(&mut self, s: Complex64) -> std::result::Result<Complex64, ()> {
        let k = self.k;
        if k == 0 {
            return Ok(Complex64::new(self.d, 0.0));
        }
        let (h, x) = (&self.h, &mut self.x);
        x[k - 1] = Complex64::new(1.0, 0.0);
        for i in (1..k).rev() {
            let row = &h[i * k + i..i * k + k];
            let (mut re, mut im) = (
                s.re * x[i].re - s.im * x[i].im,
                s.re * x[i].im + s.im * x[i].re,
            );
            for (&hij, xj) in row.iter().zip(&x[i..k]) {
                re -= hij * xj.re;
                im -= hij * xj.im;
            }
            let r = self.rsub[i - 1];
            let xi = Complex64::new(re * r, im * r);
            x[i - 1] = xi;
            if xi.re.abs() + xi.im.abs() > HYMAN_BIG {
                for v in &mut x[i - 1..k] {
                    *v *= HYMAN_SMALL;
                }
            }
        }
        let (mut are, mut aim) = (
            s.re * x[0].re - s.im * x[0].im,
            s.re * x[0].im + s.im * x[0].re,
        );
        let (mut nre, mut nim) = (0.0, 0.0);
        for ((&h0j, &cj), xj) in h[..k].iter().zip(&self.c).zip(x.iter()) {
            are -= h0j * xj.re;
            aim -= h0j * xj.im;
            nre += cj * xj.re;
            nim += cj * xj.im;
        }
        if are == 0.0 && aim == 0.0 {
            return Err(());
        }
        // Smith's division (no overflow of |α|²).
        let g = if are.abs() >= aim.abs() {
            let t = aim / are;
            let den = are + aim * t;
            Complex64::new((nre + nim * t) / den, (nim - nre * t) / den)
        } else {
            let t = are / aim;
            let den = are * t + aim;
            Complex64::new((nre * t + nim) / den, (nim * t - nre) / den)
        };
        Ok(g + self.d)
    }
}

/// `|z|²` ordering without `hypot`: `|a| > |b|` decided on the squares, with the exact
/// modulus only where a square over- or underflows.
fn larger(a: Complex64, b: Complex64) -> bool {
    let (na, nb) = (a.norm_sqr(), b.norm_sqr());
    if na.is_finite() && nb.is_finite() && na > f64::MIN_POSITIVE && nb > f64::MIN_POSITIVE {
        na > nb
    } else {
        a.norm() > b.norm()
    }
}

fn is_zero(z: Complex64) -> bool {
    z.re == 0.0 && z.im == 0.0
}

/// Solves `M X = R` in place for upper-Hessenberg `M` (Gaussian elimination with partial
/// pivoting between adjacent rows, then column-oriented back substitution). `Err` on an
/// exactly zero pivot. Entries of `M` below its subdiagonal are never read.
fn hessenberg_solve(m: &mut CMat, r: &mut CMat) -> std::result::Result<(), ()> {
    let n = m.nrows();
    let nr = r.ncols();
    let m = m.as_mut_slice(); // column-major: (i, j) at i + j n
    let r = r.as_mut_slice();
    for k in 0..n.saturating_sub(1) {
        if larger(m[k + 1 + k * n], m[k + k * n]) {
            for j in k..n {
                m.swap(k + j * n, k + 1 + j * n);
            }
            for j in 0..nr {
                r.swap(k + j * n, k + 1 + j * n);
            }
        }
        let piv = m[k + k * n];
        if is_zero(piv) {
            return Err(());
        }
        let l = m[k + 1 + k * n] / piv;
        if !is_zero(l) {
            for j in k + 1..n {
                let v = m[k + j * n];
                m[k + 1 + j * n] -= l * v;
            }
            for j in 0..nr {
                let v = r[k + j * n];
                r[k + 1 + j * n] -= l * v;
            }
        }
        m[k + 1 + k * n] = Complex64::new(0.0, 0.0);
    }
    for rc in r.chunks_exact_mut(n.max(1)).take(nr) {
        for k in (0..n).rev() {
            let col = &m[k * n..k * n + k + 1];
            let piv = col[k];
            if is_zero(piv) {
                return Err(());
            }
            let xk = rc[k] / piv;
            rc[k] = xk;
            for (ri, &mi) in rc[..k].iter_mut().zip(&col[..k]) {
                *ri -= mi * xk;
            }
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

    /// The SISO Hyman evaluator against the pivoted Hessenberg solve (two independent
    /// algorithms): a dense 7-state system with an uncontrollable block appended (a zero
    /// coupling into it), over frequencies from 10⁻³ to 10²² rad/s,
    /// and an exact pole refused.
    #[test]
    fn siso_hyman_evaluator_agrees_with_pivoted_solve() {
        let n = 9;
        let mut a = Mat::from_fn(n, n, |i, j| {
            ((3 * i + 5 * j) % 7) as f64 - 3.0 + 0.1 * i as f64
        });
        for i in 7..n {
            for j in 0..7 {
                a[(i, j)] = 0.0; // states 7, 8 are not reached from b
            }
        }
        let b = Mat::from_fn(n, 1, |i, _| if i < 7 { 1.0 + 0.5 * i as f64 } else { 0.0 });
        let c = Mat::from_fn(1, n, |_, j| (j as f64 - 4.0) * 0.3 + 0.05);
        let d = Mat::from_element(1, 1, 0.25);
        let mut siso = SisoHessenbergEvaluator::new(&a, &b, &c, &d);
        assert_eq!(siso.k, 7);
        let mut general = HessenbergEvaluator::new(&a, &b, &c, &d);
        let mut out = CMat::zeros(1, 1);
        for e in -6..=44 {
            let s = Complex64::new(0.0, 10f64.powf(e as f64 / 2.0));
            let g = siso.eval(s).unwrap();
            general.eval(s, &mut out).unwrap();
            let r = out[(0, 0)];
            assert!(
                (g - r).norm() <= 1e-12 * r.norm().max(1e-300),
                "{s}: {g} vs {r}"
            );
        }
        // 1/(s + 2): the pole s = −2 is hit exactly.
        let one = Mat::from_element(1, 1, 1.0);
        let mut p = SisoHessenbergEvaluator::new(
            &Mat::from_element(1, 1, -2.0),
            &one,
            &one,
            &Mat::zeros(1, 1),
        );
        assert!(p.eval(Complex64::new(-2.0, 0.0)).is_err());
        assert!((p.eval(Complex64::new(0.0, 0.0)).unwrap() - 0.5).norm() <= 1e-16);
    }

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
