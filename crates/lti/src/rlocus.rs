//! Root locus of a SISO loop (MATLAB `rlocus`, `rlocfind`; python-control `root_locus_map`).
//!
//! # Definitions
//!
//! With `L = N/D` (the denominator monic, as [`TransferFunction`] stores it) closed by
//! negative feedback through a gain `K ≥ 0`, the closed-loop poles are the roots of
//! `D(s) + K N(s) = 0` (z in discrete time: the algebra is the same). With `n = deg D`,
//! `m = deg N ≤ n`:
//!
//! - **Branches**: the `n` roots as functions of `K`, starting at the open-loop poles
//!   (`K = 0`). `m` of them end at the zeros, the other `n − m` go to infinity along the
//!   **asymptotes**: rays from the centroid `σ = (Σ pᵢ − Σ zⱼ)/(n − m)` at the angles
//!   `(2k + 1)π/(n − m)`, `k = 0 … n − m − 1`.
//! - **Break-away / break-in points**: points where branches meet, the roots of
//!   `dK/ds = 0` for `K = −D/N`, i.e. of `N D′ − N′ D`, kept where `K = −D(s)/N(s)` is real
//!   and `≥ 0` (relative imaginary part below `10⁻⁶`).
//! - **`rlocfind`**: the gain at a chosen point `s₀` is `K = −D(s₀)/N(s₀)` (complex unless
//!   `s₀` is on the locus); [`RlocFind`] reports its real part (MATLAB's choice), the
//!   closed-loop poles at that gain and the distance from `s₀` to the nearest of them.
//!
//! # Method
//!
//! The roots at each gain are those of [`Polynomial::roots`] (balanced companion matrix).
//! Without a gain list, the gains are `0`, 120 log-spaced values from `10⁻⁸ K_max` to `K_max`
//! and the break points' gains, where `K_max` places the infinite branches at five times the
//! extent `R` of the poles, zeros and centroid (`K = (5R)^{n−m}/|lead N|`) and the finite
//! ones within `R/100` of their zeros (`K = 100 |D(zⱼ)|/(R |N′(zⱼ)|)`); an interval over which
//! any root moves more than `R/50` is then bisected (up to 14 levels). Roots at consecutive
//! gains are matched into branches by increasing distance (greedy assignment), so each branch
//! is continuous where the gain grid resolves it. A gain at which `deg(D + K N)` drops
//! (`K = −1/lead N` for a biproper loop) is skipped.

use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::linalg::Complex64;
use crate::polynomial::Polynomial;
use crate::state_space::StateSpace;
use crate::transfer_function::TransferFunction;

/// The asymptotes of the branches that go to infinity.
#[derive(Debug, Clone, PartialEq)]
pub struct Asymptotes {
    /// Centroid `σ = (Σ pᵢ − Σ zⱼ)/(n − m)` on the real axis (NaN when `n = m`).
    pub centroid: f64,
    /// Angles `(2k + 1)π/(n − m)` in radians, in `(0, 2π)`, ascending (empty when `n = m`).
    pub angles: Vec<f64>,
}

/// A break-away or break-in point with its gain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BreakPoint {
    /// The point `s` (or `z`), a root of `N D′ − N′ D`.
    pub point: Complex64,
    /// `K = −D(s)/N(s)`, real and `≥ 0`.
    pub gain: f64,
}

/// The root locus (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct RootLocus {
    /// Gains, ascending.
    pub gains: Vec<f64>,
    /// `roots[k][b]`: branch `b` at `gains[k]` (each row has `n` entries, branches matched
    /// across rows).
    pub roots: Vec<Vec<Complex64>>,
    /// Open-loop poles (`K = 0`).
    pub poles: Vec<Complex64>,
    /// Open-loop zeros (finite ends of `m` branches).
    pub zeros: Vec<Complex64>,
    /// Asymptotes of the `n − m` infinite branches.
    pub asymptotes: Asymptotes,
    /// Break-away and break-in points with real `K ≥ 0`.
    pub break_points: Vec<BreakPoint>,
}

