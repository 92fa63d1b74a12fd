//! Part 1 chapter 6 — internal model principle and servo systems.
//!
//! Examples 6.1–6.4 use the linear cart drive `P(s) = b_c/(s² + a_c s)` (book eq. 6.7) under P
//! or PI control; example 6.5 is the LQ integral servo of the nonlinear cart pendulum. Gains are
//! reported in the book's convention `u = +K x`.

use super::common::*;
use super::mfile_refs::{OctaveDisplay, display_note};
use crate::error::BookError;
use crate::output::{ExampleOutput, Value};
use crate::registry::{Example, RunContext};
use pendulab_lti::design::lq_servo;
use pendulab_lti::interconnect::{feedback_tf, series_tf};
use pendulab_lti::response::{LsimOptions, lsim, time_vector};
use pendulab_lti::{
    Complex64, Continuous, FeedbackSign, InputHold, LtiError, Mat, StateSpace, Trajectory,
    TransferFunction,
};
use pendulab_plants::{CartEquilibrium, CartPendulum, CartPendulumParams, Drive, RigSpec};
use pendulab_plot::{Channel, SignalPanel, TimeResponse};
use pendulab_sim::controllers::{IntegrationRule, LqIntegralServo};
use pendulab_sim::{DisturbancePoint, SampledLoop, SampledOptions, Signal};

/// The chapter's examples, in book order.
pub(crate) fn examples() -> Vec<Example> {
    vec![
        Example {
            id: "p1c62_ex1_cart_p_step",
            title: "P control of the cart drive, step reference",
            section: "Part 1 §6.2, example 6.1",
            parameters: "P(s) = b_c/(s² + a_c s), table 3.5; k_P = 10, r = 0.5 m, 2.5 s",
            needs_data: None,
            run: ex1,
        },
        Example {
            id: "p1c62_ex2_cart_pi_ramp",
            title: "PI control of the cart drive, ramp reference",
            section: "Part 1 §6.2, example 6.2",
            parameters: "P(s) = b_c/(s² + a_c s), table 3.5; k_P = 10, k_I = 15, r = 0.1 t, 2.5 s",
            needs_data: None,
            run: ex2,
        },
        Example {
            id: "p1c62_ex3_cart_p_step_dis",
            title: "P control with a step disturbance",
            section: "Part 1 §6.2, example 6.3",
            parameters: "P(s) = b_c/(s² + a_c s); k_P = 10, r0 = 0.5 m, d0 = 3 V at 2.5 s, 5 s",
            needs_data: None,
            run: ex3,
        },
        Example {
            id: "p1c62_ex4_cart_pi_step_dis",
            title: "PI control with a step disturbance",
            section: "Part 1 §6.2, example 6.4",
            parameters: "P(s) = b_c/(s² + a_c s); k_P = 10, k_I = 15, r0 = 0.5 m, d0 = 3 V at 2.5 s, 5 s",
            needs_data: None,
            run: ex4,
        },
        Example {
            id: "p1c63_ex5_cdip_lqr_servo",
            title: "LQ integral servo of the cart pendulum",
            section: "Part 1 §6.3, example 6.5",
            parameters: "cart pendulum, table 3.5; q1 = 800, q2 = 20000, R = 1; nonlinear plant, filtered derivatives, 1 ms",
            needs_data: None,
            run: ex5_cdip_lqr_servo,
        },
    ]
}

/// A controller `C(s)` of the cart drive `P(s) = b_c/(s² + a_c s)` (book eq. 6.7) and the
/// loop's transfer functions by the toolkit's interconnections: `S = 1/(1 + PC)` from `r` to
/// `e` and `S P` from the input disturbance `d` to `−e` (book eqs 6.6, 6.19: `e = S r − S P d`).
pub(crate) struct DriveLoop {
    a: f64,
    b: f64,
    kp: f64,
    ki: Option<f64>,
    /// `S = 1/(1 + P C)`.
    sensitivity: TransferFunction<Continuous>,
    /// `S P = P/(1 + P C)`.
    disturbance: TransferFunction<Continuous>,
}

