//! The arm swing-up problem's derivatives against the cost they come from: the optimality
//! residual times Δτ must be the gradient of the discretised cost computed by rollouts of the
//! plant model alone (central differences), with and without the input bound.

use pendulab_control::cgmres::{Cgmres, CgmresOptions, Horizon, OptimalControlProblem};
use pendulab_control::nmpc::{ArmSwingUp, ArmSwingUpSettings, arm_swing_up_problem};
use pendulab_plants::ArmPendulum;

#[test]
fn optimality_residual_is_the_gradient_of_the_rollout_cost() {
    let plant = ArmPendulum::book();
    let q = [1.0, 1.0, 0.2, 0.1];
    let qf = [3.0, 1.0, 0.5, 0.5];
    let p = ArmSwingUp::new(plant, q, qf, 0.1, [0.0; 4]).unwrap();
    let (n, horizon) = (12, 0.5);
    let mut s = Cgmres::new(
        p.clone(),
        CgmresOptions {
            horizon: Horizon::Fixed { length: horizon },
            grid_points: n,
            ..Default::default()
        },
    )
    .unwrap();
    let u: Vec<f64> = (0..n).map(|i| 1.5 * (0.7 * i as f64).sin()).collect();
    s.set_sequence(0.0, &u).unwrap();
    let x0 = [2.0, 2.5, 1.0, -0.5];
    let mut f = vec![0.0; n];
    s.residual(0.0, &x0, &mut f).unwrap();
    let dt = horizon / n as f64;
    let cost = |u: &[f64]| {
        let mut x = x0;
        let mut j = 0.0;
        for &ui in u {
            j += p.stage_cost(&x, ui) * dt;
            let d = plant.derivative_array(&x, ui);
            for k in 0..4 {
                x[k] += dt * d[k];
            }
        }
        j + p.terminal_cost(&x)
    };
    for i in 0..n {
        let e = 1e-6;
        let (mut up, mut um) = (u.clone(), u.clone());
        up[i] += e;
        um[i] -= e;
        let g = (cost(&up) - cost(&um)) / (2.0 * e);
        // Central differences: truncation O(e²) ≈ 1e-12 times third derivatives of order 10,
        // rounding O(ε J/e) ≈ 1e-9 with J ≈ 10.
        assert!(
            (f[i] * dt - g).abs() < 1e-7 * (1.0 + g.abs()),
            "stage {i}: F·Δτ = {}, dJ/du = {g}",
            f[i] * dt
        );
    }
}

#[test]
fn bounded_problem_adds_the_dummy_input_terms() {
    // H_u of the bounded problem = base H_u + constraint terms; with a consistent stage guess
    // the dummy and multiplier rows vanish, and the input row gains 2ρu.
    let settings = ArmSwingUpSettings::book();
    let bounded = arm_swing_up_problem(ArmPendulum::book(), &settings).unwrap();
    assert_eq!((bounded.nu(), bounded.n_inputs()), (3, 1));
    let stage = bounded.stage_guess(&[1.2]).unwrap();
    let x = [0.3, -0.2, 1.0, 2.0];
    let lambda = [0.1, -0.4, 0.3, 0.2];
    let mut hu = [0.0; 3];
    bounded.hamiltonian_u(0.0, &x, &stage, &lambda, &mut hu);
    let mut hu_base = [0.0];
    bounded
        .base()
        .hamiltonian_u(0.0, &x, &stage[..1], &lambda, &mut hu_base);
    assert!((hu[0] - (hu_base[0] + 2.0 * stage[2] * stage[0])).abs() < 1e-15);
    assert!(hu[1].abs() < 1e-15 && hu[2].abs() < 1e-12);
    // The fused call agrees with the separate ones.
    let (mut hx1, mut hx2, mut hu2) = ([0.0; 4], [0.0; 4], [0.0; 3]);
    bounded.hamiltonian_x(0.0, &x, &stage, &lambda, &mut hx1);
    bounded.hamiltonian_xu(0.0, &x, &stage, &lambda, &mut hx2, &mut hu2);
    assert_eq!(hx1, hx2);
    assert_eq!(hu, hu2);
}
