//! `pendulab report`: the lab report.

use anyhow::{Result, bail};
use std::path::PathBuf;

/// Arguments of `pendulab report`.
#[derive(Debug, clap::Args)]
pub struct ReportArgs {
    /// Output directory.
    #[arg(long)]
    pub out: PathBuf,
}

/// Runs `pendulab report`.
pub fn run(args: &ReportArgs) -> Result<()> {
    bail!(
        "cannot write the report to {}: not available in this build",
        args.out.display()
    )
}
