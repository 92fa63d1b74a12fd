//! Controller files: what `pendulab rig run --controller FILE.toml` runs.
//!
//! ```toml
//! plant = "cart"                # "cart" or "arm"
//! rate_hz = 1000.0              # loop rate (default 1000)
//!
//! [controller]
//! kind = "state-feedback"       # "state-feedback", "lq-servo", "gain-scheduled", "swing-up-balance"
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
//! Controller kinds (the measurement is `y = [q₀, q₁, q̇₀, q̇₁]`, library sign `u = −K y`).
//! Each kind accepts only its own keys (plus `kind`): a key of another kind — `k2` in a
//! `state-feedback` table, say — is an error naming the key and the kind, never ignored.
//!
//! | kind | keys | runs |
//! |---|---|---|
//! | `state-feedback` | one of `k`, `k_book`, `lqr = {q, r}`; `reference` | [`StaticStateFeedback`] |
//! | `lq-servo` | `k1` + `k2` (library) or `lqr = {q (5 entries), r}`; `reference` (m or rad, servo output `q₀`), `step_time` | [`LqIntegralServo`] (forward Euler), `lq_servo` design on `C = [1 0 0 0]` |
//! | `gain-scheduled` | `coefficients = [K₀, K₁, …]` (library sign), `schedule = "one-minus-cos-q0"` or `"q0-squared"`; or `lqr` + `design_points_deg` (arm) | [`GainScheduled`] polynomial in `ρ` |
//! | `swing-up-balance` | `balance = { k | k_book | lqr }`, `switch_deg` (default 17), swing-up gains of `pendulab_control::swing_up::EnergyShapingGains::{cart_rig, arm_rig}` | energy shaping, then the balance gain (latched) |
//!
//! The `lqr` designs use `pendulab_lti::design::lqr` (continuous, `u = −K x`) on the book
//! plant's upright linearisation (`CartPendulum::book()`, `ArmPendulum::book()` at
//! `θ₁ₑ = 0`): the gains of `cdip_lqr_sim` and `adip_lqr_sim`.
//!
//! # Valid ranges
//!
//! Every number is checked when the file is loaded; an error names the key as written in the
//! file, its value and the range. The `[safety]` table is checked by
//! [`Safety::validate_at`] at the file's loop period (one set of ranges for files and programs,
//! documented on [`Safety`]; defaults in [`safety_for`]); the rest here:
//!
//! | key | range | why |
//! |---|---|---|
//! | `rate_hz` | 10 ([`RATE_HZ_MIN`]) to 50 000 Hz ([`RATE_HZ_MAX`]) | below 10 Hz no pendulum can be balanced; the loop's own capacity is above 5 kHz (docs/rig/README.md), 50 kHz leaves margin |
//! | `estimator.time_constant` | `ts/2` to 0.1 s ([`TIME_CONSTANT_MAX`]), `ts = 1/rate_hz` | see [`time_constant_range`] |
//! | gains `k`, `k_book`, `k1`, `k2`, `coefficients`, `lqr.q`, `lqr.r` | finite; 4 entries (`lqr.q` 5 for the servo); `q ≥ 0`, `r > 0` | |
//! | `reference` (state feedback) | `|q₀| < travel_limit`, `|q₁| <` the angle window, velocities finite | a reference at or beyond a limit drives the rig into the safety stop |
//! | `reference` (servo) | `|r| < travel_limit` | the same |
//! | `step_time` | 0 to 3600 s ([`DURATION_MAX`]) | the longest run `pendulab rig run --duration` accepts |
//! | `switch_deg` | above 0, at most 45° ([`SWITCH_DEG_MAX`]) | the balance gain is designed on the upright linearisation: at 45° `sin θ` is already 10 % below `θ` |
//! | `design_points_deg` | finite, two angles with different `|θ₁|` | |
//!
//! [`Loaded::pendulum_centre`] is the pendulum angle each kind stabilises (0 = upright for all
//! four: the swing-up ends balancing upright); the runtime wraps the measured angle about it.

use crate::RigError;
use crate::emulator::PlantKind;
use crate::runtime::Safety;
use pendulab_control::swing_up::{
    ArmEnergyShaping, CartEnergyShaping, EnergyShapingGains, swing_up_then_balance,
};
use pendulab_lti::design::{lq_servo, lqr};
use pendulab_lti::{Mat, StateSpace};
use pendulab_plants::{ArmEquilibrium, ArmPendulum, CartEquilibrium, CartPendulum};
use pendulab_sim::Controller;
use pendulab_sim::controllers::{
    GainScheduled, IntegrationRule, LqIntegralServo, StaticStateFeedback,
};
use pendulab_sim::signal::Signal;
use serde::Deserialize;
use std::time::Duration;

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
/// Longest run \[s\] (`step_time`, and `--duration` of `pendulab rig run` / `emulate`): an
/// experiment on the rig lasts seconds to minutes; an hour bounds the log (3.6 million rows at
/// 1 kHz, about 400 MB) and catches a duration typed in milliseconds. Longer runs: duration 0
/// (until Ctrl-C).
pub const DURATION_MAX: f64 = 3600.0;
/// Largest `switch_deg` \[°\] of `swing-up-balance`: the balance gain is designed on the upright
/// linearisation, and at 45° `sin θ` is already 10 % below `θ` (0.707 against 0.785).
pub const SWITCH_DEG_MAX: f64 = 45.0;

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

/// An LQR design request: `Q` diagonal, `R` scalar.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LqrSpec {
    /// Diagonal of `Q` (finite, ≥ 0).
    pub q: Vec<f64>,
    /// `R` (finite, > 0).
    pub r: f64,
}

/// A balance gain: exactly one of the three.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GainSpec {
    /// Library gain (`u = −K y`), 4 finite entries.
    pub k: Option<Vec<f64>>,
    /// The book's gain (`u = +K_book y`), 4 finite entries.
    pub k_book: Option<Vec<f64>>,
    /// An LQR design on the upright linearisation (`q` of length 4).
    pub lqr: Option<LqrSpec>,
}

