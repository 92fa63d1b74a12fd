//! Test support for the pendulab workspace (dev only, never a `[dependencies]` entry): the
//! book's two plants as parameter sets (book tables 3.5 and 3.7) and their linearisations written
//! out from the closed forms of `docs/model.md` §1 and §2, so that every crate's tests, down to
//! `pendulab-lti`, build the same systems from one hand-written copy.
//!
//! The crate depends on `nalgebra` and `serde_json` alone, so any crate may take it as a
//! dev-dependency without a cycle. Matrices are `nalgebra::DMatrix<f64>`, the type
//! `pendulab_lti::Mat` names. Nothing here calls the library under test: the plants' own `linearize` (`pendulab-plants`) and the
//! finite-difference `linearize` (`pendulab-sim`) are tested *against* these formulas.
//!
//! - [`cart`]: the cart-type pendulum (`docs/model.md` §1), its upright and hanging
//!   linearisations, the encoder outputs and the LQ weights the book's cart examples share;
//! - [`arm`]: the arm-type pendulum (`docs/model.md` §2) linearised at any arm angle;
//! - [`json`]: reading the reference fixtures of `tools/reference/` and their matrices.
#![warn(missing_docs)]

pub mod arm;
pub mod cart;
pub mod json;

/// The dense matrix type of the workspace (`pendulab_lti::Mat` is the same type).
pub type Mat = nalgebra::DMatrix<f64>;

/// The shape both plants' linearisations share (`docs/model.md` §1 and §2): a first-order
/// velocity drive on the first coordinate and the pendulum's row on the second, with state
/// `[q₁, q₂, q̇₁, q̇₂]`:
///
/// ```text
/// A = [[0, 0, 1, 0],
///      [0, 0, 0, 1],
///      [0, 0, −a, 0],
///      [0, k_angle, k_drive, −k_damping]],      B = [0, 0, b, −k_input]ᵀ
/// ```
///
/// `a` (1/s) and `b` (per second² and volt) are the drive's pole and gain; the pendulum's row
/// holds the gravity stiffness `k_angle` (1/s²), the coupling to the drive's velocity `k_drive`
/// (1/s), the joint's damping `k_damping` (1/s) and the input's coupling `k_input`.
fn drive_and_pendulum(a: f64, b: f64, pendulum_row: [f64; 3], k_input: f64) -> (Mat, Mat) {
    let [k_angle, k_drive, k_damping] = pendulum_row;
    #[rustfmt::skip]
    let a_mat = Mat::from_row_slice(4, 4, &[
        0.0, 0.0, 1.0, 0.0,
        0.0, 0.0, 0.0, 1.0,
        0.0, 0.0, -a, 0.0,
        0.0, k_angle, k_drive, -k_damping,
    ]);
    let b_mat = Mat::from_column_slice(4, 1, &[0.0, 0.0, b, -k_input]);
    (a_mat, b_mat)
}

/// `diag(d)` as a dense matrix.
fn diag(d: &[f64]) -> Mat {
    Mat::from_diagonal(&nalgebra::DVector::from_column_slice(d))
}
