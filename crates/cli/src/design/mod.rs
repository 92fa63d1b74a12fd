//! `pendulab design lqr|place|servo|lmi-servo|robust|gain-schedule|observer|p --lab DIR …`: a controller designed on a lab's plant,
//! written as a rig controller file that `pendulab simulate` and `pendulab rig run` take
//! (`docs/lab.md`).
//!
//! Every design works on the lab plant's linearisation about the upright
//! (`PlantParameters::linearize_upright`, `docs/model.md` §1–2; the arm at `θ₁ₑ = 0`), state
//! `x = [q₀, q₁, q̇₀, q̇₁]`, input the motor voltage `v` \[V\]:
//!
//! - `lqr --q "q0 q1 q2 q3" --r R`: the continuous LQ regulator (`pendulab_lti::design::lqr`,
//!   `Q = diag(q)`, book part 1 ch. 5), `u = −K x`;
//! - `place --poles "p1 p2 p3 p4"`: pole placement (`pendulab_lti::design::place`, MATLAB
//!   `place`); complex poles as `-3+2j` and `-3-2j`;
//! - `servo --q "q0 q1 q2 q3 qw" --r R [--reference M --step-time S]`: the LQ integral servo
//!   on the drive position (`pendulab_lti::design::lq_servo` on `[x; ∫(r − q₀)dt]`, book
//!   part 1 ch. 7), `u = −K₁ x − K₂ w`;
//! - `lmi-servo --q "q0 q1 q2 q3 qw" --r R [--reference M --step-time S]`: the same servo
//!   by the LMI guaranteed-cost LQ design on `[x; w]` (`pendulab_lmi::synthesis::lq_state_feedback`,
//!   maximise `tr X` under the LQ LMI, `K = −L X⁻¹`; book part 2 §1.2.2, example 1.4), whose
//!   gain approaches the Riccati one as the margin and the solver tolerance go to zero; the file
//!   is the same `kind = "lq-servo"`;
//! - `robust --q "q0 q1 q2 q3" --r R --vary NAME=±P% [--vary …]`: one gain with the LMI
//!   guaranteed LQ cost at every vertex of the box of parameters `value · (1 ± P/100)` (1 to 4
//!   parameters, `2ⁿ` vertices, each the upright linearisation;
//!   `pendulab_lmi::synthesis::robust_state_feedback`, book part 2 §1.3), so the bound holds
//!   on the whole box; `--decay-rate α` and `--speed-limit β` add the pole regions
//!   `−β < Re λ < −α` at every vertex (the book's examples use both: maximising `tr X`
//!   alone can give very fast poles and large gains when `Q` is singular);
//!   `kind = "state-feedback"`, the poles printed the lab plant's;
//! - `observer (--q "q0 q1 q2 q3" --r R | --poles "p1 p2 p3 p4") --observer-poles "o1 o2 o3 o4"`:
//!   the state feedback of `lqr` or `place` with a full-order observer of the encoder
//!   positions `[q₀, q₁]` (`C = [I₂ 0]`), `L` placing `A − LC` at the observer poles
//!   (`pendulab_lti::design::place_observer`, book part 1 ch. 7 §7.4), `u = −K x̂`; the file is
//!   `kind = "observer"` with `k` and `l`, its poles the 8 of plant and controller
//!   (`pendulab_control::spec::observer_design`) and its loop
//!   `K (sI − A + BK + LC)⁻¹ L C (sI − A)⁻¹ B`;
//! - `gain-schedule [--q "q0 q1 q2 q3 qw" --r R --theta1-max-deg Θ --theta10-max-deg Θ0
//!   --rho-dot-max ν --gamma-relax δ --reference RAD --step-time S]` (arm only): the
//!   gain-scheduled LQ integral servo of book part 2 §1.5 (example 1.7,
//!   `p2c15_ex7_adip_oc_gs_servo`) on the lab's arm: the LPV model `A(ρ) = A₀ + ρA₁`,
//!   `B(ρ) = B₀ + ρB₁`, `ρ = 1 − cos θ₁` (`ArmPendulum::lpv`, `docs/model.md` §2) augmented
//!   with `w = ∫(r − θ₁) dt`, `K(ρ) = −L(ρ)X(ρ)⁻¹` with `X`, `L` quadratic in `ρ` (degree 2,
//!   as the book) by the SOS program `pendulab_lmi::synthesis::gain_scheduled_lq`: cost bound
//!   `γ` minimised for `|θ₁| ≤ Θ`, `|θ₁(0)| ≤ Θ0`, `|ρ̇| ≤ ν`, then re-solved with
//!   `γ ≤ (1 + δ)γ*`. The defaults are the M-file's (`Q = diag(0.1, 1, 0.001, 0.001, 4)`,
//!   `R = 1`, 65°, 65°, 0.75 1/s, 0.06). The file is `kind = "gain-scheduled"` with
//!   `x_coefficients`, `l_coefficients`; the output adds the schedule: `K(ρ)` at five
//!   angles from 0 to Θ (both sign conventions) and the closed-loop poles of the frozen models
//!   at the range's ends `ρ = 0` and `ρ = 1 − cos Θ`; the top-level gain, poles and margins
//!   are those at `ρ = 0` (the upright). The cart's linearisation does not depend on its
//!   position: a cart lab is refused;
//! - `p --kp KP --target R`: the P-control step of the drive, `u = −k_P (q₀ − r)`, the book's
//!   identification experiment (part 1 §3.2) to run with the pendulum hanging
//!   (`pendulab rig run --hanging`).
//!
//! The file (default `DIR/designs/<method>.toml`) is a controller file
//! (`pendulab_rig::config`): `plant`, `rate_hz`, `[controller]` with the gain in the
//! library's sign (`k`, or `k1`, `k2`) and the design record `[controller.designed_for]`
//! (`pendulab_control::spec::DesignRecord`: the plant kind, its parameters and their
//! provenance, the upright operating point, the method and its inputs), which `simulate` and
//! `rig run` check against the plant they run on (another plant kind is an error, other
//! parameter values a warning); a comment header says the same in words, with the SHA-256 of
//! the lab's plant table. The output prints the gain in both sign conventions,
//! labelled — pendulab/MATLAB `u = −K x`, the book's `u = +K_book x` with `K_book = −K` — the
//! closed-loop poles (eigenvalues of `A − BK`, of the augmented servo loop for `servo`), and
//! the stability margins of the loop broken at the plant input, `L(s) = K (sI − A)⁻¹ B`
//! (`pendulab_lti::margins::stability_margins`; for the servo the augmented loop
//! `[K₁ K₂] (sI − A_aug)⁻¹ B_aug`; none for `p`, whose loop excludes the pendulum).
//!
//! A design request that does not give a stable closed loop (a pole not in the open left
//! half-plane, a Riccati equation without a stabilising solution), or a weight, pole or gain
//! that is not a finite number of the right count, is an error naming it; nothing is written.
//! The file is checked by reading it back as the rig would (`pendulab_rig::config::load`) and
//! building its controller on the lab's plant (`pendulab_control::spec::build_for`) before it
//! is written whole.

