//! Animations of the two rigs, drawn with the book's geometry (`docs/model.md` §1–2, the IP
//! Toolbox's `cdip_anime` and `adip_anime`), as animated GIF (any viewer) and as animated SVG
//! (SMIL, plays in a browser without scripts or network, also inside `<img>`).
//!
//! The state comes in as plain numbers sampled at any rate (typically 1 kHz); frames are taken
//! at the playback frame rate by linear interpolation, so a 10 s run at 25 frames/s needs 251
//! frames whatever the simulation step. Playback is in real time unless a speed factor is set;
//! when the run is longer than `max_frames` allows, the frame rate is lowered (never the speed).
//!
//! ```
//! use pendulab_plot::{Animation, AnimationOptions, CartGeometry};
//! let t: Vec<f64> = (0..=2000).map(|k| k as f64 * 1e-3).collect();
//! let z: Vec<f64> = t.iter().map(|t| 0.1 * t).collect();
//! let th: Vec<f64> = t.iter().map(|t| 0.2 * (3.0 * t).cos()).collect();
//! let anim = Animation::cart(&t, &z, &th, CartGeometry::default()).unwrap()
//!     .options(AnimationOptions { fps: 10.0, ..Default::default() });
//! assert_eq!(anim.frame_times().len(), 21);
//! let gif = anim.to_gif().unwrap();
//! assert_eq!(&gif[..6], b"GIF89a");
//! assert!(anim.to_svg().unwrap().contains("<animateTransform"));
//! ```

use std::borrow::Cow;
use std::fmt::Write as _;
use std::path::Path;

use crate::canvas::{
    Canvas, HAlign, RasterCanvas, TextStyle, VAlign, encode_png_rgb, num, xml_escape,
};
use crate::color::Color;
use crate::error::{PlotError, Result};
use crate::font::SVG_FONT_FAMILY;
use crate::style::LineStyle;
use draw::{ARM, DARK, POST, RAIL, View, draw_cart_body, draw_rod};
use frames::{Palette, TRANSPARENT, changed_box};

mod draw;
mod frames;

/// Drawing geometry of the cart-type pendulum, in metres. θ is measured from the upright
/// vertical; the pendulum tip is at (z + L sin θ, L cos θ) relative to the rail's height at
/// the pivot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartGeometry {
    /// Drawing length L_p of the pendulum (book: 0.38 m).
    pub pendulum_length: f64,
    /// Cart body width.
    pub cart_width: f64,
    /// Cart body height.
    pub cart_height: f64,
    /// Wheel radius.
    pub wheel_radius: f64,
    /// Rail extent (left and right end positions of z).
    pub rail: (f64, f64),
    /// Radius of the pendulum's bob.
    pub bob_radius: f64,
}

impl Default for CartGeometry {
    fn default() -> Self {
        Self {
            pendulum_length: 0.38,
            cart_width: 0.14,
            cart_height: 0.07,
            wheel_radius: 0.016,
            rail: (-0.5, 0.5),
            bob_radius: 0.018,
        }
    }
}

/// Drawing geometry of the arm-type pendulum, in metres. θ₁ (arm) and θ₂ (pendulum, absolute)
/// are measured from the upright vertical: arm tip (L₁ sin θ₁, L₁ cos θ₁), pendulum tip = arm tip
/// + L₂ (sin θ₂, cos θ₂), both relative to the arm's pivot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmGeometry {
    /// Arm length L₁ (book: 0.227 m).
    pub arm_length: f64,
    /// Pendulum length L₂ (book: 0.300 m).
    pub pendulum_length: f64,
    /// Radius of the pendulum's bob.
    pub bob_radius: f64,
}

