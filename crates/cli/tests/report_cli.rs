//! `pendulab report` end to end: the page, its figure links and the JSON results for the whole
//! registry; the errors for an unwritable directory and bad `--data`/`--only` arguments.

mod common;
use common::*;

use serde_json::Value;
use std::path::{Path, PathBuf};

/// Every value of `attr="..."` in the page.
fn attributes<'a>(page: &'a str, attr: &str) -> Vec<&'a str> {
    let key = format!("{attr}=\"");
    let mut out = Vec::new();
    let mut rest = page;
    while let Some(i) = rest.find(&key) {
        rest = &rest[i + key.len()..];
        let end = rest.find('"').expect("attribute closed");
        out.push(&rest[..end]);
        rest = &rest[end..];
    }
    out
}

/// Undoes the page's percent-encoding of a relative link.
fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).unwrap();
            out.push(u8::from_str_radix(hex, 16).unwrap());
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).unwrap()
}

fn resolve(dir: &Path, link: &str) -> PathBuf {
    let link = percent_decode(link);
    if link.starts_with('/') {
        PathBuf::from(link)
    } else {
        dir.join(link)
    }
}

#[test]
fn report_has_every_example_and_every_figure_link_resolves() {
    let list = pendulab(&["book", "list", "--json"]);
    assert!(list.status.success());
    let ids: Vec<String> = String::from_utf8_lossy(&list.stdout)
        .lines()
        .map(|l| {
            serde_json::from_str::<Value>(l).unwrap()["id"]
                .as_str()
                .unwrap()
                .to_string()
        })
        .collect();

    let d = Dir::new("full");
    let out = d.join("report");
    let o = pendulab(&["report", "--out", out.to_str().unwrap()]);
    let page = std::fs::read_to_string(out.join("index.html")).expect("index.html written");
    assert!(page.starts_with("<!DOCTYPE html>") && page.trim_end().ends_with("</html>"));
    // One article per example, in registry order, each linked from the contents.
    for id in &ids {
        assert!(
            page.contains(&format!("href=\"#{id}\"")),
            "{id} not in contents"
        );
        assert_eq!(
            page.matches(&format!("<article class=\"example\" id=\"{id}\">"))
                .count(),
            1,
            "{id} needs exactly one section"
        );
    }
    assert_eq!(
        page.matches("<article class=\"example\"").count(),
        ids.len()
    );
    // An example whose M-file displays a number it does not compare never has the plain
    // "reproduced" badge: its list of what is not compared is shown, and the badge says it
    // agrees where compared (or differs).
    for id in &ids {
        let start = page
            .find(&format!("<article class=\"example\" id=\"{id}\">"))
            .unwrap();
        let a = &page[start..start + page[start..].find("</article>").unwrap()];
        let heading = &a[..a.find("</h3>").unwrap()];
        let uncompared = a.contains("<div class=\"uncompared\">") || a.contains(". Not compared: ");
        if uncompared {
            assert!(
                !heading.contains("st-ok\">reproduced<"),
                "{id} lists numbers it does not compare but is badged reproduced"
            );
        }
        if heading.contains("st-part\">") {
            assert!(
                a.contains("<div class=\"uncompared\">"),
                "{id}: no list of what is not compared"
            );
        }
    }
    // Every image and link is relative and resolves to a written file in the report
    // directory; every anchor names an element of the page.
    for link in attributes(&page, "src").into_iter().chain(
        attributes(&page, "href")
            .into_iter()
            .filter(|h| !h.starts_with('#')),
    ) {
        assert!(
            !link.starts_with('/') && !link.contains(':') && !link.contains(".."),
            "link {link} leaves the report directory"
        );
        let p = resolve(&out, link);
        assert!(p.is_file(), "broken link {link} -> {}", p.display());
    }
    for anchor in attributes(&page, "href")
        .into_iter()
        .filter_map(|h| h.strip_prefix('#'))
    {
        assert!(
            page.contains(&format!(" id=\"{anchor}\"")),
            "#{anchor} names no element"
        );
    }
    // results.jsonl: one line per example with the contract's keys; failures there match the
    // exit code.
    let results = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    // No absolute path anywhere: the directory can be moved whole.
    let dir = d.join("");
    let dir = dir.to_str().unwrap().trim_end_matches('/');
    assert!(!page.contains(dir), "index.html names {dir}");
    assert!(!results.contains(dir), "results.jsonl names {dir}");
    let lines: Vec<Value> = results
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(
        lines
            .iter()
            .map(|l| l["id"].as_str().unwrap())
            .collect::<Vec<_>>(),
        ids.iter().map(String::as_str).collect::<Vec<_>>()
    );
    // Each figure path is relative to the report directory and names a written file.
    for l in &lines {
        for f in l["figures"].as_array().unwrap() {
            let f = f.as_str().unwrap();
            let id = l["id"].as_str().unwrap();
            assert!(
                f.starts_with(&format!("figures/{id}/")),
                "{id}: figure path {f}"
            );
            assert!(out.join(f).is_file(), "{f} not written");
        }
    }
    // status.md: the README table, a header, a rule and one row per example.
    let status = std::fs::read_to_string(out.join("status.md")).unwrap();
    assert_eq!(status.lines().count(), ids.len() + 2, "{status}");
    for id in &ids {
        assert!(
            status.contains(&format!("| `{id}` |")),
            "{id} not in status.md"
        );
    }
    let failing = lines.iter().filter(|l| l.get("error").is_some()).count();
    assert_eq!(o.status.success(), failing == 0, "{}", stderr(&o));
    assert!(
        page.contains(&format!("{failing} failing")),
        "page counts {failing} failing"
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains(&format!("{} examples", ids.len())),
        "{stdout}"
    );
}

