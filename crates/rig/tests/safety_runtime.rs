//! The runtime's safety findings of issue 21, each on the emulator or a fake rig on UDP
//! loopback: the pendulum angle wrapped about the equilibrium (a start "the other way round",
//! a one-turn encoder jump mid-run), stale data bridged by holding the last command and
//! stopped by the watchdog with 0 V on the wire, 0 V in the log before the rig is enabled,
//! one wild sequence number, the rig's clock going backwards, and the emulator's duration.
//!
//! As in `loopback.rs`, assertions are about behaviour and counters, never about timing; every
//! run is short (≤ 2.5 s).

mod common;
use common::{
    CART_LQR, Log, TOLERANT_WATCHDOG, col, load, read_log, run_config, run_with_log, tmp, wrap,
};
use pendulab_rig::emulator::{Emulator, EmulatorConfig, PlantKind};
use pendulab_rig::protocol::{CommandFrame, SensorFrame, flags, status};
use pendulab_rig::runtime::RunReport;
use pendulab_rig::{RigError, StopReason};
use pendulab_sim::Controller;
use std::f64::consts::PI;
use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// The emulated cart rig with its watchdog relaxed to 0.5 s (not under test here).
fn emulator(x0: [f64; 4]) -> Emulator {
    Emulator::spawn(common::emulator(PlantKind::Cart, x0)).unwrap()
}

/// A controller that counts its updates and records the largest |θ| it was given.
struct Counting {
    inner: Box<dyn Controller>,
    calls: Arc<Mutex<(u64, f64)>>,
}

impl Controller for Counting {
    fn ny(&self) -> usize {
        self.inner.ny()
    }
    fn nu(&self) -> usize {
        self.inner.nu()
    }
    fn reset(&mut self) {
        self.inner.reset()
    }
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        let mut c = self.calls.lock().unwrap();
        c.0 += 1;
        c.1 = c.1.max(y[1].abs());
        self.inner.update(t, y, u)
    }
    fn sample_time(&self) -> Option<f64> {
        self.inner.sample_time()
    }
}

/// Balances the emulated cart for `duration` s with the book's LQR (watchdog 0.5 s, so a
/// loaded machine does not end the run), logging to `log`; `during` runs beside the loop with
/// the emulator's handle. Returns the report, the final true state, the largest true
/// |wrapped θ|, the log and (controller updates, largest |θ| the controller saw).
fn balance(
    x0: [f64; 4],
    duration: f64,
    log: &str,
    during: impl FnOnce(pendulab_rig::EmulatorHandle) + Send + 'static,
) -> (RunReport, [f64; 4], f64, Log, (u64, f64)) {
    let emu = emulator(x0);
    let h = emu.handle();
    let l = load(CART_LQR).unwrap();
    let mut cfg = run_config(&l, emu.addr(), TOLERANT_WATCHDOG);
    cfg.duration = Some(duration);
    let path = tmp(log);
    let calls = Arc::new(Mutex::new((0, 0.0)));
    let mut c = Counting {
        inner: l.controller,
        calls: Arc::clone(&calls),
    };
    let side = std::thread::spawn(move || during(h));
    let r = run_with_log(&cfg, &mut c, Some(&path));
    side.join().unwrap();
    let tel = emu.stop().unwrap();
    let counted = *calls.lock().unwrap();
    (r, tel.state, tel.max_abs_pendulum, read_log(&path), counted)
}

/// The largest |v_sent| of the rows with `from_t ≤ t < to_t`.
fn max_abs_v_sent(log: &Log, from_t: f64, to_t: f64) -> f64 {
    let (hd, rows) = log;
    let (vi, ti) = (col(hd, "v_sent"), col(hd, "t"));
    rows.iter()
        .filter(|r| r[ti] >= from_t && r[ti] < to_t)
        .map(|r| r[vi].abs())
        .fold(0.0, f64::max)
}

