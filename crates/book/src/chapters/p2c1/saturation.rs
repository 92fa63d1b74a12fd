//! Part 2 §1.4: state feedback under input saturation by invariant-ellipsoid conditions on K and
//! the auxiliary gain H (example 1.6).

use super::*;

/// `u = Kx` (the book's sign) through the M-file's saturation block `±sat` (the Simulink
/// models `adip_saturation_sim` / `adip_saturation2_sim`: Matrix Gain `K` → Saturation
/// `[-sat, sat]` → plant; `u` is logged before, `v` after the saturation).
#[derive(Debug, Clone)]
pub(super) struct SaturatedGain {
    pub(super) k: [f64; 4],
    pub(super) sat: f64,
}

impl Controller for SaturatedGain {
    fn ny(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {}
    fn sample_time(&self) -> Option<f64> {
        Some(1e-3)
    }
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        let v: f64 = self.k.iter().zip(y).map(|(k, x)| k * x).sum();
        u[0] = v.clamp(-self.sat, self.sat);
    }
}

/// A number already reported in `out` (NaN when missing).
pub(super) fn num_of(out: &ExampleOutput, name: &str) -> f64 {
    match out.get(name) {
        Some(Value::Number(x)) => *x,
        _ => f64::NAN,
    }
}

pub(super) fn p2c14_ex6(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c14_ex6_adip_oc_saturation";
    let plant = ArmPendulum::book();
    let lin = plant
        .linearize(pendulab_plants::ArmEquilibrium::upright(0.0))
        .ctx(id)?;
    // p2c14_ex6_adip_oc_saturation.m lines 28-67.
    let q = diag(&[20.0, 10.0, 0.1, 0.1]);
    let r = diag(&[1.0]);
    let sigma2: f64 = 0.1 * 0.1;
    let x0v = [10f64.to_radians(), 0.0, 0.0, 0.0];
    let spec = MfileLmi::Saturation {
        a: lin.a().clone(),
        b: lin.b().clone(),
        q,
        r,
        sigma2,
        x0: Mat::from_column_slice(4, 1, &x0v),
    };
    // Lines 69-74: maximise trace(X) (OBV = -trace(X)), display double(OBV).
    let s = solve_mfile(id, &spec, &SolveOptions::default())?;
    let inv = |x: &Mat| -> Result<Mat, BookError> {
        x.clone()
            .try_inverse()
            .ok_or_else(|| fail(id, "X is singular"))
    };
    let k_max = s.kt(id)?;
    let h_max = s.v.as_ref().ok_or_else(|| fail(id, "no V"))? * inv(&s.x)?;
    // Lines 77-92: the same LMIs with trace(X) <= -double(OBV), no objective; the M-file's
    // X, K = L*inv(X), H = V*inv(X), eig(A+B*K), trace_invX and trace_X are of this point.
    let f = feasible_point(id, &spec, s.trace_x, &SolveOptions::default())?;
    let xi = inv(&f.x)?;
    let k = &f.l * &xi;
    let v = f.v.clone().ok_or_else(|| fail(id, "no V"))?;
    let h = &v * &xi;
    let poles = poles_of(id, lin.a(), lin.b(), &k)?;
    let sat = sigma2.sqrt();
    let mut out = ExampleOutput::default();
    out.value("OBV", Value::Number(-s.trace_x))
        .value("dual_bound", Value::Number(s.dual_bound))
        .value("duality_gap", Value::Number(s.gap))
        .value("dual_stationarity_residual", Value::Number(s.stationarity))
        .value(
            "lmi_min_eigenvalues_at_max_trace",
            Value::Vector(s.margins.iter().map(|m| m.1).collect()),
        )
        .value("K_at_max_trace", Value::Vector(row(&k_max)))
        .value("H_at_max_trace", Value::Vector(row(&h_max)))
        .value("X", Value::matrix(&f.x))
        .value("L", Value::Vector(row(&f.l)))
        .value("V", Value::Vector(row(&v)))
        .value("K", Value::Vector(row(&k)))
        .value("H", Value::Vector(row(&h)))
        .value("poles", Value::Complex(poles))
        .value("trace_invX", Value::Number(xi.trace()))
        .value("trace_X", Value::Number(f.x.trace()))
        .value(
            "solved_to_tolerance",
            Value::Bool(f.status == Status::Solved),
        )
        .value(
            "lmi_min_eigenvalues",
            Value::Vector(f.margins.iter().map(|m| m.1).collect()),
        )
        .value("sat", Value::Number(sat));
    // Simulations (lines 95-97): the exact-state model (adip_saturation_sim) and the model
    // with D/A and encoder resolution (adip_saturation2_sim, the one the M-file runs), 10 s.
    let kk = [k[(0, 0)], k[(0, 1)], k[(0, 2)], k[(0, 3)]];
    let sim_on = |rig: bool| -> Result<SampledRun, BookError> {
        let c = SaturatedGain { k: kk, sat };
        let mut l = SampledLoop::new(
            plant,
            c,
            SampledOptions {
                t_final: 10.0,
                ..Default::default()
            },
        )
        .ctx(id)?;
        if rig {
            l = l.with_rig(quantized_rig(id, &RigSpec::arm())?).ctx(id)?;
        }
        l.run(&x0v).ctx(id)
    };
    let mut runs = Vec::new();
    for (tag, rig) in [("", false), ("_quantised_rig", true)] {
        let run = sim_on(rig)?;
        let t = run.trajectory.t();
        // u = K x along the run (before the saturation; from the plant's states), v applied.
        let xs: Vec<Vec<f64>> = (0..4)
            .map(|j| run.trajectory.x_signal(j).to_vec())
            .collect();
        let u: Vec<f64> = (0..t.len())
            .map(|i| (0..4).map(|j| kk[j] * xs[j][i]).sum())
            .collect();
        let vv = run.trajectory.u_signal(0);
        let sat_time = u
            .iter()
            .zip(t.windows(2))
            .filter(|(u, _)| u.abs() > sat)
            .map(|(_, w)| w[1] - w[0])
            .sum::<f64>();
        out.value(
            &format!("max_abs_u{tag}"),
            Value::Number(max_abs_after(t, &u, 0.0)),
        )
        .value(
            &format!("max_abs_v{tag}"),
            Value::Number(max_abs_after(t, vv, 0.0)),
        )
        .value(&format!("saturated_seconds{tag}"), Value::Number(sat_time))
        .value(
            &format!("final_state{tag}"),
            Value::Vector(run.diagnostics.final_state.clone()),
        );
        runs.push((run, u));
    }
    out.notes.push("Gains in the book's convention u = +K x; H = V X⁻¹ is the auxiliary gain of the invariant-ellipsoid conditions.".into());
    out.notes
        .push(s.note("p2c14_ex6_adip_oc_saturation.m lines 50-74 (first solve, OBV)"));
    out.notes.push(format!(
        "Then, as the M-file does (lines 77-78), the same LMIs with trace(X) ≤ −OBV = {:.6} and no objective, \
         solver status {} ({:?}): a bound every feasible X meets, so this solve returns whichever interior \
         point the method stops at (trace(X) = {:.4} here; pendulab-lmi's Clarabel backend and CVXPY + Clarabel \
         stop elsewhere, with K differing by tens of %, tools/reference/p2c1_mfile_lmi_cvxpy.py). X, K, H, poles, \
         trace_invX and trace_X are of this point, as in the M-file; smallest LMI eigenvalue there (after the \
         margin) {:.2e}. At the max-trace point itself K_at_max_trace is extreme (X nearly singular), H_at_max_trace \
         is well determined.",
        s.trace_x,
        if f.status == Status::Solved { "solved" } else { "INACCURATE" },
        f.backend,
        f.x.trace(),
        f.margins.iter().map(|m| m.1).fold(f64::INFINITY, f64::min),
    ));
    out.notes.push(format!(
        "The LMIs bound |H x| ≤ sat = {sat} V on the ellipsoid xᵀX⁻¹x ≤ 1 containing x0 (MH, INI) and give both A + BK and \
         A + BH the LQ bound (OC1, OC2), so sat(Kx) ∈ co{{Kx, Hx}} there: K itself is allowed to saturate. From θ1(0) = 10° \
         u = K x reaches {:.3} V and is clipped to ±{sat} V for {:.2} s (exact state; {:.3} V and {:.2} s on the quantised rig).",
        num_of(&out, "max_abs_u"),
        num_of(&out, "saturated_seconds"),
        num_of(&out, "max_abs_u_quantised_rig"),
        num_of(&out, "saturated_seconds_quantised_rig"),
    ));
    saturation_display_references(id, &mut out)?;
    if ctx.figures {
        let (run, _) = &runs[0];
        let (rig_run, _) = &runs[1];
        let fig = TimeResponse::new()
            .title("p2c14_ex6: saturation design (book's K, |v| ≤ 0.1 V), θ1(0) = 10°")
            .run("exact state", &run.trajectory)
            .run("quantised rig", &rig_run.trajectory)
            .panel(SignalPanel::new(Channel::State(0), "θ1 [deg]").scaled(DEG))
            .panel(SignalPanel::new(Channel::State(1), "θ2 [deg]").scaled(DEG))
            .panel(
                SignalPanel::new(Channel::Input(0), "v = sat(Kx) [V]")
                    .reference(sat, Some("±sat"))
                    .reference(-sat, None),
            )
            .figure();
        save_figure(ctx, &mut out, id, "response", fig)?;
        save_run_animation(ctx, &mut out, id, Rig::Arm, &rig_run.trajectory, id)?;
    }
    Ok(out)
}

