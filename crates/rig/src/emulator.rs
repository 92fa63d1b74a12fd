//! The rig emulator: the nonlinear plant in real time behind the wire protocol.
//!
//! [`Emulator::spawn`] starts a thread that, every period `ts` of its own clock,
//!
//! 1. reads every command datagram waiting on its UDP socket and accepts a command only if it
//!    is a well-formed frame ([`crate::protocol`]) of the session it serves with a fresh
//!    sequence number (a new session is adopted when none is being served, i.e. at start,
//!    after a [`flags::STOP`], or after the watchdog fired); rejected frames are counted;
//! 2. runs the **watchdog**: with no fresh command for [`EmulatorConfig::watchdog`] the motor
//!    is zeroed and disabled until a fresh command arrives;
//! 3. applies the held voltage through the amplifier (±[`EmulatorConfig::voltage_limit`]
//!    saturation, optional 16-bit D/A quantisation over ±5 V) and optional Karnopp friction
//!    on the drive (voltage-equivalent), and advances the nonlinear plant
//!    (`pendulab_plants::CartPendulum` or `ArmPendulum`; unless it is held, below) by
//!    classical RK4 steps of `ts` — as many as periods have elapsed on the wall clock, so
//!    plant time follows real time even when the thread is woken late. All of this is
//!    [`RigPlant`]: sim's actuator and sensor chains (`pendulab_sim::rig::RigChains`, built
//!    from the rig's numbers) around the plant, stepped by sim's RK4 — the one model of the
//!    rig's imperfections the simulator uses too;
//! 4. reads the encoders (the book rigs' resolutions, `pendulab_plants::RigSpec`; encoder 0
//!    counts the drive from its start position, encoder 1 the pendulum from the **hanging
//!    rest**, as a real incremental encoder powered up with the pendulum hanging does), with
//!    optional Gaussian noise in counts, and sends a sensor frame to the controller's address
//!    **after every plant step** (a late wake-up sends one frame per step it took), stamped
//!    with the plant's clock in µs — the time the state it carries belongs to — so the rig's
//!    record is uniform in time as a microcontroller sampling on a timer interrupt is.
//!
//! **Holding the pendulum** ([`PlantStart`]). By default
//! ([`PlantStart::HeldUntilCommand`]) the plant is held at [`EmulatorConfig::initial_state`], as
//! a person holds the real pendulum before the controller takes over: not integrated, while
//! the clock runs on and sensor frames are answered as always (they carry the held angle).
//! The first accepted command of the session that enables the amplifier ([`flags::ENABLE`])
//! lets go, and from then on the plant is integrated as above; the disabled commands a
//! controller sends while it connects (`pendulab rig run`'s connect phase) do not. When a
//! session ends — a [`flags::STOP`], or the watchdog after the controller vanished — the motor
//! is off and the plant runs on as a real pendulum falls when its controller lets go (so the
//! telemetry still shows the state the run left); the **next session** adopted (by a command
//! other than a STOP) puts it back at the initial state and holds it again. Every session thus
//! starts from the initial state, however long after launch or after the previous run it
//! comes: the emulator serves run after run until stopped. (The same controller coming back in
//! its own session after the watchdog fired, e.g. after a stall of its own, is no new session
//! and finds its pendulum where it left it.) [`PlantStart::FreeRunning`] is the emulator
//! before the hold: one plant integrated from launch across all sessions, never reset (a 10°
//! pendulum left alone passes the runtime's 30° angle window 0.31 s after launch).
//! [`Telemetry::holding`] shows the hold and [`Telemetry::sessions`] counts the sessions served.
//!
//! Fault injection, all seeded (ChaCha8): packet loss in both directions, a fixed extra
//! latency of the sensor frames, [`EmulatorHandle::stall`] (the whole emulator freezes,
//! as a crashed or descheduled rig would) and [`EmulatorHandle::shift_pendulum_encoder`] (the
//! pendulum encoder gains or loses whole turns mid-run). With [`EmulatorConfig::duration`] the
//! thread stops by itself (validated: finite, positive, at most a year).

