//! `pendulab diskmargin` of a square MIMO loop end to end: `--json` equals
//! `pendulab_lti::mu::disk_margin_mimo` called here on the same matrices, number for number
//! (two routes to the library; JSON `null` for ∞ and NaN), the text names the channels and the
//! multi-loop bounds, and bad inputs exit 1 naming the problem. The margins themselves are
//! checked against independent references in lti's `disk_margin_mimo` tests and the Python
//! package's `test_lti_mu.py`.

mod common;
use common::*;

use pendulab_lti::disk_margin::DiskMargin;
use pendulab_lti::linalg::from_rows;
use pendulab_lti::mu::{MimoDiskMargin, disk_margin_mimo};
use pendulab_lti::{Mat, StateSpace, TimeDomain};
use serde_json::Value;

/// `v` as a number, `null` read as `+∞`.
fn num(v: &Value, what: &str) -> f64 {
    if v.is_null() {
        return f64::INFINITY;
    }
    v.as_f64().unwrap_or_else(|| panic!("{what}: {v}"))
}

/// The same number, bit for bit (`null` stands for a non-finite library value).
fn same(v: &Value, want: f64, what: &str) {
    if want.is_finite() {
        assert_eq!(
            num(v, what).to_bits(),
            want.to_bits(),
            "{what}: {v} vs {want}"
        );
    } else {
        assert!(v.is_null(), "{what}: {v} vs {want}");
    }
}

fn same_margin(v: &Value, m: &DiskMargin, what: &str) {
    same(&v["alpha"], m.alpha, what);
    assert_eq!(v["skew"].as_f64().unwrap().to_bits(), m.skew.to_bits());
    same(&v["gain_interval"][0], m.gain_interval.0, what);
    same(&v["gain_interval"][1], m.gain_interval.1, what);
    same(&v["gain_margin_db"], m.gain_margin_db(), what);
    same(&v["phase_margin_deg"], m.phase_margin_deg, what);
    same(&v["frequency"], m.frequency, what);
    assert_eq!(
        v["frequency_infinite"],
        m.frequency == f64::INFINITY,
        "{what}"
    );
    assert_eq!(v["closed_loop_stable"], m.closed_loop_stable, "{what}");
}

fn same_mimo(v: &Value, m: &MimoDiskMargin) {
    let lat = v["loop_at_a_time"].as_array().unwrap();
    assert_eq!(lat.len(), m.loop_at_a_time.len());
    for (i, (j, l)) in lat.iter().zip(&m.loop_at_a_time).enumerate() {
        same_margin(j, l, &format!("channel {i}"));
    }
    same_margin(&v["multi_loop"], &m.multi_loop, "multi-loop");
    same(
        &v["multi_loop_alpha_bounds"][0],
        m.multi_loop_alpha_bounds.0,
        "α lower",
    );
    same(
        &v["multi_loop_alpha_bounds"][1],
        m.multi_loop_alpha_bounds.1,
        "α upper",
    );
    same(&v["mu_peak"]["lower"], m.mu_peak.lower, "μ lower");
    same(&v["mu_peak"]["upper"], m.mu_peak.upper, "μ upper");
    let d: Vec<f64> = v["mu_peak"]["d_scaling"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(d, m.mu_peak.d_scaling);
    same(&v["peak_frequency"], m.peak_frequency, "peak frequency");
    assert_eq!(v["closed_loop_stable"], m.multi_loop.closed_loop_stable);
}

fn mat(rows: &[&[f64]]) -> Mat {
    from_rows(rows).unwrap()
}

/// The inline matrices of the CLI and the library's system, from the same rows.
struct Loop<'a> {
    a: &'a str,
    b: &'a str,
    c: &'a str,
    d: &'a str,
}

impl Loop<'_> {
    fn run(&self, extra: &[&str]) -> std::process::Output {
        let mut args = vec![
            "diskmargin",
            "--a",
            self.a,
            "--b",
            self.b,
            "--c",
            self.c,
            "--d",
            self.d,
        ];
        args.extend_from_slice(extra);
        pendulab(&args)
    }
}

