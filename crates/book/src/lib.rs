//! # pendulab-book — every example of the textbook as code
//!
//! Each example of 「倒立振子で学ぶ制御工学」 is an [`Example`] in the [`registry()`], named by the
//! stem of the book's MATLAB file (e.g. `p1c63_ex5_cdip_lqr_servo`). Running one returns an
//! [`ExampleOutput`]: its numbers under fixed names built from the book's symbols (gains in the
//! book's convention `u = +K x`), the book's printed values beside them where the book prints any,
//! and the figures it drew as values (rendered and written by the front end: the book touches no
//! file and prints nothing). The command line (`pendulab book`), the tests and the lab report all
//! use this one registry.
//!
//! - [`registry`](mod@registry) — [`Example`], [`RunContext`], [`registry()`], [`find`];
//! - [`output`] — [`ExampleOutput`], [`Value`], the book's [`Reference`] values and their
//!   [`Comparison`] with ours, the figures and animations as [`Graphic`] values;
//! - [`report`] — the lab report page and the README table of examples, from results;
//! - [`error`] — [`BookError`] and the [`Cause`] of a failed computation.

#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod chapters;
pub mod error;
pub mod output;
pub mod registry;
pub mod report;

pub use error::{BookError, Cause};
pub use output::{
    Comparison, ExampleOutput, Graphic, GraphicKind, Reference, RenderedFile, Uncompared, Value,
};
pub use registry::{Example, RunContext, find, registry};
