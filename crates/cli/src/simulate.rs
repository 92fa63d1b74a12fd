//! `pendulab simulate --lab DIR --controller C.toml [--scenario S.toml] [--out DIR2]`: the
//! nonlinear sampled-data simulation of a lab's plant under a controller (`docs/lab.md`).
//!
//! The controller file is a rig controller file (`docs/rig/examples/`, read by
//! `pendulab_rig::config::load`): `plant`, `rate_hz`, the `[controller]` table
//! (`pendulab_control::spec::ControllerSpec`) and the rig's safety tables. Its `plant` must be
//! the lab's. The scenario file is a `pendulab_sim::scenario::ScenarioSpec`; without one the
//! run starts at rest with the pendulum [`DEFAULT_ANGLE_DEG`] from upright, lasts
//! [`DEFAULT_DURATION`] and has the rig's quantisers, pseudo-differentiator, saturation and
//! D/A on (`Imperfections::with_quantizer`, `docs/model.md` §3). A scenario without
//! `sample_time` runs at the controller file's rate. The one simulate path
//! `pendulab_control::scenario::simulate` runs it; `run.csv` gets one row per sample:
//! `t` \[s\], the plant state named as in the rig log (`z, theta, dz, dtheta` or
//! `theta1, theta2, dtheta1, dtheta2`, SI units and rad), `v` the voltage applied to the plant
//! and `u_ctrl` the controller's command \[V\]; `run.svg` draws the drive position, the
//! pendulum angle and both voltages over time (`pendulab_plot::TimeResponse`). Nothing is
//! written unless the run and its figure succeeded.

use crate::lab;
use crate::model::state_names;
use anyhow::{Context, Result};
use pendulab_control::scenario::{Run, SETTLING_FRACTION, simulate};
use pendulab_lti::{Mat, Trajectory};
use pendulab_plants::rig::PlantKind;
use pendulab_plot::{Channel, SignalPanel, TimeResponse};
use pendulab_sim::scenario::{Imperfections, ScenarioSpec};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The default scenario's initial pendulum angle from upright \[deg\].
pub const DEFAULT_ANGLE_DEG: f64 = 5.0;
/// The default scenario's length \[s\].
pub const DEFAULT_DURATION: f64 = 5.0;

/// Arguments of `pendulab simulate`.
#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// The lab directory (holding lab.toml).
    #[arg(long)]
    pub lab: PathBuf,
    /// The controller file (a rig controller file: plant, rate_hz, [controller], [safety]).
    #[arg(long)]
    pub controller: PathBuf,
    /// The scenario file (initial_state, duration, reference, disturbance, [imperfections]);
    /// default: 5° from upright, 5 s, the rig's quantisers, saturation and D/A on.
    #[arg(long)]
    pub scenario: Option<PathBuf>,
    /// Where to write run.csv (default: LAB/runs/<controller file's stem>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object instead of a summary table.
    #[arg(long)]
    pub json: bool,
}

/// The default scenario (module documentation); both plants' states are `[q₀, q₁, q̇₀, q̇₁]`
/// with the pendulum angle `q₁` second.
pub fn default_scenario() -> ScenarioSpec {
    let mut s = ScenarioSpec::new(
        vec![0.0, DEFAULT_ANGLE_DEG.to_radians(), 0.0, 0.0],
        DEFAULT_DURATION,
    );
    s.imperfections = Imperfections::with_quantizer();
    s
}

#[derive(Serialize)]
struct SummaryJson {
    plant: &'static str,
    controller: String,
    csv: PathBuf,
    figure: PathBuf,
    samples: usize,
    ts: f64,
    /// Settling time of `q₀` \[s\] within [`SETTLING_FRACTION`] of its largest deviation.
    settling_time: Option<f64>,
    overshoot_percent: Option<f64>,
    peak_input: f64,
    peak_command: f64,
    time_in_saturation: f64,
    max_angle_deviation_deg: f64,
    left_angle_window: Option<bool>,
    left_travel: bool,
    final_state: Vec<f64>,
    /// Differences between the controller's design record and the lab's plant.
    design_warnings: Vec<String>,
}

/// The run as CSV text (module documentation).
fn csv(kind: PlantKind, run: &Run) -> String {
    let mut s = state_names(kind).join(",");
    s.insert_str(0, "t,");
    s.push_str(",v,u_ctrl\n");
    for k in 0..run.t.len() {
        let _ = write!(s, "{}", run.t[k]);
        for v in &run.x[k] {
            let _ = write!(s, ",{v}");
        }
        let _ = writeln!(s, ",{},{}", run.u[k], run.command[k]);
    }
    s
}

