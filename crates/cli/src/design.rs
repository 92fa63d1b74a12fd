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

use crate::lab;
use crate::lqr::fmt_row;
use crate::model::state_names;
use anyhow::{Context, Result, bail};
use pendulab_control::spec::design::{
    UprightDesign, drive_servo_model, lqr_upright, place_upright, pole_inputs, servo_upright,
    weight_inputs,
};
use pendulab_control::spec::{
    ControllerSpec, DesignInput, DesignRecord, ObserverSpec, build_for, observer_design,
};
use pendulab_lmi::SolveOptions;
use pendulab_lmi::synthesis::{
    GainScheduleSpec, LpvPlant, LqWeights, Region, ScheduledGain, Vertex, gain_scheduled_lq,
    lq_state_feedback, robust_state_feedback,
};
use pendulab_lti::design::{integral_augmentation, place_observer};
use pendulab_lti::margins::stability_margins;
use pendulab_lti::{Complex64, Mat, StateSpace};
use pendulab_plants::ArmPendulum;
use pendulab_plants::spec::{PlantParameters, PlantSpec};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// What a method gives: the `[controller]` table's keys, `K` as one row, the closed-loop
/// poles, the loop for the margins (if any), the inputs in words, extra header lines, and the
/// inputs for the design record.
type Designed = (
    String,
    Vec<f64>,
    Vec<Complex64>,
    Option<StateSpace<pendulab_lti::Continuous>>,
    String,
    &'static str,
    Vec<(String, DesignInput)>,
);

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

/// Numbers separated by spaces or commas, each finite, `n` of them; errors name `flag`.
fn numbers(flag: &str, text: &str, n: usize) -> Result<Vec<f64>> {
    let v = text
        .split([' ', ',', ';'])
        .filter(|s| !s.trim().is_empty())
        .map(|s| {
            let x: f64 = s
                .trim()
                .parse()
                .with_context(|| format!("{flag}: '{s}' is not a number"))?;
            if !x.is_finite() {
                bail!("{flag}: {x} is not a finite number");
            }
            Ok(x)
        })
        .collect::<Result<Vec<f64>>>()?;
    if v.len() != n {
        bail!(
            "{flag}: {n} numbers expected, found {} in '{text}'",
            v.len()
        );
    }
    Ok(v)
}

/// The LQ regulator `Q = diag(q)` (four weights ≥ 0), `R = r` (> 0) on `ss`
/// (`pendulab_control::spec::design`), with the weights; errors name the flag or the Riccati
/// equation without a stabilising solution.
fn lqr_design(
    ss: &StateSpace<pendulab_lti::Continuous>,
    q: &str,
    r: f64,
) -> Result<(UprightDesign, Vec<f64>)> {
    let qv = numbers("--q", q, 4)?;
    if qv.iter().any(|&x| x < 0.0) {
        bail!("--q {q}: the weights must be ≥ 0");
    }
    if !(r.is_finite() && r > 0.0) {
        bail!("--r {r}: must be a finite number > 0");
    }
    let l = lqr_upright(ss, &qv, r)
        .with_context(|| format!("lqr with Q = diag({q}), R = {r}: no stabilising solution"))?;
    Ok((l, qv))
}

/// Four finite poles in the open left half-plane, written as [`parse_pole`] reads them;
/// errors name `flag`.
fn four_poles(flag: &str, text: &str) -> Result<Vec<Complex64>> {
    let p: Vec<Complex64> = text
        .split([' ', ',', ';'])
        .filter(|s| !s.trim().is_empty())
        .map(|s| {
            parse_pole(s).with_context(|| {
                format!("{flag}: '{s}' is not a pole (write -3, or -3+2j with -3-2j)")
            })
        })
        .collect::<Result<_>>()?;
    if p.len() != 4 {
        bail!("{flag}: 4 poles expected, found {} in '{text}'", p.len());
    }
    if let Some(bad) = p.iter().find(|z| !(z.re.is_finite() && z.im.is_finite())) {
        bail!("{flag}: {bad} is not finite");
    }
    if let Some(bad) = p.iter().find(|z| z.re >= 0.0) {
        bail!(
            "{flag}: {bad} is not in the open left half-plane: the closed loop would not be stable"
        );
    }
    Ok(p)
}

/// `NAME=±P%` (or `NAME=+-P%`): the parameter `NAME` of `nominal` and the fraction `P/100`,
/// `0 < P < 100`; errors name the argument.
fn parse_vary(text: &str, nominal: &[(String, f64)]) -> Result<(String, f64)> {
    let Some((name, range)) = text.split_once('=') else {
        bail!("--vary {text}: write NAME=±P%, e.g. m_p=±10%");
    };
    let name = name.trim();
    if !nominal.iter().any(|(n, _)| n == name) {
        let names: Vec<&str> = nominal.iter().map(|(n, _)| n.as_str()).collect();
        bail!(
            "--vary {text}: '{name}' is not a parameter of the lab's plant ({})",
            names.join(", ")
        );
    }
    let p = range
        .trim()
        .strip_prefix('±')
        .or_else(|| range.trim().strip_prefix("+-"))
        .and_then(|r| r.strip_suffix('%'))
        .and_then(|r| r.trim().parse::<f64>().ok());
    match p {
        Some(p) if p > 0.0 && p < 100.0 => Ok((name.to_string(), p / 100.0)),
        _ => bail!("--vary {text}: the range must be ±P% with 0 < P < 100"),
    }
}

