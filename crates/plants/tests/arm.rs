//! Tests of the arm-type pendulum against independent references: the closed-form
//! linearisation and LPV matrices (`docs/model.md` §2), a hand-derived closed form of det M_c (book
//! example 5.3), central finite differences, energy conservation and the energy balance along RK4
//! trajectories (RK4 written in `common`), and an independent SymPy derivation.

mod common;

use common::*;
use pendulab_lti::Mat;
use pendulab_lti::analysis::{ctrb, rank};
use pendulab_plants::*;
use pendulab_sim::Dynamics;
use pendulab_testkit::arm::ArmParams;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_3, FRAC_PI_4, PI};

fn book() -> ArmPendulumParams {
    ArmPendulumParams::book()
}

/// The closed form of `docs/model.md` §2: pendulab-testkit's formula (the workspace's one
/// hand-written copy), the independent reference for the plant's `linearize`.
fn spec_model(p: &ArmPendulumParams, theta1e: f64) -> (Mat, Mat) {
    let params = ArmParams {
        a1: p.a1,
        b1: p.b1,
        L1: p.L1,
        m2: p.m2,
        l2: p.l2,
        J2: p.J2,
        mu2: p.mu2,
        g: p.g,
    };
    params.linearization(theta1e)
}

fn other() -> ArmPendulumParams {
    ArmPendulumParams {
        a1: 4.3,
        b1: 9.1,
        L1: 0.31,
        m2: 0.21,
        l2: 0.26,
        L2: 0.4,
        J2: 2.2e-3,
        mu2: 7.0e-4,
        g: 9.80,
    }
}

#[test]
fn linearization_equals_spec_closed_form() {
    for p in [book(), other()] {
        let plant = ArmPendulum::new(p).unwrap();
        for theta1e in [0.0, FRAC_PI_4, FRAC_PI_3, -1.0, 2.5] {
            let sys = plant.linearize(ArmEquilibrium::upright(theta1e)).unwrap();
            let (a, b) = spec_model(&p, theta1e);
            // The same formulas; the only difference is the order of a few products
            // (α₃ cos θ₁ₑ b₁ vs b₁ α₃ cos θ₁ₑ): 1e-15 relative.
            assert!(
                (sys.a() - &a).amax() <= 1e-15 * max_abs(&a),
                "A at {theta1e}: {} vs {a}",
                sys.a()
            );
            assert!(
                (sys.b() - &b).amax() <= 1e-15 * max_abs(&b),
                "B at {theta1e}"
            );
            assert_eq!(sys.c(), &Mat::identity(4, 4));
        }
    }
    // Measured outputs y = [θ₁, θ₂].
    let sys = ArmPendulum::book()
        .linearize_measured(ArmEquilibrium::upright(0.3))
        .unwrap();
    assert_eq!(sys.c(), &ArmPendulum::measured_output_matrix());
    assert_eq!(
        sys.c(),
        &Mat::from_row_slice(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0])
    );
}

#[test]
fn lpv_form_reproduces_the_linearization() {
    for p in [book(), other()] {
        let plant = ArmPendulum::new(p).unwrap();
        let lpv = plant.lpv();
        let (al2, al3) = (p.alpha2(), p.alpha3());
        // docs/model.md §2: A₁ has the single entry (4,3) = −a₁α₃/α₂, B₁ the single entry (4) =
        // b₁α₃/α₂; A₀, B₀ are the θ₁ₑ = 0 model.
        let mut a1 = Mat::zeros(4, 4);
        a1[(3, 2)] = -p.a1 * al3 / al2;
        let mut b1 = Mat::zeros(4, 1);
        b1[(3, 0)] = p.b1 * al3 / al2;
        assert!((&lpv.a1 - &a1).amax() <= 1e-15 * a1.amax());
        assert!((&lpv.b1 - &b1).amax() <= 1e-15 * b1.amax());
        let (a0, b0) = spec_model(&p, 0.0);
        assert!((&lpv.a0 - &a0).amax() <= 1e-15 * a0.amax());
        assert!((&lpv.b0 - &b0).amax() <= 1e-15 * b0.amax());
        // A(ρ(θ₁ₑ)) = linearisation at θ₁ₑ over a whole turn. The affine form rounds ρ and
        // the sum: a few ε of the largest entry.
        for k in 0..=72 {
            let theta1e = -PI + k as f64 * (2.0 * PI / 72.0);
            let rho = ArmLpv::rho(theta1e);
            assert!((rho - (1.0 - theta1e.cos())).abs() == 0.0);
            let sys = plant.linearize(ArmEquilibrium::upright(theta1e)).unwrap();
            let frozen = lpv.state_space(rho).unwrap();
            assert!(
                (frozen.a() - sys.a()).amax() <= 1e-14 * sys.a().amax(),
                "A at {theta1e}"
            );
            assert!(
                (frozen.b() - sys.b()).amax() <= 1e-14 * sys.b().amax(),
                "B at {theta1e}"
            );
        }
    }
    assert!(ArmPendulum::book().lpv().state_space(f64::NAN).is_err());
}

