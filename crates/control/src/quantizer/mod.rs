//! Quantised inputs: static and optimal dynamic quantizers (Azuma–Sugie).
//!
//! S. Azuma and T. Sugie, "Optimal dynamic quantizers for discrete-valued input control",
//! *Automatica* 44(2), 396–406, 2008, and "Synthesis of optimal dynamic quantizers for
//! discrete-valued input control", *IEEE TAC* 53(9), 2064–2075, 2008.
//!
//! ## Setting
//! A discrete-time system `G` (in a feedback loop: the ideal closed loop seen from its input)
//! should be driven by `u`, but only values on the grid `d·ℤ` can be applied. A quantizer maps
//! `u` to `v ∈ d·ℤ`; the *output deviation* is `y − y*`, the difference between the outputs
//! with `v` and with `u`. Writing the error of the static rounding inside the quantizer as
//! `w` (`|w| ≤ d/2`), every quantizer considered here has the form
//!
//! ```text
//! s = u + C_f η,   v = q(s) = d⌊s/d + ½⌋,   w = v − s,   η⁺ = A_f η + B_f w,
//! ```
//!
//! so `v − u = (I + H(z)) w` with the strictly proper *error filter*
//! `H(z) = C_f (zI − A_f)⁻¹ B_f` (noise shaping). The static quantizer is `H = 0`. Then
//! `y − y* = G(z)(I + H(z)) w` and, since `w` can be any sequence in `[−d/2, d/2]`,
//!
//! ```text
//! sup |y_i − y*_i| = E_i = (d/2) Σ_k Σ_j |g_e,ij(k)|      (g_e = impulse response of G(I + H))
//! ```
//!
//! is the worst-case deviation of output `i` (the ℓ₁ norm of the error system); the design
//! minimises `E = maxᵢ Eᵢ`. (In Azuma–Sugie's notation the quantizer is `Q = (A_f − B_f C_f,
//! B_f, C_f)` acting on `v − u`; the two forms are the same system.)
//!
//! ## Designs
//! - [`odq_analytic`] (Azuma–Sugie 2008 Automatica, Theorem 2): with `r` the relative degree
//!   (first non-zero Markov parameter `M_r = C A^{r−1} B` of full row rank), `C_f =
//!   −M_r⁺ C A^r`, `A_f = A + B C_f`, `B_f = B` makes `G(I + H) = M_r z^{−r}`, so
//!   `E = (d/2)·maxᵢ Σⱼ |M_r,ij|`, the smallest any quantizer can achieve (the first
//!   non-zero Markov parameter of `G(I + H)` is `M_r` for every strictly proper `H`). It is a
//!   valid quantizer only if `A + B C_f` — whose eigenvalues are the zeros of `G` plus poles
//!   at the origin — is stable, i.e. for minimum-phase `G`.
//! - [`odq_lp`] (Azuma–Sugie 2008 TAC): the impulse response of `G(I + H)` over the first `T`
//!   samples is affine in the first `T − 1` Markov parameters `H₀, H₁, …` of `H`, so minimising
//!   the horizon-`T` cost is a linear program (solved here with Clarabel through
//!   `pendulab-lmi`); an optional bound `γ_wv` on the ℓ₁ gain from `w` to `v`
//!   (`maxᵢ Σ |(I + H)_ij(k)| ≤ γ_wv`) keeps the quantizer's own signals small. The taps are
//!   realised exactly as an FIR filter or reduced to a given order by Ho–Kalman realisation
//!   of their Hankel matrix.
//! - [`quantizer_cost`]: `E` of any quantizer on any system, evaluated from the impulse
//!   response until it has decayed (the design's figure of merit, independent of how the
//!   quantizer was designed).
//!
//! At run time an [`InputQuantizer`] maps commands to grid values, and [`QuantizedController`]
//! puts one behind any [`Controller`].

mod design;

pub use design::{
    OdqDesign, OdqMethod, QuantizerCost, Realization, feedback_error_system, odq_analytic,
    quantizer_cost,
};
#[cfg(feature = "lmi")]
pub use design::{OdqLpOptions, odq_lp};

use crate::error::{ControlError, Result, check_matrix, check_param};
use pendulab_lti::Mat;
use pendulab_sim::Controller;

/// Rounds `s` to the grid `d·ℤ`: `q(s) = d⌊s/d + ½⌋`, so `|q(s) − s| ≤ d/2` (ties round up).
#[inline]
pub fn round_to_step(s: f64, d: f64) -> f64 {
    d * (s / d + 0.5).floor()
}

/// A dynamic quantizer with error filter `H(z) = C_f (zI − A_f)⁻¹ B_f` (see the module
/// documentation): `s = u + C_f η`, `v = q(s)`, `w = v − s`, `η⁺ = A_f η + B_f w`.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicQuantizer {
    step: f64,
    sample_time: Option<f64>,
    a: Mat,
    b: Mat,
    c: Mat,
    state: Vec<f64>,
    next: Vec<f64>,
    w: Vec<f64>,
}

