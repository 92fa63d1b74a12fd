//! Tests of the cart-type pendulum, the cart drive and the fixed-cart pendulum against
//! independent references: the numbers and closed forms of `docs/model.md` §1, the book's eqs
//! 4.39–4.45, central finite differences, energy conservation and the energy balance along
//! RK4 trajectories (RK4 written in `common`), and an independent SymPy derivation.

mod common;

use common::*;
use pendulab_lti::{Complex64, Mat};
use pendulab_plants::*;
use pendulab_sim::Dynamics;
use pendulab_testkit::cart::{CartParams, Rest};
use std::f64::consts::PI;

fn book() -> CartPendulumParams {
    CartPendulumParams::book()
}

#[test]
fn upright_open_loop_poles_are_specs() {
    // docs/model.md §1: 0, −6.25, +5.7543, −5.7867. Printed to 4 decimals: half a unit of the last
    // printed digit is the tolerance.
    let sys = CartPendulum::book()
        .linearize(CartEquilibrium::upright())
        .unwrap();
    let mut poles: Vec<Complex64> = sys.poles().unwrap();
    poles.sort_by(|a, b| a.re.total_cmp(&b.re));
    let expected = [-6.25, -5.7867, 0.0, 5.7543];
    for (p, e) in poles.iter().zip(expected) {
        assert!(p.im.abs() < 1e-12, "real poles expected, got {p}");
        assert!((p.re - e).abs() <= 5e-5, "pole {p} vs docs/model.md {e}");
    }
}

/// The closed-form A, B of `docs/model.md` §1 at the upright or hanging rest: pendulab-testkit's
/// formula (the workspace's one hand-written copy), the independent reference for the plant's
/// `linearize`.
fn spec_model(p: &CartPendulumParams, posture: Posture) -> (Mat, Mat) {
    let params = CartParams {
        a_c: p.a_c,
        b_c: p.b_c,
        m_p: p.m_p,
        l_p: p.l_p,
        J_p: p.J_p,
        mu_p: p.mu_p,
        g: p.g,
    };
    params.linearization(match posture {
        Posture::Upright => Rest::Upright,
        Posture::Hanging => Rest::Hanging,
    })
}

#[test]
fn linearization_equals_spec_closed_form() {
    let other = CartPendulumParams {
        a_c: 3.1,
        b_c: 2.7,
        m_p: 0.42,
        l_p: 0.51,
        L_p: 0.6,
        J_p: 7.3e-3,
        mu_p: 4.4e-3,
        g: 9.78,
    };
    for p in [book(), other] {
        let plant = CartPendulum::new(p).unwrap();
        for posture in [Posture::Upright, Posture::Hanging] {
            for z in [0.0, -0.3, 0.25] {
                let sys = plant.linearize(CartEquilibrium { z, posture }).unwrap();
                let (a, b) = spec_model(&p, posture);
                // Same formulas evaluated in a different order: a few roundings apart.
                let tol = 1e-14;
                assert!((sys.a() - &a).amax() <= tol * max_abs(&a), "A {posture:?}");
                assert!((sys.b() - &b).amax() <= tol * max_abs(&b), "B {posture:?}");
                assert_eq!(sys.c(), &Mat::identity(4, 4));
                assert_eq!(sys.d(), &Mat::zeros(4, 1));
            }
        }
    }
}

