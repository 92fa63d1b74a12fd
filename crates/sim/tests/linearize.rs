//! `linearize` against analytic Jacobians: the cart pendulum (the matrices of `docs/model.md` §1
//! and hand-derived Jacobians away from equilibrium), the arm pendulum at a tilted arm
//! equilibrium (the formula of `docs/model.md` §2; both closed forms from pendulab-testkit), and
//! a linear system with an output map.

mod common;

use common::CartPendulum;
use pendulab_lti::{Mat, StateSpace};
use pendulab_sim::{
    DifferenceScheme, Dynamics, FnDynamics, LinearizeOptions, SimError, jacobians, linearize,
};
use pendulab_testkit::arm::ArmParams;

/// Largest entry-wise relative error `|J − J_ref| / max(|J_ref|, scale·1e-3)`, where
/// `scale = max |J_ref|`: relative for entries of normal size, absolute (w.r.t. the matrix
/// scale) for entries that are zero or tiny.
fn rel_err(j: &Mat, r: &Mat) -> f64 {
    let scale = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut worst = 0.0f64;
    for (a, b) in j.iter().zip(r.iter()) {
        worst = worst.max((a - b).abs() / b.abs().max(1e-3 * scale));
    }
    worst
}

#[test]
fn cart_pendulum_upright_matches_spec_matrices() {
    let p = CartPendulum::default();
    let lin = p.linear();
    let opts = LinearizeOptions::default();
    let l = linearize(&p, 0.0, &[0.0; 4], &[0.0], &opts).unwrap();
    // Richardson (h⁶) differences: truncation ~1e-13 and rounding ~1e-13 relative; the
    // acceptance threshold of the project is 1e-7, asserted with margin at 1e-10.
    assert!(rel_err(l.system.a(), lin.a()) < 1e-10, "{}", l.system.a());
    assert!(rel_err(l.system.b(), lin.b()) < 1e-10);
    assert_eq!(l.equilibrium_residual(), 0.0);
    // No output map: C = I, D = 0.
    assert_eq!(l.system.c(), &Mat::identity(4, 4));
    assert_eq!(l.system.d(), &Mat::zeros(4, 1));
    // docs/model.md §1: open-loop eigenvalues 0, −6.25, +5.7543, −5.7867.
    let mut ev: Vec<f64> = pendulab_lti::linalg::eigenvalues(l.system.a())
        .unwrap()
        .iter()
        .map(|c| c.re)
        .collect();
    ev.sort_by(|a, b| a.total_cmp(b));
    for (e, r) in ev.iter().zip([-6.25, -5.7867, 0.0, 5.7543]) {
        // Printed to 4 decimals.
        assert!((e - r).abs() < 5e-5, "{ev:?}");
    }
}

#[test]
fn cart_pendulum_away_from_equilibrium_matches_hand_derived_jacobians() {
    let p = CartPendulum::default();
    for (x, v) in [
        ([0.1, 0.7, -0.3, 1.2], 0.8),
        ([-0.4, 2.9, 1.5, -4.0], -3.0),
        ([0.0, std::f64::consts::PI, 0.0, 0.0], 0.0),
    ] {
        let (ar, br) = p.jacobians(&x, v);
        for scheme in [
            DifferenceScheme::Central,
            DifferenceScheme::Richardson { extrapolations: 1 },
            DifferenceScheme::Richardson { extrapolations: 2 },
            DifferenceScheme::Richardson { extrapolations: 4 },
        ] {
            let opts = LinearizeOptions {
                scheme,
                ..Default::default()
            };
            let j = jacobians(&p, 0.0, &x, &[v], &opts).unwrap();
            // Central differences: O(h²) with h ≈ 6e-6·max(|x|, 1) gives ~1e-10; the
            // Richardson schemes ~1e-12. Project threshold 1e-7, asserted at 1e-8.
            let tol = if scheme == DifferenceScheme::Central {
                1e-8
            } else {
                1e-10
            };
            assert!(
                rel_err(&j.a, &ar) < tol,
                "{scheme:?} at {x:?}: {}",
                rel_err(&j.a, &ar)
            );
            assert!(rel_err(&j.b, &br) < tol, "{scheme:?} at {x:?}");
            // The reported error estimate bounds the actual error within a modest factor.
            let actual =
                j.a.iter()
                    .zip(ar.iter())
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
            assert!(
                actual <= 20.0 * j.error_estimate + 1e-12,
                "{actual:e} vs {:e}",
                j.error_estimate
            );
            // f0 is f at the point.
            let mut f = [0.0; 4];
            p.derivative(0.0, &x, &[v], &mut f);
            assert_eq!(j.f0, f.to_vec());
        }
    }
}