/// The gain of a chosen point (MATLAB `rlocfind`).
#[derive(Debug, Clone, PartialEq)]
pub struct RlocFind {
    /// `K = Re(−D(s₀)/N(s₀))`.
    pub gain: f64,
    /// `−D(s₀)/N(s₀)` itself (imaginary part zero when `s₀` is on the locus).
    pub gain_complex: Complex64,
    /// Closed-loop poles at `gain` (roots of `D + K N`).
    pub poles: Vec<Complex64>,
    /// Distance from `s₀` to the nearest of `poles` (0 when `s₀` is on the locus).
    pub distance: f64,
}

fn num_den<D: TimeDomain>(l: &TransferFunction<D>, what: &str) -> Result<(Polynomial, Polynomial)> {
    if !l.is_proper() {
        return Err(LtiError::Improper {
            what: what.into(),
            num_degree: l.num().degree(),
            den_degree: l.den().degree(),
        });
    }
    if l.num().is_zero() {
        return Err(LtiError::InvalidArgument(format!(
            "{what}: the loop is zero, its closed-loop poles do not depend on the gain"
        )));
    }
    Ok((l.num().clone(), l.den().clone()))
}

/// Roots of `D + K N`; `None` if the degree drops below `deg D`.
fn roots_at(n: &Polynomial, d: &Polynomial, k: f64) -> Result<Option<Vec<Complex64>>> {
    let p = d.plus(&n.scale(k));
    if p.is_zero() || p.degree() < d.degree() {
        return Ok(None);
    }
    p.roots().map(Some)
}