impl DynamicQuantizer {
    /// A quantizer with step `d` (> 0) and error filter `(A_f, B_f, C_f)` (`A_f` `r × r`,
    /// `B_f` `r × m`, `C_f` `m × r`; `r = 0` gives the static quantizer).
    ///
    /// # Errors
    /// [`ControlError::ShapeMismatch`], [`ControlError::NonFinite`],
    /// [`ControlError::InvalidParameter`] for a step that is not `> 0`.
    pub fn new(a: Mat, b: Mat, c: Mat, step: f64) -> Result<Self> {
        check_param("quantisation step d", step, step > 0.0, "must be > 0")?;
        let r = a.nrows();
        let m = c.nrows();
        check_matrix("A_f", &a, r, r)?;
        check_matrix("B_f", &b, r, m)?;
        check_matrix("C_f", &c, m, r)?;
        if m == 0 {
            return Err(ControlError::InvalidParameter {
                name: "number of quantised inputs".into(),
                value: 0.0,
                requirement: "must be ≥ 1".into(),
            });
        }
        Ok(Self {
            step,
            sample_time: None,
            a,
            b,
            c,
            state: vec![0.0; r],
            next: vec![0.0; r],
            w: vec![0.0; m],
        })
    }

    /// The static quantizer (`H = 0`) on `m` inputs.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn static_quantizer(m: usize, step: f64) -> Result<Self> {
        Self::new(Mat::zeros(0, 0), Mat::zeros(0, m), Mat::zeros(m, 0), step)
    }

    /// The FIR error filter `H(z) = Σ_{l≥0} H_l z^{−(l+1)}` with taps `H_l` (`m × m`), realised
    /// as a shift register of past rounding errors.
    ///
    /// # Errors
    /// As [`new`](Self::new); [`ControlError::ShapeMismatch`] for taps of different sizes.
    pub fn fir(taps: &[Mat], m: usize, step: f64) -> Result<Self> {
        let l = taps.len();
        for (i, t) in taps.iter().enumerate() {
            check_matrix(&format!("tap H_{i}"), t, m, m)?;
        }
        let r = l * m;
        let mut a = Mat::zeros(r, r);
        for i in m..r {
            a[(i, i - m)] = 1.0;
        }
        let mut b = Mat::zeros(r, m);
        let mut c = Mat::zeros(m, r);
        for i in 0..m.min(r) {
            b[(i, i)] = 1.0;
        }
        for (k, t) in taps.iter().enumerate() {
            c.view_mut((0, k * m), (m, m)).copy_from(t);
        }
        Self::new(a, b, c, step)
    }

    /// Quantisation step `d`.
    pub fn step(&self) -> f64 {
        self.step
    }

    /// The sample time (s) the quantizer was designed for (its filter has memory, so it must
    /// run at that rate); `None` for one built from bare matrices.
    pub fn sample_time(&self) -> Option<f64> {
        self.sample_time
    }

    /// Declares the sample time (s) the filter runs at.
    ///
    /// # Errors
    /// [`ControlError::InvalidParameter`] unless `ts > 0`.
    pub fn with_sample_time(mut self, ts: f64) -> Result<Self> {
        check_param("quantizer sample time", ts, ts > 0.0, "must be > 0 s")?;
        self.sample_time = Some(ts);
        Ok(self)
    }

    /// Number of quantised inputs `m`.
    pub fn inputs(&self) -> usize {
        self.c.nrows()
    }

    /// Order `r` of the error filter.
    pub fn order(&self) -> usize {
        self.a.nrows()
    }

    /// The error filter `(A_f, B_f, C_f)`.
    pub fn filter(&self) -> (&Mat, &Mat, &Mat) {
        (&self.a, &self.b, &self.c)
    }

    /// The first `count` Markov parameters `C_f A_f^{k} B_f`, `k = 0 … count−1`, of the error
    /// filter (`H_k` of the FIR form).
    pub fn markov_parameters(&self, count: usize) -> Vec<Mat> {
        let mut out = Vec::with_capacity(count);
        let mut ak_b = self.b.clone();
        for _ in 0..count {
            out.push(&self.c * &ak_b);
            ak_b = &self.a * ak_b;
        }
        out
    }

    /// Spectral radius of `A_f` (the quantizer's internal signals stay bounded iff it is < 1,
    /// or the filter is FIR).
    ///
    /// # Errors
    /// The eigenvalue solver's errors.
    pub fn spectral_radius(&self) -> Result<f64> {
        spectral_radius(&self.a)
    }

    /// Clears the filter state.
    pub fn reset(&mut self) {
        self.state.iter_mut().for_each(|v| *v = 0.0);
    }

    /// Quantises one sample: `v = q(u + C_f η)`, then advances the filter. `u.len()` and
    /// `v.len()` must equal [`inputs`](Self::inputs) (checked in debug builds). No allocation.
    pub fn quantize(&mut self, u: &[f64], v: &mut [f64]) {
        let (m, r) = (self.inputs(), self.order());
        debug_assert_eq!(u.len(), m);
        debug_assert_eq!(v.len(), m);
        for i in 0..m {
            let mut s = u[i];
            for k in 0..r {
                s += self.c[(i, k)] * self.state[k];
            }
            v[i] = round_to_step(s, self.step);
            self.w[i] = v[i] - s;
        }
        for i in 0..r {
            let mut acc = 0.0;
            for k in 0..r {
                acc += self.a[(i, k)] * self.state[k];
            }
            for j in 0..m {
                acc += self.b[(i, j)] * self.w[j];
            }
            self.next[i] = acc;
        }
        std::mem::swap(&mut self.state, &mut self.next);
    }
}

