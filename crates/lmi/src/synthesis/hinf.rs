//! H∞ synthesis by LMIs: output feedback by the projected LMIs of Gahinet & Apkarian ("A
//! linear matrix inequality approach to H∞ control", Int. J. Robust Nonlinear Control 4,
//! 1994) and state feedback by the bounded real lemma with `X = P⁻¹`, on the
//! [`StandardPlant`] of `pendulab-lti` (any `D₁₁`; `D₂₂ ≠ 0` by loop shifting).
//!
//! # Output feedback
//!
//! With `N_R` a basis of the null space of `[B₂ᵀ, D₁₂ᵀ]` and `N_S` one of `[C₂, D₂₁]`, a
//! controller of order `n` with `‖T_zw‖∞ < γ` exists iff some symmetric `R`, `S` satisfy
//!
//! ```text
//! [N_R 0]ᵀ [ AR + RAᵀ   RC₁ᵀ   B₁  ] [N_R 0]
//! [ 0  I]  [ C₁R        −γI    D₁₁ ] [ 0  I]  ≺ 0,
//!          [ B₁ᵀ        D₁₁ᵀ   −γI ]
//!
//! [N_S 0]ᵀ [ AᵀS + SA   SB₁    C₁ᵀ ] [N_S 0]
//! [ 0  I]  [ B₁ᵀS       −γI    D₁₁ᵀ] [ 0  I]  ≺ 0,        [ R  I ]
//!          [ C₁         D₁₁    −γI ]                       [ I  S ] ⪰ 0
//! ```
//!
//! (the first block of `N_R` multiplies the rows of `x` and `z`, that of `N_S` the rows of
//! `x` and `w`). [`hinf_lmi`] minimises `γ` subject to these LMIs (strict ones as `⪯ −εI`),
//! giving `γ_opt`; re-solves them as a feasibility problem at `γ = (1 + relax)·γ_opt` with
//! `[R I; I S] ⪰ εI`, so that `I − RS` is invertible; factors `I − RS = MNᵀ` (SVD) and forms
//! the closed-loop Lyapunov matrix `X_cl = [[I, S], [0, Nᵀ]]·[[R, I], [Mᵀ, 0]]⁻¹` (so that
//! `X_cl = [[S, N], [Nᵀ, ·]]`, `X_cl⁻¹ = [[R, M], [Mᵀ, ·]]`); and finally finds the
//! controller `Ω = [[A_k, B_k], [C_k, D_k]]` from the bounded real lemma of the closed loop
//! at that fixed `X_cl`, which is affine in `Ω`:
//!
//! ```text
//! [ He(X_cl A_cl)   X_cl B_cl   C_clᵀ ]
//! [ B_clᵀ X_cl      −γI         D_clᵀ ]  ≺ 0,
//! [ C_cl            D_cl        −γI   ]
//!
//! A_cl = [[A + B₂D_kC₂, B₂C_k], [B_kC₂, A_k]],  B_cl = [[B₁ + B₂D_kD₂₁], [B_kD₂₁]],
//! C_cl = [C₁ + D₁₂D_kC₂, D₁₂C_k],               D_cl = D₁₁ + D₁₂D_kD₂₁
//! ```
//!
//! (Gahinet & Apkarian's reconstruction, solved as an LMI feasibility problem). The controller
//! is connected as `u = K y` ([`StandardPlant::close_loop`]); its closed loop is checked to be
//! stable with `‖T_zw‖∞ < γ` by `pendulab_lti::norms::hinf_norm`
//! ([`HinfLmiController::closed_loop_norm`]), else `design` is None with
//! [`Status::NumericalTrouble`] naming the norm.
//!
//! # Conditioning
//!
//! The LMIs are solved in coordinates of the plant chosen for the solver (the `coordinates`
//! module: a state transform and scalings of `u`, `y` and of the level, under which the
//! problem is invariant; results are mapped back). The γ minimisation starts in the
//! equilibrated coordinates (Osborne's balancing of `[A B; C 0]`, unit `[B₂; D₁₂]` columns
//! and `[C₂ D₂₁]` rows) and is repeated, up to three solves, in the coordinates that balance
//! the previous solve's `(R, S)` (`T⁻¹RT⁻ᵀ = TᵀST` diagonal) with `γ` scaled to 1, as long as
//! the level decreases; the smallest accepted level is `γ_opt`. Near `γ_opt`, `R` tends to a
//! singular and `S` to an unbounded matrix along one direction (the optimum set by `X∞ = γR⁻¹`
//! growing without bound, as on mixed-sensitivity plants with slow weights); in the balanced
//! coordinates of a nearly optimal pair that direction is of unit scale, so each solve gets
//! a few decades closer. On the Slycot fixture (`crates/lti/tests/data/hinf_reference.json`)
//! this takes the dense method from numerical trouble or 2e-3 above SB10AD's optimum on the
//! two mixed-sensitivity plants to within 1e-7, and from 8e-6 to 6e-8 on the random plant.
//! The controller is computed in the coordinates of the best solve, or, if that fails, in the
//! equilibrated ones.
//!
//! # State feedback
//!
//! [`hinf_state_feedback_lmi`]: minimise `γ` over `X = Xᵀ`, `L` with `X ≻ 0` and
//!
//! ```text
//! [ He(AX + B₂L)    B₁     (C₁X + D₁₂L)ᵀ ]
//! [ B₁ᵀ             −γI    D₁₁ᵀ          ]  ≺ 0,      K = −L X⁻¹ (u = −K x),
//! [ C₁X + D₁₂L      D₁₁    −γI           ]
//! ```
//!
//! the bounded real lemma of `(A − B₂K, B₁, C₁ − D₁₂K, D₁₁)` with `P = γX⁻¹`.

