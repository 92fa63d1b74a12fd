//! End-to-end tests of `pendulab lab init`, `pendulab model` and `pendulab simulate`
//! (`docs/lab.md`).

mod common;
use common::*;

use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::PlantSpec;
use pendulab_testkit::Mat;
use pendulab_testkit::arm::ArmParams;
use pendulab_testkit::cart::{CartParams, Rest};
use std::path::PathBuf;

/// A rig controller file of `docs/rig/examples/`.
fn example(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../docs/rig/examples")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

fn json(o: &std::process::Output) -> serde_json::Value {
    assert!(o.status.success(), "stderr: {}", stderr(o));
    serde_json::from_slice(&o.stdout).unwrap()
}

fn matrix(v: &serde_json::Value) -> Mat {
    let rows: Vec<Vec<f64>> = serde_json::from_value(v.clone()).unwrap();
    let (r, c) = (rows.len(), rows[0].len());
    Mat::from_row_iterator(r, c, rows.into_iter().flatten())
}

/// `lab init DIR --plant kind` into `dir/name`; the lab directory's path.
fn init(dir: &Dir, name: &str, kind: &str) -> String {
    let lab = dir.path(name);
    let o = pendulab(&["lab", "init", &lab, "--plant", kind, "--json"]);
    let v = json(&o);
    assert_eq!(v["plant"], kind);
    lab
}

fn assert_close(got: &Mat, want: &Mat, rel: f64, what: &str) {
    assert_eq!(got.shape(), want.shape(), "{what}");
    let scale = want.amax().max(1.0);
    assert!(
        (got - want).amax() <= rel * scale,
        "{what}: got {got}, want {want}"
    );
}

/// The sorted real eigenvalues in the JSON's `poles` (`[re, im]` pairs, all real here).
fn real_poles(v: &serde_json::Value) -> Vec<f64> {
    let poles: Vec<[f64; 2]> = serde_json::from_value(v["poles"].clone()).unwrap();
    let mut re: Vec<f64> = poles
        .iter()
        .map(|[re, im]| {
            assert!(im.abs() < 1e-12, "complex pole {re} {im}");
            *re
        })
        .collect();
    re.sort_by(f64::total_cmp);
    re
}

/// The upright eigenvalues of a drive-and-pendulum `A` (`docs/model.md` §1–2): the drive gives
/// `0` and `−a`, the pendulum row `λ² + d·λ − k = 0` with `k` the gravity term and `d` the
/// pivot damping over the inertia; sorted ascending.
fn closed_form_eigenvalues(a: f64, k: f64, d: f64) -> Vec<f64> {
    let root = (d * d + 4.0 * k).sqrt();
    let mut e = vec![0.0, -a, (-d + root) / 2.0, (-d - root) / 2.0];
    e.sort_by(f64::total_cmp);
    e
}

#[test]
fn init_then_model_gives_the_cart_linearisation() {
    let dir = Dir::new("model-cart");
    let lab = init(&dir, "rig", "cart");
    let v = json(&pendulab(&["model", "--lab", &lab, "--json"]));
    let (a, b) = (matrix(&v["a"]), matrix(&v["b"]));

    // Round trip: the plants crate's linearisation of the book plant, unchanged.
    let ss = PlantSpec::book(PlantKind::Cart)
        .parameters()
        .linearize_upright(0.0)
        .unwrap();
    assert_eq!(&a, ss.a());
    assert_eq!(&b, ss.b());
    assert_eq!(&matrix(&v["c"]), ss.c());
    assert_eq!(&matrix(&v["d"]), ss.d());

    // Independent: the closed form of docs/model.md §1, written out in testkit.
    let p = CartParams::book();
    let (a_ref, b_ref) = p.linearization(Rest::Upright);
    assert_close(&a, &a_ref, 1e-12, "A");
    assert_close(&b, &b_ref, 1e-12, "B");
    let j = p.inertia();
    let want = closed_form_eigenvalues(p.a_c, p.m_p * p.g * p.l_p / j, p.mu_p / j);
    let got = real_poles(&v);
    for (g, w) in got.iter().zip(&want) {
        assert!(
            (g - w).abs() <= 1e-9 * w.abs().max(1.0),
            "{got:?} vs {want:?}"
        );
    }
    // The values docs/model.md §1 prints (4 decimals).
    for (g, printed) in got.iter().zip([-6.25, -5.7867, 0.0, 5.7543]) {
        assert!((g - printed).abs() < 5e-5, "{got:?}");
    }
    let c = &v["controllability"];
    assert_eq!(c["rank"], 4);
    assert_eq!(c["controllable"], true);
    assert!(c["sigma_min"].as_f64().unwrap() > 0.0);

    // The text table prints the same poles.
    let o = pendulab(&["model", "--lab", &lab]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("5.7543"), "{text}");
    assert!(text.contains("controllable"), "{text}");
}

#[test]
fn model_of_the_arm_at_an_arm_angle() {
    let dir = Dir::new("model-arm");
    let lab = init(&dir, "rig", "arm");
    let v = json(&pendulab(&[
        "model", "--lab", &lab, "--at", "-20", "--json",
    ]));
    let ss = PlantSpec::book(PlantKind::Arm)
        .parameters()
        .linearize_upright((-20f64).to_radians())
        .unwrap();
    assert_eq!(&matrix(&v["a"]), ss.a());
    assert_eq!(&matrix(&v["b"]), ss.b());
    let (a_ref, b_ref) = ArmParams::book().linearization((-20f64).to_radians());
    assert_close(&matrix(&v["a"]), &a_ref, 1e-12, "A");
    assert_close(&matrix(&v["b"]), &b_ref, 1e-12, "B");

    // At θ₁ₑ = 0: the eigenvalues docs/model.md §2 prints.
    let v = json(&pendulab(&["model", "--lab", &lab, "--json"]));
    let got = real_poles(&v);
    for (g, printed) in got.iter().zip([-6.3597, -6.2, 0.0, 6.3375]) {
        assert!((g - printed).abs() < 5e-5, "{got:?}");
    }

    // --at is the arm angle: refused for the cart.
    let cart = init(&dir, "cart", "cart");
    fails_with(
        &pendulab(&["model", "--lab", &cart, "--at", "10"]),
        &["--at", "cart"],
    );
}

/// `pendulab simulate --lab lab --controller controller extra…`.
fn simulate(lab: &str, controller: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["simulate", "--lab", lab, "--controller", controller];
    args.extend_from_slice(extra);
    pendulab(&args)
}

#[test]
fn simulate_the_rig_lqr_balances_and_writes_the_run() {
    let dir = Dir::new("simulate");
    let lab = init(&dir, "rig", "cart");
    let out = dir.path("run1");
    let v = json(&simulate(
        &lab,
        &example("cart_lqr.toml"),
        &["--out", &out, "--json"],
    ));
    // Default scenario: 5° for 5 s at the controller file's 1 kHz.
    let theta_final = v["final_state"][1].as_f64().unwrap();
    assert!(theta_final.abs() < 1e-2, "final θ = {theta_final}");
    assert_eq!(v["left_angle_window"], false);
    assert_eq!(v["left_travel"], false);
    assert_eq!(v["ts"], 1e-3);
    let samples = v["samples"].as_u64().unwrap() as usize;
    assert_eq!(samples, 5001); // t = 0, 1 ms, …, 5 s

    let csv = std::fs::read_to_string(dir.join("run1").join("run.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), "t,z,theta,dz,dtheta,v,u_ctrl");
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), samples);
    assert!(rows.iter().all(|r| r.len() == 7));
    assert_eq!(rows[0][..5], [0.0, 0.0, 5f64.to_radians(), 0.0, 0.0]);
    assert!((rows[samples - 1][0] - 5.0).abs() < 1e-9);
    // The CSV's last θ is the summary's final state.
    assert_eq!(rows[samples - 1][2], theta_final);
    let svg = std::fs::read_to_string(dir.join("run1").join("run.svg")).unwrap();
    assert!(
        svg.starts_with("<svg") || svg.starts_with("<?xml"),
        "{}",
        &svg[..40]
    );
    assert!(svg.contains("θ [deg]") && svg.contains("u_ctrl"));

    // A scenario file: 2 s from 3°, ideal loop.
    let scen = dir.file(
        "short.toml",
        "initial_state = [0.0, 0.05235987755982988, 0.0, 0.0]\nduration = 2.0\n",
    );
    let v = json(&simulate(
        &lab,
        &example("cart_lqr.toml"),
        &["--scenario", &scen, "--json"],
    ));
    assert_eq!(v["samples"], 2001);
    assert_eq!(v["time_in_saturation"], 0.0);
    // Default output: LAB/runs/<controller stem>/run.csv.
    let default_csv = PathBuf::from(&lab).join("runs/cart_lqr/run.csv");
    assert_eq!(
        std::fs::read_to_string(default_csv)
            .unwrap()
            .lines()
            .count(),
        2002
    );
}

/// The 1-based line of the first line of `text` equal to `line`.
fn line_of(text: &str, line: &str) -> usize {
    text.lines().position(|l| l == line).unwrap() + 1
}

#[test]
fn bad_lab_files_name_the_key_and_line() {
    let dir = Dir::new("bad-lab");
    let lab = init(&dir, "rig", "cart");
    let file = PathBuf::from(&lab).join("lab.toml");
    let good = std::fs::read_to_string(&file).unwrap();

    // A key the cart's parameters do not have.
    let text = good.replace("m_p = 0.107\n", "m_p = 0.107\ncolour = 1.0\n");
    std::fs::write(&file, &text).unwrap();
    let line = format!("line {}", line_of(&text, "colour = 1.0"));
    fails_with(
        &pendulab(&["model", "--lab", &lab]),
        &["lab.toml", "colour", &line],
    );

    // An unknown key in the rig part.
    let text = good.replace("nx = 4\n", "nx = 4\nfoo = 2\n");
    std::fs::write(&file, &text).unwrap();
    let line = format!("line {}", line_of(&text, "foo = 2"));
    fails_with(&pendulab(&["model", "--lab", &lab]), &["foo", &line]);

    // A NaN parameter (source "user", so only the range check can refuse it).
    let text = good
        .replace("b_c = 4.36\n", "b_c = nan\n")
        .replace("source = \"book\"", "source = \"user\"");
    std::fs::write(&file, &text).unwrap();
    let line = format!("line {}", line_of(&text, "b_c = nan"));
    fails_with(
        &pendulab(&["model", "--lab", &lab]),
        &["parameters.b_c", "NaN", &line],
    );

    // A missing lab directory.
    fails_with(
        &pendulab(&["model", "--lab", &dir.path("nowhere")]),
        &["nowhere", "lab.toml", "lab init"],
    );

    // init refuses to overwrite without --force, and leaves the file as it was.
    std::fs::write(&file, &text).unwrap();
    fails_with(
        &pendulab(&["lab", "init", &lab, "--plant", "arm"]),
        &["--force"],
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), text);
    let o = pendulab(&["lab", "init", &lab, "--plant", "arm", "--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let written = std::fs::read_to_string(&file).unwrap();
    assert!(written.contains("kind = \"arm\""), "{written}");
}

#[test]
fn bad_simulate_inputs_fail_without_writing() {
    let dir = Dir::new("bad-sim");
    let lab = init(&dir, "rig", "cart");
    let out = dir.path("out");
    let run = |controller: &str, extra: &[&str]| {
        let mut args = vec!["--out", out.as_str()];
        args.extend_from_slice(extra);
        simulate(&lab, controller, &args)
    };

    // A controller file for the other plant.
    fails_with(
        &run(&example("arm_lqr.toml"), &[]),
        &["arm_lqr.toml", "plant = \"arm\"", "cart"],
    );
    // A missing controller file.
    let missing = dir.path("missing.toml");
    fails_with(&run(&missing, &[]), &["controller", "missing.toml"]);
    // A controller file with a key its kind does not have.
    let bad = dir.file(
        "bad.toml",
        "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0, 1.0, 1.0, 1.0]\ngain = 2.0\n",
    );
    fails_with(&run(&bad, &[]), &["bad.toml", "gain"]);
    // A scenario of the wrong length.
    let scen = dir.file("s.toml", "initial_state = [0.0, 0.1]\nduration = 1.0\n");
    fails_with(
        &run(&example("cart_lqr.toml"), &["--scenario", &scen]),
        &["initial_state"],
    );
    // A NaN in the scenario names its key.
    let scen = dir.file(
        "n.toml",
        "initial_state = [0.0, nan, 0.0, 0.0]\nduration = 1.0\n",
    );
    fails_with(
        &run(&example("cart_lqr.toml"), &["--scenario", &scen]),
        &["initial_state[1]"],
    );
    assert!(!dir.join("out").join("run.csv").exists());
    assert!(!dir.join("out").join("run.svg").exists());
}
