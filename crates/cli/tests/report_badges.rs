//! `pendulab report`'s badges and units on real examples: an example that reproduces every
//! number it compares but lists a displayed number it does not compare gets "agrees where
//! compared", never the plain "reproduced", in the page, the contents, the summary and
//! status.md; the units an example states are shown beside its values and in results.jsonl.

mod common;
use common::*;

use serde_json::Value;

/// The `<article>` of example `id` in the page.
fn article<'a>(page: &'a str, id: &str) -> &'a str {
    let start = page
        .find(&format!("<article class=\"example\" id=\"{id}\">"))
        .unwrap_or_else(|| panic!("no article {id}"));
    let end = start + page[start..].find("</article>").unwrap();
    &page[start..end]
}

/// The badge label of the article's heading.
fn badge(article: &str) -> &str {
    let h = &article[..article.find("</h3>").unwrap()];
    let i = h.rfind("<span class=\"badge ").unwrap();
    let rest = &h[i..];
    let j = rest.find('>').unwrap() + 1;
    &rest[j..rest[j..].find('<').unwrap() + j]
}

#[test]
fn uncompared_displayed_numbers_make_the_badge_agrees_where_compared() {
    let d = Dir::new("badges");
    let out = d.join("report");
    // p1c74_ex1: its two-output L is displayed but not comparable (Octave's SLICOT place and
    // MATLAB's KNV give different valid gains); p2c13 nominal: X, L, Kt … are not determined
    // by its objective. p1c511_ex2 compares everything its (symbolic) M-file displays.
    let partly = [
        "p1c74_ex1_cdip_ob_design",
        "p2c13_ex5_adip_oc_nominal_servo",
    ];
    let whole = "p1c511_ex2";
    let mut args = vec!["report", "--out", out.to_str().unwrap()];
    for id in partly.iter().chain([&whole]) {
        args.extend(["--only", id]);
    }
    let o = pendulab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    let status = std::fs::read_to_string(out.join("status.md")).unwrap();
    for id in partly {
        let a = article(&page, id);
        assert_eq!(badge(a), "agrees where compared", "{id}");
        // The list of what is not compared, with the reasons, under the values.
        assert!(
            a.contains("<div class=\"uncompared\"><strong>Not compared</strong>"),
            "{id}"
        );
        let row = status
            .lines()
            .find(|l| l.starts_with(&format!("| `{id}` |")))
            .unwrap();
        assert!(row.ends_with("| agrees where compared |"), "{row}");
        // The contents' badge too.
        let toc = &page[page.find("<nav class=\"toc\"").unwrap()..page.find("</nav>").unwrap()];
        let li = &toc[toc.find(&format!("href=\"#{id}\"")).unwrap()..];
        let li = &li[..li.find("</li>").unwrap()];
        assert!(li.contains(">agrees where compared</span>"), "{li}");
    }
    let a = article(&page, "p1c74_ex1_cdip_ob_design");
    assert!(
        a.contains("L, and Ac, Bc built from it (lines 42-45)"),
        "{a}"
    );
    let w = article(&page, whole);
    assert_eq!(badge(w), "reproduced");
    assert!(!w.contains("class=\"uncompared\""));
    // The summary counts them apart from the reproduced ones.
    assert!(page.contains(">2 agrees where compared</span>"), "summary");
    assert!(page.contains(">1 reproduced</span>"), "summary");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("1 reproduced, 2 agree where compared"),
        "{stdout}"
    );
}

#[test]
fn stated_units_are_in_the_page_and_in_the_json() {
    let d = Dir::new("units");
    let out = d.join("report");
    let ids = [
        "p1c221_id_cart",
        "p1c321_cdip_id_pend",
        "p1c322_cdip_id_least_square",
    ];
    let mut args = vec!["report", "--out", out.to_str().unwrap()];
    for id in ids {
        args.extend(["--only", id]);
    }
    let o = pendulab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let results = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    let lines: Vec<Value> = results
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let units =
        |id: &str| -> Value { lines.iter().find(|l| l["id"] == id).unwrap()["units"].clone() };
    // The cart drive z̈ = −a_c ż + b_c v (book Part 1 §2.2, z in m, v in V): a_c in 1/s,
    // b_c in m/(s²·V); the pendulum's J_p in kg·m², μ_p in kg·m²/s (torque μ_p θ̇ in N·m).
    let u221 = units("p1c221_id_cart");
    assert_eq!(u221["ac"], "1/s");
    assert_eq!(u221["bc"], "m/(s²·V)");
    assert_eq!(u221["Tave"], "s");
    assert_eq!(u221["Kave"], "m/(s·V)");
    let u321 = units("p1c321_cdip_id_pend");
    assert_eq!(u321["Jp"], "kg·m²");
    assert_eq!(u321["mup"], "kg·m²/s");
    assert_eq!(u321["T_average"], "s");
    assert_eq!(u321["omega_n"], "rad/s");
    assert_eq!(u321["lp"], "m");
    // A dimensionless ratio states no unit.
    assert!(u321.get("lambda_average").is_none(), "{u321}");
    let u322 = units("p1c322_cdip_id_least_square");
    assert_eq!(u322["ac"], "1/s");
    assert_eq!(u322["Jp"], "kg·m²");
    // Every unit stated names a value the example reports.
    for l in &lines {
        if let Some(u) = l.get("units").and_then(Value::as_object) {
            for k in u.keys() {
                assert!(
                    l["values"].get(k).is_some(),
                    "{}: unit for unknown {k}",
                    l["id"]
                );
            }
        }
    }
    // The page shows the unit under the value's name.
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    let a = article(&page, "p1c221_id_cart");
    assert!(
        a.contains("<td class=\"name\">bc<span class=\"unit\">m/(s²·V)</span></td>"),
        "{a}"
    );
}
