//! Part 1 §2.2–§2.3: identifying the cart drive, model-matching P, P–D and I–PD designs, and the
//! crane: I–PD with and without feeding the pendulum's swing back.

use super::*;

pub(super) const ID221: &str = "p1c221_id_cart";

/// What `cartident.m` returns for one voltage step: the gain `K` and the time constant `T`.
#[derive(Debug, Clone, Copy)]
pub(super) struct CartIdent {
    /// `K = mean(dy(1400:1500))/ref` (m/s per V).
    pub(super) k: f64,
    /// `T = t(k)`, the last sample before the velocity first crosses `0.632 K ref` (s).
    pub(super) t: f64,
}

/// `cartident.m` (called by `p1c221_id_cart.m`, line 36) line by line on the sampled position
/// `y` at times `t` (`t[0] = 0`, step `ts`):
///
/// - lines 5–10: `dy` by three-point differentiation, the one-sided formulas at both ends;
/// - lines 3, 14–15: `datasize = int32(tend/ts)`, `init_data = int32(1.4/ts)` (1500 and 1400 for
///   the M-file's `ts = 0.001`, `tend = 1.5`) and `K = mean(dy(init_data:datasize))`, i.e. the
///   101 samples `t = 1.399 … 1.499 s` of MATLAB's 1-based array;
/// - lines 17–24: the first `i ≤ datasize` with `dy(i) < 0.632 K` and `dy(i+1) > 0.632 K` (both
///   strict), and `T = t(i)`, the sample *before* the crossing;
/// - line 26: `K = K/ref`.
///
/// # Errors
/// [`BookError::Computation`] if the record is shorter than `datasize + 1` samples or the
/// velocity never crosses `0.632 K` (where MATLAB would stop with "undefined k").
pub(super) fn cartident(
    id: &'static str,
    t: &[f64],
    y: &[f64],
    reference: f64,
    ts: f64,
    tend: f64,
) -> Result<CartIdent, BookError> {
    // MATLAB's int32() rounds to the nearest integer.
    let datasize = (tend / ts).round() as usize;
    let init_data = (1.4 / ts).round() as usize;
    if y.len() != t.len() || y.len() < datasize + 1 || init_data < 1 || init_data > datasize {
        return Err(fail(
            id,
            format!(
                "cartident needs {} samples of t and y (tend/ts + 1), got {} and {}",
                datasize + 1,
                t.len(),
                y.len()
            ),
        ));
    }
    let dy = pendulab_ident::three_point(y, ts).ctx(id)?;
    // dy(init_data:datasize), 1-based and inclusive.
    let window = &dy[init_data - 1..datasize];
    let k = window.iter().sum::<f64>() / window.len() as f64;
    let level = 0.632 * k;
    // for i = 1:datasize: dy(i) < 0.632K & dy(i+1) > 0.632K → T = t(i).
    let i = (0..datasize)
        .find(|&i| dy[i] < level && dy[i + 1] > level)
        .ok_or_else(|| {
            fail(
                id,
                format!(
                    "the velocity never crosses 0.632 K = {level} m/s before sample {datasize} \
                     (cartident.m, lines 17-22)"
                ),
            )
        })?;
    Ok(CartIdent {
        k: k / reference,
        t: t[i],
    })
}

/// MATLAB's `round(x*10^3)/10^3` (half away from zero, as `f64::round`).
pub(super) fn round3(x: f64) -> f64 {
    (x * 1e3).round() / 1e3
}

