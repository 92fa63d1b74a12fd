//! The arm-type pendulum of `docs/model.md` §2 (book table 3.7 parameters; its linearisation from
//! pendulab-testkit), its integral-servo augmentation and LPV form, built from the formulas in
//! the tests themselves.
#![allow(dead_code)]

use pendulab_lti::Mat;
use pendulab_testkit::arm::ArmParams;

/// The arm drive's pole a₁ (1/s) and gain b₁ (rad/(s² V)), book table 3.7.
pub const A1: f64 = ArmParams::book().a1;
pub const B1: f64 = ArmParams::book().b1;

/// A, B of the arm pendulum with drive parameters a1, b1, at θ1e (state [θ1, θ2, θ̇1, θ̇2]):
/// the closed form of `docs/model.md` §2 (pendulab-testkit) with the other parameters of table 3.7.
pub fn arm(a1: f64, b1: f64, theta1e: f64) -> (Mat, Mat) {
    ArmParams {
        a1,
        b1,
        ..ArmParams::book()
    }
    .linearization(theta1e)
}

/// Servo augmentation with ∫(r − θ1): Ã = [[A, 0], [−C, 0]], B̃ = [B; 0], C = [1, 0, 0, 0].
pub fn augment(a: &Mat, b: &Mat) -> (Mat, Mat) {
    let mut at = Mat::zeros(5, 5);
    at.view_mut((0, 0), (4, 4)).copy_from(a);
    at[(4, 0)] = -1.0;
    let mut bt = Mat::zeros(5, 1);
    bt.view_mut((0, 0), (4, 1)).copy_from(b);
    (at, bt)
}

/// The LPV form ρ = 1 − cos θ1: A(ρ) = A0 + ρ A1, B(ρ) = B0 + ρ B1 (augmented, 5 states).
pub fn lpv_servo() -> (Mat, Mat, Mat, Mat) {
    let (al2, al3, _) = ArmParams::book().alphas();
    let (a0, b0) = arm(A1, B1, 0.0);
    let (at0, bt0) = augment(&a0, &b0);
    let mut at1 = Mat::zeros(5, 5);
    at1[(3, 2)] = -A1 * al3 / al2;
    let mut bt1 = Mat::zeros(5, 1);
    bt1[(3, 0)] = B1 * al3 / al2;
    (at0, at1, bt0, bt1)
}

pub fn servo_weights() -> (Mat, Mat) {
    (
        Mat::from_diagonal(&pendulab_lti::Vector::from_vec(vec![
            0.1, 1.0, 0.001, 0.001, 4.0,
        ])),
        Mat::from_element(1, 1, 1.0),
    )
}

/// The book's p2c15_ex7 gain-scheduling problem: the LPV servo, ρ = 1 − cos θ₁ ∈ [0, 1 − cos 65°]
/// (and the same for ρ(0)), |ρ̇| ≤ 0.75, the servo weights, margin 1e-6, re-solve at
/// γ ≤ 1.06 γ*, balanced.
pub fn book_gain_schedule() -> (
    pendulab_lmi::synthesis::GainScheduleSpec,
    pendulab_lmi::synthesis::LpvPlant,
) {
    let (q, r) = servo_weights();
    let (a0, a1, b0, b1) = lpv_servo();
    let rho_bar = 1.0 - 65f64.to_radians().cos();
    let spec = pendulab_lmi::synthesis::GainScheduleSpec {
        rho_range: (0.0, rho_bar),
        rho0_range: (0.0, rho_bar),
        rho_dot_bound: 0.75,
        lq: pendulab_lmi::synthesis::LqWeights { q, r },
        margin: 1e-6,
        gamma_relax: 0.06,
        balance: true,
    };
    (spec, pendulab_lmi::synthesis::LpvPlant { a0, a1, b0, b1 })
}
