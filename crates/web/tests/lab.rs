//! The browser lab's Rust side, natively: designs against the book's printed gains and
//! SciPy's, the live loop against `pendulab_control::scenario::simulate`, balancing, the
//! exported controller file through the rig's own reader, and the C ABI.

use pendulab_control::scenario::simulate;
use pendulab_control::spec::build;
use pendulab_lti::Complex64;
use pendulab_plants::rig::{DriveFriction, PlantKind};
use pendulab_plants::spec::{PlantSpec, Provenance};
use pendulab_sim::scenario::{Imperfections, NoiseSpec, ScenarioSpec};
use pendulab_web::export::controller_file;
use pendulab_web::ffi;
use pendulab_web::{Design, Lab, Method, Mode, design};

fn lqr(kind: PlantKind, q: &[f64], r: f64) -> Design {
    design(&PlantSpec::book(kind), &Method::Lqr { q: q.to_vec(), r }).unwrap()
}

/// `|det(M − λ I)|` relative to `‖M‖^n`: zero (to rounding) exactly when `λ` is an eigenvalue.
fn eig_residual(m: &pendulab_lti::Mat, lambda: Complex64) -> f64 {
    let n = m.nrows();
    let c = nalgebra::DMatrix::<Complex64>::from_fn(n, n, |i, j| {
        Complex64::new(m[(i, j)], 0.0)
            - if i == j {
                lambda
            } else {
                Complex64::new(0.0, 0.0)
            }
    });
    c.determinant().norm() / m.norm().max(lambda.norm()).powi(n as i32)
}

fn closed_loop(d: &Design) -> pendulab_lti::Mat {
    let k = pendulab_lti::Mat::from_row_slice(1, 4, &d.gain[..4]);
    d.a() - d.b() * k
}

#[test]
fn cart_lqr_is_the_toolbox_gain() {
    // K = [3.16228, 13.47175, 4.48137, 2.26289] (IP Toolbox cdip_lqr_sim.m, Q = diag(10, 10,
    // 0, 0), R = 1; book convention u = +K x, 5 decimals): the library's K is −K.
    let d = lqr(PlantKind::Cart, &[10.0, 10.0, 0.0, 0.0], 1.0);
    for (g, w) in d.gain.iter().zip([3.16228, 13.47175, 4.48137, 2.26289]) {
        assert!((g + w).abs() <= 5e-6, "{:?}", d.gain);
    }
}

#[test]
fn arm_lqr_is_scipys_gain() {
    // adip_lqr_sim with q1 = 5 (Q = diag(5, 10, 0.1, 0.1), R = 1): SciPy's gain in the book's
    // convention, as pendulab-book's toolbox test reads it (relative 1e-8).
    let d = lqr(PlantKind::Arm, &[5.0, 10.0, 0.1, 0.1], 1.0);
    let want = [2.2360679775, 21.0210375251, 1.86621420556, 3.28297937648];
    for (g, w) in d.gain.iter().zip(want) {
        assert!((g + w).abs() <= 1e-8 * w.abs(), "{:?}", d.gain);
    }
}

#[test]
fn designs_use_the_closed_form_linearisation() {
    // testkit writes the cart's (A, B) out from docs/model.md §1 independently of the plant.
    let (a, b) = pendulab_testkit::cart::upright();
    let d = lqr(PlantKind::Cart, &[10.0, 10.0, 0.0, 0.0], 1.0);
    assert!((d.a() - &a).abs().max() < 1e-12 && (d.b() - &b).abs().max() < 1e-12);
}

#[test]
fn cart_servo_is_the_toolbox_gain() {
    // cdip_lqr_servo_sim (Q = diag(1, 5, 0, 0, 100), R = 1): K1 = [10.39942, 17.76307,
    // 6.79089, 3.04513] (5 decimals), K2 = −√(q_w/R) = −10, book convention.
    let d = design(
        &PlantSpec::book(PlantKind::Cart),
        &Method::Servo {
            q: vec![1.0, 5.0, 0.0, 0.0, 100.0],
            r: 1.0,
        },
    )
    .unwrap();
    for (g, w) in d
        .gain
        .iter()
        .zip([10.39942, 17.76307, 6.79089, 3.04513, -10.0])
    {
        assert!((g + w).abs() <= 5e-6, "{:?}", d.gain);
    }
    assert_eq!(d.poles.len(), 5);
}

