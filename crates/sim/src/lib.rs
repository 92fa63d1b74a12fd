//! (Crate documentation follows with its contents.)
#![warn(missing_docs)]
