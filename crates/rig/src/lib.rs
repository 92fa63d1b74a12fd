//! # pendulab-rig — the real-time rig loop
//!
//! What lets a lab run pendulab on a real pendulum: the wire protocol ([`protocol`]).
#![warn(missing_docs)]

pub mod protocol;
