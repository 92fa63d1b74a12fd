//! Reduction of unstable systems: `stabsep`'s additive decomposition, `hsvd`/`balreal`/`balred`
//! with unstable poles (MATLAB's behaviour), checked by defining properties on systems built as
//! a known stable part plus a known unstable part (modal blocks with chosen poles, summed and
//! hidden by a random similarity): the frequency response is reproduced, the parts carry exactly
//! the chosen poles, the Hankel singular values are those of the known stable part (a
//! realisation invariant, computed on the separately built part and by `√λ(W_c W_o)`), the
//! unstable poles survive `balred`, and Glover's bound `σ_{r+1} ≤ ‖G − G_r‖∞ ≤ 2 Σ_{i>r} σᵢ`
//! holds (H∞ norm by `hinf_norm` and by a dense frequency sweep).

use pendulab_lti::analysis::{GramianKind, gramian};
use pendulab_lti::domain::{Continuous, Discrete, TimeDomain};
use pendulab_lti::frequency_response::{freqresp, logspace};
use pendulab_lti::interconnect::parallel;
use pendulab_lti::linalg::CMat;
use pendulab_lti::norms::hinf_norm;
use pendulab_lti::random::SplitMix64;
use pendulab_lti::reduction::{BalredMethod, balreal, balred, hsvd, stabsep};
use pendulab_lti::{Complex64, LtiError, Mat, StateSpace};

/// A pole specification: `(re, 0)` a real pole, `(re, im)` with `im > 0` the pair `re ± im j`.
type Pole = (f64, f64);

/// Block-diagonal real modal matrix with the given poles (`[[a, b], [−b, a]]` for a pair).
fn modal(poles: &[Pole]) -> Mat {
    let n: usize = poles.iter().map(|p| if p.1 > 0.0 { 2 } else { 1 }).sum();
    let mut a = Mat::zeros(n, n);
    let mut k = 0;
    for &(re, im) in poles {
        a[(k, k)] = re;
        if im > 0.0 {
            a[(k + 1, k + 1)] = re;
            a[(k, k + 1)] = im;
            a[(k + 1, k)] = -im;
            k += 2;
        } else {
            k += 1;
        }
    }
    a
}

/// Every pole of the specification as complex numbers (pairs expanded).
fn expand(poles: &[Pole]) -> Vec<Complex64> {
    let mut out = Vec::new();
    for &(re, im) in poles {
        out.push(Complex64::new(re, im));
        if im > 0.0 {
            out.push(Complex64::new(re, -im));
        }
    }
    out
}

/// `got` and `want` are the same multiset to `tol` relative to `max(1, |λ|)`.
fn same_poles(got: &[Complex64], want: &[Complex64], tol: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?} vs {want:?}");
    let mut used = vec![false; got.len()];
    for w in want {
        let (j, d) = got
            .iter()
            .enumerate()
            .filter(|(j, _)| !used[*j])
            .map(|(j, g)| (j, (g - w).norm()))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        assert!(
            d <= tol * w.norm().max(1.0),
            "{what}: pole {w} missing (nearest at {d:e}); got {got:?}"
        );
        used[j] = true;
    }
}

/// A test case: `g = T⁻¹ (g_s ⊕ g_u) T` with the known parts.
struct Case<D: TimeDomain> {
    g: StateSpace<D>,
    g_s: StateSpace<D>,
    stable: Vec<Complex64>,
    unstable: Vec<Complex64>,
}

fn case<D: TimeDomain>(
    stable: &[Pole],
    unstable: &[Pole],
    (ny, nu): (usize, usize),
    domain: D,
    seed: u64,
) -> Case<D> {
    let mut rng = SplitMix64::new(seed);
    let a1 = modal(stable);
    let a2 = modal(unstable);
    let (n1, n2) = (a1.nrows(), a2.nrows());
    let g_s = StateSpace::new(
        a1,
        rng.matrix(n1, nu),
        rng.matrix(ny, n1),
        rng.matrix(ny, nu),
        domain,
    )
    .unwrap();
    let g_u = StateSpace::new(
        a2,
        rng.matrix(n2, nu),
        rng.matrix(ny, n2),
        Mat::zeros(ny, nu),
        domain,
    )
    .unwrap();
    let sum = parallel(&g_s, &g_u).unwrap();
    let n = n1 + n2;
    // A well-conditioned random similarity mixing the two parts.
    let t = Mat::identity(n, n) + rng.matrix(n, n) * 0.3;
    let ti = t.clone().try_inverse().unwrap();
    let g = StateSpace::new(
        &ti * sum.a() * &t,
        &ti * sum.b(),
        sum.c() * &t,
        sum.d().clone(),
        domain,
    )
    .unwrap();
    Case {
        g,
        g_s,
        stable: expand(stable),
        unstable: expand(unstable),
    }
}