use crate::protocol::{
    CommandFrame, RejectCounts, SensorFrame, SeqVerdict, SequenceGate, flags, status,
};
use pendulab_plants::rig::RigSpec;
use pendulab_plants::spec::{PlantParameters, PlantSpec};
use pendulab_plants::wrap_angle as wrap;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::VecDeque;
use std::io::ErrorKind;
use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::clock::sleep_until;
use crate::{ConfigError, RigError};

mod plant;
pub use plant::{FRICTION_VELOCITY_BAND, RigPlant};

/// Which rig is emulated (the workspace's rig enum, re-exported from `pendulab-plants`).
pub use pendulab_plants::rig::PlantKind;

/// How the emulator treats the plant before a controller acts on it (module docs, "Holding
/// the pendulum").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PlantStart {
    /// The default: the plant is held at the initial state from launch until the first
    /// accepted command with [`flags::ENABLE`] set, and every new session (adopted by a
    /// command other than a [`flags::STOP`]) puts it back there, held until its own first
    /// enabling command: run after run starts from the initial state. Between sessions the
    /// plant runs on with the motor off.
    #[default]
    HeldUntilCommand,
    /// One plant integrated from launch, across sessions, never reset (the emulator before
    /// the hold; `pendulab rig emulate --free-run`).
    FreeRunning,
}

/// Settings of the emulator. [`EmulatorConfig::new`] gives the book rig "with quantizer":
/// 1 kHz, ±5 V, 16-bit D/A, no noise, friction, loss or latency, 50 ms watchdog, the
/// pendulum held at the initial state until a controller's first command
/// ([`PlantStart::HeldUntilCommand`]).
#[derive(Debug, Clone, PartialEq)]
pub struct EmulatorConfig {
    /// The plant.
    pub plant: PlantKind,
    /// The plant's physical parameters (`pendulab_plants::spec::PlantParameters`: the book's
    /// table 3.5 or 3.7 by default, or a lab's, [`EmulatorConfig::for_plant`]); of the kind
    /// `plant`.
    pub parameters: PlantParameters,
    /// The rig's numbers: encoders (resolution and zero), D/A, drive friction
    /// (`pendulab_plants::RigSpec`, `docs/model.md` §3; the book rig's by default).
    /// [`EmulatorConfig::friction_volts`], when positive, replaces `rig.friction`.
    pub rig: RigSpec,
    /// Address to listen on (port 0: any free port).
    pub listen: SocketAddr,
    /// Period of the emulator's clock \[s\].
    pub ts: f64,
    /// Initial state (upright-zero angles, SI units).
    pub initial_state: [f64; 4],
    /// Held at the initial state until each session's first command (default), or free
    /// running from launch.
    pub start: PlantStart,
    /// Amplifier saturation \[V\].
    pub voltage_limit: f64,
    /// Quantise the command by the rig's 16-bit D/A over ±5 V.
    pub dac: bool,
    /// Standard deviation of Gaussian encoder noise \[counts\] (0: none).
    pub encoder_noise_counts: f64,
    /// Coulomb friction and stiction of the drive, voltage-equivalent \[V\] (0: none).
    pub friction_volts: f64,
    /// Probability that a datagram (either direction) is lost.
    pub loss: f64,
    /// Extra delay of every sensor frame.
    pub latency: Duration,
    /// Seed of noise and loss.
    pub seed: u64,
    /// No fresh command for this long → motor 0 V and disabled.
    pub watchdog: Duration,
    /// Run the emulator thread under `SCHED_FIFO` at this priority (`None`: ordinary).
    pub realtime_priority: Option<i32>,
    /// Stop by itself after this long of wall time \[s\] (`None`: until stopped). Valid:
    /// `(0, EmulatorConfig::MAX_DURATION]`.
    pub duration: Option<f64>,
}

