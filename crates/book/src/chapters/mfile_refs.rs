//! The numbers the book's M-files display, as references beside pendulab's.
//!
//! The M-files run with `format compact` in MATLAB's short format, and the book prints what
//! that display shows. The M-files that need neither Simulink nor YALMIP (or the part of them
//! before the first Simulink run) were run unchanged in GNU Octave 7.3.0 with its control
//! package 3.4.0 (`tools/reference/book_mfiles_octave.sh`; the displays are committed in
//! `crates/book/tests/data/octave/`, in `format long g`). Each displayed number is compared
//! to the digits MATLAB's short format prints ([`short_half_unit`]); a number the M-file
//! prints with `fprintf` (`%5.2e`, …) to half a unit of its last printed digit. Every example
//! that compares says in one note which displayed numbers it compares and which it cannot,
//! and why ([`display_note`]).

use super::common::{fail, sorted};
use crate::error::BookError;
use crate::output::{ExampleOutput, Uncompared, Value};
use pendulab_lti::Complex64;

/// Where the displays come from, for the references' sources.
const OCTAVE: &str =
    "run in GNU Octave 7.3.0 + control 3.4.0 (tools/reference/book_mfiles_octave.sh)";

/// Half a unit in the last digit MATLAB's `format short` prints for an array whose largest
/// magnitude is `max_abs`: four decimals, after the common scale factor `10^k`
/// (`k = ⌊log10 max_abs⌋`) that the format takes out when the largest magnitude is ≥ 1000 or
/// below 0.001 (a scalar 3899.4 prints as `3.8994e+03`: half a unit is 0.05).
pub(crate) fn short_half_unit(max_abs: f64) -> f64 {
    let scale = if max_abs >= 1000.0 || (max_abs > 0.0 && max_abs < 1e-3) {
        10f64.powi(max_abs.log10().floor() as i32)
    } else {
        1.0
    };
    0.5e-4 * scale
}

/// Largest magnitude of the elements of a value (0 for a boolean).
pub(crate) fn max_abs(v: &Value) -> f64 {
    let m = |it: &mut dyn Iterator<Item = f64>| it.fold(0.0, |a: f64, x| a.max(x.abs()));
    match v {
        Value::Bool(_) => 0.0,
        Value::Number(x) => x.abs(),
        Value::Vector(v) => m(&mut v.iter().copied()),
        Value::Matrix(r) => m(&mut r.iter().flatten().copied()),
        Value::Complex(c) => m(&mut c.iter().map(|z| z.norm())),
    }
}

/// One displayed number (scalar, row, column or matrix) of an M-file's run.
#[derive(Debug, Clone)]
pub(crate) struct Displayed {
    /// The M-file's variable name (`ans` for an expression; `fprintf` labels without spaces).
    pub(crate) name: String,
    /// The value; a column of complex numbers (eigenvalues) is [`Value::Complex`].
    pub(crate) value: Value,
    /// Half a unit of the last printed digit when the M-file printed it with `fprintf` in
    /// `e` format (`None`: a `format long g` display, compared to MATLAB's short format).
    pub(crate) printed_half_unit: Option<f64>,
}

impl Displayed {
    /// The tolerance of a comparison with this number: half a unit of the digits the M-file's
    /// display prints (its `fprintf` format, or MATLAB's short format), and 1e-9 of that half
    /// unit more, for a value that lies on a rounding boundary up to floating-point noise.
    pub(crate) fn tolerance(&self) -> f64 {
        self.printed_half_unit
            .unwrap_or_else(|| short_half_unit(max_abs(&self.value)))
            * (1.0 + 1e-9)
    }
}

/// A number token of an Octave display, with half a unit of its last digit when it is written
/// in `e` format with at most six decimals (an `fprintf` value).
fn number(token: &str) -> Option<(f64, Option<f64>)> {
    let x: f64 = token.parse().ok()?;
    let half = token
        .to_ascii_lowercase()
        .split_once('e')
        .and_then(|(m, e)| {
            let decimals = m.split_once('.').map_or(0, |(_, d)| d.len());
            let e: i32 = e.parse().ok()?;
            (decimals <= 6).then(|| 0.5 * 10f64.powi(e - decimals as i32))
        });
    Some((x, half))
}

