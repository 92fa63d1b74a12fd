//! # pendulab-rig — the real-time rig loop
//!
//! What lets a lab run pendulab on a real pendulum, as the book's rigs are run: a PC loop at
//! 1 kHz reading two encoders and writing a motor voltage.
//!
//! | item | what it is |
//! |---|---|
//! | [`protocol`] | wire protocol v1: 36-byte sensor and 24-byte command frames, CRC-16/CCITT-FALSE, sequence gate (replayed / out-of-order frames rejected and counted, far jumps held until confirmed); layout and a page of C in `docs/rig/protocol.md` |
//! | [`emulator`] | [`Emulator`]: the nonlinear cart or arm plant in real time behind the protocol on UDP, with the book's encoders, ±5 V, 16-bit D/A, seeded noise, friction, loss, latency, a stall switch, a pendulum-encoder turn shift, a validated run duration and a watchdog that zeroes the motor |
//! | [`runtime`] | [`runtime::run`]: the fixed-rate loop (sleep + spin, missed deadlines skipped), pseudo-differentiated velocities, the pendulum angle wrapped about the controller's equilibrium ([`RunConfig::pendulum_centre`]), any `pendulab_sim::Controller`, safety with documented ranges ([`Safety::validate`]: clamp, travel limit, angle window, watchdog, stale-data hold, NaN guard, stop flag), statistics (jitter, lateness, computation, round trip, deadline misses, stale data, held commands) and a [`StopReason`] for every stop; lab-PC setup in `docs/rig/lab-pc.md` |
//! | [`config`] | controller files (TOML): the loop rate, `[safety]`, `[estimator]` and the `[controller]` table as a `pendulab_control::spec::ControllerSpec`, read and checked; the controller is designed and built by the front end through `pendulab_control::spec::build` (this crate runs controllers, it does not design them) |
//! | [`log`] | [`Logger`]: lossless CSV off the control thread, flushed on every stop path; readable by `pendulab identify` |
//! | [`clock`] | the sleep-then-spin wait and nearest-rank percentiles |
//! | `serial` (feature `serial`, off by default) | the same frames over a serial port; `RunConfig::serial` makes the runtime use it |
//!
//! ```no_run
//! use pendulab_rig::emulator::{Emulator, EmulatorConfig, PlantKind};
//! use pendulab_rig::runtime::{RunConfig, run};
//! use std::sync::atomic::AtomicBool;
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // The cart rig at θ = 10°, balanced by the LQR of `cdip_lqr_sim` for 2 s at 1 kHz.
//! let emu = Emulator::spawn(EmulatorConfig::new(PlantKind::Cart, [0.0, 10f64.to_radians(), 0.0, 0.0]))?;
//! let loaded = pendulab_rig::config::load(
//!     "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [10.0, 10.0, 0.0, 0.0], r = 1.0 }\n",
//! )?;
//! // The design happens outside the real-time crate, in the controller factory.
//! let mut built = pendulab_control::spec::build(&loaded.spec, loaded.plant, loaded.ts)?;
//! let mut cfg = RunConfig::new(loaded.plant, emu.addr());
//! cfg.duration = Some(2.0);
//! cfg.safety = loaded.safety;
//! cfg.pendulum_centre = built.pendulum_centre;
//! let report = run(&cfg, built.controller.as_mut(), &AtomicBool::new(false), None)?;
//! println!("{report}");
//! # Ok(()) }
//! ```
#![warn(missing_docs)]

pub mod clock;
pub mod config;
pub mod emulator;
pub mod log;
pub mod protocol;
pub mod runtime;
#[cfg(feature = "serial")]
pub mod serial;

pub use emulator::{Emulator, EmulatorConfig, EmulatorHandle, PlantKind, Telemetry};
pub use log::{Logger, Sample};
pub use runtime::{RunConfig, RunReport, Safety, StopReason};

/// What can go wrong before or around a run (stops during a run are [`StopReason`]s).
#[derive(Debug, thiserror::Error)]
pub enum RigError {
    /// A bad setting or controller file, naming the key.
    #[error("{0}")]
    Config(String),
    /// An operating-system error, saying what was being done.
    #[error("{what}: {source}")]
    Io {
        /// What was being done.
        what: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// No rig answered.
    #[error("no rig: {0}")]
    NoRig(String),
    /// A thread died unexpectedly.
    #[error("internal error: {0}")]
    Internal(String),
}

impl RigError {
    /// An [`RigError::Io`] with context.
    pub fn io(what: impl Into<String>, source: std::io::Error) -> Self {
        RigError::Io {
            what: what.into(),
            source,
        }
    }
}
