//! The HTML page of the lab report.

mod figures;

use figures::figures_html;
pub use figures::{FIGHINT, figscroll_open};

use super::format::{escape, number, number_sig, value_html};
use super::{Entry, ReportOptions, Status, Summary, chapters};
use crate::error::BookError;
use crate::output::{ExampleOutput, Reference};
use std::fmt::Write as _;
use std::path::PathBuf;

/// The page's style sheet: inline, so the page needs nothing but its figure files. The lab
/// notebook (`pendulab report --lab`) uses it too: its layout is the same (a column of at most
/// 1180 px, tables in `div.scroll` that scroll inside their card, figures in `div.figscroll`
/// at their own size, scrolling sideways on narrow screens, `pre.file` for files shown as
/// written).
pub const STYLE: &str = r#"
:root { --fg:#1d2327; --muted:#5f6b73; --line:#d8dee3; --bg:#ffffff; --panel:#f6f8fa;
  --ok:#1a7f37; --bad:#c62828; --warn:#9a6700; --info:#0b5cad; --bar:44px; }
* { box-sizing: border-box; }
html { scroll-padding-top: calc(var(--bar) + 8px); }
body { margin:0; color:var(--fg); background:var(--bg);
  font:15px/1.5 system-ui,-apple-system,"Segoe UI",Roboto,"Noto Sans","Noto Sans CJK JP",sans-serif; }
header, main, nav.toc, footer { max-width:1180px; margin:0 auto; padding:0 24px; }
.topbar { position:sticky; top:0; z-index:10; height:var(--bar); display:flex; align-items:center; gap:14px;
  padding:0 24px; background:rgba(255,255,255,.96); border-bottom:1px solid var(--line); }
.topbar a.up { font-weight:600; white-space:nowrap; }
.topbar .name { color:var(--muted); font-size:13.5px; overflow:hidden; white-space:nowrap; text-overflow:ellipsis; }
header { padding-top:20px; }
h1 { margin:0 0 4px; font-size:28px; line-height:1.2; }
h2 { margin:40px 0 12px; padding-bottom:6px; border-bottom:2px solid var(--line); font-size:22px; line-height:1.25; }
h3 { margin:0 0 6px; font-size:18px; display:flex; flex-wrap:wrap; gap:4px 8px; align-items:baseline; }
code, .num, table.mat td { font-family:ui-monospace,"DejaVu Sans Mono",Menlo,Consolas,monospace; font-size:13.5px; }
h3 code, nav.toc code { overflow-wrap:anywhere; }
.sub { color:var(--muted); margin:0; }
.counts { display:flex; flex-wrap:wrap; gap:8px; margin:14px 0 0; padding:0; list-style:none; }
.badge { display:inline-block; padding:1px 9px; border-radius:10px; font-size:12.5px; font-weight:600;
  color:#fff; white-space:nowrap; }
.st-ok { background:var(--ok); } .st-part { background:#4d7c5a; } .st-runs { background:var(--info); } .st-differs { background:var(--warn); }
.st-data { background:#6e7781; } .st-fail { background:var(--bad); }
nav.toc { margin-top:20px; }
nav.toc > ol { padding-left:20px; columns:2 420px; column-gap:32px; }
nav.toc > ol > li { break-inside:avoid; margin-bottom:10px; }
nav.toc ul { list-style:none; padding-left:8px; margin:4px 0; }
nav.toc ul li { font-size:13.5px; display:flex; flex-wrap:wrap; gap:2px 6px; align-items:baseline; }
nav.toc .badge { font-size:12px; padding:0 7px; }
a { color:var(--info); text-decoration:none; } a:hover { text-decoration:underline; }
a:focus-visible, button:focus-visible, input:focus-visible, .scroll:focus-visible { outline:2px solid var(--info); outline-offset:2px; }
section.chapter { scroll-margin-top:calc(var(--bar) + 8px); }
article.example { border:1px solid var(--line); border-radius:8px; padding:16px 18px; margin:16px 0;
  background:var(--bg); min-width:0; }
.meta { color:var(--muted); font-size:13.5px; margin:0 0 10px; }
.meta span + span::before { content:" · "; }
.scroll { overflow-x:auto; max-width:100%; margin:8px 0 12px;
  background:linear-gradient(to right, #fff 30%, rgba(255,255,255,0)) 0 0 / 40px 100% no-repeat local,
    linear-gradient(to left, #fff 30%, rgba(255,255,255,0)) 100% 0 / 40px 100% no-repeat local,
    radial-gradient(farthest-side at 0 50%, rgba(0,0,0,.16), rgba(0,0,0,0)) 0 0 / 12px 100% no-repeat scroll,
    radial-gradient(farthest-side at 100% 50%, rgba(0,0,0,.16), rgba(0,0,0,0)) 100% 0 / 12px 100% no-repeat scroll; }
table.values { border-collapse:collapse; }
table.values th, table.values td { border-bottom:1px solid var(--line); padding:5px 10px; text-align:left;
  vertical-align:middle; }
table.values th { font-size:13px; color:var(--muted); font-weight:600; }
table.values td.name { font-family:ui-monospace,"DejaVu Sans Mono",Menlo,monospace; font-size:13.5px; }
table.values td.name .unit { display:block; font-family:system-ui,sans-serif; font-size:12.5px; color:var(--muted); }
.uncompared { border-radius:6px; padding:8px 14px; margin:8px 0; background:var(--panel); border:1px solid var(--line);
  overflow-wrap:anywhere; }
.uncompared ul { margin:4px 0 0; padding-left:20px; }
table.mat { border-collapse:separate; border-spacing:0; border-left:2px solid var(--fg);
  border-right:2px solid var(--fg); border-radius:4px; display:inline-table; }
table.mat td { padding:1px 8px; text-align:right; border:0; white-space:nowrap; }
.vec { display:inline-flex; flex-wrap:wrap; gap:0 16px; max-width:38em; padding:1px 8px; border-left:2px solid var(--fg);
  border-right:2px solid var(--fg); border-radius:4px; font-family:ui-monospace,"DejaVu Sans Mono",Menlo,Consolas,monospace;
  font-size:13.5px; }
.vec > span { white-space:nowrap; }
.check { font-size:13px; white-space:nowrap; }
.check .yes { color:var(--ok); font-weight:700; } .check .no { color:var(--bad); font-weight:700; }
.src { color:var(--muted); font-size:12.5px; display:block; min-width:14em; }
.missing { color:var(--muted); font-style:italic; }
ul.notes { margin:6px 0 10px; padding-left:20px; color:#33404a; overflow-wrap:anywhere; }
.figures { display:flex; flex-wrap:wrap; gap:14px; margin-top:8px; }
figure { margin:0; flex:0 1 auto; min-width:0; max-width:100%; border:1px solid var(--line); border-radius:6px;
  padding:8px; background:#fff; }
figure img, figure svg { display:block; max-width:100%; height:auto; }
figure .figscroll { margin:0; }
figure .figscroll img, figure .figscroll svg { max-width:none; }
.fighint { display:none; }
pre.file { background:var(--panel); padding:10px; overflow-x:auto; font-size:13px; max-width:100%; }
table.params td, table.params th { border-bottom:1px solid var(--line); padding:4px 10px; text-align:right; }
figcaption { font-size:12.5px; color:var(--muted); margin-top:4px; overflow-wrap:anywhere; }
.controls { display:flex; align-items:center; gap:10px; margin-top:6px; }
.controls[hidden] { display:none; }
.controls button { font:inherit; font-size:13.5px; min-width:5.5em; padding:3px 10px; border:1px solid var(--line);
  border-radius:6px; background:var(--panel); color:var(--fg); cursor:pointer; }
.controls input[type=range] { flex:1 1 auto; min-width:0; }
.controls output { font-family:ui-monospace,"DejaVu Sans Mono",Menlo,monospace; font-size:13px; min-width:6.5em;
  text-align:right; color:var(--muted); }
.files { font-size:13px; }
.error, .needs { border-radius:6px; padding:10px 14px; margin:8px 0; }
.error { background:#fdecea; border:1px solid #f3b8b3; }
.error pre { margin:4px 0 0; white-space:pre-wrap; font-size:13px; }
.needs { background:var(--panel); border:1px solid var(--line); }
footer { color:var(--muted); font-size:12.5px; padding:24px; }
@media (max-width:1179px) {
  .fighint { display:inline; }
}
@media (max-width:600px) {
  header, main, nav.toc, footer, .topbar { padding-left:12px; padding-right:12px; }
  article.example { padding:12px 10px; }
  h1 { font-size:23px; } h2 { font-size:19px; } h3 { font-size:16.5px; }
  nav.toc > ol { padding-left:18px; }
}
@media print {
  @page { margin:14mm 12mm; }
  body { font-size:10pt; }
  .topbar, .controls { display:none; }
  header, main, nav.toc, footer { max-width:none; padding:0; }
  nav.toc > ol { columns:1; }
  h2 { break-after:avoid; }
  section.chapter { break-before:page; }
  article.example { break-before:page; border:0; padding:0; margin:0; }
  section.chapter > h2 + article.example { break-before:avoid; }
  .scroll { overflow:visible; background:none; }
  figure .figscroll img, figure .figscroll svg { max-width:100%; }
  .fighint { display:none; }
  table.values, table.values > tbody { display:block; }
  table.values > thead { display:none; }
  table.values > tbody > tr { display:grid; grid-template-columns:minmax(7em, max-content) minmax(0, 1fr);
    column-gap:14px; padding:4px 0; border-bottom:1px solid var(--line); }
  table.values > tbody > tr > td { display:block; grid-column:2; border:0; padding:1px 0; }
  table.values > tbody > tr > td.name { grid-column:1; grid-row:1 / span 3; }
  table.values > tbody > tr > td:empty { display:none; }
  table.values > tbody > tr > td[data-label]::before { content:attr(data-label) " "; color:var(--muted);
    font-size:8.5pt; display:inline-block; min-width:3.6em; vertical-align:top; }
  table.values td[data-label] > div { display:inline-block; }
  tr, figure, .error, .needs { break-inside:avoid; }
  .figures { display:block; }
  figure { display:block; border:0; padding:0; margin:10px 0; }
  figure img, figure svg { max-height:230mm; width:auto; }
  a { color:inherit; }
}
"#;

/// The player of the inline animations: a pause/play button and a time scrubber (a range input,
/// keyboard-operable) per `.player`, driving the SMIL clock of its `<svg>`
/// (`pauseAnimations`, `setCurrentTime`). Without scripts the animations simply loop.
const PLAYER_SCRIPT: &str = r#"
(function () {
  var reduce = window.matchMedia && window.matchMedia('(prefers-reduced-motion: reduce)').matches;
  document.querySelectorAll('.player').forEach(function (p) {
    var svg = p.querySelector('svg'), c = p.querySelector('.controls');
    if (!svg || !c || !svg.pauseAnimations) return;
    var a = svg.querySelector('animate, animateTransform');
    var dur = a ? parseFloat(a.getAttribute('dur')) : NaN;
    if (!(dur > 0)) return;
    var btn = c.querySelector('button'), range = c.querySelector('input'), out = c.querySelector('output');
    range.max = dur.toFixed(2);
    var show = function (t) { range.value = t.toFixed(2); out.value = t.toFixed(2) + ' s'; };
    var label = function () {
      var paused = svg.animationsPaused();
      btn.textContent = paused ? 'Play' : 'Pause';
      btn.setAttribute('aria-pressed', paused ? 'true' : 'false');
    };
    btn.addEventListener('click', function () {
      if (svg.animationsPaused()) svg.unpauseAnimations(); else svg.pauseAnimations();
      label();
    });
    range.addEventListener('input', function () {
      svg.pauseAnimations();
      svg.setCurrentTime(parseFloat(range.value));
      show(parseFloat(range.value));
      label();
    });
    var tick = function () {
      if (!svg.animationsPaused()) show(svg.getCurrentTime() % dur);
      window.requestAnimationFrame(tick);
    };
    if (reduce) svg.pauseAnimations();
    c.hidden = false;
    label();
    show(0);
    window.requestAnimationFrame(tick);
  });
})();
"#;

/// Writes the whole report page.
///
/// Every text that comes from an example (titles, value names, notes, error messages, paths)
/// is HTML-escaped. Figures are shown with `<img>` at their own width (scaled down only when
/// the page is narrower) — SVG, PNG and GIF files; when several files share a stem (`fig.svg`
/// and `fig.png`) the SVG is shown and each format is linked. An animated SVG whose markup is
/// in [`ReportOptions::animations`] is inlined with a pause/play button and a time scrubber
/// (the page's only script); other files (e.g. CSV) are linked. Links are relative to
/// [`ReportOptions::base_dir`] when the file lies under it.
///
/// The page has a sticky bar with a link back to the contents, value tables that scroll
/// inside their card on narrow screens, and a print style sheet (one example per page,
/// figures and table rows not split, no bar or controls).
pub fn html(entries: &[Entry], options: &ReportOptions) -> String {
    let summary = Summary::of(entries);
    let chapters = chapters(entries);
    let mut s = String::with_capacity(16_384 + 4096 * entries.len());
    let title = escape(&options.title);
    let _ = write!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{title}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n\
         <div class=\"topbar\" id=\"top\"><a class=\"up\" href=\"#contents\">↑ Contents</a>\
         <span class=\"name\">{title}</span></div>\n<header>\n<h1>{title}</h1>\n"
    );
    if let Some(sub) = &options.subtitle {
        let _ = writeln!(s, "<p class=\"sub\">{}</p>", escape(sub));
    }
    for (label, href) in &options.links {
        let _ = writeln!(
            s,
            "<p class=\"sub\"><a href=\"{}\">{}</a></p>",
            escape(href),
            escape(label)
        );
    }
    s.push_str(
        "<p class=\"sub\">Every example of 「倒立振子で学ぶ制御工学」 reproduced by pendulab: \
         its numbers, the book's printed value beside ours (✓ reproduced within the stated \
         tolerance, ✗ not), and its figures. Gains are in the book's convention u = +K x.</p>\n",
    );
    let _ = write!(
        s,
        "<ul class=\"counts\" id=\"summary\"><li><span class=\"badge\" style=\"background:#24292f\">{} examples</span></li>",
        summary.total
    );
    for st in Status::ALL {
        let _ = write!(
            s,
            "<li><span class=\"badge {}\">{} {}</span></li>",
            st.class(),
            summary.count(st),
            st.label()
        );
    }
    let _ = writeln!(
        s,
        "<li><span class=\"badge\" style=\"background:#57606a\">{} figures</span></li></ul>\n</header>",
        summary.figures
    );

    // Table of contents.
    s.push_str(
        "<nav class=\"toc\" id=\"contents\" aria-label=\"Contents\">\n<h2>Contents</h2>\n<ol>\n",
    );
    for ch in &chapters {
        let _ = write!(
            s,
            "<li><a href=\"#{}\">{}</a>\n<ul>\n",
            escape(&ch.key),
            escape(&ch.heading)
        );
        for &i in &ch.members {
            let e = &entries[i];
            let st = e.status();
            let _ = writeln!(
                s,
                "<li><a href=\"#{id}\"><code>{id}</code></a> <span>{title}</span> <span class=\"badge {cls}\">{label}</span></li>",
                id = escape(e.example.id),
                title = escape(e.example.title),
                cls = st.class(),
                label = st.label()
            );
        }
        s.push_str("</ul></li>\n");
    }
    s.push_str("</ol>\n</nav>\n<main id=\"main\">\n");
    if entries.is_empty() {
        s.push_str("<p class=\"missing\">No examples are registered in this build.</p>\n");
    }

    for ch in &chapters {
        let _ = writeln!(
            s,
            "<section class=\"chapter\" id=\"{}\">\n<h2>{}</h2>",
            escape(&ch.key),
            escape(&ch.heading)
        );
        for &i in &ch.members {
            example_html(&mut s, &entries[i], options);
        }
        s.push_str("</section>\n");
    }
    let _ = writeln!(
        s,
        "</main>\n<footer>Written by pendulab {}. Figures are files beside this page. \
         <a href=\"#top\">Back to the top</a></footer>",
        env!("CARGO_PKG_VERSION")
    );
    if s.contains("<div class=\"player\">") {
        let _ = writeln!(s, "<script>{PLAYER_SCRIPT}</script>");
    }
    s.push_str("</body>\n</html>\n");
    s
}

/// One example's `<article>`.
fn example_html(s: &mut String, e: &Entry, options: &ReportOptions) {
    let ex = &e.example;
    let st = e.status();
    let _ = writeln!(
        s,
        "<article class=\"example\" id=\"{id}\">\n<h3><span>{title}</span> <code>{id}</code> <span class=\"badge {cls}\">{label}</span></h3>",
        id = escape(ex.id),
        title = escape(ex.title),
        cls = st.class(),
        label = st.label()
    );
    s.push_str("<p class=\"meta\">");
    let _ = write!(s, "<span>{}</span>", escape(ex.section));
    let _ = write!(s, "<span>parameters: {}</span>", escape(ex.parameters));
    if let Some(what) = ex.needs_data {
        let _ = write!(s, "<span>data: {}</span>", escape(what));
    }
    if let Some(t) = e.seconds {
        let _ = write!(
            s,
            "<span>ran in {} s</span>",
            escape(&number(round_time(t)))
        );
    }
    s.push_str("</p>\n");
    match &e.result {
        Ok(out) => output_html(s, ex.id, out, &e.files, options),
        Err(BookError::NeedsData { what, .. }) => {
            let _ = writeln!(
                s,
                "<div class=\"needs\"><strong>needs --data</strong>: {what}. Run it with \
                 <code>pendulab report --data {id}=FILE.csv</code> or \
                 <code>pendulab book run {id} --data FILE.csv</code>.</div>",
                what = escape(what),
                id = escape(ex.id)
            );
        }
        Err(err) => {
            let _ = writeln!(
                s,
                "<div class=\"error\"><strong>error</strong><pre>{}</pre></div>",
                escape(&err.to_string())
            );
        }
    }
    s.push_str("</article>\n");
}

/// Seconds to three significant digits (run times are noisy beyond that).
fn round_time(t: f64) -> f64 {
    if t <= 0.0 || !t.is_finite() {
        return t;
    }
    let scale = 10f64.powi(2 - t.log10().floor() as i32);
    (t * scale).round() / scale
}

/// Values with the book's values beside them, notes and figures of a successful run.
fn output_html(
    s: &mut String,
    id: &str,
    out: &ExampleOutput,
    files: &[PathBuf],
    options: &ReportOptions,
) {
    let comparisons = out.comparisons();
    let refs: Vec<(&Reference, &crate::output::Comparison)> =
        out.references.iter().zip(&comparisons).collect();
    if !out.values.is_empty() || !refs.is_empty() {
        let with_book = !refs.is_empty();
        // Wide tables scroll inside their card; focusable so the keyboard can scroll them.
        let _ = write!(
            s,
            "<div class=\"scroll\" tabindex=\"0\" role=\"region\" aria-label=\"values of {}\">",
            escape(id)
        );
        s.push_str("<table class=\"values\">\n<thead><tr><th>value</th><th>pendulab</th>");
        if with_book {
            s.push_str("<th>book</th><th>check</th>");
        }
        s.push_str("</tr></thead>\n<tbody>\n");
        for (name, v) in &out.values {
            let mine: Vec<_> = refs.iter().filter(|(r, _)| &r.name == name).collect();
            let unit = out
                .unit_of(name)
                .map(|u| format!("<span class=\"unit\">{}</span>", escape(u)))
                .unwrap_or_default();
            let _ = write!(
                s,
                "<tr><td class=\"name\">{}{unit}</td><td>{}</td>",
                escape(name),
                value_html(v)
            );
            if with_book {
                book_cells(s, &mine);
            }
            s.push_str("</tr>\n");
        }
        // Printed values the example did not report.
        for r in refs
            .iter()
            .filter(|(r, _)| !out.values.iter().any(|(n, _)| n == &r.name))
        {
            let _ = write!(
                s,
                "<tr><td class=\"name\">{}</td><td class=\"missing\">not reported</td>",
                escape(&r.0.name)
            );
            book_cells(s, &[r]);
            s.push_str("</tr>\n");
        }
        s.push_str("</tbody></table></div>\n");
    }
    if !out.uncompared.is_empty() {
        // Why the badge says "agrees where compared" rather than "reproduced".
        s.push_str(
            "<div class=\"uncompared\"><strong>Not compared</strong> — numbers the book prints \
             or the M-file displays that are not shown beside pendulab's, so the example only \
             agrees where compared:\n<ul>\n",
        );
        for u in &out.uncompared {
            let _ = writeln!(s, "<li>{}: {}</li>", escape(&u.what), escape(&u.why));
        }
        s.push_str("</ul></div>\n");
    }
    if !out.notes.is_empty() {
        s.push_str("<ul class=\"notes\">\n");
        for n in &out.notes {
            let _ = writeln!(s, "<li>{}</li>", escape(n));
        }
        s.push_str("</ul>\n");
    }
    figures_html(s, files, options);
}

/// The "book" and "check" cells of a value row.
fn book_cells(s: &mut String, refs: &[&(&Reference, &crate::output::Comparison)]) {
    if refs.is_empty() {
        s.push_str("<td></td><td></td>");
        return;
    }
    s.push_str("<td data-label=\"book\">");
    for (r, _) in refs {
        let _ = write!(
            s,
            "<div>{}<span class=\"src\">{}</span></div>",
            value_html(&r.value),
            escape(&r.source)
        );
    }
    s.push_str("</td><td class=\"check\" data-label=\"check\">");
    for (r, c) in refs {
        // Two digits say how close it is; the full values are in the neighbouring cells.
        let tol = escape(&number_sig(r.tolerance, 2));
        match c.max_abs_error {
            Some(err) if c.reproduced => {
                let _ = write!(
                    s,
                    "<div><span class=\"yes\">✓</span> |Δ| = {} ≤ {tol}</div>",
                    escape(&number_sig(err, 2))
                );
            }
            Some(err) => {
                let _ = write!(
                    s,
                    "<div><span class=\"no\">✗</span> |Δ| = {} &gt; {tol}</div>",
                    escape(&number_sig(err, 2))
                );
            }
            None => s.push_str("<div><span class=\"no\">✗</span> not comparable</div>"),
        }
    }
    s.push_str("</td>");
}

#[cfg(test)]
mod tests;
