//! The solvers' stopwatch: [`std::time::Instant`], except on `wasm32-unknown-unknown`, whose
//! `std` has no clock (`Instant::now` panics there): a stopwatch that always reads 0 s, so
//! the timing fields of a solution are 0 and a time limit never triggers (the browser lab
//! times its calls itself, `docs/web.md`).

#[cfg(not(all(target_arch = "wasm32", target_os = "unknown")))]
pub(crate) use std::time::Instant;

/// A stopwatch without a clock (module docs).
#[cfg(all(target_arch = "wasm32", target_os = "unknown"))]
#[derive(Debug, Clone, Copy)]
pub(crate) struct Instant;

#[cfg(all(target_arch = "wasm32", target_os = "unknown"))]
impl Instant {
    /// The stopwatch's start.
    pub(crate) fn now() -> Self {
        Instant
    }

    /// Time since [`Instant::now`]: always zero.
    pub(crate) fn elapsed(&self) -> std::time::Duration {
        std::time::Duration::ZERO
    }
}
