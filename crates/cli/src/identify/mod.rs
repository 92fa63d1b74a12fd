//! `pendulab identify <method> --data FILE.csv`: parameter identification from a measured CSV.
//!
//! The CSV has a header line naming its columns, as the files of `data/rig/` do; the time
//! column is `t` in seconds, uniformly sampled — or in milliseconds when the header says so
//! (`t_ms`, `t[ms]`, `t (ms)`) or `--time-unit ms` declares it (windows are always given in
//! seconds). A leading UTF-8 byte-order mark and CRLF line ends are accepted. Angles are measured from the hanging rest
//! (`φ = θ − π`), the arm angle from where the recording starts (`φ₁ = θ₁`). Columns by
//! method:
//!
//! | method | columns | estimates |
//! |---|---|---|
//! | `cart-ls` | `t, z, v` | `ac`, `bc` |
//! | `pend-ls` | `t, z, phi` | `Jp`, `mup` |
//! | `arm-ls` | `t, phi1, v` | `a1`, `b1` |
//! | `arm-pend-ls` | `t, phi1, phi2` | `J2`, `mu2` (and `alpha2`) |
//! | `cart-step` | `t, z` | `ac`, `bc`, `Tp`, `overshoot` |
//! | `arm-step` | `t, theta1` | `a1`, `b1`, `Tp`, `overshoot` |
//! | `pend-free` | `t, theta` | `Jp`, `mup`, `period`, `decay_ratio` |
//! | `arm-pend-free` | `t, theta2` | `J2`, `mu2`, `period`, `decay_ratio` |
//! | `arx`, `moesp` | `t`, `--input`, `--output` | a black-box discrete model (`identify_blackbox`, `docs/identify.md`) |
//!
//! Every identification is validated by simulating the identified model on the measured
//! input (`fit`, MATLAB's `compare` percentage); the output says which model was simulated on
//! which signal over which window and what it was compared with.
//!
//! **Refusing to guess.** Before an estimate is printed, the library's checks run (see
//! `pendulab_ident`'s crate docs): a time step plausible for the declared unit, known
//! constants in their plausible ranges, enough samples for the differentiator, a prefilter
//! time constant suited to the record and the sample time, derivatives accurate over the band
//! used, a finite and well-conditioned least-squares solution, estimates that make physical
//! sense and are resolved by the record, and every printed number finite. A failed check is
//! an error (non-zero exit) naming the cause; with `--force` the result is printed anyway and
//! every failed check is listed under `warnings` (text and JSON). Never a silent `null`.

mod methods;
mod report;
mod save;

use anyhow::{Context, Result, bail};
use methods::identify;
use pendulab_ident::{
    ArmPendulumConstants, CartPendulumConstants, Differentiator, FilterHold, LsOptions, Prefilter,
    TimeUnit,
};
use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::PlantParameters;
use pendulab_plants::{ArmPendulumParams, CartPendulumParams};
use report::print_table;
use save::save;
use serde_json::{Value, json};
use std::path::PathBuf;

/// Identification methods.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    /// Cart drive [a_c, b_c] by least squares (columns t, z, v).
    CartLs,
    /// Cart-type pendulum [J_p, μ_p] by least squares (columns t, z, phi).
    PendLs,
    /// Arm drive [a1, b1] by least squares (columns t, phi1, v).
    ArmLs,
    /// Arm-type pendulum [α2, μ2] → J2 by least squares (columns t, phi1, phi2).
    ArmPendLs,
    /// Cart drive from a P-control step response (columns t, z).
    CartStep,
    /// Arm drive from a P-control step response (columns t, theta1).
    ArmStep,
    /// Cart-type pendulum from a free oscillation (columns t, theta).
    PendFree,
    /// Arm-type pendulum from a free oscillation (columns t, theta2).
    ArmPendFree,
    /// Black-box ARX model by least squares (columns t, --input, --output).
    Arx,
    /// Black-box state-space model by PO-MOESP (columns t, --input, --output).
    Moesp,
}

impl Method {
    /// The plant the method identifies.
    fn plant(self) -> PlantKind {
        match self {
            Method::CartLs | Method::PendLs | Method::CartStep | Method::PendFree => {
                PlantKind::Cart
            }
            Method::ArmLs | Method::ArmPendLs | Method::ArmStep | Method::ArmPendFree => {
                PlantKind::Arm
            }
            // Not a plant's: `run` hands the black-box methods to `identify_blackbox` first.
            Method::Arx | Method::Moesp => PlantKind::Cart,
        }
    }

