//! The controller runtime: a fixed-rate loop against a rig speaking [`crate::protocol`].
//!
//! Period `k` (deadline `t₀ + k·ts`, waited for by [`crate::clock::sleep_until`]):
//!
//! 1. read every sensor datagram waiting; keep the newest well-formed frame of this session
//!    with a fresh sequence number (the rest are counted in [`RejectCounts`]); with none, the
//!    period is *stale*, and the data's age is `k − k_fresh` periods since the period that
//!    read the last fresh frame;
//! 2. **watchdog**: an age of `watchdog_periods` stops the run ([`StopReason::Watchdog`]);
//!    a stale period younger than that computes **nothing**: up to `stale_hold_periods` it
//!    sends the last command computed from a fresh measurement again (*held*), beyond that
//!    0 V (enabled), and goes on with step 6;
//! 3. encoder counts → positions (`q₀ = c₀ s₀`; the pendulum encoder counts from the
//!    hanging rest, `c₁ s₁ + π`, made continuous by adding each reading's difference to the
//!    previous one wrapped to `(−π, π]`, so a reading that jumps by a whole turn moves
//!    nothing), velocities by the rig's pseudo-differentiator `s/(T s + 1)`
//!    (`pendulab_sim::SensorChain`, Tustin; through a gap of `g` periods it steps `g` times
//!    on linearly interpolated positions), then the pendulum angle **wrapped about the
//!    controller's equilibrium**, `q₁ = wrap_about(·, pendulum_centre)` (upright: `(−π, π]`;
//!    [`pendulab_plants::wrap_about`], the workspace's one wrapping); `q₀` is never wrapped
//!    (the arm's turns count); `y = [q₀, q₁, q̇₀, q̇₁]`;
//! 4. safety on `y`: NaN guard, drive travel limit `|q₀| ≤ travel_limit`, and for balance
//!    controllers the angle window `|q₁ − pendulum_centre| ≤ angle_window`;
//! 5. `u = controller.update(k·ts, y)`, NaN guard on `u`, clamp to `±voltage_limit`;
//! 6. send the command frame; hand every fresh frame of the period to the logger (one row
//!    each, stamped with the rig's clock, raw angles, see [`crate::log`]);
//! 7. deadlines that have already passed are **skipped**, not replayed back to back: after a
//!    stall of `d` the loop runs the latest passed deadline at once (it reads every frame
//!    that waited) and counts the rest in [`LoopStats::skipped_periods`]; it never skips past
//!    the watchdog's deadline or the run's last period. (Replaying them made the first
//!    catch-up period read every waiting frame and the next ones find none: a 20 ms stall
//!    looked like 20 stale periods and tripped a 20-period watchdog.)
//!
//! Every stop (completed, Ctrl-C, watchdog, limits, NaN, I/O) sends 0 V with
//! [`flags::STOP`] (three times, for loss), logs a final row with `v = 0`, flushes the log and
//! reports the [`StopReason`] with the loop's statistics ([`LoopStats`]: timing, stale data
//! — periods, longest age, held and 0 V commands —, skipped periods, rejected frames, and
//! a warning if the rig's time stamps went backwards). The safety limits have documented
//! ranges ([`Safety::validate`], checked first); `docs/rig/lab-pc.md` explains the watchdog
//! and hold defaults and how to set up a lab PC.

