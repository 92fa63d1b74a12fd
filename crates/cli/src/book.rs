//! `pendulab book list` and `pendulab book run`, and the example runner `pendulab report` shares.

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use pendulab_book::report::{Entry, Status, markdown_table};
use pendulab_book::{BookError, Example, ExampleOutput, RunContext};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Arguments of `pendulab book`.
#[derive(Debug, clap::Args)]
pub struct BookArgs {
    #[command(subcommand)]
    command: BookCommand,
}

#[derive(Debug, clap::Subcommand)]
enum BookCommand {
    /// List every example with its section and title, then (without --json) the M-file stems
    /// that are aliases of an example.
    List {
        /// One JSON object per line instead of a table.
        #[arg(long, conflicts_with = "markdown")]
        json: bool,
        /// The README table (id, section, title, status); runs every example to find its
        /// status (reproduced / runs / differs from book / needs data / failing).
        #[arg(long)]
        markdown: bool,
        /// With --markdown: measured data for an example, as ID=FILE.csv (repeatable).
        #[arg(long, value_name = "ID=FILE", requires = "markdown")]
        data: Vec<String>,
    },
    /// Run examples by id (or all of them) and print their numbers.
    Run {
        /// Example ids (the book's MATLAB file stems).
        ids: Vec<String>,
        /// Run every example (examples without their data report "needs --data" and do not
        /// count as failures).
        #[arg(long)]
        all: bool,
        /// Write figures into this directory.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Measured data (CSV with a header row): FILE for every selected example that needs
        /// data, or ID=FILE for one example (repeatable).
        #[arg(long, value_name = "FILE|ID=FILE")]
        data: Vec<String>,
        /// One JSON object per example per line.
        #[arg(long)]
        json: bool,
    },
}

#[derive(Serialize)]
struct JsonLine<'a> {
    id: &'a str,
    values: BTreeMap<&'a str, &'a pendulab_book::Value>,
    /// The stated SI unit of each value that has one (`ExampleOutput::units`).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    units: BTreeMap<&'a str, &'a str>,
    figures: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    needs_data: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<String>,
}

