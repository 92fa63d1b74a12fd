//! The HTML page of the lab report.

use super::format::{escape, number, number_sig, value_html};
use super::{Entry, ReportOptions, Status, Summary, chapters};
use crate::error::BookError;
use crate::output::{ExampleOutput, Reference};
use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

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

/// Kinds of figure files, in the order of preference for display.
const SHOWN: [&str; 6] = ["svg", "png", "gif", "jpg", "jpeg", "webp"];

/// Figures grouped by stem, one `<figure>` per group; other files as links.
fn figures_html(s: &mut String, figures: &[PathBuf], options: &ReportOptions) {
    let base = options.base_dir.as_path();
    // Groups: path without extension -> files, in order of first appearance.
    let mut groups: Vec<(PathBuf, Vec<&PathBuf>)> = Vec::new();
    let mut others: Vec<&PathBuf> = Vec::new();
    for f in figures {
        let ext = extension(f);
        if SHOWN.contains(&ext.as_str()) {
            let key = f.with_extension("");
            match groups.iter_mut().find(|(k, _)| *k == key) {
                Some((_, files)) => files.push(f),
                None => groups.push((key, vec![f])),
            }
        } else {
            others.push(f);
        }
    }
    if !groups.is_empty() {
        s.push_str("<div class=\"figures\">\n");
        for (key, files) in &groups {
            // Every group holds at least one file of a shown kind; the fallback is never used.
            let shown = SHOWN
                .iter()
                .find_map(|k| files.iter().find(|f| extension(f) == *k))
                .unwrap_or(&files[0]);
            let src = escape(&href(shown, base));
            let stem = key
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let alt = escape(&stem);
            match options.animations.get(*shown) {
                Some(markup) if extension(shown) == "svg" => {
                    let _ = write!(
                        s,
                        "<figure class=\"anim\"><div class=\"player\">{scroll}{svg}</div>\
                         <div class=\"controls\" hidden><button type=\"button\" aria-label=\"Play or pause {alt}\">Pause</button>\
                         <input type=\"range\" min=\"0\" max=\"1\" step=\"0.01\" value=\"0\" aria-label=\"Animation time of {alt}, seconds\">\
                         <output aria-live=\"off\">0.00 s</output></div></div><figcaption>{alt}",
                        scroll = figscroll_open(&alt),
                        svg = inline_svg(markup, &alt)
                    );
                }
                _ => {
                    let _ = write!(
                        s,
                        "<figure>{scroll}<a href=\"{src}\"><img src=\"{src}\" alt=\"{alt}\" loading=\"lazy\"></a></div><figcaption>{alt}",
                        scroll = figscroll_open(&alt)
                    );
                }
            }
            for f in files {
                let _ = write!(
                    s,
                    " · <a href=\"{}\">{}</a>",
                    escape(&href(f, base)),
                    escape(&extension(f))
                );
            }
            s.push_str(FIGHINT);
            s.push_str("</figcaption></figure>\n");
        }
        s.push_str("</div>\n");
    }
    if !others.is_empty() {
        s.push_str("<p class=\"files\">Files:");
        for f in others {
            let name = f
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| f.display().to_string());
            let _ = write!(
                s,
                " <a href=\"{}\">{}</a>",
                escape(&href(f, base)),
                escape(&name)
            );
        }
        s.push_str("</p>\n");
    }
}

/// The opening tag of the frame that shows a figure at its own size (its text at the size it
/// was drawn, ≥ 12 px = 9 pt) and scrolls sideways inside the card when the screen is
/// narrower; focusable, so the keyboard can scroll it. `label` is already escaped.
pub fn figscroll_open(label: &str) -> String {
    format!(
        "<div class=\"scroll figscroll\" tabindex=\"0\" role=\"region\" aria-label=\"figure {label}, \
         at its own size\">"
    )
}

/// The caption's hint, shown on screens narrower than a full-size figure (CSS), that the
/// figure is at its own size and scrolls sideways.
pub const FIGHINT: &str =
    "<span class=\"fighint\"> · shown at its own size: scroll sideways to see all of it</span>";

/// An SVG document's markup for inlining into the page: the XML declaration and doctype
/// dropped, `role="img"` and the accessible name `label` (already escaped) added to the root.
fn inline_svg(markup: &str, label: &str) -> String {
    let start = markup.find("<svg").unwrap_or(0);
    let body = markup[start..].trim_end();
    match body.strip_prefix("<svg") {
        Some(rest) => format!("<svg role=\"img\" aria-label=\"{label}\"{rest}"),
        None => body.to_string(),
    }
}

