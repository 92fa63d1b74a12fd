//! The MATLAB verbs (`pendulab ss|eig|ctrb|obsv|step|impulse|initial|lsim|bode|c2d|d2c|place|lqe`)
//! end to end, each against a closed form.

mod common;
use common::*;

use serde_json::Value;

fn json(args: &[&str]) -> Value {
    let out = pendulab(args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{args:?}: {e}"))
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol * want.abs().max(1.0),
        "{what}: got {got}, want {want}"
    );
}

#[test]
fn step_and_impulse_of_a_first_order_lag() {
    // G(s) = 1/(s + 1): step y = 1 − e^{−t}, impulse y = e^{−t}.
    for (verb, f) in [
        ("step", (|t: f64| 1.0 - (-t).exp()) as fn(f64) -> f64),
        ("impulse", |t: f64| (-t).exp()),
    ] {
        let v = json(&[
            verb,
            "--num",
            "1",
            "--den",
            "1 1",
            "--t-final",
            "5",
            "--step-size",
            "0.01",
            "--json",
        ]);
        let t = floats(&v["t"]);
        let y = floats(&v["y"][0][0]);
        assert_eq!(t.len(), 501);
        for (ti, yi) in t.iter().zip(&y) {
            close(*yi, f(*ti), 1e-12, verb);
        }
    }
}

#[test]
fn default_final_time_is_seven_time_constants() {
    // The documented rule: 7 τ of the slowest mode, 1000 steps.
    let v = json(&["step", "--a", "-0.5", "--b", "1", "--json"]);
    let t = floats(&v["t"]);
    assert_eq!(t.len(), 1001);
    close(*t.last().unwrap(), 14.0, 1e-12, "t_final");
}

#[test]
fn initial_and_lsim_from_files() {
    let d = Dir::new("lsim");
    // ẋ = −2x, y = x from x0 = 3: y = 3 e^{−2t}.
    let sys = d.file("first.toml", "a = [[-2]]\nb = [[1]]\nc = [[1]]\n");
    let v = json(&["initial", &sys, "--x0", "3", "--t-final", "2", "--json"]);
    for (t, y) in floats(&v["t"]).iter().zip(floats(&v["y"][0][0])) {
        close(y, 3.0 * (-2.0 * t).exp(), 1e-12, "initial");
    }
    // 1/(s + 1) driven by the ramp u = t (exact under the first-order hold):
    // y = t − 1 + e^{−t}.
    let mut text = String::from("# t, u\n");
    for k in 0..=300 {
        let t = k as f64 * 0.01;
        text.push_str(&format!("{t},{t}\n"));
    }
    let input = d.file("ramp.csv", &text);
    let v = json(&[
        "lsim", "--num", "1", "--den", "1 1", "--input", &input, "--json",
    ]);
    for (t, y) in floats(&v["t"]).iter().zip(floats(&v["y"][0][0])) {
        close(y, t - 1.0 + (-t).exp(), 1e-12, "lsim ramp");
    }
}

#[test]
fn bode_of_a_first_order_lag() {
    // |G(jω)|² = 1/(1 + ω²), ∠G = −atan ω.
    let v = json(&[
        "bode", "--num", "1", "--den", "1 1", "--w-min", "0.01", "--w-max", "100", "--points",
        "41", "--json",
    ]);
    let w = floats(&v["w"]);
    assert_eq!(w.len(), 41);
    let mag = floats(&v["channels"][0]["magnitude_db"]);
    let ph = floats(&v["channels"][0]["phase_deg"]);
    for k in 0..w.len() {
        close(mag[k], -10.0 * (1.0 + w[k] * w[k]).log10(), 1e-12, "gain");
        close(ph[k], -w[k].atan().to_degrees(), 1e-12, "phase");
    }
}

