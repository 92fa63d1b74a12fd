//! `pendulab estimate --log FILE.csv [--method ekf|ukf|kf]`: the cart's velocities from a
//! recorded run by a Kalman filter on the book's model, beside the rig's pseudo-differentiator.
//!
//! The log is CSV with a header (`pendulab_ident::Dataset`): `t` in seconds (uniform), the
//! cart position `z` \[m\], the pendulum angle from the hanging rest `phi` (or `theta`, as the
//! book's files name it) \[rad\] and the voltage `v` \[V\] — the columns of
//! `data/rig/cdip_least_square_data.csv` (the book's least-squares run, 1 ms). The model is the
//! cart pendulum of book table 3.5 (`pendulab_plants::CartPendulum::book`) with the angle
//! `θ = φ + π` from the upright; the encoders' resolutions are the rig's
//! (`RigSpec::cart`: 4.8414·10⁻⁵ m, 2π/14400 rad), their rounding the measurement noise
//! `R = diag(q²/12)`; the process noise `Q = diag(0, 0, (σ_a ts)², (σ_α ts)²)` stands for
//! unmodelled cart and pendulum accelerations of standard deviations `--sigma-acc` \[m/s²\] and
//! `--sigma-alpha` \[rad/s²\] over a sample (plus 10⁻¹⁴ on the positions, so that `Q ≻ 0`).
//!
//! - `ekf`, `ukf`: the extended and unscented filters of `pendulab_control::kalman` on the
//!   nonlinear model (RK4 over each sample, the logged voltage held);
//! - `kf`: the Kalman filter of the model linearised at the hanging rest (ZOH), in deviations.
//!
//! The pseudo-differentiator is the rig's `s/(T s + 1)`, `T = 0.02 s` (Tustin at the log's
//! sample time, as `pendulab-sim`'s sensor chain) on the logged positions. The command writes
//! the figure (both velocity estimates over time, `--out`, SVG or PNG), optionally the
//! estimates as CSV (`--csv`), and prints the RMS difference of the two estimates and the
//! filter's mean NIS (≈ 2 for a filter whose noise model fits the data).

use anyhow::{Context, Result, bail};
use pendulab_control::kalman::{
    ExtendedKalmanFilter, KalmanFilter, Measurement, NonlinearFilter, SampledModel, SigmaPoints,
    UnscentedKalmanFilter, encoder_covariance, filter_log,
};
use pendulab_ident::Dataset;
use pendulab_lti::{Discretization, Mat, Trajectory};
use pendulab_plants::{CartEquilibrium, CartPendulum, RigSpec};
use pendulab_plot::{Channel, SignalPanel, TimeResponse};
use pendulab_sim::{Differentiation, PseudoDifferentiator};
use serde::Serialize;
use std::f64::consts::PI;
use std::path::PathBuf;

/// The estimator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum EstimateMethod {
    /// Extended Kalman filter on the nonlinear model.
    Ekf,
    /// Unscented Kalman filter on the nonlinear model (α = 1, β = 2, κ = 0).
    Ukf,
    /// Kalman filter of the model linearised at the hanging rest.
    Kf,
}

/// Arguments of `pendulab estimate`.
#[derive(Debug, clap::Args)]
pub struct EstimateArgs {
    /// The cart's log: CSV with t, z, phi (or theta, from the hanging rest) and v.
    #[arg(long)]
    pub log: PathBuf,
    /// The estimator.
    #[arg(long, value_enum, default_value_t = EstimateMethod::Ekf)]
    pub method: EstimateMethod,
    /// Standard deviation of the unmodelled cart acceleration [m/s²].
    #[arg(long, default_value_t = 0.5)]
    pub sigma_acc: f64,
    /// Standard deviation of the unmodelled pendulum acceleration [rad/s²].
    #[arg(long, default_value_t = 5.0)]
    pub sigma_alpha: f64,
    /// The figure's file, .svg or .png (default: LOG's name with _estimate.svg).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also write t, the filter's z, θ, ż, θ̇ and the pseudo-differentiator's ż, θ̇ as CSV.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Print one JSON object instead of lines.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct EstimateJson {
    log: PathBuf,
    method: String,
    samples: usize,
    sample_time: f64,
    figure: PathBuf,
    csv: Option<PathBuf>,
    /// RMS of (filter − pseudo-differentiator) for ż [m/s] and θ̇ [rad/s].
    rms_difference: [f64; 2],
    /// RMS of the filter's ż [m/s] and θ̇ [rad/s].
    rms_velocity: [f64; 2],
    mean_nis: f64,
    noise: String,
}

