use super::*;

const SF: &str =
    "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0, 1.0, 1.0, 1.0]\n";

#[test]
fn a_balancing_file_has_the_default_angle_window() {
    // The gain itself is the factory's (pendulab_control::spec, which checks it against
    // the book's cdip_lqr_sim); the file gives the run its default 30° window.
    let l = load(
        "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [10.0, 10.0, 0.0, 0.0], r = 1.0 }\n",
    )
    .unwrap();
    assert_eq!(l.safety.angle_window, Some(30f64.to_radians()));
}

#[test]
fn bad_files_are_typed_errors_naming_the_key() {
    let cases = [
        (
            "plant = \"boat\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\n",
            "boat",
        ),
        (
            "plant = \"cart\"\n[controller]\nkind = \"nope\"\n",
            "controller.kind",
        ),
        ("plant = \"cart\"\n[controller]\nk = [1.0]\n", "kind"),
        (
            "plant = \"cart\"\nrate_hz = -1.0\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\n",
            "rate_hz",
        ),
        (
            "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\n[safety]\nvoltage_limit = 0.0\n",
            "voltage_limit",
        ),
        (
            "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\ntypo = 3\n",
            "typo",
        ),
        (
            "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\n[safety]\nwatchdog = 3\n",
            "watchdog",
        ),
        ("plant = \"cart\"\n[controller\n", "controller file"),
    ];
    for (text, needle) in cases {
        let e = load(text).unwrap_err().to_string();
        assert!(e.contains(needle), "{e:?} should mention {needle:?}");
    }
}

/// The keys of each kind (`pendulab_control::spec`'s table).
const KEYS: [(&str, &[&str]); 8] = ControllerSpec::KEYS;

/// The smallest `[controller]` table of each kind (zero gains; the NMPC's keys all have
/// defaults).
const BODIES: [(&str, &str); 8] = [
    ("state-feedback", "k = [0.0, 0.0, 0.0, 0.0]"),
    ("lq-servo", "k1 = [0.0, 0.0, 0.0, 0.0]\nk2 = 0.0"),
    ("gain-scheduled", "coefficients = [[0.0, 0.0, 0.0, 0.0]]"),
    ("swing-up-balance", "balance = { k = [0.0, 0.0, 0.0, 0.0] }"),
    (
        "observer",
        "k = [0.0, 0.0, 0.0, 0.0]\nl = [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]",
    ),
    ("pid", "form = \"p\"\nkp = 0.0"),
    ("nmpc", ""),
    ("mpc", ""),
];

/// A cart file of `kind` that loads.
fn base(kind: &str) -> String {
    let (_, body) = BODIES.iter().find(|(k, _)| *k == kind).unwrap();
    format!("plant = \"cart\"\n[controller]\nkind = \"{kind}\"\n{body}\n")
}