#[test]
fn the_other_way_round_start_balances_like_the_direct_start() {
    // The same physical start, 2° from upright, once raised directly and once the other way
    // round: the pendulum encoder (counting from the hanging rest) reads a whole turn more.
    let theta0 = 2f64.to_radians();
    let direct = balance([0.0, theta0, 0.0, 0.0], 2.0, "direct.csv", |_| {});
    let round = balance([0.0, theta0 + 2.0 * PI, 0.0, 0.0], 2.0, "round.csv", |_| {});
    for (name, (r, x, max_th, log, _)) in [("direct", &direct), ("other way round", &round)] {
        assert_eq!(r.reason, StopReason::Completed, "{name}: {}", r.detail);
        // Never saturated: the raw angle's 2π error would demand far more than 5 V at once.
        assert_eq!(r.stats.clamped, 0, "{name}");
        // Balanced: upright within 1° after 2 s (the LQR settles from 2° in about a second),
        // never beyond 4°.
        assert!(wrap(x[1]).abs() < 1f64.to_radians(), "{name}: {x:?}");
        assert!(*max_th < 4f64.to_radians(), "{name}: {max_th}");
        assert!(max_abs_v_sent(log, 0.0, f64::INFINITY) > 0.0);
    }
    // The log keeps the raw angle: a whole turn apart between the two runs.
    let th = |log: &Log| log.1[0][col(&log.0, "theta")];
    assert!((th(&round.3) - th(&direct.3) - 2.0 * PI).abs() < 0.5f64.to_radians());
    // Like the direct start: the largest command within a factor of 1.5 (both are set by
    // the first periods, 2° and the few ms of fall before the loop connects), same sign.
    let (vd, vr) = (
        max_abs_v_sent(&direct.3, 0.0, f64::INFINITY),
        max_abs_v_sent(&round.3, 0.0, f64::INFINITY),
    );
    assert!(
        vr < 1.5 * vd && vd < 1.5 * vr,
        "direct {vd} V, other way round {vr} V"
    );
}

#[test]
fn a_one_turn_encoder_jump_mid_run_causes_no_lunge() {
    // Balanced from 2°; after 1 s the pendulum encoder gains a whole turn.
    let (r, x, max_th, log, (calls, max_y1)) =
        balance([0.0, 2f64.to_radians(), 0.0, 0.0], 2.5, "jump.csv", |h| {
            std::thread::sleep(Duration::from_millis(1000));
            h.shift_pendulum_encoder(1);
        });
    assert_eq!(r.reason, StopReason::Completed, "{}", r.detail);
    assert!(calls > 0);
    // The jump happened: the logged (raw) angle moves by a whole turn.
    let (hd, rows) = &log;
    let (thi, ti) = (col(hd, "theta"), col(hd, "t"));
    let t_jump = rows
        .windows(2)
        .find(|w| (w[1][thi] - w[0][thi]).abs() > PI)
        .map(|w| w[1][ti])
        .expect("the log shows the encoder's jump");
    let last = rows.last().unwrap();
    assert!((last[thi] - 2.0 * PI - wrap(last[thi])).abs() < 1e-9);
    // No lunge: the controller never saw more than the window's angle, no command was
    // clamped, the commands after the jump stay within what the run used before it, and the
    // pendulum ends balanced.
    assert!(max_y1 < 30f64.to_radians(), "{max_y1}");
    assert_eq!(r.stats.clamped, 0);
    let before = max_abs_v_sent(&log, 0.0, t_jump);
    let after = max_abs_v_sent(&log, t_jump, f64::INFINITY);
    assert!(
        after <= before,
        "after the jump {after} V, before {before} V"
    );
    assert!(wrap(x[1]).abs() < 1f64.to_radians(), "{x:?}");
    assert!(max_th < 4f64.to_radians());
}

#[test]
fn a_short_rig_stall_is_bridged_by_holding_the_last_command() {
    // The rig freezes for 8 ms at 0.5 s, well inside the hold. The hold and the watchdog are
    // at their largest (0.1 s and 0.5 s), so that the longer stalls a machine shared with
    // builds may add are held too rather than ending the run.
    let emu = emulator([0.0, 2f64.to_radians(), 0.0, 0.0]);
    let h = emu.handle();
    let l = load(CART_LQR).unwrap();
    let mut cfg = run_config(&l, emu.addr(), TOLERANT_WATCHDOG);
    cfg.duration = Some(1.5);
    cfg.safety.stale_hold_periods = 100;
    let calls = Arc::new(Mutex::new((0, 0.0)));
    let mut c = Counting {
        inner: l.controller,
        calls: Arc::clone(&calls),
    };
    let side = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(500));
        h.stall(Duration::from_millis(8));
    });
    let r = run_with_log(&cfg, &mut c, None);
    side.join().unwrap();
    let tel = emu.stop().unwrap();
    let s = r.stats;
    assert_eq!(r.reason, StopReason::Completed, "{}", r.detail);
    // The stall was seen (≥ 5 of its 8 periods without a frame) and bridged by held commands.
    assert!(s.longest_stale_run >= 5, "{s:?}");
    assert!(s.held_commands >= 1, "{s:?}");
    assert_eq!(s.zero_commands, 0, "{s:?}");
    // Every stale period sent a held command or 0 V; and the controller computed a command
    // in exactly the periods with a fresh frame (never from a stale measurement).
    assert_eq!(s.held_commands + s.zero_commands, s.stale_periods);
    let run_periods = r.samples - s.skipped_periods;
    assert_eq!(calls.lock().unwrap().0, run_periods - s.stale_periods);
    assert!(
        wrap(tel.state[1]).abs() < 1f64.to_radians(),
        "{:?}",
        tel.state
    );
    assert!(r.to_string().contains("held commands"));
}

