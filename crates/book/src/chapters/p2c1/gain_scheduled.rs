//! Part 2 §1.5: the LQ servo and the gain-scheduled LQ servo (SOS, ρ = 1 − cos θ1) on the
//! nonlinear arm pendulum, r = 60° then 0 (example 1.7).

use super::*;

/// `([[A, 0], [0, 0]], [B; 0])`: the ρ-coefficient of the LPV model padded with the integrator
/// state (the servo's `−C` row belongs to the constant term, [`arm_servo_augmentation`]).
pub(super) fn augment(a: &Mat, b: &Mat) -> (Mat, Mat) {
    let mut at = Mat::zeros(5, 5);
    at.view_mut((0, 0), (4, 4)).copy_from(a);
    let mut bt = Mat::zeros(5, 1);
    bt.view_mut((0, 0), (4, 1)).copy_from(b);
    (at, bt)
}

/// r = 60° for 0–6 s, then 0 (12 s).
pub(super) fn gs_reference(id: &str) -> Result<Signal, BookError> {
    Signal::piecewise_constant(&[0.0, 6.0], &[60f64.to_radians(), 0.0]).ctx(id)
}

pub(super) fn p2c15_lqr(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c15_ex7_adip_lqr_servo";
    let (at, bt) = nominal_servo(id)?;
    let lq = riccati_servo_gain(id, &at, &bt)?;
    let run = arm_servo_run(
        id,
        pendulab_plants::ArmPendulumParams::book(),
        &lq.gain,
        gs_reference(id)?,
        12.0,
    )?;
    // The constant gain on the frozen LPV models A(ρ), B(ρ), ρ = 1 − cos θ1, θ1 ∈ [0°, 65°].
    let lpv = ArmPendulum::book().lpv();
    let frozen = |th: f64| -> Result<f64, BookError> {
        let rho = 1.0 - th.to_radians().cos();
        let (a, b) = arm_servo_augmentation(id, &lpv.a(rho), &lpv.b(rho))?;
        Ok(max_re(&eigenvalues(&(&a - &b * &lq.gain)).ctx(id)?))
    };
    let grid: Vec<f64> = (0..=65).map(f64::from).collect();
    let mut frozen_re = Vec::new();
    for th in &grid {
        frozen_re.push(frozen(*th)?);
    }
    let limit = grid
        .iter()
        .zip(&frozen_re)
        .find(|(_, r)| **r >= 0.0)
        .map(|(t, _)| *t);
    let t = run.trajectory.t();
    let th1 = run.trajectory.x_signal(0);
    let mut out = ExampleOutput::default();
    // p2c15_ex7_adip_lqr_servo.m lines 34-36: Kt, K1, K2.
    let kb = book_row(&lq.gain);
    out.value("Kt", Value::Vector(kb.clone()))
        .value("K1", Value::Vector(kb[..4].to_vec()))
        .value("K2", Value::Number(kb[4]))
        .value("max_real_pole_frozen_at_0deg", Value::Number(frozen_re[0]))
        .value(
            "max_real_pole_frozen_at_60deg",
            Value::Number(frozen_re[60]),
        )
        .value(
            "max_theta1_deg",
            Value::Number(max_abs_after(t, th1, 0.0) * DEG),
        )
        .value(
            "final_state",
            Value::Vector(run.diagnostics.final_state.clone()),
        );
    if let Some(tf) = fell_at(&run) {
        out.value("fell_at", Value::Number(tf));
    }
    // Lines 34-36 display Kt, K1, K2, as GNU Octave printed them running the M-file up to its
    // Simulink run.
    let disp = OctaveDisplay::parse(
        id,
        include_str!("../../../tests/data/octave/p2c15_ex7_adip_lqr_servo.txt"),
    );
    for (name, line) in [("Kt", "line 34"), ("K1", "line 35"), ("K2", "line 36")] {
        disp.compare(id, &mut out, name, name, line)?;
    }
    display_note(
        &mut out,
        id,
        &["Kt", "K1", "K2"],
        &[],
        &[(
            "the response",
            "a Simulink run (adip_lqr_servo_sim, line 51), drawn, not displayed",
        )],
    );
    out.notes.push(GAIN_NOTE.into());
    out.notes.push(format!(
        "Constant LQ servo gain designed at θ1 = 0, run on the nonlinear arm pendulum (quantised rig preset). \
         On the frozen models the constant gain loses stability from θ1 ≈ {}° on (max Re λ = {:.2} 1/s at 60°): \
         the motivation for the gain-scheduled design. {}",
        limit.map_or("—".to_string(), |t| format!("{t:.0}")),
        frozen_re[60],
        match fell_at(&run) {
            Some(tf) => format!("The pendulum fell at t = {tf:.2} s (run stopped at |θ2| > 90°)."),
            None => "The run completed.".to_string(),
        }
    ));
    save_figure(
        ctx,
        &mut out,
        id,
        "response",
        arm_response(
            "p2c15_ex7: LQ servo, r = 60° then 0",
            &[("LQ servo", &run)],
            None,
        ),
    )?;
    save_run_animation(ctx, &mut out, id, Rig::Arm, &run.trajectory, id)?;
    Ok(out)
}

