//! System norms: the H2 norm from a Gramian and the H∞ norm by the Hamiltonian bisection of
//! Boyd–Balakrishnan and Bruinsma–Steinbuch (MATLAB `norm(sys, 2)`, `norm(sys, Inf)` /
//! `hinfnorm`, python-control `norm`, SLICOT `AB13BD`, `AB13DD`).
//!
//! # H2
//!
//! `‖G‖₂² = (1/2π) ∫ tr(G(jω)ᴴ G(jω)) dω = tr(Bᵀ W_o B) = tr(C W_c Cᵀ)` for a stable
//! continuous system with `D = 0`, where `W_o`, `W_c` are the observability and
//! controllability Gramians ([`gramian`](crate::analysis::gramian)); in discrete time
//! `‖G‖₂² = Σₖ tr(gₖᵀgₖ) = tr(Bᵀ W_o B + DᵀD)`. It is **infinite** for an unstable system
//! (the integral diverges) and for a continuous system with `D ≠ 0` (`|G(jω)| → |D|`), as in
//! MATLAB. The units are those of the output per input times `s^{−1/2}` (continuous).
//!
//! # H∞
//!
//! `‖G‖∞ = sup_ω σ_max(G(jω))` (continuous) or `sup_θ σ_max(G(e^{jθ}))` (discrete), infinite
//! for an unstable system or one with a pole on the stability boundary. For `γ > σ_max(D)`,
//! `γ` is a singular value of `G(jω)` exactly when `jω` is an eigenvalue of the Hamiltonian
//! (with `R = γ²I − DᵀD`)
//!
//! ```text
//! H(γ) = [ A + B R⁻¹ Dᵀ C          B R⁻¹ Bᵀ              ]
//!        [ −Cᵀ (I + D R⁻¹ Dᵀ) C    −(A + B R⁻¹ Dᵀ C)ᵀ    ]
//! ```
//!
//! (Boyd, Balakrishnan & Kabamba, Math. Control Signals Systems 2, 1989). The iteration of
//! Bruinsma & Steinbuch (Systems & Control Letters 14, 1990): `A` is reduced once to
//! Hessenberg form for every evaluation of `G(jω)` (Laub's method, no allocation per point);
//! the initial lower bound `γ_lb` is the largest of `σ_max(D)`, `σ_max(G(0))` and
//! `σ_max(G(j|p|))` over the poles `p` (one of each conjugate pair), the best of these then
//! maximised locally between its neighbouring candidate frequencies (at most a factor 4
//! away), so that for a typical system the first Hamiltonian test already confirms it;
//! the poles are computed once, for the stability test and these candidates;
//! at `γ = (1 + 2·tol)·γ_lb` collect the imaginary-axis eigenvalues `jωᵢ` of `H(γ)`; if there
//! are none, `γ` is an upper bound and the iteration stops, otherwise `γ_lb` becomes the
//! largest `σ_max(G(j√(ωᵢωᵢ₊₁)))` over consecutive pairs. The value returned is the lower bound
//! `γ_lb`, attained at [`HinfNorm::peak_frequency`]; the true norm lies in
//! `[value, upper_bound]` with `upper_bound = (1 + 2·tol)·value`. An eigenvalue `λ` of
//! `H(γ)` counts as imaginary when `|Re λ| ≤ 10⁻⁶·|λ| + 10⁻¹⁰·‖H‖_F`: a spurious one costs an
//! evaluation, never a wrong value (each `γ_lb` is an attained `σ_max`); the iteration also
//! stops when the midpoints no longer raise `γ_lb` (the imaginary eigenvalues then straddle
//! the peak already found within rounding).
//!
//! Discrete systems are mapped to continuous time by the bilinear transform
//! `z = (1 + s)/(1 − s)`, which maps the unit circle onto the imaginary axis
//! (`e^{jθ} ↔ jω` with `ω = tan(θ/2)`) and keeps the norm; the peak frequency is mapped back,
//! `ω_peak = 2·atan(ω)/ts` in rad/s.

use crate::analysis::{GramianKind, gramian};
use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::frequency_response::HessenbergEvaluator;
use crate::linalg::{CMat, Complex64, Mat, eigenvalues};
use crate::state_space::StateSpace;
use std::cell::RefCell;

