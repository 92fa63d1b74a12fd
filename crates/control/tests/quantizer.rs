//! Optimal dynamic quantizers against closed forms (the lower bound |C A^{r−1} B| d/2, the
//! analytic quantizer's Markov parameters), an independent LP solve (SciPy/HiGHS, see
//! tools/reference/odq_reference.py) and the worst-case theorem in simulation.

use pendulab_control::ControlError;
use pendulab_control::quantizer::{
    DynamicQuantizer, InputQuantizer, OdqLpOptions, OdqMethod, Realization, feedback_error_system,
    odq_analytic, odq_lp, quantizer_cost, round_to_step,
};
use pendulab_lti::design::{StateFeedback, lqr};
use pendulab_lti::{Discretization, Mat, StateSpace};
use pendulab_testkit::cart;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// G(z) = (z − zero)/((z − 0.5)(z − 0.8)) in controllable canonical form, C B = 1.
fn siso(zero: f64) -> StateSpace<pendulab_lti::Discrete> {
    StateSpace::discrete(
        Mat::from_row_slice(2, 2, &[0.0, 1.0, -0.4, 1.3]),
        Mat::from_row_slice(2, 1, &[0.0, 1.0]),
        Mat::from_row_slice(1, 2, &[-zero, 1.0]),
        Mat::zeros(1, 1),
        0.01,
    )
    .unwrap()
}

#[test]
fn analytic_quantizer_attains_the_first_markov_parameter_bound() {
    let sys = siso(0.4);
    let d = 0.5;
    let q = odq_analytic(&sys, d).unwrap();
    assert_eq!(q.method, OdqMethod::Analytic { relative_degree: 1 });
    // Closed form: E = |CB| d/2 = 0.25, the smallest any quantizer can reach (the first
    // Markov parameter of G(I + H) is CB for every strictly proper H).
    assert!((q.design_cost - 0.25).abs() < 1e-15);
    // The realised quantizer's infinite-horizon cost, computed from its impulse response,
    // equals it: G(I + H) = CB z^{-1} exactly, up to rounding in the powers of A.
    assert!((q.cost.bound - 0.25).abs() < 1e-12, "{}", q.cost.bound);
    assert!(q.cost.converged);
    // The static quantizer's cost is the ℓ1 norm of g: strictly larger.
    assert!(q.static_cost.bound > 0.25 + 1e-3);
    // A + B C_f has the zero of G (0.4) and a pole at the origin as eigenvalues.
    let mut ev: Vec<f64> = pendulab_lti::linalg::eigenvalues(q.quantizer.filter().0)
        .unwrap()
        .iter()
        .map(|z| z.re)
        .collect();
    ev.sort_by(f64::total_cmp);
    assert!(ev[0].abs() < 1e-12 && (ev[1] - 0.4).abs() < 1e-12, "{ev:?}");
}

