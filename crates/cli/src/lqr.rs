//! `pendulab lqr`: solve an LQ regulator problem given as matrix text files.
//!
//! Matrices are plain text, one row per line, no header: values separated by commas,
//! semicolons, or spaces/tabs (one convention per file), `#` comments, blank lines ignored, a
//! UTF-8 byte-order mark skipped (see [`parse_matrix`]). `Q` and `R` default to identity
//! matrices. The gain is for `u = −K x`. Only LQ problems are answered: an indefinite weight,
//! or a problem whose Hamiltonian has eigenvalues on or numerically near the imaginary axis
//! (unit circle), exits non-zero with the library's message (see
//! `pendulab_lti::design::lqr`).

use anyhow::{Context, Result, anyhow, bail};
use pendulab_lti::design::{Lqr, lqr};
use pendulab_lti::{Mat, StateSpace};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Arguments of `pendulab lqr`.
#[derive(Debug, clap::Args)]
pub struct LqrArgs {
    /// State matrix A (n×n), text (commas, semicolons or whitespace; `#` comments).
    #[arg(long)]
    pub a: PathBuf,
    /// Input matrix B (n×m), text.
    #[arg(long)]
    pub b: PathBuf,
    /// State weight Q (n×n, symmetric), text; identity if omitted.
    #[arg(long)]
    pub q: Option<PathBuf>,
    /// Input weight R (m×m, symmetric positive definite), text; identity if omitted.
    #[arg(long)]
    pub r: Option<PathBuf>,
    /// Cross weight N (n×m), text; zero if omitted.
    #[arg(long)]
    pub n: Option<PathBuf>,
    /// Treat (A, B) as a discrete-time system with this sample time in seconds (solves the
    /// DARE instead of the CARE).
    #[arg(long, value_name = "TS")]
    pub discrete: Option<f64>,
    /// Print one JSON object instead of a human-readable summary.
    #[arg(long)]
    pub json: bool,
}

/// Reads a matrix from a text file (see [`parse_matrix`] for the format).
///
/// # Errors
/// Unreadable file; the errors of [`parse_matrix`], prefixed with the file's path.
pub fn read_matrix(path: &Path) -> Result<Mat> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    parse_matrix(&text).with_context(|| format!("in {}", path.display()))
}

/// How the values of a row are separated; one convention per file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Separator {
    /// `1, 2, 3`
    Comma,
    /// `1; 2; 3`
    Semicolon,
    /// `1 2 3` or `1<TAB>2<TAB>3` (any run of spaces and tabs).
    Whitespace,
}

impl Separator {
    /// The convention of a (comment-free, trimmed, non-empty) line; `None` for a single
    /// value, which fits every convention.
    fn of(line: &str) -> Option<Self> {
        if line.contains(',') {
            Some(Separator::Comma)
        } else if line.contains(';') {
            Some(Separator::Semicolon)
        } else if line.contains(char::is_whitespace) {
            Some(Separator::Whitespace)
        } else {
            None
        }
    }

    fn name(self) -> &'static str {
        match self {
            Separator::Comma => "commas",
            Separator::Semicolon => "semicolons",
            Separator::Whitespace => "spaces/tabs",
        }
    }
}

