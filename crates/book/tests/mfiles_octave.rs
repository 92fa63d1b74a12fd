//! The book's M-files that need neither Simulink nor YALMIP, run unchanged in GNU Octave 7.3.0
//! (`tools/reference/book_mfiles_octave.sh`; their display committed in `data/octave/`), against
//! the examples that follow them. Values Octave displays in `format long g` (16 significant
//! digits) are compared to 1e-12 relative; values the M-files print with `fprintf` (`%5.2e`,
//! `%5.3e`) or as a transfer function (four significant digits), to half a unit of the last
//! printed digit.

mod common;
use common::*;
use pendulab_book::ExampleOutput;

/// The `name = value` pairs of an Octave display (several per line when separated by tabs; the
/// name's spaces dropped, so `T 1` is `T1`).
fn displayed(text: &str) -> Vec<(String, f64)> {
    text.lines()
        .flat_map(|l| l.split('\t'))
        .filter_map(|item| {
            let (name, value) = item.split_once(" = ")?;
            let v: f64 = value.trim().parse().ok()?;
            Some((name.replace(' ', ""), v))
        })
        .collect()
}

fn get(d: &[(String, f64)], name: &str) -> f64 {
    d.iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("{name} is not displayed"))
        .1
}

/// The displayed second-order `tf`: `(numerator, [1, a, b])` from the lines `num` and
/// `s^2 + a s + b`.
fn displayed_tf(text: &str) -> (f64, Vec<f64>) {
    let lines: Vec<&str> = text.lines().collect();
    let k = lines.iter().position(|l| l.contains("s^2 +")).unwrap();
    let den: Vec<f64> = lines[k]
        .split_whitespace()
        .filter_map(|w| w.parse().ok())
        .collect();
    let num: f64 = lines[k - 2].trim().parse().unwrap();
    (num, vec![1.0, den[0], den[1]])
}

/// `|x − want| ≤` half a unit of the last of `digits` significant digits of `want`.
fn printed(x: f64, want: f64, digits: i32, what: &str) {
    let unit = 10f64.powi(want.abs().log10().floor() as i32 - (digits - 1));
    assert!(
        (x - want).abs() <= 0.5 * unit * (1.0 + 1e-9),
        "{what}: {x} vs the displayed {want}"
    );
}

fn long(x: f64, want: f64, what: &str) {
    assert!(
        (x - want).abs() <= 1e-12 * want.abs(),
        "{what}: {x} vs Octave's {want}"
    );
}

#[test]
fn p1c221_cartident_as_octave_runs_it() {
    // cartident.m on the closed-form response of cart_model.slx (the script's driver), then
    // p1c221_id_cart.m lines 66-77.
    let d = displayed(include_str!("data/octave/p1c221_cartident_run.txt"));
    let out = run("p1c221_id_cart");
    for i in 1..=4 {
        for name in [format!("K{i}"), format!("T{i}")] {
            long(num(&out, &name), get(&d, &name), &name);
        }
    }
    for name in ["Kave", "Tave", "a", "b"] {
        long(num(&out, name), get(&d, name), name);
    }
}

/// A peak-time identification (`p1c321_cdip_id_cart.m`, `p1c332_adip_id_arm.m`): the values
/// it prints with `fprintf('%5.2e')` under its labels (`ours`, `theirs`), and the displayed
/// `sysGyr` to four significant digits.
fn peak_feature_as_displayed(id: &str, text: &str, names: [(&str, &str); 8]) -> ExampleOutput {
    let d = displayed(text);
    let out = run(id);
    for (ours, theirs) in names {
        printed(num(&out, ours), get(&d, theirs), 3, ours);
    }
    let (n, den) = displayed_tf(text);
    printed(vector(&out, "sysGyr_num")[0], n, 4, "sysGyr_num");
    let ours = vector(&out, "sysGyr_den");
    for i in 1..3 {
        printed(ours[i], den[i], 4, "sysGyr_den");
    }
    out
}

#[test]
fn p1c321_cdip_id_cart_as_octave_runs_it() {
    // Lines 59-71.
    peak_feature_as_displayed(
        "p1c321_cdip_id_cart",
        include_str!("data/octave/p1c321_cdip_id_cart.txt"),
        [
            ("Tp", "Tp"),
            ("Amax", "Amax"),
            ("gamma", "gamma_c"),
            ("delta", "delta_c"),
            ("omega_n", "omega_nc"),
            ("zeta", "zeta_c"),
            ("ac", "ac"),
            ("bc", "bc"),
        ],
    );
}

