//! `pendulab report`: the lab report.
//!
//! Runs every book example (in parallel), renders and writes their figures under
//! `DIR/figures/<id>/`, the notebook page `DIR/index.html`, the JSON lines of every example
//! (`DIR/results.jsonl`, the format of `pendulab book run --json`) and the README table of
//! examples with their status (`DIR/status.md`, as `pendulab book list --markdown` prints it).

use crate::book::{DataFiles, OutLayout, json_line, prepare_out_dir, run_examples};
use anyhow::{Context, Result, bail};
use pendulab_book::Example;
use pendulab_book::report::{ReportOptions, Status, Summary, html, markdown_table};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Instant, SystemTime, UNIX_EPOCH};

/// Arguments of `pendulab report`.
#[derive(Debug, clap::Args)]
pub struct ReportArgs {
    /// Output directory (created if needed): index.html, figures/, results.jsonl (default
    /// with --lab: LAB/report).
    #[arg(long, required_unless_present = "lab")]
    pub out: Option<PathBuf>,
    /// The notebook of a lab directory instead of the book's (docs/lab.md): its plant and how
    /// it was identified, its designs, their simulations and runs side by side.
    #[arg(long, conflicts_with_all = ["data", "only"])]
    pub lab: Option<PathBuf>,
    /// Measured data for an example that needs it, as ID=FILE.csv (repeatable).
    #[arg(long, value_name = "ID=FILE")]
    pub data: Vec<String>,
    /// Only these examples (repeatable); default: every example.
    #[arg(long, value_name = "ID")]
    pub only: Vec<String>,
    /// The browser lab's built site (the folder `tools/build-web SITE` writes, docs/web.md):
    /// copied into DIR/lab/ and linked under the report's title, so the folder stays whole.
    #[arg(long, value_name = "SITE", conflicts_with = "lab")]
    pub web_lab: Option<PathBuf>,
}

/// What writing a report produced.
#[derive(Debug)]
pub struct ReportRun {
    /// The page.
    pub index: PathBuf,
    /// Counts per status.
    pub summary: Summary,
    /// Ids of the failing examples.
    pub failing: Vec<&'static str>,
    /// Wall-clock seconds of running the examples and writing everything.
    pub seconds: f64,
}

/// Runs the examples and writes the report into `out`.
///
/// # Errors
/// Unknown ids in `only` or `data`, unreadable or malformed data files, an output directory
/// that cannot be created or written. Failing examples are not errors here: they are in the
/// report and in [`ReportRun::failing`].
///
/// With `web_lab`, the browser lab's site folder (it must hold `index.html`) is copied into
/// `out/lab/` (replacing an earlier copy) and linked from the page; a missing folder is an error
/// before any example runs.
pub fn generate(
    out: &Path,
    data: &[String],
    only: &[String],
    web_lab: Option<&Path>,
    progress: bool,
) -> Result<ReportRun> {
    let examples = if only.is_empty() {
        pendulab_book::registry()
    } else {
        crate::book::select(only, false)?
    };
    let data = DataFiles::parse(data, &examples, false)?;
    if let Some(site) = web_lab
        && !site.join("index.html").is_file()
    {
        bail!(
            "--web-lab {}: no index.html there (build the browser lab with tools/build-web {})",
            site.display(),
            site.display()
        );
    }
    write_report(&examples, out, &data, web_lab, progress)
}

/// Copies the files and folders under `from` into `to` (created), replacing what `to` held.
fn copy_site(from: &Path, to: &Path) -> Result<()> {
    if to.exists() {
        std::fs::remove_dir_all(to)
            .with_context(|| format!("cannot remove the old copy {}", to.display()))?;
    }
    std::fs::create_dir_all(to).with_context(|| format!("cannot create {}", to.display()))?;
    for entry in
        std::fs::read_dir(from).with_context(|| format!("cannot read {}", from.display()))?
    {
        let entry = entry.with_context(|| format!("cannot read {}", from.display()))?;
        let (src, dst) = (entry.path(), to.join(entry.file_name()));
        if entry.file_type()?.is_dir() {
            copy_site(&src, &dst)?;
        } else {
            std::fs::copy(&src, &dst)
                .with_context(|| format!("cannot copy {} to {}", src.display(), dst.display()))?;
        }
    }
    Ok(())
}

