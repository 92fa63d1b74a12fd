//! The structured singular value `μ` for diagonal complex uncertainty, and the disk margins
//! of a square MIMO loop (MATLAB `diskmargin(L)` with its loop-at-a-time and multi-loop
//! margins).
//!
//! # `μ` with diagonal complex uncertainty
//!
//! For a square complex `M` (`p × p`) and `Δ = diag(δ₁, …, δ_p)`, `δ_i ∈ ℂ`,
//!
//! ```text
//! μ(M) = 1 / min{ σ̄(Δ) : det(I − M Δ) = 0 }
//! ```
//!
//! (Doyle 1982; Packard & Doyle, "The complex structured singular value", Automatica
//! 29(1), 1993). [`mu_diag_complex`] returns bounds `lower ≤ μ ≤ upper`:
//!
//! - **upper**: `min_D σ̄(D M D⁻¹)` over positive diagonal `D = diag(e^{x})`. The function
//!   `x ↦ σ̄(e^{X} M e^{−X})` is convex (Sezginer & Overton, SIAM J. Matrix Anal. Appl.
//!   11(3), 1990), so it is minimised from Osborne's balancing (Osborne, "On pre-conditioning
//!   of matrices", J. ACM 7, 1960: `d_i² = ‖col_i‖/‖row_i‖` of the off-diagonal part, iterated)
//!   by steepest descent with backtracking on `x`, the gradient being
//!   `∂σ̄/∂x_k = σ̄ (|u_k|² − |v_k|²)` for the singular vectors `u, v` of `σ̄`.
//! - **lower**: `ρ(Q M)` for a unitary diagonal `Q` (any such `Q` gives `ρ(QM) ≤ μ`), with `Q`
//!   chosen by the power iteration of Packard & Doyle (1993, §7.2; Packard, Fan & Doyle,
//!   CDC 1988): `β a = M b`, `z_i = |w_i| a_i/|a_i|`, `γ w = Mᴴ z`, `b_i = |a_i| w_i/|w_i|`,
//!   whose fixed points satisfy `Q M b = β b` with `Q_i = e^{j(∠w_i − ∠a_i)}`; every iterate's
//!   `Q` is evaluated exactly and the best kept.
//!
//! For `p = 1` both bounds equal `|M|`. The D-scaled upper bound equals `μ` whenever the
//! structure has `2S + F ≤ 3` blocks, `S` repeated scalar and `F` full (Doyle 1982;
//! Packard & Doyle 1993, §9.1); the non-repeated scalars `δ_i` here are full `1 × 1` blocks,
//! so for `p ≤ 3` `upper = μ` up to the optimisation tolerance, and the power iteration's
//! `lower` approaches it. The reported bounds are what the two algorithms achieved, each
//! guaranteed on its side, and `lower ≤ upper` always.
//!
//! # MIMO disk margins
//!
//! With negative unit feedback, `S = (I + L)⁻¹`, and the σ-balanced sensitivity
//! `S_σ = S + (σ − 1)/2 · I` (the matrix form of [`crate::disk_margin`]'s definition):
//!
//! - **loop-at-a-time**: channel `i` broken with the others closed sees the SISO loop
//!   `L_i = 1/S_ii − 1`, so its margin is `1/‖S_ii + (σ − 1)/2‖∞` (the exact H∞ peak by
//!   [`hinf_norm`]), reported as a [`DiskMargin`].
//! - **multi-loop**: simultaneous independent perturbations `f_i ∈ D(α, σ)` in every channel;
//!   the closed loop stays stable for `α < 1/sup_ω μ(S_σ(jω))` (Seiler, Packard & Gahinet,
//!   IEEE CSM 40(5), 2020, §"Multiloop disk margins"). `μ` is bounded on a logarithmic
//!   frequency grid (40 points per decade over [`frequency_grid`]'s range of `S`, widened by
//!   two decades below and, in continuous time, one above: a coupled loop's `μ` can peak
//!   well below the closed-loop bandwidth) plus `ω = 0` and `ω = ∞`
//!   (continuous time) or the Nyquist frequency `π/T` (discrete time), and the peak is refined by golden-section search on `ln ω` between the grid
//!   neighbours of the largest upper bound. The margin interval is
//!   `[1/μ_upper, 1/μ_lower]` at the peak; between grid points the peak is located, not
//!   certified.
//!
//! An unstable nominal closed loop has every margin 0 (`closed_loop_stable = false`).

