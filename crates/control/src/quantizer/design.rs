//! The quantizer's design and evaluation: the feedback error system `(I + H)` of a loop, the
//! cost `E` of any quantizer on it ([`quantizer_cost`]), and the optimal dynamic quantizer by
//! the analytic solution ([`odq_analytic`]) or the horizon-`T` linear program ([`odq_lp`],
//! feature `lmi`).

use super::{DynamicQuantizer, spectral_radius};
use crate::error::{ControlError, Result, check_matrix, check_param};
#[cfg(feature = "lmi")]
use pendulab_lmi::{Expr, Problem, SolveOptions};
use pendulab_lti::design::StateFeedback;
use pendulab_lti::{Discrete, Mat, StateSpace};

/// The system a quantizer sees in a state-feedback loop: with the plant
/// `x⁺ = A x + B v` (discrete), the feedback `u = −K x` and the outputs of interest `y = C_y x`,
/// the deviation caused by `v ≠ u` obeys `δx⁺ = (A − BK) δx + B (v − u)`, `δy = C_y δx`;
/// returns `(A − BK, B, C_y, 0)` with the plant's sample time.
///
/// # Errors
/// [`ControlError::ShapeMismatch`] for `K` not `nu × nx` or `C_y` without `nx` columns.
pub fn feedback_error_system(
    plant: &StateSpace<Discrete>,
    feedback: &StateFeedback,
    output: &Mat,
) -> Result<StateSpace<Discrete>> {
    let (n, m) = (plant.nx(), plant.nu());
    check_matrix("K", feedback.gain(), m, n)?;
    check_matrix("output matrix C_y", output, output.nrows(), n)?;
    let a = plant.a() - plant.b() * feedback.gain();
    Ok(StateSpace::discrete(
        a,
        plant.b().clone(),
        output.clone(),
        Mat::zeros(output.nrows(), m),
        plant.ts(),
    )?)
}

/// The worst-case output deviation of a quantizer on a system (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct QuantizerCost {
    /// `E = maxᵢ Eᵢ` (output units): the supremum of `|y_i − y*_i|` over all rounding-error
    /// sequences.
    pub bound: f64,
    /// `Eᵢ` per output.
    pub per_output: Vec<f64>,
    /// Samples of the impulse response summed.
    pub samples: usize,
    /// Whether the impulse response had decayed (tail below `1e-14` of its peak) within the
    /// sample limit; `false` with `bound = ∞` when the error system is not stable.
    pub converged: bool,
}

