//! Nyquist, root locus, disk margins and sigma against python-control 0.10.2 (fixture of
//! `tools/reference/loop_analysis_python.py`), closed forms (the break-away point and
//! asymptotes of `1/(s(s+1)(s+2))`, the disk margin of `k/(s+1)`), defining residuals (a
//! root locus point satisfies `D + K N = 0`, the disk margin is attained at its critical
//! frequency) and the degenerate cases' typed errors.

mod toolbox_support;

use pendulab_lti::disk_margin::{DiskMargin, disk_margin, disk_margin_response};
use pendulab_lti::frequency_response::bode;
use pendulab_lti::linalg::Complex64;
use pendulab_lti::norms::hinf_norm;
use pendulab_lti::nyquist::{NyquistOptions, nichols, nyquist, nyquist_tf};
use pendulab_lti::rlocus::{rlocfind_tf, rlocus, rlocus_tf};
use pendulab_lti::sigma::sigma;
use pendulab_lti::{Discrete, LtiError, Mat, StateSpace, TransferFunction};
use pendulab_testkit::json::vector;
use serde_json::Value;

fn fixture() -> Value {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/loop_analysis_reference.json");
    serde_json::from_str(&std::fs::read_to_string(path).expect("fixture")).expect("json")
}

/// Every loop of the fixture (python-control's `nyquist_response` count, with
/// `Z = N + P` holding for python-control itself): the same `N`, `P` and `Z`, and the
/// criterion holds for ours.
#[test]
fn nyquist_counts_match_python_control() {
    let f = fixture();
    let cases = f["nyquist"].as_array().unwrap();
    assert!(cases.len() >= 40, "{} cases", cases.len());
    let mut nonzero = 0;
    for (k, case) in cases.iter().enumerate() {
        let sys = toolbox_support::system(case);
        let c = on_sys!(&sys, |s| nyquist(s, &NyquistOptions::default()).unwrap());
        let want = case["count"].as_i64().unwrap();
        assert_eq!(c.encirclements, want, "case {k}: winding {}", c.winding);
        assert!(
            (c.winding - want as f64).abs() < 0.05,
            "case {k}: {}",
            c.winding
        );
        assert_eq!(
            c.open_loop_unstable as u64,
            case["P"].as_u64().unwrap(),
            "case {k}"
        );
        assert_eq!(
            c.closed_loop_unstable as u64,
            case["Z"].as_u64().unwrap(),
            "case {k}"
        );
        assert!(c.criterion_holds(), "case {k}");
        nonzero += usize::from(want != 0);
    }
    assert!(nonzero >= 15, "{nonzero} loops encircle −1");
}

/// Integrator loops: the contour starts on the indentation (`s = r`, real), the curve
/// there is `≈ 1/r`, and the undamped pair `±j` is passed on the right (the contour point
/// nearest `j` lies at distance `r` from it).
#[test]
fn nyquist_indents_around_imaginary_axis_poles() {
    let r = 1e-4;
    let opts = NyquistOptions::default();
    let l = TransferFunction::continuous(&[1.0], &[1.0, 1.0, 0.0]).unwrap();
    let c = nyquist_tf(&l, &opts).unwrap();
    assert_eq!(c.indented_poles.len(), 1);
    assert!((c.contour[0] - Complex64::new(r, 0.0)).norm() < 1e-18);
    // L(r) = 1/(r(r + 1)), real.
    let want = 1.0 / (r * (r + 1.0));
    assert!((c.response[0].re - want).abs() < 1e-9 * want && c.response[0].im == 0.0);
    let l = TransferFunction::continuous(&[1.0, 0.2], &[1.0, 0.0, 1.0]).unwrap();
    let c = nyquist_tf(&l, &opts).unwrap();
    let j = Complex64::new(0.0, 1.0);
    let nearest = c
        .contour
        .iter()
        .map(|s| (s - j).norm())
        .fold(f64::INFINITY, f64::min);
    assert!((nearest - r).abs() < 1e-12, "{nearest}");
    assert!(c.contour.iter().all(|s| s.re >= 0.0));
    assert!(c.criterion_holds());
}

