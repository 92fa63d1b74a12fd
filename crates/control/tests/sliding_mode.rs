//! The LQ-optimal sliding surface against SciPy (tools/reference/sliding_mode_reference.py),
//! the equivalent-control projection, coordinate invariance and the reaching law.

use pendulab_control::ControlError;
use pendulab_control::sliding_mode::{
    ReducedWeight, RegularForm, SlidingModeController, SlidingSurface, lq_sliding_surface,
};
use pendulab_lti::{Complex64, Mat};
use pendulab_testkit::cart;

fn q() -> Mat {
    Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[10.0, 100.0, 1.0, 1.0]))
}

/// The book script's surface (part 2 §3.2.3): the book's shear to regular form and its
/// weighting of the reduced problem.
fn book_surface(a: &Mat, b: &Mat) -> SlidingSurface {
    lq_sliding_surface(
        a,
        b,
        &q(),
        RegularForm::BookShear,
        ReducedWeight::BookScript,
    )
    .unwrap()
}

/// Numbers from the committed fixture (written by the reference script).
fn fixture(key: &str) -> Vec<f64> {
    let text = include_str!("fixtures/sliding_mode_reference.json");
    let start = text.find(&format!("\"{key}\"")).unwrap();
    let open = start + text[start..].find('[').unwrap();
    let close = open + text[open..].find(']').unwrap();
    text[open + 1..close]
        .split(',')
        .map(|s| s.trim().parse().unwrap())
        .collect()
}

#[test]
fn surfaces_match_scipy_for_both_weightings() {
    let (a, b) = cart::upright();
    for (weight, key, poles) in [
        (ReducedWeight::BookScript, "S_book", "poles_book"),
        (ReducedWeight::Exact, "S_exact", "poles_exact"),
    ] {
        let s = lq_sliding_surface(&a, &b, &q(), RegularForm::BookShear, weight).unwrap();
        let expect = fixture(key);
        for (x, y) in s.s.iter().zip(&expect) {
            // Two Riccati solvers (Schur + Newton here, SciPy's Schur there) on a
            // well-conditioned 3-state problem: 1e-9 relative.
            assert!((x - y).abs() <= 1e-9 * y.abs(), "{key}: {x} vs {y}");
        }
        assert!(s.residual < 1e-12);
        let re = fixture(&format!("{poles}_re"));
        let im = fixture(&format!("{poles}_im"));
        assert_eq!(s.sliding_poles.len(), 3);
        for (r, i) in re.iter().zip(&im) {
            let z = Complex64::new(*r, *i);
            let close = s
                .sliding_poles
                .iter()
                .map(|p| (p - z).norm())
                .fold(f64::MAX, f64::min);
            assert!(
                close < 1e-9 * z.norm(),
                "{key}: pole {z} missing from {:?}",
                s.sliding_poles
            );
        }
    }
}

#[test]
fn sliding_poles_are_those_of_the_equivalent_control_projection() {
    // On σ = 0 the equivalent control u_eq = −(Sᵀb)⁻¹SᵀAx keeps σ̇ = 0, so the sliding motion
    // is ẋ = (I − b(Sᵀb)⁻¹Sᵀ)Ax: its eigenvalues are 0 (the direction leaving the surface)
    // and the n − 1 poles of the reduced LQ closed loop — computed here without the regular
    // form at all.
    let (a, b) = cart::upright();
    for form in [RegularForm::BookShear, RegularForm::Orthogonal] {
        let s = lq_sliding_surface(&a, &b, &q(), form, ReducedWeight::Exact).unwrap();
        let st = Mat::from_row_slice(1, 4, &s.s);
        let proj = Mat::identity(4, 4) - &b * &st / s.s_transpose_b;
        let mut ev = pendulab_lti::linalg::eigenvalues(&(proj * &a)).unwrap();
        ev.sort_by(|x, y| x.norm().total_cmp(&y.norm()));
        assert!(ev[0].norm() < 1e-9, "{ev:?}");
        for p in &s.sliding_poles {
            let close = ev[1..]
                .iter()
                .map(|e| (e - p).norm())
                .fold(f64::MAX, f64::min);
            assert!(close < 1e-8 * p.norm(), "pole {p} not in {ev:?}");
            assert!(p.re < 0.0);
        }
    }
}