impl Default for ArmGeometry {
    fn default() -> Self {
        Self {
            arm_length: 0.227,
            pendulum_length: 0.300,
            bob_radius: 0.018,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Rig {
    Cart(CartGeometry),
    Arm(ArmGeometry),
}

/// Playback and picture settings of an [`Animation`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnimationOptions {
    /// Frames per second wanted (default 25; GIF delays are whole hundredths of a second, so
    /// the rate used is 100 / round(100 / fps)).
    pub fps: f64,
    /// Upper bound on the number of frames (default 150); longer runs get a lower frame rate.
    pub max_frames: usize,
    /// Playback speed relative to real time (default 1).
    pub speed: f64,
    /// Picture width in pixels (default 480).
    pub width: u32,
    /// Picture height in pixels (default 320).
    pub height: u32,
    /// Seconds the last frame is held before the animation repeats (default 1).
    pub hold: f64,
    /// Show the simulation time in the upper left corner (default on).
    pub show_time: bool,
}

impl Default for AnimationOptions {
    fn default() -> Self {
        Self {
            fps: 25.0,
            max_frames: 150,
            speed: 1.0,
            width: 480,
            height: 320,
            hold: 1.0,
            show_time: true,
        }
    }
}

/// What an animation writer produced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnimationInfo {
    /// Number of frames.
    pub frames: usize,
    /// Time between frames during playback, in seconds.
    pub frame_interval: f64,
    /// Size of the encoded file in bytes.
    pub bytes: usize,
}

/// An animation of one of the rigs over a sampled trajectory.
#[derive(Debug, Clone)]
pub struct Animation {
    rig: Rig,
    t: Vec<f64>,
    a: Vec<f64>,
    b: Vec<f64>,
    opts: AnimationOptions,
    title: Option<String>,
}

fn check_series(name: &str, t: &[f64], a: &[f64], b: &[f64], an: &str, bn: &str) -> Result<()> {
    if t.is_empty() {
        return Err(PlotError::Empty {
            what: format!("{name} animation"),
        });
    }
    for (n, v) in [(an, a), (bn, b)] {
        if v.len() != t.len() {
            return Err(PlotError::LengthMismatch {
                what: format!("{name} animation (time vs {n})"),
                left: t.len(),
                right: v.len(),
            });
        }
    }
    for (n, v) in [("time", t), (an, a), (bn, b)] {
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(PlotError::NonFinite {
                what: format!("{name} animation ({n})"),
                index: i,
                value: v[i],
            });
        }
    }
    if let Some(i) = t.windows(2).position(|w| w[1] < w[0]) {
        return Err(PlotError::InvalidArgument(format!(
            "{name} animation: time decreases between samples {i} and {}",
            i + 1
        )));
    }
    Ok(())
}

impl Animation {
    /// The cart-type pendulum over samples `t` \[s\] of the cart position `z` \[m\] and the pendulum
    /// angle `theta` \[rad\] from upright.
    ///
    /// # Errors
    /// [`PlotError::Empty`], [`PlotError::LengthMismatch`], [`PlotError::NonFinite`] (NaN is
    /// rejected: an animation cannot leave a gap), [`PlotError::InvalidArgument`] for decreasing
    /// time or a bad geometry.
    pub fn cart(t: &[f64], z: &[f64], theta: &[f64], geometry: CartGeometry) -> Result<Self> {
        check_series("cart", t, z, theta, "z", "θ")?;
        let g = geometry;
        let ok = [
            g.pendulum_length,
            g.cart_width,
            g.cart_height,
            g.wheel_radius,
            g.bob_radius,
        ]
        .iter()
        .all(|v| v.is_finite() && *v > 0.0)
            && g.rail.0.is_finite()
            && g.rail.1.is_finite()
            && g.rail.0 < g.rail.1;
        if !ok {
            return Err(PlotError::InvalidArgument(format!(
                "cart geometry {g:?}: lengths must be positive and the rail increasing"
            )));
        }
        Ok(Self {
            rig: Rig::Cart(geometry),
            t: t.to_vec(),
            a: z.to_vec(),
            b: theta.to_vec(),
            opts: AnimationOptions::default(),
            title: None,
        })
    }

    /// The arm-type pendulum over samples `t` \[s\] of the arm angle `theta1` and the absolute
    /// pendulum angle `theta2` \[rad\], both from upright.
    ///
    /// # Errors
    /// As [`Animation::cart`].
    pub fn arm(t: &[f64], theta1: &[f64], theta2: &[f64], geometry: ArmGeometry) -> Result<Self> {
        check_series("arm", t, theta1, theta2, "θ₁", "θ₂")?;
        let g = geometry;
        if ![g.arm_length, g.pendulum_length, g.bob_radius]
            .iter()
            .all(|v| v.is_finite() && *v > 0.0)
        {
            return Err(PlotError::InvalidArgument(format!(
                "arm geometry {g:?}: lengths must be positive"
            )));
        }
        Ok(Self {
            rig: Rig::Arm(geometry),
            t: t.to_vec(),
            a: theta1.to_vec(),
            b: theta2.to_vec(),
            opts: AnimationOptions::default(),
            title: None,
        })
    }

