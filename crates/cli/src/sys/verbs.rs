//! The verbs' bodies: each calls the `pendulab-lti` function of its MATLAB name and prints.

use super::input::{Sys, matrix_arg, vector_arg, with_sys};
use super::{SysCommand, SystemOut};
use crate::lqr::{fmt_row, read_matrix, rows_of};
use anyhow::{Context, Result, anyhow, bail};
use pendulab_lti::Complex64;
use pendulab_lti::Mat;
use pendulab_lti::analysis::{ctrb, obsv, rank};
use pendulab_lti::design::{lqe, place};
use pendulab_lti::discretization::Discretization;
use pendulab_lti::margins::stability_margins;
use pendulab_lti::norms::{h2_norm, hinf_norm};
use pendulab_lti::reduction::{BalredMethod, balred, hsvd, minreal};
use pendulab_lti::response::{InputHold, LsimOptions, initial, lsim};
use pendulab_lti::stepinfo::{StepInfo, StepInfoOptions, stepinfo};
use serde::Serialize;
use serde_json::json;
use std::path::Path;

mod response;

use response::{bode, channels, time_grid, trajectory_out};
pub(super) use response::{frequencies, save_figure};

/// Runs `$body` (giving a system of the same domain and a value) on a system of either domain;
/// the result rewrapped as a [`Sys`], and the value.
macro_rules! map_sys {
    ($sys:expr, |$v:ident| $body:expr) => {
        match $sys {
            Sys::C($v) => {
                let (system, value) = $body;
                (Sys::C(system), value)
            }
            Sys::D($v) => {
                let (system, value) = $body;
                (Sys::D(system), value)
            }
        }
    };
}

