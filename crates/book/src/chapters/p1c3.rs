//! Part 1 chapter 3: modelling and identification (book §3.1–3.4).
//!
//! The examples run on the rig measurements of `data/rig/` (embedded); the arm-rig examples
//! (`p1c332_*`) also take another recording with the same columns through `--data`. The
//! identification examples compute what the book's M-files of the same names compute (their
//! data windows, sample indices and formulas, cited by line), and report every number the
//! M-file displays under the M-file's variable names.

use super::common::*;
use super::p1c2::simulate_cart;
use crate::error::BookError;
use crate::output::{ExampleOutput, Value};
use crate::registry::{Example, RunContext};
use pendulab_ident::{
    ArmPendulumConstants, CartPendulumConstants, Dataset, LsOptions, OscillationOptions,
    PeriodCorrection, arm_drive_ls, arm_pendulum_ls, cart_drive_ls, cart_pendulum_ls,
    free_oscillation, pendulum_from_oscillation, validate_arm_pendulum, validate_cart_pendulum,
    validate_drive, validate_oscillation, validate_p_step,
};
use pendulab_plants::{CartPendulum, CartPendulumParams, CartPendulumState};
use pendulab_plot::IdentFit;
use pendulab_sim::controllers::{OpenLoop, Pid, PidDiscretization, PidForm};
use pendulab_sim::rig::RigChains;
use pendulab_sim::{SampledLoop, SampledOptions, Signal};
use std::f64::consts::PI;
use std::path::Path;

const PCONT: [(f64, &str, &str); 4] = [
    (
        2.5,
        "cdip_cart_pcont_data_kP_025_ref_02.csv",
        include_str!("../../../../data/rig/cdip_cart_pcont_data_kP_025_ref_02.csv"),
    ),
    (
        5.0,
        "cdip_cart_pcont_data_kP_050_ref_02.csv",
        include_str!("../../../../data/rig/cdip_cart_pcont_data_kP_050_ref_02.csv"),
    ),
    (
        10.0,
        "cdip_cart_pcont_data_kP_100_ref_02.csv",
        include_str!("../../../../data/rig/cdip_cart_pcont_data_kP_100_ref_02.csv"),
    ),
    (
        20.0,
        "cdip_cart_pcont_data_kP_200_ref_02.csv",
        include_str!("../../../../data/rig/cdip_cart_pcont_data_kP_200_ref_02.csv"),
    ),
];
const PEND: &str = include_str!("../../../../data/rig/cdip_pend_data.csv");
const LS: &str = include_str!("../../../../data/rig/cdip_least_square_data.csv");
/// The arm rig's k_P = 3 P-control step (`p1c332_adip_id_arm.m`, line 10).
const ARM_STEP: (&str, &str) = (
    "adip_arm_pcont_data_kP_3_ref_1.csv",
    include_str!("../../../../data/rig/adip_arm_pcont_data_kP_3_ref_1.csv"),
);
/// The arm rig's pendulum free oscillation (`p1c332_adip_id_pend.m`, line 4).
const ARM_PEND: (&str, &str) = (
    "adip_pend_data.csv",
    include_str!("../../../../data/rig/adip_pend_data.csv"),
);
/// The arm rig's least-squares record (`p1c332_adip_id_least_square.m`, line 8).
const ARM_LS: (&str, &str) = (
    "adip_least_square_data.csv",
    include_str!("../../../../data/rig/adip_least_square_data.csv"),
);

/// Time of the reference step in the rig's P-control recordings (s).
const STEP_TIME: f64 = 1.0;
/// Target of the rig's P-control recordings (m).
const TARGET: f64 = 0.2;

/// Columns and conventions of the arm-rig CSVs (`--data`; by default the shipped recordings).
const ARM_STEP_DATA: &str = "arm P-control step (k_P = 3, 1 rad reference step at t = 1 s; \
     default data/rig/adip_arm_pcont_data_kP_3_ref_1.csv): CSV columns t, theta1 (arm angle, \
     rad), theta2 optional (pendulum angle from hanging, rad)";
const ARM_PEND_DATA: &str = "arm pendulum free oscillation with the arm held, analysed over \
     50-66 s (default data/rig/adip_pend_data.csv): CSV columns t, theta2 (pendulum angle from \
     the hanging rest, rad)";
const ARM_LS_DATA: &str = "arm rig under any excitation, used over 1-9 s (default \
     data/rig/adip_least_square_data.csv): CSV columns t, phi1 (arm angle, rad), phi2 \
     (pendulum angle from hanging, rad), v (input voltage, V)";

fn ex(
    id: &'static str,
    title: &'static str,
    section: &'static str,
    parameters: &'static str,
    needs_data: Option<&'static str>,
    run: fn(&RunContext) -> Result<ExampleOutput, BookError>,
) -> Example {
    Example {
        id,
        title,
        section,
        parameters,
        needs_data,
        run,
    }
}

/// The chapter's examples, in book order.
pub(crate) fn examples() -> Vec<Example> {
    const CART: &str = "cart pendulum, table 3.5";
    const RIG: &str = "measured cart-rig data (data/rig/), table 3.5 constants m_p, l_p, g";
    const ARM: &str =
        "measured arm-rig data (data/rig/, or --data), table 3.7 constants L1, m2, l2, g";
    vec![
        ex(
            "p1c311_cdip_lagrange",
            "Equations of motion of the cart pendulum (Lagrange) and energy conservation",
            "Part 1 §3.1.1",
            CART,
            None,
            p1c311_cdip_lagrange,
        ),
        ex(
            "p1c321_cdip_plot_pcont",
            "Measured P-control steps of the cart rig (k_P = 2.5, 5, 10, 20)",
            "Part 1 §3.2.1",
            RIG,
            None,
            p1c321_cdip_plot_pcont,
        ),
        ex(
            "p1c321_cdip_id_cart",
            "Cart drive from the measured k_P = 10 step (peak time, overshoot)",
            "Part 1 §3.2.1",
            RIG,
            None,
            p1c321_cdip_id_cart,
        ),
        ex(
            "p1c321_cdip_id_pend",
            "Pendulum from the measured free oscillation (period, decay ratio)",
            "Part 1 §3.2.1",
            RIG,
            None,
            p1c321_cdip_id_pend,
        ),
        ex(
            "p1c322_cdip_id_least_square",
            "Least-squares identification of the cart rig (T_f = 0.075 s, 1–5 s)",
            "Part 1 §3.2.2",
            RIG,
            None,
            p1c322_cdip_id_least_square,
        ),
        ex(
            "p1c332_adip_id_arm",
            "Arm drive from a P-control step of the arm rig",
            "Part 1 §3.3",
            ARM,
            Some(ARM_STEP_DATA),
            p1c332_adip_id_arm,
        ),
        ex(
            "p1c332_adip_id_pend",
            "Arm-rig pendulum from its free oscillation",
            "Part 1 §3.3",
            ARM,
            Some(ARM_PEND_DATA),
            p1c332_adip_id_pend,
        ),
        ex(
            "p1c332_adip_id_least_square",
            "Least-squares identification of the arm rig",
            "Part 1 §3.3",
            ARM,
            Some(ARM_LS_DATA),
            p1c332_adip_id_least_square,
        ),
        ex(
            "p1c34_cdip_plot_pcont",
            "Nonlinear simulation of cart P control (k_P = 10, 0.2 m) against the rig",
            "Part 1 §3.4",
            CART,
            None,
            p1c34_cdip_plot_pcont,
        ),
    ]
}

