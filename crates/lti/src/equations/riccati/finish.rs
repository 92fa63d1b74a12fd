//! Steps 4–6 of the solve (see the [module documentation](super)) shared by every method:
//! the [`Finisher`] (Newton refinement, gain, closed-loop poles, boundary verdict and residual
//! limit), the fallback over the candidate methods, and the diagnosis of a failure from the data
//! (PBH tests naming an unstabilisable or undetectable mode).

use super::boundary;
use super::data::Reduced;
use super::residual::{care_gain, care_residual_full, dare_gain, dare_residual_full};
use super::subspace::{Computed, NewtonHint};
use super::{
    Domain, FAIL_FAST_MIN_STATES, GOOD_RESIDUAL, PBH_TOLERANCE, REFINEMENT_FLOOR, RESIDUAL_LIMIT,
    RiccatiMethod, RiccatiOptions, RiccatiSolution,
};
use crate::error::{LtiError, Result};
use crate::linalg::{Complex64, Mat, check_finite, pbh_margin, symmetrize};

/// Explains a failure from the data: an uncontrollable mode that is not stable
/// ([`LtiError::NotStabilizable`]), or an unobservable (through `Q̃`) mode on the stability
/// boundary ([`LtiError::NotDetectable`]). `a`, `q` are the cross-term-free `Ã`, `Q̃`.
pub(crate) fn diagnose(domain: Domain, a: &Mat, b: &Mat, q: &Mat) -> Option<LtiError> {
    let ev = crate::linalg::eigenvalues(a).ok()?;
    let scale = match domain {
        Domain::Continuous => a.norm().max(1.0),
        Domain::Discrete => 1.0,
    };
    let tol_region = 1e-8 * scale;
    // Stabilisability: every mode with margin ≤ tol (not stable) must be controllable.
    let mut worst: Option<(f64, Complex64)> = None;
    for &l in &ev {
        if domain.stability_margin(l) <= tol_region {
            let m = pbh_margin(a, b, l);
            if worst.is_none_or(|w| m < w.0) {
                worst = Some((m, l));
            }
        }
    }
    if let Some((margin, eigenvalue)) = worst
        && margin <= PBH_TOLERANCE
    {
        return Some(LtiError::NotStabilizable { eigenvalue, margin });
    }
    // Detectability on the boundary: (Q̃, Ã) must have no unobservable boundary mode.
    let mut worst: Option<(f64, Complex64)> = None;
    for &l in &ev {
        if domain.stability_margin(l).abs() <= tol_region {
            let m = pbh_margin(&a.transpose(), q, l.conj());
            if worst.is_none_or(|w| m < w.0) {
                worst = Some((m, l));
            }
        }
    }
    if let Some((margin, eigenvalue)) = worst
        && margin <= PBH_TOLERANCE
    {
        return Some(LtiError::NotDetectable { eigenvalue, margin });
    }
    None
}

/// Step 5 and 6 for either domain: refinement, gain, poles and acceptance checks.
pub(crate) struct Finisher<'a> {
    pub domain: Domain,
    pub a: &'a Mat,
    pub b: &'a Mat,
    pub q: &'a Mat,
    pub r: &'a Mat,
    pub n: Option<&'a Mat>,
    pub red: &'a Reduced,
    /// Apply the boundary verdict ([`boundary::certify`]) to the result (`false` only for
    /// an intermediate problem whose result is finished again, e.g. the shifted DARE of a
    /// singular `R`).
    pub certify: bool,
}