use nalgebra::linalg::Schur;

use crate::disk_margin::DiskMargin;
use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::frequency_response::{freqresp, frequency_grid, logspace};
use crate::interconnect::{FeedbackSign, feedback};
use crate::linalg::svd::svd;
use crate::linalg::{CMat, Complex64, Mat};
use crate::norms::hinf_norm;
use crate::state_space::StateSpace;

/// Bounds on `μ(M)` for diagonal complex uncertainty (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct MuBounds {
    /// `ρ(QM)` of the best unitary diagonal `Q` found (a guaranteed lower bound).
    pub lower: f64,
    /// `σ̄(D M D⁻¹)` at the returned scaling (a guaranteed upper bound).
    pub upper: f64,
    /// The diagonal of the optimised scaling `D` (positive, normalised to `d₀ = 1`).
    pub d_scaling: Vec<f64>,
}

fn check_m(m: &CMat) -> Result<()> {
    if m.nrows() != m.ncols() {
        return Err(LtiError::NotSquare {
            what: "mu_diag_complex: M".into(),
            rows: m.nrows(),
            cols: m.ncols(),
        });
    }
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            let z = m[(i, j)];
            if !(z.re.is_finite() && z.im.is_finite()) {
                return Err(LtiError::NonFinite {
                    what: "mu_diag_complex: M".into(),
                    row: i,
                    col: j,
                    value: if z.re.is_finite() { z.im } else { z.re },
                });
            }
        }
    }
    Ok(())
}

/// `e^{x_i − x_j} M_ij`.
fn scaled(m: &CMat, x: &[f64]) -> CMat {
    CMat::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)] * (x[i] - x[j]).exp())
}

/// `σ̄` and its gradient with respect to `x` (module documentation).
fn sigma_grad(m: &CMat, x: &[f64]) -> (f64, Vec<f64>) {
    let s = svd(&scaled(m, x));
    let sv = s.singular_values[0];
    let g = (0..x.len())
        .map(|k| sv * (s.u[(k, 0)].norm_sqr() - s.v_t[(0, k)].norm_sqr()))
        .collect();
    (sv, g)
}

/// Osborne's balancing of the off-diagonal part, in logarithms.
fn osborne(m: &CMat) -> Vec<f64> {
    let p = m.nrows();
    let mut x = vec![0.0f64; p];
    for _ in 0..50 {
        let mut change = 0.0f64;
        for k in 0..p {
            let (mut r, mut c) = (0.0f64, 0.0f64);
            for j in 0..p {
                if j != k {
                    r += m[(k, j)].norm_sqr() * (2.0 * (x[k] - x[j])).exp();
                    c += m[(j, k)].norm_sqr() * (2.0 * (x[j] - x[k])).exp();
                }
            }
            if r > 0.0 && c > 0.0 {
                let step = 0.25 * (c / r).ln();
                x[k] += step;
                change = change.max(step.abs());
            }
        }
        if change < 1e-10 {
            break;
        }
    }
    x
}

fn upper_bound(m: &CMat) -> (f64, Vec<f64>) {
    let p = m.nrows();
    let mut x = osborne(m);
    let (mut f, mut g) = sigma_grad(m, &x);
    let mut t = 1.0 / f.max(f64::MIN_POSITIVE);
    for _ in 0..500 {
        let gn2: f64 = g.iter().map(|v| v * v).sum();
        if gn2 <= (1e-14 * f).powi(2) || f == 0.0 {
            break;
        }
        let mut improved = false;
        for _ in 0..60 {
            let xn: Vec<f64> = x.iter().zip(&g).map(|(a, b)| a - t * b).collect();
            let (fnew, gnew) = sigma_grad(m, &xn);
            if fnew <= f - 1e-4 * t * gn2 {
                let rel = (f - fnew) / f;
                (x, f, g) = (xn, fnew, gnew);
                t *= 2.0;
                improved = rel > 1e-15;
                break;
            }
            t *= 0.5;
        }
        if !improved {
            break;
        }
    }
    let x0 = x.first().copied().unwrap_or(0.0);
    let d = (0..p).map(|i| (x[i] - x0).exp()).collect();
    (f, d)
}