/// `E` of the quantizer with error filter `filter` (`None`: the static quantizer) and step `d`
/// on the system `sys = (A, B, C, D)`: `(d/2)·maxᵢ Σ_{k≥0} Σⱼ |g_e,ij(k)|`, where `g_e` is the
/// impulse response of `G(I + H)`, summed until it has decayed or `max_samples` samples
/// (`k = 0` is the feedthrough `D`).
///
/// # Errors
/// Shape errors for a filter whose input count is not `sys.nu()`;
/// [`ControlError::InvalidParameter`] for `d ≤ 0`.
pub fn quantizer_cost(
    sys: &StateSpace<Discrete>,
    filter: Option<&DynamicQuantizer>,
    step: f64,
    max_samples: usize,
) -> Result<QuantizerCost> {
    check_param("quantisation step d", step, step > 0.0, "must be > 0")?;
    let (n, m, p) = (sys.nx(), sys.nu(), sys.ny());
    let (af, bf, cf) = match filter {
        Some(q) => {
            if q.inputs() != m {
                return Err(ControlError::DimensionMismatch {
                    what: "quantizer inputs".into(),
                    expected: m,
                    found: q.inputs(),
                });
            }
            (q.a.clone(), q.b.clone(), q.c.clone())
        }
        None => (Mat::zeros(0, 0), Mat::zeros(0, m), Mat::zeros(m, 0)),
    };
    let r = af.nrows();
    // Cascade: η⁺ = A_f η + B_f w, e = C_f η + w, x⁺ = A x + B e, y = C x + D e.
    let mut aa = Mat::zeros(n + r, n + r);
    aa.view_mut((0, 0), (n, n)).copy_from(sys.a());
    aa.view_mut((0, n), (n, r)).copy_from(&(sys.b() * &cf));
    aa.view_mut((n, n), (r, r)).copy_from(&af);
    let mut ba = Mat::zeros(n + r, m);
    ba.view_mut((0, 0), (n, m)).copy_from(sys.b());
    ba.view_mut((n, 0), (r, m)).copy_from(&bf);
    let mut ca = Mat::zeros(p, n + r);
    ca.view_mut((0, 0), (p, n)).copy_from(sys.c());
    ca.view_mut((0, n), (p, r)).copy_from(&(sys.d() * &cf));
    let da = sys.d().clone();
    let mut sums = vec![0.0; p];
    for i in 0..p {
        sums[i] = (0..m).map(|j| da[(i, j)].abs()).sum();
    }
    let stable = spectral_radius(&aa)? < 1.0 || n + r == 0;
    if !stable {
        return Ok(QuantizerCost {
            bound: f64::INFINITY,
            per_output: vec![f64::INFINITY; p],
            samples: 0,
            converged: false,
        });
    }
    let mut z = ba.clone();
    let mut peak: f64 = 0.0;
    let mut samples = 1;
    let mut converged = n + r == 0;
    while samples < max_samples && !converged {
        let y = &ca * &z;
        for i in 0..p {
            sums[i] += (0..m).map(|j| y[(i, j)].abs()).sum::<f64>();
        }
        let zn = z.norm();
        peak = peak.max(zn);
        z = &aa * z;
        samples += 1;
        converged = zn <= 1e-14 * peak;
    }
    let half = step / 2.0;
    let per_output: Vec<f64> = sums.iter().map(|s| s * half).collect();
    Ok(QuantizerCost {
        bound: per_output.iter().copied().fold(0.0, f64::max),
        per_output,
        samples,
        converged,
    })
}

/// How an optimal dynamic quantizer was obtained.
#[derive(Debug, Clone, PartialEq)]
pub enum OdqMethod {
    /// The closed form for stable zero dynamics, with the relative degree `r` used.
    Analytic {
        /// Relative degree (index of the first non-zero Markov parameter).
        relative_degree: usize,
    },
    /// The linear program over horizon `T`.
    LinearProgram {
        /// Horizon `T` (samples).
        horizon: usize,
        /// The LP's optimal value `γ*` (output units per unit rounding error; `E_T ≈ γ* d/2`).
        optimum: f64,
        /// Interior-point iterations.
        iterations: u32,
        /// Whether every constraint passed the recheck on the returned values.
        checks_pass: bool,
    },
}

/// An optimal dynamic quantizer with its figures of merit.
#[derive(Debug, Clone, PartialEq)]
pub struct OdqDesign {
    /// The quantizer (realised error filter, step `d`).
    pub quantizer: DynamicQuantizer,
    /// How it was designed.
    pub method: OdqMethod,
    /// The cost the design optimised: `(d/2)·maxᵢΣⱼ|M_r,ij|` (analytic), or the horizon-`T`
    /// worst-case deviation `(d/2)·maxᵢ Σ_{k=1}^{T} Σⱼ |g_e,ij(k)|` of the LP's taps, recomputed
    /// from them.
    pub design_cost: f64,
    /// [`quantizer_cost`] of the realised quantizer (infinite horizon).
    pub cost: QuantizerCost,
    /// [`quantizer_cost`] of the static quantizer on the same system, for comparison.
    pub static_cost: QuantizerCost,
    /// ℓ₁ gain from the rounding error `w` to `v`: `maxᵢ Σ_k Σⱼ |(I + H)_ij(k)|` (of the
    /// designed taps; for the analytic design summed until decayed).
    pub filter_gain: f64,
}

const COST_SAMPLES: usize = 200_000;

#[cfg(feature = "lmi")]
fn markov(sys: &StateSpace<Discrete>, count: usize) -> Vec<Mat> {
    // M_k = C A^{k−1} B, k = 1 … count.
    let mut out = Vec::with_capacity(count);
    let mut akb = sys.b().clone();
    for _ in 0..count {
        out.push(sys.c() * &akb);
        akb = sys.a() * akb;
    }
    out
}

