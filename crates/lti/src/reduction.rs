//! Minimal realisations and balanced model reduction (MATLAB `minreal`, `hsvd`, `balreal`,
//! `balred`; python-control `minreal`, `hsvd`, `balred`; SLICOT `TB01PD`, `AB09AD`,
//! `AB09BD`).
//!
//! # Minimal realisation
//!
//! [`minreal`] removes the uncontrollable part with the controllability staircase
//! ([`controllability_staircase`](crate::analysis::controllability_staircase), orthogonal,
//! rank decisions at a tolerance) and then the unobservable part with the staircase of the
//! dual pair `(Aᵀ, Cᵀ)`; the transfer function is unchanged (the removed modes do not reach
//! it) and the result is controllable and observable at the tolerance used.
//!
//! # Balanced realisation and truncation (stable systems)
//!
//! For an asymptotically stable system with Gramians `W_c = R Rᵀ` and `W_o = L Lᵀ`
//! ([`gramian`](crate::analysis::gramian), factored through their symmetric eigenvalue
//! decompositions, negative rounding clipped), the Hankel singular values are the singular
//! values `σ₁ ≥ … ≥ σₙ ≥ 0` of `Lᵀ R = U Σ Vᵀ`, i.e. `σᵢ = √λᵢ(W_c W_o)`. The square-root
//! method (Laub, Heath, Paige & Ward, IEEE TAC 32(2), 1987; Tombs & Postlethwaite, IJC 46(4),
//! 1987) takes `T = R V Σ^{−1/2}` and `T⁻¹ = Σ^{−1/2} Uᵀ Lᵀ`, so that in `x = T x_b` both
//! Gramians equal `Σ`. Truncation to order `r` keeps the first `r` columns of `V`, `U`:
//! `A_r = T_r⁻¹ A T_r`, `B_r = T_r⁻¹ B`, `C_r = C T_r`, `D_r = D`, stable, with the bound
//! `‖G − G_r‖∞ ≤ 2 Σ_{i>r} σᵢ` (Glover, IJC 39(6), 1984). Matched DC gain (singular
//! perturbation) instead sets the derivative (continuous) or the increment (discrete) of the
//! discarded balanced states to zero:
//! `A_r = A₁₁ − A₁₂ A₂₂⁻¹ A₂₁`, `B_r = B₁ − A₁₂ A₂₂⁻¹ B₂`, `C_r = C₁ − C₂ A₂₂⁻¹ A₂₁`,
//! `D_r = D − C₂ A₂₂⁻¹ B₂` (continuous; discrete with `A₂₂ − I` in place of `A₂₂`), which keeps
//! `G(0)` (`G(1)`) and the same error bound; the states with a zero Hankel singular value
//! (non-minimal ones) are dropped first.
//!
//! # Unstable systems: stable/unstable decomposition (MATLAB `stabsep`, `hsvd`, `balreal`,
//! `balred`)
//!
//! [`stabsep`] splits `G = G_s + G_u` additively: the real Schur form `A = Z T Zᵀ` is reordered
//! so that the stable eigenvalues (`Re λ < 0` in continuous time, `|λ| < 1` in discrete time)
//! come first, `T = [[T₁₁, T₁₂], [0, T₂₂]]`, and the Sylvester equation
//! `T₁₁ X − X T₂₂ + T₁₂ = 0` (unique, the spectra of `T₁₁` and `T₂₂` are disjoint) gives
//! `W = [[I, X], [0, I]]` with `W⁻¹ T W = diag(T₁₁, T₂₂)`. With `Zᵀ B = [B₁; B₂]` and
//! `C Z = [C₁, C₂]`: `G_s = (T₁₁, B₁ − X B₂, C₁, D)` and `G_u = (T₂₂, B₂, C₁ X + C₂, 0)`; the
//! feedthrough goes to the stable part and `G_u` is strictly proper (MATLAB's convention). An
//! eigenvalue on the stability boundary (`|Re λ|`, `||λ| − 1|` at most `100·ε·max(1, ‖A‖_F)`,
//! the rule of [`StateSpace::is_stable`]) belongs to neither part: [`LtiError::InvalidArgument`]
//! naming it.
//!
//! For a system with unstable poles, as MATLAB does:
//! - [`hsvd`] returns the Hankel singular values of `G_s`, preceded by one `f64::INFINITY` per
//!   unstable state (the unstable modes are never discarded);
//! - [`balreal`] balances `G_s` and adds `G_u` back: the state is `[x_u; x_b]`, the unstable
//!   states first, and the Gramians of the stable block are `diag(σ)`;
//! - [`balred`] to `order` states keeps every unstable mode (`G_u` unchanged) and reduces `G_s`
//!   to `order − n_u` states (truncation or matched DC), so that `G − G_r = G_s − G_{s,r}` and
//!   the bound `‖G − G_r‖∞ ≤ 2 Σ_{i>order−n_u} σᵢ(G_s)` holds; `order < n_u` is an
//!   [`LtiError::InvalidArgument`].
//!
//! The Gramians of an unstable system itself still do not exist
//! ([`gramian`](crate::analysis::gramian) refuses it).