#[test]
fn a_key_of_another_kind_is_an_error_naming_the_key_and_the_kind() {
    // The finding: `k2 = nan` in a state-feedback table was ignored.
    let e = load(&format!("{}k2 = nan\n", base("state-feedback")))
        .unwrap_err()
        .to_string();
    assert!(e.contains("k2") && e.contains("state-feedback"), "{e}");
    // Every key of every other kind, with a value of the type its own kind reads (so the
    // only thing wrong is where it is).
    let value = |key: &str| match key {
        "k" | "k_book" | "k1" | "reference" | "design_points_deg" => "[0.0, 0.0, 0.0, 0.0]",
        "k2" | "step_time" | "switch_deg" => "1.0",
        "lqr" => "{ q = [1.0, 1.0, 0.0, 0.0], r = 1.0 }",
        "coefficients" | "l_coefficients" => "[[0.0, 0.0, 0.0, 0.0]]",
        "x_coefficients" => "[[[1.0, 0.0], [0.0, 1.0]]]",
        "schedule" => "\"q0-squared\"",
        "balance" => "{ k = [0.0, 0.0, 0.0, 0.0] }",
        "poles" | "observer_poles" => "[[-1.0, 0.0], [-2.0, 0.0], [-3.0, 0.0], [-4.0, 0.0]]",
        "l" => "[[0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]",
        "discretization" => "\"tustin\"",
        "form" => "\"p\"",
        "kp" | "ki" | "kd" | "tf" | "horizon" | "horizon_rate" | "r" | "u_max" | "dummy_weight"
        | "zeta" => "1.0",
        "divisions" | "gmres_iterations" => "5",
        "step" => "0.01",
        "travel_limit" | "du_max" => "1.0",
        "q" | "qf" => "[1.0, 1.0, 0.0, 0.0]",
        _ => unreachable!("{key}"),
    };
    let mut rejected = 0;
    for (kind, own) in KEYS {
        load(&base(kind)).unwrap_or_else(|e| panic!("{kind}: {e}"));
        for (_, other) in KEYS {
            for key in other.iter().filter(|k| !own.contains(k)) {
                let text = format!("{}{key} = {}\n", base(kind), value(key));
                let e = load(&text).unwrap_err().to_string();
                assert!(
                    e.contains(&format!("`{key}`")) && e.contains(kind),
                    "{kind} + {key}: {e}"
                );
                rejected += 1;
            }
        }
    }
    // Foreign keys per kind, counted by hand from the module's table (a key listed by two
    // other kinds is tried twice; `designed_for` belongs to every kind), the other kinds
    // in the order of `KINDS`: state-feedback 3 + 6 + 2 + 4 + 7 + 10 + 7 = 39, lq-servo
    // 2 + 5 + 2 + 6 + 6 + 10 + 7 = 38, gain-scheduled 2 + 2 + 2 + 6 + 6 + 10 + 7 = 35,
    // swing-up-balance 4 + 5 + 8 + 7 + 8 + 10 + 7 = 49, observer
    // 1 + 4 + 7 + 2 + 7 + 10 + 7 = 38, pid 3 + 3 + 6 + 2 + 6 + 10 + 7 = 37, nmpc
    // 4 + 5 + 8 + 2 + 7 + 8 + 3 = 37, mpc 4 + 5 + 8 + 2 + 7 + 8 + 6 = 40.
    assert_eq!(rejected, 313);
}

#[test]
fn the_findings_safety_values_are_refused_naming_key_and_value() {
    // Values from the fuzzing campaign of issue 21: each loaded before.
    for (table, key, value) in [
        ("safety", "watchdog_periods", "4294967295"),
        ("safety", "voltage_limit", "1e9"),
        ("safety", "travel_limit", "1e300"),
        ("safety", "angle_window_deg", "1e-300"),
        ("safety", "connect_timeout_s", "1e30"),
        ("safety", "connect_timeout_s", "-1.0"),
        ("safety", "stale_hold_periods", "4294967295"),
    ] {
        let text = format!("{SF}[{table}]\n{key} = {value}\n");
        let e = load(&text).unwrap_err().to_string();
        assert!(e.contains(&format!("{table}.{key}")), "{key}: {e}");
        // The message shows the value as read (the window after its trip through
        // radians, so only its key is checked).
        let v: f64 = value.parse().unwrap();
        if key != "angle_window_deg" {
            assert!(e.contains(&format!("= {v}")), "{key}: {e}");
        }
        assert!(e.contains("must be"), "{key}: {e}");
    }
    // The defaults load, and the watchdog and hold are their documented times at the
    // file's rate (1 kHz: 50 ms = 50 periods, 20 ms = 20; 100 Hz: 5 and 2).
    let l = load(SF).unwrap();
    assert_eq!(l.safety.watchdog_periods, 50);
    assert_eq!(l.safety.stale_hold_periods, 20);
    let l = load(&SF.replace("plant = \"cart\"\n", "plant = \"cart\"\nrate_hz = 100.0\n")).unwrap();
    assert_eq!(
        (l.safety.watchdog_periods, l.safety.stale_hold_periods),
        (5, 2)
    );
    // A watchdog given alone keeps the default hold below it.
    let l = load(&format!("{SF}[safety]\nwatchdog_periods = 10\n")).unwrap();
    assert_eq!(
        (l.safety.watchdog_periods, l.safety.stale_hold_periods),
        (10, 9)
    );
    // Swing-up has no window: giving one is refused, not ignored.
    let e = load(&format!(
        "{}[safety]\nangle_window_deg = 30.0\n",
        base("swing-up-balance")
    ))
    .unwrap_err()
    .to_string();
    assert!(e.contains("safety.angle_window_deg"), "{e}");
}