    /// The estimates that are plant parameters, as `(estimate name, plant file key)`.
    fn parameters(self) -> [(&'static str, &'static str); 2] {
        match self {
            Method::CartLs | Method::CartStep => [("ac", "a_c"), ("bc", "b_c")],
            Method::PendLs | Method::PendFree => [("Jp", "J_p"), ("mup", "mu_p")],
            Method::ArmLs | Method::ArmStep => [("a1", "a1"), ("b1", "b1")],
            Method::ArmPendLs | Method::ArmPendFree => [("J2", "J2"), ("mu2", "mu2")],
            Method::Arx | Method::Moesp => [("", ""); 2],
        }
    }

    fn name(self) -> &'static str {
        match self {
            Method::CartLs => "cart-ls",
            Method::PendLs => "pend-ls",
            Method::ArmLs => "arm-ls",
            Method::ArmPendLs => "arm-pend-ls",
            Method::CartStep => "cart-step",
            Method::ArmStep => "arm-step",
            Method::PendFree => "pend-free",
            Method::ArmPendFree => "arm-pend-free",
            Method::Arx => "arx",
            Method::Moesp => "moesp",
        }
    }
}

/// Unit of the data's time column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum TimeUnitArg {
    /// Seconds.
    S,
    /// Milliseconds.
    Ms,
}

impl From<TimeUnitArg> for TimeUnit {
    fn from(u: TimeUnitArg) -> Self {
        match u {
            TimeUnitArg::S => TimeUnit::Seconds,
            TimeUnitArg::Ms => TimeUnit::Milliseconds,
        }
    }
}

/// Arguments of `pendulab identify`.
#[derive(Debug, clap::Args)]
pub struct IdentifyArgs {
    /// Identification method.
    #[arg(value_enum)]
    pub method: Method,
    /// Measured data: CSV with a header line (columns as in data/rig/).
    #[arg(long)]
    pub data: PathBuf,
    /// Unit of the time column `t` (default: seconds, or what the header declares: `t_ms`,
    /// `t[ms]`, `t (ms)` are milliseconds).
    #[arg(long, value_enum, value_name = "UNIT")]
    pub time_unit: Option<TimeUnitArg>,
    /// Print the result even when a check fails (implausible time step, constants out of
    /// range, too few samples for the differentiator or filter, an ill-conditioned regressor,
    /// a non-finite or implausible estimate), listing every failed check under `warnings`.
    #[arg(long)]
    pub force: bool,
    /// Time window T0:T1 in seconds (either end may be left empty: "1:" or ":5").
    #[arg(long, value_name = "T0:T1")]
    pub window: Option<String>,
    /// Pre-filter time constant T_f of 1/(T_f s + 1)^3, seconds (least-squares methods).
    #[arg(long, default_value_t = 0.075)]
    pub tf: f64,
    /// Do not pre-filter (least-squares methods; the book shows why not to).
    #[arg(long, conflicts_with_all = ["zero_phase"])]
    pub no_filter: bool,
    /// Filter forward and backward (zero phase) instead of causally.
    #[arg(long)]
    pub zero_phase: bool,
    /// Discretise the filter with a first-order hold instead of a zero-order hold.
    #[arg(long)]
    pub foh: bool,
    /// Savitzky–Golay derivatives with this odd window (samples) instead of three-point ones.
    #[arg(long, value_name = "WINDOW")]
    pub savgol: Option<usize>,
    /// Polynomial order of the Savitzky–Golay derivatives.
    #[arg(long, default_value_t = 3)]
    pub savgol_order: usize,
    /// Cart pendulum mass m_p, kg (default: the lab's with --save, else the book's 0.107).
    #[arg(long)]
    pub mp: Option<f64>,
    /// Cart pendulum pivot to centre of mass l_p, m (default: the lab's with --save, else the book's 0.230).
    #[arg(long)]
    pub lp: Option<f64>,
    /// Gravitational acceleration g, m/s² (default: the lab's with --save, else the book's 9.81).
    #[arg(long)]
    pub g: Option<f64>,
    /// Arm length L1, m (default: the lab's with --save, else the book's 0.227).
    #[arg(long = "L1", alias = "arm-length")]
    pub l1: Option<f64>,
    /// Arm pendulum mass m2, kg (default: the lab's with --save, else the book's 0.096).
    #[arg(long)]
    pub m2: Option<f64>,
    /// Arm pendulum joint to centre of mass l2, m (default: the lab's with --save, else the book's 0.195).
    #[arg(long)]
    pub l2: Option<f64>,
    /// P gain k_P of the step experiment (default: 10 for cart-step, 3 for arm-step).
    #[arg(long)]
    pub kp: Option<f64>,
    /// Step target (default: 0.2 m for cart-step, 1 rad for arm-step).
    #[arg(long)]
    pub target: Option<f64>,
    /// Time of the reference step, s (default: the window start, or 1 s — when the rig
    /// recordings step their reference — without a window).
    #[arg(long)]
    pub step_time: Option<f64>,
    /// Signal column of the feature methods (default: z, theta1, theta, theta2).
    #[arg(long)]
    pub column: Option<String>,
    /// Correct free-oscillation periods for the pendulum's large-amplitude lengthening.
    #[arg(long)]
    pub amplitude_correction: bool,
    /// Hysteresis of the free-oscillation cycle detector (unit of the signal; default
    /// automatic).
    #[arg(long)]
    pub hysteresis: Option<f64>,
    /// Write the estimated plant parameters into DIR/lab.toml (`docs/lab.md`), with their
    /// provenance: the data file, its SHA-256, the window and the standard errors. The known
    /// constants (m_p, l_p, g or L1, m2, l2, g) are then the lab's unless given. Refused for a
    /// method of the other plant, and with --force when a check failed. With arx and moesp:
    /// the discrete model as a system file (SYS.toml or .json, `docs/sys.md`).
    #[arg(long, value_name = "DIR")]
    pub save: Option<PathBuf>,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Input column of arx/moesp (default: v).
    #[arg(long, value_name = "COLUMN")]
    pub input: Option<String>,
    /// Output column of arx/moesp (default: z).
    #[arg(long, value_name = "COLUMN")]
    pub output: Option<String>,
    /// ARX: number of A coefficients a1…a_na (default 2).
    #[arg(long)]
    pub na: Option<usize>,
    /// ARX: number of B coefficients b0…b_(nb−1) (default 2).
    #[arg(long)]
    pub nb: Option<usize>,
    /// ARX: input delay in samples (default 1).
    #[arg(long)]
    pub nk: Option<usize>,
    /// ARX: try na, nb = 1…N and keep the least AIC; MOESP: the order at the largest gap of
    /// the singular values among 1…N.
    #[arg(long, value_name = "N")]
    pub max_order: Option<usize>,
    /// MOESP: the model order (default: from the singular values).
    #[arg(long)]
    pub order: Option<usize>,
    /// MOESP: block rows of the Hankel matrices (default 10).
    #[arg(long)]
    pub horizon: Option<usize>,
    /// arx/moesp: validation window T0:T1 in seconds (default: the estimation window).
    #[arg(long, value_name = "T0:T1")]
    pub validate: Option<String>,
    /// arx/moesp: keep every Q-th sample for the black-box models (default 1).
    #[arg(long, value_name = "Q")]
    pub decimate: Option<usize>,
}