/// What `p2c14_ex6_adip_oc_saturation.m` displays against the same LMIs transcribed into
/// CVXPY and solved by Clarabel (the committed run of `tools/reference/p2c1_mfile_lmi_cvxpy.py`).
fn saturation_display_references(id: &str, out: &mut ExampleOutput) -> Result<(), BookError> {
    let (status, rec) = cvxpy_clarabel(id)?;
    let tr = rec["trace_X"]
        .as_f64()
        .ok_or_else(|| fail(id, "the CVXPY run has no trace_X"))?;
    // Line 74: double(OBV) = −max trace(X). Clarabel stops "almost solved" here (reduced gap
    // tolerance 5e-5): 1e-4 relative, looser than MATLAB's short format (5e-5).
    out.reference(
        "OBV",
        Value::Number(-tr),
        &cvxpy_source(id, "line 74 (ans = double(OBV))", &status),
        1e-4 * tr,
    );
    // H = V X⁻¹ at the max-trace point is well determined: the two methods of pendulab-lmi and
    // CVXPY + Clarabel agree on it to 2e-3 of its norm even at Clarabel's reduced accuracy.
    let h = json_value(id, &rec["H"])?;
    let hn = match &h {
        Value::Vector(v) => v.iter().map(|x| x * x).sum::<f64>().sqrt(),
        _ => return Err(fail(id, "the CVXPY run's H is not a row")),
    };
    out.reference(
        "H_at_max_trace",
        h,
        &cvxpy_source(
            id,
            "lines 72 and 85 (H = V*inv(X) at the max-trace solve)",
            &status,
        ),
        2e-3 * hn,
    );
    out.notes.push(
        "Tolerances of the comparison with CVXPY + Clarabel, looser than MATLAB's short format: \
         OBV to 1e-4 relative (Clarabel stops \"almost solved\" on this problem, at its reduced gap \
         tolerance 5e-5), H_at_max_trace to 2e-3 of its norm (what pendulab-lmi's two methods and \
         CVXPY + Clarabel agree to there; tests/p2c1_lmi.rs)."
            .into(),
    );
    display_note(
        out,
        id,
        &[
            "double(OBV) (as OBV)",
            "H of the max-trace solve (as H_at_max_trace)",
        ],
        &[
            (
                "X, K, H, eig(A+B*K), trace_invX, trace_X of lines 81-92",
                "they belong to the feasibility re-solve of lines 77-78, which has no objective: \
                 any interior point with trace(X) ≤ −OBV is an answer, and each solver stops at \
                 its own (CVXPY + Clarabel's K differs from pendulab's by tens of %), so no other \
                 run's digits are the M-file's",
            ),
            (
                "solinfo, CON",
                "the solver's report and the constraint list, not numbers of the design",
            ),
        ],
        &[],
    );
    Ok(())
}