use crate::analysis::{GramianKind, controllability_staircase, gramian};
use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::linalg::schur::real_schur;
use crate::linalg::{Complex64, Mat};
use crate::state_space::StateSpace;

/// A minimal realisation and what was removed.
#[derive(Debug, Clone, PartialEq)]
pub struct MinimalRealization<D: TimeDomain> {
    /// The controllable and observable part (same transfer function).
    pub system: StateSpace<D>,
    /// Dimension of the controllable subspace of the original realisation.
    pub controllable_dimension: usize,
    /// States removed (original order minus the minimal order).
    pub removed_states: usize,
}

/// A minimal realisation by two orthogonal staircase reductions (module documentation).
/// `tolerance` is the absolute rank-decision threshold of both staircases (default
/// `10·n·ε·max(‖A‖_F, ‖B‖_F)` and its dual with `C`).
///
/// # Errors
/// [`LtiError::InvalidArgument`] for a negative or non-finite tolerance.
pub fn minreal<D: TimeDomain>(
    sys: &StateSpace<D>,
    tolerance: Option<f64>,
) -> Result<MinimalRealization<D>> {
    if let Some(t) = tolerance
        && !(t.is_finite() && t >= 0.0)
    {
        return Err(LtiError::InvalidArgument(format!(
            "minreal: tolerance must be finite and ≥ 0, got {t}"
        )));
    }
    let n = sys.nx();
    let st = controllability_staircase(sys.a(), sys.b(), tolerance)?;
    let k = st.controllable_dimension;
    let ac = st.a.view((0, 0), (k, k)).clone_owned();
    let bc = st.b.rows(0, k).clone_owned();
    let cc = sys.c() * st.z.columns(0, k);
    let so = controllability_staircase(&ac.transpose(), &cc.transpose(), tolerance)?;
    let m = so.controllable_dimension;
    let ao = so.a.view((0, 0), (m, m)).transpose();
    let co = so.b.rows(0, m).transpose();
    let bo = (so.z.transpose() * bc).rows(0, m).clone_owned();
    Ok(MinimalRealization {
        system: StateSpace::new(ao, bo, co, sys.d().clone(), sys.domain())?,
        controllable_dimension: k,
        removed_states: n - m,
    })
}

/// The additive stable/unstable decomposition with its state transformation:
/// `x = V [x_s; x_u]`, `[x_s; x_u] = V⁻¹ x`.
struct Split<D: TimeDomain> {
    stable: StateSpace<D>,
    unstable: StateSpace<D>,
    v: Mat,
    v_inv: Mat,
}

