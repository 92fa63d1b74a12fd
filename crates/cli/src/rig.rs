//! `pendulab rig`: the rig emulator and the real-time controller runtime.
//!
//! - `pendulab rig emulate --plant cart|arm | --lab DIR [--listen ADDR] [--preset quantized|ideal|noisy]`
//!   runs the nonlinear plant (the book's, or with `--lab` the lab's parameters, encoders, D/A,
//!   amplifier limit, sample time and friction: `EmulatorConfig::for_plant`) in real time behind the wire protocol (docs/rig/protocol.md)
//!   until Ctrl-C (or `--duration`); it prints `listening on ADDR` first. It holds the
//!   pendulum at its initial angle until a controller's first command, and every new run
//!   finds it put back there, so it serves run after run; `--free-run` integrates the plant
//!   from launch instead (`pendulab_rig::emulator::PlantStart`).
//! - `pendulab rig run --connect ADDR --controller FILE.toml [--log FILE.csv] [--duration S]`
//!   runs the controller loop against a rig, prints the stop reason and the loop's jitter,
//!   latency and deadline statistics, and exits with the stop's status (0 completed,
//!   2 interrupted, 3 watchdog, 4 travel limit, 5 angle window, 6 non-finite, 7 I/O; 1 for
//!   errors before the loop starts). With `--lab DIR` the file's design requests are designed
//!   on the lab's plant (`pendulab_control::spec::build_for`), a file of the other plant is
//!   refused and its design record's differences from the lab are printed as warnings;
//!   `--hanging` runs the controller about the hanging rest (`RunConfig::pendulum_centre = π`:
//!   the controller and the angle window see the angle about it), for the identification
//!   experiments (`pendulab design p`).
//!
//! Every number on the command line has a documented range, checked before anything runs, and
//! an error names the flag, its value and the range (docs/rig/README.md, "Valid ranges"):
//! `--duration` up to [`config::DURATION_MAX`] (an hour; 0 = until Ctrl-C for `run`),
//! `--rt-priority` 1–99, `--cpu` below the number of CPUs present, `--watchdog-periods` as
//! `safety.watchdog_periods` ([`pendulab_rig::Safety`]), and the emulator's initial state and
//! imperfections (the `*_MAX` constants below).

use anyhow::{Context, Result, anyhow, bail};
use pendulab_control::spec::{Built, build, build_for};
use pendulab_rig::emulator::{Emulator, EmulatorConfig, PlantKind, PlantStart};
use pendulab_rig::runtime::{RunConfig, StopReason, run as run_loop};
use pendulab_rig::{ConfigError, Logger, RigError, Safety, config};
use std::io::Write;
use std::net::{SocketAddr, ToSocketAddrs};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// Largest `|--theta0-deg|` \[°\]: two turns either way from upright covers every pose, the
/// hanging rest (180°) and a pendulum raised to the top the other way round (360°) included.
pub const THETA0_DEG_MAX: f64 = 720.0;
/// Largest `--noise` \[counts\]: 100 counts is 2.5° on the pendulum encoder (14 400 counts a
/// turn) and 4.8 mm on the cart's; noisier than that is no longer an encoder.
pub const NOISE_COUNTS_MAX: f64 = 100.0;
/// Largest `--latency-ms` \[ms\]: a second, twice the longest watchdog the runtime accepts
/// ([`Safety::WATCHDOG_MAX_TIME`]), enough to show any run losing its rig.
pub const LATENCY_MS_MAX: f64 = 1000.0;
/// Longest `--watchdog-ms` of the emulator \[ms\].
pub const EMULATOR_WATCHDOG_MS_MAX: f64 = 60_000.0;

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
    /// Which rig: the book's cart or arm (required unless --lab gives it).
    #[arg(long, value_parser = ["cart", "arm"], required_unless_present = "lab")]
    pub plant: Option<String>,
    /// Emulate the rig of this lab directory (its lab.toml: the plant's parameters, encoders,
    /// D/A, amplifier limit, sample time and drive friction) instead of the book's.
    #[arg(long)]
    pub lab: Option<PathBuf>,
    /// UDP address to listen on (port 0: any free port).
    #[arg(long, default_value = "127.0.0.1:5005")]
    pub listen: SocketAddr,
    /// Imperfections.
    #[arg(long, value_enum, default_value_t = Preset::Quantized)]
    pub preset: Preset,
    /// Initial pendulum angle from the upright, degrees (180: hanging), |·| ≤ 720.
    #[arg(long, default_value_t = 180.0, allow_hyphen_values = true)]
    pub theta0_deg: f64,
    /// Initial drive position: cart m, arm degrees, on the track: |·| at most the longest
    /// travel limit a controller file accepts (`Safety::TRAVEL_LIMIT_MAX_CART`, `_ARM`).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub q0: f64,
    /// Encoder noise, standard deviation in counts, 0–100 (overrides the preset).
    #[arg(long)]
    pub noise: Option<f64>,
    /// Drive friction, volts, from 0 to the amplifier's range (5 V) (overrides the preset).
    #[arg(long)]
    pub friction: Option<f64>,
    /// Packet loss probability, each direction, in [0, 1) (overrides the preset).
    #[arg(long)]
    pub loss: Option<f64>,
    /// Extra latency of sensor frames, ms, 0–1000 (overrides the preset).
    #[arg(long)]
    pub latency_ms: Option<f64>,
    /// Seed of noise and loss.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Zero the motor after this long without a fresh command, ms, in (0, 60000].
    #[arg(long, default_value_t = 50.0)]
    pub watchdog_ms: f64,
    /// Stop after this many seconds, in (0, 3600] (default: until Ctrl-C).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Run the emulator thread under SCHED_FIFO at this priority (1–99; needs root or rtprio).
    #[arg(long, value_parser = clap::value_parser!(i32).range(1..=99))]
    pub rt_priority: Option<i32>,
    /// Integrate the plant from launch, one plant across all runs (the pendulum falls before
    /// a controller connects). Default: held at the initial state until a run's first
    /// command, and put back there, held, when the next run connects.
    #[arg(long)]
    pub free_run: bool,
}

