//! `pendulab`: the command-line face of the pendulab control laboratory.

mod bench;
mod book;
mod identify;
mod lqr;
mod report;
mod rig;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

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
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