// ---------------------------------------------------------------- §3.1 equations of motion

const ID311: &str = "p1c311_cdip_lagrange";

/// Runs the cart pendulum with input `v(t)` (sampled and held at 1 ms, plain rig) from `x0`.
fn open_loop_cart(
    id: &'static str,
    params: CartPendulumParams,
    v: Signal,
    x0: [f64; 4],
    t_final: f64,
) -> Result<pendulab_lti::Trajectory, BookError> {
    let plant = CartPendulum::new(params).ctx(id)?;
    let opts = SampledOptions {
        t_final,
        ..Default::default()
    };
    let mut lp = SampledLoop::new(plant, OpenLoop::new(vec![v], 4), opts)
        .ctx(id)?
        .with_rig(RigChains::plain(4))
        .ctx(id)?;
    Ok(lp.run(&x0).ctx(id)?.trajectory)
}

fn p1c311_cdip_lagrange(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let params = CartPendulumParams {
        mu_p: 0.0,
        ..CartPendulumParams::book()
    };
    let plant = CartPendulum::new(params).ctx(ID311)?;
    let energy = |tr: &pendulab_lti::Trajectory| -> Vec<f64> {
        (0..tr.len())
            .map(|k| {
                let x = CartPendulumState {
                    z: tr.x()[(k, 0)],
                    theta: tr.x()[(k, 1)],
                    dz: tr.x()[(k, 2)],
                    dtheta: tr.x()[(k, 3)],
                };
                plant.energy(&x)
            })
            .collect()
    };
    // 1) Cart at rest, no input, no friction: E must stay constant.
    let free = open_loop_cart(
        ID311,
        params,
        Signal::zero(),
        [0.0, PI - 1.0, 0.0, 0.0],
        10.0,
    )?;
    let e_free = energy(&free);
    let e0 = e_free[0];
    let drift = e_free
        .iter()
        .map(|e| (e - e0).abs() / e0)
        .fold(0.0, f64::max);
    // 2) Driven cart: dE/dt = −m_p l_p cos θ θ̇ z̈ (power of the cart's acceleration).
    let v = Signal::sine(0.6, 2.0 * PI * 0.8, 0.0).ctx(ID311)?;
    let driven = open_loop_cart(ID311, params, v, [0.0, PI - 0.5, 0.0, 0.0], 10.0)?;
    let e_dr = energy(&driven);
    let (ml, ac, bc) = (params.m_p * params.l_p, params.a_c, params.b_c);
    let power = |k: usize, vk: f64| {
        let (th, dz, dth) = (driven.x()[(k, 1)], driven.x()[(k, 2)], driven.x()[(k, 3)]);
        -ml * th.cos() * dth * (-ac * dz + bc * vk)
    };
    // The input is held on [t_k, t_{k+1}): the trapezoid on each interval with v_k at both
    // ends integrates the (smooth inside the interval) power to O(ts²).
    let t = driven.t();
    let mut work = vec![0.0; t.len()];
    for k in 0..t.len() - 1 {
        let vk = driven.u()[(k, 0)];
        work[k + 1] = work[k] + 0.5 * (t[k + 1] - t[k]) * (power(k, vk) + power(k + 1, vk));
    }
    let swing = e_dr.iter().map(|e| (e - e_dr[0]).abs()).fold(0.0, f64::max);
    let balance = e_dr
        .iter()
        .zip(&work)
        .map(|(e, w)| (e - e_dr[0] - w).abs())
        .fold(0.0, f64::max)
        / swing;
    let mut out = ExampleOutput::default();
    out.value("energy_drift", Value::Number(drift));
    out.value("power_balance_error", Value::Number(balance));
    out.notes.push(
        "Equations of motion (Euler–Lagrange with the drive as an acceleration source): \
         z̈ = −a_c ż + b_c v;  (J_p + m_p l_p²) θ̈ + m_p l_p cos θ · z̈ = m_p g l_p sin θ − μ_p θ̇ \
         (eqs 3.7, 3.21, 3.22), θ from upright. Check with μ_p = 0: E = ½ J θ̇² + m_p g l_p \
         (1 + cos θ) stays constant with the cart at rest (energy_drift: largest relative \
         change over 10 s from θ = π − 1), and with the cart driven by v = 0.6 sin(1.6π t) V its \
         change equals the work −∫ m_p l_p cos θ θ̇ z̈ dt (power_balance_error, relative to the \
         largest change of E)."
            .into(),
    );
    if let Some(dir) = &ctx.out_dir {
        let phi_free: Vec<f64> = free.x_signal(1).iter().map(|th| th - PI).collect();
        let phi_dr: Vec<f64> = driven.x_signal(1).iter().map(|th| th - PI).collect();
        let e_pred: Vec<f64> = work.iter().map(|w| e_dr[0] + w).collect();
        let fig = stacked(
            "p1c311_cdip_lagrange: energy with μ_p = 0",
            "time [s]",
            vec![
                PanelSpec::new(
                    "φ = θ − π [rad]",
                    vec![
                        ("cart at rest".into(), free.t(), phi_free),
                        ("cart driven".into(), driven.t(), phi_dr),
                    ],
                ),
                PanelSpec::new(
                    "energy E [J]",
                    vec![
                        ("cart at rest".into(), free.t(), e_free.clone()),
                        ("cart driven".into(), driven.t(), e_dr.clone()),
                        ("E(0) + work of z̈".into(), driven.t(), e_pred),
                    ],
                ),
            ],
        );
        write_figure(ID311, &mut out, dir, "p1c311_cdip_lagrange_energy", &fig)?;
        write_animation(
            ID311,
            &mut out,
            dir,
            "p1c311_cdip_lagrange_anim",
            animation(
                Rig::Cart,
                driven.t(),
                driven.x_signal(0),
                driven.x_signal(1),
                "cart driven, μ_p = 0",
            ),
        )?;
    }
    Ok(out)
}

// ---------------------------------------------------------------- §3.2 cart rig

fn dataset(id: &'static str, name: &str, text: &str) -> Result<Dataset, BookError> {
    Dataset::from_csv_str(name, text).ctx(id)
}

const ID321P: &str = "p1c321_cdip_plot_pcont";

/// A measured record: legend label, t, z, θ.
type Record = (String, Vec<f64>, Vec<f64>, Vec<f64>);

