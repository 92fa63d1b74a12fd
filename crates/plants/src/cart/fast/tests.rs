//! Tests of the cart pendulum's fast kernels against independent references: libm's sines and
//! cosines, the general RK4 loop, and the documented error bounds.
//!
//! Neighbours: `cart.rs` holds the physics, [`super`] the kernel type [`FastCart`];
//! `anchored.rs` and `lanes.rs` the kernels tested here.

use super::anchored::{WIDE_ANGLE_LIMIT, WIDE_SHIFT_LIMIT, anchor_sin_cos, stage_sin_cos};
use super::*;
use crate::cart::CartEquilibrium;
use pendulab_lti::Mat;
use pendulab_sim::fast::ROTATE_LIMIT;
use pendulab_sim::rk4_step;

/// The spacing of doubles at `v` (ulp); the smallest normal spacing at zero.
fn ulp(v: f64) -> f64 {
    let a = v.abs();
    if a == 0.0 {
        return f64::MIN_POSITIVE;
    }
    f64::from_bits(a.to_bits() + 1) - a
}

/// Uniform numbers in `[lo, hi)` from a 64-bit LCG (Knuth's MMIX constants).
fn uniform(state: &mut u64, lo: f64, hi: f64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    lo + (hi - lo) * ((*state >> 11) as f64 / (1u64 << 53) as f64)
}

/// The anchored step's first sine and cosine against libm's (the independent reference)
/// over `|θ| ≤ 0.3`: within the bound of `Trig::Anchored`, 2 ulp + 6·10⁻¹⁷ (libm < 1
/// ulp, the truncated series < 3·10⁻¹⁸, the correction's roundings ≲ 2·10⁻¹⁷, the final
/// addition half an ulp), and exactly libm's beyond the wide series' range.
#[test]
fn anchor_sine_and_cosine_are_within_the_anchored_bound_of_libm() {
    let mut state = 1u64;
    let mut worst = 0.0f64;
    let mut points: Vec<f64> = (0..400_000)
        .map(|_| uniform(&mut state, -0.3, 0.3))
        .collect();
    // The range's end and tiny angles (where the series' leading term rules).
    for b in [WIDE_ANGLE_LIMIT, 1e-3, 1e-9, 1e-300] {
        for v in [
            b,
            f64::from_bits(b.to_bits() + 1),
            f64::from_bits(b.to_bits() - 1),
        ] {
            points.extend([v, -v]);
        }
    }
    for x in points {
        let (s, c) = anchor_sin_cos(x);
        let (rs, rc) = x.sin_cos();
        if x.abs() > WIDE_ANGLE_LIMIT {
            assert_eq!((s, c), (rs, rc), "{x:e}");
            continue;
        }
        for (got, want) in [(s, rs), (c, rc)] {
            let bound = 2.0 * ulp(want) + 6e-17;
            let err = (got - want).abs();
            assert!(err <= bound, "{x:e}: {got:e} vs {want:e}");
            worst = worst.max(err / bound);
        }
    }
    // Not vacuous: the rounding shows.
    assert!(worst > 0.05, "worst error / bound {worst}");
}

