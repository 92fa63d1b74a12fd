//! Controller specifications and the factory that turns one into a running controller.
//!
//! A [`ControllerSpec`] describes a controller for one of the book rigs as plain data
//! (serde: the `[controller]` table of the rig's controller files, `docs/rig/examples/`);
//! [`build_for`] designs what the spec asks for on a plant's own parameters (a
//! [`PlantSpec`]: the book's, identified or the user's), [`build`] on the book plant, and
//! both return a [`Built`]: the
//! `Box<dyn Controller>` the simulator or the rig runtime runs, and what a runtime needs to
//! know about it. Front ends (the CLI's `pendulab rig run`, and the coming ones) read these
//! types; the real-time crate runs the result and designs nothing.
//!
//! # Conventions
//!
//! The controller measures `y = [q₀, q₁, q̇₀, q̇₁]`: the drive position `q₀` (cart position
//! `z` \[m\] or arm angle `θ₁` \[rad\]), the pendulum angle `q₁` \[rad\] from the **upward**
//! vertical, and their rates \[m/s or rad/s\]; it returns the motor voltage `u` \[V\].
//! Gains follow the library's sign, `u = −K y` (as `pendulab_lti::design::StateFeedback`);
//! a gain copied from the book, whose laws read `u = +K_book y`, is written `k_book` and
//! converted by `K = −K_book`.
//!
//! # Kinds and keys
//!
//! The tag is `kind`; each kind accepts only its own keys (plus `kind`): a key of another kind
//! is a deserialisation error naming the key, never ignored.
//!
//! | kind | keys | runs |
//! |---|---|---|
//! | `state-feedback` | one of `k`, `k_book`, `lqr = {q, r}`; `reference` | `StaticStateFeedback` |
//! | `lq-servo` | `k1` + `k2` (library) or `lqr = {q (5 entries), r}`; `reference` (servo output `q₀`), `step_time` | `LqIntegralServo` (forward Euler), `lq_servo` design on `C = [1 0 0 0]` |
//! | `gain-scheduled` | `coefficients = [K₀, K₁, …]` (library sign); or `lqr` + `design_points_deg` (arm); or `x_coefficients` + `l_coefficients` (`K(ρ) = −L(ρ) X(ρ)⁻¹`, the SOS design); `schedule`; `reference`, `step_time` (5-state gains: servo) | `GainScheduled` in `ρ`; with 5-state gains the integral servo on `[y; ∫(r − q₀)]` as `lq-servo` ([`scheduled`]) |
//! | `swing-up-balance` | `balance = { k \| k_book \| lqr }`, `switch_deg` (default 17) | energy shaping ([`crate::swing_up`], gains `EnergyShapingGains::{cart_rig, arm_rig}`), then the balance gain (latched) |
//! | `observer` | one of `k`, `k_book`, `lqr`, `poles`; one of `l`, `observer_poles`; `discretization` | `u = −K x̂`, full-order observer of `[q₀, q₁]`, Tustin or ZOH ([`observer`]) |
//! | `pid` | `form` (`p`, `pd`, `p-d`, `pi`, `pid`, `i-pd`), its gains `kp`, `ki`, `kd`, `tf`; `discretization`, `reference`, `step_time` | `pendulab_sim::controllers::Pid` on `q₀`, pendulum hanging ([`pid`]) |
//! | `nmpc` | `horizon`, `horizon_rate`, `divisions`, `q`, `qf`, `r`, `u_max`, `dummy_weight`, `gmres_iterations`, `zeta` (all optional, the book's) | the arm's C/GMRES swing-up ([`nmpc`]); arm only |
//! | `mpc` | `horizon` (steps), `step`, `q`, `r`, `u_max`, `travel_limit`, `du_max` (all optional) | constrained linear MPC about upright, one QP per period ([`mod@mpc`]) |
//! | every kind | `designed_for` (optional) | the design record ([`DesignRecord`]) |
//!
//! Every kind also takes an optional `designed_for` table, the design record
//! ([`DesignRecord`]: plant kind, parameters with provenance, operating point, sample time,
//! method and inputs). [`build_for`] and `crate::scenario::simulate` refuse a controller whose
//! record names the other plant kind ([`SpecError::WrongPlant`]) and report different
//! parameters as [`DesignWarning`]s ([`ControllerSpec::check_plant`]).
//!
//! The `lqr` designs use `pendulab_lti::design::lqr` (continuous, `u = −K x`) on the plant's
//! upright linearisation (`PlantParameters::linearize_upright`, the arm at `θ₁ₑ = 0`); on the
//! book plant these are the gains of the book's `cdip_lqr_sim` and `adip_lqr_sim`. The
//! energy shaping of `swing-up-balance` uses the plant's parameters too.
//!
//! # Checks made by [`build`]
//!
//! | key | range |
//! |---|---|
//! | gains `k`, `k_book`, `k1`, `k2`, `coefficients`, `lqr.q`, `lqr.r` | finite; 4 entries (`lqr.q` 5 for the servo, `coefficients` 4 or 5); `q ≥ 0`, `r > 0` |
//! | `x_coefficients`, `l_coefficients` | finite; `n × n` symmetric and `n` entries, `n` = 4 or 5; `X₀ ≻ 0` |
//! | `reference` | finite; 4 entries (state feedback) or 1 (servo, 5-state gain-scheduled) |
//! | `step_time` | 0 to [`DURATION_MAX`] s |
//! | `switch_deg` | above 0, at most [`SWITCH_DEG_MAX`] |
//! | `design_points_deg` | finite, two angles with different `|θ₁|`, arm only |
//!
//! Limits that depend on the rig's safety settings (a reference inside the travel limit and
//! the angle window) are checked by the front end that knows them (`pendulab_rig::config`).
//!
//! ```
//! use pendulab_control::spec::{ControllerSpec, StateFeedbackSpec, build};
//! use pendulab_plants::rig::PlantKind;
//! # fn main() -> Result<(), pendulab_control::spec::SpecError> {
//! // The book's cart gain (u = +K_book y) as a spec, built at 1 kHz.
//! let spec = ControllerSpec::StateFeedback(StateFeedbackSpec {
//!     k_book: Some(vec![3.16228, 13.47175, 4.48137, 2.26289]),
//!     ..Default::default()
//! });
//! let mut built = build(&spec, PlantKind::Cart, 1e-3)?;
//! let mut u = [0.0];
//! built.controller.update(0.0, &[0.0, 1.0, 0.0, 0.0], &mut u);
//! assert_eq!(u[0], 13.47175); // u = +K_book y
//! # Ok(()) }
//! ```