fn p1c321_cdip_plot_pcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let mut sets = Vec::new();
    for (kp, name, text) in PCONT {
        sets.push((kp, dataset(ID321P, name, text)?));
    }
    let mut zmax = Vec::new();
    let mut tmax = Vec::new();
    let mut thmax = Vec::new();
    for (_, d) in &sets {
        let (t, z, th) = (
            d.time().ctx(ID321P)?,
            d.column("z").ctx(ID321P)?,
            d.column("theta").ctx(ID321P)?,
        );
        let (k, m) = z
            .iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |(bk, bm), (k, &v)| {
                if v > bm { (k, v) } else { (bk, bm) }
            });
        zmax.push(m);
        tmax.push(t[k] - STEP_TIME);
        thmax.push(th.iter().fold(0.0f64, |a, v| a.max(v.abs())));
    }
    let mut out = ExampleOutput::default();
    out.value("z_max", Value::Vector(zmax));
    out.value("t_z_max", Value::Vector(tmax));
    out.value("phi_max", Value::Vector(thmax));
    out.notes.push(
        "Measured on the rig: u = k_P (0.2 − z), k_P = 2.5, 5, 10, 20 (values in that order), \
         the reference stepping at t = 1 s, the pendulum hanging. z_max: largest cart position \
         [m]; t_z_max: its time after the step (first sample of the plateau) [s]; phi_max: \
         largest |φ| [rad]. The peaks are flattened by belt stretch and friction."
            .into(),
    );
    if let Some(dir) = &ctx.out_dir {
        let cols: Vec<Record> = sets
            .iter()
            .map(|(kp, d)| {
                Ok((
                    format!("k_P = {kp}"),
                    d.time().ctx(ID321P)?.to_vec(),
                    d.column("z").ctx(ID321P)?.to_vec(),
                    d.column("theta").ctx(ID321P)?.to_vec(),
                ))
            })
            .collect::<Result<_, BookError>>()?;
        let fig = stacked(
            "p1c321_cdip_plot_pcont: measured P control, target 0.2 m",
            "time [s]",
            vec![
                PanelSpec::new(
                    "cart position z [m]",
                    cols.iter()
                        .map(|(l, t, z, _)| (l.clone(), t.as_slice(), z.clone()))
                        .collect(),
                )
                .reference(TARGET, "target"),
                PanelSpec::new(
                    "pendulum angle φ [rad]",
                    cols.iter()
                        .map(|(l, t, _, th)| (l.clone(), t.as_slice(), th.clone()))
                        .collect(),
                ),
            ],
        );
        write_figure(
            ID321P,
            &mut out,
            dir,
            "p1c321_cdip_plot_pcont_measured",
            &fig,
        )?;
    }
    Ok(out)
}

/// Windowed data from `t0` on.
fn from(
    id: &'static str,
    d: &Dataset,
    t0: Option<f64>,
    t1: Option<f64>,
) -> Result<Dataset, BookError> {
    d.window(t0, t1).ctx(id)
}

fn fit_figure(
    id: &'static str,
    out: &mut ExampleOutput,
    dir: &Path,
    stem: &str,
    title: &str,
    t: &[f64],
    panels: &[(&str, &[f64], &[f64])],
) -> Result<(), BookError> {
    let mut f = IdentFit::new(t).title(title);
    for (label, y, yh) in panels {
        f = f.signal(*label, y, &[("identified model", yh)]);
    }
    let fig = f.figure().ctx(id)?;
    write_figure(id, out, dir, stem, &fig)
}

/// Pads a validation output (which starts at sample `start`) with NaN to the data length.
fn padded(sim: &[f64], start: usize) -> Vec<f64> {
    let mut v = vec![f64::NAN; start];
    v.extend_from_slice(sim);
    v
}

// ---------------------------------------------------------------- the M-files' recipes

/// The rows of `(t, columns…)` whose time satisfies `keep`, with `shift` subtracted from `t`:
/// the M-files' `for i = 1:length(t_data), if t_data(i) >= tmin … t(k) = t_data(i) − tmin`
/// loops, with their exact floating-point comparisons on the recorded times.
fn mfile_rows(
    id: &'static str,
    t: &[f64],
    columns: &[&[f64]],
    keep: impl Fn(f64) -> bool,
    shift: f64,
) -> Result<(Vec<f64>, Vec<Vec<f64>>), BookError> {
    let rows: Vec<usize> = (0..t.len()).filter(|&i| keep(t[i])).collect();
    if rows.len() < 3 {
        return Err(fail(
            id,
            format!(
                "only {} samples of the data (t = {} … {} s) lie in the M-file's window",
                rows.len(),
                t.first().copied().unwrap_or(f64::NAN),
                t.last().copied().unwrap_or(f64::NAN)
            ),
        ));
    }
    let tw = rows.iter().map(|&i| t[i] - shift).collect();
    let cols = columns
        .iter()
        .map(|c| rows.iter().map(|&i| c[i]).collect())
        .collect();
    Ok((tw, cols))
}

/// The peak-time identification of `p1c321_cdip_id_cart.m` (lines 18–56) and
/// `p1c332_adip_id_arm.m` (lines 21–60), under the M-files' variable names.
#[derive(Debug, Clone, Copy)]
struct PeakFeature {
    /// `Tp = (t(imax) + t(imax_last))/2`: the middle of the first peak plateau, time after the
    /// step (s).
    tp: f64,
    /// `Amax = ymax − yc`: the overshoot above the reference (m or rad).
    amax: f64,
    /// `gamma = −(1/Tp) log(Amax/yc)` (1/s).
    gamma: f64,
    /// `delta = π/Tp` (rad/s).
    delta: f64,
    /// `omega_n = √(gamma² + delta²)` (rad/s).
    omega_n: f64,
    /// `zeta = gamma/omega_n`.
    zeta: f64,
    /// `2 zeta omega_n` (`ac`, `a1`), 1/s.
    a: f64,
    /// `omega_n²/kP` (`bc`, `b1`).
    b: f64,
}