/// The stage sines and cosines from the anchor's (`stage_sin_cos`) against libm at the
/// stage angle `x = fl(θ + d)`, corrected to first order by the rounding error of that sum
/// (`r = (θ + d) − x`, exact by Knuth's TwoSum; `sin(x + r) = sin x + r cos x` up to
/// `r²/2 < 10⁻³²`): anchors over several periods and near zero, offsets within 1/32 and
/// up to 1/8 (the wide series) and beyond (libm). Bound: 2 ulp + 6·10⁻¹⁷ for offsets
/// within 1/32 (the documented bound of `sin_cos_offset`, whose argument holds for the
/// longer series as well: its truncation is smaller); beyond, the correction term
/// `s·(cos d − 1) + c·sin d` reaches |d| + d²/2 < 0.133 and its three roundings add up to
/// 3 · 2⁻⁵³ · 0.133 < 5·10⁻¹⁷ more, so 2 ulp + 1.1·10⁻¹⁶ there.
#[test]
fn stage_sine_and_cosine_are_within_the_anchored_bound_of_libm() {
    let mut state = 2u64;
    let mut worst = [0.0f64; 2];
    for i in 0..1_000_000 {
        let a = match i % 3 {
            0 => uniform(&mut state, -20.0, 20.0),
            1 => uniform(&mut state, -1e-3, 1e-3),
            _ => uniform(&mut state, -0.25, 0.25),
        };
        let d = match i % 4 {
            0 => uniform(&mut state, -1e-3, 1e-3),
            1 => uniform(&mut state, -1.0 / 32.0, 1.0 / 32.0),
            _ => uniform(&mut state, -0.15, 0.15),
        };
        let (s, c) = a.sin_cos();
        let (gs, gc) = stage_sin_cos(a, d, s, c);
        let x = a + d;
        let bb = x - a;
        let r = (a - (x - bb)) + (d - bb);
        let (xs, xc) = x.sin_cos();
        if d.abs() > WIDE_SHIFT_LIMIT {
            assert_eq!((gs, gc), (xs, xc), "a = {a:e}, d = {d:e}");
            continue;
        }
        let (rs, rc) = (xs + r * xc, xc - r * xs);
        let tier = usize::from(d.abs() > pendulab_sim::fast::SHIFT_LIMIT);
        let extra = [6e-17, 1.1e-16][tier];
        for (got, want) in [(gs, rs), (gc, rc)] {
            let bound = 2.0 * ulp(want) + extra;
            let err = (got - want).abs();
            assert!(err <= bound, "a = {a:e}, d = {d:e}: {got:e} vs {want:e}");
            worst[tier] = worst[tier].max(err / bound);
        }
    }
    assert!(
        worst[0] > 0.05 && worst[1] > 0.05,
        "worst error / bound {worst:?}"
    );
}

/// The polynomial sine/cosine changes `θ̈` only through `sin θ` and `cos θ`: by at most
/// their error (2 ulp + 4·10⁻¹⁷·max(1, |θ|), `Trig`'s documented bound against libm)
/// times the terms they multiply, plus the rounding of the few operations after them
/// (a few ulp of the largest term). The reference is the libm plant.
#[test]
fn polynomial_trig_right_hand_side_is_within_the_documented_bound_of_libm() {
    let libm = CartPendulum::book();
    let poly = FastCart::new(CartPendulum::book(), Trig::Polynomial);
    let default = FastCart::new(libm, Trig::default());
    assert_eq!(
        (default.trig(), poly.trig()),
        (Trig::Libm, Trig::Polynomial)
    );
    let p = libm.params();
    let j = libm.inertia_about_pivot();
    let (mgl, ml) = (p.m_p * p.g * p.l_p, p.m_p * p.l_p);
    let mut worst = 0.0f64;
    for i in -40_000..=40_000 {
        let theta = i as f64 * 5e-4 + 1e-7;
        let x = [0.1, theta, -0.7, 3.0];
        let v = 2.5;
        let a = libm.derivative_array(&x, v);
        let b = poly.derivative_array(&x, v);
        assert_eq!(a[..3], b[..3]);
        let ddz = a[2].abs();
        let terms = (mgl + p.mu_p * 3.0 + ml * ddz) / j;
        let trig_err = 2.0 * f64::EPSILON + 4e-17 * theta.abs().max(1.0);
        let bound = (mgl + ml * ddz) / j * trig_err + 8.0 * f64::EPSILON * terms;
        let d = (a[3] - b[3]).abs();
        assert!(d <= bound, "θ = {theta}: |Δθ̈| = {d:e} > {bound:e}");
        worst = worst.max(d / bound);
    }
    // Not bit-identical everywhere (else the option would be pointless to document).
    assert!(worst > 0.0);
}

/// The LQR gain of the book's `cdip_lqr_sim` design (Q = diag(10, 10, 0, 0), R = 1) on
/// `plant` linearised upright: a stabilising feedback for the kernel tests.
fn cdip_lqr_gain(plant: &CartPendulum) -> Mat {
    let sys = plant.linearize(CartEquilibrium::upright()).unwrap();
    let mut q = Mat::zeros(4, 4);
    (q[(0, 0)], q[(1, 1)]) = (10.0, 10.0);
    pendulab_lti::design::lqr(&sys, &q, &Mat::identity(1, 1), None)
        .unwrap()
        .gain
}

