//! The interior-point iteration: the predictor–corrector loop with its step lengths, scaling
//! updates, stopping tests and the fallback to the best iterate (module docs of [`super`]).
//!
//! Neighbours: `embedding.rs` (iterate, residuals, stopping measures), `kkt.rs` (the Newton
//! systems), `scaling.rs` (the cones' scaling), `kernels.rs` (dense kernels).

use super::embedding::{Direction, Iterate, Measures, Residuals, outcome, residuals, stop_short};
use super::kernels::{dot, norm};
use super::kkt::{Kkt, KktSolution, Structure};
use super::scaling::Cone;
use super::{EXPON, MIN_STEP, NO_PROGRESS, Outcome, PROGRESS, STALL, STEP};
use crate::clock::Instant;
use crate::conic::{ConicData, RawStatus, Settings};

/// Solves `data` by the dense method (module docs).
pub(crate) fn solve(data: &ConicData, settings: &Settings) -> Outcome {
    let start = Instant::now();
    let (st, mut cones) = Structure::new(data);
    let (m, n) = (st.m, st.n);
    let c = &data.q;
    let b = &data.b;
    let mut it = Iterate {
        x: vec![0.0; n],
        zf: vec![0.0; m],
        s: vec![0.0; m],
        tau: 1.0,
        kappa: 1.0,
    };
    let mut best: Option<(Iterate, Measures)> = None;
    if st.degree == 0 {
        return stop_short(RawStatus::NumericalError, &it, &best, settings, 0);
    }
    let resx0 = norm(c).max(1.0);
    let resrow0 = norm(b).max(1.0);
    if let Some(certificate) = dropped_equality_certificate(&st, b, settings, resrow0) {
        return certificate;
    }

    let neg_c: Vec<f64> = c.iter().map(|v| -v).collect();
    if !starting_point(&st, &mut cones, &mut it, b, &neg_c) {
        return stop_short(RawStatus::NumericalError, &it, &best, settings, 0);
    }

    let mut stalls = 0;
    let mut since_best = 0;
    let mut best_progress = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let mut iteration = 0u32;
    let mut scratch = vec![0.0; m];
    loop {
        // Residuals and stopping tests.
        let res = residuals(&st, data, &it);
        let cx = dot(c, &it.x);
        let bz = dot(b, &it.zf);
        let sz: f64 = cones
            .iter()
            .map(|cone| {
                let r = cone.rows();
                dot(&it.s[r.clone()], &it.zf[r])
            })
            .sum();
        let mu = (sz + it.tau * it.kappa) / (st.degree as f64 + 1.0);
        let pcost = cx / it.tau;
        let dcost = -bz / it.tau;
        let rel_base = pcost.abs().min(dcost.abs()).max(1.0);
        let gap_measure = |g: f64| (g / settings.gap_abs).min(g / rel_base / settings.gap_rel);
        let meas = Measures {
            pres: norm(&res.row) / it.tau / resrow0,
            dres: norm(&res.x) / it.tau / resx0,
            pcost,
            gap_ratio: gap_measure((sz / (it.tau * it.tau)).abs())
                .max(gap_measure((pcost - dcost).abs())),
        };
        if !(meas.pres.is_finite() && meas.dres.is_finite() && mu.is_finite()) {
            return stop_short(RawStatus::NumericalError, &it, &best, settings, iteration);
        }
        if meas.ratio(settings) <= 1.0 {
            return outcome(RawStatus::Solved, &it, &meas, iteration);
        }
        if best
            .as_ref()
            .is_none_or(|(_, bm)| meas.ratio(settings) < bm.ratio(settings))
        {
            best = Some((it.clone(), meas));
        }
        // Infeasibility certificates: the ray's residual relative to its separation, as a
        // ratio to the tolerance (≤ 1: certified).
        let infeasibility_ratio = match certificates(
            &res,
            &it,
            (c, b),
            (cx, bz),
            (resx0, resrow0),
            &meas,
            settings,
            iteration,
        ) {
            Ok(ratio) => ratio,
            Err(certificate) => return certificate,
        };
        // Progress towards either kind of answer, or along the central path; the method
        // stops without it, or once complementarity is exhausted to rounding (`μ ≤ 0`: no
        // step can improve on the best iterate).
        let (optimality, infeasibility) = (meas.ratio(settings), infeasibility_ratio);
        if optimality < PROGRESS * best_progress.0
            || infeasibility < PROGRESS * best_progress.1
            || mu < PROGRESS * best_progress.2
        {
            best_progress = (
                best_progress.0.min(optimality),
                best_progress.1.min(infeasibility),
                best_progress.2.min(mu),
            );
            since_best = 0;
        } else {
            since_best += 1;
        }
        if mu <= 0.0 || since_best >= NO_PROGRESS {
            return stop_short(
                RawStatus::InsufficientProgress,
                &it,
                &best,
                settings,
                iteration,
            );
        }
        if iteration >= settings.max_iterations {
            return stop_short(RawStatus::MaxIterations, &it, &best, settings, iteration);
        }
        if start.elapsed().as_secs_f64() > settings.time_limit {
            return stop_short(RawStatus::MaxTime, &it, &best, settings, iteration);
        }
        iteration += 1;

        // The Newton systems of this scaling.
        let Some(kkt) = Kkt::factor(&st, &cones) else {
            return stop_short(RawStatus::NumericalError, &it, &best, settings, iteration);
        };
        // The scaled right-hand sides b̂ = (f, W⁻ᵀh) and r̂ = (r_y, W⁻ᵀr_z).
        let (mut bhat, mut rhat) = (b.clone(), res.row.clone());
        for cone in &cones {
            let r = cone.rows();
            cone.w_inv_t(&b[r.clone()], &mut bhat[r.clone()]);
            cone.w_inv_t(&res.row[r.clone()], &mut rhat[r]);
        }
        // fᵀy + hᵀz = b̂ᵀ(y, Wz).
        let bz_of = |u: &KktSolution| dot(&bhat, &u.yz);
        // K (x₁, y₁, z₁) = (−c, f, h).
        let u1 = kkt.solve(&st, &neg_c, &bhat);
        let denom = dot(c, &u1.x) + bz_of(&u1) - it.kappa / it.tau;
        let newton = |beta: f64, ds: &[f64], dk: f64| -> Direction {
            // ξ = λ ◇⁻¹ d_s; right-hand side (−β r_x, −β r_y, −β W⁻ᵀr_z − ξ) (scaled rows).
            let mut xi = ds.to_vec();
            for cone in &cones {
                cone.lambda_inv_prod(&mut xi[cone.rows()]);
            }
            let bx: Vec<f64> = res.x.iter().map(|v| -beta * v).collect();
            let t: Vec<f64> = rhat.iter().zip(&xi).map(|(r, x)| -beta * r - x).collect();
            let u2 = kkt.solve(&st, &bx, &t);
            let dtau = (-beta * res.tau - dk / it.tau - (dot(c, &u2.x) + bz_of(&u2))) / denom;
            let comb = |a: &[f64], b: &[f64]| -> Vec<f64> {
                a.iter().zip(b).map(|(p, q)| p + dtau * q).collect()
            };
            let (x, yz) = (comb(&u2.x, &u1.x), comb(&u2.yz, &u1.yz));
            let mut s_hat = vec![0.0; m];
            for cone in &cones {
                for k in cone.rows() {
                    s_hat[k] = xi[k] - yz[k];
                }
            }
            Direction {
                x,
                yz,
                s_hat,
                tau: dtau,
                kappa: (dk - it.kappa * dtau) / it.tau,
            }
        };
        let max_step = |d: &Direction| -> f64 {
            let mut a = f64::INFINITY;
            for cone in &cones {
                let r = cone.rows();
                a = a
                    .min(cone.max_step(&d.s_hat[r.clone()]))
                    .min(cone.max_step(&d.yz[r]));
            }
            if d.tau < 0.0 {
                a = a.min(-it.tau / d.tau);
            }
            if d.kappa < 0.0 {
                a = a.min(-it.kappa / d.kappa);
            }
            a
        };

        // Affine (predictor) direction: d_s = −λ∘λ, d_κ = −τκ.
        let mut ds = vec![0.0; m];
        for cone in &cones {
            let r = cone.rows();
            cone.lambda_sq(&mut ds[r.clone()]);
            ds[r].iter_mut().for_each(|v| *v = -*v);
        }
        let aff = newton(1.0, &ds, -it.tau * it.kappa);
        let alpha_aff = max_step(&aff).min(1.0);
        if !alpha_aff.is_finite() {
            return stop_short(RawStatus::NumericalError, &it, &best, settings, iteration);
        }
        let sigma = (1.0 - alpha_aff).max(0.0).powi(EXPON);

        // Combined direction: d_s = −λ∘λ + σμe − Δŝ_aff ∘ Δẑ_aff, d_κ = −τκ + σμ − Δτ Δκ.
        for cone in &cones {
            let r = cone.rows();
            cone.jordan(
                &aff.s_hat[r.clone()],
                &aff.yz[r.clone()],
                &mut scratch[r.clone()],
            );
            for k in r.clone() {
                ds[k] -= scratch[k];
            }
            cone.add_identity(sigma * mu, &mut ds[r]);
        }
        let dk = -it.tau * it.kappa + sigma * mu - aff.tau * aff.kappa;
        let dir = newton(1.0 - sigma, &ds, dk);
        let alpha = (STEP * max_step(&dir)).min(1.0);
        if !alpha.is_finite() || alpha <= 0.0 {
            return stop_short(RawStatus::NumericalError, &it, &best, settings, iteration);
        }
        stalls = if alpha < MIN_STEP { stalls + 1 } else { 0 };
        if stalls >= STALL {
            return stop_short(
                RawStatus::InsufficientProgress,
                &it,
                &best,
                settings,
                iteration,
            );
        }

        // Step: x and y additively, the cones' s and z from the updated scaling.
        if !take_step(&st, &mut cones, &mut it, &dir, alpha) {
            return stop_short(RawStatus::NumericalError, &it, &best, settings, iteration);
        }
    }
}