/// The M-files' peak-time recipe on the record `(t, y)`: the samples from `t ≥ 1 s` with
/// `t − 1`, `[ymax imax] = max(y)` (the first largest sample), `imax_last` the end of the plateau
/// of equal samples that follows, `Tp` its middle, then the overshoot `Amax` over the reference
/// `yc` (not over the step actually travelled) and `a = 2ζω_n`, `b = ω_n²/kP`.
///
/// # Errors
/// [`BookError::Computation`] when no sample lies at or after 1 s, or the record does not
/// overshoot `yc` (MATLAB's `log` of a non-positive ratio would turn the result complex).
fn peak_feature(
    id: &'static str,
    t_data: &[f64],
    y_data: &[f64],
    yc: f64,
    kp: f64,
) -> Result<PeakFeature, BookError> {
    let (t, cols) = mfile_rows(id, t_data, &[y_data], |t| t >= 1.0, 1.0)?;
    let y = &cols[0];
    // [ymax imax] = max(y): the first index of the largest value.
    let (imax, ymax) = y
        .iter()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |(bi, bm), (i, &v)| {
            if v > bm { (i, v) } else { (bi, bm) }
        });
    let mut imax_last = imax;
    for (i, &v) in y.iter().enumerate().skip(imax) {
        if v == ymax {
            imax_last = i;
        }
        if v < ymax {
            break;
        }
    }
    let tp = (t[imax] + t[imax_last]) / 2.0;
    let amax = ymax - yc;
    // Data are finite (the CSV reader refuses NaN), so these comparisons decide.
    if amax <= 0.0 || tp <= 0.0 {
        return Err(fail(
            id,
            format!(
                "the record does not overshoot the reference {yc} after t = 1 s (largest value \
                 {ymax} at {} s after the step): no peak time or overshoot to read",
                t[imax]
            ),
        ));
    }
    let gamma = -(1.0 / tp) * (amax / yc).ln();
    let delta = PI / tp;
    let omega_n = (gamma * gamma + delta * delta).sqrt();
    let zeta = gamma / omega_n;
    Ok(PeakFeature {
        tp,
        amax,
        gamma,
        delta,
        omega_n,
        zeta,
        a: 2.0 * zeta * omega_n,
        b: omega_n * omega_n / kp,
    })
}

/// Reports a [`PeakFeature`] under the M-file's names (`a`, `b` as `a_name`, `b_name`) with the
/// transfer function `sysGyr = tf(omega_n^2, [1 2*zeta*omega_n omega_n^2])` the M-file
/// displays, and `overshoot` (= `Amax`).
fn report_peak_feature(out: &mut ExampleOutput, f: &PeakFeature, a_name: &str, b_name: &str) {
    out.value("Tp", Value::Number(f.tp));
    out.value("Amax", Value::Number(f.amax));
    out.value("gamma", Value::Number(f.gamma));
    out.value("delta", Value::Number(f.delta));
    out.value("omega_n", Value::Number(f.omega_n));
    out.value("zeta", Value::Number(f.zeta));
    out.value(a_name, Value::Number(f.a));
    out.value(b_name, Value::Number(f.b));
    out.value("overshoot", Value::Number(f.amax));
    let w2 = f.omega_n * f.omega_n;
    out.value("sysGyr_num", Value::Vector(vec![w2]));
    out.value(
        "sysGyr_den",
        Value::Vector(vec![1.0, 2.0 * f.zeta * f.omega_n, w2]),
    );
}

const ID321C: &str = "p1c321_cdip_id_cart";

fn p1c321_cdip_id_cart(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    // p1c321_cdip_id_cart.m: line 8 loads the k_P = 10 record, kP = 10 (line 9), zc = 0.2
    // (line 11).
    let (kp, name, text) = PCONT[2];
    let raw = dataset(ID321C, name, text)?;
    let (t_all, z_all) = (raw.time().ctx(ID321C)?, raw.column("z").ctx(ID321C)?);
    let f = peak_feature(ID321C, t_all, z_all, TARGET, kp)?;
    let d = from(ID321C, &raw, Some(STEP_TIME), None)?;
    let (t, z) = (d.time().ctx(ID321C)?, d.column("z").ctx(ID321C)?);
    let val = validate_p_step(t, z, STEP_TIME, TARGET, kp, f.a, f.b).ctx(ID321C)?;
    let mut out = ExampleOutput::default();
    report_peak_feature(&mut out, &f, "ac", "bc");
    out.value("fit_percent", Value::Number(val.fit_percent));
    out.notes.push(
        "As p1c321_cdip_id_cart.m on the measured k_P = 10 step: the samples from t = 1 s \
         (line 20), Tp = the middle of the first peak plateau after the step [s] (lines 28-39), \
         Amax = zmax − zc with the reference zc = 0.2 m (line 47) and gamma = −ln(Amax/zc)/Tp \
         (line 49), delta = π/Tp, omega_n = √(gamma² + delta²), zeta = gamma/omega_n, ac = \
         2 zeta omega_n, bc = omega_n²/kP (lines 50-56); overshoot = Amax; sysGyr_num, \
         sysGyr_den: the displayed tf (line 71). fit_percent (pendulab): MATLAB compare fit of \
         the identified loop."
            .into(),
    );
    if let Some(dir) = &ctx.out_dir {
        let sim = padded(&val.simulated, val.start);
        fit_figure(
            ID321C,
            &mut out,
            dir,
            "p1c321_cdip_id_cart_fit",
            "p1c321_cdip_id_cart: k_P = 10 step, measured and identified",
            t,
            &[("cart position z [m]", z, &sim)],
        )?;
    }
    Ok(out)
}

const ID321D: &str = "p1c321_cdip_id_pend";

fn p1c321_cdip_id_pend(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let d = from(
        ID321D,
        &dataset(ID321D, "cdip_pend_data.csv", PEND)?,
        Some(35.0),
        Some(51.0),
    )?;
    let c = CartPendulumConstants::default();
    let (t, th) = (d.time().ctx(ID321D)?, d.column("theta").ctx(ID321D)?);
    let ts = d.sample_time().ctx(ID321D)?;
    let osc = free_oscillation(t, th, &OscillationOptions::default()).ctx(ID321D)?;
    let p = pendulum_from_oscillation(&osc, c.mp, c.lp, c.g, PeriodCorrection::None).ctx(ID321D)?;
    let start = osc.peaks[0].first;
    let val = validate_oscillation(ts, th, start, p.omega_n, p.zeta).ctx(ID321D)?;
    let mut out = ExampleOutput::default();
    out.value("Jp", Value::Number(p.j));
    out.value("mup", Value::Number(p.mu));
    out.value("period", Value::Number(osc.period));
    out.value("decay_ratio", Value::Number(osc.decay_ratio));
    out.value("peaks", Value::Number(osc.peaks.len() as f64));
    out.notes.push(
        "Free oscillation, window 35–51 s: mean period T̄ (peak to peak) [s] and mean decay \
         ratio λ̄ = A_{i+1}/A_i; γ = ln(1/λ̄)/T̄, δ = 2π/T̄, ω_n = √(γ² + δ²), ζ = γ/ω_n, \
         J_p = m_p g l_p/ω_n² − m_p l_p², μ_p = 2ζω_n (J_p + m_p l_p²). The book's method \
         ignores the swing's large-amplitude period lengthening (≈ 1.7 % here), which makes \
         J_p come out high (table 3.5: 1.59e-3); `pendulab identify pend-free \
         --amplitude-correction` removes it."
            .into(),
    );
    if let Some(dir) = &ctx.out_dir {
        let sim = padded(&val.simulated, val.start);
        fit_figure(
            ID321D,
            &mut out,
            dir,
            "p1c321_cdip_id_pend_fit",
            "p1c321_cdip_id_pend: free oscillation, measured and identified",
            t,
            &[("pendulum angle φ [rad]", th, &sim)],
        )?;
    }
    Ok(out)
}

