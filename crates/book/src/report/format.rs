//! Plain-text and HTML formatting of numbers and [`Value`]s for the report.

use crate::output::Value;
use pendulab_lti::Complex64;

/// Significant digits shown for a real number: enough for every value the book prints (the
/// longest have seven, e.g. the gain `13.47175`).
const SIGNIFICANT: i32 = 7;

/// Formats a real number with seven significant digits, trailing zeros removed.
///
/// Plain decimal notation for magnitudes in [1e-4, 1e6); otherwise scientific notation with a
/// mantissa of up to seven significant digits (`1.59e-9`). `NaN` and infinities are written as
/// `NaN`, `inf`, `-inf`.
pub fn number(x: f64) -> String {
    number_sig(x, SIGNIFICANT)
}

/// Formats a real number with `significant` (≥ 1) significant digits, as [`number`] does.
pub fn number_sig(x: f64, significant: i32) -> String {
    let significant = significant.max(1);
    if x.is_nan() {
        return "NaN".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf".into() } else { "-inf".into() };
    }
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    if (1e-4..1e6).contains(&a) {
        let exponent = a.log10().floor() as i32;
        let decimals = (significant - 1 - exponent).max(0) as usize;
        let s = format!("{x:.decimals$}");
        // Rounding may carry into a new digit (999999.7 -> "1000000"); that is still exact to
        // the shown digits, so keep it.
        trim_zeros(&s)
    } else {
        let s = format!("{:.*e}", (significant - 1) as usize, x);
        match s.split_once('e') {
            Some((mantissa, exp)) => format!("{}e{exp}", trim_zeros(mantissa)),
            None => s,
        }
    }
}

/// Removes trailing zeros after a decimal point, and the point itself if nothing follows.
fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

/// Formats one complex number as `re + im j` / `re - im j` (`re` alone when `im == 0`).
pub fn complex(z: Complex64) -> String {
    if z.im == 0.0 {
        return number(z.re);
    }
    let sign = if z.im < 0.0 { '-' } else { '+' };
    format!("{} {sign} {}j", number(z.re), number(z.im.abs()))
}

/// Whether `b` is the complex conjugate of `a` to rounding (relative 1e-12 of their size).
fn conjugates(a: Complex64, b: Complex64) -> bool {
    let scale = a.norm().max(b.norm()).max(f64::MIN_POSITIVE);
    a.im != 0.0 && (a.re - b.re).abs() <= 1e-12 * scale && (a.im + b.im).abs() <= 1e-12 * scale
}

/// Formats a list of complex numbers, writing each conjugate pair that appears next to each
/// other once as `re ± |im| j`.
pub fn complex_list(zs: &[Complex64]) -> Vec<String> {
    let mut out = Vec::with_capacity(zs.len());
    let mut i = 0;
    while i < zs.len() {
        if i + 1 < zs.len() && conjugates(zs[i], zs[i + 1]) {
            out.push(format!(
                "{} ± {}j",
                number(zs[i].re),
                number(zs[i].im.abs())
            ));
            i += 2;
        } else {
            out.push(complex(zs[i]));
            i += 1;
        }
    }
    out
}

/// One-line plain-text form of a value: `true`, `3.125`, `[1, 2]`, `[[1, 0], [0, 1]]`,
/// `[-3.125 ± 5.817j, -1]`.
pub fn value_text(v: &Value) -> String {
    fn list(xs: &[f64]) -> String {
        format!(
            "[{}]",
            xs.iter().map(|&x| number(x)).collect::<Vec<_>>().join(", ")
        )
    }
    match v {
        Value::Bool(b) => b.to_string(),
        Value::Number(x) => number(*x),
        Value::Vector(xs) => list(xs),
        Value::Matrix(rows) => format!(
            "[{}]",
            rows.iter().map(|r| list(r)).collect::<Vec<_>>().join(", ")
        ),
        Value::Complex(zs) => format!("[{}]", complex_list(zs).join(", ")),
    }
}

