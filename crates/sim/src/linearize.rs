//! Linearisation of any [`Dynamics`] by finite differences.
//!
//! At an operating point `(t, x₀, u₀)` the Jacobians
//! `A = ∂f/∂x`, `B = ∂f/∂u` (and, when the system has an output map `h`, `C = ∂h/∂x`,
//! `D = ∂h/∂u`; otherwise `C = I`, `D = 0`) are estimated column by column with central
//! differences `D(h) = (f(p + h eⱼ) − f(p − h eⱼ)) / (2h)`, whose error is
//! `c₂h² + c₄h⁴ + …` (only even powers). With [`DifferenceScheme::Richardson`] the estimates
//! at `h, h/2, …, h/2^m` are combined in a Richardson tableau
//! `T[i][j] = T[i][j−1] + (T[i][j−1] − T[i−1][j−1]) / (4^j − 1)`, which cancels the `h²`, …,
//! `h^{2m}` terms (Richardson 1911; the tableau as in Ridders, "Accurate computation of F'(x)
//! and F'(x)F''(x)", Adv. Eng. Software 4 (1982), with a fixed ratio 2). The difference of the
//! last two diagonal entries is the reported error estimate.
//!
//! Step sizes: coordinate `j` is perturbed by `h_j = η · max(|p_j|, s_j)` with `s_j` the
//! typical scale (default 1) and `η = ε^{1/(2m+3)}` (ε = machine epsilon), the step that
//! balances the truncation error `O(h^{2m+2})` against the rounding error `O(ε/h)`:
//! `η ≈ 6.1e-6` for plain central differences, `≈ 5.8e-3` for two extrapolations. Each step is
//! rounded so that `p_j ± h_j` is exactly representable.
//!
//! The point need not be an equilibrium: [`Linearization::f0`] holds `f(t, x₀, u₀)`, the
//! constant term of the affine approximation `ẋ ≈ f₀ + A δx + B δu`.

use crate::dynamics::Dynamics;
use crate::error::{Result, SimError, check_initial_state, check_len, check_positive};
use pendulab_lti::{Continuous, Mat, StateSpace};

/// The finite-difference scheme.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DifferenceScheme {
    /// Plain central differences (error `O(h²)`, about 1e-10 relative at the default step).
    Central,
    /// Central differences at `h, h/2, …, h/2^m` combined by Richardson extrapolation
    /// (error `O(h^{2m+2})`); `extrapolations = m ≥ 1`.
    Richardson {
        /// Number of extrapolation levels `m` (1 to 6).
        extrapolations: usize,
    },
}

/// Options of [`linearize`] and [`jacobians`].
#[derive(Debug, Clone, PartialEq)]
pub struct LinearizeOptions {
    /// The difference scheme. Default: `Richardson { extrapolations: 2 }` (error `O(h⁶)`,
    /// typically 1e-12 relative on smooth dynamics).
    pub scheme: DifferenceScheme,
    /// Relative step `η`; `None` (default) uses `ε^{1/(2m+3)}` (see the module docs).
    pub relative_step: Option<f64>,
    /// Typical magnitude `s_j` of each state then each input (length `nx + nu`), the floor of
    /// the step scale `max(|p_j|, s_j)`; `None` (default) uses 1 for every coordinate.
    pub typical_scale: Option<Vec<f64>>,
}

impl Default for LinearizeOptions {
    fn default() -> Self {
        Self {
            scheme: DifferenceScheme::Richardson { extrapolations: 2 },
            relative_step: None,
            typical_scale: None,
        }
    }
}

/// The raw Jacobians of `f` (and of the output map) at an operating point.
#[derive(Debug, Clone, PartialEq)]
pub struct Jacobians {
    /// `∂f/∂x` (`nx × nx`).
    pub a: Mat,
    /// `∂f/∂u` (`nx × nu`).
    pub b: Mat,
    /// `∂h/∂x` (`ny × nx`), or the identity if the system has no output map.
    pub c: Mat,
    /// `∂h/∂u` (`ny × nu`), or zero if the system has no output map.
    pub d: Mat,
    /// `f(t, x₀, u₀)` (zero at an equilibrium).
    pub f0: Vec<f64>,
    /// Largest estimated absolute error of any Jacobian entry (difference of the last two
    /// diagonal Richardson estimates; for plain central differences `4/3 |D(h) − D(h/2)|`).
    pub error_estimate: f64,
    /// Number of evaluations of `f` (and `h`) used.
    pub evaluations: usize,
}