/// The numbers of one row of an Octave display: reals, or complex `a + bi` / `a - bi`
/// written as three tokens.
fn row_numbers(line: &str) -> Option<Vec<Complex64>> {
    let tokens: Vec<&str> = line.split_whitespace().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < tokens.len() {
        let (re, _) = number(tokens[i])?;
        if tokens.get(i + 1).is_some_and(|s| *s == "+" || *s == "-")
            && tokens.get(i + 2).is_some_and(|s| s.ends_with('i'))
        {
            let (im, _) = number(tokens[i + 2].trim_end_matches('i'))?;
            let im = if tokens[i + 1] == "-" { -im } else { im };
            out.push(Complex64::new(re, im));
            i += 3;
        } else {
            out.push(Complex64::new(re, 0.0));
            i += 1;
        }
    }
    (!out.is_empty()).then_some(out)
}

/// A block of rows as a value: a scalar, a row or a column ([`Value::Vector`]), a matrix, or
/// [`Value::Complex`] when any element is complex.
fn block_value(rows: &[Vec<Complex64>]) -> Value {
    let complex = rows.iter().flatten().any(|z| z.im != 0.0);
    let (nr, nc) = (rows.len(), rows[0].len());
    if complex {
        return Value::Complex(rows.iter().flatten().copied().collect());
    }
    let re = |r: &Vec<Complex64>| r.iter().map(|z| z.re).collect::<Vec<f64>>();
    match (nr, nc) {
        (1, 1) => Value::Number(rows[0][0].re),
        (1, _) => Value::Vector(re(&rows[0])),
        (_, 1) => Value::Vector(rows.iter().map(|r| r[0].re).collect()),
        _ => Value::Matrix(rows.iter().map(re).collect()),
    }
}

/// The second-order transfer function `num/(s^2 + a s + b)` an M-file displays (Octave's
/// `tf` display, four significant digits): `(num, a, b)`.
pub(crate) fn displayed_tf2(text: &str) -> Option<(f64, f64, f64)> {
    let lines: Vec<&str> = text.lines().collect();
    let k = lines.iter().position(|l| l.contains("s^2 +"))?;
    let den: Vec<f64> = lines[k]
        .split_whitespace()
        .filter_map(|w| w.parse().ok())
        .collect();
    let num: f64 = lines.get(k.checked_sub(2)?)?.trim().parse().ok()?;
    Some((num, *den.first()?, *den.get(1)?))
}

/// What one M-file displayed when run in Octave, in display order.
#[derive(Debug, Clone)]
pub(crate) struct OctaveDisplay {
    /// The M-file's stem.
    pub(crate) stem: String,
    /// The displayed numbers.
    pub(crate) items: Vec<Displayed>,
}

impl OctaveDisplay {
    /// Reads an Octave display: `name = value` lines (several per line when separated by
    /// tabs, as the M-files' `fprintf` tables print them; spaces in the name dropped, so
    /// `T 1` is `T1`) and `name =` followed by the rows of an array.
    pub(crate) fn parse(stem: &str, text: &str) -> Self {
        let lines: Vec<&str> = text.lines().collect();
        let mut items = Vec::new();
        let mut k = 0;
        while k < lines.len() {
            let line = lines[k];
            k += 1;
            let trimmed = line.trim_end();
            if let Some(name) = trimmed.strip_suffix(" =") {
                let name = name.trim();
                if name.is_empty() || name.contains(char::is_whitespace) {
                    continue;
                }
                while k < lines.len() && lines[k].trim().is_empty() {
                    k += 1;
                }
                let mut rows = Vec::new();
                while k < lines.len() {
                    match row_numbers(lines[k]) {
                        Some(r) if rows.is_empty() || r.len() == rows_len(&rows) => {
                            rows.push(r);
                            k += 1;
                        }
                        _ => break,
                    }
                }
                if !rows.is_empty() {
                    items.push(Displayed {
                        name: name.to_string(),
                        value: block_value(&rows),
                        printed_half_unit: None,
                    });
                }
                continue;
            }
            for item in line.split('\t') {
                let Some((name, value)) = item.split_once(" = ") else {
                    continue;
                };
                let name: String = name.chars().filter(|c| !c.is_whitespace()).collect();
                if name.is_empty() {
                    continue;
                }
                let Some(r) = row_numbers(value) else {
                    continue;
                };
                let half = number(value.trim()).and_then(|(_, h)| h);
                items.push(Displayed {
                    name,
                    value: block_value(&[r]),
                    printed_half_unit: half,
                });
            }
        }
        Self {
            stem: stem.to_string(),
            items,
        }
    }

