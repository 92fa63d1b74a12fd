//! `pendulab identify arx|moesp --data FILE.csv --input U --output Y`: black-box models of a
//! measured record (`pendulab_ident::blackbox`), validated on a window of the record, beside
//! the book's physical least squares when the record is the cart drive's (`v` → `z`).
//!
//! * `arx`: `A(q⁻¹) y(k) = B(q⁻¹) u(k − n_k) + e(k)` with the orders `--na --nb --nk`
//!   (MATLAB's `[na nb nk]`), or every `n_a, n_b ∈ 1…N` (`--max-order N`, `n_k` from `--nk`,
//!   default 1) ranked by Akaike's criterion `AIC = N ln V + 2d` (the table is printed).
//! * `moesp`: Verhaegen's PO-MOESP with `--horizon i` block rows (default 10) and the order
//!   `--order n`, or read off the largest gap of the singular values among `1…n`
//!   (`--max-order n`; neither: among all the horizon allows); `--save SYS.toml` writes the
//!   discrete model as a system file `pendulab eig|step|bode` read (`docs/sys.md`).
//!
//! The model is estimated on `--window a:b` (seconds; default the whole record) and validated
//! on `--validate a:b` (default the estimation window) by MATLAB's `compare` fit
//! `100 (1 − ‖y − ŷ‖/‖y − mean y‖)`: the ARX model simulated from the first `max(n_a, n_k +
//! n_b − 1)` measured outputs (the fit over the samples after them), the MOESP model from the
//! zero state (the validation window should start at rest). `--decimate q` keeps every q-th
//! sample for the black-box models (ARX's equation error at 1 ms is dominated by the encoder
//! step; Ljung 1999 §13.7). With input `v` and output `z` the book's cart-drive least squares
//! (`cart-ls`, the same filter options) runs on the estimation window and its model
//! `z̈ = −a_c ż + b_c v` is simulated on the validation window (exact ZOH from the measured
//! initial position and velocity), its fit printed beside.

use crate::identify::{IdentifyArgs, Method, parse_window};
use crate::sys::input::Sys;
use anyhow::{Context, Result, bail};
use pendulab_ident::{
    Arx, ArxOrders, Dataset, Experiment, IoRecord, MoespOptions, arx, arx_order_selection,
    cart_drive_ls, moesp, validate_drive,
};
use pendulab_lti::{Discrete, StateSpace};
use serde_json::{Value, json};

/// The flags of the physical methods that the black-box methods do not read, by name.
fn check_flags(args: &IdentifyArgs) -> Result<()> {
    let arx = args.method == Method::Arx;
    let misplaced = [
        ("--order", args.order.is_some() && arx),
        ("--horizon", args.horizon.is_some() && arx),
        (
            "--na/--nb",
            (args.na.is_some() || args.nb.is_some()) && !arx,
        ),
        ("--nk", args.nk.is_some() && !arx),
        ("--force", args.force),
        ("--step-time", args.step_time.is_some()),
        ("--column", args.column.is_some()),
    ];
    if let Some((flag, _)) = misplaced.iter().find(|(_, bad)| *bad) {
        bail!(
            "identify {}: {flag} does not apply to this method",
            args.method_name()
        );
    }
    if arx && args.max_order.is_some() && (args.na.is_some() || args.nb.is_some()) {
        bail!("identify arx: give either --na/--nb or --max-order, not both");
    }
    if args.order.is_some() && args.max_order.is_some() {
        bail!("identify moesp: give either --order or --max-order, not both");
    }
    for (flag, v) in [
        ("--na", args.na),
        ("--nb", args.nb),
        ("--max-order", args.max_order),
        ("--order", args.order),
        ("--decimate", args.decimate),
    ] {
        if v == Some(0) {
            bail!("identify {}: {flag} must be at least 1", args.method_name());
        }
    }
    Ok(())
}

