//! One run from the handshake to the report, step by step ([`Session`]).

use super::link::{Link, new_session, open_transport};
use super::report::PeriodTiming;
use super::{LoopStats, RunConfig, RunReport, StopReason};
use crate::RigError;
use crate::clock::{Histogram, sleep_until, thread_cpu_time};
use crate::log::{Logger, Sample};
use crate::protocol::{RejectCounts, SensorFrame, SequenceGate, flags};
use pendulab_plants::{wrap_about, wrap_angle};
use pendulab_sim::{Controller, SensorChain};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Size of the ring of sent commands (send time and voltage by sequence number modulo the
/// ring), from which frames echoing a command get their round trip and applied voltage.
const RING: usize = 4096;

/// Why the loop ends: the reason and the report's detail (which limit, which value).
pub(super) struct Stop {
    pub(super) reason: StopReason,
    pub(super) detail: String,
}

impl Stop {
    fn new(reason: StopReason, detail: impl Into<String>) -> Self {
        Self {
            reason,
            detail: detail.into(),
        }
    }
}

/// One period's times: its deadline, the wake-up (wall clock and the thread's CPU clock) and
/// the schedule's time `t = k·ts` \[s\].
struct PeriodStart {
    deadline: Instant,
    wake: Instant,
    cpu_wake: Option<Duration>,
    t: f64,
}

/// The state of one run from the handshake to the report: the link, the estimator, the log,
/// the measurement and the statistics. Each step of the loop (module documentation) is a
/// method.
pub(super) struct Session<'a> {
    config: &'a RunConfig,
    link: Link,
    log: Option<Logger>,
    sensor: SensorChain,
    /// Encoder steps \[m or rad per count\].
    steps: [f64; 2],
    /// Encoder zeros (`EncoderSpec::zero_offset`) \[m or rad\]: the coordinate at count 0.
    zeros: [f64; 2],
    /// Send times and voltages of recent commands, by sequence number modulo [`RING`]. The
    /// connect phase's disabled commands are in it too: frames echoing them log the 0 V the
    /// rig applied.
    sent_at: Vec<(u32, Instant, f64)>,
    /// Fresh frames of the current period, oldest first (reused: no allocation per period
    /// unless a burst outgrows it).
    frames: Vec<SensorFrame>,
    /// The newest fresh frame.
    frame: SensorFrame,
    /// The log's time origin: the rig's stamp of the first frame of the run \[µs\].
    origin_us: u64,
    /// The rig time of the last logged frame \[s\].
    last_t: f64,
    jitter: Histogram,
    lateness: Histogram,
    compute: Histogram,
    rtt: Histogram,
    last_echo: u32,
    stats: LoopStats,
    period: Duration,
    spin: Duration,
    /// Periods of the run (`u64::MAX`: until stopped).
    n_max: u64,
    watchdog: u64,
    hold: u64,
    /// The measurement handed to the controller, `[q₀, q₁, q̇₀, q̇₁]`.
    y: [f64; 4],
    /// The measured positions fed to the velocity estimator: q₀ as read, the pendulum angle
    /// made continuous (each new reading moved by the wrapped difference to the previous one,
    /// so an encoder that jumps by a whole turn does not jolt the velocity estimate).
    x_meas: [f64; 4],
    /// The previous fresh measurement and the period that read it.
    x_prev: [f64; 4],
    raw_prev: f64,
    k_fresh: u64,
    measured: bool,
    u: [f64; 1],
    /// The last command computed from a fresh measurement (held while the data are stale).
    v_held: f64,
    /// Periods since the last fresh frame.
    stale_run: u64,
    prev_time_us: Option<u64>,
    prev_wake: Option<Instant>,
    in_stall: bool,
    /// The period (index into the schedule `t₀ + k·ts`).
    k: u64,
    t0: Instant,
    /// Frames received this period and not yet logged (a stop inside the period logs them).
    pending: bool,
}