/// Arguments of `pendulab rig run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// The rig's UDP address, `HOST:PORT` (`127.0.0.1:5005`, `localhost:5005`, `[::1]:5005`);
    /// a host name with several addresses is taken at its first IPv4 one (the emulator listens
    /// on 127.0.0.1 by default), and the address chosen is printed.
    #[arg(long)]
    pub connect: String,
    /// Controller file (TOML; see docs/rig/README.md).
    #[arg(long)]
    pub controller: PathBuf,
    /// Design the controller file's `lqr` requests on this lab's plant (its lab.toml) rather
    /// than the book's; the file's `plant` must be the lab's.
    #[arg(long)]
    pub lab: Option<PathBuf>,
    /// The pendulum hangs (an identification experiment such as `pendulab design p`'s): the
    /// controller and the angle window see the pendulum angle about the hanging rest (π)
    /// instead of upright.
    #[arg(long)]
    pub hanging: bool,
    /// Log every sample to this CSV file.
    #[arg(long)]
    pub log: Option<PathBuf>,
    /// Stop after this many seconds, at most 3600 (default 10; 0 runs until Ctrl-C).
    #[arg(long, default_value_t = 10.0)]
    pub duration: f64,
    /// Override the watchdog (periods without a fresh sensor frame), in the range of the
    /// file's `safety.watchdog_periods` (at most 0.5 s of periods: 500 at 1 kHz).
    #[arg(long)]
    pub watchdog_periods: Option<u32>,
    /// Run the loop under SCHED_FIFO at this priority (1–99; needs root or rtprio; if refused
    /// the run goes on with ordinary scheduling and says so).
    #[arg(long, value_parser = clap::value_parser!(i32).range(1..=99))]
    pub rt_priority: Option<i32>,
    /// Pin the loop thread to this CPU, below the number of CPUs present (e.g. a core isolated
    /// with `isolcpus=`; if refused the run goes on unpinned and says so).
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

/// `v` checked to lie in `lo ..= hi` (`lo` excluded if `open_lo`), else an error naming
/// the flag, the value and the range.
fn check_range(flag: &str, v: f64, lo: f64, open_lo: bool, hi: f64, unit: &str) -> Result<()> {
    let above = if open_lo { v > lo } else { v >= lo };
    if !(v.is_finite() && above && v <= hi) {
        let open = if open_lo { "(" } else { "[" };
        bail!("{flag} {v}: must be in {open}{lo}, {hi}]{unit}");
    }
    Ok(())
}

