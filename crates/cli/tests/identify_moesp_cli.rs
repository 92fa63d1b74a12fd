//! `pendulab identify moesp --max-order n`: the CLI passes the cap to the library
//! (`MoespOptions::max_order`) instead of choosing the order itself, so its `--json` equals
//! `pendulab_ident::moesp` called here on the same CSV columns, number for number. The record
//! is a noise-free third-order system whose weak third mode makes `σ₂/σ₃` the largest gap
//! below 3: capped at 2 the order is 2, uncapped 3.

mod common;
use common::*;
use pendulab_testkit::json::vector;

use pendulab_ident::{Dataset, IoRecord, MoespOptions, moesp};

/// `x_i(k+1) = p_i x_i(k) + b_i u(k)`, `y = Σ x_i + 0.2 u` on a deterministic ±1 input (an
/// LCG's sign bit), as CSV `t, u, y` at 0.01 s.
fn third_order_csv(n: usize) -> String {
    let (p, b) = ([0.9, 0.7, -0.6], [0.5, -0.8, 0.05]);
    let mut s = String::from("t,u,y\n");
    let (mut x, mut state) = ([0.0f64; 3], 12345u64);
    for k in 0..n {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let u = if state >> 63 == 1 { 1.0 } else { -1.0 };
        let y = x.iter().sum::<f64>() + 0.2 * u;
        s.push_str(&format!("{},{u},{y}\n", k as f64 * 0.01));
        for i in 0..3 {
            x[i] = p[i] * x[i] + b[i] * u;
        }
    }
    s
}

#[test]
fn max_order_is_the_librarys_cap() {
    let dir = Dir::new("moesp-max-order");
    let text = third_order_csv(400);
    let f = dir.file("third.csv", &text);
    let d = Dataset::from_csv_str(&f, &text).unwrap();
    let (u, y) = (d.column("u").unwrap(), d.column("y").unwrap());
    let ts = d.uniform_step().unwrap();
    for cap in [None, Some(2), Some(1)] {
        let mut args = vec![
            "identify",
            "moesp",
            "--data",
            &f,
            "--input",
            "u",
            "--output",
            "y",
            "--horizon",
            "8",
            "--json",
        ];
        let c = cap.map(|n: usize| n.to_string());
        if let Some(c) = &c {
            args.extend(["--max-order", c.as_str()]);
        }
        let v = json(&pendulab(&args));
        let opts = MoespOptions {
            horizon: 8,
            order: None,
            max_order: cap,
        };
        let s = moesp(&[IoRecord::siso(u, y)], ts, opts).unwrap();
        assert_eq!(v["model"]["order"], s.order);
        assert_eq!(v["model"]["max_order"], serde_json::json!(cap));
        assert_eq!(vector(&v["model"]["singular_values"]), s.singular_values);
        let a: Vec<Vec<f64>> = v["model"]["a"]
            .as_array()
            .unwrap()
            .iter()
            .map(vector)
            .collect();
        let want: Vec<Vec<f64>> = (0..s.order)
            .map(|i| s.model.a().row(i).iter().copied().collect())
            .collect();
        assert_eq!(a, want);
        let fit = s.fit_percent(&IoRecord::siso(u, y)).unwrap()[0];
        assert_eq!(v["fit"]["percent"].as_f64().unwrap(), fit);
        assert_eq!(s.order, cap.unwrap_or(3), "{:?}", s.singular_values);
    }
    // --order and --max-order together are refused before the library is called.
    let out = pendulab(&[
        "identify",
        "moesp",
        "--data",
        &f,
        "--input",
        "u",
        "--output",
        "y",
        "--order",
        "2",
        "--max-order",
        "2",
        "--json",
    ]);
    fails_with(&out, &["--order or --max-order"]);
}
