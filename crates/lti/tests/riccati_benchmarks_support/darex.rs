//! The DAREX collection (discrete-time algebraic Riccati equations, Benner, Laub & Mehrmann
//! SPC 95_23; version 2.0, SLICOT Working Note 1999-16): the data of each example and, where
//! the collection gives one, the closed-form stabilising solution.

use pendulab_lti::Mat;

use super::{Example, FortranData, diag, example, eye, packed_lower, rows, v3, weight};

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