impl DriveLoop {
    /// P (`ki = None`) or PI control `C(s) = k_P + k_I/s` of the book's drive (table 3.5,
    /// [`Drive::transfer_function`]).
    ///
    /// # Errors
    /// The toolkit's errors (none for finite gains).
    pub(crate) fn new(id: &str, kp: f64, ki: Option<f64>) -> Result<Self, BookError> {
        let p = CartPendulumParams::book();
        let plant = Drive::new(p.a_c, p.b_c)
            .and_then(|d| d.transfer_function())
            .ctx(id)?;
        let controller = match ki {
            None => TransferFunction::continuous(&[kp], &[1.0]),
            Some(ki) => TransferFunction::continuous(&[kp, ki], &[1.0, 0.0]),
        }
        .ctx(id)?;
        let one = TransferFunction::gain(1.0, Continuous).ctx(id)?;
        let open_loop = series_tf(&controller, &plant).ctx(id)?;
        Ok(Self {
            a: p.a_c,
            b: p.b_c,
            kp,
            ki,
            sensitivity: feedback_tf(&one, &open_loop, FeedbackSign::Negative).ctx(id)?,
            disturbance: feedback_tf(&plant, &controller, FeedbackSign::Negative).ctx(id)?,
        })
    }

    /// Closed-loop poles: the roots of the characteristic polynomial
    /// `den_C den_P + num_C num_P` (the denominator of `S`).
    pub(crate) fn poles(&self) -> Result<Vec<Complex64>, LtiError> {
        self.sensitivity.poles().map(sorted)
    }

    /// `e∞` for the reference `r0/s^k` (`k` = 1 step, 2 ramp) and the input disturbance
    /// `d0/s` by the final-value theorem: `r0 · lim s→0 S(s)/s^(k−1) − d0 · (S P)(0)`, each a
    /// DC gain with the common factors `s` cancelled.
    ///
    /// # Errors
    /// [`LtiError::PoleAtEvaluationPoint`] when a term grows without bound (a loop of too
    /// low a type for the signal).
    pub(crate) fn e_inf(&self, r0: f64, k: i32, d0: f64) -> Result<f64, LtiError> {
        let er = if r0 == 0.0 {
            0.0
        } else {
            let mut g = self.sensitivity.clone();
            for _ in 1..k {
                let integrator = TransferFunction::continuous(&[1.0], &[1.0, 0.0])?;
                g = series_tf(&g, &integrator)?;
            }
            r0 * g.dc_gain()?
        };
        let ed = if d0 == 0.0 {
            0.0
        } else {
            d0 * self.disturbance.dc_gain()?
        };
        Ok(er - ed)
    }

    /// The closed loop in state space for [`lsim`], inputs `[r, d]`, outputs `[z, e, v]`;
    /// states `[z, ż]` (P) or `[z, ż, ∫e]` (PI, `v = k_P e + k_I ∫e`). Written out: the
    /// toolkit's interconnections close SISO loops and give no internal signals (`e`, `v`) as
    /// outputs.
    fn state_space(&self) -> Result<StateSpace<Continuous>, LtiError> {
        let (a, b, kp, ki) = (self.a, self.b, self.kp, self.ki);
        let n = if ki.is_some() { 3 } else { 2 };
        let mut am = Mat::zeros(n, n);
        let mut bm = Mat::zeros(n, 2);
        let mut cm = Mat::zeros(3, n);
        let mut dm = Mat::zeros(3, 2);
        am[(0, 1)] = 1.0;
        am[(1, 0)] = -b * kp;
        am[(1, 1)] = -a;
        bm[(1, 0)] = b * kp;
        bm[(1, 1)] = b;
        cm[(0, 0)] = 1.0;
        cm[(1, 0)] = -1.0;
        dm[(1, 0)] = 1.0;
        cm[(2, 0)] = -kp;
        dm[(2, 0)] = kp;
        if let Some(ki) = ki {
            am[(1, 2)] = b * ki;
            am[(2, 0)] = -1.0;
            bm[(2, 0)] = 1.0;
            cm[(2, 2)] = ki;
        }
        StateSpace::continuous(am, bm, cm, dm)
    }

    /// Simulates the loop on `[0, t_final]` at 1 ms for `r(t)` and `d(t)`.
    fn simulate(
        &self,
        t_final: f64,
        r: impl Fn(f64) -> f64,
        d: impl Fn(f64) -> f64,
    ) -> Result<Trajectory, LtiError> {
        let sys = self.state_space()?;
        let t = time_vector(t_final, 1e-3)?;
        let u = Mat::from_fn(t.len(), 2, |k, j| if j == 0 { r(t[k]) } else { d(t[k]) });
        // The steps are held between samples (a step at 2.5 s acts from 2.5 s on).
        lsim(
            &sys,
            &u,
            &t,
            None,
            &LsimOptions {
                hold: InputHold::Zoh,
            },
        )
    }
}