/// Discrete loop with an integrator at `z = 1`: the contour leaves the unit circle there
/// (`z = e^{rT}`) and ends at the Nyquist frequency `z = −1`.
#[test]
fn nyquist_discrete_contour() {
    let l = TransferFunction::discrete(&[0.1], &[1.0, -1.0], 0.1).unwrap();
    let c = nyquist_tf(&l, &NyquistOptions::default()).unwrap();
    assert!((c.contour[0] - Complex64::new((1e-4f64 * 0.1).exp(), 0.0)).norm() < 1e-15);
    let last = *c.contour.last().unwrap();
    assert!((last - Complex64::new(-1.0, 0.0)).norm() < 1e-12);
    // L(−1) = 0.1/(−2).
    assert!((c.response.last().unwrap() - Complex64::new(-0.05, 0.0)).norm() < 1e-12);
    assert_eq!(c.encirclements, 0);
}

#[test]
fn nyquist_rejects_mimo_improper_and_ill_posed() {
    let mimo = StateSpace::continuous(
        Mat::from_element(1, 1, -1.0),
        Mat::from_row_slice(1, 2, &[1.0, 1.0]),
        Mat::from_element(1, 1, 1.0),
        Mat::zeros(1, 2),
    )
    .unwrap();
    assert!(matches!(
        nyquist(&mimo, &NyquistOptions::default()),
        Err(LtiError::NotSiso { .. })
    ));
    let pid = TransferFunction::continuous(&[1.0, 2.0, 1.0], &[1.0, 0.0]).unwrap();
    assert!(matches!(
        nyquist_tf(&pid, &NyquistOptions::default()),
        Err(LtiError::Improper { .. })
    ));
    // L = −1 + 1/(s + 1): 1 + D = 0, the loop is ill-posed.
    let bad = TransferFunction::continuous(&[-1.0, 0.0], &[1.0, 1.0]).unwrap();
    assert!(matches!(
        nyquist_tf(&bad, &NyquistOptions::default()),
        Err(LtiError::Singular { .. })
    ));
    let bad_r = NyquistOptions {
        indent_radius: 0.0,
        ..NyquistOptions::default()
    };
    let lag = TransferFunction::continuous(&[1.0], &[1.0, 1.0]).unwrap();
    assert!(matches!(
        nyquist_tf(&lag, &bad_r),
        Err(LtiError::InvalidArgument(_))
    ));
}