/// The run's figure as SVG text: `q₀` (m, or degrees for the arm), the pendulum angle in
/// degrees, and the applied voltage `v` with the command `u_ctrl`.
fn figure(kind: PlantKind, run: &Run) -> Result<String> {
    let n = run.t.len();
    let x = Mat::from_fn(n, 4, |k, i| run.x[k][i]);
    let u = Mat::from_fn(n, 2, |k, i| if i == 0 { run.u[k] } else { run.command[k] });
    let traj =
        Trajectory::new(run.t.clone(), x, u, Mat::zeros(n, 0)).context("the run's trajectory")?;
    let deg = 180.0 / std::f64::consts::PI;
    let drive = match kind {
        PlantKind::Cart => SignalPanel::new(Channel::State(0), "z [m]"),
        PlantKind::Arm => SignalPanel::new(Channel::State(0), "θ₁ [deg]").scaled(deg),
    };
    let angle = match kind {
        PlantKind::Cart => "θ [deg]",
        PlantKind::Arm => "θ₂ [deg]",
    };
    TimeResponse::new()
        .run("simulation", &traj)
        .panel(drive)
        .panel(SignalPanel::new(Channel::State(1), angle).scaled(deg))
        .panel(
            SignalPanel::new(Channel::Input(0), "voltage [V]")
                .named("v")
                .with(Channel::Input(1), "u_ctrl"),
        )
        .figure()
        .and_then(|f| f.to_svg())
        .context("drawing the run")
}

fn read(path: &Path, what: &str) -> Result<String> {
    std::fs::read_to_string(path)
        .with_context(|| format!("cannot read the {what} file {}", path.display()))
}

/// Runs `pendulab simulate`.
///
/// # Errors
/// The lab file's errors; an unreadable or invalid controller or scenario file (naming the file
/// and key); a controller file for the other plant; a failed design or simulation; an output
/// file that cannot be written.
pub fn run(args: &SimulateArgs) -> Result<()> {
    let plant = lab::load(&args.lab)?;
    let kind = plant.kind();
    let text = read(&args.controller, "controller")?;
    let loaded = pendulab_rig::config::load(&text)
        .with_context(|| format!("in {}", args.controller.display()))?;
    lab::check_controller_plant(&args.controller, loaded.plant, &plant)?;
    let mut scenario = match &args.scenario {
        Some(p) => ScenarioSpec::from_toml(&read(p, "scenario")?)
            .with_context(|| format!("in {}", p.display()))?,
        None => default_scenario(),
    };
    scenario.sample_time.get_or_insert(loaded.ts);
    let run = simulate(&plant, &loaded.spec, &scenario).context("simulating")?;
    for w in &run.design_warnings {
        eprintln!("warning: {}: {w}", args.controller.display());
    }

    let stem = args
        .controller
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "run".into());
    let out_dir = args
        .out
        .clone()
        .unwrap_or_else(|| args.lab.join("runs").join(&stem));
    std::fs::create_dir_all(&out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;
    let svg = figure(kind, &run)?;
    let csv_path = out_dir.join("run.csv");
    let svg_path = out_dir.join("run.svg");
    lab::write_whole(&csv_path, csv(kind, &run).as_bytes())?;
    lab::write_whole(&svg_path, svg.as_bytes())?;

    let s = &run.summary;
    let out = SummaryJson {
        plant: kind.name(),
        controller: loaded.spec.kind().to_string(),
        csv: csv_path,
        figure: svg_path,
        samples: run.t.len(),
        ts: run.ts,
        settling_time: s.settling_time,
        overshoot_percent: s.overshoot_percent,
        peak_input: s.peak_input,
        peak_command: s.peak_command,
        time_in_saturation: s.time_in_saturation,
        max_angle_deviation_deg: s.max_angle_deviation.to_degrees(),
        left_angle_window: s.left_angle_window,
        left_travel: s.left_travel,
        final_state: s.final_state.clone(),
        design_warnings: run.design_warnings.iter().map(|w| w.to_string()).collect(),
    };
    if args.json {
        println!("{}", serde_json::to_string(&out)?);
        return Ok(());
    }
    let opt = |v: Option<f64>, unit: &str| match v {
        Some(x) => format!("{x:.4} {unit}"),
        None => "-".into(),
    };
    println!(
        "{} pendulum, {} controller, {} samples at {} s → {}",
        out.plant,
        out.controller,
        out.samples,
        out.ts,
        out.csv.display()
    );
    println!(
        "  settling time ({:.0} % band)  {}",
        100.0 * SETTLING_FRACTION,
        opt(out.settling_time, "s")
    );
    println!(
        "  overshoot               {}",
        opt(out.overshoot_percent, "%")
    );
    println!("  peak |v| applied        {:.4} V", out.peak_input);
    println!("  peak |u| commanded      {:.4} V", out.peak_command);
    println!("  time in saturation      {:.4} s", out.time_in_saturation);
    println!(
        "  max |pendulum angle|    {:.4}°{}",
        out.max_angle_deviation_deg,
        match out.left_angle_window {
            Some(true) => " (left the angle window)",
            _ => "",
        }
    );
    let names = state_names(kind);
    let fin: Vec<String> = names
        .iter()
        .zip(&out.final_state)
        .map(|(n, v)| format!("{n} = {v:.3e}"))
        .collect();
    println!("  final state             {}", fin.join(", "));
    Ok(())
}
