//! The series sines and cosines of `Trig::Anchored` against libm's `f64::sin_cos`, the
//! independent reference: `fast::sin_cos_shifted` and `sin_cos_offset` (sine and cosine of
//! `x` from those of a nearby anchor `a`), `sin_cos_small` and `sin_cos_near_zero` (series
//! about zero), and `rotate_small` (a pair rotated by a small angle, also against a
//! double-double reference). The bound of the anchored shifts is 2 ulp + 6·10⁻¹⁷: libm's own
//! error on the anchor's sine and cosine (< 1 ulp each), the truncated series (< 3·10⁻¹⁷ for
//! `|x − a| ≤ 1/32`) and the roundings of the correction term (magnitude ≤ 1/32, a few times
//! 2⁻⁵³/32) plus half an ulp for the final addition (see the function's docs); the series
//! about zero and the small rotation have the tighter bounds derived in their docs.

use pendulab_sim::fast::{Fused, MulAdd, Separate};
use pendulab_sim::fast::{
    NEAR_ZERO_LIMIT, ROTATE_LIMIT, SHIFT_LIMIT, rotate_small, sin_cos_near_zero, sin_cos_offset,
    sin_cos_shifted, sin_cos_small,
};
use rand::{Rng, SeedableRng};

/// The spacing of doubles at `v` (ulp), for finite non-zero `v`; the smallest normal spacing
/// at zero.
fn ulp(v: f64) -> f64 {
    let a = v.abs();
    if a == 0.0 {
        return f64::MIN_POSITIVE;
    }
    f64::from_bits(a.to_bits() + 1) - a
}

fn check(x: f64, a: f64, worst: &mut f64) {
    let (s, c) = a.sin_cos();
    let (sx, cx) = sin_cos_shifted(x, a, s, c);
    let (rs, rc) = x.sin_cos();
    for (got, want, what) in [(sx, rs, "sin"), (cx, rc, "cos")] {
        let bound = 2.0 * ulp(want) + 6e-17;
        let err = (got - want).abs();
        assert!(
            err <= bound,
            "{what}({x:e}) from anchor {a:e}: {got:e} vs libm {want:e}, error {err:e} > {bound:e}"
        );
        *worst = worst.max(err / bound);
    }
}

#[test]
fn shifted_sine_and_cosine_are_within_the_documented_bound_of_libm() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2026);
    let mut worst = 0.0f64;
    for _ in 0..2_000_000 {
        // Anchors over several periods (and small ones, where sin is tiny), shifts up to the
        // limit (and tiny ones); x = a + d rounded, as a stage angle is formed.
        let a: f64 = match rng.random_range(0..3) {
            0 => rng.random_range(-20.0..20.0),
            1 => rng.random_range(-1e-3..1e-3),
            _ => rng.random_range(-4.0..4.0) * std::f64::consts::FRAC_PI_2,
        };
        let d: f64 = if rng.random_bool(0.5) {
            rng.random_range(-SHIFT_LIMIT..=SHIFT_LIMIT)
        } else {
            rng.random_range(-1e-4..1e-4)
        };
        check(a + d, a, &mut worst);
    }
    // Near the zeros of sine and cosine (where the result is tiny and the absolute term rules),
    // and at the multiples of π/4.
    for k in -40..=40 {
        let z = k as f64 * std::f64::consts::FRAC_PI_4;
        for j in -50..=50 {
            let d = j as f64 * (SHIFT_LIMIT / 50.0);
            check(z, z - d, &mut worst);
            check(z + d, z, &mut worst);
        }
    }
    eprintln!("worst error / bound: {worst}");
    // The bound is not vacuous: the worst case uses a sizeable part of it.
    assert!(worst > 0.05, "worst error / bound = {worst}");
}