fn drive_figure(
    ctx: &RunContext,
    id: &str,
    title: &str,
    traj: &Trajectory,
    out: &mut ExampleOutput,
) -> Result<(), BookError> {
    if !ctx.figures {
        return Ok(());
    }
    let fig = TimeResponse::new()
        .run("simulation", traj)
        .title(title)
        .panel(
            SignalPanel::new(Channel::Output(0), "position [m]")
                .named("y = z")
                .with(Channel::Input(0), "r"),
        )
        .panel(SignalPanel::new(Channel::Output(1), "error e [m]"))
        .panel(
            SignalPanel::new(Channel::Output(2), "voltage [V]")
                .named("u")
                .with(Channel::Input(1), "d"),
        )
        .figure()
        .ctx(id)?;
    save_figure(ctx, out, id, "response", Ok(fig))
}

struct DriveCase {
    id: &'static str,
    title: &'static str,
    ki: Option<f64>,
    ramp: bool,
    d0: f64,
    t_final: f64,
    book_poles: Option<&'static [(f64, f64)]>,
    book_e_inf: f64,
    /// The M-file's display as GNU Octave printed it, and which of its displays are the
    /// closed-loop poles `tzero(Delta)` (`ans`, `ans#2`) at which line; what else it displays.
    octave: &'static str,
    octave_poles: (&'static str, &'static str),
    not_compared: &'static [(&'static str, &'static str)],
    /// What it shows that is not a displayed number of its own (see [`display_note`]).
    not_numbers: &'static [(&'static str, &'static str)],
}

fn drive_example(ctx: &RunContext, c: &DriveCase) -> Result<ExampleOutput, BookError> {
    let id = c.id;
    let lp = DriveLoop::new(id, 10.0, c.ki)?;
    let poles = lp.poles().ctx(id)?;
    let r0 = if c.ramp { 0.1 } else { 0.5 };
    let k = if c.ramp { 2 } else { 1 };
    let e_inf = lp.e_inf(r0, k, c.d0).ctx(id)?;
    let ramp = c.ramp;
    let d0 = c.d0;
    let traj = lp
        .simulate(
            c.t_final,
            move |t| if ramp { 0.1 * t } else { 0.5 },
            move |t| if t >= 2.5 - 1e-9 { d0 } else { 0.0 },
        )
        .ctx(id)?;
    let e_end = traj.y_signal(1).last().copied().unwrap_or(f64::NAN);
    let mut out = ExampleOutput::default();
    out.value("poles", Value::Complex(poles))
        .value("e_inf", Value::Number(e_inf))
        .value("e_final_sim", Value::Number(e_end));
    if let Some(p) = c.book_poles {
        // Printed to 3 decimals in re and im: half a unit in each, |Δ| ≤ 5e-4·√2.
        out.reference(
            "poles",
            Value::Complex(sorted(complex(p))),
            "book Part 1 §6.2",
            5e-4 * 2f64.sqrt(),
        );
    }
    // e∞ is printed exactly (0 or −d0/k_P = −0.3); the final-value theorem on exact
    // polynomial data reproduces it to rounding.
    out.reference(
        "e_inf",
        Value::Number(c.book_e_inf),
        "book Part 1 §6.2",
        1e-12,
    );
    // tzero(Delta), Delta = 1 + P(s)C(s): the roots of the characteristic polynomial, as GNU
    // Octave printed them running the M-file (its Simulink runs shimmed).
    let disp = OctaveDisplay::parse(id, c.octave);
    let (ans, line) = c.octave_poles;
    disp.compare(id, &mut out, "poles", ans, line)?;
    display_note(
        &mut out,
        id,
        &["tzero(Delta) (as poles)"],
        c.not_compared,
        c.not_numbers,
    );
    out.notes.push(format!(
        "e∞ by the final-value theorem; the simulated error at {} s is {e_end:.4} m.",
        c.t_final
    ));
    drive_figure(ctx, id, c.title, &traj, &mut out)?;
    Ok(out)
}

