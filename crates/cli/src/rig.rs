//! `pendulab rig`: the rig emulator and the real-time controller runtime.
//!
//! - `pendulab rig emulate --plant cart|arm [--listen ADDR] [--preset quantized|ideal|noisy]`
//!   runs the nonlinear plant in real time behind the wire protocol (docs/rig/protocol.md)
//!   until Ctrl-C (or `--duration`); it prints `listening on ADDR` first.
//! - `pendulab rig run --connect ADDR --controller FILE.toml [--log FILE.csv] [--duration S]`
//!   runs the controller loop against a rig, prints the stop reason and the loop's jitter,
//!   latency and deadline statistics, and exits with the stop's status (0 completed,
//!   2 interrupted, 3 watchdog, 4 travel limit, 5 angle window, 6 non-finite, 7 I/O; 1 for
//!   errors before the loop starts).

use anyhow::{Context, Result, bail};
use pendulab_rig::emulator::{Emulator, EmulatorConfig, PlantKind};
use pendulab_rig::runtime::{RunConfig, StopReason, run as run_loop};
use pendulab_rig::{Logger, config};
use std::io::Write;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// Arguments of `pendulab rig`.
#[derive(Debug, clap::Args)]
pub struct RigArgs {
    /// What to do.
    #[command(subcommand)]
    pub action: RigAction,
}

/// `pendulab rig` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum RigAction {
    /// Emulate a rig: the nonlinear plant in real time, answering the wire protocol on UDP.
    Emulate(EmulateArgs),
    /// Run a controller against a rig (real or emulated) at a fixed rate.
    Run(RunArgs),
}

/// Emulator presets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Preset {
    /// The book rig with quantizer: encoders, ±5 V, 16-bit D/A.
    Quantized,
    /// Encoders and ±5 V, no D/A quantisation.
    Ideal,
    /// Quantized plus 0.5-count encoder noise, 0.1 V drive friction, 1 % loss, 1 ms latency.
    Noisy,
}

/// Arguments of `pendulab rig emulate`.
#[derive(Debug, clap::Args)]
pub struct EmulateArgs {
    /// Which rig.
    #[arg(long, value_parser = ["cart", "arm"])]
    pub plant: String,
    /// UDP address to listen on (port 0: any free port).
    #[arg(long, default_value = "127.0.0.1:5005")]
    pub listen: SocketAddr,
    /// Imperfections.
    #[arg(long, value_enum, default_value_t = Preset::Quantized)]
    pub preset: Preset,
    /// Initial pendulum angle from the upright, degrees (180: hanging).
    #[arg(long, default_value_t = 180.0, allow_hyphen_values = true)]
    pub theta0_deg: f64,
    /// Initial drive position (cart m, arm degrees).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub q0: f64,
    /// Encoder noise, standard deviation in counts (overrides the preset).
    #[arg(long)]
    pub noise: Option<f64>,
    /// Drive friction, volts (overrides the preset).
    #[arg(long)]
    pub friction: Option<f64>,
    /// Packet loss probability, each direction (overrides the preset).
    #[arg(long)]
    pub loss: Option<f64>,
    /// Extra latency of sensor frames, ms (overrides the preset).
    #[arg(long)]
    pub latency_ms: Option<f64>,
    /// Seed of noise and loss.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Zero the motor after this long without a fresh command, ms.
    #[arg(long, default_value_t = 50.0)]
    pub watchdog_ms: f64,
    /// Stop after this many seconds (default: until Ctrl-C).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Run the emulator thread under SCHED_FIFO at this priority (1–99; needs root or rtprio).
    #[arg(long)]
    pub rt_priority: Option<i32>,
}

/// Arguments of `pendulab rig run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// The rig's UDP address.
    #[arg(long)]
    pub connect: SocketAddr,
    /// Controller file (TOML; see docs/rig/README.md).
    #[arg(long)]
    pub controller: PathBuf,
    /// Log every sample to this CSV file.
    #[arg(long)]
    pub log: Option<PathBuf>,
    /// Stop after this many seconds (default 10; 0 runs until Ctrl-C).
    #[arg(long, default_value_t = 10.0)]
    pub duration: f64,
    /// Override the watchdog (periods without a fresh sensor frame).
    #[arg(long)]
    pub watchdog_periods: Option<u32>,
    /// Run the loop under SCHED_FIFO at this priority (1–99; needs root or rtprio; if refused
    /// the run goes on with ordinary scheduling and says so).
    #[arg(long)]
    pub rt_priority: Option<i32>,
    /// Pin the loop thread to this CPU (e.g. a core isolated with `isolcpus=`; if refused the
    /// run goes on unpinned and says so).
    #[arg(long)]
    pub cpu: Option<usize>,
    /// Talk to the rig over this serial port instead of UDP (`--connect` is then ignored).
    #[cfg(feature = "serial")]
    #[arg(long)]
    pub serial: Option<String>,
    /// Baud rate of `--serial`.
    #[cfg(feature = "serial")]
    #[arg(long, default_value_t = 921_600)]
    pub baud: u32,
}

