//! The synthesis verbs `hinfsyn` and `h2syn` (MATLAB `hinfsyn(P, nmeas, ncon)`,
//! `h2syn(P, nmeas, ncon)`): a standard plant read as any system file, whose last `nmeas`
//! outputs are the measurements and last `ncon` inputs the controls, synthesised by Riccati
//! equations (`pendulab_lti::design`) or LMIs (`pendulab_lmi::synthesis`). The controller is
//! connected as `u = K y` (positive feedback, the lower LFT, as MATLAB and python-control);
//! `--out FILE` writes it as a system file the other verbs read.

use super::SysCommand;
use super::input::{Sys, SysArgs};
use super::verbs::{finite_or_null, pairs, print_matrix, print_poles, system_json, write_system};
use anyhow::{Context, Result, anyhow, bail};
use pendulab_lmi::synthesis::{HinfLmiOptions, h2_output_feedback_lmi, hinf_lmi, hinf_lmi_at};
use pendulab_lti::design::{GammaIteration, StandardPlant, h2_syn, hinf_syn, hinf_syn_optimal};
use pendulab_lti::norms::{h2_norm, hinf_norm};
use pendulab_lti::{Continuous, StateSpace};
use serde_json::json;
use std::path::PathBuf;

/// The synthesis method of `hinfsyn` and `h2syn`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SynthMethod {
    /// Riccati equations (Doyle–Glover–Khargonekar–Francis; Glover–Doyle for `D₁₁ ≠ 0`).
    Riccati,
    /// Linear matrix inequalities (Gahinet–Apkarian for H∞, Scherer–Gahinet–Chilali for H2).
    Lmi,
}

/// The standard-plant arguments shared by `hinfsyn` and `h2syn`.
#[derive(Debug, Clone, clap::Args)]
pub struct PlantArgs {
    #[command(flatten)]
    pub sys: SysArgs,
    /// Number of measurements y: the last NMEAS outputs of the system.
    #[arg(long)]
    pub nmeas: usize,
    /// Number of controls u: the last NCON inputs of the system.
    #[arg(long)]
    pub ncon: usize,
    /// Synthesis method.
    #[arg(long, value_enum, default_value_t = SynthMethod::Riccati)]
    pub method: SynthMethod,
    /// Write the controller (A, B, C, D) to this file (`.toml` or `.json`), a system file the
    /// other verbs read.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Print one JSON object instead of a summary.
    #[arg(long)]
    pub json: bool,
}

/// Runs `hinfsyn` or `h2syn`.
///
/// # Errors
/// The system's errors; `nmeas`/`ncon` larger than the system's outputs/inputs or zero; a
/// discrete system; an assumption of the plant that fails (the message names it); an
/// infeasible level or a failed LMI solve; a controller file that cannot be written.
pub fn run(cmd: &SysCommand) -> Result<()> {
    match cmd {
        SysCommand::Hinfsyn {
            plant,
            gamma,
            gamma_tol,
        } => hinfsyn(plant, *gamma, *gamma_tol),
        SysCommand::H2syn { plant } => h2syn(plant),
        _ => unreachable!("synth_verbs::run called for another verb"),
    }
}

fn standard_plant(args: &PlantArgs) -> Result<StandardPlant> {
    let Sys::C(sys) = args.sys.load()? else {
        bail!("the standard plant must be continuous-time (no dt)");
    };
    let (ny, nu) = (sys.ny(), sys.nu());
    if args.nmeas == 0 || args.ncon == 0 {
        bail!(
            "--nmeas {} --ncon {}: both must be at least 1 (output feedback)",
            args.nmeas,
            args.ncon
        );
    }
    if args.nmeas >= ny || args.ncon >= nu {
        bail!(
            "--nmeas {} --ncon {}: the plant has {ny} output(s) and {nu} input(s); nmeas must be \
             below the outputs and ncon below the inputs (z and w must not be empty)",
            args.nmeas,
            args.ncon
        );
    }
    Ok(StandardPlant::new(sys, args.nmeas, args.ncon)?)
}

