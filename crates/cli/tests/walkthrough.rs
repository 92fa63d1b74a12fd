//! Issue 18's acceptance, end to end on the emulator: the commands of `docs/walkthrough.md`
//! ("your own cart rig in ten commands"), read from its `console` blocks and run in order.
//!
//! The rig is the emulator of a cart rig whose `a_c`, `b_c`, `J_p`, `μ_p` differ from the
//! book's table 3.5 by 10–20 % (`rig-lab/lab.toml`, written here). The path: `lab init` → a
//! P-control run logged on the emulator → `identify --save` recovers the four parameters
//! within 2 % → `design lqr` → `simulate` → `rig run` on the emulator started 5 s earlier →
//! `plot --vs` fit ≥ 90 % on z and θ → `report --lab` builds; and a second `rig run` against
//! the same emulator works.
//!
//! The test changes the doc's commands only where a test must: the emulator listens on a free
//! port (`--listen 127.0.0.1:0`, its address put where the doc writes 127.0.0.1:5005) and
//! stops by itself after two minutes if the test fails; `rig run` gets `--watchdog-periods
//! 500` (the machine running the tests is shared with builds and may deschedule the loop for
//! longer than the file's 50 ms watchdog, which is not under test here).

mod common;
use common::*;

use std::path::Path;
use std::process::{Child, Command};
use std::time::Duration;

/// The emulated rig's parameters: the book's with the four identifiable ones 10–20 % off.
const OFF: [(&str, f64); 4] = [("a_c", 1.15), ("b_c", 0.87), ("J_p", 1.12), ("mu_p", 1.18)];

/// The `$ pendulab …` lines of the doc's `console` blocks, without the `$ pendulab `.
fn doc_commands() -> Vec<String> {
    let doc = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/walkthrough.md"),
    )
    .unwrap();
    let mut out = Vec::new();
    let mut inside = false;
    for line in doc.lines() {
        if line.starts_with("```") {
            inside = line.trim() == "```console";
            continue;
        }
        if inside && let Some(cmd) = line.strip_prefix("$ pendulab ") {
            out.push(cmd.to_string());
        }
    }
    out
}