use crate::swing_up::{
    ArmEnergyShaping, CartEnergyShaping, EnergyShapingGains, swing_up_then_balance,
};
use pendulab_lti::{Mat, StateSpace};
use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::{PlantParameters, PlantSpec};
use pendulab_plants::{ArmPendulum, CartPendulum};
use pendulab_sim::Controller;
use pendulab_sim::controllers::{IntegrationRule, LqIntegralServo, StaticStateFeedback};
use pendulab_sim::signal::Signal;
use serde::{Deserialize, Serialize};

/// Declares the keys of one `kind`: a struct whose keys are all optional (`Option`, left out
/// of a written file when `None`) and which refuses any key it does not declare
/// (`deny_unknown_fields`, so a key of another kind is an error naming it), with the design
/// record `designed_for` every kind takes last, and `KEYS`, the keys as written in a file in
/// declaration order (read by [`ControllerSpec::KEYS`]). `#[serde(flatten)]` of a common part
/// cannot serve here: serde does not combine it with `deny_unknown_fields`.
macro_rules! kind_keys {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $(
                $(#[$field_meta:meta])*
                pub $field:ident: Option<$ty:ty>,
            )*
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Default, PartialEq, ::serde::Serialize, ::serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            $(
                $(#[$field_meta])*
                #[serde(skip_serializing_if = "Option::is_none")]
                pub $field: Option<$ty>,
            )*
            /// The model the controller was designed on
            /// ([`DesignRecord`](crate::spec::DesignRecord); optional).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub designed_for: Option<$crate::spec::DesignRecord>,
        }

        impl $name {
            /// The keys of this kind's table as written in a file (besides `kind`), in
            /// declaration order, `designed_for` last: any other key is refused when the table
            /// is read.
            pub const KEYS: &[&str] = &[$(stringify!($field),)* "designed_for"];
        }
    };
}

