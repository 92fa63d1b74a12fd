//! `pendulab lqr`: solve an LQ regulator problem given as CSV matrices.
//!
//! Matrices are plain CSV: one row per line, values separated by commas, no header; blank
//! lines are ignored. `Q` and `R` default to identity matrices. The gain is for
//! `u = −K x`.

use anyhow::{Context, Result, anyhow, bail};
use pendulab_lti::design::{Lqr, lqr};
use pendulab_lti::{Mat, StateSpace};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Arguments of `pendulab lqr`.
#[derive(Debug, clap::Args)]
pub struct LqrArgs {
    /// State matrix A (n×n), CSV.
    #[arg(long)]
    pub a: PathBuf,
    /// Input matrix B (n×m), CSV.
    #[arg(long)]
    pub b: PathBuf,
    /// State weight Q (n×n, symmetric), CSV; identity if omitted.
    #[arg(long)]
    pub q: Option<PathBuf>,
    /// Input weight R (m×m, symmetric positive definite), CSV; identity if omitted.
    #[arg(long)]
    pub r: Option<PathBuf>,
    /// Cross weight N (n×m), CSV; zero if omitted.
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

/// Reads a matrix from a plain CSV file (one row per line, comma-separated, no header).
///
/// # Errors
/// Unreadable file; a value that is not a number or not finite (naming line and column,
/// 1-based); rows of different lengths; an empty file.
pub fn read_matrix(path: &Path) -> Result<Mat> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    parse_matrix(&text).with_context(|| format!("in {}", path.display()))
}

/// Parses CSV text into a matrix (see [`read_matrix`]).
///
/// # Errors
/// As [`read_matrix`].
pub fn parse_matrix(text: &str) -> Result<Mat> {
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut first_line = 0;
    for (i, line) in text.lines().enumerate() {
        let lineno = i + 1;
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let mut row = Vec::new();
        for (j, field) in line.split(',').enumerate() {
            let field = field.trim();
            let v: f64 = field.parse().map_err(|_| {
                anyhow!("line {lineno}, column {}: '{field}' is not a number", j + 1)
            })?;
            if !v.is_finite() {
                bail!(
                    "line {lineno}, column {}: value {field} is not finite",
                    j + 1
                );
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

fn rows_of(m: &Mat) -> Vec<Vec<f64>> {
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

fn fmt_row(row: &[f64]) -> String {
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
}
