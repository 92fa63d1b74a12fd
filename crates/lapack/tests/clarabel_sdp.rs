//! Clarabel's semidefinite path running on this crate's symbols.
//!
//! - Clarabel's own SDP tests (`tests/basic_sdp.rs`, `tests/sdp_chordal.rs` of Clarabel 0.11)
//!   with their documented reference answers;
//! - Clarabel's SDP example (`examples/rust/example_sdp.rs`) against its closed form;
//! - projections onto the PSD cone of size 8 and 12 (large enough that Clarabel takes the
//!   BLAS/LAPACK code paths rather than its 1×1–3×3 special cases), against a closed form
//!   built from an exactly known eigendecomposition.
//!
//! Tolerances: Clarabel stops at relative gap / residuals 1e-8 (its defaults), which bounds
//! the solution error by roughly 1e-7 on these well-conditioned problems; 1e-6 is the bound
//! Clarabel's own tests use.

use clarabel::algebra::*;
use clarabel::solver::*;
use pendulab_lapack as _;

const SQRT2: f64 = std::f64::consts::SQRT_2;

fn quiet() -> DefaultSettings<f64> {
    DefaultSettingsBuilder::default()
        .verbose(false)
        .build()
        .unwrap()
}

fn basic_sdp_data() -> (CscMatrix<f64>, Vec<f64>, CscMatrix<f64>, Vec<f64>) {
    let p = CscMatrix::identity(6);
    let a = CscMatrix::identity(6);
    let c = vec![0.0; 6];
    let b = vec![-3., 1., 4., 1., 2., 5.];
    (p, c, a, b)
}

#[test]
fn clarabel_basic_sdp_gives_its_documented_answer() {
    let (p, c, a, b) = basic_sdp_data();
    let cones = [PSDTriangleConeT(3)];
    let mut solver = DefaultSolver::new(&p, &c, &a, &b, &cones, quiet()).unwrap();
    solver.solve();
    // Reference values from Clarabel's tests/basic_sdp.rs.
    let refsol = [
        -3.0729833267361095,
        0.3696004167288786,
        -0.022226685581313674,
        0.31441213129613066,
        -0.026739700851545107,
        -0.016084530571308823,
    ];
    let refobj = 4.840076866013861;
    assert_eq!(solver.solution.status, SolverStatus::Solved);
    let dist: f64 = solver
        .solution
        .x
        .iter()
        .zip(refsol)
        .map(|(x, r)| (x - r).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(dist <= 1e-6, "{dist:e}");
    assert!((solver.info.cost_primal - refobj).abs() <= 1e-6);
}

#[test]
fn clarabel_basic_sdp_detects_primal_infeasibility() {
    // Clarabel's test_sdp_primal_infeasible: X ⪰ B and X ⪯ 0 with B having a positive
    // eigenvalue (b encodes B = [[-3, 1/√2, 1/√2], [., 4, √2], [., ., 5]] in svec form).
    let (p, c, a, mut b) = basic_sdp_data();
    let mut a2 = a.clone();
    a2.negate();
    let a = CscMatrix::vcat(&a, &a2).unwrap();
    b.extend(vec![0.0; 6]);
    let cones = [PSDTriangleConeT(3), PSDTriangleConeT(3)];
    let mut solver = DefaultSolver::new(&p, &c, &a, &b, &cones, quiet()).unwrap();
    solver.solve();
    assert_eq!(solver.solution.status, SolverStatus::PrimalInfeasible);
}

#[test]
fn clarabel_chordal_sdp_solves_with_every_decomposition_setting() {
    // Clarabel's tests/sdp_chordal.rs: a 6×6 PSD cone with a chordal sparsity pattern plus a
    // nonnegative and two power cones, for every chordal-decomposition option.
    let p = CscMatrix::<f64>::zeros((8, 8));
    let q = vec![-1.0, -0.0, -0.0, -0.0, -0.0, -0.0, -0.0, -0.0];
    let a = CscMatrix {
        m: 28,
        n: 8,
        colptr: vec![0, 1, 4, 5, 8, 9, 10, 13, 16],
        rowval: vec![24, 7, 10, 22, 8, 12, 15, 25, 9, 13, 18, 21, 26, 0, 23, 27],
        nzval: vec![
            -1.0, -SQRT2, -1.0, -1.0, -SQRT2, -SQRT2, -1.0, -1.0, -SQRT2, -SQRT2, -SQRT2, -1.0,
            -1.0, -1.0, -1.0, -1.0,
        ],
    };
    let mut b = vec![0.0; 28];
    b[1] = 3.0;
    b[2] = 2.0 * SQRT2;
    b[3] = 2.0;
    b[4] = SQRT2;
    b[5] = SQRT2;
    b[6] = 3.0;
    let cones = [
        NonnegativeConeT(1),
        PSDTriangleConeT(6),
        PowerConeT(1.0 / 3.0),
        PowerConeT(0.5),
    ];
    for compact in [false, true] {
        for complete_dual in [false, true] {
            for merge in ["clique_graph", "parent_child", "none"] {
                let settings = DefaultSettingsBuilder::default()
                    .verbose(false)
                    .chordal_decomposition_enable(true)
                    .chordal_decomposition_compact(compact)
                    .chordal_decomposition_complete_dual(complete_dual)
                    .chordal_decomposition_merge_method(merge.to_string())
                    .max_iter(50)
                    .build()
                    .unwrap();
                let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings).unwrap();
                solver.solve();
                assert_eq!(
                    solver.solution.status,
                    SolverStatus::Solved,
                    "compact {compact}, complete_dual {complete_dual}, merge {merge}"
                );
            }
        }
    }
}

