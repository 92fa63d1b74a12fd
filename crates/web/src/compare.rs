//! The gain-scheduled arm servo beside the constant LQ servo (book part 2 §1.5, example 1.7,
//! `p2c15_ex7`): both run by `pendulab_control::scenario::simulate` on the same nonlinear arm,
//! with the same imperfections and the same reference steps of the arm angle.
//!
//! The gain-scheduled servo is a controller file of `kind = "gain-scheduled"` (`K(ρ) =
//! −L(ρ) X(ρ)⁻¹`, `ρ = 1 − cos θ₁`, `x_coefficients`, `l_coefficients` on `[y; w]`), read with
//! the controller-file layout `pendulab rig run` reads (`plant`, `rate_hz`, `[controller]`).
//! The page does not solve its SOS program: with 1081 variables it is far beyond the size the
//! dense interior-point method suits, and the browser's pendulab-lmi has no Clarabel
//! (`docs/web.md`); `tools/build-web` designs it natively with `pendulab design gain-schedule`
//! and the page carries the file. The constant servo is [`Method::Servo`] on the upright
//! linearisation with the weights given (the book's are the schedule's own `Q`, `R`).

use crate::design::{Method, Mode, design};
use crate::error::WebError;
use pendulab_control::scenario::simulate;
use pendulab_control::spec::ControllerSpec;
use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::PlantSpec;
use pendulab_sim::scenario::{Imperfections, ScenarioSpec, SignalSpec};

/// One compared sample: `[t, r, θ₁ gs, θ₂ gs, u gs, θ₁ lq, θ₂ lq, u lq]` (s, rad, V).
pub const COMPARED: usize = 8;

/// The `[controller]` table of a controller file as a spec.
///
/// # Errors
/// [`WebError::ControllerFile`] naming what is wrong with the text.
pub fn read_controller(text: &str) -> Result<ControllerSpec, WebError> {
    let table: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| WebError::ControllerFile(e.message().to_string()))?;
    let c = table
        .get("controller")
        .cloned()
        .ok_or_else(|| WebError::ControllerFile("no [controller] table".into()))?;
    c.try_into::<ControllerSpec>()
        .map_err(|e| WebError::ControllerFile(e.message().to_string()))
}

/// The scenario of a comparison: from rest at `θ₁ = 0`, the arm-angle reference `r(t)` =
/// `steps` (`(time s, value rad)`, each value held from its time on, 0 before the first), for
/// `duration` s, with `imperfections`.
pub fn steps_scenario(
    steps: &[(f64, f64)],
    duration: f64,
    imperfections: &Imperfections,
) -> ScenarioSpec {
    let mut scenario = ScenarioSpec::new(vec![0.0; 4], duration);
    scenario.reference = SignalSpec::Steps {
        times: steps.iter().map(|s| s.0).collect(),
        values: steps.iter().map(|s| s.1).collect(),
    };
    scenario.imperfections = imperfections.clone();
    scenario
}

/// Runs `scheduled` (a controller spec of the arm's gain-scheduled servo) and the constant LQ
/// servo of weights `q` (5, on `[y; w]`), `r` on `plant` (the arm) in `scenario` (its
/// reference drives both; [`steps_scenario`]); every `every`-th sample as [`COMPARED`]
/// numbers.
///
/// # Errors
/// [`WebError::OutOfRange`] for the cart; the design's and the runs' errors (an invalid
/// scenario, a controller file for the other plant).
pub fn compare_servos(
    plant: &PlantSpec,
    scheduled: &ControllerSpec,
    q: &[f64],
    r: f64,
    scenario: &ScenarioSpec,
    every: usize,
) -> Result<Vec<f64>, WebError> {
    if plant.kind() != PlantKind::Arm {
        return Err(WebError::OutOfRange {
            what: "plant",
            value: 0.0,
            range: "the arm (the schedule is in ρ = 1 − cos θ₁)",
        });
    }
    let constant =
        design(plant, &Method::Servo { q: q.to_vec(), r })?.controller(Mode::Balance, 0.0, 0.0);
    // The scenario's reference drives both: the file's own reference step (a servo's
    // `reference`, `step_time`) is set aside, as `simulate` takes one or the other.
    let mut scheduled = scheduled.clone();
    if let ControllerSpec::GainScheduled(c) = &mut scheduled {
        c.reference = None;
        c.step_time = None;
    }
    let gs = simulate(plant, &scheduled, scenario)?;
    let lq = simulate(plant, &constant, scenario)?;
    let every = every.max(1);
    let n = gs.t.len().min(lq.t.len());
    let mut out = Vec::with_capacity(COMPARED * n.div_ceil(every));
    for k in (0..n).step_by(every) {
        out.extend_from_slice(&[
            gs.t[k],
            gs.reference[k],
            gs.x[k][0],
            gs.x[k][1],
            gs.u[k],
            lq.x[k][0],
            lq.x[k][1],
            lq.u[k],
        ]);
    }
    Ok(out)
}