/// A Farkas certificate from an equality `0 = f_k` that no variable enters, when `|f_k|`
/// exceeds the feasibility tolerance (module docs).
fn dropped_equality_certificate(
    st: &Structure,
    b: &[f64],
    settings: &Settings,
    resrow0: f64,
) -> Option<Outcome> {
    let (m, n) = (st.m, st.n);
    // An equality `0 = f_k` with |f_k| beyond the feasibility tolerance: y = −sign(f_k) e_k
    // (z = 0) is a Farkas certificate, Eᵀy + Gᵀz = 0 and fᵀy = −|f_k| < 0.
    for &r in &st.dropped_eq {
        if b[r].abs() > settings.feasibility * resrow0 {
            let mut z = vec![0.0; m];
            z[r] = -b[r].signum() / b[r].abs();
            return Some(Outcome {
                status: RawStatus::Infeasible,
                x: vec![0.0; n],
                z,
                objective: f64::NAN,
                iterations: 0,
                primal_residual: f64::NAN,
                dual_residual: f64::NAN,
            });
        }
    }
    None
}

/// The starting point and its scaling: the primal least-squares and dual least-norm points of
/// `W = I`, each shifted into the cones' interior (module docs); false when a factorisation,
/// a shift or the scaling fails.
fn starting_point(
    st: &Structure,
    cones: &mut [Cone],
    it: &mut Iterate,
    b: &[f64],
    neg_c: &[f64],
) -> bool {
    let (m, n) = (st.m, st.n);
    // Starting point (Vandenberghe 2010, §7.4): with W = I, the primal least-squares point
    // and the dual least-norm point, each shifted into the cones' interior.
    let Some(kkt) = Kkt::factor(st, cones) else {
        return false;
    };
    // With W = I the scaled right-hand side is the plain one and W z = z.
    let primal = kkt.solve(st, &vec![0.0; n], b);
    let dual = kkt.solve(st, neg_c, &vec![0.0; m]);
    it.x = primal.x;
    it.zf = dual.yz;
    for cone in cones.iter() {
        for r in cone.rows() {
            it.s[r] = -primal.yz[r];
        }
    }
    // Only the cone rows of s and z are shifted; y stays.
    let mut finite = true;
    for v in [&mut it.s, &mut it.zf] {
        let t = cones
            .iter()
            .map(|cone| cone.violation(&v[cone.rows()]))
            .fold(f64::NEG_INFINITY, f64::max);
        let size = cones
            .iter()
            .map(|cone| norm(&v[cone.rows()]))
            .fold(0.0, f64::max)
            .max(1.0);
        finite &= t.is_finite();
        if t >= -1e-8 * size {
            for cone in cones.iter() {
                let r = cone.rows();
                cone.add_identity(1.0 + t, &mut v[r]);
            }
        }
    }
    if !finite {
        return false;
    }
    // The Nesterov–Todd scaling of the starting point (from W = I).
    for cone in cones.iter_mut() {
        let r = cone.rows();
        if !cone.update(&it.s[r.clone()], &it.zf[r]) {
            return false;
        }
    }
    true
}

