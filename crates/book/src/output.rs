//! What an example returns: named values, the book's values beside them, and its figures and
//! animations as values ([`Graphic`]) that the front end renders and writes.

use crate::error::BookError;
use pendulab_lti::Complex64;
use pendulab_plot::{Animation, Figure, PlotError};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// A value reported by an example.
///
/// Serialised to JSON as a number, a boolean, an array or an array of arrays; complex numbers
/// (poles, eigenvalues) as `[re, im]` pairs.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A yes/no result (e.g. `stable`, `feasible`).
    Bool(bool),
    /// A real number.
    Number(f64),
    /// A real vector (e.g. a row gain).
    Vector(Vec<f64>),
    /// A real matrix, row by row.
    Matrix(Vec<Vec<f64>>),
    /// A list of complex numbers (poles, eigenvalues), serialised as `[[re, im], ...]`.
    Complex(Vec<Complex64>),
}

impl Serialize for Value {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Value::Bool(b) => s.serialize_bool(*b),
            Value::Number(x) => s.serialize_f64(*x),
            Value::Vector(v) => v.serialize(s),
            Value::Matrix(m) => m.serialize(s),
            Value::Complex(c) => c
                .iter()
                .map(|z| [z.re, z.im])
                .collect::<Vec<_>>()
                .serialize(s),
        }
    }
}

impl Value {
    /// A matrix value from a `pendulab_lti::Mat`.
    pub fn matrix(m: &pendulab_lti::Mat) -> Self {
        Value::Matrix(
            (0..m.nrows())
                .map(|i| m.row(i).iter().copied().collect())
                .collect(),
        )
    }
    /// A vector value from a row or column matrix, or any slice.
    pub fn vector(v: &[f64]) -> Self {
        Value::Vector(v.to_vec())
    }
}

/// A value printed in the book or displayed by its M-files, shown beside pendulab's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reference {
    /// Name of the value, as in [`ExampleOutput::values`].
    pub name: String,
    /// The printed value.
    pub value: Value,
    /// Where it is printed (e.g. "book p. 74", "book Part 1 §7.4, example 7.1").
    pub source: String,
    /// Largest absolute difference per element that still counts as reproducing the printed
    /// value: half a unit in the last printed digit for a rounded number, or a stated tolerance.
    pub tolerance: f64,
}

/// The result of running one example.
#[derive(Debug, Clone, Default)]
pub struct ExampleOutput {
    /// Named values, in the order the example reports them.
    pub values: Vec<(String, Value)>,
    /// The book's printed values for comparison.
    pub references: Vec<Reference>,
    /// The figures and animations drawn, in the order drawn; empty unless the run context asks
    /// for figures ([`crate::RunContext::figures`]). Nothing is rendered or written here: the
    /// front end calls [`Graphic::render`] and writes the files.
    pub figures: Vec<Graphic>,
    /// Short remarks for the report (what the figure shows, differences from the book).
    pub notes: Vec<String>,
    /// Numbers the book prints or the M-file displays that are *not* compared with pendulab's
    /// (each with the reason). An example that reproduces every reference but lists one here
    /// only agrees where compared ([`crate::report::Status::PartlyCompared`]).
    pub uncompared: Vec<Uncompared>,
    /// The unit of a value, keyed by the value's name ([`ExampleOutput::unit`]); a value
    /// without an entry has no stated unit (dimensionless, or a gain whose compound unit the
    /// example does not state).
    pub units: Vec<(String, String)>,
}

/// A number the book prints or an M-file displays that the example does not compare.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Uncompared {
    /// What is displayed (the M-file's names, with its line).
    pub what: String,
    /// Why it is not compared.
    pub why: String,
}

