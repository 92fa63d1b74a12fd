//! Tests of the `observer`, `pid` and `nmpc` kinds (parsing, checks, the observer's closed
//! loop, the PID against sim's `Pid` run directly). The agreement with the book's examples
//! (`p1c74_ex1_cdip_ob_design`, `p1c224_i_pdcont`) is tested where both are reachable,
//! `pendulab-rig`'s `tests/config_kinds.rs`.

use super::*;
use crate::scenario::simulate;
use pendulab_lti::Complex64;
use pendulab_lti::design::lq_servo;
use pendulab_sim::scenario::{Imperfections, ScenarioSpec};

fn parse(text: &str) -> Result<ControllerSpec, String> {
    toml::from_str(text).map_err(|e| e.to_string())
}

/// Example 7.1's state-feedback poles (book part 1 §7.4) and the observer's, four times them.
const EX71: &str = "poles = [[-6.5, 1.5], [-6.5, -1.5], [-4.0, 0.0], [-2.5, 0.0]]\nobserver_poles = [[-26.0, 6.0], [-26.0, -6.0], [-16.0, 0.0], [-10.0, 0.0]]\n";

#[test]
fn observer_closed_loop_poles_are_those_of_the_separation_principle_matrix() {
    let spec = parse(&format!("kind = \"observer\"\n{EX71}")).unwrap();
    let ControllerSpec::Observer(c) = &spec else {
        panic!("{spec:?}")
    };
    for kind in [PlantKind::Cart, PlantKind::Arm] {
        let plant = PlantSpec::book(kind);
        let d = observer_design(plant.parameters(), c).unwrap();
        let (a, b, cm) = (d.model.a(), d.model.b(), d.model.c());
        // In the coordinates [x; e = x − x̂] the closed loop is block triangular:
        // [[A − BK, BK], [0, A − LC]] (separation principle).
        let mut sep = Mat::zeros(8, 8);
        sep.view_mut((0, 0), (4, 4)).copy_from(&(a - b * &d.k));
        sep.view_mut((0, 4), (4, 4)).copy_from(&(b * &d.k));
        sep.view_mut((4, 4), (4, 4)).copy_from(&(a - &d.l * cm));
        let mut want = pendulab_lti::linalg::eigenvalues(&sep).unwrap();
        pendulab_lti::linalg::sort_eigenvalues(&mut want);
        let dist = |x: &[Complex64], y: &[Complex64]| {
            x.iter()
                .zip(y)
                .map(|(p, q)| (p - q).norm() / q.norm())
                .fold(0.0, f64::max)
        };
        assert!(
            dist(&d.closed_loop_poles, &want) < 1e-8,
            "{kind:?}: {:?} vs {want:?}",
            d.closed_loop_poles
        );
        // …and those are the placed poles, the state feedback's and the observer's.
        let mut placed: Vec<Complex64> = [
            (-6.5, 1.5),
            (-6.5, -1.5),
            (-4.0, 0.0),
            (-2.5, 0.0),
            (-26.0, 6.0),
            (-26.0, -6.0),
            (-16.0, 0.0),
            (-10.0, 0.0),
        ]
        .iter()
        .map(|&(re, im)| Complex64::new(re, im))
        .collect();
        pendulab_lti::linalg::sort_eigenvalues(&mut placed);
        assert!(dist(&d.closed_loop_poles, &placed) < 1e-7, "{kind:?}");
        // The built controller reads the 4-entry measurement and has the loop's period.
        let built = build_for(&spec, &plant, 1e-3).unwrap();
        assert_eq!((built.controller.ny(), built.controller.nu()), (4, 1));
        assert_eq!(built.controller.sample_time(), Some(1e-3));
        assert_eq!(built.pendulum_centre, 0.0);
    }
}

