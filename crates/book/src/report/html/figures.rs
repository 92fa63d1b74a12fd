//! The report's figures: each example's figure files grouped by stem, one `<figure>` a group
//! (SVG inlined, raster images linked), other files as links, and the relative, percent-encoded
//! links themselves.

use super::super::ReportOptions;
use super::super::format::escape;
use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

/// Kinds of figure files, in the order of preference for display.
const SHOWN: [&str; 6] = ["svg", "png", "gif", "jpg", "jpeg", "webp"];

/// Figures grouped by stem, one `<figure>` per group; other files as links.
pub(super) fn figures_html(s: &mut String, figures: &[PathBuf], options: &ReportOptions) {
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
pub(super) fn extension(p: &Path) -> String {
    p.extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default()
}

/// Drops `.` components, so `./out/a.svg` and `out/a.svg` compare equal.
pub(super) fn clean(p: &Path) -> PathBuf {
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
