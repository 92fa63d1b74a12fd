//! [`Dataset`]: named, uniformly sampled measurement columns, from CSV text or a
//! [`Trajectory`], with validation and time windows.
//!
//! The rig files of `data/rig/` are CSV with a header line naming the columns (`t,z,phi,v`,
//! `t,theta`, ...); the time column is `t` in seconds, sampled uniformly (1 ms on the rigs).
//! A `Dataset` checks once, at construction, that every value is finite and every column has
//! the same length; [`Dataset::sample_time`] checks that `t` increases by a constant step
//! that is plausible for the rigs in the unit the column was read in.
//! Every error names the data source, the column and the sample (with its CSV line).
//!
//! **Time unit.** Time stamps are seconds unless declared otherwise: a header `t_ms`, `t[ms]`
//! or `t (ms)` declares milliseconds (`t_s`, `t[s]`, `t (s)` declare seconds), and
//! [`Dataset::with_time_unit`] declares the unit of a plain `t` (the CLI's `--time-unit ms`).
//! The column is converted to seconds and called `t`. A step over [`MAX_SAMPLE_TIME`] or
//! under [`MIN_SAMPLE_TIME`], or a span over [`MAX_RECORD_SPAN`], is rejected
//! ([`IdentError::ImplausibleTime`]): a column in milliseconds read as seconds is the usual
//! cause, and the message says how to declare the unit.
//!
//! **Text.** A leading UTF-8 byte-order mark (Excel's "CSV UTF-8") is skipped, CRLF line ends
//! are accepted, and spaces and double quotes around header names are removed; a name with
//! other invisible characters is shown escaped in messages (`"\u{200b}z"`).

use crate::error::{IdentError, Result, SamplePos, UNNAMED};
use pendulab_lti::Trajectory;

/// Name of the time column.
pub const TIME: &str = "t";

/// Largest plausible sample time, seconds: 0.5 s. The rigs' slowest dynamics are their
/// pendulums' swings, ω ≈ 5.8 rad/s (cart rig, table 3.5: period 1.09 s) and ≈ 7 rad/s (arm
/// rig); sampling slower than the Nyquist limit π/ω ≈ 0.5 s cannot represent them, so such a
/// step means the column is not in seconds (a rig logging every 1 ms in milliseconds shows
/// a step of 1).
pub const MAX_SAMPLE_TIME: f64 = 0.5;

/// Smallest plausible sample time, seconds: 10 µs, a hundred times faster than the rigs'
/// 1 kHz loop. A smaller step means a column in seconds was declared as milliseconds.
pub const MIN_SAMPLE_TIME: f64 = 1e-5;

/// Longest plausible record, seconds: one hour. The book's identification experiments last
/// seconds to a minute (`data/rig/`: 9 s to 60 s); a longer span means time stamps in a
/// smaller unit than the one declared (10 kHz samples in milliseconds, say).
pub const MAX_RECORD_SPAN: f64 = 3600.0;

/// The unit of a time column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TimeUnit {
    /// Seconds (the default).
    #[default]
    Seconds,
    /// Milliseconds.
    Milliseconds,
}

impl TimeUnit {
    /// Seconds per unit: 1 or 10⁻³.
    pub fn seconds(self) -> f64 {
        match self {
            TimeUnit::Seconds => 1.0,
            TimeUnit::Milliseconds => 1e-3,
        }
    }

    /// The unit declared by a time-column header (`t`, `t_s`, `t[s]`, `t (s)`, `t_ms`,
    /// `t[ms]`, `t (ms)`; case as written): `Some((unit, declared))`, `declared = false` for
    /// a plain `t`; `None` for any other name.
    pub fn from_header(name: &str) -> Option<(TimeUnit, bool)> {
        let compact: String = name.chars().filter(|c| !c.is_whitespace()).collect();
        match compact.as_str() {
            TIME => Some((TimeUnit::Seconds, false)),
            "t_s" | "t[s]" | "t(s)" => Some((TimeUnit::Seconds, true)),
            "t_ms" | "t[ms]" | "t(ms)" => Some((TimeUnit::Milliseconds, true)),
            _ => None,
        }
    }
}

impl std::fmt::Display for TimeUnit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            TimeUnit::Seconds => "seconds",
            TimeUnit::Milliseconds => "milliseconds",
        })
    }
}