#[test]
fn observer_gains_given_equal_gains_placed() {
    // K and L written out (as a design tool writes them) build the same controller as the
    // placement that produced them: identical commands on a measurement sequence.
    let plant = PlantSpec::book(PlantKind::Cart);
    let placed = parse(&format!(
        "kind = \"observer\"\n{EX71}discretization = \"zoh\"\n"
    ))
    .unwrap();
    let ControllerSpec::Observer(c) = &placed else {
        unreachable!()
    };
    let d = observer_design(plant.parameters(), c).unwrap();
    let rows = |m: &Mat| -> String {
        let r: Vec<String> = (0..m.nrows())
            .map(|i| format!("{:?}", m.row(i).iter().copied().collect::<Vec<_>>()))
            .collect();
        format!("[{}]", r.join(", "))
    };
    let k: Vec<f64> = d.k.iter().copied().collect();
    let given = parse(&format!(
        "kind = \"observer\"\nk = {k:?}\nl = {}\ndiscretization = \"zoh\"\n",
        rows(&d.l)
    ))
    .unwrap();
    let mut a = build_for(&placed, &plant, 1e-3).unwrap().controller;
    let mut b = build_for(&given, &plant, 1e-3).unwrap().controller;
    let (mut ua, mut ub) = ([0.0], [0.0]);
    for step in 0..50 {
        let t = step as f64 * 1e-3;
        let y = [0.01 * t.sin(), 0.1 * (-t).exp(), 9.0, -9.0];
        a.update(t, &y, &mut ua);
        b.update(t, &y, &mut ub);
        assert_eq!(ua, ub, "step {step}");
    }
}

#[test]
fn observer_keys_are_checked_by_name() {
    let plant = PlantSpec::book(PlantKind::Cart);
    let err = |body: &str| {
        let spec = parse(&format!("kind = \"observer\"\n{body}")).unwrap();
        build_for(&spec, &plant, 1e-3).unwrap_err().to_string()
    };
    let obs = "observer_poles = [[-26.0, 6.0], [-26.0, -6.0], [-16.0, 0.0], [-10.0, 0.0]]\n";
    for (body, needle) in [
        (obs.to_string(), "exactly one of k, k_book, lqr, poles"),
        (
            format!("k = [1.0, 1.0, 1.0, 1.0]\npoles = [[-1.0, 0.0]]\n{obs}"),
            "exactly one of k, k_book, lqr, poles",
        ),
        (
            "k = [1.0, 1.0, 1.0, 1.0]\n".to_string(),
            "exactly one of l, observer_poles",
        ),
        (
            format!("poles = [[-1.0, 0.0], [-2.0, 0.0]]\n{obs}"),
            "controller.poles has 2 poles",
        ),
        (
            "k = [1.0, 1.0, 1.0, 1.0]\nl = [[1.0, 0.0], [0.0, 1.0], [0.0, 0.0], [0.0, nan]]\n"
                .to_string(),
            "controller.l[3][1] = NaN",
        ),
        (
            "k = [1.0, 1.0, 1.0, 1.0]\nl = [[1.0, 0.0]]\n".to_string(),
            "controller.l has 1 rows",
        ),
        (
            format!("k = [1.0, 1.0, 1.0, 1.0]\n{obs}discretization = \"euler\"\n"),
            "controller.discretization = \"euler\"",
        ),
    ] {
        let e = err(&body);
        assert!(e.contains(needle), "{body}: {e}");
    }
}

/// The book's I–PD of part 1 §2.2.4 on the cart, binomial model ω_n = 10
/// (`k_I = ω_n³/b_c`, `k_P = 3ω_n²/b_c`, `k_D = (3ω_n − a_c)/b_c`, table 3.5).
fn ipd_gains() -> (f64, f64, f64) {
    let p = pendulab_plants::CartPendulumParams::book();
    let wn: f64 = 10.0;
    (
        wn.powi(3) / p.b_c,
        3.0 * wn * wn / p.b_c,
        (3.0 * wn - p.a_c) / p.b_c,
    )
}