fn ex1(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    drive_example(
        ctx,
        &DriveCase {
            id: "p1c62_ex1_cart_p_step",
            title: "p1c62_ex1: P control (k_P = 10), r = 0.5 m",
            ki: None,
            ramp: false,
            d0: 0.0,
            t_final: 2.5,
            book_poles: Some(&[(-3.125, 5.817), (-3.125, -5.817)]),
            book_e_inf: 0.0,
            octave: include_str!("../../tests/data/octave/p1c62_ex1_cart_p_step.txt"),
            octave_poles: ("ans", "line 21"),
            not_compared: &[],
            not_numbers: &[],
        },
    )
}

fn ex2(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    drive_example(
        ctx,
        &DriveCase {
            id: "p1c62_ex2_cart_pi_ramp",
            title: "p1c62_ex2: PI control (k_P = 10, k_I = 15), r = 0.1 t",
            ki: Some(15.0),
            ramp: true,
            d0: 0.0,
            t_final: 2.5,
            book_poles: Some(&[(-2.203, 5.534), (-2.203, -5.534), (-1.843, 0.0)]),
            book_e_inf: 0.0,
            octave: include_str!("../../tests/data/octave/p1c62_ex2_cart_pi_ramp.txt"),
            octave_poles: ("ans", "line 23"),
            not_compared: &[],
            not_numbers: &[],
        },
    )
}

fn ex3(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    drive_example(
        ctx,
        &DriveCase {
            id: "p1c62_ex3_cart_p_step_dis",
            title: "p1c62_ex3: P control, d0 = 3 V from 2.5 s",
            ki: None,
            ramp: false,
            d0: 3.0,
            t_final: 5.0,
            book_poles: None,
            book_e_inf: -0.3,
            octave: include_str!("../../tests/data/octave/p1c62_ex3_cart_p_step_dis.txt"),
            octave_poles: ("ans", "line 28"),
            not_compared: &[(
                "Delta (line 27)",
                "the transfer function 1 + P(s)C(s); its zeros are the poles compared, its \
                 coefficients are not",
            )],
            not_numbers: &[],
        },
    )
}

fn ex4(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    drive_example(
        ctx,
        &DriveCase {
            id: "p1c62_ex4_cart_pi_step_dis",
            title: "p1c62_ex4: PI control, d0 = 3 V from 2.5 s",
            ki: Some(15.0),
            ramp: false,
            d0: 3.0,
            t_final: 5.0,
            book_poles: None,
            book_e_inf: 0.0,
            octave: include_str!("../../tests/data/octave/p1c62_ex4_cart_pi_step_dis.txt"),
            octave_poles: ("ans#2", "line 44"),
            not_compared: &[(
                "Delta (lines 30, 43)",
                "the transfer functions 1 + P(s)C(s); their zeros are the poles compared, their \
                 coefficients are not",
            )],
            not_numbers: &[(
                "tzero(Delta) of the P loop (line 31)",
                "the poles of example p1c62_ex3_cart_p_step_dis, compared there",
            )],
        },
    )
}

