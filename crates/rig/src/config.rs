//! Controller files: what `pendulab rig run --controller FILE.toml` runs.
//!
//! ```toml
//! plant = "cart"                # "cart" or "arm"
//! rate_hz = 1000.0              # loop rate (default 1000)
//!
//! [controller]
//! kind = "state-feedback"       # or "lq-servo", "gain-scheduled", "swing-up-balance",
//!                               # "observer", "pid", "nmpc"
//! lqr = { q = [10.0, 10.0, 0.0, 0.0], r = 1.0 }   # design on the upright linearisation …
//! # k = [-3.16, -13.5, -4.48, -2.26]             # … or a library gain, u = −K (y − reference)
//! # k_book = [3.16, 13.5, 4.48, 2.26]            # … or the book's, u = +K_book y
//! reference = [0.0, 0.0, 0.0, 0.0]
//!
//! [safety]                      # all optional; see `safety_for` for the defaults
//! voltage_limit = 5.0           # V, at most the amplifier's range
//! travel_limit = 0.4            # m (cart) or rad (arm)
//! angle_window_deg = 30.0
//! watchdog_periods = 50         # stop after this many periods without a fresh frame
//! stale_hold_periods = 20       # hold the last command this many of them
//! connect_timeout_s = 2.0
//!
//! [estimator]
//! time_constant = 0.02          # pseudo-differentiator s/(T s + 1)
//! ```
//!
//! The `[controller]` table is a [`ControllerSpec`] (`pendulab_control::spec`, re-exported
//! here): its kinds, keys, sign convention (`u = −K y`, the book's `u = +K_book y` written
//! `k_book`) and checks are documented there, and `pendulab_control::spec::build` designs and
//! builds the controller. This module reads the file and checks the rig's own settings; it
//! designs nothing. Each kind accepts only its own keys (plus `kind`): a key of another kind —
//! `k2` in a `state-feedback` table, say — is an error naming the key and the kind, never
//! ignored.
//!
//! ```
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let loaded = pendulab_rig::config::load(
//!     "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk_book = [3.16, 13.5, 4.48, 2.26]\n",
//! )?;
//! assert_eq!((loaded.spec.kind(), loaded.ts), ("state-feedback", 1e-3));
//! // The front end (e.g. `pendulab rig run`) builds the controller from the spec:
//! let built = pendulab_control::spec::build(&loaded.spec, loaded.plant, loaded.ts)?;
//! assert_eq!((built.controller.ny(), built.controller.nu()), (4, 1));
//! # Ok(()) }
//! ```
//!
//! # Valid ranges
//!
//! Every number of the file is checked when it is loaded or built; an error names the key as
//! written in the file, its value and the range. The `[safety]` table is checked by
//! [`Safety::validate_at`] at the file's loop period (one set of ranges for files and programs,
//! documented on [`Safety`]; defaults in [`safety_for`]); the controller's own keys (gains,
//! weights, `step_time`, `switch_deg`, `design_points_deg`) by `pendulab_control::spec::build`;
//! the rest here:
//!
//! | key | range | why |
//! |---|---|---|
//! | `rate_hz` | 10 ([`RATE_HZ_MIN`]) to 50 000 Hz ([`RATE_HZ_MAX`]) | below 10 Hz no pendulum can be balanced; the loop's own capacity is above 5 kHz (docs/rig/README.md), 50 kHz leaves margin |
//! | `estimator.time_constant` | `ts/2` to 0.1 s ([`TIME_CONSTANT_MAX`]), `ts = 1/rate_hz` | see [`time_constant_range`] |
//! | `reference` (state feedback) | `|q₀| < travel_limit`, `|q₁| <` the angle window, velocities finite | a reference at or beyond a limit drives the rig into the safety stop |
//! | `reference` (servo, PID, gain-scheduled servo) | `|r| < travel_limit` | the same |
//!
//! [`ControllerSpec::pendulum_centre`] is the pendulum angle each kind keeps the pendulum
//! about (0 = upright; `π` for `pid`, whose pendulum hangs; the swing-ups end balancing
//! upright); the runtime wraps the measured angle about it.

use crate::emulator::PlantKind;
use crate::runtime::Safety;
use crate::{ConfigError, RigError};
use pendulab_control::spec::DesignWarning;
use pendulab_plants::rig::RigSpec;
use pendulab_plants::spec::PlantSpec;
use serde::Deserialize;
use std::time::Duration;

pub use pendulab_control::spec::{
    ControllerSpec, DURATION_MAX, GainScheduledSpec, GainSpec, LqServoSpec, LqrSpec, NmpcSpec,
    ObserverSpec, PidSpec, SWITCH_DEG_MAX, StateFeedbackSpec, SwingUpBalanceSpec,
};

/// Lowest loop rate `rate_hz` \[Hz\]: the book's pendulums fall over in a few tenths of a
/// second; below 10 Hz a sample-and-hold loop cannot catch them.
pub const RATE_HZ_MIN: f64 = 10.0;
/// Highest loop rate `rate_hz` \[Hz\]: the loop's own work fits above 5 kHz on the project's
/// machine (docs/rig/README.md, "Timing"); 50 kHz leaves a factor of ten for faster machines.
pub const RATE_HZ_MAX: f64 = 50_000.0;
/// Longest pseudo-differentiator time constant `estimator.time_constant` \[s\]: five times the
/// book rigs' 0.02 s. Its corner `1/T` = 10 rad/s is then within a factor of two of the
/// closed-loop poles the book places (−2.5 … −6.5 rad/s, `p1c74_ex1_cdip_ob_design`); a slower
/// estimate lags the pendulum it is meant to catch.
pub const TIME_CONSTANT_MAX: f64 = 0.1;

/// The valid `estimator.time_constant` `T` \[s\] at loop period `ts` \[s\]:
/// `[ts/2, TIME_CONSTANT_MAX]`.
///
/// The runtime realises `s/(T s + 1)` by the Tustin transform,
/// `v_k = α v_{k−1} + β (p_k − p_{k−1})` with `α = (2T − ts)/(2T + ts)`
/// (`pendulab_sim::PseudoDifferentiator`): below `T = ts/2` the pole `α` is negative and the
/// estimate rings from sample to sample; at `T = ts/2` it is the plain difference quotient.
/// The upper end is [`TIME_CONSTANT_MAX`]. (At the lowest rate, 10 Hz, the range is
/// [0.05, 0.1] s.)
pub fn time_constant_range(ts: f64) -> (f64, f64) {
    (ts / 2.0, TIME_CONSTANT_MAX)
}

/// A controller file as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControllerFile {
    /// `"cart"` or `"arm"`.
    pub plant: String,
    /// Loop rate \[Hz\], from [`RATE_HZ_MIN`] to [`RATE_HZ_MAX`] (default 1000).
    pub rate_hz: Option<f64>,
    /// The controller.
    pub controller: ControllerSpec,
    /// Limits.
    #[serde(default)]
    pub safety: SafetySpec,
    /// Velocity estimator.
    #[serde(default)]
    pub estimator: EstimatorSpec,
}

