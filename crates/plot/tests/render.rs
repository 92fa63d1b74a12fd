//! Rendering tests: every figure type to SVG and PNG on disk, decoded back; pixel positions
//! against the axis mapping measured in the image; animations decoded; typed errors.

use std::f64::consts::PI;
use std::path::PathBuf;

use pendulab_lti::{Complex64, Mat, Trajectory};
use pendulab_plot::{
    Animation, AnimationOptions, ArmGeometry, Axes, Bode, CartGeometry, Channel, Color, Figure,
    GainCurves, IdentFit, PlotError, PoleZeroMap, RegionBound, SignalPanel, Surface, TimeResponse,
    region_of_attraction,
};

/// A fresh directory under the system temp dir, unique per test.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pendulab-plot-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Decodes a PNG file into (width, height, RGB(A) bytes, channels).
fn decode_png(path: &std::path::Path) -> (u32, u32, Vec<u8>, usize) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    let ch = info.color_type.samples();
    (info.width, info.height, buf, ch)
}

/// Checks that tags nest properly (a minimal XML well-formedness check: every opened element
/// is closed in order, attribute quotes balance, no stray `<` or `&` in text).
fn assert_well_formed(svg: &str) {
    let mut stack: Vec<String> = Vec::new();
    let b = svg.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'<' {
            let end = svg[i..].find('>').expect("unclosed tag") + i;
            let tag = &svg[i + 1..end];
            assert_eq!(
                tag.matches('"').count() % 2,
                0,
                "unbalanced quotes in <{tag}>"
            );
            assert!(!tag.contains('<'), "'<' inside tag {tag}");
            if let Some(name) = tag.strip_prefix('/') {
                let open = stack
                    .pop()
                    .unwrap_or_else(|| panic!("close of unopened {name}"));
                assert_eq!(open, name.trim(), "mismatched close");
            } else if !tag.ends_with('/') && !tag.starts_with('?') && !tag.starts_with('!') {
                let name = tag.split_whitespace().next().unwrap().to_string();
                stack.push(name);
            }
            i = end + 1;
        } else {
            if b[i] == b'&' {
                let semi = svg[i..].find(';').expect("bare &") + i;
                assert!(semi - i <= 6, "bare & in text");
            }
            i += 1;
        }
    }
    assert!(stack.is_empty(), "unclosed elements {stack:?}");
}

/// Saves `fig` to SVG and PNG, decodes both and checks size, content and texts.
fn check_figure(name: &str, fig: &Figure, texts: &[&str]) {
    let dir = temp_dir(name);
    let saved = fig.save(&dir, name).unwrap();
    let svg = std::fs::read_to_string(&saved.svg).unwrap();
    assert!(svg.starts_with("<svg"));
    assert_well_formed(&svg);
    for t in texts {
        assert!(svg.contains(t), "{name}: SVG lacks text {t:?}");
    }
    let (w, h, px, ch) = decode_png(&saved.png);
    let (fw, fh) = fig.dimensions();
    // Default PNG scale 2: device pixels are twice the SVG units.
    assert_eq!(
        (w, h),
        ((fw * 2.0).round() as u32, (fh * 2.0).round() as u32),
        "{name}"
    );
    let n = (w * h) as usize;
    let inked = px
        .chunks(ch)
        .filter(|p| p[0] < 200 || p[1] < 200 || p[2] < 200)
        .count();
    // A figure with frame, ticks, labels and curves inks well over 1 % of its pixels; a blank or
    // failed render inks none.
    assert!(inked > n / 100, "{name}: only {inked} of {n} pixels inked");
    let mut colours = std::collections::HashSet::new();
    for p in px.chunks(ch) {
        colours.insert((p[0] >> 4, p[1] >> 4, p[2] >> 4));
    }
    assert!(colours.len() > 20, "{name}: only {} colours", colours.len());
    let _ = std::fs::remove_dir_all(&dir);
}

