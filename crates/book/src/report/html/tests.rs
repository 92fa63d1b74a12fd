use super::super::tests::example;
use super::figures::href;
use super::*;
use crate::output::Value;
use pendulab_lti::Complex64;
use std::path::Path;

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
    assert!(k.contains(
        "<table class=\"mat\"><tr><td>1</td><td>2</td></tr><tr><td>3</td><td>4</td></tr></table>"
    ));
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
    let bar = &page[page.find("<div class=\"topbar\"").unwrap()..page.find("<header>").unwrap()];
    assert!(bar.contains("href=\"#contents\""), "{bar}");
    assert!(page.contains("<nav class=\"toc\" id=\"contents\""));
    assert!(page.contains("<div class=\"topbar\" id=\"top\"") && page.contains("href=\"#top\""));
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
    assert!(page.contains("1 reproduced") && page.contains("2 runs") && page.contains("0 failing"));
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
    assert!(a.contains("<td class=\"name\">rank</td><td><span class=\"num\">2</span></td></tr>"));
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