/// Runs one MATLAB verb.
///
/// # Errors
/// The system's errors ([`super::input`]); the library's errors for the computation (naming
/// what failed); a figure or system file that cannot be written.
pub fn run(cmd: &SysCommand) -> Result<()> {
    match cmd {
        SysCommand::Ss { sys, out } => ss(&sys.load()?, out),
        SysCommand::Eig { sys, json } => eig(&sys.load()?, *json),
        SysCommand::Ctrb { sys, json } => {
            let s = sys.load()?;
            let (a, b, _, _) = s.matrices();
            rank_report(
                "controllability matrix [B AB … A^(n-1)B]",
                &ctrb(a, b)?,
                *json,
            )
        }
        SysCommand::Obsv { sys, json } => {
            let s = sys.load()?;
            let (a, _, c, _) = s.matrices();
            rank_report(
                "observability matrix [C; CA; …; CA^(n-1)]",
                &obsv(a, c)?,
                *json,
            )
        }
        SysCommand::Step { sys, time, fig } => channels(&sys.load()?, time, fig, false),
        SysCommand::Impulse { sys, time, fig } => channels(&sys.load()?, time, fig, true),
        SysCommand::Stepinfo { sys, time, json } => {
            let s = sys.load()?;
            let t = time_grid(&s, time)?;
            let info = with_sys!(&s, |v| stepinfo(v, &t, &StepInfoOptions::default()))?;
            let rows: Vec<Vec<serde_json::Value>> = info
                .iter()
                .map(|per_in| per_in.iter().map(stepinfo_json).collect())
                .collect();
            if *json {
                println!("{}", json!({ "stepinfo": rows, "t_final": t.last() }));
                return Ok(());
            }
            for (i, per_in) in info.iter().enumerate() {
                for (j, si) in per_in.iter().enumerate() {
                    println!(
                        "u{} → y{}: rise {:.6} s, settling {:.6} s, overshoot {:.4} %, undershoot {:.4} %, peak {:.6} at {:.6} s, final {:.6}",
                        j + 1,
                        i + 1,
                        si.rise_time,
                        si.settling_time,
                        si.overshoot,
                        si.undershoot,
                        si.peak,
                        si.peak_time,
                        si.steady_state_value
                    );
                }
            }
            Ok(())
        }
        SysCommand::Margin { sys, json } => margin(&sys.load()?, *json),
        SysCommand::Norm {
            sys,
            inf,
            tol,
            json,
        } => {
            let s = sys.load()?;
            if *inf {
                let h = with_sys!(&s, |v| hinf_norm(v, *tol))?;
                let out = json!({
                    "hinf": finite_or_null(h.value),
                    "peak_frequency": finite_or_null(h.peak_frequency),
                    "upper_bound": finite_or_null(h.upper_bound),
                    "unstable": !h.value.is_finite(),
                });
                if *json {
                    println!("{out}");
                } else if !h.value.is_finite() {
                    // `hinf_norm`: infinite only for an unstable system (MATLAB and
                    // python-control return Inf too), with no peak frequency.
                    println!("H∞ norm inf: the system is unstable");
                } else {
                    println!(
                        "H∞ norm {:.10} at ω = {:.6} rad/s (≤ {:.10})",
                        h.value, h.peak_frequency, h.upper_bound
                    );
                }
            } else {
                let h2 = with_sys!(&s, |v| h2_norm(v))?;
                if *json {
                    println!(
                        "{}",
                        json!({ "h2": finite_or_null(h2), "infinite": !h2.is_finite() })
                    );
                } else if !h2.is_finite() {
                    // `h2_norm`: infinite for an unstable system, or a continuous one with
                    // a feedthrough (its impulse response has a Dirac part).
                    let why = if with_sys!(&s, |v| v.is_stable())? {
                        "the system has a feedthrough D ≠ 0"
                    } else {
                        "the system is unstable"
                    };
                    println!("H2 norm inf: {why}");
                } else {
                    println!("H2 norm {h2:.10}");
                }
            }
            Ok(())
        }
        SysCommand::Minreal { sys, tol, out } => {
            let s = sys.load()?;
            let (reduced, removed) = map_sys!(&s, |v| {
                let m = minreal(v, *tol)?;
                (m.system, m.removed_states)
            });
            if !out.json {
                println!("{removed} state(s) removed");
            }
            ss(&reduced, out)
        }
        SysCommand::Hsvd { sys, json } => {
            let s = sys.load()?;
            let hsv = with_sys!(&s, |v| hsvd(v))?;
            if *json {
                println!("{}", json!({ "hsv": hsv }));
            } else {
                println!("Hankel singular values: {}", fmt_row(&hsv));
            }
            Ok(())
        }
        SysCommand::Balred {
            sys,
            order,
            method,
            out,
        } => {
            let s = sys.load()?;
            let method = match method.as_str() {
                "truncate" => BalredMethod::Truncate,
                "matchdc" => BalredMethod::MatchDc,
                other => bail!("--method {other}: expected truncate or matchdc"),
            };
            let (reduced, hsv) = map_sys!(&s, |v| {
                let b = balred(v, *order, method)?;
                (b.system, b.hsv)
            });
            let bound = 2.0 * hsv.iter().skip(*order).sum::<f64>();
            if !out.json {
                println!(
                    "reduced to {order} state(s); H∞ error bound 2 Σ discarded σ = {bound:.6e}"
                );
            }
            ss(&reduced, out)
        }

        SysCommand::Initial { sys, x0, time, fig } => {
            let s = sys.load()?;
            let x0 = vector_arg(x0, "x0")?;
            let t = time_grid(&s, time)?;
            let traj = with_sys!(&s, |v| initial(v, &x0, &t))?;
            trajectory_out(&[("initial", traj)], fig, "initial")
        }
        SysCommand::Lsim {
            sys,
            input,
            x0,
            hold,
            fig,
        } => {
            let s = sys.load()?;
            let data =
                read_matrix(input).with_context(|| format!("reading {}", input.display()))?;
            let nu = s.matrices().1.ncols();
            if data.ncols() != nu + 1 {
                bail!(
                    "{}: expected {} columns (t, then {nu} input(s)), found {}",
                    input.display(),
                    nu + 1,
                    data.ncols()
                );
            }
            let t: Vec<f64> = data.column(0).iter().copied().collect();
            let u = data.columns(1, nu).into_owned();
            let hold = match hold.as_str() {
                "foh" => InputHold::Foh,
                "zoh" => InputHold::Zoh,
                other => bail!("--hold {other}: expected foh or zoh"),
            };
            let x0 = x0.as_deref().map(|v| vector_arg(v, "x0")).transpose()?;
            let opts = LsimOptions { hold };
            let traj = with_sys!(&s, |v| lsim(v, &u, &t, x0.as_deref(), &opts))?;
            trajectory_out(&[("lsim", traj)], fig, "lsim")
        }
        SysCommand::Bode { sys, freq, fig } => bode(&sys.load()?, freq, fig),
        SysCommand::Nyquist { .. }
        | SysCommand::Nichols { .. }
        | SysCommand::Rlocus { .. }
        | SysCommand::Diskmargin { .. }
        | SysCommand::Sigma { .. } => super::loop_verbs::run(cmd),
        SysCommand::Hinfsyn { .. } | SysCommand::H2syn { .. } => super::synth_verbs::run(cmd),
        SysCommand::C2d {
            sys,
            ts,
            method,
            prewarp,
            out,
        } => {
            let s = sys.load()?;
            let Sys::C(c) = &s else {
                bail!(
                    "c2d discretises a continuous system; this one is discrete (dt = {})",
                    s.dt().unwrap_or(f64::NAN)
                );
            };
            let d = c.c2d(*ts, method_of(method, *prewarp)?)?;
            ss(&Sys::D(d), out)
        }
        SysCommand::Pade { delay, order, out } => {
            let g = pendulab_lti::delay::pade(*delay, *order)?;
            let s = Sys::C(g.to_state_space()?);
            if out.json {
                if let Some(path) = out.save.as_deref() {
                    write_system(&s, path)?;
                }
                let mut v = system_json(&s);
                v["num"] = json!(g.num().coefficients());
                v["den"] = json!(g.den().coefficients());
                println!("{v}");
                return Ok(());
            }
            println!("pade(T = {delay} s, n = {order}) = {g}");
            println!("num = {:?}", g.num().coefficients());
            println!("den = {:?}", g.den().coefficients());
            ss(&s, out)
        }
        SysCommand::D2c {
            sys,
            method,
            prewarp,
            out,
        } => {
            let s = sys.load()?;
            let Sys::D(d) = &s else {
                bail!("d2c converts a discrete system; this one is continuous (give dt)");
            };
            let c = d.d2c(method_of(method, *prewarp)?)?;
            ss(&Sys::C(c), out)
        }
        SysCommand::Place { sys, poles, json } => {
            let s = sys.load()?;
            let poles = parse_poles(poles)?;
            let (a, b, _, _) = s.matrices();
            let p = place(a, b, &poles)?;
            let out = json!({
                "K": rows_of(&p.gain),
                "K_book": rows_of(&(-&p.gain)),
                "convention": "u = -K x (MATLAB, python-control, pendulab); the book writes u = +K_book x with K_book = -K",
                "requested_poles": pairs(&p.requested_poles),
                "achieved_poles": pairs(&p.achieved_poles),
                "max_relative_error": p.max_relative_error,
                "eigenvector_condition": finite_or_null(p.eigenvector_condition),
            });
            if *json {
                println!("{out}");
                return Ok(());
            }
            print_matrix("K (u = −K x)", &p.gain);
            print_matrix("K_book (the book's u = +K x)", &(-&p.gain));
            print_poles("achieved poles of A − BK", &p.achieved_poles);
            println!("max relative pole error: {:.3e}", p.max_relative_error);
            Ok(())
        }
        SysCommand::Lqe {
            sys,
            g,
            qn,
            rn,
            json,
        } => {
            let s = sys.load()?;
            let n = s.matrices().0.nrows();
            let g = match g {
                Some(g) => matrix_arg(g, "G")?,
                None => Mat::identity(n, n),
            };
            let qn = matrix_arg(qn, "Qn")?;
            let rn = matrix_arg(rn, "Rn")?;
            let k = with_sys!(&s, |v| lqe(v, &g, &qn, &rn, None))?;
            let out = json!({
                "L": rows_of(&k.gain),
                "P": rows_of(&k.covariance),
                "estimator_poles": pairs(&k.estimator_poles),
                "residual": k.residual,
            });
            if *json {
                println!("{out}");
                return Ok(());
            }
            print_matrix("L (x̂' = A x̂ + B u + L (y − C x̂ − D u))", &k.gain);
            print_matrix("P (error covariance)", &k.covariance);
            print_poles("estimator poles (A − LC)", &k.estimator_poles);
            println!("relative Riccati residual: {:.3e}", k.residual);
            Ok(())
        }
    }
}