/// Parses matrix text: one row per line; values separated by commas, semicolons, or spaces
/// and/or tabs — the first row fixes the convention for the whole file, and a row using
/// another one is an error naming its line; spaces around a comma or semicolon are allowed;
/// `#` starts a comment (to the end of the line); blank and comment-only lines are skipped;
/// a leading UTF-8 byte-order mark (Excel's "CSV UTF-8") is skipped. No header.
///
/// # Errors
/// A value that is not a number or not finite, or a row mixing separators (naming line
/// and column, both 1-based; the column counts values); rows of different lengths; no rows.
pub fn parse_matrix(text: &str) -> Result<Mat> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut first_line = 0;
    // The convention and the line that set it (the first row with two or more values).
    let mut convention: Option<(Separator, usize)> = None;
    for (i, raw) in text.lines().enumerate() {
        let lineno = i + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let sep = Separator::of(line);
        if let Some(sep) = sep
            && convention.is_none()
        {
            convention = Some((sep, lineno));
        }
        let expected = convention.map(|(s, _)| s);
        let mixed = |col: usize, found: &str| {
            let (conv, from) = convention.unwrap_or((Separator::Whitespace, lineno));
            anyhow!(
                "line {lineno}, column {col}: values separated by {found}, but the file \
                 separates them by {} (from line {from}); use one separator per file",
                conv.name()
            )
        };
        if let (Some(sep), Some(exp)) = (sep, expected)
            && sep != exp
        {
            return Err(mixed(1, sep.name()));
        }
        let fields: Vec<&str> = match expected {
            Some(Separator::Comma) => line.split(',').collect(),
            Some(Separator::Semicolon) => line.split(';').collect(),
            Some(Separator::Whitespace) => line.split_whitespace().collect(),
            None => vec![line],
        };
        let mut row = Vec::with_capacity(fields.len());
        for (j, field) in fields.iter().enumerate() {
            let col = j + 1;
            let field = field.trim();
            if expected != Some(Separator::Whitespace) && field.contains(char::is_whitespace) {
                return Err(mixed(col, "spaces/tabs inside a field"));
            }
            if expected == Some(Separator::Comma) && field.contains(';') {
                return Err(mixed(col, "semicolons"));
            }
            let v: f64 = field
                .parse()
                .map_err(|_| anyhow!("line {lineno}, column {col}: '{field}' is not a number"))?;
            if !v.is_finite() {
                bail!("line {lineno}, column {col}: value {field} is not finite");
            }
            row.push(v);
        }
        if let Some(first) = rows.first()
            && first.len() != row.len()
        {
            bail!(
                "line {lineno} has {} values, but line {first_line} has {} (ragged rows)",
                row.len(),
                first.len()
            );
        }
        if rows.is_empty() {
            first_line = lineno;
        }
        rows.push(row);
    }
    if rows.is_empty() {
        bail!("no rows (empty file)");
    }
    let (n, m) = (rows.len(), rows[0].len());
    Ok(Mat::from_fn(n, m, |i, j| rows[i][j]))
}

#[derive(Debug, Serialize)]
struct LqrJson {
    gain: Vec<Vec<f64>>,
    riccati: Vec<Vec<f64>>,
    closed_loop_poles: Vec<[f64; 2]>,
    residual: f64,
}

pub(crate) fn rows_of(m: &Mat) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

fn solve(args: &LqrArgs) -> Result<Lqr> {
    let a = read_matrix(&args.a)?;
    let b = read_matrix(&args.b)?;
    if a.nrows() != a.ncols() {
        bail!(
            "A ({}) must be square, found {}x{}",
            args.a.display(),
            a.nrows(),
            a.ncols()
        );
    }
    let (n, m) = (a.nrows(), b.ncols());
    if b.nrows() != n {
        bail!(
            "B ({}) must have {n} rows (as A), found {}x{}",
            args.b.display(),
            b.nrows(),
            b.ncols()
        );
    }
    let q = match &args.q {
        Some(p) => read_matrix(p)?,
        None => Mat::identity(n, n),
    };
    let r = match &args.r {
        Some(p) => read_matrix(p)?,
        None => Mat::identity(m, m),
    };
    let nm = match &args.n {
        Some(p) => Some(read_matrix(p)?),
        None => None,
    };
    for (name, path, mat, shape) in [("Q", &args.q, &q, (n, n)), ("R", &args.r, &r, (m, m))] {
        if mat.shape() != shape {
            bail!(
                "{name} ({}) must be {}x{}, found {}x{}",
                path.as_ref()
                    .map_or("default".into(), |p| p.display().to_string()),
                shape.0,
                shape.1,
                mat.nrows(),
                mat.ncols()
            );
        }
    }
    if let (Some(nm), Some(path)) = (&nm, &args.n)
        && nm.shape() != (n, m)
    {
        bail!(
            "N ({}) must be {n}x{m}, found {}x{}",
            path.display(),
            nm.nrows(),
            nm.ncols()
        );
    }
    let (c, d) = (Mat::zeros(0, n), Mat::zeros(0, m));
    let result = match args.discrete {
        None => lqr(&StateSpace::continuous(a, b, c, d)?, &q, &r, nm.as_ref()),
        Some(ts) => lqr(&StateSpace::discrete(a, b, c, d, ts)?, &q, &r, nm.as_ref()),
    };
    Ok(result?)
}

