//! The controller files shipped in docs/rig/examples, and those the README's tour and the
//! loopback tests write, load, build (`pendulab_control::spec::build`) and give a 4-in, 1-out controller with limits inside their
//! documented ranges.

mod common;
use common::load;
use pendulab_rig::config::ControllerSpec;

#[test]
fn every_example_controller_file_loads() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/rig/examples");
    let mut n = 0;
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "toml") {
            let text = std::fs::read_to_string(&p).unwrap();
            let l = load(&text).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            assert_eq!(
                (l.controller.ny(), l.controller.nu()),
                (4, 1),
                "{}",
                p.display()
            );
            assert!(ControllerSpec::KINDS.contains(&l.spec.kind()));
            l.safety
                .validate_at(l.plant, l.ts)
                .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            // Every kind balances upright (module documentation of `config`).
            assert_eq!(l.pendulum_centre, 0.0, "{}", p.display());
            n += 1;
        }
    }
    assert_eq!(n, 6);
}

#[test]
fn the_shipped_files_keep_their_written_limits() {
    // What the files say is what runs: cart_lqr.toml writes every safety key, the servo and
    // swing-up files their travel limits (no key silently dropped or replaced).
    let read = |name: &str| {
        let p = format!(
            "{}/../../docs/rig/examples/{name}",
            env!("CARGO_MANIFEST_DIR")
        );
        load(&std::fs::read_to_string(p).unwrap()).unwrap()
    };
    let l = read("cart_lqr.toml");
    assert_eq!(l.safety.voltage_limit, 5.0);
    assert_eq!(l.safety.travel_limit, 0.4);
    assert_eq!(l.safety.angle_window, Some(30f64.to_radians()));
    assert_eq!(l.safety.watchdog_periods, 20);
    assert_eq!(l.ts, 1e-3);
    assert_eq!(read("cart_lq_servo.toml").safety.travel_limit, 0.75);
    let s = read("cart_swing_up.toml");
    assert_eq!((s.safety.travel_limit, s.safety.angle_window), (0.45, None));
}