impl IdentifyArgs {
    /// The method's name as typed (`cart-ls`, …, `arx`, `moesp`).
    pub fn method_name(&self) -> &'static str {
        self.method.name()
    }
}

pub(crate) fn parse_window(s: &str) -> Result<(Option<f64>, Option<f64>)> {
    let Some((a, b)) = s.split_once(':') else {
        bail!("--window must be T0:T1 (seconds), got '{s}'");
    };
    let parse = |x: &str, which: &str| -> Result<Option<f64>> {
        let x = x.trim();
        if x.is_empty() {
            return Ok(None);
        }
        let v: f64 = x
            .parse()
            .with_context(|| format!("--window {which} '{x}' is not a number"))?;
        if !v.is_finite() {
            bail!("--window {which} must be finite, got {x}");
        }
        Ok(Some(v))
    };
    Ok((parse(a, "start")?, parse(b, "end")?))
}

pub(crate) fn ls_options(args: &IdentifyArgs) -> LsOptions {
    let hold = if args.foh {
        FilterHold::Foh
    } else {
        FilterHold::Zoh
    };
    LsOptions {
        differentiator: match args.savgol {
            Some(window) => Differentiator::SavitzkyGolay {
                window,
                order: args.savgol_order,
            },
            None => Differentiator::ThreePoint,
        },
        prefilter: if args.no_filter {
            Prefilter::None
        } else if args.zero_phase {
            Prefilter::ZeroPhase { tf: args.tf, hold }
        } else {
            Prefilter::Causal { tf: args.tf, hold }
        },
    }
}

