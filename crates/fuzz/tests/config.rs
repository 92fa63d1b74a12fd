//! Fuzz target `config`: the rig controller-file loader `pendulab_rig::config::load` followed by
//! the controller factory `pendulab_control::spec::build` (as `pendulab rig run` does), on the
//! example files of `docs/rig/examples/` mutated as text (bytes, tokens) and as TOML (keys
//! deleted, foreign keys added, values replaced by NaN, ±∞, huge, negative, zero or
//! wrong-typed ones).
//!
//! Property: `load` never panics, and either
//! - loads a file whose every setting is finite and within its documented range: the loop
//!   rate in [10, 50 000] Hz (`config::load`), the `[safety]` table as
//!   `Safety::validate_at` checks it, a positive finite estimator time constant, and a
//!   controller that maps finite measurements to finite commands; or
//! - returns `RigError::Config` with a non-empty message (the factory's error as one).

use pendulab_control::spec::{Built, build};
use pendulab_fuzz::{TEXT_TOKENS, Target, cases, mutate, mutations};
use pendulab_rig::RigError;
use pendulab_rig::config::Loaded;
use pendulab_sim::Controller;
use proptest::prelude::*;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use toml::{Table, Value};

const TARGET: Target = Target {
    name: "config",
    extension: "toml",
};

/// The example controller files, sorted by name (the seeds of the mutations).
fn examples() -> Vec<String> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/rig/examples");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("docs/rig/examples")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(
        files.len() >= 3,
        "too few example files in {}",
        dir.display()
    );
    files
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect()
}

/// Files judged and files that loaded, for the summary each test prints.
static JUDGED: AtomicUsize = AtomicUsize::new(0);
static LOADED: AtomicUsize = AtomicUsize::new(0);

/// What `pendulab rig run` does with a file: load and check it, then build its controller.
fn load(text: &str) -> Result<(Loaded, Built), RigError> {
    let l = pendulab_rig::config::load(text)?;
    let b = build(&l.spec, l.plant, l.ts).map_err(|e| RigError::Config(e.into()))?;
    Ok((l, b))
}

/// The property on a file's bytes (corpus files are replayed through this).
fn loads_sanely(bytes: &[u8]) -> Result<(), String> {
    // The CLI refuses non-UTF-8 files before the loader sees them; the lossy conversion
    // turns invalid bytes into U+FFFD, which the loader must handle as any other character.
    let text = &*String::from_utf8_lossy(bytes);
    JUDGED.fetch_add(1, Ordering::Relaxed);
    let loaded = load(text);
    if loaded.is_ok() {
        LOADED.fetch_add(1, Ordering::Relaxed);
    }
    match loaded {
        Err(RigError::Config(m)) if !m.to_string().trim().is_empty() => Ok(()),
        Err(e) => Err(format!(
            "an error that is not a non-empty Config error: {e:?}"
        )),
        Ok((l, b)) => {
            if !(l.ts.is_finite() && (1.0 / 50_000.0..=1.0 / 10.0).contains(&l.ts)) {
                return Err(format!("loop period {} s outside [1/50000, 1/10]", l.ts));
            }
            l.safety
                .validate_at(l.plant, l.ts)
                .map_err(|e| format!("loaded safety settings out of range: {e}"))?;
            let t = l.differentiator_t;
            if !(t.is_finite() && t > 0.0) {
                return Err(format!("estimator time constant {t}"));
            }
            let mut c = b.controller;
            let (ny, nu) = (c.ny(), c.nu());
            if ny != 4 || nu != 1 {
                return Err(format!("controller with ny = {ny}, nu = {nu}"));
            }
            // A few measurements inside the safety limits: upright at rest, displaced and
            // moving, hanging; the command must be finite.
            let travel = l.safety.travel_limit;
            let mut u = [0.0];
            for (k, y) in [
                [0.0, 0.0, 0.0, 0.0],
                [0.5 * travel, 0.1, -0.3, 0.2],
                [-0.5 * travel, -0.2, 0.5, -1.0],
                [0.0, std::f64::consts::PI, 0.0, 0.0],
            ]
            .iter()
            .enumerate()
            {
                c.update(k as f64 * l.ts, y, &mut u);
                if !u[0].is_finite() {
                    return Err(format!("command {} for y = {y:?}", u[0]));
                }
            }
            Ok(())
        }
    }
}

/// A change of the parsed TOML tree.
#[derive(Debug, Clone)]
enum Edit {
    /// Deletes the `i`-th key (in a walk of every table) .
    Delete(usize),
    /// Sets the `i`-th key's value.
    Replace(usize, Value),
    /// Adds a key to the `i`-th table.
    Add(usize, String, Value),
}

/// Values that break loaders: non-finite, huge, tiny, negative and zero numbers, integers at
/// the edges of their types, wrong types.
fn bad_value() -> impl Strategy<Value = Value> {
    let floats = prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(1e300),
        Just(-1e300),
        Just(1e-300),
        Just(-1.0),
        Just(0.0),
        Just(-0.0),
        any::<f64>(),
        -1e6f64..1e6,
        0.0f64..10.0,
    ]
    .prop_map(Value::Float);
    let ints = prop_oneof![
        Just(0i64),
        Just(-1),
        Just(i64::MAX),
        Just(i64::MIN),
        Just(i64::from(u32::MAX)),
        Just(i64::from(u32::MAX) + 1),
        any::<i64>(),
        1i64..1000,
    ]
    .prop_map(Value::Integer);
    let other = prop_oneof![
        Just(Value::String("cart".into())),
        Just(Value::String("arm".into())),
        Just(Value::String("nan".into())),
        Just(Value::String(String::new())),
        Just(Value::Boolean(true)),
        Just(Value::Array(vec![])),
        Just(Value::Table(Table::new())),
    ];
    let arrays = proptest::collection::vec(
        prop_oneof![Just(f64::NAN), Just(1e300), -100.0f64..100.0].prop_map(Value::Float),
        0..7,
    )
    .prop_map(Value::Array);
    prop_oneof![3 => floats, 2 => ints, 2 => other, 2 => arrays]
}