/// Runs `pendulab book ...`.
pub fn run(args: &BookArgs) -> Result<()> {
    match &args.command {
        BookCommand::List {
            json,
            markdown,
            data,
        } => {
            if *markdown {
                let examples = pendulab_book::registry();
                let data = DataFiles::parse(data, &examples, false)?;
                let entries = run_examples(&examples, OutLayout::None, &data, true);
                print!("{}", markdown_table(&entries));
                return Ok(());
            }
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
                        "  [takes --data]"
                    } else {
                        ""
                    };
                    println!("{:<44} {:<16} {}{data}", e.id, e.section, e.title);
                }
            }
            // The book's M-files without an example of their own, each with the example that
            // computes what it computes (`pendulab book run` accepts either name). The JSON
            // lines list examples only (docs/report.md's line contract).
            if !*json {
                for a in pendulab_book::registry::aliases() {
                    println!("{:<44} alias of {}: {}", a.stem, a.id, a.note);
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
            let data = DataFiles::parse(data, &examples, true)?;
            if let Some(dir) = out {
                prepare_out_dir(dir)?;
            }
            let entries = run_examples(&examples, OutLayout::flat(out.as_deref()), &data, *all);
            let mut failures = 0usize;
            for e in &entries {
                // A missing data file is a failure when the example was asked for by name;
                // with --all it is reported and skipped.
                let failed = match e.status() {
                    Status::Failing => true,
                    Status::NeedsData => !*all,
                    _ => false,
                };
                failures += usize::from(failed);
                if *json {
                    println!("{}", json_line(e)?);
                } else {
                    print_human(e);
                }
            }
            if failures > 0 {
                bail!("{failures} of {} examples failed", entries.len());
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

/// Creates `dir` if needed and checks that files can be written into it.
///
/// # Errors
/// When the directory cannot be created or a file cannot be written in it.
pub(crate) fn prepare_out_dir(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create output directory {}", dir.display()))?;
    let probe = dir.join(format!(".pendulab-write-test-{}", std::process::id()));
    std::fs::write(&probe, b"")
        .with_context(|| format!("cannot write into output directory {}", dir.display()))?;
    // Best effort: a probe left behind is harmless.
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// Measured-data files given on the command line, read and checked.
#[derive(Debug, Default)]
pub(crate) struct DataFiles {
    /// Contents for every selected example that needs data (`--data FILE`).
    all: Option<String>,
    /// Contents per example id (`--data ID=FILE`).
    by_id: BTreeMap<String, String>,
}

impl DataFiles {
    /// Parses `--data` arguments: `ID=FILE` when the part before the first `=` is an example
    /// id, else (if `plain_allowed`) a FILE for every selected example that needs data. Each
    /// file is read and checked to be a CSV table with a header row and numeric rows.
    ///
    /// # Errors
    /// Unknown ids, ids whose example takes no data, a plain FILE where only `ID=FILE` is
    /// accepted, unreadable or malformed files.
    pub(crate) fn parse(
        args: &[String],
        selected: &[Example],
        plain_allowed: bool,
    ) -> Result<Self> {
        let mut files = DataFiles::default();
        for arg in args {
            let pair = arg
                .split_once('=')
                .filter(|(id, _)| pendulab_book::find(id).is_ok());
            match pair {
                Some((id, path)) => {
                    let ex = pendulab_book::find(id)?;
                    if ex.needs_data.is_none() {
                        bail!("--data {arg}: example '{id}' takes no measured data");
                    }
                    if !selected.iter().any(|e| e.id == id) {
                        eprintln!("warning: --data {arg}: example '{id}' is not being run");
                    }
                    let text = read_data_file(Path::new(path))?;
                    if files.by_id.insert(id.to_string(), text).is_some() {
                        bail!("--data given twice for example '{id}'");
                    }
                }
                None if plain_allowed => {
                    if files.all.is_some() {
                        bail!(
                            "--data {arg}: only one plain data FILE may be given; name the \
                             example for each further file as ID=FILE"
                        );
                    }
                    if let Some((id, _)) = arg.split_once('=')
                        && !Path::new(arg).exists()
                    {
                        bail!("--data {arg}: unknown example id '{id}' (see `pendulab book list`)");
                    }
                    if !selected.iter().any(|e| e.needs_data.is_some()) {
                        eprintln!(
                            "warning: --data {arg}: none of the selected examples takes measured data"
                        );
                    }
                    files.all = Some(read_data_file(Path::new(arg))?);
                }
                None => match arg.split_once('=') {
                    Some((id, _)) => {
                        bail!("--data {arg}: unknown example id '{id}' (see `pendulab book list`)")
                    }
                    None => bail!("--data {arg}: expected ID=FILE (example id, then the CSV file)"),
                },
            }
        }
        Ok(files)
    }

    /// Data for one example id, without reading a file.
    #[cfg(test)]
    pub(crate) fn for_tests(id: &str, text: &str) -> Self {
        DataFiles {
            all: None,
            by_id: BTreeMap::from([(id.to_string(), text.to_string())]),
        }
    }

    /// The data for one example, if any was given and the example takes data.
    fn for_example(&self, e: &Example) -> Option<String> {
        e.needs_data?;
        self.by_id.get(e.id).or(self.all.as_ref()).cloned()
    }
}

/// Reads a data file and checks it is a CSV table: a header row of non-empty names, then at
/// least one row, every row with as many fields as the header, every field a number.
///
/// # Errors
/// Names the file, and the line and field that are wrong.
pub(crate) fn read_data_file(path: &Path) -> Result<String> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read data file {}", path.display()))?;
    check_csv(&text).with_context(|| format!("malformed data file {}", path.display()))?;
    Ok(text)
}

fn check_csv(text: &str) -> Result<()> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((_, header)) = lines.next() else {
        bail!("the file is empty (expected a header row such as t,theta then numeric rows)");
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    if names.iter().any(|n| n.is_empty()) {
        bail!("line 1: the header has an empty column name");
    }
    if names.iter().all(|n| n.parse::<f64>().is_ok()) {
        bail!("line 1: expected a header row of column names, found numbers");
    }
    let mut rows = 0usize;
    for (i, line) in lines {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            bail!(
                "line {}: {} fields, but the header names {} columns",
                i + 1,
                fields.len(),
                names.len()
            );
        }
        for (f, name) in fields.iter().zip(&names) {
            match f.parse::<f64>() {
                Ok(x) if x.is_finite() => {}
                _ => bail!(
                    "line {}, column '{name}': '{f}' is not a finite number",
                    i + 1
                ),
            }
        }
        rows += 1;
    }
    if rows == 0 {
        bail!("no data rows after the header");
    }
    Ok(())
}

/// Where figures go.
#[derive(Debug, Clone, Copy)]
pub(crate) enum OutLayout<'a> {
    /// Numbers only.
    None,
    /// Every example writes into this directory.
    Flat(&'a Path),
    /// Each example writes into `dir/<id>/`.
    PerExample(&'a Path),
}

impl<'a> OutLayout<'a> {
    fn flat(dir: Option<&'a Path>) -> Self {
        dir.map_or(OutLayout::None, OutLayout::Flat)
    }
    fn dir_for(self, e: &Example) -> Option<PathBuf> {
        match self {
            OutLayout::None => None,
            OutLayout::Flat(d) => Some(d.to_path_buf()),
            OutLayout::PerExample(d) => Some(d.join(e.id)),
        }
    }
}

/// Runs the examples in parallel (rayon), results in the given order. With `progress`, shows a
/// progress bar on stderr, or, when stderr is not a terminal (a log, CI), one line per finished
/// example. A panicking example becomes a [`BookError::Computation`] naming the panic.
pub(crate) fn run_examples(
    examples: &[Example],
    layout: OutLayout<'_>,
    data: &DataFiles,
    progress: bool,
) -> Vec<Entry> {
    let bar = if progress {
        let bar = ProgressBar::new(examples.len() as u64);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:36} {pos}/{len} examples  {wide_msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar
    } else {
        ProgressBar::hidden()
    };
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    let log_lines = progress && !std::io::stderr().is_terminal();
    let done = AtomicUsize::new(0);
    let entries: Vec<Entry> = examples
        .par_iter()
        .map(|e| {
            let dir = layout.dir_for(e);
            let ctx = RunContext {
                figures: dir.is_some(),
                data_csv: data.for_example(e),
            };
            let start = Instant::now();
            let (result, files) = run_one(e, &ctx, dir.as_deref());
            let seconds = start.elapsed().as_secs_f64();
            let k = done.fetch_add(1, Ordering::Relaxed) + 1;
            if log_lines {
                eprintln!(
                    "[{k}/{}] {} — {} ({seconds:.2} s)",
                    examples.len(),
                    e.id,
                    Status::of(&result).label()
                );
            }
            bar.inc(1);
            bar.set_message(format!("{} ({:.2} s)", e.id, seconds));
            Entry {
                example: *e,
                result,
                seconds: Some(seconds),
                files,
            }
        })
        .collect();
    bar.finish_and_clear();
    entries
}

/// Runs one example and, given a figure directory (created first), renders its figures and
/// writes them there; returns the result and the files written. A figure that cannot be
/// rendered or written turns the result into that error.
fn run_one(
    e: &Example,
    ctx: &RunContext,
    dir: Option<&Path>,
) -> (Result<ExampleOutput, BookError>, Vec<PathBuf>) {
    if let Some(dir) = dir
        && let Err(source) = std::fs::create_dir_all(dir)
    {
        let err = BookError::WriteFigure {
            id: e.id.to_string(),
            path: dir.to_path_buf(),
            source,
        };
        return (Err(err), Vec::new());
    }
    let result = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| (e.run)(ctx))) {
        Ok(r) => r,
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(BookError::Panicked {
                id: e.id.to_string(),
                payload: what,
            })
        }
    };
    match (result, dir) {
        (Ok(out), Some(dir)) => match write_figures(e.id, &out, dir) {
            Ok(files) => (Ok(out), files),
            Err(err) => (Err(err), Vec::new()),
        },
        (result, _) => (result, Vec::new()),
    }
}