/// The fixed-size kernel reproduces the general sampled-data loop bit for bit with this
/// plant (the reference is `SampledLoop::run`, which evaluates `Dynamics::derivative`),
/// with either sine/cosine and on either multiply–add path (the provided RK4 step has no
/// multiply–adds to fuse), under a stabilising feedback (the LQR gain of the book's
/// `cdip_lqr_sim` design, Q = diag(10, 10, 0, 0), R = 1) from 15°.
#[test]
fn fixed_kernel_runs_are_bit_identical_to_the_general_loop() {
    use pendulab_sim::controllers::StaticStateFeedback;
    use pendulab_sim::fast::MulAddPath;
    use pendulab_sim::{SampledLoop, SampledOptions};
    for trig in [Trig::Libm, Trig::Polynomial] {
        let plant = FastCart::new(CartPendulum::book(), trig);
        let k = cdip_lqr_gain(plant.plant());
        let opts = SampledOptions::default();
        let mut g = SampledLoop::new(plant, StaticStateFeedback::new(k).unwrap(), opts).unwrap();
        let x0 = [0.0, 15f64.to_radians(), 0.0, 0.0];
        let b = g.run(&x0).unwrap();
        for path in [MulAddPath::Fused, MulAddPath::Separate] {
            let mut f = g.fixed::<4>().unwrap().with_multiply_add(path);
            let a = f.run(&x0).unwrap();
            assert_eq!(a, b, "{trig:?}, {path:?}");
            assert!(a.diagnostics.final_state[1].abs() < 1e-6);
        }
    }
}

/// The narrow anchored step (`h ≤ 2⁻⁸ s`) with either multiply–add against the classic
/// RK4 step of the libm plant (`rk4_fixed`: the generic stage code on the plain right-hand
/// side, an independent implementation) from the same state, over random states
/// (|θ| ≤ 0.6 — every series tier and libm beyond 1/4 —, |θ̇| ≤ 5, |ż| ≤ 1, |v| ≤ 10 V,
/// so |z̈| ≤ a_c|ż| + b_c|v| < 50 m/s²) and step lengths 0.25 ms, 1 ms and 2⁻⁸ s (where
/// |θ̈| > 16 rad/s² puts the third stage's offset beyond the rotation's range).
///
/// Bound. Each stage's θ̈ differs from the libm step's by: its sine and cosine, within
/// 1.5 ulp + 2.5·10⁻¹⁷ of libm's (≤ 1.9·10⁻¹⁶) at an angle that differs from the libm
/// step's stage angle by their roundings (≤ 3 ulp of |θ| < 1, 3.3·10⁻¹⁶); the rotation
/// (1.5 ulp of its result) and a few roundings of the terms on either side (≤ 4·2⁻⁵³ of
/// their sum); the cart's stage accelerations a few roundings of b_c|v| + a_c|ż|, which
/// enter through L cos θ. Altogether at most (G + L|z̈|)·10⁻¹⁵ with G = m_p g l_p/J,
/// L = m_p l_p/J, i.e. 2.0·10⁻¹³ 1/s² here; RK4's weights sum to one, so the velocities
/// move by at most h times that (the positions by h² times). Both steps round their
/// updates a few times at the size of the state: 4 ulp of it. So each component within
/// 4 ulp(x'_i) + h·2·10⁻¹³. Not vacuous: the worst difference uses a sizeable part of it;
/// both the rotation and its fallback (`sin_cos_offset`) run.
#[test]
fn narrow_anchored_step_is_within_rounding_of_the_libm_step() {
    use pendulab_sim::fast::{Fused, Separate, rk4_fixed};
    fn run<F: MulAdd>() {
        let anchored = FastCart::new(CartPendulum::book(), Trig::Anchored);
        let libm = CartPendulum::book();
        let mut state = 3u64;
        let mut worst = 0.0f64;
        let (mut rotated, mut fallback) = (0usize, 0usize);
        for i in 0..200_000 {
            let h = [2.5e-4, 1e-3, 1.0 / 256.0][i % 3];
            let x = [
                uniform(&mut state, -0.5, 0.5),
                uniform(&mut state, -0.6, 0.6),
                uniform(&mut state, -1.0, 1.0),
                uniform(&mut state, -5.0, 5.0),
            ];
            let u = uniform(&mut state, -10.0, 10.0);
            let (mut a, mut b) = (x, x);
            anchored.rk4_step_fixed_with::<F>(&mut a, u, h);
            rk4_fixed(&libm, &mut b, u, h);
            for j in 0..4 {
                let tol = 4.0 * ulp(b[j]) + h * 2e-13;
                let d = (a[j] - b[j]).abs();
                assert!(
                    d <= tol,
                    "{:?}: h = {h}, x = {x:?}, u = {u}: state {j}, {d:e}",
                    F::PATH
                );
                worst = worst.max(d / tol);
            }
            // Which way the third stage went: e₃ = (h²/4)·θ̈₁.
            let e3 = 0.25 * h * h * libm.derivative_array(&x, u)[3];
            if e3.abs() <= ROTATE_LIMIT * 0.99 {
                rotated += 1;
            } else if e3.abs() > ROTATE_LIMIT * 1.01 {
                fallback += 1;
            }
        }
        eprintln!(
            "{:?}: worst difference / tolerance {worst}; rotated {rotated}, fallback {fallback}",
            F::PATH
        );
        assert!(worst > 0.05, "{worst}");
        assert!(rotated > 10_000 && fallback > 1000, "{rotated} {fallback}");
    }
    run::<Fused>();
    run::<Separate>();
    // The two strategies do round differently (the fused one once per multiply–add),
    // which shows in some steps' results (most differences in θ̈ stay below half an ulp
    // of the state after the factor h: 35 of these 1000 steps differ).
    let anchored = FastCart::new(CartPendulum::book(), Trig::Anchored);
    let mut state = 4u64;
    let differ = (0..1000)
        .filter(|_| {
            let x = [
                0.1,
                uniform(&mut state, -0.3, 0.3),
                0.2,
                uniform(&mut state, -2.0, 2.0),
            ];
            let (mut a, mut b) = (x, x);
            anchored.rk4_step_fixed_with::<Fused>(&mut a, 1.5, 1e-3);
            anchored.rk4_step_fixed_with::<Separate>(&mut b, 1.5, 1e-3);
            a != b
        })
        .count();
    assert!(differ > 10, "{differ}");
}