use crate::RigError;
use crate::clock::{Histogram, Percentiles, sleep_until, thread_cpu_time};
use crate::emulator::PlantKind;
use crate::log::{Logger, Sample};
use crate::protocol::{CommandFrame, RejectCounts, SensorFrame, SeqVerdict, SequenceGate, flags};
use pendulab_plants::{wrap_about, wrap_angle};
use pendulab_sim::{Controller, SensorChain};
use std::f64::consts::PI;
use std::fmt;
use std::io::ErrorKind;
use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

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

    /// Defaults of a rig at its sample time (1 ms on both book rigs): the amplifier's range
    /// (±5 V), travel 0.4 m (cart) or 3 rad (arm), window 30°, watchdog
    /// [`Self::WATCHDOG_DEFAULT_TIME`] (50 periods), stale hold [`Self::STALE_HOLD_DEFAULT_TIME`]
    /// (20 periods), 2 s to connect.
    pub fn default_for(plant: PlantKind) -> Self {
        let spec = plant.spec();
        let periods = |t: f64| (t / spec.sample_time).round() as u32;
        Self {
            voltage_limit: spec.input_limit,
            travel_limit: match plant {
                PlantKind::Cart => 0.4,
                PlantKind::Arm => 3.0,
            },
            angle_window: Some(30f64.to_radians()),
            watchdog_periods: periods(Self::WATCHDOG_DEFAULT_TIME),
            stale_hold_periods: periods(Self::STALE_HOLD_DEFAULT_TIME),
            connect_timeout: Duration::from_secs(2),
        }
    }

    /// Checks every field against its range at the rig's own sample time
    /// (`plant.spec().sample_time`, 1 ms); [`Self::validate_at`] for another loop period.
    ///
    /// # Errors
    /// [`RigError::Config`] naming the TOML key as a controller file spells it, the value and
    /// the range, e.g. `safety.watchdog_periods = 4294967295: must be in [1, 500]`.
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
            Err(RigError::Config(format!(
                "safety.{key} = {value}: must be in {range}"
            )))
        };
        if !(ts.is_finite() && ts > 0.0) {
            return Err(RigError::Config(format!(
                "loop period {ts} s: must be finite and > 0"
            )));
        }
        let spec = plant.spec();
        let v = self.voltage_limit;
        if !(v > 0.0 && v <= spec.input_limit) {
            return err(
                "voltage_limit",
                v.to_string(),
                format!(
                    "(0, {}] V (the {} rig's amplifier range)",
                    spec.input_limit, plant.name()
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

/// Settings of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunConfig {
    /// Which rig (encoder resolutions).
    pub plant: PlantKind,
    /// The rig's address.
    pub connect: SocketAddr,
    /// Loop period \[s\].
    pub ts: f64,
    /// Stop after this long \[s\] (`None`: until stopped).
    pub duration: Option<f64>,
    /// Limits.
    pub safety: Safety,
    /// The pendulum angle of the equilibrium the controller stabilises \[rad\] (`0`: upright,
    /// the default; `π`: hanging). The loop hands the controller and the angle window the
    /// pendulum angle `q₁` wrapped about it, `pendulab_plants::wrap_about(q₁, pendulum_centre)`
    /// ∈ `(centre − π, centre + π]`, so a pendulum raised the other way round (the encoder a
    /// turn on) is balanced like one raised directly. The drive position `q₀` is never
    /// wrapped, and the log keeps the raw (unwrapped) angle. Valid: finite.
    pub pendulum_centre: f64,
    /// Pseudo-differentiator time constant \[s\] (0.02 s on the book rigs).
    pub differentiator_t: f64,
    /// Spin for the last part of each wait (see [`crate::clock`]), at most a quarter of the
    /// period.
    pub spin_margin: Duration,
    /// Run the loop thread under `SCHED_FIFO` at this priority ([`crate::clock::try_realtime`];
    /// `None`: ordinary scheduling). If the OS refuses, the run goes on and says so.
    pub realtime_priority: Option<i32>,
    /// Pin the loop thread to this CPU ([`crate::clock::pin_to_cpu`]; `None`: wherever the OS
    /// puts it). If the OS refuses, the run goes on and says so.
    pub cpu: Option<usize>,
    /// Talk to the rig over this serial port `(path, baud)` instead of UDP (`connect` is then
    /// only used in messages).
    #[cfg(feature = "serial")]
    pub serial: Option<(String, u32)>,
}

impl RunConfig {
    /// 1 kHz, 10 s, the rig's default safety, upright centre, `T = 0.02 s`, 200 µs spin.
    pub fn new(plant: PlantKind, connect: SocketAddr) -> Self {
        Self {
            plant,
            connect,
            ts: plant.spec().sample_time,
            duration: Some(10.0),
            safety: Safety::default_for(plant),
            pendulum_centre: 0.0,
            differentiator_t: 0.02,
            spin_margin: Duration::from_micros(200),
            realtime_priority: None,
            cpu: None,
            #[cfg(feature = "serial")]
            serial: None,
        }
    }
}

/// Why a run stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// The duration elapsed.
    Completed,
    /// The stop flag was raised (Ctrl-C, SIGTERM).
    Interrupted,
    /// No fresh sensor frame for the configured number of periods.
    Watchdog,
    /// The drive left its travel limit.
    TravelLimit,
    /// The pendulum left the balance window.
    AngleWindow,
    /// A measurement or command was not finite.
    NonFinite,
    /// The socket failed.
    Io,
}

impl StopReason {
    /// The process exit status `pendulab rig run` returns: 0 completed, 2 interrupted,
    /// 3 watchdog, 4 travel limit, 5 angle window, 6 non-finite value, 7 I/O.
    pub fn exit_code(self) -> u8 {
        match self {
            StopReason::Completed => 0,
            StopReason::Interrupted => 2,
            StopReason::Watchdog => 3,
            StopReason::TravelLimit => 4,
            StopReason::AngleWindow => 5,
            StopReason::NonFinite => 6,
            StopReason::Io => 7,
        }
    }

    /// A short name (`completed`, `interrupted`, `watchdog`, `travel-limit`,
    /// `angle-window`, `non-finite`, `io`).
    pub fn name(self) -> &'static str {
        match self {
            StopReason::Completed => "completed",
            StopReason::Interrupted => "interrupted",
            StopReason::Watchdog => "watchdog",
            StopReason::TravelLimit => "travel-limit",
            StopReason::AngleWindow => "angle-window",
            StopReason::NonFinite => "non-finite",
            StopReason::Io => "io",
        }
    }
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What the loop measured of itself. Times in seconds; percentiles from fixed-memory
/// [`Histogram`]s (resolution 1 % or 1 ns), maxima and means exact.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LoopStats {
    /// `|period − ts|` of consecutive wake-ups.
    pub jitter: Percentiles,
    /// Wake-up lateness after the deadline.
    pub lateness: Percentiles,
    /// From wake-up to the command sent.
    pub compute: Percentiles,
    /// Command sent → the rig reports it applied (echoed sequence number).
    pub round_trip: Percentiles,
    /// Periods whose command was sent after the next deadline.
    pub deadline_misses: u64,
    /// Of [`Self::deadline_misses`], those the loop thread would have made had it kept its CPU:
    /// the time it spent off the CPU since the deadline — a late wake-up plus the wall time of
    /// the period's work minus the thread's CPU time for it ([`crate::clock::thread_cpu_time`])
    /// — exceeds the amount by which the command was late. The OS or, on a virtual machine, the
    /// hypervisor ran something else. The rest, `deadline_misses − descheduled_misses`, are
    /// overruns: the loop's own work did not fit in the period. Without a per-thread CPU clock
    /// only the late wake-up counts as time off the CPU.
    pub descheduled_misses: u64,
    /// Distinct stalls: runs of consecutive periods in which the thread was off the CPU for
    /// more than a whole period. A stall of `d` seconds costs about `d / ts` periods, which the
    /// loop then runs back to back.
    pub stalls: u64,
    /// The longest time off the CPU within one period (s), as defined for
    /// [`Self::descheduled_misses`].
    pub longest_off_cpu: f64,
    /// Periods run without a fresh sensor frame.
    pub stale_periods: u64,
    /// The longest time without a fresh sensor frame, in periods (skipped periods included).
    pub longest_stale_run: u64,
    /// Stale periods in which the last command computed from a fresh measurement was sent
    /// again ([`Safety::stale_hold_periods`]).
    pub held_commands: u64,
    /// Stale periods beyond the hold, in which 0 V was sent.
    pub zero_commands: u64,
    /// Periods skipped after a stall: deadlines already passed when the loop came back, not
    /// replayed back to back (the next period reads every frame that waited).
    pub skipped_periods: u64,
    /// Fresh sensor frames whose rig time stamp is earlier than the previous fresh frame's
    /// (the rig's clock went backwards: its log times are not monotonic). Warned about in
    /// the summary.
    pub rig_time_backwards: u64,
    /// Commands clamped by the voltage limit.
    pub clamped: u64,
    /// Sensor frames rejected, by reason.
    pub rejects: RejectCounts,
}

