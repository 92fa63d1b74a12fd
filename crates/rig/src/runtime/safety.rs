//! The run's limits and their documented ranges ([`Safety`]).

use crate::emulator::PlantKind;
use crate::{ConfigError, RigError};
use pendulab_plants::rig::RigSpec;
use std::time::Duration;

/// Limits enforced by the runtime, each with a documented valid range checked by
/// [`Safety::validate`] (the bounds are the `pub const`s of [`Safety`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Safety {
    /// Commands are clamped to `±voltage_limit` \[V\]. Valid: `(0, amplifier range]`, the
    /// rig's `RigSpec::input_limit` (±5 V on both book rigs): a larger limit would put
    /// commands on the wire the amplifier clips anyway, and "clamped commands: 0" would hide it.
    pub voltage_limit: f64,
    /// Stop if `|q₀|` (cart position \[m\] or arm angle \[rad\], never wrapped: the arm's
    /// turns count) exceeds this. Valid: `(0, Safety::TRAVEL_LIMIT_MAX_CART]` m or
    /// `(0, Safety::TRAVEL_LIMIT_MAX_ARM]` rad.
    pub travel_limit: f64,
    /// Stop if the pendulum angle, wrapped about the controller's equilibrium
    /// ([`RunConfig::pendulum_centre`]), is farther than this from it \[rad\] (balance
    /// controllers; `None`: no window). Valid: `[Safety::ANGLE_WINDOW_MIN, Safety::ANGLE_WINDOW_MAX]`
    /// (1° to 90°).
    pub angle_window: Option<f64>,
    /// Stop after this many periods in a row without a fresh sensor frame. Valid:
    /// `[1, ⌊Safety::WATCHDOG_MAX_TIME / ts⌋]` (500 at 1 kHz).
    pub watchdog_periods: u32,
    /// Up to this many periods in a row without a fresh sensor frame, the loop re-sends the
    /// last command it computed from a fresh measurement (it never computes one from a stale
    /// measurement); from the next stale period until the watchdog, it sends 0 V (enabled).
    /// `0`: 0 V from the first stale period. Valid: `[0, watchdog_periods − 1]` and at most
    /// `⌊Safety::STALE_HOLD_MAX_TIME / ts⌋` (100 at 1 kHz).
    pub stale_hold_periods: u32,
    /// How long to wait for the rig's first sensor frame. Valid:
    /// `(0, Safety::CONNECT_TIMEOUT_MAX]` (60 s).
    pub connect_timeout: Duration,
}