fn key_name() -> impl Strategy<Value = String> {
    prop_oneof![
        proptest::sample::select(
            &[
                "plant",
                "rate_hz",
                "kind",
                "k",
                "k_book",
                "k1",
                "k2",
                "lqr",
                "q",
                "r",
                "reference",
                "step_time",
                "coefficients",
                "x_coefficients",
                "l_coefficients",
                "schedule",
                "design_points_deg",
                "balance",
                "switch_deg",
                "voltage_limit",
                "travel_limit",
                "angle_window_deg",
                "watchdog_periods",
                "stale_hold_periods",
                "connect_timeout_s",
                "time_constant",
                "safety",
                "estimator",
                "controller",
            ][..]
        )
        .prop_map(String::from),
        "[a-z_]{1,12}",
    ]
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        2 => any::<usize>().prop_map(Edit::Delete),
        4 => (any::<usize>(), bad_value()).prop_map(|(i, v)| Edit::Replace(i, v)),
        2 => (any::<usize>(), key_name(), bad_value()).prop_map(|(i, k, v)| Edit::Add(i, k, v)),
    ]
}

/// Every (table, key) pair, depth first, including tables inside arrays are left out.
fn keys(t: &Table, path: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    for (k, v) in t {
        path.push(k.clone());
        out.push(path.clone());
        if let Value::Table(sub) = v {
            keys(sub, path, out);
        }
        path.pop();
    }
}

fn tables(t: &Table, path: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    out.push(path.clone());
    for (k, v) in t {
        if let Value::Table(sub) = v {
            path.push(k.clone());
            tables(sub, path, out);
            path.pop();
        }
    }
}

fn table_at<'a>(t: &'a mut Table, path: &[String]) -> &'a mut Table {
    let mut cur = t;
    for p in path {
        cur = match cur.get_mut(p) {
            Some(Value::Table(sub)) => sub,
            _ => unreachable!("paths come from the same tree"),
        };
    }
    cur
}

fn apply(t: &mut Table, e: &Edit) {
    match e {
        Edit::Delete(i) | Edit::Replace(i, _) => {
            let mut all = Vec::new();
            keys(t, &mut Vec::new(), &mut all);
            if all.is_empty() {
                return;
            }
            let path = &all[i % all.len()];
            let (last, parent) = path.split_last().unwrap();
            let table = table_at(t, parent);
            match e {
                Edit::Delete(_) => {
                    table.remove(last);
                }
                Edit::Replace(_, v) => {
                    table.insert(last.clone(), v.clone());
                }
                Edit::Add(..) => unreachable!(),
            }
        }
        Edit::Add(i, k, v) => {
            let mut all = Vec::new();
            tables(t, &mut Vec::new(), &mut all);
            let path = all[i % all.len()].clone();
            table_at(t, &path).insert(k.clone(), v.clone());
        }
    }
}

/// Prints how many files were judged and loaded so far (the tests of this file share the
/// counters; a target whose mutants never load tests only the error paths).
fn summary() {
    println!(
        "config: {} files judged, {} loaded",
        JUDGED.load(Ordering::Relaxed),
        LOADED.load(Ordering::Relaxed)
    );
}

#[test]
fn examples_load() {
    // The seeds themselves are valid files (else the mutations test only the parser).
    for (i, text) in examples().iter().enumerate() {
        load(text).unwrap_or_else(|e| panic!("example {i}: {e}"));
        loads_sanely(text.as_bytes()).unwrap();
    }
}

#[test]
fn toml_edits_of_the_examples() {
    let ex = examples();
    let seeds = (0..ex.len()).prop_map(move |i| ex[i].clone());
    let make = |(seed, edits): &(String, Vec<Edit>)| {
        let mut t: Table = seed.parse().expect("an example parses");
        for e in edits {
            apply(&mut t, e);
        }
        // toml writes NaN and ±∞ as nan, inf, -inf (valid TOML 1.0 floats).
        toml::to_string(&t).expect("a table serialises")
    };
    TARGET.run(
        cases(15000),
        (seeds, proptest::collection::vec(edit(), 1..5)),
        |v| make(v).into_bytes(),
        |v| loads_sanely(make(v).as_bytes()),
    );
    summary();
}

#[test]
fn byte_mutations_of_the_examples() {
    let ex = examples();
    let seeds = (0..ex.len()).prop_map(move |i| ex[i].clone());
    TARGET.run(
        cases(15000),
        (seeds, mutations(TEXT_TOKENS, 1, 8)),
        |(s, m)| mutate(s.as_bytes(), m),
        |(s, m)| loads_sanely(&mutate(s.as_bytes(), m)),
    );
    summary();
}

#[test]
fn corpus_replays() {
    let n = TARGET.replay(&[], loads_sanely);
    println!("config corpus: {n} files replayed");
}