#[test]
fn c2d_d2c_of_a_first_order_system_and_the_file_chain() {
    // ẋ = −a x + u: ZOH gives a_d = e^{−a T}, b_d = (1 − e^{−a T})/a; Tustin
    // a_d = (1 − aT/2)/(1 + aT/2).
    let (a, ts) = (3.0_f64, 0.1_f64);
    let d = Dir::new("c2d");
    let disc = d.path("disc.json");
    let v = json(&[
        "c2d", "--a", "-3", "--b", "1", "--c", "1", "--ts", "0.1", "--save", &disc, "--json",
    ]);
    let e = (-a * ts).exp();
    close(v["a"][0][0].as_f64().unwrap(), e, 1e-14, "zoh a_d");
    close(
        v["b"][0][0].as_f64().unwrap(),
        (1.0 - e) / a,
        1e-14,
        "zoh b_d",
    );
    close(v["dt"].as_f64().unwrap(), ts, 0.0, "dt");
    let v = json(&[
        "c2d", "--a", "-3", "--b", "1", "--ts", "0.1", "--method", "tustin", "--json",
    ]);
    close(
        v["a"][0][0].as_f64().unwrap(),
        (1.0 - a * ts / 2.0) / (1.0 + a * ts / 2.0),
        1e-14,
        "tustin a_d",
    );
    // The saved file feeds the next verb: d2c recovers the continuous system, and eig of the
    // discrete one maps back to s = ln(z)/dt = −3.
    let v = json(&["d2c", &disc, "--json"]);
    close(v["a"][0][0].as_f64().unwrap(), -a, 1e-12, "d2c a");
    close(v["b"][0][0].as_f64().unwrap(), 1.0, 1e-12, "d2c b");
    let v = json(&["eig", &disc, "--json"]);
    close(
        v["poles"][0]["natural_frequency"].as_f64().unwrap(),
        a,
        1e-12,
        "ωn",
    );
}

