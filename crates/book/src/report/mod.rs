//! The lab report: results of book examples as one HTML notebook and as a Markdown table.
//!
//! This module only turns results into text; it runs nothing and touches no file. The caller
//! (the `pendulab report` command) runs the examples, renders and writes their figures under an
//! output directory and passes the results here with the files written ([`Entry::files`]) and
//! that directory, so figure links can be made relative to the page:
//!
//! - [`Entry`] — one example with its result, run time and figure files;
//! - [`Status`] — reproduced / runs / differs / needs data / failing, from a result;
//! - [`html`] — the self-contained page (inline style, no external resources, a script only
//!   for the animation players; figures are linked relative to [`ReportOptions::base_dir`]);
//! - [`markdown_table`] — the README table of examples with their status;
//! - [`Summary`] — counts per status;
//! - [`format`](mod@format) — number and value formatting shared by the page and the command line.

pub mod format;
mod html;

pub use html::{FIGHINT, STYLE, figscroll_open, html};

use crate::error::BookError;
use crate::output::ExampleOutput;
use crate::registry::Example;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// One example's result, as the report shows it.
#[derive(Debug)]
pub struct Entry {
    /// The example.
    pub example: Example,
    /// What running it gave.
    pub result: Result<ExampleOutput, BookError>,
    /// Wall-clock run time in seconds (`None` when not measured).
    pub seconds: Option<f64>,
    /// The files the front end wrote for the example's figures ([`crate::Graphic::render`]),
    /// in the order written; the page links them relative to [`ReportOptions::base_dir`].
    pub files: Vec<PathBuf>,
}

impl Entry {
    /// The entry's status.
    pub fn status(&self) -> Status {
        Status::of(&self.result)
    }
}

/// What became of one example.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Status {
    /// It ran, compares with at least one printed value, reproduces every one, and every
    /// number the book prints or the M-file displays is compared
    /// ([`ExampleOutput::uncompared`] is empty).
    Reproduced,
    /// It ran and reproduces every value it compares, but some number the book prints or the
    /// M-file displays is not compared ([`ExampleOutput::uncompared`], each with the reason).
    PartlyCompared,
    /// It ran; there is no printed value to compare with.
    Runs,
    /// It ran, but at least one printed value is not reproduced within its tolerance.
    Differs,
    /// It needs measured data that was not given ([`BookError::NeedsData`]).
    NeedsData,
    /// It stopped with an error.
    Failing,
}

impl Status {
    /// Every status, in the order the report lists them.
    pub const ALL: [Status; 6] = [
        Status::Reproduced,
        Status::PartlyCompared,
        Status::Runs,
        Status::Differs,
        Status::NeedsData,
        Status::Failing,
    ];

    /// The status of a result.
    pub fn of(result: &Result<ExampleOutput, BookError>) -> Status {
        match result {
            Err(BookError::NeedsData { .. }) => Status::NeedsData,
            Err(_) => Status::Failing,
            Ok(out) => {
                let comparisons = out.comparisons();
                if comparisons.is_empty() {
                    Status::Runs
                } else if comparisons.iter().all(|c| c.reproduced) {
                    if out.uncompared.is_empty() {
                        Status::Reproduced
                    } else {
                        Status::PartlyCompared
                    }
                } else {
                    Status::Differs
                }
            }
        }
    }

    /// Its label in the report and the README table.
    pub fn label(self) -> &'static str {
        match self {
            Status::Reproduced => "reproduced",
            Status::PartlyCompared => "agrees where compared",
            Status::Runs => "runs",
            Status::Differs => "differs from book",
            Status::NeedsData => "needs data",
            Status::Failing => "failing",
        }
    }

    /// CSS class of its badge.
    fn class(self) -> &'static str {
        match self {
            Status::Reproduced => "st-ok",
            Status::PartlyCompared => "st-part",
            Status::Runs => "st-runs",
            Status::Differs => "st-differs",
            Status::NeedsData => "st-data",
            Status::Failing => "st-fail",
        }
    }
}

/// Counts of examples per status.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Summary {
    /// All examples.
    pub total: usize,
    /// [`Status::Reproduced`].
    pub reproduced: usize,
    /// [`Status::PartlyCompared`].
    pub partly_compared: usize,
    /// [`Status::Runs`].
    pub runs: usize,
    /// [`Status::Differs`].
    pub differs: usize,
    /// [`Status::NeedsData`].
    pub needs_data: usize,
    /// [`Status::Failing`].
    pub failing: usize,
    /// Figure files written, over all examples ([`Entry::files`]).
    pub figures: usize,
}

