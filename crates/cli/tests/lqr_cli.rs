//! `pendulab lqr` end to end: runs the binary on CSV files.

mod common;
use common::*;

use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pendulab"))
        .arg("lqr")
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn cdip_lqr_gain_in_json() {
    // IP Toolbox cdip_lqr_sim.m: Q = diag(10, 10, 0, 0), R = 1 → book gain (u = +K x)
    // [3.16228, 13.47175, 4.48137, 2.26289], so the CLI's K (u = −K x) is its negative;
    // printed to 5 decimals (tolerance 5e-6).
    let d = Dir::new("ok");
    let (a, b) = cdip_csv();
    let a = d.file("A.csv", &a);
    let b = d.file("B.csv", &b);
    let q = d.file("Q.csv", "10,0,0,0\n0,10,0,0\n0,0,0,0\n0,0,0,0\n");
    let out = run(&["--a", &a, "--b", &b, "--q", &q, "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let k: Vec<f64> = v["gain"][0]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    for (got, book) in k.iter().zip([3.16228, 13.47175, 4.48137, 2.26289]) {
        assert!((got + book).abs() < 5e-6, "{k:?}");
    }
    assert_eq!(v["riccati"].as_array().unwrap().len(), 4);
    let poles = v["closed_loop_poles"].as_array().unwrap();
    assert_eq!(poles.len(), 4);
    assert!(
        poles
            .iter()
            .all(|p| p[0].as_f64().unwrap() < 0.0 && p.as_array().unwrap().len() == 2)
    );
    // Issue acceptance: relative residual ≤ 1e-12 on the book systems.
    assert!(v["residual"].as_f64().unwrap() <= 1e-12);
}

#[test]
fn bad_csv_is_reported_with_position() {
    let d = Dir::new("bad");
    let (a, b) = cdip_csv();
    let good_a = d.file("A.csv", &a);
    let good_b = d.file("B.csv", &b);
    // Non-numeric value: line and column named.
    let bad = d.file("bad.csv", "0,0,1,0\n0,0,0,1\n0,zero,1,0\n0,1,0,0\n");
    let out = run(&["--a", &bad, "--b", &good_b]);
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains("line 3, column 2") && e.contains("bad.csv"),
        "{e}"
    );
    // Ragged rows.
    let ragged = d.file("ragged.csv", "0,0,1,0\n0,0,0\n");
    let out = run(&["--a", &ragged, "--b", &good_b]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("ragged"), "{}", stderr(&out));
    // NaN.
    let nan = d.file("nan.csv", "0,0,1,0\n0,0,0,1\n0,0,NaN,0\n0,1,0,0\n");
    let out = run(&["--a", &nan, "--b", &good_b]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("not finite"), "{}", stderr(&out));
    // Shape mismatch: B with 3 rows for a 4-state A; Q of the wrong size; non-square A.
    let b3 = d.file("B3.csv", "0\n0\n1\n");
    let out = run(&["--a", &good_a, "--b", &b3]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("must have 4 rows"),
        "{}",
        stderr(&out)
    );
    let q2 = d.file("Q2.csv", "1,0\n0,1\n");
    let out = run(&["--a", &good_a, "--b", &good_b, "--q", &q2]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("Q"), "{}", stderr(&out));
    let rect = d.file("rect.csv", "1,2,3\n4,5,6\n");
    let out = run(&["--a", &rect, "--b", &good_b]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("square"), "{}", stderr(&out));
    // Missing file, invalid sample time.
    let out = run(&["--a", "/nonexistent/A.csv", "--b", &good_b]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("cannot read"), "{}", stderr(&out));
    let out = run(&["--a", &good_a, "--b", &good_b, "--discrete=-1"]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("sample time"), "{}", stderr(&out));
    // No panic anywhere: a panic exits with code 101.
    assert_ne!(out.status.code(), Some(101));
}