/// `ρ(M)` of a complex square matrix (complex Schur form).
fn spectral_radius(m: &CMat) -> f64 {
    match Schur::try_new(m.clone(), 1e-15, 10_000) {
        Some(s) => {
            let t = s.unpack().1;
            (0..t.nrows()).map(|i| t[(i, i)].norm()).fold(0.0, f64::max)
        }
        None => 0.0,
    }
}

fn unit(z: Complex64) -> Complex64 {
    let n = z.norm();
    if n > 0.0 {
        z / n
    } else {
        Complex64::new(1.0, 0.0)
    }
}

fn qm_radius(m: &CMat, q: &[Complex64]) -> f64 {
    let qm = CMat::from_fn(m.nrows(), m.ncols(), |i, j| q[i] * m[(i, j)]);
    spectral_radius(&qm)
}

/// Packard–Doyle power iteration from the start vector `b`; returns the best `ρ(QM)`.
fn power_iteration(m: &CMat, mut b: Vec<Complex64>, w0: Vec<Complex64>) -> f64 {
    let p = m.nrows();
    let mh = m.adjoint();
    let mut w = w0;
    let mut best = 0.0f64;
    for _ in 0..200 {
        let bv = nalgebra::DVector::from_vec(b.clone());
        let a = m * &bv;
        let an = a.norm();
        if an == 0.0 {
            break;
        }
        let a = a / Complex64::new(an, 0.0);
        let z: Vec<Complex64> = (0..p).map(|i| unit(a[i]) * w[i].norm()).collect();
        let wv = &mh * nalgebra::DVector::from_vec(z);
        let wn = wv.norm();
        if wn == 0.0 {
            break;
        }
        let wv = wv / Complex64::new(wn, 0.0);
        let q: Vec<Complex64> = (0..p).map(|i| unit(wv[i]) * unit(a[i]).conj()).collect();
        let r = qm_radius(m, &q);
        let nb: Vec<Complex64> = (0..p).map(|i| unit(wv[i]) * a[i].norm()).collect();
        let change: f64 = nb.iter().zip(&b).map(|(x, y)| (x - y).norm()).sum();
        w = wv.iter().copied().collect();
        b = nb;
        if r > best * (1.0 + 1e-14) {
            best = r;
        } else if change < 1e-13 {
            break;
        }
    }
    best
}

fn lower_bound(m: &CMat, d: &[f64]) -> f64 {
    let p = m.nrows();
    // Starts: the singular vectors of the scaled matrix mapped back, and the dominant
    // eigenvector direction (identity Q).
    let md = CMat::from_fn(p, p, |i, j| m[(i, j)] * d[i] / d[j]);
    let s = svd(&md);
    let v: Vec<Complex64> = (0..p).map(|i| s.v_t[(0, i)].conj() * d[i]).collect();
    let u: Vec<Complex64> = (0..p).map(|i| s.u[(i, 0)] / d[i]).collect();
    let mut best = qm_radius(m, &vec![Complex64::new(1.0, 0.0); p]);
    best = best.max(power_iteration(m, v.clone(), u.clone()));
    let ones = vec![Complex64::new(1.0, 0.0); p];
    best = best.max(power_iteration(m, ones.clone(), ones));
    best
}

/// Bounds on `μ(M)` for `Δ = diag(δ₁, …, δ_p)`, `δ_i ∈ ℂ` (module documentation).
///
/// # Errors
/// [`LtiError::NotSquare`]; [`LtiError::NonFinite`] for a NaN or infinite entry.
pub fn mu_diag_complex(m: &CMat) -> Result<MuBounds> {
    check_m(m)?;
    let p = m.nrows();
    if p == 0 {
        return Ok(MuBounds {
            lower: 0.0,
            upper: 0.0,
            d_scaling: Vec::new(),
        });
    }
    if p == 1 {
        let v = m[(0, 0)].norm();
        return Ok(MuBounds {
            lower: v,
            upper: v,
            d_scaling: vec![1.0],
        });
    }
    let (upper, d) = upper_bound(m);
    let lower = lower_bound(m, &d).min(upper);
    Ok(MuBounds {
        lower,
        upper,
        d_scaling: d,
    })
}