use super::coordinates::{Coordinates, Pass, refine};
use crate::error::{LmiError, Result};
use crate::expr::Expr;
use crate::linalg::sym;
use crate::problem::Problem;
use crate::solution::{Solution, SolveOptions, Status};
use pendulab_lti::design::StandardPlant;
use pendulab_lti::norms::hinf_norm;
use pendulab_lti::{Continuous, Mat, StateSpace};

/// Options of [`hinf_lmi`] and [`hinf_state_feedback_lmi`].
#[derive(Debug, Clone, PartialEq)]
pub struct HinfLmiOptions {
    /// Margin `ε` of the strict inequalities (`≺ 0` imposed as `⪯ −εI`). Default 1e-8.
    pub margin: f64,
    /// The controller is computed at `γ = (1 + relax)·γ_opt`. Default 0.01.
    pub relax: f64,
    /// Solver options (backend, tolerances) of every solve.
    pub solve: SolveOptions,
}

impl Default for HinfLmiOptions {
    fn default() -> Self {
        Self {
            margin: 1e-8,
            relax: 0.01,
            solve: SolveOptions::default(),
        }
    }
}

/// An output-feedback controller from [`hinf_lmi`] with its certificate.
#[derive(Debug, Clone, PartialEq)]
pub struct HinfLmiController {
    /// The level `γ` the controller was computed at (`(1 + relax)·γ_opt` for [`hinf_lmi`]):
    /// `‖T_zw‖∞ < γ`.
    pub gamma: f64,
    /// The controller `K` (`n` states, `nmeas` inputs, `ncon` outputs), `u = K y`.
    pub controller: StateSpace<Continuous>,
    /// `‖T_zw‖∞` of the closed loop (`pendulab_lti::norms::hinf_norm`, relative tolerance
    /// 1e-10), checked to be below `gamma` with the closed loop stable.
    pub closed_loop_norm: f64,
    /// The closed loop `F_l(P, K)`.
    pub closed_loop: StateSpace<Continuous>,
    /// `R` of the feasibility solve.
    pub r: Mat,
    /// `S` of the feasibility solve.
    pub s: Mat,
    /// The closed-loop Lyapunov matrix `X_cl ≻ 0` (`2n × 2n`).
    pub lyapunov: Mat,
}