#[test]
fn only_replaces_the_figure_folders_of_the_examples_it_runs() {
    let d = Dir::new("only");
    let out = d.join("report");
    let figures = out.join("figures");
    // What an earlier report may have left: a figure the example no longer draws, and another
    // example's folder.
    let id = "p1c41_cdip_response";
    for (dir, name) in [(id, "renamed_since.svg"), ("p1c511_ex1", "kept.svg")] {
        std::fs::create_dir_all(figures.join(dir)).unwrap();
        std::fs::write(figures.join(dir).join(name), "<svg/>").unwrap();
    }
    let o = pendulab(&["report", "--out", out.to_str().unwrap(), "--only", id]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut written: Vec<String> = std::fs::read_dir(figures.join(id))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert!(!written.is_empty());
    assert!(
        !written.iter().any(|f| f == "renamed_since.svg"),
        "stale figure kept: {written:?}"
    );
    // Exactly the files results.jsonl lists are in the folder.
    let results = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    let line: Value = serde_json::from_str(results.lines().next().unwrap()).unwrap();
    let mut listed: Vec<String> = line["figures"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap().rsplit('/').next().unwrap().to_string())
        .collect();
    listed.sort();
    assert_eq!(written, listed);
    // Another example's folder is not the run's business.
    assert!(figures.join("p1c511_ex1/kept.svg").is_file());
}

#[test]
fn unwritable_report_directory_is_a_clear_error() {
    let d = Dir::new("unwritable");
    let file = d.file("plain-file", "x");
    fails_with(
        &pendulab(&["report", "--out", &format!("{file}/report")]),
        &["cannot create output directory"],
    );
}

#[test]
fn bad_data_and_only_arguments_are_clear_errors() {
    let d = Dir::new("args");
    let out = d.join("r");
    let out = out.to_str().unwrap();
    let good = d.file("good.csv", "t,theta\n0,0.1\n");
    // The report takes data only as ID=FILE: with many examples a bare file is ambiguous.
    fails_with(
        &pendulab(&["report", "--out", out, "--data", &good]),
        &["expected ID=FILE"],
    );
    fails_with(
        &pendulab(&[
            "report",
            "--out",
            out,
            "--data",
            &format!("no_such_example={good}"),
        ]),
        &["unknown example id 'no_such_example'"],
    );
    fails_with(
        &pendulab(&["report", "--out", out, "--only", "no_such_example"]),
        &["unknown example id 'no_such_example'"],
    );
    // Nothing was written for a rejected command line.
    assert!(!Path::new(out).join("index.html").exists());
}

#[test]
fn web_lab_is_copied_beside_the_page_and_linked_relatively() {
    let d = Dir::new("weblab");
    // A site as tools/build-web lays it out: the page, its scripts and a nested folder.
    let site = d.join("site");
    std::fs::create_dir_all(site.join("assets")).unwrap();
    std::fs::write(site.join("index.html"), "<!DOCTYPE html><title>lab</title>").unwrap();
    std::fs::write(site.join("lab.js"), "// lab").unwrap();
    std::fs::write(site.join("assets/x.css"), "body{}").unwrap();
    let out = d.join("report");
    // An earlier copy's stray file goes.
    std::fs::create_dir_all(out.join("lab")).unwrap();
    std::fs::write(out.join("lab/stale.js"), "// old").unwrap();
    let o = pendulab(&[
        "report",
        "--out",
        out.to_str().unwrap(),
        "--only",
        "p1c41_cdip_response",
        "--web-lab",
        site.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in ["index.html", "lab.js", "assets/x.css"] {
        assert_eq!(
            std::fs::read(out.join("lab").join(f)).unwrap(),
            std::fs::read(site.join(f)).unwrap(),
            "{f}"
        );
    }
    assert!(!out.join("lab/stale.js").exists());
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    let hrefs = attributes(&page, "href");
    assert!(hrefs.contains(&"lab/index.html"), "{hrefs:?}");
    for h in hrefs.iter().filter(|h| !h.starts_with('#')) {
        assert!(resolve(&out, h).is_file(), "{h} does not resolve");
    }

    // A folder without the page is refused before anything runs.
    let empty = d.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let out2 = d.join("report2");
    fails_with(
        &pendulab(&[
            "report",
            "--out",
            out2.to_str().unwrap(),
            "--web-lab",
            empty.to_str().unwrap(),
        ]),
        &["--web-lab", "no index.html", "tools/build-web"],
    );
    assert!(!out2.join("index.html").exists());
}
