//! The plant specification: round trips through TOML and JSON, the rig part's chains against
//! the numbers of `docs/model.md` §3, and errors that name the key.

use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::{PlantParameters, PlantSpec, Provenance};
use pendulab_plants::{CartPendulumParams, DriveFriction, RigSpec};
use pendulab_sim::rig::RigChains;
use pendulab_sim::scenario::Imperfections;
use std::f64::consts::PI;

fn err(text: &str) -> String {
    PlantSpec::from_toml(text).unwrap_err().to_string()
}

fn book_text(kind: PlantKind) -> String {
    PlantSpec::book(kind).to_toml().unwrap()
}

#[test]
fn book_specs_round_trip_through_toml_and_json() {
    for kind in [PlantKind::Cart, PlantKind::Arm] {
        let spec = PlantSpec::book(kind);
        let text = spec.to_toml().unwrap();
        assert!(
            text.starts_with(&format!("kind = \"{}\"", kind.name())),
            "{text}"
        );
        assert_eq!(PlantSpec::from_toml(&text).unwrap(), spec);
        let json = serde_json::to_string(&spec).unwrap();
        assert_eq!(serde_json::from_str::<PlantSpec>(&json).unwrap(), spec);
        assert_eq!(spec.kind(), kind);
        assert_eq!(*spec.rig(), kind.spec());
    }
}

