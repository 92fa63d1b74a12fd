//! `pendulab identify --save DIR`: the estimates written into the lab's `lab.toml` with their
//! provenance (the data file, its SHA-256, the window, the standard errors).

use super::IdentifyArgs;
use super::report::Report;
use anyhow::{Context, Result, bail};
use pendulab_plants::spec::{PlantParameters, PlantSpec, Provenance};
use serde::Serialize;
use serde_json::{Map, Value, json};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

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
pub(super) fn save(args: &IdentifyArgs, dir: &Path, report: &Report) -> Result<SavedOut> {
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
pub(super) struct SavedOut {
    pub(super) file: PathBuf,
    pub(super) parameters: BTreeMap<String, (f64, f64)>,
}