const ID322: &str = "p1c322_cdip_id_least_square";

fn p1c322_cdip_id_least_square(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let d = from(
        ID322,
        &dataset(ID322, "cdip_least_square_data.csv", LS)?,
        Some(1.0),
        Some(5.0),
    )?;
    let ts = d.sample_time().ctx(ID322)?;
    let (t, z, phi, v) = (
        d.time().ctx(ID322)?,
        d.column("z").ctx(ID322)?,
        d.column("phi").ctx(ID322)?,
        d.column("v").ctx(ID322)?,
    );
    let opts = LsOptions::default();
    let c = CartPendulumConstants::default();
    let drive = cart_drive_ls(ts, z, v, &opts).ctx(ID322)?;
    let pend = cart_pendulum_ls(ts, z, phi, &c, &opts).ctx(ID322)?;
    let mut out = ExampleOutput::default();
    out.value("ac", Value::Number(drive.a));
    out.value("bc", Value::Number(drive.b));
    out.value("Jp", Value::Number(pend.jp));
    out.value("mup", Value::Number(pend.mup));
    // Table 3.5 prints the estimates of this recipe to three significant digits: half a unit
    // of the last digit.
    let src = "book table 3.5";
    out.reference("ac", Value::Number(6.25), src, 0.005);
    out.reference("bc", Value::Number(4.36), src, 0.005);
    out.reference("Jp", Value::Number(1.59e-3), src, 0.005e-3);
    out.reference("mup", Value::Number(2.35e-4), src, 0.005e-4);
    out.notes.push(
        "Least squares (eqs 3.43–3.47): three-point derivatives, every column filtered by \
         1/(0.075 s + 1)³ (exact ZOH discretisation, causal), Householder QR, data 1–5 s. \
         Table 3.5: a_c = 6.25, b_c = 4.36, J_p = 1.59e-3, μ_p = 2.35e-4."
            .into(),
    );
    if let Some(dir) = &ctx.out_dir {
        let vz = validate_drive(ts, z, v, drive.a, drive.b, "z").ctx(ID322)?;
        let vp = validate_cart_pendulum(ts, z, phi, pend.jp, pend.mup, &c).ctx(ID322)?;
        let sz = padded(&vz.simulated, vz.start);
        let sp = padded(&vp.simulated, vp.start);
        fit_figure(
            ID322,
            &mut out,
            dir,
            "p1c322_cdip_id_least_square_fit",
            "p1c322_cdip_id_least_square: measured and simulated with the estimates",
            t,
            &[
                ("cart position z [m]", z, &sz),
                ("pendulum angle φ [rad]", phi, &sp),
            ],
        )?;
    }
    Ok(out)
}

// ---------------------------------------------------------------- §3.3 arm rig

/// Minimum number of samples accepted from a `--data` file.
const MIN_SAMPLES: usize = 200;

/// The arm-rig record of an example: the file given with `--data`, else the recording shipped
/// in `data/rig/` (`shipped` = file name, contents). Checks the columns, the length and a
/// uniform sample time.
fn arm_data(
    id: &'static str,
    ctx: &RunContext,
    what: &'static str,
    columns: &[&str],
    shipped: (&str, &str),
) -> Result<Dataset, BookError> {
    let (source, text) = match ctx.data_csv.as_deref() {
        Some(text) => ("--data", text),
        None => shipped,
    };
    let d = Dataset::from_csv_str(source, text).ctx(id)?;
    for c in columns {
        d.column(c).ctx(id)?;
    }
    if d.len() < MIN_SAMPLES {
        return Err(fail(
            id,
            format!(
                "{source} has {} samples; at least {MIN_SAMPLES} are needed ({what})",
                d.len()
            ),
        ));
    }
    d.sample_time().ctx(id)?;
    Ok(d)
}

/// The file the example ran on, for its note.
fn data_source(ctx: &RunContext, shipped: (&str, &str)) -> String {
    match ctx.data_csv {
        Some(_) => "the --data file".into(),
        None => format!("data/rig/{}", shipped.0),
    }
}

const ID332A: &str = "p1c332_adip_id_arm";

fn p1c332_adip_id_arm(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let raw = arm_data(ID332A, ctx, ARM_STEP_DATA, &["t", "theta1"], ARM_STEP)?;
    // p1c332_adip_id_arm.m: kP = 3 (line 11), theta1c = 1 (line 13).
    let (kp, target) = (3.0, 1.0);
    let (t_all, th_all) = (raw.time().ctx(ID332A)?, raw.column("theta1").ctx(ID332A)?);
    let f = peak_feature(ID332A, t_all, th_all, target, kp)?;
    let d = from(ID332A, &raw, Some(STEP_TIME), None)?;
    let (t, th1) = (d.time().ctx(ID332A)?, d.column("theta1").ctx(ID332A)?);
    let val = validate_p_step(t, th1, STEP_TIME, target, kp, f.a, f.b).ctx(ID332A)?;
    let mut out = ExampleOutput::default();
    report_peak_feature(&mut out, &f, "a1", "b1");
    out.value("fit_percent", Value::Number(val.fit_percent));
    out.notes.push(format!(
        "As p1c332_adip_id_arm.m on {}: the arm's P-control step (kP = 3, theta1c = 1 rad at \
         t = 1 s), the samples from t = 1 s (line 23), Tp = the middle of the first peak \
         plateau [s] (lines 32-43), Amax = theta1_max − theta1c (line 51), gamma = \
         −ln(Amax/theta1c)/Tp, delta = π/Tp, omega_n, zeta, a1 = 2 zeta omega_n, b1 = \
         omega_n²/kP (lines 53-60); sysGyr_num, sysGyr_den: the displayed tf (line 75). Table \
         3.7 (least squares, p1c332_adip_id_least_square): a1 = 6.20, b1 = 15.8. fit_percent \
         (pendulab): MATLAB compare fit of the identified loop.",
        data_source(ctx, ARM_STEP)
    ));
    if let Some(dir) = &ctx.out_dir {
        let sim = padded(&val.simulated, val.start);
        fit_figure(
            ID332A,
            &mut out,
            dir,
            "p1c332_adip_id_arm_fit",
            "p1c332_adip_id_arm: arm step, measured and identified",
            t,
            &[("arm angle θ1 [rad]", th1, &sim)],
        )?;
    }
    Ok(out)
}

/// What `p1c332_adip_id_pend.m` reads from a free oscillation, under its names.
#[derive(Debug, Clone)]
struct FreeOscillation {
    /// `T(i) = tmax(i+1) − tmax(i)`, periods between successive positive peaks (s).
    t: Vec<f64>,
    /// `lambda(i) = Amax(i+1)/Amax(i)`, ratios of successive positive peaks.
    lambda: Vec<f64>,
    /// `Amax(j)`, the positive peaks (rad).
    amax: Vec<f64>,
    /// `tmax(j)`, their times in the window (s).
    tmax: Vec<f64>,
}

