//! `kind = "pid"`: the PID family on the drive position (book part 1 ch. 2, §2.1–§2.3).
//!
//! The law is `pendulab_sim::controllers::Pid` on the drive position `q₀ = y[0]` of the
//! rig's measurement (cart position `z` \[m\] or arm angle `θ₁` \[rad\]), with the reference
//! `r` a step of `reference` at `step_time`:
//!
//! | `form` | law | gains |
//! |---|---|---|
//! | `"p"` | `u = k_P e` | `kp` |
//! | `"pd"` | `u = k_P e + k_D s/(T_f s + 1) e` | `kp`, `kd` |
//! | `"p-d"` | `u = k_P e − k_D s/(T_f s + 1) q₀` (derivative on the output) | `kp`, `kd` |
//! | `"pi"` | `u = k_P e + (k_I/s) e` | `kp`, `ki` |
//! | `"pid"` | `u = k_P e + (k_I/s) e + k_D s/(T_f s + 1) e` | `kp`, `ki`, `kd` |
//! | `"i-pd"` | `u = (k_I/s) e − k_P q₀ − k_D s/(T_f s + 1) q₀` (book §2.2.4) | `kp`, `ki`, `kd` |
//!
//! with `e = r − q₀`, `u` in volts: the sign is the book's (a positive error drives the cart
//! forward; no sign flip as for state-feedback gains). The continuous law is discretised at the
//! loop period by Tustin (default) or backward Euler, the derivative filtered with
//! `T_f = tf` (default [`PID_TF_DEFAULT`], the rig's pseudo-differentiator). The pendulum is
//! not fed back: these are the book's controllers of the drive with the pendulum **hanging**
//! (the crane of §2.3), so the kind's pendulum centre is `π`.

use super::{ControllerSpec, SpecError, drive_reference, finite};
use pendulab_sim::Controller;
use pendulab_sim::controllers::{Pid, PidDiscretization, PidForm};

/// Default derivative filter time constant `tf` \[s\]: the rig's pseudo-differentiator
/// `s/(0.02 s + 1)` (book part 1 §2.1.2), as the book's chapter 2 simulations use it.
pub const PID_TF_DEFAULT: f64 = 0.02;

kind_keys! {
    /// Keys of `kind = "pid"` (module documentation of [`crate::spec::pid`] for the laws).
    pub struct PidSpec {
        /// The form: `"p"`, `"pd"`, `"p-d"`, `"pi"`, `"pid"` or `"i-pd"` (required).
        pub form: Option<String>,
        /// Proportional gain `k_P` \[V/m or V/rad\] (every form).
        pub kp: Option<f64>,
        /// Integral gain `k_I` \[V/(m·s) or V/(rad·s)\] (`pi`, `pid`, `i-pd` only).
        pub ki: Option<f64>,
        /// Derivative gain `k_D` \[V·s/m or V·s/rad\] (`pd`, `p-d`, `pid`, `i-pd` only).
        pub kd: Option<f64>,
        /// Derivative filter time constant `T_f` \[s\] (finite, > 0; forms with `kd` only;
        /// default [`PID_TF_DEFAULT`]).
        pub tf: Option<f64>,
        /// `"tustin"` (default) or `"backward-euler"`.
        pub discretization: Option<String>,
        /// Reference of `q₀` (one entry, m or rad, default 0), a step at `step_time`.
        pub reference: Option<Vec<f64>>,
        /// Time of the reference step \[s\], 0 to [`super::DURATION_MAX`] (default 0).
        pub step_time: Option<f64>,
    }
}

impl PidSpec {
    /// The `PidForm` the keys describe.
    ///
    /// # Errors
    /// [`SpecError::Keys`] for an unknown or missing `form`, a gain the form needs missing or
    /// one it does not take given; [`SpecError::NotFinite`] / [`SpecError::OutOfRange`] for
    /// a non-finite gain or `tf` not finite and > 0.
    pub fn pid_form(&self) -> Result<PidForm, SpecError> {
        let form = self.form.as_deref().ok_or(SpecError::Keys {
            key: "controller.form".into(),
            expected: "give the PID form: \"p\", \"pd\", \"p-d\", \"pi\", \"pid\" or \"i-pd\"",
        })?;
        // (needs ki, needs kd)
        let (i, d) = match form {
            "p" => (false, false),
            "pd" | "p-d" => (false, true),
            "pi" => (true, false),
            "pid" | "i-pd" => (true, true),
            _ => {
                return Err(SpecError::Keys {
                    key: format!("controller.form = \"{form}\""),
                    expected: "must be \"p\", \"pd\", \"p-d\", \"pi\", \"pid\" or \"i-pd\"",
                });
            }
        };
        let need = |key: &'static str, v: Option<f64>, wanted: bool| -> Result<f64, SpecError> {
            match (v, wanted) {
                (Some(x), true) => {
                    finite(&format!("controller.{key}"), &[x])?;
                    Ok(x)
                }
                (None, false) => Ok(0.0),
                (None, true) => Err(SpecError::Keys {
                    key: format!("controller.{key}"),
                    expected: "is required by this form",
                }),
                (Some(_), false) => Err(SpecError::Keys {
                    key: format!("controller.{key}"),
                    expected: "is not a gain of this form; remove it",
                }),
            }
        };
        let kp = need("kp", self.kp, true)?;
        let ki = need("ki", self.ki, i)?;
        let kd = need("kd", self.kd, d)?;
        let tf = match (self.tf, d) {
            (Some(_), false) => {
                return Err(SpecError::Keys {
                    key: "controller.tf".into(),
                    expected: "applies to forms with a derivative only; remove it",
                });
            }
            (t, _) => t.unwrap_or(PID_TF_DEFAULT),
        };
        if !(tf.is_finite() && tf > 0.0) {
            return Err(SpecError::OutOfRange {
                key: "controller.tf",
                value: tf,
                range: "(0, ∞) s".into(),
            });
        }
        Ok(match form {
            "p" => PidForm::P { kp },
            "pd" => PidForm::PD { kp, kd, tf },
            "p-d" => PidForm::PMinusD { kp, kd, tf },
            "pi" => PidForm::PI { kp, ki },
            "pid" => PidForm::PID { kp, ki, kd, tf },
            _ => PidForm::IPD { kp, ki, kd, tf },
        })
    }

    /// The discretisation the keys describe.
    ///
    /// # Errors
    /// [`SpecError::Keys`] for an unknown `discretization`.
    pub fn pid_discretization(&self) -> Result<PidDiscretization, SpecError> {
        match self.discretization.as_deref() {
            None | Some("tustin") => Ok(PidDiscretization::Tustin),
            Some("backward-euler") => Ok(PidDiscretization::BackwardEuler),
            Some(other) => Err(SpecError::Keys {
                key: format!("controller.discretization = \"{other}\""),
                expected: "must be \"tustin\" or \"backward-euler\"",
            }),
        }
    }
}

/// The PID controller of `c` at loop period `ts` on `y[0]` of the 4-entry measurement, its
/// reference the scenario's `signal` or else the spec's step.
pub(super) fn pid(
    c: &PidSpec,
    ts: f64,
    signal: Option<pendulab_sim::Signal>,
) -> Result<Box<dyn Controller>, SpecError> {
    let form = c.pid_form()?;
    let disc = c.pid_discretization()?;
    let r = drive_reference(ControllerSpec::PID, &c.reference, c.step_time, signal)?;
    Ok(Box::new(
        Pid::new(form, ts, disc)?.reference(r).measurement(0, 4)?,
    ))
}
