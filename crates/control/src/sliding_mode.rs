//! Sliding-mode control on the LQ-optimal switching hyperplane (the book §3.2; V. I. Utkin and
//! K.-K. D. Young, "Methods for constructing discontinuity planes in multidimensional
//! variable structure systems", *Automation and Remote Control* 39, 1978; C. Edwards and
//! S. K. Spurgeon, *Sliding Mode Control: Theory and Applications*, 1998, §4.2).
//!
//! ## The surface
//! For `ẋ = Ax + bu` with one input, a transformation `x̄ = T x` brings the system to the
//! regular form `T b = [0; b̄₂]`. On the surface `σ = 0` the last coordinate `x̄₂` acts as a
//! virtual input of the reduced system `ẋ̄₁ = A₁₁x̄₁ + A₁₂x̄₂`, and minimising
//! `∫ xᵀQx dt = ∫ (x̄₁ᵀQ̄₁₁x̄₁ + 2x̄₁ᵀQ̄₁₂x̄₂ + Q̄₂₂x̄₂²) dt` (`Q̄ = T⁻ᵀQT⁻¹`) is an LQ problem with a
//! cross term. With `Ã₁₁ = A₁₁ − A₁₂Q̄₂₂⁻¹Q̄₁₂ᵀ` its Riccati equation is
//! `care(Ã₁₁, A₁₂, Q̄₁₁ − Q̄₁₂Q̄₂₂⁻¹Q̄₁₂ᵀ, Q̄₂₂)`, the optimal `x̄₂ = −K x̄₁` with
//! `K = Q̄₂₂⁻¹(A₁₂ᵀP + Q̄₁₂ᵀ)`, and the surface is
//! `σ = Sᵀx`, `Sᵀ = [A₁₂ᵀP + Q̄₁₂ᵀ, Q̄₂₂] T = Q̄₂₂ [K, 1] T`. The sliding motion is
//! `ẋ̄₁ = (A₁₁ − A₁₂K)x̄₁`, the reduced LQ closed loop.
//!
//! The book's script passes `Q̄₁₁` where the completed square `Q̄₁₁ − Q̄₁₂Q̄₂₂⁻¹Q̄₁₂ᵀ` belongs
//! ([`ReducedWeight::BookScript`]). Its surface is still LQ-optimal — for the slightly larger
//! weight `Q + T̄ᵀ diag(Q̄₁₂Q̄₂₂⁻¹Q̄₁₂ᵀ, 0) T̄` — and on the cart pendulum the two differ in the
//! third digit; [`ReducedWeight::Exact`] is the optimum for `Q` itself.
//!
//! ## The control law
//! `u = −(Sᵀb)⁻¹(SᵀAx + K₂ σ/(|σ| + δ))` gives `σ̇ = −K₂ σ/(|σ| + δ)` on the linear model: with
//! `δ = 0` the sign function (finite-time reaching, chattering), with `δ > 0` a smooth
//! boundary layer ([`SlidingModeController`]).

use crate::error::{ControlError, Result, check_matrix, check_param};
use pendulab_lti::equations::{RiccatiOptions, care};
use pendulab_lti::{Complex64, Mat};
use pendulab_sim::Controller;

/// Which weight the reduced Riccati equation gets (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ReducedWeight {
    /// `Q̄₁₁ − Q̄₁₂Q̄₂₂⁻¹Q̄₁₂ᵀ`: the surface is LQ-optimal for `Q`.
    #[default]
    Exact,
    /// `Q̄₁₁`, as the book's script `p2c323_Sliding_Mode_Control.m` writes it (reproduces the
    /// book's `S`).
    BookScript,
}

/// The regular-form transformation `T` (`T b = [0; b̄₂]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RegularForm {
    /// The book's shear `T = [[I, −b₁/b_n], [0, 1]]` on the last state (`b_n ≠ 0`);
    /// `x̄` keeps `x₁ … x_{n−1}` shifted along `b` and `x̄_n = x_n`.
    #[default]
    BookShear,
    /// The Householder reflection mapping `b` to `‖b‖ e_n` (orthogonal `T`, the choice of
    /// Edwards & Spurgeon); any `b ≠ 0`.
    Orthogonal,
}