/// The `[safety]` table: the run's limits, each key overriding the rig's own number where the
/// rig has one (`travel_limit` and `angle_window_deg` are `RigSpec`'s, `voltage_limit`
/// defaults to its `input_limit`; one home, `pendulab_plants::RigSpec`, read by
/// [`Safety::from_rig`]). Ranges: [`Safety::validate_at`]; defaults: [`safety_for`].
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SafetySpec {
    /// Clamp \[V\].
    pub voltage_limit: Option<f64>,
    /// Drive travel limit \[m or rad\].
    pub travel_limit: Option<f64>,
    /// Balance window \[°\]; not allowed for `swing-up-balance` (no window: the pendulum
    /// starts hanging).
    pub angle_window_deg: Option<f64>,
    /// Watchdog \[periods\].
    pub watchdog_periods: Option<u32>,
    /// Periods the last command is held without a fresh measurement.
    pub stale_hold_periods: Option<u32>,
    /// Connect timeout \[s\].
    pub connect_timeout_s: Option<f64>,
}

/// The `[estimator]` table.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EstimatorSpec {
    /// Pseudo-differentiator time constant \[s\] (default 0.02), in [`time_constant_range`].
    pub time_constant: Option<f64>,
}

/// A controller file read and checked: the rig's settings and the controller's spec, which a
/// front end turns into a controller with `pendulab_control::spec::build(&spec, plant, ts)`.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The plant.
    pub plant: PlantKind,
    /// Loop period \[s\].
    pub ts: f64,
    /// The `[controller]` table (its references checked against the limits below; its other
    /// keys are checked when it is built).
    pub spec: ControllerSpec,
    /// Limits, checked by [`Safety::validate_at`] at `ts`.
    pub safety: Safety,
    /// The `[safety]` table as written (to apply a command-line override through
    /// [`safety_for`] again).
    pub safety_spec: SafetySpec,
    /// Pseudo-differentiator time constant \[s\].
    pub differentiator_t: f64,
    /// The rig whose limits are the defaults of `[safety]` (the book rig of `plant` for
    /// [`load`], the lab's for [`load_for`]).
    pub rig: RigSpec,
}

