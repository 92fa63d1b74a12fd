//! Part 2 §1.1–§1.2: α-stability by an LMI (examples 1.1, 1.3) and the arm pendulum's LMI LQ
//! servo, alone and with a D-stability region (example 1.4).

use super::*;

pub(super) fn a_ex1() -> Mat {
    Mat::from_row_slice(2, 2, &[0.0, 1.0, -2.25, -2.25])
}

/// `P = [[ξ1, ξ2], [ξ2, 1]] ≻ 0`, `AᵀP + PA + 2αP ≺ 0` on a fresh problem.
pub(super) fn alpha_problem(id: &str) -> Result<(Problem, Expr, Expr, Expr), BookError> {
    let a = a_ex1();
    let mut p = Problem::new();
    let xi1 = p.scalar("xi1");
    let xi2 = p.scalar("xi2");
    let pm = Expr::block(&[&[&xi1, &xi2], &[&xi2, &Expr::scalar(1.0)]]);
    p.positive_definite("P ≻ 0", &pm, EPS).ctx(id)?;
    p.negative_definite(
        "AᵀP + PA + 2αP ≺ 0",
        &((&a.transpose() * &pm).he() + pm.scale(2.0)),
        EPS,
    )
    .ctx(id)?;
    Ok((p, pm, xi1, xi2))
}

pub(super) fn p2c112_ex1(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c112_ex1_alpha_stability";
    let (p, pm, _, _) = alpha_problem(id)?;
    let sol = p.solve(&SolveOptions::default()).ctx(id)?;
    let feasible = sol.status == Status::Solved && sol.all_checks_pass();
    let mut out = ExampleOutput::default();
    out.value("feasible", Value::Bool(feasible));
    if feasible {
        out.value("P", Value::matrix(&sol.value(&pm).ctx(id)?));
    }
    let ev = sorted(eigenvalues(&a_ex1()).ctx(id)?);
    out.value("eigenvalues_A", Value::Complex(ev.clone()));
    // The M-file displays P (line 21), the solver's feasible point: any P in the feasible set
    // answers the question, so the book's printed P (not known here) cannot be a reference.
    out.notes.push(
        "α-stability: every eigenvalue of A has Re λ < −α = −1 (here −1.125 ± 0.992j), so a P exists."
            .into(),
    );
    save_figure(
        ctx,
        &mut out,
        id,
        "poles",
        Ok(PoleZeroMap::new()
            .region("Re s < −α (α = 1)", &[RegionBound::DecayRate(1.0)])
            .poles("eigenvalues of A", &ev)
            .title("p2c112_ex1: eigenvalues of A and the α-stability region")
            .figure()),
    )?;
    Ok(out)
}

pub(super) fn p2c121_ex3(_ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c121_ex3_alpha_stability_opt";
    let (mut p, _, xi1, xi2) = alpha_problem(id)?;
    p.minimize(&(&xi1 + &xi2)).ctx(id)?;
    let sol = p.solve(&SolveOptions::default()).ctx(id)?;
    if sol.status != Status::Solved {
        return Err(fail(id, format!("solver status {:?}", sol.status)));
    }
    let v = |e: &Expr| -> Result<f64, BookError> { Ok(sol.value(e).ctx(id)?[(0, 0)]) };
    let (x1, x2) = (v(&xi1)?, v(&xi2)?);
    let mut out = ExampleOutput::default();
    // p2c121_ex3_alpha_stability_opt.m lines 23-25: P = double(P), c'*xi.
    out.value("P", Value::Matrix(vec![vec![x1, x2], vec![x2, 1.0]]));
    out.value("optimum", Value::Number(x1 + x2))
        .value("xi1", Value::Number(x1))
        .value("xi2", Value::Number(x2));
    // Printed to 3 decimals: tolerance half a unit of the last digit.
    out.reference("optimum", Value::Number(2.929), "book, example 1.3", 5e-4)
        .reference("xi1", Value::Number(1.911), "book, example 1.3", 5e-4)
        .reference("xi2", Value::Number(1.019), "book, example 1.3", 5e-4);
    Ok(out)
}

pub(super) fn p2c122_ex4_servo(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c122_ex4_adip_oc_servo";
    let (at, bt) = nominal_servo(id)?;
    let (q, r) = servo_weights();
    // p2c122_ex4_adip_oc_servo.m lines 31-50: X ⪰ εI, LMI1 ⪯ −εI, obj = −trace(X).
    let spec = MfileLmi::Servo {
        models: vec![(at.clone(), bt.clone())],
        q,
        r,
        alpha: None,
        sector_k: None,
        beta: None,
    };
    let mut out = ExampleOutput::default();
    let (s, kt, kt_lq) = lmi_servo_values(id, &spec, &at, &bt, &mut out)?;
    let rel = (&kt - &kt_lq).norm() / kt_lq.norm();
    out.value("relative_difference_Kt_Kt_LQ", Value::Number(rel));
    out.notes.push(GAIN_NOTE.into());
    out.notes
        .push(s.note("p2c122_ex4_adip_oc_servo.m lines 36-50, solved once as there (no re-solve)"));
    out.notes.push(format!(
        "Kt = L X⁻¹ against the Riccati gain Kt_LQ = −lqr(At, Bt, Q, R): relative difference {rel:.1e} \
         (X⁻¹ = P up to the margin ε)."
    ));
    if ctx.figures {
        save_servo_comparison(
            ctx,
            &mut out,
            id,
            "p2c122_ex4: LMI LQ servo vs Riccati LQ servo, r = 30°",
            "LMI",
            &library_gain(&kt),
            &library_gain(&kt_lq),
        )?;
    }
    Ok(out)
}