impl Finisher<'_> {
    fn gain(&self, x: &Mat) -> Option<Mat> {
        match self.domain {
            Domain::Continuous => Some(care_gain(&self.red.l, self.b, self.n, x)),
            Domain::Discrete => dare_gain(self.a, self.b, self.r, self.n, x),
        }
    }

    fn residual(&self, x: &Mat) -> Option<(Mat, f64)> {
        match self.domain {
            Domain::Continuous => Some(care_residual_full(
                self.a,
                self.b,
                self.q,
                &self.red.l,
                self.n,
                x,
            )),
            Domain::Discrete => dare_residual_full(self.a, self.b, self.q, self.r, self.n, x),
        }
    }

    /// Refines `x`, computes the diagnostics and checks them.
    pub(crate) fn finish(
        &self,
        x: Mat,
        method: RiccatiMethod,
        options: &RiccatiOptions,
    ) -> Result<RiccatiSolution> {
        self.finish_with(Computed { x, hint: None }, method, options)
    }

    /// [`Finisher::finish`] for a computed solution that may carry a [`NewtonHint`]: the
    /// Newton steps then use it (no Schur decomposition of `A − BK`) as long as they lower the
    /// residual; after the first step that does not, the exact step (Schur decomposition of
    /// `A − BK`) is tried before giving up.
    pub(crate) fn finish_with(
        &self,
        computed: Computed,
        method: RiccatiMethod,
        options: &RiccatiOptions,
    ) -> Result<RiccatiSolution> {
        let Computed { x, hint } = computed;
        let mut hint = hint.filter(|_| self.domain == Domain::Continuous);
        let nx = self.a.nrows();
        let mut x = symmetrize(&x);
        let bad = |what: &str| LtiError::Inaccurate {
            what: format!("{what}: BᵀXB + R is singular at the computed solution"),
            residual: f64::INFINITY,
            tolerance: RESIDUAL_LIMIT,
        };
        let mut k = self.gain(&x).ok_or_else(|| bad("DARE gain"))?;
        let (mut res_mat, mut residual) = self.residual(&x).ok_or_else(|| bad("DARE residual"))?;
        let mut steps = 0;
        let floor = REFINEMENT_FLOOR * nx as f64 * f64::EPSILON;
        while steps < options.max_refinement_steps && residual > floor && residual.is_finite() {
            // Newton step in correction form: L_K(Δ) = −Res(X), with L_K the Fréchet
            // derivative at X: (A−BK)ᵀΔ + Δ(A−BK) (Kleinman) or (A−BK)ᵀΔ(A−BK) − Δ (Hewer).
            let delta = match &hint {
                Some(NewtonHint::Schur(h)) => h.newton_step(&res_mat),
                Some(NewtonHint::Smith(h)) => h.newton_step(&(self.a - self.b * &k), &res_mat),
                None => {
                    let ak = self.a - self.b * &k;
                    match self.domain {
                        Domain::Continuous => kleinman_step(&ak, &res_mat),
                        Domain::Discrete => {
                            crate::equations::dlyap(&ak.transpose(), &res_mat).map(|d| d.x)
                        }
                    }
                }
            };
            let Ok(delta) = delta else {
                if hint.take().is_some() {
                    continue;
                }
                break;
            };
            let x_new = symmetrize(&(&x + &delta));
            let Some(k_new) = self.gain(&x_new) else {
                break;
            };
            let Some((rm, rel)) = self.residual(&x_new) else {
                break;
            };
            if rel < residual {
                let gain = residual / rel;
                x = x_new;
                k = k_new;
                res_mat = rm;
                residual = rel;
                steps += 1;
                // A small gain ends the refinement; after a step from the Hamiltonian's Schur
                // data the exact step is tried first.
                if gain < 2.0 && hint.take().is_none() {
                    break;
                }
            } else if hint.take().is_none() {
                break;
            }
            // Otherwise the step from the Schur data of the Hamiltonian did not help: the exact
            // one is tried next.
        }
        let acl = self.a - self.b * &k;
        let poles = crate::linalg::eigenvalues(&acl)?;
        if self.certify {
            boundary::certify(self.domain, self.red, (&x, &acl), &poles, residual)?;
        }
        if residual.is_nan() || residual > RESIDUAL_LIMIT {
            return Err(LtiError::Inaccurate {
                what: match self.domain {
                    Domain::Continuous => "CARE solution",
                    Domain::Discrete => "DARE solution",
                }
                .into(),
                residual,
                tolerance: RESIDUAL_LIMIT,
            });
        }
        Ok(RiccatiSolution {
            x,
            gain: k,
            closed_loop_poles: poles,
            residual,
            method,
            refinement_steps: steps,
        })
    }
}

