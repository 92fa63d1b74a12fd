//! The pseudo-differentiator s/(T s + 1) against closed forms: step responses, steady-state
//! sinusoidal responses (the discrete transfer functions evaluated on the unit circle, and the
//! continuous one), ramp bias, and the continuous filter driven by a quantised ramp — the
//! evidence for the documented choice of Tustin as the default.

use num_complex::Complex64;
use pendulab_sim::{Differentiation, PseudoDifferentiator};
use std::f64::consts::PI;

const T: f64 = 0.02;
const TS: f64 = 1e-3;

fn filter(method: Differentiation) -> PseudoDifferentiator {
    PseudoDifferentiator::new(T, method, TS).unwrap()
}

#[test]
fn exact_zoh_step_response_is_the_sampled_continuous_one() {
    // A step of Δ at t = ts (held samples 0, Δ, Δ, …): the continuous filter driven by the
    // held signal answers (Δ/T) e^{−(t − ts)/T}; the ZOH equivalent reproduces it at the
    // samples (closed form of s/(Ts+1) for a step).
    let delta = 0.37;
    let p: Vec<f64> = (0..200).map(|k| if k >= 1 { delta } else { 0.0 }).collect();
    let v = filter(Differentiation::ExactZoh).filter(&p);
    assert_eq!(v[0], 0.0);
    for k in 1..200 {
        let t = k as f64 * TS;
        let want = delta / T * (-(t - TS) / T).exp();
        assert!((v[k] - want).abs() < 1e-12 * want.max(1.0), "k = {k}");
    }
}

/// Steady-state response of the recursion to p_k = sin(ω t_k), after 2 s (transients decay
/// like e^{−t/T} = e^{−100}): returns (amplitude, phase) by projecting one exact period.
fn steady_state(method: Differentiation, omega: f64) -> (f64, f64) {
    // ω chosen so that a whole number of samples spans a whole number of periods.
    let n_total = 3000usize;
    let p: Vec<f64> = (0..n_total)
        .map(|k| (omega * k as f64 * TS).sin())
        .collect();
    let v = filter(method).filter(&p);
    let window = 1000usize; // 1 s: an integer number of periods for the ω below
    let (mut s, mut c) = (0.0, 0.0);
    for k in n_total - window..n_total {
        let t = k as f64 * TS;
        s += v[k] * (omega * t).sin();
        c += v[k] * (omega * t).cos();
    }
    let (s, c) = (2.0 * s / window as f64, 2.0 * c / window as f64);
    ((s * s + c * c).sqrt(), c.atan2(s))
}

#[test]
fn discrete_frequency_responses_match_their_transfer_functions() {
    for hz in [1.0, 5.0, 20.0, 50.0] {
        let omega = 2.0 * PI * hz;
        let z = Complex64::from_polar(1.0, omega * TS);
        let a = (-TS / T).exp();
        // Closed forms of the three recursions' transfer functions.
        let h_zoh = (z - 1.0) / (z - a) / T;
        let h_tustin = 2.0 * (z - 1.0) / ((2.0 * T + TS) * z - (2.0 * T - TS));
        let h_be = (z - 1.0) / ((T + TS) * z - T);
        for (method, h) in [
            (Differentiation::ExactZoh, h_zoh),
            (Differentiation::Tustin, h_tustin),
            (Differentiation::BackwardEuler, h_be),
        ] {
            let (amp, ph) = steady_state(method, omega);
            // Projection over exact periods of a steady sinusoid: rounding only.
            assert!(
                (amp - h.norm()).abs() < 1e-9 * h.norm(),
                "{method:?} {hz} Hz"
            );
            assert!((ph - h.arg()).abs() < 1e-9, "{method:?} {hz} Hz");
        }
        // Against the continuous G(jω) = jω/(jωT + 1): Tustin is the bilinear map, exact at
        // the prewarped frequency (2/ts) tan(ω ts/2), so its relative error is O((ω ts)²);
        // the ZOH equivalent (samples taken just after each held step) overstates the gain
        // by (ts/T)/(1 − e^{−ts/T}) ≈ 1 + ts/(2T) at every frequency of the band.
        let g = |w: f64| Complex64::new(0.0, w) / Complex64::new(1.0, w * T);
        let wp = 2.0 / TS * (omega * TS / 2.0).tan();
        assert!((h_tustin - g(wp)).norm() < 1e-12 * g(wp).norm());
        let x = TS / T;
        let bias = x / (1.0 - (-x).exp());
        assert!(
            (h_zoh.norm() / g(omega).norm() - bias).abs() < 1e-5,
            "{hz} Hz"
        );
        let e_tustin = (h_tustin - g(omega)).norm() / g(omega).norm();
        let e_zoh = (h_zoh - g(omega)).norm() / g(omega).norm();
        // (ω ts)²/12 bounds Tustin's frequency warping; the ZOH error stays ≈ 2.5 %.
        assert!(e_tustin < (omega * TS).powi(2) / 6.0, "{hz} Hz: {e_tustin}");
        assert!(e_tustin < e_zoh / 10.0, "{hz} Hz: {e_tustin} vs {e_zoh}");
    }
}

