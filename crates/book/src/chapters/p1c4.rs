//! Part 1 chapter 4: state space, time responses and stability (book §4.1–4.3).

use super::common::*;
use super::mfile_refs::no_display_note;
use crate::error::BookError;
use crate::output::{ExampleOutput, Value};
use crate::registry::{Example, RunContext};
use pendulab_lti::equations::lyapunov::lyap;
use pendulab_lti::linalg::{eigenvalues, symmetric_eigenvalues};
use pendulab_lti::response::{initial, lsim};
use pendulab_lti::{LsimOptions, Mat, StateSpace};
use pendulab_plants::CartPendulumParams;
use pendulab_plot::{Figure, Surface};

/// The chapter's examples, in book order.
pub(crate) fn examples() -> Vec<Example> {
    vec![
        Example {
            id: "p1c41_cdip_response",
            title: "Zero-input, zero-state and full response of the P-controlled cart (superposition)",
            section: "Part 1 §4.1",
            parameters: "cart drive a_c = 6.25, b_c = 4.36 (table 3.5), k_P = 1",
            needs_data: None,
            run: p1c41_cdip_response,
        },
        Example {
            id: "p1c43_stability1",
            title: "Stability from the eigenvalues (an unstable 5×5 example)",
            section: "Part 1 §4.3",
            parameters: "the book's matrix A (5×5)",
            needs_data: None,
            run: p1c43_stability1,
        },
        Example {
            id: "p1c43_stability2",
            title: "Lyapunov equation PA + AᵀP = −I and stability",
            section: "Part 1 §4.3",
            parameters: "the book's matrix A (5×5)",
            needs_data: None,
            run: p1c43_stability2,
        },
        Example {
            id: "p1c43_lyapunov_func",
            title: "The Lyapunov function V = x1² + x2² as a surface",
            section: "Part 1 §4.3",
            parameters: "V(x) = x1² + x2² on [−5, 5]²",
            needs_data: None,
            run: p1c43_lyapunov_func,
        },
    ]
}

const ID41: &str = "p1c41_cdip_response";

fn p1c41_cdip_response(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let e = ID41;
    let p = CartPendulumParams::book();
    let (ac, bc, kp) = (p.a_c, p.b_c, 1.0);
    // Eq. 4.22: x = [z, ż], r the reference, y = z scaled as the book writes C = [b_c k_P, 0].
    let a = Mat::from_row_slice(2, 2, &[0.0, 1.0, -bc * kp, -ac]);
    let b = Mat::from_row_slice(2, 1, &[0.0, 1.0]);
    let c = Mat::from_row_slice(1, 2, &[bc * kp, 0.0]);
    let sys = StateSpace::continuous(a.clone(), b, c, Mat::zeros(1, 1)).ctx(e)?;
    let t: Vec<f64> = (0..=1000).map(|k| k as f64 * 0.01).collect();
    let r = Mat::from_fn(t.len(), 1, |k, _| 2.0 * t[k].sin());
    let x0 = [1.0, 1.0];
    let opts = LsimOptions::default();
    let y1 = initial(&sys, &x0, &t).ctx(e)?;
    let y2 = lsim(&sys, &r, &t, None, &opts).ctx(e)?;
    let y3 = lsim(&sys, &r, &t, Some(&x0), &opts).ctx(e)?;
    let (s1, s2, s3) = (y1.y_signal(0), y2.y_signal(0), y3.y_signal(0));
    let err = s1
        .iter()
        .zip(s2)
        .zip(s3)
        .map(|((a, b), c)| (c - a - b).abs())
        .fold(0.0, f64::max);
    let mut out = ExampleOutput::default();
    out.value("eig", Value::Complex(sorted(eigenvalues(&a).ctx(e)?)));
    out.value("max_superposition_error", Value::Number(err));
    out.notes.push(
        "y1 = initial(G, x0, t), y2 = lsim(G, 2 sin t, t), y3 = lsim(G, 2 sin t, t, x0) with the \
         exact zero-order-hold discretisation; y3 = y1 + y2 holds to rounding (eq. 4.24)."
            .into(),
    );
    if ctx.figures {
        let fig = stacked(
            "p1c41_cdip_response: y3(t) = y1(t) + y2(t)",
            "time [s]",
            vec![PanelSpec::new(
                "position [m]",
                vec![
                    ("y1(t) zero-input".into(), &t, s1.to_vec()),
                    ("y2(t) zero-state".into(), &t, s2.to_vec()),
                    ("y3(t) full".into(), &t, s3.to_vec()),
                ],
            )],
        );
        write_figure(&mut out, "p1c41_cdip_response_y", fig);
    }
    no_display_note(
        &mut out,
        "p1c41_cdip_respose",
        "it draws the initial-value and sine responses of G(s)",
    );
    Ok(out)
}

/// The matrix of `p1c43_stability1` (book §4.3).
fn a_stability1() -> Mat {
    Mat::from_row_slice(
        5,
        5,
        &[
            0.0, -1.0, 0.0, 0.0, -1.0, //
            1.0, 0.0, 0.0, 1.0, 0.0, //
            1.0, 1.0, 1.0, 0.0, 1.0, //
            0.0, 1.0, -1.0, 1.0, 0.0, //
            1.0, 1.0, 1.0, 1.0, -1.0,
        ],
    )
}

