//! Multi-loop and loop-at-a-time disk margins (`pendulab_lti::mu`) against independent
//! checks: the SISO disk margin (Hamiltonian H∞ bisection), the closed form for a diagonal
//! loop, and μ by brute force over the phases of `Q = diag(e^{jθ₁}, …)` using
//! `μ(M) = max_Q ρ(QM)` for complex uncertainty (Doyle 1982; Packard & Doyle 1993).

use pendulab_lti::disk_margin::disk_margin;
use pendulab_lti::interconnect::append;
use pendulab_lti::linalg::from_rows;
use pendulab_lti::mu::{disk_margin_mimo, mu_diag_complex};
use pendulab_lti::random::SplitMix64;
use pendulab_lti::{CMat, Complex64, Discretization, LtiError, Mat, StateSpace};

type C = Complex64;

fn siso(
    num_k: f64,
    a: &[&[f64]],
    b: &[&[f64]],
    c: &[&[f64]],
) -> StateSpace<pendulab_lti::Continuous> {
    StateSpace::continuous(
        from_rows(a).unwrap(),
        from_rows(b).unwrap(),
        from_rows(c).unwrap(),
        Mat::from_element(1, 1, num_k),
    )
    .unwrap()
}

/// `L1 = 2/(s² + s)`-like loops in companion form: `k/(s² + a1 s + a0)`.
fn second_order(k: f64, a1: f64, a0: f64) -> StateSpace<pendulab_lti::Continuous> {
    siso(
        0.0,
        &[&[0.0, 1.0], &[-a0, -a1]],
        &[&[0.0], &[k]],
        &[&[1.0, 0.0]],
    )
}

/// Eigenvalue moduli of a 2 × 2 complex matrix by the quadratic formula; the largest.
fn rho2(m: [[C; 2]; 2]) -> f64 {
    let tr = m[0][0] + m[1][1];
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let disc = (tr * tr - det * 4.0).sqrt();
    ((tr + disc) * 0.5).norm().max(((tr - disc) * 0.5).norm())
}

/// μ of a 2 × 2 matrix by brute force over the two phases of `Q` (the common phase does not
/// change ρ, so θ₁ = 0 and θ₂ runs over a fine grid, then a local grid around the best).
fn brute_mu2(m: [[C; 2]; 2]) -> f64 {
    let eval = |t: f64| {
        let q = C::from_polar(1.0, t);
        rho2([[m[0][0], m[0][1]], [q * m[1][0], q * m[1][1]]])
    };
    let n = 20_000;
    let h = std::f64::consts::TAU / n as f64;
    let (mut best_t, mut best) = (0.0, eval(0.0));
    for k in 1..n {
        let t = k as f64 * h;
        let v = eval(t);
        if v > best {
            (best_t, best) = (t, v);
        }
    }
    for k in -1000..=1000 {
        let v = eval(best_t + k as f64 * h / 500.0);
        best = best.max(v);
    }
    best
}

#[test]
fn one_by_one_loop_equals_siso_disk_margin() {
    let l = second_order(2.0, 1.0, 0.0);
    for skew in [0.0, 0.5, -0.5, 1.0] {
        let siso = disk_margin(&l, skew).unwrap();
        let m = disk_margin_mimo(&l, skew).unwrap();
        assert_eq!(m.loop_at_a_time.len(), 1);
        let lat = m.loop_at_a_time[0];
        assert!(
            (lat.alpha - siso.alpha).abs() <= 1e-9 * siso.alpha,
            "{skew}"
        );
        // The multi-loop margin comes from the μ grid search: a different algorithm.
        let (lo, hi) = m.multi_loop_alpha_bounds;
        assert!(
            (lo - siso.alpha).abs() <= 1e-6 * siso.alpha,
            "{skew}: {lo} vs {}",
            siso.alpha
        );
        assert!((hi - siso.alpha).abs() <= 1e-6 * siso.alpha);
        assert!((m.peak_frequency - siso.frequency).abs() <= 1e-3 * siso.frequency);
        assert_eq!(m.mu_peak.lower, m.mu_peak.upper);
    }
}