/// Escapes text for HTML element content and attribute values (`&`, `<`, `>`, `"`, `'`).
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// HTML form of a value: matrices as a bracketed grid (a `<table class="mat">`), vectors and
/// complex lists as a bracketed row whose entries wrap when space is short
/// (`<span class="vec">`, one `<span>` per entry), scalars as text.
pub fn value_html(v: &Value) -> String {
    fn grid<R: AsRef<[String]>>(rows: &[R]) -> String {
        let mut s = String::from("<table class=\"mat\">");
        for r in rows {
            s.push_str("<tr>");
            for c in r.as_ref() {
                s.push_str("<td>");
                s.push_str(&escape(c));
                s.push_str("</td>");
            }
            s.push_str("</tr>");
        }
        s.push_str("</table>");
        s
    }
    // A row vector in brackets whose entries wrap onto further lines when the column is
    // narrow (a long vector does not widen its table).
    fn row(cells: &[String]) -> String {
        let mut s = String::from("<span class=\"vec\">");
        for c in cells {
            s.push_str("<span>");
            s.push_str(&escape(c));
            s.push_str("</span>");
        }
        s.push_str("</span>");
        s
    }
    match v {
        Value::Bool(b) => format!("<span class=\"num\">{b}</span>"),
        Value::Number(x) => format!("<span class=\"num\">{}</span>", escape(&number(*x))),
        Value::Vector(xs) if xs.is_empty() => "<span class=\"num\">[]</span>".into(),
        Value::Vector(xs) => row(&xs.iter().map(|&x| number(x)).collect::<Vec<_>>()),
        Value::Matrix(rows) if rows.iter().all(|r| r.is_empty()) => {
            "<span class=\"num\">[]</span>".into()
        }
        Value::Matrix(rows) => grid(
            &rows
                .iter()
                .map(|r| r.iter().map(|&x| number(x)).collect::<Vec<_>>())
                .collect::<Vec<_>>(),
        ),
        Value::Complex(zs) if zs.is_empty() => "<span class=\"num\">[]</span>".into(),
        Value::Complex(zs) => row(&complex_list(zs)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_seven_significant_digits_and_drop_trailing_zeros() {
        // Book-printed values must survive formatting digit for digit.
        assert_eq!(number(3.16228), "3.16228");
        assert_eq!(number(13.47175), "13.47175");
        assert_eq!(number(-0.0220), "-0.022");
        assert_eq!(number(-3.125), "-3.125");
        assert_eq!(number(3583.7), "3583.7");
        assert_eq!(number(236.0), "236");
        assert_eq!(number(2.35e-4), "0.000235");
        assert_eq!(number(1.59e-3), "0.00159");
        assert_eq!(number(0.0), "0");
        // Rounded to seven significant digits.
        assert_eq!(number(std::f64::consts::PI), "3.141593");
        assert_eq!(number(-1.0 / 3.0), "-0.3333333");
        // Outside [1e-4, 1e6): scientific.
        assert_eq!(number(1.5e-9), "1.5e-9");
        assert_eq!(number(-4.0e7), "-4e7");
        assert_eq!(number(6.02214076e23), "6.022141e23");
        assert_eq!(number(f64::NAN), "NaN");
        assert_eq!(number(f64::NEG_INFINITY), "-inf");
        // Differences and tolerances are shown to two digits.
        assert_eq!(number_sig(0.0002676699, 2), "0.00027");
        assert_eq!(number_sig(0.0007071068, 2), "0.00071");
        assert_eq!(number_sig(3.0e-12, 2), "3e-12");
        assert_eq!(number_sig(0.05, 2), "0.05");
    }

    #[test]
    fn conjugate_pairs_are_written_once() {
        let zs = [
            Complex64::new(-3.125, 5.817),
            Complex64::new(-3.125, -5.817),
            Complex64::new(-1.843, 0.0),
            Complex64::new(0.5, -2.0),
        ];
        assert_eq!(
            complex_list(&zs),
            vec!["-3.125 ± 5.817j", "-1.843", "0.5 - 2j"]
        );
        assert_eq!(
            value_text(&Value::Complex(zs.to_vec())),
            "[-3.125 ± 5.817j, -1.843, 0.5 - 2j]"
        );
        // Not conjugates (different real parts): both written.
        let zs = [Complex64::new(1.0, 1.0), Complex64::new(2.0, -1.0)];
        assert_eq!(complex_list(&zs), vec!["1 + 1j", "2 - 1j"]);
    }

    #[test]
    fn matrices_and_vectors_format_as_grids_and_text() {
        let m = Value::Matrix(vec![vec![1.0, 0.5], vec![-2.25, 1e-9]]);
        assert_eq!(value_text(&m), "[[1, 0.5], [-2.25, 1e-9]]");
        assert_eq!(
            value_html(&m),
            "<table class=\"mat\"><tr><td>1</td><td>0.5</td></tr>\
             <tr><td>-2.25</td><td>1e-9</td></tr></table>"
        );
        assert_eq!(value_text(&Value::Vector(vec![3.0, 12.5])), "[3, 12.5]");
        assert_eq!(
            value_html(&Value::Vector(vec![3.0, -12.5])),
            "<span class=\"vec\"><span>3</span><span>-12.5</span></span>"
        );
        assert_eq!(value_text(&Value::Bool(false)), "false");
        assert_eq!(
            value_html(&Value::Vector(vec![])),
            "<span class=\"num\">[]</span>"
        );
    }

    #[test]
    fn escape_covers_markup_and_quotes() {
        assert_eq!(
            escape(r#"<a href="x">'&'</a>"#),
            "&lt;a href=&quot;x&quot;&gt;&#39;&amp;&#39;&lt;/a&gt;"
        );
    }
}
