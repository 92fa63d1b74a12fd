//! Observers: the book's output-feedback controller (p1c74_ex1) by the separation principle,
//! the minimal-order observer's error dynamics against their closed form, servo augmentation.

mod sys_support;

use pendulab_lti::design::{
    integral_augmentation, minimal_order_observer, observer_controller, place, place_observer,
};
use pendulab_lti::interconnect::{FeedbackSign, feedback};
use pendulab_lti::response::{LsimOptions, lsim};
use pendulab_lti::{Complex64, Mat, StateSpace};
use sys_support::{assert_same_poles, c, cdip, mat};

fn book_poles() -> Vec<Complex64> {
    vec![c(-6.5, 1.5), c(-6.5, -1.5), c(-4.0, 0.0), c(-2.5, 0.0)]
}

#[test]
fn p1c74_ex1_output_feedback_separation() {
    // y = [z, θ]; K places {−6.5 ± 1.5j, −4, −2.5}; the observer poles are 4× those. The
    // closed loop of plant and observer-based controller has exactly the union of both sets
    // (separation principle), a property independent of how K and L were computed.
    let (a, b) = cdip();
    let cm = mat(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let plant = StateSpace::continuous(a.clone(), b.clone(), cm.clone(), Mat::zeros(2, 1)).unwrap();
    let k = place(&a, &b, &book_poles()).unwrap().gain;
    let obs: Vec<Complex64> = book_poles().iter().map(|p| p * 4.0).collect();
    let l = place_observer(&a, &cm, &obs).unwrap().gain;
    let ctrl = observer_controller(&plant, &k, &l).unwrap();
    assert_eq!((ctrl.nu(), ctrl.ny(), ctrl.nx()), (2, 1, 4));
    // u = ctrl(y) is positive feedback of the controller's output into the plant input.
    let cl = feedback(&plant, &ctrl, FeedbackSign::Positive).unwrap();
    let mut want = book_poles();
    want.extend(obs);
    // Poles up to |26|, eigenvalue condition of the 8×8 loop moderate: 1e-8·26.
    assert_same_poles(&cl.poles().unwrap(), &want, 1e-8 * 26.0);
}

#[test]
fn minimal_order_observer_error_follows_its_closed_form() {
    // Cart pendulum with y = [z, θ] (p = 2), discretised by ZOH at 10 ms so that the
    // simulation is exact: a 2-state observer for the velocities with error poles {0.5, 0.6}.
    // From ζ[0] = 0 the error is x̂[k] − x[k] = −M₂ Fᵏ e₀, e₀ = w₀ − L ȳ₀ (w₀ = R x₀), a closed
    // form independent of the simulation.
    let (a, b) = cdip();
    let cm = mat(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let plant = StateSpace::continuous(a, b, cm, Mat::zeros(2, 1))
        .unwrap()
        .c2d(0.01, pendulab_lti::Discretization::Zoh)
        .unwrap();
    let poles = [c(0.5, 0.0), c(0.6, 0.0)];
    let ob = minimal_order_observer(&plant, &poles).unwrap();
    assert_same_poles(&ob.system.poles().unwrap(), &poles, 1e-12);
    let t: Vec<f64> = (0..100).map(|k| k as f64 * 0.01).collect();
    let u = Mat::from_fn(t.len(), 1, |k, _| (5.0 * t[k]).sin());
    let x0 = [0.02, 0.1, -0.3, 0.5];
    let tr = lsim(&plant, &u, &t, Some(&x0), &LsimOptions::default()).unwrap();
    // Observer input [u; y].
    let uy = Mat::from_fn(t.len(), 3, |k, j| {
        if j == 0 {
            u[(k, 0)]
        } else {
            tr.y()[(k, j - 1)]
        }
    });
    let est = lsim(&ob.system, &uy, &t, None, &LsimOptions::default()).unwrap();
    let tinv = ob.transformation.clone().try_inverse().unwrap();
    let m2 = tinv.columns(2, 2).clone_owned();
    let xbar0 = &ob.transformation * pendulab_lti::Vector::from_row_slice(&x0);
    let e0 = xbar0.rows(2, 2) - &ob.gain * xbar0.rows(0, 2);
    let f = ob.system.a().clone();
    let mut fk = Mat::identity(2, 2);
    for k in 0..t.len() {
        let e = &m2 * (&fk * &e0);
        for i in 0..4 {
            let err = est.y()[(k, i)] - tr.x()[(k, i)];
            // Both sides exact; only rounding on O(1) values: 1e-12.
            assert!(
                (err + e[i]).abs() < 1e-12,
                "k={k} i={i}: {err} vs {}",
                -e[i]
            );
        }
        fk = &f * fk;
    }
    // Continuous design: the error poles are placed as requested and the estimate converges.
    let (a, b) = cdip();
    let cm = mat(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let plant_c = StateSpace::continuous(a, b, cm, Mat::zeros(2, 1)).unwrap();
    let pc = [c(-20.0, 0.0), c(-25.0, 0.0)];
    let obc = minimal_order_observer(&plant_c, &pc).unwrap();
    assert_same_poles(&obc.system.poles().unwrap(), &pc, 1e-10 * 25.0);
    // Wrong pole count, rank-deficient C.
    assert!(minimal_order_observer(&plant_c, &pc[..1]).is_err());
    let (a, b) = cdip();
    let bad = StateSpace::continuous(
        a,
        b,
        mat(2, 4, &[1.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0]),
        Mat::zeros(2, 1),
    )
    .unwrap();
    assert!(minimal_order_observer(&bad, &pc).is_err());
}

#[test]
fn integral_augmentation_matches_the_book_form() {
    // Ã = [[A, 0], [−C, 0]], B̃ = [B; 0] (book eq. 6.40) for D = 0; discrete w[k+1] = w[k] − y.
    let (a, b) = cdip();
    let cm = mat(1, 4, &[1.0, 0.0, 0.0, 0.0]);
    let sys = StateSpace::continuous(a.clone(), b.clone(), cm.clone(), Mat::zeros(1, 1)).unwrap();
    let (aa, ba) = integral_augmentation(&sys).unwrap();
    assert_eq!(aa.view((0, 0), (4, 4)).clone_owned(), a);
    assert_eq!(aa.view((4, 0), (1, 4)).clone_owned(), -&cm);
    assert_eq!(aa.column(4).norm(), 0.0);
    assert_eq!(ba.view((0, 0), (4, 1)).clone_owned(), b);
    assert_eq!(ba[(4, 0)], 0.0);
    let ds = sys.c2d(0.01, pendulab_lti::Discretization::Zoh).unwrap();
    let (ad, _) = integral_augmentation(&ds).unwrap();
    assert_eq!(ad[(4, 4)], 1.0);
    // The augmented pair of the cart pendulum with y = z is controllable (no zero at s = 0).
    let aug = StateSpace::continuous(aa, ba, Mat::zeros(0, 5), Mat::zeros(0, 1)).unwrap();
    assert!(aug.is_controllable().unwrap());
}
