//! # pendulab-lmi — linear matrix inequalities and sums of squares for control design
//!
//! A modelling layer a control engineer can read, on two interior-point methods
//! ([`Backend`]): pendulab's own dense primal–dual method for the small LMIs of control
//! design (homogeneous self-dual embedding, Nesterov–Todd scaling, Schur-complement normal
//! equations), and the Clarabel solver (pure Rust; its semidefinite path runs on the
//! BLAS/LAPACK symbols of `pendulab-lapack`) for larger and sparser problems such as SOS
//! programs. [`Backend::Auto`] picks by size and falls back to Clarabel whenever the dense
//! method's answer does not pass its rechecks.
//!
//! - [`Problem`]: matrix decision variables ([`Problem::symmetric`], [`Problem::matrix`],
//!   [`Problem::scalar`]), scalar parameters ([`Problem::parameter`]), constraints
//!   `F ⪰ 0`, `F ≻ 0` with an explicit margin (`F ⪰ εI`), `F ⪯ 0`, `F ≺ 0`, `L = R`,
//!   entrywise `≥`, SOS constraints ([`Problem::sos`], [`Problem::psd_on_set`],
//!   [`Problem::sos_multiplier`]), a linear objective, and [`Problem::solve`].
//! - [`Expr`]: matrix expressions — affine in the decision variables, polynomial in the
//!   parameters — built with `+`, `-`, `*` (with other expressions, [`pendulab_lti::Mat`]
//!   constants and `f64`), [`Expr::t`], [`Expr::he`] (`M + Mᵀ`), [`Expr::block`],
//!   [`Expr::kron`], [`Expr::trace`], [`Expr::sub_block`], [`Expr::at`] (substitute a
//!   parameter). Invalid operations are reported when the expression is used, never by a
//!   panic.
//! - [`Solution`]: the [`Status`] (solved, infeasible with a Farkas [`Certificate`],
//!   unbounded, numerical trouble, ...), values of any expression ([`Solution::value`],
//!   [`Solution::value_at`]), the recheck of every constraint on the returned values
//!   ([`ConstraintCheck`]: smallest eigenvalue against the margin, equality residuals), the
//!   residual of every SOS decomposition ([`SosCheck`]), iterations, timing and problem size.
//! - [`planted::planted_sdp`]: semidefinite programs with an optimum known by construction,
//!   for tests and benchmarks of the solvers.
//! - [`synthesis`]: ready designs with their problem statements — α-stability and decay rate,
//!   LMI LQ (guaranteed-cost) state feedback, pole regions (Chilali–Gahinet), polytopic robust
//!   design, input-saturation design, and the gain-scheduled servo with SOS multipliers.
//!
//! Conventions: state feedback `u = −K x` (the textbook's `u = +K̃ x` is `K̃ = −K`); SI units.
//!
//! ## Writing and solving an LMI
//!
//! ```
//! use pendulab_lmi::{Expr, Problem, SolveOptions};
//! use pendulab_lti::Mat;
//!
//! // State feedback u = −Kx with K = −L X⁻¹ such that Re λ(A − BK) < −1:
//! // X ≻ 0,  He(AX + BL) + 2X ≺ 0.
//! let a = Mat::from_row_slice(2, 2, &[0.0, 1.0, 2.0, -1.0]);
//! let b = Mat::from_column_slice(2, 1, &[0.0, 1.0]);
//! let mut p = Problem::new();
//! let x = p.symmetric("X", 2);
//! let l = p.matrix("L", 1, 2);
//! p.positive_definite("X ≻ 0", &x, 1e-6)?;
//! let y = &a * &x + &b * &l;
//! p.negative_definite("decay rate 1", &(y.he() + x.scale(2.0)), 1e-6)?;
//! let sol = p.solve(&SolveOptions::default())?;
//! assert!(sol.all_checks_pass());
//! let k = -sol.value(&l)? * sol.value(&x)?.try_inverse().unwrap();
//! # Ok::<(), pendulab_lmi::LmiError>(())
//! ```
//!
//! [`capture_conic_problems`] records the exact conic data ([`ConicProblem`]) each solve hands
//! Clarabel, e.g. to solve the same problem with another build of Clarabel
//! (`tools/reference/lmi_clarabel_python.py`).
//!
//! Layout: `conic.rs` puts a [`Problem`] in conic form (`A x + s = b`, `s` in zero,
//! nonnegative and PSD cones, the PSD rows as the `svec` of the upper triangle column by
//! column with off-diagonals × √2) and maps answers back; `dense.rs` is the dense method;
//! exactly one file (`clarabel_backend.rs`) knows Clarabel's interface.
//!
//! ## Features
//!
//! - `clarabel` (default): the Clarabel backend. Without it the crate has no C or BLAS
//!   dependency and builds for `wasm32-unknown-unknown` (the browser lab, `docs/web.md`);
//!   [`Backend::Dense`] solves as before, [`Backend::Clarabel`] is an [`LmiError::Solver`],
//!   and [`Backend::Auto`] is one whenever it would fall back to Clarabel. On
//!   `wasm32-unknown-unknown` (no clock in `std`) the timing fields of a [`Solution`] are 0.

#![warn(missing_docs)]

mod clarabel_backend;
mod clock;
// Without Clarabel, the settings only it reads and the statuses only it reports are unused.
#[cfg_attr(not(feature = "clarabel"), allow(dead_code))]
mod conic;
mod dense;
pub mod error;
pub mod expr;
mod linalg;
pub mod planted;
pub mod problem;
pub mod solution;
pub mod sos;
pub mod synthesis;

pub use clarabel_backend::{ConicProblem, QpAnswer, capture_conic_problems, solve_qp};
pub use error::{LmiError, Result};
pub use expr::{Expr, Monomial};
pub use problem::{ConstraintId, Multiplier, Origin, Problem, Relation, Sense, SosId};
pub use solution::{
    Backend, Certificate, ConstraintCheck, DenseAttempt, Dims, KktSolver, Solution, SolveOptions,
    SosCheck, Status, Tolerances,
};