/// det M_c of (A(θ₁ₑ), B(θ₁ₑ)), derived by hand (book example 5.3, `p1c511_ex3_adip`).
///
/// Write B = [0, 0, b, d]ᵀ with b = b₁, d = −b₁α₃c/α₂ (c = cos θ₁ₑ), and the last row of A as
/// [0, α, β, −γ] with α = α₅/α₂, β = (μ₂ + a₁α₃c)/α₂, γ = μ₂/α₂. The position rows of AᵏB
/// are the velocity rows of Aᵏ⁻¹B, so with vₖ the velocity part of AᵏB,
/// M_c = [[0, v₀, v₁, v₂], [v₀, v₁, v₂, v₃]] and vₖ₊₁ = F vₖ + G vₖ₋₁
/// (F = [[−a₁, 0], [β, −γ]], G = diag(0, α)). Subtracting F × (position rows) from the
/// velocity rows (determinant unchanged) leaves [v₀, 0, G v₀, G v₁]; expanding along the θ̇₁ row
/// (only b in column 0) gives
///   det M_c = α b² [(βb + a₁d)(βb + a₁d − γd) − αd²].
/// Here βb + a₁d = b₁μ₂/α₂ exactly (the a₁ terms cancel), so
///   det M_c = α₅ b₁⁴ / α₂⁴ · [μ₂² (α₂ + α₃ cos θ₁ₑ) − α₅ α₃² cos² θ₁ₑ].
/// With μ₂ = 0 it vanishes exactly when cos θ₁ₑ = 0. (tools/reference/plants_lagrange.py
/// confirms the identity symbolically with SymPy.)
fn det_mc_closed_form(p: &ArmPendulumParams, theta1e: f64) -> f64 {
    let (al2, al3, al5) = (p.alpha2(), p.alpha3(), p.alpha5());
    let c = theta1e.cos();
    al5 * p.b1.powi(4) / al2.powi(4) * (p.mu2 * p.mu2 * (al2 + al3 * c) - al5 * al3 * al3 * c * c)
}

#[test]
fn controllability_determinant_matches_hand_derived_closed_form() {
    let frictionless = ArmPendulumParams { mu2: 0.0, ..book() };
    for p in [book(), other(), frictionless] {
        let plant = ArmPendulum::new(p).unwrap();
        for k in 0..=24 {
            let theta1e = -PI + k as f64 * (PI / 12.0);
            let sys = plant.linearize(ArmEquilibrium::upright(theta1e)).unwrap();
            let mc = ctrb(sys.a(), sys.b()).unwrap();
            let det = mc.clone().determinant();
            let closed = det_mc_closed_form(&p, theta1e);
            // LU's determinant errs by O(n ε) times Hadamard's bound Π‖column‖ (the scale of
            // the terms that cancel); 1e-13 of that bound allows for it.
            let hadamard: f64 = mc.column_iter().map(|c| c.norm()).product();
            assert!(
                (det - closed).abs() <= 1e-13 * hadamard,
                "θ1e = {theta1e}: det {det:e} vs closed form {closed:e} (bound {hadamard:e})"
            );
        }
    }
    // Example 5.3: with μ₂ = 0 the model is uncontrollable only at cos θ₁ₑ = 0. There both
    // β = (μ₂ + a₁α₃ cos θ₁ₑ)/α₂ and B's last entry vanish, so (θ₂, θ̇₂) is decoupled from the
    // arm and the input: rank 2 (the arm moves vertically and cannot tip the pendulum).
    let plant = ArmPendulum::new(frictionless).unwrap();
    for (theta1e, expected_rank) in [(0.0, 4), (FRAC_PI_4, 4), (FRAC_PI_2, 2), (-FRAC_PI_2, 2)] {
        let sys = plant.linearize(ArmEquilibrium::upright(theta1e)).unwrap();
        let r = rank(&ctrb(sys.a(), sys.b()).unwrap()).rank;
        assert_eq!(r, expected_rank, "θ1e = {theta1e}");
    }
    // With the book's friction it stays controllable even there (det = α₅b₁⁴μ₂²/α₂³ > 0).
    let sys = ArmPendulum::book()
        .linearize(ArmEquilibrium::upright(FRAC_PI_2))
        .unwrap();
    let mc = ctrb(sys.a(), sys.b()).unwrap();
    assert_eq!(rank(&mc).rank, 4);
    assert!(mc.determinant() > 0.0);
}

