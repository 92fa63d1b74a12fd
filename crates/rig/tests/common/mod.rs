//! What a front end does with a controller file, for the tests: `pendulab_rig::config::load`
//! reads and checks the file, `pendulab_control::spec::build` builds its controller (as
//! `pendulab rig run` does); and the set-up the rig's tests share: a run against an
//! emulator or a fake rig with an optional log, the log read back.
// Each test binary uses a different part of the helper.
#![allow(dead_code)]

use pendulab_control::spec::build;
use pendulab_rig::Logger;
use pendulab_rig::config::{self, Loaded};
use pendulab_rig::emulator::{EmulatorConfig, PlantKind};
use pendulab_rig::runtime::{RunConfig, RunReport, run};
use pendulab_sim::Controller;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// A controller file loaded and its controller built.
pub struct Ready {
    /// The file's settings and spec.
    pub loaded: Loaded,
    /// The controller built from the spec.
    pub controller: Box<dyn Controller>,
    /// The pendulum angle the controller stabilises \[rad\].
    pub pendulum_centre: f64,
}

impl std::ops::Deref for Ready {
    type Target = Loaded;
    fn deref(&self) -> &Loaded {
        &self.loaded
    }
}

impl std::ops::DerefMut for Ready {
    fn deref_mut(&mut self) -> &mut Loaded {
        &mut self.loaded
    }
}

impl std::fmt::Debug for Ready {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ready")
            .field("loaded", &self.loaded)
            .finish_non_exhaustive()
    }
}

/// Loads the controller file `text` and builds its controller; either error as its message.
pub fn load(text: &str) -> Result<Ready, String> {
    let loaded = config::load(text).map_err(|e| e.to_string())?;
    let built = build(&loaded.spec, loaded.plant, loaded.ts).map_err(|e| e.to_string())?;
    Ok(Ready {
        loaded,
        controller: built.controller,
        pendulum_centre: built.pendulum_centre,
    })
}

/// The cart's LQR of the book's `cdip_lqr_sim` (`Q = diag(10, 10, 0, 0)`, `R = 1`) as a
/// controller file.
pub const CART_LQR: &str = "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [10.0, 10.0, 0.0, 0.0], r = 1.0 }\n";

/// The watchdog of tests that do not test it \[periods\]: 0.5 s at 1 kHz, the longest
/// `Safety` allows. The file's 50 ms would end a behavioural test for a reason it does not
/// test: a 2-core machine shared with builds can deschedule a thread for longer (up to 0.1 s
/// was seen, `docs/rig/lab-pc.md`).
pub const TOLERANT_WATCHDOG: u32 = 500;

/// A file of this test process: `<temp>/pendulab-rig-<pid>/<name>`.
pub fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pendulab-rig-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// An angle wrapped to `(−π, π]`, independent of the crate's wrapping: atan2 of sine and
/// cosine.
pub fn wrap(a: f64) -> f64 {
    a.sin().atan2(a.cos())
}

/// A log: header and rows of numbers.
pub type Log = (Vec<String>, Vec<Vec<f64>>);

/// Reads a log written by `pendulab_rig::Logger`.
pub fn read_log(path: &Path) -> Log {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// The index of column `name` of a log's header.
pub fn col(header: &[String], name: &str) -> usize {
    header.iter().position(|h| h == name).unwrap()
}

/// The emulated `plant` at rest at `x0` with its own watchdog relaxed to 0.5 s (not under
/// test where this is used; see [`TOLERANT_WATCHDOG`]).
pub fn emulator(plant: PlantKind, x0: [f64; 4]) -> EmulatorConfig {
    let mut c = EmulatorConfig::new(plant, x0);
    c.watchdog = Duration::from_millis(500);
    c
}

/// A run of the loaded file against the rig at `rig`: its plant and `[safety]`, with the
/// watchdog set to `watchdog_periods` (the default duration of `RunConfig::new`, 10 s).
pub fn run_config(ready: &Ready, rig: SocketAddr, watchdog_periods: u32) -> RunConfig {
    let mut cfg = RunConfig::new(ready.plant, rig);
    cfg.safety = ready.safety;
    cfg.safety.watchdog_periods = watchdog_periods;
    cfg
}

/// Runs `controller` under `cfg`, logging every frame to `log` if given (the plant's log
/// columns), never interrupted; prints the report and returns it.
pub fn run_with_log(
    cfg: &RunConfig,
    controller: &mut dyn Controller,
    log: Option<&Path>,
) -> RunReport {
    let logger = log.map(|p| Logger::create(p, cfg.plant).unwrap());
    let r = run(cfg, controller, &AtomicBool::new(false), logger).unwrap();
    println!("{r}");
    r
}