    /// The first displayed number called `name`; `name#k` is its `k`-th display.
    ///
    /// # Errors
    /// [`BookError::Computation`] of example `id` when the display has no such number.
    pub(crate) fn get(&self, id: &str, name: &str) -> Result<&Displayed, BookError> {
        // `K#2`: the second display of `K` (an M-file that displays a gain per weight).
        let (base, nth) = match name.split_once('#') {
            Some((b, n)) => (b, n.parse::<usize>().unwrap_or(1).max(1)),
            None => (name, 1),
        };
        self.items
            .iter()
            .filter(|d| d.name == base)
            .nth(nth - 1)
            .ok_or_else(|| {
                fail(
                    id,
                    format!("{}.m's committed display has no number {name}", self.stem),
                )
            })
    }

    /// The numbers `prefix1`, `prefix2`, … a `fprintf` loop printed, as one row (the
    /// M-file's vector `prefix`), with the largest of their printing tolerances.
    ///
    /// # Errors
    /// [`BookError::Computation`] of example `id` when there is no `prefix1`.
    pub(crate) fn indexed(&self, id: &str, prefix: &str) -> Result<Displayed, BookError> {
        let mut v = Vec::new();
        let mut half: f64 = 0.0;
        while let Some(d) = self
            .items
            .iter()
            .find(|d| d.name == format!("{prefix}{}", v.len() + 1))
        {
            let Value::Number(x) = d.value else { break };
            v.push(x);
            half = half.max(d.tolerance());
        }
        if v.is_empty() {
            return Err(fail(
                id,
                format!("{}.m's committed display has no {prefix}1", self.stem),
            ));
        }
        Ok(Displayed {
            name: prefix.to_string(),
            value: Value::Vector(v),
            printed_half_unit: Some(half),
        })
    }

    /// The reference source of a number displayed at `line` of the M-file.
    pub(crate) fn source(&self, line: &str) -> String {
        format!("{}.m {line}, {OCTAVE}", self.stem)
    }

    /// Adds the displayed `theirs` (printed at `line` of the M-file) as the reference of
    /// pendulab's value `ours`, to the digits the display prints; complex lists are compared
    /// sorted (pendulab reports poles sorted the same way).
    ///
    /// # Errors
    /// As [`OctaveDisplay::get`].
    pub(crate) fn compare(
        &self,
        id: &str,
        out: &mut ExampleOutput,
        ours: &str,
        theirs: &str,
        line: &str,
    ) -> Result<(), BookError> {
        let d = self.get(id, theirs)?;
        let tol = d.tolerance();
        self.compare_within(id, out, ours, theirs, line, tol)
    }

    /// As [`OctaveDisplay::compare`] with the stated absolute tolerance `tol` (the caller
    /// names and justifies a tolerance looser than the printed digits in a note).
    ///
    /// # Errors
    /// As [`OctaveDisplay::get`].
    pub(crate) fn compare_within(
        &self,
        id: &str,
        out: &mut ExampleOutput,
        ours: &str,
        theirs: &str,
        line: &str,
        tol: f64,
    ) -> Result<(), BookError> {
        let d = self.get(id, theirs)?;
        let value = match (&d.value, out.get(ours)) {
            (Value::Complex(c), _) => Value::Complex(sorted(c.clone())),
            // A displayed scalar that pendulab reports as a one-element row.
            (Value::Number(x), Some(Value::Vector(v))) if v.len() == 1 => Value::Vector(vec![*x]),
            (v, _) => v.clone(),
        };
        let shown = if ours == theirs {
            String::new()
        } else {
            format!(" ({theirs})")
        };
        out.reference(ours, value, &self.source(&format!("{line}{shown}")), tol);
        Ok(())
    }
}

