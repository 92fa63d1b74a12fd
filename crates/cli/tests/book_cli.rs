//! `pendulab book` end to end: the JSON line contract of `docs/report.md` over the whole registry,
//! and the errors (wrong id, unwritable output directory, missing or malformed data file) that must
//! give a message naming the problem and a non-zero exit.

mod common;
use common::*;

use serde_json::Value;
use std::path::PathBuf;
use std::process::{Command, Output};

fn book(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pendulab"))
        .arg("book")
        .args(args)
        .output()
        .unwrap()
}

fn json_lines(o: &Output) -> Vec<Value> {
    String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not JSON ({e}): {l}")))
        .collect()
}

/// `(id, needs_data)` of every registered example, from `pendulab book list --json`.
fn listed() -> Vec<(String, bool)> {
    let o = book(&["list", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    json_lines(&o)
        .iter()
        .map(|v| {
            for key in ["id", "title", "section", "parameters"] {
                assert!(v[key].is_string(), "{key} missing in {v}");
            }
            (
                v["id"].as_str().unwrap().to_string(),
                !v["needs_data"].is_null(),
            )
        })
        .collect()
}

#[test]
fn run_all_json_follows_the_line_contract_and_writes_its_figures() {
    let examples = listed();
    let out = Dir::new("all");
    let o = book(&["run", "--all", "--json", "--out", &out.path("figs")]);
    // Examples that need data report it and are not failures: exit 0.
    assert!(o.status.success(), "{}", stderr(&o));
    let lines = json_lines(&o);
    let ids: Vec<&str> = lines.iter().map(|l| l["id"].as_str().unwrap()).collect();
    let expected: Vec<&str> = examples.iter().map(|(id, _)| id.as_str()).collect();
    assert_eq!(ids, expected, "one line per example, in registry order");
    for (line, (id, needs_data)) in lines.iter().zip(&examples) {
        assert!(line["values"].is_object(), "{id}: values is not an object");
        assert!(line["figures"].is_array(), "{id}: figures is not an array");
        assert!(
            line.get("error").is_none(),
            "{id} failed: {}",
            line["error"]
        );
        if line.get("needs_data").is_some() {
            assert!(
                needs_data,
                "{id} asks for data but is not listed as needing it"
            );
        }
        for v in line["values"].as_object().unwrap().values() {
            // docs/report.md: number | bool | [..] | [[..]].
            assert!(
                v.is_number() || v.is_boolean() || v.is_array(),
                "{id}: value {v} is neither number, boolean nor array"
            );
        }
        for f in line["figures"].as_array().unwrap() {
            let p = PathBuf::from(f.as_str().unwrap());
            assert!(p.is_file(), "{id}: figure {} was not written", p.display());
            assert!(
                p.starts_with(out.path("figs")),
                "{id}: figure outside --out"
            );
        }
    }
    // Running one example by name gives the same numbers as within --all (the examples are
    // deterministic).
    if let Some((line, (id, _))) = lines
        .iter()
        .zip(&examples)
        .find(|(l, _)| l.get("needs_data").is_none())
    {
        let one = book(&["run", id, "--json"]);
        assert!(one.status.success(), "{}", stderr(&one));
        let single = json_lines(&one);
        assert_eq!(single.len(), 1);
        assert_eq!(single[0]["id"], line["id"]);
        assert_eq!(single[0]["values"], line["values"]);
    }
}

#[test]
fn wrong_id_is_a_clear_error() {
    fails_with(
        &book(&["run", "no_such_example", "--json"]),
        &["unknown example id 'no_such_example'", "pendulab book list"],
    );
    fails_with(&book(&["run"]), &["name at least one example id"]);
    fails_with(&book(&["run", "--all", "x"]), &["not both"]);
}

#[test]
fn unwritable_output_directory_is_a_clear_error() {
    let d = Dir::new("unwritable");
    // A directory cannot be made below a regular file (this holds for root too, unlike
    // permission bits).
    let file = d.file("plain-file", "x");
    let out = format!("{file}/figs");
    fails_with(
        &book(&["run", "--all", "--out", &out]),
        &["cannot create output directory", "figs"],
    );
}

#[test]
fn missing_and_malformed_data_files_are_clear_errors() {
    let d = Dir::new("data");
    let missing = d.path("nope.csv");
    fails_with(
        &book(&["run", "--all", "--data", &missing]),
        &["cannot read data file", "nope.csv"],
    );
    let bad = d.file("bad.csv", "t,theta1,theta2\n0,0.1,0.2\n0.001,0.1,oops\n");
    fails_with(
        &book(&["run", "--all", "--data", &bad]),
        &[
            "malformed data file",
            "bad.csv",
            "line 3, column 'theta2': 'oops'",
        ],
    );
    let ragged = d.file("ragged.csv", "t,theta\n0,0.1\n0.001\n");
    fails_with(
        &book(&["run", "--all", "--data", &ragged]),
        &["line 3: 1 fields, but the header names 2 columns"],
    );
    let empty = d.file("empty.csv", "");
    fails_with(&book(&["run", "--all", "--data", &empty]), &["empty"]);
    let good = d.file("good.csv", "t,theta\n0,0.1\n");
    fails_with(
        &book(&["run", "--all", "--data", &format!("no_such_example={good}")]),
        &["unknown example id 'no_such_example'"],
    );
}

#[test]
fn examples_taking_data_run_on_their_shipped_data_or_say_what_is_missing() {
    // Named explicitly without data, an example that takes data runs on its recording shipped
    // in data/rig/; one without a shipped recording is an error whose JSON line says what is
    // missing.
    for (id, _) in listed().into_iter().filter(|(_, takes)| *takes) {
        let o = book(&["run", &id, "--json"]);
        let lines = json_lines(&o);
        assert_eq!(lines.len(), 1);
        if o.status.success() {
            assert!(lines[0].get("needs_data").is_none(), "{}", lines[0]);
            assert!(!lines[0]["values"].as_object().unwrap().is_empty(), "{id}");
        } else {
            assert!(lines[0]["needs_data"].is_string(), "{}", lines[0]);
            assert!(stderr(&o).contains("1 of 1 examples failed"));
        }
    }
}