pub mod design;
mod error;
pub mod mpc;
pub mod nmpc;
pub mod observer;
pub mod pid;
mod record;
pub mod scheduled;
pub use error::SpecError;
pub use mpc::MpcSpec;
pub use nmpc::NmpcSpec;
pub use observer::{ObserverDesign, ObserverSpec, observer_design};
pub use pid::{PID_TF_DEFAULT, PidSpec};
pub use record::{DesignInput, DesignRecord, DesignWarning};
pub use scheduled::GainScheduledSpec;

/// Longest run \[s\], and the latest `step_time` of an `lq-servo`: an experiment on the rig lasts
/// seconds to minutes; an hour bounds the log (3.6 million rows at 1 kHz, about 400 MB) and
/// catches a duration typed in milliseconds. (`pendulab_rig::config::DURATION_MAX` is this
/// constant.)
pub const DURATION_MAX: f64 = 3600.0;

/// Largest `switch_deg` \[°\] of `swing-up-balance`: the balance gain is designed on the upright
/// linearisation, and at 45° `sin θ` is already 10 % below `θ` (0.707 against 0.785).
pub const SWITCH_DEG_MAX: f64 = 45.0;

/// Default `switch_deg` \[°\] of `swing-up-balance`.
pub const SWITCH_DEG_DEFAULT: f64 = 17.0;

/// An LQR design request on the book plant's linearisation: `Q = diag(q)`, `R = r`, the
/// continuous-time cost `∫ xᵀQx + uᵀRu dt`, result in library sign `u = −K x`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LqrSpec {
    /// Diagonal of `Q` (finite, ≥ 0): 4 entries for `[q₀, q₁, q̇₀, q̇₁]` (units 1/m², 1/rad², …
    /// so that each term is V²), 5 for the servo's `[x; ∫(r − q₀)]`.
    pub q: Vec<f64>,
    /// `R` \[1/V²\] (finite, > 0).
    pub r: f64,
}

/// A balance gain: exactly one of the three.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GainSpec {
    /// Library gain `K` (`u = −K y`), 4 finite entries \[V/m or V/rad, V·s/m or V·s/rad\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k: Option<Vec<f64>>,
    /// The book's gain `K_book` (`u = +K_book y`, so `K = −K_book`), 4 finite entries.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k_book: Option<Vec<f64>>,
    /// An LQR design on the upright linearisation (`q` of length 4).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lqr: Option<LqrSpec>,
}

/// A controller for one of the book rigs: one variant per `kind`, each with its own keys only
/// (`deny_unknown_fields`: a key of another kind is an error). Measurement
/// `y = [q₀, q₁, q̇₀, q̇₁]`, command `u` \[V\], library sign `u = −K y` (module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum ControllerSpec {
    /// `kind = "state-feedback"`: `u = −K (y − reference)`.
    StateFeedback(StateFeedbackSpec),
    /// `kind = "lq-servo"`: the LQ integral servo on the drive position `q₀`,
    /// `u = −K₁ y − K₂ w`, `w = ∫(r − q₀) dt` (forward Euler at the loop period).
    LqServo(LqServoSpec),
    /// `kind = "gain-scheduled"`: `u = −K(ρ) y`, `K(ρ) = K₀ + K₁ ρ + K₂ ρ² + …` or
    /// `K(ρ) = −L(ρ) X(ρ)⁻¹`; with 5-state gains the integral servo `u = −K(ρ) [y; w]`
    /// ([`scheduled`]).
    GainScheduled(GainScheduledSpec),
    /// `kind = "swing-up-balance"`: energy shaping from the hanging rest, then a balance gain
    /// once `|wrap(q₁)| < switch_deg` (latched).
    SwingUpBalance(SwingUpBalanceSpec),
    /// `kind = "observer"`: `u = −K x̂` with a full-order observer of the encoder positions
    /// ([`observer`]).
    Observer(ObserverSpec),
    /// `kind = "pid"`: the PID family (P, PD, P–D, PI, PID, I–PD) on the drive position, the
    /// pendulum hanging ([`pid`]).
    Pid(PidSpec),
    /// `kind = "nmpc"`: the arm's C/GMRES swing-up ([`nmpc`]).
    Nmpc(NmpcSpec),
    /// `kind = "mpc"`: constrained linear MPC about upright ([`mod@mpc`]).
    Mpc(MpcSpec),
}