/// Relative tolerance on the spacing of time stamps: a step may differ from the mean step by
/// this fraction (plus the rounding of the time values themselves). Logged time stamps are
/// nominal multiples of the sample time printed to ~16 digits, so 1e-6 only admits rounding
/// while rejecting any real jitter or dropped sample (a dropped sample doubles the step).
pub const TIME_STEP_TOLERANCE: f64 = 1e-6;

/// Named columns of equal length, all finite.
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    source: String,
    names: Vec<String>,
    columns: Vec<Vec<f64>>,
    /// 1-based CSV line of each sample (empty when not from CSV).
    lines: Vec<usize>,
    /// The unit the time column was read in (its values are stored in seconds), and whether
    /// it was declared (by the header or [`Dataset::with_time_unit`]).
    time_unit: (TimeUnit, bool),
}

impl Dataset {
    /// Builds a data set from named columns.
    ///
    /// `source` labels the data in error messages (a file name, say).
    ///
    /// # Errors
    /// [`IdentError::LengthMismatch`] if the columns differ in length,
    /// [`IdentError::NonFinite`] for a NaN/∞ value, [`IdentError::InvalidParameter`] for a
    /// duplicated or empty column name or a name count different from the column count.
    pub fn from_columns(source: &str, names: &[&str], columns: Vec<Vec<f64>>) -> Result<Self> {
        let ds = Self {
            source: source.to_string(),
            names: names.iter().map(|s| s.to_string()).collect(),
            columns,
            lines: Vec::new(),
            time_unit: (TimeUnit::Seconds, false),
        };
        ds.validate()?;
        Ok(ds)
    }

    /// Builds a data set from a trajectory: the time `t` and every named signal (states,
    /// inputs, outputs) under its name. Unnamed signals are called `x0, x1, …`, `u0, …`,
    /// `y0, …`.
    ///
    /// # Errors
    /// As [`Dataset::from_columns`] (duplicated names, non-finite values).
    pub fn from_trajectory(source: &str, tr: &Trajectory) -> Result<Self> {
        let mut names = vec![TIME.to_string()];
        let mut columns = vec![tr.t().to_vec()];
        let groups = [
            ("x", tr.x_names(), tr.x()),
            ("u", tr.u_names(), tr.u()),
            ("y", tr.y_names(), tr.y()),
        ];
        for (prefix, given, m) in groups {
            let rows = m.nrows();
            for i in 0..m.ncols() {
                names.push(match given.get(i) {
                    Some(n) => n.clone(),
                    None => format!("{prefix}{i}"),
                });
                columns.push(m.as_slice()[i * rows..(i + 1) * rows].to_vec());
            }
        }
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        Self::from_columns(source, &refs, columns)
    }

