use super::*;
use crate::controllers::StaticStateFeedback;

/// `ẋ = [c·x₀², 0]`: constant for `c = 0`, escaping to infinity for `c > 0`.
#[derive(Clone)]
struct Escape(f64);

impl Dynamics for Escape {
    fn nx(&self) -> usize {
        2
    }
    fn nu(&self) -> usize {
        1
    }
    fn derivative(&self, _t: f64, x: &[f64], _u: &[f64], dx: &mut [f64]) {
        dx[0] = self.0 * x[0] * x[0];
        dx[1] = 0.0;
    }
}

impl FixedDynamics<2> for Escape {
    fn derivative_fixed(&self, x: &[f64; 2], _u: f64) -> [f64; 2] {
        [self.0 * x[0] * x[0], 0.0]
    }
}

/// `u = 0` whatever the state, without
/// [`FixedController::NON_FINITE_STATE_GIVES_NON_FINITE_COMMAND`]: the loop checks the
/// state after each step itself.
#[derive(Clone)]
struct Zero;

impl Controller for Zero {
    fn ny(&self) -> usize {
        2
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {}
    fn update(&mut self, _t: f64, _y: &[f64], u: &mut [f64]) {
        u[0] = 0.0;
    }
}

impl FixedController<2> for Zero {
    fn command(&mut self, _t: f64, _x: &[f64; 2]) -> f64 {
        0.0
    }
}

fn loops<C: Controller + FixedController<2> + Clone>(
    c: f64,
    controller: C,
) -> (SampledLoop<Escape, C>, FixedLoop<Escape, C, 2>) {
    let opts = SampledOptions {
        ts: 0.01,
        t_final: 0.5,
        ..Default::default()
    };
    let general = SampledLoop::new(Escape(c), controller, opts).expect("valid loop");
    let fixed = general.fixed::<2>().expect("covered by the kernel");
    (general, fixed)
}

/// The zero gain: its command is NaN for a non-finite state (`0·∞`), so the loop checks
/// the state through the command.
fn zero_gain() -> StaticStateFeedback {
    StaticStateFeedback::new(Mat::zeros(1, 2)).expect("finite gain")
}

/// Entries finite but their sum not (2·10³⁰⁸ overflows): the run goes on (with `Zero`,
/// every sample leaves the sample loop for the entry-by-entry check, which lets it); the
/// run is the general loop's, bit for bit, on either multiply–add path.
#[test]
fn an_overflowing_sum_of_finite_entries_resumes_the_run() {
    fn check<C: Controller + FixedController<2> + Clone>(controller: C) {
        let (mut general, fixed) = loops(0.0, controller);
        let x0 = [1e308, 1e308];
        let expected = general.run(&x0).expect("finite entries");
        assert_eq!(expected.diagnostics.samples, 51);
        for path in [MulAddPath::Fused, MulAddPath::Separate] {
            let mut fixed = fixed.clone().with_multiply_add(path);
            assert_eq!(
                fixed.run(&x0).expect("finite entries"),
                expected,
                "{path:?}"
            );
        }
    }
    check(zero_gain());
    check(Zero);
}

/// A state escaping to infinity ends the run with the general loop's error (same time,
/// entry and value), whether the loop checks it through the command (the zero gain) or
/// after each step (`Zero`).
#[test]
fn a_non_finite_state_ends_the_run_with_the_general_loops_error() {
    fn check<C: Controller + FixedController<2> + Clone>(controller: C) {
        let (mut general, fixed) = loops(1.0, controller);
        let x0 = [1e100, 0.0];
        let expected = general.run(&x0).expect_err("escapes");
        assert!(
            matches!(expected, SimError::NonFiniteState { index: 0, .. }),
            "{expected:?}"
        );
        for path in [MulAddPath::Fused, MulAddPath::Separate] {
            let mut fixed = fixed.clone().with_multiply_add(path);
            assert_eq!(fixed.run(&x0).expect_err("escapes"), expected, "{path:?}");
        }
    }
    check(zero_gain());
    check(Zero);
}