impl<'a> Session<'a> {
    /// **Connect (handshake)**: opens the transport with a new session number and sends
    /// disabled commands every 5 ms until the rig answers in this session.
    ///
    /// # Errors
    /// [`RigError::Io`] for the socket; [`RigError::InterruptedConnecting`] if `stop` is raised
    /// and [`RigError::NoAnswer`] if no frame arrives within `Safety::connect_timeout` (the
    /// log, if any, is finished first).
    pub(super) fn connect(
        config: &'a RunConfig,
        sensor: SensorChain,
        log: Option<Logger>,
        stop: &AtomicBool,
    ) -> Result<Self, RigError> {
        let spec = config.plant.spec();
        let steps = spec.encoders.map(|e| e.step);
        let zeros = spec.encoders.map(|e| e.zero_offset);
        let mut link = Link {
            transport: open_transport(config)?,
            session: new_session(),
            seq: 0,
            gate: SequenceGate::new(),
            rejects: RejectCounts::default(),
            buf: [0; 2048],
        };
        let sf = &config.safety;
        let start = Instant::now();
        let mut sent_at = vec![(0u32, start, 0.0f64); RING];
        let mut frames: Vec<SensorFrame> = Vec::with_capacity(256);
        while frames.is_empty() {
            if stop.load(Ordering::Relaxed) {
                if let Some(l) = log {
                    l.finish()?;
                }
                return Err(RigError::InterruptedConnecting {
                    rig: config.connect.to_string(),
                });
            }
            if start.elapsed() > sf.connect_timeout {
                let _ = link.send(0.0, flags::STOP, 0);
                if let Some(l) = log {
                    l.finish()?;
                }
                return Err(RigError::NoAnswer {
                    rig: config.connect.to_string(),
                    timeout: sf.connect_timeout,
                });
            }
            let seq = link
                .send(0.0, 0, 0)
                .map_err(|e| RigError::io(format_args!("sending to {}", config.connect), e))?;
            sent_at[seq as usize % RING] = (seq, Instant::now(), 0.0);
            std::thread::sleep(Duration::from_millis(5));
            link.receive(&mut frames)
                .map_err(|e| RigError::io(format_args!("receiving from {}", config.connect), e))?;
        }
        let frame = frames[frames.len() - 1];
        let origin_us = frames[0].time_us;
        let period = Duration::from_secs_f64(config.ts);
        let mut session = Self {
            config,
            link,
            log,
            sensor,
            steps,
            zeros,
            sent_at,
            frames,
            frame,
            origin_us,
            last_t: 0.0,
            jitter: Histogram::new(),
            lateness: Histogram::new(),
            compute: Histogram::new(),
            rtt: Histogram::new(),
            last_echo: 0,
            stats: LoopStats::default(),
            period,
            // Spin at most a quarter of the period: a loop that spins all the time starves
            // the other threads and, under SCHED_FIFO, runs into the kernel's real-time
            // throttling (a stall of ~50 ms each second).
            spin: config.spin_margin.min(period / 4),
            n_max: config
                .duration
                .map(|d| (d / config.ts).round() as u64)
                .unwrap_or(u64::MAX),
            watchdog: u64::from(sf.watchdog_periods),
            hold: u64::from(sf.stale_hold_periods),
            y: [0.0; 4],
            x_meas: [0.0; 4],
            x_prev: [0.0; 4],
            raw_prev: 0.0,
            k_fresh: 0,
            measured: false,
            u: [0.0],
            v_held: 0.0,
            stale_run: 0,
            prev_time_us: None,
            prev_wake: None,
            in_stall: false,
            k: 0,
            t0: start,
            pending: true,
        };
        session.last_t = session.rig_time(&frame);
        Ok(session)
    }

    /// The rig's time of a frame since the run's first frame \[s\].
    fn rig_time(&self, f: &SensorFrame) -> f64 {
        f.time_us.wrapping_sub(self.origin_us) as i64 as f64 / 1e6
    }

    /// **Arm**: starts the schedule's clock (`t₀`, period 0 at once) and resets the controller.
    /// The first command of period 0 enables the rig's amplifier.
    pub(super) fn arm(&mut self, controller: &mut dyn Controller) {
        self.t0 = Instant::now();
        controller.reset();
    }

    /// Waits for period `k`'s deadline (sleep, then spin) and records the wake-up's lateness
    /// and the jitter of the period since the last wake-up.
    fn wait_for_deadline(&mut self) -> PeriodStart {
        let deadline = self.t0 + self.period.mul_f64(self.k as f64);
        sleep_until(deadline, self.spin);
        let wake = Instant::now();
        let cpu_wake = thread_cpu_time();
        self.lateness.record((wake - deadline).as_secs_f64());
        if let Some(p) = self.prev_wake {
            self.jitter
                .record(((wake - p).as_secs_f64() - self.config.ts).abs());
        }
        self.prev_wake = Some(wake);
        PeriodStart {
            deadline,
            wake,
            cpu_wake,
            t: self.k as f64 * self.config.ts,
        }
    }

