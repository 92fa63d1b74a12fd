//! NumPy ↔ nalgebra conversions shared by every facet: any float dtype and memory order in,
//! `float64` C-ordered arrays out; shapes and finiteness checked with errors that name the
//! argument.
