//! [`Dataset`]: named, uniformly sampled measurement columns, from CSV text or a
//! [`Trajectory`], with validation and time windows.
//!
//! The rig files of `data/rig/` are CSV with a header line naming the columns (`t,z,phi,v`,
//! `t,theta`, ...); the time column is `t` in seconds, sampled uniformly (1 ms on the rigs).
//! A `Dataset` checks once, at construction, that every value is finite and every column has
//! the same length; [`Dataset::sample_time`] checks that `t` increases by a constant step.
//! Every error names the data source, the column and the sample (with its CSV line).

use crate::error::{IdentError, Result, SamplePos, UNNAMED};
use pendulab_lti::Trajectory;

/// Name of the time column.
pub const TIME: &str = "t";

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
    /// separated by commas (blank lines are skipped; surrounding spaces are ignored).
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
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty());
        let Some((_, header)) = lines.next() else {
            return Err(csv_err(1, "empty file: expected a header line".into()));
        };
        let names: Vec<String> = header
            .split(',')
            .map(|s| s.trim().trim_matches('"').to_string())
            .collect();
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
        };
        ds.validate()?;
        Ok(ds)
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

    /// The uniform sample time of `t` in seconds: checks that `t` strictly increases with a
    /// constant step (each step equal to the median step to [`TIME_STEP_TOLERANCE`] relative)
    /// and returns the mean step
    /// `(t_last − t_0)/(n − 1)`.
    ///
    /// # Errors
    /// [`IdentError::MissingColumn`] without `t`; [`IdentError::TooFewSamples`] with fewer than
    /// two samples; [`IdentError::TimeNotIncreasing`] / [`IdentError::UnevenTime`] naming the
    /// first offending sample.
    pub fn sample_time(&self) -> Result<f64> {
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
    /// As [`Dataset::sample_time`]; [`IdentError::InvalidParameter`] for a non-finite bound
    /// or `t0 ≥ t1`; [`IdentError::WindowOutsideData`] if a bound lies outside the data's time
    /// span (by more than half a step) — a window is never silently clipped;
    /// [`IdentError::TooFewSamples`] if fewer than two samples remain.
    pub fn window(&self, t0: Option<f64>, t1: Option<f64>) -> Result<Self> {
        let ts = self.sample_time()?;
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
}