/// The arm-type pendulum of `docs/model.md` §2 (book table 3.7), solved for the accelerations.
fn arm_pendulum() -> impl Dynamics {
    let p = ArmParams::book();
    let (alpha2, alpha3, alpha5) = p.alphas();
    let (a1, b1, mu2) = (p.a1, p.b1, p.mu2);
    FnDynamics::new(4, 1, move |_t, x: &[f64], u: &[f64], dx: &mut [f64]| {
        let th1dd = -a1 * x[2] + b1 * u[0];
        let d = x[0] - x[1];
        let th2dd = (alpha3 * x[2] * x[2] * d.sin() + alpha5 * x[1].sin() + mu2 * (x[2] - x[3])
            - alpha3 * d.cos() * th1dd)
            / alpha2;
        dx[0] = x[2];
        dx[1] = x[3];
        dx[2] = th1dd;
        dx[3] = th2dd;
    })
}

#[test]
fn arm_pendulum_at_tilted_arm_matches_spec_formula() {
    let sys = arm_pendulum();
    for th1e in [0.0, 0.4, -1.1, 2.0] {
        // The closed form of docs/model.md §2 (pendulab-testkit).
        let (ar, br) = ArmParams::book().linearization(th1e);
        let l = linearize(
            &sys,
            0.0,
            &[th1e, 0.0, 0.0, 0.0],
            &[0.0],
            &Default::default(),
        )
        .unwrap();
        assert!(rel_err(l.system.a(), &ar) < 1e-10, "θ1e = {th1e}");
        assert!(rel_err(l.system.b(), &br) < 1e-10, "θ1e = {th1e}");
        assert!(l.equilibrium_residual() < 1e-15);
    }
}

#[test]
fn linear_system_with_output_map_is_recovered() {
    let a = Mat::from_row_slice(3, 3, &[0.0, 1.0, 0.0, -2.0, -0.3, 4.0, 1.0, 0.0, -5.0]);
    let b = Mat::from_row_slice(3, 2, &[0.0, 1.0, 2.0, 0.0, -1.0, 0.5]);
    let c = Mat::from_row_slice(2, 3, &[1.0, 0.0, 3.0, 0.0, -2.0, 0.0]);
    let d = Mat::from_row_slice(2, 2, &[0.1, 0.0, 0.0, -0.7]);
    let sys = StateSpace::continuous(a.clone(), b.clone(), c.clone(), d.clone()).unwrap();
    let l = linearize(
        &sys,
        1.0,
        &[3.0, -1.0, 200.0],
        &[0.5, -2.0],
        &Default::default(),
    )
    .unwrap();
    // Differences of an affine map are exact up to rounding (relative ~1e-13 at |x| = 200).
    for (got, want) in [
        (l.system.a(), &a),
        (l.system.b(), &b),
        (l.system.c(), &c),
        (l.system.d(), &d),
    ] {
        let e = got
            .iter()
            .zip(want.iter())
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(e < 1e-10, "{got} vs {want}");
    }
}

#[test]
fn bad_inputs_are_typed_errors() {
    let p = CartPendulum::default();
    let o = LinearizeOptions::default();
    assert!(matches!(
        linearize(&p, 0.0, &[0.0; 3], &[0.0], &o),
        Err(SimError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        linearize(&p, 0.0, &[0.0; 4], &[], &o),
        Err(SimError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        linearize(&p, 0.0, &[0.0, f64::NAN, 0.0, 0.0], &[0.0], &o),
        Err(SimError::NonFiniteInitialState { index: 1, .. })
    ));
    assert!(linearize(&p, 0.0, &[0.0; 4], &[f64::INFINITY], &o).is_err());
    assert!(linearize(&p, f64::NAN, &[0.0; 4], &[0.0], &o).is_err());
    for scheme in [
        DifferenceScheme::Richardson { extrapolations: 0 },
        DifferenceScheme::Richardson { extrapolations: 7 },
    ] {
        let o = LinearizeOptions {
            scheme,
            ..Default::default()
        };
        assert!(matches!(
            linearize(&p, 0.0, &[0.0; 4], &[0.0], &o),
            Err(SimError::InvalidParameter { .. })
        ));
    }
    let o = LinearizeOptions {
        relative_step: Some(0.0),
        ..Default::default()
    };
    assert!(linearize(&p, 0.0, &[0.0; 4], &[0.0], &o).is_err());
    let o = LinearizeOptions {
        typical_scale: Some(vec![1.0; 4]),
        ..Default::default()
    };
    assert!(matches!(
        linearize(&p, 0.0, &[0.0; 4], &[0.0], &o),
        Err(SimError::DimensionMismatch { .. })
    ));
    // f not finite near the point (√x at x = 0 perturbed to negative values).
    let sqrt = FnDynamics::new(1, 0, |_t, x: &[f64], _u: &[f64], dx: &mut [f64]| {
        dx[0] = x[0].sqrt()
    });
    assert!(matches!(
        linearize(&sqrt, 0.0, &[0.0], &[], &LinearizeOptions::default()),
        Err(SimError::NonFiniteState { .. })
    ));
}
