//! LQR of the book's linearised cart pendulum (book table 3.5, `docs/model.md` §1) against the
//! gains the IP Toolbox samples display (`cdip_lqr_sim.m`, `cdip_lqr_servo_sim.m`). The book writes
//! u = +K x with K = −lqr(...); the library's gain is for u = −K x, so K_book = −K.

use pendulab_lti::Mat;
use pendulab_lti::equations::{RiccatiMethod, RiccatiOptions, care};
use pendulab_testkit::cart;

/// Norm-wise relative difference. The book prints 5 decimals (rounding error ≤ 5e-6 per
/// entry), which over gains of norm ≥ 14 is ≤ 1e-6 relative: the tolerance.
fn rel(k: &[f64], book: &[f64]) -> f64 {
    let num: f64 = k
        .iter()
        .zip(book)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt();
    let den: f64 = book.iter().map(|y| y * y).sum::<f64>().sqrt();
    num / den
}

#[test]
fn cdip_lqr_sim_gains() {
    let (a, b) = cart::upright();
    let book = [
        (10.0, [3.16228, 13.47175, 4.48137, 2.26289]),
        (50.0, [3.16228, 15.81695, 4.72006, 2.44448]),
        (100.0, [3.16228, 18.12126, 4.93879, 2.61065]),
    ];
    for method in [
        RiccatiMethod::Auto,
        RiccatiMethod::Schur,
        RiccatiMethod::Doubling,
    ] {
        let opts = RiccatiOptions {
            method,
            ..Default::default()
        };
        for (q2, kb) in book {
            let q = Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(&[
                10.0, q2, 0.0, 0.0,
            ]));
            let sol = care(&a, &b, &q, &Mat::identity(1, 1), None, &opts).unwrap();
            let k_book: Vec<f64> = sol.gain.iter().map(|v| -v).collect();
            let e = rel(&k_book, &kb);
            assert!(
                e <= 1e-6,
                "{method:?} q2={q2}: K_book = {k_book:?}, rel err {e:e}"
            );
            // Issue acceptance: residual ≤ 1e-12 on the book systems.
            assert!(
                sol.residual <= 1e-12,
                "{method:?} residual {:e}",
                sol.residual
            );
            assert!(sol.closed_loop_poles.iter().all(|p| p.re < 0.0));
            // Closed form: A e₁ = 0 (the cart position does not enter the dynamics), so
            // e₁ᵀ(AᵀX + XA − XBBᵀX + Q)e₁ = 0 gives (BᵀXe₁)² = q₁, i.e. |K₁| = √10.
            assert!((k_book[0] - 10f64.sqrt()).abs() <= 1e-9);
        }
    }
}

#[test]
fn cdip_lqr_servo_sim_gains() {
    let (a, b) = cart::upright();
    // Augmented plant Ã = [[A, 0], [−C, 0]], B̃ = [B; 0], C = [1, 0, 0, 0].
    let mut at = Mat::zeros(5, 5);
    at.view_mut((0, 0), (4, 4)).copy_from(&a);
    at[(4, 0)] = -1.0;
    let mut bt = Mat::zeros(5, 1);
    bt.view_mut((0, 0), (4, 1)).copy_from(&b);
    let q = Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(&[
        1.0, 5.0, 0.0, 0.0, 100.0,
    ]));
    let sol = care(
        &at,
        &bt,
        &q,
        &Mat::identity(1, 1),
        None,
        &RiccatiOptions::default(),
    )
    .unwrap();
    let k_book: Vec<f64> = sol.gain.iter().map(|v| -v).collect();
    let e = rel(&k_book, &[10.39942, 17.76307, 6.79089, 3.04513, -10.0]);
    assert!(e <= 1e-6, "K_book = {k_book:?}, rel err {e:e}");
    assert!(sol.residual <= 1e-12, "residual {:e}", sol.residual);
    // Closed form as above: Ã e₅ = 0, so |K₅| = √100 = 10.
    assert!((k_book[4] + 10.0).abs() <= 1e-9);
}
