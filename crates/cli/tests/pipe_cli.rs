//! The binary's standard streams and error messages (issue 21, item 6): output into a closed
//! pipe ends quietly with the command's own status, a failing standard output is an error, and
//! an operating-system error is printed once.

mod common;
use common::*;

use std::io::{BufRead, BufReader};
use std::process::{Command, Output, Stdio};

fn pendulab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pendulab"))
}

/// Runs `args` with standard output on a pipe whose reading end is closed before the child
/// starts: its first write fails with `EPIPE` (Rust programs ignore `SIGPIPE`, so the write
/// returns the error instead of killing the process).
fn into_closed_pipe(args: &[&str]) -> Output {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    pendulab()
        .args(args)
        .stdout(writer)
        .stderr(Stdio::piped())
        .output()
        .unwrap()
}

/// Asserts exit status 0, no panic and nothing on standard error.
fn quiet_success(o: &Output, what: &str) {
    let err = stderr(o);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{what}: {:?}, stderr: {err}",
        o.status
    );
    assert!(err.is_empty(), "{what}: stderr: {err}");
}

#[test]
fn output_into_a_closed_pipe_exits_0_quietly() {
    let d = Dir::new("closed");
    let a = d.file("A.csv", "0,1\n2,-1\n");
    let b = d.file("B.csv", "0\n1\n");
    let data = format!(
        "{}/../../data/rig/cdip_least_square_data.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    for args in [
        &["book", "list"][..],
        &["book", "list", "--json"],
        &["book", "run", "p1c211_pcont"],
        &["lqr", "--a", &a, "--b", &b],
        &["lqr", "--a", &a, "--b", &b, "--json"],
        &["identify", "cart-ls", "--data", &data],
        &["--help"],
    ] {
        quiet_success(&into_closed_pipe(args), &args.join(" "));
    }
}

#[test]
fn a_closed_pipe_leaves_the_commands_own_failure() {
    // `rig run` prints its start line (into the closed pipe), goes on, finds no rig within
    // the file's 0.2 s and fails as it would with a reader: exit 1 and the reason on stderr.
    let d = Dir::new("norig");
    let ctl = d.file(
        "c.toml",
        "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [-3.16, -13.5, -4.48, -2.26]\n[safety]\nconnect_timeout_s = 0.2\n",
    );
    let args = [
        "rig",
        "run",
        "--connect",
        "127.0.0.1:9",
        "--controller",
        &ctl,
    ];
    let o = into_closed_pipe(&[&args[..], &["--duration", "0.1"]].concat());
    assert_eq!(o.status.code(), Some(1), "{:?}", o.status);
    let err = stderr(&o);
    assert!(err.contains("no rig") && !err.contains("panicked"), "{err}");
}

#[test]
fn book_list_read_up_to_its_first_line_exits_0() {
    // What `pendulab book list | head -1` does: the reader takes one line and closes the pipe.
    let full = pendulab().args(["book", "list"]).output().unwrap();
    assert!(full.status.success());
    let first = String::from_utf8(full.stdout).unwrap();
    let first = first.lines().next().unwrap();
    let mut child = pendulab()
        .args(["book", "list"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    assert_eq!(line.trim_end(), first);
    // The reading end is closed here (the BufReader owning it was dropped).
    let o = child.wait_with_output().unwrap();
    quiet_success(&o, "book list | head -1");
}

#[cfg(target_os = "linux")]
#[test]
fn a_failing_standard_output_is_an_error() {
    // /dev/full: every write fails with ENOSPC, an error that is not a closed pipe.
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        eprintln!("no /dev/full: skipped");
        return;
    };
    let o = pendulab()
        .args(["book", "list"])
        .stdout(full)
        .output()
        .unwrap();
    let enospc = std::io::Error::from_raw_os_error(28).to_string();
    fails_with(&o, &["cannot write to standard output", &enospc]);
    assert_eq!(o.status.code(), Some(1));
    assert!(!stderr(&o).contains("panicked"));
}

#[test]
fn an_os_error_is_printed_once() {
    let d = Dir::new("oserr");
    let ctl = d.file(
        "c.toml",
        "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [-3.16, -13.5, -4.48, -2.26]\n",
    );
    // A log in a directory that does not exist: the operating system's message, as the
    // same attempt gets it here.
    let log = d.join("missing").join("x.csv");
    let os = std::fs::File::create(&log).unwrap_err().to_string();
    let o = pendulab()
        .args([
            "rig",
            "run",
            "--connect",
            "127.0.0.1:9",
            "--controller",
            &ctl,
        ])
        .args(["--duration", "0.1", "--log", &log.to_string_lossy()])
        .output()
        .unwrap();
    fails_with(&o, &[&os, "x.csv"]);
    assert_eq!(stderr(&o).matches(&os).count(), 1, "{}", stderr(&o));

    // An emulator asked to listen on a port that is taken.
    let taken = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    let addr = taken.local_addr().unwrap().to_string();
    let os = std::net::UdpSocket::bind(&addr).unwrap_err().to_string();
    let o = pendulab()
        .args(["rig", "emulate", "--plant", "cart", "--listen", &addr])
        .args(["--duration", "0.1"])
        .output()
        .unwrap();
    fails_with(&o, &[&os, &addr]);
    assert_eq!(stderr(&o).matches(&os).count(), 1, "{}", stderr(&o));

    // A data file that does not exist.
    let missing = d.path("missing.csv");
    let os = std::fs::read_to_string(&missing).unwrap_err().to_string();
    let o = pendulab()
        .args(["identify", "cart-ls", "--data", &missing])
        .output()
        .unwrap();
    fails_with(&o, &[&os, "missing.csv"]);
    assert_eq!(stderr(&o).matches(&os).count(), 1, "{}", stderr(&o));
}