/// The `[controller]` table: one variant per `kind`, each with its own keys only
/// (`deny_unknown_fields`: a key of another kind is an error).
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum ControllerSpec {
    /// `kind = "state-feedback"`: `u = −K (y − reference)`.
    StateFeedback(StateFeedbackSpec),
    /// `kind = "lq-servo"`: the LQ integral servo on the drive position.
    LqServo(LqServoSpec),
    /// `kind = "gain-scheduled"`: a gain polynomial in a scheduling variable.
    GainScheduled(GainScheduledSpec),
    /// `kind = "swing-up-balance"`: energy shaping from the hanging rest, then a balance gain.
    SwingUpBalance(SwingUpBalanceSpec),
}

impl ControllerSpec {
    /// `kind` of [`ControllerSpec::SwingUpBalance`] as written in a file.
    pub const SWING_UP_BALANCE: &str = "swing-up-balance";
    /// Every `kind`, as written in a file.
    pub const KINDS: [&str; 4] = [
        "state-feedback",
        "lq-servo",
        "gain-scheduled",
        Self::SWING_UP_BALANCE,
    ];

    /// The `kind` as written in the file.
    pub fn kind(&self) -> &'static str {
        match self {
            ControllerSpec::StateFeedback(_) => Self::KINDS[0],
            ControllerSpec::LqServo(_) => Self::KINDS[1],
            ControllerSpec::GainScheduled(_) => Self::KINDS[2],
            ControllerSpec::SwingUpBalance(_) => Self::KINDS[3],
        }
    }

    /// The pendulum angle \[rad\] the controller stabilises (0 = upright): 0 for every kind
    /// (`swing-up-balance` swings up to and then balances upright).
    pub fn pendulum_centre(&self) -> f64 {
        match self {
            ControllerSpec::StateFeedback(_)
            | ControllerSpec::LqServo(_)
            | ControllerSpec::GainScheduled(_)
            | ControllerSpec::SwingUpBalance(_) => 0.0,
        }
    }
}

/// Keys of `kind = "state-feedback"`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateFeedbackSpec {
    /// Library gain (`u = −K (y − reference)`).
    pub k: Option<Vec<f64>>,
    /// Book gain (`u = +K_book y`).
    pub k_book: Option<Vec<f64>>,
    /// LQR design (`q` of length 4).
    pub lqr: Option<LqrSpec>,
    /// State reference `[q₀, q₁, q̇₀, q̇₁]` (default 0): `|q₀| < travel_limit`, `|q₁|` inside
    /// the angle window.
    pub reference: Option<Vec<f64>>,
}

/// Keys of `kind = "lq-servo"`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LqServoSpec {
    /// Servo state gain `K₁` (library sign).
    pub k1: Option<Vec<f64>>,
    /// Servo integral gain `K₂` (library sign).
    pub k2: Option<f64>,
    /// LQR design on `[x; ∫(r − q₀)]` (`q` of length 5).
    pub lqr: Option<LqrSpec>,
    /// Servo reference of `q₀` (one entry, m or rad, default 0): `|r| < travel_limit`.
    pub reference: Option<Vec<f64>>,
    /// Time of the reference step \[s\], from 0 to [`DURATION_MAX`] (default 0).
    pub step_time: Option<f64>,
}

/// Keys of `kind = "gain-scheduled"`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GainScheduledSpec {
    /// Gain-polynomial coefficients `K₀, K₁, …` (library sign).
    pub coefficients: Option<Vec<Vec<f64>>>,
    /// Scheduling variable: `"one-minus-cos-q0"` (default) or `"q0-squared"`.
    pub schedule: Option<String>,
    /// LQR design at each of `design_points_deg`.
    pub lqr: Option<LqrSpec>,
    /// Arm angles \[°\] of two LQR designs interpolated linearly in `ρ = 1 − cos θ₁`.
    pub design_points_deg: Option<Vec<f64>>,
}

/// Keys of `kind = "swing-up-balance"`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SwingUpBalanceSpec {
    /// Balance gain.
    pub balance: Option<GainSpec>,
    /// Switch to balance when `|wrap(q₁)|` is below this \[°\], above 0 and at most
    /// [`SWITCH_DEG_MAX`] (default 17).
    pub switch_deg: Option<f64>,
}

/// The `[safety]` table; ranges: [`Safety::validate_at`], defaults: [`safety_for`].
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

/// A controller ready to run, with the settings of its file.
pub struct Loaded {
    /// The plant.
    pub plant: PlantKind,
    /// Loop period \[s\].
    pub ts: f64,
    /// The controller.
    pub controller: Box<dyn Controller>,
    /// Limits, checked by [`Safety::validate_at`] at `ts`.
    pub safety: Safety,
    /// The `[safety]` table as written (to apply a command-line override through
    /// [`safety_for`] again).
    pub safety_spec: SafetySpec,
    /// Pseudo-differentiator time constant \[s\].
    pub differentiator_t: f64,
    /// The pendulum angle \[rad\] the controller stabilises (0 = upright;
    /// [`ControllerSpec::pendulum_centre`]): the runtime wraps the measured pendulum angle
    /// to within π of it before the controller and the angle window see it.
    pub pendulum_centre: f64,
    /// The controller kind (for messages).
    pub kind: String,
}

impl std::fmt::Debug for Loaded {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Loaded")
            .field("plant", &self.plant)
            .field("ts", &self.ts)
            .field("kind", &self.kind)
            .field("safety", &self.safety)
            .field("differentiator_t", &self.differentiator_t)
            .field("pendulum_centre", &self.pendulum_centre)
            .finish_non_exhaustive()
    }
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
        let swing_up = self.kind == ControllerSpec::SWING_UP_BALANCE;
        self.safety = safety_for(self.plant, self.ts, &spec, swing_up)?;
        self.safety_spec = spec;
        Ok(())
    }
}