/// The Nichols curve is the Bode data (gain, unwrapped phase) with the phase shifted by a
/// whole number of turns.
#[test]
fn nichols_is_bode_shifted_by_turns() {
    let l = TransferFunction::continuous(&[4.0], &[1.0, 3.0, 3.0, 1.0, 0.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let w = pendulab_lti::frequency_response::logspace(-2.0, 2.0, 50);
    let n = nichols(&l, &w).unwrap();
    let b = bode(&l, &w).unwrap();
    let shift = b.phase_deg[0] - n.phase_deg[0];
    assert!((shift / 360.0 - (shift / 360.0).round()).abs() < 1e-12);
    assert!(n.phase_deg[0] <= 0.0 && n.phase_deg[0] > -360.0);
    for k in 0..w.len() {
        assert_eq!(n.magnitude_db[k], b.magnitude_db[k]);
        assert!((b.phase_deg[k] - n.phase_deg[k] - shift).abs() < 1e-9);
    }
}

/// python-control's `root_locus_map` at given gains: the same closed-loop poles (as sets,
/// to 1e-7 relative), each a root of `D + K N` (residual check).
#[test]
fn rlocus_matches_python_control() {
    let f = fixture();
    for (k, case) in f["rlocus"].as_array().unwrap().iter().enumerate() {
        let (num, den) = (vector(&case["num"]), vector(&case["den"]));
        let gains = vector(&case["gains"]);
        let want: Vec<Vec<Complex64>> = case["loci"]
            .as_array()
            .unwrap()
            .iter()
            .map(|row| {
                row.as_array()
                    .unwrap()
                    .iter()
                    .map(|p| Complex64::new(p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
                    .collect()
            })
            .collect();
        let rl = match case["dt"].as_f64() {
            None => rlocus_tf(
                &TransferFunction::continuous(&num, &den).unwrap(),
                Some(&gains),
            )
            .unwrap(),
            Some(ts) => rlocus_tf(
                &TransferFunction::discrete(&num, &den, ts).unwrap(),
                Some(&gains),
            )
            .unwrap(),
        };
        assert_eq!(rl.gains, gains, "case {k}");
        for (g, (ours, theirs)) in rl.roots.iter().zip(&want).enumerate() {
            assert_eq!(ours.len(), theirs.len());
            let scale = theirs.iter().map(|p| p.norm()).fold(1.0, f64::max);
            for p in theirs {
                let d = ours
                    .iter()
                    .map(|q| (q - p).norm())
                    .fold(f64::INFINITY, f64::min);
                // Double roots (a break point's gain) are sensitive: √ε.
                assert!(
                    d <= 2e-7 * scale,
                    "case {k} gain {}: {p} missing ({d:e})",
                    gains[g]
                );
            }
        }
    }
}

/// `1/(s(s+1)(s+2))`: asymptotes from −1 at ±60° and 180°, break-away at `−1 + 1/√3` with
/// `K = 2/(3√3)`; the automatic grid's branches are continuous and start at the poles, and
/// every point satisfies `D + K N = 0`.
#[test]
fn rlocus_closed_forms_and_branch_continuity() {
    let l = TransferFunction::continuous(&[1.0], &[1.0, 3.0, 2.0, 0.0]).unwrap();
    let rl = rlocus_tf(&l, None).unwrap();
    assert!((rl.asymptotes.centroid + 1.0).abs() < 1e-14);
    let pi = std::f64::consts::PI;
    for (a, b) in rl
        .asymptotes
        .angles
        .iter()
        .zip([pi / 3.0, pi, 5.0 * pi / 3.0])
    {
        assert!((a - b).abs() < 1e-14);
    }
    assert_eq!(rl.break_points.len(), 1, "{:?}", rl.break_points);
    let bp = rl.break_points[0];
    assert!((bp.point - Complex64::new(-1.0 + 1.0 / 3f64.sqrt(), 0.0)).norm() < 1e-12);
    assert!((bp.gain - 2.0 / (3.0 * 3f64.sqrt())).abs() < 1e-12);
    // The break point's gain is on the grid.
    assert!(rl.gains.contains(&bp.gain));
    for (i, row) in rl.roots.iter().enumerate() {
        for s in row {
            let r = l.den().eval_complex(*s) + l.num().eval_complex(*s) * rl.gains[i];
            assert!(
                r.norm() <= 1e-9 * (1.0 + s.norm()).powi(3),
                "{s} at {}",
                rl.gains[i]
            );
        }
        if i > 0 {
            let jump = row
                .iter()
                .zip(&rl.roots[i - 1])
                .map(|(a, b)| (a - b).norm())
                .fold(0.0, f64::max);
            // Refined to R/50 = 0.04 (R = 2, the largest pole magnitude), except on the two
            // intervals beside the break point, where the double root splits as √(K − K_b).
            let beside = rl.gains[i - 1] == bp.gain || rl.gains[i] == bp.gain;
            assert!(
                jump <= 0.04 * (1.0 + 1e-9) || beside,
                "jump {jump} at {}",
                rl.gains[i]
            );
        }
    }
    // The branches end far out along the asymptotes.
    let last = rl.roots.last().unwrap();
    assert!(last.iter().map(|p| p.norm()).fold(0.0, f64::max) > 5.0);
}

/// `rlocfind` at a point of the locus returns the gain that put a pole there (distance 0),
/// and off the locus a complex `−D/N` with a positive distance.
#[test]
fn rlocfind_recovers_gain() {
    let l = TransferFunction::continuous(&[1.0, 1.0], &[1.0, 3.0, -4.0, 0.0]).unwrap();
    let rl = rlocus_tf(&l, Some(&[3.0])).unwrap();
    let s0 = rl.roots[0]
        .iter()
        .copied()
        .find(|p| p.im > 0.0)
        .or(rl.roots[0].first().copied())
        .unwrap();
    let f = rlocfind_tf(&l, s0).unwrap();
    assert!((f.gain - 3.0).abs() < 1e-10, "{f:?}");
    assert!(f.gain_complex.im.abs() < 1e-10);
    assert!(f.distance < 1e-9);
    let off = rlocfind_tf(&l, Complex64::new(-3.0, 2.0)).unwrap();
    assert!(off.gain_complex.im.abs() > 1e-3 && off.distance > 1e-3);
    // The state-space route gives the same.
    let ss = l.to_state_space().unwrap();
    let g = pendulab_lti::rlocus::rlocfind(&ss, s0).unwrap();
    assert!((g.gain - 3.0).abs() < 1e-8);
    let r2 = rlocus(&ss, Some(&[3.0])).unwrap();
    assert_eq!(r2.roots[0].len(), 3);
}

#[test]
fn rlocus_degenerate_inputs() {
    let improper = TransferFunction::continuous(&[1.0, 0.0, 1.0], &[1.0, 1.0]).unwrap();
    assert!(matches!(
        rlocus_tf(&improper, None),
        Err(LtiError::Improper { .. })
    ));
    let zero = TransferFunction::continuous(&[0.0], &[1.0, 1.0]).unwrap();
    assert!(matches!(
        rlocus_tf(&zero, None),
        Err(LtiError::InvalidArgument(_))
    ));
    let l = TransferFunction::continuous(&[1.0], &[1.0, 1.0]).unwrap();
    assert!(matches!(
        rlocus_tf(&l, Some(&[-1.0])),
        Err(LtiError::InvalidArgument(_))
    ));
    assert!(matches!(
        rlocfind_tf(
            &TransferFunction::continuous(&[1.0, 2.0], &[1.0, 1.0, 1.0]).unwrap(),
            Complex64::new(-2.0, 0.0)
        ),
        Err(LtiError::PoleAtEvaluationPoint { .. })
    ));
    // Poles on the imaginary axis are fine: 1/(s² + 1) starts at ±j.
    let osc = TransferFunction::continuous(&[1.0], &[1.0, 0.0, 1.0]).unwrap();
    let rl = rlocus_tf(&osc, Some(&[0.0, 3.0])).unwrap();
    // K = 3: s² + 4 = 0.
    assert!(
        rl.roots[1]
            .iter()
            .all(|p| (p.norm() - 2.0).abs() < 1e-12 && p.re.abs() < 1e-12)
    );
}

/// python-control's `disk_margins(..., returnall=True)`: the same `α(ω)` on its grid
/// (1e-9 relative), the same gain (dB) and phase margins from it where python-control's
/// formula is the paper's, and our exact `α_max` at most the grid minimum and attained at
/// the critical frequency.
#[test]
fn disk_margins_match_python_control() {
    let f = fixture();
    let w = vector(&f["disk_omega"]);
    let cases = f["disk"].as_array().unwrap();
    assert!(cases.len() >= 16);
    for (k, case) in cases.iter().enumerate() {
        let sys = toolbox_support::system(case);
        let skew = case["skew"].as_f64().unwrap();
        let dm = vector(&case["dm"]);
        let ours = on_sys!(&sys, |s| disk_margin_response(s, skew, &w).unwrap());
        for (a, b) in ours.iter().zip(&dm) {
            assert!((a - b).abs() <= 1e-9 * b, "case {k}: {a} vs {b}");
        }
        for (i, &a) in dm.iter().enumerate() {
            let m = DiskMargin::from_alpha(a, skew);
            // The dB figure is ill-conditioned as a disk edge nears 0 or ∞ (1/(1 − b)).
            let well = 0.5 * a * (1.0 + skew.abs()) <= 0.99;
            if let Some(g) = case["dgm"][i].as_f64()
                && well
            {
                assert!(
                    (m.gain_margin_db() - g).abs() <= 1e-9 * g.abs().max(1.0),
                    "case {k}"
                );
            }
            if let Some(p) = case["dpm"][i].as_f64() {
                assert!(
                    (m.phase_margin_deg - p).abs() <= 1e-8,
                    "case {k}: {m:?} vs {p}"
                );
            }
        }
        let grid_min = dm.iter().copied().fold(f64::INFINITY, f64::min);
        let m = on_sys!(&sys, |s| disk_margin(s, skew).unwrap());
        assert!(m.closed_loop_stable);
        assert!(
            m.alpha <= grid_min * (1.0 + 1e-9),
            "case {k}: {} > {grid_min}",
            m.alpha
        );
        // The exact peak may lie between python-control's grid points (a lightly damped
        // pair): it is attained at the critical frequency and no point of a fine grid around
        // it lies below it.
        if m.frequency.is_finite() {
            let at = on_sys!(&sys, |s| disk_margin_response(s, skew, &[m.frequency])
                .unwrap());
            assert!((at[0] - m.alpha).abs() <= 1e-8 * m.alpha, "case {k}");
            let fine: Vec<f64> = (0..=2000)
                .map(|i| m.frequency * 1.2f64.powf(i as f64 / 1000.0 - 1.0))
                .collect();
            let a = on_sys!(&sys, |s| disk_margin_response(s, skew, &fine).unwrap());
            let local_min = a.iter().copied().fold(f64::INFINITY, f64::min);
            assert!(local_min >= m.alpha * (1.0 - 1e-9), "case {k}");
        } else {
            assert!(
                (m.alpha - grid_min).abs() <= 1e-4 * grid_min,
                "case {k}: {m:?}"
            );
        }
    }
}

/// `L = k/(s + 1)`: `|S − ½| = |s + 1 − k|/(2|s + 1 + k|)`, so `α = 2` (approached at
/// `ω → ∞`) for `k > 0` and `α = 2(1 + k)/(1 − k)` at `ω = 0` for `−1 < k < 0`;
/// `L = 2/(s − 1)` is stable in closed loop only for `k > 1`; `k = 0.5` gives `α = 0`.
#[test]
fn disk_margin_first_order_closed_form() {
    for k in [0.5, 2.0, 10.0] {
        let l = TransferFunction::continuous(&[k], &[1.0, 1.0])
            .unwrap()
            .to_state_space()
            .unwrap();
        let m = disk_margin(&l, 0.0).unwrap();
        assert!((m.alpha - 2.0).abs() < 1e-8, "k = {k}: {m:?}");
        assert!((m.phase_margin_deg - 90.0).abs() < 1e-5);
    }
    for k in [-0.5, -0.2] {
        let l = TransferFunction::continuous(&[k], &[1.0, 1.0])
            .unwrap()
            .to_state_space()
            .unwrap();
        let m = disk_margin(&l, 0.0).unwrap();
        let want = 2.0 * (1.0 + k) / (1.0 - k);
        assert!((m.alpha - want).abs() < 1e-9 * want, "k = {k}: {m:?}");
        assert!(m.frequency.abs() < 1e-6, "{m:?}");
        // Gain interval (2 − α)/(2 + α) … (2 + α)/(2 − α).
        let g = (2.0 + want) / (2.0 - want);
        assert!((m.gain_interval.1 - g).abs() < 1e-8 * g);
    }
    let unstable = TransferFunction::continuous(&[0.5], &[1.0, -1.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let m = disk_margin(&unstable, 0.0).unwrap();
    assert!(!m.closed_loop_stable && m.alpha == 0.0);
    // Skewed disk of S (σ = 1): α = 1/‖S‖∞, gain interval (1 − α)… wait: γ₋ = 1/(1 + α).
    let l = TransferFunction::continuous(&[4.0], &[1.0, 3.0, 3.0, 1.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let m = disk_margin(&l, 1.0).unwrap();
    let s = pendulab_lti::margins::gang_of_four(
        &l,
        &StateSpace::static_gain(Mat::identity(1, 1), l.domain()).unwrap(),
    )
    .unwrap()
    .s;
    let ms = hinf_norm(&s, 1e-12).unwrap().value;
    assert!((m.alpha - 1.0 / ms).abs() < 1e-8 / ms);
    assert!((m.gain_interval.0 - 1.0 / (1.0 + m.alpha)).abs() < 1e-12);
    assert!(matches!(
        disk_margin(&l, f64::NAN),
        Err(LtiError::InvalidArgument(_))
    ));
}

/// Discrete loop: the disk margin is the bilinear-mapped H∞ peak, checked against the
/// frequency-wise margin on a fine grid below the Nyquist frequency.
#[test]
fn disk_margin_discrete_against_grid() {
    let l = TransferFunction::<Discrete>::discrete(&[0.2, 0.1], &[1.0, -1.3, 0.4], 0.05)
        .unwrap()
        .to_state_space()
        .unwrap();
    let m = disk_margin(&l, 0.0).unwrap();
    let w: Vec<f64> = (1..4000)
        .map(|i| i as f64 / 4000.0 * std::f64::consts::PI / 0.05)
        .collect();
    let a = disk_margin_response(&l, 0.0, &w).unwrap();
    let grid_min = a.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(m.alpha <= grid_min * (1.0 + 1e-9));
    assert!(
        m.alpha >= grid_min * (1.0 - 1e-4),
        "{} vs {grid_min}",
        m.alpha
    );
}

/// python-control's `singular_values_response` (itself checked against NumPy's SVD).
#[test]
fn sigma_matches_python_control() {
    let f = fixture();
    for (k, case) in f["sigma"].as_array().unwrap().iter().enumerate() {
        let sys = toolbox_support::system(case);
        let w = vector(&case["omega"]);
        let sv = on_sys!(&sys, |s| sigma(s, &w).unwrap());
        for (i, row) in case["sv"].as_array().unwrap().iter().enumerate() {
            let want = vector(row);
            assert_eq!(sv.values[i].len(), want.len());
            for (a, b) in sv.values[i].iter().zip(&want) {
                assert!(
                    (a - b).abs() <= 1e-10 * want[0],
                    "case {k} ω {}: {a} vs {b}",
                    w[i]
                );
            }
        }
    }
}
