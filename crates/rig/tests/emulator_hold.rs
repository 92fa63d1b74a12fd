//! The emulator holds the pendulum at its initial angle until a controller's first command,
//! as a person holds the real pendulum, and serves run after run (issue 18): the book cart's
//! LQR started a second after the emulator balances the 10° pendulum, twice against the same
//! emulator; the wire-level rules of the hold (a controller's enabling command lets go, the
//! next session puts the pendulum back, held); and the free-running emulator of before, whose
//! pendulum falls before the controller connects and is never put back.
//!
//! As in `loopback.rs`, assertions are about behaviour and counters, never timing. The sleeps
//! are the scenario (a controller started a while after the emulator), not measurements.

mod common;
use common::{TOLERANT_WATCHDOG, emulator, load, run_config, run_with_log, tmp, wrap};
use pendulab_rig::emulator::{Emulator, EmulatorConfig, EmulatorHandle, PlantKind, PlantStart};
use pendulab_rig::protocol::{CommandFrame, SensorFrame, flags};
use pendulab_rig::runtime::RunReport;
use pendulab_rig::{StopReason, Telemetry};
use std::f64::consts::PI;
use std::net::{SocketAddr, UdpSocket};
use std::path::Path;
use std::time::{Duration, Instant};

/// The controller file of the README's rig tour.
const CART_LQR: &str = include_str!("../../../docs/rig/examples/cart_lqr.toml");

/// One count of the book rig's pendulum encoder: 14 400 counts a turn \[rad\].
const COUNT: f64 = 2.0 * PI / 14_400.0;

/// The pendulum encoder's reading of a pendulum held `deg` from upright: it counts from the
/// hanging rest, `14400 · (deg/360 − 1/2)` (−6800 at 10°).
fn held_counts(deg: f64) -> i32 {
    (14_400.0 * (deg / 360.0 - 0.5)).round() as i32
}

/// The first row's `theta` of a log.
fn first_theta(path: &Path) -> f64 {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let i = header.iter().position(|h| *h == "theta").unwrap();
    lines
        .next()
        .unwrap()
        .split(',')
        .nth(i)
        .unwrap()
        .parse()
        .unwrap()
}