fn check_error_system(sys: &StateSpace<Discrete>) -> Result<()> {
    if sys.d().iter().any(|v| *v != 0.0) {
        return Err(ControlError::NotApplicable {
            reason: "the quantizer designs need a strictly proper system (D = 0)".into(),
        });
    }
    if sys.nu() == 0 || sys.ny() == 0 {
        return Err(ControlError::NotApplicable {
            reason: "the system needs at least one input and one output".into(),
        });
    }
    Ok(())
}

fn filter_gain_of_taps(taps: &[Mat], m: usize) -> f64 {
    (0..m)
        .map(|i| {
            1.0 + taps
                .iter()
                .map(|t| (0..m).map(|j| t[(i, j)].abs()).sum::<f64>())
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}

/// The closed-form optimal dynamic quantizer (Azuma–Sugie 2008, Automatica) for step `d` on
/// the strictly proper system `sys` (e.g. from [`feedback_error_system`]).
///
/// With the relative degree `r` (the first Markov parameter `M_r = C A^{r−1} B` that is not
/// zero to `1e-12` relative to `‖C‖‖B‖ max(1, ‖A‖)^{r−1}`), `C_f = −M_r⁺ C A^r`,
/// `A_f = A + B C_f`, `B_f = B`; requires `M_r` of full row rank (`p ≤ m`) so that
/// `G(I + H) = M_r z^{−r}`, and `A + B C_f` stable.
///
/// # Errors
/// [`ControlError::NotApplicable`] for a system with `D ≠ 0`, all Markov parameters zero,
/// `M_r` without full row rank, or an unstable `A + B C_f` (non-minimum-phase zeros; the
/// spectral radius is given) — use [`odq_lp`] then; [`ControlError::InvalidParameter`] for
/// `d ≤ 0`.
pub fn odq_analytic(sys: &StateSpace<Discrete>, step: f64) -> Result<OdqDesign> {
    check_param("quantisation step d", step, step > 0.0, "must be > 0")?;
    check_error_system(sys)?;
    let (n, m, p) = (sys.nx(), sys.nu(), sys.ny());
    let scale_a = sys.a().norm().max(1.0);
    let scale = sys.c().norm() * sys.b().norm();
    let mut akb = sys.b().clone();
    let mut ca_r1 = sys.c().clone(); // C A^{r−1}
    let mut found = None;
    for r in 1..=n.max(1) {
        let mr = sys.c() * &akb;
        if mr.norm() > 1e-12 * scale * scale_a.powi(r as i32 - 1) {
            found = Some((r, mr));
            break;
        }
        akb = sys.a() * akb;
        ca_r1 = &ca_r1 * sys.a();
    }
    let Some((r, mr)) = found else {
        return Err(ControlError::NotApplicable {
            reason: "every Markov parameter of the system is zero".into(),
        });
    };
    let svd = pendulab_lti::linalg::svd::svd(&mr);
    let smax = svd.singular_values.max();
    let smin = if p <= m {
        svd.singular_values.min()
    } else {
        0.0
    };
    if p > m || smin <= 1e-10 * smax {
        return Err(ControlError::NotApplicable {
            reason: format!(
                "the first non-zero Markov parameter C A^{} B ({p}x{m}) does not have full row rank; the closed form needs it",
                r - 1
            ),
        });
    }
    let pinv = svd.pseudo_inverse(1e-12 * smax);
    let car = &ca_r1 * sys.a();
    let cf = -(&pinv * car);
    let af = sys.a() + sys.b() * &cf;
    let rho = spectral_radius(&af)?;
    if rho >= 1.0 - 1e-9 {
        return Err(ControlError::NotApplicable {
            reason: format!(
                "the closed-form quantizer is unstable: A + B C_f has spectral radius {rho} (the system has zeros on or outside the unit circle)"
            ),
        });
    }
    let quantizer =
        DynamicQuantizer::new(af, sys.b().clone(), cf, step)?.with_sample_time(sys.ts())?;
    let design_cost = (0..p)
        .map(|i| (0..m).map(|j| mr[(i, j)].abs()).sum::<f64>())
        .fold(0.0, f64::max)
        * step
        / 2.0;
    let cost = quantizer_cost(sys, Some(&quantizer), step, COST_SAMPLES)?;
    let static_cost = quantizer_cost(sys, None, step, COST_SAMPLES)?;
    // ℓ₁ gain of I + H, summed until the filter's impulse response has decayed.
    let mut gain_taps = Vec::new();
    let mut peak: f64 = 0.0;
    let mut akb = quantizer.b.clone();
    for _ in 0..COST_SAMPLES {
        let h = &quantizer.c * &akb;
        let hn = akb.norm();
        peak = peak.max(hn);
        gain_taps.push(h);
        if hn <= 1e-14 * peak {
            break;
        }
        akb = &quantizer.a * akb;
    }
    let filter_gain = filter_gain_of_taps(&gain_taps, m);
    Ok(OdqDesign {
        quantizer,
        method: OdqMethod::Analytic { relative_degree: r },
        design_cost,
        cost,
        static_cost,
        filter_gain,
    })
}

/// How the LP's taps are realised as a state-space error filter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Realization {
    /// Exactly, as a shift register of the last `T − 1` rounding errors (order `m(T − 1)`).
    #[default]
    Fir,
    /// Reduced to `order` states by Ho–Kalman realisation of the taps' Hankel matrix
    /// (truncated SVD; the book uses order 2); the realised quantizer's cost is re-evaluated
    /// and reported, since truncation changes it.
    Reduced {
        /// State dimension of the realisation (≥ 1).
        order: usize,
    },
}

/// Options of [`odq_lp`], with documented defaults.
#[cfg(feature = "lmi")]
#[derive(Debug, Clone, PartialEq)]
pub struct OdqLpOptions {
    /// Evaluation horizon `T` in samples (default 300, the book's; ≥ 2). The LP optimises the
    /// first `T − 1` taps of the error filter.
    pub horizon: usize,
    /// Upper bound `γ_wv ≥ 1` on the ℓ₁ gain from the rounding error `w` to `v` (default
    /// `None`: unconstrained; the book uses 3.35).
    pub max_filter_gain: Option<f64>,
    /// Realisation of the taps (default [`Realization::Fir`]).
    pub realization: Realization,
    /// Solver options (default: `pendulab-lmi`'s).
    pub solver: SolveOptions,
}

#[cfg(feature = "lmi")]
impl Default for OdqLpOptions {
    fn default() -> Self {
        Self {
            horizon: 300,
            max_filter_gain: None,
            realization: Realization::Fir,
            solver: SolveOptions::default(),
        }
    }
}

/// The optimal dynamic quantizer by linear programming (Azuma–Sugie 2008, TAC) for step `d`
/// on the strictly proper system `sys`.
///
/// Decision variables: taps `H₀ … H_{T−2}` (`m × m`), slacks `E_k ≥ |g_e(k)|` for
/// `k = 2 … T` and the bound `γ`. With the Markov parameters `M_k = C A^{k−1} B`,
/// `g_e(1) = M₁` and `g_e(k) = M_k + Σ_{l=0}^{k−2} M_{k−1−l} H_l` (affine in the taps), the LP is
///
/// ```text
/// minimise γ  s.t.  −E_k ≤ g_e(k) ≤ E_k,   Σⱼ|M₁,ij| + Σ_{k=2}^{T} Σⱼ E_k,ij ≤ γ  (each output i),
///                   [optionally] −H̄_l ≤ H_l ≤ H̄_l,  1 + Σ_l Σⱼ H̄_l,ij ≤ γ_wv  (each input i).
/// ```
///
/// The Markov parameters are scaled to unit largest entry before solving (the LP is
/// homogeneous in them). `design_cost` is the horizon-`T` worst-case deviation of the returned
/// taps (≈ `γ* d/2`); `cost` evaluates the realised quantizer over the infinite horizon.
///
/// # Errors
/// [`ControlError::InvalidParameter`] for `T < 2`, `γ_wv < 1`, order 0 or `d ≤ 0`;
/// [`ControlError::NotApplicable`] for `D ≠ 0`; [`ControlError::LinearProgram`] when the LP is
/// not solved (status given); the LMI layer's modelling errors.
#[cfg(feature = "lmi")]
#[doc(alias = "odq")]
pub fn odq_lp(sys: &StateSpace<Discrete>, step: f64, options: &OdqLpOptions) -> Result<OdqDesign> {
    check_param("quantisation step d", step, step > 0.0, "must be > 0")?;
    check_error_system(sys)?;
    let t = options.horizon;
    check_param("LP horizon T", t as f64, t >= 2, "must be ≥ 2 samples")?;
    if let Some(g) = options.max_filter_gain {
        check_param("filter gain bound γ_wv", g, g >= 1.0, "must be ≥ 1")?;
    }
    if let Realization::Reduced { order } = options.realization {
        check_param("realisation order", order as f64, order >= 1, "must be ≥ 1")?;
    }
    let (m, p) = (sys.nu(), sys.ny());
    let l = t - 1; // number of taps and of constrained samples k = 2 … T
    // M_1 … M_T, scaled to unit largest entry: the LP is homogeneous in the Markov
    // parameters for fixed taps, and unscaled data of order 1e-4 (a 10 ms sampled loop) put
    // the solver's absolute feasibility tolerance at the level of the optimum itself.
    let mut mk = markov(sys, t);
    let scale = mk
        .iter()
        .flat_map(|mm| mm.iter())
        .fold(0.0f64, |a, v| a.max(v.abs()));
    if !(scale > 0.0 && scale.is_finite()) {
        return Err(ControlError::NotApplicable {
            reason: format!("the first {t} Markov parameters of the system are all zero"),
        });
    }
    for mm in &mut mk {
        *mm /= scale;
    }
    // Φ: block (k−2, l') = M_{k−1−l'} for l' ≤ k−2 (block rows k = 2 … T), p × m blocks.
    let mut phi = Mat::zeros(p * l, m * l);
    let mut c0 = Mat::zeros(p * l, m);
    for row in 0..l {
        let k = row + 2;
        c0.view_mut((row * p, 0), (p, m)).copy_from(&mk[k - 1]);
        for col in 0..=row {
            // M_{k−1−col} = mk[k − 2 − col]
            phi.view_mut((row * p, col * m), (p, m))
                .copy_from(&mk[k - 2 - col]);
        }
    }
    let mut prob = Problem::new();
    let h = prob.matrix("H", m * l, m);
    let e = prob.matrix("E", p * l, m);
    let gamma = prob.scalar("gamma");
    let ge = &c0 + &phi * &h;
    prob.less_equal("g_e ≤ E", &ge, &e)?;
    prob.less_equal("−E ≤ g_e", &(-&e), &ge)?;
    let mut sel = Mat::zeros(p, p * l);
    for row in 0..l {
        for i in 0..p {
            sel[(i, row * p + i)] = 1.0;
        }
    }
    let ones_m = Mat::from_element(m, 1, 1.0);
    let ones_p = Mat::from_element(p, 1, 1.0);
    let m1_abs = Mat::from_fn(p, 1, |i, _| (0..m).map(|j| mk[0][(i, j)].abs()).sum());
    let per_output = &sel * &e * &ones_m + &m1_abs;
    prob.less_equal("Σ|g_e| ≤ γ", &per_output, &(&ones_p * &gamma))?;
    if let Some(gwv) = options.max_filter_gain {
        let hbar = prob.matrix("Hbar", m * l, m);
        prob.less_equal("H ≤ Hbar", &h, &hbar)?;
        prob.less_equal("−Hbar ≤ H", &(-&hbar), &h)?;
        let mut selm = Mat::zeros(m, m * l);
        for row in 0..l {
            for i in 0..m {
                selm[(i, row * m + i)] = 1.0;
            }
        }
        let gain = &selm * &hbar * &ones_m;
        prob.less_equal(
            "1 + Σ|H| ≤ γ_wv",
            &gain,
            &Expr::constant(&Mat::from_element(m, 1, gwv - 1.0)),
        )?;
    }
    prob.minimize(&gamma)?;
    let sol = prob.solve(&options.solver)?;
    if !sol.status.is_solved() {
        return Err(ControlError::LinearProgram {
            what: "the optimal dynamic quantizer".into(),
            status: format!("{:?}", sol.status),
        });
    }
    let hv = sol.value(&h)?;
    let optimum = sol.value(&gamma)?[(0, 0)] * scale;
    let taps: Vec<Mat> = (0..l)
        .map(|k| hv.view((k * m, 0), (m, m)).clone_owned())
        .collect();
    let quantizer = match options.realization {
        Realization::Fir => DynamicQuantizer::fir(&taps, m, step)?,
        Realization::Reduced { order } => ho_kalman(&taps, m, order, step)?,
    }
    .with_sample_time(sys.ts())?;
    let cost = quantizer_cost(sys, Some(&quantizer), step, COST_SAMPLES)?;
    let static_cost = quantizer_cost(sys, None, step, COST_SAMPLES)?;
    // The horizon-T cost of the taps themselves (not the LP's γ, which may sit below it by
    // the solver's feasibility tolerance).
    let fir = DynamicQuantizer::fir(&taps, m, step)?;
    let design_cost = quantizer_cost(sys, Some(&fir), step, t + 1)?.bound;
    Ok(OdqDesign {
        filter_gain: filter_gain_of_taps(&taps, m),
        quantizer,
        method: OdqMethod::LinearProgram {
            horizon: t,
            optimum,
            iterations: sol.iterations,
            checks_pass: sol.all_checks_pass(),
        },
        design_cost,
        cost,
        static_cost,
    })
}

/// Ho–Kalman realisation (B. L. Ho and R. E. Kalman, 1966; balanced by the SVD as in Kung's
/// method) of the strictly proper filter with Markov parameters `taps` (`H_k = C A^k B`),
/// truncated to `order` states.
#[cfg(feature = "lmi")]
fn ho_kalman(taps: &[Mat], m: usize, order: usize, step: f64) -> Result<DynamicQuantizer> {
    let q = taps.len().div_ceil(2).max(1);
    if taps.len() < 2 * q - 1 || q < 2 {
        return Err(ControlError::InvalidParameter {
            name: "LP horizon T for a reduced realisation".into(),
            value: (taps.len() + 1) as f64,
            requirement: "must be ≥ 4".into(),
        });
    }
    let mut hk = Mat::zeros(q * m, q * m);
    for i in 0..q {
        for j in 0..q {
            hk.view_mut((i * m, j * m), (m, m)).copy_from(&taps[i + j]);
        }
    }
    let svd = pendulab_lti::linalg::svd::svd(&hk);
    let (u, vt) = (svd.u, svd.v_t);
    let s = &svd.singular_values;
    // Singular values in decreasing order.
    let order = order.min(q * m);
    let mut sq = Mat::zeros(order, order);
    for i in 0..order {
        sq[(i, i)] = s[i].sqrt();
    }
    if s[order - 1] <= 1e-14 * s[0].max(f64::MIN_POSITIVE) {
        return Err(ControlError::InvalidParameter {
            name: "realisation order".into(),
            value: order as f64,
            requirement: format!(
                "exceeds the numerical rank of the taps' Hankel matrix (singular values {:?}…)",
                &s.as_slice()[..order.min(6)]
            ),
        });
    }
    let obs = u.columns(0, order) * &sq; // qm × r
    let ctr = &sq * vt.rows(0, order); // r × qm
    let c = obs.rows(0, m).clone_owned();
    let b = ctr.columns(0, m).clone_owned();
    let upper = obs.rows(0, (q - 1) * m).clone_owned();
    let lower = obs.rows(m, (q - 1) * m).clone_owned();
    let pinv = pendulab_lti::linalg::svd::svd(&upper).pseudo_inverse(1e-13 * s[0]);
    let a = pinv * lower;
    DynamicQuantizer::new(a, b, c, step)
}
