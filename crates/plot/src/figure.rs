//! Figures: panels laid out in rows and columns, rendered to SVG and PNG.

use std::path::{Path, PathBuf};

use std::borrow::Cow;

use crate::axes::{Axes, LegendPos, Margins, PanelLayout, TITLE_FONT};
use crate::canvas::{Canvas, HAlign, RasterCanvas, SvgCanvas, TextStyle, VAlign, encode_png_rgb};
use crate::error::{PlotError, Result};
use crate::geometry::Rect;
use crate::surface::Surface;

/// One cell of a figure's layout.
#[derive(Debug, Clone)]
pub enum Panel {
    /// A Cartesian plot.
    Axes(Axes),
    /// A 3-D surface.
    Surface(Surface),
    /// Nothing (leaves a gap in a grid).
    Empty,
}

impl From<Axes> for Panel {
    fn from(a: Axes) -> Self {
        Panel::Axes(a)
    }
}
impl From<Surface> for Panel {
    fn from(s: Surface) -> Self {
        Panel::Surface(s)
    }
}

/// A raster image: `rgba` holds `width × height` pixels, row by row, 4 bytes each (not
/// premultiplied).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Raster {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixel bytes, RGBA.
    pub rgba: Vec<u8>,
}

impl Raster {
    /// The pixel at column `x`, row `y` (row 0 at the top), or `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 4 * (y as usize * self.width as usize + x as usize);
        Some([
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ])
    }
}

/// Paths of the files written by [`Figure::save`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SavedFigure {
    /// The SVG file.
    pub svg: PathBuf,
    /// The PNG file.
    pub png: PathBuf,
}

/// A figure: an optional title over rows of panels.
///
/// Sizes are in CSS pixels (SVG user units). The PNG has the same layout at
/// [`Figure::png_scale`] device pixels per CSS pixel (default 2, recorded as 192 dpi).
///
/// ```
/// use pendulab_plot::{Axes, Figure};
/// let t = [0.0, 1.0, 2.0];
/// let mut z = Axes::new();
/// z.ylabel("z [m]").plot(&t, &[0.0, 0.1, 0.2]).label("cart");
/// let mut th = Axes::new();
/// th.xlabel("time [s]").ylabel("θ [deg]").plot(&t, &[10.0, 0.0, -1.0]);
/// let fig = Figure::column([z, th]).title("LQR, θ(0) = 10°");
/// let png = fig.to_png().unwrap();
/// assert_eq!(&png[1..4], b"PNG");
/// ```
#[derive(Debug, Clone)]
pub struct Figure {
    rows: Vec<Vec<Panel>>,
    title: Option<String>,
    size: Option<(f64, f64)>,
    png_scale: f64,
}

/// A [`LegendPos::Best`] legend that covers data moves outside the plot only if it is at most
/// this fraction of the plot's width wide: a wider one would squeeze the plot more than it helps.
pub const MAX_OUTSIDE_LEGEND: f64 = 0.4;

/// Default width of a figure with one column, in CSS pixels.
pub const DEFAULT_WIDTH: f64 = 640.0;

fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    std::fs::write(path, bytes).map_err(|source| PlotError::Io {
        path: path.to_path_buf(),
        source,
    })
}

impl Figure {
    /// A figure of one panel.
    pub fn new(panel: impl Into<Panel>) -> Self {
        Self::grid(vec![vec![panel.into()]])
    }
    /// Panels stacked top to bottom (e.g. z and θ over the same time axis).
    pub fn column<P: Into<Panel>>(panels: impl IntoIterator<Item = P>) -> Self {
        Self::grid(panels.into_iter().map(|p| vec![p.into()]).collect())
    }
    /// Panels side by side.
    pub fn row<P: Into<Panel>>(panels: impl IntoIterator<Item = P>) -> Self {
        Self::grid(vec![panels.into_iter().map(Into::into).collect()])
    }
    /// Rows of panels; each row divides the width equally among its panels.
    pub fn grid(rows: Vec<Vec<Panel>>) -> Self {
        Self {
            rows,
            title: None,
            size: None,
            png_scale: 2.0,
        }
    }
    /// Figure title, above all panels.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// Size in CSS pixels (default: 640 wide for one column, +300 per further column; 420 high
    /// for one row, 235 per row when stacked, plus the title).
    pub fn size(mut self, width: f64, height: f64) -> Self {
        self.size = Some((width, height));
        self
    }
    /// Device pixels per CSS pixel of the PNG (default 2).
    pub fn png_scale(mut self, scale: f64) -> Self {
        self.png_scale = scale;
        self
    }
    /// The panel at `row`, `col`, if it is a Cartesian plot.
    pub fn axes_mut(&mut self, row: usize, col: usize) -> Option<&mut Axes> {
        match self.rows.get_mut(row)?.get_mut(col)? {
            Panel::Axes(a) => Some(a),
            _ => None,
        }
    }
    /// Width and height in CSS pixels.
    pub fn dimensions(&self) -> (f64, f64) {
        if let Some(s) = self.size {
            return s;
        }
        let cols = self.rows.iter().map(Vec::len).max().unwrap_or(1).max(1);
        let n = self.rows.len().max(1);
        let w = DEFAULT_WIDTH + 300.0 * (cols - 1) as f64;
        let h = if n == 1 {
            420.0
        } else {
            235.0 * n as f64 + 20.0
        };
        (w, h + if self.title.is_some() { 26.0 } else { 0.0 })
    }

