//! The studies of a lab directory in `pendulab report --lab DIR` (`docs/studies.md`).
//!
//! A study saved by the Python package (`StudyResult.save(DIR)`, `pendulab.study`) is a
//! folder `DIR/studies/<name>/` holding:
//!
//! - `summary.json`: one JSON object with `kind` (`"roa"`, the region of attraction of a
//!   grid of initial states, or `"monte_carlo"`, runs over drawn plant parameters), `stats`
//!   (an object of named numbers: `n`, `caught`, `caught_fraction`, and for Monte Carlo the
//!   settling time's and peak input's statistics in s and V), `spec` (the study's
//!   specification, the object `result.study.spec` that reproduces it), `key` (its hash),
//!   `pendulab_version`, and `figure` (the figure's file name in the folder);
//! - the figure (`figure.svg`: the region-of-attraction map or the Monte Carlo histogram of
//!   `pendulab-plot`).
//!
//! [`write_studies`] adds one section per study folder, in name order: the figure (copied
//! into the report's `figures/`), the statistics as a table and the specification. A folder
//! without `summary.json` is skipped; a `summary.json` that is not a JSON object with a
//! string `kind` and an object `stats` is an error naming the file.

use anyhow::{Context, Result, bail};
use pendulab_book::report::format::escape;
use pendulab_book::report::{FIGHINT, figscroll_open};
use serde_json::Value;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One study folder, read.
struct Study {
    name: String,
    kind: String,
    stats: Vec<(String, String)>,
    spec: Option<String>,
    version: Option<String>,
    figure: Option<PathBuf>,
}