fn cfg(msg: impl Into<String>) -> RigError {
    RigError::Config(msg.into())
}

fn finite(what: &str, v: &[f64]) -> Result<(), RigError> {
    if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return Err(cfg(format!("{what}[{i}] = {x}: must be finite")));
    }
    Ok(())
}

fn row(what: &str, v: &[f64], n: usize) -> Result<Mat, RigError> {
    if v.len() != n {
        return Err(cfg(format!("{what} has {} entries, expected {n}", v.len())));
    }
    finite(what, v)?;
    Ok(Mat::from_row_slice(1, n, v))
}

/// The upright linearisation of the book plant (`C = I`).
fn upright(plant: PlantKind) -> Result<StateSpace<pendulab_lti::Continuous>, RigError> {
    match plant {
        PlantKind::Cart => CartPendulum::book().linearize(CartEquilibrium::upright()),
        PlantKind::Arm => ArmPendulum::book().linearize(ArmEquilibrium::upright(0.0)),
    }
    .map_err(|e| cfg(format!("linearising the {} plant: {e}", plant.name())))
}

fn diag(what: &str, q: &[f64], n: usize) -> Result<Mat, RigError> {
    if q.len() != n {
        return Err(cfg(format!(
            "{what} has {} diagonal entries, expected {n}",
            q.len()
        )));
    }
    finite(what, q)?;
    if let Some((i, x)) = q.iter().enumerate().find(|(_, x)| **x < 0.0) {
        return Err(cfg(format!("{what}[{i}] = {x}: must be ≥ 0")));
    }
    Ok(Mat::from_diagonal(&nalgebra::DVector::from_row_slice(q)))
}

fn check_r(what: &str, r: f64) -> Result<Mat, RigError> {
    if !(r.is_finite() && r > 0.0) {
        return Err(cfg(format!("{what}.r = {r}: must be finite and > 0")));
    }
    Ok(Mat::from_element(1, 1, r))
}

/// The library gain `K` (1 × 4) of a [`GainSpec`]-like triple.
fn gain(
    plant: PlantKind,
    k: &Option<Vec<f64>>,
    k_book: &Option<Vec<f64>>,
    l: &Option<LqrSpec>,
    what: &str,
) -> Result<Mat, RigError> {
    match (k, k_book, l) {
        (Some(k), None, None) => row(&format!("{what}.k"), k, 4),
        (None, Some(kb), None) => Ok(-row(&format!("{what}.k_book"), kb, 4)?),
        (None, None, Some(l)) => {
            let sys = upright(plant)?;
            let d = lqr(
                &sys,
                &diag(&format!("{what}.lqr.q"), &l.q, 4)?,
                &check_r(&format!("{what}.lqr"), l.r)?,
                None,
            )
            .map_err(|e| cfg(format!("{what}: LQR design failed: {e}")))?;
            Ok(d.gain)
        }
        _ => Err(cfg(format!("{what}: give exactly one of k, k_book, lqr"))),
    }
}

/// Two LQR designs of the arm at `θ₁ₑ = a, b` (degrees), joined by the line in `ρ = 1 − cos θ₁`
/// through both: `K(ρ) = K_a + (ρ − ρ_a)/(ρ_b − ρ_a)·(K_b − K_a)` as coefficients `[K₀, K₁]`.
fn scheduled_lqr(
    plant: PlantKind,
    l: &LqrSpec,
    pts: &[f64],
    schedule: Option<&str>,
) -> Result<Vec<Mat>, RigError> {
    if plant != PlantKind::Arm {
        return Err(cfg(
            "controller.design_points_deg: only the arm's linearisation depends on the drive position",
        ));
    }
    if schedule.is_some_and(|s| s != "one-minus-cos-q0") {
        return Err(cfg(
            "controller.design_points_deg interpolates in one-minus-cos-q0 only",
        ));
    }
    finite("controller.design_points_deg", pts)?;
    let rho = |deg: f64| 1.0 - deg.to_radians().cos();
    if pts.len() != 2 || (rho(pts[0]) - rho(pts[1])).abs() < 1e-6 {
        return Err(cfg(format!(
            "controller.design_points_deg = {pts:?}: give two angles with different |θ₁|"
        )));
    }
    let q = diag("controller.lqr.q", &l.q, 4)?;
    let r = check_r("controller.lqr", l.r)?;
    let mut k = Vec::new();
    for &deg in pts {
        let sys = ArmPendulum::book()
            .linearize(ArmEquilibrium::upright(deg.to_radians()))
            .map_err(|e| cfg(format!("linearising the arm at {deg}°: {e}")))?;
        k.push(
            lqr(&sys, &q, &r, None)
                .map_err(|e| cfg(format!("LQR design at θ₁ = {deg}° failed: {e}")))?
                .gain,
        );
    }
    let (ra, rb) = (rho(pts[0]), rho(pts[1]));
    let k1 = (&k[1] - &k[0]) / (rb - ra);
    let k0 = &k[0] - &k1 * ra;
    Ok(vec![k0, k1])
}

/// A TOML or serde error as a message: the line, and for an error inside the `[controller]`
/// table the kind it was read as (so a key of another kind is named with the kind).
fn parse_error(text: &str, e: &toml::de::Error) -> RigError {
    let line = e
        .span()
        .map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
    // The file is TOML: find out whether the error is the `[controller]` table's.
    if let Ok(table) = text.parse::<toml::Table>()
        && let Some(c) = table.get("controller")
        && let Err(ce) = c.clone().try_into::<ControllerSpec>()
    {
        let at = line.map(|l| format!(", line {l}")).unwrap_or_default();
        let kind = c.get("kind").and_then(|k| k.as_str());
        return match kind {
            Some(k) if ControllerSpec::KINDS.contains(&k) => cfg(format!(
                "controller file{at}: [controller] of kind '{k}': {}",
                ce.message()
            )),
            _ => cfg(format!(
                "controller file{at}: controller.kind: {}",
                ce.message()
            )),
        };
    }
    cfg(format!("controller file: {e}"))
}