/// Splits a command line at spaces, keeping "double-quoted" words whole.
fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    for c in line.chars() {
        match c {
            '"' => quoted = !quoted,
            ' ' if !quoted => {
                if !cur.is_empty() {
                    out.push(std::mem::take(&mut cur));
                }
            }
            _ => cur.push(c),
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

fn bin(dir: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_pendulab"));
    c.current_dir(dir);
    c
}

/// Starts an emulator in `dir` with the doc's arguments; its address.
fn emulate(dir: &Path, args: &[String]) -> (Child, String) {
    let mut cmd = bin(dir);
    cmd.args(args)
        .args(["--listen", "127.0.0.1:0", "--duration", "120"]);
    spawn_listening(cmd)
}

fn stop(mut emu: Child) {
    let _ = Command::new("kill")
        .args(["-INT", &emu.id().to_string()])
        .status();
    let _ = emu.wait();
}

fn parameter(lab: &str, key: &str) -> f64 {
    let t: toml::Table = std::fs::read_to_string(lab).unwrap().parse().unwrap();
    t["plant"]["parameters"][key].as_float().unwrap()
}

#[test]
fn your_own_cart_rig_in_ten_commands() {
    let d = Dir::new("walkthrough");
    let root = d.join("");
    // The rig: the book's cart with four parameters off, as its owner's lab file.
    let o = pendulab(&["lab", "init", &d.path("rig-lab"), "--plant", "cart"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut text = std::fs::read_to_string(d.join("rig-lab/lab.toml")).unwrap();
    text = text.replace("source = \"book\"", "source = \"user\"");
    for (key, factor) in OFF {
        let book = parameter(&d.path("rig-lab/lab.toml"), key);
        let line = text
            .lines()
            .find(|l| l.starts_with(&format!("{key} =")))
            .unwrap()
            .to_string();
        text = text.replace(&line, &format!("{key} = {:?}", book * factor));
    }
    std::fs::write(d.join("rig-lab/lab.toml"), text).unwrap();
    std::fs::create_dir_all(d.join("mylab/logs")).unwrap();

    let commands = doc_commands();
    assert!(commands.len() >= 10, "{commands:?}");
    let mut emu: Option<Child> = None;
    let mut addr = String::new();
    let mut lqr_runs = 0;
    let mut fits = None;
    for line in &commands {
        let mut args = words(&line.replace("127.0.0.1:5005", &addr));
        if args[..2] == ["rig", "emulate"] {
            if let Some(e) = emu.take() {
                stop(e);
            }
            let (e, a) = emulate(&root, &args);
            emu = Some(e);
            addr = a;
            continue;
        }
        if args[..2] == ["rig", "run"] {
            // The doc's address is only known now.
            args = words(&line.replace("127.0.0.1:5005", &addr));
            args.extend(["--watchdog-periods".into(), "500".into()]);
            if args.iter().any(|a| a.contains("lqr")) {
                // Issue 18: the controller started 5 s after the emulator.
                std::thread::sleep(Duration::from_secs(5));
                lqr_runs += 1;
            }
        }
        if args[0] == "plot" {
            args.push("--json".into());
        }
        let o = bin(&root).args(&args).output().unwrap();
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(o.status.success(), "pendulab {line}\n{out}\n{}", stderr(&o));
        if args[0] == "plot" {
            fits = Some(serde_json::from_str::<serde_json::Value>(&out).unwrap());
        }
        if args[..2] == ["rig", "run"] {
            assert!(out.contains("stop: completed"), "pendulab {line}\n{out}");
        }
    }
    assert_eq!(lqr_runs, 1, "{commands:?}");

    // identify --save recovered the rig's parameters within 2 %.
    let (mine, rig) = (d.path("mylab/lab.toml"), d.path("rig-lab/lab.toml"));
    for (key, _) in OFF {
        let (got, want) = (parameter(&mine, key), parameter(&rig, key));
        assert!(
            ((got - want) / want).abs() < 0.02,
            "{key}: identified {got}, the rig's {want}"
        );
    }
    // with the data file's SHA-256 (as sha256sum prints it, when the tool is there).
    let lab: toml::Table = std::fs::read_to_string(&mine).unwrap().parse().unwrap();
    let prov = &lab["plant"]["provenance"];
    assert_eq!(prov["source"].as_str(), Some("identified"));
    if let Ok(o) = Command::new("sha256sum")
        .arg(d.join("mylab/logs/p.csv"))
        .output()
    {
        let printed = String::from_utf8_lossy(&o.stdout);
        assert_eq!(
            Some(printed.split_whitespace().next().unwrap_or("")),
            prov["sha256"].as_str()
        );
    }

    // plot --vs: fit ≥ 90 % on z and θ.
    let fits = fits.expect("the doc plots the run against the simulation");
    for signal in ["z", "theta"] {
        let f = fits["fits"]
            .as_array()
            .unwrap()
            .iter()
            .find(|f| f["signal"] == signal)
            .unwrap_or_else(|| panic!("{fits}"));
        let p = f["percent"].as_f64().unwrap();
        assert!(p >= 90.0, "fit of {signal}: {p} %");
    }

    // report --lab built a page that shows the identification and the design's figures.
    let page = std::fs::read_to_string(d.join("mylab/report/index.html")).unwrap();
    assert!(
        page.contains("Identified from") && page.contains("lqr"),
        "{page}"
    );
    assert!(page.contains("figures/lqr-simulation.svg"), "{page}");
    assert!(d.join("mylab/report/figures/run-lqr.svg").exists());

    // A second run against the same emulator works too.
    let o = bin(&root)
        .args([
            "rig",
            "run",
            "--lab",
            "mylab",
            "--connect",
            &addr,
            "--controller",
            "mylab/designs/lqr.toml",
            "--duration",
            "2",
            "--watchdog-periods",
            "500",
        ])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success() && out.contains("stop: completed"),
        "{out}{}",
        stderr(&o)
    );
    if let Some(e) = emu.take() {
        stop(e);
    }
}
