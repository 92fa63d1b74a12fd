//! Gain-scheduled feedback, switching between controllers, and command saturation.

use super::row_major;
use crate::controller::Controller;
use crate::error::{Result, SimError, check_len};
use pendulab_lti::Mat;
use std::sync::Arc;

type Schedule = Arc<dyn Fn(&[f64]) -> f64 + Send + Sync>;
type GainFn = Arc<dyn Fn(f64, &mut [f64]) + Send + Sync>;

enum Family {
    /// `K(ρ) = Σ ρ^i K_i` (row-major coefficient matrices).
    Polynomial(Vec<Vec<f64>>),
    /// A closure writing `K(ρ)` row-major.
    Closure(GainFn),
}

/// Gain-scheduled state feedback `u = −K(ρ) (y − y_ref)` with scheduling variable
/// `ρ = φ(y)` evaluated at every sample.
///
/// `K(ρ)` is either a matrix polynomial `K₀ + ρ K₁ + ρ² K₂ + …` (e.g. from an LPV design with
/// `ρ = 1 − cos θ₁` for the arm pendulum) or any closure writing the `nu × ny` gain
/// row-major (e.g. `K(ρ) = L(ρ) X(ρ)⁻¹` of a parameter-dependent LMI design). Library sign
/// (`u = −K x`).
#[derive(Clone)]
pub struct GainScheduled {
    family: Arc<Family>,
    schedule: Schedule,
    nu: usize,
    ny: usize,
    y_ref: Vec<f64>,
    k: Vec<f64>,
    rho: f64,
}

impl std::fmt::Debug for GainScheduled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GainScheduled")
            .field("nu", &self.nu)
            .field("ny", &self.ny)
            .field("rho", &self.rho)
            .finish_non_exhaustive()
    }
}

impl GainScheduled {
    /// `K(ρ) = Σ ρ^i K_i` with the coefficient matrices `K_i` (all `nu × ny`, at least one),
    /// scheduled by `φ`.
    ///
    /// # Errors
    /// [`SimError::InvalidArgument`] for an empty list; [`SimError::DimensionMismatch`] for
    /// coefficients of different shapes; [`SimError::InvalidParameter`] for non-finite
    /// entries.
    pub fn polynomial<F>(coefficients: &[Mat], schedule: F) -> Result<Self>
    where
        F: Fn(&[f64]) -> f64 + Send + Sync + 'static,
    {
        let first = coefficients.first().ok_or_else(|| {
            SimError::InvalidArgument("a gain polynomial needs at least K0".into())
        })?;
        let (nu, ny) = (first.nrows(), first.ncols());
        let mut coefs = Vec::with_capacity(coefficients.len());
        for (i, k) in coefficients.iter().enumerate() {
            check_len(&format!("rows of K{i}"), k.nrows(), nu)?;
            check_len(&format!("columns of K{i}"), k.ncols(), ny)?;
            coefs.push(row_major(&format!("K{i}"), k)?);
        }
        Ok(Self {
            family: Arc::new(Family::Polynomial(coefs)),
            schedule: Arc::new(schedule),
            nu,
            ny,
            y_ref: vec![0.0; ny],
            k: vec![0.0; nu * ny],
            rho: f64::NAN,
        })
    }

    /// `K(ρ)` computed by `gain(ρ, k)` writing the `nu × ny` gain row-major into `k`,
    /// scheduled by `φ`.
    pub fn from_fn<G, F>(nu: usize, ny: usize, gain: G, schedule: F) -> Self
    where
        G: Fn(f64, &mut [f64]) + Send + Sync + 'static,
        F: Fn(&[f64]) -> f64 + Send + Sync + 'static,
    {
        Self {
            family: Arc::new(Family::Closure(Arc::new(gain))),
            schedule: Arc::new(schedule),
            nu,
            ny,
            y_ref: vec![0.0; ny],
            k: vec![0.0; nu * ny],
            rho: f64::NAN,
        }
    }

    /// Regulates to `y_ref`.
    ///
    /// # Errors
    /// [`SimError::DimensionMismatch`], [`SimError::InvalidParameter`].
    pub fn with_reference(mut self, y_ref: &[f64]) -> Result<Self> {
        crate::error::check_finite_vector(
            "scheduled feedback reference",
            "scheduled feedback reference",
            y_ref,
            self.ny,
        )?;
        self.y_ref.copy_from_slice(y_ref);
        Ok(self)
    }

    /// The scheduling variable of the last update (NaN before the first).
    pub fn rho(&self) -> f64 {
        self.rho
    }

    /// The gain `K(ρ)` (`nu × ny`).
    pub fn gain_at(&self, rho: f64) -> Mat {
        let mut k = vec![0.0; self.nu * self.ny];
        eval_family(&self.family, rho, &mut k);
        Mat::from_row_slice(self.nu, self.ny, &k)
    }
}

fn eval_family(family: &Family, rho: f64, k: &mut [f64]) {
    match family {
        Family::Polynomial(coefs) => {
            // Horner: K = (((K_m ρ + K_{m−1}) ρ + …) ρ + K₀.
            k.fill(0.0);
            for c in coefs.iter().rev() {
                for (ki, ci) in k.iter_mut().zip(c) {
                    *ki = *ki * rho + ci;
                }
            }
        }
        Family::Closure(f) => f(rho, k),
    }
}

impl Controller for GainScheduled {
    sizes_from_fields!();
    fn reset(&mut self) {
        self.rho = f64::NAN;
    }
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        self.rho = (self.schedule)(y);
        eval_family(&self.family, self.rho, &mut self.k);
        for (i, ui) in u.iter_mut().enumerate() {
            let row = &self.k[i * self.ny..(i + 1) * self.ny];
            *ui = -row
                .iter()
                .zip(y.iter().zip(&self.y_ref))
                .map(|(k, (yi, ri))| k * (yi - ri))
                .sum::<f64>();
        }
    }
}