fn split<D: TimeDomain>(sys: &StateSpace<D>) -> Result<Split<D>> {
    let n = sys.nx();
    let domain = sys.domain();
    let mut schur = real_schur(sys.a())?;
    let tol = 100.0 * f64::EPSILON * sys.a().norm().max(1.0);
    let boundary: Vec<Complex64> = schur
        .eigenvalues()
        .into_iter()
        .filter(|&l| domain.stability_distance(l).abs() <= tol)
        .collect();
    if !boundary.is_empty() {
        let list: Vec<String> = boundary
            .iter()
            .map(|l| format!("{:e}{:+e}j", l.re, l.im))
            .collect();
        let rule = match domain.sample_time() {
            None => "|Re λ|",
            Some(_) => "||λ| − 1|",
        };
        return Err(LtiError::InvalidArgument(format!(
            "stabsep: eigenvalue(s) of A on the stability boundary ({rule} ≤ {tol:e}) belong to neither part: {}",
            list.join(", ")
        )));
    }
    let ns = schur.reorder(|l| domain.stability_distance(l) < 0.0)?;
    let nu = n - ns;
    let (t, z) = schur.into_parts();
    let t11 = t.view((0, 0), (ns, ns)).clone_owned();
    let t12 = t.view((0, ns), (ns, nu)).clone_owned();
    let t22 = t.view((ns, ns), (nu, nu)).clone_owned();
    // T₁₁ X + X (−T₂₂) = −T₁₂.
    let x = crate::equations::sylvester(&t11, &(-&t22), &(-t12))?.x;
    let zb = z.transpose() * sys.b();
    let cz = sys.c() * &z;
    let (b1, b2) = (zb.rows(0, ns), zb.rows(ns, nu));
    let (c1, c2) = (cz.columns(0, ns), cz.columns(ns, nu));
    let stable = StateSpace::new(t11, b1 - &x * b2, c1.clone_owned(), sys.d().clone(), domain)?;
    let unstable = StateSpace::new(
        t22,
        b2.clone_owned(),
        c1 * &x + c2,
        Mat::zeros(sys.ny(), sys.nu()),
        domain,
    )?;
    // V = Z W, V⁻¹ = W⁻¹ Zᵀ with W = [[I, X], [0, I]], W⁻¹ = [[I, −X], [0, I]].
    let mut w = Mat::identity(n, n);
    w.view_mut((0, ns), (ns, nu)).copy_from(&x);
    let mut w_inv = Mat::identity(n, n);
    w_inv.view_mut((0, ns), (ns, nu)).copy_from(&(-&x));
    Ok(Split {
        stable,
        unstable,
        v: &z * w,
        v_inv: w_inv * z.transpose(),
    })
}

/// Additive stable/unstable decomposition `G = G_s + G_u` (MATLAB `stabsep`; module
/// documentation): `G_s` has the poles with `Re λ < 0` (`|λ| < 1` in discrete time) and the
/// feedthrough `D`, `G_u` the others and a zero feedthrough. Either part may have no states.
///
/// # Errors
/// [`LtiError::InvalidArgument`] naming the eigenvalues of `A` on the stability boundary
/// (within `100·ε·max(1, ‖A‖_F)`); [`LtiError::Inaccurate`] if the Schur reordering rejects a
/// swap; [`LtiError::NoConvergence`] from the Schur form; the Sylvester solver's errors.
pub fn stabsep<D: TimeDomain>(sys: &StateSpace<D>) -> Result<(StateSpace<D>, StateSpace<D>)> {
    let s = split(sys)?;
    Ok((s.stable, s.unstable))
}

/// Square-root factors `R` (`W_c = R Rᵀ`) and `L` (`W_o = L Lᵀ`) and the SVD of `Lᵀ R`.
struct SquareRoot {
    r: Mat,
    l: Mat,
    u: Mat,
    sigma: Vec<f64>,
    v: Mat,
}

fn factor(w: &Mat) -> Mat {
    let e = crate::linalg::symmetrize(w).symmetric_eigen();
    let mut f = e.eigenvectors.clone();
    for (j, &l) in e.eigenvalues.iter().enumerate() {
        f.column_mut(j).scale_mut(l.max(0.0).sqrt());
    }
    f
}