/// The peak search of `p1c332_adip_id_pend.m` (lines 31–91) on the windowed record
/// `(t, phi2)`, with MATLAB's 1-based indices written out:
///
/// - lines 31–44: `num(k)` = every sample `i ≤ length(t) − 1` with `phi2(i) < 0` after a
///   sample `> 0` (a negative-going zero crossing);
/// - lines 49–51: `num = [1 num]` if the record starts negative;
/// - lines 54–69: between `num(j)` and `num(j+1)`, `[Amax(j) imax(j)] = max(…)`, then
///   `imax(j) = imax(j) + num(j)` (line 57) — one sample *after* the largest sample, since
///   `max` counts from 1 — the plateau of samples equal to `Amax(j)` from there, and `tmax(j)`
///   its middle;
/// - lines 89–92: periods `T` and ratios `lambda` of successive peaks.
///
/// # Errors
/// [`BookError::Computation`] with fewer than two peaks, or a peak that is not positive.
fn mfile_free_oscillation(
    id: &'static str,
    t: &[f64],
    phi2: &[f64],
) -> Result<FreeOscillation, BookError> {
    let n = t.len();
    // 1-based sample numbers, as the M-file keeps them.
    let mut num: Vec<usize> = Vec::new();
    let mut flag = false;
    for i in 1..n {
        let p = phi2[i - 1];
        if p > 0.0 {
            flag = true;
        }
        if flag && p < 0.0 {
            num.push(i);
            flag = false;
        }
    }
    if phi2.first().is_some_and(|&p| p < 0.0) {
        num.insert(0, 1);
    }
    let mut amax = Vec::new();
    let mut tmax = Vec::new();
    for w in num.windows(2) {
        let (lo, hi) = (w[0], w[1]);
        let seg = &phi2[lo - 1..hi];
        let (k, a) = seg
            .iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |(bk, bm), (k, &v)| {
                if v > bm { (k, v) } else { (bk, bm) }
            });
        // [Amax imax] = max(...) gives k + 1; line 57 adds num(j).
        let imax = k + 1 + lo;
        let mut imax_last = imax;
        for i in imax..=hi {
            let p = phi2[i - 1];
            if p == a {
                imax_last = i;
            }
            if p < a {
                break;
            }
        }
        if a <= 0.0 || imax > n {
            return Err(fail(
                id,
                format!("no positive peak between samples {lo} and {hi} of the window"),
            ));
        }
        amax.push(a);
        tmax.push((t[imax - 1] + t[imax_last - 1]) / 2.0);
    }
    if amax.len() < 2 {
        return Err(fail(
            id,
            format!(
                "the window holds {} positive peak(s) between negative-going zero crossings; \
                 at least two are needed for a period",
                amax.len()
            ),
        ));
    }
    let t_periods = tmax.windows(2).map(|w| w[1] - w[0]).collect();
    let lambda = amax.windows(2).map(|w| w[1] / w[0]).collect();
    Ok(FreeOscillation {
        t: t_periods,
        lambda,
        amax,
        tmax,
    })
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

const ID332P: &str = "p1c332_adip_id_pend";

fn p1c332_adip_id_pend(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let raw = arm_data(ID332P, ctx, ARM_PEND_DATA, &["t", "theta2"], ARM_PEND)?;
    // p1c332_adip_id_pend.m, lines 13–20: 50 s ≤ t ≤ 66 s, t − 50.
    let (tmin, tmax) = (50.0, 50.0 + 16.0);
    let (t, cols) = mfile_rows(
        ID332P,
        raw.time().ctx(ID332P)?,
        &[raw.column("theta2").ctx(ID332P)?],
        |t| t >= tmin && t <= tmax,
        tmin,
    )?;
    let phi2 = &cols[0];
    let osc = mfile_free_oscillation(ID332P, &t, phi2)?;
    let t_average = mean(&osc.t);
    let lambda_average = mean(&osc.lambda);
    // Lines 127–140, with the M-file's m2, l2, g.
    let c = ArmPendulumConstants::default();
    let (m2, l2, g) = (c.m2, c.l2, c.g);
    let gamma = (1.0 / t_average) * (1.0 / lambda_average).ln();
    let delta = 2.0 * PI / t_average;
    let omega_n = (gamma * gamma + delta * delta).sqrt();
    let zeta = gamma / omega_n;
    let j2 = m2 * g * l2 / (omega_n * omega_n) - m2 * l2 * l2;
    let mu2 = 2.0 * zeta * omega_n * (j2 + m2 * l2 * l2);
    if j2.is_nan() || j2 <= 0.0 {
        return Err(fail(
            ID332P,
            format!(
                "J2 = m2 g l2/omega_n² − m2 l2² = {j2} is not positive (omega_n = {omega_n} \
                 rad/s): not this pendulum's oscillation"
            ),
        ));
    }
    let mut out = ExampleOutput::default();
    out.value("T", Value::Vector(osc.t.clone()));
    out.value("lambda", Value::Vector(osc.lambda.clone()));
    out.value("T_average", Value::Number(t_average));
    out.value("lambda_average", Value::Number(lambda_average));
    out.value("gamma", Value::Number(gamma));
    out.value("delta", Value::Number(delta));
    out.value("zeta", Value::Number(zeta));
    out.value("omega_n", Value::Number(omega_n));
    out.value("m2", Value::Number(m2));
    out.value("l2", Value::Number(l2));
    out.value("g", Value::Number(g));
    out.value("J2", Value::Number(j2));
    out.value("mu2", Value::Number(mu2));
    out.value("Amax", Value::Vector(osc.amax.clone()));
    out.value("tmax", Value::Vector(osc.tmax.clone()));
    out.notes.push(format!(
        "As p1c332_adip_id_pend.m on {}: the window 50 s ≤ t ≤ 66 s (lines 13-20), positive \
         peaks Amax between negative-going zero crossings at tmax, the middle of each peak's \
         plateau counted from one sample after the largest sample (the M-file's imax(j) + \
         num(j), line 57: every tmax is 1 ms late, which leaves the periods alike); periods T \
         and ratios lambda of successive peaks, T_average, lambda_average (lines 89-95); gamma \
         = ln(1/lambda_average)/T_average, delta = 2π/T_average, omega_n, zeta, J2 = m2 g \
         l2/omega_n² − m2 l2², mu2 = 2 zeta omega_n (J2 + m2 l2²) (lines 133-140). The method \
         reads the swing's large-amplitude period lengthening (0.6 rad peaks here: ≈ 2.3 %) as \
         inertia, so J2 comes out above table 3.7's least-squares 9.06e-4.",
        data_source(ctx, ARM_PEND)
    ));
    if let Some(dir) = &ctx.out_dir {
        // Lines 164–174: the free response from the first peak, drawn from tmax(1) on.
        let wd = omega_n * (1.0 - zeta * zeta).sqrt();
        let phi20 = osc.amax[0];
        let sim: Vec<f64> = t
            .iter()
            .map(|&tk| {
                let s = tk - osc.tmax[0];
                if s < 0.0 {
                    f64::NAN
                } else {
                    (-zeta * omega_n * s).exp()
                        * ((wd * s).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * s).sin())
                        * phi20
                }
            })
            .collect();
        fit_figure(
            ID332P,
            &mut out,
            dir,
            "p1c332_adip_id_pend_fit",
            "p1c332_adip_id_pend: free oscillation (50-66 s), measured and identified",
            &t,
            &[("pendulum angle φ2 [rad]", phi2, &sim)],
        )?;
    }
    Ok(out)
}

