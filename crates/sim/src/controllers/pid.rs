//! The PID family with discrete realisations.
//!
//! All forms are the two-degree-of-freedom law (Åström & Hägglund, *Advanced PID Control*,
//! 2006, §3.4) on the error `e = r − y` with set-point weights `b`, `c`:
//!
//! ```text
//! U(s) = k_P (b R − Y) + (k_I / s) (R − Y) + k_D s / (T_f s + 1) · (c R − Y)
//! ```
//!
//! | form | `b` | `c` | terms |
//! |---|---|---|---|
//! | P | 1 | – | `k_P` |
//! | PD | 1 | 1 | `k_P`, `k_D` |
//! | P–D (derivative on the output) | 1 | 0 | `k_P`, `k_D` |
//! | PI | 1 | – | `k_P`, `k_I` |
//! | PID | 1 | 1 | all |
//! | I–PD (book §5: P and D on the output) | 0 | 0 | all |
//!
//! Discrete realisations at sample time `ts` ([`PidDiscretization`]), with `s_k = c r_k − y_k`:
//!
//! | | integral `I_k` | filtered derivative `D_k` |
//! |---|---|---|
//! | Tustin | `I_{k−1} + k_I ts (e_k + e_{k−1})/2` | `((2T_f − ts) D_{k−1} + 2 k_D (s_k − s_{k−1}))/(2T_f + ts)` |
//! | backward Euler | `I_{k−1} + k_I ts e_k` | `(T_f D_{k−1} + k_D (s_k − s_{k−1}))/(T_f + ts)` |
//!
//! and `u_k = k_P (b r_k − y_k) + I_k + D_k`: exactly the `c2d` (Tustin or backward Euler) of
//! each continuous term. Start: the integral from zero with `e_{−1} = 0` (the LTI filter at
//! rest), the derivative from rest on its first sample (`s_{−1} = s_0`, so a non-zero initial
//! measurement gives no derivative kick).

use super::check_ts;
use crate::controller::Controller;
use crate::error::{Result, SimError, check_finite, check_len, check_positive};
use crate::signal::Signal;

/// A PID form with its gains (see the module documentation). `T_f` (s) is the time constant
/// of the derivative filter `k_D s/(T_f s + 1)`, `> 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PidForm {
    /// `u = k_P e`.
    P {
        /// Proportional gain.
        kp: f64,
    },
    /// `u = k_P e + k_D s/(T_f s + 1) e`.
    PD {
        /// Proportional gain.
        kp: f64,
        /// Derivative gain.
        kd: f64,
        /// Derivative filter time constant (s).
        tf: f64,
    },
    /// P–D: `u = k_P e − k_D s/(T_f s + 1) y` (derivative on the output).
    PMinusD {
        /// Proportional gain.
        kp: f64,
        /// Derivative gain.
        kd: f64,
        /// Derivative filter time constant (s).
        tf: f64,
    },
    /// `u = k_P e + (k_I/s) e`.
    PI {
        /// Proportional gain.
        kp: f64,
        /// Integral gain (1/s).
        ki: f64,
    },
    /// `u = k_P e + (k_I/s) e + k_D s/(T_f s + 1) e`.
    PID {
        /// Proportional gain.
        kp: f64,
        /// Integral gain (1/s).
        ki: f64,
        /// Derivative gain (s).
        kd: f64,
        /// Derivative filter time constant (s).
        tf: f64,
    },
    /// I–PD: `u = (k_I/s) e − k_P y − k_D s/(T_f s + 1) y`.
    IPD {
        /// Proportional gain.
        kp: f64,
        /// Integral gain (1/s).
        ki: f64,
        /// Derivative gain (s).
        kd: f64,
        /// Derivative filter time constant (s).
        tf: f64,
    },
}

impl PidForm {
    /// `(k_P, k_I, k_D, T_f, b, c)`.
    fn parameters(&self) -> (f64, f64, f64, f64, f64, f64) {
        match *self {
            PidForm::P { kp } => (kp, 0.0, 0.0, 1.0, 1.0, 0.0),
            PidForm::PD { kp, kd, tf } => (kp, 0.0, kd, tf, 1.0, 1.0),
            PidForm::PMinusD { kp, kd, tf } => (kp, 0.0, kd, tf, 1.0, 0.0),
            PidForm::PI { kp, ki } => (kp, ki, 0.0, 1.0, 1.0, 0.0),
            PidForm::PID { kp, ki, kd, tf } => (kp, ki, kd, tf, 1.0, 1.0),
            PidForm::IPD { kp, ki, kd, tf } => (kp, ki, kd, tf, 0.0, 0.0),
        }
    }
}

/// Discretisation of the integral and derivative terms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PidDiscretization {
    /// Bilinear (Tustin) transform.
    #[default]
    Tustin,
    /// Backward Euler `s ← (1 − z⁻¹)/ts`.
    BackwardEuler,
}