impl EmulatorConfig {
    /// The book rig with quantizer on loopback, any free port, at rest at `initial_state`.
    pub fn new(plant: PlantKind, initial_state: [f64; 4]) -> Self {
        Self {
            plant,
            parameters: PlantParameters::book(plant),
            rig: plant.spec(),
            listen: SocketAddr::from(([127, 0, 0, 1], 0)),
            ts: plant.spec().sample_time,
            initial_state,
            start: PlantStart::HeldUntilCommand,
            voltage_limit: plant.spec().input_limit,
            dac: true,
            encoder_noise_counts: 0.0,
            friction_volts: 0.0,
            loss: 0.0,
            latency: Duration::ZERO,
            seed: 0,
            watchdog: Duration::from_millis(50),
            realtime_priority: None,
            duration: None,
        }
    }

    /// The rig of a plant file (a lab's `[plant]` table, `docs/lab.md`): its kind, parameters
    /// and rig numbers, the loop period `rig.sample_time`, the amplifier limit
    /// `rig.input_limit` and the drive friction of `rig.friction`; the other settings as
    /// [`EmulatorConfig::new`].
    pub fn for_plant(spec: &PlantSpec, initial_state: [f64; 4]) -> Self {
        let mut c = Self::new(spec.kind(), initial_state);
        c.parameters = *spec.parameters();
        c.rig = *spec.rig();
        c.ts = c.rig.sample_time;
        c.voltage_limit = c.rig.input_limit;
        c
    }

    /// The longest run \[s\]: one year (`3.15·10⁷ s`). A bound, not a physical limit: it keeps
    /// every duration exactly representable as a [`Duration`] and an `Instant` offset.
    pub const MAX_DURATION: f64 = 365.0 * 86_400.0;
    /// The longest emulator watchdog and sensor latency: 60 s.
    pub const MAX_WATCHDOG: Duration = Duration::from_secs(60);

    /// Checks every number.
    ///
    /// # Errors
    /// [`ConfigError::Invalid`] naming the setting.
    pub fn validate(&self) -> Result<(), RigError> {
        let bad = |what: &str, v: f64, req: &str| {
            Err(ConfigError::invalid(format!("emulator {what}"), v, req).into())
        };
        if self.parameters.kind() != self.plant {
            return Err(ConfigError::invalid(
                "emulator parameters",
                format!("of the {} pendulum", self.parameters.kind().name()),
                format!("must be the {} pendulum's", self.plant.name()),
            )
            .into());
        }
        let plant_error = |what: &str, e: pendulab_plants::spec::PlantSpecError| {
            let text = e.to_string();
            Err(ConfigError::invalid(format!("emulator {what}"), text, "refused").into())
        };
        if let Err(e) = self.parameters.validate() {
            return plant_error("parameters", e);
        }
        if let Err(e) = self.rig.validate(self.plant) {
            return plant_error("rig", e);
        }
        if !(self.ts.is_finite() && self.ts >= 1e-5 && self.ts <= 0.1) {
            return bad("period", self.ts, "must be in [10 µs, 100 ms]");
        }
        if self.initial_state.iter().any(|v| !v.is_finite()) {
            return Err(ConfigError::invalid(
                "emulator initial state",
                format!("{:?}", self.initial_state),
                "must be finite",
            )
            .into());
        }
        if !(self.voltage_limit.is_finite() && self.voltage_limit > 0.0) {
            return bad("voltage limit", self.voltage_limit, "must be > 0");
        }
        if !(self.encoder_noise_counts.is_finite() && self.encoder_noise_counts >= 0.0) {
            return bad("encoder noise", self.encoder_noise_counts, "must be ≥ 0");
        }
        if !(self.friction_volts.is_finite() && self.friction_volts >= 0.0) {
            return bad("friction", self.friction_volts, "must be ≥ 0");
        }
        if !(0.0..1.0).contains(&self.loss) {
            return bad("loss", self.loss, "must be in [0, 1)");
        }
        if self.watchdog.is_zero() || self.watchdog > Self::MAX_WATCHDOG {
            return bad(
                "watchdog",
                self.watchdog.as_secs_f64(),
                "must be in (0, 60] s",
            );
        }
        if self.latency > Self::MAX_WATCHDOG {
            return bad(
                "latency",
                self.latency.as_secs_f64(),
                "must be in [0, 60] s",
            );
        }
        if let Some(d) = self.duration {
            if !(d > 0.0 && d <= Self::MAX_DURATION) {
                return bad(
                    "duration",
                    d,
                    &format!("must be in (0, {}] s", Self::MAX_DURATION),
                );
            }
            // Representable (it is, within the bound; checked rather than assumed).
            Duration::try_from_secs_f64(d)
                .map_err(|e| ConfigError::invalid("emulator duration", d, e))?;
        }
        Ok(())
    }
}