impl ControllerSpec {
    /// `kind` of [`ControllerSpec::SwingUpBalance`] as written in a file.
    pub const SWING_UP_BALANCE: &str = "swing-up-balance";
    /// `kind` of [`ControllerSpec::Observer`] as written in a file.
    pub const OBSERVER: &str = "observer";
    /// `kind` of [`ControllerSpec::Pid`] as written in a file.
    pub const PID: &str = "pid";
    /// `kind` of [`ControllerSpec::Nmpc`] as written in a file.
    pub const NMPC: &str = "nmpc";
    /// `kind` of [`ControllerSpec::Mpc`] as written in a file.
    pub const MPC: &str = "mpc";
    /// Every `kind`, as written in a file.
    pub const KINDS: [&str; 8] = [
        "state-feedback",
        "lq-servo",
        "gain-scheduled",
        Self::SWING_UP_BALANCE,
        Self::OBSERVER,
        Self::PID,
        Self::NMPC,
        Self::MPC,
    ];

    /// The keys of each `kind` (besides `kind` itself), as the module documentation lists
    /// them: any other key in a kind's table is refused when it is read.
    pub const KEYS: [(&str, &[&str]); 8] = [
        (Self::KINDS[0], StateFeedbackSpec::KEYS),
        (Self::KINDS[1], LqServoSpec::KEYS),
        (Self::KINDS[2], GainScheduledSpec::KEYS),
        (Self::KINDS[3], SwingUpBalanceSpec::KEYS),
        (Self::KINDS[4], ObserverSpec::KEYS),
        (Self::KINDS[5], PidSpec::KEYS),
        (Self::KINDS[6], NmpcSpec::KEYS),
        (Self::KINDS[7], MpcSpec::KEYS),
    ];

    /// The `kind` as written in a file.
    pub fn kind(&self) -> &'static str {
        match self {
            ControllerSpec::StateFeedback(_) => Self::KINDS[0],
            ControllerSpec::LqServo(_) => Self::KINDS[1],
            ControllerSpec::GainScheduled(_) => Self::KINDS[2],
            ControllerSpec::SwingUpBalance(_) => Self::KINDS[3],
            ControllerSpec::Observer(_) => Self::KINDS[4],
            ControllerSpec::Pid(_) => Self::KINDS[5],
            ControllerSpec::Nmpc(_) => Self::KINDS[6],
            ControllerSpec::Mpc(_) => Self::KINDS[7],
        }
    }

    /// The `designed_for` slot of whichever kind this is.
    fn record_slot_ref(&self) -> &Option<DesignRecord> {
        match self {
            ControllerSpec::StateFeedback(c) => &c.designed_for,
            ControllerSpec::LqServo(c) => &c.designed_for,
            ControllerSpec::GainScheduled(c) => &c.designed_for,
            ControllerSpec::SwingUpBalance(c) => &c.designed_for,
            ControllerSpec::Observer(c) => &c.designed_for,
            ControllerSpec::Pid(c) => &c.designed_for,
            ControllerSpec::Nmpc(c) => &c.designed_for,
            ControllerSpec::Mpc(c) => &c.designed_for,
        }
    }

    /// The `designed_for` slot of whichever kind this is, to set.
    fn record_slot(&mut self) -> &mut Option<DesignRecord> {
        match self {
            ControllerSpec::StateFeedback(c) => &mut c.designed_for,
            ControllerSpec::LqServo(c) => &mut c.designed_for,
            ControllerSpec::GainScheduled(c) => &mut c.designed_for,
            ControllerSpec::SwingUpBalance(c) => &mut c.designed_for,
            ControllerSpec::Observer(c) => &mut c.designed_for,
            ControllerSpec::Pid(c) => &mut c.designed_for,
            ControllerSpec::Nmpc(c) => &mut c.designed_for,
            ControllerSpec::Mpc(c) => &mut c.designed_for,
        }
    }

    /// Whether the controller starts from the hanging rest and swings the pendulum up (then a
    /// run has no balance window on the pendulum angle).
    pub fn is_swing_up(&self) -> bool {
        matches!(
            self,
            ControllerSpec::SwingUpBalance(_) | ControllerSpec::Nmpc(_)
        )
    }

    /// The pendulum angle \[rad\] the controller keeps the pendulum about (0 = upright): `π`
    /// for `pid` (the book's PID family controls the drive with the pendulum hanging, part 1
    /// ch. 2), 0 for every other kind (`swing-up-balance` and `nmpc` swing up to and then
    /// balance upright).
    pub fn pendulum_centre(&self) -> f64 {
        match self {
            ControllerSpec::Pid(_) => std::f64::consts::PI,
            ControllerSpec::StateFeedback(_)
            | ControllerSpec::LqServo(_)
            | ControllerSpec::GainScheduled(_)
            | ControllerSpec::SwingUpBalance(_)
            | ControllerSpec::Observer(_)
            | ControllerSpec::Nmpc(_)
            | ControllerSpec::Mpc(_) => 0.0,
        }
    }
}

