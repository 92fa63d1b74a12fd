//! The CAREX collection (continuous-time algebraic Riccati equations, Benner, Laub & Mehrmann
//! SPC 95_22; version 2.0, SLICOT Working Note 1999-14): the data of each example and, where
//! the collection gives one, the closed-form stabilising solution.

use pendulab_lti::Mat;

use super::{Example, FortranData, diag, example, eye, rows, v3, weight};

/// CAREX example `group.number` with parameter `eps` (ignored by the parameter-free ones) and
/// order parameter `size` (the scalable ones; `None` = the collection's default).
pub fn carex(group: u32, number: u32, eps: f64, size: Option<usize>) -> Example {
    let id = format!("CAREX {group}.{number}");
    match (group, number) {
        // Laub 1979, Ex. 1.
        (1, 1) => example(
            id,
            rows(2, 2, &[0.0, 1.0, 0.0, 0.0]),
            rows(2, 1, &[0.0, 1.0]),
            diag(&[1.0, 2.0]),
            eye(1),
            Some(rows(2, 2, &[2.0, 1.0, 1.0, 2.0])),
        ),
        // Laub 1979, Ex. 2: uncontrollable-unobservable data.
        (1, 2) => {
            let t = 1.0 + 2f64.sqrt();
            let w = rows(2, 2, &[9.0, 6.0, 6.0, 4.0]);
            example(
                id,
                rows(2, 2, &[4.0, 3.0, -4.5, -3.5]),
                rows(2, 1, &[1.0, -1.0]),
                w.clone(),
                eye(1),
                Some(w * t),
            )
        }
        // Beale/Shafai 1989 (L-1011), Bhattacharyya et al. 1983 (distillation column):
        // A, B and the full Q from the data file; R = I.
        (1, 3) | (1, 4) => {
            let (name, n) = if number == 3 {
                ("BB01103.dat", 4)
            } else {
                ("BB01104.dat", 8)
            };
            let mut f = FortranData::load(name);
            let a = f.matrix(n, n);
            let b = f.matrix(n, 2);
            let q = f.matrix(n, n);
            example(id, a, b, q, eye(2), None)
        }
        // Patnaik et al. 1980 (ammonia reactor): A, B from the file; Q = I, R = I.
        (1, 5) => {
            let mut f = FortranData::load("BB01105.dat");
            let a = f.matrix(9, 9);
            let b = f.matrix(9, 3);
            example(id, a, b, eye(9), eye(3), None)
        }
        // Davison/Gesing 1978 (J-100 jet engine): A, B, C from the file; W = I, R = I.
        (1, 6) => {
            let mut f = FortranData::load("BB01106.dat");
            let a = f.matrix(30, 30);
            let b = f.matrix(30, 3);
            let c = f.matrix(5, 30);
            example(id, a, b, weight(&c, &eye(5)), eye(3), None)
        }
        // Arnold/Laub 1984, Ex. 1: (A, B) unstabilisable as eps → 0.
        (2, 1) => {
            let t = (1.0 + eps * eps).sqrt();
            let x12 = 1.0 / (2.0 + t);
            let x = rows(
                2,
                2,
                &[
                    (1.0 + t) / (eps * eps),
                    x12,
                    x12,
                    (1.0 - eps * x12) * (1.0 + eps * x12) / 4.0,
                ],
            );
            let c = rows(1, 2, &[1.0, 1.0]);
            example(
                format!("{id} (eps = {eps:e})"),
                diag(&[1.0, -2.0]),
                rows(2, 1, &[eps, 0.0]),
                weight(&c, &eye(1)),
                eye(1),
                Some(x),
            )
        }
        // Arnold/Laub 1984, Ex. 3: control weighting matrix singular as eps → 0.
        (2, 2) => {
            let c = rows(1, 2, &[10.0, 100.0]);
            example(
                format!("{id} (eps = {eps:e})"),
                diag(&[-0.1, -0.02]),
                rows(2, 2, &[0.1, 0.0, 0.001, 0.01]),
                weight(&c, &eye(1)),
                rows(2, 2, &[1.0 + eps, 1.0, 1.0, 1.0]),
                None,
            )
        }
        // Kenney/Laub/Wette 1989, Ex. 2: ill conditioned as eps → ∞.
        (2, 3) => {
            let t = (1.0 + 2.0 * eps).sqrt();
            example(
                format!("{id} (eps = {eps:e})"),
                rows(2, 2, &[0.0, eps, 0.0, 0.0]),
                rows(2, 1, &[0.0, 1.0]),
                eye(2),
                eye(1),
                Some(rows(2, 2, &[t / eps, 1.0, 1.0, t])),
            )
        }
        // Bai/Qian 1994: ill-conditioned Hamiltonian as eps → 0. B = I (G = I), Q = eps² I.
        (2, 4) => {
            let t = eps + 1.0;
            let x11 = (2.0 * t + 2f64.sqrt() * ((t * t + 1.0).sqrt() + eps)) / 2.0;
            let x12 = x11 / (x11 - t);
            example(
                format!("{id} (eps = {eps:e})"),
                rows(2, 2, &[t, 1.0, 1.0, t]),
                eye(2),
                eye(2) * (eps * eps),
                eye(2),
                Some(rows(2, 2, &[x11, x12, x12, x11])),
            )
        }
        // Laub 1992: H∞-type data, Hamiltonian eigenvalues ±eps ± j; X does not depend on eps.
        (2, 5) => example(
            format!("{id} (eps = {eps:e})"),
            rows(2, 2, &[3.0 - eps, 1.0, 4.0, 2.0 - eps]),
            rows(2, 1, &[1.0, 1.0]),
            rows(
                2,
                2,
                &[
                    4.0 * eps - 11.0,
                    2.0 * eps - 5.0,
                    2.0 * eps - 5.0,
                    2.0 * eps - 2.0,
                ],
            ),
            eye(1),
            Some(rows(2, 2, &[2.0, 1.0, 1.0, 1.0])),
        ),
        // Petkov/Christov/Konstantinov 1987: increasingly badly scaled as eps → ∞.
        // A = V diag(eps, 2eps, 3eps) V, B = I, R = eps I, Q = V diag(1/eps, 1, eps) V.
        (2, 6) => {
            let v = v3();
            let e2 = eps * eps;
            let xd = diag(&[
                e2 + (e2 * e2 + 1.0).sqrt(),
                2.0 * e2 + (4.0 * e2 * e2 + eps).sqrt(),
                3.0 * e2 + eps * (9.0 * e2 + 1.0).sqrt(),
            ]);
            example(
                format!("{id} (eps = {eps:e})"),
                &v * diag(&[eps, 2.0 * eps, 3.0 * eps]) * &v,
                eye(3),
                weight(&v, &diag(&[1.0 / eps, 1.0, eps])),
                eye(3) * eps,
                Some(&v * xd * &v),
            )
        }
        // Chow/Kokotovic 1976: magnetic tape control, stiff as eps → 0.
        (2, 7) => {
            let mut a = Mat::zeros(4, 4);
            a[(0, 1)] = 0.4;
            a[(1, 2)] = 0.345;
            a[(2, 1)] = -0.524 / eps;
            a[(2, 2)] = -0.465 / eps;
            a[(2, 3)] = 0.262 / eps;
            a[(3, 3)] = -1.0 / eps;
            let mut b = Mat::zeros(4, 1);
            b[(3, 0)] = 1.0 / eps;
            let mut c = Mat::zeros(2, 4);
            c[(0, 0)] = 1.0;
            c[(1, 2)] = 1.0;
            example(
                format!("{id} (eps = {eps:e})"),
                a,
                b,
                weight(&c, &eye(2)),
                eye(1),
                None,
            )
        }
        // Arnold/Laub 1984, Ex. 2: poor separation of the closed-loop spectrum as eps → 0.
        (2, 8) => {
            let a = rows(
                4,
                4,
                &[
                    -eps, 1.0, 0.0, 0.0, //
                    -1.0, -eps, 0.0, 0.0, //
                    0.0, 0.0, eps, 1.0, //
                    0.0, 0.0, -1.0, eps,
                ],
            );
            let c = rows(1, 4, &[1.0, 1.0, 1.0, 1.0]);
            example(
                format!("{id} (eps = {eps:e})"),
                a,
                Mat::from_element(4, 1, 1.0),
                weight(&c, &eye(1)),
                eye(1),
                None,
            )
        }
        // Laub 1979, Ex. 4: a string of l high-speed vehicles, n = 2l − 1, m = l.
        (3, 1) => {
            let l = size.unwrap_or(20);
            let n = 2 * l - 1;
            let mut a = Mat::zeros(n, n);
            let mut b = Mat::zeros(n, l);
            let mut c = Mat::zeros(l - 1, n);
            for i in 1..=n {
                if i % 2 == 1 {
                    a[(i - 1, i - 1)] = -1.0;
                    b[(i - 1, i.div_ceil(2) - 1)] = 1.0;
                } else {
                    a[(i - 1, i - 2)] = 1.0;
                    a[(i - 1, i)] = -1.0;
                    c[(i / 2 - 1, i - 1)] = 1.0;
                }
            }
            example(
                format!("{id} (l = {l})"),
                a,
                b,
                weight(&c, &(eye(l - 1) * 10.0)),
                eye(l),
                None,
            )
        }
        // Laub 1979, Ex. 5: circulant A = tridiag(1, −2, 1) with corners 1; B = C = W = R = I.
        // The eigenvalues of A are λ_k = −2 + 2cos θ_k (θ_k = 2πk/n) with Fourier
        // eigenvectors, so X is circulant with eigenvalues λ_k + sqrt(λ_k² + 1).
        (3, 2) => {
            let n = size.unwrap_or(64);
            let mut a = Mat::zeros(n, n);
            for i in 0..n {
                a[(i, i)] = -2.0;
                a[(i, (i + 1) % n)] = 1.0;
                a[((i + 1) % n, i)] = 1.0;
            }
            let th = 2.0 * std::f64::consts::PI / n as f64;
            let d: Vec<f64> = (0..n)
                .map(|i| {
                    let c = (th * i as f64).cos();
                    -2.0 + 2.0 * c + (5.0 + 4.0 * c * (c - 2.0)).sqrt()
                })
                .collect();
            let col: Vec<f64> = (0..n)
                .map(|j| {
                    (0..n)
                        .map(|i| d[i] * (th * (i * j) as f64).cos())
                        .sum::<f64>()
                        / n as f64
                })
                .collect();
            let x = Mat::from_fn(n, n, |r, c| col[(r + n - c) % n]);
            example(
                format!("{id} (n = {n})"),
                a,
                eye(n),
                eye(n),
                eye(n),
                Some(x),
            )
        }
        // Laub 1979, Ex. 6: an integrator chain, ill conditioned; q = eps (weight of x₁),
        // r = 1.
        (4, 1) => {
            let n = size.unwrap_or(21);
            let mut a = Mat::zeros(n, n);
            for i in 0..n - 1 {
                a[(i, i + 1)] = 1.0;
            }
            let mut b = Mat::zeros(n, 1);
            b[(n - 1, 0)] = 1.0;
            let mut c = Mat::zeros(1, n);
            c[(0, 0)] = 1.0;
            example(
                format!("{id} (n = {n}, q = {eps:e})"),
                a,
                b,
                weight(&c, &(eye(1) * eps)),
                eye(1),
                None,
            )
        }
        // Rosen/Wang 1992: LQ control of 1-D heat flow (Galerkin finite elements, n nodes),
        // diffusion coefficient a = eps, b = c = 1, control and observation on [0.2, 0.3].
        (4, 2) => {
            let n = size.unwrap_or(100);
            let h1 = (n + 1) as f64;
            // Stiffness K (tridiagonal) and mass (Gram) matrix M of the hat functions.
            let mut k = Mat::zeros(n, n);
            let mut m = Mat::zeros(n, n);
            for i in 0..n {
                k[(i, i)] = -2.0 * eps * h1;
                m[(i, i)] = 4.0 / (6.0 * h1);
                if i + 1 < n {
                    k[(i + 1, i)] = eps * h1;
                    k[(i, i + 1)] = eps * h1;
                    m[(i + 1, i)] = 1.0 / (6.0 * h1);
                    m[(i, i + 1)] = 1.0 / (6.0 * h1);
                }
            }
            // ∫ over [lo, hi] of the i-th hat function (1-based i, nodes i/(n+1)).
            let hat_integral = |i: usize, lo: f64, hi: f64| -> f64 {
                let fi = i as f64;
                let b1 = ((fi - 1.0) / h1).max(lo);
                let b2 = ((fi + 1.0) / h1).min(hi);
                if b1 >= b2 {
                    return 0.0;
                }
                let mut s = b2 - b1;
                let t = b2.min(fi / h1);
                if b1 < t {
                    s += h1 * (t * t - b1 * b1) / 2.0 + fi * (b1 - t);
                }
                let t = b1.max(fi / h1);
                if t < b2 {
                    s -= h1 * (b2 * b2 - t * t) / 2.0 + fi * (t - b2);
                }
                s
            };
            let bvec = Mat::from_fn(n, 1, |i, _| hat_integral(i + 1, 0.2, 0.3));
            let cvec = Mat::from_fn(1, n, |_, j| hat_integral(j + 1, 0.2, 0.3));
            let lu = m.clone().lu();
            let a = lu.solve(&k).expect("mass matrix is positive definite");
            let b = lu.solve(&bvec).expect("mass matrix is positive definite");
            example(
                format!("{id} (n = {n}, a = {eps:e})"),
                a,
                b,
                weight(&cvec, &eye(1)),
                eye(1),
                None,
            )
        }
        // Hench et al. 1995: l coupled springs, dashpots and masses, n = 2l, m = 2; mass
        // mu = eps, damping delta = 4, stiffness kappa = 1; C = W = R = I.
        (4, 3) => {
            let l = size.unwrap_or(30);
            let n = 2 * l;
            let (mu, delta, kappa) = (eps, 4.0, 1.0);
            let mut a = Mat::zeros(n, n);
            for i in 0..l {
                a[(i, l + i)] = 1.0;
                a[(l + i, l + i)] = -delta / mu;
            }
            let t = kappa / mu;
            a[(l, 0)] = -t;
            a[(l, 1)] = t;
            a[(n - 1, l - 2)] = t;
            a[(n - 1, l - 1)] = -t;
            for i in 2..l {
                // 1-based row l + i, columns i − 1, i, i + 1.
                a[(l + i - 1, i - 1)] = -2.0 * t;
                a[(l + i - 1, i)] = t;
                a[(l + i - 1, i - 2)] = t;
            }
            let mut b = Mat::zeros(n, 2);
            b[(l, 0)] = 1.0 / mu;
            b[(n - 1, 1)] = -1.0 / mu;
            example(
                format!("{id} (l = {l}, mu = {eps:e})"),
                a,
                b,
                eye(n),
                eye(2),
                None,
            )
        }
        _ => panic!("no CAREX example {group}.{number}"),
    }
}