/// With `Trig::Anchored` the kernel runs `narrow_anchored_step` (1 ms steps) on either
/// multiply–add path; the general loop (which evaluates the plain right-hand side, libm
/// for this variant) is the reference. Each stage's θ̈ is within
/// (m_p g l_p + m_p l_p |z̈|)/J · 10⁻¹⁵ of the libm step's from the same state (derived in
/// `narrow_anchored_step_is_within_rounding_of_the_libm_step`), ≈ 10⁻¹³ here (|z̈| < 20
/// m/s²: |ż| < 0.8 m/s, |v| < 3.6 V), which moves the state by h times that per step, and
/// the updates round at a few ulp of the state (≤ 3·10⁻¹⁶ for |x| < 1): 10⁴ steps of 1 ms
/// add up to at most 4·10⁻¹² without any help from the loop's damping; 1e-13 is asserted
/// on the ~0.26 rad swing (the stable loop keeps the sum near a few steps' worth).
#[test]
fn anchored_trig_kernel_stays_within_rounding_of_the_libm_loop() {
    use pendulab_sim::controllers::StaticStateFeedback;
    use pendulab_sim::fast::MulAddPath;
    use pendulab_sim::{SampledLoop, SampledOptions};
    let plant = FastCart::new(CartPendulum::book(), Trig::Anchored);
    let k = cdip_lqr_gain(plant.plant());
    let feedback = StaticStateFeedback::new(k).unwrap();
    let opts = SampledOptions::default();
    let g = SampledLoop::new(plant, feedback.clone(), opts.clone()).unwrap();
    let mut libm = SampledLoop::new(CartPendulum::book(), feedback, opts).unwrap();
    let x0 = [0.0, 15f64.to_radians(), 0.0, 0.0];
    let b = libm.run(&x0).unwrap();
    // The plain right-hand side of the anchored plant is libm's.
    assert_eq!(g.clone().run(&x0).unwrap(), b);
    let mut runs = Vec::new();
    for path in [MulAddPath::Fused, MulAddPath::Separate] {
        let a = g
            .fixed::<4>()
            .unwrap()
            .with_multiply_add(path)
            .run(&x0)
            .unwrap();
        let (xa, xb) = (a.trajectory.x(), b.trajectory.x());
        assert_eq!(xa.shape(), xb.shape());
        let dev = (xa - xb).abs().max();
        assert!(dev < 1e-13, "{path:?}: max deviation {dev:e}");
        assert!(a.diagnostics.final_state[1].abs() < 1e-6);
        runs.push(a);
    }
    // The two paths differ where the processor has FMA (the fused path then rounds
    // differently), not otherwise.
    let fused = g.fixed::<4>().unwrap().multiply_add() == MulAddPath::Fused;
    assert_eq!(runs[0] != runs[1], fused);
}