/// The outcome of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunReport {
    /// Why it stopped.
    pub reason: StopReason,
    /// Human-readable detail (which limit, which value).
    pub detail: String,
    /// Periods of the schedule up to and including the stop's (skipped periods included).
    pub samples: u64,
    /// Rows the logger wrote (one per sensor frame received, plus the stop row).
    pub logged: Option<u64>,
    /// Loop statistics.
    pub stats: LoopStats,
    /// The last measurement `y`.
    pub last_y: [f64; 4],
    /// The scheduling the loop ran under (`"ordinary"`, `"SCHED_FIFO 80"`, or why not).
    pub scheduling: String,
    /// The loop period \[s\].
    pub ts: f64,
}

impl fmt::Display for RunReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let us = |p: &Percentiles| {
            format!(
                "p50 {:.1} µs, p99 {:.1} µs, max {:.1} µs, mean {:.1} µs",
                p.p50 * 1e6,
                p.p99 * 1e6,
                p.max * 1e6,
                p.mean * 1e6
            )
        };
        let s = &self.stats;
        writeln!(f, "stop: {} ({})", self.reason, self.detail)?;
        writeln!(f, "samples: {}", self.samples)?;
        writeln!(f, "scheduling: {}", self.scheduling)?;
        if let Some(n) = self.logged {
            writeln!(f, "logged: {n}")?;
        }
        writeln!(f, "period jitter: {}", us(&s.jitter))?;
        writeln!(f, "wake-up lateness: {}", us(&s.lateness))?;
        writeln!(f, "computation: {}", us(&s.compute))?;
        writeln!(f, "round trip: {}", us(&s.round_trip))?;
        writeln!(
            f,
            "deadline misses: {} ({} overruns, {} while descheduled; {} stalls longer than a period, longest {:.0} µs; {} periods skipped), stale periods: {}, clamped commands: {}",
            s.deadline_misses,
            s.deadline_misses - s.descheduled_misses,
            s.descheduled_misses,
            s.stalls,
            s.longest_off_cpu * 1e6,
            s.skipped_periods,
            s.stale_periods,
            s.clamped
        )?;
        writeln!(
            f,
            "stale data: {} periods, longest {} periods ({:.1} ms), held commands {}, 0 V commands {}",
            s.stale_periods,
            s.longest_stale_run,
            s.longest_stale_run as f64 * self.ts * 1e3,
            s.held_commands,
            s.zero_commands
        )?;
        write!(f, "rejected sensor frames: {}", s.rejects)?;
        if s.rig_time_backwards > 0 {
            write!(
                f,
                "\nwarning: the rig's time stamp went backwards {} times (log times are not monotonic)",
                s.rig_time_backwards
            )?;
        }
        Ok(())
    }
}