/// `tf(1,[Tf 1])^3` as `adip_least_square_MN_sim.slx` runs it: Simulink's `ode1` (forward
/// Euler) at the fixed step `ts` from a zero state, the output logged before each step. For
/// any state-space realisation this is three stages `y[k+1] = y[k] + (ts/Tf)(u[k] − y[k])`,
/// `y[0] = 0` (Euler's discretisation `G((z − 1)/ts)` does not depend on the realisation).
fn euler_lag3(u: &[f64], tf: f64, ts: f64) -> Vec<f64> {
    let c = ts / tf;
    let mut x = u.to_vec();
    for _ in 0..3 {
        let mut y = vec![0.0; x.len()];
        for k in 0..x.len().saturating_sub(1) {
            y[k + 1] = y[k] + c * (x[k] - y[k]);
        }
        x = y;
    }
    x
}

const ID332L: &str = "p1c332_adip_id_least_square";

fn p1c332_adip_id_least_square(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let e = ID332L;
    let raw = arm_data(e, ctx, ARM_LS_DATA, &["t", "phi1", "phi2", "v"], ARM_LS)?;
    // p1c332_adip_id_least_square.m, lines 22–33: 1 s ≤ t ≤ 9 s, t − 1.
    let (t, cols) = mfile_rows(
        e,
        raw.time().ctx(e)?,
        &[
            raw.column("phi1").ctx(e)?,
            raw.column("phi2").ctx(e)?,
            raw.column("v").ctx(e)?,
        ],
        |t| (1.0..=9.0).contains(&t),
        1.0,
    )?;
    let (p1, p2, v) = (&cols[0], &cols[1], &cols[2]);
    // Line 42: ts = 0.001 (the record's own sample time for --data).
    let ts = raw.sample_time().ctx(e)?;
    // Lines 47–79: three-point derivatives, the accelerations as derivatives of them.
    let d1 = pendulab_ident::three_point(p1, ts).ctx(e)?;
    let dd1 = pendulab_ident::three_point(&d1, ts).ctx(e)?;
    let d2 = pendulab_ident::three_point(p2, ts).ctx(e)?;
    let dd2 = pendulab_ident::three_point(&d2, ts).ctx(e)?;
    // Lines 85–97: Tf1 = Tf2 = 0.075, L1, m2, l2, L2, g, alpha3 = m2 L1 l2, alpha5 = m2 l2 g.
    let tf = pendulab_ident::BOOK_TF;
    let c = ArmPendulumConstants::default();
    let big_l2 = 0.300;
    let (alpha3, alpha5) = (c.alpha3(), c.alpha5());
    // Line 100, adip_least_square_MN_sim.slx: Mf1 = f([−dphi1, v]), Nf1 = f(ddphi1), Mf2 =
    // f([ddphi2, dphi2 − dphi1]), Nf2 = f(alpha3 cos(phi1 − phi2) ddphi1 − alpha3 dphi1²
    // sin(phi1 − phi2) − alpha5 sin(phi2)), f = tf(1,[Tf 1])^3 under ode1.
    let f = |x: &[f64]| euler_lag3(x, tf, ts);
    let neg_d1: Vec<f64> = d1.iter().map(|x| -x).collect();
    let rel: Vec<f64> = d2.iter().zip(&d1).map(|(a, b)| a - b).collect();
    let n2: Vec<f64> = (0..t.len())
        .map(|k| {
            let (s12, c12) = (p1[k] - p2[k]).sin_cos();
            alpha3 * c12 * dd1[k] - alpha3 * d1[k] * d1[k] * s12 - alpha5 * p2[k].sin()
        })
        .collect();
    let (m1a, m1b, nf1) = (f(&neg_d1), f(v), f(&dd1));
    let (m2a, m2b, nf2) = (f(&dd2), f(&rel), f(&n2));
    // Lines 102–111: p1 = [a1; b1], p2 = [alpha2; mu2], J2 = alpha2 − m2 l2² (solved here by
    // Householder QR; the M-file's inv(M'M) M'N is the same minimiser).
    let lsq1 =
        pendulab_ident::least_squares(&[("a1", &m1a), ("b1", &m1b)], ("Nf1", &nf1)).ctx(e)?;
    let lsq2 =
        pendulab_ident::least_squares(&[("alpha2", &m2a), ("mu2", &m2b)], ("Nf2", &nf2)).ctx(e)?;
    let (a1, b1) = (lsq1.estimate[0], lsq1.estimate[1]);
    let (alpha2, mu2) = (lsq2.estimate[0], lsq2.estimate[1]);
    let j2 = alpha2 - c.m2 * c.l2 * c.l2;
    // pendulab's own recipe on the same window: the filter discretised exactly (ZOH).
    let opts = LsOptions::default();
    let drive = arm_drive_ls(ts, p1, v, &opts).ctx(e)?;
    let pend = arm_pendulum_ls(ts, p1, p2, &c, &opts).ctx(e)?;
    let mut out = ExampleOutput::default();
    for (name, x) in [
        ("a1", a1),
        ("b1", b1),
        ("L1", c.l1),
        ("m2", c.m2),
        ("l2", c.l2),
        ("L2", big_l2),
        ("g", c.g),
        ("J2", j2),
        ("mu2", mu2),
        ("alpha2", alpha2),
        ("a1_zoh", drive.a),
        ("b1_zoh", drive.b),
        ("J2_zoh", pend.j2),
        ("mu2_zoh", pend.mu2),
    ] {
        out.value(name, Value::Number(x));
    }
    if ctx.data_csv.is_none() {
        // Table 3.7 prints this recipe's estimates to three significant digits: half a unit
        // of the last digit.
        let src = "book table 3.7";
        out.reference("a1", Value::Number(6.20), src, 0.005);
        out.reference("b1", Value::Number(15.8), src, 0.05);
        out.reference("J2", Value::Number(9.06e-4), src, 0.005e-4);
        out.reference("mu2", Value::Number(1.01e-4), src, 0.005e-4);
    }
    out.notes.push(format!(
        "As p1c332_adip_id_least_square.m on {}: the window 1 s ≤ t ≤ 9 s (lines 22-33), \
         three-point derivatives (lines 47-79), every column of M1 = [−dphi1, v], N1 = ddphi1, \
         M2 = [ddphi2, dphi2 − dphi1], N2 = alpha3 cos(phi1 − phi2) ddphi1 − alpha3 dphi1² \
         sin(phi1 − phi2) − alpha5 sin(phi2) through 1/(0.075 s + 1)³ as the Simulink model \
         runs it (forward Euler at 1 ms from rest), least squares (lines 102-111): a1, b1, J2 = \
         alpha2 − m2 l2², mu2; L1, m2, l2, L2, g as displayed. *_zoh: pendulab's recipe, the \
         same with the filter discretised exactly (zero-order hold).",
        data_source(ctx, ARM_LS)
    ));
    if let Some(dir) = &ctx.out_dir {
        let v1 = validate_drive(ts, p1, v, a1, b1, "phi1").ctx(e)?;
        let v2 = validate_arm_pendulum(ts, p1, p2, alpha2, mu2, &c).ctx(e)?;
        let s1 = padded(&v1.simulated, v1.start);
        let s2 = padded(&v2.simulated, v2.start);
        fit_figure(
            e,
            &mut out,
            dir,
            "p1c332_adip_id_least_square_fit",
            "p1c332_adip_id_least_square: measured and simulated with the estimates",
            &t,
            &[
                ("arm angle φ1 [rad]", p1, &s1),
                ("pendulum angle φ2 [rad]", p2, &s2),
            ],
        )?;
    }
    Ok(out)
}

