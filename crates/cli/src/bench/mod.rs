//! `pendulab bench <workload>`: the performance workloads of pendulab.
//!
//! Each workload times one job repeatedly, reports its headline figure (a time per call or a
//! rate) and the accuracy evidence that the timed job did the right thing. With `--json` the
//! output is one line `{"workload", "figure", "unit", "check"}`.

mod care;
mod ident;
mod lsim;

use anyhow::{Result, bail};
use serde::Serialize;
use std::time::{Duration, Instant};

mod book;
mod lmi;
mod mpc;
mod nmpc;
mod plants;
mod plot;
mod rig;
mod sim;
mod toolbox;

/// Arguments of `pendulab bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// Workload to run (`list` shows them all).
    pub workload: String,
    /// Print one JSON line instead of a human-readable summary.
    #[arg(long)]
    pub json: bool,
    /// Minimum measuring time per workload in seconds.
    #[arg(long, default_value_t = 1.0)]
    pub seconds: f64,
}

/// The result of one workload.
#[derive(Debug, Serialize)]
pub struct BenchReport {
    /// Workload name.
    pub workload: String,
    /// The headline figure.
    pub figure: f64,
    /// Unit of the figure (e.g. "us/solve", "samples/s").
    pub unit: String,
    /// Accuracy evidence of the timed job.
    pub check: serde_json::Value,
}

/// A registered workload.
pub struct Workload {
    /// Name used on the command line.
    pub name: &'static str,
    /// One-line description.
    pub description: &'static str,
    /// Runs it with a measuring budget.
    pub run: fn(&Budget) -> Result<BenchReport>,
}

/// How long to measure.
#[derive(Debug, Clone, Copy)]
pub struct Budget {
    /// Minimum total measuring time.
    pub min_time: Duration,
}

/// Timing statistics of repeated calls.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Timing {
    /// Calls measured.
    pub iterations: u64,
    /// Median seconds per call over the measured batches.
    pub median_s: f64,
    /// Fastest batch's seconds per call.
    pub min_s: f64,
}

/// Calls `f` repeatedly for at least `budget.min_time`, in batches sized to last ~10 ms each,
/// and returns per-call statistics (median over batches, which is robust to the noise of a
/// shared machine).
pub fn time<F: FnMut()>(budget: &Budget, mut f: F) -> Timing {
    // Warm up and size a batch.
    let start = Instant::now();
    f();
    let once = start.elapsed().max(Duration::from_nanos(20));
    let batch =
        ((Duration::from_millis(10).as_secs_f64() / once.as_secs_f64()).ceil() as u64).max(1);
    let mut per_call = Vec::new();
    let mut iterations = 0;
    let t0 = Instant::now();
    while t0.elapsed() < budget.min_time || per_call.len() < 3 {
        let s = Instant::now();
        for _ in 0..batch {
            f();
        }
        per_call.push(s.elapsed().as_secs_f64() / batch as f64);
        iterations += batch;
    }
    per_call.sort_by(|a, b| a.total_cmp(b));
    Timing {
        iterations,
        median_s: per_call[per_call.len() / 2],
        min_s: per_call[0],
    }
}

fn workloads() -> Vec<Workload> {
    let mut all = Vec::new();
    all.extend(lmi::workloads());
    all.extend(plot::workloads());
    all.extend(sim::workloads());
    all.extend(rig::workloads());
    all.extend(book::workloads());
    all.extend(toolbox::workloads());
    all.push(Workload {
        name: "ident-1e6",
        description: "book least squares (3-point, 1/(0.075s+1)^3, QR) on 10^6 quantised cart samples (ms)",
        run: ident::run,
    });
    all.push(Workload {
        name: "care-n4",
        description: "CARE of the linearised cart pendulum, Q = diag(100, 10, 1, 1), R = 1 (us/solve)",
        run: care::run_n4,
    });
    all.push(Workload {
        name: "care-n100",
        description: "CARE of a random stabilisable system, n = 100, m = 10, fixed seed (ms/solve)",
        run: care::run_n100,
    });
    all.push(Workload {
        name: "nmpc-update",
        description: "one C/GMRES update of the arm pendulum's swing-up NMPC, over a 10 s swing (us/update)",
        run: nmpc::run,
    });
    all.push(Workload {
        name: "mpc-qp",
        description: "one warm-started QP of the cart's constrained MPC, horizon 20, voltage and track limits, over a 5 s closed loop (us/solve)",
        run: mpc::run,
    });
    all.push(Workload {
        name: "lsim-1e6",
        description: "10^6 samples of a 5-state closed loop at 1 ms, FOH (samples/s)",
        run: lsim::run,
    });
    all.push(Workload {
        name: "plants-rhs",
        description: "cart/arm pendulum right-hand sides in a 1 kHz RK4 loop (evals/s)",
        run: plants::run,
    });
    all
}

/// Runs `pendulab bench`.
pub fn run(args: &BenchArgs) -> Result<()> {
    let all = workloads();
    if args.workload == "list" {
        if all.is_empty() {
            println!("no workloads registered yet");
        }
        for w in &all {
            println!("{:<20} {}", w.name, w.description);
        }
        return Ok(());
    }
    if !(args.seconds.is_finite() && args.seconds > 0.0) {
        bail!("--seconds must be a positive number, got {}", args.seconds);
    }
    let Some(w) = all.iter().find(|w| w.name == args.workload) else {
        let names: Vec<_> = all.iter().map(|w| w.name).collect();
        bail!(
            "unknown workload '{}'; known workloads: {}",
            args.workload,
            if names.is_empty() {
                "(none yet)".to_string()
            } else {
                names.join(", ")
            }
        );
    };
    let budget = Budget {
        min_time: Duration::from_secs_f64(args.seconds),
    };
    let report = (w.run)(&budget)?;
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        println!(
            "{}: {} {}\ncheck: {}",
            report.workload,
            report.figure,
            report.unit,
            serde_json::to_string_pretty(&report.check)?
        );
    }
    Ok(())
}
