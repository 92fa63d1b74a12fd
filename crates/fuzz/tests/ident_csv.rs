//! Fuzz target `ident_csv`: the identification CSV reader
//! `pendulab_ident::Dataset::from_csv_str` and what the CLI calls on its result (the time
//! column's step and unit checks, `Dataset::window`), on the heads of the rig recordings in
//! `data/rig/` and on small hand-written files, mutated as bytes and with tokens.
//!
//! Property: nothing panics; a data set that loads has unique non-empty column names, equal
//! column lengths and only finite values; a sample time that is returned is finite and
//! positive; a window that is returned has at least two samples, no more than the data, and
//! only times within the requested bounds (to a step); every error prints a non-empty message.

use pendulab_fuzz::{TEXT_TOKENS, Target, cases, mutate, mutations};
use pendulab_ident::Dataset;
use proptest::prelude::*;

const TARGET: Target = Target {
    name: "ident_csv",
    extension: "csv",
};

/// The first `lines` lines of a recording in `data/rig/`.
fn head(name: &str, lines: usize) -> String {
    let path = format!("{}/../../data/rig/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    text.lines().take(lines).map(|l| format!("{l}\n")).collect()
}

fn seeds() -> Vec<String> {
    vec![
        head("cdip_least_square_data.csv", 40),
        head("adip_least_square_data.csv", 40),
        head("cdip_pend_data.csv", 30),
        head("cdip_cart_pcont_data_kP_100_ref_02.csv", 30),
        "t_ms,z,v\n0,0.0,1.0\n1,0.001,1.0\n2,0.002,1.0\n3,0.003,1.0\n".into(),
        "\u{feff}t,theta\r\n0.000,3.14\r\n0.001,3.13\r\n0.002,3.12\r\n".into(),
        "\"t\", \"z\" ,v\n\n0, 1, 2\n0.5, 1, 2\n1.0, 1, 2\n".into(),
    ]
}

/// Window bounds: open, inside, outside, inverted, non-finite.
fn bound() -> impl Strategy<Value = Option<f64>> {
    prop_oneof![
        Just(None),
        Just(Some(f64::NAN)),
        Just(Some(f64::INFINITY)),
        Just(Some(f64::NEG_INFINITY)),
        Just(Some(1e300)),
        (-0.1f64..0.2).prop_map(Some),
        any::<f64>().prop_map(Some),
    ]
}

fn fail(what: &str, e: impl std::fmt::Display) -> Result<(), String> {
    let m = e.to_string();
    if m.trim().is_empty() {
        Err(format!("{what}: an error with an empty message"))
    } else {
        Ok(())
    }
}

/// The property on a file's bytes and two window bounds.
fn reads_sanely(bytes: &[u8], t0: Option<f64>, t1: Option<f64>) -> Result<(), String> {
    let text = String::from_utf8_lossy(bytes);
    let ds = match Dataset::from_csv_str("fuzz.csv", &text) {
        Ok(ds) => ds,
        Err(e) => return fail("from_csv_str", e),
    };
    let names = ds.names();
    let n = ds.len();
    for (i, name) in names.iter().enumerate() {
        if name.is_empty() || names[..i].contains(name) {
            return Err(format!("column names {names:?}"));
        }
        let c = ds.column(name).map_err(|e| format!("column {name}: {e}"))?;
        if c.len() != n {
            return Err(format!("column {name} has {} values, len() = {n}", c.len()));
        }
        if let Some(x) = c.iter().find(|x| !x.is_finite()) {
            return Err(format!("column {name} holds {x}"));
        }
    }
    match ds.sample_time() {
        Ok(ts) if !(ts.is_finite() && ts > 0.0) => return Err(format!("sample time {ts}")),
        Ok(_) => {}
        Err(e) => fail("sample_time", e)?,
    }
    if let Err(e) = ds.check_time_unit() {
        fail("check_time_unit", e)?;
    }
    let step = match ds.uniform_step() {
        Ok(s) if !(s.is_finite() && s > 0.0) => return Err(format!("uniform step {s}")),
        Ok(s) => s,
        Err(e) => return fail("uniform_step", e),
    };
    match ds.window(t0, t1) {
        Err(e) => fail("window", e),
        Ok(w) => {
            let t = w.time().map_err(|e| format!("window without time: {e}"))?;
            if t.len() < 2 || t.len() > n {
                return Err(format!("window of {} samples out of {n}", t.len()));
            }
            let lo = t0.unwrap_or(f64::NEG_INFINITY) - step;
            let hi = t1.unwrap_or(f64::INFINITY) + step;
            match t.iter().find(|&&x| x < lo || x > hi) {
                Some(x) => Err(format!("window {t0:?}..{t1:?} holds t = {x}")),
                None => Ok(()),
            }
        }
    }
}

#[test]
fn seeds_load() {
    for (i, s) in seeds().iter().enumerate() {
        Dataset::from_csv_str("seed", s).unwrap_or_else(|e| panic!("seed {i}: {e}"));
        reads_sanely(s.as_bytes(), None, None).unwrap();
    }
}

#[test]
fn mutated_csv_files() {
    let s = seeds();
    let seed = (0..s.len()).prop_map(move |i| s[i].clone());
    TARGET.run(
        cases(30000),
        (seed, mutations(TEXT_TOKENS, 1, 8), bound(), bound()),
        |(s, m, _, _)| mutate(s.as_bytes(), m),
        |(s, m, t0, t1)| reads_sanely(&mutate(s.as_bytes(), m), *t0, *t1),
    );
}

#[test]
fn random_windows_of_valid_files() {
    let s = seeds();
    let seed = (0..s.len()).prop_map(move |i| s[i].clone());
    TARGET.run(
        cases(15000),
        (seed, bound(), bound()),
        |(s, _, _)| s.clone().into_bytes(),
        |(s, t0, t1)| reads_sanely(s.as_bytes(), *t0, *t1),
    );
}

#[test]
fn corpus_replays() {
    // Reproducers are replayed with the whole time span and with a window in its middle.
    let n = TARGET.replay(&[], |b| {
        reads_sanely(b, None, None)?;
        reads_sanely(b, Some(0.01), Some(0.02))
    });
    println!("ident_csv corpus: {n} files replayed");
}
