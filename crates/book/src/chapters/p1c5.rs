//! Part 1 chapter 5 — controllability, pole placement, LQR.
//!
//! Gains are reported in the book's convention `u = +K x` (pendulab's library uses
//! `u = −K x`; `K_book = −K`).

use super::common::*;
use super::mfile_refs::{OctaveDisplay, display_note, symbolic_note};
use crate::error::{BookError, Cause};
use crate::output::{ExampleOutput, Value};
use crate::registry::{Example, RunContext};
use pendulab_lti::analysis::{controllable_canonical_form, ctrb, rank};
use pendulab_lti::design::{StateFeedback, lqr, place};
use pendulab_lti::{Continuous, Mat, StateSpace, Trajectory};
use pendulab_plants::{
    ArmEquilibrium, ArmPendulum, ArmPendulumParams, Posture, RigSpec, TwoPendulumCart,
    TwoPendulumCartParams,
};
use pendulab_plot::{Axes, Channel, Color, Figure, PoleZeroMap, Scale, SignalPanel, TimeResponse};
use pendulab_sim::controllers::StaticStateFeedback;
use pendulab_sim::{SampledLoop, SampledOptions};
use std::f64::consts::PI;

const BOOK_CONVENTION: &str =
    "gains in the book's convention u = +K x (pendulab's library: u = −K x)";

/// The chapter's examples, in book order.
pub(crate) fn examples() -> Vec<Example> {
    vec![
        Example {
            id: "p1c511_ex1",
            title: "Controllability matrix of a 2-state system",
            section: "Part 1 §5.1.1, example 5.1",
            parameters: "A = [[1, 0], [1, 1]], B = [1; 1]",
            needs_data: None,
            run: ex1,
        },
        Example {
            id: "p1c511_ex2",
            title: "An uncontrollable 3-state system",
            section: "Part 1 §5.1.1, example 5.2",
            parameters: "A = [[a, 0, 0], [0, 0, 1], [0, 0, 0]], B = [0; 0; 1], a = 1",
            needs_data: None,
            run: ex2,
        },
        Example {
            id: "p1c511_ex3_adip",
            title: "Controllability of the arm pendulum against the arm angle",
            section: "Part 1 §5.1.1, example 5.3",
            parameters: "arm pendulum, table 3.7, linearised at θ1 = θ1e, θ2 = 0",
            needs_data: None,
            run: ex3_adip,
        },
        Example {
            id: "p1c511_ex4_cdip",
            title: "A cart with two parallel pendulums",
            section: "Part 1 §5.1.1, example 5.4",
            parameters: "cart pendulum, table 3.5; pendulum 2 scaled by 1.2 (or identical)",
            needs_data: None,
            run: ex4_cdip,
        },
        Example {
            id: "p1c512_ex5",
            title: "Controllable canonical form of example 5.1",
            section: "Part 1 §5.1.2, example 5.5",
            parameters: "A = [[1, 0], [1, 1]], B = [1; 1]",
            needs_data: None,
            run: ex5,
        },
        Example {
            id: "p1c522_ex6",
            title: "Pole placement by coefficient matching",
            section: "Part 1 §5.2.2, example 5.6",
            parameters: "A = [[1, 0], [1, 1]], B = [1; 1], poles {−1, −2}",
            needs_data: None,
            run: ex6,
        },
        Example {
            id: "p1c522_ex7_adip_place",
            title: "Pole placement for the arm pendulum at θ1e = π/4",
            section: "Part 1 §5.2.2, example 5.7",
            parameters: "arm pendulum, table 3.7, θ1e = π/4, poles {−2, −2.5, −3, −3.5}",
            needs_data: None,
            run: ex7_adip_place,
        },
        Example {
            id: "p1c523_ex8_adip_lqr",
            title: "LQR for the arm pendulum at θ1e = π/4",
            section: "Part 1 §5.2.3, example 5.8",
            parameters: "arm pendulum, table 3.7, θ1e = π/4; nonlinear plant, filtered derivatives, 1 ms",
            needs_data: None,
            run: ex8_adip_lqr,
        },
    ]
}

