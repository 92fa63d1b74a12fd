//! The design as a controller file for `pendulab rig run --controller FILE.toml`
//! (`docs/rig/README.md`; the format of `pendulab_rig::config`): `plant`, `rate_hz` and the
//! `[controller]` table, which is the [`ControllerSpec`] serialised as the rig's files and the
//! control crate's tests write it (`toml::to_string`).

use crate::error::WebError;
use pendulab_control::spec::ControllerSpec;
use pendulab_plants::spec::PlantSpec;
use serde::Serialize;

#[derive(Serialize)]
struct ControllerFile<'a> {
    plant: &'static str,
    rate_hz: f64,
    controller: &'a ControllerSpec,
}

/// The controller file running `spec` on `plant`'s rig at its sample rate, headed by `comment`
/// lines (`#`-prefixed; the design that gave the gain).
///
/// # Errors
/// [`WebError::Toml`] when the spec cannot be written (a non-finite gain).
pub fn controller_file(
    plant: &PlantSpec,
    spec: &ControllerSpec,
    comment: &str,
) -> Result<String, WebError> {
    let body = toml::to_string(&ControllerFile {
        plant: plant.kind().name(),
        rate_hz: 1.0 / plant.rig().sample_time,
        controller: spec,
    })?;
    let head: String = comment.lines().map(|l| format!("# {l}\n")).collect();
    Ok(format!("{head}{body}"))
}