fn sample_trajectory(n: usize, phase: f64) -> Trajectory {
    let t: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3).collect();
    let x = Mat::from_fn(n, 4, |k, i| {
        let t = t[k];
        match i {
            0 => 0.2 * (1.0 - (-2.0 * t).exp()),
            1 => 0.26 * (-1.5 * t).exp() * (6.0 * t + phase).cos(),
            2 => 0.4 * (-2.0 * t).exp(),
            _ => -1.5 * (-1.5 * t).exp() * (6.0 * t).sin(),
        }
    });
    let u = Mat::from_fn(n, 1, |k, _| {
        (3.0 * (-3.0 * t[k]).exp() * 100.0).round() / 100.0
    });
    Trajectory::new(t, x, u, Mat::zeros(n, 0)).unwrap()
}

#[test]
fn time_response_of_plain_series() {
    let t: Vec<f64> = (0..=1000).map(|k| k as f64 * 0.01).collect();
    let y1: Vec<f64> = t.iter().map(|t| (-t).exp()).collect();
    let y2: Vec<f64> = t.iter().map(|t| 2.0 * t.sin()).collect();
    let mut ax = Axes::new();
    ax.xlabel("time [s]").ylabel("position [m]");
    ax.plot(&t, &y1).label("y1(t)").color(Color::RED).dashed();
    ax.plot(&t, &y2).label("y2(t)").color(Color::GREEN).dotted();
    ax.step(&t[..50], &y1[..50]).label("sampled").dash_dot();
    check_figure(
        "plain",
        &Figure::new(ax).title("Responses"),
        &[
            "time [s]",
            "position [m]",
            "y1(t)",
            "y2(t)",
            "sampled",
            "Responses",
        ],
    );
}

#[test]
fn stacked_runs_of_trajectories() {
    let a = sample_trajectory(4001, 0.0);
    let b = sample_trajectory(4001, 0.3);
    let fig = TimeResponse::new()
        .run("q = 10", &a)
        .run("q = 100", &b)
        .panel(SignalPanel::new(Channel::State(0), "z [m]").reference(0.2, Some("r")))
        .panel(SignalPanel::new(Channel::State(1), "θ [deg]").scaled(180.0 / PI))
        .panel(SignalPanel::new(Channel::Input(0), "v [V]").stairs())
        .title("LQR")
        .figure()
        .unwrap();
    check_figure(
        "stacked",
        &fig,
        &["z [m]", "θ [deg]", "v [V]", "q = 10", "q = 100", "time [s]"],
    );
    // A channel the run does not have is a typed error naming it.
    let e = TimeResponse::new()
        .run("q = 10", &a)
        .panel(SignalPanel::new(Channel::Output(2), "y"))
        .figure()
        .unwrap_err();
    assert!(
        matches!(&e, PlotError::InvalidArgument(m) if m.contains("output y[2]") && m.contains("q = 10")),
        "{e}"
    );
}

#[test]
fn bode_diagram() {
    let w: Vec<f64> = (0..=300)
        .map(|k| 10f64.powf(-2.0 + 5.0 * k as f64 / 300.0))
        .collect();
    let p: Vec<Complex64> = w
        .iter()
        .map(|&w| {
            let s = Complex64::new(0.0, w);
            4.36 / (s * (s + 6.25))
        })
        .collect();
    let c: Vec<Complex64> = w
        .iter()
        .map(|&w| {
            let s = Complex64::new(0.0, w);
            10.0 + 5.0 / s + 0.8 * s
        })
        .collect();
    let fig = Bode::new()
        .response("P(s)", &w, &p)
        .response("C(s)", &w, &c)
        .title("Bode")
        .figure();
    check_figure(
        "bode",
        &fig,
        &[
            "gain [dB]",
            "phase [deg]",
            "frequency ω [rad/s]",
            "P(s)",
            "C(s)",
            "10⁻²",
            "10³",
        ],
    );
}