/// Renders every figure of `out` and writes its files into `dir`, in order.
///
/// # Errors
/// [`BookError::Figure`] when a figure cannot be rendered, [`BookError::WriteFigure`] when a
/// file cannot be written.
pub(crate) fn write_figures(
    id: &str,
    out: &ExampleOutput,
    dir: &Path,
) -> Result<Vec<PathBuf>, BookError> {
    out.emit_figures(id, dir, |path, bytes| std::fs::write(path, bytes))
}

/// The JSON line of `docs/report.md` (`pendulab book`) for one result.
pub(crate) fn json_line(e: &Entry) -> Result<String> {
    let o = e.result.as_ref().ok();
    let line = JsonLine {
        id: e.example.id,
        values: o
            .map(|o| o.values.iter().map(|(k, v)| (k.as_str(), v)).collect())
            .unwrap_or_default(),
        units: o
            .map(|o| {
                o.units
                    .iter()
                    .map(|(k, u)| (k.as_str(), u.as_str()))
                    .collect()
            })
            .unwrap_or_default(),
        figures: e.files.iter().map(|p| p.display().to_string()).collect(),
        needs_data: match &e.result {
            Err(BookError::NeedsData { .. }) => e.example.needs_data.or(Some("measured data")),
            _ => None,
        },
        error: match &e.result {
            Err(BookError::NeedsData { .. }) | Ok(_) => None,
            Err(err) => Some(err.to_string()),
        },
    };
    Ok(serde_json::to_string(&line)?)
}

