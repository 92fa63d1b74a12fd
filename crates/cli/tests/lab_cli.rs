//! End-to-end tests of `pendulab lab init`, `pendulab model` and `pendulab simulate`
//! (`docs/lab.md`).

mod common;
use common::*;

use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::PlantSpec;
use pendulab_testkit::Mat;
use pendulab_testkit::arm::ArmParams;
use pendulab_testkit::cart::{CartParams, Rest};
use pendulab_testkit::json::matrix;
use std::path::PathBuf;

/// A rig controller file of `docs/rig/examples/`.
fn example(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../docs/rig/examples")
        .join(name)
        .to_string_lossy()
        .into_owned()
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

/// `lab init` into `dir/name`, then the cart's `a_c`, `b_c` scaled by `fa`, `fb` with
/// `provenance.source = "user"`; the lab's path.
fn own_cart(dir: &Dir, name: &str, fa: f64, fb: f64) -> String {
    let lab = init(dir, name, "cart");
    let file = format!("{lab}/lab.toml");
    let text = std::fs::read_to_string(&file)
        .unwrap()
        .replace("source = \"book\"", "source = \"user\"")
        .replace("a_c = 6.25", &format!("a_c = {:?}", 6.25 * fa))
        .replace("b_c = 4.36", &format!("b_c = {:?}", 4.36 * fb));
    std::fs::write(&file, text).unwrap();
    lab
}

fn lab_parameter(lab: &str, key: &str) -> f64 {
    let t: toml::Table = std::fs::read_to_string(format!("{lab}/lab.toml"))
        .unwrap()
        .parse()
        .unwrap();
    t["plant"]["parameters"][key].as_float().unwrap()
}

#[test]
fn identify_save_writes_the_drive_into_the_lab_with_its_provenance() {
    // A simulated LQR run of a cart whose drive is 15 % off the book's, identified by
    // `cart-ls` (columns t, z, v of run.csv) into a book lab.
    let d = Dir::new("save");
    let rig = own_cart(&d, "rig", 1.15, 0.85);
    let o = simulate(&rig, &example("cart_lqr.toml"), &["--out", &d.path("sim")]);
    assert!(o.status.success(), "{}", stderr(&o));
    let data = d.path("sim/run.csv");
    let mine = init(&d, "mine", "cart");
    let before = std::fs::read_to_string(format!("{mine}/lab.toml")).unwrap();
    let o = pendulab(&[
        "identify", "cart-ls", "--data", &data, "--save", &mine, "--json",
    ]);
    let v = json(&o);
    for key in ["a_c", "b_c"] {
        let (got, want) = (lab_parameter(&mine, key), lab_parameter(&rig, key));
        assert!(((got - want) / want).abs() < 0.02, "{key}: {got} vs {want}");
        assert_eq!(v["saved"]["parameters"][key][1].as_f64(), Some(got));
    }
    let t: toml::Table = std::fs::read_to_string(format!("{mine}/lab.toml"))
        .unwrap()
        .parse()
        .unwrap();
    let p = &t["plant"]["provenance"];
    assert_eq!(p["source"].as_str(), Some("identified"));
    assert_eq!(p["file"].as_str(), Some(data.as_str()));
    // The window is the report's; the standard errors are the report's.
    let w: Vec<f64> = serde_json::from_value(v["window"].clone()).unwrap();
    assert_eq!(p["window"][0].as_float(), Some(w[0]));
    assert_eq!(p["window"][1].as_float(), Some(w[1]));
    assert_eq!(
        p["standard_errors"]["a_c"].as_float(),
        v["std_errors"]["ac"].as_f64()
    );
    // SHA-256 as sha256sum prints it (when the tool is there).
    if let Ok(o) = std::process::Command::new("sha256sum").arg(&data).output() {
        let printed = String::from_utf8_lossy(&o.stdout);
        assert_eq!(printed.split_whitespace().next(), p["sha256"].as_str());
    }
    // The lab with identified parameters is read by the other commands.
    let o = pendulab(&["model", "--lab", &mine, "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));

    // Refused, nothing written: a method of the other plant; another record; a forced result.
    let now = std::fs::read_to_string(format!("{mine}/lab.toml")).unwrap();
    assert_ne!(now, before);
    let o = pendulab(&["identify", "arm-ls", "--data", &data, "--save", &mine]);
    fails_with(&o, &["arm-ls", "arm pendulum", "cart pendulum"]);
    let o = pendulab(&[
        "identify", "cart-ls", "--data", &data, "--window", "1:4", "--save", &mine,
    ]);
    fails_with(&o, &["another record or window"]);
    let other = init(&d, "other", "cart");
    let o = pendulab(&[
        "identify", "cart-ls", "--data", &data, "--force", "--window", "0:0.02", "--save", &other,
    ]);
    fails_with(&o, &["not saved", "check(s) failed"]);
    assert!(
        !std::fs::read_to_string(format!("{other}/lab.toml"))
            .unwrap()
            .contains("identified")
    );
    assert_eq!(
        std::fs::read_to_string(format!("{mine}/lab.toml")).unwrap(),
        now
    );
}

/// `eig(A − B K)` of the lab's linearisation (`model --json`) and `K` from `design --json`.
fn closed_loop(lab: &str, k: &[f64]) -> Vec<(f64, f64)> {
    let m = json(&pendulab(&["model", "--lab", lab, "--json"]));
    let (a, b) = (matrix(&m["a"]), matrix(&m["b"]));
    sorted_eigenvalues(a - b * Mat::from_row_slice(1, 4, k))
}

/// `pendulab design VERB --lab LAB ARGS --json`: a successful design's JSON.
fn design(verb: &str, lab: &str, args: &[&str]) -> serde_json::Value {
    let mut all = vec!["design", verb, "--lab", lab];
    all.extend(args);
    all.push("--json");
    json(&pendulab(&all))
}

/// The LQ servo's weights and reference of the servo designs below.
const SERVO_WEIGHTS: [&str; 6] = ["--q", "10 10 0 0 20", "--r", "1", "--reference", "0.1"];

/// The gain `k` (for `u = −K x`) of a design's JSON.
fn gain(v: &serde_json::Value) -> Vec<f64> {
    serde_json::from_value(v["k"].clone()).unwrap()
}

fn poles_of(v: &serde_json::Value) -> Vec<(f64, f64)> {
    let p: Vec<[f64; 2]> = serde_json::from_value(v["closed_loop_poles"].clone()).unwrap();
    let mut p: Vec<(f64, f64)> = p.into_iter().map(|[r, i]| (r, i)).collect();
    p.sort_by(|x, y| x.partial_cmp(y).unwrap());
    p
}

#[test]
fn design_writes_a_controller_file_that_simulate_takes() {
    let d = Dir::new("design");
    let lab = own_cart(&d, "lab", 1.1, 0.9);
    // LQR: the printed poles are eig(A − BK) of the lab's model; K_book = −K.
    let v = design("lqr", &lab, &["--q", "10 10 0 0", "--r", "1"]);
    let k = gain(&v);
    let kb: Vec<f64> = serde_json::from_value(v["k_book"].clone()).unwrap();
    assert!(k.iter().zip(&kb).all(|(a, b)| *a == -b));
    let (want, got) = (closed_loop(&lab, &k), poles_of(&v));
    for (w, g) in want.iter().zip(&got) {
        assert!(
            (w.0 - g.0).abs() < 1e-8 && (w.1 - g.1).abs() < 1e-8,
            "{want:?} {got:?}"
        );
    }
    assert!(got.iter().all(|p| p.0 < 0.0));
    assert!(v["margins"]["phase_margin_deg"].as_f64().is_some());
    let file = v["file"].as_str().unwrap().to_string();
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(
        text.contains("identified") || text.contains("user's parameters"),
        "{text}"
    );
    let o = simulate(&lab, &file, &["--json"]);
    let s = json(&o);
    assert_eq!(s["left_angle_window"], false);

    // place: eig(A − BK) are the requested poles.
    let v = design("place", &lab, &["--poles", "-3+1j -3-1j -5 -6"]);
    let k = gain(&v);
    let want = [(-6.0, 0.0), (-5.0, 0.0), (-3.0, -1.0), (-3.0, 1.0)];
    for (w, g) in want.iter().zip(closed_loop(&lab, &k)) {
        assert!(
            (w.0 - g.0).abs() < 1e-6 && (w.1 - g.1).abs() < 1e-6,
            "{g:?}"
        );
    }
    // servo: a file of kind lq-servo that simulate takes.
    let v = design("servo", &lab, &SERVO_WEIGHTS);
    let text = std::fs::read_to_string(v["file"].as_str().unwrap()).unwrap();
    assert!(text.contains("kind = \"lq-servo\""), "{text}");
    assert!(poles_of(&v).iter().all(|p| p.0 < 0.0));
}

/// The `[controller]` table of a written controller file.
fn controller_table(file: &str) -> toml::Table {
    let text = std::fs::read_to_string(file).unwrap();
    let t: toml::Table = toml::from_str(&text).unwrap();
    t["controller"].as_table().unwrap().clone()
}

/// The sorted eigenvalues of a matrix as `(re, im)`.
fn sorted_eigenvalues(m: Mat) -> Vec<(f64, f64)> {
    let mut e: Vec<(f64, f64)> = m
        .complex_eigenvalues()
        .iter()
        .map(|z| (z.re, z.im))
        .collect();
    e.sort_by(|x, y| x.partial_cmp(y).unwrap());
    e
}

#[test]
fn design_observer_places_the_observer_and_balances() {
    let d = Dir::new("design-observer");
    let lab = own_cart(&d, "lab", 1.1, 0.9);
    for k_args in [
        vec!["--q", "10 10 0 0", "--r", "1"],
        vec!["--poles", "-3+1j -3-1j -5 -6"],
    ] {
        let mut args = vec!["design", "observer", "--lab", &lab];
        args.extend(&k_args);
        args.extend(["--observer-poles", "-20 -21 -25+3j -25-3j", "--json"]);
        let v = json(&pendulab(&args));
        let file = v["file"].as_str().unwrap().to_string();
        let c = controller_table(&file);
        assert_eq!(c["kind"].as_str(), Some("observer"));
        // The file's L places eig(A − LC), C = [I₂ 0], at the requested poles.
        let rows: Vec<Vec<f64>> = c["l"].clone().try_into().unwrap();
        let l = Mat::from_row_iterator(4, 2, rows.into_iter().flatten());
        let m = json(&pendulab(&["model", "--lab", &lab, "--json"]));
        let a = matrix(&m["a"]);
        let cm = Mat::from_row_slice(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
        let got = sorted_eigenvalues(&a - &l * &cm);
        let want = [(-25.0, -3.0), (-25.0, 3.0), (-21.0, 0.0), (-20.0, 0.0)];
        for (w, g) in want.iter().zip(&got) {
            assert!(
                (w.0 - g.0).abs() < 1e-6 && (w.1 - g.1).abs() < 1e-6,
                "{got:?}"
            );
        }
        // The 8 printed poles: eig(A − BK) (separation principle) and the observer's.
        let k: Vec<f64> = serde_json::from_value(v["k"].clone()).unwrap();
        let mut want = closed_loop(&lab, &k);
        want.extend(got);
        want.sort_by(|x, y| x.partial_cmp(y).unwrap());
        let got = poles_of(&v);
        assert_eq!(got.len(), 8);
        for (w, g) in want.iter().zip(&got) {
            assert!(
                (w.0 - g.0).abs() < 1e-6 && (w.1 - g.1).abs() < 1e-6,
                "{want:?} {got:?}"
            );
        }
        // simulate takes the file and balances from 5°.
        let s = json(&simulate(&lab, &file, &["--json"]));
        assert_eq!(s["left_angle_window"], false);
        let theta = s["final_state"][1].as_f64().unwrap();
        assert!(theta.abs() < 1e-2, "final θ = {theta}");
    }
    // K given twice, or not at all: an error naming the flags; nothing written.
    let out = d.path("o.toml");
    for extra in [
        vec!["--q", "1 1 0 0", "--r", "1", "--poles", "-1 -2 -3 -4"],
        vec![],
    ] {
        let mut args = vec!["design", "observer", "--lab", &lab, "--out", &out];
        args.extend(&extra);
        args.extend(["--observer-poles", "-20 -21 -22 -23"]);
        fails_with(&pendulab(&args), &["--q", "--poles"]);
        assert!(!std::path::Path::new(&out).exists());
    }
    fails_with(
        &pendulab(&[
            "design",
            "observer",
            "--lab",
            &lab,
            "--out",
            &out,
            "--q",
            "1 1 0 0",
            "--r",
            "1",
            "--observer-poles",
            "-20 -21 -22 1",
        ]),
        &["--observer-poles", "left half-plane"],
    );
    assert!(!std::path::Path::new(&out).exists());
}

#[test]
fn design_lmi_servo_equals_the_riccati_servo_and_tracks() {
    let d = Dir::new("design-lmi-servo");
    let lab = own_cart(&d, "lab", 1.1, 0.9);
    let gain = |method: &str| {
        let v = design(method, &lab, &SERVO_WEIGHTS);
        (Mat::from_row_slice(1, 5, &gain(&v)), v)
    };
    // Two independent algorithms for the same LQ servo gain on [x; w]: the LMI guaranteed
    // cost (interior point, margin ε = 1e-6, gap 1e-8, amplified by κ(X)) and the CARE.
    let (k_lmi, v) = gain("lmi-servo");
    let (k_care, _) = gain("servo");
    let rel = (&k_lmi - &k_care).norm() / k_care.norm();
    assert!(rel < 1e-4, "LMI {k_lmi} vs CARE {k_care}: relative {rel:e}");
    assert_eq!(poles_of(&v).len(), 5);
    assert!(poles_of(&v).iter().all(|p| p.0 < 0.0));
    let file = v["file"].as_str().unwrap().to_string();
    let c = controller_table(&file);
    assert_eq!(c["kind"].as_str(), Some("lq-servo"));
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("method = \"lmi-servo\""), "{text}");
    // simulate takes it: balanced, the cart near the 0.1 m reference after 5 s.
    let s = json(&simulate(&lab, &file, &["--json"]));
    assert_eq!(s["left_angle_window"], false);
    let z = s["final_state"][0].as_f64().unwrap();
    assert!((z - 0.1).abs() < 1e-2, "final z = {z}");
}

#[test]
fn design_robust_is_stable_at_every_vertex() {
    let d = Dir::new("design-robust");
    let lab = own_cart(&d, "lab", 1.0, 1.0);
    let v = design(
        "robust",
        &lab,
        &[
            "--q",
            "10 10 0 0",
            "--r",
            "1",
            "--vary",
            "a_c=±20%",
            "--vary",
            "b_c=+-20%",
            "--decay-rate",
            "1",
            "--speed-limit",
            "40",
        ],
    );
    let k = gain(&v);
    // Each vertex as its own lab, linearised by `model`: eig(A − BK) in the requested region
    // −40 < Re λ < −1 at all four corners of the box.
    for (i, (fa, fb)) in [(0.8, 0.8), (0.8, 1.2), (1.2, 0.8), (1.2, 1.2)]
        .into_iter()
        .enumerate()
    {
        let corner = own_cart(&d, &format!("vertex{i}"), fa, fb);
        let e = closed_loop(&corner, &k);
        assert!(
            e.iter().all(|p| p.0 < -1.0 && p.0 > -40.0),
            "vertex a_c·{fa}, b_c·{fb}: {e:?}"
        );
    }
    // The printed poles are the lab plant's eig(A − BK).
    for (w, g) in closed_loop(&lab, &k).iter().zip(&poles_of(&v)) {
        assert!((w.0 - g.0).abs() < 1e-8 && (w.1 - g.1).abs() < 1e-8);
    }
    let file = v["file"].as_str().unwrap().to_string();
    assert_eq!(
        controller_table(&file)["kind"].as_str(),
        Some("state-feedback")
    );
    let s = json(&simulate(&lab, &file, &["--json"]));
    assert_eq!(s["left_angle_window"], false);
    // Bad ranges name the argument; nothing written.
    let out = d.path("r.toml");
    for (vary, needle) in [
        ("x=±10%", "'x' is not a parameter"),
        ("m_p=10%", "±P%"),
        ("m_p=±100%", "0 < P < 100"),
    ] {
        fails_with(
            &pendulab(&[
                "design", "robust", "--lab", &lab, "--out", &out, "--q", "1 1 0 0", "--r", "1",
                "--vary", vary,
            ]),
            &["--vary", needle],
        );
        assert!(!std::path::Path::new(&out).exists());
    }
}

#[test]
fn bad_design_requests_name_what_and_write_nothing() {
    let d = Dir::new("design-bad");
    let lab = init(&d, "lab", "cart");
    let out = d.path("c.toml");
    for (args, needles) in [
        (
            vec!["lqr", "--q", "1 1 1", "--r", "1"],
            vec!["--q", "4 numbers"],
        ),
        (
            vec!["lqr", "--q", "1 nan 1 1", "--r", "1"],
            vec!["--q", "NaN"],
        ),
        (vec!["lqr", "--q", "1 1 1 1", "--r", "0"], vec!["--r 0"]),
        (
            vec!["lqr", "--q", "1 -1 1 1", "--r", "1"],
            vec!["--q", "≥ 0"],
        ),
        (
            vec!["place", "--poles", "-1 -2 -3 1"],
            vec!["--poles", "left half-plane"],
        ),
        (
            vec!["place", "--poles", "-1 -2 -3"],
            vec!["--poles", "4 poles"],
        ),
        (
            vec!["place", "--poles", "-1 -2 -3 x"],
            vec!["--poles", "'x'"],
        ),
        (vec!["p", "--kp", "-1", "--target", "0.1"], vec!["--kp"]),
    ] {
        let mut a = vec!["design"];
        a.push(args[0]);
        a.extend(["--lab", &lab, "--out", &out]);
        a.extend(&args[1..]);
        fails_with(&pendulab(&a), &needles);
        assert!(!std::path::Path::new(&out).exists(), "{args:?} wrote {out}");
    }
    // A design for the cart refused on an arm lab by simulate and rig run.
    let v = json(&pendulab(&[
        "design", "lqr", "--lab", &lab, "--q", "1 1 0 0", "--r", "1", "--out", &out, "--json",
    ]));
    assert!(v["file"].is_string());
    let arm = init(&d, "arm", "arm");
    fails_with(
        &simulate(&arm, &out, &[]),
        &["plant = \"cart\"", "arm pendulum"],
    );
    let o = pendulab(&[
        "rig",
        "run",
        "--lab",
        &arm,
        "--connect",
        "127.0.0.1:9",
        "--controller",
        &out,
    ]);
    fails_with(&o, &["plant = \"cart\"", "arm pendulum"]);
}

#[test]
fn plot_compares_two_records_by_their_fit() {
    let d = Dir::new("plot");
    let lab = init(&d, "lab", "cart");
    let o = simulate(&lab, &example("cart_lqr.toml"), &["--out", &d.path("a")]);
    assert!(o.status.success(), "{}", stderr(&o));
    let run = d.path("a/run.csv");
    // A record against itself: every fit is 100 % (‖y − ŷ‖ = 0).
    let v = json(&pendulab(&[
        "plot",
        &run,
        "--vs",
        &run,
        "--out",
        &d.path("f.png"),
        "--json",
    ]));
    let fits = v["fits"].as_array().unwrap();
    assert!(fits.iter().any(|f| f["signal"] == "z"));
    for f in fits {
        assert_eq!(f["percent"].as_f64(), Some(100.0), "{f}");
    }
    assert!(
        std::fs::read(d.path("f.png"))
            .unwrap()
            .starts_with(b"\x89PNG")
    );
    // The mean as the model: fit 0 % by the definition.
    let text = std::fs::read_to_string(&run).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let z = header.split(',').position(|c| c == "z").unwrap();
    let mean = rows.iter().map(|r| r[z]).sum::<f64>() / rows.len() as f64;
    let mut flat = String::from("t,z,theta,v\n");
    for r in &rows {
        flat.push_str(&format!("{},{mean},{},{}\n", r[0], r[2], r[5]));
    }
    let flat_path = d.file("flat.csv", &flat);
    let v = json(&pendulab(&["plot", &run, "--vs", &flat_path, "--json"]));
    let fz = v["fits"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["signal"] == "z")
        .unwrap()["percent"]
        .as_f64()
        .unwrap();
    assert!(fz.abs() < 1e-9, "{fz}");
    // Bad input: NaN, a wrong extension, the other plant's columns.
    let nan = d.file("nan.csv", "t,z,theta,v\n0,0,0,0\n0.001,NaN,0,0\n");
    fails_with(&pendulab(&["plot", &nan]), &["nan.csv", "z"]);
    fails_with(
        &pendulab(&["plot", &run, "--out", &d.path("f.jpg")]),
        &["--out", ".svg or .png"],
    );
    let arm = d.file("arm.csv", "t,theta1,theta2,v\n0,0,0,0\n0.001,0,0,0\n");
    fails_with(
        &pendulab(&["plot", &run, "--vs", &arm]),
        &["different plants"],
    );
}