/// Column-major upper-triangle index of (i, j), i ≤ j, in Clarabel's svec layout.
fn svec_index(i: usize, j: usize) -> usize {
    j * (j + 1) / 2 + i
}

/// svec of a symmetric n × n matrix (Clarabel's scaling: off-diagonals × √2).
fn svec(m: &[Vec<f64>]) -> Vec<f64> {
    let n = m.len();
    let mut v = vec![0.0; n * (n + 1) / 2];
    for j in 0..n {
        for i in 0..=j {
            v[svec_index(i, j)] = if i == j { m[i][j] } else { SQRT2 * m[i][j] };
        }
    }
    v
}

#[test]
fn clarabel_sdp_example_reaches_its_closed_form_optimum() {
    // examples/rust/example_sdp.rs: minimise tr X subject to ⟨C, X⟩ = 1, X ⪰ 0, with
    // C = [[1, 2, 4], [2, 3, 5], [4, 5, 6]] (the last row of A is svec(C) in unscaled form).
    // Optimum: 1 / λ_max(C), attained at X = v vᵀ / λ_max.
    let nvec = 6;
    let p = CscMatrix::<f64>::zeros((nvec, nvec));
    let q = vec![1., 0., 1., 0., 0., 1.];
    let a = CscMatrix::from(&[
        [-1., 0., 0., 0., 0., 0.],
        [0., -SQRT2, 0., 0., 0., 0.],
        [0., 0., -1., 0., 0., 0.],
        [0., 0., 0., -SQRT2, 0., 0.],
        [0., 0., 0., 0., -SQRT2, 0.],
        [0., 0., 0., 0., 0., -1.],
        [1., 4., 3., 8., 10., 6.],
    ]);
    let mut b = vec![0.0; 6];
    b.push(1.0);
    let cones = [PSDTriangleConeT(3), ZeroConeT(1)];
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, quiet()).unwrap();
    solver.solve();
    assert_eq!(solver.solution.status, SolverStatus::Solved);
    // λ_max of C by power iteration (C is positive on its dominant direction; 200 steps of
    // power iteration converge far below 1e-12 for this gap, λ2/λ1 ≈ 0.1).
    let cm = [[1.0, 2.0, 4.0], [2.0, 3.0, 5.0], [4.0, 5.0, 6.0]];
    let mut v = [1.0, 1.0, 1.0];
    let mut lam = 0.0;
    for _ in 0..200 {
        let w: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| cm[i][j] * v[j]).sum())
            .collect();
        lam = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        for i in 0..3 {
            v[i] = w[i] / lam;
        }
    }
    let expect = 1.0 / lam;
    assert!(
        (solver.solution.obj_val - expect).abs() <= 1e-6,
        "{} vs {}",
        solver.solution.obj_val,
        expect
    );
}

/// B = Q diag(d) Qᵀ with Q = I − 2 u uᵀ / uᵀu (a Householder reflector, exactly orthogonal).
fn known_eigendecomposition(d: &[f64]) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let n = d.len();
    let u: Vec<f64> = (0..n).map(|i| 1.0 + 0.37 * i as f64).collect();
    let uu: f64 = u.iter().map(|x| x * x).sum();
    let q: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| (if i == j { 1.0 } else { 0.0 }) - 2.0 * u[i] * u[j] / uu)
                .collect()
        })
        .collect();
    let build = |f: &dyn Fn(f64) -> f64| -> Vec<Vec<f64>> {
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| (0..n).map(|k| q[i][k] * f(d[k]) * q[j][k]).sum())
                    .collect()
            })
            .collect()
    };
    (build(&|x| x), build(&|x| x.min(0.0)))
}

#[test]
fn clarabel_projects_onto_large_psd_cones_through_the_blas_path() {
    for n in [8usize, 12] {
        // Eigenvalues of mixed sign, well separated.
        let d: Vec<f64> = (0..n)
            .map(|k| (k as f64) - (n as f64) / 2.0 + 0.5)
            .collect();
        let (b_mat, neg_part) = known_eigendecomposition(&d);
        // minimise ½‖x‖² s.t. x + s = svec(B), s ∈ S₊: x = svec(B₋), B₋ = Q min(D, 0) Qᵀ.
        let nvec = n * (n + 1) / 2;
        let p = CscMatrix::identity(nvec);
        let a = CscMatrix::identity(nvec);
        let q = vec![0.0; nvec];
        let b = svec(&b_mat);
        let cones = [PSDTriangleConeT(n)];
        let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, quiet()).unwrap();
        solver.solve();
        assert_eq!(solver.solution.status, SolverStatus::Solved, "n = {n}");
        let expect = svec(&neg_part);
        let err = solver
            .solution
            .x
            .iter()
            .zip(&expect)
            .map(|(x, e)| (x - e).abs())
            .fold(0.0, f64::max);
        assert!(err <= 1e-6, "n = {n}: max error {err:e}");
        let obj: f64 = 0.5 * d.iter().map(|x| x.min(0.0).powi(2)).sum::<f64>();
        assert!((solver.info.cost_primal - obj).abs() <= 1e-6 * obj.max(1.0));
    }
}
