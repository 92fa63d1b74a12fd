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

pub use clock::SchedError;
pub use emulator::{Emulator, EmulatorConfig, EmulatorHandle, PlantKind, Telemetry};
pub use log::{Logger, Sample};
pub use runtime::{RunConfig, RunReport, Safety, StopReason};

/// What can go wrong before or around a run (stops during a run are [`StopReason`]s).
///
/// Each variant prints what failed once; an underlying error (the OS's, sim's) is its
/// [`std::error::Error::source`], not repeated in the message.
#[derive(Debug, thiserror::Error)]
pub enum RigError {
    /// A bad setting or controller file, naming the key ([`ConfigError`]).
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// An operating-system error, saying what was being done.
    #[error("{what}")]
    Io {
        /// What was being done (`"binding the emulator to 127.0.0.1:5005"`).
        what: String,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// `pendulab-sim` refused a number of a sensor or actuator chain built from the rig's
    /// numbers (the emulator's chains, the runtime's velocity estimator).
    #[error("{what}")]
    Chain {
        /// Which chain (`"the runtime's velocity estimator"`).
        what: &'static str,
        /// sim's error, naming the number.
        #[source]
        source: pendulab_sim::SimError,
    },
    /// No rig answered within the connect timeout.
    #[error("no rig: no sensor frame from {rig} within {timeout:?}")]
    NoAnswer {
        /// The rig's address as configured.
        rig: String,
        /// How long the runtime waited (`Safety::connect_timeout`).
        timeout: std::time::Duration,
    },
    /// The stop flag was raised while connecting, before the rig answered.
    #[error("no rig: interrupted before {rig} answered")]
    InterruptedConnecting {
        /// The rig's address as configured.
        rig: String,
    },
    /// A thread of this crate panicked.
    #[error("internal error: the {0} thread panicked")]
    ThreadPanicked(
        /// Which thread (`"emulator"`, `"logger"`).
        &'static str,
    ),
}

impl RigError {
    /// An [`RigError::Io`]: `what` was being done when the OS refused with `source`.
    pub fn io(what: impl std::fmt::Display, source: std::io::Error) -> Self {
        RigError::Io {
            what: what.to_string(),
            source,
        }
    }

    /// A [`RigError::Chain`]: sim refused `what` with `source`.
    pub fn chain(what: &'static str, source: pendulab_sim::SimError) -> Self {
        RigError::Chain { what, source }
    }
}

/// A bad setting: a controller file, a flag, an emulator or run setting. Every message names
/// the key (as a controller file spells it, or the setting), its value and what it must be.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// A value outside its documented range.
    #[error("{key} = {value}: {requirement}")]
    Invalid {
        /// The key as written (`safety.watchdog_periods`, `rate_hz`, `emulator period`).
        key: String,
        /// The value as read, with its unit where it has one.
        value: String,
        /// What it must be (`must be in [1, 500]`).
        requirement: String,
    },
    /// The controller file is not TOML, or a table does not have the form of its type.
    #[error("controller file{}: {message}", line.map(|l| format!(", line {l}")).unwrap_or_default())]
    File {
        /// The line of the error, if the TOML parser knows it.
        line: Option<usize>,
        /// The parser's or the table's complaint (for `[controller]`, with its kind).
        message: String,
    },
    /// A plant name other than `cart` or `arm`.
    #[error(transparent)]
    Plant(#[from] pendulab_plants::rig::UnknownPlant),
    /// The controller's `[controller]` table, refused by the factory
    /// (`pendulab_control::spec::build`, called by the front ends).
    #[error(transparent)]
    Controller(#[from] pendulab_control::spec::SpecError),
    /// The controller's dimensions do not fit the rig (`y = [q₀, q₁, q̇₀, q̇₁]`, one voltage).
    #[error(
        "the controller takes {ny} measurements and gives {nu} commands; the rig needs 4 and 1"
    )]
    ControllerShape {
        /// Measurements the controller takes.
        ny: usize,
        /// Commands it gives.
        nu: usize,
    },
    /// The controller was designed for another sample time than the loop's.
    #[error("the controller was designed for ts = {controller} s, the loop runs at {run} s")]
    SampleTime {
        /// The controller's sample time \[s\].
        controller: f64,
        /// The loop period \[s\].
        run: f64,
    },
    /// The serial port cannot be opened.
    #[cfg(feature = "serial")]
    #[error("serial port {path}")]
    SerialPort {
        /// The port's path.
        path: String,
        /// The driver's error.
        #[source]
        source: serialport::Error,
    },
}

impl ConfigError {
    /// A [`ConfigError::Invalid`] naming `key`, its `value` and the `requirement`.
    pub fn invalid(
        key: impl std::fmt::Display,
        value: impl std::fmt::Display,
        requirement: impl std::fmt::Display,
    ) -> Self {
        ConfigError::Invalid {
            key: key.to_string(),
            value: value.to_string(),
            requirement: requirement.to_string(),
        }
    }
}
