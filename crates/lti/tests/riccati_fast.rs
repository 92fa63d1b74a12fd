//! The fixed-size fast path that `RiccatiMethod::Auto` tries first for small CAREs (`n ≤ 8`,
//! `m ≤ n`; it reports `RiccatiMethod::Doubling`, where the general `Auto` path reports
//! `Schur` whenever the Schur method succeeds).
//!
//! Checks, each against an independent source:
//! - scalar CAREs against the closed form `x = q / (sqrt(a² + b²q/r) − a)` (the stabilising
//!   root of `(b²/r)x² − 2ax − q = 0`), for `q > 0` and for an indefinite `q < 0`;
//! - the cart pendulum of the book (`care-n4` of the benchmark): `|K₁| = sqrt(q₁₁) = 10`
//!   (closed form: `A e₁ = 0`), and the same solution as the ordered-Schur method;
//! - random LQ problems of every order 1..=8 with every input count 1..=n, with and without
//!   cross term: the fast path is taken, and agrees with the ordered-Schur method (a different
//!   algorithm) to the problem's conditioning;
//! - every CAREX example of order ≤ 8 used by `riccati_benchmarks`: the `Auto` result is at
//!   least as accurate (defining residual, recomputed here) as the Schur method's and equal to
//!   it to the problem's conditioning, and its closed loop is stable;
//! - `m > n` falls back to the general path (method `Schur`) with the right answer.
//!
//! Run with `--nocapture` to print the CAREX comparison.
//!
//! Tolerances on `X` follow `riccati_benchmarks`: a backward error `η` gives a relative forward
//! error of at most about `κ·η`, `κ = ‖Ω⁻¹‖·(‖Q‖ + 2‖A‖‖X‖ + ‖G‖‖X‖²)/‖X‖` (Byers 1985;
//! `Ω(Z) = A_cᵀZ + ZA_c`, `‖Ω⁻¹‖` by power iteration), with `η = 100·n·ε` per solution.

mod equations_support;
mod riccati_benchmarks_support;
mod riccati_support;

use equations_support::lq_data;
use pendulab_lti::Mat;
use pendulab_lti::equations::riccati::care_residual;
use pendulab_lti::equations::{RiccatiMethod, RiccatiOptions, RiccatiSolution, care};
use riccati_benchmarks_support::{Example, Sweep, carex, sweep};
use riccati_support::care_condition as condition;

const EPS: f64 = f64::EPSILON;

fn opts(method: RiccatiMethod) -> RiccatiOptions {
    RiccatiOptions {
        method,
        ..Default::default()
    }
}

fn rel(a: &Mat, b: &Mat) -> f64 {
    (a - b).norm() / b.norm().max(f64::MIN_POSITIVE)
}

/// Agreement tolerance of two backward-stable solutions: `κ·2·(100·n·ε)`, at least a few ulps,
/// capped at 1e-6 so that the test can still fail where the normwise κ is vacuous (a wrong
/// solution differs by O(1)).
fn agreement_tolerance(kappa: f64, n: usize) -> f64 {
    let eta = 100.0 * n as f64 * EPS;
    (kappa * 2.0 * eta).max(10.0 * n as f64 * EPS).min(1e-6)
}

fn all_poles_stable(a: &Mat, b: &Mat, sol: &RiccatiSolution) -> bool {
    let acl = a - b * &sol.gain;
    pendulab_lti::linalg::eigenvalues(&acl)
        .unwrap()
        .iter()
        .all(|p| p.re < 0.0)
}

/// Scalar CARE `2ax − (b²/r)x² + q = 0`: stabilising root `x = q/(sqrt(a² + b²q/r) − a)`
/// (the rationalised form of `r(a + sqrt(a² + b²q/r))/b²`, free of cancellation for `a < 0`).
#[test]
fn scalar_closed_form() {
    for &(a, b, q, r) in &[
        (1.0, 1.0, 1.0, 1.0),
        (-2.0, 0.5, 3.0, 2.0),
        (4.0, 2.0, 0.25, 0.5),
        // Indefinite weight: Q < 0 with the stabilising solution still existing (a² + b²q/r >
        // 0); X is negative, so the PSD acceptance check must not be applied.
        (-1.0, 1.0, -0.5, 1.0),
    ] {
        let (am, bm, qm, rm) = (
            Mat::from_element(1, 1, a),
            Mat::from_element(1, 1, b),
            Mat::from_element(1, 1, q),
            Mat::from_element(1, 1, r),
        );
        let sol = care(&am, &bm, &qm, &rm, None, &RiccatiOptions::default()).unwrap();
        assert_eq!(sol.method, RiccatiMethod::Doubling, "fast path not taken");
        let x = q / ((a * a + b * b * q / r).sqrt() - a);
        // A handful of roundings in the closed form and the solver, none amplified (the
        // scalar problems are well conditioned: |a − (b²/r)x| ≥ 1).
        let err = (sol.x[(0, 0)] - x).abs() / x.abs();
        assert!(err <= 1e-14, "a={a} b={b} q={q} r={r}: {err:e}");
        assert!(sol.closed_loop_poles[0].re < 0.0);
    }
}