#[test]
fn p1c321_cdip_id_pend_as_octave_runs_it() {
    let d = displayed(include_str!("data/octave/p1c321_cdip_id_pend.txt"));
    let out = run("p1c321_cdip_id_pend");
    long(num(&out, "period"), get(&d, "T_average"), "T_average");
    long(
        num(&out, "decay_ratio"),
        get(&d, "lambda_average"),
        "lambda_average",
    );
    printed(num(&out, "Jp"), get(&d, "Jp"), 3, "Jp");
    printed(num(&out, "mup"), get(&d, "mup"), 3, "mup");
}

#[test]
fn p1c332_adip_id_arm_as_octave_runs_it() {
    // Lines 63-75.
    let out = peak_feature_as_displayed(
        "p1c332_adip_id_arm",
        include_str!("data/octave/p1c332_adip_id_arm.txt"),
        [
            ("Tp", "Tp"),
            ("Amax", "Amax"),
            ("gamma", "gamma_1"),
            ("delta", "delta_1"),
            ("zeta", "zeta_1"),
            ("omega_n", "omega_n1"),
            ("a1", "a1"),
            ("b1", "b1"),
        ],
    );
    // The example's references are the same display: reproduced.
    references_reproduced(&out);
}

#[test]
fn p1c332_adip_id_pend_as_octave_runs_it() {
    let d = displayed(include_str!("data/octave/p1c332_adip_id_pend.txt"));
    let out = run("p1c332_adip_id_pend");
    long(num(&out, "T_average"), get(&d, "T_average"), "T_average");
    long(
        num(&out, "lambda_average"),
        get(&d, "lambda_average"),
        "lambda_average",
    );
    let (t, lambda) = (vector(&out, "T"), vector(&out, "lambda"));
    assert_eq!(t.len(), 14);
    for i in 0..14 {
        printed(t[i], get(&d, &format!("T{}", i + 1)), 4, "T(i)");
        printed(
            lambda[i],
            get(&d, &format!("lambda{}", i + 1)),
            4,
            "lambda(i)",
        );
    }
    for (ours, theirs) in [
        ("gamma", "gamma_2"),
        ("delta", "delta_2"),
        ("zeta", "zeta_2"),
        ("omega_n", "omega_n2"),
        ("J2", "J2"),
        ("mu2", "mu2"),
    ] {
        printed(num(&out, ours), get(&d, theirs), 3, ours);
    }
    references_reproduced(&out);
}

/// The examples whose references are the Octave displays of their M-files: every displayed
/// number compared is reproduced to the digits the M-file prints, and the example names the
/// M-file lines it follows (each reference's source cites the M-file and its line).
fn octave_badge(id: &str, stem: &str, names: &[&str]) {
    let out = run(id);
    for name in names {
        let r: Vec<_> = out
            .references
            .iter()
            .filter(|r| r.name == *name && r.source.contains("GNU Octave"))
            .collect();
        assert!(!r.is_empty(), "{id}: {name} is not compared with Octave");
        assert!(
            r.iter()
                .all(|r| r.source.starts_with(&format!("{stem}.m line")))
        );
    }
    all_reproduced(&out);
    assert!(
        out.notes
            .iter()
            .any(|n| n.starts_with(&format!("{stem}.m displays "))),
        "{id}: no note of what the M-file displays"
    );
}

#[test]
fn p1c321_badges_are_the_octave_displays() {
    // p1c321_cdip_id_cart.m lines 59-71; p1c321_cdip_id_pend.m lines 99-100, 148-166.
    octave_badge(
        "p1c321_cdip_id_cart",
        "p1c321_cdip_id_cart",
        &[
            "Tp",
            "Amax",
            "gamma",
            "delta",
            "omega_n",
            "zeta",
            "ac",
            "bc",
            "sysGyr_num",
            "sysGyr_den",
        ],
    );
    octave_badge(
        "p1c321_cdip_id_pend",
        "p1c321_cdip_id_pend",
        &[
            "T_average",
            "lambda_average",
            "T",
            "lambda",
            "gamma",
            "delta",
            "omega_n",
            "zeta",
            "mp",
            "lp",
            "g",
            "Jp",
            "mup",
        ],
    );
    // The per-period vectors are the M-file's 13 periods.
    assert_eq!(vector(&run("p1c321_cdip_id_pend"), "T").len(), 13);
}

