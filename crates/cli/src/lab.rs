//! `pendulab lab init`: a lab directory for one rig, and the reader of its `lab.toml` that
//! `pendulab model` and `pendulab simulate` share (`docs/lab.md`).
//!
//! A lab directory holds `lab.toml`, whose `[plant]` table is a plant file
//! (`pendulab_plants::spec::PlantSpec`, `docs/model.md` §6): the plant's kind, its parameters
//! with their provenance, and the rig part (sample time, amplifier, D/A, encoders, limits).
//! `lab init` writes the book's plant (table 3.5 for the cart, table 3.7 for the arm,
//! `provenance.source = "book"`). Any other top-level key is refused by name and line.

use anyhow::{Context, Result, bail};
use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::PlantSpec;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The name of the lab file inside a lab directory.
pub const LAB_FILE: &str = "lab.toml";

/// Arguments of `pendulab lab`.
#[derive(Debug, clap::Args)]
pub struct LabArgs {
    #[command(subcommand)]
    command: LabCommand,
}

#[derive(Debug, clap::Subcommand)]
enum LabCommand {
    /// Create a lab directory: DIR/lab.toml with the book's plant of the chosen kind.
    Init(InitArgs),
}

/// Arguments of `pendulab lab init`.
#[derive(Debug, clap::Args)]
struct InitArgs {
    /// The lab directory (created if missing).
    dir: PathBuf,
    /// Which pendulum: `cart` (book table 3.5) or `arm` (book table 3.7).
    #[arg(long, value_parser = ["cart", "arm"])]
    plant: String,
    /// Overwrite an existing lab.toml.
    #[arg(long)]
    force: bool,
    /// Print one JSON object instead of a human-readable line.
    #[arg(long)]
    json: bool,
}

/// The lab file's layout: `[plant]` is a plant file, nothing else.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LabFile {
    plant: PlantSpec,
}

/// Runs `pendulab lab …`.
///
/// # Errors
/// An existing lab.toml without `--force`; a directory or file that cannot be written.
pub fn run(args: &LabArgs) -> Result<()> {
    match &args.command {
        LabCommand::Init(a) => init(a),
    }
}

fn init(args: &InitArgs) -> Result<()> {
    let kind = PlantKind::parse(&args.plant)?;
    let path = args.dir.join(LAB_FILE);
    if path.exists() && !args.force {
        bail!("{} exists; pass --force to overwrite it", path.display());
    }
    let table = match kind {
        PlantKind::Cart => "3.5",
        PlantKind::Arm => "3.7",
    };
    let lab = LabFile {
        plant: PlantSpec::book(kind),
    };
    let body = toml::to_string(&lab).context("writing the lab file")?;
    let text = format!(
        "# pendulab lab: one {} rig (docs/lab.md).\n\
         # [plant] is a plant file (docs/model.md §6); the parameters are the book's table {table}.\n\
         # Edit them and set provenance.source = \"user\" for your own rig.\n\n{body}",
        kind.name()
    );
    std::fs::create_dir_all(&args.dir)
        .with_context(|| format!("cannot create {}", args.dir.display()))?;
    write_whole(&path, text.as_bytes())?;
    if args.json {
        let out = serde_json::json!({
            "lab": args.dir,
            "file": path,
            "plant": kind.name(),
            "provenance": format!("book table {table}"),
        });
        println!("{out}");
    } else {
        println!(
            "wrote {} ({} pendulum, book table {table})",
            path.display(),
            kind.name()
        );
    }
    Ok(())
}

/// Writes `bytes` to `path` whole or not at all: into a temporary file beside it, then renamed
/// over `path`.
///
/// # Errors
/// The file cannot be written or renamed (naming the path).
pub(crate) fn write_whole(path: &Path, bytes: &[u8]) -> Result<()> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp{}", std::process::id()));
    std::fs::write(&tmp, bytes).with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| {
        let _ = std::fs::remove_file(&tmp);
        format!("cannot write {}", path.display())
    })
}

/// Reads and validates `DIR/lab.toml`: its `[plant]` table as a [`PlantSpec`].
///
/// # Errors
/// A missing or unreadable file (naming it); TOML syntax errors, unknown, missing or mistyped
/// keys (naming the key, with the line); the plant's validation errors (naming the key, e.g.
/// `parameters.m_p`).
pub fn load(dir: &Path) -> Result<PlantSpec> {
    let path = dir.join(LAB_FILE);
    let text = std::fs::read_to_string(&path).with_context(|| {
        format!(
            "cannot read {} (create it with `pendulab lab init {} --plant cart|arm`)",
            path.display(),
            dir.display()
        )
    })?;
    let lab: LabFile = toml::from_str(&text)
        .map_err(|e| anyhow::anyhow!("{}", located(&text, &e)))
        .with_context(|| format!("in {}", path.display()))?;
    Ok(lab.plant)
}

/// The message of a lab file's TOML error, with the line of the key it names.
///
/// The plant's own checks (a parameter of the other plant, a value out of range) run once the
/// whole `[plant]` table is read, so TOML places them at the table's header; when the message
/// names a key of `[plant.parameters]`, `[plant.rig]` or `[plant.provenance]` (`parameters.m_p`,
/// ``unknown field `x` `` among the parameters), the line of that key is found in the text.
fn located(text: &str, e: &toml::de::Error) -> String {
    let msg = e.message().trim_end();
    let named = ["parameters", "rig", "provenance"]
        .iter()
        .find_map(|section| {
            let at = msg.find(&format!("{section}."))?;
            let key: String = msg[at + section.len() + 1..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            Some((*section, key))
        });
    let named = named.or_else(|| {
        let rest = msg
            .strip_prefix("parameters of the ")?
            .split_once("unknown field `")?
            .1;
        Some(("parameters", rest.split('`').next()?.to_string()))
    });
    match named.and_then(|(section, key)| {
        key_line(text, &format!("plant.{section}"), &key).map(|n| (section, key, n))
    }) {
        Some((section, key, line)) => {
            format!("line {line}, key plant.{section}.{key}: {msg}")
        }
        None => e.to_string().trim_end().to_string(),
    }
}

/// The 1-based line of `key = …` inside the table `[table]` of `text` (a plain scan: table
/// headers and bare keys, as `lab init` writes them).
fn key_line(text: &str, table: &str, key: &str) -> Option<usize> {
    let mut current = String::new();
    for (i, line) in text.lines().enumerate() {
        let l = line.trim();
        if let Some(h) = l.strip_prefix('[') {
            current = h.trim_matches(|c| c == '[' || c == ']').trim().to_string();
        } else if current == table
            && let Some(rest) = l.strip_prefix(key)
            && rest.trim_start().starts_with('=')
        {
            return Some(i + 1);
        }
    }
    None
}
