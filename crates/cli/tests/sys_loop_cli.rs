//! The loop-analysis verbs (`nyquist`, `nichols`, `rlocus`, `diskmargin`, `sigma`) end to
//! end, each against a closed form, with their figures and typed errors.

mod common;
use common::*;

use serde_json::Value;

fn json(args: &[&str]) -> Value {
    let out = pendulab(args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{args:?}: {e}"))
}

fn stdout(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol * want.abs().max(1.0),
        "{what}: got {got}, want {want}"
    );
}

#[test]
fn nyquist_counts_encirclements_of_an_unstable_loop() {
    // 10/(s + 1)³: s³ + 3s² + 3s + 11 has two right-half-plane roots (Routh: 3·3 < 11), the
    // open loop none, so the curve encircles −1 twice clockwise.
    let v = json(&["nyquist", "--num", "10", "--den", "1 3 3 1", "--json"]);
    assert_eq!(v["encirclements"], 2, "{}", v["winding"]);
    assert_eq!(v["open_loop_unstable"], 0);
    assert_eq!(v["closed_loop_unstable"], 2);
    assert_eq!(v["criterion_holds"], true);
    // L(0) = 10.
    close(v["re"][0].as_f64().unwrap(), 10.0, 1e-12, "L(0)");
    // (s + 2)/((s − 1)(s + 3)) with gain 5: P = 1, stable closed loop, N = −1.
    let v = json(&["nyquist", "--num", "5 10", "--den", "1 2 -3", "--json"]);
    assert_eq!(v["encirclements"], -1);
    assert_eq!(v["open_loop_unstable"], 1);
    assert_eq!(v["closed_loop_unstable"], 0);
}