fn ex5_cdip_lqr_servo(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p1c63_ex5_cdip_lqr_servo";
    let plant = CartPendulum::book();
    let lin = plant.linearize(CartEquilibrium::upright()).ctx(id)?;
    let cz = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
    let sys = StateSpace::continuous(
        lin.a().clone(),
        lin.b().clone(),
        cz.clone(),
        Mat::zeros(1, 1),
    )
    .ctx(id)?;
    // J = ∫ q1 e² + q2 w² + R u² with e = r − z (r = 0 in the design): Q = C̃ᵀ diag(q1, q2) C̃
    // = diag(q1 CᵀC, q2) on [x; w] (book eqs 6.24b, 6.30).
    let (q1, q2) = (800.0, 20000.0);
    let design = lq_servo(&sys, &diag(&[q1, 0.0, 0.0, 0.0, q2]), &diag(&[1.0])).ctx(id)?;
    let k1 = book_row(&design.state_gain);
    let k2 = book_row(&design.integral_gain);
    // Steady state of the linear loop (book eq. 6.33): x∞, w∞ from Ã + B̃K̃ and [B d0; r0].
    let (r0, d0) = (0.5, 5.0);
    let kb = Mat::from_row_slice(1, 5, &[k1[0], k1[1], k1[2], k1[3], k2[0]]);
    let (am, bm) = pendulab_lti::design::integral_augmentation(&sys).ctx(id)?;
    let acl = &am + &bm * &kb;
    let mut rhs = nalgebra::DVector::zeros(5);
    for i in 0..4 {
        rhs[i] = lin.b()[(i, 0)] * d0;
    }
    rhs[4] = r0;
    let xinf = acl
        .lu()
        .solve(&(-rhs))
        .ok_or_else(|| fail(id, "the servo loop matrix is singular"))?;
    let e_inf = r0 - xinf[0];

    // Nonlinear simulation: r = 0.5 m from 0, d = 5 V from 2.5 s, 5 s.
    let rig = filtered_rig(id, &RigSpec::cart())?;
    let ctrl = LqIntegralServo::from_design(
        &design,
        &cz,
        vec![Signal::constant(r0).ctx(id)?],
        1e-3,
        IntegrationRule::ForwardEuler,
    )
    .ctx(id)?;
    let mut chains = rig;
    chains.actuator = chains.actuator.disturbance(
        vec![Signal::step(2.5, d0).ctx(id)?],
        DisturbancePoint::AfterSaturation,
    );
    let opts = SampledOptions {
        t_final: 5.0,
        ..Default::default()
    };
    let mut lp = SampledLoop::new(plant, ctrl, opts)
        .and_then(|l| l.with_rig(chains))
        .ctx(id)?;
    let run = lp.run(&[0.0; 4]).ctx(id)?;
    let t = run.trajectory.t().to_vec();
    let z = column(run.trajectory.x(), 0);
    let undershoot = -min_of(&z).min(0.0);
    let e_end = r0 - z.last().copied().unwrap_or(f64::NAN);
    let theta_late = max_abs_after(&t, &column(run.trajectory.x(), 1), 4.5).to_degrees();

    let mut out = ExampleOutput::default();
    out.value("K1", Value::vector(&k1))
        .value("K2", Value::vector(&k2))
        .value("e_inf", Value::Number(e_inf))
        .value("undershoot", Value::Number(undershoot))
        .value("e_final_sim", Value::Number(e_end))
        .value("theta_max_after_4_5s_deg", Value::Number(theta_late));
    // e∞ = 0 (integral action, book eq. 6.33); solving the 5×5 system leaves rounding only.
    out.reference(
        "e_inf",
        Value::Number(0.0),
        "book Part 1 §6.3, eq. 6.33",
        1e-9,
    );
    // p1c63_ex5_cdip_lqr_servo.m lines 53-54 display K1 and K2 (Kt = −lqr(At, Bt, Ct'QCt, R),
    // line 51), as GNU Octave printed them running the M-file.
    let disp = OctaveDisplay::parse(
        id,
        include_str!("../../tests/data/octave/p1c63_ex5_cdip_lqr_servo.txt"),
    );
    disp.compare(id, &mut out, "K1", "K1", "line 53")?;
    disp.compare(id, &mut out, "K2", "K2", "line 54")?;
    display_note(
        &mut out,
        id,
        &["K1", "K2"],
        &[],
        &[(
            "the simulated responses",
            "Simulink runs (cdip_lqr_servo_sim, line 58 on), drawn, not displayed",
        )],
    );
    out.notes.push(format!(
        "K̃ = [K1, K2] in the book's convention u = K1 x + K2 w, w = ∫(r − z) dt. The cart first \
         moves {undershoot:.4} m the wrong way (non-minimum-phase zero of z/v). Simulated on the \
         nonlinear cart with pseudo-differentiated velocities; error at 5 s {e_end:.2e} m."
    ));
    if ctx.figures {
        let fig = TimeResponse::new()
            .run("LQ servo", &run.trajectory)
            .title("p1c63_ex5: LQ integral servo, r = 0.5 m, d = 5 V from 2.5 s")
            .panel(
                SignalPanel::new(Channel::State(0), "cart z [m]").reference(r0, Some("r0 = 0.5 m")),
            )
            .panel(
                SignalPanel::new(Channel::State(1), "pendulum θ [deg]")
                    .scaled(180.0 / std::f64::consts::PI),
            )
            .panel(SignalPanel::new(Channel::Input(0), "plant input v + d [V]").stairs())
            .figure()
            .ctx(id)?;
        save_figure(ctx, &mut out, id, "response", Ok(fig))?;
        save_run_animation(
            ctx,
            &mut out,
            id,
            Rig::Cart,
            &run.trajectory,
            "p1c63_ex5: LQ integral servo",
        )?;
    }
    Ok(out)
}