#[test]
fn an_i_pd_spec_runs_as_sims_pid_run_directly() {
    // The spec path (TOML → factory → scenario::simulate with the rig's chains) against sim's
    // Pid in a SampledLoop built by hand with the same chains: the same run, sample for
    // sample.
    use pendulab_sim::controllers::{Pid, PidDiscretization, PidForm};
    use pendulab_sim::{SampledLoop, SampledOptions};
    let (ki, kp, kd) = ipd_gains();
    let spec = parse(&format!(
        "kind = \"pid\"\nform = \"i-pd\"\nkp = {kp}\nki = {ki}\nkd = {kd}\nreference = [0.1]\n"
    ))
    .unwrap();
    let plant = PlantSpec::book(PlantKind::Cart);
    let mut scenario = ScenarioSpec::new(vec![0.0, std::f64::consts::PI, 0.0, 0.0], 3.0);
    scenario.imperfections = Imperfections::with_quantizer();
    let run = simulate(&plant, &spec, &scenario).unwrap();

    let pid = Pid::new(
        PidForm::IPD {
            kp,
            ki,
            kd,
            tf: PID_TF_DEFAULT,
        },
        1e-3,
        PidDiscretization::Tustin,
    )
    .unwrap()
    .reference(pendulab_sim::Signal::step(0.0, 0.1).unwrap())
    .measurement(0, 4)
    .unwrap();
    let chains = plant.rig().chains(&scenario.imperfections).unwrap();
    let opts = SampledOptions {
        ts: 1e-3,
        t_final: 3.0,
        ..Default::default()
    };
    let direct = SampledLoop::new(pendulab_plants::CartPendulum::book(), pid, opts)
        .and_then(|l| l.with_rig(chains))
        .and_then(|mut l| l.run(&scenario.initial_state))
        .unwrap();
    let z = direct.trajectory.x_signal(0);
    assert_eq!(run.x.len(), z.len());
    for (k, (s, d)) in run.x.iter().zip(z).enumerate() {
        assert_eq!(s[0], *d, "z at sample {k}");
    }
    // The I–PD's integral brings the cart to the reference (to the encoder's resolution and
    // the D/A step); the pendulum swings about its hanging rest (the kind's centre π), so the
    // angle deviation is measured from there (from upright it would be near π).
    assert!(
        (run.summary.final_state[0] - 0.1).abs() < 1e-3,
        "{:?}",
        run.summary
    );
    assert!(run.summary.max_angle_deviation < 1.0, "{:?}", run.summary);
    assert_eq!(run.reference[0], 0.1);
}