/// Runs `pendulab lqr`.
///
/// # Errors
/// Bad CSV, shape mismatches and the solver's errors, with a message naming the problem.
pub fn run(args: &LqrArgs) -> Result<()> {
    let sol = solve(args)?;
    if args.json {
        let out = LqrJson {
            gain: rows_of(&sol.gain),
            riccati: rows_of(&sol.riccati),
            closed_loop_poles: sol.closed_loop_poles.iter().map(|p| [p.re, p.im]).collect(),
            residual: sol.residual,
        };
        println!("{}", serde_json::to_string(&out)?);
    } else {
        println!("gain K (u = -K x):");
        for row in rows_of(&sol.gain) {
            println!("  {}", fmt_row(&row));
        }
        println!("Riccati solution X:");
        for row in rows_of(&sol.riccati) {
            println!("  {}", fmt_row(&row));
        }
        println!("closed-loop poles:");
        for p in &sol.closed_loop_poles {
            println!("  {:.10} {:+.10}j", p.re, p.im);
        }
        println!("relative residual: {:e}", sol.residual);
    }
    Ok(())
}

pub(crate) fn fmt_row(row: &[f64]) -> String {
    row.iter()
        .map(|v| format!("{v:>16.10}"))
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_reports_positions() {
        let m = parse_matrix("1, 2\n3,4\n\n").unwrap();
        assert_eq!(m, Mat::from_row_slice(2, 2, &[1.0, 2.0, 3.0, 4.0]));
        let e = parse_matrix("1,2\n3,x\n").unwrap_err().to_string();
        assert!(e.contains("line 2, column 2") && e.contains("'x'"), "{e}");
        let e = parse_matrix("1,2\n3\n").unwrap_err().to_string();
        assert!(e.contains("ragged"), "{e}");
        let e = parse_matrix("1,NaN\n").unwrap_err().to_string();
        assert!(e.contains("not finite"), "{e}");
        assert!(parse_matrix("\n\n").is_err());
        assert!(parse_matrix("1,,2").is_err());
    }

    #[test]
    fn every_separator_convention_reads_the_same_matrix() {
        let want = Mat::from_row_slice(2, 3, &[1.0, -2.5, 3e-3, 4.0, 5.0, 6.0]);
        for text in [
            "1,-2.5,3e-3\n4,5,6\n",
            "1 ; -2.5 ; 3e-3\n4;5;6",
            "1\t-2.5\t3e-3\n4\t5\t6\n",
            "  1   -2.5 3e-3\n4 \t 5  6  \n",
            "\u{feff}# A written by hand\n1, -2.5, 3e-3   # first row\n\n# comment\n4, 5, 6\n",
            "\u{feff}1 -2.5 3e-3\r\n4 5 6\r\n",
        ] {
            assert_eq!(parse_matrix(text).unwrap(), want, "{text:?}");
        }
    }

    #[test]
    fn mixed_separators_name_the_line() {
        for (text, line) in [
            ("1,2\n3;4\n", "line 2"),
            ("1 2\n3,4\n", "line 2"),
            ("# c\n1;2\n\n3 4\n", "line 4"),
            ("1,2\n3 4,5\n", "line 2"),
        ] {
            let e = parse_matrix(text).unwrap_err().to_string();
            assert!(e.contains(line) && e.contains("separat"), "{text:?}: {e}");
        }
        // A BOM is skipped only at the start; a field after it is read, not misnamed.
        let e = parse_matrix("1,x\n").unwrap_err().to_string();
        assert!(e.contains("line 1, column 2") && e.contains("'x'"), "{e}");
    }
}