#[test]
fn pole_maps_with_regions() {
    let p = [(-3.0, 2.0), (-3.0, -2.0), (-8.0, 0.0)].map(|(re, im)| Complex64::new(re, im));
    // −16 ≤ Re s ≤ −2 and the sector of half-angle π/4 about the negative real axis.
    let bounds = [
        RegionBound::DecayRate(2.0),
        RegionBound::SpeedLimit(16.0),
        RegionBound::Sector(PI / 4.0),
    ];
    let fig = PoleZeroMap::new()
        .region("D-region", &bounds)
        .poles("closed loop", &p)
        .zeros("zeros", &[Complex64::new(-5.0, 0.0)])
        .figure();
    check_figure(
        "pzmap",
        &fig,
        &[
            "D-region",
            "closed loop",
            "zeros",
            "real axis",
            "imaginary axis",
        ],
    );
    let zp: Vec<Complex64> = p.iter().map(|p| (p * 0.1).exp()).collect();
    check_figure(
        "pzmap_d",
        &PoleZeroMap::discrete().poles("ZOH", &zp).figure(),
        &["|z| &lt; 1", "ZOH"],
    );
}

#[test]
fn gain_curves_and_ident_fit() {
    let th: Vec<f64> = (0..=65).map(|k| k as f64).collect();
    let mut gc = GainCurves::new("θ₁ [deg]", &th);
    for (k, name) in ["K11", "K12", "K13", "K14", "K2"].iter().enumerate() {
        let v: Vec<f64> = th
            .iter()
            .map(|t| (k as f64 + 1.0) * (1.0 + 0.01 * t))
            .collect();
        gc = gc.gain(*name, &v, Some(k as f64 + 1.0));
    }
    check_figure(
        "gains",
        &gc.figure().unwrap(),
        &["K11", "K2", "θ₁ [deg]", "gain scheduling", "LQ (constant)"],
    );

    let t: Vec<f64> = (0..2000).map(|k| k as f64 * 1e-3).collect();
    let y: Vec<f64> = t
        .iter()
        .map(|t| (5.0 * t).sin() + 0.05 * (97.0 * t).sin())
        .collect();
    let yh: Vec<f64> = t.iter().map(|t| (5.0 * t).sin()).collect();
    let fig = IdentFit::new(&t)
        .signal("φ [rad]", &y, &[("model", &yh)])
        .figure()
        .unwrap();
    check_figure("fit", &fig, &["φ [rad]", "measured", "model (fit"]);
}

#[test]
fn cell_maps_and_surface_and_bars() {
    let n = 30;
    let cells: Vec<bool> = (0..n * n)
        .map(|k| ((k % n) as f64 - 15.0).hypot((k / n) as f64 - 15.0) < 10.0)
        .collect();
    let ax = region_of_attraction(
        (-1.0, 1.0),
        (-3.0, 3.0),
        n,
        n,
        &cells,
        "θ(0) [rad]",
        "ω(0) [rad/s]",
    );
    check_figure(
        "roa",
        &Figure::new(ax),
        &["stabilised", "not stabilised", "θ(0) [rad]"],
    );

    let vals: Vec<f64> = (0..n * n)
        .map(|k| ((k % n) as f64 * 0.2).sin() + (k / n) as f64 * 0.05)
        .collect();
    let mut ax = Axes::new();
    ax.xlabel("a")
        .ylabel("b")
        .heat_map((0.0, 1.0), (0.0, 1.0), n, n, &vals, "cost J");
    check_figure(
        "heat",
        &Figure::new(ax),
        &["cost J", "data:image/png;base64,"],
    );

    let s = Surface::from_fn((-5.0, 5.0), (-5.0, 5.0), 21, 21, |a, b| a * a + b * b)
        .labels("x₁", "x₂", "V(x)");
    check_figure("surface", &Figure::new(s), &["x₁", "x₂", "V(x)"]);

    let mut bars = Axes::new();
    bars.bar(&[1.0, 2.0, 3.0], &[0.4, 0.7, 0.75]).label("peaks");
    let mut sc = Axes::new();
    sc.scatter(&[0.1, 0.2, 0.3], &[1.0, 3.0, 2.0]).label("runs");
    check_figure("bars", &Figure::row([bars, sc]), &["peaks", "runs"]);
}