impl Loaded {
    /// Replaces `watchdog_periods` (a command-line override), re-deriving the limits from the
    /// file's `[safety]` table by [`safety_for`] so that the same ranges apply (and a
    /// default `stale_hold_periods` stays below the new watchdog).
    ///
    /// # Errors
    /// [`RigError::Config`] as [`safety_for`], naming `safety.watchdog_periods` (or
    /// `safety.stale_hold_periods` if the file's hold no longer fits below it); `self` is
    /// unchanged then.
    pub fn override_watchdog_periods(&mut self, periods: u32) -> Result<(), RigError> {
        let mut spec = self.safety_spec.clone();
        spec.watchdog_periods = Some(periods);
        self.safety = safety_for_rig(
            &self.rig,
            self.plant,
            self.ts,
            &spec,
            self.spec.is_swing_up(),
        )?;
        self.safety_spec = spec;
        Ok(())
    }
}

/// A TOML or serde error as a [`ConfigError::File`]: the line, and for an error inside the
/// `[controller]` table the kind it was read as (so a key of another kind is named with the
/// kind).
fn parse_error(text: &str, e: &toml::de::Error) -> ConfigError {
    let line = e
        .span()
        .map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
    // The file is TOML: find out whether the error is the `[controller]` table's.
    if let Ok(table) = text.parse::<toml::Table>()
        && let Some(c) = table.get("controller")
        && let Err(ce) = c.clone().try_into::<ControllerSpec>()
    {
        let kind = c.get("kind").and_then(|k| k.as_str());
        let message = match kind {
            Some(k) if ControllerSpec::KINDS.contains(&k) => {
                format!("[controller] of kind '{k}': {}", ce.message())
            }
            _ => format!("controller.kind: {}", ce.message()),
        };
        return ConfigError::File { line, message };
    }
    ConfigError::File {
        line: None,
        message: e.to_string(),
    }
}

/// `|x| < limit` for a reference entry, or an error naming it.
fn within(what: &str, x: f64, limit: f64, unit: &str, limit_key: &str) -> Result<(), RigError> {
    if !(x.is_finite() && x.abs() < limit) {
        return Err(ConfigError::invalid(
            what,
            x,
            format!("must be inside ({}, {limit}) {unit} ({limit_key})", -limit),
        )
        .into());
    }
    Ok(())
}

/// The controller's references against the run's limits: `q₀` of either reference strictly
/// inside `safety.travel_limit`, and `q₁` of a state reference inside the angle window (if the
/// run has one). Entries a reference does not have are left to the factory, which refuses a
/// reference of the wrong length.
///
/// # Errors
/// [`ConfigError::Invalid`] naming `controller.reference[i]`, its value and the limit's key.
pub fn check_references(
    spec: &ControllerSpec,
    plant: PlantKind,
    safety: &Safety,
) -> Result<(), RigError> {
    let q0_unit = match plant {
        PlantKind::Cart => "m",
        PlantKind::Arm => "rad",
    };
    let travel = |r: &[f64]| match r.first() {
        Some(&x) => within(
            "controller.reference[0]",
            x,
            safety.travel_limit,
            q0_unit,
            "safety.travel_limit",
        ),
        None => Ok(()),
    };
    match spec {
        ControllerSpec::StateFeedback(c) => {
            let Some(r) = c.reference.as_deref() else {
                return Ok(());
            };
            // The length is the factory's to refuse (before the limits, as it names it).
            if r.len() != 4 {
                return Ok(());
            }
            if let Some((i, x)) = r.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                return Err(ConfigError::invalid(
                    format!("controller.reference[{i}]"),
                    x,
                    "must be finite",
                )
                .into());
            }
            travel(r)?;
            if let Some(w) = safety.angle_window {
                within(
                    "controller.reference[1]",
                    r[1],
                    w,
                    "rad",
                    "safety.angle_window_deg",
                )?;
            }
            Ok(())
        }
        ControllerSpec::LqServo(LqServoSpec { reference, .. })
        | ControllerSpec::Pid(PidSpec { reference, .. })
        | ControllerSpec::GainScheduled(GainScheduledSpec { reference, .. }) => {
            match reference.as_deref() {
                Some(r) if r.len() == 1 => travel(r),
                _ => Ok(()),
            }
        }
        ControllerSpec::SwingUpBalance(_)
        | ControllerSpec::Observer(_)
        | ControllerSpec::Nmpc(_)
        | ControllerSpec::Mpc(_) => Ok(()),
    }
}

