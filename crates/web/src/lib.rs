//! # pendulab-web — the browser lab
//!
//! The cart and arm pendulums, their designs and the rig's sampled-data loop, compiled to
//! WebAssembly for the static page in `web/` (`docs/web.md`). A front end: it reads the shared
//! specifications (`PlantSpec`, `ControllerSpec`, `ScenarioSpec`/`Imperfections`,
//! `docs/model.md` §6) and calls the libraries; it has no model or design of its own.
//!
//! | what | where |
//! |---|---|
//! | LQR, LQ servo and pole placement on the plant spec's upright linearisation; gain, poles, the controller spec that runs the gain | [`design`] |
//! | the live rig: one sample at a time at 1 kHz, the rig's imperfections switchable, poke, hold, reference steps | [`lab`] |
//! | the design as a controller file for `pendulab rig run` | [`export`] |
//! | the gain-scheduled arm servo beside the constant LQ servo on the same reference steps | [`compare`] |
//! | the C ABI the page's loader calls (two buffers in linear memory) | [`ffi`] |
//!
//! Responses (the initial-condition and reference-step runs the page plots) are
//! `pendulab_control::scenario::simulate` runs of the running design with the lab's
//! imperfections.
#![warn(missing_docs)]

pub mod compare;
pub mod design;
pub mod error;
pub mod export;
pub mod ffi;
pub mod lab;

pub use design::{Design, Method, Mode, design};
pub use error::WebError;
pub use lab::{Effect, Lab};

// The wasm build: rand (through pendulab-sim) asks getrandom for OS entropy, which
// wasm32-unknown-unknown lacks; the lab never draws from it (its noise is seeded).
#[cfg(target_arch = "wasm32")]
use getrandom03 as _;
