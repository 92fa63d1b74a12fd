//! Reading a linear system for the MATLAB verbs: a system file (TOML or JSON) or the matrices
//! on the command line.
//!
//! A **system file** holds either the state-space matrices or one transfer function:
//!
//! ```toml
//! a = [[0, 1], [-2, -3]]   # n×n
//! b = [[0], [1]]           # n×m
//! c = [[1, 0]]             # p×n (default: the n×n identity, every state measured)
//! d = [[0]]                # p×m (default: zeros)
//! dt = 0.01                # optional: a discrete-time system with this sample time [s]
//! ```
//!
//! or `num = [1]`, `den = [1, 3, 2]` (coefficients in descending powers of `s`, or of `z` with
//! `dt`), realised in controllable canonical form (MATLAB `tf2ss`). A matrix is an array of
//! rows, a flat array is one row, a number is a 1×1 matrix. JSON takes the same keys.
//!
//! On the **command line**, `--a`, `--b`, `--c`, `--d`, `--num`, `--den` take either a file
//! (plain text as `pendulab lqr` reads it, e.g. MATLAB's `save -ascii`, or a `.json` array of
//! rows) or, when no file of that name exists, the matrix inline in MATLAB's syntax:
//! `--a "0 1; -2 -3"` (rows separated by `;`, values by spaces or commas, optional brackets).
//! `--dt TS` makes the system discrete. A system file and command-line matrices cannot be
//! mixed.

use crate::lqr::read_matrix;
use anyhow::{Context, Result, anyhow, bail};
use pendulab_lti::domain::{Continuous, Discrete};
use pendulab_lti::{Mat, StateSpace, TransferFunction};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A system of either time domain.
#[derive(Debug, Clone)]
pub enum Sys {
    /// Continuous time.
    C(StateSpace<Continuous>),
    /// Discrete time.
    D(StateSpace<Discrete>),
}

/// Runs `$body` with `$v` bound to the state-space system of either domain.
macro_rules! with_sys {
    ($sys:expr, |$v:ident| $body:expr) => {
        match $sys {
            $crate::sys::input::Sys::C($v) => $body,
            $crate::sys::input::Sys::D($v) => $body,
        }
    };
}
pub(crate) use with_sys;

impl Sys {
    /// The sample time, `None` in continuous time.
    pub fn dt(&self) -> Option<f64> {
        match self {
            Sys::C(_) => None,
            Sys::D(s) => Some(s.ts()),
        }
    }
    /// `(A, B, C, D)`.
    pub fn matrices(&self) -> (&Mat, &Mat, &Mat, &Mat) {
        with_sys!(self, |s| (s.a(), s.b(), s.c(), s.d()))
    }
}

/// Where the system comes from (flattened into every verb).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct SysArgs {
    /// System file (.toml or .json): `a`, `b` [, `c`, `d`] or `num`, `den`, and optional `dt`.
    #[arg(value_name = "SYSFILE")]
    pub sys: Option<PathBuf>,
    /// State matrix A: a file, or inline as MATLAB writes it ("0 1; -2 -3").
    #[arg(long, allow_hyphen_values = true)]
    pub a: Option<String>,
    /// Input matrix B: a file or inline.
    #[arg(long, allow_hyphen_values = true)]
    pub b: Option<String>,
    /// Output matrix C (default: identity): a file or inline.
    #[arg(long, allow_hyphen_values = true)]
    pub c: Option<String>,
    /// Feedthrough D (default: zeros): a file or inline.
    #[arg(long, allow_hyphen_values = true)]
    pub d: Option<String>,
    /// Transfer-function numerator, descending powers ("1 2"): a file or inline.
    #[arg(long, allow_hyphen_values = true)]
    pub num: Option<String>,
    /// Transfer-function denominator, descending powers ("1 3 2"): a file or inline.
    #[arg(long, allow_hyphen_values = true)]
    pub den: Option<String>,
    /// Sample time in seconds: the system is discrete.
    #[arg(long, allow_hyphen_values = true)]
    pub dt: Option<f64>,
}

/// A matrix as a file writes it: rows, one row, or one number.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum MatValue {
    Rows(Vec<Vec<f64>>),
    Row(Vec<f64>),
    Scalar(f64),
}

impl MatValue {
    fn into_mat(self, name: &str) -> Result<Mat> {
        let rows = match self {
            MatValue::Rows(r) => r,
            MatValue::Row(r) => vec![r],
            MatValue::Scalar(v) => vec![vec![v]],
        };
        rows_to_mat(rows, name)
    }
}

