//! The browser lab's LMI design (`Method::Lmi`, solved by pendulab-lmi's dense interior-point
//! method as in the wasm build) against pendulab-lmi natively with Clarabel on the same LMIs,
//! against the Riccati (LQR) gain it approaches without a region, and its certificate through
//! the C ABI.

use pendulab_lmi::synthesis::{LqWeights, Region, StateFeedbackSpec, Vertex, state_feedback};
use pendulab_lmi::{Backend, SolveOptions};
use pendulab_lti::design::integral_augmentation;
use pendulab_lti::linalg::eigenvalues;
use pendulab_lti::{Mat, StateSpace};
use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::PlantSpec;
use pendulab_web::{Method, design, ffi};

/// The plant's `(A, B)` at the upright (`C = I`), augmented with `∫(r − q₀)` for 5 weights.
fn model(kind: PlantKind, n: usize) -> (Mat, Mat) {
    let sys = PlantSpec::book(kind)
        .parameters()
        .linearize_upright(0.0)
        .unwrap();
    if n == 4 {
        return (sys.a().clone(), sys.b().clone());
    }
    let c = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
    let on_q0 =
        StateSpace::continuous(sys.a().clone(), sys.b().clone(), c, Mat::zeros(1, 1)).unwrap();
    integral_augmentation(&on_q0).unwrap()
}

/// The same LMIs solved natively by Clarabel: the gain (library sign) and `tr X`.
fn clarabel_gain(kind: PlantKind, q: &[f64], r: f64, alpha: f64) -> (Vec<f64>, f64) {
    let (a, b) = model(kind, q.len());
    let spec = StateFeedbackSpec {
        lq: Some(LqWeights {
            q: Mat::from_diagonal(&nalgebra::DVector::from_row_slice(q)),
            r: Mat::from_element(1, 1, r),
        }),
        regions: if alpha > 0.0 {
            vec![Region::DecayRate { alpha }]
        } else {
            vec![]
        },
        ..StateFeedbackSpec::default()
    };
    let options = SolveOptions {
        backend: Backend::Clarabel,
        ..SolveOptions::default()
    };
    let d = state_feedback(&[Vertex { a, b }], &spec, &options).unwrap();
    assert_eq!(d.solution.backend, Backend::Clarabel);
    let f = d.feedback.expect("Clarabel solves the LMIs");
    (f.gain.iter().copied().collect(), f.x.trace())
}

fn rel(a: &[f64], b: &[f64]) -> f64 {
    let d: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt();
    d / b.iter().map(|y| y * y).sum::<f64>().sqrt()
}

/// The lab's LMI design and Clarabel's on the same LMIs: the same `tr X` (the optimum, to the
/// solvers' tolerance) and the same gain, the poles left of `−α` by `eig(A − BK)`.
fn agrees_with_clarabel(kind: PlantKind, q: &[f64], r: f64, alpha: f64) {
    let plant = PlantSpec::book(kind);
    let d = design(
        &plant,
        &Method::Lmi {
            q: q.to_vec(),
            r,
            alpha,
        },
    )
    .unwrap();
    let cert = d.lmi.clone().expect("an LMI design has a certificate");
    assert!(cert.status.is_solved(), "{:?}", cert.status);
    assert!(cert.min_slack > -1e-7, "{cert:?}");
    assert!(cert.poles_in_region);
    let (k, tr) = clarabel_gain(kind, q, r, alpha);
    assert!(
        (cert.trace_x - tr).abs() <= 1e-3 * tr,
        "tr X: dense {} vs Clarabel {tr}",
        cert.trace_x
    );
    assert!(
        rel(&d.gain, &k) < 1e-2,
        "gain: dense {:?} vs Clarabel {k:?}",
        d.gain
    );
    let (a, b) = model(kind, q.len());
    let kk = Mat::from_row_slice(1, q.len(), &d.gain);
    for p in eigenvalues(&(&a - &b * kk)).unwrap() {
        assert!(p.re < -alpha, "pole {p} not left of −{alpha}");
    }
    assert_eq!(d.poles.len(), q.len());
}