/// The linearisation of a system at an operating point.
#[derive(Debug, Clone, PartialEq)]
pub struct Linearization {
    /// `δẋ = A δx + B δu`, `δy = C δx + D δu` as a continuous state-space system.
    pub system: StateSpace<Continuous>,
    /// `f(t, x₀, u₀)`: the constant term (zero at an equilibrium).
    pub f0: Vec<f64>,
    /// Largest estimated absolute error of any Jacobian entry.
    pub error_estimate: f64,
}

impl Linearization {
    /// The linear system.
    pub fn into_system(self) -> StateSpace<Continuous> {
        self.system
    }
    /// `max |f(t, x₀, u₀)|`: how far the point is from an equilibrium.
    pub fn equilibrium_residual(&self) -> f64 {
        self.f0.iter().fold(0.0, |m, v| m.max(v.abs()))
    }
}

/// Linearises `sys` at `(t, x₀, u₀)` by finite differences (see the module documentation).
///
/// ```
/// use pendulab_sim::{linearize, FnDynamics, LinearizeOptions};
/// # fn main() -> Result<(), pendulab_sim::SimError> {
/// // Pendulum θ̈ = −(g/l) sin θ + u about the hanging rest: A = [[0, 1], [−g/l, 0]].
/// let pend = FnDynamics::new(2, 1, |_t, x: &[f64], u: &[f64], dx: &mut [f64]| {
///     dx[0] = x[1];
///     dx[1] = -9.81 * x[0].sin() + u[0];
/// });
/// let lin = linearize(&pend, 0.0, &[0.0, 0.0], &[0.0], &LinearizeOptions::default())?;
/// assert!((lin.system.a()[(1, 0)] + 9.81).abs() < 1e-10);
/// # Ok(()) }
/// ```
///
/// # Errors
/// [`SimError::DimensionMismatch`] for wrong lengths of `x₀`, `u₀` or the typical scales;
/// [`SimError::NonFiniteInitialState`] for a non-finite `x₀`; [`SimError::InvalidParameter`]
/// for a non-finite `u₀`, a bad relative step or extrapolation count;
/// [`SimError::NonFiniteState`] if `f` is not finite at or near the point.
#[doc(alias = "linmod")]
pub fn linearize<S: Dynamics + ?Sized>(
    sys: &S,
    t: f64,
    x0: &[f64],
    u0: &[f64],
    options: &LinearizeOptions,
) -> Result<Linearization> {
    let j = jacobians(sys, t, x0, u0, options)?;
    let system = StateSpace::continuous(j.a, j.b, j.c, j.d)?;
    Ok(Linearization {
        system,
        f0: j.f0,
        error_estimate: j.error_estimate,
    })
}

