//! Instruction-count harness for the simulator's hot loops (run under
//! `valgrind --tool=callgrind`): `sim_profile rk4|batch|env <reps>`.
use pendulab_lti::Mat;
use pendulab_plants::{CartEquilibrium, CartPendulum};
use pendulab_sim::controllers::StaticStateFeedback;
use pendulab_sim::{Env, EnvConfig, Record, SampledLoop, SampledOptions, StayWithin};
use std::hint::black_box;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let what = args.get(1).map_or("rk4", |s| s.as_str());
    let reps: usize = args.get(2).map_or(10, |s| s.parse().unwrap());
    let plant = CartPendulum::book();
    let sys = plant.linearize(CartEquilibrium::upright()).unwrap();
    let mut q = Mat::zeros(4, 4);
    q[(0, 0)] = 10.0;
    q[(1, 1)] = 10.0;
    let k = pendulab_lti::design::lqr(&sys, &q, &Mat::identity(1, 1), None)
        .unwrap()
        .gain;
    let mk = |record| {
        SampledLoop::new(
            plant,
            StaticStateFeedback::new(k.clone()).unwrap(),
            SampledOptions {
                t_final: 10.0,
                record,
                ..Default::default()
            },
        )
        .unwrap()
    };
    let mut steps = 0usize;
    match what {
        "rk4" => {
            let mut lp = mk(Record::EverySample);
            let x0 = [0.0, 15f64.to_radians(), 0.0, 0.0];
            let mut last = lp.run(&x0).unwrap();
            for _ in 0..reps {
                last = lp.run_recycling(black_box(&x0), &mut (), last).unwrap();
                steps += last.diagnostics.integration.accepted_steps;
            }
        }
        "batch" => {
            let mut lp = mk(Record::Off);
            for i in 0..reps {
                let th = -1.2 + 2.4 * (i as f64 / reps as f64);
                let mut m = StayWithin::new(1, std::f64::consts::FRAC_PI_2);
                let r = lp.run_with(&[0.0, th, 0.0, 0.5], &mut m).unwrap();
                steps += r.diagnostics.integration.accepted_steps;
            }
        }
        "lanes" | "lanes-libm" | "lanes8" | "lanes16" => {
            use pendulab_sim::lanes::{LaneOptions, LibmSinCos, PolySinCos, run_feedback_lanes};
            let g = [k[(0, 0)], k[(0, 1)], k[(0, 2)], k[(0, 3)]];
            let o = LaneOptions {
                ts: 1e-3,
                t_final: 10.0,
                substeps: 1,
                stay_within: Some((1, std::f64::consts::FRAC_PI_2)),
            };
            let x0s: Vec<[f64; 4]> = (0..reps)
                .map(|i| [0.0, -1.2 + 2.4 * (i as f64 / reps as f64), 0.0, 0.5])
                .collect();
            let out = match what {
                "lanes" => run_feedback_lanes::<_, PolySinCos, 4, 4>(&plant, &g, &o, &x0s),
                "lanes8" => run_feedback_lanes::<_, PolySinCos, 4, 8>(&plant, &g, &o, &x0s),
                "lanes16" => run_feedback_lanes::<_, PolySinCos, 4, 16>(&plant, &g, &o, &x0s),
                _ => run_feedback_lanes::<_, LibmSinCos, 4, 4>(&plant, &g, &o, &x0s),
            }
            .unwrap();
            steps = out.iter().map(|o| o.steps).sum();
        }
        _ => {
            let mut env = Env::<_, 4>::new(plant, EnvConfig::cart_pole(0.4).unwrap()).unwrap();
            env.reset(Some(1));
            for i in 0..reps {
                let a = ((i * 7919) % 1000) as f64 / 100.0 - 5.0;
                let s = env.step(a).unwrap();
                if s.terminated || s.truncated {
                    env.reset(None);
                }
                steps += 1;
            }
        }
    }
    println!("{what}: {steps} steps");
}