/// Pixel centre of the runs of pixels in `line` that satisfy `pred`, in order.
fn runs(line: &[[u8; 3]], pred: impl Fn([u8; 3]) -> bool) -> Vec<f64> {
    let mut out = Vec::new();
    let mut start: Option<usize> = None;
    for (i, p) in line.iter().enumerate() {
        match (pred(*p), start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                out.push((s + i - 1) as f64 / 2.0);
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s + line.len() - 1) as f64 / 2.0);
    }
    out
}

#[test]
fn curves_land_where_the_axis_mapping_puts_them() {
    // Axes [0, 10] × [0, 10] without labels: the only dark pixels on a row or column that avoids
    // ticks are the frame. A data point (x, y) must appear at
    // left + x/10 (right − left), bottom − y/10 (bottom − top).
    let mut ax = Axes::new();
    ax.xlim(0.0, 10.0)
        .ylim(0.0, 10.0)
        .grid(false)
        .legend(pendulab_plot::LegendPos::Hidden);
    ax.plot(&[0.0, 10.0], &[2.5, 2.5])
        .color(Color::rgb(230, 0, 0))
        .width(2.0);
    ax.plot(&[7.5, 7.5], &[0.0, 10.0])
        .color(Color::rgb(0, 0, 230))
        .width(2.0);
    ax.plot(&[0.0, 10.0], &[0.0, 10.0])
        .color(Color::rgb(0, 180, 0))
        .width(2.0);
    let img = Figure::new(ax).to_raster().unwrap();
    let px = |x: u32, y: u32| {
        let p = img.pixel(x, y).unwrap();
        [p[0], p[1], p[2]]
    };
    let dark = |p: [u8; 3]| p[0] < 90 && p[1] < 90 && p[2] < 90;
    let red = |p: [u8; 3]| p[0] > 150 && p[1] < 110 && p[2] < 110;
    let blue = |p: [u8; 3]| p[2] > 150 && p[0] < 110 && p[1] < 110;
    let green = |p: [u8; 3]| p[1] > 120 && p[0] < 110 && p[2] < 110;

    // Frame edges from a row through the middle of the plot, off the tick rows (ticks every 2,
    // minor every 0.5: y = 5.3 and x = 5.3 are clear of both).
    let mid_row = img.height / 2;
    let row: Vec<[u8; 3]> = (0..img.width).map(|x| px(x, mid_row)).collect();
    let frame_x = runs(&row, dark);
    let (left, right) = (frame_x[0], frame_x[frame_x.len() - 1]);
    let col: Vec<[u8; 3]> = (0..img.height).map(|y| px(img.width / 2, y)).collect();
    let frame_y = runs(&col, dark);
    let (top, bottom) = (frame_y[0], frame_y[frame_y.len() - 1]);
    let map_x = |x: f64| left + x / 10.0 * (right - left);
    let map_y = |y: f64| bottom - y / 10.0 * (bottom - top);

    // The red line y = 2.5 on the column of x = 5.3.
    let c = map_x(5.3).round() as u32;
    let col: Vec<[u8; 3]> = (0..img.height).map(|y| px(c, y)).collect();
    let r = runs(&col, red);
    assert_eq!(r.len(), 1);
    // Tolerance 1 device pixel: frame and line centres are each found to half a pixel.
    assert!(
        (r[0] - map_y(2.5)).abs() <= 1.0,
        "red at {} expected {}",
        r[0],
        map_y(2.5)
    );
    // The blue line x = 7.5 on the row of y = 5.3.
    let rr = map_y(5.3).round() as u32;
    let row: Vec<[u8; 3]> = (0..img.width).map(|x| px(x, rr)).collect();
    let b = runs(&row, blue);
    assert_eq!(b.len(), 1);
    assert!(
        (b[0] - map_x(7.5)).abs() <= 1.0,
        "blue at {} expected {}",
        b[0],
        map_x(7.5)
    );
    // The diagonal y = x passes through (3.3, 3.3).
    let rr = map_y(3.3).round() as u32;
    let row: Vec<[u8; 3]> = (0..img.width).map(|x| px(x, rr)).collect();
    let g = runs(&row, green);
    assert_eq!(g.len(), 1);
    assert!(
        (g[0] - map_x(3.3)).abs() <= 1.5,
        "green at {} expected {}",
        g[0],
        map_x(3.3)
    );
}