/// The series about the exact anchor 0 (the step-start angle of `Trig::Anchored` near the
/// upright): the same bound against libm, which then only carries the truncation and the
/// roundings of the series.
#[test]
fn small_angle_sine_and_cosine_are_within_the_documented_bound_of_libm() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut worst = 0.0f64;
    let mut check = |x: f64| {
        let (s, c) = sin_cos_small(x);
        let (rs, rc) = x.sin_cos();
        for (got, want) in [(s, rs), (c, rc)] {
            let bound = 2.0 * ulp(want) + 6e-17;
            let err = (got - want).abs();
            assert!(err <= bound, "x = {x:e}: {got:e} vs libm {want:e}");
            worst = worst.max(err / bound);
        }
    };
    for _ in 0..1_000_000 {
        check(rng.random_range(-SHIFT_LIMIT..=SHIFT_LIMIT));
        check(rng.random_range(-1e-6..1e-6));
    }
    for x in [0.0, -0.0, 1e-300, -5e-324, SHIFT_LIMIT, -SHIFT_LIMIT] {
        check(x);
    }
    // Exact where the series is: sin 0 = 0, cos 0 = 1.
    assert_eq!(sin_cos_small(0.0), (0.0, 1.0));
    assert!(worst > 0.01, "worst error / bound = {worst}");
    // Beyond the range and for NaN: libm itself.
    for x in [SHIFT_LIMIT * 1.01, -2.0, 100.0] {
        assert_eq!(sin_cos_small(x), x.sin_cos());
    }
    assert!(sin_cos_small(f64::NAN).0.is_nan());
}

#[test]
fn beyond_the_limit_and_for_non_finite_input_it_is_libm() {
    let a = 0.7f64;
    let (s, c) = a.sin_cos();
    for x in [a + 2.0 * SHIFT_LIMIT, a - 0.5, 12.0, -3.0] {
        let got = sin_cos_shifted(x, a, s, c);
        let want = x.sin_cos();
        assert_eq!(
            (got.0.to_bits(), got.1.to_bits()),
            (want.0.to_bits(), want.1.to_bits())
        );
    }
    let (sn, cn) = sin_cos_shifted(f64::NAN, a, s, c);
    assert!(sn.is_nan() && cn.is_nan());
    let (si, ci) = sin_cos_shifted(f64::INFINITY, a, s, c);
    assert!(si.is_nan() && ci.is_nan());
    // A zero shift returns the anchor's values.
    assert_eq!(sin_cos_shifted(a, a, s, c), (s, c));
}

/// `sin_cos_offset(a, d, ·)` is the sine and cosine of the exact sum `a + d`. The reference
/// is libm at the rounded sum `x = fl(a + d)` corrected to first order by the sum's exact
/// rounding error `r = (a + d) − x` (Knuth's TwoSum): `sin(a + d) = sin x + r·cos x` up to
/// `r²/2 < 10⁻³⁰`. Same bound as `sin_cos_shifted` (2 ulp + 6·10⁻¹⁷), over both series
/// (`|d| ≤ 2⁻⁸` and up to the limit) and anchors over several periods.
#[test]
fn offset_sine_and_cosine_are_those_of_the_exact_sum() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2027);
    let mut worst = 0.0f64;
    let mut uncorrected_worst = 0.0f64;
    for _ in 0..2_000_000 {
        let a: f64 = match rng.random_range(0..3) {
            0 => rng.random_range(-20.0..20.0),
            1 => rng.random_range(-1e-3..1e-3),
            _ => rng.random_range(-4.0..4.0) * std::f64::consts::FRAC_PI_2,
        };
        let d: f64 = match rng.random_range(0..3) {
            0 => rng.random_range(-SHIFT_LIMIT..=SHIFT_LIMIT),
            1 => rng.random_range(-1.0 / 256.0..=1.0 / 256.0),
            _ => rng.random_range(-1e-4..1e-4),
        };
        let (s, c) = a.sin_cos();
        let (so, co) = sin_cos_offset(a, d, s, c);
        // TwoSum: x + r = a + d exactly.
        let x = a + d;
        let bv = x - a;
        let r = (a - (x - bv)) + (d - bv);
        let (sx, cx) = x.sin_cos();
        let (rs, rc) = (sx + r * cx, cx - r * sx);
        for (got, want, plain) in [(so, rs, sx), (co, rc, cx)] {
            let bound = 2.0 * ulp(want) + 6e-17;
            let err = (got - want).abs();
            assert!(
                err <= bound,
                "offset {d:e} from {a:e}: {got:e} vs {want:e}, error {err:e} > {bound:e}"
            );
            worst = worst.max(err / bound);
            uncorrected_worst = uncorrected_worst.max((got - plain).abs() / bound);
        }
    }
    eprintln!("worst error / bound: {worst}; against libm at fl(a + d): {uncorrected_worst}");
    assert!(worst > 0.05, "worst error / bound = {worst}");
    // Beyond the limit and for NaN: libm at a + d; a zero offset returns the anchor's values.
    let a = 0.7f64;
    let (s, c) = a.sin_cos();
    for d in [2.0 * SHIFT_LIMIT, -0.5, 3.0] {
        assert_eq!(sin_cos_offset(a, d, s, c), (a + d).sin_cos());
    }
    assert!(sin_cos_offset(a, f64::NAN, s, c).0.is_nan());
    assert_eq!(sin_cos_offset(a, 0.0, s, c), (s, c));
}

