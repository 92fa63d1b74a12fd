//! Gain-scheduled LQ state feedback for a linear parameter-varying plant with a bounded rate
//! of variation, by parameter-dependent Lyapunov matrices and SOS multipliers.

use super::state_feedback::LqWeights;
use crate::error::{LmiError, Result};
use crate::expr::Expr;
use crate::linalg::{check_finite, check_shape, psd_sqrt};
use crate::problem::Problem;
use crate::solution::{Solution, SolveOptions, Status};
use pendulab_lti::Mat;

/// `ẋ = A(ρ) x + B(ρ) u` with `A(ρ) = A₀ + ρ A₁`, `B(ρ) = B₀ + ρ B₁`.
#[derive(Debug, Clone, PartialEq)]
pub struct LpvPlant {
    /// `A₀` (`n × n`).
    pub a0: Mat,
    /// `A₁` (`n × n`).
    pub a1: Mat,
    /// `B₀` (`n × m`).
    pub b0: Mat,
    /// `B₁` (`n × m`).
    pub b1: Mat,
}

/// Specification of [`gain_scheduled_lq`].
#[derive(Debug, Clone, PartialEq)]
pub struct GainScheduleSpec {
    /// Range `[ρ_lo, ρ_hi]` of the scheduling parameter along trajectories.
    pub rho_range: (f64, f64),
    /// Range of the initial value `ρ₀` over which the cost bound `γ` must hold.
    pub rho0_range: (f64, f64),
    /// Bound `ν` on the rate: `|ρ̇| ≤ ν`.
    pub rho_dot_bound: f64,
    /// LQ weights `(Q, R)`.
    pub lq: LqWeights,
    /// Margin `ε` of the strict inequalities (the book: 1e-6).
    pub margin: f64,
    /// The second solve requires `γ ≤ (1 + relax) γ*` (the book: 0.06).
    pub gamma_relax: f64,
    /// Solve with normalised parameters `ρ = ρ_lo + (ρ_hi − ρ_lo) s`, `s ∈ [0, 1]`, and
    /// `ρ̇ = ν w`, `w ∈ [−1, 1]` (the feasible set and `γ*` are unchanged; see
    /// [`gain_scheduled_lq`]). Recommended: without it double-precision interior-point
    /// solvers stop about 1 % above `γ*` on the textbook's problem.
    pub balance: bool,
}

/// The designed schedule `X(ρ)`, `L(ρ)`, `K(ρ) = −L(ρ) X(ρ)⁻¹` (`u = −K(ρ) x`).
#[derive(Debug, Clone, PartialEq)]
pub struct ScheduledGain {
    /// `[X₀, X₁, X₂]`: `X(ρ) = X₀ + ρ X₁ + ρ² X₂` in the plant's coordinates.
    pub x_coefficients: [Mat; 3],
    /// `[L₀, L₁, L₂]`: `L(ρ) = L₀ + ρ L₁ + ρ² L₂`.
    pub l_coefficients: [Mat; 3],
    /// γ achieved by this schedule: `X(ρ₀)⁻¹ ⪯ γ I` on the `ρ₀` range, so the cost from
    /// `x₀` is at most `γ ‖x₀‖²`.
    pub gamma: f64,
    /// The design range of ρ (the guarantees hold for ρ inside it).
    pub rho_range: (f64, f64),
}

impl ScheduledGain {
    fn poly(c: &[Mat; 3], rho: f64) -> Mat {
        &c[0] + &c[1] * rho + &c[2] * (rho * rho)
    }

    /// `X(ρ)`.
    pub fn x(&self, rho: f64) -> Mat {
        Self::poly(&self.x_coefficients, rho)
    }

    /// `L(ρ)`.
    pub fn l(&self, rho: f64) -> Mat {
        Self::poly(&self.l_coefficients, rho)
    }

    /// The scheduled gain `K(ρ) = −L(ρ) X(ρ)⁻¹` (`u = −K(ρ) x`). Defined for any ρ where
    /// `X(ρ) ≻ 0`; stability and the cost bound are guaranteed inside `rho_range` (with
    /// `|ρ̇|` within the design bound).
    ///
    /// # Errors
    /// [`LmiError::InvalidArgument`] for a non-finite ρ or if `X(ρ)` is not positive definite
    /// there.
    pub fn gain(&self, rho: f64) -> Result<Mat> {
        if !rho.is_finite() {
            return Err(LmiError::InvalidArgument {
                what: "rho".into(),
                reason: format!("must be finite, got {rho}"),
            });
        }
        let x = crate::linalg::sym(&self.x(rho));
        let chol = x.cholesky().ok_or(LmiError::InvalidArgument {
            what: "rho".into(),
            reason: format!("X(ρ) is not positive definite at ρ = {rho}"),
        })?;
        Ok(-chol.solve(&self.l(rho).transpose()).transpose())
    }