#[test]
fn p1c63_p1c522_p1c74_badges_are_the_octave_displays() {
    // p1c63_ex5_cdip_lqr_servo.m lines 51-54 (Kt = -lqr(...), K1, K2).
    octave_badge(
        "p1c63_ex5_cdip_lqr_servo",
        "p1c63_ex5_cdip_lqr_servo",
        &["K1", "K2"],
    );
    // p1c522_ex7_adip_place.m line 20 (K = -place(A, B, s)).
    octave_badge("p1c522_ex7_adip_place", "p1c522_ex7_adip_place", &["K"]);
    // p1c74_ex1_cdip_ob_design.m lines 32-46.
    octave_badge(
        "p1c74_ex1_cdip_ob_design",
        "p1c74_ex1_cdip_ob_design",
        &["rank_Mc", "K", "rank_Mo", "Cc"],
    );
    // L is not compared with Octave's (another placing L: SLICOT, not MATLAB's KNV), and the
    // example says so; its poles are the book's 4 pc (tests/p1c7.rs).
    let out = run("p1c74_ex1_cdip_ob_design");
    assert!(
        out.notes
            .iter()
            .any(|n| n.contains("Not compared: L, and Ac, Bc"))
    );
}

#[test]
fn p1c511_ex4_det_mcn_is_the_octave_display_of_its_numeric_part() {
    // p1c511_ex4_cdip.m line 100 (det_Mcn = det(ctrb(A, B)) of the 1.2-times pendulum), from
    // its numeric part (lines 48 on) run in Octave; the symbolic lines before it are named.
    octave_badge("p1c511_ex4_cdip", "p1c511_ex4_cdip", &["det_Mcn"]);
    let out = run("p1c511_ex4_cdip");
    assert!(out.uncompared.is_empty(), "{:?}", out.uncompared);
}

/// The symbolic M-files (Symbolic Math Toolbox) and the example that runs each: every one says
/// what the M-file derives and how pendulab checks the same equations.
const SYMBOLIC: [(&str, &str); 8] = [
    ("p1c311_cdip_lagrange", "p1c311_cdip_lagrange"),
    ("p1c511_ex2", "p1c511_ex2"),
    ("p1c511_ex3_adip", "p1c511_ex3_adip"),
    ("p1c511_ex4_cdip", "p1c511_ex4_cdip"),
    ("p1c522_ex6", "p1c522_ex6"),
    ("p1c74_ex1_cdip_Mc", "p1c74_ex1_cdip_ob_design"),
    ("p1c74_ex2_cdip_Mo", "p1c74_ex2_cdip_Mo"),
    (
        "p1c75_ex3_cdip_detectability",
        "p1c75_ex3_cdip_detectability",
    ),
];

#[test]
fn symbolic_mfiles_say_what_they_derive_and_how_pendulab_checks_it() {
    for (stem, id) in SYMBOLIC {
        // The stem is an example id or an alias of the example.
        assert_eq!(pendulab_book::find(stem).unwrap().id, id, "{stem}");
        let out = run(id);
        let note = out
            .notes
            .iter()
            .find(|n| {
                n.starts_with(&format!(
                    "{stem}.m is symbolic (Symbolic Math Toolbox): it derives "
                ))
            })
            .unwrap_or_else(|| panic!("{id}: no note on the symbolic {stem}.m: {:?}", out.notes));
        assert!(
            note.contains("pendulab checks the same equations "),
            "{note}"
        );
        // Each compares something, and what it compares is reproduced.
        assert!(
            !out.references.is_empty()
                || stem == "p1c311_cdip_lagrange"
                || stem == "p1c511_ex3_adip",
            "{id}"
        );
        all_reproduced(&out);
    }
    // p1c511_ex2: the M-file's symbolic M_c does not depend on a: the exact integer matrix.
    let out = run("p1c511_ex2");
    assert!(
        out.references
            .iter()
            .any(|r| r.name == "Mc" && r.tolerance == 0.0)
    );
    // p1c522_ex6: K from the canonical form is the M-file's solve() result k1 = s1 s2 − 1,
    // k2 = s1 + s2 − s1 s2 − 1 at s1 = −1, s2 = −2: [1, −6].
    assert_eq!(vector(&run("p1c522_ex6"), "K").len(), 2);
    assert!(run("p1c522_ex6").references.iter().any(|r| r.name == "K"));
}