/// Loop-at-a-time and multi-loop disk margins of a square loop (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct MimoDiskMargin {
    /// Channel `i` broken with the other loops closed, for `i = 0 … p−1`.
    pub loop_at_a_time: Vec<DiskMargin>,
    /// The multi-loop margin, conservative: `α = 1/μ_upper` at the peak (its gain and phase
    /// intervals hold for simultaneous independent perturbations of every channel).
    pub multi_loop: DiskMargin,
    /// `(1/μ_upper, 1/μ_lower)` at the peak: the multi-loop `α` lies in this interval
    /// (both 0 for an unstable closed loop).
    pub multi_loop_alpha_bounds: (f64, f64),
    /// The `μ` bounds of `S_σ` at the peak frequency.
    pub mu_peak: MuBounds,
    /// The frequency (rad/s) of the largest `μ` upper bound (`+∞` for the feedthrough of a
    /// continuous loop; `NaN` for an unstable closed loop).
    pub peak_frequency: f64,
}

/// Grid density of the multi-loop search (points per decade).
const POINTS_PER_DECADE: usize = 40;

/// The loop-at-a-time and multi-loop disk margins of the square loop `L` with skew `σ`
/// (module documentation).
///
/// # Errors
/// [`LtiError::NotSquare`] for a non-square `L`; [`LtiError::InvalidArgument`] for a
/// non-finite skew; [`LtiError::Singular`] for an ill-posed loop (`I + D` singular); the
/// errors of [`hinf_norm`], [`freqresp`] and [`frequency_grid`].
#[doc(alias = "diskmargin")]
pub fn disk_margin_mimo<D: TimeDomain>(l: &StateSpace<D>, skew: f64) -> Result<MimoDiskMargin> {
    let p = l.ny();
    if l.nu() != p {
        return Err(LtiError::NotSquare {
            what: "disk_margin_mimo: L".into(),
            rows: p,
            cols: l.nu(),
        });
    }
    if !skew.is_finite() {
        return Err(LtiError::InvalidArgument(format!(
            "disk_margin_mimo: the skew must be finite, got {skew}"
        )));
    }
    let dom = l.domain();
    let eye = StateSpace::static_gain(Mat::identity(p, p), dom)?;
    let s = feedback(&eye, l, FeedbackSign::Negative)?;
    let shift = 0.5 * (skew - 1.0);
    let st = StateSpace::new(
        s.a().clone(),
        s.b().clone(),
        s.c().clone(),
        s.d() + Mat::identity(p, p) * shift,
        dom,
    )?;
    if !st.is_stable()? {
        let mut m = DiskMargin::from_alpha(0.0, skew);
        m.closed_loop_stable = false;
        return Ok(MimoDiskMargin {
            loop_at_a_time: vec![m; p],
            multi_loop: m,
            multi_loop_alpha_bounds: (0.0, 0.0),
            mu_peak: MuBounds {
                lower: f64::INFINITY,
                upper: f64::INFINITY,
                d_scaling: vec![1.0; p],
            },
            peak_frequency: f64::NAN,
        });
    }
    let mut loop_at_a_time = Vec::with_capacity(p);
    for i in 0..p {
        let sii = StateSpace::new(
            st.a().clone(),
            st.b().columns(i, 1).into_owned(),
            st.c().rows(i, 1).into_owned(),
            Mat::from_element(1, 1, st.d()[(i, i)]),
            dom,
        )?;
        let h = hinf_norm(&sii, 1e-10)?;
        let alpha = if h.value > 0.0 {
            1.0 / h.value
        } else {
            f64::INFINITY
        };
        let mut m = DiskMargin::from_alpha(alpha, skew);
        m.frequency = h.peak_frequency;
        loop_at_a_time.push(m);
    }
    // Multi-loop: μ over a grid, peak refined.
    let w = {
        let g = frequency_grid(&st, POINTS_PER_DECADE)?;
        let lo = g[0].log10() - 2.0;
        let hi = g[g.len() - 1].log10()
            + if dom.sample_time().is_none() {
                1.0
            } else {
                0.0
            };
        let n = ((hi - lo) * POINTS_PER_DECADE as f64).ceil() as usize + 1;
        logspace(lo, hi, n)
    };
    let mut best: Option<(f64, MuBounds)> = None;
    let take = |wk: f64, mb: MuBounds, best: &mut Option<(f64, MuBounds)>| {
        if best.as_ref().is_none_or(|b| mb.upper > b.1.upper) {
            *best = Some((wk, mb));
        }
    };
    let mut grid_upper = Vec::with_capacity(w.len());
    let mut grid = Vec::with_capacity(w.len());
    for (wk, g) in w.iter().zip(freqresp(&st, &w)?.response) {
        let mb = mu_diag_complex(&g)?;
        grid_upper.push(mb.upper);
        grid.push(mb.clone());
        take(*wk, mb, &mut best);
    }
    let eval = |wk: f64| -> Result<MuBounds> {
        let r = freqresp(&st, &[wk])?;
        mu_diag_complex(&r.response[0])
    };
    if let Some(k) = (0..grid_upper.len()).max_by(|&a, &b| grid_upper[a].total_cmp(&grid_upper[b]))
    {
        let lo = w[k.saturating_sub(1)].ln();
        let hi = w[(k + 1).min(w.len() - 1)].ln();
        if hi > lo {
            let (wr, mb) = golden_max(lo, hi, &eval)?;
            take(wr, mb, &mut best);
        }
    }
    // The ends of the frequency axis: DC, and ∞ (continuous) or Nyquist (discrete).
    take(0.0, eval(0.0)?, &mut best);
    match dom.sample_time() {
        None => {
            let dinf = st.d().map(|v| Complex64::new(v, 0.0));
            let mb = mu_diag_complex(&dinf)?;
            take(f64::INFINITY, mb, &mut best);
        }
        Some(ts) => {
            let wn = std::f64::consts::PI / ts;
            take(wn, eval(wn)?, &mut best);
        }
    }
    let (peak_frequency, mu_peak) = best.ok_or_else(|| {
        LtiError::InvalidArgument("disk_margin_mimo: empty frequency grid".into())
    })?;
    let inv = |v: f64| if v > 0.0 { 1.0 / v } else { f64::INFINITY };
    let bounds = (inv(mu_peak.upper), inv(mu_peak.lower));
    let mut multi_loop = DiskMargin::from_alpha(bounds.0, skew);
    multi_loop.frequency = peak_frequency;
    Ok(MimoDiskMargin {
        loop_at_a_time,
        multi_loop,
        multi_loop_alpha_bounds: bounds,
        mu_peak,
        peak_frequency,
    })
}

/// Golden-section maximisation of `μ_upper(e^t)` over `t ∈ [lo, hi]`; returns the best
/// frequency and its bounds.
fn golden_max<F>(mut lo: f64, mut hi: f64, eval: &F) -> Result<(f64, MuBounds)>
where
    F: Fn(f64) -> Result<MuBounds>,
{
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let mut t1 = hi - r * (hi - lo);
    let mut t2 = lo + r * (hi - lo);
    let mut f1 = eval(t1.exp())?;
    let mut f2 = eval(t2.exp())?;
    for _ in 0..60 {
        if (hi - lo) < 1e-10 {
            break;
        }
        if f1.upper >= f2.upper {
            hi = t2;
            (t2, f2) = (t1, f1);
            t1 = hi - r * (hi - lo);
            f1 = eval(t1.exp())?;
        } else {
            lo = t1;
            (t1, f1) = (t2, f2);
            t2 = lo + r * (hi - lo);
            f2 = eval(t2.exp())?;
        }
    }
    Ok(if f1.upper >= f2.upper {
        (t1.exp(), f1)
    } else {
        (t2.exp(), f2)
    })
}
