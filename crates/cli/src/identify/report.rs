//! What `pendulab identify` reports: the [`Report`] (estimates, standard errors, the
//! validation fit, warnings), the [`Gate`] that refuses a failed check or non-finite number
//! (with `--force` a warning instead), the fit's description, and the table printed.

use anyhow::{Result, anyhow};
use pendulab_ident::{IdentError, Validation};
use serde::Serialize;
use serde_json::{Map, Value, json};

/// One output of the identification.
#[derive(Debug, Serialize)]
pub(super) struct Report {
    pub(super) method: &'static str,
    pub(super) data: String,
    pub(super) window: [f64; 2],
    pub(super) samples: usize,
    pub(super) ts: f64,
    pub(super) options: Value,
    pub(super) constants: Value,
    pub(super) estimates: Map<String, Value>,
    pub(super) std_errors: Map<String, Value>,
    /// Least-squares methods only (the feature methods have no regressor): left out otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) condition: Option<Value>,
    /// Least-squares methods only: left out otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) residual_rms: Option<Value>,
    pub(super) fit: Value,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) fit_linear: Option<Value>,
    /// Every check that failed and was overridden by `--force` (empty otherwise).
    pub(super) warnings: Vec<String>,
    #[serde(skip)]
    pub(super) units: Vec<(&'static str, &'static str)>,
}

/// Applies the checks: a failure is an error, or with `--force` a warning.
pub(super) struct Gate {
    pub(super) force: bool,
    pub(super) warnings: Vec<String>,
}

impl Gate {
    /// Every failure of a list (the first refuses; forced, all become warnings).
    pub(super) fn check_all(&mut self, failures: Vec<IdentError>) -> Result<()> {
        for e in failures {
            self.check(Err(e))?;
        }
        Ok(())
    }

    pub(super) fn check(&mut self, r: pendulab_ident::Result<()>) -> Result<()> {
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
    pub(super) fn soft<T>(
        &mut self,
        what: &str,
        r: pendulab_ident::Result<T>,
    ) -> Result<Option<T>> {
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
    pub(super) fn put(&mut self, map: &mut Map<String, Value>, name: &str, v: f64) -> Result<()> {
        self.put_labelled(map, name, name, v)
    }

    /// As [`Gate::put`] for a standard error.
    pub(super) fn put_se(
        &mut self,
        map: &mut Map<String, Value>,
        name: &str,
        v: f64,
    ) -> Result<()> {
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
    pub(super) fn num(&mut self, label: &str, v: f64) -> Result<Value> {
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
pub(super) fn g4(x: f64) -> String {
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
pub(super) struct FitMeaning<'a> {
    pub(super) model: String,
    pub(super) input: &'a str,
    pub(super) t: &'a [f64],
}

pub(super) fn fit_json(gate: &mut Gate, v: &Validation, m: &FitMeaning<'_>) -> Result<Value> {
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

pub(super) fn print_table(r: &Report) {
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