/// How one period went: whether its command missed the next deadline and why.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PeriodTiming {
    /// Time off the CPU since the deadline: the late wake-up plus the wall time of the work
    /// minus its CPU time.
    off_cpu: Duration,
    /// The command was sent after the next deadline.
    missed: bool,
    /// It missed, and by less than the time spent off the CPU.
    descheduled: bool,
}

impl PeriodTiming {
    /// From the wake-up's lateness after the deadline, the wall time of the period's work
    /// (wake-up to command sent), the thread's CPU time for that work (if measured) and the
    /// period.
    fn of(late: Duration, work: Duration, cpu_work: Option<Duration>, period: Duration) -> Self {
        let off_cpu = late + cpu_work.map_or(Duration::ZERO, |c| work.saturating_sub(c));
        let miss_by = (late + work).saturating_sub(period);
        let missed = miss_by > Duration::ZERO;
        Self {
            off_cpu,
            missed,
            descheduled: missed && off_cpu > miss_by,
        }
    }
}

/// A session number for this run: non-zero, different between runs (clock and process id
/// mixed by SplitMix64's finaliser).
fn new_session() -> u32 {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos() as u64)
        .unwrap_or(0);
    let mut z = nanos ^ ((std::process::id() as u64) << 32);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    ((z as u32) | 1).max(1)
}

/// How frames travel: datagrams on UDP, or a byte stream on a serial port.
enum Transport {
    Udp(UdpSocket),
    #[cfg(feature = "serial")]
    Serial(Box<crate::serial::SerialLink>),
}

/// Judges one decoded frame; returns it if it is fresh and of `session`.
fn judge(
    session: u32,
    gate: &mut SequenceGate,
    rejects: &mut RejectCounts,
    f: SensorFrame,
) -> Option<SensorFrame> {
    if f.session != session {
        // Frames before the rig adopted this session carry another number.
        rejects.foreign_session += 1;
        return None;
    }
    match gate.check(f.seq) {
        SeqVerdict::Fresh { .. } => Some(f),
        v => {
            rejects.count_verdict(v);
            None
        }
    }
}

struct Link {
    transport: Transport,
    session: u32,
    seq: u32,
    gate: SequenceGate,
    rejects: RejectCounts,
    buf: [u8; 2048],
}

impl Link {
    fn send(&mut self, volts: f64, fl: u16, sensor_seq: u32) -> Result<u32, std::io::Error> {
        self.seq = self.seq.wrapping_add(1);
        let frame = CommandFrame {
            session: self.session,
            seq: self.seq,
            microvolts: CommandFrame::microvolts_of(volts),
            flags: fl,
            sensor_seq,
        };
        let sent = match &mut self.transport {
            Transport::Udp(socket) => socket.send(&frame.encode()).map(|_| ()),
            #[cfg(feature = "serial")]
            Transport::Serial(port) => port.write_frame(&frame.encode()),
        };
        match sent {
            Ok(()) => Ok(self.seq),
            // Loopback reports a vanished peer on the next call; the watchdog handles it.
            Err(e)
                if matches!(
                    e.kind(),
                    ErrorKind::ConnectionRefused | ErrorKind::WouldBlock
                ) =>
            {
                Ok(self.seq)
            }
            Err(e) => Err(e),
        }
    }

    /// Appends every fresh frame waiting to `out`, oldest first (the last is the newest).
    fn receive(&mut self, out: &mut Vec<SensorFrame>) -> Result<(), std::io::Error> {
        #[cfg(feature = "serial")]
        if let Transport::Serial(port) = &mut self.transport {
            port.poll()?;
            while let Some(f) = port.next_frame() {
                if let Some(f) = judge(self.session, &mut self.gate, &mut self.rejects, f) {
                    out.push(f);
                }
            }
            return Ok(());
        }
        loop {
            let got = match &self.transport {
                Transport::Udp(socket) => socket.recv(&mut self.buf),
                #[cfg(feature = "serial")]
                Transport::Serial(_) => return Ok(()),
            };
            match got {
                Ok(n) => {
                    let f = match SensorFrame::decode(&self.buf[..n]) {
                        Ok(f) => f,
                        Err(e) => {
                            self.rejects.count_error(e);
                            continue;
                        }
                    };
                    if let Some(f) = judge(self.session, &mut self.gate, &mut self.rejects, f) {
                        out.push(f);
                    }
                }
                Err(e) if e.kind() == ErrorKind::WouldBlock => return Ok(()),
                Err(e) if e.kind() == ErrorKind::ConnectionRefused => return Ok(()),
                Err(e) => return Err(e),
            }
        }
    }
}