fn square_root<D: TimeDomain>(sys: &StateSpace<D>) -> Result<SquareRoot> {
    let wc = gramian(sys, GramianKind::Controllability)?.x;
    let wo = gramian(sys, GramianKind::Observability)?.x;
    let r = factor(&wc);
    let l = factor(&wo);
    let s = crate::linalg::svd::svd(&(l.transpose() * &r));
    Ok(SquareRoot {
        r,
        l,
        u: s.u,
        sigma: s.singular_values.iter().copied().collect(),
        v: s.v_t.transpose(),
    })
}

/// Hankel singular values `σ₁ ≥ … ≥ σₙ` (module documentation). For a system with unstable
/// poles, those of the stable part of [`stabsep`] preceded by `f64::INFINITY` for each unstable
/// state (MATLAB's convention), `n` entries in all.
///
/// # Errors
/// [`LtiError::InvalidArgument`] for an eigenvalue on the stability boundary; the errors of
/// [`stabsep`] and of the Lyapunov solver.
pub fn hsvd<D: TimeDomain>(sys: &StateSpace<D>) -> Result<Vec<f64>> {
    if sys.nx() == 0 {
        return Ok(Vec::new());
    }
    if sys.is_stable()? {
        return Ok(square_root(sys)?.sigma);
    }
    let s = split(sys)?;
    let mut hsv = vec![f64::INFINITY; s.unstable.nx()];
    if s.stable.nx() > 0 {
        hsv.extend(square_root(&s.stable)?.sigma);
    }
    Ok(hsv)
}

/// A balanced realisation: `x = T x_b`, both Gramians of `system` equal `diag(hsv)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Balanced<D: TimeDomain> {
    /// The balanced system (or the reduced one, for [`balred`]).
    pub system: StateSpace<D>,
    /// Hankel singular values of the original system, descending.
    pub hsv: Vec<f64>,
    /// `T` (`n × r`): `x ≈ T x_b`.
    pub t: Mat,
    /// `T⁻¹` (`r × n`): `x_b = T⁻¹ x` (a left inverse, `T⁻¹ T = I`).
    pub t_inv: Mat,
    /// `2 Σ_{i>r} σᵢ`, the bound on `‖G − G_r‖∞` (zero for [`balreal`]).
    pub error_bound: f64,
}

/// Hankel singular values at or below `100·n·ε·σ₁` count as zero.
fn zero_hsv_threshold(sigma: &[f64]) -> f64 {
    100.0 * sigma.len() as f64 * f64::EPSILON * sigma.first().copied().unwrap_or(0.0)
}

fn project(sr: &SquareRoot, k: usize) -> (Mat, Mat) {
    let mut t = &sr.r * sr.v.columns(0, k);
    let mut ti = sr.u.columns(0, k).transpose() * sr.l.transpose();
    for i in 0..k {
        let s = sr.sigma[i].sqrt();
        t.column_mut(i).unscale_mut(s);
        ti.row_mut(i).unscale_mut(s);
    }
    (t, ti)
}

fn transform<D: TimeDomain>(sys: &StateSpace<D>, t: &Mat, ti: &Mat) -> Result<StateSpace<D>> {
    StateSpace::new(
        ti * sys.a() * t,
        ti * sys.b(),
        sys.c() * t,
        sys.d().clone(),
        sys.domain(),
    )
}