/// Runs `pendulab rig ...`.
pub fn run(args: &RigArgs) -> Result<()> {
    match &args.action {
        RigAction::Emulate(a) => emulate(a),
        RigAction::Run(a) => run_controller(a),
    }
}

fn stop_flag() -> Result<Arc<AtomicBool>> {
    let stop = Arc::new(AtomicBool::new(false));
    let s = Arc::clone(&stop);
    ctrlc::set_handler(move || s.store(true, Ordering::Relaxed))
        .context("installing the Ctrl-C handler")?;
    Ok(stop)
}

fn emulate(a: &EmulateArgs) -> Result<()> {
    let plant = PlantKind::parse(&a.plant)?;
    if !a.theta0_deg.is_finite() || !a.q0.is_finite() {
        bail!("--theta0-deg and --q0 must be finite numbers");
    }
    let q0 = match plant {
        PlantKind::Cart => a.q0,
        PlantKind::Arm => a.q0.to_radians(),
    };
    let mut c = EmulatorConfig::new(plant, [q0, a.theta0_deg.to_radians(), 0.0, 0.0]);
    c.listen = a.listen;
    c.seed = a.seed;
    c.realtime_priority = a.rt_priority;
    match a.preset {
        Preset::Quantized => {}
        Preset::Ideal => c.dac = false,
        Preset::Noisy => {
            c.encoder_noise_counts = 0.5;
            c.friction_volts = 0.1;
            c.loss = 0.01;
            c.latency = Duration::from_millis(1);
        }
    }
    if let Some(v) = a.noise {
        c.encoder_noise_counts = v;
    }
    if let Some(v) = a.friction {
        c.friction_volts = v;
    }
    if let Some(v) = a.loss {
        c.loss = v;
    }
    if let Some(v) = a.latency_ms {
        if !(v.is_finite() && (0.0..=1000.0).contains(&v)) {
            bail!("--latency-ms {v}: must be in [0, 1000]");
        }
        c.latency = Duration::from_secs_f64(v * 1e-3);
    }
    if !(a.watchdog_ms.is_finite() && a.watchdog_ms > 0.0 && a.watchdog_ms <= 60_000.0) {
        bail!("--watchdog-ms {}: must be in (0, 60000]", a.watchdog_ms);
    }
    c.watchdog = Duration::from_secs_f64(a.watchdog_ms * 1e-3);
    if let Some(d) = a.duration
        && !(d.is_finite() && d > 0.0)
    {
        bail!("--duration {d}: must be > 0");
    }
    let stop = stop_flag()?;
    let emu = Emulator::spawn(c)?;
    println!("listening on {}", emu.addr());
    std::io::stdout().flush().ok();
    if let Some(d) = a.duration {
        let s = Arc::clone(&stop);
        std::thread::spawn(move || {
            std::thread::sleep(Duration::from_secs_f64(d));
            s.store(true, Ordering::Relaxed);
        });
    }
    let tel = emu.wait(&stop)?;
    println!(
        "emulated {:.3} s; commands accepted {}, sensor frames {}, lost (in, out) {:?}, watchdog trips {}, late periods {}",
        tel.t,
        tel.commands_accepted,
        tel.sensor_frames,
        tel.lost,
        tel.watchdog_trips,
        tel.late_periods
    );
    println!("rejected command frames: {}", tel.rejects);
    Ok(())
}

fn run_controller(a: &RunArgs) -> Result<()> {
    let text = std::fs::read_to_string(&a.controller)
        .with_context(|| format!("reading {}", a.controller.display()))?;
    let mut loaded =
        config::load(&text).with_context(|| format!("in {}", a.controller.display()))?;
    if !(a.duration.is_finite() && a.duration >= 0.0) {
        bail!("--duration {}: must be ≥ 0", a.duration);
    }
    let mut cfg = RunConfig::new(loaded.plant, a.connect);
    cfg.ts = loaded.ts;
    cfg.duration = (a.duration > 0.0).then_some(a.duration);
    cfg.safety = loaded.safety;
    cfg.differentiator_t = loaded.differentiator_t;
    cfg.realtime_priority = a.rt_priority;
    cfg.cpu = a.cpu;
    #[cfg(feature = "serial")]
    {
        cfg.serial = a.serial.clone().map(|p| (p, a.baud));
    }
    if let Some(w) = a.watchdog_periods {
        if w == 0 {
            bail!("--watchdog-periods must be ≥ 1");
        }
        cfg.safety.watchdog_periods = w;
    }
    let stop = stop_flag()?;
    let log = match &a.log {
        Some(p) => Some(Logger::create(p, loaded.plant)?),
        None => None,
    };
    println!(
        "running {} on the {} rig at {:.0} Hz against {}",
        loaded.kind,
        loaded.plant.name(),
        1.0 / cfg.ts,
        a.connect
    );
    std::io::stdout().flush().ok();
    let report = run_loop(&cfg, loaded.controller.as_mut(), &stop, log)?;
    println!("{report}");
    std::io::stdout().flush().ok();
    if report.reason != StopReason::Completed {
        std::process::exit(i32::from(report.reason.exit_code()));
    }
    Ok(())
}
