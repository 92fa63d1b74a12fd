//! # pendulab-lmi — linear matrix inequalities and sums of squares for control design
//!
//! (Tour written with the syntheses.)

#![warn(missing_docs)]

mod backend;
pub mod error;
pub mod expr;
mod linalg;
pub mod problem;
pub mod solution;
pub mod sos;
pub mod synthesis;

pub use error::{LmiError, Result};
pub use expr::{Expr, Monomial};
pub use problem::{ConstraintId, Multiplier, Origin, Problem, Relation, Sense, SosId};
pub use solution::{
    Certificate, ConstraintCheck, Dims, Solution, SolveOptions, SosCheck, Status, Tolerances,
};