#[test]
fn the_exact_surface_does_not_depend_on_the_regular_form() {
    // The LQ-optimal sliding surface is a property of (A, b, Q): two different regular-form
    // transformations (the book's shear, an orthogonal reflection) must give the same
    // hyperplane, i.e. parallel normals.
    let (a, b) = cart::upright();
    let s1 = lq_sliding_surface(&a, &b, &q(), RegularForm::BookShear, ReducedWeight::Exact)
        .unwrap()
        .s;
    let s2 = lq_sliding_surface(&a, &b, &q(), RegularForm::Orthogonal, ReducedWeight::Exact)
        .unwrap()
        .s;
    let dot: f64 = s1.iter().zip(&s2).map(|(x, y)| x * y).sum();
    let n1 = s1.iter().map(|x| x * x).sum::<f64>().sqrt();
    let n2 = s2.iter().map(|x| x * x).sum::<f64>().sqrt();
    assert!((dot.abs() / (n1 * n2) - 1.0).abs() < 1e-12);
}

#[test]
fn the_book_weighting_is_exact_for_a_completed_weight() {
    // care(Ã₁₁, A₁₂, Q̄₁₁, Q̄₂₂) is the exact construction for Q' = Q + Tᵀ diag(Q̄₁₂Q̄₂₂⁻¹Q̄₁₂ᵀ, 0) T.
    let (a, b) = cart::upright();
    let book = book_surface(&a, &b);
    let t = &book.transformation;
    let ti = t.clone().try_inverse().unwrap();
    let qbar = ti.transpose() * q() * &ti;
    let q12 = qbar.view((0, 3), (3, 1)).clone_owned();
    let mut extra = Mat::zeros(4, 4);
    extra
        .view_mut((0, 0), (3, 3))
        .copy_from(&(&q12 * q12.transpose() / qbar[(3, 3)]));
    let q2 = q() + t.transpose() * extra * t;
    let exact =
        lq_sliding_surface(&a, &b, &q2, RegularForm::BookShear, ReducedWeight::Exact).unwrap();
    for (x, y) in book.s.iter().zip(&exact.s) {
        assert!((x - y).abs() < 1e-9 * y.abs().max(1.0));
    }
}

#[test]
fn the_law_imposes_the_reaching_dynamics_on_the_linear_model() {
    // σ̇ = Sᵀ(Ax + bu) = −K₂ σ/(|σ| + δ) for every state (identity of the law).
    let (a, b) = cart::upright();
    let s = book_surface(&a, &b);
    for delta in [0.0, 5.0] {
        let c = SlidingModeController::from_surface(&s, &a, &b, 30.0, delta).unwrap();
        for x in [[0.1, 0.2, -0.3, 0.5], [-0.05, 0.01, 0.2, -1.0], [0.0; 4]] {
            let u = c.control(&x);
            let xv = nalgebra::DVector::from_row_slice(&x);
            let dx = &a * &xv + &b * u;
            let sigma = c.switching_function(&x);
            let sdot: f64 = s.s.iter().zip(dx.iter()).map(|(p, q)| p * q).sum();
            let expect = if delta == 0.0 {
                -30.0 * sigma.signum() * (sigma != 0.0) as i32 as f64
            } else {
                -30.0 * sigma / (sigma.abs() + delta)
            };
            assert!((sdot - expect).abs() < 1e-10 * (1.0 + expect.abs()));
        }
    }
}

#[test]
fn bad_surfaces_and_laws_are_typed_errors() {
    let (a, b) = cart::upright();
    let mut b0 = b.clone();
    b0[(3, 0)] = 0.0;
    assert!(matches!(
        lq_sliding_surface(&a, &b0, &q(), RegularForm::BookShear, ReducedWeight::Exact),
        Err(ControlError::NotApplicable { .. })
    ));
    // The orthogonal form handles b_n = 0.
    assert!(
        lq_sliding_surface(&a, &b0, &q(), RegularForm::Orthogonal, ReducedWeight::Exact).is_ok()
    );
    assert!(matches!(
        lq_sliding_surface(
            &a,
            &Mat::zeros(4, 1),
            &q(),
            RegularForm::Orthogonal,
            ReducedWeight::Exact
        ),
        Err(ControlError::NotApplicable { .. })
    ));
    assert!(matches!(
        lq_sliding_surface(
            &a,
            &b,
            &Mat::zeros(3, 3),
            RegularForm::BookShear,
            ReducedWeight::Exact
        ),
        Err(ControlError::ShapeMismatch { .. })
    ));
    let s = [1.0, 0.0, 0.0, 0.0];
    assert!(matches!(
        SlidingModeController::new(&s, &a, &b, 30.0, 0.0),
        Err(ControlError::Singular { .. })
    ));
    assert!(matches!(
        SlidingModeController::new(&[1.0, 1.0, 1.0, 1.0], &a, &b, -1.0, 0.0),
        Err(ControlError::InvalidParameter { .. })
    ));
}