    /// Sets the playback and picture options.
    pub fn options(mut self, opts: AnimationOptions) -> Self {
        self.opts = opts;
        self
    }

    /// Title drawn at the top of every frame.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }

    fn check_options(&self) -> Result<()> {
        let o = &self.opts;
        if !(o.fps.is_finite() && o.fps > 0.0 && o.fps <= 50.0) {
            return Err(PlotError::InvalidArgument(format!(
                "frame rate {} must be in (0, 50]",
                o.fps
            )));
        }
        if !(o.speed.is_finite() && o.speed > 0.0) {
            return Err(PlotError::InvalidArgument(format!(
                "speed {} must be positive",
                o.speed
            )));
        }
        if o.max_frames < 2 {
            return Err(PlotError::InvalidArgument(format!(
                "max_frames {} must be at least 2",
                o.max_frames
            )));
        }
        if !(64..=4096).contains(&o.width) || !(64..=4096).contains(&o.height) {
            return Err(PlotError::InvalidArgument(format!(
                "picture size {} x {} must be between 64 and 4096 pixels",
                o.width, o.height
            )));
        }
        if !(o.hold.is_finite() && (0.0..=60.0).contains(&o.hold)) {
            return Err(PlotError::InvalidArgument(format!(
                "hold {} s must be in [0, 60]",
                o.hold
            )));
        }
        Ok(())
    }

    /// Frame delay in hundredths of a second and the simulation times of the frames.
    fn schedule(&self) -> (u16, Vec<f64>) {
        let o = &self.opts;
        let t0 = self.t[0];
        let dur = self.t[self.t.len() - 1] - t0;
        // GIF delays are whole hundredths of a second; browsers treat delays below 2 as 10.
        let base = (100.0 / o.fps).round().max(2.0);
        let need = (dur / o.speed * 100.0 / (o.max_frames - 1) as f64).ceil();
        let delay = base.max(need).min(u16::MAX as f64);
        // Frame spacing in simulation time; the second bound only matters when the delay is
        // clamped (runs of many hours), where playback then goes faster than `speed`.
        let dt = (delay / 100.0 * o.speed).max(dur / (o.max_frames - 1) as f64);
        let n = if dur > 0.0 {
            (dur / dt + 1e-9).floor() as usize + 1
        } else {
            1
        };
        let n = n.min(o.max_frames);
        (delay as u16, (0..n).map(|k| t0 + k as f64 * dt).collect())
    }

    /// Simulation times at which frames are drawn.
    pub fn frame_times(&self) -> Vec<f64> {
        self.schedule().1
    }

    /// The two state values at time `t` by linear interpolation (held outside the samples).
    fn state_at(&self, t: f64) -> (f64, f64) {
        let n = self.t.len();
        if t <= self.t[0] || n == 1 {
            return (self.a[0], self.b[0]);
        }
        if t >= self.t[n - 1] {
            return (self.a[n - 1], self.b[n - 1]);
        }
        let k = self.t.partition_point(|v| *v <= t).max(1) - 1;
        let (ta, tb) = (self.t[k], self.t[k + 1]);
        let s = if tb > ta { (t - ta) / (tb - ta) } else { 0.0 };
        (
            self.a[k] + s * (self.a[k + 1] - self.a[k]),
            self.b[k] + s * (self.b[k + 1] - self.b[k]),
        )
    }