/// What the emulator shows of itself (updated every period).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Telemetry {
    /// Plant time \[s\]: the emulator's clock, running on while the plant is held.
    pub t: f64,
    /// True plant state (upright-zero angles).
    pub state: [f64; 4],
    /// Voltage applied to the plant after saturation and D/A \[V\].
    pub applied_volts: f64,
    /// The amplifier is enabled by a fresh command.
    pub enabled: bool,
    /// The watchdog is holding the motor at 0 V.
    pub watchdog_active: bool,
    /// How often the watchdog fired.
    pub watchdog_trips: u64,
    /// Session being served (0: none).
    pub session: u32,
    /// The plant is held at the initial state, waiting for the session's first enabling
    /// command: from launch and from each new session's first command on
    /// ([`PlantStart::HeldUntilCommand`]; always `false` when free running).
    pub holding: bool,
    /// Sessions served: session numbers adopted by a command that was not a
    /// [`flags::STOP`] (one per `pendulab rig run`).
    pub sessions: u64,
    /// Commands accepted.
    pub commands_accepted: u64,
    /// Sequence number of the last accepted command.
    pub last_command_seq: u32,
    /// Sensor frames sent (including those then lost).
    pub sensor_frames: u64,
    /// Datagrams dropped by the loss injection (in, out).
    pub lost: (u64, u64),
    /// Rejected command frames by reason.
    pub rejects: RejectCounts,
    /// Largest `|wrap(pendulum angle)|` since the last [`EmulatorHandle::reset_extrema`] \[rad\].
    pub max_abs_pendulum: f64,
    /// Largest `|drive position|` since the last reset of the extrema \[m or rad\].
    pub max_abs_drive: f64,
    /// Periods where the thread woke a full period late (plant stepped several times).
    pub late_periods: u64,
    /// The thread runs under `SCHED_FIFO` (as asked and granted).
    pub realtime: bool,
}

struct Shared {
    telemetry: Mutex<Telemetry>,
    stop: AtomicBool,
    stall_until: Mutex<Option<Instant>>,
    reset_extrema: AtomicBool,
    /// Whole turns added to the pendulum encoder's reading from now on.
    pendulum_turns: AtomicI32,
}

/// A running emulator; dropping it stops the thread.
pub struct Emulator {
    addr: SocketAddr,
    shared: Arc<Shared>,
    thread: Option<JoinHandle<Result<(), RigError>>>,
}

/// A cloneable control of a running emulator (fault injection and telemetry).
#[derive(Clone)]
pub struct EmulatorHandle {
    shared: Arc<Shared>,
}

impl EmulatorHandle {
    /// A snapshot of the telemetry.
    pub fn telemetry(&self) -> Telemetry {
        *self
            .shared
            .telemetry
            .lock()
            .unwrap_or_else(|e| e.into_inner())
    }

    /// Freezes the emulator for `d` (no frames processed or sent, plant not advanced), as a
    /// hung rig would; afterwards it resumes on a rebased clock.
    pub fn stall(&self, d: Duration) {
        *self
            .shared
            .stall_until
            .lock()
            .unwrap_or_else(|e| e.into_inner()) = Some(Instant::now() + d);
    }