    fn check(&self) -> Result<()> {
        let (w, h) = self.dimensions();
        if !(w.is_finite()
            && h.is_finite()
            && w >= 50.0
            && h >= 50.0
            && w <= 20_000.0
            && h <= 20_000.0)
        {
            return Err(PlotError::InvalidArgument(format!(
                "figure size {w} x {h} px must be between 50 and 20000"
            )));
        }
        if !(self.png_scale.is_finite() && self.png_scale > 0.0 && self.png_scale <= 8.0) {
            return Err(PlotError::InvalidArgument(format!(
                "PNG scale {} must be in (0, 8]",
                self.png_scale
            )));
        }
        if self.rows.iter().all(|r| r.is_empty()) {
            return Err(PlotError::Empty {
                what: "figure (no panels)".into(),
            });
        }
        let mut k = 0;
        for row in &self.rows {
            for p in row {
                match p {
                    Panel::Axes(a) => a.check(k)?,
                    Panel::Surface(s) => s.check(k)?,
                    Panel::Empty => {}
                }
                k += 1;
            }
        }
        Ok(())
    }

    fn draw(&self, c: &mut dyn Canvas) -> Result<Vec<PanelLayout>> {
        let (w, h) = self.dimensions();
        let mut top = 0.0;
        if let Some(t) = &self.title {
            let mut ts = TextStyle::new(TITLE_FONT + 1.5, HAlign::Center, VAlign::Top);
            ts.bold = true;
            c.text(t, (w / 2.0, 10.0), &ts);
            top = 26.0;
        }
        let nrows = self.rows.len().max(1);
        let row_h = (h - top - 4.0) / nrows as f64;
        // Outer rectangles and margins of every panel.
        let mut cells: Vec<Vec<(Rect, Margins)>> = Vec::new();
        for (r, row) in self.rows.iter().enumerate() {
            let ncols = row.len().max(1);
            let col_w = (w - 4.0) / ncols as f64;
            let mut v = Vec::new();
            for (k, p) in row.iter().enumerate() {
                let outer = Rect::new(2.0 + k as f64 * col_w, top + r as f64 * row_h, col_w, row_h);
                let m = match p {
                    Panel::Axes(a) => a.margins(&outer)?,
                    _ => Margins::default(),
                };
                v.push((outer, m));
            }
            cells.push(v);
        }
        // Align plot edges: the same left/right margins down a column of equally divided rows,
        // the same top/bottom margins along a row.
        let maxcols = self.rows.iter().map(Vec::len).max().unwrap_or(0);
        for col in 0..maxcols {
            let members: Vec<(usize, usize)> = (0..cells.len())
                .filter(|&r| {
                    cells[r].len() == maxcols && matches!(self.rows[r][col], Panel::Axes(_))
                })
                .map(|r| (r, col))
                .collect();
            let l = members
                .iter()
                .map(|&(r, c)| cells[r][c].1.left)
                .fold(0.0, f64::max);
            let rr = members
                .iter()
                .map(|&(r, c)| cells[r][c].1.right)
                .fold(0.0, f64::max);
            for (r, c) in members {
                cells[r][c].1.left = l;
                cells[r][c].1.right = rr;
            }
        }
        for (r, row) in cells.iter_mut().enumerate() {
            let idx: Vec<usize> = (0..row.len())
                .filter(|&k| matches!(self.rows[r][k], Panel::Axes(_)))
                .collect();
            let t = idx.iter().map(|&k| row[k].1.top).fold(0.0, f64::max);
            let b = idx.iter().map(|&k| row[k].1.bottom).fold(0.0, f64::max);
            for k in idx {
                row[k].1.top = t;
                row[k].1.bottom = b;
            }
        }
        let mut layouts = Vec::new();
        for (r, row) in self.rows.iter().enumerate() {
            for (k, p) in row.iter().enumerate() {
                let (outer, m) = cells[r][k];
                match p {
                    Panel::Axes(a) => {
                        let rect = Rect {
                            x0: outer.x0 + m.left,
                            y0: outer.y0 + m.top,
                            x1: outer.x1 - m.right,
                            y1: outer.y1 - m.bottom,
                        };
                        layouts.push(a.draw(c, rect)?);
                    }
                    Panel::Surface(s) => s.draw(c, outer)?,
                    Panel::Empty => {}
                }
            }
        }
        Ok(layouts)
    }