/// Frequencies for a domain: 0.01–100 rad/s, or up to just below Nyquist.
fn grid<D: TimeDomain>(domain: D, n: usize) -> Vec<f64> {
    match domain.sample_time() {
        None => logspace(-2.0, 2.0, n),
        Some(ts) => logspace(-2.0, (0.999 * std::f64::consts::PI / ts).log10(), n),
    }
}

fn response<D: TimeDomain>(sys: &StateSpace<D>, w: &[f64]) -> Vec<CMat> {
    freqresp(sys, w).unwrap().response
}

/// The σ_max of a complex matrix through the eigenvalues of `MᴴM` (small matrices).
fn sigma_max(m: &CMat) -> f64 {
    let h = m.adjoint() * m;
    h.symmetric_eigenvalues()
        .iter()
        .fold(0.0f64, |acc, &v| acc.max(v))
        .sqrt()
}

fn continuous_cases() -> Vec<Case<Continuous>> {
    vec![
        case(
            &[(-1.0, 0.0), (-3.0, 0.0)],
            &[(0.5, 0.0)],
            (1, 1),
            Continuous,
            1,
        ),
        case(
            &[(-0.4, 2.0), (-2.0, 0.0), (-7.0, 0.0), (-1.2, 5.0)],
            &[(1.5, 0.0), (0.3, 1.0)],
            (2, 2),
            Continuous,
            2,
        ),
        case(
            &[
                (-0.2, 0.0),
                (-0.9, 0.0),
                (-4.0, 3.0),
                (-12.0, 0.0),
                (-30.0, 0.0),
            ],
            &[(2.0, 0.0), (0.7, 0.0), (0.1, 4.0)],
            (1, 2),
            Continuous,
            3,
        ),
    ]
}

fn discrete_cases() -> Vec<Case<Discrete>> {
    let d = Discrete::new(0.05).unwrap();
    vec![
        case(&[(0.5, 0.0), (-0.3, 0.0)], &[(1.4, 0.0)], (1, 1), d, 11),
        case(
            &[(0.6, 0.5), (0.2, 0.0), (-0.7, 0.0), (0.9, 0.1)],
            &[(1.2, 0.0), (0.8, 0.9)],
            (2, 2),
            d,
            12,
        ),
    ]
}

/// Runs `check(case, index)` on every continuous case (indices 0…) and discrete case (10…).
macro_rules! each_case {
    ($check:ident) => {
        for (k, c) in continuous_cases().iter().enumerate() {
            $check(c, k);
        }
        for (k, c) in discrete_cases().iter().enumerate() {
            $check(c, 10 + k);
        }
    };
}

fn check_stabsep<D: TimeDomain>(c: &Case<D>, k: usize) {
    let (gs, gu) = stabsep(&c.g).unwrap();
    same_poles(&gs.poles().unwrap(), &c.stable, 1e-10, "stable part");
    same_poles(&gu.poles().unwrap(), &c.unstable, 1e-10, "unstable part");
    assert!(gu.d().iter().all(|&v| v == 0.0), "G_u is strictly proper");
    assert_eq!(gs.d(), c.g.d(), "D goes to the stable part");
    let w = grid(c.g.domain(), 25);
    let (g, s, u, s0) = (
        response(&c.g, &w),
        response(&gs, &w),
        response(&gu, &w),
        response(&c.g_s, &w),
    );
    for i in 0..w.len() {
        let scale = g[i].norm().max(1.0);
        let err = (&s[i] + &u[i] - &g[i]).norm();
        assert!(err <= 1e-10 * scale, "case {k}, ω = {}: {err:e}", w[i]);
        // The additive decomposition is unique (G_u strictly proper): G_s is the built part.
        let err = (&s[i] - &s0[i]).norm();
        assert!(err <= 1e-10 * scale, "case {k}, ω = {}: G_s {err:e}", w[i]);
    }
}

#[test]
fn stabsep_reproduces_the_response_and_splits_the_poles() {
    each_case!(check_stabsep);
}

#[test]
fn stabsep_of_a_stable_or_antistable_system_has_an_empty_part() {
    let c = case(&[(-1.0, 0.0), (-2.0, 1.0)], &[], (1, 1), Continuous, 5);
    let (gs, gu) = stabsep(&c.g).unwrap();
    assert_eq!((gs.nx(), gu.nx()), (3, 0));
    let c = case(&[], &[(1.0, 0.0), (2.0, 1.0)], (1, 1), Continuous, 6);
    let (gs, gu) = stabsep(&c.g).unwrap();
    assert_eq!((gs.nx(), gu.nx()), (0, 3));
    assert_eq!(hsvd(&c.g).unwrap(), vec![f64::INFINITY; 3]);
    assert_eq!(
        balred(&c.g, 3, BalredMethod::Truncate).unwrap().system.nx(),
        3
    );
}