kind_keys! {
    /// Keys of `kind = "state-feedback"`: exactly one of `k`, `k_book`, `lqr`.
    pub struct StateFeedbackSpec {
        /// Library gain (`u = −K (y − reference)`), 4 entries.
        pub k: Option<Vec<f64>>,
        /// Book gain (`u = +K_book y`), 4 entries.
        pub k_book: Option<Vec<f64>>,
        /// LQR design (`q` of length 4).
        pub lqr: Option<LqrSpec>,
        /// State reference `[q₀, q₁, q̇₀, q̇₁]` \[m or rad, rad, m/s or rad/s, rad/s\] (default 0).
        pub reference: Option<Vec<f64>>,
    }
}

kind_keys! {
    /// Keys of `kind = "lq-servo"`: `k1` with `k2`, or `lqr`.
    pub struct LqServoSpec {
        /// Servo state gain `K₁` (library sign, 4 entries).
        pub k1: Option<Vec<f64>>,
        /// Servo integral gain `K₂` (library sign: `u = −K₁ y − K₂ w`) \[V/(m·s) or V/(rad·s)\].
        pub k2: Option<f64>,
        /// LQR design on `[x; ∫(r − q₀)]` (`q` of length 5).
        pub lqr: Option<LqrSpec>,
        /// Servo reference of `q₀` (one entry, m or rad, default 0), applied as a step at
        /// `step_time`.
        pub reference: Option<Vec<f64>>,
        /// Time of the reference step \[s\], from 0 to [`DURATION_MAX`] (default 0).
        pub step_time: Option<f64>,
    }
}

kind_keys! {
    /// Keys of `kind = "swing-up-balance"`.
    pub struct SwingUpBalanceSpec {
        /// Balance gain (required).
        pub balance: Option<GainSpec>,
        /// Switch to balance when `|wrap(q₁)|` is below this \[°\], above 0 and at most
        /// [`SWITCH_DEG_MAX`] (default [`SWITCH_DEG_DEFAULT`]).
        pub switch_deg: Option<f64>,
    }
}

/// A controller built from a [`ControllerSpec`], with what a runtime needs to know about it.
pub struct Built {
    /// The controller: 4 measurements `[q₀, q₁, q̇₀, q̇₁]` in, the voltage \[V\] out.
    pub controller: Box<dyn Controller>,
    /// The pendulum angle \[rad\] the controller stabilises ([`ControllerSpec::pendulum_centre`]):
    /// a runtime wraps the measured pendulum angle to within π of it.
    pub pendulum_centre: f64,
    /// The `kind` as written in a file ([`ControllerSpec::kind`]).
    pub kind: &'static str,
    /// Whether it swings up from the hanging rest ([`ControllerSpec::is_swing_up`]): a run has no
    /// balance window then.
    pub swing_up: bool,
}

impl std::fmt::Debug for Built {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Built")
            .field("kind", &self.kind)
            .field("pendulum_centre", &self.pendulum_centre)
            .field("swing_up", &self.swing_up)
            .finish_non_exhaustive()
    }
}