/// Result of [`hinf_lmi`].
#[derive(Debug, Clone)]
pub struct HinfLmi {
    /// Status of the last solve attempted.
    pub status: Status,
    /// The minimised level `γ_opt` (None unless the minimisation solved and passed its
    /// rechecks).
    pub gamma_opt: Option<f64>,
    /// The controller (None if a step failed; `status` tells which).
    pub design: Option<HinfLmiController>,
    /// The γ minimisation that gave `γ_opt` (else the last one tried; None for
    /// [`hinf_lmi_at`]). Its variables are those of the scaled problem (module
    /// documentation, "Conditioning"): its objective is the scaled level.
    pub optimum: Option<Solution>,
    /// The feasibility re-solve for `R`, `S` at `(1 + relax)·γ_opt`.
    pub feasibility: Option<Solution>,
    /// The reconstruction solve for `Ω`.
    pub reconstruction: Option<Solution>,
}

/// A state-feedback H∞ gain from [`hinf_state_feedback_lmi`].
#[derive(Debug, Clone)]
pub struct HinfStateFeedbackLmi {
    /// Status of the γ minimisation.
    pub status: Status,
    /// The minimised `γ` (None unless solved with all rechecks passing).
    pub gamma: Option<f64>,
    /// `K` of `u = −K x` at the optimum (None unless solved).
    pub gain: Option<Mat>,
    /// `X ≻ 0` at the optimum.
    pub x: Option<Mat>,
    /// The solve.
    pub solution: Solution,
}

/// An orthonormal basis (columns) of the null space of `m` (`p × q`): the eigenvectors of
/// the projector `I − V_rV_rᵀ` onto the complement of the row space, `V_r` the right singular
/// vectors of the singular values above `q·ε·‖m‖₂`.
pub(crate) fn null_space(m: &Mat) -> Mat {
    let q = m.ncols();
    if m.nrows() == 0 {
        return Mat::identity(q, q);
    }
    let svd = pendulab_lti::linalg::svd::svd(m);
    let smax = svd.singular_values.iter().copied().fold(0.0, f64::max);
    let tol = q.max(m.nrows()) as f64 * f64::EPSILON * smax;
    let r = svd.singular_values.iter().filter(|s| **s > tol).count();
    let vr = svd.v_t.rows(0, r).clone_owned();
    let proj = crate::linalg::sym(&(Mat::identity(q, q) - vr.transpose() * &vr));
    let e = proj.symmetric_eigen();
    let keep: Vec<usize> = (0..q).filter(|&i| e.eigenvalues[i] > 0.5).collect();
    let mut basis = Mat::zeros(q, keep.len());
    for (c, &i) in keep.iter().enumerate() {
        basis.set_column(c, &e.eigenvectors.column(i));
    }
    basis
}

/// `diag(N, I_k)` as a constant.
fn outer(n: &Mat, k: usize) -> Mat {
    let (r, c) = n.shape();
    let mut w = Mat::zeros(r + k, c + k);
    w.view_mut((0, 0), (r, c)).copy_from(n);
    w.view_mut((r, c), (k, k)).copy_from(&Mat::identity(k, k));
    w
}

fn check_options(options: &HinfLmiOptions) -> Result<()> {
    if !(options.margin.is_finite() && options.margin > 0.0) {
        return Err(LmiError::InvalidArgument {
            what: "margin".into(),
            reason: format!("must be finite and > 0, got {}", options.margin),
        });
    }
    if !(options.relax.is_finite() && options.relax > 0.0) {
        return Err(LmiError::InvalidArgument {
            what: "relax".into(),
            reason: format!("must be finite and > 0, got {}", options.relax),
        });
    }
    Ok(())
}

