//! `pendulab model --lab DIR [--at THETA1E_DEG]`: the linearised plant of a lab
//! (`docs/lab.md`).
//!
//! Prints `A, B, C, D` of the lab plant's upright linearisation in deviation variables
//! (`PlantParameters::linearize_upright`: `docs/model.md` §1 for the cart, eqs 3.7 and 3.21 of
//! the book; §2 for the arm at the arm angle `θ₁ₑ`), its poles (the eigenvalues of `A`), and
//! the controllability of `(A, B)`: the singular values of the controllability matrix
//! `M_c = [B, AB, A²B, A³B]` (`pendulab_lti::analysis::ctrb`), the smallest of them `σ_min` and
//! `σ_min/σ_max` (how far `M_c` is from rank deficiency, relative and absolute), and the
//! staircase decision (`StateSpace::is_controllable`). State `[q₀, q₁, q̇₀, q̇₁]` in m or rad and
//! m/s or rad/s, input the motor voltage \[V\], `C = I`, `D = 0`.

use crate::lab;
use crate::lqr::{fmt_row, rows_of};
use anyhow::{Context, Result, bail};
use pendulab_lti::analysis::{ctrb, rank};
use pendulab_plants::rig::{Coordinate, PlantKind};
use serde::Serialize;
use std::path::PathBuf;

/// Arguments of `pendulab model`.
#[derive(Debug, clap::Args)]
pub struct ModelArgs {
    /// The lab directory (holding lab.toml).
    #[arg(long)]
    pub lab: PathBuf,
    /// The arm angle θ₁ₑ of the linearisation [deg] (arm plant only; default 0).
    #[arg(long, value_name = "THETA1E_DEG", allow_hyphen_values = true)]
    pub at: Option<f64>,
    /// Print one JSON object instead of tables.
    #[arg(long)]
    pub json: bool,
}

/// The names of the plant's states as the rig log writes them (`z, theta, dz, dtheta` or
/// `theta1, theta2, dtheta1, dtheta2`).
pub(crate) fn state_names(kind: PlantKind) -> [String; 4] {
    let [q0, q1] = Coordinate::of(kind).map(Coordinate::name);
    [q0.into(), q1.into(), format!("d{q0}"), format!("d{q1}")]
}

#[derive(Serialize)]
struct Controllability {
    /// Singular values of `M_c`, descending.
    singular_values: Vec<f64>,
    sigma_min: f64,
    sigma_min_over_max: f64,
    rank: usize,
    controllable: bool,
}

#[derive(Serialize)]
struct ModelJson {
    plant: &'static str,
    at_deg: f64,
    states: [String; 4],
    input: &'static str,
    a: Vec<Vec<f64>>,
    b: Vec<Vec<f64>>,
    c: Vec<Vec<f64>>,
    d: Vec<Vec<f64>>,
    /// `[re, im]` pairs \[1/s\].
    poles: Vec<[f64; 2]>,
    controllability: Controllability,
}

/// Runs `pendulab model`.
///
/// # Errors
/// The lab file's errors ([`lab::load`]); `--at` for the cart or not finite; a failed
/// linearisation or eigenvalue computation.
pub fn run(args: &ModelArgs) -> Result<()> {
    let spec = lab::load(&args.lab)?;
    let kind = spec.kind();
    let at_deg = match (kind, args.at) {
        (PlantKind::Cart, Some(_)) => {
            bail!(
                "--at sets the arm angle θ₁ₑ; the lab's plant is the cart, whose linearisation does not depend on the cart position"
            )
        }
        (_, Some(d)) if !d.is_finite() => bail!("--at = {d}: must be a finite angle in degrees"),
        (_, at) => at.unwrap_or(0.0),
    };
    let ss = spec
        .parameters()
        .linearize_upright(at_deg.to_radians())
        .context("linearising the lab's plant")?;
    let poles = ss.poles().context("the poles of A")?;
    let mc = ctrb(ss.a(), ss.b()).context("the controllability matrix")?;
    let info = rank(&mc);
    let sigma_max = info.singular_values.first().copied().unwrap_or(0.0);
    let sigma_min = info.singular_values.last().copied().unwrap_or(0.0);
    let ctrl = Controllability {
        sigma_min,
        sigma_min_over_max: if sigma_max > 0.0 {
            sigma_min / sigma_max
        } else {
            0.0
        },
        rank: info.rank,
        controllable: ss
            .is_controllable()
            .context("the staircase form of (A, B)")?,
        singular_values: info.singular_values,
    };
    let out = ModelJson {
        plant: kind.name(),
        at_deg,
        states: state_names(kind),
        input: "v",
        a: rows_of(ss.a()),
        b: rows_of(ss.b()),
        c: rows_of(ss.c()),
        d: rows_of(ss.d()),
        poles: poles.iter().map(|p| [p.re, p.im]).collect(),
        controllability: ctrl,
    };
    if args.json {
        println!("{}", serde_json::to_string(&out)?);
        return Ok(());
    }
    let where_ = match kind {
        PlantKind::Cart => "upright".to_string(),
        PlantKind::Arm => format!("upright, θ₁ₑ = {at_deg}°"),
    };
    println!(
        "{} pendulum linearised about the {where_} (x = [{}], u = v [V])",
        kind.name(),
        out.states.join(", ")
    );
    for (name, m) in [("A", &out.a), ("B", &out.b), ("C", &out.c), ("D", &out.d)] {
        println!("{name}:");
        for row in m {
            println!("  {}", fmt_row(row));
        }
    }
    println!("poles [1/s]:");
    for [re, im] in &out.poles {
        println!("  {re:.10} {im:+.10}j");
    }
    let c = &out.controllability;
    println!(
        "controllability matrix [B AB A²B A³B]: rank {}, σ_min = {:e}, σ_min/σ_max = {:e} ({})",
        c.rank,
        c.sigma_min,
        c.sigma_min_over_max,
        if c.controllable {
            "controllable"
        } else {
            "not controllable"
        }
    );
    Ok(())
}