    /// This figure with every [`LegendPos::Best`] legend that would cover data moved outside
    /// its plot area ([`LegendPos::Outside`]), unless the legend is wider than
    /// [`MAX_OUTSIDE_LEGEND`] of the plot (then it stays at its least covering inside place). Moving one changes the column's margins, so the
    /// layout is redone until nothing moves (at most once per panel).
    fn resolved(&self) -> Result<Cow<'_, Figure>> {
        let mut fig = Cow::Borrowed(self);
        let (w, h) = self.dimensions();
        loop {
            let mut c = SvgCanvas::new(w, h)?;
            let layouts = fig.draw(&mut c)?;
            let mut moved = false;
            let mut k = 0;
            let mut next = (*fig).clone();
            for row in &mut next.rows {
                for p in row {
                    if let Panel::Axes(a) = p {
                        let l = &layouts[k];
                        let narrow = l.legend.is_some_and(|b| {
                            b[2] - b[0] <= MAX_OUTSIDE_LEGEND * (l.plot[2] - l.plot[0])
                        });
                        if a.legend_pos() == LegendPos::Best
                            && l.points_under_legend() > 0
                            && narrow
                        {
                            a.legend(LegendPos::Outside);
                            moved = true;
                        }
                        k += 1;
                    }
                }
            }
            if !moved {
                return Ok(fig);
            }
            fig = Cow::Owned(next);
        }
    }

    /// Where the parts of every Cartesian panel land (plot rectangle, legend box, drawn
    /// points), row by row and left to right, as [`Figure::to_svg`] draws them; surfaces and
    /// empty cells are skipped. For checking a figure's legibility, e.g. that no legend covers
    /// data: [`PanelLayout::points_under_legend`].
    ///
    /// # Errors
    /// As [`Figure::to_svg`].
    pub fn layout(&self) -> Result<Vec<PanelLayout>> {
        self.check()?;
        let (w, h) = self.dimensions();
        let mut c = SvgCanvas::new(w, h)?;
        self.resolved()?.draw(&mut c)
    }

    /// The figure as an SVG document.
    ///
    /// # Errors
    /// Bad data in a panel ([`PlotError`] naming panel, series and sample), or a bad size.
    pub fn to_svg(&self) -> Result<String> {
        self.check()?;
        let (w, h) = self.dimensions();
        let mut c = SvgCanvas::new(w, h)?;
        if let Some(t) = &self.title {
            c.out.push_str(&format!(
                "<title>{}</title>\n",
                crate::canvas::xml_escape(t)
            ));
        }
        self.resolved()?.draw(&mut c)?;
        Ok(c.finish())
    }

    /// The figure as pixels, at the PNG scale.
    ///
    /// # Errors
    /// As [`Figure::to_svg`].
    pub fn to_raster(&self) -> Result<Raster> {
        let c = self.raster_canvas()?;
        let (width, height) = c.size();
        Ok(Raster {
            width,
            height,
            rgba: c.rgba(),
        })
    }

    fn raster_canvas(&self) -> Result<RasterCanvas> {
        self.check()?;
        let (w, h) = self.dimensions();
        let mut c = RasterCanvas::new(w, h, self.png_scale)?;
        self.resolved()?.draw(&mut c)?;
        Ok(c)
    }

    /// The figure as an encoded PNG (RGB, 8 bit, resolution 96 × scale dpi).
    ///
    /// # Errors
    /// As [`Figure::to_svg`], and [`PlotError::Encode`].
    pub fn to_png(&self) -> Result<Vec<u8>> {
        let c = self.raster_canvas()?;
        encode_png_rgb(&c, Some(96.0 * self.png_scale))
    }

    /// Writes the SVG to `path`.
    ///
    /// # Errors
    /// As [`Figure::to_svg`], and [`PlotError::Io`] naming the path.
    pub fn save_svg(&self, path: impl AsRef<Path>) -> Result<()> {
        write_file(path.as_ref(), self.to_svg()?.as_bytes())
    }

    /// Writes the PNG to `path`.
    ///
    /// # Errors
    /// As [`Figure::to_png`], and [`PlotError::Io`] naming the path.
    pub fn save_png(&self, path: impl AsRef<Path>) -> Result<()> {
        write_file(path.as_ref(), &self.to_png()?)
    }

    /// Writes `dir/stem.svg` and `dir/stem.png`, creating `dir` if needed.
    ///
    /// # Errors
    /// As [`Figure::save_svg`] and [`Figure::save_png`]; [`PlotError::Io`] naming `dir` if it
    /// cannot be created.
    pub fn save(&self, dir: impl AsRef<Path>, stem: &str) -> Result<SavedFigure> {
        let dir = dir.as_ref();
        if stem.is_empty() || stem.contains(['/', '\\']) {
            return Err(PlotError::InvalidArgument(format!(
                "file stem {stem:?} must be a non-empty name without path separators"
            )));
        }
        std::fs::create_dir_all(dir).map_err(|source| PlotError::Io {
            path: dir.to_path_buf(),
            source,
        })?;
        let svg = dir.join(format!("{stem}.svg"));
        let png = dir.join(format!("{stem}.png"));
        self.save_svg(&svg)?;
        self.save_png(&png)?;
        Ok(SavedFigure { svg, png })
    }
}