/// The scheduled servo `u = −K(ρ) [x; w]`, `ρ = 1 − cos y₀`, `w_k = w_{k−1} + ts (r − y₀)`
/// (forward Euler, as [`LqIntegralServo`]), with `K(ρ) = −L(ρ) X(ρ)⁻¹` evaluated at every
/// sample on stack matrices (no allocation in `update`).
#[derive(Debug, Clone)]
pub(super) struct ScheduledServo {
    pub(super) x: [nalgebra::SMatrix<f64, 5, 5>; 3],
    pub(super) l: [nalgebra::SMatrix<f64, 1, 5>; 3],
    pub(super) r: Signal,
    pub(super) ts: f64,
    pub(super) w: f64,
    pub(super) e_prev: f64,
}

impl ScheduledServo {
    fn new(s: &ScheduledGain, r: Signal) -> Self {
        let x = std::array::from_fn(|i| {
            nalgebra::SMatrix::<f64, 5, 5>::from_fn(|a, b| s.x_coefficients[i][(a, b)])
        });
        let l = std::array::from_fn(|i| {
            nalgebra::SMatrix::<f64, 1, 5>::from_fn(|a, b| s.l_coefficients[i][(a, b)])
        });
        Self {
            x,
            l,
            r,
            ts: 1e-3,
            w: 0.0,
            e_prev: 0.0,
        }
    }
}

impl Controller for ScheduledServo {
    fn ny(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {
        self.w = 0.0;
        self.e_prev = 0.0;
    }
    fn sample_time(&self) -> Option<f64> {
        Some(self.ts)
    }
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        self.w += self.ts * self.e_prev;
        self.e_prev = self.r.value(t) - y[0];
        let rho = 1.0 - y[0].cos();
        let xm = self.x[0] + self.x[1] * rho + self.x[2] * (rho * rho);
        let lm = self.l[0] + self.l[1] * rho + self.l[2] * (rho * rho);
        let z = nalgebra::SVector::<f64, 5>::new(y[0], y[1], y[2], y[3], self.w);
        // u = −K z = L X⁻¹ z. X(ρ) ≻ 0 is certified on the design range; outside it (ρ up to
        // 2) a non-positive-definite X(ρ) gives no gain, and the command is 0.
        u[0] = match xm.cholesky() {
            Some(ch) => (lm * ch.solve(&z))[(0, 0)],
            None => 0.0,
        };
    }
}