mod file;
mod inputs;
mod methods;
mod report;
mod robust;
mod schedule;

use crate::lab;
use crate::model::state_names;
use anyhow::{Context, Result, bail};
use pendulab_control::spec::DesignInput;
use pendulab_lti::{Complex64, Continuous, StateSpace};
use pendulab_plants::spec::PlantSpec;
use std::path::PathBuf;

/// What a method gives.
struct Designed {
    /// The `[controller]` table's keys.
    table: String,
    /// `K` as one row (library sign, `u = −K x`).
    k: Vec<f64>,
    /// The closed-loop poles \[1/s\].
    poles: Vec<Complex64>,
    /// The loop broken at the plant input, for the margins (`None`: no margins).
    loop_ss: Option<StateSpace<Continuous>>,
    /// The inputs in words (the header's `Method:` line).
    inputs: String,
    /// Extra lines of the header.
    note: &'static str,
    /// The inputs for the design record.
    record: Vec<(String, DesignInput)>,
    /// `gain-schedule`'s schedule, printed after the gain at `ρ = 0`.
    schedule: Option<schedule::ScheduleJson>,
}

/// Arguments of `pendulab design`.
#[derive(Debug, clap::Args)]
pub struct DesignArgs {
    #[command(subcommand)]
    method: DesignMethod,
}

