//! The controller file `pendulab design` writes (`pendulab_rig::config`): a comment header
//! (the method, the lab, the SHA-256 of its plant table, the parameters), then `plant`,
//! `rate_hz`, `[controller]` with the design record `[controller.designed_for]`
//! (`pendulab_control::spec::DesignRecord`), checked by reading it back as the rig would and
//! building it on the lab's plant before it is written whole.

use super::Designed;
use crate::lab;
use anyhow::{Context, Result, bail};
use pendulab_control::spec::design::SERVO_METHOD;
use pendulab_control::spec::{ControllerSpec, DesignRecord, build_for};
use pendulab_plants::spec::PlantSpec;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// The file's text and what the output says of the lab.
pub(super) struct ControllerFile {
    /// The whole file.
    pub text: String,
    /// The SHA-256 (hex) of the lab's plant table.
    pub plant_sha256: String,
    /// The lab plant's provenance in words.
    pub designed_on: String,
}

/// The comment header: the method and its inputs, the lab's plant, its SHA-256 and parameters,
/// the method's note.
fn header(
    plant: &PlantSpec,
    lab_dir: &Path,
    method: &str,
    d: &Designed,
    plant_sha: &str,
    designed_on: &str,
) -> String {
    let kind = plant.kind();
    let inputs = &d.inputs;
    let mut text = String::new();
    let _ = writeln!(
        text,
        "# pendulab design {method}: a controller file for `pendulab simulate` and `pendulab rig run` (docs/lab.md)."
    );
    let _ = writeln!(
        text,
        "# Designed on the {} pendulum of {} ({designed_on}),",
        kind.name(),
        lab_dir.display()
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
    text.push_str(d.note);
    text
}

/// The TOML body: the `[controller]` table as the rig reads it, then with the design record
/// (the lab's plant, the upright operating point, a continuous-time design, the method and
/// its inputs); `p` adds a `[safety]` window for the hanging pendulum.
fn body(plant: &PlantSpec, method: &'static str, rate_hz: f64, d: &Designed) -> Result<String> {
    let kind = plant.kind();
    let draft = format!(
        "plant = \"{}\"\nrate_hz = {rate_hz:?}\n\n[controller]\n{}",
        kind.name(),
        d.table
    );
    let loaded = pendulab_rig::config::load(&draft).context("the designed controller")?;
    // The record names the method as every front end does (the browser lab's servo too); the
    // verb `servo` stays the file's stem and the JSON's `method`.
    let record_method = match method {
        "servo" => SERVO_METHOD,
        other => other,
    };
    let record = DesignRecord::new(
        plant,
        vec![0.0; 4],
        None,
        record_method,
        d.record.iter().cloned().collect(),
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
    toml::to_string(&File {
        plant: kind.name(),
        rate_hz,
        controller: &spec,
        safety,
    })
    .context("writing the controller file")
}

/// The file of design `d` by `method` on the lab's `plant` (in `lab_dir`) at `rate_hz`,
/// read back as the rig reads it and built on the lab's plant, its record checked against the
/// lab: an error unless all accept it.
pub(super) fn controller_file(
    plant: &PlantSpec,
    lab_dir: &Path,
    method: &'static str,
    rate_hz: f64,
    d: &Designed,
) -> Result<ControllerFile> {
    let plant_toml = plant.to_toml().context("the lab's plant as TOML")?;
    let plant_sha = lab::sha256_hex(plant_toml.as_bytes());
    let designed_on = lab::provenance_label(plant.provenance());
    let mut text = header(plant, lab_dir, method, d, &plant_sha, &designed_on);
    let body = body(plant, method, rate_hz, d)?;
    let _ = write!(text, "\n{body}");
    let loaded = pendulab_rig::config::load(&text).context("the designed file, read back")?;
    let warnings = loaded
        .spec
        .check_plant(plant)
        .context("the designed file's record")?;
    if let Some(w) = warnings.first() {
        bail!("the designed file's record differs from the lab: {w}");
    }
    build_for(&loaded.spec, plant, loaded.ts).context("the designed file, built")?;
    Ok(ControllerFile {
        text,
        plant_sha256: plant_sha,
        designed_on,
    })
}

/// Writes `text` to `path` whole, creating its folder.
pub(super) fn write_file(path: &Path, text: &str) -> Result<()> {
    if let Some(dir) = path.parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    lab::write_whole(path, text.as_bytes())
}