#[test]
fn discrete_one_by_one_loop_equals_siso_disk_margin() {
    let l = second_order(2.0, 1.0, 0.0)
        .c2d(0.1, Discretization::Zoh)
        .unwrap();
    for skew in [0.0, 0.5] {
        let siso = disk_margin(&l, skew).unwrap();
        let m = disk_margin_mimo(&l, skew).unwrap();
        assert!((m.loop_at_a_time[0].alpha - siso.alpha).abs() <= 1e-9 * siso.alpha);
        let (lo, hi) = m.multi_loop_alpha_bounds;
        assert!(
            (lo - siso.alpha).abs() <= 1e-6 * siso.alpha,
            "{skew}: {lo} vs {}",
            siso.alpha
        );
        assert!((hi - siso.alpha).abs() <= 1e-6 * siso.alpha);
    }
}

#[test]
fn diagonal_loop_multi_loop_is_min_of_siso_margins() {
    let l1 = second_order(2.0, 1.0, 0.0);
    let l2 = second_order(30.0, 3.0, 1.0);
    let l = append(&[&l1, &l2]).unwrap();
    for skew in [0.0, 0.3] {
        let d1 = disk_margin(&l1, skew).unwrap();
        let d2 = disk_margin(&l2, skew).unwrap();
        let m = disk_margin_mimo(&l, skew).unwrap();
        assert!((m.loop_at_a_time[0].alpha - d1.alpha).abs() <= 1e-9 * d1.alpha);
        assert!((m.loop_at_a_time[1].alpha - d2.alpha).abs() <= 1e-9 * d2.alpha);
        let want = d1.alpha.min(d2.alpha);
        let (lo, hi) = m.multi_loop_alpha_bounds;
        assert!(lo <= hi);
        assert!((lo - want).abs() <= 1e-6 * want, "{lo} vs {want}");
        assert!((hi - want).abs() <= 1e-6 * want, "{hi} vs {want}");
        assert!((m.multi_loop.alpha - lo).abs() == 0.0);
    }
}

/// The spinning satellite (Doyle; Skogestad &
/// Postlethwaite §3.7.1): `P = 1/(s² + a²) [[s − a², a(s+1)], [−a(s+1), s − a²]]`, realised
/// as `A = [[0, a], [−a, 0]]`, `B = I`, `C = [[1, a], [−a, 1]]`, with `K = I`.
const A_SAT: f64 = 10.0;

fn satellite() -> StateSpace<pendulab_lti::Continuous> {
    let a = A_SAT;
    StateSpace::continuous(
        from_rows(&[&[0.0, a], &[-a, 0.0]]).unwrap(),
        Mat::identity(2, 2),
        from_rows(&[&[1.0, a], &[-a, 1.0]]).unwrap(),
        Mat::zeros(2, 2),
    )
    .unwrap()
}

/// `S + (σ − 1)/2 I` of the satellite loop at `jω`, by direct 2 × 2 complex inversion of the
/// transfer-function entries (independent of the library's frequency response).
fn satellite_s_sigma(w: f64, skew: f64) -> [[C; 2]; 2] {
    let a = A_SAT;
    let s = C::new(0.0, w);
    let den = s * s + a * a;
    let l = [
        [(s - a * a) / den, (s + 1.0) * a / den],
        [-(s + 1.0) * a / den, (s - a * a) / den],
    ];
    let m = [[l[0][0] + 1.0, l[0][1]], [l[1][0], l[1][1] + 1.0]];
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let sh = 0.5 * (skew - 1.0);
    [
        [m[1][1] / det + sh, -m[0][1] / det],
        [-m[1][0] / det, m[0][0] / det + sh],
    ]
}

