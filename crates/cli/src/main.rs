//! `pendulab`: the command-line face of the pendulab control laboratory.
//!
//! # Standard output and standard error
//!
//! Every subcommand prints through the `print!`/`println!`/`eprint!`/`eprintln!` macros
//! defined below. Because they are defined before the `mod` items, they shadow the standard
//! library's macros of the same names in every module of this binary; unlike those, they never
//! panic when a stream cannot be written:
//!
//! - **A closed pipe** (`pendulab book list | head -1`, `ErrorKind::BrokenPipe`) is a clean
//!   stop of the output: that write and every later one to standard output are dropped, and the
//!   command finishes what it was doing (figures and logs it writes to files, the rig's safe
//!   stop) with its own exit status. A command does not die at its next print (the default
//!   `SIGPIPE` behaviour of C programs), because pendulab's commands do more than print: `rig
//!   run` reports how its run ended by its exit status (3 for a watchdog stop), which a reader
//!   that went away must not turn into a signal death, and `book run --out` writes its figures
//!   whether or not anyone reads the listing.
//! - **Any other write error** on standard output (a full disk, `> /dev/full`) drops the output
//!   likewise and makes the command fail at its end with `error: cannot write to standard
//!   output: …` (exit 1), since the output the user asked for is incomplete.
//! - **Standard error** write errors are ignored: there is nowhere left to report them.
//!
//! # Error messages
//!
//! A failing command prints `error: ` and its error with the chain of causes
//! ([`error_message`]), each cause once, and exits with status 1.

use std::fmt;
use std::io::{ErrorKind, Write};
use std::process::ExitCode;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

/// `print!` that never panics on a closed or failing standard output (see the crate docs).
macro_rules! print {
    ($($arg:tt)*) => {
        $crate::write_stdout(::std::format_args!($($arg)*), false)
    };
}

/// `println!` that never panics on a closed or failing standard output (see the crate docs).
macro_rules! println {
    () => {
        $crate::write_stdout(::std::format_args!(""), true)
    };
    ($($arg:tt)*) => {
        $crate::write_stdout(::std::format_args!($($arg)*), true)
    };
}

/// `eprint!` that ignores write errors on standard error.
#[allow(unused_macros)] // kept beside `eprintln!` so that no subcommand can reach std's
macro_rules! eprint {
    ($($arg:tt)*) => {
        $crate::write_stderr(::std::format_args!($($arg)*), false)
    };
}

/// `eprintln!` that ignores write errors on standard error.
macro_rules! eprintln {
    () => {
        $crate::write_stderr(::std::format_args!(""), true)
    };
    ($($arg:tt)*) => {
        $crate::write_stderr(::std::format_args!($($arg)*), true)
    };
}

mod bench;
mod book;
mod design;
mod estimate;
mod identify;
mod identify_blackbox;
mod lab;
mod lqr;
mod model;
mod plot;
mod report;
mod report_studies;
mod rig;
mod simulate;
mod sys;

use clap::{Parser, Subcommand};

/// Set once a write to standard output failed: later output is dropped.
static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);
/// The first standard-output write error other than a closed pipe, reported at exit.
static STDOUT_ERROR: Mutex<Option<std::io::Error>> = Mutex::new(None);

/// Writes `args` (and a newline if `newline`) to standard output. A broken pipe stops the
/// output quietly; another error stops it and is remembered for [`main`] to report.
pub(crate) fn write_stdout(args: fmt::Arguments<'_>, newline: bool) {
    if STDOUT_CLOSED.load(Ordering::Relaxed) {
        return;
    }
    let mut out = std::io::stdout().lock();
    let written = out.write_fmt(args).and_then(|()| {
        if newline {
            out.write_all(b"\n")
        } else {
            Ok(())
        }
    });
    if let Err(e) = written {
        STDOUT_CLOSED.store(true, Ordering::Relaxed);
        if e.kind() != ErrorKind::BrokenPipe {
            let mut first = STDOUT_ERROR.lock().unwrap_or_else(|p| p.into_inner());
            first.get_or_insert(e);
        }
    }
}

/// Writes `args` (and a newline if `newline`) to standard error, ignoring write errors.
pub(crate) fn write_stderr(args: fmt::Arguments<'_>, newline: bool) {
    let mut err = std::io::stderr().lock();
    let _ = err.write_fmt(args);
    if newline {
        let _ = err.write_all(b"\n");
    }
}

/// Flushes standard output at the end of a command; the first write error other than a closed
/// pipe, if any.
fn finish_stdout() -> Option<std::io::Error> {
    if !STDOUT_CLOSED.load(Ordering::Relaxed)
        && let Err(e) = std::io::stdout().lock().flush()
        && e.kind() != ErrorKind::BrokenPipe
    {
        return Some(e);
    }
    STDOUT_ERROR
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .take()
}