pub(super) fn p2c15_gs(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c15_ex7_adip_oc_gs_servo";
    let plant = ArmPendulum::book();
    let lpv = plant.lpv();
    let (a0, b0) = arm_servo_augmentation(id, &lpv.a0, &lpv.b0)?;
    let (a1, b1) = augment(&lpv.a1, &lpv.b1);
    let rho_bar = 1.0 - 65f64.to_radians().cos();
    let (q, r) = servo_weights();
    let spec = GainScheduleSpec {
        rho_range: (0.0, rho_bar),
        rho0_range: (0.0, rho_bar),
        rho_dot_bound: 0.75,
        lq: LqWeights { q, r },
        margin: EPS,
        gamma_relax: 0.06,
        balance: true,
    };
    let design = gain_scheduled_lq(
        &LpvPlant { a0, a1, b0, b1 },
        &spec,
        &SolveOptions::default(),
    )
    .ctx(id)?;
    let gamma = design
        .gamma_star
        .ok_or_else(|| fail(id, format!("γ minimisation failed: {:?}", design.status)))?;
    let sched = design.schedule.as_ref().ok_or_else(|| {
        fail(
            id,
            format!(
                "feasibility re-solve failed its rechecks: {:?}",
                design.status
            ),
        )
    })?;
    let k_opt_bar = design
        .optimum
        .as_ref()
        .map(|o| o.gain(rho_bar))
        .transpose()
        .ctx(id)?;
    let k0 = sched.gain(0.0).ctx(id)?;
    let kbar = sched.gain(rho_bar).ctx(id)?;
    let run = run_arm(
        id,
        pendulab_plants::ArmPendulumParams::book(),
        ScheduledServo::new(sched, gs_reference(id)?),
        12.0,
        &[0.0; 4],
    )?;
    let th1 = run.trajectory.x_signal(0);
    let dth1 = run.trajectory.x_signal(2);
    let rho: Vec<f64> = th1.iter().map(|t| 1.0 - t.cos()).collect();
    let rho_dot: Vec<f64> = th1.iter().zip(dth1).map(|(t, w)| t.sin() * w).collect();
    // θ1 just before r returns to 0 (the last sample before 6 s).
    let t = run.trajectory.t();
    let k6 = t.iter().rposition(|&ti| ti < 6.0 - 1e-9).unwrap_or(0);
    let e6 = (th1[k6] * DEG - 60.0).abs();
    let range = |v: &[f64]| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        vec![lo, hi]
    };
    let mut out = ExampleOutput::default();
    // p2c15_ex7_adip_oc_gs_servo.m line 120: gamma_obj = 1.06*double(gamma), displayed at
    // line 249; line 250 displays double(gamma) of the second (feasibility) solve.
    out.value("gamma", Value::Number(gamma))
        .value("gamma_obj", Value::Number(1.06 * gamma))
        .value("gamma_design", Value::Number(sched.gamma))
        .value("K_at_rho0", Value::Vector(book_row(&k0)))
        .value("K_at_rho_max", Value::Vector(book_row(&kbar)))
        .value("rho_range_seen", Value::Vector(range(&rho)))
        .value("rho_dot_range_seen", Value::Vector(range(&rho_dot)))
        .value("rho_design_range", Value::Vector(vec![0.0, rho_bar]))
        .value("tracking_error_at_6s_deg", Value::Number(e6))
        .value(
            "final_state",
            Value::Vector(run.diagnostics.final_state.clone()),
        );
    if let Some(k) = &k_opt_bar {
        out.value("K_at_rho_max_at_optimum", Value::Vector(book_row(k)));
    }
    // p2c15_ex7_adip_oc_gs_servo.m lines 135-140: the schedule's coefficients X_0, X_1, X_2
    // (5 × 5) and L_0, L_1, L_2 (1 × 5), with which the M-file's K = L*inv(X) (book sign)
    // at para = 1 - cos(th), lines 151-155.
    let rows = |m: &Mat| -> Vec<Vec<f64>> {
        (0..m.nrows())
            .map(|i| m.row(i).iter().copied().collect())
            .collect()
    };
    for (i, (x, l)) in sched
        .x_coefficients
        .iter()
        .zip(&sched.l_coefficients)
        .enumerate()
    {
        out.value(&format!("X_{i}"), Value::Matrix(rows(x))).value(
            &format!("L_{i}"),
            Value::Vector(l.row(0).iter().copied().collect()),
        );
    }
    // Book p. 164: "γ = 236 程度まで可解" — the M-file's gamma_obj (1.06 times its γ*),
    // printed as an integer: half a unit. (the 256-bit SDP optimum γ* ≈ 222 is not a
    // printed value; the tests check γ against it.)
    out.reference(
        "gamma_obj",
        Value::Number(236.0),
        "book p. 164 (γ = 236 程度)",
        0.5,
    );
    display_note(
        &mut out,
        id,
        &["gamma_obj (line 249, against the book's γ = 236 of p. 164)"],
        &[
            (
                "double(gamma) (line 250)",
                "γ of the feasibility re-solve under γ ≤ gamma_obj (line 123), which has no \
                 objective: any feasible γ up to gamma_obj answers, each solver stops at its own \
                 (pendulab's is gamma_design)",
            ),
            (
                "sol, monos, calQ (line 123) and the Feasible!! lines (129-131)",
                "the SOS solver's report and Gram matrices, not unique; pendulab certifies the \
                 schedule by its own SOS residual checks instead",
            ),
        ],
        &[],
    );
    out.notes.push(format!(
        "Why gamma_obj differs from the book's 236 by more than the printed digit: pendulab solves the \
         M-file's problem (the same SOS program; CVXPY + Clarabel on an independent transcription, \
         tools/reference/gain_schedule_sos.py, gives γ* = 222.16, and a 256-bit SDP solver ≈ 222), and its \
         γ* = {gamma:.2} is that optimum; the M-file's gamma_obj = 1.06·γ* carries SeDuMi's γ*, which on this \
         degenerate SDP stops ≈ 0.2 % high (236/1.06 = 222.6). The difference is the book's solver's stopping \
         point, not a different problem, so the tolerance stays at the printed digit."
    ));
    out.notes.push(GAIN_NOTE.into());
    out.notes.push(format!(
        "γ* = {gamma:.2}; the schedule used satisfies γ ≤ gamma_obj = 1.06 γ* = {:.2}. The book reports γ ≈ 236 from \
         SeDuMi: the 1.06 γ* cap of its second (feasibility) solve, from a γ* about 0.2 % above the optimum found here \
         (double-precision solvers stop high on this degenerate SDP; a 256-bit SDP solver gives γ* ≈ 222).",
        1.06 * gamma
    ));
    out.notes.push(
        "Solved in normalised parameters ρ = ρ̄ s, s ∈ [0, 1] (same feasible set); K(ρ̄) is well determined, K(0) is not (near-optimal solutions differ there)."
            .into(),
    );
    if ctx.figures {
        // Gain curves K(θ1) against the constant LQ servo gain.
        let (at, bt) = nominal_servo(id)?;
        let lq = riccati_servo_gain(id, &at, &bt)?;
        let lq_book = book_row(&lq.gain);
        let th: Vec<f64> = (0..=130).map(|k| k as f64 * 0.5).collect();
        let mut ks: Vec<Vec<f64>> = vec![Vec::new(); 5];
        for t in &th {
            let k = sched.gain(1.0 - t.to_radians().cos()).ctx(id)?;
            for (j, v) in book_row(&k).into_iter().enumerate() {
                ks[j].push(v);
            }
        }
        let names = ["K11", "K12", "K13", "K14", "K2"];
        let mut gc = GainCurves::new("θ1 [deg]", &th)
            .legend_names("gain scheduling K(θ1)", "LQ (constant)")
            .title("p2c15_ex7: scheduled gains against the constant LQ servo gains");
        for j in 0..5 {
            gc = gc.gain(names[j], &ks[j], Some(lq_book[j]));
        }
        save_figure(ctx, &mut out, id, "gains", gc.figure())?;
        let lq_run = arm_servo_run(
            id,
            pendulab_plants::ArmPendulumParams::book(),
            &lq.gain,
            gs_reference(id)?,
            12.0,
        )?;
        save_figure(
            ctx,
            &mut out,
            id,
            "response",
            arm_response(
                "p2c15_ex7: gain-scheduled vs LQ servo, r = 60° then 0",
                &[("gain scheduled", &run), ("LQ", &lq_run)],
                None,
            ),
        )?;
        // ρ and ρ̇ along the run with the design ranges.
        let t = run.trajectory.t();
        let mut ax1 = pendulab_plot::Axes::new();
        ax1.ylabel("ρ = 1 − cos θ1 [-]");
        ax1.plot(t, &rho).label("ρ(t)");
        ax1.hline(rho_bar)
            .label("design range")
            .color(pendulab_plot::Color::RED)
            .dashed();
        ax1.hline(0.0).color(pendulab_plot::Color::RED).dashed();
        let mut ax2 = pendulab_plot::Axes::new();
        ax2.ylabel("dρ/dt [1/s]").xlabel("time [s]");
        ax2.plot(t, &rho_dot).label("dρ/dt");
        ax2.hline(0.75)
            .label("±0.75")
            .color(pendulab_plot::Color::RED)
            .dashed();
        ax2.hline(-0.75).color(pendulab_plot::Color::RED).dashed();
        save_figure(
            ctx,
            &mut out,
            id,
            "rho",
            Ok(pendulab_plot::Figure::column([ax1, ax2])
                .title("p2c15_ex7: scheduling parameter and its rate inside the design ranges")),
        )?;
        save_run_animation(ctx, &mut out, id, Rig::Arm, &run.trajectory, id)?;
    }
    Ok(out)
}