fn check_plant(plant: &StandardPlant, output_feedback: bool) -> Result<()> {
    if plant.nx() == 0 || plant.ncon() == 0 || (output_feedback && plant.nmeas() == 0) {
        return Err(LmiError::InvalidArgument {
            what: "plant".into(),
            reason: format!(
                "needs n ≥ 1 states, ncon ≥ 1 controls{}, got n = {}, ncon = {}, nmeas = {}",
                if output_feedback {
                    " and nmeas ≥ 1 measurements"
                } else {
                    ""
                },
                plant.nx(),
                plant.ncon(),
                plant.nmeas()
            ),
        });
    }
    Ok(())
}

/// The two projected LMIs and the coupling LMI at the level `gamma` (an expression: a
/// variable or a constant), added to `p`; returns `(R, S)`.
fn projected_lmis(
    p: &mut Problem,
    plant: &StandardPlant,
    gamma: &Expr,
    margin: f64,
    coupling_margin: Option<f64>,
) -> Result<(Expr, Expr)> {
    let n = plant.nx();
    let (a, b1, b2, c1, c2) = (plant.a(), plant.b1(), plant.b2(), plant.c1(), plant.c2());
    let (d11, d12, d21) = (plant.d11(), plant.d12(), plant.d21());
    let (nw, nz) = (plant.nw(), plant.nz());
    let r = p.symmetric("R", n);
    let s = p.symmetric("S", n);
    let gi = |k: usize| gamma * &Expr::identity(k);
    // Null spaces: [B₂ᵀ D₁₂ᵀ] (n + nz columns) and [C₂ D₂₁] (n + nw columns).
    let mut top = Mat::zeros(plant.ncon(), n + nz);
    top.view_mut((0, 0), (plant.ncon(), n))
        .copy_from(&b2.transpose());
    top.view_mut((0, n), (plant.ncon(), nz))
        .copy_from(&d12.transpose());
    let mut bottom = Mat::zeros(plant.nmeas(), n + nw);
    bottom.view_mut((0, 0), (plant.nmeas(), n)).copy_from(&c2);
    bottom.view_mut((0, n), (plant.nmeas(), nw)).copy_from(&d21);
    let wr = outer(&null_space(&top), nw);
    let ws = outer(&null_space(&bottom), nz);
    let (b1e, d11e, c1e) = (
        Expr::constant(&b1),
        Expr::constant(&d11),
        Expr::constant(&c1),
    );
    let rc = &r * &c1.transpose();
    let psi_r = Expr::block(&[
        &[&(a * &r).he(), &rc, &b1e],
        &[&rc.t(), &-gi(nz), &d11e],
        &[&b1e.t(), &d11e.t(), &-gi(nw)],
    ]);
    let sb = &s * &b1;
    let psi_s = Expr::block(&[
        &[&(&s * a).he(), &sb, &c1e.t()],
        &[&sb.t(), &-gi(nw), &d11e.t()],
        &[&c1e, &d11e, &-gi(nz)],
    ]);
    let lr = &wr.transpose() * &psi_r * &wr;
    let ls = &ws.transpose() * &psi_s * &ws;
    p.negative_definite("projected LMI in R", &lr, margin)?;
    p.negative_definite("projected LMI in S", &ls, margin)?;
    let id = Expr::identity(n);
    let coupling = Expr::block(&[&[&r, &id], &[&id, &s]]);
    match coupling_margin {
        Some(eps) => p.positive_definite("[R I; I S] ≻ 0", &coupling, eps)?,
        None => p.positive_semidefinite("[R I; I S] ⪰ 0", &coupling)?,
    };
    Ok((r, s))
}