/// The matrix of `p1c43_stability2` (book §4.3).
fn a_stability2() -> Mat {
    Mat::from_row_slice(
        5,
        5,
        &[
            -1.0, -1.0, -1.0, -1.0, 0.0, //
            1.0, -1.0, -1.0, 0.0, -1.0, //
            1.0, 0.0, 0.0, -1.0, 0.0, //
            1.0, -1.0, 1.0, 0.0, -1.0, //
            -1.0, 1.0, -1.0, 1.0, 0.0,
        ],
    )
}

fn eig_figure(title: &str, ev: &[pendulab_lti::Complex64]) -> Figure {
    pendulab_plot::PoleZeroMap::new()
        .poles("eig(A)", ev)
        .title(title)
        .figure()
}

const ID431: &str = "p1c43_stability1";

fn p1c43_stability1(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let e = ID431;
    let a = a_stability1();
    let ev = eigenvalues(&a).ctx(e)?;
    // Asymptotically stable iff every eigenvalue has a negative real part (theorem 4.2).
    let stable = ev.iter().all(|z| z.re < 0.0);
    let mut out = ExampleOutput::default();
    out.value("eig", Value::Complex(sorted(ev.clone())));
    out.value("stable", Value::Bool(stable));
    // Printed to three decimals: half a unit of the last digit, on the complex modulus of the
    // difference (0.0005·√2 covers both parts rounded).
    out.reference(
        "eig",
        Value::Complex(complex(&[
            (1.0, 0.0),
            (0.906, 0.934),
            (0.906, -0.934),
            (-0.426, 0.0),
            (-1.387, 0.0),
        ])),
        "book Part 1 §4.3",
        0.0005 * std::f64::consts::SQRT_2,
    );
    out.reference("stable", Value::Bool(false), "book Part 1 §4.3", 0.0);
    if ctx.figures {
        let fig = eig_figure("p1c43_stability1: eigenvalues of A (not stable)", &ev);
        write_figure(&mut out, "p1c43_stability1_eig", fig);
    }
    Ok(out)
}

const ID432: &str = "p1c43_stability2";

fn p1c43_stability2(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let e = ID432;
    let a = a_stability2();
    // PA + AᵀP = −I is lyap(Aᵀ, I): Aᵀ P + P A + I = 0.
    let sol = lyap(&a.transpose(), &Mat::identity(5, 5)).ctx(e)?;
    if sol.residual > 1e-10 {
        return Err(fail(
            ID432,
            format!("Lyapunov residual {:.2e} too large", sol.residual),
        ));
    }
    let p_eig = symmetric_eigenvalues(&sol.x);
    let ev = eigenvalues(&a).ctx(e)?;
    let mut out = ExampleOutput::default();
    out.value("eig", Value::Complex(sorted(ev.clone())));
    out.value("P_eig", Value::Vector(p_eig.clone()));
    out.value("P", Value::matrix(&sol.x));
    out.value("lyapunov_residual", Value::Number(sol.residual));
    out.value("P_positive_definite", Value::Bool(p_eig[0] > 0.0));
    out.reference(
        "eig",
        Value::Complex(complex(&[
            (-0.0220, 1.8470),
            (-0.0220, -1.8470),
            (-0.4085, 0.0),
            (-0.7737, 1.5071),
            (-0.7737, -1.5071),
        ])),
        "book p. 74 (eig(A), format short)",
        0.00005 * std::f64::consts::SQRT_2,
    );
    // Printed to three decimals (the two largest to two): the looser half unit for all.
    out.reference(
        "P_eig",
        Value::Vector(vec![0.505, 0.650, 2.247, 45.22, 61.13]),
        "book Part 1 §4.3",
        0.005,
    );
    out.notes.push(
        "P solves PA + AᵀP = −I (Bartels–Stewart); P ≻ 0 proves asymptotic stability \
         (theorem 4.3), as the eigenvalues of A confirm."
            .into(),
    );
    if ctx.figures {
        let fig = eig_figure("p1c43_stability2: eigenvalues of A (stable)", &ev);
        write_figure(&mut out, "p1c43_stability2_eig", fig);
    }
    Ok(out)
}

const ID433: &str = "p1c43_lyapunov_func";

fn p1c43_lyapunov_func(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let n = 41;
    let grid: Vec<f64> = (0..n)
        .map(|k| -5.0 + 10.0 * k as f64 / (n - 1) as f64)
        .collect();
    let mut vmin = f64::INFINITY;
    let mut vmax = f64::NEG_INFINITY;
    let mut z = Vec::with_capacity(n * n);
    for &x2 in &grid {
        for &x1 in &grid {
            let v = x1 * x1 + x2 * x2;
            vmin = vmin.min(v);
            vmax = vmax.max(v);
            z.push(v);
        }
    }
    let mut out = ExampleOutput::default();
    out.value("V_min", Value::Number(vmin));
    out.value("V_max", Value::Number(vmax));
    out.notes.push(
        "V(x) = x1² + x2² is positive definite (zero only at the origin) and radially \
         unbounded: the bowl drawn in the book."
            .into(),
    );
    if ctx.figures {
        let s = Surface::new(&grid, &grid, &z)
            .labels("x1", "x2", "V(x)")
            .title("p1c43_lyapunov_func: V(x) = x1² + x2²");
        let fig = Figure::new(s).size(640.0, 520.0);
        write_figure(&mut out, &format!("{ID433}_surface"), fig);
    }
    no_display_note(
        &mut out,
        "p1c43_lyapunov_func",
        "it draws the surface V(x) = x1² + x2²",
    );
    Ok(out)
}