#[test]
fn nan_samples_are_gaps() {
    let x: Vec<f64> = (0..=100).map(|k| k as f64 * 0.1).collect();
    let y: Vec<f64> = x
        .iter()
        .map(|x| {
            if (4.0..=6.0).contains(x) {
                f64::NAN
            } else {
                5.0
            }
        })
        .collect();
    let mut ax = Axes::new();
    ax.xlim(0.0, 10.0).ylim(0.0, 10.0).grid(false);
    ax.plot(&x, &y).color(Color::rgb(230, 0, 0)).width(2.0);
    let img = Figure::new(ax).to_raster().unwrap();
    let red_in_column = |frac: f64| {
        let c = (img.width as f64 * frac) as u32;
        (0..img.height).any(|y| {
            let p = img.pixel(c, y).unwrap();
            p[0] > 150 && p[1] < 110
        })
    };
    // The plot spans most of the width: 20 % and 80 % of the figure lie on drawn pieces, the
    // figure's centre (x ≈ 5) in the gap.
    assert!(red_in_column(0.25));
    assert!(!red_in_column(0.52));
    assert!(red_in_column(0.85));
}

#[test]
fn bad_data_gives_typed_errors() {
    let mut ax = Axes::new();
    ax.plot(&[], &[]).label("empty");
    assert!(
        matches!(Figure::new(ax).to_svg(), Err(PlotError::Empty { what }) if what.contains("\"empty\""))
    );

    let mut ax = Axes::new();
    ax.plot(&[1.0, 2.0], &[1.0]).label("short");
    let e = Figure::new(ax).to_png().unwrap_err();
    assert!(
        matches!(
            e,
            PlotError::LengthMismatch {
                left: 2,
                right: 1,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("short"));

    let mut ax = Axes::new();
    ax.plot(&[1.0, 2.0], &[f64::NAN, f64::INFINITY]);
    assert!(matches!(
        Figure::new(ax).to_svg(),
        Err(PlotError::NothingToDraw { .. })
    ));

    let mut ax = Axes::new();
    ax.xscale(pendulab_plot::Scale::Log)
        .plot(&[0.0, -1.0], &[1.0, 2.0]);
    assert!(matches!(
        Figure::new(ax).to_svg(),
        Err(PlotError::NothingToDraw { .. })
    ));

    let mut ax = Axes::new();
    ax.xlim(1.0, 1.0).plot(&[0.0, 1.0], &[0.0, 1.0]);
    assert!(matches!(
        Figure::new(ax).to_svg(),
        Err(PlotError::InvalidArgument(_))
    ));

    let mut ax = Axes::new();
    ax.bool_map((0.0, 1.0), (0.0, 1.0), 3, 3, &[true; 8], ["a", "b"]);
    assert!(matches!(
        Figure::new(ax).to_svg(),
        Err(PlotError::LengthMismatch {
            left: 8,
            right: 9,
            ..
        })
    ));

    let s = Surface::new(&[0.0, 1.0], &[0.0, 1.0], &[1.0; 3]);
    assert!(matches!(
        Figure::new(s).to_svg(),
        Err(PlotError::LengthMismatch { .. })
    ));

    let mut ax = Axes::new();
    ax.region(&[RegionBound::Sector(2.0)]);
    assert!(matches!(
        Figure::new(ax).to_svg(),
        Err(PlotError::InvalidArgument(_))
    ));

    // An unwritable path is an I/O error naming the path.
    let mut ax = Axes::new();
    ax.plot(&[0.0, 1.0], &[0.0, 1.0]);
    let bad = std::path::Path::new("/nonexistent-dir-for-pendulab/x.png");
    match Figure::new(ax.clone()).save_png(bad) {
        Err(PlotError::Io { path, .. }) => assert_eq!(path, bad),
        other => panic!("expected Io error, got {other:?}"),
    }
    let e = Figure::new(ax).save_svg(bad).unwrap_err();
    assert!(
        e.to_string()
            .contains("/nonexistent-dir-for-pendulab/x.png")
    );
}

#[test]
fn values_far_outside_fixed_limits_do_not_break_the_output() {
    // 1e307 maps to a pixel coordinate that overflows f64: it becomes a gap, the SVG stays
    // numeric and well formed.
    let mut ax = Axes::new();
    ax.ylim(0.0, 1.0);
    ax.plot(&[0.0, 1.0, 2.0, 3.0], &[0.5, 1e307, -1e307, 0.5])
        .label("wild");
    ax.fill(&[0.0, 1.0, 2.0], &[0.0, 1e307, 0.0]);
    let fig = Figure::new(ax);
    let svg = fig.to_svg().unwrap();
    assert_well_formed(&svg);
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
    assert!(fig.to_png().is_ok());
}

#[test]
fn figures_are_send_and_sync() {
    fn check<T: Send + Sync>() {}
    check::<Figure>();
    check::<Animation>();
}

#[test]
fn figures_render_from_many_threads() {
    let handles: Vec<_> = (0..4)
        .map(|k| {
            std::thread::spawn(move || {
                let mut ax = Axes::new();
                ax.plot(&[0.0, 1.0, 2.0], &[0.0, k as f64, 0.0]).label("x");
                Figure::new(ax).to_png().map(|p| p.len())
            })
        })
        .collect();
    for h in handles {
        assert!(h.join().unwrap().unwrap() > 1000);
    }
}

fn decode_gif(bytes: &[u8]) -> Vec<(u16, u16, u16)> {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::Indexed);
    let mut d = opts.read_info(bytes).unwrap();
    let mut frames = Vec::new();
    while let Some(f) = d.read_next_frame().unwrap() {
        frames.push((f.delay, f.width, f.height));
    }
    frames
}

#[test]
fn gif_animation_has_the_expected_frames() {
    // 2 s at 1 kHz, 10 frames/s: frames at 0, 0.1, …, 2.0 s.
    let t: Vec<f64> = (0..=2000).map(|k| k as f64 * 1e-3).collect();
    let z: Vec<f64> = t.iter().map(|t| 0.2 * (2.0 * t).sin()).collect();
    let th: Vec<f64> = t.iter().map(|t| 0.3 * (5.0 * t).cos()).collect();
    let anim = Animation::cart(&t, &z, &th, CartGeometry::default())
        .unwrap()
        .options(AnimationOptions {
            fps: 10.0,
            hold: 0.5,
            ..Default::default()
        });
    let dir = temp_dir("gif");
    let info = anim.save_gif(dir.join("cart.gif")).unwrap();
    assert_eq!(info.frames, 21);
    assert!((info.frame_interval - 0.1).abs() < 1e-12);
    let bytes = std::fs::read(dir.join("cart.gif")).unwrap();
    assert_eq!(bytes.len(), info.bytes);
    let frames = decode_gif(&bytes);
    assert_eq!(frames.len(), 21);
    assert_eq!((frames[0].1, frames[0].2), (480, 320));
    assert!(frames[..20].iter().all(|f| f.0 == 10));
    assert_eq!(frames[20].0, 60); // 0.1 s + 0.5 s hold, in hundredths

    // A 16 s run at the default 25 frames/s stays within 150 frames, in real time.
    let t: Vec<f64> = (0..=16000).map(|k| k as f64 * 1e-3).collect();
    let a: Vec<f64> = t.iter().map(|t| PI * (1.0 - (-0.3 * t).exp())).collect();
    let b: Vec<f64> = t.iter().map(|t| PI * (0.7 * t).cos()).collect();
    let anim = Animation::arm(&t, &a, &b, ArmGeometry::default()).unwrap();
    let gif = anim.to_gif().unwrap();
    let frames = decode_gif(&gif);
    let n = frames.len();
    assert!((140..=150).contains(&n), "{n} frames");
    // n frames cover 16 s: (n − 1) × interval ≤ 16 < n × interval.
    let dt = frames[0].0 as f64 / 100.0;
    assert!((n - 1) as f64 * dt <= 16.0 + 1e-9 && n as f64 * dt > 16.0);
    assert!(gif.len() < 2_000_000, "{} bytes", gif.len());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn svg_animation_is_keyed_by_the_trajectory() {
    let t: Vec<f64> = (0..=1000).map(|k| k as f64 * 1e-3).collect();
    let z: Vec<f64> = t.iter().map(|t| 0.1 * t).collect();
    let th: Vec<f64> = t.iter().map(|t| 0.5 * t).collect();
    let anim = Animation::cart(&t, &z, &th, CartGeometry::default())
        .unwrap()
        .title("swing")
        .options(AnimationOptions {
            fps: 20.0,
            ..Default::default()
        });
    let svg = anim.to_svg().unwrap();
    assert_well_formed(&svg);
    assert_eq!(svg.matches("<animateTransform").count(), 2);
    assert!(svg.contains("type=\"translate\"") && svg.contains("type=\"rotate\""));
    // 21 frames (0 … 1 s every 0.05 s) plus the held last value.
    let values = svg
        .split("type=\"rotate\"")
        .nth(1)
        .unwrap()
        .split("values=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap();
    let v: Vec<f64> = values.split(';').map(|s| s.parse().unwrap()).collect();
    assert_eq!(v.len(), 22);
    // Rotation in degrees equals θ at the frame times: θ(0.5 s) = 0.25 rad.
    assert!((v[10] - 0.25f64.to_degrees()).abs() < 1e-3);
    assert_eq!(svg.matches("t = ").count(), 21);
    assert!(svg.contains(">swing</text>"));

    let arm = Animation::arm(&t, &z, &th, ArmGeometry::default())
        .unwrap()
        .to_svg()
        .unwrap();
    assert_well_formed(&arm);
    assert_eq!(arm.matches("<animateTransform").count(), 2);
}

#[test]
fn bad_animation_input_is_rejected() {
    let t = [0.0, 0.1, 0.2];
    assert!(matches!(
        Animation::cart(
            &t,
            &[0.0, f64::NAN, 0.0],
            &[0.0; 3],
            CartGeometry::default()
        ),
        Err(PlotError::NonFinite { index: 1, .. })
    ));
    assert!(matches!(
        Animation::arm(&t, &[0.0; 2], &[0.0; 3], ArmGeometry::default()),
        Err(PlotError::LengthMismatch { .. })
    ));
    assert!(matches!(
        Animation::arm(&[], &[], &[], ArmGeometry::default()),
        Err(PlotError::Empty { .. })
    ));
    assert!(matches!(
        Animation::cart(&[0.0, -1.0], &[0.0; 2], &[0.0; 2], CartGeometry::default()),
        Err(PlotError::InvalidArgument(_))
    ));
    let a = Animation::cart(&t, &[0.0; 3], &[0.0; 3], CartGeometry::default())
        .unwrap()
        .options(AnimationOptions {
            fps: 0.0,
            ..Default::default()
        });
    assert!(matches!(a.to_gif(), Err(PlotError::InvalidArgument(_))));
    let a = Animation::cart(&t, &[0.0; 3], &[0.0; 3], CartGeometry::default()).unwrap();
    assert!(matches!(
        a.save_gif("/nonexistent-dir-for-pendulab/a.gif"),
        Err(PlotError::Io { .. })
    ));
}