#[test]
fn eig_ctrb_obsv() {
    // (s + 1)(s + 2)(s + 3) = s³ + 6s² + 11s + 6 in companion form: poles −1, −2, −3, each
    // with ζ = 1 and τ = 1/|p|.
    let v = json(&[
        "eig",
        "--a",
        "0 1 0; 0 0 1; -6 -11 -6",
        "--b",
        "0;0;1",
        "--json",
    ]);
    let mut poles: Vec<f64> = v["poles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["pole"][0].as_f64().unwrap())
        .collect();
    poles.sort_by(f64::total_cmp);
    for (p, want) in poles.iter().zip([-3.0, -2.0, -1.0]) {
        close(*p, want, 1e-12, "pole");
    }
    for p in v["poles"].as_array().unwrap() {
        close(p["damping_ratio"].as_f64().unwrap(), 1.0, 1e-12, "ζ");
        let re = p["pole"][0].as_f64().unwrap();
        close(p["time_constant"].as_f64().unwrap(), -1.0 / re, 1e-12, "τ");
    }
    // Two decoupled first-order states, only the first driven: rank 1; the double integrator
    // measured in position: observable, rank 2.
    let v = json(&["ctrb", "--a", "-1 0; 0 -2", "--b", "1; 0", "--json"]);
    assert_eq!(v["rank"], 1);
    assert_eq!(v["full_rank"], false);
    let v = json(&[
        "obsv", "--a", "0 1; 0 0", "--b", "0; 1", "--c", "1 0", "--json",
    ]);
    assert_eq!(v["rank"], 2);
    assert_eq!(v["matrix"], serde_json::json!([[1.0, 0.0], [0.0, 1.0]]));
}

#[test]
fn place_and_lqe_closed_forms() {
    // Double integrator, poles −1 ± j: s² + k₂ s + k₁ = s² + 2s + 2 → K = [2, 2].
    let v = json(&[
        "place", "--a", "0 1; 0 0", "--b", "0; 1", "--poles", "-1+1i", "--json",
    ]);
    let k = floats(&v["K"][0]);
    close(k[0], 2.0, 1e-12, "k1");
    close(k[1], 2.0, 1e-12, "k2");
    assert_eq!(floats(&v["K_book"][0]), vec![-k[0], -k[1]]);
    // Scalar Kalman filter ẋ = a x + w, y = x + v: 2aP − P²/Rn + Qn = 0 →
    // P = Rn (a + √(a² + Qn/Rn)), L = P/Rn.
    let (a, qn, rn) = (0.5_f64, 2.0_f64, 0.25_f64);
    let v = json(&[
        "lqe", "--a", "0.5", "--b", "1", "--c", "1", "--qn", "2", "--rn", "0.25", "--json",
    ]);
    let p = rn * (a + (a * a + qn / rn).sqrt());
    close(v["P"][0][0].as_f64().unwrap(), p, 1e-12, "P");
    close(v["L"][0][0].as_f64().unwrap(), p / rn, 1e-12, "L");
}

#[test]
fn figures_are_real_files() {
    let d = Dir::new("fig");
    let svg = d.path("step.svg");
    let png = d.path("bode.png");
    let out = pendulab(&["step", "--num", "1", "--den", "1 2 1", "--out", &svg]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        text.starts_with("<svg") || text.starts_with("<?xml"),
        "{}",
        &text[..80]
    );
    let out = pendulab(&["bode", "--num", "1", "--den", "1 2 1", "--out", &png]);
    assert!(out.status.success(), "{}", stderr(&out));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
}

#[test]
fn bad_input_is_named() {
    let d = Dir::new("bad");
    let nan = d.file("nan.toml", "a = [[nan]]\nb = [[1]]\n");
    fails_with(
        &pendulab(&["eig", &nan]),
        &["a", "row 1, column 1", "finite"],
    );
    let unknown = d.file("unknown.toml", "a = [[1]]\nb = [[1]]\nfoo = 1\n");
    fails_with(&pendulab(&["eig", &unknown]), &["line 3", "foo"]);
    let ragged = d.file("ragged.json", r#"{"a": [[1, 2], [3]], "b": [[1], [1]]}"#);
    fails_with(&pendulab(&["eig", &ragged]), &["a", "row 2 has 1 values"]);
    fails_with(
        &pendulab(&["step", "--a", "0 1; 0 0", "--b", "1; 1; 1"]),
        &["B"],
    );
    fails_with(
        &pendulab(&["step", &nan, "--a", "1", "--b", "1"]),
        &["not both"],
    );
    fails_with(
        &pendulab(&["eig", "--a", "1 x", "--b", "1"]),
        &["`x` is not a number"],
    );
    fails_with(
        &pendulab(&[
            "step",
            "--num",
            "1",
            "--den",
            "1 1",
            "--out",
            &d.path("f.txt"),
        ]),
        &[".svg or .png"],
    );
    fails_with(
        &pendulab(&["place", "--a", "0 1; 0 0", "--b", "0; 1", "--poles", "-1"]),
        &["pole"],
    );
    // A complex pole brings its conjugate: the count and the list say so.
    fails_with(
        &pendulab(&[
            "place", "--a", "0 1; 0 0", "--b", "0; 1", "--poles", "-1+1i -2",
        ]),
        &["needs 2 poles", "got 3: -1+1i, -1-1i, -2"],
    );
    fails_with(
        &pendulab(&["c2d", "--a", "-1", "--b", "1", "--ts", "-0.1"]),
        &["sample time"],
    );
    fails_with(
        &pendulab(&["step", "--a", "-1", "--b", "1", "--t-final", "nan"]),
        &["--t-final"],
    );
    fails_with(&pendulab(&["eig"]), &["no system"]);
    fails_with(
        &pendulab(&["eig", &d.path("missing.toml")]),
        &["cannot read"],
    );
    // Nothing half-written: a failed c2d --save leaves no file.
    let save = d.path("never.toml");
    fails_with(
        &pendulab(&["c2d", "--a", "-1", "--b", "1", "--ts", "0", "--save", &save]),
        &["sample time"],
    );
    assert!(!std::path::Path::new(&save).exists());
}

#[test]
fn margins_norms_reduction_and_stepinfo_closed_forms() {
    // L = 2/(s + 1)³: the phase reaches −180° where each pole turns 60°, ω = √3, and there
    // |L| = 2/4^{3/2} = 1/4, so GM = 4.
    let v = json(&["margin", "--num", "2", "--den", "1 3 3 1", "--json"]);
    close(v["gain_margin"].as_f64().unwrap(), 4.0, 1e-8, "GM");
    close(
        v["phase_crossover_frequency"].as_f64().unwrap(),
        3f64.sqrt(),
        1e-8,
        "ω_pc",
    );
    // L = 1/(s(s + 1)): |L| = 1 at ω² = (√5 − 1)/2, PM = 90° − atan ω, no phase crossing.
    let v = json(&["margin", "--num", "1", "--den", "1 1 0", "--json"]);
    let w = ((5f64.sqrt() - 1.0) / 2.0).sqrt();
    close(
        v["gain_crossover_frequency"].as_f64().unwrap(),
        w,
        1e-8,
        "ω_gc",
    );
    close(
        v["phase_margin_deg"].as_f64().unwrap(),
        90.0 - w.atan().to_degrees(),
        1e-6,
        "PM",
    );
    assert!(v["gain_margin"].is_null(), "{v}");
    // ‖1/(s + a)‖₂ = 1/√(2a); ‖1/(s² + 2ζs + 1)‖∞ = 1/(2ζ√(1 − ζ²)) at ω = √(1 − 2ζ²).
    let v = json(&["norm", "--num", "1", "--den", "1 3", "--json"]);
    close(v["h2"].as_f64().unwrap(), 1.0 / 6f64.sqrt(), 1e-10, "H2");
    let z = 0.2_f64;
    let v = json(&["norm", "--inf", "--num", "1", "--den", "1 0.4 1", "--json"]);
    close(
        v["hinf"].as_f64().unwrap(),
        1.0 / (2.0 * z * (1.0 - z * z).sqrt()),
        1e-7,
        "H∞",
    );
    close(
        v["peak_frequency"].as_f64().unwrap(),
        (1.0 - 2.0 * z * z).sqrt(),
        1e-3,
        "ω_peak",
    );
    // Infinite norms say why (MATLAB and python-control return Inf): 1/(s − 1) is unstable;
    // 1/(s + 1) + 1 is stable with a feedthrough, so only its H2 norm is infinite (its H∞
    // norm is 2, at ω = 0).
    for (args, want) in [
        (
            &["norm", "--num", "1", "--den", "1 -1"][..],
            "H2 norm inf: the system is unstable",
        ),
        (
            &["norm", "--inf", "--num", "1", "--den", "1 -1"][..],
            "H∞ norm inf: the system is unstable",
        ),
        (
            &["norm", "--num", "1 2", "--den", "1 1"][..],
            "H2 norm inf: the system has a feedthrough D ≠ 0",
        ),
    ] {
        let out = pendulab(args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        assert_eq!(
            String::from_utf8_lossy(&out.stdout).trim(),
            want,
            "{args:?}"
        );
    }
    let v = json(&["norm", "--inf", "--num", "1 2", "--den", "1 1", "--json"]);
    close(
        v["hinf"].as_f64().unwrap(),
        2.0,
        1e-7,
        "H∞ with feedthrough",
    );
    // (s + 1)/((s + 1)(s + 2)) realised with two states: the pole −1 cancels, one state left
    // with the pole −2.
    let v = json(&["minreal", "--num", "1 1", "--den", "1 3 2", "--json"]);
    assert_eq!(v["a"].as_array().unwrap().len(), 1, "{v}");
    close(
        v["poles"][0][0].as_f64().unwrap(),
        -2.0,
        1e-10,
        "minreal pole",
    );
    // 1/(s + 1): 10–90 % rise time ln 9, 2 % settling time ln 50 (sampled every 1 ms).
    let v = json(&[
        "stepinfo",
        "--num",
        "1",
        "--den",
        "1 1",
        "--t-final",
        "10",
        "--step-size",
        "0.001",
        "--json",
    ]);
    let si = &v["stepinfo"][0][0];
    close(si["RiseTime"].as_f64().unwrap(), 9f64.ln(), 2e-3, "rise");
    close(
        si["SettlingTime"].as_f64().unwrap(),
        50f64.ln(),
        2e-3,
        "settling",
    );
    close(si["Overshoot"].as_f64().unwrap(), 0.0, 1e-9, "overshoot");
    // Balanced truncation of a stable system keeps the requested order.
    let v = json(&[
        "balred",
        "--a",
        "-1 0 0; 0 -2 0; 0 0 -30",
        "--b",
        "1; 1; 1",
        "--c",
        "1 1 1",
        "--order",
        "2",
        "--json",
    ]);
    assert_eq!(v["a"].as_array().unwrap().len(), 2, "{v}");
    fails_with(
        &pendulab(&["margin", "--a", "-1 0; 0 -2", "--b", "1 0; 0 1"]),
        &["single-input single-output"],
    );
}

#[test]
fn pade_of_order_three_is_the_closed_form() {
    // e^{−sT} ≈ Σ (−1)^k c_k (sT)^k / Σ c_k (sT)^k with c_k = (2n−k)! n! / ((2n)! k! (n−k)!):
    // n = 3, T = 1: numerator −s³ + 12 s² − 60 s + 120 (monic-scaled by 120), denominator
    // s³ + 12 s² + 60 s + 120.
    let v = json(&["pade", "--delay", "1", "--order", "3", "--json"]);
    let (num, den) = (floats(&v["num"]), floats(&v["den"]));
    for (got, want) in num.iter().zip([-1.0, 12.0, -60.0, 120.0]) {
        close(*got / den[0], want, 1e-12, "num");
    }
    for (got, want) in den.iter().zip([1.0, 12.0, 60.0, 120.0]) {
        close(*got / den[0], want, 1e-12, "den");
    }
    // A negative delay is refused with the flag named.
    let out = pendulab(&["pade", "--delay", "-1", "--order", "3"]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("delay"), "{}", stderr(&out));
}

#[test]
fn matched_c2d_of_an_integrating_plant_is_the_closed_form() {
    // G(s) = 11/(s(s + 1)), ts = 0.1, matched (MATLAB's rule): poles 0 → 1, −1 → e^{−0.1}; of
    // the two zeros at infinity one goes to z = −1; the gain matches the integrator's
    // low-frequency gain, lim s G(s) = 11 = lim (z − 1)/ts · G(z) at z = 1:
    // G(z) = k (z + 1)/((z − 1)(z − e^{−0.1})), k = 11 · 0.1 · (1 − e^{−0.1})/2.
    let v = json(&[
        "c2d", "--num", "11", "--den", "1 1 0", "--ts", "0.1", "--method", "matched", "--json",
    ]);
    let k = 11.0 * 0.1 * (1.0 - (-0.1f64).exp()) / 2.0;
    let mut poles: Vec<f64> = v["poles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| floats(p)[0])
        .collect();
    poles.sort_by(f64::total_cmp);
    close(poles[0], (-0.1f64).exp(), 1e-12, "pole e^-0.1");
    close(poles[1], 1.0, 1e-12, "pole 1");
    // Companion form: G(z) = (c₁ z + c₀)/(z² + …), so c = [k, k] is k (z + 1).
    let c = floats(&v["c"][0]);
    close(c[0], k, 1e-12, "c0");
    close(c[1], k, 1e-12, "c1");
    // impulse-invariant: ts · h(k ts) needs D = 0; a biproper system is refused.
    let out = pendulab(&[
        "c2d", "--num", "1 2", "--den", "1 1", "--ts", "0.1", "--method", "impulse",
    ]);
    assert!(!out.status.success());
}

#[test]
fn balred_and_hsvd_accept_an_unstable_system() {
    // diag(1, −2, −30) with unit B and C: G = 1/(s − 1) + 1/(s + 2) + 1/(s + 30). The unstable
    // mode is kept (its Hankel singular value is reported as infinite: JSON null), the stable
    // part 1/(s + 2) + 1/(s + 30) is reduced to one state.
    let sys = [
        "--a",
        "1 0 0; 0 -2 0; 0 0 -30",
        "--b",
        "1; 1; 1",
        "--c",
        "1 1 1",
    ];
    let mut args = vec!["hsvd"];
    args.extend(sys);
    args.push("--json");
    let v = json(&args);
    let hsv = v["hsv"].as_array().unwrap();
    assert_eq!(hsv.len(), 3, "{v}");
    assert!(hsv[0].is_null(), "{v}");
    assert!(hsv[1].as_f64().unwrap() > hsv[2].as_f64().unwrap(), "{v}");
    let mut args = vec!["balred"];
    args.extend(sys);
    args.extend(["--order", "2", "--json"]);
    let v = json(&args);
    let poles: Vec<f64> = v["poles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| floats(p)[0])
        .collect();
    assert_eq!(poles.len(), 2, "{v}");
    assert!(poles.iter().any(|p| (p - 1.0).abs() <= 1e-10), "{v}");
    assert!(poles.iter().any(|&p| p < 0.0), "{v}");
    // Below the number of unstable states: refused.
    let mut args = vec!["balred"];
    args.extend(sys);
    args.extend(["--order", "0"]);
    fails_with(&pendulab(&args), &["unstable states"]);
}