/// The balanced realisation of a minimal system (square-root method, module documentation).
/// With unstable poles (MATLAB's behaviour): the stable part of [`stabsep`] balanced and the
/// unstable part added back, state `[x_u; x_b]`, `hsv` starting with one `f64::INFINITY` per
/// unstable state.
///
/// # Errors
/// [`LtiError::InvalidArgument`] for an eigenvalue on the stability boundary;
/// [`LtiError::Singular`] if a Hankel singular value (of the stable part) is zero to working
/// precision (a non-minimal realisation: call [`minreal`] or [`balred`]); the errors of
/// [`stabsep`].
pub fn balreal<D: TimeDomain>(sys: &StateSpace<D>) -> Result<Balanced<D>> {
    if sys.nx() > 0 && !sys.is_stable()? {
        let s = split(sys)?;
        let bal = if s.stable.nx() > 0 {
            balreal(&s.stable)?
        } else {
            identity_balanced(&s.stable)
        };
        return add_unstable(&s, bal);
    }
    let sr = square_root(sys)?;
    let thr = zero_hsv_threshold(&sr.sigma);
    if let Some(&smin) = sr.sigma.last()
        && smin <= thr
    {
        return Err(LtiError::Singular {
            what: "balreal: the Hankel singular values (the realisation is not minimal)".into(),
            rcond: smin / sr.sigma[0],
        });
    }
    let n = sys.nx();
    let (t, ti) = project(&sr, n);
    Ok(Balanced {
        system: transform(sys, &t, &ti)?,
        hsv: sr.sigma,
        t,
        t_inv: ti,
        error_bound: 0.0,
    })
}

/// How [`balred`] treats the discarded balanced states.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BalredMethod {
    /// Truncation: drop them (exact at infinite frequency for `D`, MATLAB `'Truncate'`).
    Truncate,
    /// Singular perturbation: keep the DC gain (MATLAB `'MatchDC'`).
    MatchDc,
}

/// Balanced reduction to `order` states (module documentation). With unstable poles
/// (MATLAB's behaviour): every unstable mode is kept, the stable part of [`stabsep`] is
/// reduced to `order − n_u` states and the unstable part added back (state `[x_u; x_r]`,
/// `hsv` starting with one `f64::INFINITY` per unstable state, `error_bound` from the stable
/// part's discarded values).
///
/// # Errors
/// [`LtiError::InvalidArgument`] if `order > nx`, if `order` is below the number of unstable
/// states, or for an eigenvalue on the stability boundary; [`LtiError::Singular`] if
/// `σ_order` is zero to working precision (ask for fewer states) or, for
/// [`BalredMethod::MatchDc`], if `A₂₂` (`A₂₂ − I`) is singular; the errors of [`stabsep`].
pub fn balred<D: TimeDomain>(
    sys: &StateSpace<D>,
    order: usize,
    method: BalredMethod,
) -> Result<Balanced<D>> {
    let n = sys.nx();
    if order > n {
        return Err(LtiError::InvalidArgument(format!(
            "balred: order {order} exceeds the system's {n} states"
        )));
    }
    if n > 0 && !sys.is_stable()? {
        let s = split(sys)?;
        let nu = s.unstable.nx();
        if order < nu {
            return Err(LtiError::InvalidArgument(format!(
                "balred: order {order} is below the system's {nu} unstable states (they are all kept)"
            )));
        }
        let bal = if s.stable.nx() > 0 {
            balred(&s.stable, order - nu, method)?
        } else {
            identity_balanced(&s.stable)
        };
        return add_unstable(&s, bal);
    }
    let sr = square_root(sys)?;
    let thr = zero_hsv_threshold(&sr.sigma);
    let nonzero = sr.sigma.iter().take_while(|&&s| s > thr).count();
    if order > nonzero {
        return Err(LtiError::Singular {
            what: format!(
                "balred: Hankel singular value {order} (only {nonzero} are non-zero; reduce to at most {nonzero} states)"
            ),
            rcond: sr.sigma[order - 1] / sr.sigma[0],
        });
    }
    let error_bound = 2.0 * sr.sigma[order..].iter().sum::<f64>();
    let k = match method {
        BalredMethod::Truncate => order,
        BalredMethod::MatchDc => nonzero,
    };
    let (t, ti) = project(&sr, k);
    let bal = transform(sys, &t, &ti)?;
    let system = match method {
        BalredMethod::Truncate => bal,
        BalredMethod::MatchDc => singular_perturbation(&bal, order)?,
    };
    Ok(Balanced {
        system,
        hsv: sr.sigma,
        t: t.columns(0, order).clone_owned(),
        t_inv: ti.rows(0, order).clone_owned(),
        error_bound,
    })
}