#[test]
fn measured_linearization_has_encoder_outputs() {
    let plant = CartPendulum::book();
    let sys = plant
        .linearize_measured(CartEquilibrium::hanging())
        .unwrap();
    let c = Mat::from_row_slice(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    assert_eq!(sys.c(), &c);
    assert_eq!(CartPendulum::measured_output_matrix(), c);
    assert_eq!(sys.d(), &Mat::zeros(2, 1));
    let full = plant.linearize(CartEquilibrium::hanging()).unwrap();
    assert_eq!(sys.a(), full.a());
    assert_eq!(sys.b(), full.b());
}

#[test]
fn jacobian_matches_central_differences() {
    // Central differences with h = 1e-5·max(1, |x|): truncation h²|f'''|/6 ≈ 1e-10·|f'''|,
    // rounding ε|f|/h ≈ 1e-11·|f|; 1e-7 relative to the Jacobian's largest entry leaves
    // three orders of margin.
    let plant = CartPendulum::book();
    let points = [
        ([0.0, 0.0, 0.0, 0.0], 0.0),
        ([0.0, PI, 0.0, 0.0], 0.0),
        ([0.1, 0.3, -0.2, 0.5], 0.7),
        ([-0.4, 2.2, 0.9, -3.0], -2.5),
        ([0.3, -4.0, 1.1, 6.0], 4.5),
    ];
    assert_jacobian_matches_fd(
        |x, u| plant.jacobian(x, u),
        |x, u| plant.derivative_array(x, u),
        &points,
        1e-7,
    );
    // The equilibrium Jacobian is the general one evaluated at the equilibrium.
    let at_eq = plant.jacobian(&[0.2, PI, 0.0, 0.0], 0.0);
    let eq = plant
        .equilibrium_jacobian(CartEquilibrium {
            z: 0.2,
            posture: Posture::Hanging,
        })
        .unwrap();
    // sin(π) ≈ 1.2e-16 enters the general one only through a term multiplied by z̈ = 0.
    assert!((at_eq.a_matrix() - eq.a_matrix()).amax() <= 1e-15 * eq.a_matrix().amax());
}

#[test]
fn dynamics_trait_agrees_with_array_form() {
    let plant = CartPendulum::book();
    let x = [0.1, 0.3, -0.2, 0.5];
    let mut dx = [0.0; 4];
    plant.derivative(0.0, &x, &[0.7], &mut dx);
    assert_eq!(dx, plant.derivative_array(&x, 0.7));
    assert_eq!((plant.nx(), plant.nu()), (4, 1));
}

#[test]
fn nonlinear_model_matches_sympy_euler_lagrange() {
    // tools/reference/plants_lagrange.py derives the equations from the Lagrangian with SymPy
    // and evaluates them at 40 digits. Our f64 evaluation differs by a few roundings of
    // O(10) operations: 1e-12 relative to max(1, |f|) is ample and still catches any wrong
    // term or sign (those change f at the 1e-3 level or more).
    for case in sympy_cases("cart_pendulum") {
        let p = &case.params;
        let params = CartPendulumParams {
            a_c: num(&p["a_c"]),
            b_c: num(&p["b_c"]),
            m_p: num(&p["m_p"]),
            l_p: num(&p["l_p"]),
            L_p: 0.38,
            J_p: num(&p["J_p"]),
            mu_p: num(&p["mu_p"]),
            g: num(&p["g"]),
        };
        let plant = CartPendulum::new(params).unwrap();
        assert_matches_sympy(&plant.derivative_array(&case.x, case.u), &case, 1e-12);
    }
}

#[test]
fn energy_is_conserved_without_friction_with_the_cart_held() {
    // μ_p = 0, ż(0) = 0, v = 0: the drive keeps z̈ ≡ 0 (the cart is held). RK4 at 1e-4 s for
    // 10 s: the local energy error is O((ω h)⁵) ≈ (6e-4)⁵ per step, ≈ 1e-11 relative after
    // 1e5 steps; 1e-9 is the required bound.
    let p = CartPendulumParams {
        mu_p: 0.0,
        ..book()
    };
    let plant = CartPendulum::new(p).unwrap();
    for theta0 in [0.3, 2.0, PI - 0.01] {
        let x0 = [0.1, theta0, 0.0, 1.5];
        let path = rk4_path(|_, x| plant.derivative_array(x, 0.0), x0, 1e-4, 100_000);
        let e0 = plant.energy(&x0.into());
        let drift = energy_drift(&path, |x| plant.energy(&(*x).into()));
        assert!(drift <= 1e-9 * e0, "θ0 = {theta0}: drift {drift:e} of {e0}");
        // The cart really stayed put.
        assert!(path.iter().all(|x| x[0] == 0.1 && x[2] == 0.0));
    }
    // The same with the fixed-cart model.
    let fixed = plant.fixed_cart();
    let x0 = [2.0, 1.5];
    let path = rk4_path(|_, x| fixed.derivative_array(x), x0, 1e-4, 100_000);
    let e0 = fixed.energy(&x0);
    let drift = energy_drift(&path, |x| fixed.energy(x));
    assert!(drift <= 1e-9 * e0, "fixed cart drift {drift:e}");
}

#[test]
fn energy_balance_holds_with_the_cart_driven() {
    // Along any solution dE/dt = −m_p l_p cos θ θ̇ z̈ − μ_p θ̇² (the power of the inertial force
    // −m_p z̈ at the centre of mass, whose velocity relative to the cart is
    // l_p θ̇ (cos θ, −sin θ), plus friction). Check E(T) − E(0) = ∫ P dt along an RK4 path
    // driven by a smooth voltage, the integral by Simpson's rule on the same samples.
    let p = CartPendulumParams {
        mu_p: 5e-3, // larger than the book's, so friction matters in the balance
        ..book()
    };
    let plant = CartPendulum::new(p).unwrap();
    let v = |t: f64| 2.0 * (3.0 * t).sin() + 0.5 * (7.0 * t).cos();
    let power = |x: &[f64; 4], v: f64| {
        let ddz = -p.a_c * x[2] + p.b_c * v;
        -p.m_p * p.l_p * x[1].cos() * x[3] * ddz - p.mu_p * x[3] * x[3]
    };
    assert_energy_balance(
        |x, v| plant.derivative_array(x, v),
        v,
        [0.0, PI - 0.3, 0.0, 0.0],
        |x| plant.energy(&(*x).into()),
        power,
    );
}

#[test]
fn energy_levels_and_geometry() {
    let plant = CartPendulum::book();
    let p = book();
    let up = CartEquilibrium::upright().state();
    let down = CartEquilibrium::hanging().state();
    // docs/model.md §1: 0 hanging at rest, 2 m_p g l_p upright at rest.
    assert!(plant.energy(&down).abs() <= 1e-17);
    assert!((plant.energy(&up) - 2.0 * p.m_p * p.g * p.l_p).abs() <= 1e-16);
    assert_eq!(plant.upright_energy(), plant.energy(&up));
    // Tip at (z + L_p sin θ, L_p cos θ).
    let x = CartPendulumState {
        z: 0.2,
        theta: 0.7,
        dz: 0.0,
        dtheta: 0.0,
    };
    let pose = plant.pose(&x);
    assert_eq!(pose.pivot, [0.2, 0.0]);
    assert!((pose.tip[0] - (0.2 + 0.38 * 0.7f64.sin())).abs() < 1e-15);
    assert!((pose.tip[1] - 0.38 * 0.7f64.cos()).abs() < 1e-15);
    let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    assert!((d(pose.tip, pose.pivot) - 0.38).abs() < 1e-15);
    assert!((d(pose.centre_of_mass, pose.pivot) - 0.23).abs() < 1e-15);
    // Hanging: the tip is straight below the pivot.
    let pose = plant.pose(&down);
    assert!(pose.tip[0].abs() < 1e-15 && (pose.tip[1] + 0.38).abs() < 1e-15);
}

#[test]
fn state_converts_to_and_from_arrays() {
    let x = [0.1, 2.0, -0.3, 4.0];
    let s = CartPendulumState::from(x);
    assert_eq!(
        s,
        CartPendulumState {
            z: 0.1,
            theta: 2.0,
            dz: -0.3,
            dtheta: 4.0
        }
    );
    assert_eq!(<[f64; 4]>::from(s), x);
    assert_eq!((s.phi() - (2.0 - PI)).abs(), 0.0);
    assert!(s.is_finite());
    assert!(!CartPendulumState { z: f64::NAN, ..s }.is_finite());
}

#[test]
fn fixed_cart_eigenvalues_are_the_closed_forms() {
    // Eqs 4.41/4.45 against the eigenvalues of the linear models (4.40)/(4.44) computed by the
    // LTI core's Schur-based eigen-solver: two independent computations. Also a heavily
    // damped pendulum (ζ_p > 1: real hanging eigenvalues).
    let heavy = CartPendulumParams {
        mu_p: 0.2,
        ..book()
    };
    for p in [book(), heavy] {
        let plant = CartPendulum::new(p).unwrap();
        let fixed = plant.fixed_cart();
        let j = p.J_p + p.m_p * p.l_p * p.l_p;
        let w = (p.m_p * p.g * p.l_p / j).sqrt();
        let zeta = p.mu_p / (2.0 * w * j);
        assert!((fixed.natural_frequency() - w).abs() <= 1e-15 * w);
        assert!((fixed.damping_ratio() - zeta).abs() <= 1e-15 * zeta);
        for posture in [Posture::Hanging, Posture::Upright] {
            let sys = fixed.linearize(posture).unwrap();
            assert_eq!((sys.nx(), sys.nu()), (2, 0));
            let mut numeric = pendulab_lti::linalg::eigenvalues(sys.a()).unwrap();
            let mut closed = fixed.eigenvalues(posture).to_vec();
            let key =
                |a: &Complex64, b: &Complex64| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im));
            numeric.sort_by(key);
            closed.sort_by(key);
            // Eigenvalues of a 2×2 companion matrix: backward stable, well conditioned unless
            // the two roots nearly coincide (not the case here: ζ is far from 1).
            for (a, b) in numeric.iter().zip(&closed) {
                assert!((a - b).norm() <= 1e-12 * w, "{posture:?}: {a} vs {b}");
            }
            // Stability as the book concludes: hanging stable, upright unstable.
            let max_re = closed.iter().map(|l| l.re).fold(f64::MIN, f64::max);
            match posture {
                Posture::Hanging => assert!(max_re < 0.0),
                Posture::Upright => assert!(max_re > 0.0),
            }
        }
        // The fixed-cart model is the (θ, θ̇) block of the full cart model.
        let full = plant.linearize(CartEquilibrium::upright()).unwrap();
        let fixed_a = fixed.linearize(Posture::Upright).unwrap();
        for (i, fi) in [(1, 0), (3, 1)] {
            for (j, fj) in [(1, 0), (3, 1)] {
                assert_eq!(full.a()[(i, j)], fixed_a.a()[(fi, fj)]);
            }
        }
    }
}