/// `√λ(W_c W_o)` of a stable system, descending (a second algorithm for the Hankel singular
/// values: the eigenvalues of the Gramians' product rather than the square-root SVD).
fn hsv_by_gramian_product<D: TimeDomain>(sys: &StateSpace<D>) -> Vec<f64> {
    let wc = gramian(sys, GramianKind::Controllability).unwrap().x;
    let wo = gramian(sys, GramianKind::Observability).unwrap().x;
    let mut ev: Vec<f64> = (wc * wo)
        .complex_eigenvalues()
        .iter()
        .map(|l| l.re.max(0.0).sqrt())
        .collect();
    ev.sort_by(|a, b| b.total_cmp(a));
    ev
}

fn check_hsvd<D: TimeDomain>(c: &Case<D>, k: usize) {
    let hsv = hsvd(&c.g).unwrap();
    let nu = c.unstable.len();
    assert_eq!(hsv.len(), c.g.nx());
    assert!(
        hsv[..nu].iter().all(|v| v.is_infinite()),
        "case {k}: {hsv:?}"
    );
    let direct = hsvd(&c.g_s).unwrap();
    let product = hsv_by_gramian_product(&c.g_s);
    let s1 = direct[0];
    for ((got, d), p) in hsv[nu..].iter().zip(&direct).zip(&product) {
        assert!(
            (got - d).abs() <= 1e-9 * s1,
            "case {k}: {hsv:?} vs {direct:?}"
        );
        assert!(
            (got - p).abs() <= 1e-7 * s1,
            "case {k}: {hsv:?} vs {product:?}"
        );
    }
}

#[test]
fn hsvd_of_an_unstable_system_is_the_stable_parts_with_infinities() {
    each_case!(check_hsvd);
}

fn check_balred<D: TimeDomain>(c: &Case<D>, k: usize) {
    let nu = c.unstable.len();
    let ns = c.stable.len();
    let hsv_s = hsvd(&c.g_s).unwrap();
    let w = grid(c.g.domain(), 400);
    let g = response(&c.g, &w);
    for method in [BalredMethod::Truncate, BalredMethod::MatchDc] {
        for rs in 0..ns {
            let order = nu + rs;
            let red = balred(&c.g, order, method).unwrap();
            assert_eq!(red.system.nx(), order);
            // Every unstable pole survives, and the kept stable ones are stable.
            let (rs_part, ru_part) = stabsep(&red.system).unwrap();
            same_poles(&ru_part.poles().unwrap(), &c.unstable, 1e-10, "balred");
            assert_eq!(rs_part.nx(), rs);
            let bound = 2.0 * hsv_s[rs..].iter().sum::<f64>();
            assert!(
                (red.error_bound - bound).abs() <= 1e-9 * bound.max(hsv_s[0]),
                "case {k}"
            );
            // G − G_r = G_s − G_{r,s}: its H∞ norm lies between σ_{r+1} and the bound.
            let neg = StateSpace::new(
                rs_part.a().clone(),
                rs_part.b().clone(),
                -rs_part.c(),
                -rs_part.d(),
                rs_part.domain(),
            )
            .unwrap();
            let e = hinf_norm(&parallel(&c.g_s, &neg).unwrap(), 1e-8)
                .unwrap()
                .value;
            let what = format!("case {k}, {method:?}, order {order}: ‖G − G_r‖∞ = {e:e}");
            assert!(e <= bound * (1.0 + 1e-6) + 1e-12, "{what} > {bound:e}");
            assert!(
                e >= hsv_s[rs] * (1.0 - 1e-6),
                "{what} < σ = {:e}",
                hsv_s[rs]
            );
            // The same bound on the full systems' responses over a dense sweep.
            let gr = response(&red.system, &w);
            let sweep = g
                .iter()
                .zip(&gr)
                .map(|(a, b)| sigma_max(&(a - b)))
                .fold(0.0f64, f64::max);
            assert!(
                sweep <= bound * (1.0 + 1e-6) + 1e-10,
                "{what}: sweep {sweep:e}"
            );
        }
    }
}

#[test]
fn balred_keeps_the_unstable_poles_and_the_error_bound() {
    each_case!(check_balred);
}