impl Summary {
    /// Counts the entries.
    pub fn of(entries: &[Entry]) -> Summary {
        let mut s = Summary {
            total: entries.len(),
            ..Summary::default()
        };
        for e in entries {
            *s.count_mut(e.status()) += 1;
            if e.result.is_ok() {
                s.figures += e.files.len();
            }
        }
        s
    }

    /// The count of one status.
    pub fn count(&self, status: Status) -> usize {
        match status {
            Status::Reproduced => self.reproduced,
            Status::PartlyCompared => self.partly_compared,
            Status::Runs => self.runs,
            Status::Differs => self.differs,
            Status::NeedsData => self.needs_data,
            Status::Failing => self.failing,
        }
    }

    fn count_mut(&mut self, status: Status) -> &mut usize {
        match status {
            Status::Reproduced => &mut self.reproduced,
            Status::PartlyCompared => &mut self.partly_compared,
            Status::Runs => &mut self.runs,
            Status::Differs => &mut self.differs,
            Status::NeedsData => &mut self.needs_data,
            Status::Failing => &mut self.failing,
        }
    }
}

/// The widest figure the page shows at its own size, in CSS pixels, on a screen wide enough
/// (≥ 1180 px): the page's column (1180 px) less its padding (2 × 24), the example card's
/// (2 × 18 + 2 × 1 border) and the figure frame's (2 × 8 + 2 × 1). A figure no wider keeps its
/// text at the size it was drawn with ([`pendulab_plot::MIN_FONT`] = 12 px = 9 pt at least);
/// a wider one, and every figure on a narrower screen, is scaled down to fit.
pub const FIGURE_WIDTH: f64 = 1180.0 - 2.0 * 24.0 - 2.0 * (18.0 + 1.0) - 2.0 * (8.0 + 1.0);

/// How the page is put together.
#[derive(Debug, Clone)]
pub struct ReportOptions {
    /// Directory the page is written to; figure paths under it are linked relative to it.
    /// Figure paths outside it are linked as given.
    pub base_dir: PathBuf,
    /// Page title. Default: "pendulab lab notebook".
    pub title: String,
    /// A line under the title (e.g. the pendulab version and the total run time); escaped.
    pub subtitle: Option<String>,
    /// Markup of animated SVG files ([`crate::GraphicKind::Animation`]), keyed by their path
    /// as in [`Entry::files`]: these are inlined into the page with a pause/play button and a
    /// time scrubber. An animated SVG not in the map is shown as an image (it loops, without
    /// controls). The markup is our own renderer's and is inserted unescaped.
    pub animations: BTreeMap<PathBuf, String>,
    /// Links shown under the title as `(label, href)`, e.g. the browser lab copied beside the
    /// page (`pendulab report --web-lab`, docs/web.md). The href is written as given (escaped):
    /// keep it relative so the folder can be moved.
    pub links: Vec<(String, String)>,
}

impl Default for ReportOptions {
    fn default() -> Self {
        ReportOptions {
            base_dir: PathBuf::from("."),
            title: "pendulab lab notebook".into(),
            subtitle: None,
            animations: BTreeMap::new(),
            links: Vec::new(),
        }
    }
}

/// A chapter of the book: the examples whose `section` names it, in registry order.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Chapter {
    /// Anchor and grouping key, e.g. `part1-ch4`.
    pub key: String,
    /// Heading, e.g. "Part 1 ch. 4 — State space and stability".
    pub heading: String,
    /// Indices into the entries.
    pub members: Vec<usize>,
}

/// Titles of the book's chapters, in English.
fn chapter_title(part: u32, chapter: u32) -> Option<&'static str> {
    Some(match (part, chapter) {
        (1, 2) => "PID control of the cart position",
        (1, 3) => "Modelling and identification",
        (1, 4) => "State space and stability",
        (1, 5) => "Controllability, pole placement, LQR",
        (1, 6) => "Internal model principle and servo",
        (1, 7) => "Observability and observers",
        (1, 8) => "Discretisation",
        (2, 1) => "LMI and control",
        (2, 2) => "Digital control",
        (2, 3) => "Nonlinear control",
        _ => return None,
    })
}

/// Heading of the IP Toolbox samples (sections naming the toolbox).
const TOOLBOX_HEADING: &str = "IP Toolbox samples (quantised plant, filtered derivatives, 1 ms)";

/// The first run of ASCII digits in `s` as a number.
fn leading_number(s: &str) -> Option<u32> {
    let digits: String = s
        .trim_start()
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    digits.parse().ok()
}