#[test]
fn cart_drive_is_b_over_s_s_plus_a() {
    let plant = CartPendulum::book();
    let drive = plant.drive();
    assert_eq!((drive.a(), drive.b()), (6.25, 4.36));
    let sys = drive.state_space().unwrap();
    let mut poles = sys.poles().unwrap();
    poles.sort_by(|a, b| a.re.total_cmp(&b.re));
    assert!((poles[0].re + 6.25).abs() < 1e-12 && poles[1].norm() < 1e-12);
    // P(jω) = b / (jω (jω + a)) at ω = 2 from the transfer function.
    let tf = drive.transfer_function().unwrap();
    let s = Complex64::new(0.0, 2.0);
    let expected = Complex64::new(4.36, 0.0) / (s * (s + 6.25));
    assert!((tf.eval(s) - expected).norm() <= 1e-14 * expected.norm());
    // The drive's derivative is the first and third rows of the plant's.
    let x = [0.1, 0.4, -0.3, 0.2];
    let f = plant.derivative_array(&x, 1.3);
    assert_eq!(drive.derivative_array(&[x[0], x[2]], 1.3), [f[0], f[2]]);
    assert!(Drive::new(-1.0, 1.0).is_err());
    assert!(Drive::new(1.0, 0.0).is_err());
    assert!(Drive::new(0.0, 1.0).is_ok());
}