/// The infeasibility certificates at an iterate: `Err` with the certificate when the ray's
/// residual relative to its separation is within the tolerance, else `Ok` with the smaller of
/// the two ratios to the tolerance (infinite when neither ray separates).
#[allow(clippy::too_many_arguments)]
fn certificates(
    res: &Residuals,
    it: &Iterate,
    (c, b): (&[f64], &[f64]),
    (cx, bz): (f64, f64),
    (resx0, resrow0): (f64, f64),
    meas: &Measures,
    settings: &Settings,
    iteration: u32,
) -> Result<f64, Outcome> {
    let mut infeasibility_ratio = f64::INFINITY;
    if bz < 0.0 {
        // ‖Eᵀy + Gᵀz‖ = ‖r_x − cτ‖.
        let hx: Vec<f64> = res.x.iter().zip(c).map(|(r, ci)| r - ci * it.tau).collect();
        let ratio = norm(&hx) / resx0 / (-bz) / settings.infeasibility;
        if ratio <= 1.0 {
            let inv = -1.0 / bz;
            return Err(Outcome {
                status: RawStatus::Infeasible,
                x: it.x.clone(),
                z: it.zf.iter().map(|v| v * inv).collect(),
                objective: f64::NAN,
                iterations: iteration,
                primal_residual: meas.pres,
                dual_residual: meas.dres,
            });
        }
        infeasibility_ratio = ratio;
    }
    if cx < 0.0 {
        // ‖(Ex, Gx + s)‖ = ‖r_row + bτ‖.
        let hr: Vec<f64> = res
            .row
            .iter()
            .zip(b)
            .map(|(r, bi)| r + bi * it.tau)
            .collect();
        let ratio = norm(&hr) / resrow0 / (-cx) / settings.infeasibility;
        if ratio <= 1.0 {
            let inv = -1.0 / cx;
            return Err(Outcome {
                status: RawStatus::Unbounded,
                x: it.x.iter().map(|v| v * inv).collect(),
                z: it.zf.clone(),
                objective: f64::NAN,
                iterations: iteration,
                primal_residual: meas.pres,
                dual_residual: meas.dres,
            });
        }
        infeasibility_ratio = infeasibility_ratio.min(ratio);
    }
    Ok(infeasibility_ratio)
}