/// Orders `new` to follow `prev` (greedy matching by increasing distance).
fn match_roots(prev: &[Complex64], new: &[Complex64]) -> Vec<Complex64> {
    let n = prev.len();
    let mut pairs: Vec<(f64, usize, usize)> = Vec::with_capacity(n * n);
    for (i, p) in prev.iter().enumerate() {
        for (j, q) in new.iter().enumerate() {
            pairs.push(((p - q).norm(), i, j));
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = vec![Complex64::new(f64::NAN, f64::NAN); n];
    let (mut used_i, mut used_j) = (vec![false; n], vec![false; n]);
    for (_, i, j) in pairs {
        if !used_i[i] && !used_j[j] {
            out[i] = new[j];
            used_i[i] = true;
            used_j[j] = true;
        }
    }
    out
}

/// Asymptotes of the loop `N/D`.
fn asymptotes(poles: &[Complex64], zeros: &[Complex64]) -> Asymptotes {
    let q = poles.len().saturating_sub(zeros.len());
    if q == 0 {
        return Asymptotes {
            centroid: f64::NAN,
            angles: Vec::new(),
        };
    }
    let sp: f64 = poles.iter().map(|p| p.re).sum();
    let sz: f64 = zeros.iter().map(|z| z.re).sum();
    Asymptotes {
        centroid: (sp - sz) / q as f64,
        angles: (0..q)
            .map(|k| (2 * k + 1) as f64 * std::f64::consts::PI / q as f64)
            .collect(),
    }
}

/// Break-away and break-in points (roots of `N D′ − N′ D` with real `K ≥ 0`).
fn break_points(n: &Polynomial, d: &Polynomial) -> Result<Vec<BreakPoint>> {
    let p = n.times(&d.derivative()).minus(&n.derivative().times(d));
    if p.is_zero() || p.degree() == 0 {
        return Ok(Vec::new());
    }
    let mut out = Vec::new();
    for s in p.roots()? {
        let nv = n.eval_complex(s);
        if nv.norm() == 0.0 {
            continue;
        }
        let k = -d.eval_complex(s) / nv;
        if k.im.abs() <= 1e-6 * k.norm().max(1e-300) && k.re >= 0.0 && k.re.is_finite() {
            out.push(BreakPoint {
                point: s,
                gain: k.re,
            });
        }
    }
    out.sort_by(|a, b| a.gain.total_cmp(&b.gain));
    Ok(out)
}

/// The root locus of the SISO loop `L` over `gains` (each finite and `≥ 0`; sorted here) or,
/// with `None`, over the automatic adaptive grid (module documentation).
///
/// # Errors
/// [`LtiError::Improper`] for an improper loop; [`LtiError::InvalidArgument`] for the zero
/// loop, a negative or non-finite gain or an empty gain list; [`LtiError::NoConvergence`]
/// from the root finder.
#[doc(alias = "rlocus")]
#[doc(alias = "root_locus")]
pub fn rlocus_tf<D: TimeDomain>(
    l: &TransferFunction<D>,
    gains: Option<&[f64]>,
) -> Result<RootLocus> {
    let (n, d) = num_den(l, "rlocus")?;
    let poles = d.roots()?;
    let zeros = if n.degree() == 0 {
        Vec::new()
    } else {
        n.roots()?
    };
    let asym = asymptotes(&poles, &zeros);
    let bps = break_points(&n, &d)?;
    let mut ks: Vec<f64> = match gains {
        Some(g) => {
            if g.is_empty() {
                return Err(LtiError::InvalidArgument(
                    "rlocus: the gain list is empty".into(),
                ));
            }
            if let Some(k) = g.iter().find(|k| !(k.is_finite() && **k >= 0.0)) {
                return Err(LtiError::InvalidArgument(format!(
                    "rlocus: gains must be finite and >= 0, got {k}"
                )));
            }
            let mut g = g.to_vec();
            g.sort_by(f64::total_cmp);
            g
        }
        None => {
            let extent = poles
                .iter()
                .chain(zeros.iter())
                .map(|p| p.norm())
                .chain(std::iter::once(asym.centroid.abs()))
                .filter(|x| x.is_finite())
                .fold(0.0, f64::max)
                .max(1e-3);
            let q = (d.degree() - n.degree().min(d.degree())) as i32;
            let mut kmax: f64 = if q > 0 {
                (5.0 * extent).powi(q) / n.leading().abs()
            } else {
                0.0
            };
            let dn = n.derivative();
            for z in &zeros {
                let nd = dn.eval_complex(*z).norm();
                if nd > 0.0 {
                    kmax = kmax.max(100.0 * d.eval_complex(*z).norm() / (extent * nd));
                }
            }
            if !(kmax.is_finite() && kmax > 0.0) {
                kmax = 1.0;
            }
            let mut g = vec![0.0];
            g.extend(crate::frequency_response::logspace(
                (kmax * 1e-8).log10(),
                kmax.log10(),
                120,
            ));
            g.extend(bps.iter().map(|b| b.gain).filter(|k| *k <= kmax));
            g.sort_by(f64::total_cmp);
            g.dedup();
            g
        }
    };
    let step = if gains.is_none() {
        let extent = poles
            .iter()
            .chain(zeros.iter())
            .map(|p| p.norm())
            .fold(0.0, f64::max)
            .max(1e-3);
        Some(extent / 50.0)
    } else {
        None
    };
    let mut rows: Vec<(f64, Vec<Complex64>)> = Vec::with_capacity(ks.len());
    for &k in &ks {
        if let Some(r) = roots_at(&n, &d, k)? {
            rows.push((k, r));
        }
    }
    if let Some(step) = step {
        for _ in 0..14 {
            let mut inserted = false;
            let mut next: Vec<(f64, Vec<Complex64>)> = Vec::with_capacity(rows.len() * 2);
            for i in 0..rows.len() {
                next.push(rows[i].clone());
                if i + 1 == rows.len() {
                    continue;
                }
                let (k0, r0) = (&rows[i].0, &rows[i].1);
                let (k1, r1) = (&rows[i + 1].0, &rows[i + 1].1);
                let m = match_roots(r0, r1);
                let moved = r0
                    .iter()
                    .zip(&m)
                    .map(|(a, b)| (a - b).norm())
                    .fold(0.0, f64::max);
                let km = if *k0 > 0.0 {
                    (k0 * k1).sqrt()
                } else {
                    0.5 * k1
                };
                if moved > step
                    && km > *k0
                    && km < *k1
                    && let Some(r) = roots_at(&n, &d, km)?
                {
                    next.push((km, r));
                    inserted = true;
                }
            }
            rows = next;
            if !inserted || rows.len() > 20_000 {
                break;
            }
        }
    }
    // Match into branches.
    for i in 1..rows.len() {
        let m = match_roots(&rows[i - 1].1, &rows[i].1);
        rows[i].1 = m;
    }
    ks = rows.iter().map(|r| r.0).collect();
    Ok(RootLocus {
        gains: ks,
        roots: rows.into_iter().map(|r| r.1).collect(),
        poles,
        zeros,
        asymptotes: asym,
        break_points: bps,
    })
}

/// [`rlocus_tf`] of a SISO state-space loop (through its transfer function).
///
/// # Errors
/// [`LtiError::NotSiso`]; otherwise as [`rlocus_tf`].
pub fn rlocus<D: TimeDomain>(l: &StateSpace<D>, gains: Option<&[f64]>) -> Result<RootLocus> {
    rlocus_tf(&TransferFunction::from_state_space(l)?, gains)
}

/// The gain at the point `s0` (MATLAB `rlocfind`, see the module documentation).
///
/// # Errors
/// [`LtiError::Improper`]; [`LtiError::InvalidArgument`] for the zero loop or a non-finite
/// `s0`; [`LtiError::PoleAtEvaluationPoint`] if `s0` is a zero of `N` (the gain is
/// infinite); [`LtiError::NoConvergence`].
#[doc(alias = "rlocfind")]
pub fn rlocfind_tf<D: TimeDomain>(l: &TransferFunction<D>, s0: Complex64) -> Result<RlocFind> {
    let (n, d) = num_den(l, "rlocfind")?;
    if !(s0.re.is_finite() && s0.im.is_finite()) {
        return Err(LtiError::InvalidArgument(format!(
            "rlocfind: the point must be finite, got {s0}"
        )));
    }
    let nv = n.eval_complex(s0);
    if nv.norm() == 0.0 {
        return Err(LtiError::PoleAtEvaluationPoint {
            what: "rlocfind gain −D/N (a zero of the loop)".into(),
            pole: s0,
        });
    }
    let kc = -d.eval_complex(s0) / nv;
    let poles = roots_at(&n, &d, kc.re)?.unwrap_or_default();
    let distance = poles
        .iter()
        .map(|p| (p - s0).norm())
        .fold(f64::INFINITY, f64::min);
    Ok(RlocFind {
        gain: kc.re,
        gain_complex: kc,
        poles,
        distance,
    })
}

/// [`rlocfind_tf`] of a SISO state-space loop.
///
/// # Errors
/// [`LtiError::NotSiso`]; otherwise as [`rlocfind_tf`].
pub fn rlocfind<D: TimeDomain>(l: &StateSpace<D>, s0: Complex64) -> Result<RlocFind> {
    rlocfind_tf(&TransferFunction::from_state_space(l)?, s0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn branches_start_at_poles() {
        let l = TransferFunction::continuous(&[1.0], &[1.0, 3.0, 2.0, 0.0]).unwrap();
        let rl = rlocus_tf(&l, None).unwrap();
        assert_eq!(rl.gains[0], 0.0);
        let mut first = rl.roots[0].clone();
        crate::linalg::sort_eigenvalues(&mut first);
        for (a, b) in first.iter().zip(&rl.poles) {
            assert!((a - b).norm() < 1e-12);
        }
        assert!(rl.gains.len() > 100);
    }
}
