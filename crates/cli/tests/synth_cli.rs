//! The synthesis verbs `hinfsyn` and `h2syn` end to end on the standard plants of the fixture
//! of `tools/reference/hinf_reference.py` (Slycot 0.7.1's SB10AD and SB10HD through
//! python-control 0.10.2): the optimal levels and costs, the controller file they write (read
//! back by `eig`), both methods, and the typed errors of bad inputs.

mod common;
use common::*;

use serde_json::Value;

fn fixture_case(name: &str) -> Value {
    let fix = pendulab_testkit::json::read(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../lti/tests/data/hinf_reference.json"),
    );
    fix["cases"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == name)
        .unwrap()
        .clone()
}

/// The fixture case as a system file (`a`, `b`, `c`, `d`) in `dir`, and its nmeas, ncon.
fn plant_file(dir: &Dir, name: &str) -> (String, String, String, Value) {
    let case = fixture_case(name);
    let sys = serde_json::json!({
        "a": case["a"], "b": case["b"], "c": case["c"], "d": case["d"],
    });
    let path = dir.file(&format!("{name}.json"), &sys.to_string());
    let (nmeas, ncon) = (case["nmeas"].to_string(), case["ncon"].to_string());
    (path, nmeas, ncon, case)
}

fn run_json(args: &[&str]) -> Value {
    json(&pendulab(args))
}

fn stable(v: &Value) {
    for p in v["closed_loop_poles"].as_array().unwrap() {
        assert!(p[0].as_f64().unwrap() < 0.0, "pole {p}");
    }
}

/// `hinfsyn` by Riccati: γ within 1e-6 of SB10AD on the mixed-sensitivity plants (with
/// `D₁₁ = 0` and `D₁₁ = 1/M ≠ 0`) and the cart with LQ weights. A controller this close to
/// the optimum is ill-conditioned, so the controller to use is designed with `--gamma` at
/// `1.01·γ`: its closed loop is stable with `‖T_zw‖∞ < 1.01·γ`, and the file `--out` writes
/// is a system file `eig` reads, of the plant's order.
#[test]
fn hinfsyn_matches_slycot() {
    let dir = Dir::new("hinfsyn");
    for name in ["mixsyn", "mixsyn_d11", "cart_lq"] {
        let (path, nmeas, ncon, case) = plant_file(&dir, name);
        let v = run_json(&[
            "hinfsyn",
            &path,
            "--nmeas",
            &nmeas,
            "--ncon",
            &ncon,
            "--gamma-tol",
            "1e-9",
            "--json",
        ]);
        let reference = case["gamma_slycot"].as_f64().unwrap();
        let gamma = v["gamma"].as_f64().unwrap();
        assert!(
            (gamma - reference).abs() <= 1e-6 * reference,
            "{name}: {gamma} vs SB10AD {reference}"
        );
        assert!(v["gamma_lower_bound"].as_f64().unwrap() <= gamma);
        let level = 1.01 * gamma;
        let k = dir.path(&format!("{name}_k.toml"));
        let v = run_json(&[
            "hinfsyn",
            &path,
            "--nmeas",
            &nmeas,
            "--ncon",
            &ncon,
            "--gamma",
            &level.to_string(),
            "--out",
            &k,
            "--json",
        ]);
        let achieved = v["closed_loop_hinf"].as_f64().unwrap();
        assert!(achieved < level, "{name}: {achieved} ≥ {level}");
        stable(&v);
        let e = run_json(&["eig", &k, "--json"]);
        let n = case["a"].as_array().unwrap().len();
        assert_eq!(e["poles"].as_array().unwrap().len(), n, "{name}: {e}");
    }
}

