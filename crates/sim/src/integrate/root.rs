//! Bracketed scalar root finding for event location.
//!
//! Brent's method (R. P. Brent, *Algorithms for Minimization without Derivatives*, 1973,
//! ch. 4, procedure `zero`): inverse quadratic interpolation and secant steps safeguarded by
//! bisection, so it converges superlinearly on smooth functions and never slower than
//! bisection.

/// Finds `t ∈ [a, b]` with `f(t) = 0` to within `tol` given `f(a)·f(b) ≤ 0`; returns the
/// endpoint of the final bracket where `|f|` is smallest. Stops after `max_iter` evaluations
/// (returning the best point so far).
pub(crate) fn brent<F: FnMut(f64) -> f64>(
    mut f: F,
    mut a: f64,
    mut b: f64,
    mut fa: f64,
    mut fb: f64,
    tol: f64,
    max_iter: usize,
) -> f64 {
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    let mut c = a;
    let mut fc = fa;
    let mut d = b - a;
    let mut e = d;
    for _ in 0..max_iter {
        if (fb > 0.0) == (fc > 0.0) {
            // Keep the root bracketed between b and c.
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol;
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol1 || fb == 0.0 {
            return b;
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            // Interpolation: secant (two points) or inverse quadratic (three points).
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * xm * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * xm * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * xm * q - (tol1 * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol1 { d } else { tol1.copysign(xm) };
        fb = f(b);
    }
    b
}

#[cfg(test)]
mod tests {
    use super::brent;

    #[test]
    fn finds_roots_of_smooth_and_flat_functions() {
        // cos t = 0 on [1, 2]: π/2.
        let r = brent(f64::cos, 1.0, 2.0, 1f64.cos(), 2f64.cos(), 1e-15, 100);
        assert!((r - std::f64::consts::FRAC_PI_2).abs() < 1e-14);
        // (t − 1/3)³: a triple root where interpolation is poor (bisection safeguard).
        let g = |t: f64| (t - 1.0 / 3.0).powi(3);
        let r = brent(g, 0.0, 1.0, g(0.0), g(1.0), 1e-14, 200);
        // The sign of a cube is computed exactly, so the bracket keeps shrinking to `tol`.
        assert!((r - 1.0 / 3.0).abs() < 1e-13, "{r}");
        // A root at an endpoint.
        assert_eq!(brent(|t| t, 0.0, 1.0, 0.0, 1.0, 1e-12, 10), 0.0);
    }
}