// ---------------------------------------------------------------- §3.4 simulation vs rig

const ID34: &str = "p1c34_cdip_plot_pcont";

fn p1c34_cdip_plot_pcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let kp = 10.0;
    // The book's Simulink model acts continuously; a 10 µs loop reproduces it (the 1 ms loop
    // of the rig adds half a sample of delay: +0.2 % on the swing, reported as
    // `phi_peaks_1ms`).
    let fine = 1e-5;
    let p_law = |ts: f64| -> Result<Pid, BookError> {
        Pid::new(PidForm::P { kp }, ts, PidDiscretization::Tustin)
            .ctx(ID34)?
            .reference(Signal::step(0.0, TARGET).ctx(ID34)?)
            .measurement(0, 4)
            .ctx(ID34)
    };
    let opts = SampledOptions {
        ts: fine,
        t_final: 4.0,
        integrator: pendulab_sim::Integrator::Rk4 { dt: fine },
        record: pendulab_sim::Record::Every(100),
        ..Default::default()
    };
    let tr = SampledLoop::new(CartPendulum::book(), p_law(fine)?, opts)
        .ctx(ID34)?
        .run(&[0.0, PI, 0.0, 0.0])
        .ctx(ID34)?
        .trajectory;
    let theta = tr.x_signal(1).to_vec();
    let run = super::p1c2::CartRun {
        label: "simulation".into(),
        t: tr.t().to_vec(),
        z: tr.x_signal(0).to_vec(),
        z_measured: tr.y_signal(0).to_vec(),
        phi: theta.iter().map(|th| th - PI).collect(),
        theta,
        v: tr.u_signal(0).to_vec(),
    };
    let run_1ms = simulate_cart(ID34, "1 ms loop", p_law(1e-3)?, false, None, 4.0)?;
    let ext_1ms = extrema(&run_1ms.t, &run_1ms.phi, 1);
    let (k, zpk) = run
        .z
        .iter()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |(bk, bm), (k, &v)| {
            if v > bm { (k, v) } else { (bk, bm) }
        });
    let ext = extrema(&run.t, &run.phi, 1);
    if ext.len() < 3 {
        return Err(fail(ID34, "fewer than three extrema of φ in 4 s"));
    }
    let mut out = ExampleOutput::default();
    out.value("z_peak", Value::Number(zpk));
    out.value("t_z_peak", Value::Number(run.t[k]));
    out.value(
        "phi_peaks",
        Value::Vector(ext[..3].iter().map(|e| e.1).collect()),
    );
    out.value(
        "t_phi_peaks",
        Value::Vector(ext[..3].iter().map(|e| e.0).collect()),
    );
    out.value("z_final", Value::Number(run.z_final()));
    out.value(
        "phi_peaks_1ms",
        Value::Vector(ext_1ms.iter().take(3).map(|e| e.1).collect()),
    );
    let src = "book Part 1 §3.4";
    out.reference("z_peak", Value::Number(0.237), src, 0.0005);
    out.reference("t_z_peak", Value::Number(0.54), src, 0.005);
    out.reference("z_final", Value::Number(0.200), src, 0.0005);
    out.reference(
        "phi_peaks",
        Value::Vector(vec![0.394, -0.701, 0.755]),
        src,
        0.0005,
    );
    out.reference(
        "t_phi_peaks",
        Value::Vector(vec![0.30, 0.79, 1.35]),
        src,
        0.005,
    );
    out.notes.push(
        "Nonlinear cart pendulum (table 3.5), u = k_P (0.2 − z), k_P = 10, the step at t = 0, \
         pendulum hanging, plain plant (no quantisation), controller acting continuously (10 µs \
         loop, recorded every 1 ms) as in the book's Simulink model; phi_peaks_1ms: the same \
         with the rig's 1 ms sampling. φ = θ − π; t_phi_peaks: times \
         of the first three extrema. The figure overlays the rig's k_P = 10 record shifted by \
         its 1 s step."
            .into(),
    );
    if let Some(dir) = &ctx.out_dir {
        let (_, name, text) = PCONT[2];
        let d = from(
            ID34,
            &dataset(ID34, name, text)?,
            Some(STEP_TIME),
            Some(STEP_TIME + 4.0),
        )?;
        let tm: Vec<f64> = d.time().ctx(ID34)?.iter().map(|t| t - STEP_TIME).collect();
        let zm = d.column("z").ctx(ID34)?.to_vec();
        let pm = d.column("theta").ctx(ID34)?.to_vec();
        let fig = stacked(
            "p1c34_cdip_plot_pcont: k_P = 10, simulation and experiment",
            "time after the step [s]",
            vec![
                PanelSpec::new(
                    "cart position z [m]",
                    vec![
                        ("simulation".into(), &run.t, run.z.clone()),
                        ("experiment".into(), &tm, zm),
                    ],
                )
                .reference(TARGET, "target"),
                PanelSpec::new(
                    "pendulum angle φ [rad]",
                    vec![
                        ("simulation".into(), &run.t, run.phi.clone()),
                        ("experiment".into(), &tm, pm),
                    ],
                ),
            ],
        );
        write_figure(ID34, &mut out, dir, "p1c34_cdip_plot_pcont_response", &fig)?;
        write_animation(
            ID34,
            &mut out,
            dir,
            "p1c34_cdip_plot_pcont_anim",
            animation(
                Rig::Cart,
                &run.t,
                &run.z,
                &run.theta,
                "cart P control, k_P = 10",
            ),
        )?;
    }
    Ok(out)
}
