//! Workloads of the book subsystem.

use super::{BenchReport, Budget, Workload};
use anyhow::Result;
use std::time::Instant;

/// The workloads of this module.
pub(super) fn workloads() -> Vec<Workload> {
    vec![Workload {
        name: "book-report",
        description: "the whole lab report: every example, its figures and index.html, into a temporary directory (s)",
        run: report,
    }]
}

/// Times `pendulab report` end to end (examples in parallel, figures, page) into a fresh
/// temporary directory. One report is long, so this repeats whole reports only while the budget
/// lasts (at least one) and takes the median.
fn report(budget: &Budget) -> Result<BenchReport> {
    let dir =
        std::env::temp_dir().join(format!("pendulab-bench-book-report-{}", std::process::id()));
    let mut times = Vec::new();
    let t0 = Instant::now();
    let last = loop {
        // Start from an empty directory each time, so every report writes every figure.
        let _ = std::fs::remove_dir_all(&dir);
        let r = crate::report::generate(&dir, &[], &[], None, false);
        let r = match r {
            Ok(r) => r,
            Err(e) => {
                let _ = std::fs::remove_dir_all(&dir);
                return Err(e);
            }
        };
        times.push(r.seconds);
        if t0.elapsed() >= budget.min_time {
            break r;
        }
    };
    let html_bytes = std::fs::metadata(&last.index).map(|m| m.len()).unwrap_or(0);
    let _ = std::fs::remove_dir_all(&dir);
    times.sort_by(f64::total_cmp);
    let s = &last.summary;
    Ok(BenchReport {
        workload: "book-report".into(),
        figure: times[times.len() / 2],
        unit: "s".into(),
        check: serde_json::json!({
            "reports": times.len(),
            "examples": s.total,
            "reproduced": s.reproduced,
            "runs": s.runs,
            "differs": s.differs,
            "needs_data": s.needs_data,
            "failing": s.failing,
            "failing_ids": last.failing,
            "figures": s.figures,
            "index_html_bytes": html_bytes,
            "threads": rayon::current_num_threads(),
        }),
    })
}
