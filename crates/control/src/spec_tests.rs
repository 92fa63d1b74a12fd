//! Tests of the controller specs and the factory (moved here from the rig's controller-file
//! loader with the code; the file-level tests stay in `pendulab_rig::config`).

use super::*;
use pendulab_lti::design::lqr;
use pendulab_plants::ArmEquilibrium;

/// The parts of a rig controller file the factory reads (other tables are ignored here).
#[derive(Deserialize)]
struct File {
    plant: String,
    controller: ControllerSpec,
}

/// Parses a controller file's `plant` and `[controller]` and builds at 1 kHz (the files'
/// default rate).
fn load(text: &str) -> Result<Built, String> {
    let f: File = toml::from_str(text).map_err(|e| e.to_string())?;
    let plant = PlantKind::parse(&f.plant).map_err(|e| e.to_string())?;
    build(&f.controller, plant, 1e-3).map_err(|e| e.to_string())
}

#[test]
fn cart_lqr_design_reproduces_the_book_gain() {
    // The book's cdip_lqr_sim: Q = diag(10, 10, 0, 0), R = 1 gives
    // K_book = [3.16228, 13.47175, 4.48137, 2.26289]; u = +K_book x means the library's
    // u = −K x has K = −K_book. The printed digits bound the agreement (5e-5).
    let l = load(
        "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [10.0, 10.0, 0.0, 0.0], r = 1.0 }\n",
    )
    .unwrap();
    let mut u = [0.0];
    let mut c = l.controller;
    let kb = [3.16228, 13.47175, 4.48137, 2.26289];
    for i in 0..4 {
        let mut y = [0.0; 4];
        y[i] = 1.0;
        c.update(0.0, &y, &mut u);
        assert!((u[0] - kb[i]).abs() < 5e-5, "K[{i}] = {}", u[0]);
    }
}

#[test]
fn cart_lq_servo_design_reproduces_the_book_gains() {
    // The book's cdip_lqr_servo_sim: Q = diag(1, 5, 0, 0, 100), R = 1 gives
    // K1_book = [10.39942, 17.76307, 6.79089, 3.04513], K2_book = −10 (u = K1 x + K2 w,
    // w = ∫(r − z)). At rest with y = e_i and r = 0 the first command is +K1_book·e_i
    // (forward Euler: w is still 0). Printed digits bound the agreement (5e-5).
    let text = "plant = \"cart\"\n[controller]\nkind = \"lq-servo\"\nlqr = { q = [1.0, 5.0, 0.0, 0.0, 100.0], r = 1.0 }\nreference = [0.0]\n";
    let k1b = [10.39942, 17.76307, 6.79089, 3.04513];
    for i in 0..4 {
        let mut c = load(text).unwrap().controller;
        let mut y = [0.0; 4];
        y[i] = 1.0;
        let mut u = [0.0];
        c.update(0.0, &y, &mut u);
        assert!((u[0] - k1b[i]).abs() < 5e-5, "K1[{i}] = {}", u[0]);
    }
    // Integral gain: with y = 0 and r = 0.1, w = 0.1·ts after the first period and
    // u = K2_book · w = −10 · 1e-4 at the second.
    let mut c = load(&text.replace("[0.0]", "[0.1]")).unwrap().controller;
    let mut u = [0.0];
    c.update(0.0, &[0.0; 4], &mut u);
    assert_eq!(u[0], 0.0);
    c.update(1e-3, &[0.0; 4], &mut u);
    assert!((u[0] - (-10.0 * 1e-4)).abs() < 5e-9, "{}", u[0]);
}

#[test]
fn bad_controller_tables_are_typed_errors_naming_the_key() {
    let cases = [
        (
            "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0]\n",
            "controller.k",
        ),
        (
            "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\n",
            "exactly one",
        ),
        (
            "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [1.0, -1.0, 0.0, 0.0], r = 1.0 }\n",
            "lqr.q[1]",
        ),
        (
            "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [1.0, 1.0, 0.0, 0.0], r = nan }\n",
            "lqr.r",
        ),
    ];
    for (text, needle) in cases {
        let e = load(text).unwrap_err();
        assert!(e.contains(needle), "{e:?} should mention {needle:?}");
    }
    // A non-positive loop period is refused, not integrated with.
    let spec = ControllerSpec::LqServo(LqServoSpec {
        k1: Some(vec![0.0; 4]),
        k2: Some(0.0),
        ..Default::default()
    });
    for ts in [0.0, -1e-3, f64::NAN] {
        let e = build(&spec, PlantKind::Cart, ts).unwrap_err();
        assert!(matches!(e, SpecError::SampleTime { .. }), "{e}");
    }
}