#[test]
fn rates_and_estimator_are_bounded() {
    let with = |head: &str, extra: &str| {
        format!(
            "plant = \"cart\"\n{head}[controller]\nkind = \"state-feedback\"\nk = [0.0, 0.0, 0.0, 0.0]\n{extra}"
        )
    };
    let tiny = format!("estimator.time_constant = {}", 1e-300);
    for (text, key) in [
        (with("rate_hz = 5.0\n", ""), "rate_hz = 5:"),
        (with("rate_hz = 1e6\n", ""), "rate_hz = 1000000"),
        (with("rate_hz = nan\n", ""), "rate_hz = NaN"),
        (
            with("", "[estimator]\ntime_constant = 1e-300\n"),
            tiny.as_str(),
        ),
        (
            with("", "[estimator]\ntime_constant = 0.2\n"),
            "estimator.time_constant = 0.2",
        ),
        (
            with("", "[estimator]\ntime_constant = inf\n"),
            "estimator.time_constant = inf",
        ),
        // 20 Hz: ts/2 = 25 ms is above the 20 ms default.
        (
            with("rate_hz = 20.0\n", ""),
            "estimator.time_constant = 0.02",
        ),
    ] {
        let e = load(&text).unwrap_err().to_string();
        assert!(e.contains(key), "{key}: {e}");
        assert!(e.contains("must be"), "{key}: {e}");
    }
    // The ends of the documented ranges load: T = ts/2 (the plain difference quotient,
    // α = 0) and TIME_CONSTANT_MAX at 1 kHz; rates 10 Hz (with T = 0.05 = ts/2) and 50 kHz
    // (switch_deg and step_time: pendulab_control::spec's tests).
    for text in [
        with("", "[estimator]\ntime_constant = 0.0005\n"),
        with("", "[estimator]\ntime_constant = 0.1\n"),
        with("rate_hz = 10.0\n", "[estimator]\ntime_constant = 0.05\n"),
        with("rate_hz = 50000.0\n", ""),
    ] {
        load(&text).unwrap_or_else(|e| panic!("{text}: {e}"));
    }
    // Just inside them, the other side refuses.
    for text in [
        with("", "[estimator]\ntime_constant = 0.00049\n"),
        with("rate_hz = 9.99\n", "[estimator]\ntime_constant = 0.06\n"),
    ] {
        assert!(load(&text).is_err(), "{text}");
    }
}