/// Designs and builds the controller `spec` describes for the book rig `plant`, running at
/// loop period `ts` \[s\] (used by the servo's integrator): [`build_for`] on
/// `PlantSpec::book(plant)`.
///
/// `lqr` requests are designed on the book plant (`CartPendulum::book()`,
/// `ArmPendulum::book()`), as the module documentation says; given gains are used as written
/// (`k_book` negated).
///
/// # Errors
/// As [`build_for`].
pub fn build(spec: &ControllerSpec, plant: PlantKind, ts: f64) -> Result<Built, SpecError> {
    build_for(spec, &PlantSpec::book(plant), ts)
}

/// Designs and builds the controller `spec` describes for `plant`, designing on the plant's
/// own parameters (`plant.parameters()`), running at loop period `ts` \[s\].
///
/// # Errors
/// [`SpecError`] naming the key, its value and what is wrong: a design record of the other
/// plant kind or malformed ([`ControllerSpec::check_plant`]; parameter differences are not
/// errors here), a gain or weight of the wrong length or not finite, a negative `q` or non-positive `r`, keys missing or given together,
/// `step_time`/`switch_deg` out of range, a failed design, or `ts` not positive.
pub fn build_for(spec: &ControllerSpec, plant: &PlantSpec, ts: f64) -> Result<Built, SpecError> {
    spec.check_plant(plant)?;
    build_with(spec, plant.parameters(), ts, None)
}

/// [`build_for`] with the drive-position reference `q₀ = r(t)` given as a signal (a
/// scenario's reference) instead of the spec's: the state feedback's reference becomes
/// `[r(t), 0, 0, 0]`, the servo's reference `r(t)`. A spec that has its own `reference` or
/// `step_time`, or a kind without a reference, is refused.
pub(crate) fn build_with(
    spec: &ControllerSpec,
    plant: &PlantParameters,
    ts: f64,
    reference: Option<Signal>,
) -> Result<Built, SpecError> {
    if !(ts.is_finite() && ts > 0.0) {
        return Err(SpecError::SampleTime { ts });
    }
    let controller: Box<dyn Controller> = match (spec, reference) {
        (ControllerSpec::StateFeedback(c), r) => state_feedback(plant, c, r)?,
        (ControllerSpec::LqServo(c), r) => servo(plant, c, ts, r)?,
        (ControllerSpec::GainScheduled(c), r) => scheduled::gain_scheduled(plant, c, ts, r)?,
        (ControllerSpec::SwingUpBalance(c), None) => swing_up_balance(plant, c)?,
        (ControllerSpec::Observer(c), None) => observer::observer(plant, c, ts)?,
        (ControllerSpec::Pid(c), r) => pid::pid(c, ts, r)?,
        (ControllerSpec::Nmpc(c), None) => nmpc::nmpc(plant, c, ts)?,
        (ControllerSpec::Mpc(c), None) => mpc::mpc(plant, c, ts)?,
        (_, Some(_)) => {
            return Err(SpecError::Reference {
                kind: spec.kind(),
                detail: "this kind tracks no reference",
            });
        }
    };
    Ok(Built {
        controller,
        pendulum_centre: spec.pendulum_centre(),
        kind: spec.kind(),
        swing_up: spec.is_swing_up(),
    })
}

fn finite(key: &str, v: &[f64]) -> Result<(), SpecError> {
    if let Some((index, &value)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return Err(SpecError::NotFinite {
            key: key.to_string(),
            index,
            value,
        });
    }
    Ok(())
}

fn row(key: &str, v: &[f64], n: usize) -> Result<Mat, SpecError> {
    if v.len() != n {
        return Err(SpecError::Length {
            key: key.to_string(),
            entries: "entries",
            got: v.len(),
            expected: n,
        });
    }
    finite(key, v)?;
    Ok(Mat::from_row_slice(1, n, v))
}

/// The upright linearisation of the plant (`C = I`; the arm at `θ₁ₑ = 0`).
fn upright(plant: &PlantParameters) -> Result<StateSpace<pendulab_lti::Continuous>, SpecError> {
    plant
        .linearize_upright(0.0)
        .map_err(|source| SpecError::Linearisation {
            at: format!("{} plant", plant.kind().name()),
            source,
        })
}

