//! The Riccati benchmark collections CAREX and DAREX (Benner, Laub & Mehrmann, TU Chemnitz
//! SPC 95_22 and 95_23, 1995; version 2.0 by Abels & Benner, SLICOT Working Notes 1999-14 and
//! 1999-16), written from the published definitions (the SLICOT generators `BB01AD`/`BB02AD`
//! document them): the data of each example and, where the collection gives one, the closed-form
//! stabilising solution.
//!
//! Conventions of the collections, mapped to pendulab's:
//! - CAREX: `0 = Q + AᵀX + XA − XGX` with `G = BR⁻¹Bᵀ` and `Q = CᵀWC`. An example with
//!   "`B = I`" and a weight `R` has `G = R⁻¹`; we pass `B = I`, `R` as is.
//! - DAREX: `0 = AᵀXA − X − (AᵀXB + S)(R + BᵀXB)⁻¹(BᵀXA + Sᵀ) + Q` with `Q = CᵀQ₀C`; `S` is
//!   pendulab's cross term `N`.
//! - Symmetric weights are listed by the generators in packed lower-triangular order
//!   (column by column); [`packed_lower`] unpacks them.
//!
//! Nothing here computes a solution: the closed forms are the formulas printed in the
//! collections.
#![allow(dead_code)]

use pendulab_lti::Mat;

/// One benchmark problem.
#[derive(Debug, Clone)]
pub struct Example {
    /// "CAREX 2.1 (eps = 1e-6)", ...
    pub id: String,
    /// State matrix.
    pub a: Mat,
    /// Input matrix.
    pub b: Mat,
    /// State weight `Q = CᵀWC` (continuous) or `CᵀQ₀C` (discrete).
    pub q: Mat,
    /// Input weight.
    pub r: Mat,
    /// Cross weight (`S` of DAREX), if any.
    pub n: Option<Mat>,
    /// The stabilising solution in closed form, if the collection gives one.
    pub x: Option<Mat>,
}

/// Unpacks a symmetric `k × k` matrix from its packed lower triangle (column by column).
pub fn packed_lower(k: usize, p: &[f64]) -> Mat {
    assert_eq!(p.len(), k * (k + 1) / 2);
    let mut m = Mat::zeros(k, k);
    let mut pos = 0;
    for j in 0..k {
        for i in j..k {
            m[(i, j)] = p[pos];
            m[(j, i)] = p[pos];
            pos += 1;
        }
    }
    m
}

fn rows(r: usize, c: usize, v: &[f64]) -> Mat {
    Mat::from_row_slice(r, c, v)
}

fn eye(n: usize) -> Mat {
    Mat::identity(n, n)
}

fn diag(v: &[f64]) -> Mat {
    Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(v))
}

/// `CᵀWC`, symmetrised.
fn weight(c: &Mat, w: &Mat) -> Mat {
    let q = c.transpose() * w * c;
    (&q + q.transpose()) * 0.5
}

/// The weights of Sima's paper machine models (DAREX 1.11 and 1.12): `C` has the two quality
/// outputs in its first two rows (`quality`: entries `(row, column, value)`) and picks the
/// last two states (integrating: the error integrators of 1.11, the disturbance states of
/// 1.12) in rows 3 and 4; `Q₀ = diag(0.5, 5, 0.5, 5)`, `R = diag(400, 700)`.
fn paper_machine(id: String, a: Mat, b: Mat, quality: &[(usize, usize, f64)]) -> Example {
    let n = a.nrows();
    let mut c = Mat::zeros(4, n);
    for &(i, j, v) in quality {
        c[(i, j)] = v;
    }
    c[(2, n - 2)] = 1.0;
    c[(3, n - 1)] = 1.0;
    let q = weight(&c, &diag(&[0.5, 5.0, 0.5, 5.0]));
    example(id, a, b, q, diag(&[400.0, 700.0]), None)
}