fn hinfsyn(args: &PlantArgs, gamma: Option<f64>, gamma_tol: f64) -> Result<()> {
    let plant = standard_plant(args)?;
    if let Some(g) = gamma
        && !(g.is_finite() && g > 0.0)
    {
        bail!("--gamma {g}: must be finite and > 0");
    }
    if !(gamma_tol.is_finite() && gamma_tol > 0.0 && gamma_tol < 1.0) {
        bail!("--gamma-tol {gamma_tol}: must be in (0, 1)");
    }
    // (level, lower bound of the optimum if known, controller, closed loop)
    let (level, lower, controller, closed_loop) = match args.method {
        SynthMethod::Riccati => match gamma {
            Some(g) => {
                let k = hinf_syn(&plant, g)?;
                (g, None, k.controller, k.closed_loop)
            }
            None => {
                let opt = hinf_syn_optimal(
                    &plant,
                    &GammaIteration {
                        tolerance: gamma_tol,
                        ..GammaIteration::default()
                    },
                )?;
                (
                    opt.gamma,
                    Some(opt.gamma_infeasible),
                    opt.design.controller,
                    opt.design.closed_loop,
                )
            }
        },
        SynthMethod::Lmi => {
            let options = HinfLmiOptions::default();
            let r = match gamma {
                Some(g) => hinf_lmi_at(&plant, g, &options)?,
                None => hinf_lmi(&plant, &options)?,
            };
            let d = r.design.ok_or_else(|| {
                anyhow!(
                    "infeasible: the H∞ LMIs did not solve (status {:?}){}",
                    r.status,
                    gamma.map(|g| format!(" at γ = {g}")).unwrap_or_default()
                )
            })?;
            (d.gamma, None, d.controller, d.closed_loop)
        }
    };
    let achieved = hinf_norm(&closed_loop, 1e-10)?;
    let mut extra = json!({
        "gamma": level,
        "closed_loop_hinf": finite_or_null(achieved.value),
    });
    if let Some(lo) = lower {
        extra["gamma_lower_bound"] = finite_or_null(lo);
    }
    report("hinfsyn", args, &controller, &closed_loop, extra, |out| {
        println!("γ = {level:.10}");
        if let Some(lo) = lower {
            println!("  (the optimum lies in ({lo:.10}, {level:.10}])");
        }
        println!(
            "closed-loop ‖T_zw‖∞ = {:.10}",
            out["closed_loop_hinf"].as_f64().unwrap_or(f64::INFINITY)
        );
    })
}

fn h2syn(args: &PlantArgs) -> Result<()> {
    let plant = standard_plant(args)?;
    let (cost, controller, closed_loop) = match args.method {
        SynthMethod::Riccati => {
            let k = h2_syn(&plant)?;
            (k.norm, k.controller, k.closed_loop)
        }
        SynthMethod::Lmi => {
            let r = h2_output_feedback_lmi(&plant, &Default::default())?;
            let (Some(norm), Some(d)) = (r.norm, r.design) else {
                bail!(
                    "infeasible: the H2 LMIs did not solve (status {:?})",
                    r.status
                );
            };
            (norm, d.controller, d.closed_loop)
        }
    };
    let achieved = h2_norm(&closed_loop)?;
    let extra = json!({ "h2": cost, "closed_loop_h2": finite_or_null(achieved) });
    report("h2syn", args, &controller, &closed_loop, extra, |_| {
        println!("H2 cost ‖T_zw‖₂ = {cost:.10}");
        println!("closed-loop ‖T_zw‖₂ = {achieved:.10}");
    })
}

/// Prints the controller, the closed-loop poles and the verb's figures (`extra`, printed by
/// `summary` unless `--json`), and writes the controller with `--out`.
fn report(
    verb: &str,
    args: &PlantArgs,
    controller: &StateSpace<Continuous>,
    closed_loop: &StateSpace<Continuous>,
    extra: serde_json::Value,
    summary: impl FnOnce(&serde_json::Value),
) -> Result<()> {
    let k = Sys::C(controller.clone());
    if let Some(path) = &args.out {
        write_system(&k, path).with_context(|| format!("{verb}: writing the controller"))?;
    }
    let poles = closed_loop.poles()?;
    if args.json {
        let mut out = extra;
        out["controller"] = system_json(&k);
        out["closed_loop_poles"] = json!(pairs(&poles));
        out["method"] = json!(match args.method {
            SynthMethod::Riccati => "riccati",
            SynthMethod::Lmi => "lmi",
        });
        println!("{out}");
        return Ok(());
    }
    summary(&extra);
    println!(
        "controller u = K y: {} state(s), {} input(s), {} output(s)",
        controller.nx(),
        controller.nu(),
        controller.ny()
    );
    let (a, b, c, d) = k.matrices();
    for (name, m) in [("A", a), ("B", b), ("C", c), ("D", d)] {
        print_matrix(name, m);
    }
    print_poles("closed-loop poles", &poles);
    if let Some(path) = &args.out {
        println!("written: {}", path.display());
    }
    Ok(())
}