fn diag(key: &str, q: &[f64], n: usize) -> Result<Mat, SpecError> {
    if q.len() != n {
        return Err(SpecError::Length {
            key: key.to_string(),
            entries: "diagonal entries",
            got: q.len(),
            expected: n,
        });
    }
    finite(key, q)?;
    if let Some((index, &value)) = q.iter().enumerate().find(|(_, x)| **x < 0.0) {
        return Err(SpecError::Negative {
            key: key.to_string(),
            index,
            value,
        });
    }
    Ok(Mat::from_diagonal(&nalgebra::DVector::from_row_slice(q)))
}

fn check_r(key: &str, r: f64) -> Result<Mat, SpecError> {
    if !(r.is_finite() && r > 0.0) {
        return Err(SpecError::InputWeight {
            key: key.to_string(),
            value: r,
        });
    }
    Ok(Mat::from_element(1, 1, r))
}

/// The library gain `K` (1 × 4) of a [`GainSpec`]-like triple under the table `key`.
fn gain(
    plant: &PlantParameters,
    k: &Option<Vec<f64>>,
    k_book: &Option<Vec<f64>>,
    l: &Option<LqrSpec>,
    key: &str,
) -> Result<Mat, SpecError> {
    match (k, k_book, l) {
        (Some(k), None, None) => row(&format!("{key}.k"), k, 4),
        (None, Some(kb), None) => Ok(-row(&format!("{key}.k_book"), kb, 4)?),
        (None, None, Some(l)) => {
            diag(&format!("{key}.lqr.q"), &l.q, 4)?;
            check_r(&format!("{key}.lqr"), l.r)?;
            let d = design::lqr_upright(&upright(plant)?, &l.q, l.r).map_err(|source| {
                SpecError::Design {
                    what: format!("{key}: LQR design"),
                    source,
                }
            })?;
            Ok(d.gain)
        }
        _ => Err(SpecError::Keys {
            key: key.to_string(),
            expected: "give exactly one of k, k_book, lqr",
        }),
    }
}

fn state_feedback(
    plant: &PlantParameters,
    c: &StateFeedbackSpec,
    signal: Option<Signal>,
) -> Result<Box<dyn Controller>, SpecError> {
    let k = gain(plant, &c.k, &c.k_book, &c.lqr, "controller")?;
    if let Some(signal) = signal {
        if c.reference.is_some() {
            return Err(SpecError::Reference {
                kind: ControllerSpec::KINDS[0],
                detail: "give the reference in the scenario or in controller.reference, not both",
            });
        }
        return Ok(Box::new(TrackDrive::new(
            StaticStateFeedback::new(k)?,
            signal,
        )));
    }
    let r = c.reference.clone().unwrap_or(vec![0.0; 4]);
    if r.len() != 4 {
        return Err(SpecError::Length {
            key: "controller.reference".into(),
            entries: "entries",
            got: r.len(),
            expected: 4,
        });
    }
    finite("controller.reference", &r)?;
    Ok(Box::new(StaticStateFeedback::new(k)?.with_reference(&r)?))
}

fn servo(
    plant: &PlantParameters,
    c: &LqServoSpec,
    ts: f64,
    signal: Option<Signal>,
) -> Result<Box<dyn Controller>, SpecError> {
    let c_q0 = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
    let (k1, k2) = match (&c.k1, c.k2, &c.lqr) {
        (Some(k1), Some(k2), None) => {
            finite("controller.k2", &[k2])?;
            (row("controller.k1", k1, 4)?, Mat::from_element(1, 1, k2))
        }
        (None, None, Some(l)) => {
            diag("controller.lqr.q", &l.q, 5)?;
            check_r("controller.lqr", l.r)?;
            let d = design::servo_upright(&upright(plant)?, &l.q, l.r).map_err(|source| {
                SpecError::Design {
                    what: "controller: LQ servo design".into(),
                    source,
                }
            })?;
            // The gain is [K₁ K₂] on [x; w].
            (
                d.gain.columns(0, 4).clone_owned(),
                d.gain.columns(4, 1).clone_owned(),
            )
        }
        _ => {
            return Err(SpecError::Keys {
                key: "controller (lq-servo)".into(),
                expected: "give k1 and k2, or lqr = { q = [5 entries], r }",
            });
        }
    };
    let sig = drive_reference(ControllerSpec::KINDS[1], &c.reference, c.step_time, signal)?;
    Ok(Box::new(LqIntegralServo::new(
        &k1,
        &k2,
        &c_q0,
        vec![sig],
        ts,
        IntegrationRule::ForwardEuler,
    )?))
}