fn emulate(a: &EmulateArgs) -> Result<()> {
    let lab = a.lab.as_deref().map(crate::lab::load).transpose()?;
    let plant = match (&a.plant, &lab) {
        (Some(p), Some(spec)) if PlantKind::parse(p)? != spec.kind() => bail!(
            "--plant {p}, but the lab's plant is the {} pendulum",
            spec.kind().name()
        ),
        (_, Some(spec)) => spec.kind(),
        (Some(p), None) => PlantKind::parse(p)?,
        (None, None) => bail!("--plant cart|arm or --lab DIR is required"),
    };
    check_range(
        "--theta0-deg",
        a.theta0_deg,
        -THETA0_DEG_MAX,
        false,
        THETA0_DEG_MAX,
        "°",
    )?;
    let (q0, q0_max, unit) = match plant {
        PlantKind::Cart => (a.q0, Safety::TRAVEL_LIMIT_MAX_CART, " m (the cart's track)"),
        PlantKind::Arm => (
            a.q0.to_radians(),
            Safety::TRAVEL_LIMIT_MAX_ARM.to_degrees(),
            "° (the arm's range)",
        ),
    };
    check_range("--q0", a.q0, -q0_max, false, q0_max, unit)?;
    let x0 = [q0, a.theta0_deg.to_radians(), 0.0, 0.0];
    let mut c = match &lab {
        Some(spec) => EmulatorConfig::for_plant(spec, x0),
        None => EmulatorConfig::new(plant, x0),
    };
    c.listen = a.listen;
    c.seed = a.seed;
    if a.free_run {
        c.start = PlantStart::FreeRunning;
    }
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
        check_range("--noise", v, 0.0, false, NOISE_COUNTS_MAX, " counts")?;
        c.encoder_noise_counts = v;
    }
    if let Some(v) = a.friction {
        let amp = c.rig.input_limit;
        check_range(
            "--friction",
            v,
            0.0,
            false,
            amp,
            " V (the amplifier's range)",
        )?;
        c.friction_volts = v;
    }
    if let Some(v) = a.loss {
        if !(0.0..1.0).contains(&v) {
            bail!("--loss {v}: must be in [0, 1)");
        }
        c.loss = v;
    }
    if let Some(v) = a.latency_ms {
        check_range("--latency-ms", v, 0.0, false, LATENCY_MS_MAX, " ms")?;
        c.latency = Duration::from_secs_f64(v * 1e-3);
    }
    check_range(
        "--watchdog-ms",
        a.watchdog_ms,
        0.0,
        true,
        EMULATOR_WATCHDOG_MS_MAX,
        " ms",
    )?;
    c.watchdog = Duration::from_secs_f64(a.watchdog_ms * 1e-3);
    if let Some(d) = a.duration {
        check_range("--duration", d, 0.0, true, config::DURATION_MAX, " s")?;
    }
    // The emulator's own clock ends the run (`EmulatorConfig::duration`).
    c.duration = a.duration;
    let stop = stop_flag()?;
    let emu = Emulator::spawn(c)?;
    println!("listening on {}", emu.addr());
    if let (Some(dir), Some(spec)) = (&a.lab, &lab) {
        println!(
            "emulating the {} rig of {} ({})",
            spec.kind().name(),
            dir.display(),
            crate::lab::provenance_label(spec.provenance())
        );
    }
    if a.free_run {
        println!("free running: the plant is integrated from now on, across runs");
    } else {
        println!(
            "holding the pendulum at {}° until a controller's first command; every new run finds it there again",
            a.theta0_deg
        );
    }
    std::io::stdout().flush().ok();
    let tel = emu.wait(&stop)?;
    println!(
        "emulated {:.3} s; sessions served {}, commands accepted {}, sensor frames {}, lost (in, out) {:?}, watchdog trips {}, late periods {}",
        tel.t,
        tel.sessions,
        tel.commands_accepted,
        tel.sensor_frames,
        tel.lost,
        tel.watchdog_trips,
        tel.late_periods
    );
    println!("rejected command frames: {}", tel.rejects);
    Ok(())
}

/// The address `--connect` names: a socket address as written, or a host name resolved by
/// the system (`ToSocketAddrs`). Of several addresses the first IPv4 one is taken (the
/// emulator listens on 127.0.0.1 by default; `localhost` often resolves to `::1` first), else
/// the first.
///
/// # Errors
/// A message naming `--connect` and the text when it is not `HOST:PORT` or does not resolve.
pub fn resolve_connect(text: &str) -> Result<SocketAddr> {
    let addrs: Vec<SocketAddr> = text
        .to_socket_addrs()
        .with_context(|| {
            format!("--connect {text}: not a HOST:PORT that resolves (e.g. 127.0.0.1:5005 or localhost:5005)")
        })?
        .collect();
    addrs
        .iter()
        .find(|a| a.is_ipv4())
        .or(addrs.first())
        .copied()
        .with_context(|| format!("--connect {text}: the name resolves to no address"))
}