/// What every design takes.
#[derive(Debug, clap::Args)]
struct Common {
    /// The lab directory (holding lab.toml): the plant designed on.
    #[arg(long)]
    lab: PathBuf,
    /// Where to write the controller file (default: LAB/designs/<method>.toml).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Loop rate of the controller file [Hz] (default: 1/the lab's rig.sample_time).
    #[arg(long)]
    rate_hz: Option<f64>,
    /// Print one JSON object instead of tables.
    #[arg(long)]
    json: bool,
}

/// What the servo designs (`servo`, `lmi-servo`) take.
#[derive(Debug, clap::Args)]
struct ServoArgs {
    /// Diagonal of Q, five weights for [q0, q1, dq0, dq1, w], w = ∫(r − q0) dt.
    #[arg(long, allow_hyphen_values = true)]
    q: String,
    /// R (> 0).
    #[arg(long)]
    r: f64,
    /// The servo reference of q0 [m or rad] (default 0).
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    reference: f64,
    /// Time of the reference step [s] (default 0).
    #[arg(long, default_value_t = 0.0)]
    step_time: f64,
}

/// What `gain-schedule` takes (defaults: `p2c15_ex7_adip_oc_gs_servo.m`).
#[derive(Debug, clap::Args)]
struct ScheduleArgs {
    /// Diagonal of Q, five weights for [θ1, θ2, dθ1, dθ2, w], w = ∫(r − θ1) dt.
    #[arg(
        long,
        allow_hyphen_values = true,
        default_value = "0.1 1 0.001 0.001 4"
    )]
    q: String,
    /// R (> 0).
    #[arg(long, default_value_t = 1.0)]
    r: f64,
    /// The design range |θ1| ≤ this [deg], 0 < Θ < 90 (the M-file's th1_max): ρ = 1 − cos θ1
    /// from 0 to 1 − cos Θ.
    #[arg(long, default_value_t = 65.0)]
    theta1_max_deg: f64,
    /// The initial arm angles |θ1(0)| ≤ this [deg] over which the cost bound γ holds
    /// (the M-file's th10_max), 0 < Θ0 < 90; default: --theta1-max-deg.
    #[arg(long)]
    theta10_max_deg: Option<f64>,
    /// The rate bound |dρ/dt| ≤ ν [1/s] (the M-file's drho_max), ≥ 0.
    #[arg(long, default_value_t = 0.75)]
    rho_dot_max: f64,
    /// The second solve's cap γ ≤ (1 + δ) γ* (the M-file's 1.06: δ = 0.06), ≥ 0.
    #[arg(long, default_value_t = 0.06)]
    gamma_relax: f64,
    /// The servo reference of θ1 [rad] (default 0).
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    reference: f64,
    /// Time of the reference step [s] (default 0).
    #[arg(long, default_value_t = 0.0)]
    step_time: f64,
}