/// Output-feedback H∞ synthesis by LMIs (module documentation): `γ_opt` by up to three γ
/// minimisations in successively balanced coordinates ("Conditioning") and a full-order
/// controller at `(1 + relax)·γ_opt` (as [`hinf_lmi_at`]). A plant with `D₂₂ ≠ 0` is designed
/// with `D₂₂ = 0` and the controller shifted ([`StandardPlant::shift_d22`]).
///
/// A solve that fails (not solved, or a recheck failing) ends the design: `status` and the
/// solutions tell where, `design` is None.
///
/// # Errors
/// [`LmiError::InvalidArgument`] for a plant without states, controls or measurements or
/// invalid options; modelling and solver errors; [`LmiError::Lti`] from the loop shift and the
/// closed loop.
#[doc(alias = "hinfsyn")]
pub fn hinf_lmi(plant: &StandardPlant, options: &HinfLmiOptions) -> Result<HinfLmi> {
    check_options(options)?;
    check_plant(plant, true)?;
    let design_plant = plant.without_d22()?;
    let start = Coordinates::equilibrated(&design_plant);
    let refined = refine(start.clone(), true, |coords| {
        let mut p = Problem::new();
        let gamma = p.scalar("gamma");
        let (r, s) = projected_lmis(
            &mut p,
            &coords.plant(&design_plant)?,
            &gamma,
            options.margin,
            None,
        )?;
        p.minimize(&gamma)?;
        let sol = p.solve(&options.solve)?;
        let pair = match (sol.value(&r), sol.value(&s)) {
            (Ok(r), Ok(s)) => Some((r, s)),
            _ => None,
        };
        Ok(Pass {
            objective: sol.objective.map(|g| coords.gamma(g)),
            accepted: sol.all_checks_pass(),
            pair,
            data: sol,
        })
    })?;
    let (g_opt, coords, optimum) = match refined {
        Ok(best) => best,
        Err(optimum) => {
            return Ok(HinfLmi {
                status: optimum.status.clone(),
                gamma_opt: None,
                design: None,
                optimum: Some(optimum),
                feasibility: None,
                reconstruction: None,
            });
        }
    };
    let level_gamma = (1.0 + options.relax) * g_opt;
    let mut out = level(plant, &coords, level_gamma, options)?;
    if out.design.is_none() && coords != start {
        // The coordinates of the best solve can be too close to the degenerate optimum for
        // the feasibility solve or the reconstruction at the relaxed level: retry in the
        // equilibrated ones.
        let retry = level(plant, &start, level_gamma, options)?;
        if retry.design.is_some() {
            out = retry;
        }
    }
    out.gamma_opt = Some(g_opt);
    out.optimum = Some(optimum);
    Ok(out)
}

/// The output-feedback controller at a given level `γ` by LMIs: the projected LMIs in `R`,
/// `S` as a feasibility problem (with `[R I; I S] ⪰ εI`), then the reconstruction (module
/// documentation), in the equilibrated coordinates ("Conditioning"). Below the optimal
/// level the feasibility solve ends [`Status::Infeasible`] (with its certificate) and
/// `design` is None. `gamma_opt` and `optimum` of the result are None.
///
/// # Errors
/// As [`hinf_lmi`]; [`LmiError::InvalidArgument`] for a `γ` that is not finite and positive.
pub fn hinf_lmi_at(plant: &StandardPlant, gamma: f64, options: &HinfLmiOptions) -> Result<HinfLmi> {
    check_options(options)?;
    check_plant(plant, true)?;
    if !(gamma.is_finite() && gamma > 0.0) {
        return Err(LmiError::InvalidArgument {
            what: "gamma".into(),
            reason: format!("must be finite and > 0, got {gamma}"),
        });
    }
    let design_plant = plant.without_d22()?;
    level(
        plant,
        &Coordinates::equilibrated(&design_plant),
        gamma,
        options,
    )
}