fn open_transport(config: &RunConfig) -> Result<Transport, RigError> {
    #[cfg(feature = "serial")]
    if let Some((path, baud)) = &config.serial {
        return Ok(Transport::Serial(Box::new(
            crate::serial::SerialLink::open(path, *baud)?,
        )));
    }
    let bind: SocketAddr = if config.connect.is_ipv4() {
        SocketAddr::from(([0, 0, 0, 0], 0))
    } else {
        SocketAddr::from(([0u16; 8], 0))
    };
    let socket = UdpSocket::bind(bind).map_err(|e| RigError::io("binding a UDP socket", e))?;
    socket
        .connect(config.connect)
        .map_err(|e| RigError::io(format!("connecting to {}", config.connect), e))?;
    socket
        .set_nonblocking(true)
        .map_err(|e| RigError::io("setting the socket non-blocking", e))?;
    Ok(Transport::Udp(socket))
}

/// Logs one row per frame of a period, oldest first, stamped with the rig's time; `v` is the
/// voltage of the command each frame echoes (from the ring of sent commands, falling back to
/// the period's), `period = [dz, dθ, v_sent, u_ctrl]` the period's values. Returns `false` if
/// the writer has stopped.
#[allow(clippy::too_many_arguments)]
fn log_frames(
    l: &Logger,
    frames: &[SensorFrame],
    sent_at: &[(u32, Instant, f64)],
    (k, t_nominal, t_wall): (u64, f64, f64),
    rig_time: &dyn Fn(&SensorFrame) -> f64,
    steps: &[f64; 2],
    period: [f64; 4],
    last_t: &mut f64,
) -> bool {
    let mut alive = true;
    for f in frames {
        let applied = match f.command_seq {
            0 => 0.0,
            c => match sent_at[c as usize % sent_at.len()] {
                (s, _, volts) if s == c => volts,
                // Older than the ring: not known any more.
                _ => period[2],
            },
        };
        *last_t = rig_time(f);
        alive &= l.log(Sample {
            k,
            t: *last_t,
            t_nominal,
            t_wall,
            seq: f.seq,
            q: [
                f.counts[0] as f64 * steps[0],
                f.counts[1] as f64 * steps[1] + PI,
            ],
            dq: [period[0], period[1]],
            v: applied,
            v_sent: period[2],
            u_ctrl: period[3],
            status: f.status,
        });
    }
    alive
}