    /// Parses CSV text: a header line of column names, then one line of numbers per sample,
    /// separated by commas (blank lines are skipped; surrounding spaces are ignored; a leading
    /// UTF-8 byte-order mark is skipped; CRLF line ends are accepted). A time column headed
    /// `t_ms`, `t[ms]` or `t (ms)` is converted from milliseconds to seconds and called `t`
    /// (see [`TimeUnit::from_header`]).
    ///
    /// # Errors
    /// [`IdentError::Csv`] for an empty text, a malformed number or a line with the wrong
    /// number of fields (naming the line); [`IdentError::NonFinite`] for NaN/∞ values;
    /// [`IdentError::InvalidParameter`] for duplicated or empty header names.
    pub fn from_csv_str(source: &str, text: &str) -> Result<Self> {
        let csv_err = |line: usize, message: String| IdentError::Csv {
            source_name: source.to_string(),
            line,
            message,
        };
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty());
        let Some((_, header)) = lines.next() else {
            return Err(csv_err(1, "empty file: expected a header line".into()));
        };
        let mut names: Vec<String> = header
            .split(',')
            .map(|s| s.trim().trim_matches('"').trim().to_string())
            .collect();
        // The first column that names time in a declared unit becomes `t` (unless a plain
        // `t` is also present, which then stays the time column and the other one data).
        let mut time_unit = (TimeUnit::Seconds, false);
        if !names.iter().any(|n| n == TIME)
            && let Some((j, unit)) = names
                .iter()
                .enumerate()
                .find_map(|(j, n)| TimeUnit::from_header(n).map(|u| (j, u)))
        {
            names[j] = TIME.to_string();
            time_unit = unit;
        }
        let width = names.len();
        let mut columns: Vec<Vec<f64>> = vec![Vec::new(); width];
        let mut line_numbers = Vec::new();
        for (lineno, line) in lines {
            let mut count = 0;
            for (j, field) in line.split(',').enumerate() {
                if j >= width {
                    return Err(csv_err(
                        lineno,
                        format!(
                            "more than the {width} fields of the header ({})",
                            names.join(",")
                        ),
                    ));
                }
                let field = field.trim();
                let v: f64 = field.parse().map_err(|_| {
                    csv_err(
                        lineno,
                        format!("column '{}': '{field}' is not a number", names[j]),
                    )
                })?;
                columns[j].push(v);
                count += 1;
            }
            if count != width {
                return Err(csv_err(
                    lineno,
                    format!(
                        "{count} fields, the header ({}) has {width}",
                        names.join(",")
                    ),
                ));
            }
            line_numbers.push(lineno);
        }
        let ds = Self {
            source: source.to_string(),
            names,
            columns,
            lines: line_numbers,
            time_unit: (TimeUnit::Seconds, false),
        };
        ds.validate()?;
        if time_unit.1 {
            return ds.with_time_unit(time_unit.0);
        }
        Ok(ds)
    }

    /// Declares the unit of the time column `t` and converts it to seconds.
    ///
    /// Declaring the unit a header already declared is a no-op; declaring the unit of a
    /// plain `t` scales it by [`TimeUnit::seconds`] (declaring seconds only records that
    /// the unit was declared).
    ///
    /// # Errors
    /// [`IdentError::MissingColumn`] without a time column; [`IdentError::InvalidParameter`]
    /// if the header declared another unit.
    pub fn with_time_unit(mut self, unit: TimeUnit) -> Result<Self> {
        let j = self.time_index()?;
        match self.time_unit {
            (u, true) if u == unit => return Ok(self),
            (u, true) => {
                return Err(IdentError::InvalidParameter {
                    name: format!("{}: time unit", self.source),
                    value: unit.seconds(),
                    reason: format!(
                        "the header declares the time column in {u}, not {unit} (seconds per unit given)"
                    ),
                });
            }
            _ => {}
        }
        let f = unit.seconds();
        if f != 1.0 {
            for v in &mut self.columns[j] {
                *v *= f;
            }
        }
        self.time_unit = (unit, true);
        Ok(self)
    }

    /// The unit the time column was read in, and whether it was declared (by a header such
    /// as `t_ms` or by [`Dataset::with_time_unit`]) rather than assumed.
    pub fn time_unit(&self) -> (TimeUnit, bool) {
        self.time_unit
    }

    fn time_index(&self) -> Result<usize> {
        self.names
            .iter()
            .position(|n| n == TIME)
            .ok_or_else(|| IdentError::MissingColumn {
                source_name: self.source.clone(),
                column: TIME.to_string(),
                available: self.names.clone(),
            })
    }

    fn validate(&self) -> Result<()> {
        if self.names.len() != self.columns.len() {
            return Err(IdentError::InvalidParameter {
                name: format!("{}: column names", self.source),
                value: self.names.len() as f64,
                reason: format!(
                    "{} names for {} columns",
                    self.names.len(),
                    self.columns.len()
                ),
            });
        }
        for (i, n) in self.names.iter().enumerate() {
            if n.is_empty() || self.names[..i].contains(n) {
                return Err(IdentError::InvalidParameter {
                    name: format!("{}: column name '{n}'", self.source),
                    value: i as f64,
                    reason: "column names must be non-empty and distinct".into(),
                });
            }
        }
        let len = self.columns.first().map_or(0, Vec::len);
        for (name, col) in self.names.iter().zip(&self.columns) {
            if col.len() != len {
                return Err(IdentError::LengthMismatch {
                    source_name: self.source.clone(),
                    column: name.clone(),
                    expected: len,
                    found: col.len(),
                });
            }
            if let Some(k) = col.iter().position(|v| !v.is_finite()) {
                return Err(IdentError::NonFinite {
                    source_name: self.source.clone(),
                    column: name.clone(),
                    at: self.pos(k),
                    value: col[k],
                });
            }
        }
        Ok(())
    }

    /// Position of sample `k` for error messages.
    pub fn pos(&self, k: usize) -> SamplePos {
        SamplePos {
            index: k,
            line: self.lines.get(k).copied(),
        }
    }

    /// The label of the data (file name) used in error messages.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Column names in order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }

    /// `true` if there are no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The column called `name`.
    ///
    /// # Errors
    /// [`IdentError::MissingColumn`] naming the data source and the columns present.
    pub fn column(&self, name: &str) -> Result<&[f64]> {
        match self.names.iter().position(|n| n == name) {
            Some(i) => Ok(&self.columns[i]),
            None => Err(IdentError::MissingColumn {
                source_name: self.source.clone(),
                column: name.to_string(),
                available: self.names.clone(),
            }),
        }
    }

    /// The time column `t`, seconds.
    ///
    /// # Errors
    /// [`IdentError::MissingColumn`] if there is none.
    pub fn time(&self) -> Result<&[f64]> {
        self.column(TIME)
    }

    /// The uniform sample time of `t` in seconds, checked for plausibility: as
    /// [`Dataset::uniform_step`], then [`Dataset::check_time_unit`].
    ///
    /// # Errors
    /// Those of [`Dataset::uniform_step`] and [`Dataset::check_time_unit`].
    pub fn sample_time(&self) -> Result<f64> {
        let ts = self.uniform_step()?;
        self.check_time_unit()?;
        Ok(ts)
    }

    /// Checks that the time column's step lies in [[`MIN_SAMPLE_TIME`],
    /// [`MAX_SAMPLE_TIME`]] and its span is at most [`MAX_RECORD_SPAN`] — in seconds, after
    /// conversion from the declared unit.
    ///
    /// # Errors
    /// [`IdentError::ImplausibleTime`] naming the step, the span, the unit the column was
    /// read in and how to declare another one; those of [`Dataset::uniform_step`].
    pub fn check_time_unit(&self) -> Result<()> {
        let ts = self.uniform_step()?;
        let t = self.time()?;
        let span = t[t.len() - 1] - t[0];
        let (unit, declared) = self.time_unit;
        let (reason, hint) = if ts > MAX_SAMPLE_TIME {
            (
                format!(
                    "a step of {ts} s, over the {MAX_SAMPLE_TIME} s that can still sample the rigs' pendulum swings"
                ),
                if unit == TimeUnit::Seconds {
                    "if it is in milliseconds, declare it: a header t_ms or t[ms], or --time-unit ms"
                } else {
                    "check the time column"
                },
            )
        } else if ts < MIN_SAMPLE_TIME {
            (
                format!(
                    "a step of {ts} s, under the {MIN_SAMPLE_TIME} s a hundred times faster than the rigs' 1 kHz loop"
                ),
                if unit == TimeUnit::Milliseconds {
                    "if it is in seconds, declare it: a header t or t_s, or --time-unit s"
                } else {
                    "check the time column"
                },
            )
        } else if span > MAX_RECORD_SPAN {
            (
                format!(
                    "a span of {span} s, over the {MAX_RECORD_SPAN} s of any identification record"
                ),
                if unit == TimeUnit::Seconds {
                    "if it is in milliseconds, declare it: a header t_ms or t[ms], or --time-unit ms"
                } else {
                    "check the time column"
                },
            )
        } else {
            return Ok(());
        };
        Err(IdentError::ImplausibleTime {
            source_name: self.source.clone(),
            unit,
            declared,
            step: ts,
            span,
            reason,
            hint: hint.to_string(),
        })
    }

    /// The uniform step of `t` in seconds, without the plausibility check of
    /// [`Dataset::sample_time`]: checks that `t` strictly increases with a constant step (each
    /// step equal to the median step to [`TIME_STEP_TOLERANCE`] relative) and returns the mean
    /// step `(t_last − t_0)/(n − 1)`.
    ///
    /// # Errors
    /// [`IdentError::MissingColumn`] without `t`; [`IdentError::TooFewSamples`] with fewer than
    /// two samples; [`IdentError::TimeNotIncreasing`] / [`IdentError::UnevenTime`] naming the
    /// first offending sample.
    pub fn uniform_step(&self) -> Result<f64> {
        let t = self.time()?;
        if t.len() < 2 {
            return Err(IdentError::TooFewSamples {
                source_name: self.source.clone(),
                what: "a sample time".into(),
                needed: 2,
                found: t.len(),
            });
        }
        if let Some(k) = t.windows(2).position(|w| w[1] <= w[0]) {
            return Err(IdentError::TimeNotIncreasing {
                source_name: self.source.clone(),
                at: self.pos(k + 1),
                t: t[k + 1],
                previous: t[k],
            });
        }
        let n = t.len();
        // The typical step is the median one, so the first irregular step is the one named.
        let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
        let mid = steps.len() / 2;
        let typical = *steps.select_nth_unstable_by(mid, f64::total_cmp).1;
        let tmax = t[0].abs().max(t[n - 1].abs());
        let tol = TIME_STEP_TOLERANCE * typical + 8.0 * f64::EPSILON * tmax;
        if let Some(k) = t
            .windows(2)
            .position(|w| ((w[1] - w[0]) - typical).abs() > tol)
        {
            return Err(IdentError::UnevenTime {
                source_name: self.source.clone(),
                at: self.pos(k + 1),
                step: t[k + 1] - t[k],
                expected: typical,
            });
        }
        // Every step agrees with the typical one; the mean step is the most precise value.
        Ok((t[n - 1] - t[0]) / (n - 1) as f64)
    }

    /// The samples with `t0 ≤ t ≤ t1` (to a hundredth of a sample step, so windows given on
    /// the grid include their end points as MATLAB's `t >= tmin & t <= tmax` does on exact
    /// values); `None` for an open end. The time column keeps its values (it is not shifted).
    ///
    /// # Errors
    /// As [`Dataset::uniform_step`] (the time unit is checked by [`Dataset::sample_time`], not
    /// here); [`IdentError::InvalidParameter`] for a non-finite bound
    /// or `t0 ≥ t1`; [`IdentError::WindowOutsideData`] if a bound lies outside the data's time
    /// span (by more than half a step) — a window is never silently clipped;
    /// [`IdentError::TooFewSamples`] if fewer than two samples remain.
    pub fn window(&self, t0: Option<f64>, t1: Option<f64>) -> Result<Self> {
        let ts = self.uniform_step()?;
        let t = self.time()?;
        let (first, last) = (t[0], t[t.len() - 1]);
        let a = t0.unwrap_or(first);
        let b = t1.unwrap_or(last);
        for (name, v) in [("window start", a), ("window end", b)] {
            if !v.is_finite() {
                return Err(IdentError::InvalidParameter {
                    name: name.into(),
                    value: v,
                    reason: "must be a finite time in seconds".into(),
                });
            }
        }
        if a >= b {
            return Err(IdentError::InvalidParameter {
                name: "window start".into(),
                value: a,
                reason: format!("must be less than the window end {b} s"),
            });
        }
        if a < first - 0.5 * ts || b > last + 0.5 * ts {
            return Err(IdentError::WindowOutsideData {
                source_name: self.source.clone(),
                t0: a,
                t1: b,
                data_start: first,
                data_end: last,
            });
        }
        let eps = 0.01 * ts;
        let lo = t.partition_point(|&v| v < a - eps);
        let hi = t.partition_point(|&v| v <= b + eps);
        if hi < lo + 2 {
            return Err(IdentError::TooFewSamples {
                source_name: self.source.clone(),
                what: format!("the window [{a} s, {b} s]"),
                needed: 2,
                found: hi.saturating_sub(lo),
            });
        }
        Ok(Self {
            source: self.source.clone(),
            names: self.names.clone(),
            columns: self.columns.iter().map(|c| c[lo..hi].to_vec()).collect(),
            lines: if self.lines.is_empty() {
                Vec::new()
            } else {
                self.lines[lo..hi].to_vec()
            },
            time_unit: self.time_unit,
        })
    }
}