/// The input path of a quantised-input loop, as a value.
#[derive(Debug, Clone, PartialEq)]
pub enum InputQuantizer {
    /// No quantisation: `v = u` (the ideal system the others are compared with).
    Ideal,
    /// Static rounding to `d·ℤ`.
    Static {
        /// Step `d` (> 0).
        step: f64,
    },
    /// A dynamic quantizer (boxed: it owns its filter matrices and state).
    Dynamic(Box<DynamicQuantizer>),
}

impl From<DynamicQuantizer> for InputQuantizer {
    fn from(q: DynamicQuantizer) -> Self {
        InputQuantizer::Dynamic(Box::new(q))
    }
}

impl InputQuantizer {
    /// Maps `u` to `v` for one sample (allocation-free).
    pub fn apply(&mut self, u: &[f64], v: &mut [f64]) {
        match self {
            InputQuantizer::Ideal => v.copy_from_slice(u),
            InputQuantizer::Static { step } => {
                for (vi, ui) in v.iter_mut().zip(u) {
                    *vi = round_to_step(*ui, *step);
                }
            }
            InputQuantizer::Dynamic(q) => q.quantize(u, v),
        }
    }

    /// Clears any internal state.
    pub fn reset(&mut self) {
        if let InputQuantizer::Dynamic(q) = self {
            q.reset();
        }
    }
}

/// A controller whose commands pass through an [`InputQuantizer`] before they are held:
/// `u_k = quantizer(inner(y_k))`. A dynamic quantizer must run at the rate it was designed for:
/// the controller reports that sample time (when the inner controller has none), so the
/// sampled loop refuses any other.
#[derive(Debug, Clone)]
pub struct QuantizedController<C> {
    inner: C,
    quantizer: InputQuantizer,
    buffer: Vec<f64>,
}

impl<C: Controller> QuantizedController<C> {
    /// Puts `quantizer` behind `inner`.
    ///
    /// # Errors
    /// [`ControlError::DimensionMismatch`] if a dynamic quantizer's input count differs from
    /// the controller's; [`ControlError::InvalidParameter`] if both declare different sample
    /// times.
    pub fn new(inner: C, quantizer: InputQuantizer) -> Result<Self> {
        if let InputQuantizer::Dynamic(q) = &quantizer
            && q.inputs() != inner.nu()
        {
            return Err(ControlError::DimensionMismatch {
                what: "dynamic quantizer inputs".into(),
                expected: inner.nu(),
                found: q.inputs(),
            });
        }
        if let (InputQuantizer::Dynamic(q), Some(tc)) = (&quantizer, inner.sample_time())
            && let Some(tq) = q.sample_time()
            && (tq - tc).abs() > 1e-12 * tc
        {
            return Err(ControlError::InvalidParameter {
                name: "dynamic quantizer sample time".into(),
                value: tq,
                requirement: format!("must equal the controller's sample time {tc} s"),
            });
        }
        let nu = inner.nu();
        Ok(Self {
            inner,
            quantizer,
            buffer: vec![0.0; nu],
        })
    }

    /// The wrapped controller.
    pub fn inner(&self) -> &C {
        &self.inner
    }

    /// The quantizer.
    pub fn quantizer(&self) -> &InputQuantizer {
        &self.quantizer
    }

    /// The last unquantised command `inner(y_k)`.
    pub fn unquantized(&self) -> &[f64] {
        &self.buffer
    }
}

impl<C: Controller> Controller for QuantizedController<C> {
    fn ny(&self) -> usize {
        self.inner.ny()
    }

    fn nu(&self) -> usize {
        self.inner.nu()
    }

    fn reset(&mut self) {
        self.inner.reset();
        self.quantizer.reset();
        self.buffer.iter_mut().for_each(|v| *v = 0.0);
    }

    fn sample_time(&self) -> Option<f64> {
        match (&self.quantizer, self.inner.sample_time()) {
            (_, Some(ts)) => Some(ts),
            (InputQuantizer::Dynamic(q), None) => q.sample_time(),
            _ => None,
        }
    }

    fn switch_times(&self) -> &[f64] {
        self.inner.switch_times()
    }

    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        self.inner.update(t, y, &mut self.buffer);
        self.quantizer.apply(&self.buffer, u);
    }
}

fn spectral_radius(a: &Mat) -> Result<f64> {
    if a.nrows() == 0 {
        return Ok(0.0);
    }
    Ok(pendulab_lti::linalg::eigenvalues(a)?
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max))
}