#[test]
fn pid_forms_and_their_keys() {
    let plant = PlantSpec::book(PlantKind::Cart);
    let ok = |body: &str| {
        let spec = parse(&format!("kind = \"pid\"\n{body}")).unwrap();
        let b = build_for(&spec, &plant, 1e-3).unwrap_or_else(|e| panic!("{body}: {e}"));
        assert_eq!(b.pendulum_centre, std::f64::consts::PI);
        assert!(!b.swing_up);
        b
    };
    // P with k_P = 5 on e = r − z, r = 0: u = −5 z (the book's sign, no flip).
    let mut p = ok("form = \"p\"\nkp = 5.0\n").controller;
    let mut u = [0.0];
    p.update(0.0, &[0.02, 3.0, 0.0, 0.0], &mut u);
    assert_eq!(u[0], -5.0 * 0.02);
    for body in [
        "form = \"pd\"\nkp = 10.0\nkd = 0.8\n",
        "form = \"p-d\"\nkp = 10.0\nkd = 0.8\ntf = 0.01\n",
        "form = \"pi\"\nkp = 10.0\nki = 5.0\n",
        "form = \"pid\"\nkp = 10.0\nki = 5.0\nkd = 0.8\ndiscretization = \"backward-euler\"\n",
        "form = \"i-pd\"\nkp = 10.0\nki = 5.0\nkd = 0.8\nreference = [0.1]\nstep_time = 1.0\n",
    ] {
        ok(body);
    }
    let err = |body: &str| {
        let spec = parse(&format!("kind = \"pid\"\n{body}")).unwrap();
        build_for(&spec, &plant, 1e-3).unwrap_err().to_string()
    };
    for (body, needle) in [
        ("kp = 1.0\n", "controller.form"),
        ("form = \"pdq\"\nkp = 1.0\n", "controller.form = \"pdq\""),
        ("form = \"pi\"\nkp = 1.0\n", "controller.ki: is required"),
        (
            "form = \"p\"\nkp = 1.0\nki = 1.0\n",
            "controller.ki: is not a gain",
        ),
        (
            "form = \"pi\"\nkp = 1.0\nki = 1.0\ntf = 0.1\n",
            "controller.tf",
        ),
        (
            "form = \"pd\"\nkp = 1.0\nkd = 1.0\ntf = 0.0\n",
            "controller.tf = 0",
        ),
        ("form = \"p\"\nkp = inf\n", "controller.kp[0] = inf"),
        (
            "form = \"p\"\nkp = 1.0\nreference = [0.1, 0.2]\n",
            "a pid is one value",
        ),
        (
            "form = \"p\"\nkp = 1.0\nstep_time = -1.0\n",
            "controller.step_time = -1",
        ),
        (
            "form = \"p\"\nkp = 1.0\ndiscretization = \"zoh\"\n",
            "controller.discretization = \"zoh\"",
        ),
    ] {
        let e = err(body);
        assert!(e.contains(needle), "{body}: {e}");
    }
}

#[test]
fn nmpc_runs_on_the_arm_with_its_settings_and_is_refused_on_the_cart() {
    let spec = parse("kind = \"nmpc\"\nhorizon = 0.4\ndivisions = 20\n").unwrap();
    let ControllerSpec::Nmpc(c) = &spec else {
        unreachable!()
    };
    // Left-out keys are the book's; the period sets ζ = 1/ts.
    let s = c.settings(2e-3).unwrap();
    let book = crate::nmpc::ArmSwingUpSettings::book();
    assert_eq!(
        (s.q, s.qf, s.r, s.u_max),
        (book.q, book.qf, book.r, book.u_max)
    );
    assert_eq!(s.solver.grid_points, 20);
    assert_eq!(s.solver.zeta, 500.0);
    assert_eq!(s.ts, 2e-3);
    assert_eq!(
        s.solver.horizon,
        crate::cgmres::Horizon::Growing {
            final_length: 0.4,
            rate: 0.5
        }
    );
    let arm = PlantSpec::book(PlantKind::Arm);
    let b = build_for(&spec, &arm, 1e-3).unwrap();
    assert!(b.swing_up);
    assert_eq!(
        (b.controller.ny(), b.controller.nu(), b.pendulum_centre),
        (4, 1, 0.0)
    );
    let e = build_for(&spec, &PlantSpec::book(PlantKind::Cart), 1e-3).unwrap_err();
    assert!(matches!(e, SpecError::NotForPlant { .. }), "{e}");
    let m = e.to_string();
    assert!(
        m.contains("nmpc") && m.contains("arm") && m.contains("cart"),
        "{m}"
    );
    for (body, needle) in [
        ("horizon = 0.0\n", "controller.horizon = 0"),
        ("divisions = 0\n", "controller.divisions = 0"),
        ("q = [1.0, 1.0]\n", "controller.q has 2"),
        ("qf = [1.0, -1.0, 0.0, 0.0]\n", "controller.qf[1] = -1"),
        ("zeta = 2000.0\n", "controller.zeta = 2000"),
        ("u_max = nan\n", "controller.u_max = NaN"),
    ] {
        let spec = parse(&format!("kind = \"nmpc\"\n{body}")).unwrap();
        let e = build_for(&spec, &arm, 1e-3).unwrap_err().to_string();
        assert!(e.contains(needle), "{body}: {e}");
    }
}

