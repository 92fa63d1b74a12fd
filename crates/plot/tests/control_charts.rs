//! The loop-analysis figures rendered once each from pendulab-lti's numbers: SVG text, PNG
//! decoded, the critical point drawn in red, no legend over the data.

use std::path::PathBuf;

use pendulab_lti::frequency_response::logspace;
use pendulab_lti::nyquist::{NyquistOptions, nichols, nyquist_tf};
use pendulab_lti::rlocus::{rlocfind_tf, rlocus_tf};
use pendulab_lti::sigma::sigma;
use pendulab_lti::{Mat, StateSpace, TransferFunction};
use pendulab_plot::{Figure, Nichols, Nyquist, RootLocusPlot, SigmaPlot};

fn out_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("pendulab-plot-control-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Saves both formats and returns the SVG text and the count of strongly red PNG pixels.
fn render(fig: &Figure, stem: &str) -> (String, usize) {
    let saved = fig.save(out_dir(), stem).unwrap();
    let svg = std::fs::read_to_string(&saved.svg).unwrap();
    let raster = fig.to_raster().unwrap();
    let (w, h) = (raster.width, raster.height);
    let mut red = 0;
    for y in 0..h {
        for x in 0..w {
            if let Some([r, g, b, _]) = raster.pixel(x, y)
                && r > 180
                && g < 80
                && b < 80
            {
                red += 1;
            }
        }
    }
    for l in fig.layout().unwrap() {
        assert!(l.points_under_legend() <= 2, "{stem}: legend over data");
    }
    (svg, red)
}

#[test]
fn nyquist_figure_of_an_integrator_loop() {
    // 4/(s(s + 1)(0.5 s + 1)): indented at s = 0, the curve runs off to −j∞ and is clipped;
    // s³ + 3s² + 2s + 8 (Routh: 3·2 < 8) has two right-half-plane roots, so N = 2.
    let l = TransferFunction::continuous(&[4.0], &[0.5, 1.5, 1.0, 0.0]).unwrap();
    let c = nyquist_tf(&l, &NyquistOptions::default()).unwrap();
    let fig = Nyquist::new()
        .curve("L(s) = 4/(s(s+1)(0.5s+1))", &c.response)
        .title(format!(
            "Nyquist: N = {}, P = {}",
            c.encirclements, c.open_loop_unstable
        ))
        .figure();
    let (svg, red) = render(&fig, "nyquist");
    assert!(
        svg.contains("−1") && svg.contains("N = 2"),
        "count in the title"
    );
    assert!(red > 20, "critical point drawn ({red} red px)");
}

#[test]
fn root_locus_figure_with_gain_annotation() {
    // (s + 3)/(s(s + 1)(s + 2)(s + 5)); the annotated point is a closed-loop pole at K = 6,
    // found back by rlocfind.
    let l = TransferFunction::continuous(&[1.0, 3.0], &[1.0, 8.0, 17.0, 10.0, 0.0]).unwrap();
    let rl = rlocus_tf(&l, None).unwrap();
    let at6 = rlocus_tf(&l, Some(&[6.0])).unwrap();
    let near = at6.roots[0].iter().copied().find(|p| p.im > 0.0).unwrap();
    let f = rlocfind_tf(&l, near).unwrap();
    assert!((f.gain - 6.0).abs() < 1e-9);
    let fig = RootLocusPlot::new(&rl.roots)
        .poles(&rl.poles)
        .zeros(&rl.zeros)
        .asymptotes(rl.asymptotes.centroid, &rl.asymptotes.angles)
        .break_points(&rl.break_points.iter().map(|b| b.point).collect::<Vec<_>>())
        .annotate(near, f.gain)
        .title("root locus of (s + 3)/(s(s + 1)(s + 2)(s + 5))")
        .figure();
    let (svg, red) = render(&fig, "rlocus");
    assert!(svg.contains("K = 6") && svg.contains("asymptotes"));
    assert!(red > 20);
}

#[test]
fn nichols_figure_with_grid() {
    let l = TransferFunction::continuous(&[4.0], &[1.0, 3.0, 3.0, 1.0, 0.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let w = logspace(-2.0, 1.5, 400);
    let n = nichols(&l, &w).unwrap();
    let fig = Nichols::new()
        .curve("L(s) = 4/(s(s+1)³)", &n.phase_deg, &n.magnitude_db)
        .title("Nichols chart")
        .figure();
    let (svg, red) = render(&fig, "nichols");
    assert!(svg.contains("3 dB") && svg.contains("open-loop gain [dB]"));
    assert!(red > 10);
}

#[test]
fn sigma_figure_of_a_two_by_two_system() {
    let a = Mat::from_row_slice(3, 3, &[-1.0, 2.0, 0.0, -2.0, -1.0, 0.0, 0.0, 0.0, -5.0]);
    let b = Mat::from_row_slice(3, 2, &[1.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
    let c = Mat::from_row_slice(2, 3, &[1.0, 0.0, 1.0, 0.0, 1.0, 0.0]);
    let g = StateSpace::continuous(a, b, c, Mat::zeros(2, 2)).unwrap();
    let w = logspace(-2.0, 2.0, 300);
    let sv = sigma(&g, &w).unwrap();
    let fig = SigmaPlot::new()
        .response("G", &sv.w, &sv.values)
        .title("singular values")
        .figure();
    let (svg, _) = render(&fig, "sigma");
    assert!(svg.contains("σ₁"));
}