#[test]
fn invalid_parameters_are_typed_errors() {
    let fields = fields![CartPendulumParams;
        a_c = true, b_c = false, m_p = false, l_p = false, L_p = false, J_p = false, mu_p = true,
        g = false];
    assert_fields_validated(
        book(),
        &fields,
        &[f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0],
        CartPendulum::new,
        |p| assert!(FixedCartPendulum::new(p).is_err()),
    );
    // The message names parameter and value.
    let p = CartPendulumParams {
        m_p: -0.1,
        ..book()
    };
    let msg = CartPendulum::new(p).unwrap_err().to_string();
    assert!(msg.contains("m_p") && msg.contains("-0.1"), "{msg}");
    // Valid but absurd: the derived inertia overflows.
    let p = CartPendulumParams {
        m_p: 1e200,
        l_p: 1e200,
        ..book()
    };
    assert!(matches!(
        CartPendulum::new(p),
        Err(PlantError::DerivedQuantity { .. })
    ));
    // A non-finite operating point.
    let plant = CartPendulum::book();
    let eq = CartEquilibrium {
        z: f64::NAN,
        posture: Posture::Upright,
    };
    assert!(matches!(
        plant.linearize(eq),
        Err(PlantError::NonFiniteOperatingPoint { what: "z", .. })
    ));
    assert_eq!(CartPendulum::new(book()).unwrap(), CartPendulum::book());
}