/// The Jacobians `∂f/∂x`, `∂f/∂u` (and of the output map) at `(t, x₀, u₀)` by finite
/// differences; see [`linearize`].
///
/// # Errors
/// As [`linearize`].
pub fn jacobians<S: Dynamics + ?Sized>(
    sys: &S,
    t: f64,
    x0: &[f64],
    u0: &[f64],
    options: &LinearizeOptions,
) -> Result<Jacobians> {
    let (nx, nu, ny) = (sys.nx(), sys.nu(), sys.ny());
    check_initial_state(x0, nx)?;
    check_len("operating input u0", u0.len(), nu)?;
    for (i, &v) in u0.iter().enumerate() {
        crate::error::check_finite(&format!("operating input u0[{i}]"), v)?;
    }
    crate::error::check_finite("linearisation time t", t)?;
    let m = match options.scheme {
        DifferenceScheme::Central => 0,
        DifferenceScheme::Richardson { extrapolations } => {
            if !(1..=6).contains(&extrapolations) {
                return Err(SimError::InvalidParameter {
                    what: "Richardson extrapolations".into(),
                    value: extrapolations as f64,
                    requirement: "must be between 1 and 6",
                });
            }
            extrapolations
        }
    };
    let eta = match options.relative_step {
        Some(e) => {
            check_positive("relative step", e)?;
            e
        }
        None => f64::EPSILON.powf(1.0 / (2.0 * m as f64 + 3.0)),
    };
    let typical = match &options.typical_scale {
        Some(s) => {
            check_len("typical scales (states then inputs)", s.len(), nx + nu)?;
            for (i, &v) in s.iter().enumerate() {
                check_positive(&format!("typical scale {i}"), v)?;
            }
            s.clone()
        }
        None => vec![1.0; nx + nu],
    };
    let with_output = ny > 0;
    let nout = if with_output { ny } else { 0 };
    // Evaluates [f; h] at (x, u) into `out` (length nx + nout).
    let eval = |x: &[f64], u: &[f64], out: &mut [f64]| -> Result<()> {
        let (fpart, hpart) = out.split_at_mut(nx);
        sys.derivative(t, x, u, fpart);
        if with_output {
            sys.output(t, x, u, hpart);
        }
        if let Some((index, &value)) = out.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(SimError::NonFiniteState { t, index, value });
        }
        Ok(())
    };
    let rows = nx + nout;
    let mut f0 = vec![0.0; rows];
    eval(x0, u0, &mut f0)?;
    let mut evaluations = 1;
    let mut x = x0.to_vec();
    let mut u = u0.to_vec();
    let mut fp = vec![0.0; rows];
    let mut fm = vec![0.0; rows];
    // Jacobian columns of [f; h] w.r.t. [x; u].
    let mut jac = Mat::zeros(rows, nx + nu);
    let mut error_estimate = 0.0f64;
    // Central differences at h0, h0/2, …, h0/2^L (plain central still computes h0/2 for its
    // error estimate); `diffs[level * rows + r]`.
    let levels = m.max(1) + 1;
    let mut diffs = vec![0.0; levels * rows];
    for col in 0..nx + nu {
        let p0 = if col < nx { x0[col] } else { u0[col - nx] };
        let h0 = eta * p0.abs().max(typical[col]);
        for level in 0..levels {
            let h_try = h0 / f64::powi(2.0, level as i32);
            // Exactly representable perturbations.
            let hp = (p0 + h_try) - p0;
            let hm = p0 - (p0 - h_try);
            set_coordinate(&mut x, &mut u, nx, col, p0 + hp);
            eval(&x, &u, &mut fp)?;
            set_coordinate(&mut x, &mut u, nx, col, p0 - hm);
            eval(&x, &u, &mut fm)?;
            set_coordinate(&mut x, &mut u, nx, col, p0);
            evaluations += 2;
            for r in 0..rows {
                diffs[level * rows + r] = (fp[r] - fm[r]) / (hp + hm);
            }
        }
        for r in 0..rows {
            let (value, err) = if m == 0 {
                let (d0, d1) = (diffs[r], diffs[rows + r]);
                // |D(h) − D(h/2)| ≈ ¾ |c₂| h², an upper estimate of D(h)'s error c₂h².
                (d0, (d0 - d1).abs() * 4.0 / 3.0)
            } else {
                // Richardson tableau, row by row (at most 7 × 7).
                let mut t = [[0.0f64; 7]; 7];
                for i in 0..=m {
                    t[i][0] = diffs[i * rows + r];
                    for j in 1..=i {
                        let factor = f64::powi(4.0, j as i32) - 1.0;
                        t[i][j] = t[i][j - 1] + (t[i][j - 1] - t[i - 1][j - 1]) / factor;
                    }
                }
                (t[m][m], (t[m][m] - t[m - 1][m - 1]).abs())
            };
            jac[(r, col)] = value;
            error_estimate = error_estimate.max(err);
        }
    }
    let a = jac.view((0, 0), (nx, nx)).clone_owned();
    let b = jac.view((0, nx), (nx, nu)).clone_owned();
    let (c, d) = if with_output {
        (
            jac.view((nx, 0), (ny, nx)).clone_owned(),
            jac.view((nx, nx), (ny, nu)).clone_owned(),
        )
    } else {
        (Mat::identity(nx, nx), Mat::zeros(nx, nu))
    };
    f0.truncate(nx);
    Ok(Jacobians {
        a,
        b,
        c,
        d,
        f0,
        error_estimate,
        evaluations,
    })
}

/// Sets coordinate `col` of the stacked point `[x; u]`.
fn set_coordinate(x: &mut [f64], u: &mut [f64], nx: usize, col: usize, value: f64) {
    if col < nx {
        x[col] = value;
    } else {
        u[col - nx] = value;
    }
}