/// The run's [`Safety`] from a `[safety]` table, for `plant` at loop period `ts` \[s\], checked
/// by [`Safety::validate_at`] (the ranges live there, shared with every other front end).
///
/// Keys left out take [`Safety::default_for`]'s values, except that the two counts measured
/// in periods keep their default *times* at the loop's rate: `watchdog_periods` defaults to
/// [`Safety::WATCHDOG_DEFAULT_TIME`]` / ts` and `stale_hold_periods` to
/// [`Safety::STALE_HOLD_DEFAULT_TIME`]` / ts` (rounded, at least 1 and 0), the latter also
/// kept below `watchdog_periods` when only the watchdog is given. `swing_up`: the run has no
/// angle window, and giving `angle_window_deg` is an error.
///
/// # Errors
/// [`ConfigError::Invalid`] naming the key (`safety.…`), its value and its range.
pub fn safety_for(
    plant: PlantKind,
    ts: f64,
    s: &SafetySpec,
    swing_up: bool,
) -> Result<Safety, RigError> {
    safety_for_rig(&plant.spec(), plant, ts, s, swing_up)
}

/// [`safety_for`] with the defaults taken from `rig`'s own limits ([`Safety::from_rig`]: a
/// lab's rig file) instead of the book rig's; the ranges are the same
/// ([`Safety::validate_at`] for `plant`).
///
/// # Errors
/// As [`safety_for`].
pub fn safety_for_rig(
    rig: &RigSpec,
    plant: PlantKind,
    ts: f64,
    s: &SafetySpec,
    swing_up: bool,
) -> Result<Safety, RigError> {
    let mut safety = Safety::from_rig(rig);
    let periods = |t: f64| (t / ts).round();
    if let Some(v) = s.voltage_limit {
        safety.voltage_limit = v;
    }
    if let Some(v) = s.travel_limit {
        safety.travel_limit = v;
    }
    if swing_up {
        if let Some(v) = s.angle_window_deg {
            return Err(ConfigError::invalid(
                "safety.angle_window_deg",
                v,
                "must not be given: a swing-up-balance run has no angle window (the pendulum starts hanging); remove the key",
            )
            .into());
        }
        safety.angle_window = None;
    } else if let Some(v) = s.angle_window_deg {
        safety.angle_window = Some(v.to_radians());
    }
    safety.watchdog_periods = match s.watchdog_periods {
        Some(v) => v,
        None => periods(Safety::WATCHDOG_DEFAULT_TIME).max(1.0) as u32,
    };
    safety.stale_hold_periods = match s.stale_hold_periods {
        Some(v) => v,
        None => (periods(Safety::STALE_HOLD_DEFAULT_TIME) as u32)
            .min(safety.watchdog_periods.saturating_sub(1)),
    };
    if let Some(v) = s.connect_timeout_s {
        safety.connect_timeout = Duration::try_from_secs_f64(v).map_err(|_| {
            ConfigError::invalid(
                "safety.connect_timeout_s",
                v,
                format!(
                    "must be in (0, {}] s",
                    Safety::CONNECT_TIMEOUT_MAX.as_secs_f64()
                ),
            )
        })?;
    }
    safety.validate_at(plant, ts)?;
    Ok(safety)
}