/// Runs the loop until the duration elapses, `stop` is raised or a safety stop.
///
/// `controller` sees `y = [q₀, q₁, q̇₀, q̇₁]` and must have `ny = 4`, `nu = 1`, and a sample
/// time (if it has one) equal to `config.ts`. With `log`, every sensor frame is logged and the log
/// is finished (flushed) before returning, on every path.
///
/// # Errors
/// [`RigError::Config`] for a mismatched controller or bad settings; [`RigError::Io`] if the
/// socket cannot be set up; [`RigError::NoRig`] if no sensor frame arrives within the connect
/// timeout. Stops after the loop has started are [`RunReport`]s, not errors.
pub fn run(
    config: &RunConfig,
    controller: &mut dyn Controller,
    stop: &AtomicBool,
    log: Option<Logger>,
) -> Result<RunReport, RigError> {
    if controller.ny() != 4 || controller.nu() != 1 {
        return Err(RigError::Config(format!(
            "the controller takes {} measurements and gives {} commands; the rig needs 4 and 1",
            controller.ny(),
            controller.nu()
        )));
    }
    if !(config.ts.is_finite() && config.ts >= 2e-5 && config.ts <= 0.1) {
        return Err(RigError::Config(format!(
            "loop period {} s: must be in [20 µs, 100 ms]",
            config.ts
        )));
    }
    if let Some(ts) = controller.sample_time()
        && (ts - config.ts).abs() > 1e-9 * config.ts
    {
        return Err(RigError::Config(format!(
            "the controller was designed for ts = {ts} s, the loop runs at {} s",
            config.ts
        )));
    }
    let sf = &config.safety;
    sf.validate_at(config.plant, config.ts)?;
    if !config.pendulum_centre.is_finite() {
        return Err(RigError::Config(format!(
            "pendulum centre {} rad: must be finite",
            config.pendulum_centre
        )));
    }
    if let Some(d) = config.duration
        && !(d.is_finite() && d > 0.0)
    {
        return Err(RigError::Config(format!("duration {d} s: must be > 0")));
    }
    let scheduling = match config.realtime_priority {
        None => "ordinary".to_string(),
        Some(p) => match crate::clock::try_realtime(p) {
            Ok(()) => format!("SCHED_FIFO {}", p.clamp(1, 99)),
            Err(e) => format!("ordinary (real-time refused: {e})"),
        },
    };
    let scheduling = match config.cpu {
        None => scheduling,
        Some(c) => match crate::clock::pin_to_cpu(c) {
            Ok(()) => format!("{scheduling}, pinned to CPU {c}"),
            Err(e) => format!("{scheduling}, not pinned ({e})"),
        },
    };
    let spec = config.plant.spec();
    let steps = [spec.encoders[0].step, spec.encoders[1].step];
    let mut sensor = SensorChain::state_layout(
        4,
        &[],
        &[
            (0, 2, config.differentiator_t),
            (1, 3, config.differentiator_t),
        ],
    )
    .and_then(|mut s| s.prepare(4, config.ts).map(|_| s))
    .map_err(|e| RigError::Config(format!("velocity estimator: {e}")))?;

    let transport = open_transport(config)?;
    let mut link = Link {
        transport,
        session: new_session(),
        seq: 0,
        gate: SequenceGate::new(),
        rejects: RejectCounts::default(),
        buf: [0; 2048],
    };

    // Connect: disabled commands until the rig answers in this session.
    let start = Instant::now();
    // Send times and voltages of recent commands, indexed by sequence number modulo the ring
    // size. The connect phase's disabled commands are in it too: frames echoing them log the
    // 0 V the rig applied.
    const RING: usize = 4096;
    let mut sent_at = vec![(0u32, start, 0.0f64); RING];
    // Fresh frames of the current period, oldest first (reused: no allocation per period
    // unless a burst outgrows it).
    let mut frames: Vec<SensorFrame> = Vec::with_capacity(256);
    while frames.is_empty() {
        if stop.load(Ordering::Relaxed) {
            if let Some(l) = log {
                l.finish()?;
            }
            return Err(RigError::NoRig(format!(
                "interrupted before {} answered",
                config.connect
            )));
        }
        if start.elapsed() > sf.connect_timeout {
            let _ = link.send(0.0, flags::STOP, 0);
            if let Some(l) = log {
                l.finish()?;
            }
            return Err(RigError::NoRig(format!(
                "no sensor frame from {} within {:?}",
                config.connect, sf.connect_timeout
            )));
        }
        let seq = link
            .send(0.0, 0, 0)
            .map_err(|e| RigError::io(format!("sending to {}", config.connect), e))?;
        sent_at[seq as usize % RING] = (seq, Instant::now(), 0.0);
        std::thread::sleep(Duration::from_millis(5));
        link.receive(&mut frames)
            .map_err(|e| RigError::io(format!("receiving from {}", config.connect), e))?;
    }
    let mut frame = frames[frames.len() - 1];
    // The log's time origin: the rig's stamp of the first frame of the run.
    let origin_us = frames[0].time_us;
    let rig_time = |f: &SensorFrame| f.time_us.wrapping_sub(origin_us) as i64 as f64 / 1e6;
    let mut last_t = rig_time(&frame);

    let n_max = config
        .duration
        .map(|d| (d / config.ts).round() as u64)
        .unwrap_or(u64::MAX);
    // Fixed memory however long the run (`duration: None` runs until stopped).
    let mut jitter = Histogram::new();
    let mut lateness = Histogram::new();
    let mut compute = Histogram::new();
    let mut rtt = Histogram::new();
    let mut last_echo = 0u32;
    let mut stats = LoopStats::default();
    let period = Duration::from_secs_f64(config.ts);
    // Spin at most a quarter of the period: a loop that spins all the time starves the other
    // threads and, under SCHED_FIFO, runs into the kernel's real-time throttling (a stall of
    // ~50 ms each second).
    let spin = config.spin_margin.min(period / 4);
    let mut y = [0.0; 4];
    // The measured positions fed to the velocity estimator: q₀ as read, the pendulum angle
    // made continuous (each new reading moved by the wrapped difference to the previous one,
    // so an encoder that jumps by a whole turn does not jolt the velocity estimate).
    let mut x_meas = [0.0; 4];
    // The previous fresh measurement and the period that read it.
    let mut x_prev = [0.0; 4];
    let mut raw_prev = 0.0;
    let mut k_fresh: u64 = 0;
    let mut measured = false;
    let mut u = [0.0];
    // The last command computed from a fresh measurement (held while the data are stale).
    let mut v_held = 0.0;
    let mut stale_run: u64;
    let mut prev_time_us: Option<u64> = None;
    let mut prev_wake: Option<Instant> = None;
    let mut in_stall = false;
    let mut reason = StopReason::Completed;
    let detail: String;
    let mut k: u64 = 0;
    let t0 = Instant::now();
    controller.reset();
    let mut logger_alive = true;
    // Frames received this period and not yet logged (a stop inside the period logs them).
    let mut pending = true;
    let watchdog = u64::from(sf.watchdog_periods);
    let hold = u64::from(sf.stale_hold_periods);

    loop {
        let deadline = t0 + period.mul_f64(k as f64);
        sleep_until(deadline, spin);
        let wake = Instant::now();
        let cpu_wake = thread_cpu_time();
        lateness.record((wake - deadline).as_secs_f64());
        if let Some(p) = prev_wake {
            jitter.record(((wake - p).as_secs_f64() - config.ts).abs());
        }
        prev_wake = Some(wake);
        let t = k as f64 * config.ts;

        // 1. Sensors.
        if k > 0 {
            frames.clear();
            match link.receive(&mut frames) {
                Ok(()) => pending = !frames.is_empty(),
                Err(e) => {
                    reason = StopReason::Io;
                    detail = format!("receiving from {}: {e}", config.connect);
                    break;
                }
            }
        }
        for f in &frames {
            // Fresh frames have increasing sequence numbers; their rig time must not go back.
            if let Some(p) = prev_time_us
                && (f.time_us.wrapping_sub(p) as i64) < 0
            {
                stats.rig_time_backwards += 1;
            }
            prev_time_us = Some(f.time_us);
        }
        let fresh = frames.last().copied();
        match fresh {
            Some(f) => {
                frame = f;
                stale_run = 0;
                if f.command_seq != last_echo && f.command_seq != 0 {
                    last_echo = f.command_seq;
                    let (s, at, _) = sent_at[f.command_seq as usize % RING];
                    if s == f.command_seq {
                        rtt.record((wake - at).as_secs_f64());
                    }
                }
            }
            None => {
                // Staleness is the time since the last fresh frame, in periods (skipped
                // periods count: they passed without a fresh frame too).
                stats.stale_periods += 1;
                stale_run = k - k_fresh;
                stats.longest_stale_run = stats.longest_stale_run.max(stale_run);
            }
        }
        // 2. Watchdog.
        if stale_run >= watchdog {
            reason = StopReason::Watchdog;
            detail = format!(
                "no fresh sensor frame for {stale_run} periods ({:.1} ms)",
                stale_run as f64 * config.ts * 1e3
            );
            break;
        }
        let (v, u_ctrl) = if fresh.is_some() {
            // 3. Measurement.
            let raw = frame.counts[1] as f64 * steps[1] + PI;
            x_meas[0] = frame.counts[0] as f64 * steps[0];
            x_meas[1] = if measured {
                x_meas[1] + wrap_angle(raw - raw_prev)
            } else {
                raw
            };
            raw_prev = raw;
            // Periods without a fresh frame since the last one: the estimator steps through
            // them on positions interpolated linearly, so its filter keeps real time.
            let gap = if measured { k - k_fresh } else { 1 };
            for i in 1..gap {
                let s = i as f64 / gap as f64;
                let xi: [f64; 4] = std::array::from_fn(|j| x_prev[j] + s * (x_meas[j] - x_prev[j]));
                sensor.measure(&xi, &mut y);
            }
            sensor.measure(&x_meas, &mut y);
            x_prev = x_meas;
            k_fresh = k;
            measured = true;
            // The pendulum angle about the controller's equilibrium (velocities come from the
            // continuous angle above; q₀ is never wrapped).
            y[1] = wrap_about(y[1], config.pendulum_centre);
            // 4. Safety on y.
            if y.iter().any(|v| !v.is_finite()) {
                reason = StopReason::NonFinite;
                detail = format!("measurement {y:?}");
                break;
            }
            if y[0].abs() > sf.travel_limit {
                reason = StopReason::TravelLimit;
                detail = format!("|q0| = {:.4} > {}", y[0].abs(), sf.travel_limit);
                break;
            }
            if let Some(w) = sf.angle_window
                && (y[1] - config.pendulum_centre).abs() > w
            {
                reason = StopReason::AngleWindow;
                detail = format!(
                    "|pendulum angle − centre| = {:.2}° > {:.2}°",
                    (y[1] - config.pendulum_centre).abs().to_degrees(),
                    w.to_degrees()
                );
                break;
            }
            // 5. Control.
            controller.update(t, &y, &mut u);
            let u_ctrl = u[0];
            if !u_ctrl.is_finite() {
                reason = StopReason::NonFinite;
                detail = format!("command {u_ctrl} at t = {t} s");
                break;
            }
            let v = u_ctrl.clamp(-sf.voltage_limit, sf.voltage_limit);
            if v != u_ctrl {
                stats.clamped += 1;
            }
            v_held = v;
            (v, u_ctrl)
        } else if stale_run <= hold {
            // Stale: never a command from an old measurement; the last safe one is held.
            stats.held_commands += 1;
            (v_held, v_held)
        } else {
            // Stale beyond the hold: 0 V until a fresh frame or the watchdog.
            stats.zero_commands += 1;
            (0.0, 0.0)
        };
        let seq = match link.send(v, flags::ENABLE, frame.seq) {
            Ok(s) => s,
            Err(e) => {
                reason = StopReason::Io;
                detail = format!("sending to {}: {e}", config.connect);
                break;
            }
        };
        let done = Instant::now();
        sent_at[seq as usize % RING] = (seq, done, v);
        compute.record((done - wake).as_secs_f64());
        let cpu_done = thread_cpu_time();
        let cpu_work = cpu_wake.zip(cpu_done).map(|(a, b)| b.saturating_sub(a));
        let p = PeriodTiming::of(
            wake.saturating_duration_since(deadline),
            done - wake,
            cpu_work,
            period,
        );
        stats.longest_off_cpu = stats.longest_off_cpu.max(p.off_cpu.as_secs_f64());
        let stalled = p.off_cpu > period;
        if stalled && !in_stall {
            stats.stalls += 1;
        }
        in_stall = stalled;
        if p.missed {
            stats.deadline_misses += 1;
            stats.descheduled_misses += u64::from(p.descheduled);
        }
        if let Some(l) = &log
            && !frames.is_empty()
        {
            logger_alive &= log_frames(
                l,
                &frames,
                &sent_at,
                (k, t, (wake - t0).as_secs_f64()),
                &rig_time,
                &steps,
                [y[2], y[3], v, u_ctrl],
                &mut last_t,
            );
            pending = false;
            if !logger_alive {
                reason = StopReason::Io;
                detail = "the log writer stopped".into();
                k += 1;
                break;
            }
        }
        k += 1;
        if stop.load(Ordering::Relaxed) {
            reason = StopReason::Interrupted;
            detail = format!("stop requested at t = {t:.3} s");
            break;
        }
        if k >= n_max {
            detail = format!("{:.3} s", k as f64 * config.ts);
            break;
        }
        // Missed deadlines are skipped, not replayed back to back: after a stall the loop
        // goes on with the latest deadline already passed (the rig's frames of the stall wait
        // in the socket and the next period reads them). It never skips past the watchdog's
        // deadline or the run's last period.
        let behind =
            (Instant::now().saturating_duration_since(t0).as_secs_f64() / config.ts).floor() as u64;
        if behind > k {
            let next = behind.min(k_fresh + watchdog).min(n_max - 1).max(k);
            stats.skipped_periods += next - k;
            k = next;
        }
    }

    // Safe stop: 0 V, disabled, session freed; a final row records it.
    for _ in 0..3 {
        let _ = link.send(0.0, flags::STOP, frame.seq);
    }
    let wake = Instant::now();
    if reason != StopReason::Completed {
        if let Some(l) = &log {
            // The frames of the stop's period, if the stop came before they were logged.
            if pending {
                log_frames(
                    l,
                    &frames,
                    &sent_at,
                    (k, k as f64 * config.ts, (wake - t0).as_secs_f64()),
                    &rig_time,
                    &steps,
                    [y[2], y[3], 0.0, 0.0],
                    &mut last_t,
                );
            }
            // Not a measurement: the last one repeated, stamped one period after it, with the
            // 0 V the stop commands.
            l.log(Sample {
                k,
                t: last_t + config.ts,
                t_nominal: k as f64 * config.ts,
                t_wall: (wake - t0).as_secs_f64(),
                seq: frame.seq,
                // The raw angle of the last frame, as every row of the log.
                q: [
                    frame.counts[0] as f64 * steps[0],
                    frame.counts[1] as f64 * steps[1] + PI,
                ],
                dq: [y[2], y[3]],
                v: 0.0,
                v_sent: 0.0,
                u_ctrl: 0.0,
                status: frame.status,
            });
        }
        k += 1;
    }
    let logged = match log {
        Some(l) => Some(l.finish()?),
        None => None,
    };
    stats.jitter = jitter.summary();
    stats.lateness = lateness.summary();
    stats.compute = compute.summary();
    stats.round_trip = rtt.summary();
    stats.rejects = link.rejects;
    Ok(RunReport {
        reason,
        detail,
        samples: k,
        logged,
        stats,
        last_y: y,
        scheduling,
        ts: config.ts,
    })
}

