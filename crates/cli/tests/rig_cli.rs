//! `pendulab rig` end to end on loopback: the runtime binary killed mid-run (SIGKILL: the
//! emulator's watchdog zeroes the motor and the log is intact; SIGINT and SIGTERM: a safe stop
//! with every sample logged and the stop's exit status), the emulator subcommand, a log read
//! back by `pendulab identify`, and bad input.
//!
//! Assertions are about behaviour; timing is only printed (2 shared cores under load). The
//! identification accuracy is asserted because the log's time is the rig's, not the loop's.

mod common;
use common::*;

use pendulab_rig::emulator::{Emulator, EmulatorConfig, PlantKind};
use serde_json::Value;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

const CART_LQR: &str = "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [10.0, 10.0, 0.0, 0.0], r = 1.0 }\n[safety]\nwatchdog_periods = 500\n";

fn pendulab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pendulab"))
}

fn spawn_run(addr: &str, controller: &str, log: &str) -> Child {
    pendulab()
        .args([
            "rig",
            "run",
            "--connect",
            addr,
            "--controller",
            controller,
            "--log",
            log,
            "--duration",
            "60",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Rows of a log; panics on a malformed row (every row must be complete).
fn rows(path: &str) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let mut lines = text.lines();
    let Some(header) = lines.next() else {
        return Vec::new();
    };
    let n = header.split(',').count();
    lines
        .map(|l| {
            let r: Vec<f64> = l
                .split(',')
                .map(|x| x.parse().unwrap_or_else(|_| panic!("bad field in {l:?}")))
                .collect();
            assert_eq!(r.len(), n, "incomplete row {l:?}");
            assert!(r.iter().all(|x| x.is_finite()), "non-finite field in {l:?}");
            r
        })
        .collect()
}

/// Waits until the log of a running child has at least `n` rows.
fn wait_rows(path: &str, n: usize, child: &mut Child) {
    let t0 = Instant::now();
    loop {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        if text.lines().count() > n {
            return;
        }
        if let Some(s) = child.try_wait().unwrap() {
            panic!("pendulab rig run exited early: {s}");
        }
        assert!(t0.elapsed() < Duration::from_secs(30), "no progress");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Every rig frame from the first is in the log, in order: the rig's time stamp `t` (column 1)
/// advances by exactly one rig period (1 ms, µs / 10⁶) per row, and the loop period `k`
/// (column 0) that read it never decreases. `skip_last` leaves out a stop row.
fn assert_contiguous(r: &[Vec<f64>], skip_last: bool) {
    let n = if skip_last { r.len() - 1 } else { r.len() };
    for (j, row) in r[..n].iter().enumerate() {
        assert_eq!(row[1], j as f64 / 1e3, "row {j}");
        if j > 0 {
            assert!(row[0] >= r[j - 1][0], "row {j}");
        }
    }
}

#[test]
fn killing_the_controller_makes_the_emulator_zero_the_motor_and_leaves_an_intact_log() {
    let d = Dir::new("kill");
    let mut ec = EmulatorConfig::new(PlantKind::Cart, [0.0, 5f64.to_radians(), 0.0, 0.0]);
    ec.watchdog = Duration::from_millis(50);
    let emu = Emulator::spawn(ec).unwrap();
    let h = emu.handle();
    let ctl = d.file("lqr.toml", CART_LQR);
    let log = d.path("kill.csv");
    let mut child = spawn_run(&emu.addr().to_string(), &ctl, &log);
    wait_rows(&log, 500, &mut child);
    let before = h.telemetry();
    assert!(before.enabled && before.session != 0, "{before:?}");
    child.kill().unwrap(); // SIGKILL: no handler runs
    child.wait().unwrap();
    // The emulator's watchdog (50 ms) zeroes and disables the motor.
    let t0 = Instant::now();
    let tel = loop {
        let tel = h.telemetry();
        if tel.watchdog_active {
            break tel;
        }
        assert!(t0.elapsed() < Duration::from_secs(10), "{tel:?}");
        std::thread::sleep(Duration::from_millis(5));
    };
    assert_eq!(tel.applied_volts, 0.0);
    assert!(!tel.enabled);
    assert!(tel.watchdog_trips >= 1);
    // The log: every row complete and contiguous from k = 0 (nothing torn, nothing skipped).
    let r = rows(&log);
    assert!(r.len() >= 500);
    assert_contiguous(&r, false);
    println!(
        "SIGKILL: {} rows logged; the emulator accepted {} commands",
        r.len(),
        tel.commands_accepted
    );
    emu.stop().unwrap();
}

#[test]
fn ctrl_c_and_sigterm_stop_safely_with_every_sample_logged() {
    let d = Dir::new("sigint");
    let ctl = d.file("lqr.toml", CART_LQR);
    for (signal, tag) in [("-INT", "int"), ("-TERM", "term")] {
        let emu = Emulator::spawn(EmulatorConfig::new(
            PlantKind::Cart,
            [0.0, 5f64.to_radians(), 0.0, 0.0],
        ))
        .unwrap();
        let h = emu.handle();
        let log = d.path(&format!("{tag}.csv"));
        let mut child = spawn_run(&emu.addr().to_string(), &ctl, &log);
        wait_rows(&log, 300, &mut child);
        let st = Command::new("kill")
            .args([signal, &child.id().to_string()])
            .status()
            .unwrap();
        assert!(st.success());
        let out = child.wait_with_output().unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        println!("{stdout}");
        // Exit status 2 = interrupted (StopReason::exit_code), and the reason is printed.
        assert_eq!(out.status.code(), Some(2), "{stdout}");
        assert!(stdout.contains("stop: interrupted"), "{stdout}");
        assert!(stdout.contains("period jitter: p50"));
        let samples: usize = stdout
            .lines()
            .find_map(|l| l.strip_prefix("samples: "))
            .unwrap()
            .parse()
            .unwrap();
        // Every frame up to the stop is in the log, then the 0 V stop row, logged in the
        // stop's period (the last of `samples`).
        let r = rows(&log);
        assert_contiguous(&r, true);
        let last = r.last().unwrap();
        assert_eq!(last[0], (samples - 1) as f64); // column k
        assert_eq!(last[10], 0.0); // column v
        // The STOP frames freed the emulator at once: 0 V, no session.
        let t0 = Instant::now();
        while h.telemetry().session != 0 {
            assert!(t0.elapsed() < Duration::from_secs(10));
            std::thread::sleep(Duration::from_millis(5));
        }
        assert_eq!(h.telemetry().applied_volts, 0.0);
        emu.stop().unwrap();
    }
}

fn emulate(args: &[&str]) -> (Child, String) {
    let mut cmd = pendulab();
    cmd.args(["rig", "emulate", "--listen", "127.0.0.1:0"])
        .args(args);
    spawn_listening(cmd)
}

fn ok(o: &Output) -> String {
    assert!(
        o.status.success(),
        "failed ({:?}): {}{}",
        o.status,
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn a_servo_log_from_the_emulator_identifies_the_book_cart_drive() {
    // `pendulab rig emulate` (the book plant) and `pendulab rig run` with the LQ servo to
    // 0.3 m; the log goes straight into `pendulab identify cart-ls` (columns t, z, v as the
    // rig data of data/rig/). The emulated plant has a_c = 6.25 1/s, b_c = 4.36 m/(s² V)
    // (table 3.5, the emulator's parameters). The log's t is the rig's own stamp (plant time)
    // and v the voltage the rig had applied for each frame, so the loop's late wake-ups do not
    // enter the data: the estimates are those of the rig's uniform record. What remains is
    // systematic and timing-free: v is the voltage applied over the step *before* each
    // sample while the least-squares model holds it over the step after, a shift of one
    // period, a bias of the order of a_c·ts ≈ 0.6 % (the estimates come out 0.3–0.4 % high
    // whatever the load: 26–161 deadline misses gave the same digits), plus the encoder
    // (0.048 mm) and D/A quantisation and the hanging pendulum's reaction, which the drive
    // model leaves out. 2 % bounds that with margin; the nominal-time log this replaces gave
    // 7.8 (+25 %) on a loaded machine, so the bound fails for the defect.
    let d = Dir::new("ident");
    let (mut emu, addr) = emulate(&["--plant", "cart", "--theta0-deg", "0", "--duration", "30"]);
    let ctl = d.file(
        "servo.toml",
        "plant = \"cart\"\n[controller]\nkind = \"lq-servo\"\nlqr = { q = [1.0, 5.0, 0.0, 0.0, 100.0], r = 1.0 }\nreference = [0.3]\nstep_time = 0.5\n[safety]\nwatchdog_periods = 500\n",
    );
    let log = d.path("servo.csv");
    let out = ok(&pendulab()
        .args([
            "rig",
            "run",
            "--connect",
            &addr,
            "--controller",
            &ctl,
            "--log",
            &log,
            "--duration",
            "4",
        ])
        .output()
        .unwrap());
    println!("{out}");
    assert!(out.contains("stop: completed"));
    assert!(out.contains("samples: 4000"));
    emu.kill().unwrap();
    emu.wait().unwrap();
    let v: Value = serde_json::from_str(&ok(&pendulab()
        .args([
            "identify", "cart-ls", "--data", &log, "--window", "0.4:3.5", "--json",
        ])
        .output()
        .unwrap()))
    .unwrap();
    let (ac, bc) = (
        v["estimates"]["ac"].as_f64().unwrap(),
        v["estimates"]["bc"].as_f64().unwrap(),
    );
    println!("identified from the rig log: ac = {ac}, bc = {bc}");
    // 0.4 s to 3.5 s of rig time inclusive at the rig's 1 kHz: every frame is there.
    assert_eq!(v["samples"], 3101);
    assert!((ac / 6.25 - 1.0).abs() < 0.02, "ac = {ac}");
    assert!((bc / 4.36 - 1.0).abs() < 0.02, "bc = {bc}");
}

#[test]
fn bad_input_is_an_error_naming_what_and_where() {
    let d = Dir::new("bad");
    // A controller file with a wrong gain length: exit 1, the key named.
    let bad = d.file(
        "bad.toml",
        "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0, 2.0]\n",
    );
    let o = pendulab()
        .args([
            "rig",
            "run",
            "--connect",
            "127.0.0.1:9",
            "--controller",
            &bad,
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("controller.k") && e.contains("bad.toml"), "{e}");
    // A missing file names the file.
    let o = pendulab()
        .args([
            "rig",
            "run",
            "--connect",
            "127.0.0.1:9",
            "--controller",
            "/nonexistent/c.toml",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("/nonexistent/c.toml"));
    // Nobody listening: "no rig" after the connect timeout, exit 1.
    let quiet = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    let ctl = d.file(
        "c.toml",
        "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [0.0, 0.0, 0.0, 0.0]\n[safety]\nconnect_timeout_s = 0.3\n",
    );
    let o = pendulab()
        .args([
            "rig",
            "run",
            "--connect",
            &quiet.local_addr().unwrap().to_string(),
            "--controller",
            &ctl,
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no rig"));
    // Emulator options out of range.
    let o = pendulab()
        .args(["rig", "emulate", "--plant", "cart", "--loss", "1.5"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("loss"));
    assert!(d.join("").exists());
}

/// A run that should never start: exit 1 and every needle in stderr.
fn refused(o: &Output, needles: &[&str]) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{e}");
    assert_ne!(o.status.code(), Some(101), "panicked: {e}");
    for n in needles {
        assert!(e.contains(n), "stderr lacks {n:?}: {e}");
    }
}

#[test]
fn unbounded_safety_settings_are_refused_in_the_file_and_on_the_command_line() {
    // Issue 21's findings, each of which was accepted. Nothing listens on 127.0.0.1:9: a
    // check that let the run start would end in "no rig" after 0.2 s, which the needles
    // (the flag or key named) tell apart.
    let d = Dir::new("bounds");
    let good = "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [0.0, 0.0, 0.0, 0.0]\n[safety]\nconnect_timeout_s = 0.2\n";
    let ok_file = d.file("ok.toml", good);
    let run = |file: &str, extra: &[&str]| {
        pendulab()
            .args([
                "rig",
                "run",
                "--connect",
                "127.0.0.1:9",
                "--controller",
                file,
            ])
            .args(extra)
            .output()
            .unwrap()
    };
    // In the file: key and value named, exit 1.
    for (i, (line, needles)) in [
        (
            "watchdog_periods = 4294967295",
            &["safety.watchdog_periods = 4294967295", "must be in"][..],
        ),
        (
            "voltage_limit = 1e9",
            &["safety.voltage_limit = 1000000000", "must be in"][..],
        ),
        (
            "travel_limit = 1e300",
            &["safety.travel_limit", "must be in"][..],
        ),
        (
            "angle_window_deg = 1e-300",
            &["safety.angle_window_deg", "must be in"][..],
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let f = d.file(&format!("s{i}.toml"), &format!("{good}{line}\n"));
        let o = run(&f, &[]);
        assert_eq!(o.status.code(), Some(1), "{line}");
        refused(&o, needles);
    }
    // A key of another kind.
    let f = d.file(
        "k2.toml",
        "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [0.0, 0.0, 0.0, 0.0]\nk2 = nan\n",
    );
    refused(&run(&f, &[]), &["k2", "state-feedback"]);
    // On the command line: the flag and its value named.
    for (args, needles) in [
        (
            &["--watchdog-periods", "4294967295"][..],
            &["--watchdog-periods 4294967295", "must be in"][..],
        ),
        (
            &["--watchdog-periods", "0"][..],
            &["--watchdog-periods 0"][..],
        ),
        (&["--rt-priority", "200"][..], &["--rt-priority", "200"][..]),
        (&["--rt-priority", "0"][..], &["--rt-priority", "0"][..]),
        (
            &["--cpu", "100000"][..],
            &["--cpu 100000", "must be below"][..],
        ),
        (
            &["--duration", "1e20"][..],
            &["--duration", "must be in"][..],
        ),
        (&["--duration=-1"][..], &["--duration -1", "must be in"][..]),
    ] {
        refused(&run(&ok_file, args), needles);
    }
    // The emulator's flags: refused before it listens.
    for (args, needles) in [
        (
            &["--plant", "cart", "--q0", "5"][..],
            &["--q0 5", "track"][..],
        ),
        (&["--plant", "cart", "--q0", "-1.5"][..], &["--q0 -1.5"][..]),
        (
            &["--plant", "arm", "--q0", "200"][..],
            &["--q0 200", "arm"][..],
        ),
        (
            &["--plant", "cart", "--theta0-deg", "1e9"][..],
            &["--theta0-deg"][..],
        ),
        (&["--plant", "cart", "--noise=-1"][..], &["--noise -1"][..]),
        (&["--plant", "cart", "--noise", "1e9"][..], &["--noise"][..]),
        (
            &["--plant", "cart", "--friction", "10"][..],
            &["--friction 10"][..],
        ),
        (&["--plant", "cart", "--loss", "1"][..], &["--loss 1"][..]),
        (
            &["--plant", "cart", "--latency-ms", "1e9"][..],
            &["--latency-ms"][..],
        ),
        (
            &["--plant", "cart", "--duration", "1e20"][..],
            &["--duration"][..],
        ),
        (
            &["--plant", "cart", "--rt-priority", "200"][..],
            &["--rt-priority"][..],
        ),
    ] {
        let o = pendulab()
            .args(["rig", "emulate", "--listen", "127.0.0.1:0"])
            .args(args)
            .output()
            .unwrap();
        refused(&o, needles);
        assert!(
            !String::from_utf8_lossy(&o.stdout).contains("listening"),
            "{args:?}"
        );
    }
}

#[test]
fn connect_takes_a_host_name() {
    // `localhost:PORT` reaches the emulator listening on 127.0.0.1 (the address chosen is
    // printed), and the run balances the cart from 5° to completion.
    let d = Dir::new("host");
    let emu = Emulator::spawn(EmulatorConfig::new(
        PlantKind::Cart,
        [0.0, 5f64.to_radians(), 0.0, 0.0],
    ))
    .unwrap();
    let h = emu.handle();
    let port = emu.addr().port();
    let ctl = d.file("lqr.toml", CART_LQR);
    let o = pendulab()
        .args([
            "rig",
            "run",
            "--connect",
            &format!("localhost:{port}"),
            "--controller",
            &ctl,
            "--duration",
            "0.5",
        ])
        .output()
        .unwrap();
    let out = ok(&o);
    println!("{out}");
    assert!(
        out.contains(&format!("against localhost:{port} (127.0.0.1:{port})")),
        "{out}"
    );
    assert!(out.contains("stop: completed"), "{out}");
    assert!(h.telemetry().commands_accepted > 0);
    emu.stop().unwrap();
    // Names that do not resolve, and text that is no HOST:PORT, are errors naming --connect.
    for bad in ["no-such-host.invalid:5005", "localhost", "127.0.0.1"] {
        let o = pendulab()
            .args(["rig", "run", "--connect", bad, "--controller", &ctl])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(1), "{bad}");
        refused(&o, &[&format!("--connect {bad}")]);
    }
}

#[test]
fn emulate_stops_by_itself_after_its_duration() {
    // The emulator's own clock ends `--duration` (the 1e20 of issue 21 is refused above).
    let o = pendulab()
        .args([
            "rig",
            "emulate",
            "--plant",
            "arm",
            "--listen",
            "127.0.0.1:0",
            "--duration",
            "0.3",
        ])
        .output()
        .unwrap();
    let out = ok(&o);
    assert!(out.starts_with("listening on 127.0.0.1:"), "{out}");
    assert!(out.contains("emulated "), "{out}");
}

/// One count of the book rig's pendulum encoder: 14 400 counts a turn \[rad\].
const PENDULUM_COUNT: f64 = 2.0 * std::f64::consts::PI / 14_400.0;

/// The README's rig tour controller.
const TOUR_LQR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../docs/rig/examples/cart_lqr.toml"
);

/// `pendulab rig run` of the tour's LQR for 1.5 s against `addr`, logged to `log`. The
/// runtime's watchdog is relaxed to 0.5 s (`--watchdog-periods 500`): a 2-core machine shared
/// with builds can deschedule a thread for longer than the file's 20 ms, and the watchdog is
/// not under test here.
fn tour_run(addr: &str, log: &str) -> Output {
    pendulab()
        .args(["rig", "run", "--connect", addr, "--controller", TOUR_LQR])
        .args([
            "--log",
            log,
            "--duration",
            "1.5",
            "--watchdog-periods",
            "500",
        ])
        .output()
        .unwrap()
}

/// Ends `pendulab rig emulate` with Ctrl-C (SIGINT) and returns the rest of its output.
fn interrupt(emu: Child) -> String {
    let st = Command::new("kill")
        .args(["-INT", &emu.id().to_string()])
        .status()
        .unwrap();
    assert!(st.success());
    let out = emu.wait_with_output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "{text}");
    text
}

#[test]
fn the_rig_tour_works_with_the_controller_a_second_late_and_twice() {
    // Issue 18: the tour's two terminals, the second started a while after the first. The
    // emulator holds the 10° pendulum until the controller's first command: the run completes
    // and its first logged frame is the held 10°, to one encoder count; a second run against
    // the same emulator finds it held at 10° again. (`--duration 60` only keeps a failed test
    // from leaving the emulator running.)
    let d = Dir::new("tour");
    let (emu, addr) = emulate(&["--plant", "cart", "--theta0-deg", "10", "--duration", "60"]);
    std::thread::sleep(Duration::from_secs(1));
    for n in 1..=2 {
        let log = d.path(&format!("tour{n}.csv"));
        let o = tour_run(&addr, &log);
        let out = ok(&o);
        assert!(out.contains("stop: completed"), "run {n}: {out}");
        let first = &rows(&log)[0];
        let theta = first[6]; // k,t,t_nominal,t_wall,seq,z,theta
        assert!(
            (theta - 10f64.to_radians()).abs() <= PENDULUM_COUNT,
            "run {n}: first θ = {}°",
            theta.to_degrees()
        );
    }
    let out = interrupt(emu);
    println!("{out}");
    assert!(out.contains("sessions served 2,"), "{out}");
}

#[test]
fn free_running_the_tour_pendulum_falls_before_the_controller_connects() {
    // `--free-run`: the emulator of before, integrating from launch. The 10° pendulum left
    // alone (the cart at rest stays at rest: the fixed-pivot pendulum
    // J θ̈ = m_p g l_p sin θ − μ_p θ̇ of the book's table 3.5) is outside the 30° window from
    // 0.31 s to 1.04 s after launch (RK4 at 0.1 ms in Python), so a controller started 0.45 s
    // after the emulator finds it fallen: angle-window, exit 5, at the first frame.
    let d = Dir::new("tour-free");
    let (emu, addr) = emulate(&[
        "--plant",
        "cart",
        "--theta0-deg",
        "10",
        "--free-run",
        "--duration",
        "60",
    ]);
    std::thread::sleep(Duration::from_millis(450));
    let log = d.path("free.csv");
    let o = tour_run(&addr, &log);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(5), "{out}");
    assert!(out.contains("stop: angle-window"), "{out}");
    let theta = rows(&log)[0][6];
    assert!(
        theta.sin().atan2(theta.cos()).abs() > 30f64.to_radians(),
        "first θ = {}°",
        theta.to_degrees()
    );
    let out = interrupt(emu);
    assert!(out.contains("sessions served 1,"), "{out}");
}