/// Part and chapter named by a `section` string such as "Part 1 §4.1" or "Part 2 ch. 3",
/// or `None` for anything else (then the section string is its own group).
pub(crate) fn part_and_chapter(section: &str) -> Option<(u32, u32)> {
    let lower = section.to_lowercase();
    let after_part = &lower[lower.find("part")? + 4..];
    let part = leading_number(after_part)?;
    let chapter = if let Some(i) = after_part.find('§') {
        leading_number(&after_part[i + '§'.len_utf8()..])?
    } else {
        let i = after_part.find("ch")?;
        let rest =
            after_part[i..].trim_start_matches(|c: char| c.is_ascii_alphabetic() || c == '.');
        leading_number(rest)?
    };
    Some((part, chapter))
}

/// Groups entries by chapter, chapters in order of first appearance.
pub(crate) fn chapters(entries: &[Entry]) -> Vec<Chapter> {
    let mut out: Vec<Chapter> = Vec::new();
    for (i, e) in entries.iter().enumerate() {
        let section = e.example.section;
        let (key, heading) = match part_and_chapter(section) {
            None if section.to_lowercase().contains("toolbox") => {
                ("toolbox".to_string(), TOOLBOX_HEADING.to_string())
            }
            Some((p, c)) => (
                format!("part{p}-ch{c}"),
                match chapter_title(p, c) {
                    Some(t) => format!("Part {p} ch. {c} — {t}"),
                    None => format!("Part {p} ch. {c}"),
                },
            ),
            None => {
                let slug: String = section
                    .chars()
                    .map(|c| {
                        if c.is_ascii_alphanumeric() {
                            c.to_ascii_lowercase()
                        } else {
                            '-'
                        }
                    })
                    .collect();
                let heading = if section.trim().is_empty() {
                    "Other examples".to_string()
                } else {
                    section.to_string()
                };
                (format!("sec-{slug}"), heading)
            }
        };
        match out.iter_mut().find(|c| c.key == key) {
            Some(c) => c.members.push(i),
            None => out.push(Chapter {
                key,
                heading,
                members: vec![i],
            }),
        }
    }
    out
}