/// The feasibility solve at `gamma` (a level of `plant`) and the reconstruction, both in
/// `coords`; the design mapped back and checked ([`hinf_lmi_at`]).
fn level(
    plant: &StandardPlant,
    coords: &Coordinates,
    gamma: f64,
    options: &HinfLmiOptions,
) -> Result<HinfLmi> {
    let design_plant = coords.plant(&plant.without_d22()?)?;
    let scaled_gamma = coords.scaled_gamma(gamma);
    let mut q = Problem::new();
    let (r, s) = projected_lmis(
        &mut q,
        &design_plant,
        &Expr::scalar(scaled_gamma),
        options.margin,
        Some(options.margin),
    )?;
    let feas = q.solve(&options.solve)?;
    let mut out = HinfLmi {
        status: feas.status.clone(),
        gamma_opt: None,
        design: None,
        optimum: None,
        feasibility: None,
        reconstruction: None,
    };
    let ok = feas.all_checks_pass();
    let (rv, sv) = if ok {
        (sym(&feas.value(&r)?), sym(&feas.value(&s)?))
    } else {
        (Mat::zeros(0, 0), Mat::zeros(0, 0))
    };
    out.feasibility = Some(feas);
    if !ok {
        return Ok(out);
    }
    let xcl = closed_loop_lyapunov(&rv, &sv)?;
    let (recon, k0) = reconstruct(&design_plant, &xcl, scaled_gamma, options)?;
    out.status = recon.status.clone();
    out.reconstruction = Some(recon);
    let Some(k0) = k0 else {
        return Ok(out);
    };
    let controller = plant.shift_d22(coords.controller(&k0)?)?;
    let closed_loop = plant.close_loop(&controller)?;
    // The certificate holds up to the solver's tolerances: check the closed loop itself.
    let closed_loop_norm = if closed_loop.is_stable()? {
        hinf_norm(&closed_loop, 1e-10)?.value
    } else {
        f64::INFINITY
    };
    if closed_loop_norm.is_nan() || closed_loop_norm >= gamma {
        out.status = Status::NumericalTrouble {
            reason: format!(
                "the reconstructed controller's closed loop has ‖T_zw‖∞ = {closed_loop_norm:e} \
                 (∞: unstable), not below γ = {gamma:e}"
            ),
        };
        return Ok(out);
    }
    out.design = Some(HinfLmiController {
        gamma,
        closed_loop_norm,
        controller,
        closed_loop,
        r: coords.r(&rv),
        s: coords.s(&sv),
        lyapunov: coords.lyapunov(&xcl),
    });
    Ok(out)
}

/// `X_cl = [[I, S], [0, Nᵀ]]·[[R, I], [Mᵀ, 0]]⁻¹` with `I − RS = MNᵀ` split evenly by the SVD
/// `I − RS = UΣVᵀ`, `M = UΣ^½`, `N = VΣ^½`.
fn closed_loop_lyapunov(r: &Mat, s: &Mat) -> Result<Mat> {
    let n = r.nrows();
    let e = Mat::identity(n, n) - r * s;
    let svd = pendulab_lti::linalg::svd::svd(&e);
    let root = Mat::from_diagonal(&svd.singular_values.map(f64::sqrt));
    let m = &svd.u * &root;
    let nn = svd.v_t.transpose() * &root;
    let mut pi1 = Mat::zeros(2 * n, 2 * n);
    pi1.view_mut((0, 0), (n, n)).copy_from(r);
    pi1.view_mut((0, n), (n, n)).copy_from(&Mat::identity(n, n));
    pi1.view_mut((n, 0), (n, n)).copy_from(&m.transpose());
    let mut pi2 = Mat::zeros(2 * n, 2 * n);
    pi2.view_mut((0, 0), (n, n)).copy_from(&Mat::identity(n, n));
    pi2.view_mut((0, n), (n, n)).copy_from(s);
    pi2.view_mut((n, n), (n, n)).copy_from(&nn.transpose());
    // X_cl Π₁ = Π₂  ⇔  Π₁ᵀ X_clᵀ = Π₂ᵀ.
    let xt = pi1
        .transpose()
        .lu()
        .solve(&pi2.transpose())
        .ok_or(LmiError::InvalidArgument {
            what: "R, S".into(),
            reason: "I − RS is singular: no full-order controller from this certificate".into(),
        })?;
    Ok(crate::linalg::sym(&xt.transpose()))
}