/// `|x| < limit` for a reference entry, or an error naming it.
fn within(what: &str, x: f64, limit: f64, unit: &str, limit_key: &str) -> Result<(), RigError> {
    if !(x.is_finite() && x.abs() < limit) {
        return Err(cfg(format!(
            "{what} = {x}: must be inside ({}, {limit}) {unit} ({limit_key})",
            -limit
        )));
    }
    Ok(())
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
/// [`RigError::Config`] naming the key (`safety.…`), its value and its range.
pub fn safety_for(
    plant: PlantKind,
    ts: f64,
    s: &SafetySpec,
    swing_up: bool,
) -> Result<Safety, RigError> {
    let mut safety = Safety::default_for(plant);
    let periods = |t: f64| (t / ts).round();
    if let Some(v) = s.voltage_limit {
        safety.voltage_limit = v;
    }
    if let Some(v) = s.travel_limit {
        safety.travel_limit = v;
    }
    if swing_up {
        if let Some(v) = s.angle_window_deg {
            return Err(cfg(format!(
                "safety.angle_window_deg = {v}: a swing-up-balance run has no angle window (the pendulum starts hanging); remove the key"
            )));
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
            cfg(format!(
                "safety.connect_timeout_s = {v}: must be in (0, {}] s",
                Safety::CONNECT_TIMEOUT_MAX.as_secs_f64()
            ))
        })?;
    }
    safety.validate_at(plant, ts)?;
    Ok(safety)
}