/// The one-line message of an error and its causes, `outer: cause: cause…`, each cause once.
///
/// Library errors often print their source inside their own message (`"{what}: {source}"`,
/// the `thiserror` idiom) and also return it from `source()`; printing the chain naively then
/// repeats the operating system's message (`No such file or directory (os error 2): No such
/// file or directory (os error 2)`). A cause whose message is already part of the text so far
/// adds nothing and is left out; empty messages too.
pub(crate) fn error_message(e: &anyhow::Error) -> String {
    let mut text = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !c.is_empty() && !text.contains(&c) {
            text.push_str(": ");
            text.push_str(&c);
        }
    }
    text
}

/// pendulab — a control-engineering laboratory for the cart-type and arm-type inverted
/// pendulums of 「倒立振子で学ぶ制御工学」.
#[derive(Debug, Parser)]
#[command(name = "pendulab", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// List and run the book's examples.
    Book(book::BookArgs),
    /// Run a performance workload and report its headline figure.
    Bench(bench::BenchArgs),
    /// Identify plant parameters from measured data (CSV), as the book does and better.
    Identify(identify::IdentifyArgs),
    /// Solve an LQ regulator problem (continuous CARE or discrete DARE) from CSV matrices.
    Lqr(lqr::LqrArgs),
    /// Write the lab report: every example's numbers, figures and animations as HTML.
    Report(report::ReportArgs),
    /// Run the rig emulator or the real-time controller runtime.
    Rig(rig::RigArgs),
    /// Create a lab directory for your own rig (lab.toml: the plant and its rig).
    Lab(lab::LabArgs),
    /// Print the linearised model of a lab's plant: A, B, C, D, poles, controllability.
    Model(model::ModelArgs),
    /// Simulate a controller file on a lab's plant with the rig's imperfections.
    Simulate(simulate::SimulateArgs),
    /// Design a controller on a lab's plant (lqr, place, servo, p) and write its file.
    Design(design::DesignArgs),
    /// Plot a rig log or a simulation, and compare two with the fit per signal.
    Plot(plot::PlotArgs),
    /// Estimate the cart's velocities from a log by a Kalman filter (EKF, UKF or linear),
    /// beside the rig's pseudo-differentiator.
    Estimate(estimate::EstimateArgs),
    /// MATLAB's verbs for any linear system (ss, eig, ctrb, obsv, step, impulse, initial, lsim,
    /// bode, c2d, d2c, place, lqe).
    #[command(flatten)]
    Sys(sys::SysCommand),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Book(args) => book::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Identify(args) => identify::run(&args),
        Command::Lqr(args) => lqr::run(&args),
        Command::Report(args) => report::run(&args),
        Command::Rig(args) => rig::run(&args),
        Command::Lab(args) => lab::run(&args),
        Command::Model(args) => model::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Design(args) => design::run(&args),
        Command::Plot(args) => plot::run(&args),
        Command::Estimate(args) => estimate::run(&args),
        Command::Sys(cmd) => sys::run(&cmd),
    };
    let result = result.and_then(|()| match finish_stdout() {
        Some(e) => Err(anyhow::Error::new(e).context("cannot write to standard output")),
        None => Ok(()),
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", error_message(&e));
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::error_message;
    use std::fmt;

    /// An error that prints its source inside its own message, as `RigError::Io` does.
    #[derive(Debug)]
    struct WithSource {
        what: &'static str,
        source: std::io::Error,
    }
    impl fmt::Display for WithSource {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            write!(f, "{}: {}", self.what, self.source)
        }
    }
    impl std::error::Error for WithSource {
        fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
            Some(&self.source)
        }
    }

    fn os_error() -> std::io::Error {
        std::io::Error::new(std::io::ErrorKind::NotFound, "no such thing")
    }

    #[test]
    fn a_source_printed_inside_its_error_appears_once() {
        let e = anyhow::Error::new(WithSource {
            what: "creating the log x.csv",
            source: os_error(),
        })
        .context("in run");
        let m = error_message(&e);
        assert_eq!(m.matches("no such thing").count(), 1, "{m}");
        assert!(m.starts_with("in run: creating the log x.csv"), "{m}");
        // The naive chain, for contrast: anyhow's alternate form repeats it.
        assert_eq!(format!("{e:#}").matches("no such thing").count(), 2);
    }

    #[test]
    fn distinct_causes_are_all_printed_in_order() {
        let e = anyhow::Error::new(os_error())
            .context("cannot read data.csv")
            .context("identify");
        assert_eq!(
            error_message(&e),
            "identify: cannot read data.csv: no such thing"
        );
    }
}