/// `hinfsyn --method lmi` returns the controller at `1.01·γ_opt` (the LMI's relaxation):
/// within 2·10⁻² of SB10AD's level and meeting it in closed loop; `--gamma` above the optimum
/// designs at that level by either method.
#[test]
fn hinfsyn_lmi_and_fixed_level() {
    let dir = Dir::new("hinfsyn-lmi");
    let (path, nmeas, ncon, case) = plant_file(&dir, "cart_lq");
    let reference = case["gamma_slycot"].as_f64().unwrap();
    let v = run_json(&[
        "hinfsyn", &path, "--nmeas", &nmeas, "--ncon", &ncon, "--method", "lmi", "--json",
    ]);
    let gamma = v["gamma"].as_f64().unwrap();
    assert!(
        gamma >= reference * (1.0 - 1e-4) && gamma <= reference * 1.02,
        "{gamma} vs {reference}"
    );
    assert!(v["closed_loop_hinf"].as_f64().unwrap() < gamma);
    stable(&v);
    let level = format!("{}", 1.2 * reference);
    for method in ["riccati", "lmi"] {
        let v = run_json(&[
            "hinfsyn", &path, "--nmeas", &nmeas, "--ncon", &ncon, "--method", method, "--gamma",
            &level, "--json",
        ]);
        assert_eq!(v["gamma"].as_f64().unwrap(), 1.2 * reference);
        assert!(
            v["closed_loop_hinf"].as_f64().unwrap() < 1.2 * reference,
            "{method}"
        );
        stable(&v);
    }
}

/// `h2syn`: the Riccati cost equals SB10HD's closed-loop H2 norm to 1e-8 and the LMI cost
/// to 1e-5 (cart with LQ weights); both closed loops are stable with `‖T_zw‖₂` equal to the
/// printed cost.
#[test]
fn h2syn_matches_slycot() {
    let dir = Dir::new("h2syn");
    let (path, nmeas, ncon, case) = plant_file(&dir, "cart_lq");
    let reference = case["h2_optimal"].as_f64().unwrap();
    for (method, tol) in [("riccati", 1e-8), ("lmi", 1e-5)] {
        let v = run_json(&[
            "h2syn", &path, "--nmeas", &nmeas, "--ncon", &ncon, "--method", method, "--json",
        ]);
        let cost = v["h2"].as_f64().unwrap();
        assert!(
            (cost - reference).abs() <= tol * reference,
            "{method}: {cost} vs SB10HD {reference}"
        );
        let cl = v["closed_loop_h2"].as_f64().unwrap();
        assert!((cl - cost).abs() <= tol * cost, "{method}: {cl} vs {cost}");
        stable(&v);
    }
}

/// Bad inputs exit 1 with a named error: nmeas/ncon out of range or zero, a failed plant
/// assumption (named), a level below the optimum (the failed condition), a level below the
/// bound `D₁₁` sets, and `h2syn` of a plant with `D₁₁ ≠ 0`.
#[test]
fn bad_inputs_are_named_errors() {
    let dir = Dir::new("synth-errors");
    let (path, _, _, case) = plant_file(&dir, "mixsyn_d11");
    let out = pendulab(&["hinfsyn", &path, "--nmeas", "3", "--ncon", "1"]);
    fails_with(&out, &["--nmeas 3", "output(s)"]);
    assert_eq!(out.status.code(), Some(1));
    fails_with(
        &pendulab(&["hinfsyn", &path, "--nmeas", "0", "--ncon", "1"]),
        &["at least 1"],
    );
    fails_with(
        &pendulab(&["h2syn", &path, "--nmeas", "1", "--ncon", "1"]),
        &["D11 = 0"],
    );
    // D11 = [2/3; 0] with z₁ not reachable by u: the bound is 2/3.
    fails_with(
        &pendulab(&[
            "hinfsyn", &path, "--nmeas", "1", "--ncon", "1", "--gamma", "0.5",
        ]),
        &["D1111", "6.666666666666"],
    );
    let below = format!("{}", 0.9 * case["gamma_slycot"].as_f64().unwrap());
    fails_with(
        &pendulab(&[
            "hinfsyn", &path, "--nmeas", "1", "--ncon", "1", "--gamma", &below,
        ]),
        &["no controller achieves"],
    );
    // D12 = 0: the control does not reach z.
    let p = dir.file(
        "singular.toml",
        "a = [[-1.0]]\nb = [[1.0, 1.0]]\nc = [[1.0], [1.0]]\nd = [[0.0, 0.0], [1.0, 0.0]]\n",
    );
    let out = pendulab(&["hinfsyn", &p, "--nmeas", "1", "--ncon", "1"]);
    fails_with(&out, &["D12 of full column rank"]);
    assert_eq!(out.status.code(), Some(1));
}
