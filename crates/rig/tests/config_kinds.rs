//! Controller files of the kinds `observer`, `pid` and `nmpc`: read by the rig's loader, built
//! by the factory and run by `pendulab_control::scenario::simulate`, against the book's
//! examples that use them (`pendulab-book`, run here): the spec path and the book's own path
//! must give the same numbers.

mod common;
use pendulab_book::{RunContext, Value, find};
use pendulab_control::scenario::simulate;
use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::PlantSpec;
use pendulab_rig::config;
use pendulab_sim::scenario::{Imperfections, ScenarioSpec};

/// The values of a book example, computed now.
fn book(id: &str) -> pendulab_book::ExampleOutput {
    (find(id).unwrap().run)(&RunContext::default()).unwrap_or_else(|e| panic!("{id}: {e}"))
}

fn vector(out: &pendulab_book::ExampleOutput, name: &str) -> Vec<f64> {
    match out.get(name) {
        Some(Value::Vector(v)) => v.clone(),
        v => panic!("{name}: {v:?}"),
    }
}

fn number(out: &pendulab_book::ExampleOutput, name: &str) -> f64 {
    match out.get(name) {
        Some(Value::Number(x)) => *x,
        v => panic!("{name}: {v:?}"),
    }
}

#[test]
fn the_observer_file_reproduces_the_books_example_7_1() {
    // p1c74_ex1_cdip_ob_design (book part 1 §7.4, example 7.1): K placed at −6.5 ± 1.5j, −4,
    // −2.5, the observer at four times those, the continuous controller run as its Tustin
    // discretisation at 1 ms on the quantised cart (encoders z, θ; ±5 V; 16-bit D/A) from
    // θ₀ = 10° for 3 s.
    let ex = book("p1c74_ex1_cdip_ob_design");
    let text = "plant = \"cart\"\n[controller]\nkind = \"observer\"\n\
        poles = [[-6.5, 1.5], [-6.5, -1.5], [-4.0, 0.0], [-2.5, 0.0]]\n\
        observer_poles = [[-26.0, 6.0], [-26.0, -6.0], [-16.0, 0.0], [-10.0, 0.0]]\n";
    let loaded = config::load(text).unwrap();
    let plant = PlantSpec::book(PlantKind::Cart);
    // The design: the spec's K and L are the book example's (u = +K_book x, A + L_book C).
    let pendulab_control::spec::ControllerSpec::Observer(c) = &loaded.spec else {
        panic!("{:?}", loaded.spec)
    };
    let d = pendulab_control::spec::observer_design(plant.parameters(), c).unwrap();
    let k_book = vector(&ex, "K");
    for (i, kb) in k_book.iter().enumerate() {
        assert!((-d.k[(0, i)] - kb).abs() < 1e-9 * kb.abs(), "K[{i}]");
    }
    let Some(Value::Matrix(l_book)) = ex.get("L") else {
        panic!("L")
    };
    for (i, r) in l_book.iter().enumerate() {
        for (j, lb) in r.iter().enumerate() {
            assert!(
                (-d.l[(i, j)] - lb).abs() < 1e-9 * lb.abs().max(1.0),
                "L[{i}][{j}]"
            );
        }
    }
    // The run: the scenario with the same rig effects (the velocities are not read).
    let mut scenario = ScenarioSpec::new(vec![0.0, 10f64.to_radians(), 0.0, 0.0], 3.0);
    scenario.sample_time = Some(loaded.ts);
    scenario.imperfections = Imperfections {
        quantization: true,
        saturation: true,
        dac: true,
        ..Imperfections::default()
    };
    let run = simulate(&plant, &loaded.spec, &scenario).unwrap();
    let after = |from: f64, i: usize| {
        run.t
            .iter()
            .zip(&run.x)
            .filter(|(t, _)| **t >= from)
            .map(|(_, x)| x[i].abs())
            .fold(0.0, f64::max)
    };
    let (theta, z) = (after(2.0, 1).to_degrees(), after(0.0, 0));
    let (theta_book, z_book) = (
        number(&ex, "theta_max_after_2s_deg"),
        number(&ex, "z_max_abs"),
    );
    assert!(
        (theta - theta_book).abs() <= 1e-9 * theta_book.abs().max(1e-3),
        "{theta} vs {theta_book}"
    );
    assert!((z - z_book).abs() <= 1e-9 * z_book, "{z} vs {z_book}");
    assert!(z > 0.0 && z < 0.4, "{z}");
}