fn m(r: usize, c: usize, v: &[f64]) -> Mat {
    Mat::from_row_slice(r, c, v)
}

fn ex1(_ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p1c511_ex1";
    let mc = ctrb(&m(2, 2, &[1.0, 0.0, 1.0, 1.0]), &m(2, 1, &[1.0, 1.0])).ctx(id)?;
    let mut out = ExampleOutput::default();
    out.value("Mc", Value::matrix(&mc))
        .value("rank", Value::Number(rank(&mc).rank as f64));
    // Exact small integers: the products of integer matrices are exact in floating point.
    exact_references(
        &mut out,
        "book Part 1 §5.1.1, example 5.1",
        [
            ("Mc", Value::Matrix(vec![vec![1.0, 1.0], vec![1.0, 2.0]])),
            ("rank", Value::Number(2.0)),
        ],
    );
    out.notes
        .push("M_c = [B, AB] has full rank 2: the pair is controllable.".into());
    Ok(out)
}

fn ex2(_ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p1c511_ex2";
    let a = m(3, 3, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
    let b = m(3, 1, &[0.0, 0.0, 1.0]);
    let mc = ctrb(&a, &b).ctx(id)?;
    let mut out = ExampleOutput::default();
    out.value("Mc", Value::matrix(&mc))
        .value("rank", Value::Number(rank(&mc).rank as f64));
    exact_references(
        &mut out,
        "book Part 1 §5.1.1, example 5.2",
        [("rank", Value::Number(2.0))],
    );
    // The M-file's symbolic Mc = [B, AB, A²B] (line 11): B = e3, AB = e2, A²B = A e2 = 0 for
    // every a, so its display is this integer matrix whatever a is.
    out.reference(
        "Mc",
        Value::Matrix(vec![
            vec![0.0, 0.0, 0.0],
            vec![0.0, 1.0, 0.0],
            vec![1.0, 0.0, 0.0],
        ]),
        "p1c511_ex2.m line 16 (symbolic; a drops out of [B, AB, A²B])",
        0.0,
    );
    out.notes.push(
        "The mode x1' = a x1 receives no input: rank M_c = 2 < 3, uncontrollable (a = 1).".into(),
    );
    symbolic_note(
        &mut out,
        id,
        "M_c = [B, AB, A²B] for a symbolic a, and its rank",
        "by computing M_c with a = 1: M_c does not depend on a (B = e3, AB = e2, A²B = 0), so the \
         M-file's displayed matrix and rank_Mc = 2 are compared exactly",
    );
    Ok(out)
}

/// det M_c of the arm model linearised at `θ1e`.
///
/// # Errors
/// The linearisation's [`Cause::Plant`] or the controllability matrix's [`Cause::Lti`].
pub(crate) fn arm_det_mc(plant: &ArmPendulum, theta1e: f64) -> Result<f64, Cause> {
    let sys = plant.linearize(ArmEquilibrium::upright(theta1e))?;
    let mc = ctrb(sys.a(), sys.b())?;
    Ok(mc.determinant())
}

fn ex3_adip(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p1c511_ex3_adip";
    let book = ArmPendulum::book();
    let frictionless = ArmPendulum::new(ArmPendulumParams {
        mu2: 0.0,
        ..ArmPendulumParams::book()
    })
    .ctx(id)?;
    let d0 = arm_det_mc(&book, 0.0).ctx(id)?;
    let d90 = arm_det_mc(&book, PI / 2.0).ctx(id)?;
    let d90_free = arm_det_mc(&frictionless, PI / 2.0).ctx(id)?;
    let mut out = ExampleOutput::default();
    out.value("det_Mc_at_0", Value::Number(d0))
        .value("det_Mc_at_pi_over_2", Value::Number(d90))
        .value("det_Mc_at_pi_over_2_mu2_zero", Value::Number(d90_free));
    out.notes.push(format!(
        "det M_c vanishes only where cos θ1e = 0 and μ2 = 0: with the book's μ2 = 1.01e-4 it is \
         {d90:.4e} at θ1e = π/2 (tiny against {d0:.4e} at 0), without friction {d90_free:.1e}."
    ));
    symbolic_note(
        &mut out,
        id,
        "det M_c of the arm model linearised at a symbolic θ1e (in α2, α3, α5, a1, b1, μ2) and \
         det_Mc_0, the same with μ2 = 0",
        "numerically: det M_c of the book's arm at θ1e = 0 and π/2, with and without μ2, here, \
         and in pendulab-plants' tests (arm.rs) against the closed form det M_c = α5 b1⁴/α2⁴ · \
         [μ2² (α2 + α3 cos θ1e) − α5 α3² cos² θ1e] at 25 angles for three parameter sets; the \
         M-file's conclusion, det_Mc_0 = 0 exactly where cos θ1e = 0, is what \
         det_Mc_at_pi_over_2_mu2_zero shows",
    );
    if ctx.figures {
        let th: Vec<f64> = (0..=360).map(|k| -PI + k as f64 * PI / 180.0).collect();
        let deg: Vec<f64> = th.iter().map(|t| t.to_degrees()).collect();
        let mut dets = Vec::with_capacity(th.len());
        let mut dets0 = Vec::with_capacity(th.len());
        for &t in &th {
            dets.push(arm_det_mc(&book, t).ctx(id)?);
            dets0.push(arm_det_mc(&frictionless, t).ctx(id)?);
        }
        let mut ax = Axes::new();
        ax.xlabel("arm angle θ1e [deg]").ylabel("det M_c");
        ax.plot(&deg, &dets)
            .label("μ2 = 1.01e-4 (book)")
            .color(Color::BLUE);
        ax.plot(&deg, &dets0)
            .label("μ2 = 0")
            .color(Color::RED)
            .dashed();
        ax.hline(0.0);
        ax.vline(90.0);
        ax.vline(-90.0);
        let abs: Vec<f64> = dets.iter().map(|d| d.abs()).collect();
        let abs0: Vec<f64> = dets0.iter().map(|d| d.abs().max(1e-30)).collect();
        let mut lg = Axes::new();
        lg.xlabel("arm angle θ1e [deg]")
            .ylabel("|det M_c|")
            .yscale(Scale::Log)
            .ylim(1e-2, 1e9);
        lg.plot(&deg, &abs)
            .label("μ2 = 1.01e-4 (book)")
            .color(Color::BLUE);
        lg.plot(&deg, &abs0)
            .label("μ2 = 0")
            .color(Color::RED)
            .dashed();
        let fig = Figure::column([ax, lg]).title("p1c511_ex3_adip: det M_c against θ1e");
        save_figure(ctx, &mut out, id, "det_mc", Ok(fig))?;
    }
    Ok(out)
}

fn ex4_cdip(_ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p1c511_ex4_cdip";
    let rank_of = |p: TwoPendulumCartParams| -> Result<usize, BookError> {
        let plant = TwoPendulumCart::new(p).ctx(id)?;
        let sys = plant
            .linearize(0.0, Posture::Upright, Posture::Upright)
            .ctx(id)?;
        let mc = ctrb(sys.a(), sys.b()).ctx(id)?;
        Ok(rank(&mc).rank)
    };
    let rd = rank_of(TwoPendulumCartParams::book_example())?;
    let ri = rank_of(TwoPendulumCartParams::identical())?;
    let plant = TwoPendulumCart::new(TwoPendulumCartParams::book_example()).ctx(id)?;
    let sys = plant
        .linearize(0.0, Posture::Upright, Posture::Upright)
        .ctx(id)?;
    let det_mcn = ctrb(sys.a(), sys.b()).ctx(id)?.determinant();
    let mut out = ExampleOutput::default();
    out.value("rank_different", Value::Number(rd as f64))
        .value("rank_identical", Value::Number(ri as f64))
        .value("det_Mcn", Value::Number(det_mcn));
    // The numeric part of the M-file (lines 48 on, after its symbolic part) displays
    // det_Mcn = det(ctrb(A, B)) of the 1.2-times pendulum (line 100), as GNU Octave printed
    // it running those lines unchanged; compared to MATLAB's short format (1.6650e+13).
    OctaveDisplay::parse(
        "p1c511_ex4_cdip",
        include_str!("../../tests/data/octave/p1c511_ex4_cdip_numeric.txt"),
    )
    .compare(
        id,
        &mut out,
        "det_Mcn",
        "det_Mcn",
        "line 100 (its numeric part, lines 48 on)",
    )?;
    display_note(
        &mut out,
        "p1c511_ex4_cdip",
        &["det_Mcn"],
        &[],
        &[(
            "det_Mc, det_Mc_same (lines 40, 43)",
            "formulas of the symbolic part, see the next note",
        )],
    );
    exact_references(
        &mut out,
        "book Part 1 §5.1.1, example 5.4 (controllable: full rank 6)",
        [("rank_different", Value::Number(6.0))],
    );
    out.notes.push(
        "Identical pendulums: θa − θb obeys an input-free second-order equation, so two \
         directions are uncontrollable (rank 4)."
            .into(),
    );
    symbolic_note(
        &mut out,
        id,
        "det M_c of the two-pendulum cart for symbolic pendulums (α1, α2, β1, β2) and \
         det_Mc_same, which is 0 when the pendulums are the same",
        "numerically: rank M_c = 6 for the book's 1.2-times pendulum (compared with the book) \
         and 4 for identical pendulums (det_Mc_same = 0 means rank < 6), and the numeric \
         det_Mcn that the M-file's last part displays (compared with its Octave run)",
    );
    Ok(out)
}

fn ex5(_ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p1c512_ex5";
    let sys = StateSpace::continuous(
        m(2, 2, &[1.0, 0.0, 1.0, 1.0]),
        m(2, 1, &[1.0, 1.0]),
        m(1, 2, &[1.0, 0.0]),
        Mat::zeros(1, 1),
    )
    .ctx(id)?;
    let f = controllable_canonical_form(&sys).ctx(id)?;
    let mut out = ExampleOutput::default();
    out.value("T", Value::matrix(&f.t))
        .value("A_hat", Value::matrix(f.system.a()));
    // Printed as exact integers; the transformation is computed to rounding (residual ≤ 1e-15
    // on this 2×2 system), so 1e-9 is generous and still far below any printed digit.
    out.reference(
        "T",
        Value::Matrix(vec![vec![-1.0, 1.0], vec![0.0, 1.0]]),
        "book Part 1 §5.1.2, example 5.5",
        1e-9,
    )
    .reference(
        "A_hat",
        Value::Matrix(vec![vec![0.0, 1.0], vec![-1.0, 2.0]]),
        "book Part 1 §5.1.2, example 5.5",
        1e-9,
    );
    out.notes
        .push("x = T x̂, Â = T⁻¹ A T, B̂ = T⁻¹ B = [0; 1].".into());
    Ok(out)
}

/// Pole placement for example 5.1 by coefficient matching in controllable canonical
/// coordinates: with `x = T x̂`, `det(sI − Â − B̂ K̂) = s² + (−a₁ − k̂₂) s + (−a₀ − k̂₁)`, so
/// `K̂ = [a₀ − d₀, a₁ − d₁]` for the desired `s² + d₁ s + d₀`, and `K = K̂ T⁻¹` (book
/// convention `u = +K x`).
fn ex6(_ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p1c522_ex6";
    let a = m(2, 2, &[1.0, 0.0, 1.0, 1.0]);
    let b = m(2, 1, &[1.0, 1.0]);
    let sys = StateSpace::continuous(a, b, m(1, 2, &[1.0, 0.0]), Mat::zeros(1, 1)).ctx(id)?;
    let f = controllable_canonical_form(&sys).ctx(id)?;
    // Desired (s + 1)(s + 2) = s² + 3 s + 2.
    let (d0, d1) = (2.0, 3.0);
    let c = &f.characteristic_coefficients;
    let k_hat = m(1, 2, &[c[0] - d0, c[1] - d1]);
    let t_inv =
        f.t.clone()
            .try_inverse()
            .ok_or_else(|| fail(id, "the canonical transformation T is singular"))?;
    let k = &k_hat * t_inv;
    // The closed loop A + BK (book sign) of the toolkit's state feedback.
    let closed = StateFeedback::from_book(&k)
        .ctx(id)?
        .closed_loop(&sys)
        .ctx(id)?;
    let poles = sorted(closed.poles().ctx(id)?);
    let mut out = ExampleOutput::default();
    out.value("K", Value::vector(&[k[(0, 0)], k[(0, 1)]]))
        .value("K_hat", Value::vector(&[k_hat[(0, 0)], k_hat[(0, 1)]]))
        .value("poles", Value::Complex(poles));
    // (s + 1)(s + 2) assigned: eigenvalues of a 2×2 with distinct real roots, to rounding.
    out.reference(
        "poles",
        Value::Complex(complex(&[(-1.0, 0.0), (-2.0, 0.0)])),
        "design specification",
        1e-9,
    );
    // The M-file's symbolic solution (line 29): k1 = s1 s2 − 1, k2 = s1 + s2 − s1 s2 − 1.
    let (s1, s2) = (-1.0, -2.0);
    out.reference(
        "K",
        Value::Vector(vec![s1 * s2 - 1.0, s1 + s2 - s1 * s2 - 1.0]),
        "p1c522_ex6.m line 29 (solve), at s1 = −1, s2 = −2",
        1e-9,
    );
    out.notes.push(format!(
        "The book solves det(λI − A − BK) = (λ − s1)(λ − s2) symbolically: k1 = s1 s2 − 1, \
         k2 = s1 + s2 − s1 s2 − 1. Shown for s1 = −1, s2 = −2 (the book keeps them symbolic), \
         through the controllable canonical form. {BOOK_CONVENTION}."
    ));
    symbolic_note(
        &mut out,
        id,
        "det(λI − (A + BK)) for symbolic k1, k2 and its coefficients, (λ − s1)(λ − s2) and \
         its coefficients, and k1, k2 by equating them (solve)",
        "at s1 = −1, s2 = −2: K from the controllable canonical form equals the M-file's \
         solution k1 = s1 s2 − 1 = 1, k2 = s1 + s2 − s1 s2 − 1 = −6, and the closed loop's \
         poles are the assigned ones (both compared)",
    );
    Ok(out)
}

fn arm_at(id: &str, theta1e: f64) -> Result<StateSpace<Continuous>, BookError> {
    ArmPendulum::book()
        .linearize(ArmEquilibrium::upright(theta1e))
        .ctx(id)
}

fn ex7_adip_place(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p1c522_ex7_adip_place";
    let sys = arm_at(id, PI / 4.0)?;
    let want = complex(&[(-2.0, 0.0), (-2.5, 0.0), (-3.0, 0.0), (-3.5, 0.0)]);
    let pl = place(sys.a(), sys.b(), &want).ctx(id)?;
    let mut out = ExampleOutput::default();
    out.value("K", Value::vector(&book_row(&pl.gain)))
        .value("poles", Value::Complex(pl.achieved_poles.clone()));
    out.reference(
        "poles",
        Value::Complex(sorted(want)),
        "book Part 1 §5.2.2, example 5.7 (design poles)",
        1e-6,
    );
    // Line 20 displays K = −place(A, B, s), as GNU Octave printed it running the M-file (one
    // input: the gain that places the poles is unique).
    OctaveDisplay::parse(
        id,
        include_str!("../../tests/data/octave/p1c522_ex7_adip_place.txt"),
    )
    .compare(id, &mut out, "K", "K", "line 20")?;
    display_note(&mut out, id, &["K"], &[], &[]);
    out.notes.push(BOOK_CONVENTION.into());
    if ctx.figures {
        let open = sorted(sys.poles().ctx(id)?);
        let fig = PoleZeroMap::new()
            .poles("open loop", &open)
            .poles("A + BK", &pl.achieved_poles)
            .title("p1c522_ex7_adip_place: poles at θ1e = π/4")
            .figure();
        save_figure(ctx, &mut out, id, "poles", Ok(fig))?;
    }
    Ok(out)
}

/// The three LQR designs of example 5.8: `(label, Q diagonal, R)`.
pub(crate) const EX8_CASES: [(&str, [f64; 4], f64); 3] = [
    ("case1", [10.0, 10.0, 1.0, 1.0], 1.0),
    ("case2", [10.0, 10.0, 1.0, 1.0], 10.0),
    ("case3", [20.0, 10.0, 1.0, 1.0], 1.0),
];

fn ex8_adip_lqr(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p1c523_ex8_adip_lqr";
    let theta1e = PI / 4.0;
    let sys = arm_at(id, theta1e)?;
    let mut out = ExampleOutput::default();
    let mut runs: Vec<(String, Trajectory)> = Vec::new();
    let rig = filtered_rig(id, &RigSpec::arm())?;
    for (case, q, r) in EX8_CASES {
        let l = lqr(&sys, &diag(&q), &diag(&[r]), None).ctx(id)?;
        out.value(&format!("K_{case}"), Value::vector(&book_row(&l.gain)));
        // u = −K (y − x_e): the arm is driven from θ1 = 0 to the equilibrium θ1e = π/4.
        let ctrl = StaticStateFeedback::new(l.gain.clone())
            .and_then(|c| c.with_reference(&[theta1e, 0.0, 0.0, 0.0]))
            .ctx(id)?;
        let opts = SampledOptions {
            t_final: 3.0,
            ..Default::default()
        };
        let mut lp = SampledLoop::new(ArmPendulum::book(), ctrl, opts)
            .and_then(|l| l.with_rig(rig.clone()))
            .ctx(id)?;
        let run = lp.run(&[0.0, 0.0, 0.0, 0.0]).ctx(id)?;
        let th1 = column(run.trajectory.x(), 0);
        let th2 = column(run.trajectory.x(), 1);
        out.value(
            &format!("theta1_final_deg_{case}"),
            Value::Number(th1.last().copied().unwrap_or(f64::NAN).to_degrees()),
        );
        out.value(
            &format!("theta2_range_deg_{case}"),
            Value::vector(&[min_of(&th2).to_degrees(), max_of(&th2).to_degrees()]),
        );
        let label = format!(
            "{case}: Q = diag({}, {}, {}, {}), R = {r}",
            q[0], q[1], q[2], q[3]
        );
        runs.push((label, run.trajectory));
    }
    // Line 22 displays K = −lqr(A, B, Q, R) of the first case (Q = diag(10, 10, 1, 1),
    // R = 1), as GNU Octave printed it running the M-file.
    OctaveDisplay::parse(
        id,
        include_str!("../../tests/data/octave/p1c523_ex8_adip_lqr.txt"),
    )
    .compare(id, &mut out, "K_case1", "K", "line 22")?;
    display_note(
        &mut out,
        id,
        &["K (as K_case1)"],
        &[(
            "K_case2, K_case3",
            "the weights of the plotting variant p1c523_ex8_adip_lqr_plot.m, which displays \
             them only around its Simulink runs",
        )],
        &[],
    );
    out.notes.push(format!(
        "Nonlinear arm pendulum from θ1 = 0 (pendulum upright) under u = K(x − x_e), \
         x_e = [π/4, 0, 0, 0], velocities by the pseudo-differentiator, 1 ms; {BOOK_CONVENTION}."
    ));
    if ctx.figures {
        let mut tr = TimeResponse::new().title("p1c523_ex8_adip_lqr: LQR at θ1e = π/4");
        for (label, t) in &runs {
            tr = tr.run(label.clone(), t);
        }
        let deg = 180.0 / PI;
        let fig = tr
            .panel(
                SignalPanel::new(Channel::State(0), "arm θ1 [deg]")
                    .scaled(deg)
                    .reference(45.0, Some("θ1e = 45°")),
            )
            .panel(SignalPanel::new(Channel::State(1), "pendulum θ2 [deg]").scaled(deg))
            .panel(SignalPanel::new(Channel::Input(0), "input v [V]").stairs())
            .figure()
            .ctx(id)?;
        save_figure(ctx, &mut out, id, "response", Ok(fig))?;
        save_run_animation(
            ctx,
            &mut out,
            id,
            Rig::Arm,
            &runs[0].1,
            "p1c523_ex8_adip_lqr, case 1",
        )?;
    }
    Ok(out)
}
