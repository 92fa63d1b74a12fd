//! The controller runtime: a fixed-rate loop against a rig speaking [`crate::protocol`].
//!
//! Period `k` (deadline `t₀ + k·ts`, waited for by [`crate::clock::sleep_until`]):
//!
//! 1. read every sensor datagram waiting; keep the newest well-formed frame of this session
//!    with a fresh sequence number (the rest are counted in
//!    [`RejectCounts`](crate::protocol::RejectCounts)); with none, the period is *stale*, and
//!    the data's age is `k − k_fresh` periods since the period that read the last fresh frame;
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
//! [`flags::STOP`](crate::protocol::flags::STOP) (three times, for loss), logs a final row
//! with `v = 0`, flushes the log and reports the [`StopReason`] with the loop's statistics ([`LoopStats`]: timing, stale data
//! — periods, longest age, held and 0 V commands —, skipped periods, rejected frames, and
//! a warning if the rig's time stamps went backwards). The safety limits have documented
//! ranges ([`Safety::validate`], checked first); `docs/rig/lab-pc.md` explains the watchdog
//! and hold defaults and how to set up a lab PC.
//!
//! The code follows the steps: [`run`] checks the settings, arranges the scheduling and
//! builds the estimator, then a private `Session` connects (handshake), arms, runs period
//! after period (one method per step: read, watchdog, estimate, safety check, control,
//! write, log, next period), stops and parks, and flushes the log into the report. The
//! submodules: the limits (`safety`), the report (`report`), the wire (`link`), the run
//! (`session`).

mod link;
mod report;
mod safety;
mod session;

pub use report::{LoopStats, RunReport, StopReason};
pub use safety::Safety;

use crate::emulator::PlantKind;
use crate::log::Logger;
use crate::{ConfigError, RigError};
use pendulab_sim::{Controller, SensorChain};
use session::Session;
use std::net::SocketAddr;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

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

/// Checks a run's settings and controller before anything is opened: the controller's
/// dimensions and sample time, the loop period, [`Safety::validate_at`], the pendulum centre
/// and the duration.
fn check_run(config: &RunConfig, controller: &dyn Controller) -> Result<(), RigError> {
    if controller.ny() != 4 || controller.nu() != 1 {
        return Err(ConfigError::ControllerShape {
            ny: controller.ny(),
            nu: controller.nu(),
        }
        .into());
    }
    if !(config.ts.is_finite() && config.ts >= 2e-5 && config.ts <= 0.1) {
        return Err(ConfigError::invalid(
            "loop period",
            format!("{} s", config.ts),
            "must be in [20 µs, 100 ms]",
        )
        .into());
    }
    if let Some(ts) = controller.sample_time()
        && (ts - config.ts).abs() > 1e-9 * config.ts
    {
        return Err(ConfigError::SampleTime {
            controller: ts,
            run: config.ts,
        }
        .into());
    }
    config.safety.validate_at(config.plant, config.ts)?;
    if !config.pendulum_centre.is_finite() {
        return Err(ConfigError::invalid(
            "pendulum centre",
            format!("{} rad", config.pendulum_centre),
            "must be finite",
        )
        .into());
    }
    if let Some(d) = config.duration
        && !(d.is_finite() && d > 0.0)
    {
        return Err(ConfigError::invalid("duration", format!("{d} s"), "must be > 0").into());
    }
    Ok(())
}

/// Asks for the scheduling of [`RunConfig::realtime_priority`] and [`RunConfig::cpu`] for
/// the calling thread; returns the line the report prints (`"SCHED_FIFO 80, pinned to CPU
/// 1"`, or what was refused and why — the run goes on either way).
fn arrange_scheduling(config: &RunConfig) -> String {
    let scheduling = match config.realtime_priority {
        None => "ordinary".to_string(),
        Some(p) => match crate::clock::try_realtime(p) {
            Ok(()) => format!("SCHED_FIFO {}", p.clamp(1, 99)),
            Err(e) => format!("ordinary (real-time refused: {})", e.describe()),
        },
    };
    match config.cpu {
        None => scheduling,
        Some(c) => match crate::clock::pin_to_cpu(c) {
            Ok(()) => format!("{scheduling}, pinned to CPU {c}"),
            Err(e) => format!("{scheduling}, not pinned ({})", e.describe()),
        },
    }
}

/// The runtime's velocity estimator: the rig's pseudo-differentiators
/// (`RigSpec::velocity_estimators`, time constant [`RunConfig::differentiator_t`]) of the
/// two positions, in the layout of the state, prepared at the loop period.
fn velocity_estimator(config: &RunConfig) -> Result<SensorChain, RigError> {
    let spec = config.plant.spec();
    let velocities = spec
        .velocity_estimators
        .map(|e| (e.position_state, e.velocity_state, config.differentiator_t));
    SensorChain::state_layout(4, &[], &velocities)
        .and_then(|mut s| s.prepare(4, config.ts).map(|_| s))
        .map_err(|e| RigError::chain("the runtime's velocity estimator", e))
}

/// Runs the loop until the duration elapses, `stop` is raised or a safety stop.
///
/// In named steps: the checks of the settings and the controller, the scheduling, the
/// estimator, connect (handshake), arm, then period after period read → watchdog → estimate →
/// safety check → control → write → log, and at the end stop and park, log flush and the
/// report (module documentation).
///
/// `controller` sees `y = [q₀, q₁, q̇₀, q̇₁]` and must have `ny = 4`, `nu = 1`, and a sample
/// time (if it has one) equal to `config.ts`. With `log`, every sensor frame is logged and the log
/// is finished (flushed) before returning, on every path.
///
/// # Errors
/// [`RigError::Config`] for a mismatched controller or bad settings; [`RigError::Io`] if the
/// socket cannot be set up; [`RigError::NoAnswer`] if no sensor frame arrives within the
/// connect timeout, [`RigError::InterruptedConnecting`] if `stop` is raised before. Stops
/// after the loop has started are [`RunReport`]s, not errors.
pub fn run(
    config: &RunConfig,
    controller: &mut dyn Controller,
    stop: &AtomicBool,
    log: Option<Logger>,
) -> Result<RunReport, RigError> {
    check_run(config, controller)?;
    let scheduling = arrange_scheduling(config);
    let sensor = velocity_estimator(config)?;
    let mut session = Session::connect(config, sensor, log, stop)?;
    session.arm(controller);
    let end = loop {
        if let Err(end) = session.period(controller, stop) {
            break end;
        }
    };
    session.park(end.reason);
    session.finish(end, scheduling)
}