    /// Shifts the pendulum encoder's reading by `turns` whole turns (`turns · 14400` counts)
    /// from the next frame on, as an encoder that lost or gained a revolution (a missed index,
    /// a counter glitch) would; the plant itself is untouched. Shifts add up.
    pub fn shift_pendulum_encoder(&self, turns: i32) {
        self.shared
            .pendulum_turns
            .fetch_add(turns, Ordering::Relaxed);
    }

    /// Restarts the extrema of the telemetry.
    pub fn reset_extrema(&self) {
        self.shared.reset_extrema.store(true, Ordering::Relaxed);
    }
}

impl Emulator {
    /// Binds the socket and starts the emulator thread.
    ///
    /// # Errors
    /// [`RigError::Config`] for bad settings; [`RigError::Io`] if the socket cannot be bound.
    pub fn spawn(config: EmulatorConfig) -> Result<Self, RigError> {
        config.validate()?;
        let socket = UdpSocket::bind(config.listen)
            .map_err(|e| RigError::io(format!("binding the emulator to {}", config.listen), e))?;
        socket
            .set_nonblocking(true)
            .map_err(|e| RigError::io("setting the emulator socket non-blocking", e))?;
        let addr = socket
            .local_addr()
            .map_err(|e| RigError::io("reading the emulator's address", e))?;
        let shared = Arc::new(Shared {
            telemetry: Mutex::new(Telemetry {
                state: config.initial_state,
                holding: config.start == PlantStart::HeldUntilCommand,
                ..Default::default()
            }),
            stop: AtomicBool::new(false),
            stall_until: Mutex::new(None),
            reset_extrema: AtomicBool::new(false),
            pendulum_turns: AtomicI32::new(0),
        });
        let s2 = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name("rig-emulator".into())
            .spawn(move || emulate(config, socket, &s2))
            .map_err(|e| RigError::io("starting the emulator thread", e))?;
        Ok(Self {
            addr,
            shared,
            thread: Some(thread),
        })
    }

    /// The address the emulator listens on.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// A handle for telemetry and fault injection.
    pub fn handle(&self) -> EmulatorHandle {
        EmulatorHandle {
            shared: Arc::clone(&self.shared),
        }
    }

