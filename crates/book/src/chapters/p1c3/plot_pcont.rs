//! Part 1 §3.4: the simulated cart pendulum under P control against the rig's measurement.

use super::*;

pub(super) const ID34: &str = "p1c34_cdip_plot_pcont";

pub(super) fn p1c34_cdip_plot_pcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let kp = 10.0;
    // The book's Simulink model acts continuously; a 10 µs loop reproduces it (the 1 ms loop
    // of the rig adds half a sample of delay: +0.2 % on the swing, reported as
    // `phi_peaks_1ms`).
    let fine = 1e-5;
    let p_law = |ts: f64| -> Result<Pid, BookError> {
        Pid::new(PidForm::P { kp }, ts, PidDiscretization::Tustin)
            .ctx(ID34)?
            .reference(Signal::step(0.0, TARGET).ctx(ID34)?)
            .measurement(0, 4)
            .ctx(ID34)
    };
    let opts = SampledOptions {
        ts: fine,
        t_final: 4.0,
        integrator: pendulab_sim::Integrator::Rk4 { dt: fine },
        record: pendulab_sim::Record::Every(100),
        ..Default::default()
    };
    let tr = SampledLoop::new(CartPendulum::book(), p_law(fine)?, opts)
        .ctx(ID34)?
        .run(&[0.0, PI, 0.0, 0.0])
        .ctx(ID34)?
        .trajectory;
    let theta = tr.x_signal(1).to_vec();
    let run = CartRun {
        label: "simulation".into(),
        t: tr.t().to_vec(),
        z: tr.x_signal(0).to_vec(),
        z_measured: tr.y_signal(0).to_vec(),
        phi: theta.iter().map(|th| th - PI).collect(),
        theta,
        v: tr.u_signal(0).to_vec(),
    };
    let run_1ms = simulate_cart(ID34, "1 ms loop", p_law(1e-3)?, false, None, 4.0)?;
    let ext_1ms = extrema(&run_1ms.t, &run_1ms.phi, 1);
    let (k, zpk) = run
        .z
        .iter()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |(bk, bm), (k, &v)| {
            if v > bm { (k, v) } else { (bk, bm) }
        });
    let ext = extrema(&run.t, &run.phi, 1);
    if ext.len() < 3 {
        return Err(fail(ID34, "fewer than three extrema of φ in 4 s"));
    }
    let mut out = ExampleOutput::default();
    out.value("z_peak", Value::Number(zpk));
    out.value("t_z_peak", Value::Number(run.t[k]));
    out.value(
        "phi_peaks",
        Value::Vector(ext[..3].iter().map(|e| e.1).collect()),
    );
    out.value(
        "t_phi_peaks",
        Value::Vector(ext[..3].iter().map(|e| e.0).collect()),
    );
    out.value("z_final", Value::Number(run.z_final()));
    out.value(
        "phi_peaks_1ms",
        Value::Vector(ext_1ms.iter().take(3).map(|e| e.1).collect()),
    );
    let src = "book Part 1 §3.4";
    out.reference("z_peak", Value::Number(0.237), src, 0.0005);
    out.reference("t_z_peak", Value::Number(0.54), src, 0.005);
    out.reference("z_final", Value::Number(0.200), src, 0.0005);
    out.reference(
        "phi_peaks",
        Value::Vector(vec![0.394, -0.701, 0.755]),
        src,
        0.0005,
    );
    out.reference(
        "t_phi_peaks",
        Value::Vector(vec![0.30, 0.79, 1.35]),
        src,
        0.005,
    );
    out.notes.push(
        "Nonlinear cart pendulum (table 3.5), u = k_P (0.2 − z), k_P = 10, the step at t = 0, \
         pendulum hanging, plain plant (no quantisation), controller acting continuously (10 µs \
         loop, recorded every 1 ms) as in the book's Simulink model; phi_peaks_1ms: the same \
         with the rig's 1 ms sampling. φ = θ − π; t_phi_peaks: times \
         of the first three extrema. The figure overlays the rig's k_P = 10 record shifted by \
         its 1 s step."
            .into(),
    );
    if ctx.figures {
        let (_, name, text) = PCONT[2];
        let d = from(
            ID34,
            &dataset(ID34, name, text)?,
            Some(STEP_TIME),
            Some(STEP_TIME + 4.0),
        )?;
        let tm: Vec<f64> = d.time().ctx(ID34)?.iter().map(|t| t - STEP_TIME).collect();
        let zm = d.column("z").ctx(ID34)?.to_vec();
        let pm = d.column("theta").ctx(ID34)?.to_vec();
        let fig = stacked(
            "p1c34_cdip_plot_pcont: k_P = 10, simulation and experiment",
            "time after the step [s]",
            vec![
                PanelSpec::new(
                    "cart position z [m]",
                    vec![
                        ("simulation".into(), &run.t, run.z.clone()),
                        ("experiment".into(), &tm, zm),
                    ],
                )
                .reference(TARGET, "target"),
                PanelSpec::new(
                    "pendulum angle φ [rad]",
                    vec![
                        ("simulation".into(), &run.t, run.phi.clone()),
                        ("experiment".into(), &tm, pm),
                    ],
                ),
            ],
        );
        write_figure(&mut out, "p1c34_cdip_plot_pcont_response", fig);
        write_animation(
            ID34,
            &mut out,
            "p1c34_cdip_plot_pcont_anim",
            animation(
                Rig::Cart,
                &run.t,
                &run.z,
                &run.theta,
                "cart P control, k_P = 10",
            ),
        )?;
    }
    Ok(out)
}