/// The keys of each kind, as the module documentation lists them.
const KEYS: [(&str, &[&str]); 8] = ControllerSpec::KEYS;

/// A file of each kind that loads, for the plant given.
fn base(kind: &str) -> String {
    let body = match kind {
        "state-feedback" => "k = [0.0, 0.0, 0.0, 0.0]\n",
        "lq-servo" => "k1 = [0.0, 0.0, 0.0, 0.0]\nk2 = 0.0\n",
        "gain-scheduled" => "coefficients = [[0.0, 0.0, 0.0, 0.0]]\n",
        "swing-up-balance" => "balance = { k = [0.0, 0.0, 0.0, 0.0] }\n",
        "observer" => {
            "k = [0.0, 0.0, 0.0, 0.0]\nl = [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]\n"
        }
        "pid" => "form = \"p\"\nkp = 0.0\n",
        "nmpc" | "mpc" => "",
        _ => unreachable!(),
    };
    format!("plant = \"cart\"\n[controller]\nkind = \"{kind}\"\n{body}")
}

#[test]
fn integers_still_read_as_numbers_inside_the_kind_tables() {
    // The tagged enum buffers the table before reading it: `k = [1, 2, 3, 4]` must still
    // read as the floats it did, giving u = −K·e_i = −(i + 1).
    let mut c =
        load("plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1, 2, 3, 4]\n")
            .unwrap()
            .controller;
    let mut u = [0.0];
    for i in 0..4 {
        let mut y = [0.0; 4];
        y[i] = 1.0;
        c.update(0.0, &y, &mut u);
        assert_eq!(u[0], -((i + 1) as f64));
    }
}

#[test]
fn switch_and_step_time_are_bounded() {
    for (text, key) in [
        (
            format!("{}switch_deg = 90.0\n", base("swing-up-balance")),
            "controller.switch_deg = 90",
        ),
        (
            format!("{}switch_deg = 0.0\n", base("swing-up-balance")),
            "controller.switch_deg = 0",
        ),
        (
            format!("{}step_time = -1.0\n", base("lq-servo")),
            "controller.step_time = -1",
        ),
        (
            format!("{}step_time = 1e9\n", base("lq-servo")),
            "controller.step_time = 1000000000",
        ),
    ] {
        let e = load(&text).unwrap_err();
        assert!(e.contains(key), "{key}: {e}");
        assert!(e.contains("must be"), "{key}: {e}");
    }
    // The ends of the documented ranges load: switch_deg = SWITCH_DEG_MAX, step_time =
    // DURATION_MAX.
    for text in [
        format!("{}switch_deg = 45.0\n", base("swing-up-balance")),
        format!("{}step_time = 3600.0\n", base("lq-servo")),
    ] {
        load(&text).unwrap_or_else(|e| panic!("{text}: {e}"));
    }
    // Just outside, they are refused.
    let text = format!("{}switch_deg = 45.01\n", base("swing-up-balance"));
    assert!(load(&text).is_err(), "{text}");
}

#[test]
fn every_kind_balances_about_upright() {
    // The four kinds that balance (the PID family keeps the pendulum hanging, centre π, and
    // the NMPC runs on the arm only: `kinds_tests`).
    for &(kind, _) in &KEYS[..4] {
        let l = load(&base(kind)).unwrap();
        assert_eq!(l.pendulum_centre, 0.0, "{kind}");
        assert_eq!(l.kind, kind);
        assert_eq!(l.swing_up, kind == ControllerSpec::SWING_UP_BALANCE);
    }
}

#[test]
fn scheduled_lqr_interpolates_the_two_designs_exactly_at_their_points() {
    // At θ₁ = 0 and 60° the scheduled gain must equal the LQR designed at that angle
    // (the defining property of the interpolation), to rounding.
    let text = "plant = \"arm\"\n[controller]\nkind = \"gain-scheduled\"\nlqr = { q = [5.0, 10.0, 0.1, 0.1], r = 1.0 }\ndesign_points_deg = [0.0, 60.0]\n";
    let sys = |deg: f64| {
        ArmPendulum::book()
            .linearize(ArmEquilibrium::upright(deg.to_radians()))
            .unwrap()
    };
    let q = diag("q", &[5.0, 10.0, 0.1, 0.1], 4).unwrap();
    let r = check_r("lqr", 1.0).unwrap();
    for deg in [0.0, 60.0] {
        let k = lqr(&sys(deg), &q, &r, None).unwrap().gain;
        let th = deg.to_radians();
        let mut c = load(text).unwrap().controller;
        let mut u0 = [0.0];
        c.update(0.0, &[th, 0.0, 0.0, 0.0], &mut u0);
        if deg != 0.0 {
            // u = −K(ρ)·[θ₁, 0, 0, 0] = −K₀₀(ρ) θ₁.
            let k0 = -u0[0] / th;
            assert!((k0 - k[(0, 0)]).abs() < 1e-9 * k[(0, 0)].abs(), "{k0}");
        }
        for i in 1..4 {
            // The law is linear in y at fixed ρ (ρ depends on θ₁ only).
            let mut y = [th, 0.0, 0.0, 0.0];
            y[i] = 1.0;
            let mut u1 = [0.0];
            c.update(0.0, &y, &mut u1);
            let ki = -(u1[0] - u0[0]);
            assert!(
                (ki - k[(0, i)]).abs() < 1e-9 * k[(0, i)].abs().max(1.0),
                "{deg}° K[{i}]: {ki} vs {}",
                k[(0, i)]
            );
        }
    }
}

