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

use anyhow::{Context, Result, anyhow, bail};
use pendulab_ident::{
    ArmPendulumConstants, CartPendulumConstants, Dataset, Differentiator, FilterHold, IdentError,
    LsOptions, OscillationOptions, PStepOptions, PeriodCorrection, Prefilter, TimeUnit, Validation,
    arm_drive_ls, arm_pendulum_ls, cart_drive_ls, cart_pendulum_ls, free_oscillation, p_step,
    pendulum_from_oscillation, validate_arm_pendulum, validate_cart_pendulum, validate_drive,
    validate_free_pendulum, validate_oscillation, validate_p_step,
};
use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::{PlantParameters, PlantSpec, Provenance};
use pendulab_plants::{ArmPendulumParams, CartPendulumParams};
use serde::Serialize;
use serde_json::{Map, Value, json};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

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

/// One output of the identification.
#[derive(Debug, Serialize)]
struct Report {
    method: &'static str,
    data: String,
    window: [f64; 2],
    samples: usize,
    ts: f64,
    options: Value,
    constants: Value,
    estimates: Map<String, Value>,
    std_errors: Map<String, Value>,
    /// Least-squares methods only (the feature methods have no regressor): left out otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    condition: Option<Value>,
    /// Least-squares methods only: left out otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    residual_rms: Option<Value>,
    fit: Value,
    #[serde(skip_serializing_if = "Option::is_none")]
    fit_linear: Option<Value>,
    /// Every check that failed and was overridden by `--force` (empty otherwise).
    warnings: Vec<String>,
    #[serde(skip)]
    units: Vec<(&'static str, &'static str)>,
}

/// Applies the checks: a failure is an error, or with `--force` a warning.
struct Gate {
    force: bool,
    warnings: Vec<String>,
}

impl Gate {
    /// Every failure of a list (the first refuses; forced, all become warnings).
    fn check_all(&mut self, failures: Vec<IdentError>) -> Result<()> {
        for e in failures {
            self.check(Err(e))?;
        }
        Ok(())
    }

    fn check(&mut self, r: pendulab_ident::Result<()>) -> Result<()> {
        match r {
            Ok(()) => Ok(()),
            Err(e) if self.force => {
                // A number already reported non-finite (by the least-squares check) is not
                // reported again when it is written out.
                let text = e.to_string();
                let head = text.split(" is not a finite number").next().unwrap_or("");
                let repeat = matches!(e, IdentError::NonFiniteResult { .. })
                    && self.warnings.iter().any(|w| w.starts_with(head));
                if !repeat {
                    self.warnings.push(text);
                }
                Ok(())
            }
            Err(e) => Err(anyhow!(
                "{e}\n(refused; --force prints the result anyway, with this as a warning)"
            )),
        }
    }

    /// A computation that may fail after the estimate exists (validation): its value, or
    /// with `--force` `None` and a warning.
    fn soft<T>(&mut self, what: &str, r: pendulab_ident::Result<T>) -> Result<Option<T>> {
        match r {
            Ok(v) => Ok(Some(v)),
            Err(e) if self.force => {
                self.warnings.push(format!("{what} not run: {e}"));
                Ok(None)
            }
            Err(e) => Err(anyhow::Error::new(e).context(what.to_string())),
        }
    }

    /// Inserts a number into an output map; a NaN or ∞ is refused (forced: `null` and a
    /// warning naming it).
    fn put(&mut self, map: &mut Map<String, Value>, name: &str, v: f64) -> Result<()> {
        self.put_labelled(map, name, name, v)
    }

    /// As [`Gate::put`] for a standard error.
    fn put_se(&mut self, map: &mut Map<String, Value>, name: &str, v: f64) -> Result<()> {
        self.put_labelled(map, name, &format!("standard error of {name}"), v)
    }

    fn put_labelled(
        &mut self,
        map: &mut Map<String, Value>,
        name: &str,
        label: &str,
        v: f64,
    ) -> Result<()> {
        let x = self.num(label, v)?;
        map.insert(name.into(), x);
        Ok(())
    }

    /// A number for the output: a JSON number if finite; a NaN or ∞ is refused (forced: the
    /// string `"NaN"`, `"inf"` or `"-inf"`, never a `null`, and a warning naming it).
    fn num(&mut self, label: &str, v: f64) -> Result<Value> {
        if v.is_finite() {
            return Ok(json!(v));
        }
        self.check(Err(IdentError::NonFiniteResult {
            what: label.into(),
            value: v,
            reason: "written as a string in the JSON output".into(),
        }))?;
        Ok(Value::String(format!("{v}")))
    }
}

