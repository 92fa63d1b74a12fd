//! # pendulab-lti — linear time-invariant systems
//!
//! Everything a user of MATLAB's Control System Toolbox reaches for first, in pure Rust:
//!
//! - [`StateSpace<Continuous>`] / [`StateSpace<Discrete>`]: systems with the time domain in the
//!   type ([`domain`]).
//! - [`Trajectory`]: the one time-series type of the workspace (rows = samples).
//! - [`linalg`]: the matrix types ([`Mat`]), checks, eigenvalues, real Schur and QZ forms with
//!   reordering.
//! - [`equations`]: Sylvester, Lyapunov (`lyap`, `dlyap`), Riccati (`care`, `dare`), each with
//!   its relative residual.
//!
//! Conventions: SI units, radians; state feedback is `u = −K x` (the textbook's `u = +K x` is
//! converted explicitly where it is shown).

#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod analysis;
pub mod design;
pub mod discretization;
pub mod domain;
pub mod equations;
pub mod error;
pub mod frequency_response;
pub mod interconnect;
pub mod linalg;
pub mod matrix_functions;
pub mod polynomial;
pub mod response;
pub mod state_space;
pub mod trajectory;
pub mod transfer_function;

pub use domain::{Continuous, Discrete, TimeDomain};
pub use error::{LtiError, Result};
pub use linalg::{CMat, Complex64, Mat, Vector};
pub use state_space::StateSpace;
pub use trajectory::Trajectory;