    /// The schedule as a closure `ρ ↦ K(ρ)` (for a simulator or the rig loop).
    pub fn as_fn(&self) -> impl Fn(f64) -> Result<Mat> + '_ {
        move |rho| self.gain(rho)
    }
}

/// Result of [`gain_scheduled_lq`].
#[derive(Debug, Clone)]
pub struct GainSchedule {
    /// Status of the final (feasibility) solve, or of the γ minimisation if it failed.
    pub status: Status,
    /// The minimised cost bound `γ*` (None if the minimisation did not solve).
    pub gamma_star: Option<f64>,
    /// The schedule from the feasibility re-solve (`γ ≤ (1 + relax) γ*`), when it solved
    /// and every constraint and SOS decomposition passed its recheck: the design to use.
    pub schedule: Option<ScheduledGain>,
    /// The schedule at the γ minimum itself (solved, possibly to reduced accuracy; not
    /// rechecked). On the boundary of the feasible set: `K(ρ_hi)` is well determined there,
    /// `K(ρ_lo)` is not (solutions within 0.5 % of `γ*` differ there by a factor of ten).
    pub optimum: Option<ScheduledGain>,
    /// The γ minimisation.
    pub optimization: Solution,
    /// The feasibility re-solve.
    pub refined: Option<Solution>,
}

fn validate(plant: &LpvPlant, spec: &GainScheduleSpec) -> Result<(usize, usize)> {
    let n = plant.a0.nrows();
    let m = plant.b0.ncols();
    if n == 0 || m == 0 {
        return Err(LmiError::InvalidArgument {
            what: "plant".into(),
            reason: format!("needs n ≥ 1 states and m ≥ 1 inputs, got n = {n}, m = {m}"),
        });
    }
    for (what, mat, r, c) in [
        ("A0", &plant.a0, n, n),
        ("A1", &plant.a1, n, n),
        ("B0", &plant.b0, n, m),
        ("B1", &plant.b1, n, m),
        ("Q", &spec.lq.q, n, n),
        ("R", &spec.lq.r, m, m),
    ] {
        check_shape(what, mat, r, c)?;
        check_finite(what, mat)?;
    }
    let range_ok = |(lo, hi): (f64, f64)| lo.is_finite() && hi.is_finite() && lo < hi;
    if !range_ok(spec.rho_range) {
        return Err(LmiError::InvalidArgument {
            what: "rho_range".into(),
            reason: format!("needs finite lo < hi, got {:?}", spec.rho_range),
        });
    }
    if !range_ok(spec.rho0_range) {
        return Err(LmiError::InvalidArgument {
            what: "rho0_range".into(),
            reason: format!("needs finite lo < hi, got {:?}", spec.rho0_range),
        });
    }
    for (what, v, allow_zero) in [
        ("rho_dot_bound", spec.rho_dot_bound, true),
        ("margin", spec.margin, false),
        ("gamma_relax", spec.gamma_relax, true),
    ] {
        if !(v.is_finite() && (v > 0.0 || (allow_zero && v == 0.0))) {
            return Err(LmiError::InvalidArgument {
                what: what.into(),
                reason: format!("must be finite and positive, got {v}"),
            });
        }
    }
    Ok((n, m))
}

