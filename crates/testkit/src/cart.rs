//! The cart-type pendulum of `docs/model.md` §1 (book part 1 §2.2 and §3.1, eqs 3.7 and 3.21):
//! state `x = [z, θ, ż, θ̇]` (m, rad, m/s, rad/s), input the motor voltage `v` (V), `θ` from the
//! upward vertical.

use crate::{Mat, diag, drive_and_pendulum};

/// The cart pendulum's parameters (SI units), the fields of `docs/model.md` §1 without the
/// drawing-only tip length `L_p`.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartParams {
    /// Velocity pole of the drive `a_c` (1/s).
    pub a_c: f64,
    /// Gain of the drive `b_c` (m/(s² V)).
    pub b_c: f64,
    /// Pendulum mass `m_p` (kg).
    pub m_p: f64,
    /// Pivot to centre of mass `l_p` (m).
    pub l_p: f64,
    /// Inertia about the centre of mass `J_p` (kg m²).
    pub J_p: f64,
    /// Viscous friction of the pivot `μ_p` (N m s/rad).
    pub mu_p: f64,
    /// Gravity `g` (m/s²).
    pub g: f64,
}

/// The rest the cart pendulum is linearised at: the pendulum upright (`θ = 0`) or hanging
/// (`θ = π`), the cart anywhere, everything at rest.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rest {
    /// `θ = 0`, `cos θ = 1`: the unstable rest the balancing controllers hold.
    Upright,
    /// `θ = π`, `cos θ = −1`.
    Hanging,
}

impl Rest {
    /// `cos θ` at this rest: exactly `1` or `−1`.
    fn cos(self) -> f64 {
        match self {
            Rest::Upright => 1.0,
            Rest::Hanging => -1.0,
        }
    }
}

impl CartParams {
    /// Book table 3.5 (the IP Toolbox's `cdip_para.m`): `a_c = 6.25`, `b_c = 4.36`,
    /// `m_p = 0.107`, `l_p = 0.230`, `J_p = 1.59·10⁻³`, `μ_p = 2.35·10⁻⁴`, `g = 9.81`.
    pub const fn book() -> Self {
        Self {
            a_c: 6.25,
            b_c: 4.36,
            m_p: 0.107,
            l_p: 0.230,
            J_p: 1.59e-3,
            mu_p: 2.35e-4,
            g: 9.81,
        }
    }

    /// The inertia about the pivot `J = J_p + m_p l_p²` (kg m²).
    pub fn inertia(&self) -> f64 {
        self.J_p + self.m_p * self.l_p * self.l_p
    }

    /// The linearisation at `rest` in deviation variables, written out from `docs/model.md` §1
    /// with `c = cos θ` of the rest (±1):
    ///
    /// ```text
    /// A = [[0, 0, 1, 0],
    ///      [0, 0, 0, 1],
    ///      [0, 0, −a_c, 0],
    ///      [0, c m_p g l_p/J, c a_c m_p l_p/J, −μ_p/J]],   B = [0, 0, b_c, −c b_c m_p l_p/J]ᵀ
    /// ```
    ///
    /// Upright, `c = 1` and the products are those of the formula as printed.
    pub fn linearization(&self, rest: Rest) -> (Mat, Mat) {
        let (c, j) = (rest.cos(), self.inertia());
        let (m, l) = (self.m_p, self.l_p);
        drive_and_pendulum(
            self.a_c,
            self.b_c,
            [
                c * m * self.g * l / j,
                c * self.a_c * m * l / j,
                self.mu_p / j,
            ],
            c * self.b_c * m * l / j,
        )
    }
}

/// `(A, B)` of the book's cart pendulum (table 3.5) at the upright rest, `docs/model.md` §1;
/// its eigenvalues are `0, −6.25, +5.7543, −5.7867` (1/s).
pub fn upright() -> (Mat, Mat) {
    CartParams::book().linearization(Rest::Upright)
}

/// The rig's encoder outputs `y = [z, θ]`: `C = [[1, 0, 0, 0], [0, 1, 0, 0]]` (with `D = 0`,
/// 2 × 1).
pub fn measured_output() -> Mat {
    Mat::from_row_slice(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0])
}

/// The LQ weights of the book's cart state-feedback examples (part 2 §2.3.4,
/// `p2c234_ex1_cdip_odq`, and the rig's default balance controller): `Q = diag(10, 10, 0, 0)`
/// on `[z, θ, ż, θ̇]`, `R = 1`.
pub fn lqr_weights() -> (Mat, Mat) {
    (diag(&[10.0, 10.0, 0.0, 0.0]), diag(&[1.0]))
}