impl Safety {
    /// The largest cart travel limit \[m\]. Neither the rig's numbers (`docs/model.md` §3,
    /// `pendulab_plants::RigSpec`) nor the book's recordings give the length of the cart's
    /// track; the book's recorded experiments move the cart at most to its 0.2 m reference
    /// (`data/rig/`), but its servo examples take it to `r = 0.5 m` (`cdip_lqr_servo_sim`,
    /// `p1c63_ex5_cdip_lqr_servo`), which `docs/rig/examples/cart_lq_servo.toml` runs with a
    /// 0.75 m travel limit. pendulab bounds the limit at 1 m, so that a typo (`4`, `1e300`)
    /// is refused; a lab with a longer track raises this constant.
    pub const TRAVEL_LIMIT_MAX_CART: f64 = 1.0;
    /// The largest arm travel limit \[rad\]: half a turn either side of where the arm
    /// started (`π`). An arm that has swung half a turn away while balancing has run away;
    /// the limit also keeps the pendulum encoder's cable, which rides on the arm, from
    /// winding up.
    pub const TRAVEL_LIMIT_MAX_ARM: f64 = std::f64::consts::PI;
    /// The widest angle window \[rad\] (90°): at a quarter turn from upright the pendulum is
    /// horizontal, the drive's acceleration no longer acts on it (the coupling is
    /// `m_p l_p cos θ · z̈`, `cos 90° = 0`), and no balance controller designed about
    /// upright can bring it back.
    pub const ANGLE_WINDOW_MAX: f64 = std::f64::consts::FRAC_PI_2;
    /// The narrowest angle window \[rad\] (1°, 40 counts of the pendulum encoder's 2π/14400):
    /// a balancing pendulum wobbles by more than that, so a narrower window (`1e-300`) would
    /// only stop every run at its first sample.
    pub const ANGLE_WINDOW_MIN: f64 = std::f64::consts::PI / 180.0;
    /// The longest time \[s\] the watchdog may let the loop run blind: 0.5 s. The upright cart
    /// pendulum's unstable pole is 5.75 s⁻¹ (`docs/model.md` §1), so in 0.5 s an error grows by
    /// `e^{2.9} ≈ 18×`; longer makes the watchdog useless.
    pub const WATCHDOG_MAX_TIME: f64 = 0.5;
    /// The longest time \[s\] a command may be held without a fresh measurement: 0.1 s
    /// (an error grows by `e^{0.58} ≈ 1.8×` meanwhile on the upright cart pendulum).
    pub const STALE_HOLD_MAX_TIME: f64 = 0.1;
    /// The longest connect timeout: 60 s (enough to power a rig up by hand).
    pub const CONNECT_TIMEOUT_MAX: Duration = Duration::from_secs(60);
    /// The default watchdog time \[s\]: 50 ms, chosen from stalls measured on the 2-core
    /// development machine with the other core busy (`docs/rig/lab-pc.md`): with ordinary
    /// scheduling the longest time without a fresh frame in six 30 s runs at 1 kHz was 12–38 ms
    /// (all six completed at this default), under `SCHED_FIFO` on a pinned core 9 ms. 50 ms is
    /// above all of them and a tenth of [`Self::WATCHDOG_MAX_TIME`]; the rarer longer host
    /// stalls of ordinary scheduling (one of 99 ms in twelve runs) are what a lab PC's
    /// real-time setup is for.
    pub const WATCHDOG_DEFAULT_TIME: f64 = 0.05;
    /// The default stale-hold time \[s\]: 20 ms. A held command is at most 20 ms old, a sixth
    /// of the upright cart pendulum's doubling time (`ln 2 / 5.75 s⁻¹ = 0.12 s`); in the
    /// measured runs of `docs/rig/lab-pc.md` it bridged all but 6 of 26 613 stale periods.
    pub const STALE_HOLD_DEFAULT_TIME: f64 = 0.02;

    /// Defaults of a rig at its sample time (1 ms on both book rigs), from its numbers
    /// (`pendulab_plants::RigSpec`): the amplifier's range (±5 V), the travel limit (0.4 m on
    /// the cart, 3 rad on the arm) and the angle window (30°), watchdog
    /// [`Self::WATCHDOG_DEFAULT_TIME`] (50 periods), stale hold [`Self::STALE_HOLD_DEFAULT_TIME`]
    /// (20 periods), 2 s to connect.
    pub fn default_for(plant: PlantKind) -> Self {
        Self::from_rig(&plant.spec())
    }

    /// Defaults of the rig `rig` describes (the one home of its limits,
    /// `pendulab_plants::RigSpec`: a lab's rig file or the book's): clamp at its amplifier
    /// range `input_limit` \[V\], its `travel_limit` \[m or rad\] and `angle_window_deg`
    /// (in radians here), the watchdog and stale hold [`Self::WATCHDOG_DEFAULT_TIME`] and
    /// [`Self::STALE_HOLD_DEFAULT_TIME`] in periods of its `sample_time`, 2 s to connect.
    /// Not validated: [`Self::validate_at`] checks the result against the ranges.
    pub fn from_rig(rig: &RigSpec) -> Self {
        let periods = |t: f64| (t / rig.sample_time).round() as u32;
        Self {
            voltage_limit: rig.input_limit,
            travel_limit: rig.travel_limit,
            angle_window: Some(rig.angle_window()),
            watchdog_periods: periods(Self::WATCHDOG_DEFAULT_TIME),
            stale_hold_periods: periods(Self::STALE_HOLD_DEFAULT_TIME),
            connect_timeout: Duration::from_secs(2),
        }
    }

