//! The closed forms against the eigenvalues `docs/model.md` prints (§1 for the cart, §2 for the
//! arm), computed two ways: nalgebra's Schur decomposition of the written-out `A`, and the
//! roots of the characteristic polynomial. `A` is block triangular, so its eigenvalues are `0`,
//! the drive pole `−a` and the roots of the pendulum block `s² + k_d s − k_a` (`k_a` the gravity
//! stiffness, `k_d` the joint's damping), `(−k_d ± √(k_d² + 4 k_a))/2`.

use pendulab_testkit::Mat;
use pendulab_testkit::arm::ArmParams;
use pendulab_testkit::cart::{self, CartParams, Rest};

/// Real parts of the eigenvalues of `a` (Schur, nalgebra), ascending; asserts they are real.
fn real_eigenvalues(a: &Mat) -> Vec<f64> {
    let mut ev: Vec<f64> = a
        .complex_eigenvalues()
        .iter()
        .map(|l| {
            assert!(l.im.abs() < 1e-12, "{l}");
            l.re
        })
        .collect();
    ev.sort_by(f64::total_cmp);
    ev
}

/// `0`, `−a` and the pendulum block's roots, ascending.
fn block_roots(drive_pole: f64, k_angle: f64, k_damping: f64) -> Vec<f64> {
    let disc = (k_damping * k_damping + 4.0 * k_angle).sqrt();
    let mut ev = vec![
        0.0,
        -drive_pole,
        (-k_damping + disc) / 2.0,
        (-k_damping - disc) / 2.0,
    ];
    ev.sort_by(f64::total_cmp);
    ev
}

#[test]
fn cart_upright_eigenvalues_are_the_printed_ones() {
    let (a, b) = cart::upright();
    let p = CartParams::book();
    let j = p.inertia();
    let schur = real_eigenvalues(&a);
    let roots = block_roots(p.a_c, p.m_p * p.g * p.l_p / j, p.mu_p / j);
    // docs/model.md §1, printed to 4 decimals: half a unit of the last digit.
    for ((s, r), printed) in schur.iter().zip(&roots).zip([-6.25, -5.7867, 0.0, 5.7543]) {
        assert!((s - printed).abs() <= 5e-5, "{schur:?}");
        // Two routes to the same well-separated eigenvalues of a 4×4 matrix of norm ≈ 30.
        assert!((s - r).abs() <= 1e-12, "{schur:?} vs {roots:?}");
    }
    // The input enters the drive with b_c and the pendulum with −b_c m_p l_p / J.
    assert_eq!(b[(2, 0)], 4.36);
    assert!((b[(3, 0)] + 4.36 * 0.107 * 0.230 / 7.2503e-3).abs() <= 1e-4 * b[(3, 0)].abs());
}

#[test]
fn cart_hanging_rest_flips_the_pendulum_terms() {
    // docs/model.md §1: cos θ = −1 flips the signs of the m_p l_p terms and of m_p g l_p / J;
    // the friction and the drive stay.
    let p = CartParams::book();
    let (up_a, up_b) = p.linearization(Rest::Upright);
    let (a, b) = p.linearization(Rest::Hanging);
    for (i, j) in [(3, 1), (3, 2)] {
        assert_eq!(a[(i, j)], -up_a[(i, j)]);
    }
    assert_eq!(b[(3, 0)], -up_b[(3, 0)]);
    assert_eq!(
        (a[(2, 2)], a[(3, 3)], b[(2, 0)]),
        (up_a[(2, 2)], up_a[(3, 3)], up_b[(2, 0)])
    );
    // Hanging, the pendulum block is a lightly damped oscillator: complex roots of
    // s² + (μ_p/J) s + m_p g l_p/J with |s| = ω_np = 5.7705 rad/s (docs/model.md §1).
    let ev = a.complex_eigenvalues();
    let osc: Vec<_> = ev.iter().filter(|l| l.im.abs() > 1.0).collect();
    assert_eq!(osc.len(), 2);
    for l in osc {
        assert!((l.norm() - 5.7705).abs() <= 5e-5, "{l}");
    }
}

#[test]
fn arm_upright_eigenvalues_are_the_printed_ones() {
    let p = ArmParams::book();
    let (a, _) = p.linearization(0.0);
    let (al2, _, al5) = p.alphas();
    let schur = real_eigenvalues(&a);
    let roots = block_roots(p.a1, al5 / al2, p.mu2 / al2);
    // docs/model.md §2, printed to 4 decimals (−6.2 exactly: the drive pole).
    for ((s, r), printed) in schur.iter().zip(&roots).zip([-6.3597, -6.2, 0.0, 6.3375]) {
        assert!((s - printed).abs() <= 5e-5, "{schur:?}");
        assert!((s - r).abs() <= 1e-12, "{schur:?} vs {roots:?}");
    }
    // docs/model.md §2's derived constants, printed to 5 significant digits.
    let (al2, al3, al5) = p.alphas();
    for (got, printed) in [(al2, 4.5564e-3), (al3, 4.2494e-3), (al5, 0.18364)] {
        assert!(
            (got - printed).abs() <= 5e-5 * printed,
            "{got} vs {printed}"
        );
    }
}

#[test]
fn arm_angle_enters_only_through_its_cosine() {
    // docs/model.md §2: A(ρ) = A₀ + ρ A₁, B(ρ) = B₀ + ρ B₁ with ρ = 1 − cos θ₁ₑ, A₁ the single
    // entry (4, 3) = −a₁α₃/α₂ and B₁ the single entry (4) = b₁α₃/α₂.
    let p = ArmParams::book();
    let (al2, al3, _) = p.alphas();
    let (a0, b0) = p.linearization(0.0);
    for theta1e in [0.3, -1.2, 2.9] {
        let rho = 1.0 - f64::cos(theta1e);
        let (a, b) = p.linearization(theta1e);
        let mut a_affine = a0.clone();
        a_affine[(3, 2)] -= rho * p.a1 * al3 / al2;
        let mut b_affine = b0.clone();
        b_affine[(3, 0)] += rho * p.b1 * al3 / al2;
        // The same numbers summed in another order: a few roundings of entries ≤ 60.
        assert!((&a - &a_affine).amax() <= 1e-13, "θ1e = {theta1e}");
        assert!((&b - &b_affine).amax() <= 1e-13, "θ1e = {theta1e}");
    }
}
