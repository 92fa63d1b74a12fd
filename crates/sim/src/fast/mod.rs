//! The fast paths, in one place: kernels specialised for speed that the general API
//! ([`SampledLoop`](crate::SampledLoop), [`simulate`](crate::simulate), [`Env`](crate::Env))
//! does not need. Each is chosen by a switch the caller passes to the loop — a strategy type
//! parameter ([`MulAdd`], [`SinCos`]) or a kernel type that carries a [`Trig`] — never by a
//! field of a physics type.
//!
//! | what | where | relation to the general API |
//! |---|---|---|
//! | one fixed-size closed loop (`[f64; N]` plant, static state feedback or the LQ servo, ZOH, RK4, saturation), monomorphised | [`FixedLoop`], [`FixedDynamics`], [`FixedController`] ([`fixed`]); [`SampledLoop::fixed`](crate::SampledLoop::fixed) converts | bit-identical to the general loop with the provided RK4 step; compiled a second time for FMA, chosen at run time, for plant steps that fuse their multiply–adds |
//! | SIMD lanes for batch studies of static feedback | [`run_feedback_lanes`], [`LaneDynamics`] ([`lanes`]) | `L` runs stepped together; bit-identical to the general loop with [`LibmSinCos`] |
//! | the strategy switches | [`MulAdd`] ([`Fused`], [`Separate`], [`MulAddPath`]), [`SinCos`] ([`LibmSinCos`], [`PolySinCos`], [`AnchoredSinCos`]), [`Trig`] ([`strategy`]) | the default of each is the general API's arithmetic |
//! | sines and cosines by polynomial, series and the addition theorem, with their error bounds | [`sin_cos_lanes`], [`sin_cos_near_zero`], [`sin_cos_offset`], [`rotate_small`], … ([`trig`]) | within a few ulp of libm (bounds on each function) |
//!
//! [`FixedEnv`](crate::env::FixedEnv) is the environment over a [`FixedDynamics`] plant; the
//! cart pendulum's own fast kernels (the anchored-trig RK4 step and its lane form) live in
//! `pendulab_plants::cart::fast`.

pub mod fixed;
pub mod lanes;
pub mod strategy;
pub mod trig;

pub use fixed::{FixedController, FixedDynamics, FixedLoop, FixedStep, StepVisitor, rk4_fixed};
pub use lanes::{LaneDynamics, LaneOptions, LaneOutcome, rk4_lanes, run_feedback_lanes};
pub use strategy::{
    AnchoredSinCos, Fused, LibmSinCos, MulAdd, MulAddPath, PolySinCos, Separate, SinCos, Trig,
};
pub use trig::{
    COS_TAYLOR, NEAR_ZERO_LIMIT, ROTATE_LIMIT, SHIFT_LIMIT, SIN_TAYLOR, rotate_small,
    sin_cos_lanes, sin_cos_near_zero, sin_cos_offset, sin_cos_offset_lanes, sin_cos_shifted,
    sin_cos_small,
};