    /// Checks every field against its range at the rig's own sample time
    /// (`plant.spec().sample_time`, 1 ms); [`Self::validate_at`] for another loop period.
    ///
    /// # Errors
    /// [`ConfigError::Invalid`] naming the TOML key as a controller file spells it, the value
    /// and the range, e.g. `safety.watchdog_periods = 4294967295: must be in [1, 500]`.
    pub fn validate(&self, plant: PlantKind) -> Result<(), RigError> {
        self.validate_at(plant, plant.spec().sample_time)
    }

    /// Checks every field against its range with the loop running at period `ts` \[s\] (the
    /// watchdog and stale-hold counts are bounded in time, so their bounds in periods scale
    /// with `1/ts`).
    ///
    /// # Errors
    /// As [`Self::validate`]; also for a `ts` that is not finite and positive.
    pub fn validate_at(&self, plant: PlantKind, ts: f64) -> Result<(), RigError> {
        let err = |key: &str, value: String, range: String| {
            Err(ConfigError::invalid(
                format!("safety.{key}"),
                value,
                format!("must be in {range}"),
            )
            .into())
        };
        if !(ts.is_finite() && ts > 0.0) {
            return Err(ConfigError::invalid(
                "loop period",
                format!("{ts} s"),
                "must be finite and > 0",
            )
            .into());
        }
        let spec = plant.spec();
        let v = self.voltage_limit;
        if !(v > 0.0 && v <= spec.input_limit) {
            return err(
                "voltage_limit",
                v.to_string(),
                format!(
                    "(0, {}] V (the {} rig's amplifier range)",
                    spec.input_limit,
                    plant.name()
                ),
            );
        }
        let (tmax, unit) = match plant {
            PlantKind::Cart => (Self::TRAVEL_LIMIT_MAX_CART, "m"),
            PlantKind::Arm => (Self::TRAVEL_LIMIT_MAX_ARM, "rad"),
        };
        let t = self.travel_limit;
        if !(t > 0.0 && t <= tmax) {
            return err("travel_limit", t.to_string(), format!("(0, {tmax}] {unit}"));
        }
        // The bounds with a relative 10⁻¹² of slack: a window written in degrees reaches
        // radians by one rounding (`90f64.to_radians()` need not be `FRAC_PI_2` exactly).
        if let Some(w) = self.angle_window
            && !(Self::ANGLE_WINDOW_MIN * (1.0 - 1e-12)..=Self::ANGLE_WINDOW_MAX * (1.0 + 1e-12))
                .contains(&w)
        {
            return err(
                "angle_window_deg",
                w.to_degrees().to_string(),
                format!(
                    "[{}, {}]",
                    Self::ANGLE_WINDOW_MIN.to_degrees().round(),
                    Self::ANGLE_WINDOW_MAX.to_degrees().round()
                ),
            );
        }
        // A hair of slack so that 0.5 s / 1 ms is 500, not 499.
        let periods_in = |time: f64| (time / ts * (1.0 + 1e-9)).floor().min(u32::MAX as f64) as u32;
        let wmax = periods_in(Self::WATCHDOG_MAX_TIME).max(1);
        if !(1..=wmax).contains(&self.watchdog_periods) {
            return err(
                "watchdog_periods",
                self.watchdog_periods.to_string(),
                format!("[1, {wmax}]"),
            );
        }
        let hmax = periods_in(Self::STALE_HOLD_MAX_TIME).min(self.watchdog_periods - 1);
        if self.stale_hold_periods > hmax {
            return err(
                "stale_hold_periods",
                self.stale_hold_periods.to_string(),
                format!(
                    "[0, {hmax}] (below watchdog_periods = {} and at most {} s)",
                    self.watchdog_periods,
                    Self::STALE_HOLD_MAX_TIME
                ),
            );
        }
        let c = self.connect_timeout;
        if c.is_zero() || c > Self::CONNECT_TIMEOUT_MAX {
            return err(
                "connect_timeout_s",
                c.as_secs_f64().to_string(),
                format!("(0, {}]", Self::CONNECT_TIMEOUT_MAX.as_secs_f64()),
            );
        }
        Ok(())
    }
}