pub(super) fn p1c221_id_cart(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let e = ID221;
    // p1c221_id_cart.m, lines 33–63: cart_model.slx for ref = 0.8, 0.9, 1.0, 1.1 V, each record
    // through cartident(t, y_raw, ref, 0.001, 1.5). The model is the cart with the encoder and
    // D/A quantizers and ±5 V, the step applied at t = 0, 1 ms fixed step: pendulab's quantised
    // rig with a constant input. y_raw is the encoder position.
    let refs = [0.8, 0.9, 1.0, 1.1];
    let mut runs = Vec::new();
    let mut ids = Vec::new();
    let mut exact = Vec::new();
    for u in refs {
        let ctrl = OpenLoop::new(vec![Signal::step(0.0, u).ctx(e)?], 4);
        let run = simulate_cart(ID221, format!("u(t) = {u}"), ctrl, true, None, 2.0)?;
        ids.push(cartident(e, &run.t, &run.z_measured, u, TS, 1.5)?);
        exact.push(cartident(e, &run.t, &run.z, u, TS, 1.5)?);
        runs.push(run);
    }
    // Lines 69–70: the means rounded to 1e-3; lines 72–77 print K, T, a = 1/T, b = K/T.
    let mean = |f: &dyn Fn(&CartIdent) -> f64, v: &[CartIdent]| {
        v.iter().map(f).sum::<f64>() / v.len() as f64
    };
    let tave = round3(mean(&|c| c.t, &ids));
    let kave = round3(mean(&|c| c.k, &ids));
    let (a, b) = (1.0 / tave, kave / tave);
    let mut out = ExampleOutput::default();
    out.value("ac", Value::Number(a));
    out.value("bc", Value::Number(b));
    out.value("Kave", Value::Number(kave));
    out.value("Tave", Value::Number(tave));
    out.value("a", Value::Number(a));
    out.value("b", Value::Number(b));
    for (j, c) in ids.iter().enumerate() {
        out.value(&format!("K{}", j + 1), Value::Number(c.k));
        out.value(&format!("T{}", j + 1), Value::Number(c.t));
    }
    // pendulab's addition: the same recipe on the exact (unquantised) cart position.
    let tx = round3(mean(&|c| c.t, &exact));
    let kx = round3(mean(&|c| c.k, &exact));
    out.value("ac_unquantised", Value::Number(1.0 / tx));
    out.value("bc_unquantised", Value::Number(kx / tx));
    // The drive model z̈ = −a_c ż + b_c v (z in m, v in V): K = b_c/a_c is the steady
    // velocity per volt, T = 1/a_c the time constant.
    let (ks, ts): (Vec<String>, Vec<String>) = (1..=ids.len())
        .map(|j| (format!("K{j}"), format!("T{j}")))
        .unzip();
    let ks: Vec<&str> = ks.iter().map(String::as_str).collect();
    let ts: Vec<&str> = ts.iter().map(String::as_str).collect();
    out.unit(&["ac", "a", "ac_unquantised"], "1/s")
        .unit(&["bc", "b", "bc_unquantised"], "m/(s²·V)")
        .unit(&["Kave"], "m/(s·V)")
        .unit(&ks, "m/(s·V)")
        .unit(&["Tave"], "s")
        .unit(&ts, "s");
    // The book prints a = 6.250e+00, b = 4.362e+00 (Kave = 0.698, Tave = 0.160 → b = 4.3625):
    // both are exact results of the rounded means, so the tolerance is the rounding of b's
    // last printed digit.
    let src = "book §2.2.1 (p1c221_id_cart.m, lines 72-77)";
    out.reference("Kave", Value::Number(0.698), src, 1e-9);
    out.reference("Tave", Value::Number(0.160), src, 1e-9);
    out.reference("a", Value::Number(6.250), src, 0.0005);
    out.reference("b", Value::Number(4.3625), src, 0.0005);
    out.reference(
        "ac",
        Value::Number(6.250),
        "book Part 1 §2.2.1 (cdip_para2.m)",
        0.0005,
    );
    out.reference(
        "bc",
        Value::Number(4.362),
        "book Part 1 §2.2.1 (cdip_para2.m)",
        0.001,
    );
    out.notes.push(
        "As p1c221_id_cart.m with cartident.m: open-loop voltage steps u = 0.8, 0.9, 1.0, 1.1 V \
         on the simulated rig (nonlinear cart pendulum, table 3.5, encoder and 16-bit D/A \
         quantizers, 1 ms); dy by three-point differentiation of the encoder position; K_i = \
         mean of dy over samples 1400-1500 of the M-file's 1-based array (t = 1.399-1.499 s) \
         divided by u; T_i = the last sample below 0.632 K u before the first crossing. Kave, \
         Tave: the means rounded to 1e-3 (lines 69-70); a = 1/Tave, b = Kave/Tave (ac, bc). \
         The quantised velocity moves in steps of 0.024 m/s, so the T_i scatter by several ms \
         (K1..K4, T1..T4); ac_unquantised, bc_unquantised: the same recipe on the exact \
         position."
            .into(),
    );
    if ctx.figures {
        let vel: Vec<Vec<f64>> = runs
            .iter()
            .map(|r| pendulab_ident::three_point(&r.z_measured, TS).ctx(e))
            .collect::<Result<_, _>>()?;
        let lines: Vec<Line<'_>> = runs
            .iter()
            .zip(&vel)
            .map(|(r, v)| (r.label.clone(), r.t.as_slice(), v.clone()))
            .collect();
        let mut panel = PanelSpec::new("dy(t)/dt [m/s]", lines);
        for (u, c) in refs.iter().zip(&ids) {
            panel = panel.reference(c.k * u, &format!("K u = {:.3}", c.k * u));
        }
        let fig = stacked(
            "p1c221_id_cart: open-loop velocity steps",
            "t [s]",
            vec![panel],
        );
        write_figure(&mut out, "p1c221_id_cart_velocity", fig);
    }
    Ok(out)
}