impl ExampleOutput {
    /// Adds a value.
    pub fn value(&mut self, name: &str, value: Value) -> &mut Self {
        self.values.push((name.to_string(), value));
        self
    }
    /// Adds the book's value for `name`, reproduced when every element of the computed value
    /// lies within `tolerance` (absolute) of it.
    pub fn reference(
        &mut self,
        name: &str,
        value: Value,
        source: &str,
        tolerance: f64,
    ) -> &mut Self {
        self.references.push(Reference {
            name: name.to_string(),
            value,
            source: source.to_string(),
            tolerance,
        });
        self
    }
    /// Adds a figure whose files are `<stem>.svg` and `<stem>.png`.
    pub fn figure(&mut self, stem: impl Into<String>, figure: Figure) -> &mut Self {
        self.figures.push(Graphic {
            stem: stem.into(),
            kind: GraphicKind::Figure(figure),
        });
        self
    }
    /// Adds an animation whose files are `<stem>.gif` and the animated `<stem>.svg`.
    pub fn animation(&mut self, stem: impl Into<String>, animation: Animation) -> &mut Self {
        self.figures.push(Graphic {
            stem: stem.into(),
            kind: GraphicKind::Animation(animation),
        });
        self
    }
    /// Looks a value up by name.
    pub fn get(&self, name: &str) -> Option<&Value> {
        self.values.iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }
    /// States the SI unit of the values `names` as the book writes it (`m`, `rad`, `V`, `s`,
    /// `1/s`, `N·m`, …); a later call for the same name replaces the unit.
    pub fn unit(&mut self, names: &[&str], unit: &str) -> &mut Self {
        for name in names {
            match self.units.iter_mut().find(|(n, _)| n == name) {
                Some((_, u)) => *u = unit.to_string(),
                None => self.units.push((name.to_string(), unit.to_string())),
            }
        }
        self
    }
    /// The stated unit of value `name`, if any.
    pub fn unit_of(&self, name: &str) -> Option<&str> {
        self.units
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, u)| u.as_str())
    }
}

/// A figure or an animation an example drew, as a value: the front end renders it with
/// [`Graphic::render`] and writes the files; the book writes nothing.
#[derive(Debug, Clone)]
pub struct Graphic {
    /// File stem, unique within the example and starting with its id (e.g.
    /// `p1c41_cdip_response_y`); [`Graphic::file_names`] gives the files.
    pub stem: String,
    /// What is drawn.
    pub kind: GraphicKind,
}

/// What a [`Graphic`] holds.
#[derive(Debug, Clone)]
pub enum GraphicKind {
    /// A static figure, rendered as SVG and PNG.
    Figure(Figure),
    /// A rig animation, rendered as an animated GIF and an animated (SMIL) SVG.
    Animation(Animation),
}

/// One rendered file of a [`Graphic`]: its name (stem and extension, no directory) and bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RenderedFile {
    /// File name, e.g. `p1c41_cdip_response_y.svg`.
    pub name: String,
    /// The file's contents.
    pub bytes: Vec<u8>,
}

impl Graphic {
    /// The extensions of the files, in the order [`Graphic::render`] returns them:
    /// `["svg", "png"]` for a figure, `["gif", "svg"]` for an animation.
    pub fn extensions(&self) -> [&'static str; 2] {
        match self.kind {
            GraphicKind::Figure(_) => ["svg", "png"],
            GraphicKind::Animation(_) => ["gif", "svg"],
        }
    }

    /// The file names `<stem>.<extension>`, in the order of [`Graphic::extensions`].
    pub fn file_names(&self) -> [String; 2] {
        self.extensions().map(|ext| format!("{}.{ext}", self.stem))
    }