/// The balanced data of a system without states (its only realisation).
fn identity_balanced<D: TimeDomain>(stable: &StateSpace<D>) -> Balanced<D> {
    Balanced {
        system: stable.clone(),
        hsv: Vec::new(),
        t: Mat::zeros(0, 0),
        t_inv: Mat::zeros(0, 0),
        error_bound: 0.0,
    }
}

/// Puts the unstable part of `s` back in front of the balanced (or reduced) stable part `bal`:
/// state `[x_u; x_b]`, `T = [V_u, V_s T_b]`, `T⁻¹ = [V⁻¹_u; T_b⁻¹ V⁻¹_s]`, `hsv` with one
/// infinity per unstable state first.
fn add_unstable<D: TimeDomain>(s: &Split<D>, bal: Balanced<D>) -> Result<Balanced<D>> {
    let (nu, ns) = (s.unstable.nx(), s.stable.nx());
    let r = bal.system.nx();
    let k = nu + r;
    let u = &s.unstable;
    let g = &bal.system;
    let mut a = Mat::zeros(k, k);
    a.view_mut((0, 0), (nu, nu)).copy_from(u.a());
    a.view_mut((nu, nu), (r, r)).copy_from(g.a());
    let mut b = Mat::zeros(k, u.nu());
    b.rows_mut(0, nu).copy_from(u.b());
    b.rows_mut(nu, r).copy_from(g.b());
    let mut c = Mat::zeros(u.ny(), k);
    c.columns_mut(0, nu).copy_from(u.c());
    c.columns_mut(nu, r).copy_from(g.c());
    let n = s.v.nrows();
    let mut t = Mat::zeros(n, k);
    t.columns_mut(0, nu).copy_from(&s.v.columns(ns, nu));
    let mut t_inv = Mat::zeros(k, n);
    t_inv.rows_mut(0, nu).copy_from(&s.v_inv.rows(ns, nu));
    if r > 0 {
        t.columns_mut(nu, r)
            .copy_from(&(s.v.columns(0, ns) * &bal.t));
        t_inv
            .rows_mut(nu, r)
            .copy_from(&(&bal.t_inv * s.v_inv.rows(0, ns)));
    }
    let mut hsv = vec![f64::INFINITY; nu];
    hsv.extend(bal.hsv);
    Ok(Balanced {
        system: StateSpace::new(a, b, c, g.d().clone(), g.domain())?,
        hsv,
        t,
        t_inv,
        error_bound: bal.error_bound,
    })
}

/// Residualises the states `r..` of `sys` (module documentation, matched DC).
fn singular_perturbation<D: TimeDomain>(sys: &StateSpace<D>, r: usize) -> Result<StateSpace<D>> {
    let k = sys.nx();
    let q = k - r;
    if q == 0 {
        return Ok(sys.clone());
    }
    let (a, b, c) = (sys.a(), sys.b(), sys.c());
    let a11 = a.view((0, 0), (r, r));
    let a12 = a.view((0, r), (r, q));
    let a21 = a.view((r, 0), (q, r));
    let mut a22 = a.view((r, r), (q, q)).clone_owned();
    let discrete = sys.domain().sample_time().is_some();
    if discrete {
        a22 -= Mat::identity(q, q);
    }
    let b1 = b.rows(0, r);
    let b2 = b.rows(r, q);
    let c1 = c.columns(0, r);
    let c2 = c.columns(r, q);
    let lu = a22.clone().lu();
    let sing = || LtiError::Singular {
        what: "balred MatchDc: A₂₂ of the discarded balanced states (A₂₂ − I in discrete time)"
            .into(),
        rcond: 0.0,
    };
    let x_a = lu.solve(&a21.clone_owned()).ok_or_else(sing)?;
    let x_b = lu.solve(&b2.clone_owned()).ok_or_else(sing)?;
    StateSpace::new(
        a11 - a12 * &x_a,
        b1 - a12 * &x_b,
        c1 - c2 * &x_a,
        sys.d() - c2 * &x_b,
        sys.domain(),
    )
}
