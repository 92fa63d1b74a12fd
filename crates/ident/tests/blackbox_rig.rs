//! Black-box identification of the cart drive from the real rig's P-control records
//! (`data/rig/cdip_cart_pcont_data_kP_*_ref_02.csv`), compared with the book's physical model
//! `z̈ = −a_c ż + b_c v` (part 1 §3.2, table 3.5: a_c = 6.25 1/s, b_c = 4.36 m/(s² V)).
//!
//! The records log the cart position z only; the voltage is the P law the rig ran,
//! `v = k_P (r − z)` with `r` stepping from 0 to 0.2 m at t = 1 s (`data/rig/README.md`; the
//! logged `v` of `cdip_least_square_data.csv`, k_P = 10, is exactly that law). Under one static
//! gain `v` is an affine function of `z` except where `r` steps, so a single record barely
//! separates the plant from the controller; the records under k_P = 2.5, 5 and 20 together do. The k_P = 10 record with its
//! logged voltage validates the models (open-loop simulation, MATLAB `compare` fit).

use pendulab_ident::*;
use pendulab_lti::Discretization;

const AC: f64 = 6.25;
const BC: f64 = 4.36;

fn p_record(name: &str, text: &str, kp: f64) -> (Vec<f64>, Vec<f64>) {
    let d = Dataset::from_csv_str(name, text)
        .unwrap()
        .window(Some(0.5), Some(4.0))
        .unwrap();
    assert!((d.sample_time().unwrap() - 1e-3).abs() < 1e-12);
    let (t, z) = (d.time().unwrap(), d.column("z").unwrap());
    let v = t
        .iter()
        .zip(z)
        .map(|(t, z)| kp * (if *t >= 1.0 - 1e-9 { 0.2 } else { 0.0 } - z))
        .collect();
    (v, z.to_vec())
}

fn estimation_records() -> Vec<(Vec<f64>, Vec<f64>)> {
    vec![
        p_record(
            "kP_025",
            include_str!("../../../data/rig/cdip_cart_pcont_data_kP_025_ref_02.csv"),
            2.5,
        ),
        p_record(
            "kP_050",
            include_str!("../../../data/rig/cdip_cart_pcont_data_kP_050_ref_02.csv"),
            5.0,
        ),
        p_record(
            "kP_200",
            include_str!("../../../data/rig/cdip_cart_pcont_data_kP_200_ref_02.csv"),
            20.0,
        ),
    ]
}

/// The k_P = 10 record with its logged voltage.
fn validation_record() -> (Vec<f64>, Vec<f64>) {
    let d = Dataset::from_csv_str(
        "cdip_least_square_data.csv",
        include_str!("../../../data/rig/cdip_least_square_data.csv"),
    )
    .unwrap()
    .window(Some(0.5), Some(4.0))
    .unwrap();
    let (t, z, v) = (
        d.time().unwrap(),
        d.column("z").unwrap(),
        d.column("v").unwrap(),
    );
    // The logged voltage is the P law the estimation records' voltage is rebuilt from.
    for ((t, z), v) in t.iter().zip(z).zip(v) {
        let r = if *t >= 1.0 - 1e-9 { 0.2 } else { 0.0 };
        assert!((v - 10.0 * (r - z)).abs() < 1e-9);
    }
    (v.to_vec(), z.to_vec())
}

/// Continuous poles of a discrete model by `d2c` (ZOH, the rig's D/A), sorted by real part.
fn continuous_poles(sys: &pendulab_lti::StateSpace<pendulab_lti::Discrete>) -> Vec<f64> {
    let c = sys.d2c(Discretization::Zoh).unwrap();
    let mut p: Vec<f64> = pendulab_lti::linalg::eigenvalues(c.a())
        .unwrap()
        .iter()
        .map(|z| {
            assert!(z.im.abs() < 1e-9, "complex pole {z}");
            z.re
        })
        .collect();
    p.sort_by(f64::total_cmp);
    p
}

/// The constant term of the numerator of the continuous transfer function: `b_c` for
/// `G(s) = b_c/(s (s + a_c))`.
fn numerator_constant(sys: &pendulab_lti::StateSpace<pendulab_lti::Discrete>) -> f64 {
    let c = sys.d2c(Discretization::Zoh).unwrap();
    let tf = pendulab_lti::TransferFunction::from_state_space(&c).unwrap();
    *tf.num().coefficients().last().unwrap()
}

/// Every `q`-th sample (the records are smooth at 1 kHz: the cart's time constant is 160 ms).
fn decimate(x: &[f64], q: usize) -> Vec<f64> {
    x.iter().step_by(q).copied().collect()
}