/// The Kleinman–Newton correction: `Δ` with `FᵀΔ + ΔF = −Res` for the closed loop `F`, by
/// Bartels–Stewart on the real Schur form `Fᵀ = USUᵀ` (`SY + YSᵀ = −UᵀResU`, `Δ = UYUᵀ`) —
/// the computation of [`lyap`](crate::equations::lyap) without its input checks and its
/// residual evaluation (the caller evaluates the Riccati residual of `X + Δ` instead). An
/// eigenvalue collision `λᵢ(F) + λⱼ(F) ≈ 0` (no unique correction) is an error.
fn kleinman_step(f: &Mat, res: &Mat) -> Result<Mat> {
    let (s, u) = crate::linalg::schur::real_schur(&f.transpose())?.into_parts();
    let mut y = -(u.transpose() * res * &u);
    y = symmetrize(&y);
    let perturbed = crate::equations::triangular::solve_quasi_sylvester(
        &s,
        &s,
        crate::equations::triangular::RightCoef::TransposeOfUpper,
        &mut y,
    );
    if perturbed {
        return Err(LtiError::Singular {
            what: "Lyapunov operator of the Newton step (closed loop not stable)".into(),
            rcond: 0.0,
        });
    }
    let d = symmetrize(&(&u * y * u.transpose()));
    check_finite("Newton correction", &d)?;
    Ok(d)
}

/// Runs the candidate methods in order and returns the first accepted solution with a
/// residual at most [`GOOD_RESIDUAL`], else the most accurate accepted one; when none is
/// accepted the data are diagnosed and the most informative error is returned.
pub(crate) fn solve_with_fallback(
    fin: &Finisher<'_>,
    candidates: &[RiccatiMethod],
    options: &RiccatiOptions,
    compute: impl FnMut(RiccatiMethod) -> Result<Computed>,
) -> Result<RiccatiSolution> {
    solve_with_fallback_prior(fin, candidates, options, None, compute)
}

/// [`solve_with_fallback`] with the finished result of one candidate already known (`prior`,
/// used in its place instead of computing it again).
pub(crate) fn solve_with_fallback_prior(
    fin: &Finisher<'_>,
    candidates: &[RiccatiMethod],
    options: &RiccatiOptions,
    mut prior: Option<(RiccatiMethod, Result<RiccatiSolution>)>,
    mut compute: impl FnMut(RiccatiMethod) -> Result<Computed>,
) -> Result<RiccatiSolution> {
    let mut first_err: Option<LtiError> = None;
    let mut best: Option<RiccatiSolution> = None;
    for &m in candidates {
        let attempt = match prior.take_if(|(pm, _)| *pm == m) {
            Some((_, known)) => known,
            None => compute(m).and_then(|c| fin.finish_with(c, m, options)),
        };
        match attempt {
            Ok(sol) => {
                if sol.residual <= GOOD_RESIDUAL {
                    return Ok(sol);
                }
                if best.as_ref().is_none_or(|b| sol.residual < b.residual) {
                    best = Some(sol);
                }
            }
            // Fail fast: a large problem whose stable subspace cannot be inverted stops
            // here, before the remaining methods and the O(k·n³) diagnosis (PBH tests on
            // every non-stable mode) that would otherwise take minutes at n = 600.
            Err(e @ LtiError::IllConditioned { .. }) if fin.a.nrows() > FAIL_FAST_MIN_STATES => {
                return Err(e);
            }
            Err(e) => {
                if first_err.is_none() {
                    first_err = Some(e);
                }
            }
        }
    }
    if let Some(sol) = best {
        return Ok(sol);
    }
    if let Some(d) = diagnose(fin.domain, &fin.red.a, fin.b, &fin.red.q) {
        return Err(d);
    }
    Err(first_err.unwrap_or_else(|| LtiError::InvalidArgument("no Riccati method selected".into())))
}

/// The stabilising solution of the empty problem (`n = 0`).
pub(crate) fn empty_solution(m: usize, method: RiccatiMethod) -> RiccatiSolution {
    RiccatiSolution {
        x: Mat::zeros(0, 0),
        gain: Mat::zeros(m, 0),
        closed_loop_poles: Vec::new(),
        residual: 0.0,
        method,
        refinement_steps: 0,
    }
}