#[test]
fn the_i_pd_file_runs_the_books_i_pd_gains_to_the_reference() {
    // p1c224_i_pdcont (book part 1 §2.2.4): I–PD gains [k_I, k_P, k_D] from the ITAE model
    // ω_n = 10 on table 3.5's drive, the book printing [229.358, 49.312, 2.580]; the cart
    // follows a 0.1 m step with the pendulum hanging, on the quantised rig at 1 kHz.
    let ex = book("p1c224_i_pdcont");
    let [ki, kp, kd] = vector(&ex, "gains_itae")[..] else {
        panic!("gains_itae")
    };
    for (g, printed) in [(ki, 229.358), (kp, 49.312), (kd, 2.580)] {
        assert!((g - printed).abs() < 5e-4, "{g} vs {printed}");
    }
    let text = format!(
        "plant = \"cart\"\n[controller]\nkind = \"pid\"\nform = \"i-pd\"\nkp = {kp}\nki = {ki}\nkd = {kd}\nreference = [0.1]\n"
    );
    let loaded = config::load(&text).unwrap();
    assert_eq!(loaded.spec.pendulum_centre(), std::f64::consts::PI);
    let plant = PlantSpec::book(PlantKind::Cart);
    let mut scenario = ScenarioSpec::new(vec![0.0, std::f64::consts::PI, 0.0, 0.0], 3.0);
    scenario.imperfections = Imperfections::with_quantizer();
    let run = simulate(&plant, &loaded.spec, &scenario).unwrap();
    // The ITAE model has a 2 % settling time near 0.5 s at ω_n = 10 (≈ 4.8/ω_n); the cart
    // is within 1 mm of the reference at the end.
    assert!(
        (run.summary.final_state[0] - 0.1).abs() < 1e-3,
        "{:?}",
        run.summary
    );
    let settling = run.summary.settling_time.unwrap();
    assert!(settling < 1.5, "{settling}");
}

#[test]
fn a_foreign_key_in_a_new_kind_is_refused_naming_key_and_kind() {
    for (kind, body, key) in [
        ("observer", "k = [0.0, 0.0, 0.0, 0.0]\nkp = 1.0\n", "kp"),
        (
            "pid",
            "form = \"p\"\nkp = 1.0\nobserver_poles = []\n",
            "observer_poles",
        ),
        ("nmpc", "switch_deg = 10.0\n", "switch_deg"),
    ] {
        let text = format!("plant = \"arm\"\n[controller]\nkind = \"{kind}\"\n{body}");
        let e = config::load(&text).unwrap_err().to_string();
        assert!(
            e.contains(&format!("`{key}`")) && e.contains(kind),
            "{kind}: {e}"
        );
    }
}

#[test]
fn an_nmpc_file_runs_on_the_arm_only() {
    let arm =
        common::load("plant = \"arm\"\n[controller]\nkind = \"nmpc\"\nhorizon = 0.5\n").unwrap();
    assert!(arm.loaded.spec.is_swing_up());
    assert_eq!(arm.loaded.safety.angle_window, None);
    assert_eq!((arm.controller.ny(), arm.controller.nu()), (4, 1));
    let e = common::load("plant = \"cart\"\n[controller]\nkind = \"nmpc\"\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("nmpc") && e.contains("arm") && e.contains("cart"),
        "{e}"
    );
}