/// The lane kernel with `AnchoredSinCos` (the cart's own lane RK4 step) against the
/// lane kernel with libm (bit-identical to the general loop) on a grid of initial states
/// that includes falling runs, at 1 kHz (stage offsets in the series' range) and at
/// 50 Hz (large offsets: some steps fall back to the plain step), over 0.5 s (states
/// still O(1)) and 10 s: the same outcome (upright or not, steps run) for every run, and
/// final states — of the fallen runs the first sample past the bound — within 1e-11.
/// Per step the two kernels differ by a few roundings of θ̈ (stage sines within
/// 2 ulp + 6·10⁻¹⁷, prescaled constants), ~1e-15 of the state; the largest difference
/// seen is 2e-13, and 1e-11 leaves that growth a factor 50 while an O(h²) error in a
/// stage formula (≥ 1e-6 per step) stays far above it.
#[test]
fn anchored_lane_kernel_agrees_with_the_libm_lanes() {
    use pendulab_sim::fast::{AnchoredSinCos, LaneOptions, LibmSinCos, run_feedback_lanes};
    let plant = CartPendulum::book();
    let k = cdip_lqr_gain(&plant);
    let gain = [k[(0, 0)], k[(0, 1)], k[(0, 2)], k[(0, 3)]];
    let mut x0s = Vec::new();
    for i in 0..6 {
        for j in 0..6 {
            let th = -1.2 + 2.4 * i as f64 / 5.0;
            let w = -3.0 + 6.0 * j as f64 / 5.0;
            x0s.push([0.0, th, 0.0, w]);
        }
    }
    for (ts, t_final) in [(1e-3, 0.5), (1e-3, 10.0), (0.02, 0.5), (0.02, 10.0)] {
        let options = LaneOptions {
            ts,
            t_final,
            substeps: 1,
            stay_within: Some((1, std::f64::consts::FRAC_PI_2)),
        };
        let a =
            run_feedback_lanes::<_, AnchoredSinCos, 4, 8>(&plant, &gain, &options, &x0s).unwrap();
        let b = run_feedback_lanes::<_, LibmSinCos, 4, 8>(&plant, &gain, &options, &x0s).unwrap();
        let held = a.iter().filter(|o| o.held).count();
        assert!(held > 0 && held < a.len(), "grid has both outcomes: {held}");
        let mut worst = 0.0f64;
        for (ra, rb) in a.iter().zip(&b) {
            assert_eq!((ra.held, ra.steps), (rb.held, rb.steps), "ts = {ts}");
            for i in 0..4 {
                worst = worst.max((ra.final_state[i] - rb.final_state[i]).abs());
            }
        }
        eprintln!("ts = {ts}, {t_final} s: largest final-state difference {worst:e}");
        assert!(worst < 1e-11, "ts = {ts}, {t_final} s: {worst:e}");
    }
}

/// Ten seconds of 20 ms RK4 steps (the environment's step) from a large swing of the
/// hanging, damped pendulum under a varying voltage: the libm and polynomial plants agree
/// to 1e-11 (per-step differences are ~1e-16 relative; the stable hanging motion keeps
/// their sum far below this tolerance, which allows a 10⁴-fold growth).
#[test]
fn polynomial_trig_trajectories_stay_close_to_libm() {
    let libm = CartPendulum::book();
    let poly = FastCart::new(CartPendulum::book(), Trig::Polynomial);
    let mut xa = [0.0, std::f64::consts::PI - 1.0, 0.0, 0.0];
    let mut xb = xa;
    for k in 0..500 {
        let t = k as f64 * 0.02;
        let v = 2.0 * (3.0 * t).sin();
        rk4_step(&libm, t, &mut xa, &[v], 0.02);
        rk4_step(&poly, t, &mut xb, &[v], 0.02);
    }
    for i in 0..4 {
        assert!((xa[i] - xb[i]).abs() < 1e-11, "state {i}: {xa:?} vs {xb:?}");
    }
}