#[test]
fn nmpc_swings_the_book_arm_up_through_simulate() {
    // The book's setting from the hanging rest x₀ = [π, π, 0, 0] (p2c33_adip_nmpc_swing_up):
    // the run ends near upright (both angles wrapped to within 0.2 rad of 0) with |u| ≤ u_max.
    let spec = parse("kind = \"nmpc\"\n").unwrap();
    let plant = PlantSpec::book(PlantKind::Arm);
    let pi = std::f64::consts::PI;
    let scenario = ScenarioSpec::new(vec![pi, pi, 0.0, 0.0], 10.0);
    let run = simulate(&plant, &spec, &scenario).unwrap();
    let x = &run.summary.final_state;
    let wrap = |a: f64| pendulab_plants::wrap_about(a, 0.0);
    assert!(wrap(x[0]).abs() < 0.2 && wrap(x[1]).abs() < 0.2, "{x:?}");
    assert!(
        run.summary.peak_command <= 2.5 + 1e-9,
        "{}",
        run.summary.peak_command
    );
    assert_eq!(run.summary.left_angle_window, None);
}

#[test]
fn a_foreign_key_is_refused_by_name_in_each_new_kind() {
    for (kind, key) in [("observer", "kp"), ("pid", "poles"), ("nmpc", "k")] {
        let e = parse(&format!("kind = \"{kind}\"\n{key} = 1.0\n")).unwrap_err();
        assert!(e.contains(&format!("`{key}`")), "{kind}: {e}");
    }
}

// ------------------------------------------------------------------ gain-scheduled: X, L

/// A symmetric positive definite `n × n` matrix (`M = G Gᵀ + n I`, `G` a fixed pattern).
fn spd(n: usize) -> Mat {
    let g = Mat::from_fn(n, n, |i, j| ((3 * i + 5 * j) % 7) as f64 * 0.25 - 0.6);
    &g * g.transpose() + Mat::identity(n, n) * n as f64
}

/// `[[row], [row], …]` of a matrix, TOML.
fn toml_rows(m: &Mat) -> String {
    let rows: Vec<String> = (0..m.nrows())
        .map(|i| {
            let r: Vec<String> = m.row(i).iter().map(|v| format!("{v:?}")).collect();
            format!("[{}]", r.join(", "))
        })
        .collect();
    format!("[{}]", rows.join(", "))
}

/// `kind = "gain-scheduled"` with `X(ρ) = Σ ρ^i X_i`, `L(ρ) = Σ ρ^i L_i` and `extra` keys.
fn x_l_spec(x: &[Mat], l: &[Mat], extra: &str) -> String {
    let xs: Vec<String> = x.iter().map(toml_rows).collect();
    let ls: Vec<String> = l
        .iter()
        .map(|m| {
            toml_rows(m)
                .trim_start_matches('[')
                .trim_end_matches(']')
                .to_string()
        })
        .map(|r| format!("[{r}]"))
        .collect();
    format!(
        "kind = \"gain-scheduled\"\nx_coefficients = [{}]\nl_coefficients = [{}]\n{extra}",
        xs.join(", "),
        ls.join(", ")
    )
}