/// Runs `examples` and writes the report into `out` (see [`generate`]).
fn write_report(
    examples: &[Example],
    out: &Path,
    data: &DataFiles,
    web_lab: Option<&Path>,
    progress: bool,
) -> Result<ReportRun> {
    let start = Instant::now();
    prepare_out_dir(out)?;
    let mut links = Vec::new();
    if let Some(site) = web_lab {
        copy_site(site, &out.join("lab"))?;
        links.push((
            "The browser lab: both rigs live, designed and balanced in this browser".to_string(),
            "lab/index.html".to_string(),
        ));
    }
    let figures = out.join("figures");
    // What an earlier report wrote for these examples goes: a figure since renamed or dropped
    // would otherwise stay in the folder.
    for e in examples {
        let dir = figures.join(e.id);
        if dir.exists() {
            std::fs::remove_dir_all(&dir)
                .with_context(|| format!("cannot remove the old figures in {}", dir.display()))?;
        }
    }
    let mut entries = run_examples(examples, OutLayout::PerExample(&figures), data, progress);
    // Paths relative to the report directory, in the page and in results.jsonl, so the
    // directory can be moved whole.
    let mut animations = BTreeMap::new();
    for e in &mut entries {
        for f in &mut e.files {
            if let Ok(rel) = f.strip_prefix(out) {
                *f = rel.to_path_buf();
            }
        }
        if e.result.is_ok() {
            animations.extend(animation_markup(out, &e.files)?);
        }
    }
    let summary = Summary::of(&entries);
    let run_seconds = start.elapsed().as_secs_f64();
    let options = ReportOptions {
        base_dir: PathBuf::new(),
        animations,
        links,
        subtitle: Some(format!(
            "pendulab {} · {} examples run in {:.1} s · written {}",
            env!("CARGO_PKG_VERSION"),
            summary.total,
            run_seconds,
            utc_now()
        )),
        ..ReportOptions::default()
    };
    let page = html(&entries, &options);
    let index = out.join("index.html");
    std::fs::write(&index, page).with_context(|| format!("cannot write {}", index.display()))?;
    let mut lines = String::new();
    for e in &entries {
        lines.push_str(&json_line(e)?);
        lines.push('\n');
    }
    let results = out.join("results.jsonl");
    std::fs::write(&results, lines)
        .with_context(|| format!("cannot write {}", results.display()))?;
    let table = out.join("status.md");
    std::fs::write(&table, markdown_table(&entries))
        .with_context(|| format!("cannot write {}", table.display()))?;
    let failing = entries
        .iter()
        .filter(|e| e.status() == Status::Failing)
        .map(|e| e.example.id)
        .collect();
    Ok(ReportRun {
        index,
        summary,
        failing,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The animated SVGs among an example's files (an SVG beside a GIF of the same stem, as
/// [`pendulab_book::Graphic::render`] writes an animation), read back for the page's players,
/// keyed by their path relative to `out`.
fn animation_markup(out: &Path, files: &[PathBuf]) -> Result<Vec<(PathBuf, String)>> {
    let mut found = Vec::new();
    for f in files {
        let is_svg = f.extension().is_some_and(|x| x == "svg");
        if is_svg && files.contains(&f.with_extension("gif")) {
            let path = out.join(f);
            let text = std::fs::read_to_string(&path)
                .with_context(|| format!("cannot read {} back", path.display()))?;
            found.push((f.clone(), text));
        }
    }
    Ok(found)
}

/// Runs `pendulab report`.
pub fn run(args: &ReportArgs) -> Result<()> {
    if let Some(lab) = &args.lab {
        let out = args.out.clone().unwrap_or_else(|| lab.join("report"));
        let index = write_lab_notebook(lab, &out)?;
        println!("wrote {}", index.display());
        return Ok(());
    }
    let Some(out) = &args.out else {
        bail!("--out DIR is required (or --lab DIR)");
    };
    let r = generate(out, &args.data, &args.only, args.web_lab.as_deref(), true)?;
    outcome(&r)
}

/// Prints the summary line; an error when an example failed.
fn outcome(r: &ReportRun) -> Result<()> {
    let s = &r.summary;
    println!(
        "wrote {} in {:.1} s: {} examples — {} reproduced, {} agree where compared, {} run, \
         {} differ from the book, {} need data, {} failing; {} figures",
        r.index.display(),
        r.seconds,
        s.total,
        s.reproduced,
        s.partly_compared,
        s.runs,
        s.differs,
        s.needs_data,
        s.failing,
        s.figures
    );
    if !r.failing.is_empty() {
        bail!(
            "{} of {} examples failed ({}); their errors are in the report",
            r.failing.len(),
            s.total,
            r.failing.join(", ")
        );
    }
    Ok(())
}

/// The current time as `YYYY-MM-DD HH:MM UTC`.
fn utc_now() -> String {
    let secs = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    let (y, m, d) = civil_from_days(days);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02} UTC",
        rem / 3600,
        rem % 3600 / 60
    )
}

/// Proleptic Gregorian date of a day count since 1970-01-01 (H. Hinnant, "chrono-compatible
/// low-level date algorithms", `civil_from_days`).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

/// The lab notebook's page (`pendulab report --lab DIR`, `docs/lab.md`): `OUT/index.html`
/// with the lab's plant (each parameter beside the book's value, its standard error when
/// identified, and the provenance: file, SHA-256, window, method), then one section per
/// design (`DIR/designs/*.toml`: its file as written, with the model it was designed on in
/// its header) with its simulation's figure (`DIR/runs/<design>/run.svg`, from `pendulab
/// simulate`) beside the figures of its rig runs (`DIR/logs/<design>*.svg`, from `pendulab
/// plot`). The figures are copied under `OUT/figures/` and linked by relative paths, so the
/// directory can be moved whole. Self-contained: inline style, no scripts.
///
/// # Errors
/// The lab file's errors; a design or figure that cannot be read; the page that cannot be
/// written.
fn write_lab_notebook(lab: &Path, out: &Path) -> Result<PathBuf> {
    use pendulab_book::report::format::{escape, number, number_sig};
    use pendulab_book::report::{FIGHINT, STYLE, figscroll_open};
    use pendulab_plants::spec::{PlantParameters, Provenance};
    use std::fmt::Write as _;
    let plant = crate::lab::load(lab)?;
    let figs = out.join("figures");
    std::fs::create_dir_all(&figs).with_context(|| format!("cannot create {}", figs.display()))?;
    let mut s = String::new();
    let title = format!("pendulab lab notebook: {}", lab.display());
    let _ = write!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{t}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n<header>\n<h1>{t}</h1>\n\
         </header>\n<main>\n",
        t = escape(&title)
    );
    let _ = writeln!(
        s,
        "<h2 id=\"plant\">The plant</h2>\n<p>The {} pendulum: {}.</p>",
        plant.kind().name(),
        escape(&crate::lab::provenance_label(plant.provenance()))
    );
    let errors = match plant.provenance() {
        Provenance::Identified {
            standard_errors, ..
        } => standard_errors.clone(),
        _ => Default::default(),
    };
    let book = PlantParameters::book(plant.kind()).entries();
    s.push_str(
        "<div class=\"scroll\" tabindex=\"0\" role=\"region\" aria-label=\"parameters\">\
         <table class=\"values params\"><tr><th>parameter</th><th>value</th>\
         <th>standard error</th><th>book</th><th>value / book</th></tr>\n",
    );
    for ((k, v), (_, b)) in plant.parameters().entries().into_iter().zip(book) {
        let se = errors
            .get(&k)
            .map_or("—".to_string(), |e| number_sig(*e, 3));
        let _ = writeln!(
            s,
            "<tr><td>{}</td><td>{}</td><td>{se}</td><td>{}</td><td>{:.4}</td></tr>",
            escape(&k),
            number(v),
            number(b),
            v / b
        );
    }
    s.push_str("</table></div>\n");
    if let Provenance::Identified {
        file,
        sha256,
        window,
        method,
        ..
    } = plant.provenance()
    {
        let _ = writeln!(
            s,
            "<p>Identified from <code>{}</code> (SHA-256 <code>{}</code>), t = {}–{} s, by {}.</p>",
            escape(file),
            escape(sha256),
            window[0],
            window[1],
            escape(method.as_deref().unwrap_or("an unnamed method"))
        );
    }
    let mut designs: Vec<PathBuf> = match std::fs::read_dir(lab.join("designs")) {
        Ok(rd) => rd
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .collect(),
        Err(_) => Vec::new(),
    };
    designs.sort();
    s.push_str("<h2 id=\"designs\">Designs, simulations and runs</h2>\n");
    if designs.is_empty() {
        s.push_str("<p>No design yet (<code>pendulab design … --lab DIR</code>).</p>\n");
    }
    let copy = |src: &Path, name: String| -> Result<String> {
        std::fs::copy(src, figs.join(&name))
            .with_context(|| format!("cannot copy {} into the report", src.display()))?;
        Ok(format!("figures/{name}"))
    };
    for d in &designs {
        let stem = d
            .file_stem()
            .map(|x| x.to_string_lossy().into_owned())
            .unwrap_or_default();
        let text =
            std::fs::read_to_string(d).with_context(|| format!("cannot read {}", d.display()))?;
        let _ = writeln!(
            s,
            "<h3 id=\"{0}\">{0}</h3>\n<pre class=\"file\">{1}</pre>\n<div class=\"figures\">",
            escape(&stem),
            escape(&text)
        );
        let sim = lab.join("runs").join(&stem).join("run.svg");
        if sim.exists() {
            let rel = copy(&sim, format!("{stem}-simulation.svg"))?;
            let _ = writeln!(
                s,
                "<figure>{}<img src=\"{rel}\" alt=\"simulation\"></div><figcaption>simulation \
                 (pendulab simulate){FIGHINT}</figcaption></figure>",
                figscroll_open("simulation")
            );
        }
        let mut runs: Vec<PathBuf> = match std::fs::read_dir(lab.join("logs")) {
            Ok(rd) => rd
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.extension().is_some_and(|x| x == "svg")
                        && p.file_stem()
                            .is_some_and(|n| n.to_string_lossy().starts_with(stem.as_str()))
                })
                .collect(),
            Err(_) => Vec::new(),
        };
        runs.sort();
        for r in &runs {
            let name = r
                .file_name()
                .map(|x| x.to_string_lossy().into_owned())
                .unwrap_or_default();
            let rel = copy(r, format!("run-{name}"))?;
            let _ = writeln!(
                s,
                "<figure>{}<img src=\"{rel}\" alt=\"run\"></div><figcaption>rig run {} (pendulab \
                 plot){FIGHINT}</figcaption></figure>",
                figscroll_open("rig run"),
                escape(&name)
            );
        }
        if !sim.exists() && runs.is_empty() {
            s.push_str("<p>Not simulated or run yet.</p>\n");
        }
        s.push_str("</div>\n");
    }
    crate::report_studies::write_studies(lab, &figs, &mut s)?;
    s.push_str("</main>\n</body>\n</html>\n");
    let index = out.join("index.html");
    crate::lab::write_whole(&index, s.as_bytes())?;
    Ok(index)
}