/// The `care-n4` workload: the linearised cart pendulum (book table 3.5, `docs/model.md` §1),
/// `Q = diag(100, 10, 1, 1)`, `R = 1`.
#[test]
fn cart_pendulum_fast_path() {
    let (a, b, q, r) = riccati_support::cart_pendulum();
    let sol = care(&a, &b, &q, &r, None, &RiccatiOptions::default()).unwrap();
    assert_eq!(sol.method, RiccatiMethod::Doubling, "fast path not taken");
    let res = care_residual(&a, &b, &q, &r, None, &sol.x);
    // The fast path's acceptance bound, recomputed independently.
    assert!(res <= 100.0 * 4.0 * EPS, "residual {res:e}");
    assert!(all_poles_stable(&a, &b, &sol));
    // A e₁ = 0 ⇒ e₁ᵀ(Riccati residual)e₁ = q₁₁ − K₁² = 0. |K₁| = 10 to the relative accuracy
    // of K (κ·η ≈ 1e-13 here, see the agreement check below).
    assert!((sol.gain[(0, 0)].abs() - 10.0).abs() <= 1e-12 * 10.0);
    let schur = care(&a, &b, &q, &r, None, &opts(RiccatiMethod::Schur)).unwrap();
    assert_eq!(schur.method, RiccatiMethod::Schur);
    let tol = agreement_tolerance(condition(&a, &b, &q, &r, &schur), 4);
    let e = rel(&sol.x, &schur.x);
    assert!(e <= tol, "fast vs Schur: {e:e} > {tol:e}");
}

#[test]
fn random_small_problems_match_schur() {
    let mut seed = 7000;
    for n in 1..=8 {
        for m in 1..=n {
            for cross in [false, true] {
                seed += 1;
                let (a, b, q, r, nn) = lq_data(seed, n, m, cross);
                let id = format!("n={n} m={m} cross={cross} seed={seed}");
                let fast = care(&a, &b, &q, &r, nn.as_ref(), &RiccatiOptions::default())
                    .unwrap_or_else(|e| panic!("{id}: {e}"));
                // These problems are well conditioned: the fast path must not decline them
                // (otherwise this test would only exercise the general path).
                assert_eq!(
                    fast.method,
                    RiccatiMethod::Doubling,
                    "{id}: fast path declined"
                );
                let res = care_residual(&a, &b, &q, &r, nn.as_ref(), &fast.x);
                assert!(res <= 100.0 * n as f64 * EPS, "{id}: residual {res:e}");
                assert!(
                    all_poles_stable(&a, &b, &fast),
                    "{id}: closed loop unstable"
                );
                assert_eq!(fast.x, fast.x.transpose(), "{id}: X not symmetric");
                let min = pendulab_lti::linalg::symmetric_eigenvalues(&fast.x)[0];
                assert!(min >= -1e-12 * fast.x.norm(), "{id}: X not PSD ({min:e})");
                let schur = care(&a, &b, &q, &r, nn.as_ref(), &opts(RiccatiMethod::Schur))
                    .unwrap_or_else(|e| panic!("{id} (Schur): {e}"));
                // With a cross term the condition number of the reduced problem is what
                // matters; the gain of the reduced problem is the same K.
                let kappa = condition(&a, &b, &q, &r, &schur);
                let tol = agreement_tolerance(kappa, n);
                let e = rel(&fast.x, &schur.x);
                assert!(
                    e <= tol,
                    "{id}: fast vs Schur {e:e} > {tol:e} (κ ≈ {kappa:e})"
                );
                let ek = rel(&fast.gain, &schur.gain);
                assert!(ek <= 10.0 * tol, "{id}: gains differ by {ek:e}");
            }
        }
    }
}