/// The lane form `sin_cos_offset_lanes`: every lane against the sine and cosine of the exact
/// sum (the reference of `offset_sine_and_cosine_are_those_of_the_exact_sum`), same bound;
/// `None` as soon as one lane's offset is beyond the limit or NaN.
#[test]
fn lane_offsets_are_those_of_the_exact_sum_and_refuse_out_of_range() {
    use pendulab_sim::fast::sin_cos_offset_lanes;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2028);
    let mut worst = 0.0f64;
    for _ in 0..100_000 {
        let a: [f64; 8] = std::array::from_fn(|_| rng.random_range(-20.0..20.0));
        let d: [f64; 8] = std::array::from_fn(|_| {
            if rng.random_bool(0.5) {
                rng.random_range(-SHIFT_LIMIT..=SHIFT_LIMIT)
            } else {
                rng.random_range(-1.0 / 256.0..=1.0 / 256.0)
            }
        });
        let s: [f64; 8] = std::array::from_fn(|l| a[l].sin());
        let c: [f64; 8] = std::array::from_fn(|l| a[l].cos());
        let (so, co) = sin_cos_offset_lanes(&d, &s, &c).expect("all offsets in range");
        for l in 0..8 {
            let x = a[l] + d[l];
            let bv = x - a[l];
            let r = (a[l] - (x - bv)) + (d[l] - bv);
            let (sx, cx) = x.sin_cos();
            for (got, want) in [(so[l], sx + r * cx), (co[l], cx - r * sx)] {
                let bound = 2.0 * ulp(want) + 6e-17;
                let err = (got - want).abs();
                assert!(err <= bound, "lane {l}: offset {:e} from {:e}", d[l], a[l]);
                worst = worst.max(err / bound);
            }
        }
    }
    assert!(worst > 0.05, "worst error / bound = {worst}");
    let (s, c) = ([0.3f64; 4], [0.9f64; 4]);
    assert!(sin_cos_offset_lanes(&[0.0, 0.01, -0.02, SHIFT_LIMIT], &s, &c).is_some());
    assert!(sin_cos_offset_lanes(&[0.0, 0.01, -0.02, 1.01 * SHIFT_LIMIT], &s, &c).is_none());
    assert!(sin_cos_offset_lanes(&[f64::NAN, 0.0, 0.0, 0.0], &s, &c).is_none());
}

