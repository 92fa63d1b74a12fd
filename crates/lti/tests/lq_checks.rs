//! `lqr` answers only LQ problems (issue 21, item 4): indefinite weights are refused, a
//! Hamiltonian (symplectic) eigenvalue on or numerically near the stability boundary is "no
//! stabilising solution", an ill-conditioned large problem fails fast.
//!
//! References: closed forms derived beside each case; SciPy 1.17.1's verdicts on the same data
//! (`tools/reference/lq_checks_scipy.py`, fixture `lq_checks_scipy.json`).

use pendulab_lti::design::{LQ_WEIGHT_TOLERANCE, Lqr, lqe, lqr};
use pendulab_lti::equations::{RiccatiOptions, care};
use pendulab_lti::{Complex64, LtiError, Mat, StateSpace, TimeDomain};

fn m(r: usize, c: usize, v: &[f64]) -> Mat {
    Mat::from_row_slice(r, c, v)
}

fn cont(a: &Mat, b: &Mat) -> StateSpace<pendulab_lti::Continuous> {
    let (n, k) = (a.nrows(), b.ncols());
    StateSpace::continuous(a.clone(), b.clone(), Mat::zeros(0, n), Mat::zeros(0, k)).unwrap()
}

fn disc(a: &Mat, b: &Mat) -> StateSpace<pendulab_lti::Discrete> {
    let (n, k) = (a.nrows(), b.ncols());
    StateSpace::discrete(
        a.clone(),
        b.clone(),
        Mat::zeros(0, n),
        Mat::zeros(0, k),
        0.1,
    )
    .unwrap()
}

const EPS: f64 = f64::EPSILON;