/// The CAREX examples of `riccati_benchmarks` with `n ≤ 8` (the rest never reach the fast
/// path).
fn carex_small() -> Vec<Example> {
    let table: Sweep<'_> = &[
        (1, &[1, 2, 3, 4], &[0.0], None),
        (2, &[1], &[1.0, 1e-2, 1e-4, 1e-6], None),
        (2, &[2], &[1.0, 1e-4, 1e-8], None),
        (2, &[3], &[1.0, 1e3, 1e7], None),
        (2, &[4], &[1.0, 1e-3, 1e-6, 1e-7], None),
        (2, &[5], &[1.0, 1e-2, 1e-4, 1e-6], None),
        (2, &[6], &[1.0, 1e3, 1e6, 1e7], None),
        (2, &[7], &[1e-2, 1e-6], None),
        (2, &[8], &[1.0, 1e-3, 1e-6], None),
    ];
    let all = sweep(carex, table);
    all.into_iter().filter(|e| e.a.nrows() <= 8).collect()
}

#[test]
fn carex_small_accuracy_unchanged() {
    let mut fast_taken = 0;
    let examples = carex_small();
    for e in &examples {
        let n = e.a.nrows();
        let auto = care(
            &e.a,
            &e.b,
            &e.q,
            &e.r,
            e.n.as_ref(),
            &RiccatiOptions::default(),
        )
        .unwrap_or_else(|err| panic!("{}: {err}", e.id));
        let schur = care(
            &e.a,
            &e.b,
            &e.q,
            &e.r,
            e.n.as_ref(),
            &opts(RiccatiMethod::Schur),
        );
        let res_auto = care_residual(&e.a, &e.b, &e.q, &e.r, e.n.as_ref(), &auto.x);
        assert!(all_poles_stable(&e.a, &e.b, &auto), "{}: unstable", e.id);
        if auto.method == RiccatiMethod::Doubling {
            fast_taken += 1;
        }
        let Ok(schur) = schur else {
            // The Schur method alone fails; Auto's fallback answered (checked against the
            // collection's references by `riccati_benchmarks`).
            continue;
        };
        let res_schur = care_residual(&e.a, &e.b, &e.q, &e.r, e.n.as_ref(), &schur.x);
        // Never less accurate than the ordered-Schur method (the fast path accepts only
        // residuals ≤ 100·n·ε; otherwise Auto runs the general path, which returns the Schur
        // result or a more accurate one).
        assert!(
            res_auto <= (100.0 * n as f64 * EPS).max(res_schur),
            "{}: Auto residual {res_auto:e} vs Schur {res_schur:e}",
            e.id
        );
        let tol = agreement_tolerance(condition(&e.a, &e.b, &e.q, &e.r, &schur), n);
        let err = rel(&auto.x, &schur.x);
        eprintln!(
            "{}: n={n} {:?} residual {res_auto:.1e} (Schur {res_schur:.1e}), ‖ΔX‖/‖X‖ {err:.1e} ≤ {tol:.1e}",
            e.id, auto.method
        );
        assert!(err <= tol, "{}: Auto vs Schur {err:e} > {tol:e}", e.id);
    }
    // The well-conditioned members of the collection go through the fast path.
    assert!(
        fast_taken >= examples.len() / 2,
        "fast path taken on only {fast_taken} of {} examples",
        examples.len()
    );
}

/// More inputs than states: the fast path declines and the general path answers. Scalar
/// with `B = [1 1]`, `R = I`: `G = 2`, `x = q/(sqrt(a² + 2q) − a)`.
#[test]
fn more_inputs_than_states_falls_back() {
    let (a, q) = (0.5, 2.0);
    let sol = care(
        &Mat::from_element(1, 1, a),
        &Mat::from_row_slice(1, 2, &[1.0, 1.0]),
        &Mat::from_element(1, 1, q),
        &Mat::identity(2, 2),
        None,
        &RiccatiOptions::default(),
    )
    .unwrap();
    assert_eq!(sol.method, RiccatiMethod::Schur);
    let x = q / ((a * a + 2.0 * q).sqrt() - a);
    assert!((sol.x[(0, 0)] - x).abs() <= 1e-14 * x);
}