/// The H2 norm (see the module documentation): `‖G‖₂`, infinite for an unstable system and
/// for a continuous system with a non-zero feedthrough `D`.
///
/// # Errors
/// The Lyapunov solver's errors ([`LtiError::NoUniqueSolution`], [`LtiError::NoConvergence`]).
#[doc(alias = "norm")]
pub fn h2_norm<D: TimeDomain>(sys: &StateSpace<D>) -> Result<f64> {
    let discrete = sys.domain().sample_time().is_some();
    let dd = sys.d().norm_squared();
    if !discrete && dd > 0.0 {
        return Ok(f64::INFINITY);
    }
    if sys.nx() == 0 {
        return Ok(dd.sqrt());
    }
    if !sys.is_stable()? {
        return Ok(f64::INFINITY);
    }
    let wo = gramian(sys, GramianKind::Observability)?.x;
    let t = (sys.b().transpose() * wo * sys.b()).trace() + if discrete { dd } else { 0.0 };
    Ok(t.max(0.0).sqrt())
}

/// The H∞ norm with the frequency where it is attained.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HinfNorm {
    /// `‖G‖∞`, attained (`σ_max(G(jω))` evaluated) at `peak_frequency`; infinite for an
    /// unstable system.
    pub value: f64,
    /// Frequency in rad/s where `value` is attained (`∞` when the supremum is the
    /// feedthrough's `σ_max(D)` at infinite frequency, which happens for a continuous system
    /// whose response never exceeds it; `NaN` for an unstable system).
    pub peak_frequency: f64,
    /// The level `(1 + 2·tol)·value` at which the iteration stopped: its Hamiltonian had no
    /// imaginary eigenvalues (so `‖G‖∞ ≤ upper_bound`), or their midpoints no longer raised
    /// the lower bound (module documentation).
    pub upper_bound: f64,
    /// Hamiltonian eigenvalue problems solved.
    pub iterations: usize,
}

/// The H∞ norm by Hamiltonian bisection (see the module documentation), to relative
/// tolerance `tol` (e.g. `1e-8`).
///
/// # Errors
/// [`LtiError::InvalidArgument`] unless `0 < tol < 1` (finite); [`LtiError::NoConvergence`]
/// from the eigenvalue computations or after 100 iterations; [`LtiError::Singular`] if the
/// bilinear map of a discrete system meets a pole at `z = −1` it should not.
#[doc(alias = "hinfnorm")]
#[doc(alias = "norm")]
pub fn hinf_norm<D: TimeDomain>(sys: &StateSpace<D>, tol: f64) -> Result<HinfNorm> {
    if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
        return Err(LtiError::InvalidArgument(format!(
            "hinf_norm: tolerance must be in (0, 1), got {tol}"
        )));
    }
    let dmax = sigma_max(&sys.d().map(|v| v.into()));
    if sys.nx() == 0 {
        return Ok(HinfNorm {
            value: dmax,
            peak_frequency: 0.0,
            upper_bound: dmax,
            iterations: 0,
        });
    }
    // The poles once: the stability test (`StateSpace::is_stable`'s rule, strictly inside by
    // more than 100 ε max(1, ‖A‖_F)) and the candidate frequencies of the lower bound.
    let poles = sys.poles()?;
    let tol_stab = 100.0 * f64::EPSILON * sys.a().norm().max(1.0);
    let domain = sys.domain();
    if poles
        .iter()
        .any(|&p| domain.stability_distance(p) >= -tol_stab)
    {
        return Ok(HinfNorm {
            value: f64::INFINITY,
            peak_frequency: f64::NAN,
            upper_bound: f64::INFINITY,
            iterations: 0,
        });
    }
    match domain.sample_time() {
        None => hinf_continuous(sys.a(), sys.b(), sys.c(), sys.d(), &poles, tol),
        Some(ts) => {
            let (a, b, c, d) = bilinear(sys)?;
            // z = (1 + s)/(1 − s) ⇔ s = (z − 1)/(z + 1); no pole is at z = −1 (stable).
            let one = crate::linalg::Complex64::new(1.0, 0.0);
            let pc: Vec<_> = poles.iter().map(|&z| (z - one) / (z + one)).collect();
            let mut r = hinf_continuous(&a, &b, &c, &d, &pc, tol)?;
            r.peak_frequency = 2.0 * r.peak_frequency.atan() / ts;
            Ok(r)
        }
    }
}