#[derive(Debug, clap::Subcommand)]
enum DesignMethod {
    /// LQ regulator: Q = diag(--q), R = --r (u = −K x).
    Lqr {
        #[command(flatten)]
        common: Common,
        /// Diagonal of Q, four weights for [q0, q1, dq0, dq1] (space or comma separated).
        #[arg(long, allow_hyphen_values = true)]
        q: String,
        /// R (> 0).
        #[arg(long)]
        r: f64,
    },
    /// Pole placement: four closed-loop poles (complex as -3+2j, with its conjugate).
    Place {
        #[command(flatten)]
        common: Common,
        /// The poles [1/s], space or comma separated.
        #[arg(long, allow_hyphen_values = true)]
        poles: String,
    },
    /// LQ integral servo of the drive position: Q = diag(--q) on [x; w], R = --r.
    Servo {
        #[command(flatten)]
        common: Common,
        #[command(flatten)]
        servo: ServoArgs,
    },
    /// Observer-based output feedback: u = −K x̂, K by LQR (--q, --r) or placement (--poles),
    /// x̂ from a full-order observer of [q0, q1] with A − LC at --observer-poles.
    Observer {
        #[command(flatten)]
        common: Common,
        /// Diagonal of Q, four weights for [q0, q1, dq0, dq1] (with --r).
        #[arg(long, allow_hyphen_values = true)]
        q: Option<String>,
        /// R (> 0, with --q).
        #[arg(long)]
        r: Option<f64>,
        /// Four closed-loop poles of A − BK [1/s] (instead of --q, --r).
        #[arg(long, allow_hyphen_values = true)]
        poles: Option<String>,
        /// Four observer poles, eigenvalues of A − LC [1/s].
        #[arg(long, allow_hyphen_values = true)]
        observer_poles: String,
    },
    /// LMI LQ integral servo of the drive position (book part 2 §1.2.2): the guaranteed-cost
    /// LQ design by LMIs on [x; w], Q = diag(--q), R = --r.
    LmiServo {
        #[command(flatten)]
        common: Common,
        #[command(flatten)]
        servo: ServoArgs,
    },
    /// Robust LQ state feedback (book part 2 §1.3): one gain with the LMI guaranteed LQ cost at
    /// every vertex of a box of parameters around the lab's values, u = −K x.
    Robust {
        #[command(flatten)]
        common: Common,
        /// Diagonal of Q, four weights for [q0, q1, dq0, dq1].
        #[arg(long, allow_hyphen_values = true)]
        q: String,
        /// R (> 0).
        #[arg(long)]
        r: f64,
        /// A parameter's range, NAME=±P% (also NAME=+-P%), 0 < P < 100; repeat for each
        /// parameter (1 to 4), the vertices being every combination of the ends.
        #[arg(long = "vary", required = true)]
        vary: Vec<String>,
        /// Decay rate α > 0 [1/s]: every vertex's poles with Re λ < −α.
        #[arg(long)]
        decay_rate: Option<f64>,
        /// Speed limit β > 0 [1/s]: every vertex's poles with Re λ > −β (bounds the gain; the
        /// book's examples use one).
        #[arg(long)]
        speed_limit: Option<f64>,
    },
    /// Gain-scheduled LQ integral servo of the arm (book part 2 §1.5, example 1.7): K(ρ) =
    /// −L(ρ) X(ρ)⁻¹, ρ = 1 − cos θ1, by the book's SOS program; the defaults are the M-file's.
    GainSchedule {
        #[command(flatten)]
        common: Common,
        #[command(flatten)]
        schedule: ScheduleArgs,
    },
    /// P control of the drive, u = −kP (q0 − target): the identification experiment, run
    /// with the pendulum hanging (rig run --hanging).
    P {
        #[command(flatten)]
        common: Common,
        /// The P gain kP [V/m or V/rad] (> 0).
        #[arg(long)]
        kp: f64,
        /// The drive's target [m or rad].
        #[arg(long, allow_hyphen_values = true)]
        target: f64,
    },
}