#[test]
fn discrete_lqr_with_cross_term() {
    // ZOH model of ẋ = −x + u at 0.1 s (A_d = e^{−0.1}, B_d = 1 − e^{−0.1}) with Q = 1,
    // R = 1, N = 0.1: the scalar DARE is checked through its defining equation evaluated
    // here (independently of the solver), the gain formula and |a − bK| < 1.
    let d = Dir::new("disc");
    let a = (-0.1f64).exp();
    let b = 1.0 - a;
    let fa = d.file("A.csv", &format!("{a}\n"));
    let fb = d.file("B.csv", &format!("{b}\n"));
    let fq = d.file("Q.csv", "1\n");
    let fr = d.file("R.csv", "1\n");
    let fnn = d.file("N.csv", "0.1\n");
    let out = run(&[
        "--a",
        &fa,
        "--b",
        &fb,
        "--q",
        &fq,
        "--r",
        &fr,
        "--n",
        &fnn,
        "--discrete",
        "0.1",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let x = v["riccati"][0][0].as_f64().unwrap();
    let k = v["gain"][0][0].as_f64().unwrap();
    // DARE: a²x − x − (axb + n)²/(b²x + r) + q = 0, K = (bxa + n)/(b²x + r).
    let res = a * a * x - x - (a * x * b + 0.1).powi(2) / (b * b * x + 1.0) + 1.0;
    assert!(res.abs() < 1e-12 * x.abs().max(1.0), "residual {res:e}");
    assert!((k - (b * x * a + 0.1) / (b * b * x + 1.0)).abs() < 1e-12);
    assert!((a - b * k).abs() < 1.0);
    let p = &v["closed_loop_poles"][0];
    assert!((p[0].as_f64().unwrap() - (a - b * k)).abs() < 1e-12);
}

#[test]
fn whitespace_semicolon_and_commented_files_read_as_the_csv() {
    // The same cart-pendulum problem as CSV, whitespace (A.txt), tab-, semicolon-separated
    // and with a BOM and comments: every run prints the same JSON (the parser, not the
    // solver, is under test, so the outputs must be identical).
    let d = Dir::new("formats");
    let (a, b) = cdip_csv();
    let q = "10,0,0,0\n0,10,0,0\n0,0,0,0\n0,0,0,0\n";
    let run_with = |tag: &str, conv: &dyn Fn(&str) -> String| {
        let fa = d.file(&format!("A-{tag}.txt"), &conv(&a));
        let fb = d.file(&format!("B-{tag}.txt"), &conv(&b));
        let fq = d.file(&format!("Q-{tag}.txt"), &conv(q));
        let out = run(&["--a", &fa, "--b", &fb, "--q", &fq, "--json"]);
        assert!(out.status.success(), "{tag}: {}", stderr(&out));
        out.stdout
    };
    let csv = run_with("csv", &|t| t.to_string());
    let ws = run_with("ws", &|t| t.replace(',', "  "));
    let tab = run_with("tab", &|t| t.replace(',', "\t"));
    let semi = run_with("semi", &|t| t.replace(',', "; "));
    let bom = run_with("bom", &|t| {
        format!(
            "\u{feff}# exported from a spreadsheet\n{}",
            t.replace('\n', "  # row\n")
        )
    });
    for (tag, other) in [("ws", ws), ("tab", tab), ("semi", semi), ("bom", bom)] {
        assert_eq!(other, csv, "{tag} differs from the CSV run");
    }
    // A mix is an error naming the file and the line.
    let mixed = d.file("mixed.txt", "0 0 1 0\n0,0,0,1\n0 0 -6.25 0\n0 1 0 0\n");
    let fb = d.file("B.csv", &b);
    let out = run(&["--a", &mixed, "--b", &fb]);
    fails_with(&out, &["mixed.txt", "line 2", "separat"]);
    assert_ne!(out.status.code(), Some(101));
}

#[test]
fn indefinite_weights_exit_non_zero_naming_the_smallest_eigenvalue() {
    // Q = diag(10, −1, 0, 0): its smallest eigenvalue is −1 (a diagonal matrix's
    // eigenvalues are its entries) — not a cost; the library's message names it.
    let d = Dir::new("indef");
    let (a, b) = cdip_csv();
    let fa = d.file("A.csv", &a);
    let fb = d.file("B.csv", &b);
    let fq = d.file("Q.csv", "10,0,0,0\n0,-1,0,0\n0,0,0,0\n0,0,0,0\n");
    let out = run(&["--a", &fa, "--b", &fb, "--q", &fq]);
    fails_with(&out, &["Q must be positive semidefinite", "-1e0"]);
    assert!(out.stdout.is_empty());
    // Q ⪰ 0, R ≻ 0 but [Q N; Nᵀ R] indefinite: scalar a = 1, q = r = 1, N = 2 has the joint
    // eigenvalues 1 ± 2, the smallest −1.
    let one = d.file("one.csv", "1\n");
    let two = d.file("two.csv", "2\n");
    let out = run(&[
        "--a", &one, "--b", &one, "--q", &one, "--r", &one, "--n", &two,
    ]);
    fails_with(&out, &["[Q N; Nᵀ R] must be positive semidefinite", "-1e0"]);
    // The same in discrete time.
    let out = run(&[
        "--a",
        &one,
        "--b",
        &one,
        "--q",
        &one,
        "--r",
        &one,
        "--n",
        &two,
        "--discrete",
        "0.1",
    ]);
    fails_with(&out, &["[Q N; Nᵀ R] must be positive semidefinite", "-1e0"]);
}

#[test]
fn imaginary_axis_hamiltonian_exits_with_no_stabilising_solution() {
    // Undamped oscillator ẋ₁ = x₂, ẋ₂ = −x₁ + u with Q = 0: the Hamiltonian
    // [[A, −BBᵀ], [−Q, −Aᵀ]] is block triangular, its eigenvalues those of A and −Aᵀ: ±j,
    // twice — on the imaginary axis. The discrete rotation [[0, 1], [−1, 0]] with Q = 0 puts
    // the symplectic pencil's eigenvalues ±j on the unit circle the same way.
    let d = Dir::new("axis");
    let fa = d.file("A.txt", "0 1\n-1 0\n");
    let fb = d.file("B.txt", "0\n1\n");
    let fq = d.file("Q.txt", "0 0\n0 0\n");
    for extra in [&[][..], &["--discrete", "0.1"][..]] {
        let mut args = vec!["--a", fa.as_str(), "--b", fb.as_str(), "--q", fq.as_str()];
        args.extend_from_slice(extra);
        let out = run(&args);
        fails_with(&out, &["no stabilising solution", "0+1j"]);
        assert!(out.stdout.is_empty());
        assert_ne!(out.status.code(), Some(101));
    }
    // Q = diag(1e-6, 0) observes the oscillator: the stabilising solution exists, its poles
    // the stable roots of 1 + q·G(−s)G(s) = 0 with G(s) = 1/(s² + 1), i.e.
    // (s² + 1)² + 10⁻⁶ = 0, s² = −1 ± 10⁻³j (|Re s| ≈ 5·10⁻⁴). The poles' eigenvalue
    // condition is ≈ 1/(2·5·10⁻⁴) = 10³: 1e-12 allows 10⁴ ulps.
    let fq = d.file("Qsmall.txt", "1e-6 0\n0 0\n");
    let out = run(&["--a", &fa, "--b", &fb, "--q", &fq, "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let s = num_root();
    for p in v["closed_loop_poles"].as_array().unwrap() {
        let (re, im) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
        assert!(
            (re - s.0).abs() < 1e-12 && (im.abs() - s.1).abs() < 1e-12,
            "{p}"
        );
    }
}

/// The root s of s² = −1 + 10⁻³j with Re s < 0, as (Re s, |Im s|), in closed form:
/// s = ±√r (cos(φ/2) + j sin(φ/2)) with r = |−1 + 10⁻³j| and φ its argument.
fn num_root() -> (f64, f64) {
    let (x, y) = (-1.0f64, 1e-3f64);
    let r = (x * x + y * y).sqrt();
    let phi = y.atan2(x);
    let (re, im) = (r.sqrt() * (phi / 2.0).cos(), r.sqrt() * (phi / 2.0).sin());
    if re < 0.0 {
        (re, im.abs())
    } else {
        (-re, im.abs())
    }
}