/// Step response of the reference model ω_n²/(s² + 2ζω_n s + ω_n²) at times `t`.
pub(super) fn second_order_step(t: &[f64], wn: f64, zeta: f64) -> Vec<f64> {
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let phi = zeta.acos();
    t.iter()
        .map(|&t| {
            R * (1.0 - (-zeta * wn * t).exp() / (1.0 - zeta * zeta).sqrt() * (wd * t + phi).sin())
        })
        .collect()
}

pub(super) const ZETA: f64 = std::f64::consts::FRAC_1_SQRT_2;

pub(super) const ID223: &str = "p1c223_pcont";

pub(super) fn p1c223_pcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let (ac, bc) = drive();
    let speed = |wn: f64| wn * wn / bc;
    let partial = |wn: f64| ac * wn / (2.0 * bc * ZETA);
    let gains = [
        ("kP_speed_wn5", "speed matching, ω_n = 5", speed(5.0)),
        ("kP_speed_wn10", "speed matching, ω_n = 10", speed(10.0)),
        (
            "kP_partial_wn10",
            "partial model matching, ω_n = 10",
            partial(10.0),
        ),
    ];
    let mut out = ExampleOutput::default();
    let mut runs = Vec::new();
    for (name, label, kp) in gains {
        out.value(name, Value::Number(kp));
        runs.push(simulate_cart(
            ID223,
            format!("{label} (k_P = {kp:.3})"),
            pid(ID223, PidForm::P { kp })?,
            true,
            None,
            3.0,
        )?);
    }
    finish_model_match(
        ctx,
        out,
        ID223,
        "Reference model ω_n²/(s² + 2ζω_n s + ω_n²), ζ = 1/√2. Speed matching equates the \
         constant terms: k_P = ω_n²/b_c; partial model matching the ratio of the first two \
         coefficients: k_P = a_c ω_n/(2 b_c ζ). a_c, b_c from table 3.5.",
        "P control against the reference models",
        &runs,
    )
}

/// The tail of the model-matching examples (p1c223, p1c224 P–D): the gains note and the
/// example's `note`, the figure `{id}_response` (titled `{id}: {title}`) of the runs against
/// the reference models, and the note that the M-file displays no number.
fn finish_model_match(
    ctx: &RunContext,
    mut out: ExampleOutput,
    id: &str,
    note: &str,
    title: &str,
    runs: &[CartRun],
) -> Result<ExampleOutput, BookError> {
    out.notes.push(NOTE_GAINS.into());
    out.notes.push(note.into());
    if ctx.figures {
        let fig = model_match_figure(&format!("{id}: {title}"), runs);
        write_figure(&mut out, &format!("{id}_response"), fig);
    }
    no_display_note(
        &mut out,
        id,
        "it sets the gains and draws the responses of its Simulink model",
    );
    Ok(out)
}

/// Cart position and input of `runs` (3 s steps of r), the position overlaid with the reference
/// models' steps for ω_n = 5 and 10 rad/s.
pub(super) fn model_match_figure(title: &str, runs: &[CartRun]) -> pendulab_plot::Figure {
    let t = runs[0].t.clone();
    let mut lines: Vec<Line<'_>> = runs
        .iter()
        .map(|r| (r.label.clone(), r.t.as_slice(), r.z.clone()))
        .collect();
    lines.push(("model ω_n = 5".into(), &t, second_order_step(&t, 5.0, ZETA)));
    lines.push((
        "model ω_n = 10".into(),
        &t,
        second_order_step(&t, 10.0, ZETA),
    ));
    stacked(
        title,
        "time [s]",
        vec![
            PanelSpec::new("cart position z [m]", lines),
            PanelSpec::new(
                "input voltage v [V]",
                runs.iter()
                    .map(|r| (r.label.clone(), r.t.as_slice(), r.v.clone()))
                    .collect(),
            ),
        ],
    )
}