/// Runs the nonlinear arm servo with the designed gain `k` and the Riccati gain `k_lq` for a
/// 30° step and writes both responses (titled `title`, the design labelled `label`) and an
/// animation of the design's run.
pub(super) fn save_servo_comparison(
    ctx: &RunContext,
    out: &mut ExampleOutput,
    id: &str,
    title: &str,
    label: &str,
    k: &Mat,
    k_lq: &Mat,
) -> Result<(), BookError> {
    let step = Signal::step(0.0, 30f64.to_radians()).ctx(id)?;
    let params = pendulab_plants::ArmPendulumParams::book();
    let run = arm_servo_run(id, params, k, step.clone(), 6.0)?;
    let lq_run = arm_servo_run(id, params, k_lq, step, 6.0)?;
    save_figure(
        ctx,
        out,
        id,
        "response",
        arm_response(title, &[(label, &run), ("Riccati LQ", &lq_run)], Some(30.0)),
    )?;
    save_run_animation(ctx, out, id, Rig::Arm, &run.trajectory, id)
}

pub(super) fn multiobjective_regions() -> [Region; 3] {
    [
        Region::DecayRate { alpha: 2.0 },
        Region::SpeedLimit { beta: 16.0 },
        Region::Sector {
            theta: std::f64::consts::FRAC_PI_4,
        },
    ]
}

pub(super) fn p2c122_ex4_multiobjective(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c122_ex4_adip_oc_multiobjective_servo";
    let (at, bt) = nominal_servo(id)?;
    let (q, r) = servo_weights();
    // p2c122_ex4_adip_oc_multiobjective_servo.m lines 36-39: St = 1.5, α = 3/St, β = 8α,
    // θ = π/4, k = tan θ; lines 45-58: LMI1, LMI2 ⪯ −εI, LMI3 ⪯ −εI, LMI4 ⪰ εI.
    let alpha = 3.0 / 1.5;
    let beta = 8.0 * alpha;
    let theta = std::f64::consts::FRAC_PI_4;
    let spec = MfileLmi::Servo {
        models: vec![(at.clone(), bt.clone())],
        q,
        r,
        alpha: Some(alpha),
        sector_k: Some(theta.tan()),
        beta: Some(beta),
    };
    let mut out = ExampleOutput::default();
    let (s, kt, kt_lq) = lmi_servo_values(id, &spec, &at, &bt, &mut out)?;
    let poles = poles_of(id, &at, &bt, &kt)?;
    let regions = multiobjective_regions();
    let inside = poles
        .iter()
        .all(|z| regions.iter().all(|reg| reg.contains(*z)));
    out.value("poles_in_region", Value::Bool(inside));
    out.notes.push(GAIN_NOTE.into());
    out.notes.push(s.note(
        "p2c122_ex4_adip_oc_multiobjective_servo.m lines 41-62, solved once as there (no re-solve)",
    ));
    out.notes.push(ILL_DETERMINED_KT.into());
    out.notes.push(
        "Region: Re λ < −α = −2, Re λ > −β = −16, sector |Im λ| < tan(π/4)(−Re λ), the sector LMI written \
         with k = tan θ as in the M-file (line 50)."
            .into(),
    );
    if ctx.figures {
        let lq_poles = poles_of(id, &at, &bt, &kt_lq)?;
        save_figure(
            ctx,
            &mut out,
            id,
            "poles",
            Ok(PoleZeroMap::new()
                .region(
                    "design region",
                    &[
                        RegionBound::DecayRate(alpha),
                        RegionBound::SpeedLimit(beta),
                        RegionBound::Sector(theta),
                    ],
                )
                .poles("multi-objective LMI", &poles)
                .poles("Riccati LQ", &lq_poles)
                .title("p2c122_ex4: closed-loop poles and the D-stability region")
                .figure()),
        )?;
        save_servo_comparison(
            ctx,
            &mut out,
            id,
            "p2c122_ex4: multi-objective servo vs LQ servo, r = 30°",
            "multi-objective LMI",
            &library_gain(&kt),
            &library_gain(&kt_lq),
        )?;
    }
    Ok(out)
}