/// One window of the record: its time span and the (decimated) input and output columns.
struct Part {
    span: [f64; 2],
    samples: usize,
    u: Vec<f64>,
    y: Vec<f64>,
    /// Undecimated, for the physical least squares.
    u_full: Vec<f64>,
    y_full: Vec<f64>,
}

fn part(data: &Dataset, window: Option<&str>, input: &str, output: &str, q: usize) -> Result<Part> {
    let (w0, w1) = match window {
        Some(s) => parse_window(s)?,
        None => (None, None),
    };
    let d = data.window(w0, w1)?;
    let t = d.time()?;
    let (u, y) = (d.column(input)?, d.column(output)?);
    let every = |x: &[f64]| x.iter().step_by(q).copied().collect::<Vec<f64>>();
    Ok(Part {
        span: [t[0], t[t.len() - 1]],
        samples: d.len(),
        u: every(u),
        y: every(y),
        u_full: u.to_vec(),
        y_full: y.to_vec(),
    })
}

fn rows(m: &pendulab_lti::Mat) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| m.row(i).iter().copied().collect())
        .collect()
}

/// The ARX model as JSON: orders, polynomials, standard errors, noise variance, `G(z)`.
fn arx_json(m: &Arx) -> Result<Value> {
    let tf = m.transfer_function()?;
    Ok(json!({
        "na": m.orders.na, "nb": m.orders.nb, "nk": m.orders.nk,
        "a": m.a, "b": m.b,
        "std_error": m.std_error,
        "noise_variance": m.noise_variance,
        "num": tf.num().coefficients(), "den": tf.den().coefficients(),
        "dt": m.ts,
    }))
}

fn ss_json(s: &StateSpace<Discrete>) -> Result<Value> {
    let poles: Vec<[f64; 2]> = s.poles()?.iter().map(|p| [p.re, p.im]).collect();
    Ok(json!({
        "a": rows(s.a()), "b": rows(s.b()), "c": rows(s.c()), "d": rows(s.d()),
        "dt": s.ts(), "poles": poles,
    }))
}

/// Runs `pendulab identify arx|moesp`.
///
/// # Errors
/// A flag of another method; an unreadable or malformed CSV; an unknown column; a window
/// outside the data; orders below 1 or too large for the data; non-finite samples; a
/// regressor that the input does not excite; a system file that cannot be written.
pub fn run(args: &IdentifyArgs) -> Result<()> {
    check_flags(args)?;
    let report = identify(args)?;
    if let Some(path) = &args.save {
        let s = &report.1;
        crate::sys::write_system(&Sys::D(s.clone()), path)
            .with_context(|| format!("--save {}", path.display()))?;
    }
    let mut v = report.0;
    if let Some(path) = &args.save {
        v["saved"] = json!(path.display().to_string());
    }
    if args.json {
        println!("{v}");
    } else {
        print_text(&v);
    }
    Ok(())
}