pub(super) const ID224PD: &str = "p1c224_p_dcont";

pub(super) fn p1c224_p_dcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let (ac, bc) = drive();
    let mut out = ExampleOutput::default();
    let mut runs = Vec::new();
    for wn in [5.0, 10.0] {
        let kp = wn * wn / bc;
        let kd = (2.0 * ZETA * wn - ac) / bc;
        out.value(&format!("kP_wn{wn}"), Value::Number(kp));
        out.value(&format!("kD_wn{wn}"), Value::Number(kd));
        runs.push(simulate_cart(
            ID224PD,
            format!("ω_n = {wn} (k_P = {kp:.3}, k_D = {kd:.3})"),
            pid(ID224PD, PidForm::PMinusD { kp, kd, tf: TF })?,
            true,
            None,
            3.0,
        )?);
    }
    finish_model_match(
        ctx,
        out,
        ID224PD,
        "P–D (derivative on the output z): the loop is exactly the reference model \
         ω_n²/(s² + 2ζω_n s + ω_n²) with k_P = ω_n²/b_c, k_D = (2ζω_n − a_c)/b_c, ζ = 1/√2.",
        "P–D control and its reference models",
        &runs,
    )
}

/// I–PD gains `[k_I, k_P, k_D]` from `s³ + α₂ω_n s² + α₁ω_n² s + ω_n³`, in the order of
/// `p1c224_i_pdcont.m` (lines 42–44): `k_I = ω_n³/b_c`, `k_P = α₁ω_n²/b_c`,
/// `k_D = (α₂ω_n − a_c)/b_c`.
pub(crate) fn ipd_gains(alpha1: f64, alpha2: f64, wn: f64) -> [f64; 3] {
    let (ac, bc) = drive();
    [
        wn.powi(3) / bc,
        alpha1 * wn * wn / bc,
        (alpha2 * wn - ac) / bc,
    ]
}

pub(super) const ID224IPD: &str = "p1c224_i_pdcont";

pub(super) fn p1c224_i_pdcont(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let wn = 10.0;
    let mut out = ExampleOutput::default();
    let mut runs = Vec::new();
    // p1c224_i_pdcont.m: omegaM = 10 (line 36); (alpha1, alpha2) = (3, 3) binomial (lines
    // 39–40), (2, 2) Butterworth (lines 54–55), (2.15, 1.75) ITAE (lines 68–69).
    for (name, label, alpha1, alpha2) in [
        ("gains_binomial", "binomial", 3.0, 3.0),
        ("gains_butterworth", "Butterworth", 2.0, 2.0),
        ("gains_itae", "ITAE", 2.15, 1.75),
    ] {
        let [ki, kp, kd] = ipd_gains(alpha1, alpha2, wn);
        out.value(name, Value::Vector(vec![ki, kp, kd]));
        runs.push(simulate_cart(
            ID224IPD,
            label,
            pid(ID224IPD, PidForm::IPD { kp, ki, kd, tf: TF })?,
            true,
            None,
            3.0,
        )?);
    }
    out.value("alpha1", Value::Vector(vec![3.0, 2.0, 2.15]));
    out.value("alpha2", Value::Vector(vec![3.0, 2.0, 1.75]));
    // The M-file's ITAE gains with table 3.5 (a_c = 6.25, b_c = 4.36), rounded to 1e-3:
    // [1000/4.36, 215/4.36, (17.5 − 6.25)/4.36].
    out.reference(
        "gains_itae",
        Value::Vector(vec![229.358, 49.312, 2.580]),
        "p1c224_i_pdcont.m, lines 68-73",
        0.0005,
    );
    out.notes.push(NOTE_GAINS.into());
    out.notes.push(
        "I–PD u = (k_I/s) e − k_P z − k_D ż: closed loop b_c k_I/(s³ + (a_c + b_c k_D) s² + \
         b_c k_P s + b_c k_I) matched to ω_n³/(s³ + α₂ω_n s² + α₁ω_n² s + ω_n³), ω_n = 10, as \
         p1c224_i_pdcont.m: kI = ω_n³/b, kP = α₁ω_n²/b, kD = (α₂ω_n − a)/b; gains reported as \
         [kI, kP, kD] for (α₁, α₂) = (3, 3) binomial, (2, 2) Butterworth, (2.15, 1.75) ITAE \
         (alpha1, alpha2 in that order)."
            .into(),
    );
    if ctx.figures {
        let fig = response_figure("p1c224_i_pdcont: I–PD, ω_n = 10", &runs, R);
        write_figure(&mut out, "p1c224_i_pdcont_response", fig);
    }
    Ok(out)
}

