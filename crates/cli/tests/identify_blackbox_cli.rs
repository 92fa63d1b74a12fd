//! `pendulab identify arx|moesp` end to end: on the shipped cart record the reported fits equal
//! the library's on the same windows (two routes: the binary and `pendulab_ident` called
//! here), the physical model's fit is the library's `cart-ls` + `validate_drive`; on a
//! simulated first-order system ARX recovers the known coefficients and MOESP the known pole;
//! bad inputs exit 1 naming the problem; `--save` writes a system file `pendulab eig` reads.

mod common;
use common::*;
use pendulab_testkit::json::vector;

use pendulab_ident::{
    ArxOrders, Dataset, Differentiator, Experiment, FilterHold, IoRecord, LsOptions, MoespOptions,
    Prefilter, arx, arx_order_selection, cart_drive_ls, moesp, validate_drive,
};
use serde_json::Value;

fn rig(name: &str) -> String {
    format!("{}/../../data/rig/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn identify(args: &[&str]) -> Value {
    let mut a = vec!["identify"];
    a.extend_from_slice(args);
    json(&pendulab(&a))
}

/// `(v, z)` of the cart record on `[t0, t1]`, every `q`-th sample.
fn cart(t0: f64, t1: f64, q: usize) -> (Vec<f64>, Vec<f64>) {
    let f = rig("cdip_least_square_data.csv");
    let d = Dataset::from_csv_str(&f, &std::fs::read_to_string(&f).unwrap())
        .unwrap()
        .window(Some(t0), Some(t1))
        .unwrap();
    let every = |x: &[f64]| x.iter().step_by(q).copied().collect::<Vec<f64>>();
    (every(d.column("v").unwrap()), every(d.column("z").unwrap()))
}

#[test]
fn arx_on_the_cart_record_equals_the_library() {
    let f = rig("cdip_least_square_data.csv");
    let v = identify(&[
        "arx",
        "--data",
        &f,
        "--input",
        "v",
        "--output",
        "z",
        "--na",
        "2",
        "--nb",
        "2",
        "--nk",
        "1",
        "--decimate",
        "10",
        "--window",
        "0.5:5",
        "--validate",
        "0.5:9",
        "--json",
    ]);
    let (ue, ye) = cart(0.5, 5.0, 10);
    let (uv, yv) = cart(0.5, 9.0, 10);
    let m = arx(&[Experiment::new(&ue, &ye)], 0.01, ArxOrders::new(2, 2, 1)).unwrap();
    assert_eq!(vector(&v["model"]["a"]), m.a);
    assert_eq!(vector(&v["model"]["b"]), m.b);
    let fit = m.fit_percent(&uv, &yv).unwrap();
    assert_eq!(v["fit"]["percent"].as_f64().unwrap(), fit);
    assert_eq!(v["dt"].as_f64().unwrap(), 0.01);
    // The physical least squares beside it: cart-ls's defaults (causal T_f = 0.075 ZOH
    // prefilter, three-point derivatives) on the estimation window, simulated on the
    // validation window.
    let (uf, yf) = cart(0.5, 5.0, 1);
    let (uvf, yvf) = cart(0.5, 9.0, 1);
    let opts = LsOptions {
        differentiator: Differentiator::ThreePoint,
        prefilter: Prefilter::Causal {
            tf: 0.075,
            hold: FilterHold::Zoh,
        },
    };
    let d = cart_drive_ls(1e-3, &yf, &uf, &opts).unwrap();
    let val = validate_drive(1e-3, &yvf, &uvf, d.a, d.b, "z").unwrap();
    let p = &v["physical"];
    assert_eq!(p["ac"].as_f64().unwrap(), d.a);
    assert_eq!(p["bc"].as_f64().unwrap(), d.b);
    assert_eq!(p["fit_percent"].as_f64().unwrap(), val.fit_percent);
}

#[test]
fn arx_order_selection_reports_the_aic_table() {
    let f = rig("cdip_least_square_data.csv");
    let v = identify(&[
        "arx",
        "--data",
        &f,
        "--max-order",
        "3",
        "--decimate",
        "10",
        "--window",
        "0.5:5",
        "--json",
    ]);
    let (ue, ye) = cart(0.5, 5.0, 10);
    let s = arx_order_selection(&[Experiment::new(&ue, &ye)], 0.01, 1..=3, 1..=3, 1..=1).unwrap();
    let table = v["order_selection"].as_array().unwrap();
    assert_eq!(table.len(), 9);
    for (row, c) in table.iter().zip(&s.candidates) {
        assert_eq!(row["aic"].as_f64().unwrap(), c.aic);
    }
    // The model reported is the table's least AIC.
    let best = table
        .iter()
        .min_by(|a, b| {
            a["aic"]
                .as_f64()
                .unwrap()
                .total_cmp(&b["aic"].as_f64().unwrap())
        })
        .unwrap();
    assert_eq!(best["na"], v["model"]["na"]);
    assert_eq!(best["nb"], v["model"]["nb"]);
    // Without --validate the validation window is the estimation window.
    assert_eq!(v["validation_window"], v["window"]);
    let fit = s.model.fit_percent(&ue, &ye).unwrap();
    assert_eq!(v["fit"]["percent"].as_f64().unwrap(), fit);
}

#[test]
fn moesp_on_the_cart_record_equals_the_library_and_saves_a_system() {
    let f = rig("cdip_least_square_data.csv");
    let dir = Dir::new("moesp");
    let sys = dir.path("cart.toml");
    let v = identify(&[
        "moesp",
        "--data",
        &f,
        "--horizon",
        "20",
        "--order",
        "2",
        "--window",
        "0.5:5",
        "--validate",
        "0.5:9",
        "--save",
        &sys,
        "--json",
    ]);
    let (ue, ye) = cart(0.5, 5.0, 1);
    let (uv, yv) = cart(0.5, 9.0, 1);
    let s = moesp(
        &[IoRecord::siso(&ue, &ye)],
        1e-3,
        MoespOptions {
            horizon: 20,
            order: Some(2),
            max_order: None,
        },
    )
    .unwrap();
    let fit = s.fit_percent(&IoRecord::siso(&uv, &yv)).unwrap()[0];
    assert_eq!(v["fit"]["percent"].as_f64().unwrap(), fit);
    assert_eq!(v["model"]["order"], 2);
    assert_eq!(vector(&v["model"]["singular_values"]), s.singular_values);
    assert!(v["physical"]["fit_percent"].as_f64().is_some());
    // The saved file is the model `pendulab eig` reads: its poles are the reported ones.
    let e = json(&pendulab(&["eig", &sys, "--json"]));
    assert_eq!(e["dt"].as_f64().unwrap(), 1e-3);
    let mut got: Vec<f64> = e["poles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["pole"][0].as_f64().unwrap())
        .collect();
    let mut want: Vec<f64> = v["model"]["poles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p[0].as_f64().unwrap())
        .collect();
    got.sort_by(f64::total_cmp);
    want.sort_by(f64::total_cmp);
    for (g, w) in got.iter().zip(&want) {
        assert!((g - w).abs() < 1e-12, "{got:?} vs {want:?}");
    }
}

/// `y(k+1) = a y(k) + b u(k)` on a deterministic ±1 input (a maximal-length-like LCG sign
/// sequence), written as CSV `t, u, y` at `ts = 0.01 s`.
fn first_order_csv(a: f64, b: f64, n: usize) -> String {
    let mut s = String::from("t,u,y\n");
    let (mut y, mut state) = (0.0f64, 12345u64);
    for k in 0..n {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let u = if state >> 63 == 1 { 1.0 } else { -1.0 };
        s.push_str(&format!("{},{u},{y}\n", k as f64 * 0.01));
        y = a * y + b * u;
    }
    s
}

#[test]
fn a_simulated_first_order_system_is_recovered() {
    let (a, b) = (0.9, 0.5);
    let dir = Dir::new("first-order");
    let f = dir.file("fo.csv", &first_order_csv(a, b, 600));
    // Noise-free ARX [1 1 1]: A = 1 − a q⁻¹, B = b q⁻¹ exactly (the regression's residual is 0).
    let v = identify(&[
        "arx", "--data", &f, "--input", "u", "--output", "y", "--na", "1", "--nb", "1", "--json",
    ]);
    let (am, bm) = (vector(&v["model"]["a"]), vector(&v["model"]["b"]));
    assert!((am[1] + a).abs() < 1e-10, "{am:?}");
    assert!((bm[0] - b).abs() < 1e-10, "{bm:?}");
    assert!((v["fit"]["percent"].as_f64().unwrap() - 100.0).abs() < 1e-6);
    assert!(v["physical"].is_null());
    // MOESP's order from the singular values is 1 and its pole is a.
    let v = identify(&[
        "moesp",
        "--data",
        &f,
        "--input",
        "u",
        "--output",
        "y",
        "--max-order",
        "4",
        "--json",
    ]);
    assert_eq!(v["model"]["order"], 1);
    let p = v["model"]["poles"].as_array().unwrap();
    assert_eq!(p.len(), 1);
    assert!((p[0][0].as_f64().unwrap() - a).abs() < 1e-8, "{p:?}");
    assert!((v["fit"]["percent"].as_f64().unwrap() - 100.0).abs() < 1e-5);
}

#[test]
fn bad_inputs_exit_1_naming_the_problem() {
    let f = rig("cdip_least_square_data.csv");
    let run = |args: &[&str]| {
        let mut a = vec!["identify"];
        a.extend_from_slice(args);
        pendulab(&a)
    };
    let code = |o: &std::process::Output| o.status.code();
    let o = run(&["arx", "--data", &f, "--input", "w"]);
    fails_with(&o, &["no column 'w'"]);
    assert_eq!(code(&o), Some(1));
    let o = run(&["moesp", "--data", &f, "--window", "0:100"]);
    fails_with(&o, &["not inside the data"]);
    assert_eq!(code(&o), Some(1));
    let o = run(&["arx", "--data", &f, "--na", "0"]);
    fails_with(&o, &["--na must be at least 1"]);
    assert_eq!(code(&o), Some(1));
    let o = run(&[
        "arx", "--data", &f, "--window", "0.5:0.52", "--na", "30", "--nb", "30",
    ]);
    fails_with(&o, &["ARX(30, 30, 1)", "needs at least"]);
    let o = run(&["moesp", "--data", &f, "--order", "30"]);
    fails_with(&o, &["MOESP order", "1..=9"]);
    let o = run(&[
        "moesp",
        "--data",
        &f,
        "--window",
        "0.5:0.6",
        "--horizon",
        "40",
    ]);
    fails_with(&o, &["horizon 40", "needs at least"]);
    let dir = Dir::new("bad");
    let nan = dir.file("nan.csv", "t,v,z\n0,1,2\n0.01,nan,3\n0.02,1,2\n");
    let o = run(&["arx", "--data", &nan]);
    fails_with(&o, &["column 'v'", "not finite"]);
    assert_eq!(code(&o), Some(1));
    // The physical methods refuse the black-box flags, and the other way round.
    fails_with(&run(&["cart-ls", "--data", &f, "--na", "2"]), &["--na"]);
    fails_with(
        &run(&["arx", "--data", &f, "--horizon", "5"]),
        &["--horizon"],
    );
}