#[cfg(test)]
mod tests {
    use super::PeriodTiming;
    use std::time::Duration;

    fn us(v: u64) -> Duration {
        Duration::from_micros(v)
    }

    #[test]
    fn a_period_that_fits_is_no_miss() {
        let p = PeriodTiming::of(us(5), us(30), Some(us(30)), us(200));
        assert!(!p.missed && !p.descheduled);
        assert_eq!(p.off_cpu, us(5));
    }

    #[test]
    fn work_that_used_the_cpu_all_along_is_an_overrun() {
        // Woken on time, 250 µs of work on the CPU in a 200 µs period: the loop's own fault.
        let p = PeriodTiming::of(us(0), us(250), Some(us(250)), us(200));
        assert!(p.missed && !p.descheduled);
    }

    #[test]
    fn work_interrupted_by_a_stall_is_a_descheduled_miss() {
        // 30 µs of CPU spread over 3 ms of wall time: 2.97 ms off the CPU, missed by 2.8 ms.
        let p = PeriodTiming::of(us(0), us(3000), Some(us(30)), us(200));
        assert!(p.missed && p.descheduled);
        assert_eq!(p.off_cpu, us(2970));
    }

    #[test]
    fn a_late_wake_up_counts_as_time_off_the_cpu() {
        // Woken 1 ms late (with or without a CPU clock): missed by 0.83 ms < 1 ms off the CPU.
        for cpu in [Some(us(30)), None] {
            let p = PeriodTiming::of(us(1000), us(30), cpu, us(200));
            assert!(p.missed && p.descheduled, "{cpu:?}");
        }
    }

    #[test]
    fn a_short_stall_does_not_excuse_a_long_overrun() {
        // 50 µs off the CPU cannot explain missing by 300 µs.
        let p = PeriodTiming::of(us(50), us(450), Some(us(450)), us(200));
        assert!(p.missed && !p.descheduled);
    }
}