/// An LQ-optimal switching surface with its diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct SlidingSurface {
    /// The surface normal `S` (`n` entries): `σ = Sᵀx`.
    pub s: Vec<f64>,
    /// The regular-form transformation `T` (`x̄ = Tx`).
    pub transformation: Mat,
    /// The reduced gain `K` (`1 × (n−1)`): on the surface `x̄₂ = −K x̄₁`.
    pub reduced_gain: Mat,
    /// The reduced Riccati solution `P`.
    pub riccati: Mat,
    /// Relative residual of the reduced Riccati equation.
    pub residual: f64,
    /// Poles of the sliding motion `eig(A₁₁ − A₁₂K)` (`n − 1` of them).
    pub sliding_poles: Vec<Complex64>,
    /// `Sᵀb` (must be non-zero for the control law).
    pub s_transpose_b: f64,
}

/// Designs the LQ-optimal switching surface for `ẋ = Ax + bu` (`A` `n × n`, `b` `n × 1`,
/// `n ≥ 2`) and the state weight `Q` (`n × n`, symmetric positive semidefinite with
/// `Q̄₂₂ > 0`), with the transformation `form` and the reduced weight `weight`.
///
/// # Errors
/// Shape/finiteness errors; [`ControlError::NotApplicable`] for `b = 0`, `b_n = 0` with
/// [`RegularForm::BookShear`], or `Q̄₂₂ ≤ 0`; the Riccati solver's errors (e.g. the reduced
/// pair not stabilisable).
pub fn lq_sliding_surface(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    form: RegularForm,
    weight: ReducedWeight,
) -> Result<SlidingSurface> {
    let n = a.nrows();
    check_param("state dimension n", n as f64, n >= 2, "must be ≥ 2")?;
    check_matrix("A", a, n, n)?;
    check_matrix("b", b, n, 1)?;
    check_matrix("Q", q, n, n)?;
    let bnorm = b.norm();
    if bnorm == 0.0 {
        return Err(ControlError::NotApplicable {
            reason: "the input vector b is zero".into(),
        });
    }
    let t = match form {
        RegularForm::BookShear => {
            let bn = b[(n - 1, 0)];
            if bn.abs() <= 1e-12 * bnorm {
                return Err(ControlError::NotApplicable {
                    reason: format!(
                        "the book's regular form needs b_n ≠ 0 (b_n = {bn:e}); use RegularForm::Orthogonal"
                    ),
                });
            }
            let mut t = Mat::identity(n, n);
            for i in 0..n - 1 {
                t[(i, n - 1)] = -b[(i, 0)] / bn;
            }
            t
        }
        RegularForm::Orthogonal => {
            // v = b − ‖b‖eₙ (or b + ‖b‖eₙ, whichever is longer), H = I − 2vvᵀ/vᵀv; H b ∝ eₙ.
            let mut v = b.clone();
            let sign = if b[(n - 1, 0)] >= 0.0 { -1.0 } else { 1.0 };
            v[(n - 1, 0)] += sign * bnorm;
            let vv = (v.transpose() * &v)[(0, 0)];
            Mat::identity(n, n) - &v * v.transpose() * (2.0 / vv)
        }
    };
    let tinv = t
        .clone()
        .try_inverse()
        .ok_or_else(|| ControlError::Singular {
            what: "regular-form transformation T".into(),
            value: 0.0,
        })?;
    let abar = &t * a * &tinv;
    let qbar = tinv.transpose() * q * &tinv;
    let m = n - 1;
    let a11 = abar.view((0, 0), (m, m)).clone_owned();
    let a12 = abar.view((0, m), (m, 1)).clone_owned();
    let q11 = qbar.view((0, 0), (m, m)).clone_owned();
    let q12 = qbar.view((0, m), (m, 1)).clone_owned();
    let q22 = qbar[(m, m)];
    if q22 <= 1e-14 * q.norm().max(f64::MIN_POSITIVE) {
        return Err(ControlError::NotApplicable {
            reason: format!(
                "the weight of the virtual input Q̄₂₂ = {q22:e} must be > 0 (weight the last regular-form coordinate)"
            ),
        });
    }
    let at11 = &a11 - &a12 * q12.transpose() / q22;
    let qr = match weight {
        ReducedWeight::Exact => &q11 - &q12 * q12.transpose() / q22,
        ReducedWeight::BookScript => q11.clone(),
    };
    let qr = (&qr + qr.transpose()) * 0.5;
    let r = Mat::from_element(1, 1, q22);
    let sol = care(&at11, &a12, &qr, &r, None, &RiccatiOptions::default())?;
    let p = sol.x;
    let k = (a12.transpose() * &p + q12.transpose()) / q22;
    let mut row = Mat::zeros(1, n);
    row.view_mut((0, 0), (1, m)).copy_from(&(&k * q22));
    row[(0, m)] = q22;
    let st = row * &t;
    let s: Vec<f64> = st.iter().copied().collect();
    let sliding = &a11 - &a12 * &k;
    let mut poles = pendulab_lti::linalg::eigenvalues(&sliding)?;
    pendulab_lti::linalg::sort_eigenvalues(&mut poles);
    let stb = (&st * b)[(0, 0)];
    Ok(SlidingSurface {
        s,
        transformation: t,
        reduced_gain: k,
        riccati: p,
        residual: sol.residual,
        sliding_poles: poles,
        s_transpose_b: stb,
    })
}