/// The README table of examples: `| id | section | title | status |`, one row per entry in the
/// given order. `|` inside a field is escaped as `\|`.
pub fn markdown_table(entries: &[Entry]) -> String {
    fn cell(s: &str) -> String {
        s.replace('|', "\\|").replace('\n', " ")
    }
    let mut s = String::from("| id | section | title | status |\n|---|---|---|---|\n");
    for e in entries {
        s.push_str(&format!(
            "| `{}` | {} | {} | {} |\n",
            cell(e.example.id),
            cell(e.example.section),
            cell(e.example.title),
            e.status().label()
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::Value;
    use crate::registry::RunContext;

    fn no_run(_: &RunContext) -> Result<ExampleOutput, BookError> {
        Err(BookError::Computation {
            id: "test".into(),
            source: Box::new(crate::Cause::Check("not run in tests".into())),
        })
    }

    pub(crate) fn example(id: &'static str, section: &'static str) -> Example {
        Example {
            id,
            title: "a test example",
            section,
            parameters: "none",
            needs_data: None,
            run: no_run,
        }
    }

    fn ok_with(reference: f64, ours: f64, tol: f64) -> Result<ExampleOutput, BookError> {
        let mut o = ExampleOutput::default();
        o.value("x", Value::Number(ours));
        o.reference("x", Value::Number(reference), "book", tol);
        Ok(o)
    }

    #[test]
    fn status_follows_the_comparisons_and_the_error_kind() {
        // |1.0004 - 1| = 4e-4 <= 5e-4: reproduced; |1.001 - 1| = 1e-3 > 5e-4: differs.
        assert_eq!(Status::of(&ok_with(1.0, 1.0004, 5e-4)), Status::Reproduced);
        assert_eq!(Status::of(&ok_with(1.0, 1.001, 5e-4)), Status::Differs);
        assert_eq!(Status::of(&Ok(ExampleOutput::default())), Status::Runs);
        let needs = Err(BookError::NeedsData {
            id: "a".into(),
            what: "t,theta".into(),
        });
        assert_eq!(Status::of(&needs), Status::NeedsData);
        let failed = Err(BookError::UnknownId("a".into()));
        assert_eq!(Status::of(&failed), Status::Failing);
        // Every reference reproduced but a displayed number not compared: only partly.
        let mut partly = ok_with(1.0, 1.0004, 5e-4).unwrap();
        partly.uncompared.push(crate::output::Uncompared {
            what: "x.m: L (line 41)".into(),
            why: "not unique".into(),
        });
        assert_eq!(Status::of(&Ok(partly.clone())), Status::PartlyCompared);
        // ... and a failing comparison still makes it differ.
        partly.values[0].1 = Value::Number(1.001);
        assert_eq!(Status::of(&Ok(partly.clone())), Status::Differs);
        // Nothing compared at all: it runs.
        partly.references.clear();
        assert_eq!(Status::of(&Ok(partly)), Status::Runs);
        // A reference to a value the example never reported does not count as reproduced.
        let mut o = ExampleOutput::default();
        o.reference("missing", Value::Number(1.0), "book", 1.0);
        assert_eq!(Status::of(&Ok(o)), Status::Differs);
    }

    #[test]
    fn summary_counts_each_status_and_the_figures() {
        let entries = vec![
            Entry {
                example: example("a", "Part 1 §4.1"),
                result: Ok(ExampleOutput::default()),
                seconds: None,
                files: vec!["a.svg".into(), "a.png".into()],
            },
            Entry {
                example: example("b", "Part 1 §4.1"),
                result: ok_with(2.0, 2.0, 0.0),
                seconds: None,
                files: Vec::new(),
            },
            Entry {
                example: example("c", "Part 1 §4.1"),
                result: Err(BookError::UnknownId("c".into())),
                seconds: None,
                files: Vec::new(),
            },
        ];
        let s = Summary::of(&entries);
        assert_eq!(
            s,
            Summary {
                total: 3,
                reproduced: 1,
                partly_compared: 0,
                runs: 1,
                differs: 0,
                needs_data: 0,
                failing: 1,
                figures: 2,
            }
        );
    }

    #[test]
    fn sections_parse_to_part_and_chapter() {
        assert_eq!(part_and_chapter("Part 1 §4.1"), Some((1, 4)));
        assert_eq!(part_and_chapter("Part 2 §1.2.2"), Some((2, 1)));
        assert_eq!(part_and_chapter("part 1 ch. 6"), Some((1, 6)));
        assert_eq!(part_and_chapter("Part 1 chapter 3"), Some((1, 3)));
        assert_eq!(part_and_chapter("IP Toolbox"), None);
        assert_eq!(part_and_chapter("Part one"), None);
    }

    #[test]
    fn chapters_group_sections_in_first_appearance_order() {
        let entries: Vec<Entry> = [
            ("a", "Part 1 §4.1"),
            ("b", "Part 1 §5.1"),
            ("c", "Part 1 §4.3"),
            ("d", "IP Toolbox sample"),
            ("e", "Part 2 §1.1"),
            ("f", "Appendix A"),
        ]
        .into_iter()
        .map(|(id, section)| Entry {
            example: example(id, section),
            result: Ok(ExampleOutput::default()),
            seconds: None,
            files: Vec::new(),
        })
        .collect();
        let ch = chapters(&entries);
        let got: Vec<(&str, &str, Vec<usize>)> = ch
            .iter()
            .map(|c| (c.key.as_str(), c.heading.as_str(), c.members.clone()))
            .collect();
        assert_eq!(
            got,
            vec![
                (
                    "part1-ch4",
                    "Part 1 ch. 4 — State space and stability",
                    vec![0, 2]
                ),
                (
                    "part1-ch5",
                    "Part 1 ch. 5 — Controllability, pole placement, LQR",
                    vec![1]
                ),
                ("toolbox", TOOLBOX_HEADING, vec![3]),
                ("part2-ch1", "Part 2 ch. 1 — LMI and control", vec![4]),
                ("sec-appendix-a", "Appendix A", vec![5]),
            ]
        );
    }

    #[test]
    fn markdown_table_has_one_row_per_entry_and_escapes_pipes() {
        let mut ex = example("p1c41_cdip_response", "Part 1 §4.1");
        ex.title = "y1 | y2";
        let entries = vec![
            Entry {
                example: ex,
                result: ok_with(1.0, 1.0, 0.0),
                seconds: None,
                files: Vec::new(),
            },
            Entry {
                example: example("needs", "Part 1 §3.3"),
                result: Err(BookError::NeedsData {
                    id: "needs".into(),
                    what: "arm data".into(),
                }),
                seconds: None,
                files: Vec::new(),
            },
        ];
        let md = markdown_table(&entries);
        let lines: Vec<&str> = md.lines().collect();
        assert_eq!(lines.len(), 4);
        assert_eq!(lines[0], "| id | section | title | status |");
        assert_eq!(
            lines[2],
            "| `p1c41_cdip_response` | Part 1 §4.1 | y1 \\| y2 | reproduced |"
        );
        assert_eq!(
            lines[3],
            "| `needs` | Part 1 §3.3 | a test example | needs data |"
        );
    }
}