/// A statistic's value as shown: integers as integers, other numbers with 6 significant
/// digits, `null` (a statistic with no value, e.g. no run settled) as a dash.
fn show(v: &Value) -> String {
    match v {
        Value::Number(n) => match (n.as_i64(), n.as_f64()) {
            (Some(i), _) => i.to_string(),
            (None, Some(x)) => format!("{x:.6}"),
            _ => n.to_string(),
        },
        Value::Null => "—".into(),
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// Reads `dir/summary.json` (`None` when the folder has none).
fn read_study(dir: &Path) -> Result<Option<Study>> {
    let path = dir.join("summary.json");
    if !path.exists() {
        return Ok(None);
    }
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let v: Value = serde_json::from_str(&text)
        .with_context(|| format!("{}: not valid JSON", path.display()))?;
    let Some(obj) = v.as_object() else {
        bail!("{}: expected a JSON object", path.display());
    };
    let Some(kind) = obj.get("kind").and_then(Value::as_str) else {
        bail!("{}: key kind: expected a string", path.display());
    };
    let Some(stats) = obj.get("stats").and_then(Value::as_object) else {
        bail!("{}: key stats: expected an object", path.display());
    };
    let figure = match obj.get("figure") {
        None | Some(Value::Null) => None,
        Some(Value::String(f)) => {
            // Only a file of the folder itself.
            if Path::new(f).components().count() != 1 || f.starts_with('.') {
                bail!(
                    "{}: key figure: {f:?} is not a file name of the study folder",
                    path.display()
                );
            }
            Some(dir.join(f)).filter(|p| p.exists())
        }
        Some(_) => bail!("{}: key figure: expected a file name", path.display()),
    };
    let name = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    Ok(Some(Study {
        name,
        kind: kind.to_string(),
        stats: stats.iter().map(|(k, v)| (k.clone(), show(v))).collect(),
        spec: obj
            .get("spec")
            .map(|s| serde_json::to_string_pretty(s).unwrap_or_else(|_| s.to_string())),
        version: obj
            .get("pendulab_version")
            .and_then(Value::as_str)
            .map(str::to_string),
        figure,
    }))
}

/// What a study's kind is called on the page.
fn kind_label(kind: &str) -> &str {
    match kind {
        "roa" => "region of attraction",
        "monte_carlo" => "Monte Carlo",
        other => other,
    }
}

/// Appends the section "Studies" for every folder of `lab/studies/` to the page `s`, copying
/// each study's figure into `figs` as `study-<name>.<ext>` (see the module documentation
/// for the folder's format). Nothing is appended when the lab has no `studies/` folder.
///
/// # Errors
/// An unreadable folder or `summary.json`, a malformed `summary.json` (named), a figure that
/// cannot be copied.
pub(crate) fn write_studies(lab: &Path, figs: &Path, s: &mut String) -> Result<()> {
    let root = lab.join("studies");
    let Ok(rd) = std::fs::read_dir(&root) else {
        return Ok(());
    };
    let mut dirs: Vec<PathBuf> = rd
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    let mut studies = Vec::new();
    for d in &dirs {
        if let Some(st) = read_study(d)? {
            studies.push(st);
        }
    }
    if studies.is_empty() {
        return Ok(());
    }
    s.push_str("<h2 id=\"studies\">Studies</h2>\n");
    for st in &studies {
        let _ = writeln!(
            s,
            "<h3 id=\"study-{0}\">{0}</h3>\n<p>{1} study{2}.</p>\n<div class=\"figures\">",
            escape(&st.name),
            escape(kind_label(&st.kind)),
            st.version
                .as_ref()
                .map_or(String::new(), |v| format!(" (pendulab {})", escape(v)))
        );
        if let Some(f) = &st.figure {
            let ext = f
                .extension()
                .map_or("svg".into(), |e| e.to_string_lossy().into_owned());
            let name = format!("study-{}.{ext}", st.name);
            std::fs::copy(f, figs.join(&name))
                .with_context(|| format!("cannot copy {} into the report", f.display()))?;
            let _ = writeln!(
                s,
                "<figure>{2}<img src=\"figures/{0}\" alt=\"{1}\"></div><figcaption>{1} \
                 (pendulab-plot){FIGHINT}</figcaption></figure>",
                escape(&name),
                escape(kind_label(&st.kind)),
                figscroll_open(&escape(kind_label(&st.kind)))
            );
        }
        let _ = writeln!(
            s,
            "<div class=\"scroll\" tabindex=\"0\" role=\"region\" aria-label=\"statistics of {}\">\
             <table class=\"values\"><tr><th>statistic</th><th>value</th></tr>",
            escape(&st.name)
        );
        for (k, v) in &st.stats {
            let _ = writeln!(s, "<tr><td>{}</td><td>{}</td></tr>", escape(k), escape(v));
        }
        s.push_str("</table></div>\n</div>\n");
        if let Some(spec) = &st.spec {
            let _ = writeln!(
                s,
                "<details><summary>specification</summary><pre class=\"file\">{}</pre></details>",
                escape(spec)
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!(
            "pendulab-report-studies-{tag}-{}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn a_hand_written_study_folder_is_shown_with_its_figure_and_statistics() {
        let lab = scratch("ok");
        let study = lab.join("studies").join("mc-book-k");
        std::fs::create_dir_all(&study).unwrap();
        let figs = lab.join("out-figures");
        std::fs::create_dir_all(&figs).unwrap();
        std::fs::write(
            study.join("figure.svg"),
            "<svg xmlns=\"http://www.w3.org/2000/svg\"/>",
        )
        .unwrap();
        std::fs::write(
            study.join("summary.json"),
            r#"{"kind": "monte_carlo", "figure": "figure.svg", "pendulab_version": "0.1.0",
                "key": "abc", "spec": {"n": 3, "seed": 1},
                "stats": {"n": 3, "caught": 2, "caught_fraction": 0.6666666666666666,
                          "settling_time_mean": null}}"#,
        )
        .unwrap();
        // A folder without summary.json is not a study.
        std::fs::create_dir_all(lab.join("studies").join("scratch")).unwrap();
        let mut s = String::new();
        write_studies(&lab, &figs, &mut s).unwrap();
        let copied = figs.join("study-mc-book-k.svg").exists();
        let _ = std::fs::remove_dir_all(&lab);
        assert!(copied);
        assert!(s.contains("<h2 id=\"studies\">Studies</h2>"));
        assert!(s.contains("<h3 id=\"study-mc-book-k\">mc-book-k</h3>"));
        assert!(s.contains("Monte Carlo study (pendulab 0.1.0)"));
        assert!(s.contains("<img src=\"figures/study-mc-book-k.svg\""));
        assert!(s.contains("<tr><td>caught</td><td>2</td></tr>"));
        assert!(s.contains("<tr><td>caught_fraction</td><td>0.666667</td></tr>"));
        assert!(s.contains("<tr><td>settling_time_mean</td><td>—</td></tr>"));
        assert!(s.contains("&quot;seed&quot;: 1") || s.contains("\"seed\": 1"));
        assert!(!s.contains("scratch"));
    }

    #[test]
    fn no_studies_folder_adds_nothing_and_a_malformed_summary_is_named() {
        let lab = scratch("bad");
        let figs = lab.join("f");
        std::fs::create_dir_all(&figs).unwrap();
        let mut s = String::new();
        write_studies(&lab, &figs, &mut s).unwrap();
        assert!(s.is_empty());
        let study = lab.join("studies").join("broken");
        std::fs::create_dir_all(&study).unwrap();
        std::fs::write(
            study.join("summary.json"),
            r#"{"kind": "roa", "stats": [1, 2]}"#,
        )
        .unwrap();
        let e1 = write_studies(&lab, &figs, &mut s).unwrap_err().to_string();
        std::fs::write(
            study.join("summary.json"),
            r#"{"kind": "roa", "stats": {}, "figure": "../../x.svg"}"#,
        )
        .unwrap();
        let e2 = write_studies(&lab, &figs, &mut s).unwrap_err().to_string();
        let _ = std::fs::remove_dir_all(&lab);
        assert!(
            e1.contains("summary.json") && e1.contains("key stats"),
            "{e1}"
        );
        assert!(e2.contains("key figure"), "{e2}");
    }
}
