//! `pendulab estimate` end to end on the book's cart log (`data/rig/cdip_least_square_data.csv`):
//! the filter's velocity integrates back to the logged cart position, the filter and the rig's
//! pseudo-differentiator agree to within a fraction of the signal, the EKF and the UKF agree,
//! and a log without the voltage column is refused naming it.

mod common;
use common::*;

fn rig(name: &str) -> String {
    format!("{}/../../data/rig/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn read_csv(path: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let names = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (names, rows)
}

#[test]
fn ekf_on_the_cart_log() {
    let dir = Dir::new("estimate");
    let (fig, csv) = (dir.path("ekf.svg"), dir.path("ekf.csv"));
    let log = rig("cdip_least_square_data.csv");
    let ekf = json(&pendulab(&[
        "estimate", "--log", &log, "--method", "ekf", "--out", &fig, "--csv", &csv, "--json",
    ]));
    assert_eq!(ekf["samples"], 8967);
    assert_eq!(ekf["sample_time"], 0.001);
    assert!(std::fs::read_to_string(&fig).unwrap().contains("<svg"));
    // The estimated ż, integrated by the trapezoidal rule, stays within 2 mm of the logged z
    // (the log swings the cart over ~0.2 m).
    let (names, rows) = read_csv(&csv);
    assert_eq!(
        names,
        ["t", "z", "theta", "dz", "dtheta", "dz_pd", "dtheta_pd"]
    );
    let (_, logged) = read_csv(&log);
    let mut z = logged[0][1];
    let mut worst: f64 = 0.0;
    for k in 1..rows.len() {
        z += 0.5 * (rows[k][0] - rows[k - 1][0]) * (rows[k][3] + rows[k - 1][3]);
        worst = worst.max((z - logged[k][1]).abs());
    }
    assert!(worst < 2e-3, "{worst}");
    // Filter and pseudo-differentiator: the same signal up to the latter's 20 ms lag.
    for i in 0..2 {
        let (d, v) = (
            ekf["rms_difference"][i].as_f64().unwrap(),
            ekf["rms_velocity"][i].as_f64().unwrap(),
        );
        assert!(d < 0.2 * v, "{d} vs {v}");
    }
    let ukf = json(&pendulab(&[
        "estimate", "--log", &log, "--method", "ukf", "--out", &fig, "--json",
    ]));
    for i in 0..2 {
        let (a, b) = (
            ekf["rms_velocity"][i].as_f64().unwrap(),
            ukf["rms_velocity"][i].as_f64().unwrap(),
        );
        assert!((a - b).abs() < 1e-3 * a, "{a} vs {b}");
    }
}

#[test]
fn a_log_without_the_voltage_is_refused() {
    let dir = Dir::new("estimate-bad");
    let bad = dir.file("no_v.csv", "t,z,phi\n0.0,0,0\n0.001,0,0\n0.002,0,0\n");
    let out = pendulab(&["estimate", "--log", &bad, "--out", &dir.path("f.svg")]);
    fails_with(&out, &["no column v"]);
}