/// A discrete PID-family controller acting on one measurement (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Pid {
    form: PidForm,
    disc: PidDiscretization,
    ts: f64,
    reference: Signal,
    index: usize,
    ny: usize,
    kp: f64,
    ki: f64,
    b: f64,
    c: f64,
    // D_k = alpha D_{k−1} + beta (s_k − s_{k−1}); I_k = I_{k−1} + gi_now e_k + gi_prev e_{k−1}.
    alpha: f64,
    beta: f64,
    gi_now: f64,
    gi_prev: f64,
    integral: f64,
    derivative: f64,
    e_prev: f64,
    s_prev: f64,
    started: bool,
}

impl Pid {
    /// The PID `form` at sample time `ts`, acting on `y[0]` of a one-entry measurement with
    /// reference `r = 0` (see [`Pid::reference`], [`Pid::measurement`]).
    ///
    /// # Errors
    /// [`SimError::InvalidSampleTime`]; [`SimError::InvalidParameter`] for non-finite gains
    /// or `T_f ≤ 0`.
    pub fn new(form: PidForm, ts: f64, discretization: PidDiscretization) -> Result<Self> {
        check_ts(ts)?;
        let (kp, ki, kd, tf, b, c) = form.parameters();
        check_finite("k_P", kp)?;
        check_finite("k_I", ki)?;
        check_finite("k_D", kd)?;
        check_positive("derivative filter time constant T_f", tf)?;
        let (alpha, beta, gi_now, gi_prev) = match discretization {
            PidDiscretization::Tustin => (
                (2.0 * tf - ts) / (2.0 * tf + ts),
                2.0 * kd / (2.0 * tf + ts),
                0.5 * ki * ts,
                0.5 * ki * ts,
            ),
            PidDiscretization::BackwardEuler => (tf / (tf + ts), kd / (tf + ts), ki * ts, 0.0),
        };
        Ok(Self {
            form,
            disc: discretization,
            ts,
            reference: Signal::zero(),
            index: 0,
            ny: 1,
            kp,
            ki,
            b,
            c,
            alpha,
            beta,
            gi_now,
            gi_prev,
            integral: 0.0,
            derivative: 0.0,
            e_prev: 0.0,
            s_prev: 0.0,
            started: false,
        })
    }

    /// Sets the reference `r(t)`.
    pub fn reference(mut self, r: Signal) -> Self {
        self.reference = r;
        self
    }

    /// Acts on entry `index` of an `ny`-entry measurement.
    ///
    /// # Errors
    /// [`SimError::InvalidArgument`] if `index ≥ ny`.
    pub fn measurement(mut self, index: usize, ny: usize) -> Result<Self> {
        if index >= ny {
            return Err(SimError::InvalidArgument(format!(
                "PID measurement index {index} is out of range for {ny} measurements"
            )));
        }
        self.index = index;
        self.ny = ny;
        Ok(self)
    }

    /// The form and gains.
    pub fn form(&self) -> PidForm {
        self.form
    }
    /// The discretisation.
    pub fn discretization(&self) -> PidDiscretization {
        self.disc
    }
    /// The integral term `I_k` after the last update.
    pub fn integral_term(&self) -> f64 {
        self.integral
    }
    /// Convenience: a PID on the error alone for a single-entry measurement, checking `y`.
    ///
    /// # Errors
    /// [`SimError::DimensionMismatch`] if `y.len() != ny`.
    pub fn control(&mut self, t: f64, y: &[f64]) -> Result<f64> {
        check_len("PID measurement", y.len(), self.ny)?;
        let mut u = [0.0];
        self.update(t, y, &mut u);
        Ok(u[0])
    }
}

impl Controller for Pid {
    fn ny(&self) -> usize {
        self.ny
    }
    fn nu(&self) -> usize {
        1
    }
    fn sample_time(&self) -> Option<f64> {
        Some(self.ts)
    }
    fn reset(&mut self) {
        self.integral = 0.0;
        self.derivative = 0.0;
        self.e_prev = 0.0;
        self.s_prev = 0.0;
        self.started = false;
    }
    #[inline]
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        let r = self.reference.value(t);
        let yk = y[self.index];
        let e = r - yk;
        let s = self.c * r - yk;
        if !self.started {
            self.s_prev = s;
            self.started = true;
        }
        if self.ki != 0.0 {
            self.integral += self.gi_now * e + self.gi_prev * self.e_prev;
        }
        self.derivative = self.alpha * self.derivative + self.beta * (s - self.s_prev);
        self.e_prev = e;
        self.s_prev = s;
        u[0] = self.kp * (self.b * r - yk) + self.integral + self.derivative;
    }
}