#[test]
fn satellite_bounds_bracket_brute_force_mu() {
    let l = satellite();
    for skew in [0.0, 0.5] {
        let m = disk_margin_mimo(&l, skew).unwrap();
        let wp = m.peak_frequency;
        assert!(wp.is_finite(), "{wp}");
        let brute = brute_mu2(satellite_s_sigma(wp, skew));
        assert!(m.mu_peak.lower <= m.mu_peak.upper);
        assert!(
            (m.mu_peak.upper - brute).abs() <= 1e-3 * brute,
            "upper {} vs brute {brute}",
            m.mu_peak.upper
        );
        assert!(
            (m.mu_peak.lower - brute).abs() <= 1e-3 * brute,
            "lower {} vs brute {brute}",
            m.mu_peak.lower
        );
        // The located peak is the sup over a fine independent frequency sweep.
        let sweep = (0..4000)
            .map(|k| 10f64.powf(-2.0 + 5.0 * k as f64 / 3999.0))
            .map(|w| brute_mu2_coarse(satellite_s_sigma(w, skew)))
            .fold(0.0, f64::max);
        assert!(
            sweep <= m.mu_peak.upper * (1.0 + 1e-6),
            "{sweep} > {}",
            m.mu_peak.upper
        );
        assert!(
            sweep >= m.mu_peak.upper * (1.0 - 1e-3),
            "{sweep} << {}",
            m.mu_peak.upper
        );
        // Loop-at-a-time: α_i = 1/sup |S_ii + (σ−1)/2| over the same sweep.
        for i in 0..2 {
            let peak = (0..20_000)
                .map(|k| 10f64.powf(-2.0 + 5.0 * k as f64 / 19_999.0))
                .map(|w| satellite_s_sigma(w, skew)[i][i].norm())
                .fold(0.0, f64::max);
            let alpha = m.loop_at_a_time[i].alpha;
            assert!(alpha <= 1.0 / peak * (1.0 + 1e-9));
            assert!(
                alpha >= 1.0 / peak * (1.0 - 1e-3),
                "{alpha} vs {}",
                1.0 / peak
            );
        }
        if skew == 0.0 {
            // Closed form: with the other loop closed each channel sees L_i = 1/s, so
            // S_ii − ½ = (s − 1)/(2(s + 1)) has modulus ½ at every ω and α_i = 2.
            for w in [0.0, 0.05, 1.0, 7.0, 300.0] {
                assert!((satellite_s_sigma(w, 0.0)[0][0].norm() - 0.5).abs() < 1e-12);
            }
            for d in &m.loop_at_a_time {
                assert!((d.alpha - 2.0).abs() <= 1e-9, "{d:?}");
            }
        }
        // Simultaneous perturbations can only do worse than one channel at a time.
        let lat = m
            .loop_at_a_time
            .iter()
            .map(|d| d.alpha)
            .fold(f64::INFINITY, f64::min);
        assert!(m.multi_loop_alpha_bounds.1 <= lat * (1.0 + 1e-9));
    }
}

fn brute_mu2_coarse(m: [[C; 2]; 2]) -> f64 {
    (0..720)
        .map(|k| {
            let q = C::from_polar(1.0, k as f64 * std::f64::consts::TAU / 720.0);
            rho2([[m[0][0], m[0][1]], [q * m[1][0], q * m[1][1]]])
        })
        .fold(0.0, f64::max)
}

/// ρ of a complex square matrix (nalgebra's complex Schur form).
fn rho(m: &CMat) -> f64 {
    let t = nalgebra::linalg::Schur::new(m.clone()).unpack().1;
    (0..t.nrows()).map(|i| t[(i, i)].norm()).fold(0.0, f64::max)
}