/// `balreal`: unstable states first with infinite `hsv`, the stable block's Gramians equal
/// `diag(σ)`, the response and `T⁻¹ T = I` unchanged.
fn check_balreal<D: TimeDomain>(c: &Case<D>, k: usize) {
    let nu = c.unstable.len();
    let n = c.g.nx();
    let b = balreal(&c.g).unwrap();
    assert!(b.hsv[..nu].iter().all(|v| v.is_infinite()));
    let sys = &b.system;
    let ab = sys.a().view((nu, nu), (n - nu, n - nu)).clone_owned();
    assert!(
        sys.a()
            .view((nu, 0), (n - nu, nu))
            .iter()
            .all(|&v| v == 0.0)
    );
    assert!(
        sys.a()
            .view((0, nu), (nu, n - nu))
            .iter()
            .all(|&v| v == 0.0)
    );
    same_poles(
        &pendulab_lti::linalg::eigenvalues(&sys.a().view((0, 0), (nu, nu)).clone_owned()).unwrap(),
        &c.unstable,
        1e-10,
        "balreal unstable block",
    );
    let stable = StateSpace::new(
        ab,
        sys.b().rows(nu, n - nu).clone_owned(),
        sys.c().columns(nu, n - nu).clone_owned(),
        sys.d().clone(),
        sys.domain(),
    )
    .unwrap();
    let s1 = b.hsv[nu];
    for kind in [GramianKind::Controllability, GramianKind::Observability] {
        let wg = gramian(&stable, kind).unwrap().x;
        for i in 0..n - nu {
            for j in 0..n - nu {
                let want = if i == j { b.hsv[nu + i] } else { 0.0 };
                assert!(
                    (wg[(i, j)] - want).abs() <= 1e-9 * s1,
                    "case {k}, {kind:?} ({i},{j}): {} vs {want}",
                    wg[(i, j)]
                );
            }
        }
    }
    let eye = &b.t_inv * &b.t - Mat::identity(n, n);
    assert!(
        eye.norm() <= 1e-10 * b.t.norm() * b.t_inv.norm(),
        "case {k}"
    );
    // A = T Â T⁻¹ maps back.
    let back = &b.t * sys.a() * &b.t_inv - c.g.a();
    assert!(back.norm() <= 1e-9 * c.g.a().norm(), "case {k}");
    let w = grid(c.g.domain(), 20);
    for (x, y) in response(&c.g, &w).iter().zip(&response(sys, &w)) {
        assert!((x - y).norm() <= 1e-9 * x.norm().max(1.0), "case {k}");
    }
}

#[test]
fn balreal_of_an_unstable_system_balances_the_stable_part() {
    each_case!(check_balreal);
}

fn is_invalid(r: Result<impl std::fmt::Debug, LtiError>, needle: &str) {
    match r {
        Err(LtiError::InvalidArgument(m)) => assert!(m.contains(needle), "{m}"),
        other => panic!("expected InvalidArgument containing {needle:?}, got {other:?}"),
    }
}

#[test]
fn boundary_eigenvalues_and_too_small_orders_are_typed_errors() {
    // An integrator (s = 0) and an undamped pair (±2j) beside a stable and an unstable pole.
    let c = case(
        &[(-1.0, 0.0), (0.0, 0.0), (0.0, 2.0)],
        &[(1.0, 0.0)],
        (1, 1),
        Continuous,
        7,
    );
    is_invalid(stabsep(&c.g), "stability boundary");
    is_invalid(hsvd(&c.g), "stability boundary");
    is_invalid(
        balred(&c.g, 3, BalredMethod::Truncate),
        "stability boundary",
    );
    is_invalid(balreal(&c.g), "stability boundary");
    // The message names each boundary eigenvalue (±2j and 0).
    let Err(LtiError::InvalidArgument(m)) = stabsep(&c.g) else {
        unreachable!()
    };
    assert_eq!(m.matches("j").count(), 3, "{m}");
    // Discrete: z = −1 and the pair e^{±0.5j} on the unit circle.
    let d = Discrete::new(0.1).unwrap();
    let (cs, sn) = (0.5f64.cos(), 0.5f64.sin());
    let c = case(
        &[(0.5, 0.0), (-1.0, 0.0), (cs, sn)],
        &[(1.3, 0.0)],
        (1, 1),
        d,
        8,
    );
    is_invalid(stabsep(&c.g), "stability boundary");
    is_invalid(hsvd(&c.g), "stability boundary");
    // Three unstable states cannot be reduced to two.
    let c = &continuous_cases()[1];
    is_invalid(balred(&c.g, 2, BalredMethod::Truncate), "unstable states");
    is_invalid(balred(&c.g, 0, BalredMethod::MatchDc), "unstable states");
    assert_eq!(
        balred(&c.g, 3, BalredMethod::MatchDc).unwrap().system.nx(),
        3
    );
}