/// The controller `Ω` from the closed-loop bounded real lemma at the fixed `X_cl`.
fn reconstruct(
    plant: &StandardPlant,
    xcl: &Mat,
    gamma: f64,
    options: &HinfLmiOptions,
) -> Result<(Solution, Option<StateSpace<Continuous>>)> {
    let n = plant.nx();
    let (nu, ny, nw, nz) = (plant.ncon(), plant.nmeas(), plant.nw(), plant.nz());
    let (a, b1, b2, c1, c2) = (plant.a(), plant.b1(), plant.b2(), plant.c1(), plant.c2());
    let (d11, d12, d21) = (plant.d11(), plant.d12(), plant.d21());
    let mut p = Problem::new();
    let ak = p.matrix("Ak", n, n);
    let bk = p.matrix("Bk", n, ny);
    let ck = p.matrix("Ck", nu, n);
    let dk = p.matrix("Dk", nu, ny);
    let acl = Expr::block(&[
        &[&(a + &(&b2 * &dk * &c2)), &(&b2 * &ck)],
        &[&(&bk * &c2), &ak],
    ]);
    let bcl = Expr::block(&[&[&(&b1 + &(&b2 * &dk * &d21))], &[&(&bk * &d21)]]);
    let ccl = Expr::block(&[&[&(&c1 + &(&d12 * &dk * &c2)), &(&d12 * &ck)]]);
    let dcl = &d11 + &(&d12 * &dk * &d21);
    let xa = xcl * &acl;
    let xb = xcl * &bcl;
    let lmi = Expr::block(&[
        &[&xa.he(), &xb, &ccl.t()],
        &[&xb.t(), &Expr::identity(nw).scale(-gamma), &dcl.t()],
        &[&ccl, &dcl, &Expr::identity(nz).scale(-gamma)],
    ]);
    p.negative_definite("closed-loop bounded real lemma", &lmi, options.margin)?;
    let sol = p.solve(&options.solve)?;
    if !sol.all_checks_pass() {
        return Ok((sol, None));
    }
    let k = StateSpace::continuous(
        sol.value(&ak)?,
        sol.value(&bk)?,
        sol.value(&ck)?,
        sol.value(&dk)?,
    )?;
    Ok((sol, Some(k)))
}

/// State-feedback H∞ synthesis by the bounded real lemma (module documentation): the minimal
/// `γ` and the gain `K = −LX⁻¹` there.
///
/// The gain is returned only if its own closed loop is stable with `‖T_zw‖∞ ≤ (1 + 10⁻⁴)·γ`
/// (lti's `hinf_norm`); otherwise `gamma` and `gain` are `None` and the status is
/// [`Status::NumericalTrouble`] with the reason (an ill-conditioned `X` at the optimum).
///
/// # Errors
/// [`LmiError::InvalidArgument`] for a plant without states or controls or invalid options;
/// modelling and solver errors.
pub fn hinf_state_feedback_lmi(
    plant: &StandardPlant,
    options: &HinfLmiOptions,
) -> Result<HinfStateFeedbackLmi> {
    check_options(options)?;
    check_plant(plant, false)?;
    let n = plant.nx();
    let (nw, nz) = (plant.nw(), plant.nz());
    let (a, b1, b2, c1) = (plant.a(), plant.b1(), plant.b2(), plant.c1());
    let (d11, d12) = (plant.d11(), plant.d12());
    let mut p = Problem::new();
    let x = p.symmetric("X", n);
    let l = p.matrix("L", plant.ncon(), n);
    let gamma = p.scalar("gamma");
    p.positive_definite("X ≻ 0", &x, options.margin)?;
    let y = a * &x + &b2 * &l;
    let cz = &c1 * &x + &d12 * &l;
    let (b1e, d11e) = (Expr::constant(&b1), Expr::constant(&d11));
    let lmi = Expr::block(&[
        &[&y.he(), &b1e, &cz.t()],
        &[&b1e.t(), &-(&gamma * &Expr::identity(nw)), &d11e.t()],
        &[&cz, &d11e, &-(&gamma * &Expr::identity(nz))],
    ]);
    p.negative_definite("bounded real lemma", &lmi, options.margin)?;
    p.minimize(&gamma)?;
    let solution = p.solve(&options.solve)?;
    let mut out = HinfStateFeedbackLmi {
        status: solution.status.clone(),
        gamma: None,
        gain: None,
        x: None,
        solution,
    };
    if out.solution.all_checks_pass() {
        let (gain, xv) = state_feedback_gain(&out.solution, &x, &l)?;
        let level = out.solution.objective.unwrap_or(f64::NAN);
        // The certificate holds up to the solver's tolerances; an ill-conditioned X can still
        // give a gain whose loop is unstable: check the loop itself.
        if let Some(reason) = state_feedback_loop_fails(plant, &gain, |cl| {
            let norm = hinf_norm(cl, 1e-10)?.value;
            Ok((norm <= level * (1.0 + STATE_FEEDBACK_NORM_SLACK))
                .then_some(())
                .ok_or(format!("‖T_zw‖∞ = {norm:e} above γ = {level:e}")))
        })? {
            out.status = Status::NumericalTrouble { reason };
            return Ok(out);
        }
        out.gain = Some(gain);
        out.gamma = out.solution.objective;
        out.x = Some(xv);
    }
    Ok(out)
}