fn identify(args: &IdentifyArgs) -> Result<(Value, StateSpace<Discrete>)> {
    let source = args.data.display().to_string();
    let text =
        std::fs::read_to_string(&args.data).with_context(|| format!("cannot read {source}"))?;
    let mut data = Dataset::from_csv_str(&source, &text)?;
    if let Some(u) = args.time_unit {
        data = data.with_time_unit(u.into())?;
    }
    data.check_time_unit()?;
    let ts = data.uniform_step()?;
    let input = args.input.as_deref().unwrap_or("v");
    let output = args.output.as_deref().unwrap_or("z");
    let q = args.decimate.unwrap_or(1);
    let est = part(&data, args.window.as_deref(), input, output, q)?;
    let val = part(
        &data,
        args.validate.as_deref().or(args.window.as_deref()),
        input,
        output,
        q,
    )?;
    let dt = ts * q as f64;
    let ex = [Experiment::new(&est.u, &est.y)];
    let mut out = json!({
        "method": args.method_name(),
        "data": source,
        "input": input,
        "output": output,
        "ts": ts,
        "decimate": q,
        "dt": dt,
        "window": est.span,
        "samples": est.samples,
        "validation_window": val.span,
        "validation_samples": val.samples,
    });
    let (model, fit, fit_what) = if args.method == Method::Arx {
        let (m, selection) = match args.max_order {
            Some(n) => {
                let nk = args.nk.unwrap_or(1);
                let s = arx_order_selection(&ex, dt, 1..=n, 1..=n, nk..=nk)?;
                let table: Vec<Value> = s
                    .candidates
                    .iter()
                    .map(|c| {
                        json!({"na": c.orders.na, "nb": c.orders.nb, "nk": c.orders.nk,
                               "loss": c.loss, "aic": c.aic})
                    })
                    .collect();
                (s.model, Some(table))
            }
            None => {
                let o = ArxOrders::new(
                    args.na.unwrap_or(2),
                    args.nb.unwrap_or(2),
                    args.nk.unwrap_or(1),
                );
                (arx(&ex, dt, o)?, None)
            }
        };
        let fit = m
            .fit_percent(&val.u, &val.y)
            .context("validation of the ARX model")?;
        let ss = m.state_space()?;
        out["model"] = arx_json(&m)?;
        out["model"]["poles"] = ss_json(&ss)?["poles"].take();
        out["order_selection"] = json!(selection);
        let what = format!(
            "ARX [{} {} {}] simulated on the measured {input} from the first {} measured {output}",
            m.orders.na,
            m.orders.nb,
            m.orders.nk,
            m.orders.lag()
        );
        (ss, fit, what)
    } else {
        let horizon = args.horizon.unwrap_or(10);
        let rec = [IoRecord::siso(&est.u, &est.y)];
        let opts = MoespOptions {
            horizon,
            order: args.order,
            max_order: args.max_order,
        };
        let s = moesp(&rec, dt, opts)?;
        let fit = s
            .fit_percent(&IoRecord::siso(&val.u, &val.y))
            .context("validation of the MOESP model")?[0];
        let mut m = ss_json(&s.model)?;
        m["order"] = json!(s.order);
        m["horizon"] = json!(horizon);
        m["max_order"] = json!(args.max_order);
        m["singular_values"] = json!(s.singular_values);
        out["model"] = m;
        let what = format!(
            "MOESP n = {} simulated on the measured {input} from the zero state",
            s.order
        );
        (s.model, fit, what)
    };
    out["fit"] = json!({
        "percent": fit,
        "description": format!(
            "{fit_what}, t = {}–{} s, compared with the measured {output}",
            val.span[0], val.span[1]
        ),
    });
    out["physical"] = if input == "v" && output == "z" {
        physical(args, ts, &est, &val)
    } else {
        Value::Null
    };
    Ok((out, model))
}

/// The book's cart-drive least squares on the estimation window, validated on the validation
/// window; a failure is reported in the object (the black-box result stands without it).
fn physical(args: &IdentifyArgs, ts: f64, est: &Part, val: &Part) -> Value {
    let opts = crate::identify::ls_options(args);
    let d = match cart_drive_ls(ts, &est.y_full, &est.u_full, &opts) {
        Ok(d) => d,
        Err(e) => return json!({"error": e.to_string()}),
    };
    match validate_drive(ts, &val.y_full, &val.u_full, d.a, d.b, "z") {
        Ok(v) => json!({
            "ac": d.a, "bc": d.b,
            "fit_percent": v.fit_percent,
            "description": format!(
                "the book's least squares (cart-ls) z'' = −a_c z' + b_c v simulated on the measured v (exact ZOH from the measured initial state), t = {}–{} s",
                val.span[0], val.span[1]
            ),
        }),
        Err(e) => json!({"ac": d.a, "bc": d.b, "error": e.to_string()}),
    }
}