/// `sin_cos_near_zero` against libm's `f64::sin_cos` at the same argument, with either
/// multiply–add: within its documented 1.5 ulp + 2.5·10⁻¹⁷ (½ ulp + 2.4·10⁻¹⁷ of the exact
/// values, libm within 1 ulp) in every tier — random points per tier, tiny ones, and the tier
/// limits with their neighbours; libm itself beyond 1/4 and for NaN. With `Separate` the
/// first two tiers are `sin_cos_small` bit for bit. Not vacuous: the worst error uses a
/// sizeable part of the bound in each tier, and the same formulas without their last term
/// (`x⁵`, `x⁷`, `x¹¹` of the sine) break it on these points.
#[test]
fn near_zero_sine_and_cosine_are_within_the_documented_bound_of_libm() {
    fn run<F: MulAdd>() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2029);
        let limits = [1.0 / 256.0, SHIFT_LIMIT, NEAR_ZERO_LIMIT];
        let mut worst = [0.0f64; 3];
        let mut mutant_worst = [0.0f64; 3];
        let mut points = Vec::new();
        for (tier, &lim) in limits.iter().enumerate() {
            let below = if tier == 0 { 0.0 } else { limits[tier - 1] };
            for _ in 0..300_000 {
                let m: f64 = rng.random_range(below..=lim);
                points.push(if rng.random_bool(0.5) { m } else { -m });
            }
            for v in [lim, f64::from_bits(lim.to_bits() - 1)] {
                points.extend([v, -v]);
            }
        }
        for _ in 0..10_000 {
            points.push(rng.random_range(-1e-6..1e-6));
        }
        points.extend([0.0, -0.0, 1e-300, -5e-324]);
        for x in points {
            let (s, c) = sin_cos_near_zero::<F>(x);
            let (rs, rc) = x.sin_cos();
            let m = x.abs();
            let tier = limits.iter().position(|&l| m <= l).unwrap();
            for (got, want) in [(s, rs), (c, rc)] {
                let bound = 1.5 * ulp(want) + 2.5e-17;
                let err = (got - want).abs();
                assert!(err <= bound, "x = {x:e}: {got:e} vs libm {want:e}");
                worst[tier] = worst[tier].max(err / bound);
            }
            // The sine without its last term in each tier (x⁵/5!, x⁷/7!, x¹¹/11!).
            let z = x * x;
            let dropped = [
                x - x * z / 6.0,
                x + x * z * (-1.0 / 6.0 + z / 120.0),
                x + x * z * (-1.0 / 6.0 + z * (1.0 / 120.0 + z * (-1.0 / 5040.0 + z / 362_880.0))),
            ][tier];
            let bound = 1.5 * ulp(rs) + 2.5e-17;
            mutant_worst[tier] = mutant_worst[tier].max((dropped - rs).abs() / bound);
            if F::PATH == pendulab_sim::fast::MulAddPath::Separate && m <= SHIFT_LIMIT {
                assert_eq!((s, c), sin_cos_small(x), "x = {x:e}");
            }
        }
        eprintln!("{:?}: worst error / bound per tier {worst:?}", F::PATH);
        assert!(worst.iter().all(|&w| w > 0.1), "{worst:?}");
        assert!(mutant_worst.iter().all(|&w| w > 1.0), "{mutant_worst:?}");
        for x in [NEAR_ZERO_LIMIT * 1.0001, -0.3, 2.0, -100.0] {
            assert_eq!(sin_cos_near_zero::<F>(x), x.sin_cos());
        }
        assert!(sin_cos_near_zero::<F>(f64::NAN).0.is_nan());
        assert_eq!(sin_cos_near_zero::<F>(0.0), (0.0, 1.0));
    }
    run::<Fused>();
    run::<Separate>();
}

/// `p·cos e + q·sin e + a` for a double-double reference: `cos e − 1 = −2 sin²(e/2)` and
/// `sin e` from libm (relative errors of an ulp, so absolute ones below `10⁻²⁴·|p|` and
/// `7·10⁻²¹·|q|` for `|e| ≤ 2⁻¹⁴`), `q·sin e` split exactly by a fused multiply–add (Dekker's
/// TwoProduct) and the sums by Knuth's TwoSum. Returns `(hi, lo)`.
fn rotation_reference(p: f64, q: f64, e: f64, a: f64) -> (f64, f64) {
    let two_sum = |x: f64, y: f64| {
        let s = x + y;
        let b = s - x;
        (s, (x - (s - b)) + (y - b))
    };
    let half = (0.5 * e).sin();
    let cm1 = -2.0 * half * half;
    let se = e.sin();
    let qs = q * se;
    let qs_lo = q.mul_add(se, -qs);
    let (h1, l1) = two_sum(a, p);
    let (h2, l2) = two_sum(h1, qs);
    let lo = ((l1 + l2) + qs_lo) + p * cm1;
    two_sum(h2, lo)
}

