//! The standard plants the H∞/H2 synthesis tests share: the fixture of
//! `tools/reference/hinf_reference.py` (python-control 0.10.2, Slycot 0.7.1, in
//! `crates/lti/tests/data/hinf_reference.json`) and the scalar full-information problem with
//! its closed form. `pendulab-lti`'s own tests use it as `mod hinf_support;`, `pendulab-lmi`'s
//! LMI syntheses, tested on the same plants, through `#[path]`.
#![allow(dead_code)]

use pendulab_lti::design::StandardPlant;
use pendulab_lti::{Mat, StateSpace};
use pendulab_testkit::json::matrix;
use serde_json::Value;

/// The fixture: each case's `a`, `b`, `c`, `d`, `nmeas`, `ncon` and Slycot's results.
pub fn fixture() -> Value {
    pendulab_testkit::json::read(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../lti/tests/data/hinf_reference.json"),
    )
}

/// A fixture case as a standard plant.
pub fn plant_of(case: &Value) -> StandardPlant {
    let sys = StateSpace::continuous(
        matrix(&case["a"]),
        matrix(&case["b"]),
        matrix(&case["c"]),
        matrix(&case["d"]),
    )
    .unwrap();
    StandardPlant::new(
        sys,
        case["nmeas"].as_u64().unwrap() as usize,
        case["ncon"].as_u64().unwrap() as usize,
    )
    .unwrap()
}

/// Every fixture case as `(name, plant, case)`: the loop the synthesis tests share.
pub fn cases() -> Vec<(String, StandardPlant, Value)> {
    let fix = fixture();
    fix["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|case| {
            (
                case["name"].as_str().unwrap().to_owned(),
                plant_of(case),
                case.clone(),
            )
        })
        .collect()
}

/// ẋ = a x + w + u, z = [x; u]: the full-information optimum is `1/√(1 + a²)` at the static
/// gain `u = x/a` (a < 0), and `1` (not attained) for a > 0: `‖T_zw‖∞² = (1 + k²)/(k − a)²`
/// at ω = 0 for `u = −k x`, minimised over `k > a`.
pub fn scalar_full_information(a: f64) -> StandardPlant {
    let m = Mat::from_row_slice;
    StandardPlant::from_blocks(
        &m(1, 1, &[a]),
        &m(1, 1, &[1.0]),
        &m(1, 1, &[1.0]),
        &m(2, 1, &[1.0, 0.0]),
        &Mat::zeros(0, 1),
        &Mat::zeros(2, 1),
        &m(2, 1, &[0.0, 1.0]),
        &Mat::zeros(0, 1),
        &Mat::zeros(0, 1),
    )
    .unwrap()
}
