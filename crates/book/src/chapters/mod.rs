//! The examples, one module per chapter.

use crate::registry::Example;

mod common;
mod mfile_refs;
mod p1c2;
mod p1c3;
mod p1c4;
mod p1c5;
mod p1c6;
mod p1c7;
mod p1c8;
mod p2c1;
mod p2c2;
mod p2c3;
mod toolbox;

/// Every example in book order.
pub(crate) fn all() -> Vec<Example> {
    let mut all = Vec::new();
    all.extend(p1c2::examples());
    all.extend(p1c3::examples());
    all.extend(p1c4::examples());
    all.extend(p1c5::examples());
    all.extend(p1c6::examples());
    all.extend(p1c7::examples());
    all.extend(p1c8::examples());
    all.extend(p2c1::examples());
    all.extend(p2c2::examples());
    all.extend(p2c3::examples());
    all.extend(toolbox::examples());
    all
}