fn fixture() -> serde_json::Value {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/lq_checks_scipy.json");
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn fx_mat(v: &serde_json::Value) -> Mat {
    let rows: Vec<Vec<f64>> = serde_json::from_value(v.clone()).unwrap();
    let (r, c) = (rows.len(), rows.first().map_or(0, |x| x.len()));
    Mat::from_fn(r, c, |i, j| rows[i][j])
}

/// The case's data (A, B, Q, R) and SciPy's verdict from the fixture.
fn case(name: &str) -> (Mat, Mat, Mat, Mat, serde_json::Value) {
    let fx = fixture();
    let e = fx["cases"][name].clone();
    assert!(e.is_object(), "fixture has no {name}");
    (
        fx_mat(&e["a"]),
        fx_mat(&e["b"]),
        fx_mat(&e["q"]),
        fx_mat(&e["r"]),
        e,
    )
}

/// a = −1, b = 1, r = 1, q = −1/2: the CARE −2x − x² − 1/2 = 0 has the roots
/// x = −1 ± √(1/2); the stabilising one (a − x < 0 ⇔ x > −1) is x* = −1 + √(1/2) < 0, with the
/// closed-loop pole −√(1/2) ≈ −0.707, slower than the open loop's −1 — the equation is solved,
/// but no cost is minimised: `care` returns x*, `lqr` refuses Q with its eigenvalue −1/2.
#[test]
fn lqr_refuses_an_indefinite_q_that_care_solves() {
    let (a, b, q, r) = (
        m(1, 1, &[-1.0]),
        m(1, 1, &[1.0]),
        m(1, 1, &[-0.5]),
        m(1, 1, &[1.0]),
    );
    let x_star = -1.0 + 0.5f64.sqrt();
    let sol = care(&a, &b, &q, &r, None, &RiccatiOptions::default()).unwrap();
    // A scalar root to a few ulps.
    assert!((sol.x[(0, 0)] - x_star).abs() <= 8.0 * EPS, "{}", sol.x);
    assert!((sol.closed_loop_poles[0].re + 0.5f64.sqrt()).abs() <= 8.0 * EPS);
    for e in [
        lqr(&cont(&a, &b), &q, &r, None).unwrap_err(),
        lqr(&disc(&m(1, 1, &[0.5]), &b), &q, &r, None).unwrap_err(),
    ] {
        match &e {
            LtiError::NotPositiveSemidefinite {
                what,
                min_eigenvalue,
                tolerance,
            } => {
                assert_eq!(what, "Q");
                assert_eq!(*min_eigenvalue, -0.5);
                // τ = 100·(n + m)… for Q alone: 100·1·ε·‖Q‖_F.
                assert_eq!(*tolerance, LQ_WEIGHT_TOLERANCE * EPS * 0.5);
            }
            other => panic!("expected NotPositiveSemidefinite, got {other:?}"),
        }
        assert!(e.to_string().contains("-5e-1"), "{e}");
    }
}

/// Q = 1 ⪰ 0 and R = 1 ≻ 0 separately, but with N = 2 the joint weight
/// W = [[1, 2], [2, 1]] has the eigenvalues 1 ± 2: −1 < 0, so xᵀQx + uᵀRu + 2xᵀNu is not a
/// cost (x = 1, u = −1 gives −2). Continuous and discrete refuse it naming −1.
#[test]
fn lqr_refuses_an_indefinite_joint_weight() {
    let (b, q, r, n) = (
        m(1, 1, &[1.0]),
        m(1, 1, &[1.0]),
        m(1, 1, &[1.0]),
        m(1, 1, &[2.0]),
    );
    let errors = [
        lqr(&cont(&m(1, 1, &[1.0]), &b), &q, &r, Some(&n)).unwrap_err(),
        lqr(&disc(&m(1, 1, &[1.5]), &b), &q, &r, Some(&n)).unwrap_err(),
    ];
    for e in errors {
        match e {
            LtiError::NotPositiveSemidefinite {
                what,
                min_eigenvalue,
                ..
            } => {
                assert_eq!(what, "[Q N; Nᵀ R]");
                // A 2×2 symmetric eigenvalue to a few ulps of ‖W‖.
                assert!(
                    (min_eigenvalue + 1.0).abs() <= 16.0 * EPS,
                    "{min_eigenvalue}"
                );
            }
            other => panic!("expected NotPositiveSemidefinite, got {other:?}"),
        }
    }
    // N = 1/2: eigenvalues 1 ± 1/2 > 0, an LQ problem; it solves.
    let ok = lqr(&cont(&m(1, 1, &[1.0]), &b), &q, &r, Some(&m(1, 1, &[0.5]))).unwrap();
    assert!(ok.closed_loop_poles[0].re < 0.0);
}

/// The tolerance τ = LQ_WEIGHT_TOLERANCE·k·ε·‖W‖_F separates rounding from indefiniteness:
/// Q = diag(1, −τ/2) is accepted, Q = diag(1, −2τ) refused; a rank-one CᵀC formed in floating
/// point (eigenvalues 0, 0 up to rounding) is accepted.
#[test]
fn the_semidefiniteness_tolerance_is_relative_to_the_weight() {
    let sys = cont(&m(2, 2, &[-1.0, 0.0, 0.0, -2.0]), &Mat::identity(2, 2));
    let r = Mat::identity(2, 2);
    for scale in [1.0, 1e-6, 1e6] {
        let tau = |d: f64| LQ_WEIGHT_TOLERANCE * 2.0 * EPS * (scale * scale + d * d).sqrt();
        let d_ok = -0.5 * tau(0.0);
        let q_ok = m(2, 2, &[scale, 0.0, 0.0, d_ok]);
        assert!(lqr(&sys, &q_ok, &r, None).is_ok(), "scale {scale}");
        let d_bad = -2.0 * tau(0.0);
        let q_bad = m(2, 2, &[scale, 0.0, 0.0, d_bad]);
        assert!(
            matches!(
                lqr(&sys, &q_bad, &r, None),
                Err(LtiError::NotPositiveSemidefinite { min_eigenvalue, .. }) if min_eigenvalue == d_bad
            ),
            "scale {scale}"
        );
    }
    let c = m(1, 3, &[0.1, 0.7, 0.3]);
    let q = c.transpose() * &c;
    let a = m(3, 3, &[-1.0, 1.0, 0.0, 0.0, -2.0, 1.0, 0.0, 0.0, -3.0]);
    assert!(
        lqr(
            &cont(&a, &Mat::identity(3, 3)),
            &q,
            &Mat::identity(3, 3),
            None
        )
        .is_ok()
    );
}

/// Kalman filter noise intensities are covariances: an indefinite Qn is refused by `lqe`.
#[test]
fn lqe_refuses_indefinite_noise_intensities() {
    let a = m(2, 2, &[0.0, 1.0, -1.0, -0.5]);
    let sys = StateSpace::continuous(
        a,
        m(2, 1, &[0.0, 1.0]),
        m(1, 2, &[1.0, 0.0]),
        Mat::zeros(1, 1),
    )
    .unwrap();
    let e = lqe(
        &sys,
        &Mat::identity(2, 2),
        &m(2, 2, &[1.0, 0.0, 0.0, -0.25]),
        &Mat::identity(1, 1),
        None,
    )
    .unwrap_err();
    assert!(
        matches!(&e, LtiError::NotPositiveSemidefinite { what, min_eigenvalue, .. }
            if what == "Qn" && *min_eigenvalue == -0.25),
        "{e:?}"
    );
}

/// The error names the boundary eigenvalue `target` (and its conjugate): for
/// `BoundaryEigenvalue` among its listed eigenvalues, for `NotDetectable` as the mode; the
/// message says "no stabilising solution".
fn assert_no_stabilising_solution(e: &LtiError, target: Complex64, tol: f64) {
    assert!(
        e.to_string().contains("no stabilising solution"),
        "message: {e}"
    );
    let near = |l: &Complex64| {
        (l.re - target.re).abs() <= tol && (l.im.abs() - target.im.abs()).abs() <= tol
    };
    match e {
        LtiError::BoundaryEigenvalue { eigenvalues, .. } => {
            assert!(eigenvalues.iter().any(near), "{eigenvalues:?}")
        }
        LtiError::NotDetectable { eigenvalue, .. } => assert!(near(eigenvalue), "{eigenvalue}"),
        other => panic!("expected no stabilising solution, got {other:?}"),
    }
}

/// A pair of fixture cases on and near the stability boundary: SciPy's verdicts are "not
/// stabilising" for `on` and "stabilising" for `near`; `lqr` on `system(A, B)` refuses `on`
/// (naming the boundary eigenvalue ±j within `tol`) and solves `near`. Returns `near`'s
/// solution, its weight `q = Q₁₁` and SciPy's `X` for it.
fn on_and_near_the_boundary<D: TimeDomain>(
    on: &str,
    near: &str,
    system: fn(&Mat, &Mat) -> StateSpace<D>,
    tol: f64,
) -> (Lqr, f64, Mat) {
    let (a, b, q, r, fx) = case(on);
    assert_eq!(fx["verdict"], "not stabilising");
    let e = lqr(&system(&a, &b), &q, &r, None).unwrap_err();
    assert_no_stabilising_solution(&e, Complex64::new(0.0, 1.0), tol);

    let (a, b, q, r, fx) = case(near);
    assert_eq!(fx["verdict"], "stabilising");
    let sol = lqr(&system(&a, &b), &q, &r, None).unwrap();
    (sol, q[(0, 0)], fx_mat(&fx["x"]))
}

/// Oscillator ẋ₁ = x₂, ẋ₂ = −x₁ + u with Q = 0, R = 1: the Hamiltonian
/// [[A, −BBᵀ], [−Q, −Aᵀ]] is block upper triangular, so its eigenvalues are those of A and of
/// −Aᵀ — ±j, each twice, on the imaginary axis: no stabilising solution. SciPy 1.17.1 returns
/// X = 0 with closed-loop poles ±j (fixture verdict "not stabilising").
#[test]
fn oscillator_unseen_by_q_has_no_stabilising_solution() {
    let (a, b, q, r, fx) = case("oscillator_q0");
    assert_eq!(fx["verdict"], "not stabilising");
    assert_eq!(q.norm(), 0.0); // the block structure of the closed form
    let e = lqr(&cont(&a, &b), &q, &r, None).unwrap_err();
    // The oscillator's eigenvalues ±j are exact in floating point ([[0, 1], [−1, 0]]).
    assert_no_stabilising_solution(&e, Complex64::new(0.0, 1.0), 1e-12);
}

/// The oscillator plus a stable state x₃' = −x₃ + u, rotated by the orthogonal T of the data,
/// Q = T diag(0, 0, 1) Tᵀ: Q does not see the oscillator, so ±j are again double Hamiltonian
/// eigenvalues on the axis (T only rounds them). SciPy 1.17.1 returns an X whose closed-loop
/// poles lie 1e-9 left of the axis, the "hair left of the axis" of the issue; `lqr` refuses.
#[test]
fn hidden_unobservable_oscillator_has_no_stabilising_solution() {
    let (a, b, q, r, fx) = case("hidden_oscillator");
    assert_eq!(fx["verdict"], "not stabilising");
    assert!(fx["min_margin"].as_f64().unwrap() < 1e-8);
    let e = lqr(&cont(&a, &b), &q, &r, None).unwrap_err();
    // T has 2-digit entries, so A and Q carry rounding of ≈ ε: the eigenvalues move by at
    // most O(sqrt(ε)) ≈ 1.5e-8 (a double eigenvalue); 1e-6 leaves room.
    assert_no_stabilising_solution(&e, Complex64::new(0.0, 1.0), 1e-6);
}

/// CAREX 2.5 at ε = 0 (indefinite Q, so `care`, not `lqr`): X = [[2, 1], [1, 1]] solves the
/// equation and leaves A − BK = [[0, −1], [1, 0]] with poles ±j — a double Hamiltonian
/// eigenvalue on the axis, which rounding splits to ±3·10⁻⁸ ± j. SciPy returns that split
/// X (poles −3.8·10⁻⁸ ± j); `care` refuses it as numerically on the axis.
#[test]
fn rounding_split_boundary_eigenvalue_is_refused() {
    let (a, b, q, r, fx) = case("carex_2_5_eps0");
    assert_eq!(fx["verdict"], "not stabilising");
    let e = care(&a, &b, &q, &r, None, &RiccatiOptions::default()).unwrap_err();
    // The split is O(sqrt(ε)·‖H‖) ≈ 1e-7 here; 1e-6 leaves a factor 10.
    assert_no_stabilising_solution(&e, Complex64::new(0.0, 1.0), 1e-6);
    if let LtiError::BoundaryEigenvalue {
        distance,
        tolerance,
        ..
    } = e
    {
        assert!(distance <= tolerance, "{distance:e} > {tolerance:e}");
    }
}

/// Q = diag(q, 0) observes the oscillator weakly. The closed-loop poles are the stable roots of
/// 1 + q·G(−s)G(s) = 0 with G(s) = 1/(s² + 1), i.e. (s² + 1)² + q = 0, s² = −1 ± j√q: at
/// q = 1e-30 they lie ≈ √q/2 = 5·10⁻¹⁶ from the axis — numerically on it, refused (SciPy's X
/// has relative residual 1); at q = 1e-6 at 5·10⁻⁴, a genuine solution, kept and equal to
/// SciPy's.
#[test]
fn weakly_observed_oscillator_near_and_on_the_axis() {
    let (sol, qq, xs) =
        on_and_near_the_boundary("oscillator_q1e-30", "oscillator_q1e-6", cont, 1e-6);
    for sign in [1.0, -1.0] {
        let s = (Complex64::new(-1.0, sign * qq.sqrt())).sqrt();
        let s = if s.re < 0.0 { s } else { -s };
        // Pole error ≈ κ(λ)·η·‖H‖ with κ ≈ 1/(2·5e-4) = 1e3: 1e-11 is generous.
        assert!(
            sol.closed_loop_poles
                .iter()
                .any(|p| (p - s).norm() <= 1e-11),
            "{s} not in {:?}",
            sol.closed_loop_poles
        );
    }
    // Against SciPy: κ_CARE ≈ ‖X‖/sep ≈ 1e3–1e4 times the backward errors (ours ≈ 1e-16,
    // SciPy's 1.5e-13): 1e-8 relative.
    let d = (&sol.riccati - &xs).norm() / xs.norm();
    assert!(d <= 1e-8, "{d:e}");
}

/// Discrete counterpart: the rotation A = [[0, 1], [−1, 0]] (eigenvalues ±j on the unit
/// circle), B = [0; 1], Q = 0, R = 1. The symplectic pencil [[A, 0], [−Q, I]] − z[[I, G],
/// [0, Aᵀ]] is block triangular with Q = 0: eigenvalues those of A and of A⁻ᵀ, ±j twice, on the
/// unit circle. SciPy returns X = 0 (poles ±j); `lqr` refuses. With Q = diag(q, 0),
/// q = 1e-6, the poles are the stable roots of (z² + 1)² + q z² = 0, i.e.
/// z = ±j(√(q + 4) − √q)/2 (|z| ≈ 1 − √q/2): kept and equal to SciPy's X.
#[test]
fn discrete_rotation_on_and_near_the_unit_circle() {
    let (sol, qq, xs) = on_and_near_the_boundary("rotation_q0", "rotation_q1e-6", disc, 1e-12);
    let mag = ((qq + 4.0).sqrt() - qq.sqrt()) / 2.0;
    for p in &sol.closed_loop_poles {
        // κ ≈ 1/(2·5e-4) again: 1e-11.
        assert!(
            p.re.abs() <= 1e-11 && (p.im.abs() - mag).abs() <= 1e-11,
            "{p}"
        );
    }
    let d = (&sol.riccati - &xs).norm() / xs.norm();
    assert!(d <= 1e-8, "{d:e}");
}

/// SplitMix64 entries uniform in [−1, 1) (`pendulab_lti::random`).
fn splitmix(r: usize, c: usize, seed: u64) -> Mat {
    pendulab_lti::random::SplitMix64::new(seed).matrix(r, c)
}

/// A random 100-state system (about half its modes unstable) driven through one input of
/// size 1e-8: the unstable modes are all but uncontrollable, and the stable-subspace basis
/// block U₁ is singular to working precision. Above `FAIL_FAST_MIN_STATES` states the solve
/// stops there with the estimated condition number (above 1/(n·ε), the limit it reports)
/// instead of trying the other method and diagnosing every mode (at n = 600 that took 187 s
/// before this exit and takes 5 s with it; no timing is asserted here).
#[test]
fn ill_conditioned_large_problem_fails_fast_with_its_condition_number() {
    let n = 100;
    assert!(n > pendulab_lti::equations::riccati::FAIL_FAST_MIN_STATES);
    let a = splitmix(n, n, 1);
    let b = splitmix(n, 1, 2) * 1e-8;
    let e = lqr(
        &cont(&a, &b),
        &Mat::identity(n, n),
        &Mat::identity(1, 1),
        None,
    )
    .unwrap_err();
    match &e {
        LtiError::IllConditioned {
            condition, limit, ..
        } => {
            assert_eq!(*limit, 1.0 / (n as f64 * EPS));
            assert!(condition > limit, "{condition:e} ≤ {limit:e}");
        }
        other => panic!("expected IllConditioned, got {other:?}"),
    }
    assert!(e.to_string().contains("condition number"), "{e}");
}