    /// Renders the files in memory, in the order of [`Graphic::file_names`]: a figure's SVG
    /// ([`Figure::to_svg`]) and PNG ([`Figure::to_png`]), an animation's GIF
    /// ([`Animation::to_gif`]) and animated SVG ([`Animation::to_svg`]).
    ///
    /// # Errors
    /// The plot crate's rendering errors (bad options, data that cannot be drawn).
    pub fn render(&self) -> Result<Vec<RenderedFile>, PlotError> {
        let bytes: [Vec<u8>; 2] = match &self.kind {
            GraphicKind::Figure(f) => [f.to_svg()?.into_bytes(), f.to_png()?],
            GraphicKind::Animation(a) => [a.to_gif()?, a.to_svg()?.into_bytes()],
        };
        Ok(self
            .file_names()
            .into_iter()
            .zip(bytes)
            .map(|(name, bytes)| RenderedFile { name, bytes })
            .collect())
    }
}

impl ExampleOutput {
    /// Renders every figure of example `id` in order ([`Graphic::render`]) and hands each file
    /// to `write` with its path `dir/<file name>`; returns the paths. The book writes nothing
    /// itself: the front end's `write` does (e.g. `std::fs::write`), so the CLI, the report and
    /// the Python package share this one loop.
    ///
    /// # Errors
    /// [`BookError::Figure`] when a figure cannot be rendered; [`BookError::WriteFigure`] with
    /// the path when `write` fails.
    pub fn emit_figures(
        &self,
        id: &str,
        dir: &Path,
        mut write: impl FnMut(&Path, &[u8]) -> std::io::Result<()>,
    ) -> Result<Vec<PathBuf>, BookError> {
        let mut files = Vec::new();
        for g in &self.figures {
            let rendered = g.render().map_err(|source| BookError::Figure {
                id: id.to_string(),
                stem: g.stem.clone(),
                source,
            })?;
            for f in rendered {
                let path = dir.join(&f.name);
                write(&path, &f.bytes).map_err(|source| BookError::WriteFigure {
                    id: id.to_string(),
                    path: path.clone(),
                    source,
                })?;
                files.push(path);
            }
        }
        Ok(files)
    }
}

/// How a computed value compares with the book's value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    /// Name of the value.
    pub name: String,
    /// Largest absolute difference over the elements (`None` if shapes or kinds differ, or the
    /// example did not report the value).
    pub max_abs_error: Option<f64>,
    /// Whether the difference is within the reference's tolerance.
    pub reproduced: bool,
}

impl Value {
    /// Largest absolute elementwise difference to `other`, or `None` when the kinds or shapes
    /// differ. Complex lists are compared element by element in order (sort both the same way).
    pub fn max_abs_diff(&self, other: &Value) -> Option<f64> {
        fn vec_diff(a: &[f64], b: &[f64]) -> Option<f64> {
            (a.len() == b.len()).then(|| {
                a.iter()
                    .zip(b)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max)
            })
        }
        match (self, other) {
            (Value::Bool(a), Value::Bool(b)) => Some(if a == b { 0.0 } else { f64::INFINITY }),
            (Value::Number(a), Value::Number(b)) => Some((a - b).abs()),
            (Value::Vector(a), Value::Vector(b)) => vec_diff(a, b),
            (Value::Matrix(a), Value::Matrix(b)) => {
                if a.len() != b.len() {
                    return None;
                }
                a.iter()
                    .zip(b)
                    .map(|(r, s)| vec_diff(r, s))
                    .try_fold(0.0, |m, d| d.map(|d| f64::max(m, d)))
            }
            (Value::Complex(a), Value::Complex(b)) => (a.len() == b.len()).then(|| {
                a.iter()
                    .zip(b)
                    .map(|(x, y)| (x - y).norm())
                    .fold(0.0, f64::max)
            }),
            _ => None,
        }
    }
}

impl ExampleOutput {
    /// Compares every reference with the computed value of the same name.
    pub fn comparisons(&self) -> Vec<Comparison> {
        self.references
            .iter()
            .map(|r| {
                let err = self.get(&r.name).and_then(|v| v.max_abs_diff(&r.value));
                Comparison {
                    name: r.name.clone(),
                    max_abs_error: err,
                    reproduced: err.is_some_and(|e| e <= r.tolerance),
                }
            })
            .collect()
    }
}