/// The keys of a system file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SysFile {
    a: Option<MatValue>,
    b: Option<MatValue>,
    c: Option<MatValue>,
    d: Option<MatValue>,
    num: Option<Vec<f64>>,
    den: Option<Vec<f64>>,
    dt: Option<f64>,
}

/// Builds a matrix from rows, checking that they have one length and that every value is finite.
fn rows_to_mat(rows: Vec<Vec<f64>>, name: &str) -> Result<Mat> {
    let nrows = rows.len();
    let ncols = rows.first().map_or(0, Vec::len);
    if nrows == 0 || ncols == 0 {
        bail!("{name}: the matrix is empty");
    }
    for (i, r) in rows.iter().enumerate() {
        if r.len() != ncols {
            bail!(
                "{name}: row {} has {} values, row 1 has {ncols}",
                i + 1,
                r.len()
            );
        }
        if let Some((j, v)) = r.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            bail!(
                "{name}: the value at row {}, column {} is {v}; every value must be finite",
                i + 1,
                j + 1
            );
        }
    }
    Ok(Mat::from_fn(nrows, ncols, |i, j| rows[i][j]))
}

/// Parses a matrix in MATLAB's inline syntax: optional `[` `]`, rows separated by `;` or line
/// breaks, values by commas and/or whitespace.
///
/// # Errors
/// A value that is not a finite number, rows of different lengths, no values (each naming
/// `name`, the row and the column).
pub fn parse_inline(text: &str, name: &str) -> Result<Mat> {
    let body = text.trim();
    let body = body.strip_prefix('[').unwrap_or(body);
    let body = body.strip_suffix(']').unwrap_or(body);
    let mut rows = Vec::new();
    for (i, row) in body.split([';', '\n']).enumerate() {
        let row = row.trim();
        if row.is_empty() {
            continue;
        }
        let values = row
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|v| !v.is_empty())
            .enumerate()
            .map(|(j, v)| {
                v.parse::<f64>().map_err(|_| {
                    anyhow!(
                        "{name}: row {}, column {}: `{v}` is not a number",
                        i + 1,
                        j + 1
                    )
                })
            })
            .collect::<Result<Vec<f64>>>()?;
        rows.push(values);
    }
    rows_to_mat(rows, name)
}

/// A matrix from a command-line value: the file of that name if one exists (`.json`: an array
/// of rows; otherwise text as [`read_matrix`] reads it), else the inline text.
///
/// # Errors
/// An unreadable or malformed file (naming it), or malformed inline text.
pub fn matrix_arg(value: &str, name: &str) -> Result<Mat> {
    let path = Path::new(value);
    if path.is_file() {
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read {}", path.display()))?;
            let v: MatValue = serde_json::from_str(&text).with_context(|| {
                format!(
                    "{name}: {} is not a JSON matrix (an array of rows)",
                    path.display()
                )
            })?;
            return v
                .into_mat(name)
                .with_context(|| format!("in {}", path.display()));
        }
        return read_matrix(path).with_context(|| format!("reading {name}"));
    }
    parse_inline(value, name)
}

/// A vector from a command-line value (a 1×n or n×1 matrix, see [`matrix_arg`]).
///
/// # Errors
/// As [`matrix_arg`]; a matrix with more than one row and more than one column.
pub fn vector_arg(value: &str, name: &str) -> Result<Vec<f64>> {
    let m = matrix_arg(value, name)?;
    if m.nrows() != 1 && m.ncols() != 1 {
        bail!(
            "{name}: expected a vector, found a {}×{} matrix",
            m.nrows(),
            m.ncols()
        );
    }
    Ok(m.iter().copied().collect())
}

/// The matrices or transfer function a system is built from.
struct Parts {
    a: Option<Mat>,
    b: Option<Mat>,
    c: Option<Mat>,
    d: Option<Mat>,
    num: Option<Vec<f64>>,
    den: Option<Vec<f64>>,
    dt: Option<f64>,
}