#[test]
fn nyquist_figure_and_errors() {
    let dir = Dir::new("sys-nyquist");
    let png = dir.join("ny.png");
    let out = pendulab(&[
        "nyquist",
        "--num",
        "1",
        "--den",
        "1 1 0",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(std::fs::metadata(&png).unwrap().len() > 10_000);
    assert!(stdout(&out).contains("1 indented pole"), "{}", stdout(&out));
    // Two inputs: not a SISO loop.
    let out = pendulab(&["nyquist", "--a", "-1", "--b", "1 1", "--c", "1", "--json"]);
    fails_with(&out, &["single-input single-output"]);
}

#[test]
fn rlocus_break_point_asymptotes_and_rlocfind() {
    // 1/(s(s + 1)(s + 2)): break-away at −1 + 1/√3, K = 2/(3√3); asymptotes from −1 at 60°,
    // 180°, 300°; the imaginary-axis crossing s = j√2 has K = 6.
    let v = json(&[
        "rlocus",
        "--num",
        "1",
        "--den",
        "1 3 2 0",
        "--at",
        "0+1.4142135623730951i",
        "--json",
    ]);
    let bp = &v["break_points"][0];
    close(
        bp["point"][0].as_f64().unwrap(),
        -1.0 + 1.0 / 3f64.sqrt(),
        1e-10,
        "break point",
    );
    close(
        bp["gain"].as_f64().unwrap(),
        2.0 / (3.0 * 3f64.sqrt()),
        1e-10,
        "K_b",
    );
    close(
        v["asymptotes"]["centroid"].as_f64().unwrap(),
        -1.0,
        1e-12,
        "centroid",
    );
    let angles: Vec<f64> = v["asymptotes"]["angles_deg"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a.as_f64().unwrap())
        .collect();
    for (a, b) in angles.iter().zip([60.0, 180.0, 300.0]) {
        close(*a, b, 1e-10, "asymptote angle");
    }
    close(
        v["rlocfind"]["gain"].as_f64().unwrap(),
        6.0,
        1e-9,
        "rlocfind K",
    );
    assert!(v["rlocfind"]["distance"].as_f64().unwrap() < 1e-8);
    // Given gains: K = 2 for 1/(s(s + 3)) puts the poles at −1 and −2.
    let v = json(&[
        "rlocus", "--num", "1", "--den", "1 3 0", "--gains", "2", "--json",
    ]);
    let mut re: Vec<f64> = v["roots"][0]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p[0].as_f64().unwrap())
        .collect();
    re.sort_by(f64::total_cmp);
    close(re[0], -2.0, 1e-12, "pole");
    close(re[1], -1.0, 1e-12, "pole");
    let dir = Dir::new("sys-rlocus");
    let svg = dir.join("rl.svg");
    let out = pendulab(&[
        "rlocus",
        "--num",
        "1",
        "--den",
        "1 3 2 0",
        "--at",
        "-0.3+1i",
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(std::fs::read_to_string(&svg).unwrap().contains("K = "));
    let out = pendulab(&["rlocus", "--num", "1", "--den", "1 1", "--at", "x"]);
    fails_with(&out, &["--at"]);
}

#[test]
fn diskmargin_closed_forms() {
    // L = −0.5/(s + 1): α = 2(1 + k)/(1 − k) = 2/3 at ω = 0; γ = (2 + α)/(2 − α) = 2.
    let v = json(&["diskmargin", "--num", "-0.5", "--den", "1 1", "--json"]);
    close(v["alpha"].as_f64().unwrap(), 2.0 / 3.0, 1e-9, "α");
    close(v["gain_interval"][1].as_f64().unwrap(), 2.0, 1e-8, "γ₊");
    close(v["gain_interval"][0].as_f64().unwrap(), 0.5, 1e-8, "γ₋");
    close(
        v["phase_margin_deg"].as_f64().unwrap(),
        2.0 * (1.0f64 / 3.0).atan().to_degrees(),
        1e-7,
        "PM",
    );
    // An unstable closed loop: α = 0.
    let v = json(&["diskmargin", "--num", "0.5", "--den", "1 -1", "--json"]);
    assert_eq!(v["closed_loop_stable"], false);
    assert_eq!(v["alpha"], 0.0);
}

#[test]
fn sigma_and_nichols_closed_forms() {
    // diag(1/(s + 1), 2/(s + 2)) at ω: σ = 1/√(1 + ω²), 2/√(4 + ω²) sorted.
    let v = json(&[
        "sigma",
        "--a",
        "-1 0; 0 -2",
        "--b",
        "1 0; 0 2",
        "--c",
        "1 0; 0 1",
        "--w-min",
        "0.1",
        "--w-max",
        "10",
        "--points",
        "5",
        "--json",
    ]);
    let w: Vec<f64> = v["w"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    for (k, wk) in w.iter().enumerate() {
        let mut want = [1.0 / (1.0 + wk * wk).sqrt(), 2.0 / (4.0 + wk * wk).sqrt()];
        want.sort_by(|a, b| b.total_cmp(a));
        for i in 0..2 {
            close(v["sv"][k][i].as_f64().unwrap(), want[i], 1e-12, "σ");
        }
    }
    // Nichols of 1/(s(s + 1)): phase −90° − atan ω in (−360°, 0°].
    let v = json(&[
        "nichols", "--num", "1", "--den", "1 1 0", "--w-min", "0.1", "--w-max", "10", "--points",
        "3", "--json",
    ]);
    for (k, wk) in [0.1f64, 1.0, 10.0].iter().enumerate() {
        close(
            v["phase_deg"][k].as_f64().unwrap(),
            -90.0 - wk.atan().to_degrees(),
            1e-9,
            "Nichols phase",
        );
    }
    let dir = Dir::new("sys-nichols");
    for (verb, file) in [("nichols", "n.png"), ("sigma", "s.svg")] {
        let p = dir.join(file);
        let out = pendulab(&[
            verb,
            "--num",
            "4",
            "--den",
            "1 3 3 1 0",
            "--out",
            p.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{verb}: {}", stderr(&out));
        assert!(p.exists());
    }
}
