//! Helpers shared by the CLI's end-to-end tests: the binary, its stderr, scratch directories.
#![allow(dead_code)] // each test file uses its own subset

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Output, Stdio};

/// Runs the `pendulab` binary built for these tests with `args`.
pub fn pendulab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pendulab"))
        .args(args)
        .output()
        .unwrap()
}

/// The process's standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Successful run's standard output as one JSON document (panics, with stderr, on failure).
pub fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "stderr: {}", stderr(o));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// Failing run: non-zero exit and a message containing every `needle`.
pub fn fails_with(o: &Output, needles: &[&str]) {
    let err = stderr(o);
    assert!(!o.status.success(), "expected failure, stderr: {err}");
    for n in needles {
        assert!(err.contains(n), "stderr lacks {n:?}: {err}");
    }
}

/// A fresh scratch directory, named after the test file, `tag` and the process, removed on drop.
pub struct Dir(PathBuf);

impl Dir {
    pub fn new(tag: &str) -> Self {
        let p = std::env::temp_dir().join(format!(
            "pendulab-{}-{tag}-{}",
            env!("CARGO_CRATE_NAME"),
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&p);
        std::fs::create_dir_all(&p).unwrap();
        Dir(p)
    }
    /// Writes `text` to `name` inside the directory and returns its path.
    pub fn file(&self, name: &str, text: &str) -> String {
        let p = self.0.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_string_lossy().into_owned()
    }
    /// The path of `name` inside the directory, as text.
    pub fn path(&self, name: &str) -> String {
        self.join(name).to_string_lossy().into_owned()
    }
    /// The path of `name` inside the directory.
    pub fn join(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for Dir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The linearised cart pendulum of `docs/model.md` §1 (book table 3.5 parameters) as CSV
/// text: `(A, B)`.
pub fn cdip_csv() -> (String, String) {
    let (ac, bc, mp, lp, jp, mup, g) = (6.25f64, 4.36, 0.107, 0.230, 1.59e-3, 2.35e-4, 9.81);
    let j = jp + mp * lp * lp;
    let a = format!(
        "0,0,1,0\n0,0,0,1\n0,0,{},0\n0,{},{},{}\n",
        -ac,
        mp * g * lp / j,
        ac * mp * lp / j,
        -mup / j
    );
    let b = format!("0\n0\n{bc}\n{}\n", -bc * mp * lp / j);
    (a, b)
}

/// Spawns `cmd` (a `rig emulate` command listening on port 0) with its standard output piped;
/// the child and the address it printed on its first line, `listening on ADDR`.
pub fn spawn_listening(mut cmd: Command) -> (Child, String) {
    let mut child = cmd.stdout(Stdio::piped()).spawn().unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.as_mut().unwrap())
        .read_line(&mut line)
        .unwrap();
    let addr = line
        .trim()
        .strip_prefix("listening on ")
        .unwrap_or_else(|| panic!("{line:?}"))
        .to_string();
    (child, addr)
}