/// Parses, checks and builds a controller file.
///
/// Every key is checked against its documented range (module documentation; the `[safety]`
/// table by [`Safety::validate`]), and the `[controller]` table may hold only the keys of its
/// `kind`.
///
/// # Errors
/// [`RigError::Config`] naming the key, its value and what is wrong (TOML syntax errors carry
/// the line; a key foreign to the controller kind names the kind).
pub fn load(text: &str) -> Result<Loaded, RigError> {
    let file: ControllerFile = toml::from_str(text).map_err(|e| parse_error(text, &e))?;
    let plant = PlantKind::parse(&file.plant)?;
    let rate = file.rate_hz.unwrap_or(1000.0);
    if !(rate.is_finite() && (RATE_HZ_MIN..=RATE_HZ_MAX).contains(&rate)) {
        return Err(cfg(format!(
            "rate_hz = {rate}: must be in [{RATE_HZ_MIN}, {RATE_HZ_MAX}]"
        )));
    }
    let ts = 1.0 / rate;
    let c = &file.controller;
    let swing_up = matches!(c, ControllerSpec::SwingUpBalance(_));
    let safety = safety_for(plant, ts, &file.safety, swing_up)?;
    let differentiator_t = file.estimator.time_constant.unwrap_or(0.02);
    let (t_lo, t_hi) = time_constant_range(ts);
    if !(differentiator_t.is_finite() && (t_lo..=t_hi).contains(&differentiator_t)) {
        return Err(cfg(format!(
            "estimator.time_constant = {differentiator_t}{}: must be in [{t_lo}, {t_hi}] s (half the loop period 1/rate_hz, to {TIME_CONSTANT_MAX} s)",
            if file.estimator.time_constant.is_none() {
                " (the default)"
            } else {
                ""
            }
        )));
    }
    let travel = safety.travel_limit;
    let q0_unit = match plant {
        PlantKind::Cart => "m",
        PlantKind::Arm => "rad",
    };

    let controller: Box<dyn Controller> = match c {
        ControllerSpec::StateFeedback(c) => {
            let k = gain(plant, &c.k, &c.k_book, &c.lqr, "controller")?;
            let r = c.reference.clone().unwrap_or(vec![0.0; 4]);
            if r.len() != 4 {
                return Err(cfg(format!(
                    "controller.reference has {} entries, expected 4",
                    r.len()
                )));
            }
            finite("controller.reference", &r)?;
            within(
                "controller.reference[0]",
                r[0],
                travel,
                q0_unit,
                "safety.travel_limit",
            )?;
            if let Some(w) = safety.angle_window {
                within(
                    "controller.reference[1]",
                    r[1],
                    w,
                    "rad",
                    "safety.angle_window_deg",
                )?;
            }
            Box::new(
                StaticStateFeedback::new(k)
                    .and_then(|f| f.with_reference(&r))
                    .map_err(|e| cfg(format!("controller: {e}")))?,
            )
        }
        ControllerSpec::LqServo(c) => {
            let (k1, k2) = match (&c.k1, c.k2, &c.lqr) {
                (Some(k1), Some(k2), None) => {
                    finite("controller.k2", &[k2])?;
                    (row("controller.k1", k1, 4)?, Mat::from_element(1, 1, k2))
                }
                (None, None, Some(l)) => {
                    let lin = upright(plant)?;
                    let cs = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
                    let sys = StateSpace::continuous(
                        lin.a().clone(),
                        lin.b().clone(),
                        cs,
                        Mat::zeros(1, 1),
                    )
                    .map_err(|e| cfg(format!("servo model: {e}")))?;
                    let d = lq_servo(
                        &sys,
                        &diag("controller.lqr.q", &l.q, 5)?,
                        &check_r("controller.lqr", l.r)?,
                    )
                    .map_err(|e| cfg(format!("controller: LQ servo design failed: {e}")))?;
                    (d.state_gain, d.integral_gain)
                }
                _ => {
                    return Err(cfg(
                        "controller (lq-servo): give k1 and k2, or lqr = { q = [5 entries], r }",
                    ));
                }
            };
            let r = c.reference.clone().unwrap_or(vec![0.0]);
            if r.len() != 1 {
                return Err(cfg(format!(
                    "controller.reference of an lq-servo is one value (of q0), got {}",
                    r.len()
                )));
            }
            within(
                "controller.reference[0]",
                r[0],
                travel,
                q0_unit,
                "safety.travel_limit",
            )?;
            let t_step = c.step_time.unwrap_or(0.0);
            if !(t_step.is_finite() && (0.0..=DURATION_MAX).contains(&t_step)) {
                return Err(cfg(format!(
                    "controller.step_time = {t_step}: must be in [0, {DURATION_MAX}] s"
                )));
            }
            let sig = Signal::step(t_step, r[0])
                .map_err(|e| cfg(format!("controller.step_time = {t_step}: {e}")))?;
            Box::new(
                LqIntegralServo::new(
                    &k1,
                    &k2,
                    &Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]),
                    vec![sig],
                    ts,
                    IntegrationRule::ForwardEuler,
                )
                .map_err(|e| cfg(format!("controller: {e}")))?,
            )
        }
        ControllerSpec::GainScheduled(c) => {
            let mats = match (&c.coefficients, &c.lqr, &c.design_points_deg) {
                (Some(coefs), None, None) => {
                    if coefs.is_empty() {
                        return Err(cfg("controller.coefficients: give at least K0"));
                    }
                    coefs
                        .iter()
                        .enumerate()
                        .map(|(i, k)| row(&format!("controller.coefficients[{i}]"), k, 4))
                        .collect::<Result<Vec<_>, _>>()?
                }
                (None, Some(l), Some(pts)) => scheduled_lqr(plant, l, pts, c.schedule.as_deref())?,
                _ => {
                    return Err(cfg(
                        "controller (gain-scheduled): give coefficients, or lqr with design_points_deg (arm)",
                    ));
                }
            };
            let sched = c.schedule.as_deref().unwrap_or("one-minus-cos-q0");
            let g = match sched {
                "one-minus-cos-q0" => GainScheduled::polynomial(&mats, |y| 1.0 - y[0].cos()),
                "q0-squared" => GainScheduled::polynomial(&mats, |y| y[0] * y[0]),
                other => {
                    return Err(cfg(format!(
                        "controller.schedule = '{other}': expected 'one-minus-cos-q0' or 'q0-squared'"
                    )));
                }
            }
            .map_err(|e| cfg(format!("controller: {e}")))?;
            Box::new(g)
        }
        ControllerSpec::SwingUpBalance(c) => {
            let b = c
                .balance
                .as_ref()
                .ok_or_else(|| cfg("controller (swing-up-balance): balance = { … } is missing"))?;
            let k = gain(plant, &b.k, &b.k_book, &b.lqr, "controller.balance")?;
            let sw = c.switch_deg.unwrap_or(17.0);
            if !(sw.is_finite() && sw > 0.0 && sw <= SWITCH_DEG_MAX) {
                return Err(cfg(format!(
                    "controller.switch_deg = {sw}: must be in (0, {SWITCH_DEG_MAX}]"
                )));
            }
            let balance =
                StaticStateFeedback::new(k).map_err(|e| cfg(format!("controller: {e}")))?;
            let windows = vec![(1, sw.to_radians())];
            match plant {
                PlantKind::Cart => Box::new(
                    CartEnergyShaping::new(&CartPendulum::book(), EnergyShapingGains::cart_rig())
                        .and_then(|s| swing_up_then_balance(s, balance, windows))
                        .map_err(|e| cfg(format!("controller: {e}")))?,
                ),
                PlantKind::Arm => Box::new(
                    ArmEnergyShaping::new(&ArmPendulum::book(), EnergyShapingGains::arm_rig())
                        .and_then(|s| swing_up_then_balance(s, balance, windows))
                        .map_err(|e| cfg(format!("controller: {e}")))?,
                ),
            }
        }
    };
    Ok(Loaded {
        plant,
        ts,
        controller,
        safety,
        safety_spec: file.safety.clone(),
        differentiator_t,
        pendulum_centre: c.pendulum_centre(),
        kind: c.kind().to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const SF: &str =
        "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0, 1.0, 1.0, 1.0]\n";

    #[test]
    fn cart_lqr_design_reproduces_the_book_gain() {
        // examples.md, cdip_lqr_sim: Q = diag(10, 10, 0, 0), R = 1 gives
        // K_book = [3.16228, 13.47175, 4.48137, 2.26289]; u = +K_book x means the library's
        // u = −K x has K = −K_book. The printed digits bound the agreement (5e-5).
        let l = load(
            "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [10.0, 10.0, 0.0, 0.0], r = 1.0 }\n",
        )
        .unwrap();
        let mut u = [0.0];
        let mut c = l.controller;
        let kb = [3.16228, 13.47175, 4.48137, 2.26289];
        for i in 0..4 {
            let mut y = [0.0; 4];
            y[i] = 1.0;
            c.update(0.0, &y, &mut u);
            assert!((u[0] - kb[i]).abs() < 5e-5, "K[{i}] = {}", u[0]);
        }
        assert_eq!(l.safety.angle_window, Some(30f64.to_radians()));
    }

    #[test]
    fn cart_lq_servo_design_reproduces_the_book_gains() {
        // examples.md, cdip_lqr_servo_sim: Q = diag(1, 5, 0, 0, 100), R = 1 gives
        // K1_book = [10.39942, 17.76307, 6.79089, 3.04513], K2_book = −10 (u = K1 x + K2 w,
        // w = ∫(r − z)). At rest with y = e_i and r = 0 the first command is +K1_book·e_i
        // (forward Euler: w is still 0). Printed digits bound the agreement (5e-5).
        let text = "plant = \"cart\"\n[controller]\nkind = \"lq-servo\"\nlqr = { q = [1.0, 5.0, 0.0, 0.0, 100.0], r = 1.0 }\nreference = [0.0]\n";
        let k1b = [10.39942, 17.76307, 6.79089, 3.04513];
        for i in 0..4 {
            let mut c = load(text).unwrap().controller;
            let mut y = [0.0; 4];
            y[i] = 1.0;
            let mut u = [0.0];
            c.update(0.0, &y, &mut u);
            assert!((u[0] - k1b[i]).abs() < 5e-5, "K1[{i}] = {}", u[0]);
        }
        // Integral gain: with y = 0 and r = 0.1, w = 0.1·ts after the first period and
        // u = K2_book · w = −10 · 1e-4 at the second.
        let mut c = load(&text.replace("[0.0]", "[0.1]")).unwrap().controller;
        let mut u = [0.0];
        c.update(0.0, &[0.0; 4], &mut u);
        assert_eq!(u[0], 0.0);
        c.update(1e-3, &[0.0; 4], &mut u);
        assert!((u[0] - (-10.0 * 1e-4)).abs() < 5e-9, "{}", u[0]);
    }

    #[test]
    fn bad_files_are_typed_errors_naming_the_key() {
        let cases = [
            (
                "plant = \"boat\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\n",
                "boat",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0]\n",
                "controller.k",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"nope\"\n",
                "controller.kind",
            ),
            ("plant = \"cart\"\n[controller]\nk = [1.0]\n", "kind"),
            (
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\n",
                "exactly one",
            ),
            (
                "plant = \"cart\"\nrate_hz = -1.0\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\n",
                "rate_hz",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\n[safety]\nvoltage_limit = 0.0\n",
                "voltage_limit",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [1.0, -1.0, 0.0, 0.0], r = 1.0 }\n",
                "lqr.q[1]",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [1.0, 1.0, 0.0, 0.0], r = nan }\n",
                "lqr.r",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\ntypo = 3\n",
                "typo",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\n[safety]\nwatchdog = 3\n",
                "watchdog",
            ),
            ("plant = \"cart\"\n[controller\n", "controller file"),
        ];
        for (text, needle) in cases {
            let e = load(text).unwrap_err().to_string();
            assert!(e.contains(needle), "{e:?} should mention {needle:?}");
        }
    }

    /// The keys of each kind, as the module documentation lists them.
    const KEYS: [(&str, &[&str]); 4] = [
        ("state-feedback", &["k", "k_book", "lqr", "reference"]),
        ("lq-servo", &["k1", "k2", "lqr", "reference", "step_time"]),
        (
            "gain-scheduled",
            &["coefficients", "schedule", "lqr", "design_points_deg"],
        ),
        ("swing-up-balance", &["balance", "switch_deg"]),
    ];

    /// A file of each kind that loads, for the plant given.
    fn base(kind: &str) -> String {
        let body = match kind {
            "state-feedback" => "k = [0.0, 0.0, 0.0, 0.0]\n",
            "lq-servo" => "k1 = [0.0, 0.0, 0.0, 0.0]\nk2 = 0.0\n",
            "gain-scheduled" => "coefficients = [[0.0, 0.0, 0.0, 0.0]]\n",
            "swing-up-balance" => "balance = { k = [0.0, 0.0, 0.0, 0.0] }\n",
            _ => unreachable!(),
        };
        format!("plant = \"cart\"\n[controller]\nkind = \"{kind}\"\n{body}")
    }

    #[test]
    fn a_key_of_another_kind_is_an_error_naming_the_key_and_the_kind() {
        // The finding: `k2 = nan` in a state-feedback table was ignored.
        let e = load(&format!("{}k2 = nan\n", base("state-feedback")))
            .unwrap_err()
            .to_string();
        assert!(e.contains("k2") && e.contains("state-feedback"), "{e}");
        // Every key of every other kind, with a value of the type its own kind reads (so the
        // only thing wrong is where it is).
        let value = |key: &str| match key {
            "k" | "k_book" | "k1" | "reference" | "design_points_deg" => "[0.0, 0.0, 0.0, 0.0]",
            "k2" | "step_time" | "switch_deg" => "1.0",
            "lqr" => "{ q = [1.0, 1.0, 0.0, 0.0], r = 1.0 }",
            "coefficients" => "[[0.0, 0.0, 0.0, 0.0]]",
            "schedule" => "\"q0-squared\"",
            "balance" => "{ k = [0.0, 0.0, 0.0, 0.0] }",
            _ => unreachable!("{key}"),
        };
        let mut rejected = 0;
        for (kind, own) in KEYS {
            load(&base(kind)).unwrap_or_else(|e| panic!("{kind}: {e}"));
            for (_, other) in KEYS {
                for key in other.iter().filter(|k| !own.contains(k)) {
                    let text = format!("{}{key} = {}\n", base(kind), value(key));
                    let e = load(&text).unwrap_err().to_string();
                    assert!(
                        e.contains(&format!("`{key}`")) && e.contains(kind),
                        "{kind} + {key}: {e}"
                    );
                    rejected += 1;
                }
            }
        }
        // Foreign keys per kind, counted by hand from the module's table (a key listed by two
        // other kinds is tried twice): state-feedback 3 + 3 + 2 = 8, lq-servo 2 + 3 + 2 = 7,
        // gain-scheduled 3 + 4 + 2 = 9, swing-up-balance 4 + 5 + 4 = 13.
        assert_eq!(rejected, 37);
    }

    #[test]
    fn integers_still_read_as_numbers_inside_the_kind_tables() {
        // The tagged enum buffers the table before reading it: `k = [1, 2, 3, 4]` must still
        // read as the floats it did, giving u = −K·e_i = −(i + 1).
        let mut c =
            load("plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1, 2, 3, 4]\n")
                .unwrap()
                .controller;
        let mut u = [0.0];
        for i in 0..4 {
            let mut y = [0.0; 4];
            y[i] = 1.0;
            c.update(0.0, &y, &mut u);
            assert_eq!(u[0], -((i + 1) as f64));
        }
    }

    #[test]
    fn the_findings_safety_values_are_refused_naming_key_and_value() {
        // Values from the fuzzing campaign of issue 21: each loaded before.
        for (table, key, value) in [
            ("safety", "watchdog_periods", "4294967295"),
            ("safety", "voltage_limit", "1e9"),
            ("safety", "travel_limit", "1e300"),
            ("safety", "angle_window_deg", "1e-300"),
            ("safety", "connect_timeout_s", "1e30"),
            ("safety", "connect_timeout_s", "-1.0"),
            ("safety", "stale_hold_periods", "4294967295"),
        ] {
            let text = format!("{SF}[{table}]\n{key} = {value}\n");
            let e = load(&text).unwrap_err().to_string();
            assert!(e.contains(&format!("{table}.{key}")), "{key}: {e}");
            // The message shows the value as read (the window after its trip through
            // radians, so only its key is checked).
            let v: f64 = value.parse().unwrap();
            if key != "angle_window_deg" {
                assert!(e.contains(&format!("= {v}")), "{key}: {e}");
            }
            assert!(e.contains("must be"), "{key}: {e}");
        }
        // The defaults load, and the watchdog and hold are their documented times at the
        // file's rate (1 kHz: 50 ms = 50 periods, 20 ms = 20; 100 Hz: 5 and 2).
        let l = load(SF).unwrap();
        assert_eq!(l.safety.watchdog_periods, 50);
        assert_eq!(l.safety.stale_hold_periods, 20);
        let l =
            load(&SF.replace("plant = \"cart\"\n", "plant = \"cart\"\nrate_hz = 100.0\n")).unwrap();
        assert_eq!(
            (l.safety.watchdog_periods, l.safety.stale_hold_periods),
            (5, 2)
        );
        // A watchdog given alone keeps the default hold below it.
        let l = load(&format!("{SF}[safety]\nwatchdog_periods = 10\n")).unwrap();
        assert_eq!(
            (l.safety.watchdog_periods, l.safety.stale_hold_periods),
            (10, 9)
        );
        // Swing-up has no window: giving one is refused, not ignored.
        let e = load(&format!(
            "{}[safety]\nangle_window_deg = 30.0\n",
            base("swing-up-balance")
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("safety.angle_window_deg"), "{e}");
    }

    #[test]
    fn rates_estimator_switch_and_step_time_are_bounded() {
        let with = |head: &str, extra: &str| {
            format!(
                "plant = \"cart\"\n{head}[controller]\nkind = \"state-feedback\"\nk = [0.0, 0.0, 0.0, 0.0]\n{extra}"
            )
        };
        let tiny = format!("estimator.time_constant = {}", 1e-300);
        for (text, key) in [
            (with("rate_hz = 5.0\n", ""), "rate_hz = 5:"),
            (with("rate_hz = 1e6\n", ""), "rate_hz = 1000000"),
            (with("rate_hz = nan\n", ""), "rate_hz = NaN"),
            (
                with("", "[estimator]\ntime_constant = 1e-300\n"),
                tiny.as_str(),
            ),
            (
                with("", "[estimator]\ntime_constant = 0.2\n"),
                "estimator.time_constant = 0.2",
            ),
            (
                with("", "[estimator]\ntime_constant = inf\n"),
                "estimator.time_constant = inf",
            ),
            // 20 Hz: ts/2 = 25 ms is above the 20 ms default.
            (
                with("rate_hz = 20.0\n", ""),
                "estimator.time_constant = 0.02",
            ),
            (
                format!("{}switch_deg = 90.0\n", base("swing-up-balance")),
                "controller.switch_deg = 90",
            ),
            (
                format!("{}switch_deg = 0.0\n", base("swing-up-balance")),
                "controller.switch_deg = 0",
            ),
            (
                format!("{}step_time = -1.0\n", base("lq-servo")),
                "controller.step_time = -1",
            ),
            (
                format!("{}step_time = 1e9\n", base("lq-servo")),
                "controller.step_time = 1000000000",
            ),
        ] {
            let e = load(&text).unwrap_err().to_string();
            assert!(e.contains(key), "{key}: {e}");
            assert!(e.contains("must be"), "{key}: {e}");
        }
        // The ends of the documented ranges load: T = ts/2 (the plain difference quotient,
        // α = 0) and TIME_CONSTANT_MAX at 1 kHz; switch_deg = SWITCH_DEG_MAX; rates 10 Hz (with
        // T = 0.05 = ts/2) and 50 kHz.
        for text in [
            with("", "[estimator]\ntime_constant = 0.0005\n"),
            with("", "[estimator]\ntime_constant = 0.1\n"),
            with("rate_hz = 10.0\n", "[estimator]\ntime_constant = 0.05\n"),
            with("rate_hz = 50000.0\n", ""),
            format!("{}switch_deg = 45.0\n", base("swing-up-balance")),
            format!("{}step_time = 3600.0\n", base("lq-servo")),
        ] {
            load(&text).unwrap_or_else(|e| panic!("{text}: {e}"));
        }
        // Just inside them, the other side refuses.
        for text in [
            with("", "[estimator]\ntime_constant = 0.00049\n"),
            with("rate_hz = 9.99\n", "[estimator]\ntime_constant = 0.06\n"),
            format!("{}switch_deg = 45.01\n", base("swing-up-balance")),
        ] {
            assert!(load(&text).is_err(), "{text}");
        }
    }

    #[test]
    fn references_lie_inside_the_travel_and_the_angle_window() {
        // Cart travel 0.4 m by default: a state reference at 0.5 m, or at the limit itself,
        // would drive the cart into the travel stop; 0.3 m is fine. Likewise the servo.
        let sf = |r: &str, safety: &str| {
            format!(
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [0.0, 0.0, 0.0, 0.0]\nreference = {r}\n{safety}"
            )
        };
        let servo = |r: &str, safety: &str| {
            format!(
                "plant = \"cart\"\n[controller]\nkind = \"lq-servo\"\nk1 = [0.0, 0.0, 0.0, 0.0]\nk2 = 0.0\nreference = {r}\n{safety}"
            )
        };
        for (text, needle) in [
            (
                sf("[0.5, 0.0, 0.0, 0.0]", ""),
                "controller.reference[0] = 0.5",
            ),
            (
                sf("[-0.4, 0.0, 0.0, 0.0]", ""),
                "controller.reference[0] = -0.4",
            ),
            (
                sf("[0.3, 0.0, 0.0, 0.0]", "[safety]\ntravel_limit = 0.2\n"),
                "controller.reference[0] = 0.3",
            ),
            // 0.6 rad = 34° outside the default 30° window.
            (
                sf("[0.0, 0.6, 0.0, 0.0]", ""),
                "controller.reference[1] = 0.6",
            ),
            (sf("[0.0, 0.0, nan, 0.0]", ""), "controller.reference[2]"),
            (servo("[0.5]", ""), "controller.reference[0] = 0.5"),
            (servo("[inf]", ""), "controller.reference[0] = inf"),
        ] {
            let e = load(&text).unwrap_err().to_string();
            assert!(e.contains(needle), "{needle}: {e}");
        }
        for text in [
            sf("[0.3, 0.5, 0.0, 0.0]", ""),
            sf("[-0.39, 0.0, 0.1, 0.0]", ""),
            servo("[0.5]", "[safety]\ntravel_limit = 0.75\n"),
        ] {
            load(&text).unwrap_or_else(|e| panic!("{text}: {e}"));
        }
    }

    #[test]
    fn every_kind_balances_about_upright() {
        for (kind, _) in KEYS {
            let l = load(&base(kind)).unwrap();
            assert_eq!(l.pendulum_centre, 0.0, "{kind}");
            assert_eq!(l.kind, kind);
        }
    }

    #[test]
    fn a_command_line_watchdog_goes_through_the_same_ranges() {
        let mut l = load(SF).unwrap();
        // 0.5 s at 1 kHz is the longest watchdog (Safety::WATCHDOG_MAX_TIME / ts = 500).
        let e = l
            .override_watchdog_periods(u32::MAX)
            .unwrap_err()
            .to_string();
        assert!(e.contains("safety.watchdog_periods = 4294967295"), "{e}");
        assert_eq!(l.safety.watchdog_periods, 50, "unchanged after the error");
        assert!(l.override_watchdog_periods(0).is_err());
        l.override_watchdog_periods(500).unwrap();
        assert_eq!(l.safety.watchdog_periods, 500);
        assert!(l.override_watchdog_periods(501).is_err());
        // The default hold follows the watchdog down; a hold written in the file does not.
        l.override_watchdog_periods(10).unwrap();
        assert_eq!(
            (l.safety.watchdog_periods, l.safety.stale_hold_periods),
            (10, 9)
        );
        let mut l = load(&format!("{SF}[safety]\nstale_hold_periods = 20\n")).unwrap();
        let e = l.override_watchdog_periods(10).unwrap_err().to_string();
        assert!(e.contains("safety.stale_hold_periods = 20"), "{e}");
        // The swing-up keeps its missing window through the override.
        let mut l = load(&base("swing-up-balance")).unwrap();
        l.override_watchdog_periods(100).unwrap();
        assert_eq!(l.safety.angle_window, None);
    }

    #[test]
    fn scheduled_lqr_interpolates_the_two_designs_exactly_at_their_points() {
        // At θ₁ = 0 and 60° the scheduled gain must equal the LQR designed at that angle
        // (the defining property of the interpolation), to rounding.
        let text = "plant = \"arm\"\n[controller]\nkind = \"gain-scheduled\"\nlqr = { q = [5.0, 10.0, 0.1, 0.1], r = 1.0 }\ndesign_points_deg = [0.0, 60.0]\n";
        let sys = |deg: f64| {
            ArmPendulum::book()
                .linearize(ArmEquilibrium::upright(deg.to_radians()))
                .unwrap()
        };
        let q = diag("q", &[5.0, 10.0, 0.1, 0.1], 4).unwrap();
        let r = check_r("lqr", 1.0).unwrap();
        for deg in [0.0, 60.0] {
            let k = lqr(&sys(deg), &q, &r, None).unwrap().gain;
            let th = deg.to_radians();
            let mut c = load(text).unwrap().controller;
            let mut u0 = [0.0];
            c.update(0.0, &[th, 0.0, 0.0, 0.0], &mut u0);
            if deg != 0.0 {
                // u = −K(ρ)·[θ₁, 0, 0, 0] = −K₀₀(ρ) θ₁.
                let k0 = -u0[0] / th;
                assert!((k0 - k[(0, 0)]).abs() < 1e-9 * k[(0, 0)].abs(), "{k0}");
            }
            for i in 1..4 {
                // The law is linear in y at fixed ρ (ρ depends on θ₁ only).
                let mut y = [th, 0.0, 0.0, 0.0];
                y[i] = 1.0;
                let mut u1 = [0.0];
                c.update(0.0, &y, &mut u1);
                let ki = -(u1[0] - u0[0]);
                assert!(
                    (ki - k[(0, i)]).abs() < 1e-9 * k[(0, i)].abs().max(1.0),
                    "{deg}° K[{i}]: {ki} vs {}",
                    k[(0, i)]
                );
            }
        }
    }

    #[test]
    fn swing_up_balance_has_no_angle_window() {
        let l = load(
            "plant = \"arm\"\n[controller]\nkind = \"swing-up-balance\"\nbalance = { lqr = { q = [5.0, 10.0, 0.1, 0.1], r = 1.0 } }\n",
        )
        .unwrap();
        assert_eq!(l.safety.angle_window, None);
        assert_eq!((l.controller.ny(), l.controller.nu()), (4, 1));
    }
}