#[test]
fn poles_are_eigenvalues_of_the_closed_loop() {
    let d = lqr(PlantKind::Arm, &[5.0, 10.0, 0.1, 0.1], 1.0);
    let acl = closed_loop(&d);
    for &p in &d.poles {
        assert!(p.re < 0.0);
        assert!(eig_residual(&acl, p) < 1e-10, "{p}");
    }
    for &p in d.open_loop() {
        assert!(eig_residual(d.a(), p) < 1e-10, "{p}");
    }
}

/// Slider walks as the page's arrow keys give them (a twentieth of a decade per move, up
/// then down, on every weight and on R): each move is designed from the last one
/// (`Designer::design_from`: the symmetric root locus from the last poles, else the warm
/// Riccati solve) and must be the design from scratch (the compact Riccati solver's sign
/// function path): the same gain to 1e-9 and the same poles, both rigs, LQR and servo.
#[test]
fn slider_moves_are_the_designs_from_scratch() {
    use pendulab_web::design::Designer;
    for kind in [PlantKind::Cart, PlantKind::Arm] {
        let designer = Designer::new(&PlantSpec::book(kind)).unwrap();
        for (servo, q0) in [
            (false, vec![10.0, 10.0, 0.0, 0.0]),
            (true, vec![1.0, 5.0, 0.0, 0.0, 100.0]),
        ] {
            let method = |q: &[f64], r: f64| {
                let q = q.to_vec();
                if servo {
                    Method::Servo { q, r }
                } else {
                    Method::Lqr { q, r }
                }
            };
            for slider in 0..=q0.len() {
                let (mut q, mut r) = (q0.clone(), 1.0);
                let mut last = designer.design(&method(&q, r)).unwrap();
                for mv in 0..40 {
                    let f = 10f64.powf(if mv < 20 { 0.05 } else { -0.05 });
                    match q.get_mut(slider) {
                        Some(v) if *v == 0.0 => *v = 0.1,
                        Some(v) => *v *= f,
                        None => r *= f,
                    }
                    let warm = designer.design_from(method(&q, r), Some(&last)).unwrap();
                    let cold = designer.design(&method(&q, r)).unwrap();
                    let what = format!("{kind:?} servo {servo}, slider {slider}, move {mv}");
                    let norm = |v: &[f64]| v.iter().map(|x| x.abs()).sum::<f64>();
                    let diff: Vec<f64> = warm
                        .gain
                        .iter()
                        .zip(&cold.gain)
                        .map(|(a, b)| a - b)
                        .collect();
                    assert!(
                        norm(&diff) <= 1e-9 * norm(&cold.gain),
                        "{what}: {:?} vs {:?}",
                        warm.gain,
                        cold.gain
                    );
                    let scale = cold.poles.iter().map(|p| p.norm()).fold(0.0, f64::max);
                    for (p, c) in warm.poles.iter().zip(&cold.poles) {
                        assert!(
                            (p - c).norm() <= 1e-9 * scale,
                            "{what}: {:?} vs {:?}",
                            warm.poles,
                            cold.poles
                        );
                    }
                    last = warm;
                }
            }
        }
    }
}

#[test]
fn placement_puts_the_poles_where_asked() {
    let want = vec![
        Complex64::new(-3.0, 2.0),
        Complex64::new(-3.0, -2.0),
        Complex64::new(-6.0, 0.0),
        Complex64::new(-7.0, 0.0),
    ];
    let plant = PlantSpec::book(PlantKind::Cart);
    let d = design(
        &plant,
        &Method::Place {
            poles: want.clone(),
        },
    )
    .unwrap();
    let acl = closed_loop(&d);
    for p in want {
        assert!(eig_residual(&acl, p) < 1e-9, "{p}");
    }
    // A pole without its conjugate is refused, not placed.
    let bad = Method::Place {
        poles: vec![
            Complex64::new(-3.0, 2.0),
            Complex64::new(-3.0, 0.0),
            Complex64::new(-6.0, 0.0),
            Complex64::new(-7.0, 0.0),
        ],
    };
    assert!(design(&plant, &bad).is_err());
}