fn options_json(o: &LsOptions) -> Value {
    let differentiator = match o.differentiator {
        Differentiator::ThreePoint => json!({"kind": "three-point"}),
        Differentiator::SavitzkyGolay { window, order } => {
            json!({"kind": "savitzky-golay", "window": window, "order": order})
        }
    };
    let hold = |h: FilterHold| match h {
        FilterHold::Zoh => "zoh",
        FilterHold::Foh => "foh",
    };
    let filter = match o.prefilter {
        Prefilter::None => json!({"kind": "none"}),
        Prefilter::Causal { tf, hold: h } => json!({"kind": "causal", "tf": tf, "hold": hold(h)}),
        Prefilter::ZeroPhase { tf, hold: h } => {
            json!({"kind": "zero-phase", "tf": tf, "hold": hold(h)})
        }
    };
    json!({"differentiator": differentiator, "filter": filter})
}

/// Runs `pendulab identify`.
///
/// # Errors
/// Unreadable file, malformed CSV, missing columns, bad time stamps, a window outside the
/// data, too few samples, a rank-deficient regressor, absent features and implausible
/// estimates — each naming the file, column or row.
pub fn run(args: &IdentifyArgs) -> Result<()> {
    if matches!(args.method, Method::Arx | Method::Moesp) {
        return crate::identify_blackbox::run(args);
    }
    let blackbox_flags = [
        ("--input", args.input.is_some()),
        ("--output", args.output.is_some()),
        ("--na", args.na.is_some()),
        ("--nb", args.nb.is_some()),
        ("--nk", args.nk.is_some()),
        ("--max-order", args.max_order.is_some()),
        ("--order", args.order.is_some()),
        ("--horizon", args.horizon.is_some()),
        ("--validate", args.validate.is_some()),
        ("--decimate", args.decimate.is_some()),
    ];
    if let Some((flag, _)) = blackbox_flags.iter().find(|(_, given)| *given) {
        bail!(
            "identify {}: {flag} applies to arx and moesp only",
            args.method.name()
        );
    }
    if let Some(dir) = &args.save {
        // Refused before any work: a lab of the other plant.
        let lab = crate::lab::load(dir)?;
        if lab.kind() != args.method.plant() {
            bail!(
                "--save {}: {} identifies the {} pendulum, but the lab's plant is the {} pendulum",
                dir.display(),
                args.method.name(),
                args.method.plant().name(),
                lab.kind().name()
            );
        }
    }
    let report = identify(args)?;
    for w in &report.warnings {
        eprintln!("warning (--force): {w}");
    }
    let saved = match &args.save {
        Some(dir) => Some(save(args, dir, &report)?),
        None => None,
    };
    if args.json {
        let mut v = serde_json::to_value(&report)?;
        if let (Some(s), Some(m)) = (&saved, v.as_object_mut()) {
            m.insert("saved".into(), serde_json::to_value(s)?);
        }
        println!("{v}");
    } else {
        print_table(&report);
        if let Some(s) = &saved {
            println!();
            let set: Vec<String> = s
                .parameters
                .iter()
                .map(|(k, (old, new))| format!("{k} = {new:.6e} (was {old:.6e})"))
                .collect();
            println!("saved to {}: {}", s.file.display(), set.join(", "));
        }
    }
    Ok(())
}

/// The known constants of the pendulum methods: the flags, else (with `--save`) the lab's
/// parameters, else the book's (tables 3.5 and 3.7).
fn known_constants(args: &IdentifyArgs) -> Result<(CartPendulumConstants, ArmPendulumConstants)> {
    let params = match &args.save {
        Some(dir) => *crate::lab::load(dir)?.parameters(),
        None => PlantParameters::book(args.method.plant()),
    };
    let (cb, ab) = (CartPendulumParams::book(), ArmPendulumParams::book());
    let (cp, ap) = match params {
        PlantParameters::Cart(p) => (p, ab),
        PlantParameters::Arm(p) => (cb, p),
    };
    let g = match params {
        PlantParameters::Cart(p) => p.g,
        PlantParameters::Arm(p) => p.g,
    };
    Ok((
        CartPendulumConstants {
            mp: args.mp.unwrap_or(cp.m_p),
            lp: args.lp.unwrap_or(cp.l_p),
            g: args.g.unwrap_or(g),
        },
        ArmPendulumConstants {
            l1: args.l1.unwrap_or(ap.L1),
            m2: args.m2.unwrap_or(ap.m2),
            l2: args.l2.unwrap_or(ap.l2),
            g: args.g.unwrap_or(g),
        },
    ))
}