/// The upright linearisations at the `2ⁿ` vertices of the box `value · (1 ± fraction)` of the
/// `n` varied parameters (the others at their lab values), in binary order of the ends
/// (first parameter slowest).
fn box_vertices(
    nominal: &pendulab_plants::spec::PlantParameters,
    ranges: &[(String, f64)],
) -> Result<Vec<Vertex>> {
    let n = ranges.len();
    (0..1usize << n)
        .map(|corner| {
            let entries = nominal.entries().into_iter().map(|(name, v)| {
                match ranges.iter().position(|(r, _)| *r == name) {
                    Some(i) => {
                        let sign = if corner >> (n - 1 - i) & 1 == 1 {
                            1.0
                        } else {
                            -1.0
                        };
                        let value = v * (1.0 + sign * ranges[i].1);
                        (name, value)
                    }
                    None => (name, v),
                }
            });
            let p = pendulab_plants::spec::PlantParameters::from_entries(nominal.kind(), entries)
                .context("a vertex of the --vary box")?;
            p.validate().context("a vertex of the --vary box")?;
            let ss = p
                .linearize_upright(0.0)
                .context("linearising a vertex of the --vary box")?;
            Ok(Vertex {
                a: ss.a().clone(),
                b: ss.b().clone(),
            })
        })
        .collect()
}

/// Poles as `[re, im]` rows (the design record's form).
fn pole_rows(p: &[Complex64]) -> Vec<Vec<f64>> {
    p.iter().map(|z| vec![z.re, z.im]).collect()
}

/// Poles in words, `[-3+1i, …]`.
fn pole_words(p: &[Complex64]) -> String {
    let listed: Vec<String> = p.iter().map(|z| format!("{z}")).collect();
    format!("[{}]", listed.join(", "))
}

/// A pole `re`, `re+imj` or `re-imj` (also `i`).
fn parse_pole(s: &str) -> Option<Complex64> {
    let s = s.trim();
    if let Some(body) = s.strip_suffix('j').or_else(|| s.strip_suffix('i')) {
        // The sign of the imaginary part: the last + or − that is not an exponent's.
        let b = body.as_bytes();
        let at = (1..b.len())
            .rev()
            .find(|&i| (b[i] == b'+' || b[i] == b'-') && !matches!(b[i - 1], b'e' | b'E'))?;
        let re: f64 = body[..at].parse().ok()?;
        let im: f64 = body[at..].parse().ok()?;
        return Some(Complex64::new(re, im));
    }
    s.parse().ok().map(|re| Complex64::new(re, 0.0))
}