/// Takes the step `alpha` along `dir`: `x` and `y` additively, the scaling updated from the
/// scaled iterates and the cones' `s`, `z` taken from it (module docs); false when a cone's
/// scaling update fails (the cones before it are updated).
fn take_step(
    st: &Structure,
    cones: &mut [Cone],
    it: &mut Iterate,
    dir: &Direction,
    alpha: f64,
) -> bool {
    for (v, d) in it.x.iter_mut().zip(&dir.x) {
        *v += alpha * d;
    }
    for &r in &st.eq_rows {
        it.zf[r] += alpha * dir.yz[r];
    }
    it.tau += alpha * dir.tau;
    it.kappa += alpha * dir.kappa;
    for cone in cones.iter_mut() {
        let r = cone.rows();
        let lambda = cone.lambda_vec();
        let step =
            |d: &[f64]| -> Vec<f64> { lambda.iter().zip(d).map(|(l, x)| l + alpha * x).collect() };
        let (st_, zt) = (step(&dir.s_hat[r.clone()]), step(&dir.yz[r.clone()]));
        if !cone.update(&st_, &zt) {
            return false;
        }
        // s = Wᵀλ, z = W⁻¹λ: the cone iterates from the updated scaling itself, so that
        // they lie in the cone and agree with the scaling to rounding (as CVXOPT's
        // conelp does); Δs of the direction is not needed beyond the scaled step.
        let lam = cone.lambda_vec();
        cone.w_t(&lam, &mut it.s[r.clone()]);
        cone.w_inv(&lam, &mut it.zf[r]);
    }
    true
}