/// Relative slack on the level a state-feedback gain's closed loop must meet: the strict LMIs
/// hold up to the solver's tolerances.
pub(super) const STATE_FEEDBACK_NORM_SLACK: f64 = 1e-4;

/// `None` if the loop `(A − B₂K, B₁, C₁ − D₁₂K, D₁₁)` of gain `K` (`u = −Kx`) is stable and
/// passes `norm_check`; otherwise the reason (an unstable pole, or `norm_check`'s message).
pub(super) fn state_feedback_loop_fails(
    plant: &StandardPlant,
    k: &Mat,
    norm_check: impl Fn(&StateSpace<Continuous>) -> Result<std::result::Result<(), String>>,
) -> Result<Option<String>> {
    let cl = StateSpace::continuous(
        plant.a() - plant.b2() * k,
        plant.b1(),
        plant.c1() - plant.d12() * k,
        plant.d11(),
    )?;
    if !cl.is_stable()? {
        return Ok(Some(format!(
            "the gain from the solve does not stabilise the plant (largest real part of a \
             closed-loop pole {:e}): X is too ill-conditioned for K = −LX⁻¹",
            cl.poles()?
                .iter()
                .map(|p| p.re)
                .fold(f64::NEG_INFINITY, f64::max)
        )));
    }
    Ok(norm_check(&cl)?.err())
}

/// The state-feedback gain `K = −L X⁻¹` (`u = −K x`) and the symmetrised `X` of a solved
/// problem in the variables `X`, `L` (the H∞ and H2 state-feedback LMIs).
///
/// `Kᵀ = −X⁻¹ Lᵀ` by an LU solve: `X ⪰ εI` by its constraint, and LU also serves the `X` of the
/// scale of ε that a zero optimum produces.
///
/// # Errors
/// [`LmiError::InvalidArgument`] when the returned `X` is singular; the solution's own errors
/// when `X` or `L` is not one of its variables.
pub(super) fn state_feedback_gain(solution: &Solution, x: &Expr, l: &Expr) -> Result<(Mat, Mat)> {
    let xv = crate::linalg::sym(&solution.value(x)?);
    let lv = solution.value(l)?;
    let kt = xv
        .clone()
        .lu()
        .solve(&lv.transpose())
        .ok_or(LmiError::InvalidArgument {
            what: "X".into(),
            reason: "returned X is singular".into(),
        })?;
    Ok((-kt.transpose(), xv))
}