/// A fake rig on loopback: answers the first command, then sends `frames` (each with the
/// session filled in) one per ms, then goes silent while recording every command it receives
/// until `listen_after` has passed.
fn fake_rig(
    frames: Vec<SensorFrame>,
    listen_after: Duration,
) -> (SocketAddr, std::thread::JoinHandle<Vec<CommandFrame>>) {
    let rig = UdpSocket::bind("127.0.0.1:0").unwrap();
    let addr = rig.local_addr().unwrap();
    let t = std::thread::spawn(move || {
        let mut buf = [0u8; 64];
        let (n, peer) = rig.recv_from(&mut buf).unwrap();
        let first = CommandFrame::decode(&buf[..n]).unwrap();
        let mut got = vec![first];
        rig.set_nonblocking(true).unwrap();
        let mut drain = |got: &mut Vec<CommandFrame>| {
            while let Ok(n) = rig.recv(&mut buf) {
                if let Ok(c) = CommandFrame::decode(&buf[..n]) {
                    got.push(c);
                }
            }
        };
        for f in frames {
            let f = SensorFrame {
                session: first.session,
                ..f
            };
            rig.send_to(&f.encode(), peer).unwrap();
            std::thread::sleep(Duration::from_millis(1));
            drain(&mut got);
        }
        let until = std::time::Instant::now() + listen_after;
        while std::time::Instant::now() < until {
            std::thread::sleep(Duration::from_millis(2));
            drain(&mut got);
        }
        got
    });
    (addr, t)
}

fn frame(seq: u32, counts: [i32; 2]) -> SensorFrame {
    SensorFrame {
        session: 0,
        seq,
        time_us: seq as u64 * 1000,
        counts,
        command_seq: 0,
        status: 0,
    }
}

#[test]
fn a_stall_longer_than_the_watchdog_holds_then_sends_0_v_then_stops() {
    // The pendulum still at 2° from upright (80 counts of 2π/14400 rad past the upright
    // −7200) for 150 ms, then silence. The LQR's command for a constant 2° is a constant
    // non-zero voltage, so held commands are recognisable on the wire.
    let frames = (1..=150).map(|s| frame(s, [0, -7200 + 80])).collect();
    let (addr, rig) = fake_rig(frames, Duration::from_millis(400));
    let mut l = load(CART_LQR).unwrap();
    let cfg = run_config(&l, addr, l.safety.watchdog_periods);
    let (hold, watchdog) = (cfg.safety.stale_hold_periods, cfg.safety.watchdog_periods);
    let r = run_with_log(&cfg, l.controller.as_mut(), None);
    let cmds = rig.join().unwrap();
    assert_eq!(r.reason, StopReason::Watchdog, "{}", r.detail);
    let s = r.stats;
    // On the wire, from the command computed from frame 150 (the last frame) on: only held
    // commands (its voltage again), then 0 V enabled, then 0 V with STOP — nothing else.
    let i0 = cmds
        .iter()
        .position(|c| c.sensor_seq == 150 && c.flags == flags::ENABLE)
        .unwrap();
    let tail = &cmds[i0..];
    let computed = tail[0].microvolts;
    assert_ne!(computed, 0);
    let held = tail[1..]
        .iter()
        .take_while(|c| c.microvolts == computed && c.flags == flags::ENABLE)
        .count();
    let zeros = tail[1 + held..]
        .iter()
        .take_while(|c| c.microvolts == 0 && c.flags == flags::ENABLE)
        .count();
    let stops = &tail[1 + held + zeros..];
    assert!(held + zeros >= 1);
    assert!(held <= hold as usize && zeros <= (watchdog - 1 - hold) as usize);
    assert!(!stops.is_empty());
    assert!(
        stops
            .iter()
            .all(|c| c.microvolts == 0 && c.flags & flags::STOP != 0),
        "{stops:?}"
    );
    // The report counts every stale period's command (earlier, shorter gaps between the fake
    // rig's frames included); the watchdog's own period is stale and sends the STOP instead.
    assert_eq!(s.held_commands + s.zero_commands + 1, s.stale_periods);
    assert!(s.held_commands >= held as u64 && s.zero_commands >= zeros as u64);
}

