//! Legend placement checked from the figure's own layout data ([`Figure::layout`]): the legend
//! box must contain none of the points the panel drew.

use pendulab_plot::{Axes, Figure, LegendPos, MAX_OUTSIDE_LEGEND};

fn grid(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    (0..n)
        .map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64)
        .collect()
}

/// Data in all four corners (a line along the bottom, two pieces along the top) but none in
/// the middle of the right edge: a corner legend would cover data, `Best` must find the
/// free place.
#[test]
fn best_legend_leaves_the_corners_when_they_hold_data() {
    let x = grid(201, 0.0, 10.0);
    let bottom = vec![-1.0; x.len()];
    let top: Vec<f64> = x
        .iter()
        .map(|&t| {
            if (3.0..7.0).contains(&t) {
                f64::NAN
            } else {
                1.0
            }
        })
        .collect();
    let mut ax = Axes::new();
    ax.ylim(-1.2, 1.2).legend(LegendPos::Best);
    ax.plot(&x, &bottom).label("lower bound");
    ax.plot(&x, &top).label("upper pieces");
    let layout = Figure::new(ax.clone()).layout().unwrap();
    assert_eq!(layout.len(), 1);
    let p = &layout[0];
    let [lx0, ly0, lx1, ly1] = p.legend.expect("a legend is drawn");
    let [px0, py0, px1, py1] = p.plot;
    assert!(
        lx0 >= px0 && lx1 <= px1 && ly0 >= py0 && ly1 <= py1,
        "{p:?}"
    );
    assert_eq!(p.points_under_legend(), 0, "legend {:?}", p.legend);
    // Each fixed corner does cover data here: the check above is not vacuous.
    for pos in [
        LegendPos::UpperRight,
        LegendPos::UpperLeft,
        LegendPos::LowerLeft,
        LegendPos::LowerRight,
    ] {
        ax.legend(pos);
        let l = Figure::new(ax.clone()).layout().unwrap();
        assert!(l[0].points_under_legend() > 0, "{pos:?} covers nothing");
    }
}

/// Data everywhere in the panel: every inside place covers data, `Outside` (and `Best`, which
/// falls back to it) puts the legend right of the frame, within the figure, covering nothing.
#[test]
fn outside_legend_covers_no_data_when_the_panel_is_full() {
    let x = grid(4001, 0.0, 10.0);
    let mut ax = Axes::new();
    for k in 0..6 {
        let y: Vec<f64> = x
            .iter()
            .map(|t| (7.0 * t + k as f64).sin() * (1.0 - 0.1 * k as f64))
            .collect();
        ax.plot(&x, &y).label(format!("curve {k}"));
    }
    let inside_places = [
        LegendPos::UpperRight,
        LegendPos::UpperLeft,
        LegendPos::LowerLeft,
        LegendPos::LowerRight,
    ];
    let mut inside = Vec::new();
    for pos in inside_places {
        ax.legend(pos);
        inside = Figure::new(ax.clone()).layout().unwrap();
        assert!(inside[0].points_under_legend() > 0, "{pos:?}");
    }

    ax.legend(LegendPos::Best);
    let best = Figure::new(ax.clone()).layout().unwrap();
    ax.legend(LegendPos::Outside);
    let fig = Figure::new(ax);
    assert_eq!(best, fig.layout().unwrap(), "Best falls back to Outside");
    let (w, h) = fig.dimensions();
    let out = fig.layout().unwrap();
    let p = &out[0];
    let [lx0, ly0, lx1, ly1] = p.legend.expect("a legend is drawn");
    let [_, py0, px1, _] = p.plot;
    assert!(
        lx0 > px1,
        "legend {:?} not right of the plot {:?}",
        p.legend,
        p.plot
    );
    assert!(
        lx1 <= w && ly0 >= py0 && ly1 <= h,
        "legend {:?} outside the figure",
        p.legend
    );
    assert_eq!(p.points_under_legend(), 0);
    // The plot area gave the legend its width.
    assert!(p.plot[2] < inside[0].plot[2] - (lx1 - lx0));
    // Drawing still works and names every entry.
    let svg = fig.to_svg().unwrap();
    assert!(svg.contains("curve 5"));
}

/// A panel without labels has no legend box, whatever the placement.
#[test]
fn no_labels_no_legend_box() {
    let x = grid(11, 0.0, 1.0);
    let mut ax = Axes::new();
    ax.plot(&x, &x);
    ax.legend(LegendPos::Outside);
    let l = Figure::new(ax).layout().unwrap();
    assert_eq!(l[0].legend, None);
    assert_eq!(l[0].points_under_legend(), 0);
    assert!(!l[0].points.is_empty());
}

/// In a column of panels, a `Best` legend that must go outside widens the shared right margin;
/// the other panels' legends are placed again in their narrower plots and cover nothing either.
#[test]
fn stacked_panels_keep_every_legend_clear() {
    let x = grid(2001, 0.0, 10.0);
    let chatter: Vec<f64> = x.iter().map(|t| (40.0 * t).sin().signum()).collect();
    let smooth: Vec<f64> = x.iter().map(|t| (-0.5 * t).exp()).collect();
    let mut a = Axes::new();
    a.plot(&x, &smooth).label("smooth");
    let mut b = Axes::new();
    b.plot(&x, &chatter).label("chattering");
    b.plot(&x, &smooth).label("smooth");
    let fig = Figure::column([a, b]);
    let l = fig.layout().unwrap();
    assert_eq!(l.len(), 2);
    for p in &l {
        assert!(p.legend.is_some());
        assert_eq!(p.points_under_legend(), 0, "{:?}", p.legend);
    }
    // The chattering panel's legend went outside; both plots share the right edge.
    assert!(l[1].legend.unwrap()[0] > l[1].plot[2]);
    assert_eq!(l[0].plot[2], l[1].plot[2]);
}

/// A legend wider than `MAX_OUTSIDE_LEGEND` of the plot does not squeeze the plot: `Best` keeps
/// it inside, at the place covering the fewest points of the nine.
#[test]
fn too_wide_a_legend_stays_inside() {
    let x = grid(4001, 0.0, 10.0);
    let y: Vec<f64> = x.iter().map(|t| (7.0 * t).sin()).collect();
    let label = "a very long legend entry that names every parameter of this run in full";
    let mut ax = Axes::new();
    ax.plot(&x, &y).label(label);
    ax.ylim(-1.0, 1.0).legend(LegendPos::Best);
    let l = Figure::new(ax.clone()).layout().unwrap();
    let [lx0, _, lx1, _] = l[0].legend.unwrap();
    let [px0, _, px1, _] = l[0].plot;
    assert!(lx1 - lx0 > MAX_OUTSIDE_LEGEND * (px1 - px0));
    assert!(lx0 >= px0 && lx1 <= px1, "legend stayed inside");
    let least = l[0].points_under_legend();
    assert!(least > 0);
    for pos in [
        LegendPos::UpperRight,
        LegendPos::UpperLeft,
        LegendPos::LowerLeft,
        LegendPos::LowerRight,
    ] {
        ax.legend(pos);
        let c = Figure::new(ax.clone()).layout().unwrap();
        assert!(c[0].points_under_legend() >= least, "{pos:?}");
    }
}