/// `z = (1 + s)/(1 − s)`: `A_c = (A + I)⁻¹(A − I)`, `B_c = √2 (A + I)⁻¹ B`,
/// `C_c = √2 C (A + I)⁻¹`, `D_c = D − C (A + I)⁻¹ B`.
fn bilinear<D: TimeDomain>(sys: &StateSpace<D>) -> Result<(Mat, Mat, Mat, Mat)> {
    let n = sys.nx();
    let api = sys.a() + Mat::identity(n, n);
    let lu = api.clone().lu();
    let sing = || LtiError::Singular {
        what: "A + I in the bilinear map of hinf_norm".into(),
        rcond: 0.0,
    };
    let inv = lu.try_inverse().ok_or_else(sing)?;
    let s2 = std::f64::consts::SQRT_2;
    let ac = &inv * (sys.a() - Mat::identity(n, n));
    let ib = &inv * sys.b();
    let bc = &ib * s2;
    let cc = sys.c() * &inv * s2;
    let dc = sys.d() - sys.c() * ib;
    Ok((ac, bc, cc, dc))
}

fn sigma_max(m: &CMat) -> f64 {
    if m.nrows() == 0 || m.ncols() == 0 {
        return 0.0;
    }
    if m.nrows() == 1 && m.ncols() == 1 {
        return m[(0, 0)].norm();
    }
    crate::linalg::svd::svd(m).singular_values.max()
}

fn hinf_continuous(
    a: &Mat,
    b: &Mat,
    c: &Mat,
    d: &Mat,
    poles: &[Complex64],
    tol: f64,
) -> Result<HinfNorm> {
    let n = a.nrows();
    let (ny, nu) = d.shape();
    // One Hessenberg reduction of A for every evaluation of σ_max(G(jω)).
    let evaluator = RefCell::new((HessenbergEvaluator::new(a, b, c, d), CMat::zeros(ny, nu)));
    let sig = |w: &[f64]| -> Result<Vec<f64>> {
        let mut guard = evaluator.borrow_mut();
        let (ev, out) = &mut *guard;
        w.iter()
            .map(|&wk| {
                let s = Complex64::new(0.0, wk);
                ev.eval(s, out)
                    .map_err(|()| LtiError::PoleAtEvaluationPoint {
                        what: format!("hinf_norm at {wk} rad/s"),
                        pole: s,
                    })?;
                Ok(sigma_max(out))
            })
            .collect()
    };
    // Initial lower bound: D (ω = ∞), ω = 0 and every pole's natural frequency |p| (one of
    // each conjugate pair), the best of them then maximised locally between its neighbours.
    let mut cand: Vec<f64> = std::iter::once(0.0)
        .chain(poles.iter().filter(|p| p.im >= 0.0).map(|p| p.norm()))
        .filter(|w| w.is_finite())
        .collect();
    cand.sort_by(f64::total_cmp);
    cand.dedup_by(|x, y| (*x - *y).abs() <= 1e-12 * y.abs());
    let s0 = sig(&cand)?;
    let mut lb = sigma_max(&d.map(|v| v.into()));
    let mut peak = f64::INFINITY;
    let mut best = None;
    for (k, (&w, &s)) in cand.iter().zip(&s0).enumerate() {
        if s > lb {
            lb = s;
            peak = w;
            best = Some(k);
        }
    }
    if let Some(k) = best {
        let lo = if k > 0 {
            cand[k - 1].max(peak / 4.0)
        } else {
            0.0
        };
        let hi = match cand.get(k + 1) {
            Some(&w) if peak > 0.0 => w.min(4.0 * peak),
            Some(&w) => w,
            None => 4.0 * peak,
        };
        if hi > lo {
            (peak, lb) = polish(&sig, lo, hi, peak, lb)?;
        }
    }
    if lb == 0.0 {
        // G ≡ 0 on the points tried; any positive level decides.
        lb = f64::MIN_POSITIVE.sqrt();
    }
    let mut iterations = 0;
    loop {
        iterations += 1;
        if iterations > 100 {
            return Err(LtiError::NoConvergence {
                algorithm: "hinf_norm bisection".into(),
                iterations: 100,
            });
        }
        let gamma = (1.0 + 2.0 * tol) * lb;
        let r = Mat::identity(nu, nu) * (gamma * gamma) - d.transpose() * d;
        let rinv = r
            .clone()
            .cholesky()
            .ok_or(LtiError::Singular {
                what: "γ²I − DᵀD in hinf_norm".into(),
                rcond: 0.0,
            })?
            .inverse();
        let f = a + b * &rinv * d.transpose() * c;
        let g = b * &rinv * b.transpose();
        let h21 = -(c.transpose() * (Mat::identity(ny, ny) + d * &rinv * d.transpose()) * c);
        let mut h = Mat::zeros(2 * n, 2 * n);
        h.view_mut((0, 0), (n, n)).copy_from(&f);
        h.view_mut((0, n), (n, n)).copy_from(&g);
        h.view_mut((n, 0), (n, n)).copy_from(&h21);
        h.view_mut((n, n), (n, n)).copy_from(&(-f.transpose()));
        let hn = h.norm();
        let ev = eigenvalues(&h)?;
        let mut ws: Vec<f64> = ev
            .iter()
            .filter(|l| l.im >= 0.0 && l.re.abs() <= 1e-6 * l.norm() + 1e-10 * hn)
            .map(|l| l.im)
            .collect();
        ws.sort_by(f64::total_cmp);
        if ws.is_empty() {
            return Ok(HinfNorm {
                value: lb,
                peak_frequency: peak,
                upper_bound: gamma,
                iterations,
            });
        }
        let mids: Vec<f64> = if ws.len() == 1 {
            ws.clone()
        } else {
            ws.windows(2)
                .map(|p| {
                    if p[0] > 0.0 {
                        (p[0] * p[1]).sqrt()
                    } else {
                        0.5 * p[1]
                    }
                })
                .collect()
        };
        let sv = sig(&mids)?;
        let mut improved = false;
        let mut best = None;
        for (i, (w, s)) in mids.into_iter().zip(sv).enumerate() {
            if s > lb {
                lb = s;
                peak = w;
                improved = true;
                best = Some(i);
            }
        }
        // Polish the new lower bound inside its interval of the imaginary eigenvalues (where
        // σ_max ≥ γ): a sharp peak is then found to working precision in a few steps, so the
        // next level is above it and the iteration ends.
        if let Some(i) = best
            && ws.len() > 1
        {
            let (w, s) = polish(&sig, ws[i], ws[i + 1], peak, lb)?;
            peak = w;
            lb = s;
        }
        if !improved {
            // The imaginary eigenvalues were rounding artefacts around the peak already found.
            return Ok(HinfNorm {
                value: lb,
                peak_frequency: peak,
                upper_bound: gamma,
                iterations,
            });
        }
    }
}

