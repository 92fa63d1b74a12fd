//! Examples of this chapter.

use crate::registry::Example;

/// The chapter's examples, in book order.
pub(crate) fn examples() -> Vec<Example> {
    Vec::new()
}
