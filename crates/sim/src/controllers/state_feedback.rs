//! Static state feedback and the LQ integral servo.

use super::{check_ts, mat_vec, row_major};
use crate::controller::Controller;
use crate::error::{Result, check_len};
use crate::signal::Signal;
use pendulab_lti::Mat;
use pendulab_lti::design::{LqServo, StateFeedback};

/// Static feedback `u = −K (y − y_ref)` on the measurement `y` (the state, or its estimate
/// from the sensor chain).
///
/// **Sign convention.** `K` is the library's gain (`u = −K x`, closed loop `A − BK`, what
/// `pendulab_lti::design::lqr` returns). The textbook writes `u = +K_book x` with
/// `K_book = −K`: build it with [`StaticStateFeedback::from_book`], never by flipping signs by
/// hand.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticStateFeedback {
    k: Vec<f64>,
    y_ref: Vec<f64>,
    /// `y_ref` is all `+0.0` (`y − y_ref` is then `y` bit for bit).
    zero_ref: bool,
    nu: usize,
    ny: usize,
}

impl StaticStateFeedback {
    /// `u = −K y` with the library's `K` (`nu × ny`).
    ///
    /// # Errors
    /// [`crate::SimError::InvalidParameter`] for a non-finite entry.
    pub fn new(k: Mat) -> Result<Self> {
        let (nu, ny) = (k.nrows(), k.ncols());
        Ok(Self {
            k: row_major("K", &k)?,
            y_ref: vec![0.0; ny],
            zero_ref: true,
            nu,
            ny,
        })
    }

    /// `u = +K_book y` — the textbook's convention (`K = −K_book`).
    ///
    /// # Errors
    /// As [`StaticStateFeedback::new`].
    pub fn from_book(k_book: &Mat) -> Result<Self> {
        Self::new(-k_book)
    }

    /// From a [`StateFeedback`] of `pendulab-lti` (`u = −K x`).
    ///
    /// # Errors
    /// As [`StaticStateFeedback::new`].
    pub fn from_state_feedback(f: &StateFeedback) -> Result<Self> {
        Self::new(f.gain().clone())
    }

    /// Regulates to `y_ref` instead of the origin.
    ///
    /// # Errors
    /// [`crate::SimError::DimensionMismatch`] for a wrong length,
    /// [`crate::SimError::InvalidParameter`] for a non-finite entry.
    pub fn with_reference(mut self, y_ref: &[f64]) -> Result<Self> {
        crate::error::check_finite_vector(
            "feedback reference",
            "feedback reference",
            y_ref,
            self.ny,
        )?;
        self.y_ref.copy_from_slice(y_ref);
        self.zero_ref = y_ref.iter().all(|v| v.to_bits() == 0);
        Ok(self)
    }

    /// `K` row-major, `y_ref` and whether `y_ref` is all `+0.0` (for the fixed-size kernel,
    /// [`crate::fast::fixed`]).
    #[inline(always)]
    pub(crate) fn parts(&self) -> (&[f64], &[f64], bool) {
        (&self.k, &self.y_ref, self.zero_ref)
    }

    /// The library gain `K` (`u = −K y`).
    pub fn gain(&self) -> Mat {
        Mat::from_row_slice(self.nu, self.ny, &self.k)
    }
}

impl Controller for StaticStateFeedback {
    sizes_from_fields!();
    fn reset(&mut self) {}
    /// `gain`: the library's `K` (`nu × ny`, row-major); the reference stays.
    fn retune(&mut self, gain: &[f64]) -> Result<bool> {
        check_gain(gain, self.nu * self.ny)?;
        self.k.copy_from_slice(gain);
        Ok(true)
    }
    #[inline]
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        let n = self.ny;
        for (i, ui) in u.iter_mut().enumerate() {
            let row = &self.k[i * n..(i + 1) * n];
            let mut acc = 0.0;
            for ((k, yi), ri) in row.iter().zip(y).zip(&self.y_ref) {
                acc += k * (yi - ri);
            }
            *ui = -acc;
        }
    }
}

/// Checks a replacement gain for [`Controller::retune`]: `expected` entries, all finite.
fn check_gain(gain: &[f64], expected: usize) -> Result<()> {
    crate::error::check_finite_vector("retuned gain entries", "retuned gain entry", gain, expected)
}

/// How the servo integrator `ẇ = e` is realised at the sample rate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IntegrationRule {
    /// `w_k = w_{k−1} + ts·e_{k−1}`: the command at `t_k` uses the errors up to `t_{k−1}`.
    /// Simulink's Discrete-Time Integrator default, and the exact (ZOH) sampling of
    /// `ẇ = e` when `e` is held between samples.
    #[default]
    ForwardEuler,
    /// `w_k = w_{k−1} + ts·e_k`: the current error acts at once.
    BackwardEuler,
    /// `w_k = w_{k−1} + ts·(e_k + e_{k−1})/2` (Tustin), starting from `e_{−1} = 0`.
    Trapezoidal,
}