#[test]
fn lp_design_matches_the_analytic_one_where_both_apply() {
    let sys = siso(0.4);
    let d = 0.5;
    let analytic = odq_analytic(&sys, d).unwrap();
    let t = 40;
    let lp = odq_lp(
        &sys,
        d,
        &OdqLpOptions {
            horizon: t,
            ..Default::default()
        },
    )
    .unwrap();
    let OdqMethod::LinearProgram {
        optimum,
        checks_pass,
        ..
    } = lp.method
    else {
        panic!("not an LP design")
    };
    assert!(checks_pass);
    // The LP optimum is the lower bound |CB| = 1 (Clarabel stops at 1e-8 relative gap).
    assert!((optimum - 1.0).abs() < 1e-6, "LP optimum {optimum}");
    // The optimum is unique: g_e(2 … T) = 0 fixes the taps recursively (M_1 = 1 ≠ 0), so
    // they must be the analytic filter's Markov parameters C_f A_f^k B_f. The LP's taps
    // carry its 1e-8-level residuals, amplified along the recursion by at most Σ|M_k| ≈ 5.
    let expect = analytic.quantizer.markov_parameters(t - 1);
    let got = lp.quantizer.markov_parameters(t - 1);
    for (k, (a, b)) in expect.iter().zip(&got).enumerate() {
        assert!(
            (a[(0, 0)] - b[(0, 0)]).abs() < 1e-6,
            "tap {k}: analytic {}, LP {}",
            a[(0, 0)],
            b[(0, 0)]
        );
    }
    // The FIR realisation's infinite-horizon cost: beyond T the response is the analytic
    // one's tail, which is zero; so it equals the bound up to the taps' error.
    assert!((lp.cost.bound - 0.25).abs() < 1e-5, "{}", lp.cost.bound);
    // Ho–Kalman reduction to order 2 (the analytic filter's order) reproduces the same
    // quantizer up to the LP accuracy.
    let reduced = odq_lp(
        &sys,
        d,
        &OdqLpOptions {
            horizon: t,
            realization: Realization::Reduced { order: 2 },
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(reduced.quantizer.order(), 2);
    assert!((reduced.cost.bound - 0.25).abs() < 1e-5);
}

#[test]
fn non_minimum_phase_systems_need_the_lp() {
    let sys = siso(1.5);
    let d = 1.0;
    assert!(matches!(
        odq_analytic(&sys, d),
        Err(ControlError::NotApplicable { .. })
    ));
    // The static quantizer (taps = 0) is feasible, so its horizon-T cost bounds the optimum
    // from above; |CB| d/2 = 0.5 bounds every quantizer from below (closed form).
    let horizon_static = quantizer_cost(&sys, None, d, 60).unwrap().bound;
    // Without a bound on the filter gain the finite-horizon LP can approach the lower bound
    // by taps growing like 1.5^k (inverting the zero over the horizon), a solution no solver
    // tolerance distinguishes from nearby ones: only the bounds are checked.
    let free = odq_lp(
        &sys,
        d,
        &OdqLpOptions {
            horizon: 60,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        free.design_cost >= 0.5 * (1.0 - 1e-9),
        "{}",
        free.design_cost
    );
    assert!(free.design_cost <= horizon_static + 1e-7);
    // With the filter gain bounded (γ_wv = 3.35, the book's value) the taps cannot invert the
    // zero: the lower bound is out of reach, and the quantizer beats the static one.
    let lp = odq_lp(
        &sys,
        d,
        &OdqLpOptions {
            horizon: 60,
            max_filter_gain: Some(3.35),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(lp.design_cost > 0.5 + 1e-3, "{}", lp.design_cost);
    assert!(lp.design_cost <= horizon_static + 1e-7);
    assert!(lp.filter_gain <= 3.35 + 1e-6);
    assert!(lp.cost.bound < lp.static_cost.bound);
}

fn reference() -> serde_like::Json {
    serde_like::parse(include_str!("fixtures/odq_reference.json"))
}

/// A minimal JSON reader for the fixture (numbers, arrays, objects, strings).
mod serde_like {
    #[derive(Debug, Clone)]
    pub enum Json {
        Num(f64),
        Str(String),
        Arr(Vec<Json>),
        Obj(Vec<(String, Json)>),
    }
    impl Json {
        pub fn get(&self, k: &str) -> &Json {
            match self {
                Json::Obj(v) => &v.iter().find(|(n, _)| n == k).unwrap().1,
                _ => panic!("not an object"),
            }
        }
        pub fn num(&self) -> f64 {
            match self {
                Json::Num(x) => *x,
                _ => panic!("not a number"),
            }
        }
        pub fn arr(&self) -> Vec<f64> {
            match self {
                Json::Arr(v) => v.iter().map(|x| x.num()).collect(),
                _ => panic!("not an array"),
            }
        }
    }
    pub fn parse(s: &str) -> Json {
        let b = s.as_bytes();
        let mut i = 0;
        value(b, &mut i)
    }
    fn ws(b: &[u8], i: &mut usize) {
        while *i < b.len() && (b[*i] as char).is_whitespace() {
            *i += 1;
        }
    }
    fn value(b: &[u8], i: &mut usize) -> Json {
        ws(b, i);
        match b[*i] {
            b'{' => {
                *i += 1;
                let mut v = Vec::new();
                loop {
                    ws(b, i);
                    if b[*i] == b'}' {
                        *i += 1;
                        break;
                    }
                    let Json::Str(k) = value(b, i) else { panic!() };
                    ws(b, i);
                    *i += 1; // ':'
                    let x = value(b, i);
                    v.push((k, x));
                    ws(b, i);
                    if b[*i] == b',' {
                        *i += 1;
                    }
                }
                Json::Obj(v)
            }
            b'[' => {
                *i += 1;
                let mut v = Vec::new();
                loop {
                    ws(b, i);
                    if b[*i] == b']' {
                        *i += 1;
                        break;
                    }
                    v.push(value(b, i));
                    ws(b, i);
                    if b[*i] == b',' {
                        *i += 1;
                    }
                }
                Json::Arr(v)
            }
            b'"' => {
                *i += 1;
                let s = *i;
                while b[*i] != b'"' {
                    *i += 1;
                }
                *i += 1;
                Json::Str(String::from_utf8_lossy(&b[s..*i - 1]).into_owned())
            }
            _ => {
                let s = *i;
                while *i < b.len()
                    && !matches!(b[*i], b',' | b']' | b'}')
                    && !(b[*i] as char).is_whitespace()
                {
                    *i += 1;
                }
                Json::Num(std::str::from_utf8(&b[s..*i]).unwrap().parse().unwrap())
            }
        }
    }
}

/// The book's ODQ plant (p2c234_ex1_cdip_odq): the linearised cart pendulum (pendulab-testkit),
/// its LQR gain for Q = diag(10, 10, 0, 0), R = 1, and its ZOH discretisation at 10 ms.
fn cdip_lqr_zoh() -> (Mat, StateSpace<pendulab_lti::Discrete>) {
    let (a, b) = cart::upright();
    let sys = StateSpace::continuous(a, b, Mat::identity(4, 4), Mat::zeros(4, 1)).unwrap();
    let (q, r) = cart::lqr_weights();
    let k = lqr(&sys, &q, &r, None).unwrap().gain;
    (k, sys.c2d(0.01, Discretization::Zoh).unwrap())
}

/// The book's ODQ setting: the error system of [`cdip_lqr_zoh`] with outputs y = [z, θ], step
/// d = 2 V.
fn cdip_error_system() -> StateSpace<pendulab_lti::Discrete> {
    let (k, dsys) = cdip_lqr_zoh();
    let sf = StateFeedback::new(k).unwrap();
    feedback_error_system(&dsys, &sf, &cart::measured_output()).unwrap()
}

#[test]
fn cdip_lp_design_agrees_with_an_independent_lp_solve() {
    let r = reference();
    let sys = cdip_error_system();
    let d = r.get("step").num();
    // Static quantizer: an impulse-response sum computed independently in NumPy.
    let stat = quantizer_cost(&sys, None, d, 200_000).unwrap();
    for (a, b) in stat
        .per_output
        .iter()
        .zip(r.get("static_cost_per_output").arr())
    {
        // Same sums to convergence, only the summation order differs: 1e-10 relative.
        assert!((a - b).abs() <= 1e-10 * b, "static: {a} vs {b}");
    }
    for (gwv, key) in [
        (None, "lp_optimum_unconstrained"),
        (Some(r.get("gamma_wv").num()), "lp_optimum_gamma_wv_3_35"),
    ] {
        let design = odq_lp(
            &sys,
            d,
            &OdqLpOptions {
                horizon: r.get("horizon").num() as usize,
                max_filter_gain: gwv,
                ..Default::default()
            },
        )
        .unwrap();
        let OdqMethod::LinearProgram { optimum, .. } = design.method else {
            panic!()
        };
        let expect = r.get(key).num();
        // Two solvers on the same LP: their feasibility tolerances (HiGHS 1e-7, Clarabel
        // 1e-8 on the scaled data), summed over the ≈600 rows that enter the cost, allow
        // about 1e-5 relative.
        assert!(
            (optimum - expect).abs() <= 2e-5 * expect,
            "{key}: pendulab {optimum}, HiGHS {expect}"
        );
        // The cost recomputed from the returned taps is the LP's value (same tolerance).
        assert!((design.design_cost - expect * d / 2.0).abs() <= 2e-5 * expect * d / 2.0);
        if let Some(g) = gwv {
            assert!(
                design.filter_gain <= g * (1.0 + 1e-6),
                "{}",
                design.filter_gain
            );
        }
        // Far below the static quantizer's worst-case deviation (the LP could choose zero
        // taps): at least 50 times smaller for both outputs' maximum.
        assert!(design.design_cost * 50.0 < stat.bound);
    }
}

/// Simulates the linear closed loop x⁺ = A x + B v, u = −K x (as the error system's input
/// path) against the ideal x*⁺ = (A − BK)x*, returning max |y − y*| per output.
fn simulate_deviation(
    sys: &StateSpace<pendulab_lti::Discrete>,
    plant_b_k: (&Mat, &Mat, &Mat),
    quantizer: &mut InputQuantizer,
    x0: &[f64],
    steps: usize,
) -> Vec<f64> {
    let (ad, bd, k) = plant_b_k;
    let n = ad.nrows();
    let mut x = nalgebra::DVector::from_column_slice(x0);
    let mut xs = x.clone();
    let mut dev = vec![0.0f64; sys.ny()];
    let mut v = [0.0];
    for _ in 0..steps {
        let u = -(k * &x);
        quantizer.apply(u.as_slice(), &mut v);
        x = ad * &x + bd * v[0];
        xs = sys.a() * &xs;
        let dy = sys.c() * (&x - &xs);
        for i in 0..dev.len() {
            dev[i] = dev[i].max(dy[i].abs());
        }
    }
    let _ = n;
    dev
}

#[test]
fn simulated_deviation_respects_the_worst_case_bound_and_beats_the_static_quantizer() {
    // Same plant and gain as the cdip design, simulated linearly: the theorem says
    // |y_i − y*_i| ≤ E_i for every run, whatever the rounding errors turn out to be.
    let (k, dsys) = cdip_lqr_zoh();
    let err = cdip_error_system();
    let d = 2.0;
    let design = odq_lp(
        &err,
        d,
        &OdqLpOptions {
            max_filter_gain: Some(3.35),
            ..Default::default()
        },
    )
    .unwrap();
    let x0 = [0.0, 10f64.to_radians(), 0.0, 0.0];
    let mut dynamic = InputQuantizer::from(design.quantizer.clone());
    let mut stat = InputQuantizer::Static { step: d };
    let dev_dyn = simulate_deviation(&err, (dsys.a(), dsys.b(), &k), &mut dynamic, &x0, 500);
    let dev_stat = simulate_deviation(&err, (dsys.a(), dsys.b(), &k), &mut stat, &x0, 500);
    for i in 0..2 {
        assert!(dev_dyn[i] <= design.cost.per_output[i] * (1.0 + 1e-9));
        assert!(dev_stat[i] <= design.static_cost.per_output[i] * (1.0 + 1e-9));
    }
    // The dynamic quantizer's deviation is a small fraction of the static one's in this run
    // (its worst case is ≈ 100 times smaller; demand a factor of 5 on an actual run).
    for i in 0..2 {
        assert!(
            dev_dyn[i] * 5.0 < dev_stat[i],
            "output {i}: dynamic {}, static {}",
            dev_dyn[i],
            dev_stat[i]
        );
    }
}

#[test]
fn quantizer_outputs_lie_on_the_grid_with_bounded_rounding_error() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let d = 0.3;
    let taps = vec![Mat::from_element(1, 1, -1.2), Mat::from_element(1, 1, 0.4)];
    let mut q = DynamicQuantizer::fir(&taps, 1, d).unwrap();
    let mut past = [0.0f64; 2];
    for _ in 0..1000 {
        let u: f64 = rng.random_range(-5.0..5.0);
        let mut v = [0.0];
        q.quantize(&[u], &mut v);
        let k = v[0] / d;
        assert!((k - k.round()).abs() < 1e-9, "v = {} not on the grid", v[0]);
        // v − u = w + H₀ w(t−1) + H₁ w(t−2) with |w| ≤ d/2: recover w and check it.
        let s = u - 1.2 * past[0] + 0.4 * past[1];
        let w = v[0] - s;
        assert!(w.abs() <= d / 2.0 + 1e-12);
        assert_eq!(v[0], round_to_step(s, d));
        past = [w, past[0]];
    }
}

#[test]
fn bad_quantizer_inputs_are_typed_errors() {
    let sys = siso(0.4);
    assert!(matches!(
        odq_analytic(&sys, 0.0),
        Err(ControlError::InvalidParameter { .. })
    ));
    assert!(matches!(
        odq_lp(
            &sys,
            1.0,
            &OdqLpOptions {
                horizon: 1,
                ..Default::default()
            }
        ),
        Err(ControlError::InvalidParameter { .. })
    ));
    assert!(matches!(
        odq_lp(
            &sys,
            1.0,
            &OdqLpOptions {
                max_filter_gain: Some(0.5),
                ..Default::default()
            }
        ),
        Err(ControlError::InvalidParameter { .. })
    ));
    let with_d = StateSpace::discrete(
        sys.a().clone(),
        sys.b().clone(),
        sys.c().clone(),
        Mat::from_element(1, 1, 1.0),
        0.01,
    )
    .unwrap();
    assert!(matches!(
        odq_lp(&with_d, 1.0, &OdqLpOptions::default()),
        Err(ControlError::NotApplicable { .. })
    ));
    assert!(matches!(
        DynamicQuantizer::new(Mat::zeros(2, 2), Mat::zeros(3, 1), Mat::zeros(1, 2), 1.0),
        Err(ControlError::ShapeMismatch { .. })
    ));
    assert!(matches!(
        DynamicQuantizer::static_quantizer(1, f64::NAN),
        Err(ControlError::InvalidParameter { .. })
    ));
}

#[test]
fn two_input_lp_design_matches_the_analytic_one() {
    // Block-diagonal system of two minimum-phase channels with C B = diag(1, 2): the closed
    // form gives E = (d/2)·max(1, 2), and the LP over the 2×2 taps must reach it.
    let g1 = siso(0.4);
    let g2 = siso(0.2);
    let mut a = Mat::zeros(4, 4);
    a.view_mut((0, 0), (2, 2)).copy_from(g1.a());
    a.view_mut((2, 2), (2, 2)).copy_from(g2.a());
    let mut b = Mat::zeros(4, 2);
    b.view_mut((0, 0), (2, 1)).copy_from(g1.b());
    b.view_mut((2, 1), (2, 1)).copy_from(&(g2.b() * 2.0));
    let mut c = Mat::zeros(2, 4);
    c.view_mut((0, 0), (1, 2)).copy_from(g1.c());
    c.view_mut((1, 2), (1, 2)).copy_from(g2.c());
    let sys = StateSpace::discrete(a, b, c, Mat::zeros(2, 2), 0.01).unwrap();
    let d = 0.5;
    let analytic = odq_analytic(&sys, d).unwrap();
    assert!((analytic.design_cost - 0.5).abs() < 1e-15);
    assert!((analytic.cost.bound - 0.5).abs() < 1e-12);
    let t = 30;
    let lp = odq_lp(
        &sys,
        d,
        &OdqLpOptions {
            horizon: t,
            ..Default::default()
        },
    )
    .unwrap();
    // The LP minimises the worse output only; the better one (C B = 1) need not reach its own
    // bound, so compare the optimum and the worse output's taps.
    assert!((lp.design_cost - 0.5).abs() < 1e-6, "{}", lp.design_cost);
    assert!(lp.cost.per_output[1] <= 0.5 + 1e-5);
    let expect = analytic.quantizer.markov_parameters(t - 1);
    let got = lp.quantizer.markov_parameters(t - 1);
    for (k, (e, g)) in expect.iter().zip(&got).enumerate() {
        assert!((e[(1, 1)] - g[(1, 1)]).abs() < 1e-6, "tap {k}");
        assert!(
            g[(1, 0)].abs() < 1e-6,
            "tap {k}: cross-coupling into the worse channel"
        );
    }
}