/// Polls the telemetry until `pred` holds (10 s at most) and returns it.
fn wait_for(h: &EmulatorHandle, what: &str, pred: impl Fn(&Telemetry) -> bool) -> Telemetry {
    let t0 = Instant::now();
    loop {
        let tel = h.telemetry();
        if pred(&tel) {
            return tel;
        }
        assert!(t0.elapsed() < Duration::from_secs(10), "{what}: {tel:?}");
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// The tour's LQR against `addr` for `duration` s, logged to `log`. The runtime's watchdog is
/// relaxed to 0.5 s (a 2-core machine shared with builds can deschedule a thread for longer
/// than the file's 20 ms; the watchdog is not under test here).
fn run_lqr(addr: SocketAddr, duration: f64, log: &Path) -> RunReport {
    let mut l = load(CART_LQR).unwrap();
    let mut cfg = run_config(&l, addr, TOLERANT_WATCHDOG);
    cfg.duration = Some(duration);
    run_with_log(&cfg, l.controller.as_mut(), Some(log))
}

/// The book cart at `deg` from upright, its watchdog relaxed to 0.5 s where not under test.
fn cart_at(deg: f64, start: PlantStart) -> EmulatorConfig {
    let mut c = emulator(PlantKind::Cart, [0.0, deg.to_radians(), 0.0, 0.0]);
    c.start = start;
    c
}

#[test]
fn the_tour_lqr_started_a_second_late_balances_the_held_pendulum_twice() {
    let x0 = [0.0, 10f64.to_radians(), 0.0, 0.0];
    let c = cart_at(10.0, PlantStart::HeldUntilCommand);
    assert_eq!(c.start, PlantStart::default());
    let emu = Emulator::spawn(c).unwrap();
    let h = emu.handle();
    // The scenario: the controller of the second terminal comes a second later.
    std::thread::sleep(Duration::from_secs(1));
    let tel = h.telemetry();
    // Held: the state is the initial one, bit for bit, while the rig's clock ran on.
    assert!(tel.holding, "{tel:?}");
    assert_eq!(tel.state, x0);
    assert!(tel.t > 0.0);
    assert_eq!(tel.sessions, 0);
    for n in 1..=2u64 {
        let log = tmp(&format!("run{n}.csv"));
        let r = run_lqr(emu.addr(), 1.5, &log);
        assert_eq!(r.reason, StopReason::Completed, "run {n}: {}", r.detail);
        // The first frame the run logged is the held pendulum: 10° to the encoder's count.
        let th = first_theta(&log);
        assert!(
            (th - 10f64.to_radians()).abs() <= COUNT,
            "run {n}: first θ = {}°",
            th.to_degrees()
        );
        // The run's STOP freed the rig (one more session served); the pendulum is no longer
        // held: the motor is off and it runs on from where the run left it until the next
        // session puts it back (the second run's first frame above).
        let tel = wait_for(&h, "freed after the run", |t| t.session == 0);
        assert!(!tel.holding, "run {n}: {tel:?}");
        assert_ne!(tel.state, x0, "run {n}");
        assert_eq!(tel.sessions, n);
        assert_eq!(tel.applied_volts, 0.0);
    }
    emu.stop().unwrap();
}

#[test]
fn free_running_the_pendulum_has_fallen_when_the_controller_connects() {
    // The emulator of before: integrated from launch. The 10° pendulum, left alone with the
    // cart at rest (z̈ = −a_c ż keeps ż = 0, so it is the fixed-pivot pendulum
    // J θ̈ = m_p g l_p sin θ − μ_p θ̇), passes 30° at 0.31 s, 90° at 0.51 s and swings back
    // into the 30° window on the other side only at 1.04 s (RK4 at 0.1 ms in Python on the
    // book's table 3.5 values). The run is started once the emulator reports 90°.
    let emu = Emulator::spawn(cart_at(10.0, PlantStart::FreeRunning)).unwrap();
    let h = emu.handle();
    assert!(!h.telemetry().holding);
    wait_for(&h, "fallen past 90°", |t| {
        wrap(t.state[1]).abs() > 90f64.to_radians()
    });
    let log = tmp("free.csv");
    let r = run_lqr(emu.addr(), 1.5, &log);
    assert_eq!(r.reason, StopReason::AngleWindow, "{}", r.detail);
    assert!(wrap(first_theta(&log)).abs() > 30f64.to_radians());
    assert!(!h.telemetry().holding);
    emu.stop().unwrap();
}

/// A controller speaking the wire protocol by hand.
struct Client {
    socket: UdpSocket,
    session: u32,
    seq: u32,
}

impl Client {
    fn new(addr: SocketAddr, session: u32) -> Self {
        let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
        socket.connect(addr).unwrap();
        socket
            .set_read_timeout(Some(Duration::from_secs(5)))
            .unwrap();
        Self {
            socket,
            session,
            seq: 0,
        }
    }

    /// Sends a 0 V command with `fl` flags.
    fn send(&mut self, fl: u16) {
        self.seq += 1;
        let c = CommandFrame {
            session: self.session,
            seq: self.seq,
            microvolts: 0,
            flags: fl,
            sensor_seq: 0,
        };
        self.socket.send(&c.encode()).unwrap();
    }

    /// The next sensor frame.
    fn frame(&self) -> SensorFrame {
        let mut buf = [0u8; 64];
        let n = self.socket.recv(&mut buf).unwrap();
        SensorFrame::decode(&buf[..n]).unwrap()
    }
}

#[test]
fn disabled_commands_keep_the_hold_an_enabling_one_lets_go_the_next_session_puts_it_back() {
    let x0 = [0.0, 10f64.to_radians(), 0.0, 0.0];
    let mut c = cart_at(10.0, PlantStart::HeldUntilCommand);
    c.watchdog = Duration::from_secs(30);
    let emu = Emulator::spawn(c).unwrap();
    let h = emu.handle();
    // A controller connecting (disabled 0 V commands, as `rig run` sends until the rig
    // answers): every frame it gets carries the held angle.
    let mut a = Client::new(emu.addr(), 41);
    a.send(0);
    for i in 0..200 {
        let f = a.frame();
        assert_eq!(f.session, 41);
        assert_eq!(f.counts, [0, held_counts(10.0)], "frame {i}");
        if i % 20 == 0 {
            a.send(0);
        }
    }
    let tel = h.telemetry();
    assert!(tel.holding && tel.sessions == 1, "{tel:?}");
    assert_eq!(tel.state, x0);
    // The first enabling command (0 V: the motor does nothing) lets go: the pendulum falls
    // away from upright, the encoder counts rise from the held −6800.
    a.send(flags::ENABLE);
    let t0 = Instant::now();
    while a.frame().counts[1] <= held_counts(10.0) {
        assert!(t0.elapsed() < Duration::from_secs(10), "never released");
    }
    let tel = h.telemetry();
    assert!(!tel.holding, "{tel:?}");
    assert!(tel.state[1] > x0[1]);
    // STOP ends the session: the motor is off and the pendulum goes on falling (not put back
    // yet: the telemetry keeps what the session left).
    a.send(flags::STOP);
    let tel = wait_for(&h, "freed by STOP", |t| t.session == 0);
    assert!(!tel.holding, "{tel:?}");
    assert!(tel.state[1] > x0[1]);
    // The next controller finds the pendulum back at the initial state, held; a STOP is no
    // session served.
    let mut b = Client::new(emu.addr(), 42);
    b.send(0);
    assert_eq!(b.frame().counts, [0, held_counts(10.0)]);
    let tel = wait_for(&h, "the next session", |t| t.sessions == 2);
    assert!(tel.holding && tel.session == 42, "{tel:?}");
    assert_eq!(tel.state, x0);
    emu.stop().unwrap();
}

#[test]
fn after_the_watchdog_the_pendulum_falls_until_the_next_session_puts_it_back() {
    let x0 = [0.0, 10f64.to_radians(), 0.0, 0.0];
    let mut c = cart_at(10.0, PlantStart::HeldUntilCommand);
    c.watchdog = Duration::from_millis(50);
    let emu = Emulator::spawn(c).unwrap();
    let h = emu.handle();
    let mut a = Client::new(emu.addr(), 7);
    a.send(flags::ENABLE);
    // The controller vanishes: the watchdog zeroes the motor, and the pendulum falls, as a
    // real one does when its controller dies.
    wait_for(&h, "watchdog", |t| t.watchdog_trips >= 1);
    // (Free, it passes 90° at 0.51 s and is back within 30° of upright only at 1.04 s, see
    // the free-running test above.)
    let tel = wait_for(&h, "fallen", |t| {
        wrap(t.state[1]).abs() > 90f64.to_radians()
    });
    assert!(!tel.holding && !tel.enabled, "{tel:?}");
    // The same controller coming back in its session (a stall of its own) finds the pendulum
    // where it left it: no reset.
    let accepted = tel.commands_accepted;
    a.send(0);
    let tel = wait_for(&h, "the same session again", |t| {
        t.commands_accepted > accepted
    });
    assert!(
        !tel.holding && tel.session == 7 && tel.sessions == 1,
        "{tel:?}"
    );
    assert!(wrap(tel.state[1]).abs() > 30f64.to_radians(), "{tel:?}");
    // A new controller, once the watchdog has freed the rig again, is adopted: the pendulum
    // is put back at the initial state and held.
    let mut b = Client::new(emu.addr(), 8);
    let t0 = Instant::now();
    while h.telemetry().sessions < 2 {
        assert!(
            t0.elapsed() < Duration::from_secs(10),
            "{:?}",
            h.telemetry()
        );
        b.send(0);
        std::thread::sleep(Duration::from_millis(10));
    }
    let tel = h.telemetry();
    assert!(tel.holding && tel.session == 8, "{tel:?}");
    assert_eq!(tel.state, x0);
    emu.stop().unwrap();
}

#[test]
fn a_free_running_plant_moves_without_any_command_and_no_session_puts_it_back() {
    let emu = Emulator::spawn(cart_at(10.0, PlantStart::FreeRunning)).unwrap();
    let h = emu.handle();
    // Nobody connected: the pendulum falls all the same.
    let tel = wait_for(&h, "fallen alone", |t| {
        wrap(t.state[1]).abs() > 90f64.to_radians()
    });
    assert!(!tel.holding && tel.commands_accepted == 0, "{tel:?}");
    let mut a = Client::new(emu.addr(), 5);
    a.send(flags::ENABLE);
    a.send(flags::STOP);
    let tel = wait_for(&h, "stopped", |t| t.commands_accepted >= 2);
    assert!(!tel.holding && tel.sessions == 1, "{tel:?}");
    // Nor does a new session put it back: its first frame is nowhere near the initial 10°
    // (−6800 counts; the falling pendulum is more than 30° away, 1200 counts).
    let mut b = Client::new(emu.addr(), 6);
    b.send(0);
    let f = b.frame();
    assert_eq!(f.session, 6);
    assert!((f.counts[1] - held_counts(10.0)).abs() > 1200, "{f:?}");
    let tel = wait_for(&h, "the next session", |t| t.sessions == 2);
    assert!(!tel.holding, "{tel:?}");
    emu.stop().unwrap();
}