    /// **Read** (step 1): every fresh frame waiting (period 0 uses the handshake's), the rig
    /// time going backwards counted, the round trip of the newest frame's echoed command;
    /// returns the newest fresh frame, or `None` for a stale period (its age counted).
    fn read(&mut self, wake: Instant) -> Result<Option<SensorFrame>, Stop> {
        if self.k > 0 {
            self.frames.clear();
            match self.link.receive(&mut self.frames) {
                Ok(()) => self.pending = !self.frames.is_empty(),
                Err(e) => {
                    return Err(Stop::new(
                        StopReason::Io,
                        format!("receiving from {}: {e}", self.config.connect),
                    ));
                }
            }
        }
        for f in &self.frames {
            // Fresh frames have increasing sequence numbers; their rig time must not go back.
            if let Some(p) = self.prev_time_us
                && (f.time_us.wrapping_sub(p) as i64) < 0
            {
                self.stats.rig_time_backwards += 1;
            }
            self.prev_time_us = Some(f.time_us);
        }
        let fresh = self.frames.last().copied();
        match fresh {
            Some(f) => {
                self.frame = f;
                self.stale_run = 0;
                if f.command_seq != self.last_echo && f.command_seq != 0 {
                    self.last_echo = f.command_seq;
                    let (s, at, _) = self.sent_at[f.command_seq as usize % RING];
                    if s == f.command_seq {
                        self.rtt.record((wake - at).as_secs_f64());
                    }
                }
            }
            None => {
                // Staleness is the time since the last fresh frame, in periods (skipped
                // periods count: they passed without a fresh frame too).
                self.stats.stale_periods += 1;
                self.stale_run = self.k - self.k_fresh;
                self.stats.longest_stale_run = self.stats.longest_stale_run.max(self.stale_run);
            }
        }
        Ok(fresh)
    }

    /// **Watchdog** (step 2): stops once the data are `watchdog_periods` old.
    fn check_watchdog(&self) -> Result<(), Stop> {
        if self.stale_run >= self.watchdog {
            return Err(Stop::new(
                StopReason::Watchdog,
                format!(
                    "no fresh sensor frame for {} periods ({:.1} ms)",
                    self.stale_run,
                    self.stale_run as f64 * self.config.ts * 1e3
                ),
            ));
        }
        Ok(())
    }

    /// **Estimate** (step 3): the newest frame's counts to positions (the pendulum angle made
    /// continuous), velocities by the pseudo-differentiator (stepping through a gap of `g`
    /// periods on linearly interpolated positions, so its filter keeps real time), and the
    /// pendulum angle wrapped about the controller's equilibrium into `y`.
    fn estimate(&mut self) {
        let frame = self.frame;
        let [raw0, raw] = self.raw_positions(&frame);
        self.x_meas[0] = raw0;
        self.x_meas[1] = if self.measured {
            self.x_meas[1] + wrap_angle(raw - self.raw_prev)
        } else {
            raw
        };
        self.raw_prev = raw;
        let gap = if self.measured {
            self.k - self.k_fresh
        } else {
            1
        };
        for i in 1..gap {
            let s = i as f64 / gap as f64;
            let xi: [f64; 4] =
                std::array::from_fn(|j| self.x_prev[j] + s * (self.x_meas[j] - self.x_prev[j]));
            self.sensor.measure(&xi, &mut self.y);
        }
        self.sensor.measure(&self.x_meas, &mut self.y);
        self.x_prev = self.x_meas;
        self.k_fresh = self.k;
        self.measured = true;
        // The pendulum angle about the controller's equilibrium (velocities come from the
        // continuous angle above; q₀ is never wrapped).
        self.y[1] = wrap_about(self.y[1], self.config.pendulum_centre);
    }

    /// **Safety check** (step 4) on `y`: the NaN guard, the travel limit and the angle window.
    fn check_safety(&self) -> Result<(), Stop> {
        let (y, sf, centre) = (&self.y, &self.config.safety, self.config.pendulum_centre);
        if y.iter().any(|v| !v.is_finite()) {
            return Err(Stop::new(
                StopReason::NonFinite,
                format!("measurement {y:?}"),
            ));
        }
        if y[0].abs() > sf.travel_limit {
            return Err(Stop::new(
                StopReason::TravelLimit,
                format!("|q0| = {:.4} > {}", y[0].abs(), sf.travel_limit),
            ));
        }
        if let Some(w) = sf.angle_window
            && (y[1] - centre).abs() > w
        {
            return Err(Stop::new(
                StopReason::AngleWindow,
                format!(
                    "|pendulum angle − centre| = {:.2}° > {:.2}°",
                    (y[1] - centre).abs().to_degrees(),
                    w.to_degrees()
                ),
            ));
        }
        Ok(())
    }