/// Gain-scheduled LQ servo/regulator design (the textbook's problem (1.62), p. 164).
///
/// **Plant and law.** `ẋ = A(ρ)x + B(ρ)u`, `A(ρ) = A₀ + ρA₁`, `B(ρ) = B₀ + ρB₁`,
/// `ρ ∈ [ρ_lo, ρ_hi]`, `|ρ̇| ≤ ν`; `u = −K(ρ)x` with `K(ρ) = −L(ρ)X(ρ)⁻¹`,
/// `X(ρ) = X₀ + ρX₁ + ρ²X₂`, `L(ρ) = L₀ + ρL₁ + ρ²L₂`, `Ẋ = ρ̇(X₁ + 2ρX₂)`.
///
/// **Conditions** (`g₁(ρ) = (ρ − ρ_lo)(ρ_hi − ρ)`, `g₂(ρ₀)` likewise on the `ρ₀` range,
/// `g_a = ν − ρ̇`, `g_b = ρ̇ + ν`; every `S = (I ⊗ z)ᵀ R (I ⊗ z)` an SOS multiplier with
/// `R ⪰ 0`, `z₁ = [1, ρ]`, `z₂ = [1, ρ₀]`, `z₃ = [1, ρ, ρ², ρ³]`; "SOS" = a sum of squares
/// in the parameters, so the matrix is `⪰ 0` on the box wherever the `g ≥ 0`):
///
/// ```text
/// M₁(ρ)    = X(ρ) − g₁ S₁₁ − εI                                   is SOS   (X ≻ 0)
/// M₂(ρ₀)   = [ X(ρ₀) − g₂ S₂₂ − εI   I  ]                          is SOS   (X(ρ₀)⁻¹ ⪯ γI)
///            [ I                      γI ]
/// M₃(ρ,ρ̇)  = [ Ẋ − He(AX + BL) − g₁S₃₁ − g_a S_a − g_b S_b − εI   X C_qᵀ   Lᵀ R^½ ]
///            [ C_q X                                               I        0      ]  is SOS
///            [ R^½ L                                               0        I      ]
/// ```
///
/// (`Q = C_qᵀ C_q`). `M₃ ⪰ 0` says that `V = xᵀ X(ρ)⁻¹ x` satisfies
/// `V̇ ≤ −(xᵀQx + uᵀRu)`, so `J ≤ x₀ᵀ X(ρ₀)⁻¹ x₀ ≤ γ ‖x₀‖²`. The design minimises `γ`
/// (giving `γ*`), then re-solves as a feasibility problem with `γ ≤ (1 + relax) γ*`, whose
/// interior solution is returned (the textbook's 236 is this cap over its solver's optimum).
///
/// **Numerics.** With `spec.balance` the problem is solved in the normalised parameters
/// `ρ = ρ_lo + (ρ_hi − ρ_lo)s`, `ρ₀ = ρ_lo + (ρ_hi − ρ_lo)s₀`, `ρ̇ = ν w`
/// (`s ∈ [0, 1]`, `w ∈ [−1, 1]`). An affine change of a single parameter maps polynomials of
/// each degree, the multiplier families `(I ⊗ z)ᵀR(I ⊗ z)` (z spanning all monomials up to a
/// degree) and the Gram parametrisations one-to-one, and the `g`'s only change by positive
/// factors, so the feasible set and `γ*` are exactly those of the original problem; the
/// coefficients come back in the `ρ` basis. On the textbook's servo this moves Clarabel's
/// optimum from 223.97 (raw `ρ`, 0.9 % high) to 222.05 (the optimum is ≈ 222). A diagonal
/// *state* scaling making `X` unit-diagonal was also tried: it is an equivalent problem too,
/// but made the solver fail (numerical error), so it is not used.
///
/// # Errors
/// Shape, finiteness and range errors of the data; solver setup errors. Infeasibility and
/// solver trouble are reported in `status`.
pub fn gain_scheduled_lq(
    plant: &LpvPlant,
    spec: &GainScheduleSpec,
    options: &SolveOptions,
) -> Result<GainSchedule> {
    let (n, m) = validate(plant, spec)?;
    let (rlo, rhi) = spec.rho_range;
    let (r0lo, r0hi) = spec.rho0_range;

    // Parameter normalisation: ρ = off + scale·s (also for ρ₀, so that X(ρ₀) = X̂(s₀)),
    // ρ̇ = ν·w, w ∈ [−1, 1] (then ṡ = (ν / scale)·w).
    let (scale_s, off_s) = if spec.balance {
        (rhi - rlo, rlo)
    } else {
        (1.0, 0.0)
    };
    let to_s = |r: f64| (r - off_s) / scale_s;
    // In the solved coordinates: A(s) = Â₀ + s Â₁, B(s) = B̂₀ + s B̂₁.
    let a_hat0 = &plant.a0 + &plant.a1 * off_s;
    let a_hat1 = &plant.a1 * scale_s;
    let b_hat0 = &plant.b0 + &plant.b1 * off_s;
    let b_hat1 = &plant.b1 * scale_s;
    let cq = super::state_feedback::weight_factor("Q", &spec.lq.q)?;
    let rh = psd_sqrt("R", &spec.lq.r)?;
    let (s_lo, s_hi) = (to_s(rlo), to_s(rhi));
    let (s0_lo, s0_hi) = (to_s(r0lo), to_s(r0hi));
    let rate_scale = spec.rho_dot_bound / scale_s;

    let mut p = Problem::new();
    let s = p.parameter("s");
    let s0 = p.parameter("s0");
    let w = p.parameter("w");
    let xs: Vec<Expr> = (0..3).map(|k| p.symmetric(&format!("X{k}"), n)).collect();
    let ls: Vec<Expr> = (0..3).map(|k| p.matrix(&format!("L{k}"), m, n)).collect();
    let gamma = p.scalar("gamma");
    let poly = |c: &[Expr], v: &Expr| &c[0] + v * &c[1] + (v * v) * &c[2];
    let x_s = poly(&xs, &s);
    let l_s = poly(&ls, &s);
    let x_s0 = poly(&xs, &s0);
    let one = Expr::scalar(1.0);
    let g1 = (&s - s_lo) * (Expr::scalar(s_hi) - &s);
    let g2 = (&s0 - s0_lo) * (Expr::scalar(s0_hi) - &s0);
    let ga = &one - &w;
    let gb = &one + &w;
    let z1 = Expr::monomials(&s, 1);
    let z2 = Expr::monomials(&s0, 1);
    let z3 = Expr::monomials(&s, 3);
    let eps = Expr::identity(n).scale(spec.margin);

    // M1: X(s) ≻ 0 on the range.
    let s11 = p.sos_multiplier("S11", n, &z1)?;
    let m1 = &x_s - &g1 * &s11.s - &eps;
    p.sos("M1: X(ρ) ≻ 0", &m1)?;

    // M2: [[X(s0) − g2 S22 − εI, I], [I, γI]].
    let s22 = p.sos_multiplier("S22", n, &z2)?;
    let m211 = &x_s0 - &g2 * &s22.s - &eps;
    let id = Expr::identity(n);
    let m2 = Expr::block(&[&[&m211, &id], &[&id, &(&gamma * &id)]]);
    p.sos("M2: X(ρ0)⁻¹ ⪯ γI", &m2)?;

    // M3: the decrease condition.
    let a_s = Expr::constant(&a_hat0) + &s * &Expr::constant(&a_hat1);
    let b_s = Expr::constant(&b_hat0) + &s * &Expr::constant(&b_hat1);
    let xdot = (&w * rate_scale) * (&xs[1] + (&s * 2.0) * &xs[2]);
    let s31 = p.sos_multiplier("S31", n, &z3)?;
    let sa = p.sos_multiplier("Sa33", n, &z3)?;
    let sb = p.sos_multiplier("Sb33", n, &z3)?;
    let y = &a_s * &x_s + &b_s * &l_s;
    let m311 = &xdot - y.he() - &g1 * &s31.s - &ga * &sa.s - &gb * &sb.s - &eps;
    let rq = cq.nrows();
    let xc = &x_s * &Expr::constant(&cq.transpose());
    let lr = l_s.t() * &rh;
    let m3 = Expr::block(&[
        &[&m311, &xc, &lr],
        &[&xc.t(), &Expr::identity(rq), &Expr::zeros(rq, m)],
        &[&lr.t(), &Expr::zeros(m, rq), &Expr::identity(m)],
    ]);
    p.sos("M3: decrease", &m3)?;
    p.minimize(&gamma)?;
    let optimization = p.solve(options)?;

    let gamma_star = optimization
        .status
        .is_solved()
        .then_some(optimization.objective)
        .flatten();
    let mut refined = None;
    if let Some(gs) = gamma_star {
        let mut q = p.clone();
        q.clear_objective();
        q.less_equal(
            "γ ≤ (1 + relax) γ*",
            &gamma,
            &Expr::scalar((1.0 + spec.gamma_relax) * gs),
        )?;
        refined = Some(q.solve(options)?);
    }
    let final_sol = refined.as_ref().unwrap_or(&optimization);
    let status = final_sol.status.clone();
    // Back to the ρ basis: X(ρ) = X̂(s) with s = (ρ − off)/scale.
    let extract = |sol: &Solution| -> Result<ScheduledGain> {
        let xh: Vec<Mat> = xs
            .iter()
            .map(|e| sol.value(e).map(|v| crate::linalg::sym(&v)))
            .collect::<Result<_>>()?;
        let lh: Vec<Mat> = ls.iter().map(|e| sol.value(e)).collect::<Result<_>>()?;
        let to_rho = |c: &[Mat]| -> [Mat; 3] {
            // c0 + c1 (ρ − o)/h + c2 (ρ − o)²/h².
            let (o, h) = (off_s, scale_s);
            [
                &c[0] - &c[1] * (o / h) + &c[2] * (o * o / (h * h)),
                &c[1] / h - &c[2] * (2.0 * o / (h * h)),
                &c[2] / (h * h),
            ]
        };
        Ok(ScheduledGain {
            x_coefficients: to_rho(&xh),
            l_coefficients: to_rho(&lh),
            gamma: sol.value(&gamma)?[(0, 0)],
            rho_range: spec.rho_range,
        })
    };
    let schedule = if refined.is_some() && final_sol.all_checks_pass() {
        Some(extract(final_sol)?)
    } else {
        None
    };
    let optimum = if optimization.status.is_solved() {
        Some(extract(&optimization)?)
    } else {
        None
    };
    Ok(GainSchedule {
        status,
        gamma_star,
        schedule,
        optimum,
        optimization,
        refined,
    })
}