/// The sliding-mode law `u = −(Sᵀb)⁻¹(SᵀAx + K₂ σ/(|σ| + δ))`, `σ = Sᵀx`, on the full state
/// `y = x` (`n` entries; angles as the linear model expects them, e.g. wrapped near the
/// upright). `δ = 0` uses `sign(σ)` (0 at `σ = 0`).
#[derive(Debug, Clone, PartialEq)]
pub struct SlidingModeController {
    s: Vec<f64>,
    sta: Vec<f64>,
    stb: f64,
    k2: f64,
    delta: f64,
    sigma: f64,
}

impl SlidingModeController {
    /// The law for the surface `s` (`n` entries) on the model `(A, b)` with reaching gain
    /// `K₂ > 0` and boundary layer `δ ≥ 0`.
    ///
    /// # Errors
    /// Shape/finiteness errors; [`ControlError::InvalidParameter`] for `K₂ ≤ 0` or `δ < 0`;
    /// [`ControlError::Singular`] when `Sᵀb ≈ 0`.
    pub fn new(s: &[f64], a: &Mat, b: &Mat, k2: f64, delta: f64) -> Result<Self> {
        let n = s.len();
        crate::error::check_finite_slice("S", s)?;
        check_matrix("A", a, n, n)?;
        check_matrix("b", b, n, 1)?;
        check_param("reaching gain K2", k2, k2 > 0.0, "must be > 0")?;
        check_param("boundary layer δ", delta, delta >= 0.0, "must be ≥ 0")?;
        let stb: f64 = (0..n).map(|i| s[i] * b[(i, 0)]).sum();
        let snorm = s.iter().map(|v| v * v).sum::<f64>().sqrt();
        if stb.abs() <= 1e-12 * snorm * b.norm() {
            return Err(ControlError::Singular {
                what: "Sᵀb of the sliding-mode law".into(),
                value: stb.abs(),
            });
        }
        let sta = (0..n)
            .map(|j| (0..n).map(|i| s[i] * a[(i, j)]).sum())
            .collect();
        Ok(Self {
            s: s.to_vec(),
            sta,
            stb,
            k2,
            delta,
            sigma: 0.0,
        })
    }

    /// The law on a designed surface.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn from_surface(
        surface: &SlidingSurface,
        a: &Mat,
        b: &Mat,
        k2: f64,
        delta: f64,
    ) -> Result<Self> {
        Self::new(&surface.s, a, b, k2, delta)
    }

    /// `σ = Sᵀx` at the last update.
    pub fn sigma(&self) -> f64 {
        self.sigma
    }

    /// `σ = Sᵀx` for a state.
    pub fn switching_function(&self, x: &[f64]) -> f64 {
        self.s.iter().zip(x).map(|(a, b)| a * b).sum()
    }

    /// The control for a state (allocation-free).
    pub fn control(&self, x: &[f64]) -> f64 {
        let sigma = self.switching_function(x);
        let sax: f64 = self.sta.iter().zip(x).map(|(a, b)| a * b).sum();
        let reach = if self.delta == 0.0 {
            if sigma > 0.0 {
                1.0
            } else if sigma < 0.0 {
                -1.0
            } else {
                0.0
            }
        } else {
            sigma / (sigma.abs() + self.delta)
        };
        -(sax + self.k2 * reach) / self.stb
    }
}

impl Controller for SlidingModeController {
    fn ny(&self) -> usize {
        self.s.len()
    }

    fn nu(&self) -> usize {
        1
    }

    fn reset(&mut self) {
        self.sigma = 0.0;
    }

    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        self.sigma = self.switching_function(y);
        u[0] = self.control(y);
    }
}
