//! Helpers shared by the plant tests: a classic RK4 written here (independent of
//! pendulab-sim's integrators), central finite differences, the SymPy fixture, and the checks
//! every plant goes through (Jacobian against differences, model against SymPy, energy drift and
//! energy balance along RK4 paths), written once and generic over the plant.
#![allow(dead_code)]

use pendulab_lti::Mat;
use pendulab_plants::{Jacobian, PlantError};

/// One classic fourth-order Runge–Kutta step of `ẋ = f(t, x)`.
pub fn rk4_step<const N: usize>(
    f: &impl Fn(f64, &[f64; N]) -> [f64; N],
    t: f64,
    x: &[f64; N],
    h: f64,
) -> [f64; N] {
    let add = |x: &[f64; N], k: &[f64; N], s: f64| {
        let mut y = *x;
        for i in 0..N {
            y[i] += s * k[i];
        }
        y
    };
    let k1 = f(t, x);
    let k2 = f(t + 0.5 * h, &add(x, &k1, 0.5 * h));
    let k3 = f(t + 0.5 * h, &add(x, &k2, 0.5 * h));
    let k4 = f(t + h, &add(x, &k3, h));
    let mut y = *x;
    for i in 0..N {
        y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
    y
}

/// `steps` RK4 steps of size `h` from `(0, x0)`; returns the states at every step (including
/// the initial one).
pub fn rk4_path<const N: usize>(
    f: impl Fn(f64, &[f64; N]) -> [f64; N],
    x0: [f64; N],
    h: f64,
    steps: usize,
) -> Vec<[f64; N]> {
    let mut out = Vec::with_capacity(steps + 1);
    let mut x = x0;
    out.push(x);
    for k in 0..steps {
        x = rk4_step(&f, k as f64 * h, &x, h);
        out.push(x);
    }
    out
}

/// Central-difference Jacobian of `f(x, u)` w.r.t. `x` and `u` with steps
/// `h_j = 1e-5 · max(1, |x_j|)`.
pub fn fd_jacobian<const N: usize>(
    f: impl Fn(&[f64; N], f64) -> [f64; N],
    x: &[f64; N],
    u: f64,
) -> ([[f64; N]; N], [f64; N]) {
    let mut a = [[0.0; N]; N];
    for j in 0..N {
        let h = 1e-5 * x[j].abs().max(1.0);
        let (mut xp, mut xm) = (*x, *x);
        xp[j] += h;
        xm[j] -= h;
        let (fp, fm) = (f(&xp, u), f(&xm, u));
        for i in 0..N {
            a[i][j] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    let h = 1e-5 * u.abs().max(1.0);
    let (fp, fm) = (f(x, u + h), f(x, u - h));
    let mut b = [0.0; N];
    for i in 0..N {
        b[i] = (fp[i] - fm[i]) / (2.0 * h);
    }
    (a, b)
}

/// Asserts that the analytic Jacobian `jacobian(x, u)` equals central differences of `f`
/// ([`fd_jacobian`]) at each of `points`, entry by entry within `tol` times the largest entry of
/// the analytic `A` and `B`; a failure names the entry and the point.
pub fn assert_jacobian_matches_fd<const N: usize>(
    jacobian: impl Fn(&[f64; N], f64) -> Jacobian<N>,
    f: impl Fn(&[f64; N], f64) -> [f64; N],
    points: &[([f64; N], f64)],
    tol: f64,
) {
    for (x, u) in points {
        let jac = jacobian(x, *u);
        let (a_fd, b_fd) = fd_jacobian(&f, x, *u);
        let scale = jac.a_matrix().amax().max(jac.b_matrix().amax());
        for i in 0..N {
            for j in 0..N {
                assert!(
                    (jac.a[i][j] - a_fd[i][j]).abs() <= tol * scale,
                    "A[{i}][{j}] at {x:?}: {} vs {}",
                    jac.a[i][j],
                    a_fd[i][j]
                );
            }
            assert!((jac.b[i] - b_fd[i]).abs() <= tol * scale, "B[{i}] at {x:?}");
        }
    }
}

/// A parameter's name as the error reports it, how to set it, and whether zero is valid.
pub type Field<P> = (&'static str, fn(&mut P, f64), bool);

/// The [`Field`]s of a parameter struct: `fields![P; a_c = true, b_c = false]` lists `a_c` (zero
/// valid) and `b_c` (zero refused) of `P`.
#[macro_export]
macro_rules! fields {
    ($p:ty; $($name:ident = $zero_ok:expr),* $(,)?) => {
        [$((stringify!($name), (|p: &mut $p, v: f64| p.$name = v) as fn(&mut $p, f64), $zero_ok)),*]
    };
}

/// Asserts that `new` refuses each of the values `bad` in each of `fields` (set on `book`) with
/// `PlantError::InvalidParameter` naming the field and carrying the value, and accepts zero
/// exactly where the field says so; `also` sees every refused parameter set, for the checks a
/// plant adds (another constructor refusing it too).
pub fn assert_fields_validated<P: Copy, T: std::fmt::Debug>(
    book: P,
    fields: &[Field<P>],
    bad: &[f64],
    new: impl Fn(P) -> Result<T, PlantError>,
    also: impl Fn(&P),
) {
    for &(name, set, zero_ok) in fields {
        for &bad in bad {
            let mut p = book;
            set(&mut p, bad);
            match new(p) {
                Err(PlantError::InvalidParameter { name: n, value, .. }) => {
                    assert_eq!(n, name);
                    assert!(value.is_nan() && bad.is_nan() || value == bad);
                }
                other => panic!("{name} = {bad}: expected InvalidParameter, got {other:?}"),
            }
            also(&p);
        }
        let mut p = book;
        set(&mut p, 0.0);
        assert_eq!(new(p).is_ok(), zero_ok, "{name} = 0");
    }
}

/// Largest absolute entry.
pub fn max_abs(m: &Mat) -> f64 {
    m.iter().fold(0.0f64, |acc, v| acc.max(v.abs()))
}

/// The SymPy/mpmath fixture written by `tools/reference/plants_lagrange.py`.
pub fn fixture() -> serde_json::Value {
    let text = include_str!("../fixtures/lagrange.json");
    serde_json::from_str(text).expect("fixture is valid JSON")
}

pub fn num(v: &serde_json::Value) -> f64 {
    v.as_f64().expect("a number")
}

pub fn arr<const N: usize>(v: &serde_json::Value) -> [f64; N] {
    let a = v.as_array().expect("an array");
    assert_eq!(a.len(), N);
    std::array::from_fn(|i| num(&a[i]))
}

/// One case of the SymPy fixture's section `key` (`tools/reference/plants_lagrange.py`): the
/// parameters, the state, the input, and SymPy's `f(x, u)` evaluated at 40 digits.
pub struct SympyCase {
    pub params: serde_json::Value,
    pub x: [f64; 4],
    pub u: f64,
    pub f: [f64; 4],
}

/// The fixture's cases of section `key` (eight per plant).
pub fn sympy_cases(key: &str) -> Vec<SympyCase> {
    let fx = fixture();
    let cases = fx[key].as_array().expect("a section of cases");
    assert_eq!(cases.len(), 8);
    cases
        .iter()
        .map(|case| SympyCase {
            params: case["params"].clone(),
            x: arr(&case["x"]),
            u: num(&case["u"]),
            f: arr(&case["f"]),
        })
        .collect()
}

/// Asserts `|f_i − f_i^SymPy| ≤ tol · max(1, |f_i^SymPy|)` for every entry.
pub fn assert_matches_sympy(f: &[f64; 4], case: &SympyCase, tol: f64) {
    for i in 0..4 {
        assert!(
            (f[i] - case.f[i]).abs() <= tol * case.f[i].abs().max(1.0),
            "f[{i}] at {:?}: {} vs SymPy {}",
            case.x,
            f[i],
            case.f[i]
        );
    }
}

/// The largest `|E(x) − E(x₀)|` along `path`, `x₀` its first state.
pub fn energy_drift<const N: usize>(path: &[[f64; N]], energy: impl Fn(&[f64; N]) -> f64) -> f64 {
    let e0 = energy(&path[0]);
    path.iter()
        .map(|x| (energy(x) - e0).abs())
        .fold(0.0, f64::max)
}

/// The energy balance along an RK4 path of `ẋ = f(x, v(t))` from `x0`, 4 s in steps of
/// `h = 1e-4` s: asserts `E(T) − E(0) = ∫ P dt`, `P(x, v)` the power the model says flows into
/// `E`, both integrals by Simpson's rule on the path's samples, and that the run moves energy
/// (`∫ |P| dt > 1e-2`), so the check cannot pass by standing still.
///
/// RK4 and Simpson both err by O(h⁴) ≈ 1e-16 times derivatives of the motion (ω ≈ 10 rad/s, so
/// ≈ 1e-12 relative): 1e-9 of the energy moved (`∫ |P| dt`) is a safe bound; a wrong coefficient
/// in a model would show at 1e-2.
pub fn assert_energy_balance<const N: usize>(
    f: impl Fn(&[f64; N], f64) -> [f64; N],
    v: impl Fn(f64) -> f64,
    x0: [f64; N],
    energy: impl Fn(&[f64; N]) -> f64,
    power: impl Fn(&[f64; N], f64) -> f64,
) {
    let (h, steps) = (1e-4, 40_000);
    let path = rk4_path(|t, x| f(x, v(t)), x0, h, steps);
    let power: Vec<f64> = path
        .iter()
        .enumerate()
        .map(|(k, x)| power(x, v(k as f64 * h)))
        .collect();
    let gained = energy(&path[steps]) - energy(&path[0]);
    let integral = simpson(&power, h);
    let magnitude = simpson(&power.iter().map(|p| p.abs()).collect::<Vec<_>>(), h);
    assert!(
        (gained - integral).abs() <= 1e-9 * magnitude,
        "ΔE = {gained}, ∫P dt = {integral}"
    );
    assert!(magnitude > 1e-2, "the test must move energy ({magnitude})");
}

/// Composite Simpson's rule on `2m + 1` equally spaced samples.
pub fn simpson(y: &[f64], h: f64) -> f64 {
    let n = y.len() - 1;
    assert!(n.is_multiple_of(2) && n >= 2);
    let mut s = y[0] + y[n];
    for k in 1..n {
        s += if !k.is_multiple_of(2) { 4.0 } else { 2.0 } * y[k];
    }
    s * h / 3.0
}
