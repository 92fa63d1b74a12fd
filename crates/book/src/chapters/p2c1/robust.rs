//! Part 2 §1.3: the arm servo at the four parameter vertices — nominal Riccati and LMI designs,
//! and the robust LMI design over the polytope (example 1.5).

use super::*;

/// The four vertices `(a1, b1)` of the p2c13 M-files (lines 37-47 of
/// `p2c13_ex5_adip_lqr_servo.m`): the nominal values × [0.55, 1.45], in `mvert(2)`'s column
/// order (ρ1 min/ρ2 min, ρ1 max/ρ2 min, ρ1 min/ρ2 max, ρ1 max/ρ2 max).
pub(super) fn vertex_params() -> Vec<(f64, f64)> {
    let p = pendulab_plants::ArmPendulumParams::book();
    let (lo, hi) = (0.55, 1.45);
    // mvert(2) = [0 1 0 1; 0 0 1 1]; vertex = range(1) + diff(range) * ve.
    let ve = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
    ve.iter()
        .map(|&(e1, e2)| {
            (
                p.a1 * lo + (p.a1 * hi - p.a1 * lo) * e1,
                p.b1 * lo + (p.b1 * hi - p.b1 * lo) * e2,
            )
        })
        .collect()
}

/// `vertex` as the M-files display it: row 1 the a1 values, row 2 the b1 values.
pub(super) fn vertex_value() -> Value {
    let v = vertex_params();
    Value::Matrix(vec![
        v.iter().map(|p| p.0).collect(),
        v.iter().map(|p| p.1).collect(),
    ])
}

pub(super) fn vertices(id: &str) -> Result<Vec<Vertex>, BookError> {
    vertex_params()
        .into_iter()
        .map(|(a1, b1)| arm_servo_model(id, a1, b1).map(|(a, b)| Vertex { a, b }))
        .collect()
}

/// Values, notes and figures shared by the three p2c13 examples for a gain `k` (library sign).
pub(super) fn p2c13_report(
    ctx: &RunContext,
    id: &str,
    gain_name: &str,
    k: &Mat,
    regions: bool,
    out: &mut ExampleOutput,
) -> Result<(), BookError> {
    let verts = vertices(id)?;
    let mut maxre = Vec::new();
    let mut all_poles = Vec::new();
    for v in &verts {
        let p = feedback_poles(id, &v.a, &v.b, k)?;
        maxre.push(max_re(&p));
        all_poles.push(p);
    }
    let kb = book_row(k);
    out.value(gain_name, Value::Vector(kb.clone()))
        .value("K1", Value::Vector(kb[..4].to_vec()))
        .value("K2", Value::Number(kb[4]))
        .value("max_real_pole_per_vertex", Value::Vector(maxre.clone()))
        .value(
            "stable_at_all_vertices",
            Value::Bool(maxre.iter().all(|r| *r < 0.0)),
        );
    out.notes.push(GAIN_NOTE.into());
    out.notes.push(
        "Vertices (a1, b1) in mvert(2)'s order, as the M-files number them: (3.41, 8.69), (8.99, 8.69), (3.41, 22.91), (8.99, 22.91)."
            .into(),
    );
    if !ctx.figures {
        return Ok(());
    }
    let mut map = PoleZeroMap::new();
    if regions {
        map = map.region(
            "α = 2, β = 40",
            &[RegionBound::DecayRate(2.0), RegionBound::SpeedLimit(40.0)],
        );
    }
    for ((a1, b1), p) in vertex_params().iter().zip(&all_poles) {
        map = map.poles(format!("a1 = {a1:.2}, b1 = {b1:.2}"), p);
    }
    save_figure(
        ctx,
        out,
        id,
        "poles",
        Ok(map
            .title(format!("{id}: closed-loop poles at the four vertices"))
            .figure()),
    )?;
    // Nonlinear runs at the vertices, r = 30°, 6 s (an unstable vertex swings away; the
    // ±5 V amplifier bounds it).
    let step = Signal::step(0.0, 30f64.to_radians()).ctx(id)?;
    let mut runs = Vec::new();
    for (a1, b1) in vertex_params() {
        let params = pendulab_plants::ArmPendulumParams {
            a1,
            b1,
            ..pendulab_plants::ArmPendulumParams::book()
        };
        runs.push((
            format!("a1 = {a1:.2}, b1 = {b1:.2}"),
            arm_servo_run(id, params, k, step.clone(), 6.0)?,
        ));
    }
    let refs: Vec<(&str, &SampledRun)> = runs.iter().map(|(n, r)| (n.as_str(), r)).collect();
    save_figure(
        ctx,
        out,
        id,
        "response",
        arm_response(
            &format!("{id}: r = 30° at the four vertices"),
            &refs,
            Some(30.0),
        ),
    )?;
    // Animation at the vertex the nominal LQ servo cannot hold (a1 max, b1 min).
    save_run_animation(ctx, out, id, Rig::Arm, &runs[1].1.trajectory, id)?;
    Ok(())
}

