//! What `pendulab design` prints: the gain in both sign conventions, the closed-loop poles
//! and the stability margins of the loop broken at the plant input
//! (`pendulab_lti::margins::stability_margins`), as tables or one JSON object.

use super::schedule::{ScheduleJson, print_schedule};
use crate::lqr::fmt_row;
use anyhow::{Context, Result};
use pendulab_lti::margins::stability_margins;
use pendulab_lti::{Continuous, StateSpace};
use pendulab_plants::spec::PlantSpec;
use serde::Serialize;
use std::path::PathBuf;

#[derive(Serialize)]
pub(super) struct Margins {
    /// The gain margin \[dB\] (`None`: infinite, no phase crossing).
    gain_margin_db: Option<f64>,
    gain_crossover_rad_s: Option<f64>,
    /// The phase margin \[deg\] (`None`: infinite, no gain crossing).
    phase_margin_deg: Option<f64>,
    phase_crossover_rad_s: Option<f64>,
    delay_margin_s: Option<f64>,
    #[serde(rename = "loop")]
    loop_: &'static str,
}

#[derive(Serialize)]
pub(super) struct DesignJson {
    pub plant: &'static str,
    pub method: &'static str,
    pub file: PathBuf,
    pub designed_on: String,
    pub plant_sha256: String,
    pub states: Vec<String>,
    /// pendulab/MATLAB convention `u = −K x`.
    pub k: Vec<f64>,
    /// The book's convention `u = +K_book x`, `K_book = −K`.
    pub k_book: Vec<f64>,
    pub closed_loop_poles: Vec<[f64; 2]>,
    pub margins: Option<Margins>,
    /// `gain-schedule`'s schedule (the gain and poles above are at `ρ = 0`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub schedule: Option<ScheduleJson>,
}

/// The margins of `loop_ss` (none without a loop: `p`), the loop named as `method` breaks it.
pub(super) fn margins(
    loop_ss: Option<&StateSpace<Continuous>>,
    method: &str,
) -> Result<Option<Margins>> {
    let Some(l) = loop_ss else {
        return Ok(None);
    };
    let m = stability_margins(l).context("the loop's stability margins")?;
    let gm = m.gain_margin();
    let pm = m.phase_margin();
    Ok(Some(Margins {
        gain_margin_db: gm.map(|g| g.gain_margin_db()),
        phase_crossover_rad_s: gm.map(|g| g.frequency),
        phase_margin_deg: pm.map(|g| g.phase_margin_deg),
        gain_crossover_rad_s: pm.map(|g| g.frequency),
        delay_margin_s: m.delay_margin().map(|g| g.delay_margin),
        loop_: if method == "observer" {
            "broken at the plant input: L(s) = K (sI − A + BK + LC)⁻¹ L C (sI − A)⁻¹ B"
        } else if method == "gain-schedule" {
            "of the frozen model at ρ = 0, broken at the plant input: L(s) = K(0) (sI − Ã(0))⁻¹ B̃(0)"
        } else {
            "broken at the plant input: L(s) = K (sI − A)⁻¹ B"
        },
    }))
}

/// Prints the design's tables.
pub(super) fn print_design(out: &DesignJson, plant: &PlantSpec) {
    println!(
        "{} design on the {} pendulum ({}) → {}",
        out.method,
        plant.kind().name(),
        out.designed_on,
        out.file.display()
    );
    println!("state x = [{}]", out.states.join(", "));
    println!(
        "K      (pendulab/MATLAB, u = −K x):      {}",
        fmt_row(&out.k)
    );
    println!(
        "K_book (the book's, u = +K_book x):      {}",
        fmt_row(&out.k_book)
    );
    println!("closed-loop poles [1/s]:");
    for [re, im] in &out.closed_loop_poles {
        println!("  {re:.6} {im:+.6}j");
    }
    match &out.margins {
        Some(m) => {
            let show = |v: Option<f64>, unit: &str| match v {
                Some(x) => format!("{x:.4} {unit}"),
                None => "∞".into(),
            };
            println!("margins of the loop {}:", m.loop_);
            println!(
                "  gain margin  {} (at {})",
                show(m.gain_margin_db, "dB"),
                show(m.phase_crossover_rad_s, "rad/s")
            );
            println!(
                "  phase margin {} (at {})",
                show(m.phase_margin_deg, "°"),
                show(m.gain_crossover_rad_s, "rad/s")
            );
            println!("  delay margin {}", show(m.delay_margin_s, "s"));
        }
        None => println!("margins: none (the P loop closes the drive only)"),
    }
    if let Some(s) = &out.schedule {
        print_schedule(s);
    }
}