#[test]
fn jacobian_matches_central_differences() {
    // As for the cart: central differences with h = 1e-5·max(1, |x|) are accurate to ~1e-9
    // of the Jacobian's scale; 1e-7 leaves two orders of margin.
    let plant = ArmPendulum::book();
    let points = [
        ([0.0, 0.0, 0.0, 0.0], 0.0),
        ([FRAC_PI_3, 0.0, 0.0, 0.0], 0.0),
        ([0.2, 0.1, -0.3, 0.8], 0.5),
        ([1.3, -0.4, 2.0, -1.5], -2.0),
        ([-2.0, 3.0, -4.0, 7.0], 4.9),
    ];
    assert_jacobian_matches_fd(
        |x, u| plant.jacobian(x, u),
        |x, u| plant.derivative_array(x, u),
        &points,
        1e-7,
    );
    // Hanging equilibria: the equilibrium Jacobian equals the general one there.
    for theta1e in [0.0, 0.7, -2.0] {
        let eq = ArmEquilibrium::hanging(theta1e);
        let a = plant.equilibrium_jacobian(eq).unwrap().a_matrix();
        let g = plant.jacobian(&eq.state().to_array(), 0.0).a_matrix();
        // Differ only by the rounding of cos(θ₁ₑ − π) against −cos θ₁ₑ.
        assert!((a - g).amax() <= 1e-14 * plant.jacobian(&[0.0; 4], 0.0).a_matrix().amax());
        // And it is an equilibrium.
        let f = plant.derivative_array(&eq.state().to_array(), 0.0);
        assert!(f.iter().all(|v| v.abs() < 1e-12));
    }
}

#[test]
fn nonlinear_model_matches_sympy_euler_lagrange() {
    // tools/reference/plants_lagrange.py (SymPy Euler–Lagrange, mpmath at 40 digits); f64
    // evaluation differs by a few roundings: 1e-12 relative to max(1, |f|).
    for case in sympy_cases("arm_pendulum") {
        let p = &case.params;
        let params = ArmPendulumParams {
            a1: num(&p["a1"]),
            b1: num(&p["b1"]),
            L1: num(&p["L1"]),
            m2: num(&p["m2"]),
            l2: num(&p["l2"]),
            L2: 0.3,
            J2: num(&p["J2"]),
            mu2: num(&p["mu2"]),
            g: num(&p["g"]),
        };
        let plant = ArmPendulum::new(params).unwrap();
        let f = plant.derivative_array(&case.x, case.u);
        assert_matches_sympy(&f, &case, 1e-12);
        let mut dx = [0.0; 4];
        plant.derivative(0.0, &case.x, &[case.u], &mut dx);
        assert_eq!(dx, f);
    }
}

#[test]
fn pendulum_energy_is_conserved_with_the_arm_held() {
    // μ₂ = 0, θ̇₁(0) = 0, v = 0: the arm stays at θ₁(0). RK4, 1e-4 s, 10 s; error bound as for
    // the cart (≈ 1e-11 expected), 1e-9 required.
    let p = ArmPendulumParams { mu2: 0.0, ..book() };
    let plant = ArmPendulum::new(p).unwrap();
    for (theta1, theta2) in [(0.0, 0.4), (0.8, 2.5), (-1.0, PI - 0.05)] {
        let x0 = [theta1, theta2, 0.0, 2.0];
        let path = rk4_path(|_, x| plant.derivative_array(x, 0.0), x0, 1e-4, 100_000);
        let e0 = plant.pendulum_energy(&x0.into());
        let drift = energy_drift(&path, |x| plant.pendulum_energy(&(*x).into()));
        assert!(drift <= 1e-9 * e0, "drift {drift:e} of {e0}");
        assert!(path.iter().all(|x| x[0] == theta1 && x[2] == 0.0));
    }
}