type Condition = Arc<dyn Fn(f64, &[f64]) -> bool + Send + Sync>;

/// The active mode of a [`Switching`] controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// The first controller (e.g. swing-up).
    A,
    /// The second controller (e.g. balance).
    B,
}

/// Runs controller `A` until `condition(t, y)` holds at a sample, then controller `B` from that
/// sample on (e.g. swing-up → balance when the pendulum nears the top); optionally back to
/// `A` when `back_when(t, y)` holds. Each switch time is recorded
/// ([`Controller::switch_times`]) and each mode's controller is reset when it takes over.
#[derive(Clone)]
pub struct Switching<A, B> {
    a: A,
    b: B,
    to_b: Condition,
    to_a: Option<Condition>,
    mode: Mode,
    times: Vec<f64>,
}

impl<A, B> std::fmt::Debug for Switching<A, B> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Switching")
            .field("mode", &self.mode)
            .field("switch_times", &self.times)
            .finish_non_exhaustive()
    }
}

impl<A: Controller, B: Controller> Switching<A, B> {
    /// Mode `A` until `condition(t, y)` holds, then `B`.
    ///
    /// # Errors
    /// [`SimError::DimensionMismatch`] unless both controllers have the same `ny` and `nu`;
    /// [`SimError::SampleTimeMismatch`] if both declare different sample times.
    pub fn new<F>(a: A, b: B, condition: F) -> Result<Self>
    where
        F: Fn(f64, &[f64]) -> bool + Send + Sync + 'static,
    {
        check_len("measurements of mode B (as mode A)", b.ny(), a.ny())?;
        check_len("commands of mode B (as mode A)", b.nu(), a.nu())?;
        if let (Some(ta), Some(tb)) = (a.sample_time(), b.sample_time())
            && (ta - tb).abs() > 1e-12 * ta
        {
            return Err(SimError::SampleTimeMismatch {
                controller: tb,
                sampled: ta,
            });
        }
        Ok(Self {
            a,
            b,
            to_b: Arc::new(condition),
            to_a: None,
            mode: Mode::A,
            times: Vec::with_capacity(64),
        })
    }

    /// Also switches back from `B` to `A` when `condition(t, y)` holds.
    pub fn back_when<F>(mut self, condition: F) -> Self
    where
        F: Fn(f64, &[f64]) -> bool + Send + Sync + 'static,
    {
        self.to_a = Some(Arc::new(condition));
        self
    }

    /// The active mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }
    /// Mode A's controller.
    pub fn first(&self) -> &A {
        &self.a
    }
    /// Mode B's controller.
    pub fn second(&self) -> &B {
        &self.b
    }
}

impl<A: Controller, B: Controller> Controller for Switching<A, B> {
    fn ny(&self) -> usize {
        self.a.ny()
    }
    fn nu(&self) -> usize {
        self.a.nu()
    }
    fn sample_time(&self) -> Option<f64> {
        self.a.sample_time().or(self.b.sample_time())
    }
    fn switch_times(&self) -> &[f64] {
        &self.times
    }
    fn reset(&mut self) {
        self.mode = Mode::A;
        self.times.clear();
        self.a.reset();
        self.b.reset();
    }
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        match self.mode {
            Mode::A if (self.to_b)(t, y) => {
                self.mode = Mode::B;
                self.times.push(t);
                self.b.reset();
            }
            Mode::B if self.to_a.as_ref().is_some_and(|c| c(t, y)) => {
                self.mode = Mode::A;
                self.times.push(t);
                self.a.reset();
            }
            _ => {}
        }
        match self.mode {
            Mode::A => self.a.update(t, y, u),
            Mode::B => self.b.update(t, y, u),
        }
    }
}

/// A controller whose commands are clipped to `[lo, hi]` (the controller's own limiter, as
/// opposed to the amplifier's saturation in the [`crate::Actuator`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Saturated<C> {
    inner: C,
    lo: f64,
    hi: f64,
    clipped: usize,
}

impl<C: Controller> Saturated<C> {
    /// Clips every command of `inner` to `[lo, hi]`.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] unless `lo < hi`, both not NaN.
    pub fn new(inner: C, lo: f64, hi: f64) -> Result<Self> {
        if lo.is_nan() || hi.is_nan() || lo >= hi {
            return Err(SimError::InvalidParameter {
                what: "command limits lo".into(),
                value: lo,
                requirement: "must be below hi (neither NaN)",
            });
        }
        Ok(Self {
            inner,
            lo,
            hi,
            clipped: 0,
        })
    }
    /// Number of updates whose command was clipped since the last reset.
    pub fn clipped(&self) -> usize {
        self.clipped
    }
    /// The inner controller.
    pub fn inner(&self) -> &C {
        &self.inner
    }
}

impl<C: Controller> Controller for Saturated<C> {
    fn ny(&self) -> usize {
        self.inner.ny()
    }
    fn nu(&self) -> usize {
        self.inner.nu()
    }
    fn sample_time(&self) -> Option<f64> {
        self.inner.sample_time()
    }
    fn switch_times(&self) -> &[f64] {
        self.inner.switch_times()
    }
    fn reset(&mut self) {
        self.clipped = 0;
        self.inner.reset();
    }
    #[inline]
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        self.inner.update(t, y, u);
        let mut hit = false;
        for v in u.iter_mut() {
            if *v > self.hi {
                *v = self.hi;
                hit = true;
            } else if *v < self.lo {
                *v = self.lo;
                hit = true;
            }
        }
        self.clipped += hit as usize;
    }
}