    /// **Control** (step 5): `u = controller.update(t, y)`, the NaN guard on `u`, the clamp to
    /// `±voltage_limit`; returns `(v, u)` (sent and computed) and keeps `v` to hold.
    fn control(&mut self, controller: &mut dyn Controller, t: f64) -> Result<(f64, f64), Stop> {
        controller.update(t, &self.y, &mut self.u);
        let u_ctrl = self.u[0];
        if !u_ctrl.is_finite() {
            return Err(Stop::new(
                StopReason::NonFinite,
                format!("command {u_ctrl} at t = {t} s"),
            ));
        }
        let limit = self.config.safety.voltage_limit;
        let v = u_ctrl.clamp(-limit, limit);
        if v != u_ctrl {
            self.stats.clamped += 1;
        }
        self.v_held = v;
        Ok((v, u_ctrl))
    }

    /// The command of a stale period (step 2): never one from an old measurement; the last
    /// safe one held up to `stale_hold_periods`, 0 V beyond.
    fn stale_command(&mut self) -> (f64, f64) {
        if self.stale_run <= self.hold {
            self.stats.held_commands += 1;
            (self.v_held, self.v_held)
        } else {
            self.stats.zero_commands += 1;
            (0.0, 0.0)
        }
    }

    /// **Write** (step 6): sends `v` enabled, echoing the newest frame; returns when it was
    /// sent.
    fn write(&mut self, v: f64) -> Result<Instant, Stop> {
        let seq = self
            .link
            .send(v, flags::ENABLE, self.frame.seq)
            .map_err(|e| {
                Stop::new(
                    StopReason::Io,
                    format!("sending to {}: {e}", self.config.connect),
                )
            })?;
        let done = Instant::now();
        self.sent_at[seq as usize % RING] = (seq, done, v);
        Ok(done)
    }

    /// Records the period's computation time and attributes a missed deadline
    /// ([`PeriodTiming`]).
    fn record_timing(&mut self, p: &PeriodStart, done: Instant) {
        self.compute.record((done - p.wake).as_secs_f64());
        let cpu_done = thread_cpu_time();
        let cpu_work = p.cpu_wake.zip(cpu_done).map(|(a, b)| b.saturating_sub(a));
        let timing = PeriodTiming::of(
            p.wake.saturating_duration_since(p.deadline),
            done - p.wake,
            cpu_work,
            self.period,
        );
        let s = &mut self.stats;
        s.longest_off_cpu = s.longest_off_cpu.max(timing.off_cpu.as_secs_f64());
        let stalled = timing.off_cpu > self.period;
        if stalled && !self.in_stall {
            s.stalls += 1;
        }
        self.in_stall = stalled;
        if timing.missed {
            s.deadline_misses += 1;
            s.descheduled_misses += u64::from(timing.descheduled);
        }
    }

    /// Hands the period's fresh frames to the logger (step 6); stops the run if the writer
    /// has stopped.
    fn log_period(&mut self, p: &PeriodStart, v: f64, u_ctrl: f64) -> Result<(), Stop> {
        if self.log.is_none() || self.frames.is_empty() {
            return Ok(());
        }
        let wall = (p.wake - self.t0).as_secs_f64();
        let alive = self.log_frames((self.k, p.t, wall), [self.y[2], self.y[3], v, u_ctrl]);
        self.pending = false;
        if !alive {
            self.k += 1;
            return Err(Stop::new(StopReason::Io, "the log writer stopped"));
        }
        Ok(())
    }

    /// Logs one row per frame of the period, oldest first, stamped with the rig's time; `v`
    /// is the voltage of the command each frame echoes (from the ring of sent commands,
    /// falling back to the period's), `period = [dz, dθ, v_sent, u_ctrl]` the period's values.
    /// Returns `false` if the writer has stopped (or there is no log).
    fn log_frames(&mut self, (k, t_nominal, t_wall): (u64, f64, f64), period: [f64; 4]) -> bool {
        let Some(l) = &self.log else {
            return false;
        };
        let mut alive = true;
        for f in &self.frames {
            let applied = match f.command_seq {
                0 => 0.0,
                c => match self.sent_at[c as usize % RING] {
                    (s, _, volts) if s == c => volts,
                    // Older than the ring: not known any more.
                    _ => period[2],
                },
            };
            self.last_t = f.time_us.wrapping_sub(self.origin_us) as i64 as f64 / 1e6;
            alive &= l.log(Sample {
                k,
                t: self.last_t,
                t_nominal,
                t_wall,
                seq: f.seq,
                q: self.raw_positions(f),
                dq: [period[0], period[1]],
                v: applied,
                v_sent: period[2],
                u_ctrl: period[3],
                status: f.status,
            });
        }
        alive
    }