impl DesignMethod {
    /// The options every method takes and the method's name (the file's default stem and the
    /// design record's `method`).
    fn common_and_name(&self) -> (&Common, &'static str) {
        match self {
            DesignMethod::Lqr { common, .. } => (common, "lqr"),
            DesignMethod::Place { common, .. } => (common, "place"),
            DesignMethod::Servo { common, .. } => (common, "servo"),
            DesignMethod::LmiServo { common, .. } => (common, "lmi-servo"),
            DesignMethod::Robust { common, .. } => (common, "robust"),
            DesignMethod::P { common, .. } => (common, "p"),
            DesignMethod::Observer { common, .. } => (common, "observer"),
            DesignMethod::GainSchedule { common, .. } => (common, "gain-schedule"),
        }
    }

    /// The method's design on the lab's `plant`, `ss` its upright linearisation.
    fn design(&self, plant: &PlantSpec, ss: &StateSpace<Continuous>) -> Result<Designed> {
        match self {
            DesignMethod::Lqr { q, r, .. } => methods::lqr(ss, q, *r),
            DesignMethod::Place { poles, .. } => methods::place(ss, poles),
            DesignMethod::Servo { servo, .. } => methods::servo(ss, servo, false),
            DesignMethod::LmiServo { servo, .. } => methods::servo(ss, servo, true),
            DesignMethod::Robust {
                q,
                r,
                vary,
                decay_rate,
                speed_limit,
                ..
            } => robust::robust(
                plant,
                ss,
                &robust::RobustArgs {
                    q,
                    r: *r,
                    vary,
                    decay_rate: *decay_rate,
                    speed_limit: *speed_limit,
                },
            ),
            DesignMethod::Observer {
                q,
                r,
                poles,
                observer_poles,
                ..
            } => methods::observer(
                plant,
                ss,
                q.as_deref(),
                *r,
                poles.as_deref(),
                observer_poles,
            ),
            DesignMethod::GainSchedule { schedule: sa, .. } => {
                schedule::gain_schedule_method(plant, ss, sa)
            }
            DesignMethod::P { kp, target, .. } => methods::p_step(ss, *kp, *target),
        }
    }
}

/// Runs `pendulab design`.
///
/// # Errors
/// The lab's errors; an argument that is not what it must be; a design without a stable
/// closed loop; the file rejected when read back; a file that cannot be written.
pub fn run(args: &DesignArgs) -> Result<()> {
    let (common, method) = args.method.common_and_name();
    let plant = lab::load(&common.lab)?;
    let kind = plant.kind();
    let rate_hz = common.rate_hz.unwrap_or(1.0 / plant.rig().sample_time);
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        bail!("--rate-hz {rate_hz}: must be a positive number of Hz");
    }
    let ss = plant
        .parameters()
        .linearize_upright(0.0)
        .context("linearising the lab's plant")?;
    let d = args.method.design(&plant, &ss)?;
    let file = file::controller_file(&plant, &common.lab, method, rate_hz, &d)?;
    if let Some(bad) = d.poles.iter().find(|p| p.re >= 0.0) {
        bail!(
            "{method}: the closed loop has the pole {bad} outside the open left half-plane; nothing written"
        );
    }
    let margins = report::margins(d.loop_ss.as_ref(), method)?;
    let out_path = common
        .out
        .clone()
        .unwrap_or_else(|| common.lab.join("designs").join(format!("{method}.toml")));
    file::write_file(&out_path, &file.text)?;

    let k_book: Vec<f64> = d.k.iter().map(|x| -x).collect();
    let mut states: Vec<String> = state_names(kind).into_iter().collect();
    if matches!(method, "servo" | "lmi-servo" | "gain-schedule") {
        states.push("w".into());
    }
    let out = report::DesignJson {
        plant: kind.name(),
        method,
        file: out_path,
        designed_on: file.designed_on,
        plant_sha256: file.plant_sha256,
        states,
        k: d.k,
        k_book,
        closed_loop_poles: d.poles.iter().map(|p| [p.re, p.im]).collect(),
        margins,
        schedule: d.schedule,
    };
    if common.json {
        println!("{}", serde_json::to_string(&out)?);
        return Ok(());
    }
    report::print_design(&out, &plant);
    Ok(())
}