fn rows_len(rows: &[Vec<Complex64>]) -> usize {
    rows[0].len()
}

/// The note that lists what an M-file displays: the numbers compared with pendulab's (each a
/// reference of the example), the displayed numbers that are not (each with the reason; they
/// also go to [`ExampleOutput::uncompared`], so the example's badge says it agrees only where
/// compared), and what the M-file shows that is not a displayed number of its own
/// (`not_numbers`: responses it only draws, a number it displays again that is compared under
/// another name), each with the reason.
pub(crate) fn display_note(
    out: &mut ExampleOutput,
    stem: &str,
    compared: &[&str],
    not_compared: &[(&str, &str)],
    not_numbers: &[(&str, &str)],
) {
    let list = |items: &[(&str, &str)]| {
        items
            .iter()
            .map(|(what, why)| format!("{what} ({why})"))
            .collect::<Vec<_>>()
            .join("; ")
    };
    let mut s = format!("{stem}.m displays ");
    if compared.is_empty() {
        s.push_str("no number that can be compared");
    } else {
        s.push_str(&format!(
            "{}: compared to its printed digits",
            compared.join(", ")
        ));
    }
    if !not_compared.is_empty() {
        s.push_str(". Not compared: ");
        s.push_str(&list(not_compared));
    }
    if !not_numbers.is_empty() {
        s.push_str(". Not a displayed number of its own: ");
        s.push_str(&list(not_numbers));
    }
    s.push('.');
    out.notes.push(s);
    out.uncompared
        .extend(not_compared.iter().map(|(what, why)| Uncompared {
            what: format!("{stem}.m: {what}"),
            why: (*why).to_string(),
        }));
}

/// The note of an example whose M-file derives equations with the Symbolic Math Toolbox:
/// what it derives (`derives`; its display is formulas, not numbers to compare digit by
/// digit) and how pendulab checks the same equations (`checks`).
pub(crate) fn symbolic_note(out: &mut ExampleOutput, stem: &str, derives: &str, checks: &str) {
    out.notes.push(format!(
        "{stem}.m is symbolic (Symbolic Math Toolbox): it derives {derives}. Its display is \
         formulas, not numbers to compare digit by digit. pendulab checks the same equations \
         {checks}."
    ));
}

/// The note of an example whose M-file displays no number: what it shows instead (`shows`).
pub(crate) fn no_display_note(out: &mut ExampleOutput, stem: &str, shows: &str) {
    out.notes.push(format!(
        "{stem}.m displays no number ({shows}): there is no displayed value of the M-file to \
         compare."
    ));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_format_digits_follow_matlab_scale_factor() {
        assert_eq!(short_half_unit(539.4), 0.5e-4);
        assert!((short_half_unit(3899.4) - 0.05).abs() < 1e-15);
        assert!((short_half_unit(2.3e-4) - 0.5e-8).abs() < 1e-20);
    }

    #[test]
    fn reads_scalars_arrays_complex_and_fprintf_values() {
        let text = "A =\n                       1                     2.5\n                       3                       4\n\nb =                3\nz =\n                    -0.5 +      1.322875655532295i\n                    -0.5 -      1.322875655532295i\n\nT 1 = 1.112e+00\tlambda 1 = 9.823e-01\n";
        let d = OctaveDisplay::parse("x", text);
        let names: Vec<&str> = d.items.iter().map(|i| i.name.as_str()).collect();
        assert_eq!(names, ["A", "b", "z", "T1", "lambda1"]);
        assert_eq!(
            d.items[0].value,
            Value::Matrix(vec![vec![1.0, 2.5], vec![3.0, 4.0]])
        );
        assert_eq!(d.items[1].value, Value::Number(3.0));
        let Value::Complex(z) = &d.items[2].value else {
            panic!()
        };
        assert_eq!(z[1], Complex64::new(-0.5, -1.322875655532295));
        assert!((d.items[3].tolerance() - 0.5e-3).abs() < 1e-11);
        assert!((d.items[4].tolerance() - 0.5e-4).abs() < 1e-12);
    }
}