/// I–PD on the cart position plus pendulum damping `u ← u − (k_P2 φ + k_D2 φ̇)` (book §2.3).
#[derive(Debug, Clone)]
pub(super) struct Crane {
    pub(super) ipd: Pid,
    pub(super) kp2: f64,
    pub(super) kd2: f64,
}

impl Controller for Crane {
    fn ny(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {
        self.ipd.reset();
    }
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        self.ipd.update(t, y, u);
        // y = [z, θ, ż, θ̇] (quantised, pseudo-differentiated); φ = θ − π.
        u[0] -= self.kp2 * (y[1] - PI) + self.kd2 * y[3];
    }
    fn sample_time(&self) -> Option<f64> {
        self.ipd.sample_time()
    }
}

pub(super) const ID23: &str = "p1c23_crane";

pub(super) fn p1c23_crane(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let e = ID23;
    let [ki, kp, kd] = ipd_gains(2.0, 2.0, 10.0);
    let plant = CartPendulum::book();
    let lin = plant.linearize(CartEquilibrium::hanging()).ctx(e)?;
    let mut out = ExampleOutput::default();
    let mut runs = Vec::new();
    for (name, kp2, kd2) in [("without", 0.0, 0.0), ("with", -1.0, -0.1)] {
        // Linear closed loop on x̃ = [z, φ, ż, φ̇, w], ẇ = r − z, u = k_I w − k_P z − k_D ż −
        // k_P2 φ − k_D2 φ̇ (ideal derivative).
        let mut acl = Mat::zeros(5, 5);
        acl.view_mut((0, 0), (4, 4)).copy_from(lin.a());
        acl[(4, 0)] = -1.0;
        let k = [-kp, -kp2, -kd, -kd2, ki];
        for i in 0..4 {
            for (j, kj) in k.iter().enumerate() {
                acl[(i, j)] += lin.b()[(i, 0)] * kj;
            }
        }
        let poles = pendulab_lti::linalg::eigenvalues(&acl).ctx(e)?;
        out.value(&format!("poles_{name}"), Value::Complex(sorted(poles)));
        let ctrl = Crane {
            ipd: pid(ID23, PidForm::IPD { kp, ki, kd, tf: TF })?,
            kp2,
            kd2,
        };
        let label = if name == "without" {
            "without damping".to_string()
        } else {
            "with damping (k_P2 = −1, k_D2 = −0.1)".to_string()
        };
        let run = simulate_cart(ID23, label, ctrl, true, None, 5.0)?;
        let k1 = run.t.partition_point(|&t| t < 1.0);
        let m = run.phi[k1..].iter().fold(0.0f64, |m, p| m.max(p.abs()));
        out.value(&format!("phi_max_after_1s_{name}"), Value::Number(m));
        runs.push(run);
    }
    out.notes.push(NOTE_GAINS.into());
    out.notes.push(
        "I–PD (Butterworth, ω_n = 10) on the cart; the damping term u ← u − (k_P2 φ + k_D2 φ̇) \
         with k_P2 = −1, k_D2 = −0.1 feeds the swing back into the drive. poles_*: the \
         linearised (hanging) closed loop on [z, φ, ż, φ̇, w]; without damping they are the \
         I–PD poles ω_n·{−1, −½ ± j√3/2} and the free pendulum's. phi_max_after_1s_*: the \
         largest |φ| after the cart has arrived."
            .into(),
    );
    if ctx.figures {
        let fig = response_figure("p1c23_crane: I–PD with and without damping", &runs, R);
        write_figure(&mut out, "p1c23_crane_response", fig);
        for (run, stem) in runs.iter().zip(["without", "with"]) {
            write_animation(
                ID23,
                &mut out,
                &format!("p1c23_crane_anim_{stem}"),
                animation(
                    Rig::Cart,
                    &run.t,
                    &run.z,
                    &run.theta,
                    &format!("crane, {}", run.label),
                ),
            )?;
        }
    }
    no_display_note(
        &mut out,
        "p1c23_crane",
        "it sets the gains and draws the responses of its Simulink model",
    );
    Ok(out)
}