#[test]
fn references_lie_inside_the_travel_and_the_angle_window() {
    // Cart travel 0.4 m by default: a state reference at 0.5 m, or at the limit itself,
    // would drive the cart into the travel stop; 0.3 m is fine. Likewise the servo.
    let sf = |r: &str, safety: &str| {
        format!(
            "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [0.0, 0.0, 0.0, 0.0]\nreference = {r}\n{safety}"
        )
    };
    let servo = |r: &str, safety: &str| {
        format!(
            "plant = \"cart\"\n[controller]\nkind = \"lq-servo\"\nk1 = [0.0, 0.0, 0.0, 0.0]\nk2 = 0.0\nreference = {r}\n{safety}"
        )
    };
    for (text, needle) in [
        (
            sf("[0.5, 0.0, 0.0, 0.0]", ""),
            "controller.reference[0] = 0.5",
        ),
        (
            sf("[-0.4, 0.0, 0.0, 0.0]", ""),
            "controller.reference[0] = -0.4",
        ),
        (
            sf("[0.3, 0.0, 0.0, 0.0]", "[safety]\ntravel_limit = 0.2\n"),
            "controller.reference[0] = 0.3",
        ),
        // 0.6 rad = 34° outside the default 30° window.
        (
            sf("[0.0, 0.6, 0.0, 0.0]", ""),
            "controller.reference[1] = 0.6",
        ),
        (sf("[0.0, 0.0, nan, 0.0]", ""), "controller.reference[2]"),
        (servo("[0.5]", ""), "controller.reference[0] = 0.5"),
        (servo("[inf]", ""), "controller.reference[0] = inf"),
    ] {
        let e = load(&text).unwrap_err().to_string();
        assert!(e.contains(needle), "{needle}: {e}");
    }
    for text in [
        sf("[0.3, 0.5, 0.0, 0.0]", ""),
        sf("[-0.39, 0.0, 0.1, 0.0]", ""),
        servo("[0.5]", "[safety]\ntravel_limit = 0.75\n"),
    ] {
        load(&text).unwrap_or_else(|e| panic!("{text}: {e}"));
    }
}

#[test]
fn every_kind_balances_about_upright() {
    // The four balancing kinds; the PID family keeps the pendulum hanging (centre π) and
    // the NMPC swings up (`tests/config_kinds.rs`).
    for &(kind, _) in &KEYS[..4] {
        let l = load(&base(kind)).unwrap();
        assert_eq!(l.spec.pendulum_centre(), 0.0, "{kind}");
        assert_eq!(l.spec.kind(), kind);
    }
}

#[test]
fn a_command_line_watchdog_goes_through_the_same_ranges() {
    let mut l = load(SF).unwrap();
    // 0.5 s at 1 kHz is the longest watchdog (Safety::WATCHDOG_MAX_TIME / ts = 500).
    let e = l
        .override_watchdog_periods(u32::MAX)
        .unwrap_err()
        .to_string();
    assert!(e.contains("safety.watchdog_periods = 4294967295"), "{e}");
    assert_eq!(l.safety.watchdog_periods, 50, "unchanged after the error");
    assert!(l.override_watchdog_periods(0).is_err());
    l.override_watchdog_periods(500).unwrap();
    assert_eq!(l.safety.watchdog_periods, 500);
    assert!(l.override_watchdog_periods(501).is_err());
    // The default hold follows the watchdog down; a hold written in the file does not.
    l.override_watchdog_periods(10).unwrap();
    assert_eq!(
        (l.safety.watchdog_periods, l.safety.stale_hold_periods),
        (10, 9)
    );
    let mut l = load(&format!("{SF}[safety]\nstale_hold_periods = 20\n")).unwrap();
    let e = l.override_watchdog_periods(10).unwrap_err().to_string();
    assert!(e.contains("safety.stale_hold_periods = 20"), "{e}");
    // The swing-up keeps its missing window through the override.
    let mut l = load(&base("swing-up-balance")).unwrap();
    l.override_watchdog_periods(100).unwrap();
    assert_eq!(l.safety.angle_window, None);
}

#[test]
fn a_controller_designed_for_the_other_plant_is_refused_naming_both() {
    use pendulab_control::spec::DesignRecord;
    use pendulab_plants::spec::PlantSpec;
    // A cart design's record (as a design tool writes it), in a cart file and an arm file.
    let record = DesignRecord::new(
        &PlantSpec::book(PlantKind::Cart),
        vec![0.0; 4],
        Some(1e-3),
        "lqr",
        Default::default(),
    );
    let spec = load(SF).unwrap().spec.with_designed_for(record);
    let table = toml::to_string(&spec)
        .unwrap()
        .replace("[designed_for", "[controller.designed_for");
    let cart = format!("plant = \"cart\"\n[controller]\n{table}");
    assert_eq!(load(&cart).unwrap().spec, spec);
    let arm = cart.replace(
        "plant = \"cart\"\n[controller]",
        "plant = \"arm\"\n[controller]",
    );
    let e = load(&arm).unwrap_err();
    assert!(
        matches!(e, RigError::Config(ConfigError::Controller(_))),
        "{e:?}"
    );
    let e = e.to_string();
    assert!(
        e.contains("designed_for.plant") && e.contains("cart") && e.contains("arm"),
        "{e}"
    );
}