#[test]
fn ramp_velocity_bias() {
    // A ramp p = c t has derivative c; the continuous filter settles at exactly c. The
    // recursions settle at β c ts / (1 − α): c for Tustin and backward Euler, and
    // c (ts/T)/(1 − e^{−ts/T}) ≈ 1.0252 c for the ZOH equivalent.
    let c = 0.3;
    let p: Vec<f64> = (0..2000).map(|k| c * k as f64 * TS).collect();
    let last = |m| *filter(m).filter(&p).last().unwrap();
    assert!((last(Differentiation::Tustin) - c).abs() < 1e-12);
    assert!((last(Differentiation::BackwardEuler) - c).abs() < 1e-12);
    let x = TS / T;
    assert!((last(Differentiation::ExactZoh) - c * x / (1.0 - (-x).exp())).abs() < 1e-12);
}

#[test]
fn tustin_matches_the_continuous_filter_on_a_quantised_ramp() {
    // The book's Simulink model: s/(Ts + 1) applied to the quantised (not yet sampled) encoder
    // signal. For a ramp p = c t quantised to the nearest level q, the level changes at
    // τ_j = (j − ½) q / c, and the continuous filter's output is exactly
    // v(t) = Σ_{τ_j ≤ t} (q/T) e^{−(t − τ_j)/T}. The discrete filters see the sampled
    // quantised signal. Over the second second (steady state), Tustin's mean error is ~0
    // and its RMS error below the ZOH equivalent's, whose mean is biased by ≈ +2.5 % c.
    let q = 4.8414e-5; // the cart encoder
    let c = 0.0137; // m/s: a level every 3.5 ms, at instants unrelated to the samples
    let n = 2000usize;
    let p: Vec<f64> = (0..n)
        .map(|k| q * (c * k as f64 * TS / q).round())
        .collect();
    let v_cont: Vec<f64> = (0..n)
        .map(|k| {
            let t = k as f64 * TS;
            let mut s = 0.0;
            let mut j = 1usize;
            loop {
                let tau = (j as f64 - 0.5) * q / c;
                if tau > t {
                    break;
                }
                s += q / T * (-(t - tau) / T).exp();
                j += 1;
            }
            s
        })
        .collect();
    let stats = |m: Differentiation| {
        let v = filter(m).filter(&p);
        let errs: Vec<f64> = (n / 2..n).map(|k| v[k] - v_cont[k]).collect();
        let mean = errs.iter().sum::<f64>() / errs.len() as f64;
        let rms = (errs.iter().map(|e| e * e).sum::<f64>() / errs.len() as f64).sqrt();
        (mean, rms)
    };
    let (m_t, r_t) = stats(Differentiation::Tustin);
    let (m_z, r_z) = stats(Differentiation::ExactZoh);
    // ZOH bias ≈ +2.5 % of c (the first-order average of e^{(t_k − τ)/T} − 1).
    assert!(
        (m_z / c - 0.025).abs() < 0.005,
        "ZOH mean error {m_z} ({})",
        m_z / c
    );
    // Tustin: unbiased to within 0.3 % of c (second-order terms and a finite window).
    assert!(m_t.abs() < 0.003 * c, "Tustin mean error {m_t}");
    assert!(r_t < r_z, "RMS: Tustin {r_t}, ZOH {r_z}");
}
