//! `pendulab book list` and `pendulab book run`.

use anyhow::{Context, Result, bail};
use pendulab_book::{Example, ExampleOutput, RunContext};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Arguments of `pendulab book`.
#[derive(Debug, clap::Args)]
pub struct BookArgs {
    #[command(subcommand)]
    command: BookCommand,
}

#[derive(Debug, clap::Subcommand)]
enum BookCommand {
    /// List every example with its section and title.
    List {
        /// One JSON object per line instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Run examples by id (or all of them) and print their numbers.
    Run {
        /// Example ids (the book's MATLAB file stems).
        ids: Vec<String>,
        /// Run every example.
        #[arg(long)]
        all: bool,
        /// Write figures into this directory.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Measured data (CSV) for the examples that need it.
        #[arg(long)]
        data: Option<PathBuf>,
        /// One JSON object per example per line.
        #[arg(long)]
        json: bool,
    },
}

#[derive(Serialize)]
struct JsonLine<'a> {
    id: &'a str,
    values: BTreeMap<&'a str, &'a pendulab_book::Value>,
    figures: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<String>,
}

/// Runs `pendulab book ...`.
pub fn run(args: &BookArgs) -> Result<()> {
    match &args.command {
        BookCommand::List { json } => {
            for e in pendulab_book::registry() {
                if *json {
                    println!(
                        "{}",
                        serde_json::json!({
                            "id": e.id, "title": e.title, "section": e.section,
                            "parameters": e.parameters, "needs_data": e.needs_data,
                        })
                    );
                } else {
                    let data = if e.needs_data.is_some() {
                        "  [needs --data]"
                    } else {
                        ""
                    };
                    println!("{:<44} {:<16} {}{data}", e.id, e.section, e.title);
                }
            }
            Ok(())
        }
        BookCommand::Run {
            ids,
            all,
            out,
            data,
            json,
        } => {
            let examples = select(ids, *all)?;
            let data_csv = match data {
                Some(p) => Some(
                    std::fs::read_to_string(p)
                        .with_context(|| format!("cannot read data file {}", p.display()))?,
                ),
                None => None,
            };
            if let Some(dir) = out {
                std::fs::create_dir_all(dir)
                    .with_context(|| format!("cannot create output directory {}", dir.display()))?;
            }
            let ctx = RunContext {
                out_dir: out.clone(),
                data_csv,
            };
            let mut failures = 0usize;
            for e in &examples {
                let result = (e.run)(&ctx);
                match (&result, *json) {
                    (Ok(o), true) => println!("{}", json_line(e, Some(o), None)?),
                    (Ok(o), false) => print_human(e, o),
                    (Err(err), true) => {
                        failures += 1;
                        println!("{}", json_line(e, None, Some(err.to_string()))?);
                    }
                    (Err(err), false) => {
                        failures += 1;
                        eprintln!("{}: error: {err}", e.id);
                    }
                }
            }
            if failures > 0 {
                bail!("{failures} of {} examples failed", examples.len());
            }
            Ok(())
        }
    }
}

/// The examples named by `ids`, or all of them.
pub fn select(ids: &[String], all: bool) -> Result<Vec<Example>> {
    if all {
        if !ids.is_empty() {
            bail!("give example ids or --all, not both");
        }
        return Ok(pendulab_book::registry());
    }
    if ids.is_empty() {
        bail!("name at least one example id, or pass --all (see `pendulab book list`)");
    }
    ids.iter()
        .map(|id| pendulab_book::find(id).map_err(anyhow::Error::from))
        .collect()
}

fn json_line(e: &Example, o: Option<&ExampleOutput>, error: Option<String>) -> Result<String> {
    let line = JsonLine {
        id: e.id,
        values: o
            .map(|o| o.values.iter().map(|(k, v)| (k.as_str(), v)).collect())
            .unwrap_or_default(),
        figures: o
            .map(|o| o.figures.iter().map(|p| p.display().to_string()).collect())
            .unwrap_or_default(),
        error,
    };
    Ok(serde_json::to_string(&line)?)
}

fn print_human(e: &Example, o: &ExampleOutput) {
    println!("{} — {} ({})", e.id, e.title, e.section);
    for (name, v) in &o.values {
        let book = o
            .references
            .iter()
            .find(|r| &r.name == name)
            .map(|r| {
                format!(
                    "   [book: {}]",
                    serde_json::to_string(&r.value).unwrap_or_default()
                )
            })
            .unwrap_or_default();
        println!(
            "  {name} = {}{book}",
            serde_json::to_string(v).unwrap_or_default()
        );
    }
    for f in &o.figures {
        println!("  figure: {}", f.display());
    }
    for n in &o.notes {
        println!("  note: {n}");
    }
}
