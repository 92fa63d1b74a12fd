//! `lsim-1e6`: 10⁶ samples of a 5-state closed loop at 1 ms with a first-order hold.
//!
//! Figure: samples per second of the simulation (exact FOH discretisation plus the
//! allocation-free recursion into reused buffers); the `lsim` convenience call, which also
//! allocates its result, is reported in the check.
//!
//! The system is the cart pendulum of the book (table 3.5, `docs/model.md` §1) with the
//! integral-servo augmentation `Ã = [[A, 0], [−C, 0]]`, `B̃ = [B; 0]`, `y = z`, closed by a
//! pole-placement gain (poles −2, −3, −4, −5 ± 1j), driven through the integrator by a reference
//! `r(t)`: a triangle wave (amplitude 0.5 m, period 200 s) whose corners fall on the sample grid,
//! so the FOH simulation is exact. The accuracy check recomputes the final state by an independent
//! route: one block exponential per linear segment of `r` (5 exponentials of a 7×7 matrix over
//! 200 s each instead of 10⁶ steps of 1 ms).

use super::{BenchReport, Budget, time};
use anyhow::Result;
use pendulab_lti::design::{integral_augmentation, place};
use pendulab_lti::matrix_functions::expm;
use pendulab_lti::response::{InputHold, LsimKernel, LsimOptions, lsim};
use pendulab_lti::{Complex64, Mat, StateSpace};
use pendulab_plants::{CartEquilibrium, CartPendulum};
use serde_json::json;

const SAMPLES: usize = 1_000_000;
const DT: f64 = 1e-3;
const PERIOD: f64 = 200.0;
const AMPLITUDE: f64 = 0.5;

fn closed_loop() -> Result<StateSpace<pendulab_lti::Continuous>> {
    // The library's own path to the model: the plant's linearisation at the upright rest.
    let lin = CartPendulum::book().linearize(CartEquilibrium::upright())?;
    let c = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
    let plant = StateSpace::continuous(lin.a().clone(), lin.b().clone(), c, Mat::zeros(1, 1))?;
    let (aa, ba) = integral_augmentation(&plant)?;
    let poles = [
        Complex64::new(-2.0, 0.0),
        Complex64::new(-3.0, 0.0),
        Complex64::new(-4.0, 0.0),
        Complex64::new(-5.0, 1.0),
        Complex64::new(-5.0, -1.0),
    ];
    let k = place(&aa, &ba, &poles)?.gain;
    let acl = &aa - &ba * &k;
    // The reference enters the integrator: ẇ = r − y.
    let mut br = Mat::zeros(5, 1);
    br[(4, 0)] = 1.0;
    let mut cy = Mat::zeros(1, 5);
    cy[(0, 0)] = 1.0;
    Ok(StateSpace::continuous(acl, br, cy, Mat::zeros(1, 1))?)
}

/// Triangle wave with corners at multiples of PERIOD/2 (on the grid).
fn reference(t: f64) -> f64 {
    let ph = (t / PERIOD).fract();
    if ph < 0.5 {
        AMPLITUDE * 4.0 * ph - AMPLITUDE
    } else {
        AMPLITUDE * (3.0 - 4.0 * ph)
    }
}

/// Final state by exact segment-wise propagation: on each linear piece of `r`,
/// `d/dt [x; r; ṙ] = [[A, B, 0], [0, 0, 1], [0, 0, 0]] [x; r; ṙ]`.
fn exact_final_state(sys: &StateSpace<pendulab_lti::Continuous>, t_end: f64) -> Result<Vec<f64>> {
    let n = sys.nx();
    let mut m = Mat::zeros(n + 2, n + 2);
    m.view_mut((0, 0), (n, n)).copy_from(sys.a());
    m.view_mut((0, n), (n, 1)).copy_from(sys.b());
    m[(n, n + 1)] = 1.0;
    let half = PERIOD / 2.0;
    let e = expm(&(m * half))?;
    let mut z = vec![0.0; n + 2];
    let segments = (t_end / half).round() as usize;
    for s in 0..segments {
        let t0 = s as f64 * half;
        z[n] = reference(t0);
        z[n + 1] = (reference(t0 + half * 0.5) - reference(t0)) / (half * 0.5);
        let zn: Vec<f64> = (0..n + 2)
            .map(|i| (0..n + 2).map(|j| e[(i, j)] * z[j]).sum())
            .collect();
        z = zn;
    }
    Ok(z[..n].to_vec())
}