/// Checks an identified drive against table 3.5 and the validation record: a pole near the
/// integrator, the other within `tol_a` of −a_c, the numerator within `tol_b` of b_c. The
/// tolerances allow for what the linear model leaves out (the drive's Coulomb friction and
/// dead zone, the encoder step 4.8e-5 m, closed-loop data) and are wider than the book's own
/// least squares on the voltage-logged record (1 %, `rig_data.rs`).
fn check_drive(what: &str, poles: &[f64], b: f64, fit: f64) {
    println!("{what}: continuous poles {poles:?}, b = {b:.4}, validation fit {fit:.2} %");
    assert_eq!(poles.len(), 2);
    assert!(
        poles[1].abs() < 0.1 * AC,
        "{what}: integrator pole {}",
        poles[1]
    );
    assert!(
        (-poles[0] / AC - 1.0).abs() < 0.15,
        "{what}: pole {} vs -a_c",
        poles[0]
    );
    assert!((b / BC - 1.0).abs() < 0.2, "{what}: b {b} vs b_c");
    assert!(fit > 80.0, "{what}: fit {fit} %");
}

#[test]
fn arx_of_the_cart_drive_matches_table_3_5() {
    // ARX [2 2 1] at 10 ms: at the logging rate of 1 ms the equation error is dominated by the
    // encoder step and the fit is poor, the classic high-sampling-rate bias of ARX
    // (Ljung 1999 §13.7); decimated, the model is the book's second-order drive.
    let q = 10;
    let recs: Vec<(Vec<f64>, Vec<f64>)> = estimation_records()
        .iter()
        .map(|(v, z)| (decimate(v, q), decimate(z, q)))
        .collect();
    let ex: Vec<Experiment<'_>> = recs.iter().map(|(v, z)| Experiment::new(v, z)).collect();
    let m = arx(&ex, 1e-3 * q as f64, ArxOrders::new(2, 2, 1)).unwrap();
    let (vv, zv) = validation_record();
    let fit = m.fit_percent(&decimate(&vv, q), &decimate(&zv, q)).unwrap();
    let ss = m.state_space().unwrap();
    check_drive(
        "ARX [2 2 1], 10 ms",
        &continuous_poles(&ss),
        numerator_constant(&ss),
        fit,
    );
}

#[test]
fn moesp_of_the_cart_drive_matches_table_3_5() {
    // PO-MOESP on the 1 ms records, horizon 20, the physical order 2 (the largest gap of the
    // singular values is after the first: the integrator dominates the response).
    let recs = estimation_records();
    let io: Vec<IoRecord<'_>> = recs.iter().map(|(v, z)| IoRecord::siso(v, z)).collect();
    let s = moesp(
        &io,
        1e-3,
        MoespOptions {
            horizon: 20,
            order: Some(2),
            max_order: None,
        },
    )
    .unwrap();
    let sv = &s.singular_values;
    println!("MOESP singular values {:?}", &sv[..4]);
    assert!(sv[1] > 50.0 * sv[2], "{sv:?}");
    let (vv, zv) = validation_record();
    let fit = s.fit_percent(&IoRecord::siso(&vv, &zv)).unwrap()[0];
    check_drive(
        "MOESP n = 2, 1 ms",
        &continuous_poles(&s.model),
        numerator_constant(&s.model),
        fit,
    );
}

#[test]
fn arx_of_the_cart_drive_matches_numpy() {
    // tools/reference/blackbox_reference.py: the same regression by NumPy's SVD least squares,
    // the continuous poles as log(z)/Ts of numpy.roots (independent of QR and of d2c).
    let r: serde_json::Value =
        serde_json::from_str(include_str!("data/blackbox_reference.json")).unwrap();
    let q = r["decimation"].as_u64().unwrap() as usize;
    let recs: Vec<(Vec<f64>, Vec<f64>)> = estimation_records()
        .iter()
        .map(|(v, z)| (decimate(v, q), decimate(z, q)))
        .collect();
    let ex: Vec<Experiment<'_>> = recs.iter().map(|(v, z)| Experiment::new(v, z)).collect();
    let m = arx(&ex, r["ts"].as_f64().unwrap(), ArxOrders::new(2, 2, 1)).unwrap();
    assert_eq!(m.lsq.samples as u64, r["samples"].as_u64().unwrap());
    let num = |key: &str| -> Vec<f64> {
        r[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect()
    };
    for (e, t) in m.a.iter().zip(num("a")) {
        assert!((e - t).abs() < 1e-9, "a: {e} vs {t}");
    }
    for (e, t) in m.b.iter().zip(num("b")) {
        assert!((e - t).abs() < 1e-7 * t.abs(), "b: {e} vs {t}");
    }
    let poles = continuous_poles(&m.state_space().unwrap());
    for (e, t) in poles.iter().zip(num("continuous_poles")) {
        assert!((e - t).abs() < 1e-7, "pole: {e} vs {t}");
    }
}
