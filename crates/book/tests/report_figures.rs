//! Every figure the lab report shows, checked on the figure's own layout data (issue 23,
//! item 4): no legend covers a plotted point, every text is at least
//! [`pendulab_plot::MIN_FONT`] (12 px = 9 pt) and the figure fits the page's figure column
//! ([`pendulab_book::report::FIGURE_WIDTH`]), so it is shown at its own size and its text stays
//! at least 9 pt on a wide screen.
//!
//! The examples run in-process with figures, as `pendulab report` runs them; the figures are
//! the [`GraphicKind::Figure`] values the report renders.

use pendulab_book::report::FIGURE_WIDTH;
use pendulab_book::{GraphicKind, RunContext};
use pendulab_plot::MIN_FONT;
use rayon::prelude::*;

/// Every `font-size="…"` of an SVG document, in its user units (= CSS px at the figure's size).
fn font_sizes(svg: &str) -> Vec<f64> {
    svg.split("font-size=\"")
        .skip(1)
        .map(|rest| {
            let v = &rest[..rest.find('"').expect("attribute closed")];
            v.trim_end_matches("px").parse().expect("numeric font size")
        })
        .collect()
}

#[test]
fn font_sizes_are_read_from_the_markup() {
    let svg = r#"<text font-size="12" x="1">a</text><text y="2" font-size="13.5px">b</text>"#;
    assert_eq!(font_sizes(svg), vec![12.0, 13.5]);
}

#[test]
fn every_report_figure_keeps_its_legend_off_the_data_and_its_text_legible() {
    let ctx = RunContext {
        figures: true,
        data_csv: None,
    };
    let problems: Vec<String> = pendulab_book::registry()
        .par_iter()
        .flat_map_iter(|e| {
            let mut found = Vec::new();
            let out = match (e.run)(&ctx) {
                Ok(out) => out,
                // A failing example is the subject of its own tests; it draws nothing here.
                Err(_) => return found,
            };
            for g in &out.figures {
                let GraphicKind::Figure(fig) = &g.kind else {
                    continue;
                };
                let (w, _) = fig.dimensions();
                if w > FIGURE_WIDTH {
                    found.push(format!(
                        "{}: {w} px wide, the page shows at most {FIGURE_WIDTH}",
                        g.stem
                    ));
                }
                match fig.layout() {
                    Ok(panels) => {
                        for (k, p) in panels.iter().enumerate() {
                            let n = p.points_under_legend();
                            if n > 0 {
                                found.push(format!(
                                    "{}: panel {k}: the legend {:?} covers {n} plotted points",
                                    g.stem, p.legend
                                ));
                            }
                        }
                    }
                    Err(err) => found.push(format!("{}: no layout: {err}", g.stem)),
                }
                match fig.to_svg() {
                    Ok(svg) => {
                        let sizes = font_sizes(&svg);
                        let small = sizes.iter().copied().fold(f64::INFINITY, f64::min);
                        if sizes.is_empty() || small < MIN_FONT {
                            found.push(format!(
                                "{}: smallest text {small} px < {MIN_FONT} px",
                                g.stem
                            ));
                        }
                    }
                    Err(err) => found.push(format!("{}: no SVG: {err}", g.stem)),
                }
            }
            found
        })
        .collect();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