#[test]
fn swing_up_balance_is_four_in_one_out() {
    let l = load(
        "plant = \"arm\"\n[controller]\nkind = \"swing-up-balance\"\nbalance = { lqr = { q = [5.0, 10.0, 0.1, 0.1], r = 1.0 } }\n",
    )
    .unwrap();
    assert!(l.swing_up);
    assert_eq!((l.controller.ny(), l.controller.nu()), (4, 1));
}

#[test]
fn a_spec_written_back_reads_as_the_same_spec() {
    // What a front end writes, the rig's file format reads: serialising each kind's base
    // table to TOML and reading it again gives the same spec (and no key of another kind).
    for (kind, own) in KEYS {
        let f: File = toml::from_str(&base(kind)).unwrap();
        let text = toml::to_string(&f.controller).unwrap();
        let back: ControllerSpec = toml::from_str(&text).unwrap();
        assert_eq!(back, f.controller, "{kind}: {text}");
        let table: toml::Table = text.parse().unwrap();
        assert_eq!(table["kind"].as_str(), Some(kind));
        assert!(
            table
                .keys()
                .all(|k| k == "kind" || own.contains(&k.as_str())),
            "{kind}: {text}"
        );
    }
}

/// A state-feedback spec with the book's cart gain and a design record made on `plant`.
fn recorded_on(plant: &PlantSpec) -> ControllerSpec {
    let inputs = [
        (
            "q".to_string(),
            DesignInput::List(vec![10.0, 10.0, 0.0, 0.0]),
        ),
        ("r".to_string(), DesignInput::Number(1.0)),
    ]
    .into_iter()
    .collect();
    ControllerSpec::StateFeedback(StateFeedbackSpec {
        k_book: Some(vec![3.16228, 13.47175, 4.48137, 2.26289]),
        ..Default::default()
    })
    .with_designed_for(DesignRecord::new(
        plant,
        vec![0.0; 4],
        Some(1e-3),
        "lqr",
        inputs,
    ))
}

#[test]
fn a_cart_design_on_the_arm_plant_is_an_error_naming_both() {
    let spec = recorded_on(&PlantSpec::book(PlantKind::Cart));
    let arm = PlantSpec::book(PlantKind::Arm);
    let named = |e: &SpecError| {
        let m = e.to_string();
        assert!(matches!(
            e,
            SpecError::WrongPlant {
                designed: PlantKind::Cart,
                plant: PlantKind::Arm
            }
        ));
        assert!(
            m.contains("designed_for.plant") && m.contains("cart") && m.contains("arm"),
            "{m}"
        );
    };
    named(&spec.check_plant(&arm).unwrap_err());
    named(&build_for(&spec, &arm, 1e-3).unwrap_err());
    named(&build(&spec, PlantKind::Arm, 1e-3).unwrap_err());
    let scenario = pendulab_sim::scenario::ScenarioSpec::new(vec![0.0; 4], 0.1);
    match crate::scenario::simulate(&arm, &spec, &scenario).unwrap_err() {
        crate::scenario::ScenarioError::Controller(e) => named(&e),
        e => panic!("{e}"),
    }
    // On the plant it was designed for, it builds and has nothing to report.
    let cart = PlantSpec::book(PlantKind::Cart);
    assert_eq!(spec.check_plant(&cart).unwrap(), vec![]);
    build_for(&spec, &cart, 1e-3).unwrap();
}

