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
use pendulab_plants::spec::{PlantSpec, Provenance};
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
    let table = book_table(kind);
    std::fs::create_dir_all(&args.dir)
        .with_context(|| format!("cannot create {}", args.dir.display()))?;
    write_lab(&args.dir, &PlantSpec::book(kind))?;
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

/// Writes `DIR/lab.toml` whole (through [`write_whole`]) for `plant`, with a header comment
/// saying where the parameters came from; returns the file's path.
///
/// # Errors
/// The TOML writer refuses a value; the file cannot be written.
pub(crate) fn write_lab(dir: &Path, plant: &PlantSpec) -> Result<PathBuf> {
    let path = dir.join(LAB_FILE);
    let lab = LabFile {
        plant: plant.clone(),
    };
    let body = toml::to_string(&lab).context("writing the lab file")?;
    let kind = plant.kind();
    let origin = match plant.provenance() {
        Provenance::Book {} => format!(
            "the parameters are the book's table {}.\n\
             # Edit them and set provenance.source = \"user\" for your own rig.",
            book_table(kind)
        ),
        p => format!("the parameters are {}.", provenance_label(p)),
    };
    let text = format!(
        "# pendulab lab: one {} rig (docs/lab.md).\n\
         # [plant] is a plant file (docs/model.md §6); {origin}\n\n{body}",
        kind.name()
    );
    write_whole(&path, text.as_bytes())?;
    Ok(path)
}

/// The book's table of a plant's parameters: 3.5 (cart), 3.7 (arm).
fn book_table(kind: PlantKind) -> &'static str {
    match kind {
        PlantKind::Cart => "3.5",
        PlantKind::Arm => "3.7",
    }
}

/// The SHA-256 digest of `bytes` as 64 lower-case hexadecimal digits, as `sha256sum` prints
/// it (FIPS 180-4 §6.2: 512-bit blocks, the message padded with a 1 bit, zeros and its
/// length in bits as a 64-bit big-endian number).
pub(crate) fn sha256_hex(bytes: &[u8]) -> String {
    const K: [u32; 64] = [
        0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4,
        0xab1c5ed5, 0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe,
        0x9bdc06a7, 0xc19bf174, 0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f,
        0x4a7484aa, 0x5cb0a9dc, 0x76f988da, 0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7,
        0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967, 0x27b70a85, 0x2e1b2138, 0x4d2c6dfc,
        0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85, 0xa2bfe8a1, 0xa81a664b,
        0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070, 0x19a4c116,
        0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
        0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7,
        0xc67178f2,
    ];
    let mut h: [u32; 8] = [
        0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a, 0x510e527f, 0x9b05688c, 0x1f83d9ab,
        0x5be0cd19,
    ];
    let mut msg = bytes.to_vec();
    let bits = (bytes.len() as u64).wrapping_mul(8);
    msg.push(0x80);
    while msg.len() % 64 != 56 {
        msg.push(0);
    }
    msg.extend_from_slice(&bits.to_be_bytes());
    for block in msg.chunks_exact(64) {
        let mut w = [0u32; 64];
        for (i, word) in block.chunks_exact(4).enumerate() {
            w[i] = u32::from_be_bytes([word[0], word[1], word[2], word[3]]);
        }
        for i in 16..64 {
            let s0 = w[i - 15].rotate_right(7) ^ w[i - 15].rotate_right(18) ^ (w[i - 15] >> 3);
            let s1 = w[i - 2].rotate_right(17) ^ w[i - 2].rotate_right(19) ^ (w[i - 2] >> 10);
            w[i] = w[i - 16]
                .wrapping_add(s0)
                .wrapping_add(w[i - 7])
                .wrapping_add(s1);
        }
        let mut v = h;
        for i in 0..64 {
            let [a, b, c, d, e, f, g, hh] = v;
            let s1 = e.rotate_right(6) ^ e.rotate_right(11) ^ e.rotate_right(25);
            let ch = (e & f) ^ (!e & g);
            let t1 = hh
                .wrapping_add(s1)
                .wrapping_add(ch)
                .wrapping_add(K[i])
                .wrapping_add(w[i]);
            let s0 = a.rotate_right(2) ^ a.rotate_right(13) ^ a.rotate_right(22);
            let maj = (a & b) ^ (a & c) ^ (b & c);
            let t2 = s0.wrapping_add(maj);
            v = [t1.wrapping_add(t2), a, b, c, d.wrapping_add(t1), e, f, g];
        }
        for (x, y) in h.iter_mut().zip(v) {
            *x = x.wrapping_add(y);
        }
    }
    h.iter().map(|x| format!("{x:08x}")).collect()
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

/// A one-line description of where a plant's parameters came from: `book table 3.5`,
/// `identified from run.csv (sha256 1a2b3c4d…, t = 0–8 s)`, `user`.
pub(crate) fn provenance_label(p: &Provenance) -> String {
    match p {
        Provenance::Book {} => "the book's parameters".into(),
        Provenance::Identified {
            file,
            sha256,
            window,
            ..
        } => format!(
            "identified from {file} (sha256 {}…, t = {}–{} s)",
            &sha256[..sha256.len().min(12)],
            window[0],
            window[1]
        ),
        Provenance::User { note } => match note {
            Some(n) => format!("the user's parameters: {n}"),
            None => "the user's parameters".into(),
        },
    }
}

/// Refuses a controller file written for the other plant than the lab's.
///
/// # Errors
/// The file's `plant` is not the lab's kind (naming the file and both plants).
pub(crate) fn check_controller_plant(file: &Path, plant: PlantKind, lab: &PlantSpec) -> Result<()> {
    if plant != lab.kind() {
        bail!(
            "{}: plant = \"{}\", but the lab's plant is the {} pendulum",
            file.display(),
            plant.name(),
            lab.kind().name()
        );
    }
    Ok(())
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

#[cfg(test)]
mod tests {
    use super::sha256_hex;

    /// FIPS 180-4's examples (the NIST "abc" and two-block vectors) and the empty message, as
    /// `sha256sum` prints them.
    #[test]
    fn sha256_matches_the_standard_vectors() {
        assert_eq!(
            sha256_hex(b""),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        assert_eq!(
            sha256_hex(b"abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1"
        );
    }
}