#[test]
fn a_labs_rig_limits_are_the_safety_defaults_and_its_plant_is_checked() {
    use pendulab_control::spec::{DesignRecord, DesignWarning};
    use pendulab_plants::spec::{PlantParameters, PlantSpec, Provenance};
    let book = PlantSpec::book(PlantKind::Cart);
    // The book rig: load and load_for agree.
    let (l, w) = load_for(SF, &book).unwrap();
    assert_eq!(l.safety, load(SF).unwrap().safety);
    assert_eq!(w, vec![]);
    // A lab rig with a shorter track and a narrower window, a heavier pendulum.
    let mut rig = *book.rig();
    rig.travel_limit = 0.3;
    rig.angle_window_deg = 20.0;
    let PlantParameters::Cart(mut p) = *book.parameters() else {
        unreachable!()
    };
    p.m_p *= 1.2;
    let lab = PlantSpec::new(
        PlantParameters::Cart(p),
        Provenance::User { note: None },
        rig,
    )
    .unwrap();
    let (l, _) = load_for(SF, &lab).unwrap();
    assert_eq!(l.safety.travel_limit, 0.3);
    assert_eq!(l.safety.angle_window, Some(20f64.to_radians()));
    // The file's own keys still win, and a command-line override keeps the lab's
    // defaults.
    let (mut l, _) = load_for(&format!("{SF}[safety]\ntravel_limit = 0.25\n"), &lab).unwrap();
    assert_eq!(l.safety.travel_limit, 0.25);
    l.override_watchdog_periods(100).unwrap();
    assert_eq!(l.safety.angle_window, Some(20f64.to_radians()));
    // A reference beyond the lab's travel is refused although inside the book's.
    let e = load_for(
        &SF.replace("k = [1.0", "reference = [0.35, 0.0, 0.0, 0.0]\nk = [1.0"),
        &lab,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("controller.reference[0] = 0.35"), "{e}");
    // A design made on the book's parameters: the heavier pendulum is a warning.
    let spec = load(SF).unwrap().spec.with_designed_for(DesignRecord::new(
        &book,
        vec![0.0; 4],
        None,
        "lqr",
        Default::default(),
    ));
    let table = toml::to_string(&spec)
        .unwrap()
        .replace("[designed_for", "[controller.designed_for");
    let text = format!("plant = \"cart\"\n[controller]\n{table}");
    let (_, w) = load_for(&text, &lab).unwrap();
    assert_eq!(
        w,
        vec![DesignWarning::Parameter {
            key: "parameters.m_p".into(),
            designed: book
                .parameters()
                .entries()
                .iter()
                .find(|e| e.0 == "m_p")
                .unwrap()
                .1,
            plant: p.m_p,
        }]
    );
    // A cart file for an arm lab names the key `plant`.
    let e = load_for(SF, &PlantSpec::book(PlantKind::Arm))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("plant = \"cart\"") && e.contains("\"arm\""),
        "{e}"
    );
}

#[test]
fn swing_up_balance_has_no_angle_window() {
    let l = load(
        "plant = \"arm\"\n[controller]\nkind = \"swing-up-balance\"\nbalance = { lqr = { q = [5.0, 10.0, 0.1, 0.1], r = 1.0 } }\n",
    )
    .unwrap();
    assert_eq!(l.safety.angle_window, None);
    assert!(l.spec.is_swing_up());
}