/// The number of CPUs present (on Linux one more than the highest index in
/// `/sys/devices/system/cpu/present`), not only those this process may run on: a core
/// isolated with `isolcpus=`, where `--cpu` is meant to put the loop, is outside the process's
/// default affinity. Elsewhere, the parallelism available to the process.
fn cpus_present() -> usize {
    let sysfs = std::fs::read_to_string("/sys/devices/system/cpu/present")
        .ok()
        .and_then(|s| {
            s.trim()
                .split([',', '-'])
                .map(|x| x.parse::<usize>().ok())
                .collect::<Option<Vec<_>>>()
        })
        .and_then(|v| v.into_iter().max())
        .map(|m| m + 1);
    sysfs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

#[cfg(feature = "serial")]
fn uses_serial(a: &RunArgs) -> bool {
    a.serial.is_some()
}

#[cfg(not(feature = "serial"))]
fn uses_serial(_: &RunArgs) -> bool {
    false
}

/// Reads and checks a controller file (`pendulab_rig::config::load`: the rig's settings and
/// the `[controller]` spec), then designs and builds its controller with the factory
/// `pendulab_control::spec::build` at the file's loop period.
///
/// # Errors
/// The loader's or the factory's error, naming the key, its value and what is wrong.
pub(crate) fn load_and_build(text: &str) -> Result<(config::Loaded, Built)> {
    let loaded = config::load(text)?;
    let built = build(&loaded.spec, loaded.plant, loaded.ts)?;
    Ok((loaded, built))
}

fn run_controller(a: &RunArgs) -> Result<()> {
    let text = std::fs::read_to_string(&a.controller)
        .with_context(|| format!("reading {}", a.controller.display()))?;
    let (mut loaded, mut built) = match &a.lab {
        None => load_and_build(&text).with_context(|| format!("in {}", a.controller.display()))?,
        Some(dir) => {
            let plant = crate::lab::load(dir)?;
            let loaded =
                config::load(&text).with_context(|| format!("in {}", a.controller.display()))?;
            crate::lab::check_controller_plant(&a.controller, loaded.plant, &plant)?;
            let warnings = loaded
                .spec
                .check_plant(&plant)
                .with_context(|| format!("in {}", a.controller.display()))?;
            for w in &warnings {
                eprintln!("warning: {}: {w}", a.controller.display());
            }
            let built = build_for(&loaded.spec, &plant, loaded.ts)
                .with_context(|| format!("in {}", a.controller.display()))?;
            (loaded, built)
        }
    };
    if a.hanging {
        built.pendulum_centre = std::f64::consts::PI;
    }
    if !(a.duration.is_finite() && (0.0..=config::DURATION_MAX).contains(&a.duration)) {
        bail!(
            "--duration {}: must be in [0, {}] s (0: until Ctrl-C)",
            a.duration,
            config::DURATION_MAX
        );
    }
    if let Some(w) = a.watchdog_periods {
        loaded.override_watchdog_periods(w).map_err(|e| match e {
            // The flag's own value out of range: named once, as the flag.
            RigError::Config(ConfigError::Invalid {
                key,
                value,
                requirement,
            }) if key == "safety.watchdog_periods" => {
                anyhow!("--watchdog-periods {value}: {requirement} (the file's {key})")
            }
            // Another key refused because of the flag (a hold no longer below it).
            e => anyhow::Error::new(e).context(format!("--watchdog-periods {w}")),
        })?;
    }
    if let Some(c) = a.cpu {
        let n = cpus_present();
        if c >= n {
            bail!(
                "--cpu {c}: must be below the number of CPUs present ({n}: 0 to {})",
                n - 1
            );
        }
    }
    let addr = match resolve_connect(&a.connect) {
        Ok(addr) => addr,
        // Over a serial port `--connect` only appears in messages.
        Err(_) if uses_serial(a) => SocketAddr::from(([0, 0, 0, 0], 0)),
        Err(e) => return Err(e),
    };
    let mut cfg = RunConfig::new(loaded.plant, addr);
    cfg.ts = loaded.ts;
    cfg.duration = (a.duration > 0.0).then_some(a.duration);
    cfg.safety = loaded.safety;
    cfg.differentiator_t = loaded.differentiator_t;
    cfg.pendulum_centre = built.pendulum_centre;
    cfg.realtime_priority = a.rt_priority;
    cfg.cpu = a.cpu;
    #[cfg(feature = "serial")]
    {
        cfg.serial = a.serial.clone().map(|p| (p, a.baud));
    }
    let stop = stop_flag()?;
    let log = match &a.log {
        Some(p) => Some(Logger::create(p, loaded.plant)?),
        None => None,
    };
    let against = if a.connect == addr.to_string() {
        a.connect.clone()
    } else {
        format!("{} ({addr})", a.connect)
    };
    println!(
        "running {} on the {} rig at {:.0} Hz against {against}",
        built.kind,
        loaded.plant.name(),
        1.0 / cfg.ts,
    );
    std::io::stdout().flush().ok();
    let report = run_loop(&cfg, built.controller.as_mut(), &stop, log)?;
    println!("{report}");
    std::io::stdout().flush().ok();
    if report.reason != StopReason::Completed {
        std::process::exit(i32::from(report.reason.exit_code()));
    }
    Ok(())
}