    /// Stops the thread and returns the final telemetry.
    ///
    /// # Errors
    /// The thread's I/O error, if it stopped on one.
    pub fn stop(mut self) -> Result<Telemetry, RigError> {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            match t.join() {
                Ok(r) => r?,
                Err(_) => return Err(RigError::ThreadPanicked("emulator")),
            }
        }
        Ok(self.handle().telemetry())
    }

    /// Runs until the stop flag is set or the configured [`EmulatorConfig::duration`] has
    /// elapsed (for `pendulab rig emulate`), printing nothing.
    ///
    /// # Errors
    /// The thread's I/O error.
    pub fn wait(mut self, stop: &AtomicBool) -> Result<Telemetry, RigError> {
        while !stop.load(Ordering::Relaxed) {
            if self.thread.as_ref().is_some_and(|t| t.is_finished()) {
                break;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            match t.join() {
                Ok(r) => r?,
                Err(_) => return Err(RigError::ThreadPanicked("emulator")),
            }
        }
        Ok(self.handle().telemetry())
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn emulate(cfg: EmulatorConfig, socket: UdpSocket, shared: &Shared) -> Result<(), RigError> {
    let realtime = cfg
        .realtime_priority
        .is_some_and(|p| crate::clock::try_realtime(p).is_ok());
    // The plant between the D/A converter and the encoders: sim's chains and integrator.
    let mut rig = RigPlant::new(&cfg)?;
    let ts = cfg.ts;
    let period = Duration::from_secs_f64(ts);
    // Packet loss; the encoder noise has its own generator (in the sensor chain).
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed);
    let hold = cfg.start == PlantStart::HeldUntilCommand;
    // The plant is held at the initial state (not integrated) while this is set.
    let mut holding = hold;
    let mut t = 0.0;
    let mut session: u32 = 0;
    let mut gate = SequenceGate::new();
    let mut peer: Option<SocketAddr> = None;
    let mut held: Option<CommandFrame> = None;
    let mut last_fresh = Instant::now();
    let mut watchdog_active = false;
    let mut tel = Telemetry {
        state: cfg.initial_state,
        realtime,
        ..Default::default()
    };
    let mut out_queue: VecDeque<(Instant, [u8; crate::protocol::SENSOR_LEN])> = VecDeque::new();
    let mut seq: u32 = 0;
    let mut bad_since_last = false;
    let mut buf = [0u8; 2048];
    let t0 = Instant::now();
    let mut base = t0;
    let mut k: u64 = 0;
    // Validated: finite and at most a year.
    let end = cfg.duration.map(|d| t0 + Duration::from_secs_f64(d));
    while !shared.stop.load(Ordering::Relaxed) {
        if end.is_some_and(|e| Instant::now() >= e) {
            break;
        }
        // Stall injection: freeze, then rebase the clock.
        let stall = *shared.stall_until.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(until) = stall {
            if Instant::now() < until {
                std::thread::sleep(Duration::from_millis(1));
                continue;
            }
            *shared.stall_until.lock().unwrap_or_else(|e| e.into_inner()) = None;
            base = Instant::now();
            k = 0;
            last_fresh = Instant::now();
            // The frames that queued up while frozen are read below like any others.
        }
        k += 1;
        let deadline = base + period * (k as u32).max(1);
        sleep_until(deadline, Duration::from_micros(150));
        let now = Instant::now();
        // How many periods are due (≥ 1); a wake-up later than a period steps several times.
        let due = ((now - base).as_secs_f64() / ts).floor() as u64;
        let mut n_steps = due.saturating_sub(k - 1).max(1);
        if n_steps > 1 {
            tel.late_periods += 1;
            if n_steps > 200 {
                // Hopelessly behind (e.g. the process was suspended): rebase, one step.
                base = now;
                k = 0;
                n_steps = 1;
            } else {
                k += n_steps - 1;
            }
        }

        // 1. Commands.
        loop {
            match socket.recv_from(&mut buf) {
                Ok((n, from)) => {
                    if cfg.loss > 0.0 && rng.random::<f64>() < cfg.loss {
                        tel.lost.0 += 1;
                        continue;
                    }
                    let cmd = match CommandFrame::decode(&buf[..n]) {
                        Ok(c) => c,
                        Err(e) => {
                            tel.rejects.count_error(e);
                            bad_since_last = true;
                            continue;
                        }
                    };
                    if cmd.session == 0 {
                        tel.rejects.malformed += 1;
                        bad_since_last = true;
                        continue;
                    }
                    if cmd.session != session {
                        if session == 0 || watchdog_active {
                            session = cmd.session;
                            gate.reset();
                            held = None;
                            // A new session starts from the initial state, held. (A STOP
                            // adopts and frees a session at once: the runtime's second and
                            // third STOP frames after a run do, and must not put the
                            // pendulum back under the run's final state.)
                            if cmd.flags & flags::STOP == 0 {
                                tel.sessions += 1;
                                if hold {
                                    rig.set_state(cfg.initial_state);
                                    holding = true;
                                }
                            }
                        } else {
                            tel.rejects.foreign_session += 1;
                            bad_since_last = true;
                            continue;
                        }
                    }
                    let verdict = gate.check(cmd.seq);
                    if !matches!(verdict, SeqVerdict::Fresh { .. }) {
                        tel.rejects.count_verdict(verdict);
                        bad_since_last = true;
                        continue;
                    }
                    peer = Some(from);
                    tel.commands_accepted += 1;
                    tel.last_command_seq = cmd.seq;
                    last_fresh = Instant::now();
                    watchdog_active = false;
                    if cmd.flags & flags::STOP != 0 {
                        held = None;
                        session = 0;
                        gate.reset();
                    } else {
                        held = Some(cmd);
                        // The controller's first enabling command lets go of the pendulum.
                        if cmd.flags & flags::ENABLE != 0 {
                            holding = false;
                        }
                    }
                }
                Err(e) if e.kind() == ErrorKind::WouldBlock => break,
                // An ICMP "port unreachable" from a vanished controller surfaces here.
                Err(e) if e.kind() == ErrorKind::ConnectionRefused => continue,
                Err(e) if e.kind() == ErrorKind::ConnectionReset => continue,
                Err(e) => return Err(RigError::io("emulator receive", e)),
            }
        }

        // 2. Watchdog.
        if held.is_some() && last_fresh.elapsed() > cfg.watchdog {
            held = None;
            watchdog_active = true;
            tel.watchdog_trips += 1;
        }

        // 3. Amplifier and plant.
        let command = match held {
            Some(c) if c.flags & flags::ENABLE != 0 => c.volts(),
            _ => 0.0,
        };
        let mut st = 0u16;
        let (v, saturated) = rig.amplify(command);
        if saturated {
            st |= status::SATURATED;
        }
        if held.is_some_and(|c| c.flags & flags::ENABLE != 0) {
            st |= status::ENABLED;
        }
        if watchdog_active {
            st |= status::WATCHDOG;
        }
        if bad_since_last {
            st |= status::BAD_FRAME;
            bad_since_last = false;
        }
        // One sensor frame per plant step, as a microcontroller samples on every tick: a late
        // wake-up steps several times and sends each step's frame, so the rig's record stays
        // uniform. Frames are stamped with the plant's own clock (`t` after the step, µs):
        // the time the state they carry belongs to.
        // While held the plant stays at the initial state; the clock and the frames go on.
        for _ in 0..n_steps {
            if !holding {
                rig.step(v);
            }
            t += ts;

            // 4. Encoders and the sensor frame.
            let counts = rig.counts(shared.pendulum_turns.load(Ordering::Relaxed));
            seq = seq.wrapping_add(1);
            let frame = SensorFrame {
                session,
                seq,
                time_us: (t * 1e6).round() as u64,
                counts,
                command_seq: tel.last_command_seq,
                status: st,
            };
            if peer.is_some() {
                tel.sensor_frames += 1;
                if cfg.loss > 0.0 && rng.random::<f64>() < cfg.loss {
                    tel.lost.1 += 1;
                } else {
                    out_queue.push_back((now + cfg.latency, frame.encode()));
                }
            }
        }
        if let Some(p) = peer {
            while let Some((at, bytes)) = out_queue.front() {
                if *at > Instant::now() {
                    break;
                }
                match socket.send_to(bytes, p) {
                    Ok(_) => {}
                    Err(e)
                        if matches!(
                            e.kind(),
                            ErrorKind::WouldBlock
                                | ErrorKind::ConnectionRefused
                                | ErrorKind::ConnectionReset
                        ) => {}
                    Err(e) => return Err(RigError::io("emulator send", e)),
                }
                out_queue.pop_front();
            }
        }

        // Telemetry.
        if shared.reset_extrema.swap(false, Ordering::Relaxed) {
            tel.max_abs_pendulum = 0.0;
            tel.max_abs_drive = 0.0;
        }
        let x = rig.state();
        tel.t = t;
        tel.state = x;
        tel.applied_volts = v;
        tel.enabled = st & status::ENABLED != 0;
        tel.watchdog_active = watchdog_active;
        tel.session = session;
        tel.holding = holding;
        tel.max_abs_pendulum = tel.max_abs_pendulum.max(wrap(x[1]).abs());
        tel.max_abs_drive = tel.max_abs_drive.max(x[0].abs());
        *shared.telemetry.lock().unwrap_or_else(|e| e.into_inner()) = tel;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn wrap_maps_into_minus_pi_pi() {
        assert!((wrap(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap(-0.5) + 0.5).abs() < 1e-15);
        assert!((wrap(2.0 * PI + 0.25) - 0.25).abs() < 1e-12);
    }
}