/// Maximises `σ_max(G(jω))` on `[lo, hi]` (log scale when `lo > 0`) by repeated 8-point
/// subdivision around the best point (one response call per step, 16 steps, each narrowing
/// the interval by a factor 4.5); returns the best `(ω, σ_max)`, never below `(w0, s0)`.
fn polish<F>(sig: &F, lo: f64, hi: f64, w0: f64, s0: f64) -> Result<(f64, f64)>
where
    F: Fn(&[f64]) -> Result<Vec<f64>>,
{
    let log = lo > 0.0;
    let (to, from) = (
        |w: f64, log: bool| if log { w.ln() } else { w },
        |x: f64, log: bool| if log { x.exp() } else { x },
    );
    let (mut a, mut b) = (to(lo, log), to(hi, log));
    let (mut bw, mut bs) = (w0, s0);
    for _ in 0..16 {
        let xs: Vec<f64> = (0..=8).map(|k| a + (b - a) * k as f64 / 8.0).collect();
        let ws: Vec<f64> = xs.iter().map(|&x| from(x, log)).collect();
        let sv = sig(&ws)?;
        let (k, &s) = sv
            .iter()
            .enumerate()
            .max_by(|x, y| x.1.total_cmp(y.1))
            .expect("nine points");
        if s > bs {
            bs = s;
            bw = ws[k];
        }
        a = xs[k.saturating_sub(1)];
        b = xs[(k + 1).min(8)];
        if (b - a).abs() <= 4.0 * f64::EPSILON * a.abs().max(b.abs()) {
            break;
        }
    }
    Ok((bw, bs))
}
