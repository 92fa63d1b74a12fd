//! The emulator runs a lab's plant (`EmulatorConfig::for_plant`): its own parameters, not the
//! book's, checked against the closed form of the cart drive (`docs/model.md` §1,
//! `z̈ = −a_c ż + b_c v`), and a mismatched plant is refused by name.

use pendulab_plants::CartPendulumParams;
use pendulab_plants::rig::{PlantKind, RigSpec};
use pendulab_plants::spec::{PlantParameters, PlantSpec, Provenance};
use pendulab_rig::emulator::{EmulatorConfig, RigPlant};

/// The cart rig with the drive's `a_c`, `b_c` 15 % off the book's.
fn own_cart() -> PlantSpec {
    let mut p = CartPendulumParams::book();
    p.a_c *= 1.15;
    p.b_c *= 0.85;
    PlantSpec::new(
        PlantParameters::Cart(p),
        Provenance::User { note: None },
        RigSpec::book(PlantKind::Cart),
    )
    .unwrap()
}

/// The drive's velocity under a held voltage `v` from rest: `ż(t) = (b_c/a_c) v (1 − e^{−a_c t})`
/// (the first-order solution of `z̈ = −a_c ż + b_c v`), against the emulator's RK4 steps.
#[test]
fn the_lab_plant_drives_the_cart_with_its_own_a_c_and_b_c() {
    let spec = own_cart();
    let PlantParameters::Cart(p) = *spec.parameters() else {
        unreachable!()
    };
    let mut cfg = EmulatorConfig::for_plant(&spec, [0.0; 4]);
    cfg.dac = false; // 1 V exactly, not the D/A's nearest step
    assert_eq!(cfg.parameters, *spec.parameters());
    let mut rig = RigPlant::new(&cfg).unwrap();
    let (v, _) = rig.amplify(1.0);
    let n = 500;
    for _ in 0..n {
        rig.step(v);
    }
    let t = n as f64 * cfg.ts;
    let dz = (p.b_c / p.a_c) * v * (1.0 - (-p.a_c * t).exp());
    // RK4's local error is O(h⁵): at h = 1 ms and a_c·h < 0.01 the difference is far below 1e-9.
    assert!(
        (rig.state()[2] - dz).abs() < 1e-9,
        "{} vs {dz}",
        rig.state()[2]
    );
    // The book plant would be 15 % and more away.
    let book = (4.36 / 6.25) * (1.0 - (-6.25f64 * t).exp());
    assert!((rig.state()[2] - book).abs() > 0.1 * book);
}

#[test]
fn parameters_of_the_other_plant_are_refused_by_name() {
    let mut cfg = EmulatorConfig::new(PlantKind::Cart, [0.0; 4]);
    cfg.parameters = PlantParameters::book(PlantKind::Arm);
    let e = cfg.validate().unwrap_err().to_string();
    assert!(
        e.contains("emulator parameters") && e.contains("arm") && e.contains("cart"),
        "{e}"
    );
    let mut cfg = EmulatorConfig::new(PlantKind::Cart, [0.0; 4]);
    if let PlantParameters::Cart(p) = &mut cfg.parameters {
        p.b_c = f64::NAN;
    }
    let e = cfg.validate().unwrap_err().to_string();
    assert!(e.contains("b_c"), "{e}");
}