#[cfg(test)]
mod tests {
    use super::*;
    use pendulab_book::{BookError, Cause, ExampleOutput, RunContext, Value};

    fn draws(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
        let mut o = ExampleOutput::default();
        o.value("x", Value::Number(1.5));
        o.reference("x", Value::Number(1.5), "book", 0.0);
        assert!(ctx.figures, "the report asks for figures");
        let mut ax = pendulab_plot::Axes::new();
        ax.plot(&[0.0, 1.0], &[0.0, 1.5]);
        o.figure("fig", pendulab_plot::Figure::new(ax));
        Ok(o)
    }
    fn fails(_: &RunContext) -> Result<ExampleOutput, BookError> {
        Err(BookError::Computation {
            id: "fails".into(),
            source: Box::new(Cause::Check("Riccati <solver> diverged".into())),
        })
    }
    fn panics(_: &RunContext) -> Result<ExampleOutput, BookError> {
        panic!("boom")
    }
    fn needs(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
        match &ctx.data_csv {
            Some(text) => {
                let mut o = ExampleOutput::default();
                o.value("rows", Value::Number((text.lines().count() - 1) as f64));
                Ok(o)
            }
            None => Err(BookError::NeedsData {
                id: "needs".into(),
                what: "columns t,theta".into(),
            }),
        }
    }
    fn takes_none(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
        match ctx.data_csv {
            None => Ok(ExampleOutput::default()),
            Some(_) => Err(BookError::Computation {
                id: "takes_none".into(),
                source: Box::new(Cause::Check("was given data".into())),
            }),
        }
    }
    fn example(
        id: &'static str,
        run: fn(&RunContext) -> Result<ExampleOutput, BookError>,
    ) -> Example {
        Example {
            id,
            title: "test",
            section: "Part 1 §4.1",
            parameters: "none",
            needs_data: (id == "needs").then_some("columns t,theta"),
            run,
        }
    }