/// A number in a description: five significant digits.
fn g4(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-3..1e5).contains(&x.abs()) {
        format!("{x:.4e}")
    } else {
        format!("{:.5}", x)
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    }
}

/// What a validation simulated: the model, its input, the window and the compared signal.
struct FitMeaning<'a> {
    model: String,
    input: &'a str,
    t: &'a [f64],
}

fn fit_json(gate: &mut Gate, v: &Validation, m: &FitMeaning<'_>) -> Result<Value> {
    let t0 = m.t[v.start.min(m.t.len() - 1)];
    let t1 = m.t[m.t.len() - 1];
    let description = format!(
        "{} simulated on {}, t = {t0}–{t1} s, compared with the measured {}",
        m.model, m.input, v.output
    );
    Ok(json!({
        "output": v.output,
        "percent": gate.num("validation fit", v.fit_percent)?,
        "rms_error": gate.num("validation RMS error", v.rms_error)?,
        "model": m.model,
        "input": m.input,
        "window": [t0, t1],
        "description": description,
    }))
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

/// Writes the method's parameter estimates into `DIR/lab.toml` (`--save`).
///
/// The provenance becomes `identified` with the data file as named, the SHA-256 of its bytes,
/// the window of the report and the standard errors of the estimates. Parameters identified
/// earlier from the **same** record (same SHA-256 and window) keep theirs, so `cart-ls` and
/// `pend-ls` on one run both land in the file; a lab identified from another record or window
/// is refused (its other parameters would be left with no provenance) unless
/// `provenance.source` is first set back to "user" or "book" by hand.
///
/// # Errors
/// A forced result (failed checks); an estimate that is not a number; the lab's validation of
/// the new values (naming the key); a file that cannot be written. Nothing is written then.
fn save(args: &IdentifyArgs, dir: &Path, report: &Report) -> Result<SavedOut> {
    if !report.warnings.is_empty() {
        bail!(
            "--save {}: not saved, {} check(s) failed (see the warnings)",
            dir.display(),
            report.warnings.len()
        );
    }
    let lab = crate::lab::load(dir)?;
    let bytes = std::fs::read(&args.data)
        .with_context(|| format!("cannot read {}", args.data.display()))?;
    let sha = crate::lab::sha256_hex(&bytes);
    let file = args.data.display().to_string();
    let window = report.window;
    let mut errors = BTreeMap::new();
    let mut method = format!("pendulab identify {}", args.method.name());
    match lab.provenance() {
        Provenance::Identified {
            sha256: old_sha,
            window: old_window,
            standard_errors,
            method: old_method,
            ..
        } => {
            if *old_sha != sha || *old_window != window {
                bail!(
                    "--save {}: the lab's parameters were identified from another record or window ({}); \
                     identify from the same record and window, or set provenance.source = \"user\" in {} first",
                    dir.display(),
                    crate::lab::provenance_label(lab.provenance()),
                    dir.join(crate::lab::LAB_FILE).display()
                );
            }
            errors = standard_errors.clone();
            if let Some(m) = old_method
                && !m.contains(&method)
            {
                method = format!("{m}; {method}");
            }
        }
        Provenance::Book {} | Provenance::User { .. } => {}
    }
    let mut entries = lab.parameters().entries();
    let mut changed = Map::new();
    for (est, key) in args.method.parameters() {
        let value = report
            .estimates
            .get(est)
            .and_then(Value::as_f64)
            .with_context(|| format!("--save: the estimate {est} is not a number"))?;
        let se = report.std_errors.get(est).and_then(Value::as_f64);
        let entry = entries
            .iter_mut()
            .find(|(k, _)| k == key)
            .with_context(|| format!("--save: the lab has no parameter {key}"))?;
        changed.insert(key.into(), json!([entry.1, value]));
        entry.1 = value;
        match se {
            Some(se) => errors.insert(key.to_string(), se),
            None => errors.remove(key),
        };
    }
    let parameters = PlantParameters::from_entries(lab.kind(), entries)?;
    let provenance = Provenance::Identified {
        file,
        sha256: sha,
        window,
        standard_errors: errors,
        method: Some(method),
    };
    let spec = PlantSpec::new(parameters, provenance, *lab.rig())
        .with_context(|| format!("--save {}: the identified parameters", dir.display()))?;
    let path = crate::lab::write_lab(dir, &spec)?;
    Ok(SavedOut {
        file: path,
        parameters: changed
            .into_iter()
            .filter_map(|(k, v)| {
                let a = v.as_array()?;
                Some((k, (a[0].as_f64()?, a[1].as_f64()?)))
            })
            .collect(),
    })
}

/// What `--save` wrote: the lab file and each parameter's `(old, new)` value.
#[derive(Serialize)]
struct SavedOut {
    file: PathBuf,
    parameters: BTreeMap<String, (f64, f64)>,
}

fn identify(args: &IdentifyArgs) -> Result<Report> {
    let source = args.data.display().to_string();
    let text =
        std::fs::read_to_string(&args.data).with_context(|| format!("cannot read {source}"))?;
    let mut gate = Gate {
        force: args.force,
        warnings: Vec::new(),
    };
    let mut full = Dataset::from_csv_str(&source, &text)?;
    if let Some(u) = args.time_unit {
        full = full.with_time_unit(u.into())?;
    }
    // The unit is judged on the whole record, before a window (in seconds) is cut from it.
    gate.check(full.check_time_unit())?;
    let (w0, w1) = match &args.window {
        Some(s) => parse_window(s)?,
        None => (None, None),
    };
    let data = full.window(w0, w1)?;
    let ts = data.uniform_step()?;
    let t = data.time()?;
    let span = [t[0], t[t.len() - 1]];
    let opts = ls_options(args);
    let (cart, arm) = known_constants(args)?;
    let mut est = Map::new();
    let mut se = Map::new();
    let mut report = Report {
        method: args.method.name(),
        data: source.clone(),
        window: span,
        samples: data.len(),
        ts,
        options: Value::Null,
        constants: Value::Null,
        estimates: Map::new(),
        std_errors: Map::new(),
        condition: None,
        residual_rms: None,
        fit: json!({"skipped": "no validation was run"}),
        fit_linear: None,
        warnings: Vec::new(),
        units: Vec::new(),
    };
    // Structural errors first: every column the method reads must be present.
    let signal = |cart: &str, arm: &str| -> String {
        args.column.clone().unwrap_or_else(|| {
            if matches!(args.method, Method::CartStep | Method::PendFree) {
                cart.to_string()
            } else {
                arm.to_string()
            }
        })
    };
    let needed: Vec<String> = match args.method {
        Method::CartLs => vec!["z".into(), "v".into()],
        Method::ArmLs => vec!["phi1".into(), "v".into()],
        Method::PendLs => vec!["z".into(), "phi".into()],
        Method::ArmPendLs => vec!["phi1".into(), "phi2".into()],
        Method::CartStep | Method::ArmStep => vec![signal("z", "theta1")],
        Method::PendFree | Method::ArmPendFree => vec![signal("theta", "theta2")],
        Method::Arx | Method::Moesp => {
            bail!("identify: arx and moesp are run by identify_blackbox")
        }
    };
    for c in &needed {
        data.column(c)?;
    }
    let ls_method = matches!(
        args.method,
        Method::CartLs | Method::ArmLs | Method::PendLs | Method::ArmPendLs
    );
    if ls_method {
        let named = opts.check_data(ts, data.len()).map_err(|e| match e {
            IdentError::TooFewSamples {
                what,
                needed,
                found,
                ..
            } => IdentError::TooFewSamples {
                source_name: format!("{source} (t = {} … {} s)", span[0], span[1]),
                what,
                needed,
                found,
            },
            other => other,
        });
        gate.check(named)?;
    }
    match args.method {
        Method::PendLs | Method::PendFree => gate.check(cart.check_range())?,
        Method::ArmPendLs | Method::ArmPendFree => gate.check(arm.check_range())?,
        _ => {}
    }
    match args.method {
        Method::CartLs | Method::ArmLs => {
            let (ycol, names) = if args.method == Method::CartLs {
                ("z", ["ac", "bc"])
            } else {
                ("phi1", ["a1", "b1"])
            };
            let (y, v) = (data.column(ycol)?, data.column("v")?);
            let d = if args.method == Method::CartLs {
                cart_drive_ls(ts, y, v, &opts)?
            } else {
                arm_drive_ls(ts, y, v, &opts)?
            };
            gate.check_all(d.failed_checks(ts))?;
            for (i, n) in names.iter().enumerate() {
                gate.put(&mut est, n, d.lsq.estimate[i])?;
                gate.put_se(&mut se, n, d.lsq.std_error[i])?;
            }
            report.condition = Some(gate.num("condition number", d.lsq.condition)?);
            report.residual_rms = Some(gate.num("residual RMS", d.lsq.residual_rms)?);
            let meaning = FitMeaning {
                model: format!(
                    "the identified drive {ycol}'' = −{} {ycol}' + ({}) v (exact ZOH simulation, open loop from the measured initial state)",
                    g4(d.a),
                    g4(d.b)
                ),
                input: "the measured voltage v",
                t,
            };
            if let Some(val) = gate.soft("validation", validate_drive(ts, y, v, d.a, d.b, ycol))? {
                report.fit = fit_json(&mut gate, &val, &meaning)?;
            }
            report.options = options_json(&opts);
            report.constants = json!({});
            report.units = if args.method == Method::CartLs {
                vec![("ac", "1/s"), ("bc", "m/(s^2 V)")]
            } else {
                vec![("a1", "1/s"), ("b1", "rad/(s^2 V)")]
            };
        }
        Method::PendLs => {
            let (z, phi) = (data.column("z")?, data.column("phi")?);
            let p = cart_pendulum_ls(ts, z, phi, &cart, &opts)?;
            gate.check_all(p.failed_checks(ts, &cart))?;
            gate.put(&mut est, "Jp", p.jp)?;
            gate.put(&mut est, "mup", p.mup)?;
            gate.put_se(&mut se, "Jp", p.lsq.std_error[0])?;
            gate.put_se(&mut se, "mup", p.lsq.std_error[1])?;
            report.condition = Some(gate.num("condition number", p.lsq.condition)?);
            report.residual_rms = Some(gate.num("residual RMS", p.lsq.residual_rms)?);
            let meaning = FitMeaning {
                model: "the identified nonlinear cart pendulum (J_p, μ_p with the known m_p, l_p, g; RK4 from the measured initial angle and rate)".into(),
                input: "the measured cart acceleration (three-point z'' of z)",
                t,
            };
            if let Some(val) = gate.soft(
                "validation",
                validate_cart_pendulum(ts, z, phi, p.jp, p.mup, &cart),
            )? {
                report.fit = fit_json(&mut gate, &val, &meaning)?;
            }
            report.options = options_json(&opts);
            report.constants = json!({"mp": cart.mp, "lp": cart.lp, "g": cart.g});
            report.units = vec![("Jp", "kg m^2"), ("mup", "N m s/rad")];
        }
        Method::ArmPendLs => {
            let (p1, p2) = (data.column("phi1")?, data.column("phi2")?);
            let p = arm_pendulum_ls(ts, p1, p2, &arm, &opts)?;
            gate.check_all(p.failed_checks(ts, &arm))?;
            gate.put(&mut est, "J2", p.j2)?;
            gate.put(&mut est, "mu2", p.mu2)?;
            gate.put(&mut est, "alpha2", p.alpha2)?;
            gate.put_se(&mut se, "J2", p.lsq.std_error[0])?;
            gate.put_se(&mut se, "mu2", p.lsq.std_error[1])?;
            gate.put_se(&mut se, "alpha2", p.lsq.std_error[0])?;
            report.condition = Some(gate.num("condition number", p.lsq.condition)?);
            report.residual_rms = Some(gate.num("residual RMS", p.lsq.residual_rms)?);
            let meaning = FitMeaning {
                model: "the identified nonlinear arm pendulum (α₂, μ₂ with the known L1, m2, l2, g; RK4 from the measured initial angle and rate)".into(),
                input: "the measured arm motion phi1 (with its three-point derivatives)",
                t,
            };
            if let Some(val) = gate.soft(
                "validation",
                validate_arm_pendulum(ts, p1, p2, p.alpha2, p.mu2, &arm),
            )? {
                report.fit = fit_json(&mut gate, &val, &meaning)?;
            }
            report.options = options_json(&opts);
            report.constants = json!({"L1": arm.l1, "m2": arm.m2, "l2": arm.l2, "g": arm.g});
            report.units = vec![("J2", "kg m^2"), ("mu2", "N m s/rad"), ("alpha2", "kg m^2")];
        }
        Method::CartStep | Method::ArmStep => {
            let cart_step = args.method == Method::CartStep;
            let col = args
                .column
                .clone()
                .unwrap_or_else(|| if cart_step { "z" } else { "theta1" }.to_string());
            let y = data.column(&col)?;
            let o = PStepOptions {
                step_time: args.step_time.or(w0).unwrap_or(1.0),
                target: args.target.unwrap_or(if cart_step { 0.2 } else { 1.0 }),
                k_p: args.kp.unwrap_or(if cart_step { 10.0 } else { 3.0 }),
            };
            let e = p_step(t, y, &o).with_context(|| format!("{source}: column '{col}'"))?;
            let (a, b) = if cart_step {
                ("ac", "bc")
            } else {
                ("a1", "b1")
            };
            gate.put(&mut est, a, e.a)?;
            gate.put(&mut est, b, e.b)?;
            gate.put(&mut est, "Tp", e.tp)?;
            gate.put(&mut est, "overshoot", e.overshoot)?;
            gate.put(&mut est, "omega_n", e.omega_n)?;
            gate.put(&mut est, "zeta", e.zeta)?;
            let meaning = FitMeaning {
                model: format!(
                    "the P-control loop of the identified drive ({a} = {}, {b} = {}, k_P = {}), at rest at the step time {} s",
                    g4(e.a),
                    g4(e.b),
                    o.k_p,
                    o.step_time
                ),
                input: &format!("the reference step to {}", o.target),
                t,
            };
            if let Some(mut val) = gate.soft(
                "validation",
                validate_p_step(t, y, o.step_time, o.target, o.k_p, e.a, e.b),
            )? {
                val.output = col.clone();
                report.fit = fit_json(&mut gate, &val, &meaning)?;
            }
            report.options = json!({"column": col, "step_time": o.step_time});
            report.constants = json!({"kP": o.k_p, "target": o.target});
            report.units = vec![
                (a, "1/s"),
                (
                    b,
                    if cart_step {
                        "m/(s^2 V)"
                    } else {
                        "rad/(s^2 V)"
                    },
                ),
                ("Tp", "s"),
                ("overshoot", if cart_step { "m" } else { "rad" }),
                ("omega_n", "rad/s"),
                ("zeta", "-"),
            ];
        }
        Method::PendFree | Method::ArmPendFree => {
            let cart_pend = args.method == Method::PendFree;
            let col = args
                .column
                .clone()
                .unwrap_or_else(|| if cart_pend { "theta" } else { "theta2" }.to_string());
            let y = data.column(&col)?;
            let osc = free_oscillation(
                t,
                y,
                &OscillationOptions {
                    hysteresis: args.hysteresis,
                },
            )
            .with_context(|| format!("{source}: column '{col}'"))?;
            let (m, l, g) = if cart_pend {
                (cart.mp, cart.lp, cart.g)
            } else {
                (arm.m2, arm.l2, arm.g)
            };
            let correction = if args.amplitude_correction {
                PeriodCorrection::LargeAmplitude
            } else {
                PeriodCorrection::None
            };
            let p = pendulum_from_oscillation(&osc, m, l, g, correction)?;
            let (jn, mun) = if cart_pend {
                ("Jp", "mup")
            } else {
                ("J2", "mu2")
            };
            gate.put(&mut est, jn, p.j)?;
            gate.put(&mut est, mun, p.mu)?;
            gate.put(&mut est, "period", osc.period)?;
            gate.put(&mut est, "decay_ratio", osc.decay_ratio)?;
            gate.put(&mut est, "omega_n", p.omega_n)?;
            gate.put(&mut est, "zeta", p.zeta)?;
            if let Some((sj, sm)) = p.std_errors {
                gate.put_se(&mut se, jn, sj)?;
                gate.put_se(&mut se, mun, sm)?;
            }
            if let Some(s) = osc.period_std_error {
                gate.put_se(&mut se, "period", s)?;
            }
            if let Some(s) = osc.decay_ratio_std_error {
                gate.put_se(&mut se, "decay_ratio", s)?;
            }
            // Two checks from the first peak: the nonlinear pendulum the parameters belong
            // to (`fit`), and the book's linear oscillation (`fit_linear`).
            let start = osc.peaks[0].first;
            let nonlinear_meaning = FitMeaning {
                model: format!(
                    "the identified nonlinear pendulum on a held support ({jn}, {mun} with the known m, l, g), released at rest from the first peak"
                ),
                input: "no input (free swing)",
                t,
            };
            let linear_meaning = FitMeaning {
                model: format!(
                    "the book's linear oscillation (ω_n = {}, ζ = {}), released at rest from the first peak",
                    g4(p.omega_n),
                    g4(p.zeta)
                ),
                input: "no input (free swing)",
                t,
            };
            if let Some(mut nonlinear) = gate.soft(
                "validation",
                validate_free_pendulum(ts, y, start, p.j, p.mu, (m, l, g)),
            )? {
                nonlinear.output = col.clone();
                report.fit = fit_json(&mut gate, &nonlinear, &nonlinear_meaning)?;
            }
            if let Some(mut linear) = gate.soft(
                "linear validation",
                validate_oscillation(ts, y, start, p.omega_n, p.zeta),
            )? {
                linear.output = col.clone();
                report.fit_linear = Some(fit_json(&mut gate, &linear, &linear_meaning)?);
            }
            report.options = json!({
                "column": col,
                "peaks": osc.peaks.len(),
                "hysteresis": osc.hysteresis,
                "amplitude_correction": args.amplitude_correction,
                "corrected_period": p.period,
            });
            report.constants = if cart_pend {
                json!({"mp": m, "lp": l, "g": g})
            } else {
                json!({"m2": m, "l2": l, "g": g})
            };
            report.units = vec![
                (jn, "kg m^2"),
                (mun, "N m s/rad"),
                ("period", "s"),
                ("decay_ratio", "-"),
                ("omega_n", "rad/s"),
                ("zeta", "-"),
            ];
        }
        // Bailed out above (the columns' match).
        Method::Arx | Method::Moesp => {}
    }
    report.estimates = est;
    report.std_errors = se;
    report.warnings = gate.warnings;
    Ok(report)
}

fn print_table(r: &Report) {
    println!(
        "pendulab identify {} — {}: {} samples, t = {} … {} s, ts = {} s",
        r.method, r.data, r.samples, r.window[0], r.window[1], r.ts
    );
    if !r.options.is_null() {
        println!("options: {}", r.options);
    }
    if r.constants.as_object().is_some_and(|m| !m.is_empty()) {
        println!("known constants: {}", r.constants);
    }
    println!();
    println!(
        "{:<12} {:>14} {:>12}  unit",
        "parameter", "estimate", "std. error"
    );
    for (name, unit) in &r.units {
        let v = match r.estimates.get(*name) {
            None => continue,
            Some(x) => x.as_f64().unwrap_or(f64::NAN),
        };
        let se = r
            .std_errors
            .get(*name)
            .map_or("—".to_string(), |s| match s.as_f64() {
                Some(s) => format!("{s:.3e}"),
                None => s.as_str().unwrap_or("—").to_string(),
            });
        let shown = if v.is_finite() {
            format!("{v:.6e}")
        } else {
            "not finite".to_string()
        };
        println!("{name:<12} {shown:>14} {se:>12}  {unit}");
    }
    println!();
    let shown = |x: &Value, digits: usize, sci: bool| match x.as_f64() {
        Some(v) if sci => format!("{v:.digits$e}"),
        Some(v) => format!("{v:.digits$}"),
        None => format!("{} (not finite)", x.as_str().unwrap_or("?")),
    };
    if let Some(c) = &r.condition {
        println!("condition number of the regressor: {}", shown(c, 4, false));
    }
    if let Some(rms) = &r.residual_rms {
        println!("residual RMS: {}", shown(rms, 4, true));
    }
    let describe = |f: &Value, label: &str| match f.get("percent") {
        Some(p) => println!(
            "{label}: {} % — {}  (fit = 100 (1 − ‖y − ŷ‖/‖y − mean y‖))",
            p.as_f64()
                .map_or_else(|| format!("{p} (not finite)"), |p| format!("{p:.2}")),
            f.get("description").and_then(Value::as_str).unwrap_or("")
        ),
        None => println!("{label}: not run (see the warnings)"),
    };
    describe(&r.fit, "validation fit");
    if let Some(f) = &r.fit_linear {
        describe(
            f,
            "validation fit of the linearised oscillation (the book's check)",
        );
    }
    if !r.warnings.is_empty() {
        println!();
        println!(
            "WARNINGS — {} check(s) failed; printed only because of --force, the numbers above are not to be trusted:",
            r.warnings.len()
        );
        for w in &r.warnings {
            println!("  - {w}");
        }
    }
}