#[test]
fn x_and_l_coefficients_give_minus_l_x_inverse() {
    // X(ρ) = (1 + ρ) M, L(ρ) = −(K₀ + ρ K₁) M: then −L(ρ) X(ρ)⁻¹ = (K₀ + ρ K₁)/(1 + ρ) in
    // closed form, whatever the (non-diagonal) M.
    let m = spd(4);
    let k0 = Mat::from_row_slice(1, 4, &[-2.0, 30.0, -1.5, 4.0]);
    let k1 = Mat::from_row_slice(1, 4, &[1.0, -8.0, 0.5, 2.0]);
    let spec = parse(&x_l_spec(
        &[m.clone(), m.clone()],
        &[-(&k0 * &m), -(&k1 * &m)],
        "",
    ))
    .unwrap();
    let arm = PlantSpec::book(PlantKind::Arm);
    let mut b = build_for(&spec, &arm, 1e-3).unwrap();
    assert_eq!((b.controller.ny(), b.controller.nu()), (4, 1));
    for th in [0.0f64, 0.3, 0.8, -1.0] {
        let rho = 1.0 - th.cos();
        let k = (&k0 + &k1 * rho) / (1.0 + rho);
        // u is affine in y at fixed q₀: the gain column by column, u(y + e_i) − u(y).
        let y = [th, 0.0, 0.0, 0.0];
        let mut u0 = [0.0];
        b.controller.update(0.0, &y, &mut u0);
        assert!(
            (u0[0] + k[(0, 0)] * th).abs() < 1e-12 * (1.0 + k[(0, 0)].abs()),
            "{th}: {u0:?}"
        );
        for i in 1..4 {
            let mut yi = y;
            yi[i] = 1.0;
            let mut u1 = [0.0];
            b.controller.update(0.0, &yi, &mut u1);
            let ki = -(u1[0] - u0[0]);
            assert!(
                (ki - k[(0, i)]).abs() < 1e-12 * k[(0, i)].abs().max(1.0),
                "{th} K[{i}]: {ki} vs {}",
                k[(0, i)]
            );
        }
    }
}

#[test]
fn a_five_state_schedule_is_the_lq_servo_when_the_gain_is_constant() {
    // X = M (5 × 5, ρ-independent), L = −K M: K(ρ) = K = [K₁ K₂] at every ρ, so the scheduled
    // servo must command what `lq-servo` with k1 = K₁, k2 = K₂ commands, sample by sample,
    // through a reference step (its integrator, its rule, its reference handling); and the
    // polynomial form `coefficients = [K]` likewise.
    let k = [-1.2, 25.0, -0.8, 3.5, -2.0];
    let km = Mat::from_row_slice(1, 5, &k);
    let m = spd(5);
    let steps = "reference = [0.3]\nstep_time = 0.01\n";
    let scheduled = parse(&x_l_spec(std::slice::from_ref(&m), &[-(&km * &m)], steps)).unwrap();
    let poly = parse(&format!(
        "kind = \"gain-scheduled\"\ncoefficients = [[{}]]\n{steps}",
        k.map(|v| format!("{v:?}")).join(", ")
    ))
    .unwrap();
    let servo = parse(&format!(
        "kind = \"lq-servo\"\nk1 = [{}]\nk2 = {:?}\n{steps}",
        k[..4]
            .iter()
            .map(|v| format!("{v:?}"))
            .collect::<Vec<_>>()
            .join(", "),
        k[4]
    ))
    .unwrap();
    let arm = PlantSpec::book(PlantKind::Arm);
    let ts = 2e-3;
    let mut c: Vec<Built> = [&scheduled, &poly, &servo]
        .iter()
        .map(|s| build_for(s, &arm, ts).unwrap())
        .collect();
    for b in &c {
        assert_eq!(b.controller.sample_time(), Some(ts));
    }
    for step in 0..40 {
        let t = step as f64 * ts;
        let y = [0.01 * step as f64, -0.002 * step as f64, 0.1, -0.05];
        let mut u = [[0.0]; 3];
        for (b, ui) in c.iter_mut().zip(&mut u) {
            b.controller.update(t, &y, ui);
        }
        let tol = 1e-10 * u[2][0].abs().max(1.0);
        assert!((u[0][0] - u[2][0]).abs() < tol, "t = {t}: {u:?}");
        assert!((u[1][0] - u[2][0]).abs() < tol, "t = {t}: {u:?}");
    }
    // After reset the integrators start again from 0.
    c[0].controller.reset();
    c[2].controller.reset();
    let mut u = [[0.0]; 2];
    c[0].controller.update(0.0, &[0.0; 4], &mut u[0]);
    c[2].controller.update(0.0, &[0.0; 4], &mut u[1]);
    assert_eq!(u[0], u[1]);
}

