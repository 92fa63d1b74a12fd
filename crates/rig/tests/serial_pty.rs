//! The runtime over a serial line (feature `serial`): a pseudo-terminal pair stands for the
//! USB-serial cable, a thread on the master side plays the rig.
#![cfg(all(feature = "serial", unix))]

use pendulab_rig::protocol::{
    COMMAND_LEN, CommandFrame, KIND_COMMAND, SensorFrame, StreamDecoder, flags,
};
use pendulab_rig::runtime::{RunConfig, run};
use pendulab_rig::{PlantKind, StopReason};
use pendulab_sim::controllers::StaticStateFeedback;
use serialport::{SerialPort, TTYPort};
use std::io::{Read, Write};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

#[test]
fn the_loop_runs_over_a_serial_line_with_garbage_in_the_stream() {
    let (mut master, slave) = TTYPort::pair().unwrap();
    let name = slave.name().unwrap();
    master.set_timeout(Duration::from_millis(1)).unwrap();
    let rig = std::thread::spawn(move || {
        let mut dec = StreamDecoder::new();
        let mut buf = [0u8; 512];
        let mut session = 0;
        let mut seq = 0u32;
        let mut enabled_commands = 0u32;
        let mut stop_seen = false;
        let t0 = Instant::now();
        while t0.elapsed() < Duration::from_secs(20) && !stop_seen {
            if let Ok(n) = master.read(&mut buf) {
                dec.push(&buf[..n]);
            }
            while let Some(f) = dec.next_frame(COMMAND_LEN, KIND_COMMAND) {
                let c = CommandFrame::decode(&f).unwrap();
                session = c.session;
                if c.flags & flags::ENABLE != 0 {
                    enabled_commands += 1;
                }
                stop_seen |= c.flags & flags::STOP != 0;
            }
            if session != 0 {
                seq += 1;
                let f = SensorFrame {
                    session,
                    seq,
                    time_us: t0.elapsed().as_micros() as u64,
                    counts: [100, -7200],
                    command_seq: 0,
                    status: 0,
                };
                // Line noise before every tenth frame: the runtime must resynchronise.
                if seq.is_multiple_of(10) {
                    master.write_all(b"\x00noise").unwrap();
                }
                master.write_all(&f.encode()).unwrap();
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        (enabled_commands, stop_seen)
    });
    let mut k = StaticStateFeedback::new(pendulab_lti::Mat::zeros(1, 4)).unwrap();
    let mut cfg = RunConfig::new(PlantKind::Cart, "127.0.0.1:9".parse().unwrap());
    cfg.serial = Some((name, 115_200));
    cfg.duration = Some(0.5);
    cfg.safety.watchdog_periods = 500;
    let r = run(&cfg, &mut k, &AtomicBool::new(false), None).unwrap();
    println!("{r}");
    let (enabled, stop) = rig.join().unwrap();
    assert_eq!(r.reason, StopReason::Completed, "{}", r.detail);
    // Every period sent one enabled command; the rig read them all and the final stop.
    assert_eq!(enabled as u64, r.samples);
    assert!(stop);
    // The encoder reading went through: q0 = 100 counts of 4.8414e-5 m.
    assert!((r.last_y[0] - 100.0 * 4.8414e-5).abs() < 1e-12);
}
