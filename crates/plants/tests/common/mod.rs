//! Helpers shared by the plant tests: a classic RK4 written here (independent of
//! pendulab-sim's integrators), central finite differences, the SymPy fixture.
#![allow(dead_code)]

use pendulab_lti::Mat;

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