/// A list of benchmark examples: `(group, numbers, parameter values, size)` stands for the
/// examples `group.number` for each of `numbers`, each at every parameter value (`eps` of the
/// collection; `0.0` for the examples without one), in that order.
pub type Sweep<'a> = &'a [(u32, &'a [u32], &'a [f64], Option<usize>)];

/// The examples of `table` from `collection` ([`carex`] or [`darex`]), in the table's order.
pub fn sweep(
    collection: fn(u32, u32, f64, Option<usize>) -> Example,
    table: Sweep<'_>,
) -> Vec<Example> {
    let mut examples = Vec::new();
    for &(group, numbers, values, size) in table {
        for &number in numbers {
            for &eps in values {
                examples.push(collection(group, number, eps, size));
            }
        }
    }
    examples
}

fn example(id: String, a: Mat, b: Mat, q: Mat, r: Mat, x: Option<Mat>) -> Example {
    Example {
        id,
        a,
        b,
        q,
        r,
        n: None,
        x,
    }
}

/// Reads Fortran list-directed data the way the generators do: each `read(count)` starts on a
/// new line and consumes lines until `count` numbers are read (the rest of its last line is
/// discarded). `D` exponents are accepted.
pub struct FortranData {
    lines: Vec<Vec<f64>>,
    next: usize,
}

impl FortranData {
    /// Loads `tests/fixtures/riccati_benchmarks/<name>`.
    pub fn load(name: &str) -> Self {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/fixtures/riccati_benchmarks")
            .join(name);
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
        let lines = text
            .lines()
            .map(|l| {
                l.split_whitespace()
                    .map(|t| {
                        t.replace(['D', 'd'], "E")
                            .parse::<f64>()
                            .unwrap_or_else(|_| panic!("{name}: bad number {t}"))
                    })
                    .collect::<Vec<_>>()
            })
            .filter(|v| !v.is_empty())
            .collect();
        Self { lines, next: 0 }
    }

    /// One list-directed read of `count` numbers.
    pub fn read(&mut self, count: usize) -> Vec<f64> {
        let mut out = Vec::with_capacity(count);
        while out.len() < count {
            let line = &self.lines[self.next];
            self.next += 1;
            let take = (count - out.len()).min(line.len());
            out.extend_from_slice(&line[..take]);
        }
        out
    }

    /// `r` reads of `c` numbers: a matrix given row by row.
    pub fn matrix(&mut self, r: usize, c: usize) -> Mat {
        let mut m = Mat::zeros(r, c);
        for i in 0..r {
            let row = self.read(c);
            for j in 0..c {
                m[(i, j)] = row[j];
            }
        }
        m
    }
}

/// `V = I − (2/3) 1 1ᵀ` (3×3, symmetric orthogonal), used by CAREX 2.6 and DAREX 2.4.
fn v3() -> Mat {
    Mat::from_fn(3, 3, |i, j| if i == j { 1.0 / 3.0 } else { -2.0 / 3.0 })
}

// ---------------------------------------------------------------------------------------------
// CAREX.

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

// ---------------------------------------------------------------------------------------------
// DAREX.

