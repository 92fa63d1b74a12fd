//! Batch runs: the parallel map equals one-by-one runs, a region-of-attraction map has the
//! symmetry of the dynamics, Monte Carlo over parameters is reproducible.

mod common;

use common::CartPendulum;
use pendulab_lti::Mat;
use pendulab_sim::batch::{Axis, grid, monte_carlo, par_map, run_initial_states};
use pendulab_sim::controllers::StaticStateFeedback;
use pendulab_sim::{MaxAbs, Record, RunStatus, SampledLoop, SampledOptions, StayWithin};
use rand::Rng;

fn lqr_gain() -> Mat {
    let q = Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[10.0, 10.0, 0.0, 0.0]));
    pendulab_lti::design::lqr(
        &CartPendulum::default().linear(),
        &q,
        &Mat::identity(1, 1),
        None,
    )
    .unwrap()
    .gain
}

#[test]
fn region_of_attraction_map() {
    let n = 15;
    let x0s = grid(
        &[0.0; 4],
        &[Axis::new(1, -1.2, 1.2, n), Axis::new(3, -3.0, 3.0, n)],
    )
    .unwrap();
    let template = SampledLoop::new(
        CartPendulum::default(),
        StaticStateFeedback::new(lqr_gain()).unwrap(),
        SampledOptions {
            t_final: 3.0,
            record: Record::Off,
            ..Default::default()
        },
    )
    .unwrap();
    let upright = |_: usize| {
        (
            StayWithin::new(1, std::f64::consts::FRAC_PI_2),
            MaxAbs::new(0),
        )
    };
    let map = run_initial_states(&template, &x0s, upright, |_, (s, m), run| {
        (s.held(), m.value, run.status == RunStatus::Completed)
    })
    .unwrap();
    assert_eq!(map.len(), n * n);
    // Parallel and one-by-one runs agree exactly.
    for (i, x0) in x0s.iter().enumerate().step_by(17) {
        let mut lp = template.clone();
        let mut mon = upright(i);
        let run = lp.run_with(x0, &mut mon).unwrap();
        assert_eq!(
            map[i],
            (
                mon.0.held(),
                mon.1.value,
                run.status == RunStatus::Completed
            )
        );
    }
    // The closed loop is odd (f(−x, −u) = −f(x, u), u = −Kx): the run from −x0 mirrors the
    // run from x0 sample by sample, so the map is point-symmetric on the grid.
    for i in 0..n * n {
        assert_eq!(map[i], map[n * n - 1 - i], "grid point {i}");
    }
    // The upright rest is inside; stopped runs are exactly those that fell.
    let centre = (n / 2) * n + n / 2;
    assert!(map[centre].0);
    assert!(map.iter().all(|&(held, _, completed)| held == completed));
    let inside = map.iter().filter(|m| m.0).count();
    assert!(inside > 0 && inside < n * n, "{inside}");
}

#[test]
fn monte_carlo_over_parameters_is_reproducible() {
    // Pendulum mass ±20 %: final |θ| after 2 s from 0.2 rad under the nominal LQR.
    let k = lqr_gain();
    let masses = |seed| monte_carlo(seed, 24, |rng, _| 0.107 * (0.8 + 0.4 * rng.random::<f64>()));
    let cases = masses(42);
    assert_eq!(cases, masses(42));
    assert_ne!(cases, masses(43));
    assert!(cases.iter().all(|&m| (0.0856..=0.1284).contains(&m)));
    let run_one = |mp: f64| {
        let plant = CartPendulum {
            mp,
            ..Default::default()
        };
        let mut lp = SampledLoop::new(
            plant,
            StaticStateFeedback::new(k.clone()).unwrap(),
            SampledOptions {
                t_final: 2.0,
                record: Record::Off,
                ..Default::default()
            },
        )?;
        Ok(lp.run(&[0.0, 0.2, 0.0, 0.0])?.diagnostics.final_state[1].abs())
    };
    let par = par_map(&cases, |_, &m| run_one(m)).unwrap();
    let seq: Vec<f64> = cases.iter().map(|&m| run_one(m).unwrap()).collect();
    assert_eq!(par, seq);
    assert!(par.iter().all(|&th| th < 0.05));
}