impl Default for Dataset {
    fn default() -> Self {
        Self {
            source: UNNAMED.into(),
            names: Vec::new(),
            columns: Vec::new(),
            lines: Vec::new(),
            time_unit: (TimeUnit::Seconds, false),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_windows() {
        let text = "t,z\n0.0,1\n0.001,2\n\n0.002,3\n0.003,4\n";
        let ds = Dataset::from_csv_str("f.csv", text).unwrap();
        assert_eq!(ds.len(), 4);
        assert_eq!(ds.column("z").unwrap(), &[1.0, 2.0, 3.0, 4.0]);
        assert!((ds.sample_time().unwrap() - 0.001).abs() < 1e-15);
        let w = ds.window(Some(0.001), Some(0.002)).unwrap();
        assert_eq!(w.column("z").unwrap(), &[2.0, 3.0]);
        // Line numbers survive windowing (line 5 is the sample after the blank line).
        assert_eq!(w.pos(1).line, Some(5));
    }

    #[test]
    fn from_trajectory_names_signals() {
        use pendulab_lti::Mat;
        let tr = Trajectory::new(
            vec![0.0, 0.001, 0.002],
            Mat::from_row_slice(3, 2, &[1.0, 10.0, 2.0, 20.0, 3.0, 30.0]),
            Mat::from_row_slice(3, 1, &[0.5, 0.6, 0.7]),
            Mat::zeros(3, 0),
        )
        .unwrap()
        .with_names(vec!["z".into(), "phi".into()], vec!["v".into()], vec![])
        .unwrap();
        let ds = Dataset::from_trajectory("sim", &tr).unwrap();
        assert_eq!(ds.names(), &["t", "z", "phi", "v"]);
        assert_eq!(ds.column("phi").unwrap(), &[10.0, 20.0, 30.0]);
        assert_eq!(ds.column("v").unwrap(), &[0.5, 0.6, 0.7]);
        // Unnamed signals get positional names.
        let tr = Trajectory::new(
            vec![0.0, 1.0],
            Mat::zeros(2, 1),
            Mat::zeros(2, 0),
            Mat::zeros(2, 1),
        )
        .unwrap();
        let ds = Dataset::from_trajectory("sim", &tr).unwrap();
        assert_eq!(ds.names(), &["t", "x0", "y0"]);
    }

    #[test]
    fn errors_name_the_place() {
        let e = Dataset::from_csv_str("f.csv", "t,z\n0,1\n0.001,x\n").unwrap_err();
        assert!(matches!(&e, IdentError::Csv { line: 3, .. }), "{e}");
        assert!(e.to_string().contains("f.csv") && e.to_string().contains("'z'"));
        let e = Dataset::from_csv_str("f.csv", "t,z\n0,1\n0.001,NaN\n").unwrap_err();
        assert!(
            matches!(&e, IdentError::NonFinite { column, at, .. } if column == "z" && at.line == Some(3)),
            "{e}"
        );
        let e = Dataset::from_csv_str("f.csv", "t,z\n0,1\n0.001\n").unwrap_err();
        assert!(matches!(e, IdentError::Csv { line: 3, .. }));
        let e = Dataset::from_csv_str("f.csv", "").unwrap_err();
        assert!(matches!(e, IdentError::Csv { .. }));
        let ds = Dataset::from_csv_str("f.csv", "t,z\n0,1\n0.001,1\n0.0005,1\n").unwrap();
        let e = ds.sample_time().unwrap_err();
        assert!(
            matches!(&e, IdentError::TimeNotIncreasing { at, .. } if at.index == 2 && at.line == Some(4))
        );
        let ds = Dataset::from_csv_str("f.csv", "t,z\n0,1\n0.001,1\n0.003,1\n0.004,1\n").unwrap();
        let e = ds.sample_time().unwrap_err();
        assert!(
            matches!(&e, IdentError::UnevenTime { at, .. } if at.index == 2),
            "{e}"
        );
        let ds = Dataset::from_csv_str("f.csv", "t,z\n0,1\n0.001,1\n0.002,1\n").unwrap();
        let e = ds.column("phi").unwrap_err();
        assert!(e.to_string().contains("'phi'") && e.to_string().contains("t, z"));
        assert!(matches!(
            ds.window(Some(0.0), Some(1.0)),
            Err(IdentError::WindowOutsideData { .. })
        ));
        assert!(matches!(
            ds.window(Some(0.002), Some(0.001)),
            Err(IdentError::InvalidParameter { .. })
        ));
        let e = Dataset::from_csv_str("f.csv", "t,t\n0,1\n").unwrap_err();
        assert!(matches!(e, IdentError::InvalidParameter { .. }));
    }

    /// `n` samples of `t,z` at `step` in the given unit (header `head`), z = k.
    fn csv(head: &str, step: f64, n: usize) -> String {
        let mut s = format!("{head},z\n");
        for k in 0..n {
            s.push_str(&format!("{},{k}\n", k as f64 * step));
        }
        s
    }

    #[test]
    fn byte_order_mark_crlf_and_padded_names_are_read() {
        let plain = csv("t", 0.001, 5);
        let bom = format!(
            "\u{feff}{}",
            plain
                .replace('\n', "\r\n")
                .replacen("t,z", " t , \"z\" ", 1)
        );
        let a = Dataset::from_csv_str("a.csv", &plain).unwrap();
        let b = Dataset::from_csv_str("b.csv", &bom).unwrap();
        assert_eq!(b.names(), &["t", "z"]);
        assert_eq!(a.column("z").unwrap(), b.column("z").unwrap());
        assert_eq!(a.time().unwrap(), b.time().unwrap());
        assert_eq!(b.pos(0).line, Some(2));
        // An invisible character elsewhere is shown escaped in the message.
        let zw = plain.replacen("t,z", "t,\u{200b}z", 1);
        let e = Dataset::from_csv_str("c.csv", &zw)
            .unwrap()
            .column("z")
            .unwrap_err();
        assert!(e.to_string().contains(r#""\u{200b}z""#), "{e}");
        assert!(e.to_string().contains("'z'"), "{e}");
    }

    #[test]
    fn time_unit_declared_by_header_or_call() {
        // Milliseconds by header: t_ms, t[ms], t (ms) all become seconds.
        for head in ["t_ms", "t[ms]", "t (ms)"] {
            let ds = Dataset::from_csv_str("f.csv", &csv(head, 1.0, 50)).unwrap();
            assert_eq!(ds.names()[0], "t");
            assert_eq!(ds.time_unit(), (TimeUnit::Milliseconds, true));
            assert!((ds.sample_time().unwrap() - 1e-3).abs() < 1e-15, "{head}");
        }
        // The same values under a plain `t` are taken as seconds: a 1 s step is refused,
        // naming the step and how to declare the unit.
        let ds = Dataset::from_csv_str("f.csv", &csv("t", 1.0, 50)).unwrap();
        let e = ds.sample_time().unwrap_err();
        assert!(
            matches!(&e, IdentError::ImplausibleTime { step, unit: TimeUnit::Seconds, .. } if *step == 1.0),
            "{e}"
        );
        assert!(
            e.to_string().contains("--time-unit ms") && e.to_string().contains("t_ms"),
            "{e}"
        );
        // The step itself is still available without the plausibility check.
        assert_eq!(ds.uniform_step().unwrap(), 1.0);
        // Declared by a call: converted, then plausible.
        let ms = ds.clone().with_time_unit(TimeUnit::Milliseconds).unwrap();
        assert!((ms.sample_time().unwrap() - 1e-3).abs() < 1e-15);
        assert_eq!(ms.time().unwrap()[49], 49.0 * 1e-3);
        // A header's unit cannot be contradicted.
        let hdr = Dataset::from_csv_str("f.csv", &csv("t_ms", 1.0, 50)).unwrap();
        assert!(matches!(
            hdr.clone().with_time_unit(TimeUnit::Seconds),
            Err(IdentError::InvalidParameter { .. })
        ));
        assert_eq!(
            hdr.clone().with_time_unit(TimeUnit::Milliseconds).unwrap(),
            hdr
        );
    }

    #[test]
    fn time_step_and_span_bounds() {
        // Either side of each documented bound (seconds).
        let ok = |step: f64, n: usize| {
            Dataset::from_csv_str("f.csv", &csv("t", step, n))
                .unwrap()
                .sample_time()
        };
        assert!(ok(MAX_SAMPLE_TIME, 10).is_ok());
        assert!(matches!(
            ok(2.0 * MAX_SAMPLE_TIME, 10),
            Err(IdentError::ImplausibleTime { .. })
        ));
        assert!(ok(MIN_SAMPLE_TIME, 10).is_ok());
        let e = ok(0.5 * MIN_SAMPLE_TIME, 10).unwrap_err();
        assert!(matches!(e, IdentError::ImplausibleTime { .. }), "{e}");
        // Seconds declared as milliseconds: a 1 µs step, and the hint says so.
        let e = Dataset::from_csv_str("f.csv", &csv("t_ms", 0.001, 10))
            .unwrap()
            .sample_time()
            .unwrap_err();
        assert!(e.to_string().contains("--time-unit s"), "{e}");
        // 0.1 s steps over 3600 s are fine; over 4000 s the span is refused.
        assert!(ok(0.1, 36_001).is_ok());
        let e = ok(0.1, 40_001).unwrap_err();
        assert!(
            matches!(&e, IdentError::ImplausibleTime { span, .. } if (*span - 4000.0).abs() < 1e-6),
            "{e}"
        );
    }
}