fn check<D: TimeDomain>(l: &Loop<'_>, sys: &StateSpace<D>, skew: f64, extra: &[&str]) -> Value {
    let s = skew.to_string();
    let mut args = vec!["--skew", s.as_str(), "--json"];
    args.extend_from_slice(extra);
    let v = json(&l.run(&args));
    same_mimo(&v, &disk_margin_mimo(sys, skew).unwrap());
    v
}

/// Doyle's spinning satellite with `K = I` (`a = 10`; Skogestad & Postlethwaite §3.7.1).
const SATELLITE: Loop<'static> = Loop {
    a: "0 10; -10 0",
    b: "1 0; 0 1",
    c: "1 10; -10 1",
    d: "0 0; 0 0",
};

fn satellite() -> StateSpace<pendulab_lti::Continuous> {
    StateSpace::continuous(
        mat(&[&[0.0, 10.0], &[-10.0, 0.0]]),
        Mat::identity(2, 2),
        mat(&[&[1.0, 10.0], &[-10.0, 1.0]]),
        Mat::zeros(2, 2),
    )
    .unwrap()
}

#[test]
fn satellite_json_equals_the_library() {
    for skew in [0.0, 0.5, -0.5] {
        let v = check(&SATELLITE, &satellite(), skew, &[]);
        // The coupled loop is fragile: a multi-loop α far below each channel's.
        let multi = num(&v["multi_loop"]["alpha"], "α");
        assert!(multi < 0.2, "{v}");
    }
}

#[test]
fn a_discrete_coupled_loop_equals_the_library() {
    let l = Loop {
        a: "0.5 0.1; 0 0.3",
        b: "1 0.2; 0 1",
        c: "0.4 0; 0.3 0.6",
        d: "0.1 0; 0 0",
    };
    let sys = StateSpace::discrete(
        mat(&[&[0.5, 0.1], &[0.0, 0.3]]),
        mat(&[&[1.0, 0.2], &[0.0, 1.0]]),
        mat(&[&[0.4, 0.0], &[0.3, 0.6]]),
        mat(&[&[0.1, 0.0], &[0.0, 0.0]]),
        0.01,
    )
    .unwrap();
    check(&l, &sys, 0.0, &["--dt", "0.01"]);
}

#[test]
fn an_unstable_closed_loop_reports_zero_margins() {
    // L = −2 I/(s + 1): det(I + L) has a zero at s = 1.
    let l = Loop {
        a: "-1 0; 0 -1",
        b: "1 0; 0 1",
        c: "-2 0; 0 -2",
        d: "0 0; 0 0",
    };
    let sys = StateSpace::continuous(
        -Mat::identity(2, 2),
        Mat::identity(2, 2),
        Mat::identity(2, 2) * -2.0,
        Mat::zeros(2, 2),
    )
    .unwrap();
    let v = check(&l, &sys, 0.0, &[]);
    assert_eq!(v["closed_loop_stable"], false);
    assert_eq!(v["multi_loop"]["alpha"], 0.0);
    assert!(v["peak_frequency"].is_null());
    let out = l.run(&[]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(String::from_utf8_lossy(&out.stdout).contains("unstable"));
}

#[test]
fn text_names_each_channel_and_the_multi_loop_bounds() {
    let out = SATELLITE.run(&[]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in ["channel 0", "channel 1", "multi-loop", "1/μ upper"] {
        assert!(text.contains(needle), "{needle:?} missing: {text}");
    }
}

#[test]
fn bad_inputs_exit_1_naming_the_problem() {
    // Two outputs, one input: not a square loop.
    let out = pendulab(&[
        "diskmargin",
        "--a",
        "-1 0; 0 -2",
        "--b",
        "1; 1",
        "--c",
        "1 0; 0 1",
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    fails_with(&out, &["disk_margin_mimo", "must be square", "2x1"]);
    let out = SATELLITE.run(&["--skew", "nan", "--json"]);
    assert_eq!(out.status.code(), Some(1));
    fails_with(&out, &["skew must be finite"]);
    // I + D singular: the loop is ill-posed.
    let out = Loop {
        a: "-1 0; 0 -1",
        b: "1 0; 0 1",
        c: "1 0; 0 1",
        d: "-1 0; 0 -1",
    }
    .run(&["--json"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(!stderr(&out).is_empty());
}