    #[test]
    fn failing_and_panicking_examples_are_reported_after_everything_is_written() {
        let out = std::env::temp_dir().join(format!("pendulab-report-unit-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&out);
        let examples = [
            example("draws", draws),
            example("fails", fails),
            example("panics", panics),
            example("needs", needs),
        ];
        let r = write_report(&examples, &out, &DataFiles::default(), None, false).unwrap();
        let page = std::fs::read_to_string(out.join("index.html")).unwrap();
        let results = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
        let status = std::fs::read_to_string(out.join("status.md")).unwrap();
        let _ = std::fs::remove_dir_all(&out);
        assert_eq!(r.failing, vec!["fails", "panics"]);
        assert_eq!(
            (
                r.summary.reproduced,
                r.summary.needs_data,
                r.summary.failing
            ),
            (1, 1, 2)
        );
        // The figure went to figures/<id>/ and is linked relative to the page.
        assert!(page.contains("<img src=\"figures/draws/fig.svg\""));
        assert!(page.contains("Riccati &lt;solver&gt; diverged"));
        assert!(page.contains("example &#39;panics&#39;: panicked: boom"));
        assert_eq!(results.lines().count(), 4);
        assert!(
            status.contains("| `panics` | Part 1 §4.1 | test | failing |"),
            "{status}"
        );
        assert!(
            results
                .lines()
                .nth(3)
                .unwrap()
                .contains("\"needs_data\":\"columns t,theta\"")
        );
        // The command fails, naming the failing examples.
        let err = outcome(&r).unwrap_err().to_string();
        assert!(
            err.contains("2 of 4 examples failed (fails, panics)"),
            "{err}"
        );
    }

    #[test]
    fn data_reaches_only_the_example_that_takes_it() {
        let out = std::env::temp_dir().join(format!("pendulab-report-data-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&out);
        let examples = [example("needs", needs), example("takes_none", takes_none)];
        let data = DataFiles::for_tests("needs", "t,theta\n0,1\n0.001,1.1\n");
        let r = write_report(&examples, &out, &data, None, false).unwrap();
        let results = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
        let _ = std::fs::remove_dir_all(&out);
        assert_eq!(r.summary.runs, 2, "{results}");
        // Two data rows under the header.
        assert!(results.contains("\"rows\":2.0"), "{results}");
        assert!(outcome(&r).is_ok());
    }

    #[test]
    fn civil_dates_match_known_days() {
        // Day numbers from the Unix epoch: 0 = 1970-01-01; 11016 = 2000-02-29 (leap day of a
        // year divisible by 400); 20784 = 2026-11-27 (date(1) -d @1795737600).
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(20_784), (2026, 11, 27));
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
    }
}
