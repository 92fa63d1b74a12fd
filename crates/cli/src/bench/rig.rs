//! Workloads of the rig subsystem.

use super::Workload;

/// The workloads of this module.
pub(super) fn workloads() -> Vec<Workload> {
    Vec::new()
}