fn stepinfo_json(si: &StepInfo) -> serde_json::Value {
    json!({
        "RiseTime": finite_or_null(si.rise_time),
        "SettlingTime": finite_or_null(si.settling_time),
        "SettlingMin": finite_or_null(si.settling_min),
        "SettlingMax": finite_or_null(si.settling_max),
        "Overshoot": finite_or_null(si.overshoot),
        "Undershoot": finite_or_null(si.undershoot),
        "Peak": finite_or_null(si.peak),
        "PeakTime": finite_or_null(si.peak_time),
        "SteadyStateValue": finite_or_null(si.steady_state_value),
    })
}

/// `margin`: every crossing of the SISO loop and the reported margins (MATLAB's choices).
fn margin(s: &Sys, as_json: bool) -> Result<()> {
    let m = with_sys!(s, |v| stability_margins(v))?;
    let gm = m.gain_margin();
    let pm = m.phase_margin();
    let dm = m.delay_margin();
    let out = json!({
        "gain_margin": gm.map(|g| finite_or_null(g.gain_margin)),
        "gain_margin_db": gm.map(|g| finite_or_null(g.gain_margin_db())),
        "phase_crossover_frequency": gm.map(|g| g.frequency),
        "phase_margin_deg": pm.map(|p| p.phase_margin_deg),
        "gain_crossover_frequency": pm.map(|p| p.frequency),
        "delay_margin": dm.map(|d| d.delay_margin),
        "delay_margin_frequency": dm.map(|d| d.frequency),
        "gain_crossings": m.gain_crossings.iter().map(|g| json!({
            "frequency": g.frequency, "phase_margin_deg": g.phase_margin_deg, "delay_margin": g.delay_margin,
        })).collect::<Vec<_>>(),
        "phase_crossings": m.phase_crossings.iter().map(|p| json!({
            "frequency": p.frequency, "gain_margin": finite_or_null(p.gain_margin),
        })).collect::<Vec<_>>(),
        "boundary_pole_frequencies": m.boundary_pole_frequencies,
        "dt": m.sample_time,
        "convention": "null margin = infinite (no crossing); GM = 1/|L| at a phase crossing, PM = mod(∠L, 360°) − 180° at a gain crossing, DM = mod(PM, 360°)/ω",
    });
    if as_json {
        println!("{out}");
        return Ok(());
    }
    match gm {
        Some(g) => println!(
            "gain margin {:.6} ({:.4} dB) at ω = {:.6} rad/s",
            g.gain_margin,
            g.gain_margin_db(),
            g.frequency
        ),
        None => println!("gain margin ∞ (no phase crossing)"),
    }
    match pm {
        Some(p) => println!(
            "phase margin {:.4}° at ω = {:.6} rad/s",
            p.phase_margin_deg, p.frequency
        ),
        None => println!("phase margin ∞ (no gain crossing)"),
    }
    if let Some(d) = dm {
        println!(
            "delay margin {:.6} s at ω = {:.6} rad/s",
            d.delay_margin, d.frequency
        );
    }
    println!(
        "{} gain crossing(s), {} phase crossing(s)",
        m.gain_crossings.len(),
        m.phase_crossings.len()
    );
    Ok(())
}