fn nums(v: &Value) -> Vec<f64> {
    v.as_array()
        .map(|a| a.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default()
}

fn poly(c: &[f64], first: usize) -> String {
    c.iter()
        .enumerate()
        .map(|(i, x)| match i + first {
            0 => format!("{x:.6e}"),
            p => format!("{x:+.6e} q^-{p}"),
        })
        .collect::<Vec<_>>()
        .join(" ")
}

fn print_text(v: &Value) {
    let m = &v["model"];
    println!(
        "pendulab identify {} — {}: {} → {}, ts = {} s (decimated ×{}: dt = {} s)",
        v["method"].as_str().unwrap_or(""),
        v["data"].as_str().unwrap_or(""),
        v["input"].as_str().unwrap_or(""),
        v["output"].as_str().unwrap_or(""),
        v["ts"],
        v["decimate"],
        v["dt"]
    );
    println!(
        "estimation window t = {} s ({} samples), validation window t = {} s ({} samples)",
        v["window"], v["samples"], v["validation_window"], v["validation_samples"]
    );
    println!();
    if v["method"] == "arx" {
        if let Some(table) = v["order_selection"].as_array() {
            println!("order selection (AIC = N ln V + 2d):");
            println!(
                "  {:>3} {:>3} {:>3} {:>14} {:>14}",
                "na", "nb", "nk", "V", "AIC"
            );
            for c in table {
                println!(
                    "  {:>3} {:>3} {:>3} {:>14.6e} {:>14.6}",
                    c["na"].as_u64().unwrap_or(0),
                    c["nb"].as_u64().unwrap_or(0),
                    c["nk"].as_u64().unwrap_or(0),
                    c["loss"].as_f64().unwrap_or(f64::NAN),
                    c["aic"].as_f64().unwrap_or(f64::NAN)
                );
            }
            println!();
        }
        println!("ARX [{} {} {}]:", m["na"], m["nb"], m["nk"]);
        println!("  A(q^-1) = {}", poly(&nums(&m["a"]), 0));
        let nk = m["nk"].as_u64().unwrap_or(0) as usize;
        println!("  B(q^-1) = {}", poly(&nums(&m["b"]), nk));
        println!(
            "  noise variance {:.4e}",
            m["noise_variance"].as_f64().unwrap_or(f64::NAN)
        );
    } else {
        let sv = nums(&m["singular_values"]);
        let shown: Vec<String> = sv.iter().take(8).map(|s| format!("{s:.4e}")).collect();
        println!(
            "MOESP, horizon {}, order {}; singular values {}",
            m["horizon"],
            m["order"],
            shown.join(" ")
        );
        for name in ["a", "b", "c", "d"] {
            println!("  {}:", name.to_uppercase());
            for row in m[name].as_array().into_iter().flatten() {
                let r: Vec<String> = nums(row).iter().map(|x| format!("{x:>14.6e}")).collect();
                println!("    {}", r.join(" "));
            }
        }
    }
    let poles: Vec<String> = m["poles"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|p| {
            let p = nums(p);
            format!("{:.6}{:+.6}j", p[0], p[1])
        })
        .collect();
    if !poles.is_empty() {
        println!("  poles (z): {}", poles.join(", "));
    }
    println!();
    println!(
        "validation fit: {:.2} % — {}",
        v["fit"]["percent"].as_f64().unwrap_or(f64::NAN),
        v["fit"]["description"].as_str().unwrap_or("")
    );
    let p = &v["physical"];
    if let Some(f) = p["fit_percent"].as_f64() {
        println!(
            "physical model fit: {f:.2} % (a_c = {:.4}, b_c = {:.4}) — {}",
            p["ac"].as_f64().unwrap_or(f64::NAN),
            p["bc"].as_f64().unwrap_or(f64::NAN),
            p["description"].as_str().unwrap_or("")
        );
    } else if let Some(e) = p["error"].as_str() {
        println!("physical model (cart-ls): not available — {e}");
    }
    if let Some(s) = v["saved"].as_str() {
        println!("written: {s}");
    }
}