#[test]
fn cart_lmi_with_a_decay_rate_is_clarabels_design() {
    agrees_with_clarabel(PlantKind::Cart, &[10.0, 10.0, 0.0, 0.0], 1.0, 1.0);
}

#[test]
fn arm_lmi_with_a_decay_rate_is_clarabels_design() {
    agrees_with_clarabel(PlantKind::Arm, &[5.0, 10.0, 0.1, 0.1], 1.0, 2.0);
}

#[test]
fn cart_lmi_servo_is_clarabels_design() {
    agrees_with_clarabel(PlantKind::Cart, &[1.0, 5.0, 0.0, 0.0, 100.0], 1.0, 0.5);
}

#[test]
fn without_a_region_the_lmi_gain_is_the_riccati_gain() {
    // max tr X under the LQ cost LMI drives X⁻¹ to the Riccati solution (margin 1e-6).
    let plant = PlantSpec::book(PlantKind::Cart);
    let q = vec![10.0, 10.0, 0.0, 0.0];
    let lmi = design(
        &plant,
        &Method::Lmi {
            q: q.clone(),
            r: 1.0,
            alpha: 0.0,
        },
    )
    .unwrap();
    let lqr = design(&plant, &Method::Lqr { q, r: 1.0 }).unwrap();
    assert!(
        rel(&lmi.gain, &lqr.gain) < 1e-3,
        "{:?} vs {:?}",
        lmi.gain,
        lqr.gain
    );
}

#[test]
fn bad_lmi_inputs_are_refused_naming_them() {
    let plant = PlantSpec::book(PlantKind::Cart);
    let e = design(
        &plant,
        &Method::Lmi {
            q: vec![1.0; 4],
            r: 1.0,
            alpha: -1.0,
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("alpha"), "{e}");
    let e = design(
        &plant,
        &Method::Lmi {
            q: vec![1.0; 3],
            r: 1.0,
            alpha: 1.0,
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains('q'), "{e}");
}

#[test]
fn the_c_abi_returns_the_lmi_certificate() {
    assert_eq!(ffi::pl_init(0), 0);
    let io = unsafe { std::slice::from_raw_parts_mut(ffi::pl_io(), ffi::IO_LEN) };
    io[..4].copy_from_slice(&[10.0, 10.0, 0.0, 0.0]);
    io[5] = 4.0;
    io[6] = 1.0;
    assert_eq!(ffi::pl_design(3, 1.0), 0);
    let io = unsafe { std::slice::from_raw_parts(ffi::pl_io(), ffi::IO_LEN) };
    assert_eq!(io[ffi::DESIGN_N], 4.0);
    let c = &io[ffi::DESIGN_LMI..ffi::DESIGN_LMI + 6];
    assert!(c[0] == 1.0 || c[0] == 2.0, "{c:?}");
    assert!(c[1] > 0.0 && c[2] >= 2.0 && c[5] == 1.0, "{c:?}");
    let (k, _) = clarabel_gain(PlantKind::Cart, &[10.0, 10.0, 0.0, 0.0], 1.0, 1.0);
    assert!(rel(&io[..4], &k) < 1e-2);
    let text =
        unsafe { std::slice::from_raw_parts(ffi::pl_text_out(), ffi::pl_text_out_len() as usize) };
    let text = String::from_utf8_lossy(text);
    assert!(text.contains("dense interior-point"), "{text}");
    // The servo (5 weights) through the same entry point.
    let io = unsafe { std::slice::from_raw_parts_mut(ffi::pl_io(), ffi::IO_LEN) };
    io[..5].copy_from_slice(&[1.0, 5.0, 0.0, 0.0, 100.0]);
    io[5] = 5.0;
    io[6] = 0.5;
    assert_eq!(ffi::pl_design(3, 1.0), 0);
    let io = unsafe { std::slice::from_raw_parts(ffi::pl_io(), ffi::IO_LEN) };
    assert_eq!(io[ffi::DESIGN_N], 5.0);
}