pub(super) fn pairs(p: &[Complex64]) -> Vec<[f64; 2]> {
    p.iter().map(|z| [z.re, z.im]).collect()
}

pub(super) fn finite_or_null(v: f64) -> serde_json::Value {
    if v.is_finite() {
        json!(v)
    } else {
        serde_json::Value::Null
    }
}

pub(super) fn print_matrix(name: &str, m: &Mat) {
    println!("{name}:");
    for row in rows_of(m) {
        println!("  {}", fmt_row(&row));
    }
}

pub(super) fn print_poles(name: &str, p: &[Complex64]) {
    println!("{name}:");
    for z in p {
        println!("  {:.10} {:+.10}j", z.re, z.im);
    }
}

/// A discretisation method by its MATLAB name.
fn method_of(name: &str, prewarp: Option<f64>) -> Result<Discretization> {
    if prewarp.is_some() && name != "tustin" {
        bail!("--prewarp applies to the tustin method only (got --method {name})");
    }
    Ok(match name {
        "zoh" => Discretization::Zoh,
        "foh" => Discretization::Foh,
        "tustin" | "bilinear" => Discretization::Tustin { prewarp },
        "euler" | "forward" => Discretization::ForwardEuler,
        "backward" => Discretization::BackwardEuler,
        "matched" => Discretization::Matched,
        "impulse" | "imp" => Discretization::Impulse,
        other => bail!(
            "--method {other}: expected zoh, foh, tustin, euler, backward, matched or impulse"
        ),
    })
}

