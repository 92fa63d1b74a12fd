//! `pendulab rig`: the rig emulator and the real-time controller runtime.

use anyhow::{Result, bail};

/// Arguments of `pendulab rig`.
#[derive(Debug, clap::Args)]
pub struct RigArgs {
    /// What to do.
    pub action: String,
}

/// Runs `pendulab rig ...`.
pub fn run(args: &RigArgs) -> Result<()> {
    bail!("pendulab rig {}: not available in this build", args.action)
}