/// `rotate_small` against the double-double rotation of the same `p, q, a` (the pairs of a
/// sine and cosine, and the larger pairs of the cart's accelerations, `|p|, |q| ≤ 60`), with
/// either multiply–add: within its documented 1.5 ulp + ½ ulp(fl(a + p)) +
/// 6·10⁻¹⁹·(|p| + |q|) for `|e| ≤ 2⁻¹⁴`. Then the stage-sine view against libm at the
/// rounded angle `x = fl(θ + e)` corrected by the sum's exact rounding error (TwoSum, as
/// `offset_sine_and_cosine_are_those_of_the_exact_sum`): with `p = sin θ`, `q = cos θ` from
/// libm (1 ulp each) the rotation's bound grows by `ulp(p) + 2⁻¹⁴·ulp(q)` and libm's ulp at
/// `x`. Not vacuous: the worst errors use a sizeable part of the bounds, and the formula
/// without its `e³` term breaks both.
#[test]
fn small_rotation_is_within_its_bound_of_the_exact_rotation() {
    fn run<F: MulAdd>() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2030);
        let (mut worst, mut worst_libm, mut mutant, mut mutant_libm) =
            (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for i in 0..1_000_000 {
            let e: f64 = match i % 3 {
                0 => rng.random_range(-ROTATE_LIMIT..=ROTATE_LIMIT),
                1 => rng.random_range(-1e-5..1e-5),
                _ => {
                    rng.random_range(0.9 * ROTATE_LIMIT..=ROTATE_LIMIT)
                        * if rng.random_bool(0.5) { 1.0 } else { -1.0 }
                }
            };
            let theta: f64 = rng.random_range(-20.0..20.0);
            let (s, c) = theta.sin_cos();
            let (p, q, a) = if i % 2 == 0 {
                (s, c, 0.0)
            } else {
                (
                    rng.random_range(-60.0..60.0),
                    rng.random_range(-60.0..60.0),
                    rng.random_range(-1.0..1.0),
                )
            };
            let got = rotate_small::<F>(p, q, e, a);
            let (hi, lo) = rotation_reference(p, q, e, a);
            let sum_ulp = if a == 0.0 { 0.0 } else { 0.5 * ulp(a + p) };
            let bound = 1.5 * ulp(got) + sum_ulp + 6e-19 * (p.abs() + q.abs());
            let err = ((got - hi) - lo).abs();
            assert!(
                err <= bound,
                "p = {p:e}, q = {q:e}, e = {e:e}, a = {a:e}: {got:e} vs {hi:e}"
            );
            worst = worst.max(err / bound);
            let cut = F::mul_add(e * e, -0.5 * p, F::mul_add(e, q, a + p));
            mutant = mutant.max(((cut - hi) - lo).abs() / bound);
            if a == 0.0 {
                // sin(θ + e) against libm at x = fl(θ + e), corrected by r = (θ + e) − x.
                let x = theta + e;
                let bv = x - theta;
                let r = (theta - (x - bv)) + (e - bv);
                let (sx, cx) = x.sin_cos();
                let want = sx + r * cx;
                let bound = 2.5 * ulp(want) + ulp(p) + ulp(q) / 16384.0 + 1.2e-18;
                let err = (got - want).abs();
                assert!(
                    err <= bound,
                    "θ = {theta:e}, e = {e:e}: {got:e} vs {want:e}"
                );
                worst_libm = worst_libm.max(err / bound);
                mutant_libm = mutant_libm.max((cut - want).abs() / bound);
            }
        }
        eprintln!(
            "{:?}: worst error / bound {worst}, against libm {worst_libm}",
            F::PATH
        );
        assert!(worst > 0.1 && worst_libm > 0.1, "{worst} {worst_libm}");
        assert!(mutant > 1.0 && mutant_libm > 1.0, "{mutant} {mutant_libm}");
        // A zero angle returns the first-order sum itself.
        assert_eq!(rotate_small::<F>(0.3, 0.9, 0.0, 0.0), 0.3);
        assert_eq!(rotate_small::<F>(0.3, 0.9, 0.0, -0.1), -0.1 + 0.3);
    }
    run::<Fused>();
    run::<Separate>();
}