/// Runs the workload.
pub fn run(budget: &Budget) -> Result<BenchReport> {
    let sys = closed_loop()?;
    let t: Vec<f64> = (0..SAMPLES).map(|k| k as f64 * DT).collect();
    let u = Mat::from_fn(SAMPLES, 1, |k, _| reference(t[k]));
    let opts = LsimOptions {
        hold: InputHold::Foh,
    };
    // Headline: the simulation itself — exact FOH discretisation (`LsimKernel::new`, one
    // block exponential) and the 10⁶-step recursion (`LsimKernel::run`), writing states and
    // outputs into caller-owned buffers that are reused between calls (no allocation).
    let mut xb = vec![0.0; SAMPLES * 5];
    let mut yb = vec![0.0; SAMPLES];
    let x0 = [0.0; 5];
    let timing = time(budget, || {
        let kernel = LsimKernel::new(&sys, DT, InputHold::Foh).expect("kernel");
        kernel
            .run(SAMPLES, u.as_slice(), &x0, &mut xb, &mut yb)
            .expect("kernel run");
    });
    // Also measured: the convenience call `lsim`, which additionally validates `t` and `u`
    // and allocates a fresh 56 MB `Trajectory` (t, x, u, y) per call; on this machine the
    // first-touch page faults of that memory cost about as much as the simulation.
    let mut last = None;
    let full = time(budget, || {
        last = Some(lsim(&sys, &u, &t, None, &opts).expect("lsim"));
    });
    let tr = last.expect("ran at least once");
    // The two routes must produce identical samples.
    let same = (0..5).all(|i| tr.x_signal(i) == &xb[i * SAMPLES..(i + 1) * SAMPLES])
        && tr.y_signal(0) == &yb[..];
    // Accuracy: final state against the segment-wise exact propagation.
    let t_end = (SAMPLES - 1) as f64 * DT;
    // Compare at the last multiple of PERIOD/2 on the grid (999.9 s is not a corner; use
    // 900 s, sample 900 000).
    let k_check = 900_000;
    let exact = exact_final_state(&sys, k_check as f64 * DT)?;
    let sim: Vec<f64> = (0..5).map(|i| tr.x()[(k_check, i)]).collect();
    let scale = exact.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let err = sim
        .iter()
        .zip(&exact)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let max_abs_y = tr.y_signal(0).iter().fold(0.0f64, |m, v| m.max(v.abs()));
    Ok(BenchReport {
        workload: "lsim-1e6".into(),
        figure: SAMPLES as f64 / timing.median_s,
        unit: "samples/s".into(),
        check: json!({
            "samples": SAMPLES,
            "dt": DT,
            "states": 5,
            "hold": "foh",
            "t_end": t_end,
            "figure_measures": "LsimKernel::new + LsimKernel::run into reused buffers (exact FOH discretisation and the 10^6-step recursion, allocation-free)",
            "median_s_per_call": timing.median_s,
            "min_s_per_call": timing.min_s,
            "calls": timing.iterations,
            "lsim_call_samples_per_s": SAMPLES as f64 / full.median_s,
            "lsim_call_median_s": full.median_s,
            "lsim_call_identical_to_kernel": same,
            "check_time_s": k_check as f64 * DT,
            "final_state_max_abs_error": err,
            "final_state_relative_error": err / scale.max(f64::MIN_POSITIVE),
            "final_state_reference": "segment-wise block exponential (independent of the time stepping)",
            "max_abs_y": max_abs_y,
        }),
    })
}