/// Parses poles: real numbers and complex numbers written `a+bi`/`a-bj`, separated by spaces,
/// commas or semicolons. A complex pole whose conjugate is missing gets it added (MATLAB
/// needs both; writing one is the common slip, and the gain is real only for the pair).
fn parse_poles(text: &str) -> Result<Vec<Complex64>> {
    let mut out: Vec<Complex64> = Vec::new();
    for tok in text
        .trim()
        .trim_start_matches('[')
        .trim_end_matches(']')
        .split([' ', ',', ';', '\t'])
        .filter(|t| !t.is_empty())
    {
        out.push(parse_complex(tok).ok_or_else(|| {
            anyhow!("--poles: `{tok}` is not a number (write complex poles as -1+2i)")
        })?);
    }
    if out.is_empty() {
        bail!("--poles: no poles given");
    }
    // A complex pole without its conjugate gets it, right after it.
    let mut closed = Vec::with_capacity(2 * out.len());
    for p in &out {
        closed.push(*p);
        if p.im != 0.0 && !out.iter().any(|q| q.re == p.re && q.im == -p.im) {
            closed.push(p.conj());
        }
    }
    Ok(closed)
}

/// `a`, `a+bi`, `a-bj`, `bi`; `None` for anything else or a non-finite part.
pub(super) fn parse_complex(tok: &str) -> Option<Complex64> {
    let z = if let Some(body) = tok.strip_suffix(['i', 'j']) {
        // The sign that separates the real and the imaginary part: the last + or − that is
        // not at the start and not an exponent's sign.
        let bytes = body.as_bytes();
        let split = (1..bytes.len()).rev().find(|&k| {
            (bytes[k] == b'+' || bytes[k] == b'-') && !matches!(bytes[k - 1], b'e' | b'E')
        });
        match split {
            Some(k) => {
                let re: f64 = body[..k].parse().ok()?;
                let im_text = &body[k..];
                let im: f64 = match im_text {
                    "+" => 1.0,
                    "-" => -1.0,
                    s => s.parse().ok()?,
                };
                Complex64::new(re, im)
            }
            None => {
                let im: f64 = match body {
                    "" | "+" => 1.0,
                    "-" => -1.0,
                    s => s.parse().ok()?,
                };
                Complex64::new(0.0, im)
            }
        }
    } else {
        Complex64::new(tok.parse().ok()?, 0.0)
    };
    (z.re.is_finite() && z.im.is_finite()).then_some(z)
}

/// The realisation as JSON (`a`, `b`, `c`, `d`, `dt` when discrete): the system-file format.
pub(super) fn system_json(s: &Sys) -> serde_json::Value {
    let (a, b, c, d) = s.matrices();
    let mut v = json!({ "a": rows_of(a), "b": rows_of(b), "c": rows_of(c), "d": rows_of(d) });
    if let Some(dt) = s.dt() {
        v["dt"] = json!(dt);
    }
    v
}

