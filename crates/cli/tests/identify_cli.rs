//! `pendulab identify` end to end: runs the binary on the rig CSV files and on CSV files
//! written here, and checks the JSON, the table and the errors (non-zero exit, a message
//! naming file, column or line).

mod common;
use common::*;

use serde_json::Value;
use std::process::{Command, Output};

const AC: f64 = 6.25;
const BC: f64 = 4.36;
const JP: f64 = 1.59e-3;
const MUP: f64 = 2.35e-4;

fn rig(name: &str) -> String {
    format!("{}/../../data/rig/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pendulab"))
        .arg("identify")
        .args(args)
        .output()
        .unwrap()
}

fn est(v: &Value, name: &str) -> f64 {
    v["estimates"][name]
        .as_f64()
        .unwrap_or_else(|| panic!("no estimate {name} in {v}"))
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn least_squares_on_the_rig_data() {
    // Book part 1 §3.2 (p1c322_cdip_id_least_square.m): 1–5 s, T_f = 0.075 → within 1 % of
    // table 3.5.
    let f = rig("cdip_least_square_data.csv");
    let v = json(&run(&[
        "cart-ls", "--data", &f, "--window", "1:5", "--tf", "0.075", "--json",
    ]));
    assert_eq!(v["method"], "cart-ls");
    assert_eq!(v["samples"], 4001);
    assert!(rel(est(&v, "ac"), AC) < 0.01 && rel(est(&v, "bc"), BC) < 0.01);
    for k in ["ac", "bc"] {
        assert!(v["std_errors"][k].as_f64().unwrap() > 0.0);
    }
    assert!(v["condition"].as_f64().unwrap() >= 1.0);
    assert_eq!(v["fit"]["output"], "z");
    assert!(v["fit"]["percent"].as_f64().unwrap() > 90.0);
    let v = json(&run(&[
        "pend-ls", "--data", &f, "--window", "1:5", "--json",
    ]));
    assert!(rel(est(&v, "Jp"), JP) < 0.01 && rel(est(&v, "mup"), MUP) < 0.01);
    assert_eq!(v["constants"]["mp"], 0.107);
    // The plain output is a table naming the parameters and the fit.
    let o = run(&["pend-ls", "--data", &f, "--window", "1:5"]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("Jp") && text.contains("mup") && text.contains("validation fit"));
    // Without the filter the pendulum estimate is nonsense (J_p < 0): refused, not printed.
    let o = run(&["pend-ls", "--data", &f, "--window", "1:5", "--no-filter"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("Jp"), "{}", stderr(&o));
    // A known constant reaches the regression: N₂ of eq. 3.45 is proportional to m_p and M₂
    // does not contain it, so doubling m_p doubles both estimates exactly.
    let v2 = json(&run(&[
        "pend-ls", "--data", &f, "--window", "1:5", "--mp", "0.214", "--json",
    ]));
    assert!(rel(est(&v2, "Jp"), 2.0 * est(&v, "Jp")) < 1e-9);
    assert!(rel(est(&v2, "mup"), 2.0 * est(&v, "mup")) < 1e-9);
}

#[test]
fn feature_methods_on_the_rig_data() {
    // Book part 1 §3.2.1, p1c321_cdip_id_cart.m (t ≥ 1 s, k_P = 10, 0.2 m) and p1c321_cdip_id_pend
    // (35–51 s). The values within the feature methods' bias (crates/ident/tests/rig_data.rs
    // explains it): 2 % for the drive, 20 % for J_p and 15 % for μ_p.
    let v = json(&run(&[
        "cart-step",
        "--data",
        &rig("cdip_cart_pcont_data_kP_100_ref_02.csv"),
        "--window",
        "1:",
        "--json",
    ]));
    assert!(rel(est(&v, "ac"), AC) < 0.02 && rel(est(&v, "bc"), BC) < 0.02);
    // T_p and the overshoot the table implies in closed form: 0.54011 s, 0.036978 m.
    assert!(rel(est(&v, "Tp"), 0.54011) < 0.01);
    assert!(rel(est(&v, "overshoot"), 0.036978) < 0.02);
    // A feature method has no regressor: no condition number or residual, and no null.
    assert!(
        v.get("condition").is_none() && v.get("residual_rms").is_none(),
        "{v}"
    );
    let f = rig("cdip_pend_data.csv");
    let v = json(&run(&[
        "pend-free",
        "--data",
        &f,
        "--window",
        "35:51",
        "--json",
    ]));
    assert!(rel(est(&v, "Jp"), JP) < 0.20 && rel(est(&v, "mup"), MUP) < 0.15);
    // Table 3.5's small-swing period is 1.0888 s; the swing's amplitude lengthens it ~1.8 %.
    assert!(rel(est(&v, "period"), 1.0888) < 0.03);
    assert!(est(&v, "decay_ratio") > 0.95 && est(&v, "decay_ratio") < 1.0);
    for k in ["Jp", "mup", "period", "decay_ratio"] {
        assert!(v["std_errors"][k].as_f64().unwrap() > 0.0, "{k}");
    }
    // With the large-amplitude correction J_p is right to 2 %, and the nonlinear pendulum with
    // those parameters follows the record (fit) far better than with the book's.
    let c = json(&run(&[
        "pend-free",
        "--data",
        &f,
        "--window",
        "35:51",
        "--amplitude-correction",
        "--json",
    ]));
    assert!(rel(est(&c, "Jp"), JP) < 0.02);
    assert!(c["fit"]["percent"].as_f64().unwrap() > v["fit"]["percent"].as_f64().unwrap());
    assert!(c["fit"]["percent"].as_f64().unwrap() > 90.0);
}

/// Arm-rig data written here: the arm follows φ₁(t) = A sin(ωt) + B sin(2.3ωt) exactly (so
/// φ̇₁, φ̈₁ are known in closed form), the pendulum obeys `docs/model.md` §2 with φ₂ = θ₂ − π,
/// integrated by RK4 at 0.1 ms and sampled at 1 ms; quantised to the arm rig's encoders.
fn arm_pendulum_csv(j2: f64, mu2: f64) -> String {
    arm_pendulum_csv_with(j2, mu2, 1.0, 0.0, 10.0)
}

/// As [`arm_pendulum_csv`] with the arm motion scaled by `arm_scale`, the pendulum released
/// from `phi2_0` at rest, over `t_end` seconds.
fn arm_pendulum_csv_with(j2: f64, mu2: f64, arm_scale: f64, phi2_0: f64, t_end: f64) -> String {
    let (l1, m2, l2, g) = (0.227, 0.096, 0.195, 9.81);
    let (a3, a5, alpha2) = (m2 * l1 * l2, m2 * l2 * g, j2 + m2 * l2 * l2);
    let (amp, w, amp2) = (0.5 * arm_scale, 4.0, 0.2 * arm_scale);
    let arm = |t: f64| {
        let (s1, c1) = (w * t).sin_cos();
        let (s2, c2) = (2.3 * w * t).sin_cos();
        (
            amp * s1 + amp2 * s2,
            amp * w * c1 + amp2 * 2.3 * w * c2,
            -amp * w * w * s1 - amp2 * 5.29 * w * w * s2,
        )
    };
    let f = |t: f64, x: f64, v: f64| {
        let (p1, d1, dd1) = arm(t);
        let (s12, c12) = (p1 - x).sin_cos();
        (a3 * c12 * dd1 - a3 * d1 * d1 * s12 - a5 * x.sin() - mu2 * (v - d1)) / alpha2
    };
    let (q1, q2) = (
        2.0 * std::f64::consts::PI / 200_000.0,
        2.0 * std::f64::consts::PI / 14_400.0,
    );
    let h = 1e-4;
    let (mut x, mut v) = (phi2_0, 0.0f64);
    let mut out = String::from("t,phi1,phi2,theta2\n");
    let steps = (t_end / h).round() as usize;
    for k in 0..=steps {
        let t = k as f64 * h;
        if k % 10 == 0 {
            let p1 = arm(t).0;
            let p2 = (x / q2).round() * q2;
            out.push_str(&format!(
                "{},{},{p2},{p2}\n",
                (k / 10) as f64 * 1e-3,
                (p1 / q1).round() * q1,
            ));
        }
        let (k1x, k1v) = (v, f(t, x, v));
        let (k2x, k2v) = (
            v + 0.5 * h * k1v,
            f(t + 0.5 * h, x + 0.5 * h * k1x, v + 0.5 * h * k1v),
        );
        let (k3x, k3v) = (
            v + 0.5 * h * k2v,
            f(t + 0.5 * h, x + 0.5 * h * k2x, v + 0.5 * h * k2v),
        );
        let (k4x, k4v) = (v + h * k3v, f(t + h, x + h * k3x, v + h * k3v));
        x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    }
    out
}

#[test]
fn arm_methods_on_simulated_data() {
    let d = Dir::new("arm");
    // Arm pendulum by least squares with table 3.7's J₂ = 9.06e-4, μ₂ = 1.01e-4: the data obey
    // the regression's model exactly up to RK4 error (~1e-12) and the encoder quantisation
    // (2π/14400 on φ₂), which the book's filter suppresses; 5 % on μ₂ (a small term, ~1 % of
    // the torque) and 1 % on J₂.
    let f = d.file("arm_pend.csv", &arm_pendulum_csv(9.06e-4, 1.01e-4));
    let v = json(&run(&["arm-pend-ls", "--data", &f, "--json"]));
    assert!(rel(est(&v, "J2"), 9.06e-4) < 0.01, "{v}");
    assert!(rel(est(&v, "mu2"), 1.01e-4) < 0.05, "{v}");
    assert!(
        (est(&v, "alpha2") - est(&v, "J2") - 0.096 * 0.195 * 0.195).abs() < 1e-12,
        "α₂ = J₂ + m₂ l₂²"
    );
    assert!(v["fit"]["percent"].as_f64().unwrap() > 90.0);
    // A missing column of the arm methods is named.
    let o = run(&["arm-ls", "--data", &f]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("'v'") && stderr(&o).contains("arm_pend.csv"));
}

#[test]
fn arm_feature_methods_on_simulated_data() {
    let d = Dir::new("armfeat");
    // Free swing of the arm pendulum with the arm held (`docs/model.md` §2 with θ̇₁ = θ̈₁ = 0):
    // from 0.4 rad, 30 s, quantised. With the amplitude correction the period gives J₂ to 1 %
    // (the decay is viscous only, so μ₂ comes back within a few percent: 5 %).
    let f = d.file(
        "arm_free.csv",
        &arm_pendulum_csv_with(9.06e-4, 1.01e-4, 0.0, 0.4, 30.0),
    );
    let v = json(&run(&[
        "arm-pend-free",
        "--data",
        &f,
        "--amplitude-correction",
        "--json",
    ]));
    assert!(rel(est(&v, "J2"), 9.06e-4) < 0.01, "{v}");
    assert!(rel(est(&v, "mu2"), 1.01e-4) < 0.05, "{v}");
    assert!(v["fit"]["percent"].as_f64().unwrap() > 90.0);

    // Arm P-control step (k_P = 3, 1 rad at 1 s) of the linear arm drive with table 3.7's
    // a₁ = 6.20, b₁ = 15.8, written in closed form: ω_n² = b₁k_P, ζ = a₁/(2ω_n),
    // θ₁ = 1 − e^{−ζω_n s}(cos ω_d s + ζ/√(1−ζ²) sin ω_d s), s = t − 1; quantised to the arm
    // encoder. The method reads the peak of a plateau of equal samples: within 1 %.
    let (a1, b1, kp): (f64, f64, f64) = (6.20, 15.8, 3.0);
    let wn = (b1 * kp).sqrt();
    let zeta = a1 / (2.0 * wn);
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let q = 2.0 * std::f64::consts::PI / 200_000.0;
    let mut csv = String::from("t,theta1,theta2\n");
    for k in 0..4000 {
        let t = k as f64 * 1e-3;
        let s = t - 1.0;
        let th = if s <= 0.0 {
            0.0
        } else {
            1.0 - (-zeta * wn * s).exp()
                * ((wd * s).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * s).sin())
        };
        csv.push_str(&format!("{t},{},0\n", (th / q).round() * q));
    }
    let f = d.file("arm_step.csv", &csv);
    let v = json(&run(&["arm-step", "--data", &f, "--json"]));
    assert!(rel(est(&v, "a1"), a1) < 0.01, "{v}");
    assert!(rel(est(&v, "b1"), b1) < 0.01, "{v}");
    assert_eq!(v["constants"]["kP"], 3.0);
}

#[test]
fn bad_input_fails_with_a_clear_message() {
    let d = Dir::new("bad");
    let ok_rows: String = (0..50)
        .map(|k| format!("{},{},{}\n", k as f64 * 1e-3, 0.01 * k as f64, 1.0))
        .collect();
    let cases: Vec<(&str, String, Vec<&str>, Vec<&str>)> = vec![
        // (file, content, extra args, fragments the message must contain)
        (
            "nocol.csv",
            format!("t,z,volt\n{ok_rows}"),
            vec![],
            vec!["nocol.csv", "'v'", "t, z, volt"],
        ),
        (
            "nan.csv",
            "t,z,v\n0,0,1\n0.001,NaN,1\n0.002,0,1\n".into(),
            vec![],
            vec!["nan.csv", "'z'", "line 3"],
        ),
        (
            "text.csv",
            "t,z,v\n0,0,1\n0.001,abc,1\n".into(),
            vec![],
            vec!["text.csv", "line 3", "not a number"],
        ),
        (
            "backwards.csv",
            "t,z,v\n0,0,1\n0.001,0,1\n0.0005,0,1\n0.002,0,1\n".into(),
            vec![],
            vec!["backwards.csv", "does not increase", "line 4"],
        ),
        (
            "uneven.csv",
            "t,z,v\n0,0,1\n0.001,0,1\n0.002,0,1\n0.004,0,1\n0.005,0,1\n".into(),
            vec![],
            vec!["uneven.csv", "uneven sampling", "line 5"],
        ),
        (
            "short.csv",
            "t,z,v\n0,0,1\n0.001,0,1\n".into(),
            vec![],
            vec!["needs at least"],
        ),
        (
            "window.csv",
            format!("t,z,v\n{ok_rows}"),
            vec!["--window", "0:2"],
            vec!["window.csv", "not inside the data"],
        ),
        (
            // 1000 samples (1 s), so that the checks of the record (stencils, T_f ≤ span/10)
            // pass and the regression itself is reached.
            "zero.csv",
            (0..1000)
                .map(|k| format!("{},0,0\n", k as f64 * 1e-3))
                .fold("t,z,v\n".to_string(), |a, b| a + &b),
            vec![],
            vec!["rank-deficient"],
        ),
        (
            "badwin.csv",
            format!("t,z,v\n{ok_rows}"),
            vec!["--window", "1-5"],
            vec!["--window"],
        ),
    ];
    for (name, content, extra, fragments) in cases {
        let f = d.file(name, &content);
        let mut args = vec!["cart-ls", "--data", &f];
        args.extend(extra);
        let o = run(&args);
        assert!(!o.status.success(), "{name} should fail");
        let e = stderr(&o);
        for frag in fragments {
            assert!(e.contains(frag), "{name}: '{frag}' not in: {e}");
        }
        assert!(!e.contains("panicked"), "{name}: {e}");
    }
    let o = run(&["cart-ls", "--data", "/nonexistent/file.csv"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("/nonexistent/file.csv"));
}

/// The book's record (`data/rig/cdip_least_square_data.csv`) with every line passed through
/// `row` (the header line as it is unless `header` is given).
fn book_variant(header: Option<&str>, row: impl Fn(&[f64]) -> Vec<f64>) -> String {
    let text = std::fs::read_to_string(rig("cdip_least_square_data.csv")).unwrap();
    let mut lines = text.lines();
    let head = lines.next().unwrap();
    let mut out = format!("{}\n", header.unwrap_or(head));
    for l in lines.filter(|l| !l.trim().is_empty()) {
        let v: Vec<f64> = l.split(',').map(|f| f.trim().parse().unwrap()).collect();
        let r: Vec<String> = row(&v).iter().map(|x| format!("{x:?}")).collect();
        out.push_str(&r.join(","));
        out.push('\n');
    }
    out
}

/// `true` if the document holds a `null` anywhere.
fn has_null(v: &Value) -> bool {
    match v {
        Value::Null => true,
        Value::Array(a) => a.iter().any(has_null),
        Value::Object(o) => o.values().any(has_null),
        _ => false,
    }
}

fn warnings(v: &Value) -> Vec<String> {
    v["warnings"]
        .as_array()
        .unwrap_or_else(|| panic!("no warnings list in {v}"))
        .iter()
        .map(|w| w.as_str().unwrap().to_string())
        .collect()
}

/// Each careless input of issue 21 is refused with its cause named; `--force` prints the
/// result with that cause among the warnings (text and JSON) and exits 0.
#[test]
fn identification_refuses_to_guess() {
    let d = Dir::new("guess");
    let book = rig("cdip_least_square_data.csv");
    // Time in milliseconds under a plain `t` header: read as seconds, the step is 1 s.
    let ms = d.file(
        "ms.csv",
        &book_variant(None, |r| {
            let mut r = r.to_vec();
            r[0] = (r[0] * 1000.0).round();
            r
        }),
    );
    // The cart position scaled by 1e300 (the fuzzer's "scaled data").
    let scaled = d.file(
        "scaled.csv",
        &book_variant(None, |r| vec![r[0], r[1] * 1e300, r[2], r[3]]),
    );
    let cases: Vec<(&str, Vec<&str>, Vec<&str>)> = vec![
        // (name, arguments, fragments naming the cause)
        (
            "ms time",
            vec!["pend-ls", "--data", &ms],
            vec!["ms.csv", "step of 1 s", "--time-unit ms"],
        ),
        (
            "scaled data",
            vec!["pend-ls", "--data", &scaled, "--window", "1:5"],
            vec!["standard error of Jp", "not a finite number"],
        ),
        (
            "2 ms window",
            vec!["cart-ls", "--data", &book, "--window", "1:1.002"],
            vec!["needs at least 20 samples, got 3", "t = 1 … 1.002 s"],
        ),
        (
            "4001-sample Savitzky–Golay window",
            vec![
                "pend-ls", "--data", &book, "--window", "1:5", "--savgol", "4001",
            ],
            vec!["Savitzky–Golay", "4001-sample window", "got 4001"],
        ),
        (
            "--tf 1e9",
            vec!["cart-ls", "--data", &book, "--window", "1:5", "--tf", "1e9"],
            vec!["T_f = 1e9 s", "record span 4 s"],
        ),
        (
            "--mp 1e-300",
            vec![
                "pend-ls", "--data", &book, "--window", "1:5", "--mp", "1e-300",
            ],
            vec!["m_p = 1e-300 kg", "plausible range"],
        ),
    ];
    for (name, args, fragments) in &cases {
        let o = run(args);
        assert!(!o.status.success(), "{name}: accepted");
        let e = stderr(&o);
        for f in fragments {
            assert!(e.contains(f), "{name}: '{f}' not in: {e}");
        }
        assert!(
            e.contains("--force") && !e.contains("panicked"),
            "{name}: {e}"
        );
        // Forced: exit 0, the cause among the JSON warnings and on standard error, and no
        // silent null (every null estimate is named by a warning).
        let mut forced = args.clone();
        forced.extend(["--force", "--json"]);
        let o = run(&forced);
        let v = json(&o);
        let w = warnings(&v);
        assert!(
            w.iter().any(|w| fragments.iter().all(|f| w.contains(f))),
            "{name}: cause not among the warnings {w:?}"
        );
        assert!(stderr(&o).contains("warning"), "{name}");
        assert!(!has_null(&v), "{name}: a null in {v}");
        for part in ["estimates", "std_errors"] {
            for (k, x) in v[part].as_object().unwrap() {
                if let Some(text) = x.as_str() {
                    // A non-finite number is written as text, and a warning names it.
                    assert!(
                        ["NaN", "inf", "-inf"].contains(&text),
                        "{name}: {k} = {text}"
                    );
                    assert!(
                        w.iter().any(|w| w.contains(&format!("{k} = {text}"))),
                        "{name}: {k}"
                    );
                }
            }
        }
        // The text table shows the warnings too.
        forced.pop();
        let o = run(&forced);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(
            text.contains("WARNINGS") && text.contains(fragments[0]),
            "{name}: {text}"
        );
    }
    // A checked run has an empty warnings list.
    let v = json(&run(&[
        "cart-ls", "--data", &book, "--window", "1:5", "--json",
    ]));
    assert!(warnings(&v).is_empty());
}

/// Declaring the unit fixes the millisecond file: by option or by header, it gives the book
/// file's estimates (the time stamps are the same numbers scaled by 10⁻³; 1e-9 relative
/// covers the rounding of the scaled time stamps in the mean sample time).
#[test]
fn millisecond_time_declared() {
    let d = Dir::new("ms");
    let to_ms = |r: &[f64]| {
        let mut r = r.to_vec();
        r[0] = (r[0] * 1000.0).round();
        r
    };
    let plain = d.file("ms.csv", &book_variant(None, to_ms));
    let header = d.file("t_ms.csv", &book_variant(Some("t_ms,z,phi,v"), to_ms));
    let book = rig("cdip_least_square_data.csv");
    let reference = json(&run(&[
        "pend-ls", "--data", &book, "--window", "1:5", "--json",
    ]));
    for args in [
        vec![
            "pend-ls",
            "--data",
            &plain,
            "--time-unit",
            "ms",
            "--window",
            "1:5",
            "--json",
        ],
        vec!["pend-ls", "--data", &header, "--window", "1:5", "--json"],
    ] {
        let v = json(&run(&args));
        assert_eq!(v["samples"], 4001);
        for k in ["Jp", "mup"] {
            assert!(rel(est(&v, k), est(&reference, k)) < 1e-9, "{k}: {v}");
        }
    }
    // A header in ms contradicted by the option is an error.
    let o = run(&["pend-ls", "--data", &header, "--time-unit", "s"]);
    assert!(
        !o.status.success() && stderr(&o).contains("milliseconds"),
        "{}",
        stderr(&o)
    );
}

/// Excel's "CSV UTF-8": a byte-order mark, CRLF line ends, padded header names — read as the
/// plain file, the same estimates bit for bit. An invisible character left in a header name
/// is shown escaped when the column is missing.
#[test]
fn byte_order_mark_is_read() {
    let d = Dir::new("bom");
    let text = std::fs::read_to_string(rig("cdip_least_square_data.csv")).unwrap();
    let excel = format!(
        "\u{feff}{}",
        text.replacen("t,z,phi,v", "t, z ,phi,v ", 1)
            .replace('\n', "\r\n")
    );
    let bom = d.file("bom.csv", &excel);
    for method in ["cart-ls", "pend-ls"] {
        let a = json(&run(&[
            method,
            "--data",
            &rig("cdip_least_square_data.csv"),
            "--window",
            "1:5",
            "--json",
        ]));
        let b = json(&run(&[method, "--data", &bom, "--window", "1:5", "--json"]));
        assert_eq!(a["estimates"], b["estimates"], "{method}");
        assert_eq!(a["std_errors"], b["std_errors"], "{method}");
    }
    let hidden = d.file(
        "hidden.csv",
        &text.replacen("t,z,phi,v", "t,z,phi,\u{200b}v", 1),
    );
    let o = run(&["cart-ls", "--data", &hidden]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains(r#""\u{200b}v""#), "{}", stderr(&o));
}

/// The validation says what it validated: which model, on which signal, over which window,
/// compared with which measurement.
#[test]
fn validation_fit_states_what_it_validates() {
    let book = rig("cdip_least_square_data.csv");
    let v = json(&run(&[
        "cart-ls", "--data", &book, "--window", "1:5", "--json",
    ]));
    let f = &v["fit"];
    assert_eq!(f["window"], serde_json::json!([1.0, 5.0]));
    assert!(f["input"].as_str().unwrap().contains("voltage v"));
    assert!(f["model"].as_str().unwrap().contains("drive"));
    let o = run(&["pend-ls", "--data", &book, "--window", "1:5"]);
    let text = String::from_utf8_lossy(&o.stdout);
    let line = text
        .lines()
        .find(|l| l.starts_with("validation fit"))
        .unwrap_or_else(|| panic!("{text}"));
    for frag in [
        "cart pendulum",
        "cart acceleration",
        "t = 1–5 s",
        "compared with the measured phi",
    ] {
        assert!(line.contains(frag), "'{frag}' not in: {line}");
    }
}