impl SysArgs {
    /// The system the arguments describe.
    ///
    /// # Errors
    /// Neither or both of a system file and command-line matrices; an unreadable or malformed
    /// file (naming it, and for TOML the line); an unknown key; missing or inconsistent parts;
    /// wrong shapes; non-finite values; a sample time that is not finite and positive.
    pub fn load(&self) -> Result<Sys> {
        let inline = [&self.a, &self.b, &self.c, &self.d, &self.num, &self.den]
            .iter()
            .any(|v| v.is_some());
        let parts = match (&self.sys, inline) {
            (Some(_), true) => bail!(
                "give the system either as a file or with --a/--b/--c/--d or --num/--den, not both"
            ),
            (None, false) => bail!(
                "no system: give a system file (.toml or .json) or the matrices (--a … --b …, or --num … --den …)"
            ),
            (Some(path), false) => {
                let parts = read_file(path)?;
                if let (Some(f), Some(c)) = (parts.dt, self.dt) {
                    bail!(
                        "the sample time is given twice: dt = {f} in {} and --dt {c}",
                        path.display()
                    );
                }
                Parts {
                    dt: parts.dt.or(self.dt),
                    ..parts
                }
            }
            (None, true) => {
                let m = |v: &Option<String>, n: &str| {
                    v.as_deref().map(|v| matrix_arg(v, n)).transpose()
                };
                let vec = |v: &Option<String>, n: &str| {
                    v.as_deref().map(|v| vector_arg(v, n)).transpose()
                };
                Parts {
                    a: m(&self.a, "A")?,
                    b: m(&self.b, "B")?,
                    c: m(&self.c, "C")?,
                    d: m(&self.d, "D")?,
                    num: vec(&self.num, "num")?,
                    den: vec(&self.den, "den")?,
                    dt: self.dt,
                }
            }
        };
        let where_ = self
            .sys
            .as_ref()
            .map(|p| format!(" (in {})", p.display()))
            .unwrap_or_default();
        build(parts).with_context(|| format!("the system{where_}"))
    }
}

/// Reads a system file (TOML, or JSON by its `.json` extension).
fn read_file(path: &Path) -> Result<Parts> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let file: SysFile = if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        serde_json::from_str(&text).with_context(|| format!("in {}", path.display()))?
    } else {
        toml::from_str(&text).map_err(|e| {
            let line = e
                .span()
                .map(|s| {
                    format!(
                        "line {}: ",
                        text[..s.start.min(text.len())].matches('\n').count() + 1
                    )
                })
                .unwrap_or_default();
            anyhow!("in {}: {line}{}", path.display(), e.message())
        })?
    };
    let m = |v: Option<MatValue>, n: &str| v.map(|v| v.into_mat(n)).transpose();
    Ok(Parts {
        a: m(file.a, "a")?,
        b: m(file.b, "b")?,
        c: m(file.c, "c")?,
        d: m(file.d, "d")?,
        num: file.num,
        den: file.den,
        dt: file.dt,
    })
}

fn build(p: Parts) -> Result<Sys> {
    if let Some(dt) = p.dt
        && !(dt.is_finite() && dt > 0.0)
    {
        bail!("dt = {dt}: the sample time must be finite and > 0 seconds");
    }
    let has_ss = p.a.is_some() || p.b.is_some() || p.c.is_some() || p.d.is_some();
    let has_tf = p.num.is_some() || p.den.is_some();
    match (has_ss, has_tf) {
        (true, true) => bail!(
            "give either the matrices (a, b, c, d) or a transfer function (num, den), not both"
        ),
        (false, false) => bail!("no system: the matrices a, b (and c, d) or num, den are needed"),
        (false, true) => {
            let (Some(num), Some(den)) = (p.num, p.den) else {
                bail!("a transfer function needs both num and den");
            };
            for (name, v) in [("num", &num), ("den", &den)] {
                if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                    bail!("{name}[{i}] = {x}: every coefficient must be finite");
                }
            }
            Ok(match p.dt {
                None => Sys::C(
                    TransferFunction::from_coefficients(&num, &den, Continuous)?
                        .to_state_space()?,
                ),
                Some(dt) => Sys::D(
                    TransferFunction::from_coefficients(&num, &den, Discrete::new(dt)?)?
                        .to_state_space()?,
                ),
            })
        }
        (true, false) => {
            let (Some(a), Some(b)) = (p.a, p.b) else {
                bail!(
                    "a state-space system needs at least a and b (c defaults to the identity, d to zeros)"
                );
            };
            let n = a.nrows();
            let c = p.c.unwrap_or_else(|| Mat::identity(n, n));
            let d = p.d.unwrap_or_else(|| Mat::zeros(c.nrows(), b.ncols()));
            Ok(match p.dt {
                None => Sys::C(StateSpace::continuous(a, b, c, d)?),
                Some(dt) => Sys::D(StateSpace::discrete(a, b, c, d, dt)?),
            })
        }
    }
}
