//! The examples, one module per chapter.

use crate::registry::Example;

/// Every example in book order.
pub(crate) fn all() -> Vec<Example> {
    Vec::new()
}