#[derive(Serialize)]
struct Margins {
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
struct DesignJson {
    plant: &'static str,
    method: &'static str,
    file: PathBuf,
    designed_on: String,
    plant_sha256: String,
    states: Vec<String>,
    /// pendulab/MATLAB convention `u = −K x`.
    k: Vec<f64>,
    /// The book's convention `u = +K_book x`, `K_book = −K`.
    k_book: Vec<f64>,
    closed_loop_poles: Vec<[f64; 2]>,
    margins: Option<Margins>,
    /// `gain-schedule`'s schedule (the gain and poles above are at `ρ = 0`).
    #[serde(skip_serializing_if = "Option::is_none")]
    schedule: Option<ScheduleJson>,
}

/// The margin `ε` of the SOS program's strict inequalities (the M-file's `ep = 1e-6`).
const SOS_MARGIN: f64 = 1e-6;

/// What `gain_schedule` designs, besides its printed schedule: the schedule, the frozen model
/// `(Ã(0), B̃(0))` of the upright, `K(0)` and its closed-loop poles, `Q`'s diagonal and `Θ0`.
struct GsDesign {
    sched: ScheduledGain,
    a0: Mat,
    b0: Mat,
    k0: Mat,
    poles0: Vec<Complex64>,
    q: Vec<f64>,
    theta10_max_deg: f64,
}

/// The schedule as printed: `K(ρ)` at a few angles, the frozen closed loops at the range's
/// ends, the cost bounds.
#[derive(Serialize)]
struct ScheduleJson {
    /// The scheduling variable.
    variable: &'static str,
    /// The design range of `ρ`.
    rho_range: [f64; 2],
    /// The design range of `|θ₁|` \[deg\].
    theta1_range_deg: [f64; 2],
    /// The rate bound `|ρ̇| ≤ ν` \[1/s\].
    rho_dot_max: f64,
    /// The minimised cost bound `γ*`.
    gamma_star: f64,
    /// The cost bound of the schedule written (`≤ (1 + δ) γ*`).
    gamma: f64,
    /// `K(ρ)` at five angles from 0 to `Θ`.
    gains: Vec<GainAt>,
    /// The closed-loop poles of the frozen models at `ρ = 0` and `ρ = ρ̄`.
    vertices: Vec<VertexPoles>,
}

#[derive(Serialize)]
struct GainAt {
    theta1_deg: f64,
    rho: f64,
    /// pendulab/MATLAB convention `u = −K(ρ) [x; w]`.
    k: Vec<f64>,
    /// The book's convention `u = +K_book [x; w]`, `K_book = L(ρ) X(ρ)⁻¹ = −K(ρ)`.
    k_book: Vec<f64>,
}

#[derive(Serialize)]
struct VertexPoles {
    rho: f64,
    closed_loop_poles: Vec<[f64; 2]>,
}

/// `gain-schedule`: the book's SOS gain-scheduled LQ servo on the lab's arm (module
/// documentation); errors name the option, the cart, or the failed solve.
fn gain_schedule(plant: &PlantSpec, sa: &ScheduleArgs) -> Result<(GsDesign, ScheduleJson)> {
    let PlantParameters::Arm(p) = plant.parameters() else {
        bail!(
            "design gain-schedule: the lab's plant is the cart pendulum, and this design is the arm's \
             (book part 2 §1.5: ρ = 1 − cos θ1 schedules the arm's linearisation; the cart's does not \
             depend on its position). Use `design servo` or `design lmi-servo` for the cart"
        );
    };
    let q = numbers("--q", &sa.q, 5)?;
    if q.iter().any(|&x| x < 0.0) {
        bail!("--q {}: the weights must be ≥ 0", sa.q);
    }
    if !(sa.r.is_finite() && sa.r > 0.0) {
        bail!("--r {}: must be a finite number > 0", sa.r);
    }
    let angle = |flag: &str, v: f64| -> Result<f64> {
        if !(v.is_finite() && v > 0.0 && v < 90.0) {
            bail!(
                "{flag} {v}: the design range 0 ≤ |θ1| ≤ {v}° is empty or reaches 90° (where cos θ1 = 0); give 0 < {flag} < 90"
            );
        }
        Ok(v)
    };
    let th_max = angle("--theta1-max-deg", sa.theta1_max_deg)?;
    let th0_max = angle("--theta10-max-deg", sa.theta10_max_deg.unwrap_or(th_max))?;
    if !(sa.rho_dot_max.is_finite() && sa.rho_dot_max >= 0.0) {
        bail!(
            "--rho-dot-max {}: must be a finite number ≥ 0",
            sa.rho_dot_max
        );
    }
    if !(sa.gamma_relax.is_finite() && sa.gamma_relax >= 0.0) {
        bail!(
            "--gamma-relax {}: must be a finite number ≥ 0",
            sa.gamma_relax
        );
    }
    if !sa.reference.is_finite() || !sa.step_time.is_finite() || sa.step_time < 0.0 {
        bail!(
            "--reference {}, --step-time {}: must be finite, the step time ≥ 0",
            sa.reference,
            sa.step_time
        );
    }
    if sa.reference.abs().to_degrees() > th_max {
        bail!(
            "--reference {} rad ({:.2}°) is outside the design range |θ1| ≤ {th_max}° (--theta1-max-deg): the schedule is not certified there",
            sa.reference,
            sa.reference.to_degrees()
        );
    }
    let lpv = ArmPendulum::new(*p).context("the lab's arm")?.lpv();
    // [x; w], w = ∫(r − θ1) dt: Ã(ρ) = [[A(ρ), 0], [−C, 0]], B̃(ρ) = [B(ρ); 0]; the −C row
    // belongs to the constant term, the ρ-coefficient is padded with zeros.
    let (a0, b0) = pendulab_lti::design::integral_augmentation(&StateSpace::continuous(
        lpv.a0.clone(),
        lpv.b0.clone(),
        Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]),
        Mat::zeros(1, 1),
    )?)?;
    let mut a1 = Mat::zeros(5, 5);
    a1.view_mut((0, 0), (4, 4)).copy_from(&lpv.a1);
    let mut b1 = Mat::zeros(5, 1);
    b1.view_mut((0, 0), (4, 1)).copy_from(&lpv.b1);
    let rho_bar = 1.0 - th_max.to_radians().cos();
    let spec = GainScheduleSpec {
        rho_range: (0.0, rho_bar),
        rho0_range: (0.0, 1.0 - th0_max.to_radians().cos()),
        rho_dot_bound: sa.rho_dot_max,
        lq: LqWeights {
            q: Mat::from_diagonal(&nalgebra::DVector::from_vec(q.clone())),
            r: Mat::from_element(1, 1, sa.r),
        },
        margin: SOS_MARGIN,
        gamma_relax: sa.gamma_relax,
        balance: true,
    };
    let lpv_aug = LpvPlant {
        a0: a0.clone(),
        a1: a1.clone(),
        b0: b0.clone(),
        b1: b1.clone(),
    };
    let d = gain_scheduled_lq(&lpv_aug, &spec, &SolveOptions::default())
        .context("the gain-scheduled SOS design")?;
    let Some(gamma_star) = d.gamma_star else {
        bail!(
            "gain-schedule: the γ minimisation was not solved (status {:?}): no schedule for these weights and ranges; nothing written",
            d.status
        );
    };
    let Some(sched) = d.schedule else {
        bail!(
            "gain-schedule: the re-solve with γ ≤ (1 + {}) γ* did not pass its rechecks (status {:?}); nothing written",
            sa.gamma_relax,
            d.status
        );
    };
    let gains = (0..5)
        .map(|j| {
            let th = th_max * f64::from(j) / 4.0;
            let rho = 1.0 - th.to_radians().cos();
            let k: Vec<f64> = sched.gain(rho)?.row(0).iter().copied().collect();
            Ok(GainAt {
                theta1_deg: th,
                rho,
                k_book: k.iter().map(|x| -x).collect(),
                k,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let mut vertices = Vec::new();
    let mut poles0 = Vec::new();
    for rho in [0.0, rho_bar] {
        let (a, b) = (&a0 + &a1 * rho, &b0 + &b1 * rho);
        let poles = pendulab_lti::linalg::eigenvalues(&(&a - &b * &sched.gain(rho)?))?;
        if let Some(bad) = poles.iter().find(|z| z.re >= 0.0) {
            bail!(
                "gain-schedule: the frozen closed loop at ρ = {rho} has the pole {bad} outside the open left half-plane; nothing written"
            );
        }
        vertices.push(VertexPoles {
            rho,
            closed_loop_poles: poles.iter().map(|z| [z.re, z.im]).collect(),
        });
        if rho == 0.0 {
            poles0 = poles;
        }
    }
    let out = ScheduleJson {
        variable: "rho = 1 - cos(theta1)",
        rho_range: [0.0, rho_bar],
        theta1_range_deg: [0.0, th_max],
        rho_dot_max: sa.rho_dot_max,
        gamma_star,
        gamma: sched.gamma,
        gains,
        vertices,
    };
    let k0 = sched.gain(0.0)?;
    Ok((
        GsDesign {
            sched,
            a0,
            b0,
            k0,
            poles0,
            q,
            theta10_max_deg: th0_max,
        },
        out,
    ))
}

/// Runs `pendulab design`.
///
/// # Errors
/// The lab's errors; an argument that is not what it must be; a design without a stable
/// closed loop; the file rejected when read back; a file that cannot be written.
pub fn run(args: &DesignArgs) -> Result<()> {
    let (common, method) = match &args.method {
        DesignMethod::Lqr { common, .. } => (common, "lqr"),
        DesignMethod::Place { common, .. } => (common, "place"),
        DesignMethod::Servo { common, .. } => (common, "servo"),
        DesignMethod::LmiServo { common, .. } => (common, "lmi-servo"),
        DesignMethod::Robust { common, .. } => (common, "robust"),
        DesignMethod::P { common, .. } => (common, "p"),
        DesignMethod::Observer { common, .. } => (common, "observer"),
        DesignMethod::GainSchedule { common, .. } => (common, "gain-schedule"),
    };
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
    let (a, b) = (ss.a().clone(), ss.b().clone());
    let fmt = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:?}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    // `gain-schedule`'s schedule, printed after the gain at ρ = 0.
    let mut schedule_out: Option<ScheduleJson> = None;
    // (the [controller] table, K as one row, closed-loop poles, the loop for the margins,
    // the inputs as recorded, extra lines of the header)
    let (table, k, poles, loop_ss, inputs, note, record): Designed = match &args.method {
        DesignMethod::Lqr { q, r, .. } => {
            let (l, qv) = lqr_design(&ss, q, *r)?;
            let inputs: Vec<(String, DesignInput)> = weight_inputs(&qv, *r).into_iter().collect();
            let k: Vec<f64> = l.gain.row(0).iter().copied().collect();
            let loop_ss = StateSpace::new(
                a.clone(),
                b.clone(),
                l.gain.clone(),
                Mat::zeros(1, 1),
                ss.domain(),
            )?;
            (
                format!("kind = \"state-feedback\"\nk = [{}]\n", fmt(&k)),
                k,
                l.poles,
                Some(loop_ss),
                format!("Q = diag([{}]), R = {r}", fmt(&qv)),
                "",
                inputs,
            )
        }
        DesignMethod::Place { poles, .. } => {
            let p = four_poles("--poles", poles)?;
            let pl = place_upright(&ss, &p).with_context(|| format!("place with poles {poles}"))?;
            let k: Vec<f64> = pl.gain.row(0).iter().copied().collect();
            let loop_ss =
                StateSpace::new(a.clone(), b.clone(), pl.gain, Mat::zeros(1, 1), ss.domain())?;
            (
                format!("kind = \"state-feedback\"\nk = [{}]\n", fmt(&k)),
                k,
                pl.poles,
                Some(loop_ss),
                format!("poles = {}", pole_words(&p)),
                "",
                pole_inputs(&p).into_iter().collect(),
            )
        }
        DesignMethod::Servo {
            servo:
                ServoArgs {
                    q,
                    r,
                    reference,
                    step_time,
                },
            ..
        }
        | DesignMethod::LmiServo {
            servo:
                ServoArgs {
                    q,
                    r,
                    reference,
                    step_time,
                },
            ..
        } => {
            let qv = numbers("--q", q, 5)?;
            if qv.iter().any(|&x| x < 0.0) {
                bail!("--q {q}: the weights must be ≥ 0");
            }
            if !(r.is_finite() && *r > 0.0) {
                bail!("--r {r}: must be a finite number > 0");
            }
            if !reference.is_finite() || !step_time.is_finite() || *step_time < 0.0 {
                bail!(
                    "--reference {reference}, --step-time {step_time}: must be finite, the step time ≥ 0"
                );
            }
            // The gain on [x; w] (1 × 5, u = −K [x; w]), its closed-loop poles and the
            // augmented model: by the Riccati equation (`servo`), or by the LMI
            // guaranteed-cost LQ design on the same augmented model (`lmi-servo`, book part 2
            // §1.2.2).
            let (gain, cl_poles, aa, ba) = if method == "lmi-servo" {
                let qm = Mat::from_diagonal(&nalgebra::DVector::from_vec(qv.clone()));
                let rm = Mat::from_element(1, 1, *r);
                let (aa, ba) = integral_augmentation(&drive_servo_model(&ss)?)?;
                let d = lq_state_feedback(&aa, &ba, &qm, &rm, &SolveOptions::default())
                    .with_context(|| {
                        format!("LMI LQ servo with Q = diag({}), R = {r}", fmt(&qv))
                    })?;
                let Some(f) = d.feedback else {
                    bail!(
                        "LMI LQ servo with Q = diag({}), R = {r}: the LMIs were not solved (status {:?}); nothing written",
                        fmt(&qv),
                        d.status
                    );
                };
                let poles = f.closed_loop_poles.into_iter().next().unwrap_or_default();
                (f.gain, poles, aa, ba)
            } else {
                let s = servo_upright(&ss, &qv, *r).with_context(|| {
                    format!(
                        "lq servo with Q = diag({}), R = {r}: no stabilising solution",
                        fmt(&qv)
                    )
                })?;
                (s.gain, s.poles, s.a, s.b)
            };
            let k: Vec<f64> = gain.row(0).iter().copied().collect();
            let (k1, k2) = (k[..4].to_vec(), k[4]);
            let loop_ss = StateSpace::new(aa, ba, gain, Mat::zeros(1, 1), ss.domain())?;
            (
                format!(
                    "kind = \"lq-servo\"\nk1 = [{}]\nk2 = {k2:?}\nreference = [{reference:?}]\nstep_time = {step_time:?}\n",
                    fmt(&k1)
                ),
                k,
                cl_poles,
                Some(loop_ss),
                format!(
                    "Q = diag([{}]), R = {r}, on [x; w], w = ∫(r − q0) dt",
                    fmt(&qv)
                ),
                "",
                weight_inputs(&qv, *r)
                    .into_iter()
                    .chain([
                        ("reference".to_string(), DesignInput::Number(*reference)),
                        ("step_time".to_string(), DesignInput::Number(*step_time)),
                    ])
                    .collect(),
            )
        }
        DesignMethod::Robust {
            q,
            r,
            vary,
            decay_rate,
            speed_limit,
            ..
        } => {
            let mut regions = Vec::new();
            if let Some(alpha) = decay_rate {
                if !(alpha.is_finite() && *alpha > 0.0) {
                    bail!("--decay-rate {alpha}: must be a finite number > 0");
                }
                regions.push(Region::DecayRate { alpha: *alpha });
            }
            if let Some(beta) = speed_limit {
                if !(beta.is_finite() && *beta > decay_rate.unwrap_or(0.0)) {
                    bail!("--speed-limit {beta}: must be a finite number > 0 and > --decay-rate");
                }
                regions.push(Region::SpeedLimit { beta: *beta });
            }
            let qv = numbers("--q", q, 4)?;
            if qv.iter().any(|&x| x < 0.0) {
                bail!("--q {q}: the weights must be ≥ 0");
            }
            if !(r.is_finite() && *r > 0.0) {
                bail!("--r {r}: must be a finite number > 0");
            }
            let nominal = plant.parameters().entries();
            let ranges = vary
                .iter()
                .map(|v| parse_vary(v, &nominal))
                .collect::<Result<Vec<_>>>()?;
            if ranges.len() > 4 {
                bail!(
                    "--vary: at most 4 parameters (16 vertices), {} given",
                    ranges.len()
                );
            }
            if let Some((i, (name, _))) = ranges
                .iter()
                .enumerate()
                .find(|(i, (n, _))| ranges[..*i].iter().any(|(m, _)| m == n))
            {
                bail!("--vary {}: {name} is given twice", vary[i]);
            }
            let vertices = box_vertices(plant.parameters(), &ranges)?;
            let qm = Mat::from_diagonal(&nalgebra::DVector::from_vec(qv.clone()));
            let d = robust_state_feedback(
                &vertices,
                &qm,
                &Mat::from_element(1, 1, *r),
                &regions,
                &SolveOptions::default(),
            )
            .with_context(|| format!("robust LQ with Q = diag({}), R = {r}", fmt(&qv)))?;
            let Some(f) = d.feedback else {
                bail!(
                    "robust LQ with Q = diag({}), R = {r}: no common gain found for the {} vertices (status {:?}); nothing written",
                    fmt(&qv),
                    vertices.len(),
                    d.status
                );
            };
            let worst = f
                .closed_loop_poles
                .iter()
                .flatten()
                .map(|z| z.re)
                .fold(f64::NEG_INFINITY, f64::max);
            if !f.poles_in_regions {
                bail!(
                    "robust LQ: a vertex's closed-loop poles are not all inside the requested region; nothing written"
                );
            }
            if worst >= 0.0 {
                bail!(
                    "robust LQ: a vertex's closed loop has a pole with real part {worst}; nothing written"
                );
            }
            let k: Vec<f64> = f.gain.row(0).iter().copied().collect();
            let nominal_poles = pendulab_lti::linalg::eigenvalues(&(&a - &b * &f.gain))?;
            let loop_ss =
                StateSpace::new(a.clone(), b.clone(), f.gain, Mat::zeros(1, 1), ss.domain())?;
            let words: Vec<String> = ranges
                .iter()
                .map(|(n, frac)| format!("{n} ± {}%", frac * 100.0))
                .collect();
            let mut rec = vec![
                ("q".to_string(), DesignInput::List(qv.clone())),
                ("r".to_string(), DesignInput::Number(*r)),
            ];
            if let Some(alpha) = decay_rate {
                rec.push(("decay_rate".to_string(), DesignInput::Number(*alpha)));
            }
            if let Some(beta) = speed_limit {
                rec.push(("speed_limit".to_string(), DesignInput::Number(*beta)));
            }
            for (n, frac) in &ranges {
                rec.push((format!("vary_{n}"), DesignInput::Number(*frac)));
            }
            (
                format!("kind = \"state-feedback\"\nk = [{}]\n", fmt(&k)),
                k,
                nominal_poles,
                Some(loop_ss),
                format!(
                    "Q = diag([{}]), R = {r}, robust over the {} vertices of {} (largest closed-loop real part over the vertices {worst:.4} 1/s; the poles printed are the lab's nominal plant's)",
                    fmt(&qv),
                    vertices.len(),
                    words.join(", ")
                ),
                "",
                rec,
            )
        }
        DesignMethod::Observer {
            q,
            r,
            poles,
            observer_poles,
            ..
        } => {
            // K: an LQ regulator or a placement, as `lqr` and `place` design it.
            let (k_mat, k_inputs, k_words) = match (q, r, poles) {
                (Some(q), Some(r), None) => {
                    let (l, qv) = lqr_design(&ss, q, *r)?;
                    let inputs: Vec<(String, DesignInput)> =
                        weight_inputs(&qv, *r).into_iter().collect();
                    let words = format!("K by LQR, Q = diag([{}]), R = {r}", fmt(&qv));
                    (l.gain, inputs, words)
                }
                (None, None, Some(text)) => {
                    let p = four_poles("--poles", text)?;
                    let g = place_upright(&ss, &p)
                        .with_context(|| format!("place with poles {text}"))?
                        .gain;
                    (
                        g,
                        pole_inputs(&p).into_iter().collect(),
                        format!("K placed at {}", pole_words(&p)),
                    )
                }
                _ => bail!("observer: give the state feedback as --q with --r, or as --poles"),
            };
            // L: A − LC at the observer poles, C = [I₂ 0] (the encoder positions).
            let op = four_poles("--observer-poles", observer_poles)?;
            let c = Mat::from_row_slice(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
            let l_mat = place_observer(&a, &c, &op)
                .with_context(|| format!("observer placement at {observer_poles}"))?
                .gain;
            let k: Vec<f64> = k_mat.row(0).iter().copied().collect();
            let l_rows: Vec<Vec<f64>> = (0..4)
                .map(|i| l_mat.row(i).iter().copied().collect())
                .collect();
            // The 8 closed-loop poles of plant and observer-based controller, as the
            // controller kind computes them.
            let d = observer_design(
                plant.parameters(),
                &ObserverSpec {
                    k: Some(k.clone()),
                    l: Some(l_rows.clone()),
                    ..ObserverSpec::default()
                },
            )
            .context("the observer-based loop")?;
            // The loop broken at the plant input: plant (A, B, C) into the controller
            // (A − BK − LC, L, K): states [x; x̂], L(s) = K x̂ / u.
            let mut al = Mat::zeros(8, 8);
            al.view_mut((0, 0), (4, 4)).copy_from(&a);
            al.view_mut((4, 0), (4, 4)).copy_from(&(&l_mat * &c));
            al.view_mut((4, 4), (4, 4))
                .copy_from(&(&a - &b * &k_mat - &l_mat * &c));
            let mut bl = Mat::zeros(8, 1);
            bl.view_mut((0, 0), (4, 1)).copy_from(&b);
            let mut cl = Mat::zeros(1, 8);
            cl.view_mut((0, 4), (1, 4)).copy_from(&k_mat);
            let loop_ss = StateSpace::new(al, bl, cl, Mat::zeros(1, 1), ss.domain())?;
            let mut rec = k_inputs;
            rec.push((
                "observer_poles".to_string(),
                DesignInput::Rows(pole_rows(&op)),
            ));
            (
                format!(
                    "kind = \"observer\"\nk = [{}]\nl = [{}]\n",
                    fmt(&k),
                    l_rows
                        .iter()
                        .map(|r| format!("[{}]", fmt(r)))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                k,
                d.closed_loop_poles,
                Some(loop_ss),
                format!(
                    "{k_words}, observer of [q0, q1] with A − LC at {}",
                    pole_words(&op)
                ),
                "",
                rec,
            )
        }
        DesignMethod::GainSchedule { schedule: sa, .. } => {
            let (d, designed) = gain_schedule(&plant, sa)?;
            let rows = |m: &Mat| -> String {
                let r: Vec<String> = (0..m.nrows())
                    .map(|i| format!("[{}]", fmt(&m.row(i).iter().copied().collect::<Vec<_>>())))
                    .collect();
                format!("[{}]", r.join(", "))
            };
            let xs: Vec<String> = d.sched.x_coefficients.iter().map(rows).collect();
            let ls: Vec<String> = d
                .sched
                .l_coefficients
                .iter()
                .map(|l| format!("[{}]", fmt(&l.row(0).iter().copied().collect::<Vec<_>>())))
                .collect();
            let loop_ss = StateSpace::new(
                d.a0.clone(),
                d.b0.clone(),
                d.k0.clone(),
                Mat::zeros(1, 1),
                ss.domain(),
            )?;
            let note = "# K(ρ) = −L(ρ) X(ρ)⁻¹ (library sign, u = −K(ρ) [x; w]), ρ = 1 − cos θ1, w = ∫(r − θ1) dt;\n\
                 # the book's K = L X⁻¹ is −K(ρ). Guaranteed for ρ and dρ/dt in the design ranges of the record.\n";
            let table = format!(
                "kind = \"gain-scheduled\"\nschedule = \"one-minus-cos-q0\"\nx_coefficients = [{}]\nl_coefficients = [{}]\nreference = [{:?}]\nstep_time = {:?}\n",
                xs.join(", "),
                ls.join(", "),
                sa.reference,
                sa.step_time
            );
            let k: Vec<f64> = d.k0.row(0).iter().copied().collect();
            let words = format!(
                "Q = diag([{}]), R = {}, on [x; w], w = ∫(r − θ1) dt, |θ1| ≤ {}°, |θ1(0)| ≤ {}°, |dρ/dt| ≤ {}, γ* = {:.4}, γ = {:.4} ≤ (1 + {}) γ*",
                fmt(&d.q),
                sa.r,
                sa.theta1_max_deg,
                d.theta10_max_deg,
                sa.rho_dot_max,
                designed.gamma_star,
                designed.gamma,
                sa.gamma_relax
            );
            let rec = vec![
                ("q".to_string(), DesignInput::List(d.q.clone())),
                ("r".to_string(), DesignInput::Number(sa.r)),
                (
                    "rho_range".to_string(),
                    DesignInput::List(vec![designed.rho_range[0], designed.rho_range[1]]),
                ),
                (
                    "rho0_range".to_string(),
                    DesignInput::List(vec![0.0, 1.0 - d.theta10_max_deg.to_radians().cos()]),
                ),
                (
                    "rho_dot_max".to_string(),
                    DesignInput::Number(sa.rho_dot_max),
                ),
                (
                    "gamma_relax".to_string(),
                    DesignInput::Number(sa.gamma_relax),
                ),
                ("margin".to_string(), DesignInput::Number(SOS_MARGIN)),
                ("reference".to_string(), DesignInput::Number(sa.reference)),
                ("step_time".to_string(), DesignInput::Number(sa.step_time)),
            ];
            let poles = d.poles0.clone();
            schedule_out = Some(designed);
            (table, k, poles, Some(loop_ss), words, note, rec)
        }
        DesignMethod::P { kp, target, .. } => {
            if !(kp.is_finite() && *kp > 0.0) {
                bail!("--kp {kp}: must be a finite number > 0");
            }
            if !target.is_finite() {
                bail!("--target {target}: must be finite");
            }
            // The drive alone, q0'' = −a q0' + b v under u = −kP q0: s² + a s + b kP.
            let k = vec![*kp, 0.0, 0.0, 0.0];
            let drive = Mat::from_row_slice(2, 2, &[0.0, 1.0, -b[(2, 0)] * kp, a[(2, 2)]]);
            let poles = pendulab_lti::linalg::eigenvalues(&drive)?;
            (
                format!(
                    "kind = \"state-feedback\"\nk = [{}]\nreference = [{target:?}, 0.0, 0.0, 0.0]\n",
                    fmt(&k)
                ),
                k,
                poles,
                None,
                format!("kP = {kp}, target = {target}"),
                "# The drive's P-control step (book part 1 §3.2) with the pendulum hanging: run it\n\
                 # with `pendulab rig run --hanging`, identify with `pendulab identify`.\n",
                vec![
                    ("kp".to_string(), DesignInput::Number(*kp)),
                    ("target".to_string(), DesignInput::Number(*target)),
                ],
            )
        }
    };
    let states: Vec<String> = state_names(kind).into_iter().collect();
    let plant_toml = plant.to_toml().context("the lab's plant as TOML")?;
    let plant_sha = lab::sha256_hex(plant_toml.as_bytes());
    let designed_on = lab::provenance_label(plant.provenance());
    let mut text = String::new();
    let _ = writeln!(
        text,
        "# pendulab design {method}: a controller file for `pendulab simulate` and `pendulab rig run` (docs/lab.md)."
    );
    let _ = writeln!(
        text,
        "# Designed on the {} pendulum of {} ({designed_on}),",
        kind.name(),
        common.lab.display()
    );
    let _ = writeln!(
        text,
        "# linearised about the upright (docs/model.md), sha256 of its plant table {plant_sha}."
    );
    let _ = writeln!(text, "# Method: {method}, {inputs}.");
    let params: Vec<String> = plant
        .parameters()
        .entries()
        .iter()
        .map(|(k, v)| format!("{k} = {v:?}"))
        .collect();
    let _ = writeln!(text, "# Parameters: {}.", params.join(", "));
    text.push_str(note);
    // The [controller] table as the rig reads it, then with the design record
    // (`pendulab_control::spec::DesignRecord`: the lab's plant, the upright operating point,
    // a continuous-time design, the method and its inputs).
    let draft = format!(
        "plant = \"{}\"\nrate_hz = {rate_hz:?}\n\n[controller]\n{table}",
        kind.name()
    );
    let loaded = pendulab_rig::config::load(&draft).context("the designed controller")?;
    let record = DesignRecord::new(
        &plant,
        vec![0.0; 4],
        None,
        method,
        record.into_iter().collect(),
    );
    #[derive(Serialize)]
    struct File<'a> {
        plant: &'static str,
        rate_hz: f64,
        controller: &'a ControllerSpec,
        #[serde(skip_serializing_if = "Option::is_none")]
        safety: Option<toml::Table>,
    }
    let spec = loaded.spec.with_designed_for(record);
    let safety = (method == "p").then(|| {
        // About the hanging rest the pendulum swings: a window wider than the balancing one.
        let mut t = toml::Table::new();
        t.insert("angle_window_deg".into(), toml::Value::Float(60.0));
        t
    });
    let body = toml::to_string(&File {
        plant: kind.name(),
        rate_hz,
        controller: &spec,
        safety,
    })
    .context("writing the controller file")?;
    let _ = write!(text, "\n{body}");
    // Read back as the rig reads it and built on the lab's plant, its record checked against
    // the lab: nothing is written unless all accept it.
    let loaded = pendulab_rig::config::load(&text).context("the designed file, read back")?;
    let warnings = loaded
        .spec
        .check_plant(&plant)
        .context("the designed file's record")?;
    if let Some(w) = warnings.first() {
        bail!("the designed file's record differs from the lab: {w}");
    }
    build_for(&loaded.spec, &plant, loaded.ts).context("the designed file, built")?;

    if let Some(bad) = poles.iter().find(|p| p.re >= 0.0) {
        bail!(
            "{method}: the closed loop has the pole {bad} outside the open left half-plane; nothing written"
        );
    }
    let margins = match &loop_ss {
        Some(l) => {
            let m = stability_margins(l).context("the loop's stability margins")?;
            let gm = m.gain_margin();
            let pm = m.phase_margin();
            Some(Margins {
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
            })
        }
        None => None,
    };
    let out_path = common
        .out
        .clone()
        .unwrap_or_else(|| common.lab.join("designs").join(format!("{method}.toml")));
    write_file(&out_path, &text)?;

    let k_book: Vec<f64> = k.iter().map(|x| -x).collect();
    let mut states = states;
    if matches!(method, "servo" | "lmi-servo" | "gain-schedule") {
        states.push("w".into());
    }
    let out = DesignJson {
        plant: kind.name(),
        method,
        file: out_path,
        designed_on,
        plant_sha256: plant_sha,
        states,
        k,
        k_book,
        closed_loop_poles: poles.iter().map(|p| [p.re, p.im]).collect(),
        margins,
        schedule: schedule_out,
    };
    if common.json {
        println!("{}", serde_json::to_string(&out)?);
        return Ok(());
    }
    print_design(&out, &plant);
    Ok(())
}

fn write_file(path: &Path, text: &str) -> Result<()> {
    if let Some(dir) = path.parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    lab::write_whole(path, text.as_bytes())
}

fn print_design(out: &DesignJson, plant: &PlantSpec) {
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
        println!(
            "schedule K(ρ), ρ = 1 − cos θ1, designed for ρ ∈ [{:.6}, {:.6}] (|θ1| ≤ {}°), |dρ/dt| ≤ {}; γ* = {:.4}, γ = {:.4}",
            s.rho_range[0],
            s.rho_range[1],
            s.theta1_range_deg[1],
            s.rho_dot_max,
            s.gamma_star,
            s.gamma
        );
        println!("(the gain and poles above are those at ρ = 0)");
        for g in &s.gains {
            println!("  θ1 = {:6.2}°, ρ = {:.6}", g.theta1_deg, g.rho);
            println!("    K      (u = −K(ρ) [x; w]):      {}", fmt_row(&g.k));
            println!("    K_book (u = +K_book [x; w]):    {}", fmt_row(&g.k_book));
        }
        println!("closed-loop poles of the frozen models at the range's ends [1/s]:");
        for v in &s.vertices {
            let p: Vec<String> = v
                .closed_loop_poles
                .iter()
                .map(|[re, im]| format!("{re:.4}{im:+.4}j"))
                .collect();
            println!("  ρ = {:.6}: {}", v.rho, p.join(", "));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::parse_pole;
    use pendulab_lti::Complex64;

    #[test]
    fn poles_parse_in_their_written_forms() {
        assert_eq!(parse_pole("-3"), Some(Complex64::new(-3.0, 0.0)));
        assert_eq!(parse_pole("-3+2j"), Some(Complex64::new(-3.0, 2.0)));
        assert_eq!(parse_pole("-3-2.5i"), Some(Complex64::new(-3.0, -2.5)));
        assert_eq!(parse_pole("-1e-1-2e+0j"), Some(Complex64::new(-0.1, -2.0)));
        assert_eq!(parse_pole("x"), None);
    }
}