/// The drive-position reference of a `kind` with `reference` (one entry, default 0) and
/// `step_time` (default 0) keys: the scenario's `signal` if given (the spec must then have
/// neither key), else `reference[0]` as a step at `step_time`.
fn drive_reference(
    kind: &'static str,
    reference: &Option<Vec<f64>>,
    step_time: Option<f64>,
    signal: Option<Signal>,
) -> Result<Signal, SpecError> {
    if let Some(s) = signal {
        if reference.is_some() || step_time.is_some() {
            return Err(SpecError::Reference {
                kind,
                detail: "give the reference in the scenario or in controller.reference/step_time, not both",
            });
        }
        return Ok(s);
    }
    let r = reference.clone().unwrap_or(vec![0.0]);
    if r.len() != 1 {
        return Err(SpecError::ServoReferenceLength { kind, got: r.len() });
    }
    finite("controller.reference", &r)?;
    let t_step = step_time.unwrap_or(0.0);
    if !(t_step.is_finite() && (0.0..=DURATION_MAX).contains(&t_step)) {
        return Err(SpecError::OutOfRange {
            key: "controller.step_time",
            value: t_step,
            range: format!("[0, {DURATION_MAX}] s"),
        });
    }
    Signal::step(t_step, r[0]).map_err(|source| SpecError::Step {
        time: t_step,
        source,
    })
}

fn swing_up_balance(
    plant: &PlantParameters,
    c: &SwingUpBalanceSpec,
) -> Result<Box<dyn Controller>, SpecError> {
    let b = c.balance.as_ref().ok_or(SpecError::Keys {
        key: "controller (swing-up-balance)".into(),
        expected: "balance = { … } is missing",
    })?;
    let k = gain(plant, &b.k, &b.k_book, &b.lqr, "controller.balance")?;
    let sw = c.switch_deg.unwrap_or(SWITCH_DEG_DEFAULT);
    if !(sw.is_finite() && sw > 0.0 && sw <= SWITCH_DEG_MAX) {
        return Err(SpecError::OutOfRange {
            key: "controller.switch_deg",
            value: sw,
            range: format!("(0, {SWITCH_DEG_MAX}]"),
        });
    }
    let balance = StaticStateFeedback::new(k)?;
    let windows = vec![(1, sw.to_radians())];
    let model = |source| SpecError::Linearisation {
        at: format!("{} plant", plant.kind().name()),
        source,
    };
    Ok(match plant {
        PlantParameters::Cart(p) => Box::new(swing_up_then_balance(
            CartEnergyShaping::new(
                &CartPendulum::new(*p).map_err(model)?,
                EnergyShapingGains::cart_rig(),
            )?,
            balance,
            windows,
        )?),
        PlantParameters::Arm(p) => Box::new(swing_up_then_balance(
            ArmEnergyShaping::new(
                &ArmPendulum::new(*p).map_err(model)?,
                EnergyShapingGains::arm_rig(),
            )?,
            balance,
            windows,
        )?),
    })
}

/// State feedback that tracks a drive-position signal: `u = −K (y − [r(t), 0, …])`.
struct TrackDrive {
    inner: StaticStateFeedback,
    signal: Signal,
    shifted: Vec<f64>,
}

impl TrackDrive {
    fn new(inner: StaticStateFeedback, signal: Signal) -> Self {
        let ny = inner.ny();
        Self {
            inner,
            signal,
            shifted: vec![0.0; ny],
        }
    }
}

impl Controller for TrackDrive {
    fn ny(&self) -> usize {
        self.inner.ny()
    }
    fn nu(&self) -> usize {
        self.inner.nu()
    }
    fn reset(&mut self) {
        self.inner.reset()
    }
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        self.shifted.copy_from_slice(y);
        self.shifted[0] -= self.signal.value(t);
        self.inner.update(t, &self.shifted, u)
    }
    fn retune(&mut self, gain: &[f64]) -> pendulab_sim::Result<bool> {
        self.inner.retune(gain)
    }
}

#[cfg(test)]
#[path = "spec_tests.rs"]
mod tests;

#[cfg(test)]
mod kinds_tests;