    /// A frame's positions as the log keeps them: `c s + zero_offset` of each encoder, so
    /// `q₀` and the raw pendulum angle (`c₁ s₁ + π` on the book rigs, counted from the
    /// hanging rest; not wrapped).
    fn raw_positions(&self, f: &SensorFrame) -> [f64; 2] {
        [
            f.counts[0] as f64 * self.steps[0] + self.zeros[0],
            f.counts[1] as f64 * self.steps[1] + self.zeros[1],
        ]
    }

    /// Ends the period (step 7): the stop flag and the duration, then missed deadlines
    /// skipped — after a stall the loop goes on with the latest deadline already passed (the
    /// rig's frames of the stall wait in the socket and the next period reads them), never
    /// past the watchdog's deadline or the run's last period.
    fn next_period(&mut self, stop: &AtomicBool, t: f64) -> Result<(), Stop> {
        self.k += 1;
        if stop.load(Ordering::Relaxed) {
            return Err(Stop::new(
                StopReason::Interrupted,
                format!("stop requested at t = {t:.3} s"),
            ));
        }
        if self.k >= self.n_max {
            return Err(Stop::new(
                StopReason::Completed,
                format!("{:.3} s", self.k as f64 * self.config.ts),
            ));
        }
        let behind = (Instant::now()
            .saturating_duration_since(self.t0)
            .as_secs_f64()
            / self.config.ts)
            .floor() as u64;
        if behind > self.k {
            let next = behind
                .min(self.k_fresh + self.watchdog)
                .min(self.n_max - 1)
                .max(self.k);
            self.stats.skipped_periods += next - self.k;
            self.k = next;
        }
        Ok(())
    }

    /// One period: wait, read, watchdog, estimate, safety check, control (or the stale
    /// command), write, timing, log, next period. `Err` ends the loop.
    pub(super) fn period(
        &mut self,
        controller: &mut dyn Controller,
        stop: &AtomicBool,
    ) -> Result<(), Stop> {
        let p = self.wait_for_deadline();
        let fresh = self.read(p.wake)?;
        self.check_watchdog()?;
        let (v, u_ctrl) = if fresh.is_some() {
            self.estimate();
            self.check_safety()?;
            self.control(controller, p.t)?
        } else {
            self.stale_command()
        };
        let done = self.write(v)?;
        self.record_timing(&p, done);
        self.log_period(&p, v, u_ctrl)?;
        self.next_period(stop, p.t)
    }

    /// **Stop and park**: 0 V with [`flags::STOP`] three times (for loss: disabled, session
    /// freed); after any stop but completion, the stop period's frames if not yet logged and
    /// a final row with the 0 V the stop commands.
    pub(super) fn park(&mut self, reason: StopReason) {
        for _ in 0..3 {
            let _ = self.link.send(0.0, flags::STOP, self.frame.seq);
        }
        if reason == StopReason::Completed {
            return;
        }
        let wake = Instant::now();
        let (k, ts) = (self.k, self.config.ts);
        let wall = (wake - self.t0).as_secs_f64();
        if self.log.is_some() {
            // The frames of the stop's period, if the stop came before they were logged.
            if self.pending {
                self.log_frames((k, k as f64 * ts, wall), [self.y[2], self.y[3], 0.0, 0.0]);
            }
            // Not a measurement: the last one repeated, stamped one period after it, with
            // the 0 V the stop commands (the raw angle of the last frame, as every row).
            let row = Sample {
                k,
                t: self.last_t + ts,
                t_nominal: k as f64 * ts,
                t_wall: wall,
                seq: self.frame.seq,
                q: self.raw_positions(&self.frame),
                dq: [self.y[2], self.y[3]],
                v: 0.0,
                v_sent: 0.0,
                u_ctrl: 0.0,
                status: self.frame.status,
            };
            if let Some(l) = &self.log {
                l.log(row);
            }
        }
        self.k += 1;
    }

    /// **Log flush and report**: finishes the log (flushed, its rows counted) and summarises
    /// the statistics.
    pub(super) fn finish(self, stop: Stop, scheduling: String) -> Result<RunReport, RigError> {
        let logged = match self.log {
            Some(l) => Some(l.finish()?),
            None => None,
        };
        let mut stats = self.stats;
        stats.jitter = self.jitter.summary();
        stats.lateness = self.lateness.summary();
        stats.compute = self.compute.summary();
        stats.round_trip = self.rtt.summary();
        stats.rejects = self.link.rejects;
        Ok(RunReport {
            reason: stop.reason,
            detail: stop.detail,
            samples: self.k,
            logged,
            stats,
            last_y: self.y,
            scheduling,
            ts: self.config.ts,
        })
    }
}