#[test]
fn log_rows_before_the_rig_is_enabled_carry_0_v() {
    let emu = emulator([0.0, 1f64.to_radians(), 0.0, 0.0]);
    let mut l = load(CART_LQR).unwrap();
    let mut cfg = run_config(&l, emu.addr(), TOLERANT_WATCHDOG);
    cfg.duration = Some(0.3);
    let path = tmp("enable.csv");
    let r = run_with_log(&cfg, l.controller.as_mut(), Some(&path));
    emu.stop().unwrap();
    assert_eq!(r.reason, StopReason::Completed, "{}", r.detail);
    let (hd, rows) = read_log(&path);
    let (vi, sti) = (col(&hd, "v"), col(&hd, "status"));
    let enabled = |row: &Vec<f64>| (row[sti] as u16) & status::ENABLED != 0;
    // The connect phase's frames come first, from a rig not yet enabled: 0 V applied.
    let before: Vec<_> = rows.iter().take_while(|r| !enabled(r)).collect();
    assert!(!before.is_empty());
    assert!(before.iter().all(|r| r[vi] == 0.0), "{before:?}");
    // Once enabled, the log shows the voltages the loop sent (non-zero at 1°).
    assert!(rows.iter().any(|r| enabled(r) && r[vi] != 0.0));
}

#[test]
fn one_wild_sequence_number_does_not_reject_the_good_frames_after_it() {
    // Frames 1..=120 at upright; after frame 60 one frame 2³¹ − 1 ahead, whose cart count
    // (≈ 0.97 m) would trip the travel limit if it were ever used.
    let mut frames: Vec<SensorFrame> = (1..=120).map(|s| frame(s, [0, -7200])).collect();
    frames.insert(
        60,
        frame(60u32.wrapping_add((1 << 31) - 1), [20_000, -7200]),
    );
    let (addr, rig) = fake_rig(frames, Duration::ZERO);
    let mut l = load(CART_LQR).unwrap();
    let cfg = run_config(&l, addr, 100);
    let path = tmp("wild.csv");
    let r = run_with_log(&cfg, l.controller.as_mut(), Some(&path));
    rig.join().unwrap();
    assert_eq!(r.reason, StopReason::Watchdog, "{}", r.detail);
    assert_eq!(r.stats.rejects.jump, 1);
    assert_eq!(r.stats.rejects.out_of_order, 0);
    // Every good frame was used and logged (120 rows and the stop row), none of the wild one.
    let (hd, rows) = read_log(&path);
    assert_eq!(rows.len(), 121);
    let (zi, si) = (col(&hd, "z"), col(&hd, "seq"));
    assert!(rows.iter().all(|r| r[zi] == 0.0));
    assert_eq!(rows[119][si], 120.0);
}

#[test]
fn rig_time_going_backwards_is_counted_and_warned_about() {
    // Fresh sequence numbers 1..=80, but frame 40 stamped 5 ms before frame 39.
    let mut frames: Vec<SensorFrame> = (1..=80).map(|s| frame(s, [0, -7200])).collect();
    frames[39].time_us = frames[38].time_us - 5000;
    let (addr, rig) = fake_rig(frames, Duration::ZERO);
    let mut l = load(CART_LQR).unwrap();
    let cfg = run_config(&l, addr, 100);
    let r = run_with_log(&cfg, l.controller.as_mut(), None);
    rig.join().unwrap();
    // Backwards once (frame 40 after 39); frame 41 is later than 40 again.
    assert_eq!(r.stats.rig_time_backwards, 1);
    let text = r.to_string();
    assert!(
        text.contains("warning") && text.contains("backwards 1 times"),
        "{text}"
    );
}

#[test]
fn emulator_durations_are_validated_and_honoured() {
    for bad in [1e20, f64::NAN, f64::INFINITY, 0.0, -1.0] {
        let mut c = EmulatorConfig::new(PlantKind::Cart, [0.0, PI, 0.0, 0.0]);
        c.duration = Some(bad);
        match Emulator::spawn(c) {
            Err(RigError::Config(m)) => assert!(m.to_string().contains("duration"), "{m}"),
            Err(e) => panic!("{bad}: {e}"),
            Ok(_) => panic!("{bad} accepted"),
        }
    }
    // A valid duration ends the emulator by itself: wait returns without the stop flag.
    let mut c = EmulatorConfig::new(PlantKind::Cart, [0.0, PI, 0.0, 0.0]);
    c.duration = Some(0.2);
    let tel = Emulator::spawn(c)
        .unwrap()
        .wait(&AtomicBool::new(false))
        .unwrap();
    assert!(tel.t > 0.0);
}