fn print_human(e: &Entry) {
    let ex = &e.example;
    println!("{} — {} ({})", ex.id, ex.title, ex.section);
    let o = match &e.result {
        Ok(o) => o,
        Err(err @ BookError::NeedsData { .. }) => {
            println!("  needs --data: {err}");
            return;
        }
        Err(err) => {
            println!("  error: {err}");
            return;
        }
    };
    let comparisons = o.comparisons();
    for (name, v) in &o.values {
        let book: String = o
            .references
            .iter()
            .zip(&comparisons)
            .filter(|(r, _)| &r.name == name)
            .map(|(r, c)| {
                format!(
                    "   [book: {} {}]",
                    pendulab_book::report::format::value_text(&r.value),
                    if c.reproduced { "✓" } else { "✗" }
                )
            })
            .collect();
        println!(
            "  {name} = {}{book}",
            pendulab_book::report::format::value_text(v)
        );
    }
    for f in &e.files {
        println!("  figure: {}", f.display());
    }
    for n in &o.notes {
        println!("  note: {n}");
    }
}

#[cfg(test)]
mod tests {
    use super::check_csv;

    #[test]
    fn csv_check_accepts_the_rig_format_and_names_what_is_wrong() {
        assert!(check_csv("t,theta\n0.0,1.5\n0.001,-2e-3\n").is_ok());
        let err = |s: &str| format!("{:#}", check_csv(s).unwrap_err());
        assert!(err("").contains("empty"));
        assert!(err("t,theta\n").contains("no data rows"));
        assert!(err("0.1,0.2\n0.2,0.3\n").contains("header"));
        assert!(err("t,theta\n0,1\n0.1\n").contains("line 3: 1 fields"));
        assert!(err("t,theta\n0,1\n0.1,abc\n").contains("line 3, column 'theta': 'abc'"));
        assert!(err("t,theta\n0,NaN\n").contains("not a finite number"));
    }
}