/// Lower-case extension of a path ("" if none).
fn extension(p: &Path) -> String {
    p.extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default()
}

/// Drops `.` components, so `./out/a.svg` and `out/a.svg` compare equal.
fn clean(p: &Path) -> PathBuf {
    p.components()
        .filter(|c| !matches!(c, Component::CurDir))
        .collect()
}

/// The URL of `path` as seen from a page in `base`: relative with `/` separators when `path`
/// lies under `base`, else the path as given. Each segment is percent-encoded (RFC 3986
/// unreserved characters are kept).
pub(crate) fn href(path: &Path, base: &Path) -> String {
    let p = clean(path);
    let b = clean(base);
    let rel = p.strip_prefix(&b).map(Path::to_path_buf).unwrap_or(p);
    let absolute = rel.has_root();
    let segments: Vec<String> = rel
        .components()
        .filter_map(|c| match c {
            Component::Normal(n) => Some(percent_encode(&n.to_string_lossy())),
            Component::ParentDir => Some("..".to_string()),
            _ => None,
        })
        .collect();
    let joined = segments.join("/");
    if absolute {
        format!("/{joined}")
    } else {
        joined
    }
}

fn percent_encode(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for b in s.bytes() {
        if b.is_ascii_alphanumeric() || matches!(b, b'-' | b'.' | b'_' | b'~') {
            out.push(b as char);
        } else {
            let _ = write!(out, "%{b:02X}");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::tests::example;
    use super::*;
    use crate::output::Value;
    use pendulab_lti::Complex64;

    /// The `<article>` of one example in a page.
    fn article<'a>(page: &'a str, id: &str) -> &'a str {
        let start = page
            .find(&format!("<article class=\"example\" id=\"{id}\">"))
            .expect("article present");
        let end = start + page[start..].find("</article>").expect("article closed");
        &page[start..end]
    }

    fn entry(
        id: &'static str,
        section: &'static str,
        result: Result<ExampleOutput, BookError>,
    ) -> Entry {
        Entry {
            example: example(id, section),
            result,
            seconds: Some(0.01234),
            files: Vec::new(),
        }
    }

    #[test]
    fn text_from_examples_is_escaped() {
        let mut o = ExampleOutput::default();
        o.value("<b>K</b>", Value::Number(1.0));
        o.notes.push("<script>alert('x')</script> & more".into());
        let mut ex = example("esc", "Part 1 §4.1");
        ex.title = "A <i>title</i>";
        ex.parameters = "\"quoted\"";
        let entries = vec![
            Entry {
                example: ex,
                result: Ok(o),
                seconds: None,
                files: Vec::new(),
            },
            entry(
                "err",
                "Part 1 §4.1",
                Err(BookError::Computation {
                    id: "err".into(),
                    source: Box::new(crate::Cause::Check("matrix <A> is singular & bad".into())),
                }),
            ),
        ];
        let page = html(&entries, &ReportOptions::default());
        assert!(!page.contains("<script>"));
        assert!(!page.contains("<b>K</b>"));
        assert!(!page.contains("<i>title</i>"));
        assert!(page.contains("&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt; &amp; more"));
        assert!(page.contains("&lt;b&gt;K&lt;/b&gt;"));
        assert!(page.contains("A &lt;i&gt;title&lt;/i&gt;"));
        assert!(page.contains("&quot;quoted&quot;"));
        assert!(article(&page, "err").contains("matrix &lt;A&gt; is singular &amp; bad"));
    }

    #[test]
    fn book_values_stand_beside_ours_with_the_check_mark() {
        let mut o = ExampleOutput::default();
        o.value(
            "poles",
            Value::Complex(vec![
                Complex64::new(-3.125, 5.817),
                Complex64::new(-3.125, -5.817),
            ]),
        );
        o.value("kP", Value::Number(5.7339));
        o.value("K", Value::Matrix(vec![vec![1.0, 2.0], vec![3.0, 4.0]]));
        // Within half a unit of the 4th decimal: reproduced.
        o.reference(
            "poles",
            Value::Complex(vec![
                Complex64::new(-3.125, 5.817),
                Complex64::new(-3.125, -5.817),
            ]),
            "book p. 100",
            5e-4,
        );
        // 5.7339 against 5.70 with tolerance 5e-3: |Δ| = 0.0339 > 5e-3 (shown to two digits).
        o.reference("kP", Value::Number(5.70), "book Part 1 §2.2.3", 5e-3);
        o.reference("missing_value", Value::Number(1.0), "book p. 1", 0.5);
        let page = html(
            &[entry("cmp", "Part 1 §6.2", Ok(o))],
            &ReportOptions::default(),
        );
        let a = article(&page, "cmp");
        // Rows in the order of the values, then the unreported reference.
        let row_of = |name: &str| {
            let i = a
                .find(&format!("<td class=\"name\">{name}</td>"))
                .expect(name);
            // Rows end with a newline; the grids of matrix values inside them do not.
            &a[i..i + a[i..].find("</tr>\n").unwrap()]
        };
        let poles = row_of("poles");
        assert!(poles.contains("-3.125 ± 5.817j"));
        assert!(poles.contains("book p. 100"));
        assert!(poles.contains("class=\"yes\">✓"));
        let kp = row_of("kP");
        assert!(kp.contains("5.7339") && kp.contains("5.7<"));
        assert!(kp.contains("class=\"no\">✗</span> |Δ| = 0.034 &gt; 0.005"));
        let k = row_of("K");
        assert!(k.contains("<table class=\"mat\"><tr><td>1</td><td>2</td></tr><tr><td>3</td><td>4</td></tr></table>"));
        assert!(
            k.ends_with("<td></td><td></td>"),
            "no book value for K: {k}"
        );
        let missing = row_of("missing_value");
        assert!(missing.contains("not reported") && missing.contains("not comparable"));
        assert!(a.contains("differs from book"));
    }

    #[test]
    fn figures_are_linked_relative_and_grouped_by_stem() {
        let base = PathBuf::from("out");
        let mut e = entry("fig", "Part 1 §4.1", Ok(ExampleOutput::default()));
        e.files = vec![
            base.join("figures/fig/step.svg"),
            base.join("figures/fig/step.png"),
            base.join("figures/fig/cart anim.gif"),
            base.join("figures/fig/cart anim.svg"),
            base.join("figures/fig/only.png"),
            base.join("figures/fig/data.csv"),
            PathBuf::from("/elsewhere/x.png"),
        ];
        let opts = ReportOptions {
            base_dir: PathBuf::from("./out"),
            ..ReportOptions::default()
        };
        let page = html(&[e], &opts);
        let a = article(&page, "fig");
        assert_eq!(a.matches("<figure>").count(), 4, "{a}");
        // SVG shown when a PNG shares the stem; both linked.
        assert!(a.contains("<img src=\"figures/fig/step.svg\" alt=\"step\" loading=\"lazy\">"));
        // Shown at its own size in a frame that scrolls sideways on a narrow screen, with the
        // hint in the caption.
        assert!(a.contains(
            "<figure><div class=\"scroll figscroll\" tabindex=\"0\" role=\"region\" \
             aria-label=\"figure step, at its own size\"><a href=\"figures/fig/step.svg\">"
        ));
        assert_eq!(a.matches(FIGHINT).count(), 4);
        for rule in [
            "figure .figscroll img, figure .figscroll svg { max-width:none; }",
            "@media (max-width:1179px) {\n  .fighint { display:inline; }",
        ] {
            assert!(STYLE.contains(rule), "{rule}");
        }
        assert!(a.contains("<a href=\"figures/fig/step.png\">png</a>"));
        // The animation: SVG shown, GIF linked; the space is percent-encoded.
        assert!(a.contains("<img src=\"figures/fig/cart%20anim.svg\""));
        assert!(a.contains("<a href=\"figures/fig/cart%20anim.gif\">gif</a>"));
        assert!(a.contains("<img src=\"figures/fig/only.png\""));
        assert!(a.contains("<img src=\"/elsewhere/x.png\""));
        assert!(a.contains("Files: <a href=\"figures/fig/data.csv\">data.csv</a>"));
    }

    #[test]
    fn needs_data_and_errors_are_shown_in_place() {
        let entries = vec![
            entry(
                "arm_id",
                "Part 1 §3.3",
                Err(BookError::NeedsData {
                    id: "arm_id".into(),
                    what: "arm step response, columns t,phi1,phi2,v".into(),
                }),
            ),
            entry(
                "broken",
                "Part 1 §3.3",
                Err(BookError::Computation {
                    id: "broken".into(),
                    source: Box::new(crate::Cause::Check(
                        "Riccati solver did not converge".into(),
                    )),
                }),
            ),
        ];
        let page = html(&entries, &ReportOptions::default());
        let a = article(&page, "arm_id");
        assert!(a.contains("needs --data"));
        assert!(a.contains("columns t,phi1,phi2,v"));
        assert!(a.contains("pendulab report --data arm_id=FILE.csv"));
        let b = article(&page, "broken");
        assert!(b.contains("class=\"error\""));
        assert!(b.contains("example &#39;broken&#39;: Riccati solver did not converge"));
        assert!(b.contains("badge st-fail\">failing"));
    }

    #[test]
    fn page_has_contents_chapters_and_counts() {
        let mut ok = ExampleOutput::default();
        ok.value("x", Value::Number(2.0));
        ok.reference("x", Value::Number(2.0), "book", 0.0);
        let entries = vec![
            entry("a41", "Part 1 §4.1", Ok(ok)),
            entry("a51", "Part 1 §5.1", Ok(ExampleOutput::default())),
            entry("a43", "Part 1 §4.3", Ok(ExampleOutput::default())),
        ];
        let opts = ReportOptions {
            subtitle: Some("v <1>".into()),
            ..ReportOptions::default()
        };
        let page = html(&entries, &opts);
        assert!(page.starts_with("<!DOCTYPE html>"));
        assert!(page.trim_end().ends_with("</html>"));
        assert!(page.contains("<p class=\"sub\">v &lt;1&gt;</p>"));
        // No external resources: nothing is fetched from the network.
        assert!(!page.contains("http://") && !page.contains("https://"));
        // No animation, no script.
        assert!(!page.contains("<script"));
        // The sticky bar links back to the contents; the footer to the top.
        let bar =
            &page[page.find("<div class=\"topbar\"").unwrap()..page.find("<header>").unwrap()];
        assert!(bar.contains("href=\"#contents\""), "{bar}");
        assert!(page.contains("<nav class=\"toc\" id=\"contents\""));
        assert!(
            page.contains("<div class=\"topbar\" id=\"top\"") && page.contains("href=\"#top\"")
        );
        // The print style sheet starts each example on a new page and keeps figures whole.
        let print = &page[page.find("@media print").unwrap()..];
        assert!(print.contains("article.example { break-before:page;"));
        assert!(print.contains("figure, .error, .needs { break-inside:avoid; }"));
        // Table of contents links every chapter and example.
        for anchor in ["#part1-ch4", "#part1-ch5", "#a41", "#a51", "#a43"] {
            assert!(page.contains(&format!("href=\"{anchor}\"")), "{anchor}");
        }
        // Chapter 4 holds both of its examples, before chapter 5.
        let ch4 = page
            .find("<section class=\"chapter\" id=\"part1-ch4\">")
            .unwrap();
        let ch5 = page
            .find("<section class=\"chapter\" id=\"part1-ch5\">")
            .unwrap();
        let a41 = page.find("<article class=\"example\" id=\"a41\">").unwrap();
        let a43 = page.find("<article class=\"example\" id=\"a43\">").unwrap();
        let a51 = page.find("<article class=\"example\" id=\"a51\">").unwrap();
        assert!(ch4 < a41 && a41 < a43 && a43 < ch5 && ch5 < a51);
        assert!(page.contains("3 examples"));
        assert!(
            page.contains("1 reproduced") && page.contains("2 runs") && page.contains("0 failing")
        );
        assert!(article(&page, "a41").contains("ran in 0.0123 s"));
    }

    #[test]
    fn partly_compared_examples_list_what_is_not_compared_and_units_show() {
        let mut o = ExampleOutput::default();
        o.value("K", Value::Vector(vec![1.0, 2.0]));
        o.value("a_c", Value::Number(6.25));
        o.unit(&["a_c"], "1/s");
        o.reference("K", Value::Vector(vec![1.0, 2.0]), "x.m line 3", 5e-5);
        o.uncompared.push(crate::output::Uncompared {
            what: "x.m: L (line 41)".into(),
            why: "not unique <with two outputs>".into(),
        });
        let page = html(
            &[entry("part", "Part 1 §7.4", Ok(o))],
            &ReportOptions::default(),
        );
        let a = article(&page, "part");
        assert!(
            a.contains("badge st-part\">agrees where compared</span>"),
            "{a}"
        );
        assert!(!a.contains(">reproduced<"));
        assert!(a.contains("<li>x.m: L (line 41): not unique &lt;with two outputs&gt;</li>"));
        assert!(a.contains("<td class=\"name\">a_c<span class=\"unit\">1/s</span></td>"));
        assert!(a.contains("<td class=\"name\">K</td>"));
        assert!(page.contains("1 agrees where compared") && page.contains("0 reproduced"));
    }

    #[test]
    fn values_without_book_values_have_no_book_columns() {
        let mut o = ExampleOutput::default();
        o.value("rank", Value::Number(2.0));
        let page = html(
            &[entry("plain", "Part 1 §5.1", Ok(o))],
            &ReportOptions::default(),
        );
        let a = article(&page, "plain");
        assert!(a.contains("<tr><th>value</th><th>pendulab</th></tr>"));
        assert!(!a.contains("<th>book</th>"));
        assert!(
            a.contains("<td class=\"name\">rank</td><td><span class=\"num\">2</span></td></tr>")
        );
        // The table scrolls inside its card, focusable for the keyboard.
        assert!(a.contains(
            "<div class=\"scroll\" tabindex=\"0\" role=\"region\" aria-label=\"values of plain\"><table class=\"values\">"
        ));
        assert!(a.contains("</tbody></table></div>"));
    }

    #[test]
    fn animations_given_as_markup_are_inlined_with_a_player() {
        let mut e = entry("anim", "Part 1 §4.1", Ok(ExampleOutput::default()));
        e.files = ["a.gif", "a.svg", "b.gif", "b.svg"]
            .iter()
            .map(|f| PathBuf::from("figures/anim").join(f))
            .collect();
        let mut opts = ReportOptions::default();
        opts.animations.insert(
            PathBuf::from("figures/anim/a.svg"),
            "<?xml version=\"1.0\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"480\">\
             <animate dur=\"2s\"/></svg>\n"
                .into(),
        );
        let page = html(&[e], &opts);
        let a = article(&page, "anim");
        assert_eq!(a.matches("<div class=\"player\">").count(), 1, "{a}");
        // Inlined without the XML declaration, named for assistive technology.
        assert!(a.contains(
            "<figure class=\"anim\"><div class=\"player\"><div class=\"scroll figscroll\" \
             tabindex=\"0\" role=\"region\" aria-label=\"figure a, at its own size\"><svg \
             role=\"img\" aria-label=\"a\" xmlns=\"http://www.w3.org/2000/svg\" \
             width=\"480\"><animate dur=\"2s\"/></svg></div>"
        ));
        assert!(!a.contains("<?xml"));
        // The controls: a button and a range input, hidden until the script shows them.
        assert!(a.contains("<div class=\"controls\" hidden><button type=\"button\""));
        assert!(a.contains("<input type=\"range\""));
        // Both files of the animation stay linked.
        assert!(a.contains("<a href=\"figures/anim/a.gif\">gif</a>"));
        assert!(a.contains("<a href=\"figures/anim/a.svg\">svg</a>"));
        // Without its markup, the other animation is an image.
        assert!(a.contains("<img src=\"figures/anim/b.svg\""));
        // One script, after the content, driving the SMIL clock.
        assert_eq!(page.matches("<script>").count(), 1);
        assert!(page.find("<script>").unwrap() > page.find("</main>").unwrap());
        assert!(page.contains("setCurrentTime") && page.contains("pauseAnimations"));
    }

    #[test]
    fn figure_width_is_what_the_style_sheet_leaves_for_a_figure() {
        // Column 1180 px with 24 px padding; card: 1 px border, 18 px padding; figure frame:
        // 1 px border, 8 px padding (all border-box).
        for rule in [
            "* { box-sizing: border-box; }",
            "header, main, nav.toc, footer { max-width:1180px; margin:0 auto; padding:0 24px; }",
            "article.example { border:1px solid var(--line); border-radius:8px; padding:16px 18px;",
            "figure { margin:0; flex:0 1 auto; min-width:0; max-width:100%; border:1px solid var(--line); border-radius:6px;\n  padding:8px;",
            "figure img, figure svg { display:block; max-width:100%; height:auto; }",
        ] {
            assert!(STYLE.contains(rule), "{rule}");
        }
        assert_eq!(super::super::FIGURE_WIDTH, 1076.0);
    }

    #[test]
    fn empty_registry_gives_a_valid_page() {
        let page = html(&[], &ReportOptions::default());
        assert!(page.contains("No examples are registered"));
        assert!(page.contains("0 examples"));
    }

    #[test]
    fn href_is_relative_to_the_base_when_possible() {
        assert_eq!(href(Path::new("out/a/b.svg"), Path::new("out")), "a/b.svg");
        assert_eq!(href(Path::new("./out/b.svg"), Path::new("out/")), "b.svg");
        assert_eq!(href(Path::new("b.svg"), Path::new(".")), "b.svg");
        assert_eq!(
            href(Path::new("/tmp/r/f/x#1.png"), Path::new("/tmp/r")),
            "f/x%231.png"
        );
        assert_eq!(
            href(Path::new("/other/x.png"), Path::new("/tmp/r")),
            "/other/x.png"
        );
        assert_eq!(href(Path::new("図.svg"), Path::new(".")), "%E5%9B%B3.svg");
    }
}