#[test]
fn a_five_state_schedule_tracks_a_scenario_reference_on_the_arm() {
    // The constant LQ servo gain of the book's arm (Q = diag(0.1, 1, 0.001, 0.001, 4), R = 1)
    // written as X = I, L = −K: a scenario's 0.3 rad step is reached, as `lq-servo` reaches it.
    let arm = PlantSpec::book(PlantKind::Arm);
    let lin = arm.parameters().linearize_upright(0.0).unwrap();
    let sys = StateSpace::continuous(
        lin.a().clone(),
        lin.b().clone(),
        Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]),
        Mat::zeros(1, 1),
    )
    .unwrap();
    let q = diag("q", &[0.1, 1.0, 0.001, 0.001, 4.0], 5).unwrap();
    let d = lq_servo(&sys, &q, &check_r("r", 1.0).unwrap()).unwrap();
    let mut k = Mat::zeros(1, 5);
    k.view_mut((0, 0), (1, 4)).copy_from(&d.state_gain);
    k[(0, 4)] = d.integral_gain[(0, 0)];
    let spec = parse(&x_l_spec(&[Mat::identity(5, 5)], &[-k], "")).unwrap();
    let mut scenario = ScenarioSpec::new(vec![0.0; 4], 8.0);
    scenario.reference = pendulab_sim::scenario::SignalSpec::Constant { value: 0.3 };
    let run = simulate(&arm, &spec, &scenario).unwrap();
    let x = &run.summary.final_state;
    assert!((x[0] - 0.3).abs() < 0.01 && x[1].abs() < 0.01, "{x:?}");
    // A 4-state schedule tracks no reference: the scenario's is refused, naming the kind.
    let reg = parse(&x_l_spec(&[spd(4)], &[Mat::zeros(1, 4)], "")).unwrap();
    let e = simulate(&arm, &reg, &scenario).unwrap_err().to_string();
    assert!(e.contains("gain-scheduled"), "{e}");
}