#[test]
fn different_parameters_are_warnings_naming_each_key_and_both_values() {
    use pendulab_plants::spec::{PlantParameters, Provenance};
    let book = PlantSpec::book(PlantKind::Cart);
    let spec = recorded_on(&book);
    // The same rig with two parameters changed (a user's plant).
    let PlantParameters::Cart(mut p) = *book.parameters() else {
        unreachable!()
    };
    let (m_p, mu_p) = (p.m_p * 1.1, p.mu_p * 0.5);
    p.m_p = m_p;
    p.mu_p = mu_p;
    let user = PlantSpec::new(
        PlantParameters::Cart(p),
        Provenance::User { note: None },
        *book.rig(),
    )
    .unwrap();
    let w = spec.check_plant(&user).unwrap();
    let book_p = pendulab_plants::CartPendulumParams::book();
    let expected = vec![
        DesignWarning::Parameter {
            key: "parameters.m_p".into(),
            designed: book_p.m_p,
            plant: m_p,
        },
        DesignWarning::Parameter {
            key: "parameters.mu_p".into(),
            designed: book_p.mu_p,
            plant: mu_p,
        },
    ];
    // Warnings come in the order of the plant's parameters (the struct's fields).
    let order: Vec<String> = user
        .parameters()
        .entries()
        .into_iter()
        .map(|e| e.0)
        .collect();
    let pos = |k: &str| order.iter().position(|n| n == k).unwrap();
    let mut expected = expected;
    expected.sort_by_key(|w| match w {
        DesignWarning::Parameter { key, .. } => pos(&key["parameters.".len()..]),
        DesignWarning::SampleTime { .. } => usize::MAX,
    });
    assert_eq!(w, expected);
    assert!(w[0].to_string().contains("parameters."), "{}", w[0]);
    // The run goes ahead and carries the warnings, plus the sample time's when the loop
    // runs at another period than the record's 1 ms.
    let mut scenario = pendulab_sim::scenario::ScenarioSpec::new(vec![0.0; 4], 0.05);
    scenario.sample_time = Some(2e-3);
    let run = crate::scenario::simulate(&user, &spec, &scenario).unwrap();
    assert_eq!(run.design_warnings[..2], expected[..]);
    assert_eq!(
        run.design_warnings[2],
        DesignWarning::SampleTime {
            designed: 1e-3,
            run: 2e-3
        }
    );
    scenario.sample_time = None;
    let run = crate::scenario::simulate(&book, &spec, &scenario).unwrap();
    assert_eq!(run.design_warnings, vec![]);
}

#[test]
fn the_design_record_round_trips_through_toml_and_is_checked_by_key() {
    let spec = recorded_on(&PlantSpec::book(PlantKind::Arm));
    let text = toml::to_string(&spec).unwrap();
    let back: ControllerSpec = toml::from_str(&text).unwrap();
    assert_eq!(back, spec, "{text}");
    assert!(text.contains("[designed_for]"), "{text}");
    // In a rig controller file it is the [controller.designed_for] table.
    let file = format!(
        "plant = \"arm\"\n[controller]\n{}",
        text.replace("[designed_for", "[controller.designed_for")
    );
    let f: File = toml::from_str(&file).unwrap();
    assert_eq!(f.controller, spec);
    // A foreign key inside the record is refused by name.
    let bad = text.replace("method = ", "methd = ");
    let e = toml::from_str::<ControllerSpec>(&bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("methd"), "{e}");
    // Malformed records: each error names its key.
    let arm = PlantSpec::book(PlantKind::Arm);
    let with = |f: &dyn Fn(&mut DesignRecord)| {
        let mut r = spec.designed_for().unwrap().clone();
        f(&mut r);
        spec.clone()
            .with_designed_for(r)
            .check_plant(&arm)
            .unwrap_err()
            .to_string()
    };
    for (e, key) in [
        (
            with(&|r| r.operating_point = vec![0.0; 3]),
            "designed_for.operating_point",
        ),
        (
            with(&|r| r.operating_point[1] = f64::NAN),
            "designed_for.operating_point",
        ),
        (
            with(&|r| r.sample_time = Some(0.0)),
            "designed_for.sample_time",
        ),
        (with(&|r| r.method = " ".into()), "designed_for.method"),
        (
            with(&|r| {
                r.inputs
                    .insert("r".into(), DesignInput::Number(f64::INFINITY));
            }),
            "designed_for.inputs.r",
        ),
        (
            with(&|r| {
                r.parameters.remove("a1");
            }),
            "a1",
        ),
        (
            with(&|r| {
                r.parameters.insert("a_c".into(), 1.0);
            }),
            "a_c",
        ),
    ] {
        assert!(e.contains(key), "{key}: {e}");
    }
    // No record: nothing to check.
    let bare = ControllerSpec::StateFeedback(StateFeedbackSpec::default());
    assert_eq!(bare.check_plant(&arm).unwrap(), vec![]);
    assert!(bare.designed_for().is_none());
}