pub(super) fn p2c13_lqr(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c13_ex5_adip_lqr_servo";
    let (at, bt) = nominal_servo(id)?;
    let lq = riccati_servo_gain(id, &at, &bt)?;
    let mut out = ExampleOutput::default();
    // p2c13_ex5_adip_lqr_servo.m line 33: Kt_LQ = -lqr(At_nominal, Bt_nominal, Q, R).
    out.value(
        "ve",
        Value::Matrix(vec![vec![0.0, 1.0, 0.0, 1.0], vec![0.0, 0.0, 1.0, 1.0]]),
    )
    .value("vertex", vertex_value());
    p2c13_report(ctx, id, "Kt_LQ", &lq.gain, false, &mut out)?;
    out.notes.push(
        "The nominal Riccati LQ servo is unstable at the second vertex (a1, b1) = (8.99, 8.69)."
            .into(),
    );
    // What the M-file displays (lines 33, 44, 47, 49-50), as GNU Octave printed it running the
    // M-file up to its Simulink runs.
    let disp = OctaveDisplay::parse(
        id,
        include_str!("../../../tests/data/octave/p2c13_ex5_adip_lqr_servo.txt"),
    );
    for (name, line) in [
        ("Kt_LQ", "line 33"),
        ("ve", "line 44"),
        ("vertex", "line 47"),
        ("K1", "line 49"),
        ("K2", "line 50"),
    ] {
        disp.compare(id, &mut out, name, name, line)?;
    }
    display_note(
        &mut out,
        id,
        &["Kt_LQ", "ve", "vertex", "K1", "K2"],
        &[],
        &[(
            "the responses at the vertices",
            "Simulink runs (adip_servo_sim, line 64 on), drawn, not displayed",
        )],
    );
    Ok(out)
}

/// The p2c13 LMI servo (nominal model only, or all four vertices): α = 3/St = 2,
/// β = 20α = 40, `obj = -trace(X)`.
pub(super) fn p2c13_lmi(
    ctx: &RunContext,
    id: &str,
    robust: bool,
) -> Result<ExampleOutput, BookError> {
    let (q, r) = servo_weights();
    let models: Vec<(Mat, Mat)> = if robust {
        vertices(id)?.into_iter().map(|v| (v.a, v.b)).collect()
    } else {
        vec![nominal_servo(id)?]
    };
    let alpha = 3.0 / 1.5;
    let spec = MfileLmi::Servo {
        models,
        q,
        r,
        alpha: Some(alpha),
        sector_k: None,
        beta: Some(20.0 * alpha),
    };
    let s = solve_mfile(id, &spec, &SolveOptions::default())?;
    let kt = s.kt(id)?;
    let mut out = ExampleOutput::default();
    // The M-files display trace(inv(X)) as `trase_invX` (sic).
    report_solution(id, &s, "trase_invX", &mut out)?;
    out.value(
        "ve",
        Value::Matrix(vec![vec![0.0, 1.0, 0.0, 1.0], vec![0.0, 0.0, 1.0, 1.0]]),
    )
    .value("vertex", vertex_value());
    p2c13_report(ctx, id, "Kt", &library_gain(&kt), true, &mut out)?;
    out.notes.push(s.note(if robust {
        "p2c13_ex5_adip_oc_robust_servo.m lines 47-79 (common X, L at the four vertices), solved once as there (no re-solve)"
    } else {
        "p2c13_ex5_adip_oc_nominal_servo.m lines 31-58 (nominal model), solved once as there (no re-solve)"
    }));
    out.notes.push(
        "Region as in the M-file: M'+M+2αX ⪯ −εI (Re λ < −2) and M'+M+2βX ⪰ εI (Re λ > −40, a half-plane)."
            .into(),
    );
    if !robust {
        out.notes.push(ILL_DETERMINED_KT.into());
    }
    mfile_display_references(id, robust, &mut out)?;
    Ok(out)
}