#[test]
fn bad_weights_are_refused_naming_them() {
    let plant = PlantSpec::book(PlantKind::Cart);
    let e = design(
        &plant,
        &Method::Lqr {
            q: vec![1.0, -1.0, 0.0, 0.0],
            r: 1.0,
        },
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("q = -1"), "{e}");
    let e = design(
        &plant,
        &Method::Lqr {
            q: vec![1.0; 4],
            r: 0.0,
        },
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("r = 0"), "{e}");
    let e = design(
        &plant,
        &Method::Servo {
            q: vec![1.0; 4],
            r: 1.0,
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("expected 5"), "{e}");
}

/// The book's cart with a 0.1 V dead zone written into its rig part, so that
/// `scenario::simulate` can switch drive friction on too.
fn cart_with_friction() -> PlantSpec {
    let book = PlantSpec::book(PlantKind::Cart);
    let mut rig = *book.rig();
    rig.friction = Some(DriveFriction::DeadZone { width: 0.1 });
    PlantSpec::new(*book.parameters(), Provenance::Book {}, rig).unwrap()
}

#[test]
fn the_live_loop_is_the_simulate_path() {
    // Every effect on, 3 samples of delay: the lab's sample-by-sample loop against the one
    // simulate path on the same specs, over 3 s.
    let plant = cart_with_friction();
    let d = lqr(PlantKind::Cart, &[10.0, 10.0, 0.0, 0.0], 1.0);
    let mut imp = Imperfections::with_quantizer();
    imp.drive_friction = true;
    imp.delay_samples = 3;
    imp.noise = Some(NoiseSpec {
        std: vec![1e-4, 1e-3, 0.0, 0.0],
        seed: 7,
    });
    let x0 = [0.05, 5f64.to_radians(), 0.0, 0.0];
    let mut lab = Lab::new(plant.clone(), d.clone(), Mode::Balance, imp.clone(), &x0).unwrap();
    let mut rec = Vec::new();
    lab.advance(3001, 1, &mut rec).unwrap();

    let mut sc = ScenarioSpec::new(x0.to_vec(), 3.0);
    sc.imperfections = imp;
    let run = simulate(&plant, &d.controller(Mode::Balance, 0.0, 0.0), &sc).unwrap();
    assert_eq!(rec.len() / 6, run.t.len());
    for (k, row) in rec.chunks(6).enumerate() {
        assert!((row[0] - run.t[k]).abs() < 1e-12);
        for i in 0..4 {
            assert!(
                (row[1 + i] - run.x[k][i]).abs() <= 1e-12 * (1.0 + run.x[k][i].abs()),
                "k = {k}, i = {i}"
            );
        }
        assert!(
            (row[5] - run.u[k]).abs() <= 1e-12 * (1.0 + run.u[k].abs()),
            "u at k = {k}"
        );
    }
}

#[test]
fn the_cart_balances_ten_seconds_after_a_five_degree_poke() {
    let d = lqr(PlantKind::Cart, &[10.0, 10.0, 0.0, 0.0], 1.0);
    let plant = PlantSpec::book(PlantKind::Cart);
    let mut lab = Lab::new(
        plant,
        d,
        Mode::Balance,
        Imperfections::with_quantizer(),
        &[0.0; 4],
    )
    .unwrap();
    let mut rec = Vec::new();
    lab.advance(1000, 0, &mut rec).unwrap();
    lab.poke(0.0, 5f64.to_radians());
    lab.advance(10_000, 10, &mut rec).unwrap();
    let worst_z = rec.chunks(6).map(|r| r[1].abs()).fold(0.0, f64::max);
    let worst_theta = rec.chunks(6).map(|r| r[2].abs()).fold(0.0, f64::max);
    assert!(worst_z < 0.4, "left the travel: {worst_z} m");
    assert!(
        worst_theta <= 5.01f64.to_radians(),
        "fell further: {worst_theta}"
    );
    assert!(
        lab.angle().abs() < 0.2f64.to_radians(),
        "θ = {}",
        lab.angle()
    );
}

#[test]
fn swing_up_then_catch() {
    let d = lqr(PlantKind::Cart, &[10.0, 10.0, 0.0, 0.0], 1.0);
    let hanging = [0.0, std::f64::consts::PI + 0.001, 0.0, 0.0];
    let mut lab = Lab::new(
        PlantSpec::book(PlantKind::Cart),
        d,
        Mode::SwingUp,
        Imperfections::with_quantizer(),
        &hanging,
    )
    .unwrap();
    let mut rec = Vec::new();
    lab.advance(15_000, 0, &mut rec).unwrap();
    assert!(lab.angle().abs() < 1f64.to_radians(), "θ = {}", lab.angle());
}

#[test]
fn the_exported_file_is_a_rig_controller_file() {
    let d = lqr(PlantKind::Cart, &[10.0, 10.0, 0.0, 0.0], 1.0);
    let plant = PlantSpec::book(PlantKind::Cart);
    for (mode, r) in [
        (Mode::Balance, 0.0),
        (Mode::Balance, 0.1),
        (Mode::SwingUp, 0.0),
    ] {
        let spec = d.controller(mode, r, 0.0);
        let text = controller_file(&plant, &spec, "a test\nof two lines").unwrap();
        assert!(text.starts_with("# a test\n# of two lines\n"));
        assert!(text.contains("[controller.designed_for]"), "{text}");
        let loaded = pendulab_rig::config::load(&text).unwrap();
        assert_eq!(loaded.spec, spec);
        assert_eq!(loaded.ts, plant.rig().sample_time);
        // The file's controller answers a unit measurement of each state with −K.
        if mode == Mode::Balance && r == 0.0 {
            let mut built = build(&loaded.spec, PlantKind::Cart, loaded.ts).unwrap();
            for i in 0..4 {
                let mut y = [0.0; 4];
                y[i] = 1.0;
                let mut u = [0.0];
                built.controller.update(0.0, &y, &mut u);
                assert_eq!(u[0], -d.gain[i]);
            }
        }
    }
}

#[test]
fn the_c_abi_designs_runs_and_reports_errors() {
    assert_eq!(ffi::pl_init(0), 0);
    let io = ffi::pl_io();
    let q = [10.0, 10.0, 0.0, 0.0];
    // SAFETY: pl_io points at the module's IO_LEN f64s; nothing else touches them here.
    let buf = unsafe { std::slice::from_raw_parts_mut(io, ffi::IO_LEN) };
    buf[..4].copy_from_slice(&q);
    assert_eq!(ffi::pl_design(0, 1.0), 0);
    let d = lqr(PlantKind::Cart, &q, 1.0);
    // SAFETY: as above.
    let buf = unsafe { std::slice::from_raw_parts(ffi::pl_io(), ffi::IO_LEN) };
    // The module's design starts from the running design's gain (a warm start): the same
    // stabilising solution as the cold design, to rounding.
    for (got, want) in buf[..4].iter().zip(&d.gain) {
        assert!((got - want).abs() <= 1e-12 * want.abs(), "{got} vs {want}");
    }
    assert_eq!(buf[ffi::DESIGN_N], 4.0);
    assert_eq!(ffi::pl_reset(0.0, 0.05), 0);
    assert_eq!(ffi::pl_advance(100, 10), 10);
    // SAFETY: as above.
    let buf = unsafe { std::slice::from_raw_parts(ffi::pl_io(), ffi::IO_LEN) };
    assert!((buf[0] - 0.1).abs() < 1e-12);
    let n = ffi::pl_response(0, 0.05, 1.0, 10);
    assert_eq!(n, 101);
    assert!(ffi::pl_controller_toml() > 0);
    // A bad weight: −1 and the message in the text buffer.
    // SAFETY: as above.
    let buf = unsafe { std::slice::from_raw_parts_mut(ffi::pl_io(), ffi::IO_LEN) };
    buf[..4].copy_from_slice(&q);
    assert_eq!(ffi::pl_design(0, -1.0), -1);
    // SAFETY: pl_text_out points at pl_text_out_len bytes of UTF-8.
    let msg =
        unsafe { std::slice::from_raw_parts(ffi::pl_text_out(), ffi::pl_text_out_len() as usize) };
    assert_eq!(
        std::str::from_utf8(msg).unwrap(),
        "r = -1: must be finite and > 0"
    );
    assert_eq!(ffi::pl_effect(7, 1), -1);
    assert_eq!(ffi::pl_init(2), -1);
}

#[test]
fn a_lab_file_or_a_plant_file_is_read() {
    let plant = PlantSpec::book(PlantKind::Arm);
    let text = plant.to_toml().unwrap();
    assert_eq!(ffi::read_plant(&text).unwrap(), plant);
    let nested: String = text
        .lines()
        .map(|l| match (l.strip_prefix("[["), l.strip_prefix('[')) {
            (Some(rest), _) => format!("[[plant.{rest}\n"),
            (None, Some(rest)) => format!("[plant.{rest}\n"),
            _ => format!("{l}\n"),
        })
        .collect();
    let lab_file = format!("[plant]\n{nested}");
    assert_eq!(ffi::read_plant(&lab_file).unwrap(), plant);
    assert!(ffi::read_plant("kind = \"boat\"").is_err());
}