    /// World window (x0, x1, y0, y1) in metres and the pixel mapping.
    fn view(&self) -> View {
        let (w, h) = (self.opts.width as f64, self.opts.height as f64);
        let top = if self.title.is_some() { 30.0 } else { 10.0 };
        // The window covers the motion actually drawn, plus the static parts.
        let (mut x0, mut x1, mut y0, mut y1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        let mut cover = |x: f64, y: f64, r: f64| {
            x0 = x0.min(x - r);
            x1 = x1.max(x + r);
            y0 = y0.min(y - r);
            y1 = y1.max(y + r);
        };
        match self.rig {
            Rig::Cart(g) => {
                let l = g.pendulum_length;
                for (z, th) in self.a.iter().zip(&self.b) {
                    cover(z + l * th.sin(), l * th.cos(), g.bob_radius + 0.02);
                    cover(*z, 0.0, g.cart_width / 2.0 + 0.02);
                }
                cover(g.rail.0 - g.cart_width / 2.0, 0.0, 0.02);
                cover(g.rail.1 + g.cart_width / 2.0, 0.0, 0.02);
                cover(0.0, -(g.cart_height / 2.0 + 2.0 * g.wheel_radius), 0.04);
                cover(0.0, g.cart_height / 2.0, 0.04);
            }
            Rig::Arm(g) => {
                for (a, b) in self.a.iter().zip(&self.b) {
                    let (ax, ay) = (g.arm_length * a.sin(), g.arm_length * a.cos());
                    cover(ax, ay, 0.03);
                    cover(
                        ax + g.pendulum_length * b.sin(),
                        ay + g.pendulum_length * b.cos(),
                        g.bob_radius + 0.02,
                    );
                }
                cover(0.0, 0.0, 0.13);
                cover(0.0, -Self::post_height(&g) - 0.02, 0.02);
            }
        }
        let scale = ((w - 20.0) / (x1 - x0)).min((h - top - 10.0) / (y1 - y0));
        let cx = w / 2.0 - scale * (x0 + x1) / 2.0;
        let cy = top + (h - top - 10.0) / 2.0 + scale * (y0 + y1) / 2.0;
        View { scale, cx, cy }
    }

    /// Draws the frame at simulation time `t` onto a canvas of the picture size.
    fn draw_frame(&self, c: &mut dyn Canvas, t: f64) {
        let v = self.view();
        let (qa, qb) = self.state_at(t);
        let (w, _) = (self.opts.width as f64, self.opts.height as f64);
        self.draw_static(c, &v);
        match self.rig {
            Rig::Cart(g) => {
                let s = v.scale;
                let p = v.p(qa, 0.0);
                draw_cart_body(c, p, &g, s);
                let tip = v.p(
                    qa + g.pendulum_length * qb.sin(),
                    g.pendulum_length * qb.cos(),
                );
                draw_rod(c, p, tip, g.bob_radius * s);
            }
            Rig::Arm(g) => {
                let s = v.scale;
                let p = v.p(0.0, 0.0);
                let arm = v.p(g.arm_length * qa.sin(), g.arm_length * qa.cos());
                c.polyline(&[p, arm], &LineStyle::new(ARM, (0.022 * s).max(3.0)));
                c.circle(p, (0.012 * s).max(2.5), Some(DARK), None);
                let tip = v.p(
                    g.arm_length * qa.sin() + g.pendulum_length * qb.sin(),
                    g.arm_length * qa.cos() + g.pendulum_length * qb.cos(),
                );
                draw_rod(c, arm, tip, g.bob_radius * s);
            }
        }
        if self.opts.show_time {
            let mut ts = TextStyle::new(13.0, HAlign::Left, VAlign::Top);
            ts.color = Color::DARK_GREY;
            c.text(
                &format!("t = {:.2} s", t - self.t[0]),
                (10.0, if self.title.is_some() { 34.0 } else { 10.0 }),
                &ts,
            );
        }
        if let Some(title) = &self.title {
            c.text(
                title,
                (w / 2.0, 10.0),
                &TextStyle::new(14.0, HAlign::Center, VAlign::Top),
            );
        }
    }

    /// Height of the arm rig's post below the pivot [m].
    fn post_height(g: &ArmGeometry) -> f64 {
        0.5 * (g.arm_length + g.pendulum_length)
    }

    /// Parts that never move: rail, or base and post.
    fn draw_static(&self, c: &mut dyn Canvas, v: &View) {
        match self.rig {
            Rig::Cart(g) => {
                let y = -(g.cart_height / 2.0 + 2.0 * g.wheel_radius);
                let a = v.p(g.rail.0 - g.cart_width / 2.0, y);
                let b = v.p(g.rail.1 + g.cart_width / 2.0, y);
                c.polyline(&[a, b], &LineStyle::new(RAIL, (0.008 * v.scale).max(2.5)));
                for e in [g.rail.0 - g.cart_width / 2.0, g.rail.1 + g.cart_width / 2.0] {
                    let p = v.p(e, y);
                    c.polyline(
                        &[(p.0, p.1 - 0.03 * v.scale), (p.0, p.1 + 0.015 * v.scale)],
                        &LineStyle::new(DARK, 3.0),
                    );
                }
            }
            Rig::Arm(g) => {
                let base_y = -Self::post_height(&g);
                let p = v.p(0.0, 0.0);
                let q = v.p(0.0, base_y);
                let hw = 0.025 * v.scale;
                c.polygon(
                    &[
                        (p.0 - hw, p.1),
                        (p.0 + hw, p.1),
                        (q.0 + hw, q.1),
                        (q.0 - hw, q.1),
                    ],
                    Some(POST),
                    Some(&LineStyle::new(DARK, 1.0)),
                );
                let bw = 0.12 * v.scale;
                c.polygon(
                    &[
                        (q.0 - bw, q.1),
                        (q.0 + bw, q.1),
                        (q.0 + bw, q.1 + 0.015 * v.scale),
                        (q.0 - bw, q.1 + 0.015 * v.scale),
                    ],
                    Some(DARK),
                    None,
                );
            }
        }
    }

    fn raster_frame(&self, c: &mut RasterCanvas, t: f64) {
        c.clear(Color::WHITE);
        self.draw_frame(c, t);
    }

    /// A still picture (PNG) of the rig at simulation time `t`, e.g. a poster frame.
    ///
    /// # Errors
    /// Bad options ([`PlotError::InvalidArgument`]) or [`PlotError::Encode`].
    pub fn frame_png(&self, t: f64) -> Result<Vec<u8>> {
        self.check_options()?;
        let mut c = RasterCanvas::new(self.opts.width as f64, self.opts.height as f64, 1.0)?;
        self.raster_frame(&mut c, t);
        encode_png_rgb(&c, None)
    }

    /// The animation as an animated GIF (looping), in memory.
    ///
    /// Every frame is drawn anti-aliased, mapped to one fixed palette of the scene's colours
    /// and their blends with white, and only the pixels that changed since the previous frame
    /// are stored (the rest is transparent), which keeps files small.
    ///
    /// # Errors
    /// Bad options ([`PlotError::InvalidArgument`]) or [`PlotError::Encode`].
    pub fn to_gif(&self) -> Result<Vec<u8>> {
        Ok(self.encode_gif()?.0)
    }

    fn encode_gif(&self) -> Result<(Vec<u8>, AnimationInfo)> {
        self.check_options()?;
        let (delay, times) = self.schedule();
        let (w, h) = (self.opts.width, self.opts.height);
        let pal = Palette::new();
        let mut out = Vec::new();
        let enc_err = |e: gif::EncodingError| PlotError::Encode {
            format: "GIF",
            message: e.to_string(),
        };
        {
            let mut enc =
                gif::Encoder::new(&mut out, w as u16, h as u16, &pal.bytes).map_err(enc_err)?;
            enc.set_repeat(gif::Repeat::Infinite).map_err(enc_err)?;
            let mut canvas = RasterCanvas::new(w as f64, h as f64, 1.0)?;
            let mut prev: Option<Vec<u8>> = None;
            for (k, &t) in times.iter().enumerate() {
                self.raster_frame(&mut canvas, t);
                let idx = pal.index_image(canvas.data());
                let mut d = delay;
                if k + 1 == times.len() {
                    d = d.saturating_add((self.opts.hold * 100.0).round() as u16);
                }
                let frame = match &prev {
                    None => gif::Frame {
                        delay: d,
                        width: w as u16,
                        height: h as u16,
                        buffer: Cow::Borrowed(&idx),
                        ..gif::Frame::default()
                    },
                    Some(p) => {
                        let (x0, y0, x1, y1) =
                            changed_box(p, &idx, w as usize, h as usize).unwrap_or((0, 0, 0, 0));
                        let (bw, bh) = (x1 - x0 + 1, y1 - y0 + 1);
                        let mut buf = Vec::with_capacity(bw * bh);
                        for y in y0..=y1 {
                            for x in x0..=x1 {
                                let i = y * w as usize + x;
                                buf.push(if idx[i] == p[i] { TRANSPARENT } else { idx[i] });
                            }
                        }
                        gif::Frame {
                            delay: d,
                            dispose: gif::DisposalMethod::Keep,
                            transparent: Some(TRANSPARENT),
                            left: x0 as u16,
                            top: y0 as u16,
                            width: bw as u16,
                            height: bh as u16,
                            buffer: Cow::Owned(buf),
                            ..gif::Frame::default()
                        }
                    }
                };
                enc.write_frame(&frame).map_err(enc_err)?;
                prev = Some(idx);
            }
        }
        let info = AnimationInfo {
            frames: times.len(),
            frame_interval: delay as f64 / 100.0,
            bytes: out.len(),
        };
        Ok((out, info))
    }

    /// Writes the animated GIF to `path`.
    ///
    /// # Errors
    /// As [`Animation::to_gif`], and [`PlotError::Io`] naming the path.
    pub fn save_gif(&self, path: impl AsRef<Path>) -> Result<AnimationInfo> {
        let (bytes, info) = self.encode_gif()?;
        write(path.as_ref(), &bytes)?;
        Ok(info)
    }

    /// The animation as a self-contained animated SVG: the static parts drawn once, the moving
    /// parts in groups driven by SMIL `<animateTransform>` elements keyed at the frame times
    /// (linear interpolation between frames), the time stamp by discrete `<animate>` of
    /// visibility. Loops, holding the last frame for [`AnimationOptions::hold`] seconds.
    ///
    /// # Errors
    /// Bad options ([`PlotError::InvalidArgument`]).
    pub fn to_svg(&self) -> Result<String> {
        self.check_options()?;
        let (delay, times) = self.schedule();
        let n = times.len();
        let dt = delay as f64 / 100.0;
        let total = (n.saturating_sub(1)) as f64 * dt + self.opts.hold.max(0.01);
        let key = |k: usize| k as f64 * dt / total;
        let mut key_times: Vec<String> = (0..n).map(|k| format!("{:.5}", key(k))).collect();
        key_times.push("1".into());
        let key_times = key_times.join(";");
        let v = self.view();
        let (w, h) = (self.opts.width as f64, self.opts.height as f64);
        let states: Vec<(f64, f64)> = times.iter().map(|&t| self.state_at(t)).collect();
        let mut s = String::with_capacity(16 * 1024);
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="{ff}">"#,
            w = num(w),
            h = num(h),
            ff = SVG_FONT_FAMILY.replace('\'', "&#39;")
        );
        let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
        let anim = |values: String, kind: &str| -> String {
            format!(
                r#"<animateTransform attributeName="transform" type="{kind}" dur="{}s" repeatCount="indefinite" calcMode="linear" keyTimes="{key_times}" values="{values}"/>"#,
                num_fine(total)
            )
        };
        let mut svg = crate::canvas::SvgCanvas::new(w, h)?;
        svg.out.clear();
        self.draw_static(&mut svg, &v);
        s.push_str(&svg.out);
        svg.out.clear();
        match self.rig {
            Rig::Cart(g) => {
                let p0 = v.p(0.0, 0.0);
                let mut vals: Vec<String> = states
                    .iter()
                    .map(|(z, _)| format!("{},0", num_fine(z * v.scale)))
                    .collect();
                vals.push(vals[vals.len() - 1].clone());
                let mut angs: Vec<String> = states
                    .iter()
                    .map(|(_, th)| num_fine(th.to_degrees()))
                    .collect();
                angs.push(angs[angs.len() - 1].clone());
                let _ = writeln!(
                    s,
                    r#"<g transform="translate({} {})">"#,
                    num(p0.0),
                    num(p0.1)
                );
                let _ = writeln!(s, "<g>{}", anim(vals.join(";"), "translate"));
                draw_cart_body(&mut svg, (0.0, 0.0), &g, v.scale);
                s.push_str(&svg.out);
                svg.out.clear();
                let _ = writeln!(s, "<g>{}", anim(angs.join(";"), "rotate"));
                draw_rod(
                    &mut svg,
                    (0.0, 0.0),
                    (0.0, -g.pendulum_length * v.scale),
                    g.bob_radius * v.scale,
                );
                s.push_str(&svg.out);
                svg.out.clear();
                s.push_str("</g>\n</g>\n</g>\n");
            }
            Rig::Arm(g) => {
                let p0 = v.p(0.0, 0.0);
                let mut a1: Vec<String> = states
                    .iter()
                    .map(|(a, _)| num_fine(a.to_degrees()))
                    .collect();
                a1.push(a1[a1.len() - 1].clone());
                let mut rel: Vec<String> = states
                    .iter()
                    .map(|(a, b)| num_fine((b - a).to_degrees()))
                    .collect();
                rel.push(rel[rel.len() - 1].clone());
                let la = g.arm_length * v.scale;
                let _ = writeln!(
                    s,
                    r#"<g transform="translate({} {})">"#,
                    num(p0.0),
                    num(p0.1)
                );
                let _ = writeln!(s, "<g>{}", anim(a1.join(";"), "rotate"));
                svg.polyline(
                    &[(0.0, 0.0), (0.0, -la)],
                    &LineStyle::new(ARM, (0.022 * v.scale).max(3.0)),
                );
                s.push_str(&svg.out);
                svg.out.clear();
                let _ = writeln!(
                    s,
                    r#"<g transform="translate(0 {})"><g>{}"#,
                    num(-la),
                    anim(rel.join(";"), "rotate")
                );
                draw_rod(
                    &mut svg,
                    (0.0, 0.0),
                    (0.0, -g.pendulum_length * v.scale),
                    g.bob_radius * v.scale,
                );
                s.push_str(&svg.out);
                svg.out.clear();
                s.push_str("</g></g>\n</g>\n");
                svg.circle((0.0, 0.0), (0.012 * v.scale).max(2.5), Some(DARK), None);
                let _ = writeln!(s, "{}</g>", svg.out.trim_end());
                svg.out.clear();
            }
        }
        if self.opts.show_time {
            let y = if self.title.is_some() { 34.0 } else { 10.0 } + crate::font::cap_height(13.0);
            for (k, t) in times.iter().enumerate() {
                let (vals, kt) = if n == 1 {
                    ("visible".to_string(), "0".to_string())
                } else if k == 0 {
                    ("visible;hidden".to_string(), format!("0;{:.5}", key(1)))
                } else if k + 1 == n {
                    ("hidden;visible".to_string(), format!("0;{:.5}", key(k)))
                } else {
                    (
                        "hidden;visible;hidden".to_string(),
                        format!("0;{:.5};{:.5}", key(k), key(k + 1)),
                    )
                };
                let _ = writeln!(
                    s,
                    r##"<text x="10" y="{}" font-size="13" fill="#404040" visibility="{}">t = {:.2} s<animate attributeName="visibility" calcMode="discrete" dur="{}s" repeatCount="indefinite" keyTimes="{kt}" values="{vals}"/></text>"##,
                    num(y),
                    if k == 0 { "visible" } else { "hidden" },
                    t - self.t[0],
                    num_fine(total)
                );
            }
        }
        if let Some(title) = &self.title {
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}" font-size="14" text-anchor="middle">{}</text>"#,
                num(w / 2.0),
                num(10.0 + crate::font::cap_height(14.0)),
                xml_escape(title)
            );
        }
        s.push_str("</svg>\n");
        Ok(s)
    }

    /// Writes the animated SVG to `path`.
    ///
    /// # Errors
    /// As [`Animation::to_svg`], and [`PlotError::Io`] naming the path.
    pub fn save_svg(&self, path: impl AsRef<Path>) -> Result<AnimationInfo> {
        let s = self.to_svg()?;
        write(path.as_ref(), s.as_bytes())?;
        let (delay, times) = self.schedule();
        Ok(AnimationInfo {
            frames: times.len(),
            frame_interval: delay as f64 / 100.0,
            bytes: s.len(),
        })
    }
}

fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    std::fs::write(path, bytes).map_err(|source| PlotError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Three decimals, for animation values.
fn num_fine(v: f64) -> String {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" || s.is_empty() {
        "0".into()
    } else {
        s.to_string()
    }
}