/// Parses and checks a controller file: the plant, the loop rate, the `[safety]` and
/// `[estimator]` tables against their documented ranges (module documentation; the
/// `[safety]` table by [`Safety::validate`]), the `[controller]` table's keys against its
/// `kind`, its design record against the file's `plant` (`ControllerSpec::check_kind`: a
/// controller designed for the other plant is refused; the parameters are compared by the
/// front end that knows the plant, `ControllerSpec::check_plant`), and its references
/// against the limits ([`check_references`]). The controller itself
/// is built from [`Loaded::spec`] by `pendulab_control::spec::build`, which checks the rest of
/// the table.
///
/// # Errors
/// [`RigError::Config`]: [`ConfigError::Invalid`] naming the key, its value and what is wrong;
/// [`ConfigError::File`] for TOML syntax errors (with the line) and a key foreign to the
/// controller kind (naming the kind); [`ConfigError::Plant`] for an unknown plant;
/// [`ConfigError::Controller`] for a design record of the other plant.
pub fn load(text: &str) -> Result<Loaded, RigError> {
    let file: ControllerFile = toml::from_str(text).map_err(|e| parse_error(text, &e))?;
    let plant = PlantKind::parse(&file.plant).map_err(ConfigError::from)?;
    load_file(file, plant.spec())
}

/// [`load`] for a lab's plant `lab` (a `PlantSpec`: its parameters and rig): the file's
/// `plant` must be `lab`'s kind, the `[safety]` defaults are `lab`'s rig limits
/// ([`safety_for_rig`]), and the controller's design record is compared with `lab`
/// (`ControllerSpec::check_plant`): the differences it finds (parameters the design did not
/// use) are returned for the front end to print.
///
/// # Errors
/// As [`load`]; [`ConfigError::Invalid`] naming `plant` for a file of the other plant;
/// [`ConfigError::Controller`] for a design record of the other plant kind or a malformed
/// one.
pub fn load_for(text: &str, lab: &PlantSpec) -> Result<(Loaded, Vec<DesignWarning>), RigError> {
    let file: ControllerFile = toml::from_str(text).map_err(|e| parse_error(text, &e))?;
    let plant = PlantKind::parse(&file.plant).map_err(ConfigError::from)?;
    if plant != lab.kind() {
        return Err(ConfigError::invalid(
            "plant",
            format!("\"{}\"", plant.name()),
            format!("must be the lab's plant, \"{}\"", lab.kind().name()),
        )
        .into());
    }
    let warnings = file
        .controller
        .check_plant(lab)
        .map_err(ConfigError::from)?;
    Ok((load_file(file, *lab.rig())?, warnings))
}

/// The checks of [`load`] on a parsed file of `plant`'s, with `rig`'s limits as the safety
/// defaults.
fn load_file(file: ControllerFile, rig: RigSpec) -> Result<Loaded, RigError> {
    let plant = PlantKind::parse(&file.plant).map_err(ConfigError::from)?;
    file.controller
        .check_kind(plant)
        .map_err(ConfigError::from)?;
    let rate = file.rate_hz.unwrap_or(1000.0);
    if !(rate.is_finite() && (RATE_HZ_MIN..=RATE_HZ_MAX).contains(&rate)) {
        return Err(ConfigError::invalid(
            "rate_hz",
            rate,
            format!("must be in [{RATE_HZ_MIN}, {RATE_HZ_MAX}]"),
        )
        .into());
    }
    let ts = 1.0 / rate;
    let spec = file.controller;
    let safety = safety_for_rig(&rig, plant, ts, &file.safety, spec.is_swing_up())?;
    let differentiator_t = file.estimator.time_constant.unwrap_or(0.02);
    let (t_lo, t_hi) = time_constant_range(ts);
    if !(differentiator_t.is_finite() && (t_lo..=t_hi).contains(&differentiator_t)) {
        let default = if file.estimator.time_constant.is_none() {
            " (the default)"
        } else {
            ""
        };
        return Err(ConfigError::invalid(
            "estimator.time_constant",
            format!("{differentiator_t}{default}"),
            format!("must be in [{t_lo}, {t_hi}] s (half the loop period 1/rate_hz, to {TIME_CONSTANT_MAX} s)"),
        )
        .into());
    }
    check_references(&spec, plant, &safety)?;
    Ok(Loaded {
        plant,
        ts,
        spec,
        safety,
        safety_spec: file.safety,
        differentiator_t,
        rig,
    })
}

#[cfg(test)]
mod tests;