#[test]
fn pendulum_energy_balance_holds_with_the_arm_driven() {
    // In the frame translating with the arm's tip the pendulum feels the inertial force
    // −m₂ a_tip at its centre of mass, whose relative velocity is l₂ θ̇₂ (cos θ₂, −sin θ₂), and
    // the joint's friction torque μ₂ (θ̇₁ − θ̇₂). With the tip at L₁ (sin θ₁, cos θ₁):
    //   a_tip = L₁ (cos θ₁ θ̈₁ − sin θ₁ θ̇₁², −sin θ₁ θ̈₁ − cos θ₁ θ̇₁²),
    //   dE₂/dt = −m₂ a_tip · v_rel + μ₂ (θ̇₁ − θ̇₂) θ̇₂.
    // Check E₂(T) − E₂(0) = ∫ P dt along an RK4 path (Simpson on the same samples).
    let p = ArmPendulumParams {
        mu2: 2e-3,
        ..book()
    };
    let plant = ArmPendulum::new(p).unwrap();
    let v = |t: f64| 1.5 * (4.0 * t).sin() - 0.7 * (9.0 * t).cos();
    let power = |x: &[f64; 4], v: f64| {
        let dd1 = -p.a1 * x[2] + p.b1 * v;
        let (s1, c1) = x[0].sin_cos();
        let (s2, c2) = x[1].sin_cos();
        let acc = [
            p.L1 * (c1 * dd1 - s1 * x[2] * x[2]),
            p.L1 * (-s1 * dd1 - c1 * x[2] * x[2]),
        ];
        let vrel = [p.l2 * x[3] * c2, -p.l2 * x[3] * s2];
        -p.m2 * (acc[0] * vrel[0] + acc[1] * vrel[1]) + p.mu2 * (x[2] - x[3]) * x[3]
    };
    assert_energy_balance(
        |x, v| plant.derivative_array(x, v),
        v,
        [0.1, PI - 0.2, 0.0, 0.0],
        |x| plant.pendulum_energy(&(*x).into()),
        power,
    );
}

#[test]
fn energy_levels_geometry_and_states() {
    let plant = ArmPendulum::book();
    let p = book();
    assert!(
        plant
            .pendulum_energy(&ArmEquilibrium::hanging(0.4).state())
            .abs()
            <= 1e-17
    );
    let up = plant.pendulum_energy(&ArmEquilibrium::upright(0.4).state());
    assert!((up - 2.0 * p.m2 * p.l2 * p.g).abs() <= 1e-16);
    assert_eq!(up, plant.upright_energy());
    let x = ArmPendulumState {
        theta1: 0.5,
        theta2: -0.3,
        dtheta1: 1.0,
        dtheta2: 2.0,
    };
    assert_eq!(ArmPendulumState::from(x.to_array()), x);
    assert_eq!(<[f64; 4]>::from(x), [0.5, -0.3, 1.0, 2.0]);
    assert_eq!(x.relative_angle(), -0.8);
    let pose = plant.pose(&x);
    // Arm tip (L₁ sin θ₁, L₁ cos θ₁); pendulum tip = arm tip + L₂ (sin θ₂, cos θ₂).
    assert!((pose.arm_tip[0] - 0.227 * 0.5f64.sin()).abs() < 1e-15);
    assert!((pose.arm_tip[1] - 0.227 * 0.5f64.cos()).abs() < 1e-15);
    let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    assert!((d(pose.pendulum_tip, pose.arm_tip) - 0.3).abs() < 1e-15);
    assert!((d(pose.centre_of_mass, pose.arm_tip) - 0.195).abs() < 1e-15);
    assert!((pose.pendulum_tip[0] - pose.arm_tip[0] - 0.3 * (-0.3f64).sin()).abs() < 1e-15);
    assert_eq!((plant.nx(), plant.nu()), (4, 1));
    assert_eq!(plant.drive().a(), 6.20);
    assert_eq!(plant.drive().b(), 15.8);
}

#[test]
fn invalid_parameters_are_typed_errors() {
    let fields = fields![ArmPendulumParams;
        a1 = true, b1 = false, L1 = false, m2 = false, l2 = false, L2 = false, J2 = false,
        mu2 = true, g = false];
    assert_fields_validated(
        book(),
        &fields,
        &[f64::NAN, f64::INFINITY, -2.0],
        ArmPendulum::new,
        |_| {},
    );
    let msg = ArmPendulum::new(ArmPendulumParams {
        J2: f64::NAN,
        ..book()
    })
    .unwrap_err()
    .to_string();
    assert!(msg.contains("J2") && msg.contains("NaN"), "{msg}");
    assert!(matches!(
        ArmPendulum::book().linearize(ArmEquilibrium::upright(f64::INFINITY)),
        Err(PlantError::NonFiniteOperatingPoint { what: "theta1", .. })
    ));
    assert_eq!(ArmPendulum::new(book()).unwrap(), ArmPendulum::book());
}