#[test]
fn x_and_l_keys_are_checked_by_name() {
    let arm = PlantSpec::book(PlantKind::Arm);
    let m = spd(5);
    let l = Mat::from_row_slice(1, 5, &[1.0, 2.0, 3.0, 4.0, 5.0]);
    let mut asym = m.clone();
    asym[(0, 1)] += 1e-3;
    let mut indefinite = m.clone();
    indefinite[(2, 2)] = -1.0;
    let l4 = Mat::from_row_slice(1, 4, &[1.0, 2.0, 3.0, 4.0]);
    let cases: Vec<(String, &str)> = vec![
        (
            x_l_spec(&[m.clone(), asym], std::slice::from_ref(&l), ""),
            "controller.x_coefficients[1]: must be symmetric",
        ),
        (
            x_l_spec(&[indefinite], std::slice::from_ref(&l), ""),
            "controller.x_coefficients[0]: X(0) = X0 must be positive definite",
        ),
        (
            x_l_spec(&[spd(3)], std::slice::from_ref(&l), ""),
            "controller.x_coefficients[0] has 3 entries",
        ),
        (
            x_l_spec(&[m.clone(), spd(4)], std::slice::from_ref(&l), ""),
            "controller.x_coefficients[1] has 4 rows, expected 5",
        ),
        (
            x_l_spec(std::slice::from_ref(&m), &[l.clone(), l4], ""),
            "controller.l_coefficients[1] has 4 entries, expected 5",
        ),
        (
            x_l_spec(std::slice::from_ref(&m), &[], ""),
            "give at least X0 and L0",
        ),
        (
            x_l_spec(std::slice::from_ref(&m), std::slice::from_ref(&l), "")
                .replace("x_coefficients = [[[", "x_coefficients = [[[nan, "),
            "controller.x_coefficients[0][0] has 6 entries",
        ),
        (
            x_l_spec(&[spd(4)], &[Mat::zeros(1, 4)], "reference = [0.1]\n"),
            "controller.reference, controller.step_time: a 4-state gain-scheduled regulator tracks no reference",
        ),
        (
            x_l_spec(
                std::slice::from_ref(&m),
                std::slice::from_ref(&l),
                "coefficients = [[0.0, 0.0, 0.0, 0.0]]\n",
            ),
            "give coefficients; or lqr with design_points_deg (arm); or x_coefficients with l_coefficients",
        ),
        (
            "kind = \"gain-scheduled\"\nx_coefficients = [[[1.0]]]\n".to_string(),
            "or x_coefficients with l_coefficients",
        ),
        (
            x_l_spec(
                std::slice::from_ref(&m),
                std::slice::from_ref(&l),
                "reference = [0.1, 0.2]\n",
            ),
            "controller.reference of a gain-scheduled is one value",
        ),
        (
            x_l_spec(
                std::slice::from_ref(&m),
                std::slice::from_ref(&l),
                "step_time = -1.0\n",
            ),
            "controller.step_time = -1",
        ),
        (
            x_l_spec(
                std::slice::from_ref(&m),
                std::slice::from_ref(&l),
                "schedule = \"theta\"\n",
            ),
            "controller.schedule = 'theta'",
        ),
        (
            "kind = \"gain-scheduled\"\ncoefficients = [[1.0, 2.0, 3.0]]\n".to_string(),
            "controller.coefficients[0] has 3 entries",
        ),
    ];
    for (text, needle) in cases {
        let spec = parse(&text).unwrap_or_else(|e| panic!("{text}: {e}"));
        let e = build_for(&spec, &arm, 1e-3).unwrap_err().to_string();
        assert!(e.contains(needle), "{needle}:\n{e}");
    }
    // A NaN entry (in a well-shaped matrix) is named with its row and index.
    let mut nan = m.clone();
    nan[(2, 3)] = f64::NAN;
    nan[(3, 2)] = f64::NAN;
    let spec =
        parse(&x_l_spec(&[nan], std::slice::from_ref(&l), "").replace("NaN", "nan")).unwrap();
    let e = build_for(&spec, &arm, 1e-3).unwrap_err().to_string();
    assert!(
        e.contains("controller.x_coefficients[0][2][3] = NaN"),
        "{e}"
    );
}

#[test]
fn x_and_l_coefficients_round_trip_through_toml() {
    let m = spd(5);
    let text = x_l_spec(
        &[m.clone(), &m * 0.1, &m * 0.01],
        &[
            Mat::from_row_slice(1, 5, &[1.0, 2.0, 3.0, 4.0, 5.0]),
            Mat::from_row_slice(1, 5, &[0.1, 0.2, 0.3, 0.4, 0.5]),
            Mat::from_row_slice(1, 5, &[1e-3, 2e-3, 3e-3, 4e-3, 1.0 / 3.0]),
        ],
        "reference = [1.0471975511965976]\nstep_time = 0.5\nschedule = \"one-minus-cos-q0\"\n",
    );
    let spec = parse(&text).unwrap();
    let back = parse(&toml::to_string(&spec).unwrap()).unwrap();
    assert_eq!(back, spec);
    let ControllerSpec::GainScheduled(c) = &back else {
        panic!("{back:?}")
    };
    assert_eq!(c.x_coefficients.as_ref().map(Vec::len), Some(3));
    assert_eq!(c.l_coefficients.as_ref().unwrap()[2][4], 1.0 / 3.0);
    build_for(&back, &PlantSpec::book(PlantKind::Arm), 1e-3).unwrap();
}