fn column<'a>(data: &'a Dataset, names: &[&str]) -> Result<&'a [f64]> {
    for n in names {
        if data.names().iter().any(|c| c == n) {
            return Ok(data.column(n)?);
        }
    }
    bail!(
        "{}: no column {} (columns: {})",
        data.source(),
        names.join(" or "),
        data.names().join(", ")
    )
}

fn rms(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x * x, n + 1));
    (s / n.max(1) as f64).sqrt()
}

/// Runs `pendulab estimate`.
///
/// # Errors
/// An unreadable or malformed log (naming the file and column), a non-uniform time column,
/// non-positive noise levels, a filter that fails (a typed error of `pendulab-control`), a
/// figure or CSV that cannot be written.
pub fn run(args: &EstimateArgs) -> Result<()> {
    let source = args.log.display().to_string();
    let text =
        std::fs::read_to_string(&args.log).with_context(|| format!("cannot read {source}"))?;
    let data = Dataset::from_csv_str(&source, &text)?;
    let ts = data.sample_time()?;
    let t = data.time()?.to_vec();
    let z = column(&data, &["z"])?;
    let phi = column(&data, &["phi", "theta"])?;
    let v = column(&data, &["v"])?;
    for (name, c) in [("z", z), ("phi", phi), ("v", v)] {
        if let Some(k) = c.iter().position(|x| !x.is_finite()) {
            bail!(
                "{source}: column '{name}', row {}: not a finite number",
                k + 2
            );
        }
    }
    for (name, s) in [
        ("--sigma-acc", args.sigma_acc),
        ("--sigma-alpha", args.sigma_alpha),
    ] {
        if !(s.is_finite() && s > 0.0) {
            bail!("{name} {s}: must be positive");
        }
    }
    let rig = RigSpec::cart();
    let r = encoder_covariance(&[rig.encoders[0].step, rig.encoders[1].step])?;
    let q = Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[
        1e-14,
        1e-14,
        (args.sigma_acc * ts).powi(2),
        (args.sigma_alpha * ts).powi(2),
    ]));
    // θ from the upright: the log's angle is from the hanging rest.
    let y: Vec<Vec<f64>> = z.iter().zip(phi).map(|(&z, &p)| vec![z, p + PI]).collect();
    let u: Vec<Vec<f64>> = v.iter().map(|&v| vec![v]).collect();
    let x0 = [y[0][0], y[0][1], 0.0, 0.0];
    let p0 = Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[
        r[(0, 0)],
        r[(1, 1)],
        1e-2,
        1e-2,
    ]));
    let plant = CartPendulum::book();
    let model = || SampledModel::new(plant, ts, 1, Measurement::States(vec![0, 1]), &q, &r);
    let (states, nis): (Vec<Vec<f64>>, Vec<f64>) = match args.method {
        EstimateMethod::Ekf => {
            let mut f = ExtendedKalmanFilter::new(model()?, &x0, &p0)?;
            let run = filter_log(&mut f as &mut dyn NonlinearFilter, &t, &u, &y)?;
            (run.states, run.nis)
        }
        EstimateMethod::Ukf => {
            let mut f = UnscentedKalmanFilter::new(model()?, &x0, &p0, SigmaPoints::default())?;
            let run = filter_log(&mut f, &t, &u, &y)?;
            (run.states, run.nis)
        }
        EstimateMethod::Kf => {
            let rest = CartEquilibrium::hanging();
            let lin = plant
                .linearize_measured(rest)?
                .c2d(ts, Discretization::Zoh)?;
            let xe = rest.state().to_array();
            let dev = |x: &[f64]| -> Vec<f64> { x.iter().zip(&xe).map(|(a, b)| a - b).collect() };
            let mut f = KalmanFilter::new(&dev(&x0), &p0)?;
            let (mut states, mut nis) = (Vec::new(), Vec::new());
            for k in 0..t.len() {
                if k > 0 {
                    f.predict(lin.a(), lin.b(), &u[k - 1], &q)?;
                }
                let inn = f.update(lin.c(), None, &dev(&y[k]), &r)?;
                nis.push(inn.nis);
                states.push(f.state().iter().zip(&xe).map(|(a, b)| a + b).collect());
            }
            (states, nis)
        }
    };
    let pd = PseudoDifferentiator::new(
        rig.velocity_estimators[0].time_constant,
        Differentiation::Tustin,
        ts,
    )?;
    let dz_pd = pd.filter(z);
    let dth_pd = pd.filter(phi);
    let n = t.len();
    let filt = Mat::from_fn(n, 4, |k, i| states[k][i]);
    let pdm = Mat::from_fn(n, 4, |k, i| match i {
        0 => y[k][0],
        1 => y[k][1],
        2 => dz_pd[k],
        _ => dth_pd[k],
    });
    let vin = Mat::from_fn(n, 1, |k, _| v[k]);
    let tr_f = Trajectory::new(t.clone(), filt, vin.clone(), Mat::zeros(n, 0))?;
    let tr_p = Trajectory::new(t.clone(), pdm, vin, Mat::zeros(n, 0))?;
    let name = match args.method {
        EstimateMethod::Ekf => "EKF",
        EstimateMethod::Ukf => "UKF",
        EstimateMethod::Kf => "KF (hanging linearisation)",
    };
    let figure = TimeResponse::new()
        .run(name, &tr_f)
        .run("pseudo-differentiator s/(0.02 s + 1)", &tr_p)
        .title(format!("{}: cart velocities", args.log.display()))
        .panel(SignalPanel::new(Channel::State(2), "dz/dt [m/s]"))
        .panel(SignalPanel::new(Channel::State(3), "dθ/dt [rad/s]"))
        .panel(SignalPanel::new(Channel::Input(0), "v [V]"))
        .figure()
        .context("drawing the figure")?;
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = args
            .log
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "log".into());
        args.log.with_file_name(format!("{stem}_estimate.svg"))
    });
    let bytes = match out.extension().and_then(|e| e.to_str()) {
        Some("svg") => figure.to_svg()?.into_bytes(),
        Some("png") => figure.to_png()?,
        _ => bail!("--out {}: must end in .svg or .png", out.display()),
    };
    crate::lab::write_whole(&out, &bytes)?;
    if let Some(path) = &args.csv {
        let mut s = String::from("t,z,theta,dz,dtheta,dz_pd,dtheta_pd\n");
        for k in 0..n {
            let x = &states[k];
            s.push_str(&format!(
                "{},{},{},{},{},{},{}\n",
                t[k], x[0], x[1], x[2], x[3], dz_pd[k], dth_pd[k]
            ));
        }
        crate::lab::write_whole(path, s.as_bytes())?;
    }
    let json = EstimateJson {
        log: args.log.clone(),
        method: name.into(),
        samples: n,
        sample_time: ts,
        figure: out,
        csv: args.csv.clone(),
        rms_difference: [
            rms(states.iter().zip(&dz_pd).map(|(x, p)| x[2] - p)),
            rms(states.iter().zip(&dth_pd).map(|(x, p)| x[3] - p)),
        ],
        rms_velocity: [
            rms(states.iter().map(|x| x[2])),
            rms(states.iter().map(|x| x[3])),
        ],
        mean_nis: nis.iter().sum::<f64>() / n as f64,
        noise: format!(
            "R = diag(q²/12) for the encoder steps {} m, {} rad; Q = diag(1e-14, 1e-14, ({} ts)², ({} ts)²)",
            rig.encoders[0].step, rig.encoders[1].step, args.sigma_acc, args.sigma_alpha
        ),
    };
    if args.json {
        println!("{}", serde_json::to_string(&json)?);
        return Ok(());
    }
    println!("wrote {}", json.figure.display());
    if let Some(c) = &json.csv {
        println!("wrote {}", c.display());
    }
    println!(
        "{}: {} samples at {} s; {}",
        json.method, json.samples, json.sample_time, json.noise
    );
    println!(
        "RMS of the filter's velocities: ż {:.4} m/s, θ̇ {:.4} rad/s",
        json.rms_velocity[0], json.rms_velocity[1]
    );
    println!(
        "RMS difference filter − pseudo-differentiator: ż {:.4} m/s, θ̇ {:.4} rad/s",
        json.rms_difference[0], json.rms_difference[1]
    );
    println!(
        "mean NIS {:.2} (2 for a filter whose noise model fits the data)",
        json.mean_nis
    );
    Ok(())
}