#[test]
fn identified_parameters_round_trip_with_their_provenance() {
    let p = CartPendulumParams {
        m_p: 0.11,
        ..CartPendulumParams::book()
    };
    let prov = Provenance::Identified {
        file: "data/rig/cart_step.csv".into(),
        sha256: "ab".repeat(32),
        window: [0.5, 4.0],
        standard_errors: [("m_p".to_string(), 0.002)].into_iter().collect(),
        method: Some("least squares, part 1 §3.2".into()),
    };
    let spec = PlantSpec::new(PlantParameters::Cart(p), prov, RigSpec::cart()).unwrap();
    let text = spec.to_toml().unwrap();
    assert!(text.contains("source = \"identified\""), "{text}");
    assert_eq!(PlantSpec::from_toml(&text).unwrap(), spec);
    // The same values claimed as the book's are refused, naming the parameter.
    let e = err(&text.replace("source = \"identified\"", "source = \"book\""));
    assert!(e.contains("unknown field") || e.contains("file"), "{e}");
    let e = PlantSpec::new(
        PlantParameters::Cart(p),
        Provenance::Book {},
        RigSpec::cart(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("parameters.m_p = 0.11 differs from the book's 0.107"),
        "{e}"
    );
}

#[test]
fn with_quantizer_chains_are_the_rig_numbers_of_the_model_doc() {
    // docs/model.md §3, typed from the table: encoders 4.8414e-5 m and 2π/(4·3600) rad (cart),
    // 2π/(4·1000·50) and 2π/(4·3600) rad (arm); velocities s/(0.02 s + 1); ±5 V, 16 bits.
    let cases = [
        (RigSpec::cart(), [4.8414e-5, 2.0 * PI / (4.0 * 3600.0)]),
        (
            RigSpec::arm(),
            [2.0 * PI / (4.0 * 1000.0 * 50.0), 2.0 * PI / (4.0 * 3600.0)],
        ),
    ];
    for (rig, steps) in cases {
        let expected = RigChains::with_quantizer(
            4,
            &[(0, steps[0]), (1, steps[1])],
            &[(0, 2, 0.02), (1, 3, 0.02)],
            5.0,
            16,
        )
        .unwrap();
        assert_eq!(
            rig.chains(&Imperfections::with_quantizer()).unwrap(),
            expected
        );
        assert_eq!(
            rig.chains(&Imperfections::ideal()).unwrap(),
            RigChains::plain(4)
        );
    }
}

#[test]
fn drive_friction_needs_a_rig_with_friction() {
    let on = Imperfections {
        drive_friction: true,
        ..Imperfections::ideal()
    };
    let e = RigSpec::cart().chains(&on).unwrap_err().to_string();
    assert!(e.contains("rig.friction"), "{e}");
    let mut rig = RigSpec::cart();
    rig.friction = Some(DriveFriction::Coulomb {
        coulomb: 0.3,
        stiction: 0.4,
        velocity_band: 1e-3,
    });
    let chains = rig.chains(&on).unwrap();
    assert!(chains.actuator.friction_model().is_some());
    // In a file, the friction table reads back.
    let spec = PlantSpec::new(
        PlantParameters::book(PlantKind::Cart),
        Provenance::User { note: None },
        rig,
    )
    .unwrap();
    let text = spec.to_toml().unwrap();
    assert!(text.contains("model = \"coulomb\""), "{text}");
    assert_eq!(PlantSpec::from_toml(&text).unwrap(), spec);
}

#[test]
fn optional_keys_take_their_defaults() {
    // zero_offset may be left out (0), friction too (none).
    let text = book_text(PlantKind::Cart).replace("zero_offset = 3.141592653589793\n", "");
    let spec = PlantSpec::from_toml(&text).unwrap();
    assert_eq!(spec.rig().encoders[1].zero_offset, 0.0);
    assert_eq!(spec.rig().friction, None);
}

#[test]
fn errors_name_the_key() {
    let cart = book_text(PlantKind::Cart);
    let arm = book_text(PlantKind::Arm);
    let user = |t: &str| t.replace("source = \"book\"", "source = \"user\"");
    let cases: Vec<(String, &[&str])> = vec![
        // A parameter of the other plant, a missing one, a bad value.
        (
            cart.replace("a_c =", "a1 ="),
            &["a1", "parameters of the cart plant"],
        ),
        (cart.replace("m_p = 0.107\n", ""), &["missing field `m_p`"]),
        (
            user(&cart).replace("m_p = 0.107", "m_p = -0.1"),
            &["parameters.m_p", "-0.1"],
        ),
        (
            arm.replace("kind = \"arm\"", "kind = \"boat\""),
            &["boat", "line 1"],
        ),
        // Book values are the book's.
        (
            cart.replace("b_c = 4.36", "b_c = 4.5"),
            &["parameters.b_c = 4.5 differs"],
        ),
        // The rig part.
        (
            cart.replace("sample_time = 0.001", "sample_time = 0.0"),
            &["rig.sample_time"],
        ),
        (
            cart.replace("travel_limit = 0.4", "travel_limit = -1.0"),
            &["rig.travel_limit"],
        ),
        (
            cart.replace("angle_window_deg = 30.0", "angle_window_deg = 120.0"),
            &["rig.angle_window_deg"],
        ),
        (
            cart.replace("coordinate = \"theta\"", "coordinate = \"theta2\""),
            &["rig.encoders[1]", "'theta'"],
        ),
        (cart.replace("bits = 16", "bits = 0"), &["rig.dac.bits"]),
        (
            cart.replace("zero_offset = 3.141592653589793", "zero_offset = 1.0"),
            &["rig.encoders[1].zero_offset"],
        ),
        (
            cart.replace("input_limit = 5.0", "input_limt = 5.0"),
            &["input_limt"],
        ),
        (
            cart.replace("time_constant = 0.02", "time_constant = 0.0"),
            &["rig.velocity_estimators[0].time_constant"],
        ),
    ];
    for (text, needles) in cases {
        let e = err(&text);
        for n in needles {
            assert!(e.contains(n), "expected '{n}' in: {e}");
        }
    }
    // Provenance of an identification.
    let ident = |extra: &str| {
        cart.replace(
            "source = \"book\"",
            &format!("source = \"identified\"\nfile = \"run.csv\"\n{extra}"),
        )
    };
    let sha = format!("sha256 = \"{}\"", "0f".repeat(32));
    for (text, needle) in [
        (
            ident("sha256 = \"xyz\"\nwindow = [0.0, 1.0]"),
            "provenance.sha256",
        ),
        (
            ident(&format!("{sha}\nwindow = [2.0, 1.0]")),
            "provenance.window",
        ),
        (
            ident(&format!(
                "{sha}\nwindow = [0.0, 1.0]\nstandard_errors = {{ m2 = 0.1 }}"
            )),
            "'m2' is no parameter of the cart plant",
        ),
        (
            ident(&format!(
                "{sha}\nwindow = [0.0, 1.0]\nstandard_errors = {{ m_p = -0.1 }}"
            )),
            "provenance.standard_errors.m_p",
        ),
    ] {
        let e = err(&text);
        assert!(e.contains(needle), "expected '{needle}' in: {e}");
    }
    // Friction: stiction below the Coulomb level.
    let mut rig = RigSpec::arm();
    rig.friction = Some(DriveFriction::Coulomb {
        coulomb: 0.5,
        stiction: 0.4,
        velocity_band: 1e-3,
    });
    let e = PlantSpec::new(
        PlantParameters::book(PlantKind::Arm),
        Provenance::User { note: None },
        rig,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("rig.friction.stiction"), "{e}");
}

#[test]
fn the_plant_file_printed_in_the_model_doc_is_the_book_cart() {
    let doc = include_str!("../../../docs/model.md");
    let start = doc
        .find("A plant file for the book's cart rig reads")
        .expect("docs/model.md §6 prints the cart's plant file");
    let block = &doc[start..];
    let open = block.find("```toml\n").unwrap() + "```toml\n".len();
    let close = open + block[open..].find("```").unwrap();
    let spec = PlantSpec::from_toml(&block[open..close]).unwrap();
    assert_eq!(spec, PlantSpec::book(PlantKind::Cart));
}