/// `ss`, `c2d`, `d2c`: prints the realisation and its poles, and writes it with `--save`.
fn ss(s: &Sys, out: &SystemOut) -> Result<()> {
    let (save, as_json) = (out.save.as_deref(), out.json);
    let poles = with_sys!(s, |v| v.poles())?;
    if let Some(path) = save {
        write_system(s, path)?;
    }
    let mut out = system_json(s);
    out["poles"] = json!(pairs(&poles));
    if as_json {
        println!("{out}");
        return Ok(());
    }
    let (a, b, c, d) = s.matrices();
    match s.dt() {
        None => println!(
            "continuous-time system, {} state(s), {} input(s), {} output(s)",
            a.nrows(),
            b.ncols(),
            c.nrows()
        ),
        Some(dt) => println!(
            "discrete-time system, dt = {dt} s, {} state(s), {} input(s), {} output(s)",
            a.nrows(),
            b.ncols(),
            c.nrows()
        ),
    }
    for (name, m) in [("A", a), ("B", b), ("C", c), ("D", d)] {
        print_matrix(name, m);
    }
    print_poles("poles", &poles);
    if let Some(path) = save {
        println!("written: {}", path.display());
    }
    Ok(())
}

/// Writes a system file (TOML, or JSON by the `.json` extension), whole or not at all.
pub(crate) fn write_system(s: &Sys, path: &Path) -> Result<()> {
    let v = system_json(s);
    let text = if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        serde_json::to_string_pretty(&v)? + "\n"
    } else {
        toml::to_string(&v).context("formatting the system as TOML")?
    };
    crate::lab::write_whole(path, text.as_bytes())
}

#[derive(Serialize)]
struct RankJson {
    matrix: Vec<Vec<f64>>,
    rank: usize,
    full_rank: bool,
    tolerance: f64,
    singular_values: Vec<f64>,
}

fn rank_report(name: &str, m: &Mat, as_json: bool) -> Result<()> {
    let info = rank(m);
    let out = RankJson {
        matrix: rows_of(m),
        rank: info.rank,
        full_rank: info.rank == m.nrows().min(m.ncols()),
        tolerance: info.tolerance,
        singular_values: info.singular_values,
    };
    if as_json {
        println!("{}", serde_json::to_string(&out)?);
        return Ok(());
    }
    print_matrix(name, m);
    println!(
        "rank {} of {} (tolerance {:.3e}); singular values: {}",
        out.rank,
        m.nrows().min(m.ncols()),
        out.tolerance,
        fmt_row(&out.singular_values)
    );
    Ok(())
}

fn eig(s: &Sys, as_json: bool) -> Result<()> {
    let damp = with_sys!(s, |v| v.damp())?;
    let rows: Vec<_> = damp
        .iter()
        .map(|d| {
            json!({
                "pole": [d.pole.re, d.pole.im],
                "natural_frequency": finite_or_null(d.natural_frequency),
                "damping_ratio": finite_or_null(d.damping_ratio),
                "time_constant": finite_or_null(d.time_constant),
            })
        })
        .collect();
    if as_json {
        println!("{}", json!({ "poles": rows, "dt": s.dt() }));
        return Ok(());
    }
    println!(
        "{:>30}  {:>12}  {:>10}  {:>12}",
        "pole", "ωn [rad/s]", "ζ", "τ [s]"
    );
    for d in &damp {
        println!(
            "{:>14.6} {:+14.6}j  {:>12.6}  {:>10.5}  {:>12.6}",
            d.pole.re, d.pole.im, d.natural_frequency, d.damping_ratio, d.time_constant
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::parse_complex;
    use pendulab_lti::Complex64;

    #[test]
    fn complex_numbers_parse_as_matlab_writes_them() {
        let c = |re, im| Some(Complex64::new(re, im));
        assert_eq!(parse_complex("-1"), c(-1.0, 0.0));
        assert_eq!(parse_complex("-1+2i"), c(-1.0, 2.0));
        assert_eq!(parse_complex("-1-2j"), c(-1.0, -2.0));
        assert_eq!(parse_complex("1e-3-2e+1i"), c(1e-3, -20.0));
        assert_eq!(parse_complex("2i"), c(0.0, 2.0));
        assert_eq!(parse_complex("-i"), c(0.0, -1.0));
        assert_eq!(parse_complex("x"), None);
        assert_eq!(parse_complex("nan"), None);
    }
}