/// What the p2c13 LMI M-files display (`ve`, `vertex`, `X`, `L`, `Kt`, `trase_invX`,
/// `trace_X`, `K1`, `K2`) against an independent solve of the same LMIs: the M-files' problem
/// transcribed into CVXPY and solved by Clarabel (the committed run of
/// `tools/reference/p2c1_mfile_lmi_cvxpy.py`); `ve` against `mvert.m`'s closed form.
fn mfile_display_references(
    id: &str,
    robust: bool,
    out: &mut ExampleOutput,
) -> Result<(), BookError> {
    let (ve_line, lines) = if robust {
        ("lines 19-22", "lines 81-86 and 122-123")
    } else {
        ("lines 76-79", "lines 60-65 and 81-82")
    };
    // mvert(2): the 2^2 vertices of [0, 1]², first coordinate fastest (mvert.m).
    exact_references(
        out,
        &format!("{id}.m {ve_line}, mvert(2) (mvert.m, closed form)"),
        [(
            "ve",
            Value::Matrix(vec![vec![0.0, 1.0, 0.0, 1.0], vec![0.0, 0.0, 1.0, 1.0]]),
        )],
    );
    let (status, rec) = cvxpy_clarabel(id)?;
    let vertex = json_value(id, &cvxpy_run(id)?["vertex"])?;
    out.reference(
        "vertex",
        vertex.clone(),
        &format!("{id}.m {ve_line}, NumPy's vertices in tools/reference/p2c1_mfile_lmi_cvxpy.py"),
        short_half_unit(max_abs(&vertex)),
    );
    let src = cvxpy_source(id, lines, &status);
    let tr = rec["trace_X"]
        .as_f64()
        .ok_or_else(|| fail(id, "the CVXPY run has no trace_X"))?;
    if robust {
        let k = json_value(id, &rec["K"])?;
        let Value::Vector(kv) = &k else {
            return Err(fail(id, "the CVXPY run's K is not a row"));
        };
        // Two interior-point solvers at their 1e-8 tolerances, with the M-file's ε = 1e-6
        // margins, agree on the optimum to 1e-6 of trace(X), and on the well-conditioned
        // optimum's X, L, Kt to 2e-4 of their norms (tests/p2c1_lmi.rs): the tolerances,
        // looser than the 4 decimals MATLAB's short format prints.
        let rel_k = 2e-4;
        let norm = |v: &Value| -> f64 {
            match v {
                Value::Vector(v) => v.iter().map(|x| x * x).sum::<f64>().sqrt(),
                Value::Matrix(r) => r.iter().flatten().map(|x| x * x).sum::<f64>().sqrt(),
                Value::Number(x) => x.abs(),
                _ => 0.0,
            }
        };
        let x = json_value(id, &rec["X"])?;
        let l = json_value(id, &rec["L"])?;
        out.reference("trace_X", Value::Number(tr), &src, 1e-6 * tr);
        let ti = rec["trace_invX"]
            .as_f64()
            .ok_or_else(|| fail(id, "the CVXPY run has no trace_invX"))?;
        out.reference("trase_invX", Value::Number(ti), &src, rel_k * ti);
        // X and L one by one are less well determined than Kt = L X⁻¹: L differs from CVXPY's
        // by 5e-4 of its norm.
        let rel_xl = 1e-3;
        out.reference("X", x.clone(), &src, rel_xl * norm(&x));
        out.reference("L", l.clone(), &src, rel_xl * norm(&l));
        out.reference("Kt", k.clone(), &src, rel_k * norm(&k));
        out.reference(
            "K1",
            Value::Vector(kv[..4].to_vec()),
            &src,
            rel_k * norm(&k),
        );
        out.reference("K2", Value::Number(kv[4]), &src, rel_k * norm(&k));
        out.notes.push(
            "Tolerances of the comparison with CVXPY + Clarabel, looser than the four decimals of \
             MATLAB's short format: trace_X to 1e-6 relative, Kt (K1, K2) and trase_invX to 2e-4 of \
             their norms, X and L to 1e-3 of theirs (L differs by 5e-4) — what two interior-point solvers stopping at 1e-8 tolerances, \
             with the M-file's ε = 1e-6 margins, agree to on this well-conditioned optimum (the \
             M-file's own SeDuMi run stops at such a point too)."
                .into(),
        );
        display_note(
            out,
            id,
            &[
                "ve",
                "vertex",
                "X",
                "L",
                "Kt",
                "trase_invX",
                "trace_X",
                "K1",
                "K2",
            ],
            &[],
            &[(
                "the closed-loop poles",
                "drawn (line 96), not displayed; reported here as poles per vertex",
            )],
        );
    } else {
        // Clarabel stops "almost solved" on this problem (reduced tolerances: relative gap
        // 5e-5): trace(X) agrees to 1e-4 of itself, looser than MATLAB's short format (0.05).
        out.reference("trace_X", Value::Number(tr), &src, 1e-4 * tr);
        out.notes.push(
            "trace_X is compared with CVXPY + Clarabel to 1e-4 relative, looser than MATLAB's \
             short format (0.05): Clarabel stops \"almost solved\" here, at its reduced gap \
             tolerance 5e-5."
                .into(),
        );
        display_note(
            out,
            id,
            &["ve", "vertex", "trace_X"],
            &[(
                "X, L, Kt, K1, K2, trase_invX",
                "not determined by this objective: X is near singular at the optimum, and \
                     solvers stopping within 1e-5 of the optimal trace(X) give Kt differing by \
                     5-35 % and trace(inv(X)) by orders of magnitude (CVXPY + Clarabel: \
                     trace(inv(X)) = 6.6e5); any solver's digits, the M-file's included, are \
                     where it stopped",
            )],
            &[],
        );
    }
    Ok(())
}

pub(super) fn p2c13_nominal(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    p2c13_lmi(ctx, "p2c13_ex5_adip_oc_nominal_servo", false)
}

pub(super) fn p2c13_robust(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c13_ex5_adip_oc_robust_servo";
    let mut out = p2c13_lmi(ctx, id, true)?;
    out.notes.push(
        "Stable at all four vertices. The optimum is well conditioned: CVXPY + Clarabel \
         (tools/reference/p2c1_mfile_lmi_cvxpy.py) agrees on trace(X) to 2e-7 and on Kt to 1e-4."
            .into(),
    );
    Ok(out)
}