/// LQ integral servo (book §6.3): `u = −K₁ y − K₂ w` with `w ≈ ∫(r − C_s y) dt`.
///
/// `y` is the measurement (the state or its estimate), `C_s` (`p × ny`) picks the servo
/// outputs from it (for the cart, `z = [1 0 0 0] y`), `r(t)` is a [`Signal`] per servo output,
/// and the integral is realised by an [`IntegrationRule`] at sample time `ts`. Gains are the
/// library's (`pendulab_lti::design::lq_servo`); the book's `K₁_book = −K₁`,
/// `K₂_book = −K₂` go through [`LqIntegralServo::from_book`].
#[derive(Debug, Clone, PartialEq)]
pub struct LqIntegralServo {
    k1: Vec<f64>,
    k2: Vec<f64>,
    cs: Vec<f64>,
    reference: Vec<Signal>,
    rule: IntegrationRule,
    ts: f64,
    nu: usize,
    ny: usize,
    w: Vec<f64>,
    e: Vec<f64>,
    e_prev: Vec<f64>,
    tmp: Vec<f64>,
}

impl LqIntegralServo {
    /// `u = −K₁ y − K₂ w`, `K₁` (`nu × ny`), `K₂` (`nu × p`), `C_s` (`p × ny`), one reference
    /// signal per servo output, at sample time `ts`.
    ///
    /// # Errors
    /// [`crate::SimError::DimensionMismatch`] for inconsistent shapes;
    /// [`crate::SimError::InvalidParameter`] for non-finite entries;
    /// [`crate::SimError::InvalidSampleTime`].
    pub fn new(
        k1: &Mat,
        k2: &Mat,
        cs: &Mat,
        reference: Vec<Signal>,
        ts: f64,
        rule: IntegrationRule,
    ) -> Result<Self> {
        check_ts(ts)?;
        let (nu, ny, p) = (k1.nrows(), k1.ncols(), k2.ncols());
        check_len("K2 rows (commands)", k2.nrows(), nu)?;
        check_len("C_s rows (servo outputs)", cs.nrows(), p)?;
        check_len("C_s columns (measurements)", cs.ncols(), ny)?;
        check_len(
            "reference signals (one per servo output)",
            reference.len(),
            p,
        )?;
        Ok(Self {
            k1: row_major("K1", k1)?,
            k2: row_major("K2", k2)?,
            cs: row_major("C_s", cs)?,
            reference,
            rule,
            ts,
            nu,
            ny,
            w: vec![0.0; p],
            e: vec![0.0; p],
            e_prev: vec![0.0; p],
            tmp: vec![0.0; nu],
        })
    }

    /// From the textbook's gains, `u = +K₁_book y + K₂_book w` (`K = −K_book`).
    ///
    /// # Errors
    /// As [`LqIntegralServo::new`].
    pub fn from_book(
        k1_book: &Mat,
        k2_book: &Mat,
        cs: &Mat,
        reference: Vec<Signal>,
        ts: f64,
        rule: IntegrationRule,
    ) -> Result<Self> {
        Self::new(&-k1_book, &-k2_book, cs, reference, ts, rule)
    }

    /// From an [`LqServo`] design of `pendulab-lti`.
    ///
    /// # Errors
    /// As [`LqIntegralServo::new`].
    pub fn from_design(
        design: &LqServo,
        cs: &Mat,
        reference: Vec<Signal>,
        ts: f64,
        rule: IntegrationRule,
    ) -> Result<Self> {
        Self::new(
            &design.state_gain,
            &design.integral_gain,
            cs,
            reference,
            ts,
            rule,
        )
    }

    /// The integrator state `w` (after the last update).
    pub fn integral(&self) -> &[f64] {
        &self.w
    }
}

impl Controller for LqIntegralServo {
    sizes_from_fields!(sampled);
    fn reset(&mut self) {
        self.w.iter_mut().for_each(|v| *v = 0.0);
        self.e_prev.iter_mut().for_each(|v| *v = 0.0);
    }
    /// `gain`: `[K₁ K₂]` (`nu × (ny + p)`, row-major: row `i` is `K₁`'s row `i`, then
    /// `K₂`'s); the integrator's state, the references and the rule stay.
    fn retune(&mut self, gain: &[f64]) -> Result<bool> {
        let (ny, p) = (self.ny, self.w.len());
        check_gain(gain, self.nu * (ny + p))?;
        for (i, row) in gain.chunks_exact(ny + p).enumerate() {
            self.k1[i * ny..(i + 1) * ny].copy_from_slice(&row[..ny]);
            self.k2[i * p..(i + 1) * p].copy_from_slice(&row[ny..]);
        }
        Ok(true)
    }
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        // e = r − C_s y.
        mat_vec(&self.cs, y, &mut self.e);
        for (e, r) in self.e.iter_mut().zip(&self.reference) {
            *e = r.value(t) - *e;
        }
        let ts = self.ts;
        match self.rule {
            IntegrationRule::ForwardEuler => {}
            IntegrationRule::BackwardEuler => {
                for (w, e) in self.w.iter_mut().zip(&self.e) {
                    *w += ts * e;
                }
            }
            IntegrationRule::Trapezoidal => {
                for ((w, e), ep) in self.w.iter_mut().zip(&self.e).zip(&self.e_prev) {
                    *w += 0.5 * ts * (e + ep);
                }
            }
        }
        mat_vec(&self.k1, y, u);
        mat_vec(&self.k2, &self.w, &mut self.tmp);
        for (ui, ti) in u.iter_mut().zip(&self.tmp) {
            *ui = -(*ui + ti);
        }
        if self.rule == IntegrationRule::ForwardEuler {
            for (w, e) in self.w.iter_mut().zip(&self.e) {
                *w += ts * e;
            }
        }
        self.e_prev.copy_from_slice(&self.e);
    }
}