#[test]
fn random_three_by_three_bounds_are_ordered_and_bracket_brute_force() {
    let mut rng = SplitMix64::new(19);
    for case in 0..12 {
        let re = rng.matrix(3, 3);
        let im = rng.matrix(3, 3);
        let m = CMat::from_fn(3, 3, |i, j| C::new(re[(i, j)], im[(i, j)]));
        let b = mu_diag_complex(&m).unwrap();
        assert!(b.lower <= b.upper, "{case}: {b:?}");
        assert_eq!(b.d_scaling.len(), 3);
        // The upper bound is σ̄(DMD⁻¹) at the returned D (its defining residual).
        let d = &b.d_scaling;
        let md = CMat::from_fn(3, 3, |i, j| m[(i, j)] * d[i] / d[j]);
        let sv = md.singular_values()[0];
        assert!((sv - b.upper).abs() <= 1e-10 * sv);
        // Brute force over the two relative phases: max ρ(QM) ≤ μ ≤ upper, and for three
        // scalar blocks upper = μ (Doyle 1982), so the grid maximum comes close.
        let n = 180;
        let mut brute = 0.0f64;
        for k1 in 0..n {
            for k2 in 0..n {
                let q = [
                    C::new(1.0, 0.0),
                    C::from_polar(1.0, k1 as f64 * std::f64::consts::TAU / n as f64),
                    C::from_polar(1.0, k2 as f64 * std::f64::consts::TAU / n as f64),
                ];
                brute = brute.max(rho(&CMat::from_fn(3, 3, |i, j| q[i] * m[(i, j)])));
            }
        }
        assert!(
            brute <= b.upper * (1.0 + 1e-9),
            "{case}: {brute} > {}",
            b.upper
        );
        assert!(
            brute >= b.upper * (1.0 - 2e-3),
            "{case}: {brute} << {}",
            b.upper
        );
        assert!(
            b.lower >= brute * (1.0 - 2e-3),
            "{case}: lower {} << {brute}",
            b.lower
        );
    }
}

#[test]
fn scalar_and_invariance() {
    let m = CMat::from_element(1, 1, C::new(3.0, -4.0));
    let b = mu_diag_complex(&m).unwrap();
    assert_eq!((b.lower, b.upper), (5.0, 5.0));
    // μ is invariant under diagonal similarity: a badly scaled 2 × 2 has the same bounds.
    let m = CMat::from_row_slice(
        2,
        2,
        &[
            C::new(1.0, 1.0),
            C::new(2.0, 0.0),
            C::new(0.5, -1.0),
            C::new(-1.0, 0.3),
        ],
    );
    let s = CMat::from_fn(2, 2, |i, j| m[(i, j)] * [1.0, 1e4][i] / [1.0, 1e4][j]);
    let (b1, b2) = (mu_diag_complex(&m).unwrap(), mu_diag_complex(&s).unwrap());
    let brute = brute_mu2([[m[(0, 0)], m[(0, 1)]], [m[(1, 0)], m[(1, 1)]]]);
    for b in [b1, b2] {
        assert!((b.upper - brute).abs() <= 1e-6 * brute, "{b:?} vs {brute}");
        assert!((b.lower - brute).abs() <= 1e-6 * brute, "{b:?} vs {brute}");
    }
}

#[test]
fn errors_and_unstable_loop() {
    let m = CMat::zeros(2, 3);
    assert!(matches!(
        mu_diag_complex(&m),
        Err(LtiError::NotSquare { .. })
    ));
    let mut m = CMat::zeros(2, 2);
    m[(1, 0)] = C::new(f64::NAN, 0.0);
    assert!(matches!(
        mu_diag_complex(&m),
        Err(LtiError::NonFinite { .. })
    ));
    let ns = StateSpace::continuous(
        Mat::zeros(1, 1),
        Mat::zeros(1, 2),
        Mat::zeros(1, 1),
        Mat::zeros(1, 2),
    )
    .unwrap();
    assert!(matches!(
        disk_margin_mimo(&ns, 0.0),
        Err(LtiError::NotSquare { .. })
    ));
    assert!(matches!(
        disk_margin_mimo(&satellite(), f64::NAN),
        Err(LtiError::InvalidArgument(_))
    ));
    // 1 + L = (s − 1)/(s + 1) for L = −2/(s + 1): unstable closed loop, margins 0.
    let l1 = siso(0.0, &[&[-1.0]], &[&[1.0]], &[&[-2.0]]);
    let l = append(&[&l1, &second_order(2.0, 1.0, 0.0)]).unwrap();
    let m = disk_margin_mimo(&l, 0.0).unwrap();
    assert!(!m.multi_loop.closed_loop_stable);
    assert_eq!(m.multi_loop.alpha, 0.0);
    assert!(
        m.loop_at_a_time
            .iter()
            .all(|d| d.alpha == 0.0 && !d.closed_loop_stable)
    );
}