/// DAREX example `group.number` with parameter `eps` (ignored by the parameter-free ones) and
/// order `size` (4.1; `None` = the collection's default 100).
pub fn darex(group: u32, number: u32, eps: f64, size: Option<usize>) -> Example {
    let id = format!("DAREX {group}.{number}");
    let with_n = |mut e: Example, s: Mat| {
        e.n = Some(s);
        e
    };
    match (group, number) {
        // Van Dooren 1981, Ex. II: R = 0 (singular).
        (1, 1) => {
            let c = rows(1, 2, &[0.0, 1.0]);
            example(
                id,
                rows(2, 2, &[2.0, -1.0, 1.0, 0.0]),
                rows(2, 1, &[1.0, 0.0]),
                weight(&c, &eye(1)),
                Mat::zeros(1, 1),
                Some(eye(2)),
            )
        }
        // Ionescu/Weiss 1992: singular R, nonzero S.
        (1, 2) => with_n(
            example(
                id,
                rows(2, 2, &[0.0, 1.0, 0.0, -1.0]),
                rows(2, 2, &[1.0, 0.0, 2.0, 1.0]),
                packed_lower(2, &[-4.0 / 11.0, -4.0 / 11.0, 7.0 / 11.0]),
                packed_lower(2, &[9.0, 3.0, 1.0]),
                None,
            ),
            rows(2, 2, &[3.0, 1.0, -1.0, 7.0]),
        ),
        // Jonckheere 1981: (A, B) controllable, no solution X ≤ 0.
        (1, 3) => example(
            id,
            rows(2, 2, &[0.0, 1.0, 0.0, 0.0]),
            rows(2, 1, &[0.0, 1.0]),
            packed_lower(2, &[1.0, 2.0, 4.0]),
            eye(1),
            Some(rows(2, 2, &[1.0, 2.0, 2.0, 2.0 + 5f64.sqrt()])),
        ),
        // Sun 1998: R singular, Q indefinite. The collection prints X = diag(1e5, 1e3, 0),
        // which solves the equation for q₃₃ = −0.1; with the distributed q₃₃ = −10 the
        // stabilising solution is diag(1e5, 1e3, −9.9): for X = diag(x₁, x₂, x₃), AᵀXA =
        // diag(0, 0.01x₁, 1e-4·x₂), AᵀXB = 0.1x₁e₂e₁ᵀ, R + BᵀXB = diag(x₁, 1 + x₃), so the
        // diagonal equations read −x₁ + 1e5 = 0, 0.01x₁ − x₂ − 0.01x₁ + 1e3 = 0,
        // 1e-4·x₂ − x₃ − 10 = 0; the gain K = 0.1·e₁e₂ᵀ leaves A − BK nilpotent (stable).
        (1, 4) => {
            let mut a = Mat::zeros(3, 3);
            a[(0, 1)] = 0.1;
            a[(1, 2)] = 0.01;
            let mut b = Mat::zeros(3, 2);
            b[(0, 0)] = 1.0;
            b[(2, 1)] = 1.0;
            example(
                id,
                a,
                b,
                diag(&[1e5, 1e3, -10.0]),
                packed_lower(2, &[0.0, 0.0, 1.0]),
                Some(diag(&[1e5, 1e3, -9.9])),
            )
        }
        // Ackerson/Fu 1970 (satellite), Litkouhi 1983 (slow and fast modes): A, B from the
        // file, C = I, R = I.
        (1, 5) => {
            let mut f = FortranData::load("BB02105.dat");
            let a = f.matrix(4, 4);
            let b = f.matrix(4, 2);
            let mut q = Mat::zeros(4, 4);
            for (i, j, v) in [
                (0, 0, 1.87),
                (3, 0, -0.244),
                (1, 1, 0.744),
                (2, 1, 0.205),
                (2, 2, 0.589),
                (3, 3, 1.048),
            ] {
                q[(i, j)] = v;
                q[(j, i)] = v;
            }
            example(id, a, b, q, eye(2), None)
        }
        (1, 6) => {
            let mut f = FortranData::load("BB02106.dat");
            let a = f.matrix(4, 4);
            let b = f.matrix(4, 2);
            example(id, a, b, eye(4) * 0.01, eye(2), None)
        }
        // Lu/Lin 1993, Ex. 4.3: C upper triangular, R = I.
        (1, 7) => {
            let mut f = FortranData::load("BB02107.dat");
            let a = f.matrix(4, 4);
            let b = f.matrix(4, 4);
            let c = rows(
                4,
                4,
                &[
                    1.0, 1.0, 2.0, 4.0, //
                    0.0, 1.0, 1.0, 2.0, //
                    0.0, 0.0, 1.0, 1.0, //
                    0.0, 0.0, 0.0, 1.0,
                ],
            );
            let q0 = packed_lower(4, &[2.0, -1.0, 0.0, 0.0, 2.0, -1.0, 0.0, 2.0, 0.0, 0.0]);
            example(id, a, b, weight(&c, &q0), eye(4), None)
        }
        // Gajic/Shen 1993 (chemical plant): C = Q₀ = R = I.
        (1, 8) => {
            let mut f = FortranData::load("BB02108.dat");
            let a = f.matrix(5, 5);
            let b = f.matrix(5, 2);
            example(id, a, b, eye(5), eye(2), None)
        }
        // Davison/Wang 1974: nonzero S.
        (1, 9) => {
            let mut a = Mat::zeros(6, 6);
            for (i, j) in [(0, 1), (1, 2), (3, 4), (4, 5)] {
                a[(i, j)] = 1.0;
            }
            let mut b = Mat::zeros(6, 2);
            b[(2, 0)] = 1.0;
            b[(5, 1)] = 1.0;
            let c = rows(
                2,
                6,
                &[
                    1.0, 1.0, 0.0, 0.0, 0.0, 0.0, //
                    0.0, 0.0, 0.0, 1.0, -1.0, 0.0,
                ],
            );
            let mut s = Mat::zeros(6, 2);
            for (i, v) in [(0, 1.0), (1, 1.0), (3, 1.0), (4, -1.0)] {
                s[(i, 0)] = v;
            }
            with_n(
                example(id, a, b, weight(&c, &eye(2)), diag(&[3.0, 1.0]), None),
                s,
            )
        }
        // Patnaik et al. 1980 (ammonia reactor, discrete): C picks x₁, x₅; Q₀ = 50 I.
        (1, 10) => {
            let mut f = FortranData::load("BB02110.dat");
            let a = f.matrix(9, 9);
            let b = f.matrix(9, 3);
            let mut c = Mat::zeros(2, 9);
            c[(0, 0)] = 1.0;
            c[(1, 4)] = 1.0;
            example(id, a, b, weight(&c, &(eye(2) * 50.0)), eye(3), None)
        }
        // Sima 1996, Sec. 1.2.2: paper machine model with error integrators.
        (1, 11) => {
            let mut f = FortranData::load("BB02111.dat");
            let mut a = f.matrix(11, 11);
            let b = f.matrix(11, 2);
            a[(9, 9)] = 1.0;
            a[(10, 10)] = 1.0;
            let quality = [(0, 5, 15.0), (1, 6, 7.0), (1, 7, -5.357), (1, 8, -3.943)];
            paper_machine(id, a, b, &quality)
        }
        // Sima 1996, Ex. 2.6: paper machine model with disturbances.
        (1, 12) => {
            let mut a = Mat::zeros(13, 13);
            for i in 0..10 {
                a[(i, i + 1)] = 1.0;
            }
            a[(5, 6)] = 0.0;
            a[(7, 8)] = 0.0;
            a[(11, 11)] = 1.0;
            a[(12, 12)] = 1.0;
            a[(11, 0)] = -3.318;
            a[(12, 0)] = -1.5484;
            a[(5, 5)] = 0.7788;
            a[(7, 6)] = -0.4724;
            a[(12, 6)] = 0.3981;
            a[(7, 7)] = 1.3746;
            a[(12, 7)] = 0.5113;
            a[(12, 8)] = 5.7865;
            a[(10, 10)] = 0.8071;
            let mut b = Mat::zeros(13, 2);
            b[(5, 0)] = 1.0;
            b[(7, 1)] = 1.0;
            let quality = [
                (0, 0, 3.318),
                (1, 0, 1.5484),
                (1, 6, -0.3981),
                (1, 7, -0.5113),
                (1, 8, -5.7865),
            ];
            paper_machine(id, a, b, &quality)
        }
        // Laub 1979, Ex. 2 (discrete): X = t·Q₀ with t = (1 + sqrt(1 + 4 eps))/2, R = eps.
        (2, 1) => {
            let t = (1.0 + (1.0 + 4.0 * eps).sqrt()) / 2.0;
            let q0 = rows(2, 2, &[9.0, 6.0, 6.0, 4.0]);
            example(
                format!("{id} (eps = {eps:e})"),
                rows(2, 2, &[4.0, 3.0, -4.5, -3.5]),
                rows(2, 1, &[1.0, -1.0]),
                q0.clone(),
                eye(1) * eps,
                Some(q0 * t),
            )
        }
        // Laub 1979, Ex. 3: increasingly ill-conditioned R = diag(1/(3eps), 3eps).
        (2, 2) => example(
            format!("{id} (eps = {eps:e})"),
            diag(&[0.9512, 0.9048]),
            rows(2, 2, &[4.877, 4.877, -1.1895, 3.569]),
            diag(&[0.005, 0.02]),
            diag(&[1.0 / (3.0 * eps), 3.0 * eps]),
            None,
        ),
        // Increasingly badly scaled as eps → ∞: X = diag(1, 1 + eps²).
        (2, 3) => example(
            format!("{id} (eps = {eps:e})"),
            rows(2, 2, &[0.0, eps, 0.0, 0.0]),
            rows(2, 1, &[0.0, 1.0]),
            eye(2),
            eye(1),
            Some(diag(&[1.0, 1.0 + eps * eps])),
        ),
        // Petkov et al. 1989: A = V diag(0, 1, 3) V, B = I, R = eps I, Q = eps V V = eps I.
        (2, 4) => {
            let v = v3();
            let xd = diag(&[
                eps,
                eps * (1.0 + 5f64.sqrt()) / 2.0,
                eps * (9.0 + 85f64.sqrt()) / 2.0,
            ]);
            example(
                format!("{id} (eps = {eps:e})"),
                &v * diag(&[0.0, 1.0, 3.0]) * &v,
                eye(3),
                weight(&v, &(eye(3) * eps)),
                eye(3) * eps,
                Some(&v * xd * &v),
            )
        }
        // Pappas et al. 1980: paper machine process control; tau = eps, D = K = 1, r = 0.25.
        (2, 5) => {
            let (d, k, r) = (1.0, 1.0, 0.25);
            let t = d / eps;
            let beta = k * t;
            let alpha = 1.0 - t;
            let mut a = Mat::zeros(4, 4);
            a[(0, 0)] = alpha;
            for i in 0..3 {
                a[(i + 1, i)] = 1.0;
            }
            let mut b = Mat::zeros(4, 1);
            b[(0, 0)] = beta;
            let mut c = Mat::zeros(1, 4);
            c[(0, 3)] = 1.0;
            let b2 = beta * beta;
            let tt = r * (alpha + 1.0) * (alpha - 1.0) + b2;
            let x11 = (tt + (tt * tt + 4.0 * b2 * r).sqrt()) / 2.0 / b2;
            example(
                format!("{id} (tau = {eps:e})"),
                a,
                b,
                weight(&c, &eye(1)),
                eye(1) * r,
                Some(diag(&[x11, 1.0, 1.0, 1.0])),
            )
        }
        // Pappas et al. 1980, Ex. 3: a shift register of order n, R = eps: X = diag(1, …, n).
        (4, 1) => {
            let n = size.unwrap_or(100);
            let mut a = Mat::zeros(n, n);
            for i in 0..n - 1 {
                a[(i, i + 1)] = 1.0;
            }
            let mut b = Mat::zeros(n, 1);
            b[(n - 1, 0)] = 1.0;
            let x = Mat::from_fn(n, n, |i, j| if i == j { (i + 1) as f64 } else { 0.0 });
            example(
                format!("{id} (n = {n}, r = {eps:e})"),
                a,
                b,
                eye(n),
                eye(1) * eps,
                Some(x),
            )
        }
        _ => panic!("no DAREX example {group}.{number}"),
    }
}
